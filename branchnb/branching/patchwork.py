"""Grounds made of flat patches with sharp borders (beyond the paper, issue 23).

An aerial photo's patchwork of fields, a city map's blocks: the ground
between the branches is a few flat colours side by side. Such a ground has
no light to take out (its large-scale variation *is* its patches) and no
seam to hide by a gradient-domain correction (which smears one patch's
colour into the next): :func:`~branchnb.branching.synthesize_image` copies
it as it is, with graph-cut seams only (see :func:`is_patchwork`).
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

__all__ = ["bank_only", "ground_palette", "is_patchwork", "patch_diameter"]

#: Colours of the ground closer than this (RGB distance) are one patch colour (grain splits none).
MERGE = 0.06
#: A patchwork's pixels lie within this RGB distance of one of its patch colours ...
NEAR = 0.1
#: ... at least this share of them (a continuous ground, e.g. dunes or vignetting, leaves more between).
COVERAGE = 0.9
#: Smallest share of the ground a patch colour covers to count.
MIN_SHARE = 0.03
#: A pixel is clean when it lies within this fraction of the distance of the two closest patch
#: colours from one of them ...
FLATNESS = 0.25
#: ... and at least this share of a patchwork's ground is clean (a quantised ramp or texture is not).
CLEAN = 0.76
#: Grain smoothing before the ground is measured (median filter side, pixels: keeps borders sharp).
SMOOTH = 5
#: Ground a fragment keeps beside its branch on a patchwork ground (pixels beyond the branch's radius).
BANK = 2.0
#: :func:`paste_fields` lays a field cut by the example's frame against the same side of the output's
#: frame (beyond the paper, issue 23, branching103); False = left out while three whole fields exist.
FRAME_FIELDS = True
#: :func:`paste_fields` draws a field already laid ``u`` times ``(1 + u) ** -REPEAT_PENALTY`` as often.
REPEAT_PENALTY = 1.0


def _frame_shift(field, box, centre, side, hy, hx, h, w, H, W) -> tuple[int, int] | None:
    """``(dy, dx)`` that lays ``field`` ((ys, xs) in an ``h x w`` example; ``box`` its mask in its bounding
    box, ``centre`` the index of its deepest pixel, ``side`` (top, bottom, left, right) the example's frame
    sides it touches) over the ``H x W`` output's pixel (``hy``, ``hx``) with its frame cuts on the same
    sides of the output's frame; None when no such place covers that pixel.

    Examples
    --------
    >>> ys, xs = np.nonzero(np.ones((3, 4), bool))            # a field in the top-left corner of 10 x 10
    >>> _frame_shift((ys, xs), np.ones((3, 4), bool), 5, (True, False, True, False), 1, 2, 10, 10, 20, 20)
    (0, 0)
    >>> _frame_shift((ys, xs), np.ones((3, 4), bool), 5, (True, False, True, False), 9, 2, 10, 10, 20, 20) is None
    True
    >>> _frame_shift((ys, xs), np.ones((3, 4), bool), 5, (False,) * 4, 9, 2, 10, 10, 20, 20)
    (8, 1)
    """
    ys, xs = field
    dy = 0 if side[0] else (H - h if side[1] else None)
    dx = 0 if side[2] else (W - w if side[3] else None)
    if dy is None and dx is None:
        return int(hy - ys[centre]), int(hx - xs[centre])
    y0, x0 = int(ys.min()), int(xs.min())
    if dy is not None and dx is not None:
        r, c = hy - dy - y0, hx - dx - x0
        inside = 0 <= r < box.shape[0] and 0 <= c < box.shape[1] and bool(box[r, c])
        return (int(dy), int(dx)) if inside else None
    if dy is not None:   # the row it must cover; along it, the pixel nearest its deepest one
        r = hy - dy - y0
        if not 0 <= r < box.shape[0] or not box[r].any():
            return None
        cols = np.flatnonzero(box[r]) + x0
        return int(dy), int(hx - cols[np.argmin(np.abs(cols - xs[centre]))])
    c = hx - dx - x0
    if not 0 <= c < box.shape[1] or not box[:, c].any():
        return None
    rows = np.flatnonzero(box[:, c]) + y0
    return int(hy - rows[np.argmin(np.abs(rows - ys[centre]))]), int(dx)


def _smoothed(image) -> np.ndarray:
    """The colour channels of ``image`` (at most three; a grey image's one) with their grain
    smoothed away (median of ``SMOOTH`` px): (H, W, n) float32."""
    img = np.asarray(image, np.float32)
    n = 3 if img.shape[2] >= 3 else 1
    return np.dstack([cv2.medianBlur(np.ascontiguousarray(img[..., c]), SMOOTH) for c in range(n)])


def _kmeans(x: np.ndarray, k: int, iters: int = 20) -> tuple[np.ndarray, np.ndarray]:
    """Deterministic k-means of the rows of ``x`` (farthest-point start): ``(centres, labels)``.

    scikit-learn's Lloyd iterations from a farthest-point start (the first row,
    then each time the row farthest from the centres so far): one run, no
    random restarts, so the palette is the same for the same ground. Fewer
    than ``k`` centres when the rows hold fewer distinct points.
    """
    from sklearn.cluster import KMeans

    centres = [x[0]]
    d = np.linalg.norm(x - x[0], axis=1)
    for _ in range(1, k):
        j = int(np.argmax(d))
        if d[j] <= 1e-6:
            break
        centres.append(x[j])
        d = np.minimum(d, np.linalg.norm(x - x[j], axis=1))
    c = np.array(centres)
    if len(c) == 1:
        return c, np.zeros(len(x), int)
    km = KMeans(n_clusters=len(c), init=c, n_init=1, max_iter=iters, tol=1e-8, algorithm="lloyd").fit(x)
    return km.cluster_centers_, km.labels_.astype(int)


def ground_palette(image, background, k: int = 8, max_samples: int = 20000) -> tuple[np.ndarray, np.ndarray]:
    """The ground's patch colours: k-means of its (grain-smoothed) colours, clusters closer than
    :data:`MERGE` merged; ``(colours (m, 3), shares (m,))``, shares of the ground, largest first.

    Parameters
    ----------
    image : (H, W, C) float array
        The example (its first three channels are used).
    background : (H, W) bool array
        The ground's pixels.
    k : int, default 8
        Clusters before merging.
    max_samples : int, default 20000
        Ground pixels clustered (evenly strided).

    Returns
    -------
    colours : (m, n) ndarray
        n = 3 (1 for a grey image).
    shares : (m,) ndarray

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((40, 40, 3), np.float32); img[:, 20:] = 0.6
    >>> c, s = ground_palette(img, np.ones((40, 40), bool))
    >>> len(c), bool(np.allclose(s.sum(), 1.0))
    (2, True)
    """
    img = np.asarray(image, np.float32)
    bg = np.asarray(background, bool)
    if img.ndim != 3 or img.shape[:2] != bg.shape:
        raise ValueError(f"image must be (H, W, C) with background's shape {bg.shape}, got {img.shape}")
    x = _smoothed(img)[bg].astype(np.float64)
    if len(x) == 0:
        return np.zeros((0, x.shape[1])), np.zeros(0)
    x = x[:: max(len(x) // max_samples, 1)]
    c, lab = _kmeans(x, k)
    w = np.bincount(lab, minlength=len(c)).astype(float)
    # merge the closest pair until every two colours differ by MERGE (grain and shading split clusters)
    c, w = list(c), list(w)
    while len(c) > 1:
        arr = np.array(c)
        d = np.linalg.norm(arr[:, None] - arr[None], axis=2) + np.eye(len(c)) * 1e9
        i, j = np.unravel_index(int(np.argmin(d)), d.shape)
        if d[i, j] >= MERGE:
            break
        c[i] = (c[i] * w[i] + c[j] * w[j]) / (w[i] + w[j])
        w[i] += w[j]
        del c[j], w[j]
    arr, w = np.array(c), np.array(w) / max(sum(w), 1.0)
    order = np.argsort(-w)
    return arr[order], w[order]


def is_patchwork(image, background) -> bool:
    """Whether the ground (``background`` pixels of ``image``) is a patchwork of flat colours.

    True when at least two colours of :func:`ground_palette` each cover
    :data:`MIN_SHARE` of the ground, :data:`COVERAGE` of the ground lies within
    :data:`NEAR` of one of them, and inside the patches (each colour's pixels
    eroded by 3 px) the colour spreads by less than :data:`FLATNESS` of the
    distance of the two closest colours. A smooth ramp (vignetting, dunes),
    grain or blotchy texture (a forest, a fundus, clouds) is none: its
    colours merge into one, or its quantised bands are no flat patches.

    Parameters
    ----------
    image : (H, W, C) float array
        The example.
    background : (H, W) bool array
        The ground's pixels (no branch, no matte).

    Returns
    -------
    bool

    Examples
    --------
    >>> import numpy as np
    >>> img = np.full((64, 64, 3), 0.3, np.float32); img[:, 32:] = (0.7, 0.6, 0.4)
    >>> ramp = np.dstack([np.tile(np.linspace(0.2, 0.8, 64), (64, 1))] * 3).astype(np.float32)
    >>> bg = np.ones((64, 64), bool)
    >>> is_patchwork(img, bg), is_patchwork(ramp, bg)
    (True, False)
    """
    bg = np.asarray(background, bool)
    if np.count_nonzero(bg) < 256:
        return False
    colours, shares = ground_palette(image, bg)
    keep = shares >= MIN_SHARE
    if np.count_nonzero(keep) < 2:
        return False
    colours = colours[keep]
    x = _smoothed(image)
    d = np.linalg.norm(x[..., None, :] - colours[None, None].astype(np.float32), axis=-1)
    near = d.min(axis=-1)
    if float(np.mean(near[bg] <= NEAR)) < COVERAGE:
        return False
    pair = np.linalg.norm(colours[:, None] - colours[None], axis=2) + np.eye(len(colours)) * 1e9
    # flat patches with sharp borders: nearly every pixel is close to its patch's colour (a ramp or
    # a dune's slope passes through every colour between two of them)
    return bool(np.mean(near[bg] <= FLATNESS * float(pair.min())) >= CLEAN)


def patch_diameter(image, background) -> float:
    """Typical diameter (pixels) of the ground's patches: ``sqrt(ground area / number of patches)``,
    a patch being a connected piece of one :func:`ground_palette` colour of at least 0.2 % of the
    ground (0.0 without ground).

    Parameters
    ----------
    image : (H, W, C) float array
        The example.
    background : (H, W) bool array
        The ground's pixels.

    Returns
    -------
    float

    Examples
    --------
    >>> import numpy as np
    >>> img = np.zeros((64, 64, 3), np.float32); img[:32, 32:] = img[32:, :32] = 0.6
    >>> patch_diameter(img, np.ones((64, 64), bool))
    32.0
    """
    bg = np.asarray(background, bool)
    area = np.count_nonzero(bg)
    if area == 0:
        return 0.0
    colours, shares = ground_palette(image, bg)
    colours = colours[shares >= MIN_SHARE]
    if len(colours) == 0:
        return 0.0
    x = _smoothed(image)
    lab = np.argmin(np.linalg.norm(x[..., None, :] - colours[None, None].astype(np.float32), axis=-1), axis=-1)
    count = 0
    for i in range(len(colours)):
        pieces, n = ndi.label((lab == i) & bg)
        if n:
            count += int(np.count_nonzero(np.bincount(pieces.ravel())[1:] >= 0.002 * area))
    return float(np.sqrt(area / max(count, 1)))


def bank_only(out, pm, bank: float = BANK) -> None:
    """Uncover the fragments' ground beyond ``bank`` pixels of the target's branches (in place).

    Beyond the paper (issue 23). A fragment is copied with the ground of
    its disk (3 radii about its branch); on a patchwork ground that ground
    is one field's colour, which the fragment carried beside the river over
    whatever fields the output lays there: a halo of it along the river (in
    the aerial examples, a chain of dark beads). Keeping the branch and a
    bank of ``bank`` pixels (its anti-aliased rim) leaves the fields beside
    it to the gap completion, which continues the fields around.

    Parameters
    ----------
    out : _Canvas
        The fragments' canvas (``covered``, ``frag_index``, ``source`` are updated).
    pm : PixelMap
        The target structure's pixel map.
    bank : float, default BANK
        Pixels kept beyond each branch's radius.
    """
    if bank < 0:
        raise ValueError(f"bank must be >= 0, got {bank}")
    keep = (pm.dist <= pm.radius + bank) | out.body
    drop = out.covered & ~keep
    out.covered &= keep
    out.frag_index[drop] = -1
    out.source[drop] = np.nan


def _mask(ys: np.ndarray, xs: np.ndarray) -> np.ndarray:
    """The pixels (``ys``, ``xs``) as a mask of their bounding box."""
    m = np.zeros((np.ptp(ys) + 1, np.ptp(xs) + 1), bool)
    m[ys - ys.min(), xs - xs.min()] = True
    return m


def paste_fields(canvas: np.ndarray, covered: np.ndarray, example, forbidden: np.ndarray, rng=None,
                 min_area: int = 16) -> tuple[np.ndarray, np.ndarray]:
    """Fill the uncovered pixels of ``canvas`` with whole fields of the example's patchwork (in place).

    Beyond the paper (issue 23). Quilting a patchwork ground with square
    patches left the fields' borders where two patches met: a grid of
    axis-aligned edges (about a third of the ground's colour edges in the
    aerial examples, against 3-13 % in the examples' Voronoi fields). Here
    the ground is laid field by field: at the deepest uncovered pixel
    (the middle of the largest gap), a field of the example (a connected
    piece of one :func:`ground_palette` colour, its grain included), drawn
    at random by area, is laid with its own deepest pixel there; it fills
    the uncovered pixels under it. Colours are drawn by their share of the
    example's ground, fields of a colour by area (up to four draws for one that does not
    border mostly its own colour: two fields of one colour side by side
    read as one). Fields laid later are clipped by those laid
    before, so every border is a piece of some field's own outline. Fields
    that touch the example's frame are laid against the same side(s) of the
    output's frame (:data:`FRAME_FIELDS`), so their straight cut edges lie on
    the frame, never inside the ground; those cut by ``forbidden`` pixels count
    a quarter of their area (their cut edges follow the example's branches);
    a field already laid ``u`` times is drawn ``(1 + u) ** -REPEAT_PENALTY`` as
    often.

    Notes
    -----
    Beyond branching93 (issue 23, branching103): framed fields were left out
    while three others existed and laid anywhere otherwise, so a small
    example (160-256 px, 21 Voronoi fields: 8-11 reach its frame, 2-3 do
    not) was paved with its 2-3 whole fields, each laid many times (97-100 %
    of the pasted pixels in a field laid 3+ times), or with straight cut
    edges inside the ground.

    Parameters
    ----------
    canvas : (H, W, C) float32 ndarray
        The output (modified).
    covered : (H, W) bool ndarray
        Pixels already drawn (modified: all True on return, unless the example has no field).
    example : (h, w, C) float array
        The example.
    forbidden : (h, w) bool ndarray
        Example pixels never copied (branches with a margin, matte).
    rng : int or numpy.random.Generator, optional
        Seed or generator.
    min_area : int, default 16
        Smallest field used (pixels; at least 0.2 % of the ground, as for :func:`patch_diameter`).

    Returns
    -------
    filled : (H, W) bool ndarray
        Pixels filled here.
    source : (H, W, 2) float ndarray
        Example pixel (x, y) each filled pixel was copied from (NaN elsewhere).
    """
    from branchnb.core.random import as_rng

    rng = as_rng(rng)
    ex = np.asarray(example, np.float32)
    forb = np.asarray(forbidden, bool)
    H, W = covered.shape
    if canvas.shape[:2] != (H, W) or ex.shape[:2] != forb.shape or canvas.shape[2] != ex.shape[2]:
        raise ValueError(f"canvas {canvas.shape}, covered {covered.shape}, example {ex.shape} and forbidden "
                         f"{forb.shape} do not agree")
    filled = np.zeros((H, W), bool)
    source = np.full((H, W, 2), np.nan)
    ground = ~forb
    colours, shares = ground_palette(ex, ground)
    colours = colours[shares >= MIN_SHARE]
    if covered.all() or len(colours) == 0:
        return filled, source
    x = _smoothed(ex)
    lab = np.argmin(np.linalg.norm(x[..., None, :] - colours[None, None].astype(np.float32), axis=-1), axis=-1)
    fields, clean, sides = [], [], []
    h, w = forb.shape
    near_forb = ndi.binary_dilation(forb, iterations=2)
    for i in range(len(colours)):
        pieces, n = ndi.label((lab == i) & ground)
        for k, sl in enumerate(ndi.find_objects(pieces), 1):
            if sl is None:
                continue
            m = pieces[sl] == k
            if np.count_nonzero(m) < max(min_area, 0.002 * np.count_nonzero(ground)):
                continue
            ys, xs = np.nonzero(m)
            ys, xs = ys + sl[0].start, xs + sl[1].start
            side = (ys.min() == 0, ys.max() == h - 1, xs.min() == 0, xs.max() == w - 1)
            if (side[0] and side[1] and H != h) or (side[2] and side[3] and W != w):
                continue   # cut by two opposite sides of another length: no place keeps both cuts on the frame
            fields.append((ys, xs))
            sides.append(side)
            # 1: cut by the branches' margin (a curved edge, a quarter of its area); 2: whole or cut by the
            # frame only (laid against the same side of the output's frame, see FRAME_FIELDS)
            clean.append(1 if near_forb[ys, xs].any() else 2)
    if not fields:
        return filled, source
    clean = np.asarray(clean)
    framed = np.array([any(sd) for sd in sides])
    use = fields if FRAME_FIELDS else [f for f, c in zip(fields, framed) if not c]
    keep = np.ones(len(fields), bool) if FRAME_FIELDS else ~framed
    if not use:   # (FRAME_FIELDS off and every field framed: laid anywhere, as before)
        use, keep = fields, np.ones(len(fields), bool)
    sides_use = [sd if FRAME_FIELDS else (False,) * 4 for sd, k in zip(sides, keep) if k]
    area = np.array([len(f[0]) for f in use], float) * np.where(clean[keep] == 1, 0.25, 1.0)
    labels_use = np.array([lab[ys[0], xs[0]] for ys, xs in use])
    # by area (a colour whose fields mostly reach the frame is rarer than in the example: boosting
    # its few whole fields repeated one triangle and its slivers all over the ground)
    holes = ~covered
    centres, boxes = [], []
    for ys, xs in use:   # each field's deepest pixel: laid there, the field covers the gap around it
        box = _mask(ys, xs)
        d = ndi.distance_transform_edt(np.pad(box, 1))[1:-1, 1:-1]
        centres.append(int(np.argmax(d[ys - ys.min(), xs - xs.min()])))
        boxes.append(box)
    uses = np.zeros(len(use))
    out_lab = np.full((H, W), -1, int)
    out_lab[covered] = -2
    while holes.any():
        # the deepest uncovered pixel (the middle of the largest gap left): fields laid at random
        # pixels left slivers and specks between them
        depth = ndi.distance_transform_edt(holes)
        hy, hx = np.unravel_index(int(np.argmax(depth)), depth.shape)
        shift = [_frame_shift(use[f], boxes[f], centres[f], sides_use[f], hy, hx, h, w, H, W)
                 for f in range(len(use))]
        ok_f = np.array([t is not None for t in shift])
        # a field laid again is drawn less often (REPEAT_PENALTY): on a small example the few fields
        # were each laid 3+ times side by side
        wgt = np.where(ok_f, area / (1.0 + uses) ** REPEAT_PENALTY, 0.0)
        prob = wgt / wgt.sum()
        for _try in range(4):
            f = int(rng.choice(len(use), p=prob))
            ys, xs = use[f]
            dy, dx = shift[f]
            ty, tx = ys + dy, xs + dx
            ok = (ty >= 0) & (ty < H) & (tx >= 0) & (tx < W)
            ty, tx, sy, sx = ty[ok], tx[ok], ys[ok], xs[ok]
            put = holes[ty, tx]
            ty, tx, sy, sx = ty[put], tx[put], sy[put], sx[put]
            # not beside a field of its own colour (two of one colour side by side read as one field)
            ring = np.zeros((H, W), bool)
            ring[ty, tx] = True
            ring = ndi.binary_dilation(ring) & ~ring & ~holes
            if not ring.any() or np.mean(out_lab[ring] == labels_use[f]) < 0.3:
                break
        uses[f] += 1
        canvas[ty, tx] = ex[sy, sx]
        source[ty, tx, 0], source[ty, tx, 1] = sx, sy
        holes[ty, tx] = False
        filled[ty, tx] = True
        out_lab[ty, tx] = labels_use[f]
    covered |= filled
    return filled, source
