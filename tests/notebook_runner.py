"""Run a notebook top to bottom in a fresh kernel (shared by the notebook test files).

The notebooks are split over two test files so that pytest-xdist (``--dist loadfile``) can run them
on two workers at once: one file would hold them all on one worker for ten minutes.
"""

from __future__ import annotations

from pathlib import Path

import nbformat
from nbclient import NotebookClient

NOTEBOOKS = sorted((Path(__file__).resolve().parent.parent / "notebooks").glob("*.ipynb"))
SIZE_BUDGET = 2_500_000


def half(which: int) -> list[Path]:
    """Every other notebook, starting at ``which`` (0 or 1): together the halves hold every notebook."""
    return NOTEBOOKS[which::2]


def run_notebook(path: Path) -> None:
    """Execute ``path`` (a copy in memory) and fail on an over-budget file or any error output."""
    assert path.stat().st_size < SIZE_BUDGET, f"{path.name} is over the {SIZE_BUDGET / 1e6:.1f} MB budget"
    nb = nbformat.read(path, as_version=4)
    client = NotebookClient(nb, kernel_name="python3", timeout=600,
                            resources={"metadata": {"path": str(path.parent)}})
    client.execute()
    errors = [
        out for cell in nb.cells if cell.cell_type == "code"
        for out in cell.get("outputs", []) if out.get("output_type") == "error"
    ]
    assert not errors, errors
