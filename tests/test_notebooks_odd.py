"""The other half of the notebooks (see ``test_notebooks.py``), in a file of its own so that it runs
on a second worker."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from notebook_runner import half, run_notebook  # noqa: E402


@pytest.mark.parametrize("path", half(1), ids=[p.name for p in half(1)])
def test_notebook_runs(path: Path):
    run_notebook(path)
