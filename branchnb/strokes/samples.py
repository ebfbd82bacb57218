"""Samples along a target stroke: every ``h`` px of arc length and every control point.

A sample ``p`` between target control points ``c_i`` and ``c_i+1`` maps to
the point ``p'`` at the same arc-length fraction between the corresponding
source control points
(:meth:`~branchnb.strokes.strokes.StrokePair.source_arc_length`). Split out
of :mod:`branchnb.strokes.fetch`; the names are importable from there too.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.validate import MAX_COUNT, Real, check_real, checked
from .strokes import StrokePair

__all__ = ["Samples", "sample_pair"]


def _SPACING(value, name, allow_none):
    """A step ``h > 0`` in pixels, or a function of the arc length giving one."""
    return value if callable(value) else check_real(value, name, 0, 1e5, low_open=True)


@dataclass
class Samples:
    """Samples along one target stroke.

    Parameters
    ----------
    s : (M,) ndarray
        Target arc lengths.
    points : (M, 2) ndarray
        Target positions ``p``.
    angles : (M,) ndarray
        Target stroke direction at ``p`` (radians).
    source_s : (M,) ndarray
        Nominal source arc lengths of ``p'`` (arc-length fraction between
        control points).
    pinned : (M,) bool ndarray
        Samples at control points (their correspondence is fixed).
    """

    s: np.ndarray
    points: np.ndarray
    angles: np.ndarray
    source_s: np.ndarray
    pinned: np.ndarray

    def __len__(self) -> int:
        return len(self.s)


@checked(spacing=_SPACING, window=Real(0, 1e4))
def sample_pair(pair: StrokePair, spacing, *, window: float) -> Samples:
    """Sample the target stroke of ``pair`` every ``spacing`` pixels (about).

    Each stretch between consecutive target control points is divided
    into the fewest equal-count steps no longer than ``spacing``, so the
    control points themselves are samples (and are pinned).

    Parameters
    ----------
    pair : StrokePair
        The pair whose target stroke is sampled; its control points are
        samples.
    spacing : float or callable
        The step ``h`` (px), or a function of the target arc length
        giving the local step (e.g. half the local patch radius): the
        samples are then spread so that each step is about ``h`` where it
        starts.
    window : float
        Chord half-length for the target directions.

    Examples
    --------
    >>> from branchnb.strokes.strokes import Stroke, StrokePair
    >>> pair = StrokePair(Stroke([(0, 0), (20, 0)]), Stroke([(0, 0), (0, 10)]))
    >>> smp = sample_pair(pair, 4.0, window=2.0)
    >>> smp.s.tolist(), smp.source_s.tolist()
    ([0.0, 3.3333333333333335, 6.666666666666667, 10.0], [0.0, 6.666666666666667, 13.333333333333334, 20.0])
    """
    ct = pair.control[:, 1]
    if callable(spacing):
        grid = np.linspace(0.0, pair.target.length, max(2, int(np.ceil(pair.target.length * 2)) + 1))
        h = np.asarray(spacing(grid), float)
        if h.shape != grid.shape or not np.all(np.isfinite(h) & (h > 0)):
            raise ValueError("spacing(s) must return finite steps > 0")
        # N(s) = integral of ds / h: samples at equal steps of N.
        n_of_s = np.concatenate([[0.0], np.cumsum(np.diff(grid) * 0.5 * (1 / h[1:] + 1 / h[:-1]))])
    else:
        if pair.target.length / spacing > MAX_COUNT:
            raise ValueError(f"spacing {spacing:g} would make more than {MAX_COUNT} samples along the target stroke")
        grid = np.array([0.0, pair.target.length])
        n_of_s = grid / float(spacing)
    parts = [np.array([ct[0]])]
    pinned = [True]
    for t0, t1 in zip(ct[:-1], ct[1:]):
        n0, n1 = np.interp([t0, t1], grid, n_of_s)
        n = max(1, int(np.ceil(n1 - n0 - 1e-9)))
        inner = np.interp(np.linspace(n0, n1, n + 1)[1:-1], n_of_s, grid)
        parts.append(np.concatenate([inner, [t1]]))
        pinned.extend([False] * (n - 1) + [True])
    s = np.concatenate(parts)
    return Samples(
        s=s,
        points=pair.target.point_at(s),
        angles=pair.target.angle_at(s, window=window),
        source_s=pair.source_arc_length(s),
        pinned=np.array(pinned, bool),
    )
