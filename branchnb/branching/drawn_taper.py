"""Drawn masks: children that taper like the example's, no blunt ends, no stubs (beyond the paper, issue 23).

A mask drawn in its style (:func:`~branchnb.branching.drawing.draw_in_style`) draws every branch at the
radii the synthesized structure carries. Those radii are copied piece by piece from the example, so a child
can start with a trunk's piece (thicker than the parent it leaves), keep one radius to its end and stop
there at full width with a round cap (a bulbous stub), and a child barely longer than its parent is wide
reads as a comb tooth. The example's own branches thin out towards their tips. Here the drawn radius of
every branch is bounded by what the example shows:

* where a child leaves its parent it is no thicker than the parent there;
* along a branch the radius stays under a straight ramp from its start radius to ``taper`` x that radius at
  its end (``taper``: the example's median end-to-start radius ratio, :func:`example_taper`);
* a free end (not at the frame, not running into another branch) narrows to the example's tip radius over
  its last ``3 r`` pixels;
* a child that sticks out of its parent by less than 3 of its radii is drawn no thicker than a third of
  that length less a pixel (a one-pixel line at least), so it reads as a short thin twig, not a blunt tooth;
  a leaf twig that would still show less than 3 radii and a pixel is left out (:func:`burrs`).

Notes
-----
Beyond the paper. The two rules keep :data:`STUB_MARGIN` (one pixel) between a drawn child and the
3-radius line: capped at exactly a third of what shows, a child sat on that line and the rasterization
of its cap and of its parent's edge (half a pixel each) decided whether the drawing showed a twig or a
stub (3 stubs in 243 outputs of ``_mask_taper_check``, each 2.9 radii out). With the margin a child
is either drawn clearly beyond 3 radii or not drawn.
"""

from __future__ import annotations

import numpy as np
from scipy.spatial import cKDTree

from ..core.structure import Structure

__all__ = ["burrs", "example_taper", "tapered_radii"]

#: a child is a stub when it sticks out of its parent by less than this many of its radii
STUB_RADII = 3.0
#: pixels a drawn child keeps beyond the stub line (rasterization moves the parent's edge and the child's
#: cap by up to half a pixel each)
STUB_MARGIN = 1.0
#: the free end narrows over this many of its radii
TIP_RADII = 3.0
#: a child starts no thicker than its parent where it leaves (off: a thick child the synthesis grew off
#: a thinner parent keeps its radius, tapering from there; on, a 4-px crack mask's output lost its
#: thick lines)
CHILD_BELOW_PARENT = False


def _arc(points: np.ndarray) -> np.ndarray:
    p = np.asarray(points, np.float64)
    return np.r_[0.0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))] if len(p) > 1 else np.zeros(len(p))


def _free_ends(structure: Structure, shape) -> np.ndarray:
    """Per branch: its last vertex is a free tip (>= 3 px inside the frame, not within another branch's
    body + 1 px)."""
    bs = structure.branches
    h, w = int(shape[0]), int(shape[1])
    pts, own, rad = [], [], []
    for i, b in enumerate(bs):
        p = np.asarray(b.points, np.float64)
        if len(p) < 2:
            continue
        t = _arc(p)
        s = np.arange(0.0, t[-1] + 1e-9, 0.5)
        pts.append(np.c_[np.interp(s, t, p[:, 0]), np.interp(s, t, p[:, 1])])
        own.append(np.full(len(s), i))
        rad.append(np.interp(s, t, np.asarray(b.thickness, np.float64)))
    free = np.zeros(len(bs), bool)
    if not pts:
        return free
    pts, own, rad = np.vstack(pts), np.concatenate(own), np.concatenate(rad)
    tree = cKDTree(pts)
    reach = float(rad.max()) + 1.5
    length = np.array([b.length if len(b.points) > 1 else 0.0 for b in bs])
    for i, b in enumerate(bs):
        if len(b.points) < 2:
            continue
        x, y = np.asarray(b.points[-1], np.float64)
        if min(x, y, w - 1 - x, h - 1 - y) < 3:
            continue
        # a child leaving at the very end continues the branch only when it is no stub itself
        # (a 3-vertex twig at the end of a thick piece left that piece's end blunt)
        short = STUB_RADII * float(b.thickness[-1])
        near = tree.query_ball_point((x, y), reach)
        hit = [j for j in near if own[j] != i and own[j] != b.parent
               and not (bs[own[j]].parent == i and length[own[j]] < short)
               and np.hypot(*(pts[j] - (x, y))) <= rad[j] + 1.0]
        free[i] = not hit
    return free


def example_taper(structure: Structure, shape) -> tuple[float | None, float]:
    """``(taper, tip)`` of an example: the median over its branches (>= 6 vertices, >= 8 px) of the
    median radius of their last fifth over that of their first, clipped to [0.25, 2] (None with fewer
    than 3 such branches), and the median last radius of its free ends (0 without any).

    Parameters
    ----------
    structure : Structure
        The example's structure.
    shape : (H, W)
        Its image's shape (free ends at the frame do not count).

    Returns
    -------
    (float or None, float)
        ``(taper, tip)``.

    Examples
    --------
    >>> from branchnb.core.structure import Branch
    >>> s = Structure([Branch(np.c_[np.linspace(10, 90, 20), np.full(20, y)], np.linspace(3, 1, 20))
    ...                for y in (20.0, 50.0, 80.0)])
    >>> taper, tip = example_taper(s, (100, 100))
    >>> round(taper, 2), round(tip, 2)
    (0.41, 1.0)
    """
    ratios = []
    for b in structure.branches:
        t = np.asarray(b.thickness, np.float64)
        n = len(t)
        if n < 6 or b.length < 8:
            continue
        k = max(2, n // 5)
        a = float(np.median(t[:k]))
        if a > 0:
            ratios.append(float(np.median(t[-k:])) / a)
    taper = float(np.clip(np.median(ratios), 0.25, 2.0)) if len(ratios) >= 3 else None
    free = _free_ends(structure, shape)
    tips = [float(b.thickness[-1]) for b, f in zip(structure.branches, free) if f]
    return taper, float(np.median(tips)) if tips else 0.0


def tapered_radii(structure: Structure, shape, taper: float | None, tip: float) -> list[np.ndarray]:
    """The radius to draw at every vertex of every branch of ``structure`` (see the module's rules).

    Parameters
    ----------
    structure : Structure
        The branches to draw (parents listed before their children, as synthesized).
    shape : (H, W)
        The drawing's size (ends within 3 px of its frame are no tips).
    taper : float or None
        The example's end-to-start radius ratio (:func:`example_taper`); None: no ramp.
    tip : float
        The example's tip radius; 0: free ends keep their radius.

    Returns
    -------
    list of (N_i,) float ndarray
        Never above the structure's own radii.
    """
    bs = structure.branches
    out: list[np.ndarray] = [np.asarray(b.thickness, np.float64).copy() for b in bs]
    free = _free_ends(structure, shape) if tip > 0 else np.zeros(len(bs), bool)
    order = sorted(range(len(bs)), key=lambda i: _depth(bs, i))
    for i in order:
        b = bs[i]
        r = out[i]
        if len(r) < 2:
            continue
        s = _arc(b.points)
        length = float(s[-1])
        r0 = float(r[0])
        if b.parent is not None and 0 <= b.parent < len(bs) and len(out[b.parent]):
            pr = out[b.parent]
            rp = float(pr[int(np.clip(b.parent_vertex or 0, 0, len(pr) - 1))])
            if CHILD_BELOW_PARENT:
                r0 = min(r0, rp)
            # what shows beyond the parent's body: a short one is a twig, never a blunt tooth
            beyond = length - rp
            r = np.minimum(r, max((beyond - STUB_MARGIN) / STUB_RADII, 0.5))
            r0 = min(r0, float(r[0]))
        if taper is not None and length > 0:
            r = np.minimum(r, r0 * (1.0 + (taper - 1.0) * s / length))
        # never more than twice as thick as where it starts (no bulbous end), whatever the example
        r = np.minimum(r, 2.0 * r0)
        if free[i] and r[-1] > tip:
            # the last 3 r narrow to the example's tip radius
            span = max(TIP_RADII * float(r[-1]), 1.0)
            left = length - s
            r = np.minimum(r, tip + (r - tip) * np.clip(left / span, 0.0, 1.0))
        out[i] = np.maximum(r, min(0.5, float(np.min(b.thickness))))
    return out


def _depth(bs, i: int) -> int:
    d = 0
    seen = set()
    while bs[i].parent is not None and i not in seen and 0 <= bs[i].parent < len(bs):
        seen.add(i)
        i = bs[i].parent
        d += 1
    return d


def burrs(structure: Structure, radii: list, scale: float = 1.0) -> np.ndarray:
    """Per branch: a leaf child (no children of its own) that shows less than 3 of its radii and a pixel
    (:data:`STUB_MARGIN`) beyond its parent's drawn body (``radii`` x ``scale``: the radii of
    :func:`tapered_radii` as drawn), a radius below a pixel counting as one pixel and the parent's edge
    rasterized half a pixel out: a burr on its parent's line (a comb's tooth), not a branch;
    :func:`~branchnb.branching.drawing.draw_in_style` leaves it out.

    Parameters
    ----------
    structure : Structure
        The structure drawn.
    radii : list of (N_i,) ndarray
        The radii each branch is drawn with.
    scale : float
        Pixels per structure unit.

    Returns
    -------
    (B,) bool ndarray
        Per branch, whether it is a burr.

    Examples
    --------
    >>> from branchnb.core.structure import Branch
    >>> s = Structure([Branch([(0, 10), (40, 10)], 1.0), Branch([(20, 10), (20, 13)], 0.5, 0, 1),
    ...                Branch([(30, 10), (30, 20)], 0.5, 0, 1)])
    >>> burrs(s, [b.thickness for b in s.branches]).tolist()
    [False, True, False]
    """
    bs = structure.branches
    has_kids = np.zeros(len(bs), bool)
    for b in bs:
        if b.parent is not None and 0 <= b.parent < len(bs):
            has_kids[b.parent] = True
    out = np.zeros(len(bs), bool)
    for i, b in enumerate(bs):
        if b.parent is None or has_kids[i] or len(b.points) < 2 or not 0 <= b.parent < len(bs):
            continue
        pr = np.asarray(radii[b.parent], np.float64)
        if not len(pr):
            continue
        rp = scale * float(pr[int(np.clip(b.parent_vertex or 0, 0, len(pr) - 1))]) + 0.5
        out[i] = b.length - rp < STUB_RADII * max(scale * float(np.max(radii[i])), 1.0) + STUB_MARGIN
    return out
