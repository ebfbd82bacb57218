"""Ground clutter at the trunk foot: find it and split it off the tree.

Drawn and photographed trees often stand on something: a pile of fallen
leaves, a tuft of grass, a shadow, rocks, a hill, a tray or a base disc.
The paper's exemplars are clean cut-outs; with clutter at the foot the
lowest contour point is not the trunk foot, the segmentation calls the
leaf pile crown, and every mix maps a trunk onto a leaf pile. So before
anything else the clutter is cut off (:func:`split_ground`), and the tree
alone is normalised, segmented and pinned.

The cut is geometric and reads the silhouette like a person would: the
trunk is the narrow *neck* between the crown above and whatever it stands
on below. For every row ``y`` the *neck width* ``c(y)`` is the number of
opaque pixels of row ``y`` that are connected to the crown through the rows
above ``y`` **and** to the bottom of the picture through the rows below it
(:func:`neck_profile`). A hill beside the trunk, a sun behind the island or
a frond hanging down beside the stem do not count; a leaf pile round the
trunk does, because it touches the trunk. Read from the bottom up, ``c``
is wide on the ground, narrow on the trunk (``w_t``, the median over the
narrow band) and wide again on the crown. The trunk foot is the lowest row
of the trunk, found by walking down from the narrow band while
``c(y) <= jump * w_t`` (a flared trunk base stays trunk); the tree is the
part above the foot that is connected to the crown, the ground is the rest.
Beyond that, a drawn trunk whose lowest rows carry pieces of the pile drawn
over it is drawn on down from its clean rows above them (``repaint``), so
no leaf colours or outlines stay at the foot.

No ground is reported when the bottom rows are already the trunk, when no
narrow band of at least ``min_stem_height`` of the tree height sits under
a crown, or when the wide rows at the bottom are taller than
``max_ground_height`` of the tree (a bush or a conifer whose branches reach
the ground).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_mask
from ..core.params import check_params, param
from .exemplar import tree_rgba

__all__ = ["GroundParams", "GroundSplit", "neck_profile", "split_ground", "ground_mask"]

@dataclass
class GroundParams:
    """Parameters of :func:`split_ground` (not in the paper: its exemplars have no ground).

    Parameters
    ----------
    stem_width : float
        A row is trunk while its neck width is below this fraction of the
        crown's widest row.
    jump : float
        Below the trunk, a row wider than ``jump`` times the trunk width is
        ground (a flared trunk base up to that width stays trunk, if it
        widens smoothly: by at most 25 % per row).
    min_stem_height : float
        The narrow band must be at least this fraction of the tree height.
    max_ground_height : float
        Wide bottom rows taller than this fraction of the tree are no
        ground but the tree itself (bushes, conifers).
    work_size : int
        Long side of the image the profile is computed on.

    Examples
    --------
    >>> GroundParams(jump=3.0).stem_width
    0.45
    """

    stem_width: float = param(0.45, min=0.05, max=0.95, step=0.05,
                              help="trunk rows are narrower than this fraction of the crown")
    jump: float = param(2.0, min=1.0, max=10.0, step=0.1,
                        help="ground rows are wider than this multiple of the trunk")
    min_stem_height: float = param(0.015, min=0.0, max=0.5, step=0.01,
                                   help="shortest trunk (fraction of the tree height)")
    max_ground_height: float = param(0.5, min=0.0, max=0.9, step=0.05,
                                     help="tallest ground (fraction of the height)")
    work_size: int = param(256, min=64, max=2048, step=32, help="long side of the working mask")


@dataclass
class GroundSplit:
    """A tree image split into the tree and the clutter at its foot.

    Parameters
    ----------
    tree : (H, W) bool ndarray
        Opaque pixels of the tree (crown and trunk down to the foot).
    ground : (H, W) bool ndarray
        Opaque pixels that are not the tree (empty when there is no ground).
    foot : (float, float) or None
        ``(x, y)`` of the trunk foot (middle of the trunk's lowest row),
        None without a visible trunk.
    trunk_width : float
        Neck width of the trunk band in input pixels (0 without trunk).
    stem : (H, W) bool ndarray
        The trunk as the geometry sees it: the neck pixels from the foot up
        to where the crown widens (empty without a visible trunk). Colour
        cannot find a green palm trunk or a trunk a few pixels wide; this can.
    repaint : (indices, values) pair of ndarrays or None
        Flat pixel indices and their new RGBA values, set by :meth:`cut` on
        RGBA images: a drawn trunk whose lowest rows carry the pile's leaves
        is drawn on down from its clean rows above them (beyond the paper);
        None when nothing is repainted.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((60, 40, 4), np.float32)
    >>> img[5:30, 5:35] = (0.1, 0.6, 0.1, 1); img[30:50, 18:22] = (0.4, 0.25, 0.1, 1)
    >>> img[50:56, 2:38] = (0.7, 0.4, 0.1, 1)
    >>> s = split_ground(img)
    >>> int(s.ground.sum()) > 0, float(s.cut(img)[53, 5, 3])
    (True, 0.0)
    """

    tree: np.ndarray
    ground: np.ndarray
    foot: tuple[float, float] | None
    trunk_width: float
    stem: np.ndarray | None = None
    repaint: tuple[np.ndarray, np.ndarray] | None = None

    @property
    def has_ground(self) -> bool:
        return bool(self.ground.any())

    def cut(self, image) -> np.ndarray:
        """``image`` (RGBA) with the ground made transparent (and black).

        The ground's anti-aliased rim (alpha below 0.5, within 2 px of the
        ground) goes too, so no faint outline of a cut leaf pile stays.

        Parameters
        ----------
        image : (H, W, C) array_like
            The image the split was made from (same H, W); for RGBA the rim
            rule applies, other images just get the ground pixels zeroed.

        Returns
        -------
        (H, W, C) float32 ndarray
            A copy with ground pixels set to 0 in every channel and, on RGBA
            images, the ``repaint`` pixels set; the input is not modified.
        """
        img = np.array(image, dtype=np.float32, copy=True)
        gone = self.ground
        if gone.any() and img.ndim == 3 and img.shape[2] == 4:
            near = cv2.dilate(gone.astype(np.uint8), np.ones((5, 5), np.uint8)) > 0
            gone = gone | (near & (img[:, :, 3] < 0.5) & ~self.tree)
        img[gone] = 0.0
        if self.repaint is not None and img.ndim == 3 and img.shape[2] == 4:
            img.reshape(-1, 4)[self.repaint[0]] = self.repaint[1]
        return img


def _crown_component(labels: np.ndarray, top_rows: int) -> int:
    """The label owning most pixels of the top rows (the crown)."""
    counts = np.bincount(labels[:top_rows].ravel())
    counts[0] = 0
    return int(np.argmax(counts)) if counts.max() > 0 else 0


def neck_profile(mask, *, top_fraction: float = 0.3, return_mask: bool = False):
    """Neck width ``c(y)`` of every row of a silhouette (see the module text).

    Parameters
    ----------
    mask : (H, W) array_like
        The opaque pixels.
    top_fraction : float
        The crown is the component owning most pixels of this top share of
        the rows above ``y``.

    return_mask : bool
        Also return the ``(H, W)`` mask of those pixels.

    Returns
    -------
    (H,) float64 ndarray
        Opaque pixels of each row connected both to the crown above and to
        the lowest opaque row below (8-connectivity); 0 on empty rows.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((30, 20), bool); m[2:14, 2:18] = True; m[14:24, 9:11] = True
    >>> m[24:28, 1:19] = True; m[18:24, 1:5] = True     # ground, and a rock beside the trunk
    >>> c = neck_profile(m); int(c[20]), int(c[26]), int(c[8])
    (2, 18, 16)
    """
    m = as_mask(mask, name="mask")
    h = m.shape[0]
    c = np.zeros(h)
    neck = np.zeros_like(m)
    rows = np.flatnonzero(m.any(axis=1))
    if rows.size == 0:
        return (c, neck) if return_mask else c
    y0, y1 = int(rows[0]), int(rows[-1])
    eight = np.ones((3, 3), bool)
    for y in range(y0, y1 + 1):
        if not m[y].any():
            continue
        top, _ = ndi.label(m[y0:y + 1], structure=eight)
        n_top = max(1, int(round(top_fraction * (y - y0 + 1))))
        crown = _crown_component(top, n_top)
        above = top[-1] == crown
        below, _ = ndi.label(m[y:y1 + 1], structure=eight)
        ids = np.unique(below[-1])
        ids = ids[ids > 0]
        reach = np.isin(below[0], ids)
        neck[y] = above & reach & m[y]
        c[y] = float(np.count_nonzero(neck[y]))
    return (c, neck) if return_mask else c


def _foot_row(c: np.ndarray, widths: np.ndarray, p: GroundParams) -> tuple[int | None, float, int]:
    """(foot row or None, trunk width, top row of the trunk band) from the neck profile."""
    rows = np.flatnonzero(widths > 0)
    y0, y1 = int(rows[0]), int(rows[-1])
    height = y1 - y0 + 1
    crown_w = float(widths[y0:y0 + max(1, int(0.6 * height))].max())
    narrow = p.stem_width * crown_w
    runs, n = ndi.label((c > 0) & (c < narrow))
    min_rows = max(2, p.min_stem_height * height)
    best = None  # (trunk width, top, bottom)
    for k in range(n, 0, -1):
        band = np.flatnonzero(runs == k)
        top, bottom = int(band[0]), int(band[-1])
        if bottom - top + 1 < min_rows:
            continue
        if bottom < y0 + (1.0 - p.max_ground_height) * height - 1:
            break     # the wide rows below are too tall to be ground
        # A crown must sit on the band (the pointed tip of a conifer is no trunk).
        # The crown sits right on top: a low wide patch (a leaf pile above
        # the tapering lower edge of the ground) is no crown.
        above = widths[max(y0, top - int(0.25 * height)):top]
        if np.count_nonzero(above >= narrow) < 0.1 * height:
            continue
        # The band can hold the trunk and a narrow stand below it (a tray):
        # the trunk is its narrow part.
        w_t = float(np.percentile(c[top:bottom + 1], 25))
        if bottom >= y1 - 1 and bottom - top + 1 < 0.5 * c[top:bottom + 1].max():
            continue  # the rounded bottom of a crown is no trunk
        # Of several bands the trunk is the narrowest: the others are the
        # tapering lower edge of a ground patch, or a stand.
        if best is None or w_t < best[0]:
            best = (w_t, top, bottom)
    if best is None:
        return None, 0.0, y1
    w_t, top, bottom = best
    # The foot ends the trunk's run of narrow rows, across short interruptions
    # (a grass blade or a stroke across the trunk): a leaf pile narrower than the
    # crown is one long interruption, and the tapering tail below it no trunk.
    slim = np.flatnonzero(c[top:bottom + 1] <= 1.5 * w_t)
    gaps = np.flatnonzero(np.diff(slim) > max(2.0, 0.25 * w_t) + 1)
    foot = top + int(slim[gaps[0]] if gaps.size else slim[-1])
    # Walk down while the trunk widens smoothly (a leaning or flared trunk):
    # at most 25 % (or 2 px) per row and ``jump`` times its width overall;
    # ground starts where the width jumps.
    cap = p.jump * max(w_t, c[foot])
    while (foot + 1 <= y1 and 0 < c[foot + 1] <= cap
           and c[foot + 1] <= max(1.25 * c[foot], c[foot] + 2)):
        foot += 1
    return foot, w_t, top


def _drop_side_clutter(tree: np.ndarray, stem: np.ndarray, top: int, foot: int,
                       trunk_width: float) -> np.ndarray:
    """Cut grass blades and leaves that lean on the trunk above the foot.

    In the trunk rows, whatever is neither the trunk (the neck opened with a
    horizontal line of half the trunk width, grown back by one pixel) nor
    connected to the crown above is clutter.
    """
    k = max(3, int(round(0.5 * trunk_width)))
    core = cv2.morphologyEx((stem & tree).astype(np.uint8), cv2.MORPH_OPEN, np.ones((1, k), np.uint8))
    core = cv2.dilate(core, np.ones((3, 3), np.uint8)).astype(bool) & tree
    rest = tree & ~core
    lab, n = ndi.label(rest, structure=np.ones((3, 3), bool))
    if n == 0:
        return tree
    crown_ids = np.unique(lab[:max(top, 0)])
    band = np.zeros_like(tree)
    band[max(top, 0):foot + 1] = True
    clutter = (lab > 0) & ~np.isin(lab, crown_ids) & band
    return tree & ~clutter


def _drop_foot_leaves(tree: np.ndarray, stem: np.ndarray, foreign_small: np.ndarray, y_f: int,
                      trunk_width: float) -> np.ndarray:
    """Cut leaves of the pile that overlap the lowest rows of the trunk.

    The cut at the foot row leaves the pile's pieces drawn over the trunk
    just above it (a red leaf leaning on the foot). In the last 1.5 trunk
    widths above the foot, the clutter-coloured pixels (with their
    outlines, :func:`_foreign_to_trunk`) outside the trunk's column (its
    span in the narrowest row above, plus 2 px) go, and the tree is again the piece
    connected to the crown.
    """
    h, w = tree.shape
    k = max(2, int(round(1.5 * trunk_width)))
    # The trunk's column: the narrowest tree row of the two trunk widths above the band.
    r0, r1 = max(0, y_f - 3 * k), max(1, y_f - k)
    widths = tree[r0:r1].sum(axis=1)
    if not (widths > 0).any():
        return tree
    r = r0 + int(np.argmin(np.where(widths > 0, widths, np.iinfo(np.int64).max)))
    xs = np.flatnonzero(tree[r])
    if xs[-1] - xs[0] + 1 > 2.5 * trunk_width:
        return tree
    foreign = cv2.resize(foreign_small.astype(np.uint8), (w, h), interpolation=cv2.INTER_NEAREST) > 0
    foreign = cv2.dilate(foreign.astype(np.uint8), np.ones((3, 3), np.uint8)) > 0
    col = np.zeros_like(tree)
    col[:, max(0, xs[0] - 2):xs[-1] + 3] = True
    band = np.zeros_like(tree)
    band[max(0, y_f - k):y_f + 1] = True
    out = tree & ~(foreign & band & ~col)
    lab, n = ndi.label(out, structure=np.ones((3, 3), bool))
    if n > 1:
        ys = np.flatnonzero(out.any(axis=1))
        out = lab == _crown_component(lab[ys[0]:], max(1, int(0.3 * (ys[-1] - ys[0] + 1))))
    return out


def _drop_foot_spurs(tree: np.ndarray, rgb: np.ndarray, y_f: int, trunk_width: float) -> np.ndarray:
    """Cut the thin dark spurs a cut leaves beside the trunk foot (beyond the paper; issue 24).

    The pile's leaves drawn against the foot keep their upper outlines above the foot row:
    a 2-4 px ink line sticking out sideways from the trunk's lowest rows, which every mix
    then shows as a black fleck beside its trunk foot. In the last half trunk width above the
    foot, pieces outside the trunk's column (its span in the row above, plus 1 px) that are
    mostly ink (darker than half the trunk row's median), thin (at most a quarter trunk
    width, 3 px at least) and lying sideways (1.5 times as wide as tall) go; a flared foot
    (fill-coloured or thick) and the trunk's own outline running up from it stay.
    """
    k = max(2, int(round(0.5 * trunk_width)))
    r = y_f - k - 1
    if r < 0 or not tree[r].any():
        return tree
    lum = np.asarray(rgb, np.float32) @ np.array([0.299, 0.587, 0.114], np.float32)
    xs = np.flatnonzero(tree[r])
    # the trunk's run in that row: the one under the foot's median column
    runs = np.split(xs, np.flatnonzero(np.diff(xs) > 1) + 1)
    mid = np.median(np.flatnonzero(tree[y_f])) if tree[y_f].any() else np.median(xs)
    run = min(runs, key=lambda q: 0 if q[0] <= mid <= q[-1] else min(abs(q[0] - mid), abs(q[-1] - mid)))
    col = np.zeros_like(tree)
    col[:, max(0, run[0] - 1):run[-1] + 2] = True
    band = np.zeros_like(tree)
    band[r + 1:y_f + 1] = True
    out = tree & band & ~col
    if not out.any():
        return tree
    dark = lum <= 0.5 * float(np.median(lum[r, run]))
    lab, n = ndi.label(out, structure=np.ones((3, 3), bool))
    thick = ndi.distance_transform_edt(np.pad(out, 1))[1:-1, 1:-1]
    idx = np.arange(1, n + 1)
    dark_share = ndi.mean(dark, lab, idx)
    thickness = 2 * ndi.maximum(thick, lab, idx) - 1
    # sideways: a trunk's own outline flaring at the foot runs up along the trunk instead
    sl = ndi.find_objects(lab)
    wide = np.array([(q[1].stop - q[1].start) >= max(3, 1.5 * (q[0].stop - q[0].start)) for q in sl])
    drop = (dark_share >= 0.75) & (thickness <= max(3.0, 0.25 * trunk_width)) & wide
    if not drop.any():
        return tree
    res = tree & ~np.isin(lab, idx[drop])
    lab2, n2 = ndi.label(res, structure=np.ones((3, 3), bool))
    if n2 > 1:
        ys = np.flatnonzero(res.any(axis=1))
        res = lab2 == _crown_component(lab2[ys[0]:], max(1, int(0.3 * (ys[-1] - ys[0] + 1))))
    return res


def _clean_foot(tree: np.ndarray, rgb: np.ndarray, stem: np.ndarray, stem_top: int, y_f: int,
                trunk_width: float):
    """The trunk's clean rows above the pile's pieces drawn over it (beyond the paper; issue 24).

    Leaves drawn over the trunk's lowest rows sit *inside* its column, where
    :func:`_drop_foot_leaves` (outside the column) cannot take them: a cut at the row where the
    pile widens the neck keeps their colours and outlines as a blob at the foot. The trunk's
    column and colour are read on the two to six trunk widths above the foot (its sides fitted
    as straight lines nearest the foot; the median of its middle third lighter than ink; its
    outline's width at the sides); a row is dirty where a pixel of the column inside the
    outline is opaque and farther than 25 CIELAB units from that colour (another colour, or
    ink across the trunk). Walking up from the foot over dirty rows (gaps of at most 2 rows)
    gives the lowest clean row, at most two trunk widths up: returns it with the fitted sides
    (polynomials in the row), or None when the foot is clean or cannot be read. Not read:
    curved trunks (a quarter of the rows off the straight sides by more than 1.5 px or 5 % of
    the trunk width; a palm's ring sticking out is allowed) and trunks whose rows the sides
    are fitted on are more than a quarter dirty themselves (bark in a photograph, a painted
    trunk).
    """
    h, w = tree.shape
    if trunk_width < 4:
        return None
    lab = cv2.cvtColor(np.ascontiguousarray(rgb, dtype=np.float32), cv2.COLOR_RGB2LAB)
    # the trunk's rows above the pile, followed up from two trunk widths over the foot (the
    # stem can stop short where fronds hang beside it)
    y_hi = y_f - int(np.ceil(2 * trunk_width))
    if y_hi < 0 or not tree[y_hi].any():
        return None
    xs = np.flatnonzero(stem[y_hi] & tree[y_hi]) if stem[y_hi].any() else np.flatnonzero(tree[y_hi])
    centre = float(np.median(xs))
    ys, lefts, rights = [], [], []
    for y in range(y_hi, max(-1, y_hi - int(4 * trunk_width)), -1):
        xs = np.flatnonzero(tree[y])
        runs = np.split(xs, np.flatnonzero(np.diff(xs) > 1) + 1) if xs.size else []
        run = next((q for q in runs if q[0] <= centre <= q[-1]), None)
        if run is None or not 0.6 * trunk_width <= run.size <= 1.6 * trunk_width:
            break
        ys.append(y)
        lefts.append(run[0])
        rights.append(run[-1])
        centre = 0.5 * (run[0] + run[-1])
    if len(ys) < max(6, trunk_width):
        return None
    ys, lefts, rights = np.array(ys), np.array(lefts), np.array(rights)
    # colour: the middle third of the rows (away from the outline); margin: the outline's
    # width at the sides (the run of other colours in from each side), plus 2 px
    mid = np.concatenate([lab[y, lf + (rt - lf) // 3:rt - (rt - lf) // 3 + 1]
                          for y, lf, rt in zip(ys, lefts, rights)])
    light = mid[:, 0] > 25.0
    if light.mean() < 0.5:
        return None                              # a trunk that is all ink: no colour to tell by
    colour = np.median(mid[light], axis=0)
    side = []
    for y, lf, rt in zip(ys, lefts, rights):
        same = np.flatnonzero(np.linalg.norm(lab[y, lf:rt + 1] - colour, axis=1) <= 25.0)
        if same.size:
            side += [same[0], rt - lf - same[-1]]
    if not side:
        return None
    m = int(min(np.percentile(side, 90) + 2, 0.35 * trunk_width))
    # the sides as straight lines fitted nearest the foot (a leaning or bent trunk)
    near = slice(0, max(6, int(np.ceil(2 * trunk_width))))
    fl, fr = np.polyfit(ys[near], lefts[near], 1), np.polyfit(ys[near], rights[near], 1)
    resid = np.maximum(np.abs(np.polyval(fl, ys[near]) - lefts[near]),
                       np.abs(np.polyval(fr, ys[near]) - rights[near]))
    if np.percentile(resid, 75) > max(1.5, 0.05 * trunk_width):
        return None                              # a curved trunk: no straight column to carry down

    def interior(y):
        return (max(0, int(np.ceil(np.polyval(fl, y))) + m),
                min(w - 1, int(np.floor(np.polyval(fr, y))) - m))

    def dirty(y):
        a, b = interior(y)
        if b <= a:
            return True
        px = lab[y, a:b + 1]
        bad = (np.linalg.norm(px - colour, axis=1) > 25.0) & tree[y, a:b + 1]
        return bool(bad.any())

    # the trunk's own rows the sides are fitted on must be clean (flat drawn fills, not bark)
    if np.mean([dirty(y) for y in ys[near]]) > 0.25:
        return None
    cap = int(np.ceil(2 * trunk_width))
    y, top_dirty, gap = y_f, None, 0
    while y >= y_f - cap:
        if dirty(y):
            top_dirty, gap = y, 0
        elif top_dirty is not None:
            gap += 1
            if gap > 2:
                break
        elif y < y_f - 2:
            return None                          # a clean foot
        y -= 1
    if top_dirty is None or y < y_f - cap:
        return None
    return top_dirty - 1, fl, fr


def _repaint_foot(tree: np.ndarray, image: np.ndarray, y_c: int, y_f: int, fl, fr,
                  trunk_width: float):
    """The trunk drawn on down from its clean rows above ``y_c`` to the foot ``y_f`` under the pile.

    Rows ``y_c + 1 .. y_f`` keep only the trunk's column: its run in row ``y_c`` carried down
    along the fitted sides' slopes (``fl``, ``fr``: the trunk's lean); each of its pixels takes
    the median RGBA of the pixels at the same place across the trunk in rows ``y_c - 2 .. y_c``
    (fill and both outlines), so the foot stays where the shape put it (pins do not move) and
    the pile's pieces on it go. Returns the tree mask and the ``(flat indices, RGBA values)``
    of the repainted pixels, or None for them when row ``y_c`` shows no trunk.
    """
    h, w = tree.shape
    mid = 0.5 * (np.polyval(fl, y_c) + np.polyval(fr, y_c))
    xs = np.flatnonzero(tree[y_c])
    runs = np.split(xs, np.flatnonzero(np.diff(xs) > 1) + 1) if xs.size else []
    run = min(runs, key=lambda q: 0 if q[0] <= mid <= q[-1] else min(abs(q[0] - mid), abs(q[-1] - mid)),
              default=None)
    if run is None or y_c < 2:
        return tree, None
    a0, b0 = float(run[0]), float(run[-1])
    out = tree.copy()
    pad = int(np.ceil(2 * trunk_width))
    idx, vals = [], []
    for y in range(y_c + 1, y_f + 1):
        a, b = a0 + fl[0] * (y - y_c), b0 + fr[0] * (y - y_c)
        out[y, max(0, int(min(a, a0)) - pad):min(w, int(max(b, b0)) + pad + 1)] = False
        xs = np.arange(max(0, int(round(a))), min(w - 1, int(round(b))) + 1)
        u = (xs - a) / max(b - a, 1.0)
        rows = []
        for k in range(3):                       # rows y_c - 2 .. y_c at the same place across
            yy = y_c - k
            aa, bb = a0 - fl[0] * k, b0 - fr[0] * k
            rows.append(image[yy, np.clip(np.round(aa + u * (bb - aa)).astype(int), 0, w - 1)])
        out[y, xs] = True
        idx.append(y * w + xs)
        vals.append(np.median(np.stack(rows), axis=0))
    if not idx:
        return tree, None
    return out, (np.concatenate(idx), np.concatenate(vals).astype(np.float32))


def _cut_below(tree: np.ndarray, y: int) -> np.ndarray:
    """``tree``, again the piece connected to the crown, without its rows below ``y``."""
    out = tree.copy()
    out[y + 1:] = False
    lab, n = ndi.label(out, structure=np.ones((3, 3), bool))
    if n > 1:
        ys = np.flatnonzero(out.any(axis=1))
        out = lab == _crown_component(lab[ys[0]:], max(1, int(0.3 * (ys[-1] - ys[0] + 1))))
    return out


def _profile_and_foot(small: np.ndarray, p: GroundParams):
    """(neck widths, neck mask, foot row, trunk width, band top) of a working mask.

    The profile is read on the crown's own piece: leaves or stones lying
    apart below the foot are no bottom the trunk must reach (they are
    ground all the same: the tree is the piece connected to the crown).
    """
    lab, _ = ndi.label(small, structure=np.ones((3, 3), bool))
    ys = np.flatnonzero(small.any(axis=1))
    main = lab == _crown_component(lab[ys[0]:], max(1, int(0.3 * (ys[-1] - ys[0] + 1))))
    c, neck = neck_profile(main, return_mask=True)
    foot, w_t, top = _foot_row(c, main.sum(axis=1).astype(float), p)
    return c, neck, foot, w_t, top


def _foreign_to_trunk(rgb: np.ndarray, small: np.ndarray, neck: np.ndarray, top: int,
                      foot: int) -> np.ndarray | None:
    """Pixels below the trunk's upper half whose colour is not the trunk's (with their outlines).

    A pile of leaves as narrow as the trunk does not widen the neck enough
    to be told apart by shape, but it is another colour: red, orange or
    yellow leaves round a brown trunk, a green tray under a brown one. The
    trunk colour is the median CIELAB colour of the neck between 30 % and
    60 % of the way down the trunk (away from the clutter below and fronds
    hanging beside its top), over its pixels that are not a dark outline;
    pixels below that more than 25 units from it are clutter, and so
    are the dark outline pixels round them (a drawn leaf has its own
    outline). Returns ``(foreign, trunk-coloured)`` masks, or None when the
    trunk has no colour of its own (a silhouette, a trunk that is all
    outline) or nothing looks foreign.
    """
    lab = cv2.cvtColor(np.ascontiguousarray(rgb, dtype=np.float32), cv2.COLOR_RGB2LAB)
    upper = np.zeros_like(small)
    r0 = top + int(0.3 * (foot - top))
    mid = top + max(1, int(0.6 * (foot - top)))
    upper[r0:mid] = neck[r0:mid]
    light = lab[:, :, 0] > 25.0
    ref = upper & light
    if ref.sum() < max(4, 0.3 * upper.sum()):
        return None
    colour = np.median(lab[ref], axis=0)
    below = np.zeros_like(small)
    below[mid:] = True
    far = np.linalg.norm(lab - colour, axis=2) > 25.0
    foreign = small & below & light & far
    if foreign.sum() < 4:
        return None
    # The outline round a foreign patch: dark pixels within 2 px of it.
    near = cv2.dilate(foreign.astype(np.uint8), np.ones((5, 5), np.uint8)) > 0
    foreign = foreign | (near & small & below & ~light)
    return foreign, small & light & ~far


def _visible_foot(small: np.ndarray, visible: np.ndarray, neck: np.ndarray, cover: int,
                  lowest: int) -> int:
    """Lowest row where trunk colour still shows under the clutter.

    ``cover`` is the row where the clutter starts to hide the trunk, and
    ``lowest`` the foot read from the shape alone. Grass blades or leaves
    drawn across the trunk hide it in places, but its colour shows between
    them: in the trunk's column (its span in the rows above ``cover``) the
    foot is the lowest trunk-coloured row that is connected to the trunk
    above through the column.
    """
    rows = slice(max(0, cover - 3), cover + 1)
    xs = np.flatnonzero(neck[rows].any(axis=0))
    if xs.size == 0:
        return cover
    column = np.zeros_like(small)
    column[cover:lowest + 1, xs[0]:xs[-1] + 1] = True
    column &= small
    lab, _ = ndi.label(column, structure=np.ones((3, 3), bool))
    ids = np.unique(lab[cover][lab[cover] > 0])
    shown = np.isin(lab, ids) & visible
    ys = np.flatnonzero(shown.any(axis=1))
    return int(ys[-1]) if ys.size else cover


def split_ground(image, params: GroundParams | None = None, **overrides) -> GroundSplit:
    """Split the clutter at the trunk foot (leaves, grass, shadow, rocks, hill) off a tree.

    Parameters
    ----------
    image : (H, W, 4) array_like or (H, W) bool array_like
        RGBA tree on a transparent background, or its opacity mask.
    params : GroundParams, optional
        Trunk width / jump / heights rules; None uses the defaults.
    **overrides
        Fields of ``params``.

    Returns
    -------
    GroundSplit
        ``tree`` and ``ground`` masks at the input resolution and the
        trunk foot.

    Raises
    ------
    ValueError
        No alpha channel, fully transparent or fully opaque image.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((60, 40, 4), np.float32)
    >>> img[5:30, 5:35] = (0.1, 0.6, 0.1, 1)          # crown
    >>> img[30:50, 18:22] = (0.4, 0.25, 0.1, 1)       # trunk
    >>> img[50:56, 2:38] = (0.7, 0.4, 0.1, 1)         # leaf pile
    >>> s = split_ground(img)
    >>> s.has_ground, bool(s.tree[40, 20]), bool(s.ground[53, 5]), s.foot
    (True, True, True, (19.5, 49.0))
    """
    p = check_params(params if params is not None else GroundParams())
    if overrides:
        from dataclasses import replace
        p = check_params(replace(p, **overrides))
    arr = np.asarray(image)
    rgb = None
    if arr.ndim == 2:
        mask = as_mask(arr, name="image")
        if not mask.any():
            raise ValueError("image has no opaque pixel")
    else:
        img, mask = tree_rgba(image, name="image")
        rgb = img[:, :, :3]
    h, w = mask.shape
    s = min(1.0, p.work_size / max(h, w))
    size = (max(1, round(w * s)), max(1, round(h * s)))
    small = mask if s >= 1.0 else cv2.resize(
        mask.astype(np.float32), size, interpolation=cv2.INTER_AREA) >= 0.5
    if not small.any():
        small = mask
        s = 1.0
    empty = np.zeros_like(mask)
    repaint = None
    c, neck, foot_small, w_t, top_small = _profile_and_foot(small, p)
    foreign_small = None
    if foot_small is not None and rgb is not None:
        rgb_small = rgb if s >= 1.0 else cv2.resize(rgb, (small.shape[1], small.shape[0]),
                                                    interpolation=cv2.INTER_AREA)
        cue = _foreign_to_trunk(rgb_small, small, neck, top_small, foot_small)
        if cue is not None:
            foreign, visible = cue
            again = _profile_and_foot(small & ~foreign, p)
            # Clutter lies at the foot: a cut high up the trunk is a wrong colour
            # reference (a frond hanging beside a palm's trunk), not clutter.
            if again[2] is not None and top_small + 0.6 * (foot_small - top_small) <= again[2] < foot_small:
                foot = _visible_foot(small, visible, again[1], again[2], foot_small)
                c, neck, _, w_t, _ = again
                foot_small = foot
                foreign_small = foreign
            elif again[2] is not None and again[2] >= foot_small:
                # The shape found the foot already: the clutter's leaves drawn over
                # the trunk's lowest rows still go.
                foreign_small = foreign
    if foot_small is None:
        return GroundSplit(mask.copy(), empty, None, 0.0, empty.copy())
    # The stem ends where the crown widens: walking up from the foot while
    # the neck does not widen by more than 25 % (or 2 px) per row.
    stem_top = foot_small
    while (stem_top - 1 >= top_small and c[stem_top - 1] > 0
           and c[stem_top - 1] <= max(1.25 * c[stem_top], c[stem_top] + 2)):
        stem_top -= 1
    stem_small = np.zeros_like(small)
    stem_small[stem_top:foot_small + 1] = neck[stem_top:foot_small + 1]
    stem = stem_small if s >= 1.0 else cv2.resize(
        stem_small.astype(np.uint8), (w, h), interpolation=cv2.INTER_NEAREST).astype(bool)
    rows_small = np.flatnonzero(small.any(axis=1))
    if foot_small >= rows_small[-1]:
        ys = np.flatnonzero(mask.any(axis=1))
        y_f = int(ys[-1])
        tree = mask.copy()
        ground = empty
    else:
        # Foot row at the input resolution: the bottom edge of the small row.
        y_f = min(h - 1, int(np.floor((foot_small + 1) / s)) - 1) if s < 1.0 else foot_small
        upper = mask.copy()
        upper[y_f + 1:] = False
        lab, _ = ndi.label(upper, structure=np.ones((3, 3), bool))
        ys = np.flatnonzero(upper.any(axis=1))
        top_rows = max(1, int(0.3 * (y_f - ys[0] + 1)))
        crown = _crown_component(lab[ys[0]:], top_rows)
        tree = lab == crown
        tree = _drop_side_clutter(tree, stem, int(np.floor(stem_top / s)), y_f, w_t / s)
        if foreign_small is not None:
            tree = _drop_foot_leaves(tree, stem, foreign_small, y_f, w_t / s)
        if rgb is not None:
            clean = _clean_foot(tree, rgb, stem, int(np.floor(stem_top / s)), y_f, w_t / s)
            if clean is not None:
                tree, repaint = _repaint_foot(tree, img, clean[0], y_f, clean[1], clean[2], w_t / s)
                tree = _cut_below(tree, y_f)
            tree = _drop_foot_spurs(tree, rgb, y_f, w_t / s)
        ground = mask & ~tree
    xs = np.flatnonzero(tree[y_f])
    foot = (float(np.median(xs)), float(y_f)) if xs.size else None
    if s < 1.0:  # nearest upsampling misses the trunk's edge pixels
        k = 2 * int(np.ceil(1.0 / s)) + 1
        stem = cv2.dilate(stem.astype(np.uint8), np.ones((1, k), np.uint8)).astype(bool)
    stem &= tree
    stem[y_f + 1:] = False
    if repaint is not None:
        keep = tree.ravel()[repaint[0]]
        repaint = (repaint[0][keep], repaint[1][keep])
    return GroundSplit(tree, ground, foot, w_t / s, stem, repaint)


def ground_mask(image, params: GroundParams | None = None, **overrides) -> np.ndarray:
    """Just the ground of :func:`split_ground` (an ``(H, W)`` bool mask).

    Parameters
    ----------
    image : (H, W, 4) array_like or (H, W) bool array_like
        RGBA tree on a transparent background, or its opacity mask.
    params : GroundParams, optional
        As for :func:`split_ground`; None uses the defaults.
    **overrides
        Fields of ``params`` to override.

    Returns
    -------
    (H, W) bool ndarray
        Opaque pixels at the trunk foot that are not the tree (all False
        when there is no ground).

    Raises
    ------
    ValueError
        No alpha channel, fully transparent or fully opaque image.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((60, 40, 4), np.float32)
    >>> img[5:30, 5:35] = (0.1, 0.6, 0.1, 1); img[30:50, 18:22] = (0.4, 0.25, 0.1, 1)
    >>> bool(ground_mask(img).any())
    False
    """
    return split_ground(image, params, **overrides).ground
