"""Pieces of a frame-entering line cut off by the false-ridge tests, linked back (issue 23).

Beyond the paper. :func:`~branchnb.branching.line_profiles.false_ridge_pixels` judges each stretch
of the skeleton between junctions by medians over the stretch. On a bolt's thin (1-3 px) side
branch where it leaves the bright trunk, the stretch next to the trunk sees the trunk on one side
only and reads as the edge of a lit region: it is dropped, and the rest of the side branch becomes
a piece of its own. Such a piece does not reach the frame; rooted at its thickest end it grew a
tree inside the picture, and the learnt main branch pointed away from where the example's lines
enter (5 of 15 procedural bolts from the top, 256-768 px, > 25 degrees off).

A stretch that the false-ridge tests dropped is put back when it is the whole link between such
a floating piece and a piece that reaches the frame (directly or through pieces linked before):
a line entering from the frame goes on through it. A stretch of a true edge (a lit field's rim
hanging off a river) links nothing that survives on its own: the rest of that edge is dropped
too, and what is left of it (stretches shorter than the tests' ``min_run``) is far under
``min_component_length``.
"""
from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

__all__ = ["relink_fragments"]

#: A piece reaches the frame within this many working-scale pixels (as in
#: :func:`~branchnb.branching.skeleton_tree.skeleton_to_structure`'s frame rule).
FRAME_PX = 4.0
#: A dropped stretch is put back only when it is at most this many times as long as the floating
#: piece it links (a much longer dropped stretch is a line of its own, judged false on its own merits).
#: In a glowing bolt (white core, blue halo) a side branch's first 90 px ran in the trunk's glow and were
#: dropped, leaving a 94 px piece (512 px); at 1024 px 185-196 px were dropped before an 85 px piece.
LINK_SHARE = 4.0

_EIGHT = np.ones((3, 3), bool)


def relink_fragments(skel: np.ndarray, dropped: np.ndarray, min_length: float) -> np.ndarray:
    """``skel`` with the dropped stretches put back that link floating pieces to the frame.

    Parameters
    ----------
    skel : (H, W) bool ndarray
        The skeleton after the false-ridge tests (working scale).
    dropped : (H, W) bool ndarray
        The skeleton pixels those tests dropped.
    min_length : float
        Working-scale pixels a piece needs to count (shorter floating pieces are left alone: the
        structure drops them).

    Returns
    -------
    (H, W) bool ndarray
        ``skel`` or ``skel`` with some of ``dropped`` set again.

    Notes
    -----
    A piece *floats* when no pixel of it lies within :data:`FRAME_PX` of the frame; it is linked
    when a connected stretch of ``dropped`` (8-connected) touches it and touches a piece anchored
    to the frame, and the stretch has at most :data:`LINK_SHARE` x the floating piece's pixels.
    Linked pieces anchor further ones (a side branch cut twice). Nothing is linked when no piece
    reaches the frame (a tree standing inside the picture keeps its own rules).

    Examples
    --------
    >>> import numpy as np
    >>> sk = np.zeros((60, 60), bool); sk[0:30, 20] = True; sk[30:50, 20] = True
    >>> drop = np.zeros_like(sk); drop[30:38, 20] = True; sk[30:38, 20] = False
    >>> from scipy import ndimage as ndi
    >>> int(ndi.label(relink_fragments(sk, drop, 10.0), np.ones((3, 3)))[1])
    1
    """
    skel = np.asarray(skel, bool)
    dropped = np.asarray(dropped, bool) & ~skel
    if skel.shape != dropped.shape or skel.ndim != 2:
        raise ValueError(f"skel and dropped must be 2-D of one shape, got {skel.shape} and {dropped.shape}")
    if not dropped.any() or not skel.any():
        return skel
    lab, n = ndi.label(skel, _EIGHT)
    if n < 2:
        return skel
    hh, ww = skel.shape
    yy, xx = np.nonzero(skel)
    fd = np.minimum(np.minimum(yy, hh - 1 - yy), np.minimum(xx, ww - 1 - xx))
    near = np.full(n + 1, np.inf)
    np.minimum.at(near, lab[yy, xx], fd)
    size = np.bincount(lab[yy, xx], minlength=n + 1).astype(np.float64)
    anchored = near <= FRAME_PX
    anchored[0] = False
    if not anchored.any():
        return skel
    dlab, nd = ndi.label(dropped, _EIGHT)
    dsize = np.bincount(dlab.ravel(), minlength=nd + 1)
    # which pieces each dropped stretch touches: the pieces in its one-pixel ring
    touch: list[set[int]] = [set() for _ in range(nd + 1)]
    ring = ndi.grey_dilation(dlab, footprint=_EIGHT)
    ry, rx = np.nonzero(skel & (ring > 0))
    for y, x in zip(ry, rx):
        # a skeleton pixel may border two stretches: every dropped neighbour counts
        ys, xs = slice(max(y - 1, 0), y + 2), slice(max(x - 1, 0), x + 2)
        for d in np.unique(dlab[ys, xs]):
            if d:
                touch[int(d)].add(int(lab[y, x]))
    out = skel.copy()
    changed = True
    while changed:
        changed = False
        for d in range(1, nd + 1):
            ps = touch[d]
            if len(ps) < 2 or not any(anchored[p] for p in ps):
                continue
            loose = [p for p in ps if not anchored[p] and size[p] >= min_length
                     and dsize[d] <= LINK_SHARE * size[p]]
            if not loose:
                continue
            out |= dlab == d
            for p in loose:
                anchored[p] = True
            touch[d] = set()
            changed = True
    return out
