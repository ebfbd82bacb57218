"""Every notebook in notebooks/ runs top to bottom in a fresh kernel (even-numbered half here,
the rest in ``test_notebooks_odd.py``)."""

from __future__ import annotations

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
from notebook_runner import NOTEBOOKS, half, run_notebook  # noqa: E402


def test_there_are_notebooks():
    assert any(nb.name == "00_tour.ipynb" for nb in NOTEBOOKS)
    assert sorted(half(0) + half(1)) == NOTEBOOKS


@pytest.mark.parametrize("path", half(0), ids=[p.name for p in half(0)])
def test_notebook_runs(path: Path):
    run_notebook(path)
