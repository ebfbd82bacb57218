"""Step 5 of the edit, the joints closed: masks and closings at joints and carried parts.

Which joints are closed wide (:func:`_turned`, :func:`_pocket`,
:func:`_thin_closing`), what the closings must leave open
(:class:`_SourcePockets`, :func:`_along_children`), the notches strokes' roots
cut into carried parts (:func:`_part_notches`, :func:`_refill_notches`) and the
rims of parts lying over others (:func:`_overlap_rims`). Used by
:func:`~branchnb.strokes.synthesis.compose_patches`.
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

from .crotches import _child_width
from .outline import _POCKET, _disk_closing
from .parts import rigid_frame

__all__: list[str] = []


def _stroke_ends(index, attached) -> list[tuple[int, np.ndarray, float]]:
    """``(stroke, point, half width)`` of every source stroke's ends."""
    out = []
    for k, p in enumerate(attached):
        w = index.half_width(k, np.array([0.0, p.source.length]))
        out += [(k, p.source.points[0], float(w[0])), (k, p.source.points[-1], float(w[1]))]
    return out


def _notch_radius(part, ends) -> int:
    """Radius (px) of the closing that finds the notches strokes' roots cut into ``part``: the
    widest half width of a stroke end within its half width (+ 2 px) of the part, the stroke it
    hangs from aside (0: none)."""
    ys, xs = np.nonzero(part.mask)
    if not len(ys):
        return 0
    pts = np.c_[xs + part.box[1].start, ys + part.box[0].start].astype(float)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    best = 0.0
    for k, q, hw in ends:
        if k == part.stroke or hw <= best or (q < lo - hw - 2.0).any() or (q > hi + hw + 2.0).any():
            continue
        if float(np.min(np.hypot(*(pts - q).T))) <= hw + 2.0:
            best = hw
    return int(np.ceil(best)) + 1 if best > 0 else 0


def _part_notches(pix: np.ndarray, valid: np.ndarray, keep, radius: int) -> np.ndarray | None:
    """Pixels of a carried part's square that close a notch in it: within its closing by a
    disk of ``radius`` px, not its own, opaque in the source there (None if none)."""
    if radius < 1 or not valid.any():
        return None
    # (a closing by a disk as two distance transforms: linear in the pixels, not in the disk's area)
    pad = radius + 2
    m = cv2.copyMakeBorder(valid.astype(np.uint8), pad, pad, pad, pad, cv2.BORDER_CONSTANT, value=0)
    grown = (cv2.distanceTransform(1 - m, cv2.DIST_L2, cv2.DIST_MASK_PRECISE) <= radius).astype(np.uint8)
    closed = cv2.distanceTransform(grown, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)[pad:-pad, pad:-pad] > radius
    notch = closed & ~valid & (pix[..., 3] > 0.5)
    if keep is not None:
        notch &= keep
    return notch if notch.any() else None


def _refill_notches(comp, placed: list, notches: list) -> None:
    """Lay a carried part's notch pixels (:func:`_part_notches`) where the composition left no
    opaque pixel, in place (``comp``'s image and labels).

    A part nobody stroked hangs round the roots of the strokes that leave it (an
    octopus's head round its tentacles): the strokes' tubes take those root pixels,
    so the part has a notch there. When a stroke turns its part away, nothing lays
    the root's place: a transparent sliver opened in the head, which the cut-face
    outline then drew as a dark wedge. The part's own source pixels there (the
    flesh the root sat in) close it. Beyond the paper.
    """
    for i, notch in notches:
        if notch is None:
            continue
        pp = placed[i]
        win = pp.window(comp.image.shape)
        if win is None:
            continue
        canvas, patch, _ = win
        sub = notch[patch]
        open_ = sub & (comp.image[canvas][..., 3] < 0.5)
        if not open_.any():
            continue
        comp.image[canvas][open_] = pp.pixels[patch][open_]
        comp.labels[canvas][open_] = i
        comp.covered[canvas] |= open_


def _overlap_rims(index, attached, junctions, placed, labels, depth, style, layer) -> np.ndarray | None:
    """Pixels of a part's rim (and the band just inside it) where another part only lies
    under it, not joined to it: None if there are none.

    A stroke whose two ends both touch other strokes hangs from one and merely touches
    the other: a copy of an arm laid across the arm's tip, a curled tentacle's tip on
    its neighbour. :func:`~branchnb.strokes.junctions.find_junctions` still makes the
    second contact a junction, and the rim of the part touched, now inside the object's
    silhouette, was repainted as the stale rim of a joint (the copy's outline across
    the arm lost). Here, within the two parts' half widths + the outline's width + 2 px
    of such a contact, the touched part's own rim pixels (source depth up to the
    outline's width + 1.5 px) are kept as they were laid. The stroke is taken to hang
    from the part at its first point (strokes drawn from their roots): the contact at
    its last point is the touch. Beyond the paper.
    """
    ends: dict = {}
    for jn in junctions:
        ends.setdefault(jn.child, set()).add((jn.end, jn.parent))
    touch = [jn for jn in junctions
             if len({e for e, _ in ends[jn.child]}) == 2
             and any(e != jn.end and p != jn.parent for e, p in ends[jn.child])
             and jn.end == 1]
    if not touch:
        return None
    stroke_of = np.array([pp.stroke if pp.stroke is not None else -1 for pp in placed] + [-1])
    rim = (depth > 0) & (depth <= style.width + 1.5) & (layer[:, :, 3] > 0.02)
    h, w = labels.shape
    out = np.zeros((h, w), bool)
    for jn in touch:
        hw = float(index.half_width(jn.parent, attached[jn.parent].source_arc_length(jn.parent_s)))
        r = hw + _child_width(index, jn.child) + style.width + 2.0
        x, y = jn.point
        r0, r1 = max(int(y - r), 0), min(int(y + r) + 2, h)
        c0, c1 = max(int(x - r), 0), min(int(x + r) + 2, w)
        if r0 >= r1 or c0 >= c1:
            continue
        yy, xx = np.ogrid[r0:r1, c0:c1]
        box = (slice(r0, r1), slice(c0, c1))
        out[box] |= (np.hypot(xx - x, yy - y) <= r) & rim[box] & (stroke_of[labels[box]] == jn.parent)
    return out if out.any() else None


class _SourcePockets:
    """``(rows, cols, k) -> bool``: result pixels copied from a pocket of the source itself.

    A pocket is what the joints' closing (a disk of ``k`` px) would fill in the
    source: the bottom of a narrow crotch. Such a pixel, copied by a patch from
    that very place, is the source's own shape, not a gap the edit opened (an
    identity edit of a finger drawn from inside its palm closed the crotches beside
    it with a thick dark notch and steps up the finger's sides). A pixel no patch
    laid (between the patches, deep in a crotch) is mapped by the patch of its
    nearest laid pixel (within ``2 k + 3`` px; none: it stays closable). The
    source's closing is computed on the box of the pixels asked about, grown by
    ``2 k + 3`` px (all the pixels it depends on).
    """

    def __init__(self, index, labels: np.ndarray, placed: list):
        self.obj = index.premult[:, :, 3] > 0.5
        self.labels, self.placed = labels, placed

    def __call__(self, rows: np.ndarray, cols: np.ndarray, k: int) -> np.ndarray:
        out = np.zeros(len(rows), bool)
        lab = self.labels[rows, cols].copy()
        g = 2 * int(k) + 3
        loose = lab < 0
        if loose.any():
            # the patch of the nearest laid pixel (on the loose pixels' box grown by g)
            lr, lc = rows[loose], cols[loose]
            H, W = self.labels.shape
            r0, r1 = max(int(lr.min()) - g, 0), min(int(lr.max()) + g + 1, H)
            c0, c1 = max(int(lc.min()) - g, 0), min(int(lc.max()) + g + 1, W)
            sub = self.labels[r0:r1, c0:c1]
            if (sub >= 0).any():
                dist, (ir, ic) = ndi.distance_transform_edt(sub < 0, return_indices=True)
                near = dist[lr - r0, lc - c0] <= g
                lab[np.flatnonzero(loose)[near]] = sub[ir[lr - r0, lc - c0], ic[lr - r0, lc - c0]][near]
        sx = np.full(len(rows), -1, np.intp)
        sy = np.full(len(rows), -1, np.intp)
        for i in np.unique(lab[lab >= 0]):
            m = self.placed[i].source_map
            if m is None:
                continue
            sel = lab == i
            x, y = cols[sel], rows[sel]
            sx[sel] = np.rint(m[0, 0] * x + m[0, 1] * y + m[0, 2]).astype(np.intp)
            sy[sel] = np.rint(m[1, 0] * x + m[1, 1] * y + m[1, 2]).astype(np.intp)
        h, w = self.obj.shape
        ok = (sx >= 0) & (sx < w) & (sy >= 0) & (sy < h)
        if not ok.any():
            return out
        r0, r1 = max(int(sy[ok].min()) - g, 0), min(int(sy[ok].max()) + g + 1, h)
        c0, c1 = max(int(sx[ok].min()) - g, 0), min(int(sx[ok].max()) + g + 1, w)
        sub = self.obj[r0:r1, c0:c1]
        pocket = _disk_closing(sub, int(k)) & ~sub
        out[ok] = pocket[sy[ok] - r0, sx[ok] - c0]
        return out


def _along_children(wide, attached, shape, where: np.ndarray | None = None, index=None) -> np.ndarray:
    """Pixels within ``3 r`` (r: the joint's closing radius, half the child's half width,
    so 1.5 child widths) of a wide joint's child target stroke, near the joint (only
    among the pixels ``where``, if given: the others are False).

    With ``index``, only pixels whose source under the parent's frame at the junction
    was the object (within 2 px): the wedge a turned child leaves at its parent's side
    was flesh (the child's old root); the V between the child and a neighbour it was
    turned toward was not (a starfish's arm turned toward the next: the closing webbed
    the V, 215 px outside the silhouette at 1000 px).
    """
    h, w = shape
    out = np.zeros((h, w), bool)
    for point, reach, r, jn in wide:
        x, y = point
        m = int(np.ceil(2 * reach)) + 2 + int(np.ceil(r))
        r0, r1, c0, c1 = max(int(y) - m, 0), min(int(y) + m + 1, h), max(int(x) - m, 0), min(int(x) + m + 1, w)
        if r0 >= r1 or c0 >= c1:
            continue
        if where is None:
            yy, xx = np.mgrid[r0:r1, c0:c1]
        else:
            yy, xx = np.nonzero(where[r0:r1, c0:c1])
            yy, xx = yy + r0, xx + c0
        if not yy.size:
            continue
        q = np.c_[xx.ravel(), yy.ravel()].astype(float)
        _, d = attached[jn.child].target.project(q)
        ok = d <= 3.0 * r
        if index is not None and ok.any():
            parent = attached[jn.parent]
            fwd = rigid_frame(parent.source, parent.target, float(parent.source_arc_length(jn.parent_s)),
                              float(jn.parent_s), window=3.0)
            sx, sy = np.rint((q[ok] - fwd[:, 2]) @ fwd[:, :2]).astype(int).T
            ok[np.flatnonzero(ok)[~_near_object(index.object, sx, sy)]] = False
        out[yy, xx] |= ok.reshape(yy.shape)
    return out


def _near_object(obj: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Whether each pixel ``(x, y)`` lies within 2 px (city block) of ``obj`` (False off the image):
    ``binary_dilation(obj, iterations=2)`` read at those pixels only."""
    h, w = obj.shape
    out = np.zeros(len(x), bool)
    for dy in range(-2, 3):
        for dx in range(-2 + abs(dy), 3 - abs(dy)):
            xx, yy = x + dx, y + dy
            on = (xx >= 0) & (xx < w) & (yy >= 0) & (yy < h) & ~out
            out[on] = obj[yy[on], xx[on]]
    return out & (x >= 0) & (x < w) & (y >= 0) & (y < h)


#: Turn (radians) of a child at its joint, relative to its parent, below which the
#: joint keeps the usual small closing (see :func:`_turned`).
_POCKET_TURN = np.radians(5.0)


def _turned(attached, jn, window: float) -> bool:
    """Whether junction ``jn``'s child leaves its parent at another angle than in the source.

    The wide closing of :func:`_pocket` fills the wedge a turned child's cut face
    leaves at its parent's side. A child that only changes length (or bends further
    out) leaves no wedge, and the closing instead webbed the crotches beside its
    root: a finger lengthened 1.4x got a 2-3 px outward jog of its outline just
    above both crotches (1000 px; beyond the paper). The turn is the change of the
    child's direction at its joined end less the parent's own turn at the joint.
    """
    child, parent = attached[jn.child], attached[jn.parent]
    s_t = 0.0 if jn.end == 0 else child.target.length
    s_s = 0.0 if jn.end == 0 else child.source.length
    w = min(window, 0.5 * child.target.length, 0.5 * child.source.length)
    turn = float(child.target.angle_at(s_t, window=w)) - float(child.source.angle_at(s_s, window=w))
    ps = float(jn.parent_s)
    turn -= float(parent.target.angle_at(ps, window=window)) - float(
        parent.source.angle_at(float(parent.source_arc_length(ps)), window=window))
    return abs(float(np.angle(np.exp(1j * turn)))) >= _POCKET_TURN


def _thin_closing(index, jn) -> float | None:
    """The closing at junction ``jn`` (None: the usual :data:`_POCKET`, 2 px): 1 px
    where the child's typical half width is under twice that.

    A 2-px closing fills gaps up to ~4 px wide: a slit between two patches
    on a large object, but on a 150-px antler (tines 1-3 px in half width) the
    gap between a new tine and its neighbour, which merged into a blob.
    Beyond the paper (whose closing is not sized at all).
    """
    if jn is None or _child_width(index, jn.child) >= 2 * _POCKET:
        return None
    return 1.0


def _pocket(index, jn) -> float | None:
    """Radius of the closing at junction ``jn``: half the child's half width where
    it leaves its parent's silhouette (None: the usual small closing).

    A child turned far from its source direction (an arm raised by 50
    degrees) has its cut face turned with it, which leaves a wedge between
    the face and the parent's side; a 2-px closing fills only the wedge's
    tip, a closing of half the child's half width rounds the joint like a
    branch collar. (Beyond the paper, whose junctions keep the source angle.)
    """
    child, parent = index.strokes[jn.child], index.strokes[jn.parent]
    t = np.arange(0.0, child.length, 1.0)
    pts = child.point_at(t if jn.end == 0 else child.length - t)
    s_par, d = parent.project(pts)
    out = np.flatnonzero(d > index.edge_width(jn.parent, s_par) + 2.0)
    if not len(out):
        return None
    q = np.rint(pts[out[0]:out[0] + 6]).astype(int)
    h, w = index.shape
    q = q[(q[:, 0] >= 0) & (q[:, 0] < w) & (q[:, 1] >= 0) & (q[:, 1] < h)]
    if not len(q):
        return None
    r = float(index.depth[q[:, 1], q[:, 0]].min()) / 2.0
    return r if r > _POCKET else None
