"""Importance emphasis: the thickness of the dendrite (paper, section 6).

**Importance thickness.** Each node's radius follows a rolling average
of the importance sampled along its branch, over a window of ``window``
nodes centred on the node. Toward the root the window continues into the
parent branch (through the junction; only at the root of the whole tree
does it shrink); toward the tip it is allowed to overshoot the branch end,
where the importance counts as zero, so the last ``window / 2`` nodes of
every branch taper off and tips thin out naturally:

    r(i) = r_min + (r_max - r_min) * mean(I over the window of i)

**Branch thickness.** Without an image, the radius comes from the tree
itself: ``"subtree"`` uses the pipe model (Leonardo's rule),
``r = r_tip * n_tips ** (1 / exponent)`` with ``n_tips`` the number of
endpoints the node carries (``exponent = 2``: cross-section areas add up
at forks); ``"distance"`` thins linearly with the path length from the
root (the trunk).
"""

from __future__ import annotations

import numba
import numpy as np

from ..core.validate import Array, Int, Real, checked
from .dendrite import Dendrite

__all__ = ["branch_thickness", "importance_thickness", "rolling_importance"]


@numba.njit(cache=True)
def _rolling(values, parent, nxt, half):
    n = values.shape[0]
    out = np.empty(n)
    for i in range(n):
        acc = values[i]
        count = 1 + half  # the tip side always counts its full half window
        # toward the root (through junctions into parent branches); the window
        # shrinks at the root itself, so the trunk base keeps its width
        j = i
        for _ in range(half):
            j = parent[j]
            if j < 0:
                break
            acc += values[j]
            count += 1
        # toward the tip; past the tip the window overshoots into zeros
        j = i
        for _ in range(half):
            j = nxt[j]
            if j < 0:
                break
            acc += values[j]
        out[i] = acc / count
    return out


@checked(importance=Array(ndim=2), window=Int(1, 10_000))
def rolling_importance(dendrite: Dendrite, importance, window: int = 15) -> np.ndarray:
    """Rolling mean of ``importance`` along the branches (see the module docstring).

    Parameters
    ----------
    dendrite : Dendrite
    importance : (H, W) array_like or (M,) per-node values
        Importance map on the dendrite's lattice (sampled at the nodes), or
        one value per tree node.
    window : int
        Window length in nodes (odd; an even value is rounded up).

    Returns
    -------
    (M,) float64
    """
    if not isinstance(dendrite, Dendrite):
        raise TypeError("dendrite must be a Dendrite")
    if isinstance(window, bool) or not isinstance(window, (int, np.integer)) or window < 1:
        raise ValueError(f"window must be a positive int, got {window!r}")
    imp = np.asarray(importance, dtype=np.float64)
    if imp.ndim == 2:
        if dendrite.shape is None or imp.shape != tuple(dendrite.shape):
            raise ValueError(f"importance has shape {imp.shape}, expected {dendrite.shape}")
        vals = imp.ravel()[dendrite.nodes]
    elif imp.shape == (dendrite.n_nodes,):
        vals = imp
    else:
        raise ValueError("importance must be an (H, W) map or one value per tree node")
    if not np.all(np.isfinite(vals)):
        raise ValueError("importance contains NaN or infinite values")
    return _rolling(vals, dendrite.parent, dendrite.next_in_branch(), int(window) // 2)


@checked(importance=Array(ndim=2), window=Int(1, 10_000), min_width=Real(0, 1e4), max_width=Real(0, 1e4),
         contrast=Real(0, 1e3), reference=Real(0, low_open=True))
def importance_thickness(dendrite: Dendrite, importance, *, window: int = 15,
                         min_width: float = 0.4, max_width: float = 4.0,
                         contrast: float = 1.0, reference: float | None = None) -> Dendrite:
    """Radius from the rolling importance ``A`` (see the module docstring):

        width = w_min + (w_max - w_min) * clip(A / reference, 0, 1) ** contrast

    Parameters
    ----------
    window : int
        Rolling-average window (nodes).
    min_width, max_width : float
        Stroke widths (pixels) for ``A = 0`` and ``A >= reference``.
    contrast : float
        Exponent on the normalised importance (> 1 thins the unimportant
        strokes further).
    reference : float, optional
        The importance that gets the full width: 1 by default (importance in
        [0, 1]). :class:`~branchnb.dendrite.stylize.Stylizer` passes the
        image's 99th percentile so strong features always reach ``max_width``.
        A constant importance gives a constant width, except the tapering tips.

    Returns
    -------
    Dendrite
        A copy with the new radius (half the width).

    Examples
    --------
    >>> from branchnb.dendrite import plan, make_lattice, build_dendrite
    >>> res = plan(make_lattice(np.zeros((40, 40)), rng=0), (20, 39))
    >>> d = importance_thickness(build_dendrite(res, [(3, 3)]), np.ones((40, 40)))
    >>> bool(d.radius[d.tips[0]] < d.radius[len(d.radius) // 2])
    True
    """
    _check_widths(min_width, max_width)
    if not np.isfinite(contrast) or contrast <= 0:
        raise ValueError(f"contrast must be > 0, got {contrast}")
    ref = 1.0 if reference is None else float(reference)
    if not np.isfinite(ref) or ref <= 0:
        raise ValueError(f"reference must be > 0, got {reference}")
    avg = np.clip(rolling_importance(dendrite, importance, window) / ref, 0.0, 1.0)
    return dendrite.with_radius(0.5 * (min_width + (max_width - min_width) * avg ** contrast))


@checked(min_width=Real(0, 1e4), max_width=Real(0, 1e4), exponent=Real(0, 100, low_open=True))
def branch_thickness(dendrite: Dendrite, *, mode: str = "subtree", min_width: float = 0.6,
                     max_width: float | None = 8.0, exponent: float = 2.0) -> Dendrite:
    """Radius from the tree structure alone.

    Parameters
    ----------
    mode : {"subtree", "distance"}
        ``"subtree"``: pipe model ``width = min_width * n_tips ** (1 / exponent)``,
        clipped at ``max_width``. ``"distance"``: linear from ``max_width``
        at the root to ``min_width`` at the farthest tip.
    exponent : float
        Pipe-model exponent (2: da Vinci's rule; ~2.5-3 for Murray's law).

    Returns
    -------
    Dendrite
        A copy with the new radius.
    """
    _check_widths(min_width, max_width if max_width is not None else min_width)
    if mode == "subtree":
        if not np.isfinite(exponent) or exponent <= 0:
            raise ValueError(f"exponent must be > 0, got {exponent}")
        w = min_width * np.maximum(dendrite.leaf_count(), 1.0) ** (1.0 / exponent)
        if max_width is not None:
            w = np.minimum(w, max_width)
    elif mode == "distance":
        if max_width is None:
            raise ValueError("mode='distance' needs max_width")
        d = dendrite.arc_depth()
        t = d / d.max() if d.size and d.max() > 0 else np.zeros_like(d)
        w = max_width + (min_width - max_width) * t
    else:
        raise ValueError(f"mode must be 'subtree' or 'distance', got {mode!r}")
    return dendrite.with_radius(0.5 * w)


def _check_widths(lo, hi):
    for name, v in (("min_width", lo), ("max_width", hi)):
        if not np.isfinite(v) or v < 0:
            raise ValueError(f"{name} must be finite and >= 0, got {v}")
    if hi < lo:
        raise ValueError(f"max_width ({hi}) must be >= min_width ({lo})")
