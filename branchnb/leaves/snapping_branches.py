"""The training layer's skeleton as branches (step 3 of :mod:`branchnb.leaves.snapping`): pixel chains cut at
its junctions (:func:`layer_branches`) and the main ones the template carries (:func:`main_branches`)."""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_mask


def layer_branches(mask) -> tuple[list, list]:
    """A thin layer's skeleton cut at its junctions: pixel chains (x, y) and their widths.

    Each branch keeps the junction pixels it touches at its ends, so
    branches meeting at a junction share the end point.

    Parameters
    ----------
    mask : (H, W) bool array_like
        The thin layer.

    Returns
    -------
    chains : list of (N, 2) int ndarray
        Ordered pixel chains (x, y).
    widths : list of float
        Median ``2 EDT - 1`` of each chain on the layer.
    """
    from skimage.morphology import skeletonize
    m = as_mask(mask, name="mask")
    skel = skeletonize(m)
    if not skel.any():
        return [], []
    edt = ndi.distance_transform_edt(m)
    nb = ndi.convolve(skel.astype(np.int32), np.ones((3, 3), np.int32), mode="constant") - 1
    junction = skel & (nb >= 3)
    body = skel & ~junction
    lab, n = ndi.label(body, structure=np.ones((3, 3)))
    chains, widths = [], []
    jy, jx = np.nonzero(junction)
    jset = set(zip(jy.tolist(), jx.tolist()))
    objs = ndi.find_objects(lab)
    for k in range(1, n + 1):
        sl = objs[k - 1]
        ys, xs = np.nonzero(lab[sl] == k)
        ys, xs = ys + sl[0].start, xs + sl[1].start
        pts = list(zip(ys.tolist(), xs.tolist()))
        chain = _order(pts)
        # Attach the junction pixels next to the chain's two ends.
        for end_i in (0, -1):
            y, x = chain[end_i]
            near = [(y + dy, x + dx) for dy in (-1, 0, 1) for dx in (-1, 0, 1) if (y + dy, x + dx) in jset]
            if near:
                chain = [near[0]] + chain if end_i == 0 else chain + [near[0]]
        c = np.array(chain)[:, ::-1]
        if len(c) < 2:
            continue
        chains.append(c)
        widths.append(float(max(1.0, np.median(2.0 * edt[c[:, 1], c[:, 0]] - 1.0))))
    return chains, widths


def main_branches(chains, widths, size: float, *, min_length: float = 0.12):
    """The branches of a layer's main structure: long (``min_length`` of the leaf size) or wide.

    Fine veins are grown anew on every leaf (they lie elsewhere on the
    next one): snapping them would paste the training leaf's fine veins
    onto whatever ridge is near; they are left to the colour term. Wide:
    at least the 75th percentile of the branches' widths (length-weighted)
    and wider than the thinnest.

    Parameters
    ----------
    chains : list of (N, 2) ndarray
        Branches from :func:`layer_branches`.
    widths : list of float
        Their widths.
    size : float
        The leaf's size in pixels (``sqrt(blade area)``).
    min_length : float
        Shortest main branch, as a fraction of ``size`` (default 0.12).

    Returns
    -------
    chains : list of (N, 2) ndarray
    widths : list of float
        The kept branches and their widths, in the input order.
    """
    if not chains:
        return [], []
    lens = np.array([len(c) for c in chains], float)
    w = np.asarray(widths, float)
    order = np.argsort(w)
    cum = np.cumsum(lens[order]) / lens.sum()
    w75 = float(w[order][np.searchsorted(cum, 0.75)])
    keep = (lens >= min_length * size) | ((w >= w75) & (w > w.min()))
    return [c for c, k in zip(chains, keep) if k], [x for x, k in zip(widths, keep) if k]


def _order(pts: list) -> list:
    """Pixels of one skeleton branch in order along it (from an end, or anywhere on a loop)."""
    s = set(pts)

    def nbrs(p):
        y, x = p
        return [(y + dy, x + dx) for dy in (-1, 0, 1) for dx in (-1, 0, 1)
                if (dy or dx) and (y + dy, x + dx) in s]

    ends = [p for p in pts if len(nbrs(p)) <= 1]
    start = ends[0] if ends else pts[0]
    out, seen = [start], {start}
    cur = start
    while True:
        nxt = [q for q in nbrs(cur) if q not in seen]
        if not nxt:
            break
        # 4-neighbours first: a diagonal step past a 4-neighbour would skip it.
        nxt.sort(key=lambda q: abs(q[0] - cur[0]) + abs(q[1] - cur[1]))
        cur = nxt[0]
        out.append(cur)
        seen.add(cur)
    return out
