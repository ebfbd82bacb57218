"""Shared test setup.

Kernels started by the notebook and browser tests must import this
checkout's ``branchnb`` (not another installed copy), so the project root
goes first on ``PYTHONPATH`` for every child process.
"""

from __future__ import annotations

import os
from pathlib import Path

import matplotlib

matplotlib.use("Agg")

ROOT = Path(__file__).resolve().parent.parent
os.environ["PYTHONPATH"] = os.pathsep.join(
    [str(ROOT)] + [p for p in os.environ.get("PYTHONPATH", "").split(os.pathsep) if p]
)
os.environ.setdefault("MPLBACKEND", "Agg")
