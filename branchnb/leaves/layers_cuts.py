"""Graph cuts of lazy snapping (:func:`branchnb.leaves.layers.grow_layers`, steps 3-4).

The superpixels' adjacency graph and its border lengths
(:func:`_superpixel_graph`), the contrast weight ``beta`` of ``E2``
(:func:`_beta`) and the pixel-level cut over the blade that refines the
superpixel labelling (:func:`_refine`).
"""

from __future__ import annotations

import maxflow
import numpy as np

from .layers_colours import _nearest

__all__: list[str] = []

#: A pinned node's terminal capacity (a hard constraint).
_HARD = 1e9
#: Cost of "layer" off a line, relative to the cost of "blade" on one (thin line layers).
_LINE_PENALTY = 0.3


def _superpixel_graph(labels: np.ndarray, n: int):
    """Pairs of 4-adjacent superpixels and the length of their shared border."""
    pairs = []
    for a, b in ((labels[:, :-1], labels[:, 1:]), (labels[:-1, :], labels[1:, :])):
        m = (a != b) & (a > 0) & (b > 0)
        pairs.append(np.stack([a[m], b[m]], 1))
    p = np.concatenate(pairs)
    p.sort(axis=1)
    key = p[:, 0].astype(np.int64) * (n + 1) + p[:, 1]
    uniq, counts = np.unique(key, return_counts=True)
    return np.stack([uniq // (n + 1), uniq % (n + 1)], 1), counts.astype(np.float64)


def _beta(diff2: np.ndarray) -> float:
    m = float(np.mean(diff2)) if diff2.size else 1.0
    return 1.0 / (2.0 * max(m, 1e-6))


def _refine(mask, feat, blade, fg_px, bg_px, fg_c, bg_c, prior, smoothness: float, line=None,
            line_weight: float = 0.0, distances=None) -> np.ndarray:
    """Pixel-level graph cut over the whole blade (lazy snapping's second step).

    Data term: the pixel's own colour costs plus ``prior`` (per pixel:
    the weight times the superpixel's colour confidence) for the
    superpixel labelling (so the superpixels steady the cut, while a layer
    thinner than a superpixel, a one-pixel vein, can still be found).
    ``distances``: ``(d_F, d_B)`` of the blade pixels (``feat[blade]``) to
    ``fg_c`` and ``bg_c`` when the caller has them (the same values).
    """
    rows, cols = np.nonzero(blade)
    r0, r1, c0, c1 = rows.min(), rows.max() + 1, cols.min(), cols.max() + 1
    f = feat[r0:r1, c0:c1]
    reg = blade[r0:r1, c0:c1]
    shp = reg.shape
    if distances is None:
        flat = f.reshape(-1, f.shape[2])
        d_f = _nearest(flat, fg_c).reshape(shp)
        d_b = _nearest(flat, bg_c).reshape(shp)
    else:
        # Only the blade's costs are read (the rest of the box is pinned to the background).
        d_f = np.zeros(shp, np.float32)
        d_b = np.zeros(shp, np.float32)
        d_f[reg] = distances[0]
        d_b[reg] = distances[1]
    tot = d_f + d_b + 1e-6
    m = mask[r0:r1, c0:c1]
    pr = np.broadcast_to(np.asarray(prior, float), mask.shape)[r0:r1, c0:c1]
    cost_fg = d_f / tot + pr * (~m)
    cost_bg = d_b / tot + pr * m
    if line is not None:
        # A thin line layer: a pixel pays for being on a line as blade, and
        # less (_LINE_PENALTY) for being off one as layer: a vein wider than
        # the filter (a petiole) or fainter than the scribbled ones still
        # joins the layer by its colour.
        lc = np.asarray(line, np.float32)[r0:r1, c0:c1]
        cost_fg = cost_fg + _LINE_PENALTY * line_weight * (1.0 - lc)
        cost_bg = cost_bg + line_weight * lc
    pin_f = fg_px[r0:r1, c0:c1]
    pin_b = (~reg | bg_px[r0:r1, c0:c1]) & ~pin_f
    g = maxflow.Graph[float]()
    ids = g.add_grid_nodes(shp)
    dr = ((f[:, 1:] - f[:, :-1]) ** 2).sum(2)
    dd = ((f[1:] - f[:-1]) ** 2).sum(2)
    beta = _beta(np.concatenate([dr[reg[:, 1:] & reg[:, :-1]], dd[reg[1:] & reg[:-1]]]))
    wr = np.zeros(shp)
    wr[:, :-1] = smoothness * np.exp(-beta * dr)
    wd = np.zeros(shp)
    wd[:-1] = smoothness * np.exp(-beta * dd)
    g.add_grid_edges(ids, weights=wr, structure=np.array([[0, 0, 0], [0, 0, 1], [0, 0, 0]]), symmetric=True)
    g.add_grid_edges(ids, weights=wd, structure=np.array([[0, 0, 0], [0, 0, 0], [0, 1, 0]]), symmetric=True)
    src = np.where(reg, cost_bg, 0.0) + np.where(pin_f, _HARD, 0.0)
    snk = np.where(reg, cost_fg, 0.0) + np.where(pin_b, _HARD, 0.0)
    g.add_grid_tedges(ids, src, snk)
    g.maxflow()
    fg = ~g.get_grid_segments(ids)
    out = np.zeros_like(mask)
    out[r0:r1, c0:c1] = fg & reg
    return out
