"""A lightning bolt over several separate objects traced along their outlines (issue 25,
dendrite40; beyond the papers).

On a word logo (thick letters on a paper ground), a row of icons or a few fruits, the bolt
of :func:`~branchnb.dendrite.main_channel.strike_weights` ran down through the object its
seed lies over and its few other branches (one tip per ``LIGHTNING_SPACING`` of the
diagonal, squared) forked inside the objects, away from their outlines: on "Oak" one
horizontal bolt along the bottom of the letters, no letter readable. A letter is read by
its outline, so where the picture's silhouette has two or more parts of at least
``OUTLINE_MIN_PART`` of the picture each (:func:`outline_parts`), the bolt's tips are laid
along every part's outline, holes included (:func:`outline_endpoints`: one per
``OUTLINE_SPACING`` of the diagonal of outline), and the band just inside the outlines is
made cheap (:func:`outline_weights`), so the branches from the main channel run along the
letters' edges to their tips. One-object pictures keep the paper's look.

The bolt's strokes across the ground between the objects are drawn as thin as its thinnest
twig (:func:`thin_on_ground`): the widest path jumped from letter to letter, and on a row of
icons a quarter of the ink lay on the paper. Parts are found on the object that differs in
colour from the frame (:func:`~branchnb.dendrite.foreground._object_mask`) where there is
one: the importance's blurred edges and a drop shadow joined the letters of "Oak" into one
blob. Objects that overlap or touch along a wide stretch are split where they differ in
colour along a sharp border (:func:`split_by_colour`, dendrite41: two overlapping fruits of
different colours, letters of two colours overlapping in a bold word), each traced on its own:
least outline coverage 0.05-0.22 -> 0.66-0.96 on 2-3 overlapping shaded fruits (white, cream,
textured grounds) and overlapping bold "OK" / "ab" in two colours at 300 and 750 px.
Touching objects of one colour are split by shape (:func:`split_by_shape`, dendrite42: a
watershed of the distance map, kept where the neck's half width is under ``SHAPE_SPLIT_NECK``
of the smaller part's inscribed radius and the part is round): least outline coverage
(ink within 4 px) before -> after at 256 / 750 px on two overlapping discs 0.08 / 0.03 ->
0.68 / 0.73, three in a row 0.05 / 0.04 -> 0.67 / 0.61, two apples 0.06 / 0.03 -> 0.76 /
0.80, a snowman 0.04 / 0.11 -> 0.77 / 0.85, two pebbles 0.07 / 0.10 -> 0.70 / 0.82, discs of
radii 1 and 0.7 0.05 / 0.05 -> 0.64 / 0.86; discs, ellipses, squares, bumpy blobs, capsules,
bananas and worms of varying width at 128-1000 px stay one part.
A piece with no neck is cut at its outline's notches (:func:`~branchnb.dendrite.strike_notch.split_at_notches`,
dendrite43): a 2 x 2 cluster of discs whose middle fills in (its deepest point in the middle)
and a bold word of one colour whose letters touch side by side (their join as wide as two
strokes). Least outline coverage (ink within 4 px of each object's own outline) before ->
after at 256 / 768 px: bold "HAM" 0.07 / 0.07 -> 0.58 / 0.84, "MOON" 0.10 / 0.07 -> 0.41 /
0.74 (its "M" and "N" were cut inside; strokes41: cut between its letters only, parts 6 -> 4,
each letter's share in its part 0.53 -> 0.99; the least coverage, on an "O" whose sides are
joins, 0.52 / 0.71 -> 0.50 / 0.71), a 2 x 2 cluster of discs 1.4 radii apart 0.17 / 0.08 ->
0.41 / 0.57 (only ~0.5 of each disc's own outline lies on the cluster's outline, the rest inside; on that share 0.51 /
0.93); single bold letters M, W (0.12-0.20) and the thin and multi-object kinds of
``_thin_check``, ``_thin_branch_check`` and ``_multi_bolt_check`` keep their parts. Limits:
letters under ``OUTLINE_MIN_PART`` of the picture (a line of small text) keep the paper's bolt;
a thin piece without a core (a pole) counts as a part but is not split.

Measured with the defaults (before -> after; the least share, over a picture's objects of at
least 2 % of it, of the outline with ink within 4 px; and the share of the ink within 3 px of
the objects): the issue's "Oak" logo (480 x 240, cream, drop shadow) 0.08 -> 0.64, 0.86 ->
0.95; bold words "FERN" (640, white) 0.15 -> 0.82, "Hi" (300, dark) 0.06 -> 0.73, "TREES"
(800, cream, shadow) 0.03 -> 0.77, "GO" (256, white) 0.17 -> 0.44, "MAPLE" (1000, dark)
0.14 -> 0.71, "ab" (200, white) 0.04 -> 0.56, "WAVE" (960, cream, shadow) 0.08 -> 0.72 (ink
inside 0.85-0.97 -> 0.95-1.00); a row of 4 icons (640 cream / 1000 dark) 0.03 / 0.03 -> 0.89
/ 0.64, ink inside 0.70 / 0.64 -> 0.92 / 0.87; 3 fruits (420, white) 0.06 -> 0.65; blobs (2
on dark 256, 4 on cream 800) 0.03 / 0.02 -> 0.88 / 0.93, ink inside 0.86 / 0.65 -> 1.00 /
0.88; ``_multi_bolt_check`` kinds at 250 / 500 px: lamp and toadstool 0.03 / 0.09 -> 0.81 /
0.61, blobs 0.06 / 0.03 -> 0.56 / 0.88, letters on a sky 0.24 / 0.14 -> 0.39 / 0.63, trees
0.03 / 0.03 -> 0.53 / 0.77 (ink inside 0.51-0.92 -> 0.89-1.00; poles, no part of 2 %,
unchanged). One-object pictures (a blob at 300 / 400 / 1000 px on white and dark) unchanged.
"""

from __future__ import annotations

import heapq

import numpy as np
from scipy import ndimage

__all__: list[str] = []

#: Smallest part of a silhouette (share of the picture) counted as an object of its own.
OUTLINE_MIN_PART = 0.02
#: Least part cut out of one connected piece of the silhouette by :func:`_shape_parts` (a share
#: of that piece, when below ``OUTLINE_MIN_PART`` of the picture; dendrite46): beads of a ring
#: (8-10 beads 1.2-1.8 radii apart, each 1-2 % of a 256-768 px picture, 10-12 % of the ring)
#: and a 3 x 3 cluster's discs (11 %) came apart in pairs or not at all under the picture's
#: floor; the 119 word cases keep their parts with 0.05.
OUTLINE_PART_SHARE = 0.05
#: ... when the piece comes apart into at least this many parts (a pole's knob, a flower's head
#: on its stem: 2; a ring of beads 6-10).
OUTLINE_PART_COUNT = 3
#: Half the widest neck (share of the diagonal) at which :func:`outline_parts` splits a part.
OUTLINE_NECK = 0.012
#: Spacing of the bolt's tips along the objects' outlines (share of the lattice's diagonal).
OUTLINE_SPACING = 0.025
#: Factor on the lattice's weights in the band inside the outlines (the branches run there).
OUTLINE_DISCOUNT = 0.15
#: Depth of that band (share of the diagonal; at least 1 px).
OUTLINE_BAND = 0.008


def outline_parts(sil: np.ndarray, min_part: float = OUTLINE_MIN_PART,
                  neck: float = OUTLINE_NECK, image: np.ndarray | None = None) -> np.ndarray:
    """Label image of a silhouette's parts of at least ``min_part`` of the picture each (0
    elsewhere): its 8-connected pieces, split where they join through a neck narrower than
    ``2 x neck`` of the diagonal (letters and fruits whose blurred edges or shadows touch),
    every pixel going to the nearest part; then split by colour (with ``image``), where
    round parts meet at a neck much narrower than each (:func:`split_by_shape`: two
    overlapping discs, apples side by side) and, with no neck, at the outline's notches
    (:func:`~branchnb.dendrite.strike_notch.split_at_notches`: a 2 x 2 cluster of discs,
    the touching letters of a bold word); a ring of round parts round a hole is first cut
    from its outline's notches to the hole's corners
    (:func:`~branchnb.dendrite.strike_notch.split_round_hole`). A part cut out of one
    connected piece by shape may be as small as ``OUTLINE_PART_SHARE`` of that piece when
    that is under ``min_part`` of the picture and the piece comes apart into at least
    ``OUTLINE_PART_COUNT`` parts (the beads of a ring, dendrite46); separate pieces under
    ``min_part`` still fall out.

    Parameters
    ----------
    sil : (H, W) bool ndarray
        The silhouette (objects found on their ground).
    min_part : float
        Least area of a part, as a share of the picture.
    neck : float
        Half width of a neck that splits two parts, as a share of the diagonal.
    image : (H, W, 3) ndarray, optional
        The picture on the silhouette's grid: a part made of two regions of different colour
        meeting along a sharp border (two overlapping fruits, touching letters of two colours)
        is split along it (:func:`split_by_colour`). None keeps the shape alone.

    Returns
    -------
    (H, W) int ndarray
        Part labels 1..n, 0 elsewhere.

    Examples
    --------
    >>> m = np.zeros((40, 40), bool); m[2:20, 2:10] = True; m[2:20, 20:30] = True; m[35, 35] = True
    >>> int(outline_parts(m).max())
    2
    >>> m[10, 10:20] = True  # joined by a 1-px bridge: still two parts
    >>> int(outline_parts(m).max())
    2
    """
    s = np.asarray(sil, bool)
    if s.ndim != 2:
        raise ValueError(f"sil must be 2-D, got shape {s.shape}")
    r = max(1, int(round(neck * float(np.hypot(*s.shape)))))
    disk = np.hypot(*np.mgrid[-r:r + 1, -r:r + 1]) <= r
    comp, n = ndimage.label(s, structure=np.ones((3, 3), bool))
    lab = np.zeros(s.shape, np.int64)
    count = 0
    for k, box in enumerate(ndimage.find_objects(comp), 1):
        piece = comp[box] == k
        core = ndimage.binary_erosion(np.pad(piece, r), disk)[r:-r, r:-r]
        cores, m = ndimage.label(core, structure=np.ones((3, 3), bool))
        if m < 2:  # one part (a thin piece without a core too: a separate object all the same)
            lab[box][piece] = count + 1
            count += 1
            continue
        # every pixel of the piece goes to its nearest core; the cores whose share stays
        # under min_part (a toadstool's cap cut from its stem) give theirs to the others
        _, (iy, ix) = ndimage.distance_transform_edt(cores == 0, return_indices=True)
        sub = np.where(piece, cores[iy, ix], 0)
        big = np.flatnonzero(np.bincount(sub.ravel(), minlength=m + 1)[1:] >= min_part * s.size) + 1
        if big.size < 2:
            lab[box][piece] = count + 1
            count += 1
            continue
        cores = np.where(np.isin(cores, big), cores, 0)
        _, (iy, ix) = ndimage.distance_transform_edt(cores == 0, return_indices=True)
        lab[box][piece] = count + cores[iy, ix][piece]
        count += m
    if image is not None:
        img = np.asarray(image, np.float64)
        if img.ndim != 3 or img.shape[:2] != s.shape or img.shape[2] < 3:
            raise ValueError(f"image must be (H, W, 3) on sil's grid {s.shape}, got {img.shape}")
        lab, count = _colour_parts(lab, count, img[..., :3], min_part)
    # after the colours: where two objects differ in colour their border is sharper than
    # the distance map's watershed line
    floor = _piece_floor(lab, s, min_part)
    cut, cut_count = _shape_parts(lab, count, min_part, floor)
    # parts under min_part of the picture stand only where their piece comes apart into
    # several (a ring of beads, a cluster): a pole's knob, a flower's head on its stem and
    # two small cores joined by a neck stay with the rest of their piece
    comp, _ = ndimage.label(s, structure=np.ones((3, 3), bool))
    sizes = np.bincount(cut.ravel())
    again = False
    for k, box in enumerate(ndimage.find_objects(comp), 1):
        where = comp[box] == k
        ks = np.unique(cut[box][where])
        if ks.size < OUTLINE_PART_COUNT and (sizes[ks] < min_part * s.size).any():
            mine = np.unique(lab[box][where])
            if (floor[mine] < min_part * s.size).any():
                floor[mine] = min_part * s.size
                again = True
    lab, count = _shape_parts(lab, count, min_part, floor) if again else (cut, cut_count)
    sizes = np.bincount(lab.ravel())
    # a part cut out of a piece by shape stands at the piece's floor (a bead of a ring); a
    # piece under min_part of the picture (a line of small text) still falls out
    keep = np.flatnonzero(sizes >= _piece_floor(lab, s, min_part))
    keep = keep[keep > 0]
    out = np.zeros_like(lab)
    for i, k in enumerate(keep, 1):
        out[lab == k] = i
    return out


#: Widest neck (its half width over the smaller part's inscribed radius) at which
#: :func:`split_by_shape` splits two parts.
SHAPE_SPLIT_NECK = 0.85
#: Largest area of a part that :func:`split_by_shape` splits off, over that of its inscribed
#: disc (a disc 1, an ellipse of aspect a: a; an egg overlapped by its twin ~1.2).
SHAPE_SPLIT_ROUND = 2.0
#: Least inscribed radius (px) of a part that :func:`split_by_shape` splits off: below it the
#: distance map's steps (1, 1.4, 2 px) are as large as a neck.
SHAPE_SPLIT_DEPTH = 3.0


def _basin_necks(basins: np.ndarray, depth: np.ndarray, n: int) -> list[dict[int, float]]:
    """Per basin 1..n of ``basins``: its touching basins and the neck between each pair, the
    deepest pair of touching pixels across their border (the shallower of the two)."""
    h, w = basins.shape
    keys, values = [], []
    for dy, dx in ((0, 1), (1, 0), (1, 1), (1, -1)):
        here = (slice(0, h - dy), slice(max(0, -dx), w - max(0, dx)))
        there = (slice(dy, h), slice(max(0, dx), w - max(0, -dx)))
        a, b = basins[here], basins[there]
        cross = (a != b) & (a > 0) & (b > 0)
        lo = np.minimum(a[cross], b[cross]).astype(np.int64)
        hi = np.maximum(a[cross], b[cross]).astype(np.int64)
        keys.append(lo * (n + 1) + hi)
        values.append(np.minimum(depth[here], depth[there])[cross])
    keys, values = np.concatenate(keys), np.concatenate(values)
    necks: list[dict[int, float]] = [{} for _ in range(n + 1)]
    if keys.size:
        unique, inverse = np.unique(keys, return_inverse=True)
        deepest = np.full(unique.size, -1.0)
        np.maximum.at(deepest, inverse, values)
        for key, v in zip(unique.tolist(), deepest.tolist()):
            a, b = divmod(key, n + 1)
            necks[a][b] = necks[b][a] = v
    return necks


def split_by_shape(piece: np.ndarray, least: float, neck: float = SHAPE_SPLIT_NECK) -> np.ndarray | None:
    """Labels (1..n; 0 off ``piece``) of ``piece`` split where it narrows into a neck between
    two round parts (two overlapping discs, fruits side by side), or None when it is one.

    The piece's distance map is cut into the basins of its maxima (a watershed; maxima
    within 1 px of a higher one are one), then neighbouring basins are merged, the pair
    with the widest neck first, while the neck's half width (the highest depth along their
    border) reaches ``neck`` of the smaller one's deepest point: a limb, a pole or a
    stroke off a blob (its border as deep as it is) and bumps on an outline stay with it;
    so does a basin over ``SHAPE_SPLIT_ROUND`` times the area of its inscribed disc (a
    stretch of a worm or a stroke whose width varies: its narrow places are no necks
    between round parts).
    Basins under ``least`` pixels or ``SHAPE_SPLIT_DEPTH`` deep go to the neighbour they
    share the widest neck with.

    Parameters
    ----------
    piece : (H, W) bool ndarray
        One connected part of a silhouette.
    least : float
        Least pixels of a part.
    neck : float
        Widest neck that splits, as a share of the smaller part's inscribed radius (two
        discs of radius R with centres ``d`` apart have ``sqrt(1 - (d / 2R)^2)``: 0.85 at
        ``d = 1.05 R``; with 0.8 two bumpy discs 1.4 R apart at 128 px, their inscribed
        radii below R, stayed one).

    Returns
    -------
    (H, W) int ndarray or None

    Notes
    -----
    Beyond the papers (dendrite42): objects of one colour touching along a wide stretch
    (overlapping discs, two apples side by side) were one part, and the bolt traced them as
    one (their least outline coverage 0.05-0.3). Letters of a bold word touching side by
    side are not split here (their join is as wide as two strokes, no neck), nor is a 2 x 2
    cluster of discs (its middle is its deepest point):
    :func:`~branchnb.dendrite.strike_notch.split_at_notches` cuts those.

    Examples
    --------
    >>> y, x = np.mgrid[0:60, 0:100]
    >>> two = (np.hypot(x - 33, y - 30) < 22) | (np.hypot(x - 67, y - 30) < 22)
    >>> out = split_by_shape(two, 300)
    >>> int(out.max()), int(out[30, 20]), int(out[30, 80])
    (2, 1, 2)
    >>> split_by_shape(np.hypot(x - 50, (y - 30) * 2.5) < 45, 300) is None  # an ellipse
    True
    """
    from skimage.morphology import h_maxima
    from skimage.segmentation import watershed

    piece = np.asarray(piece, bool)
    if piece.sum() < 2 * least:
        return None
    depth = ndimage.distance_transform_edt(np.pad(piece, 1))[1:-1, 1:-1]
    if depth.max() < 2 * SHAPE_SPLIT_DEPTH:
        return None
    peaks = h_maxima(depth, 1.0)
    markers, n = ndimage.label(peaks, np.ones((3, 3), bool))
    if n < 2:
        return None
    basins = watershed(-depth, markers, mask=piece)
    top = np.zeros(n + 1)
    np.maximum.at(top, basins.ravel(), depth.ravel())
    size = np.bincount(basins.ravel(), minlength=n + 1).astype(float)
    necks = _basin_necks(basins, depth, n)
    owner = np.arange(n + 1)
    alive = np.ones(n + 1, bool)
    alive[0] = False
    version = np.zeros(n + 1, np.int64)

    def merge(a: int, b: int) -> None:
        for c, v in necks[b].items():
            del necks[c][b]
            if c != a and v > necks[a].get(c, -1.0):
                necks[a][c] = necks[c][a] = v
        necks[b] = {}
        top[a] = max(top[a], top[b])
        size[a] += size[b]
        alive[b] = False
        owner[owner == b] = a
        version[a] += 1

    def is_long(k: int) -> bool:
        # a long basin (a stretch of a stroke whose width varies) is no round part
        return bool(size[k] > SHAPE_SPLIT_ROUND * np.pi * top[k] ** 2)

    def entry(a: int, b: int) -> tuple:
        a, b = min(a, b), max(a, b)
        ratio = np.inf if is_long(a) or is_long(b) else necks[a][b] / max(min(top[a], top[b]), 1e-9)
        return (-ratio, a, b, int(version[a]), int(version[b]))

    # the widest neck first: a heap whose entries go stale when one of their basins grows (the
    # dense all-pairs search this replaces took minutes on speckled pieces of thousands of basins)
    heap = [entry(a, b) for a in range(1, n + 1) for b in necks[a] if a < b]
    heapq.heapify(heap)
    while heap:
        neg, a, b, va, vb = heapq.heappop(heap)
        if not (alive[a] and alive[b]) or va != version[a] or vb != version[b]:
            continue
        if -neg < neck:
            break
        merge(a, b)
        for c in necks[a]:
            heapq.heappush(heap, entry(a, c))
    while alive.sum() > 1:  # too small or too shallow to stand alone: to its widest neck
        weak = np.flatnonzero(alive & ((size < least) | (top < SHAPE_SPLIT_DEPTH)))
        if weak.size == 0:
            break
        b = int(weak[np.argmin(size[weak])])
        if not necks[b]:
            break
        merge(max(necks[b], key=lambda c: (necks[b][c], -c)), b)
    if alive.sum() < 2:
        return None
    keep = np.flatnonzero(alive)
    relabel = np.zeros(n + 1, np.int64)
    relabel[keep] = np.arange(1, keep.size + 1)
    return np.where(piece, relabel[owner[basins]], 0)


def _piece_floor(lab_img: np.ndarray, sil: np.ndarray, min_part: float) -> np.ndarray:
    """Per part label of ``lab_img``: the least pixels of a part cut out of it by shape,
    ``min_part`` of the picture or ``OUTLINE_PART_SHARE`` of the connected piece of ``sil``
    it lies in, whichever is less, when that piece holds ``min_part`` of the picture (else
    ``min_part`` of the picture: small separate pieces are no parts)."""
    big = min_part * sil.size
    comp, _ = ndimage.label(sil, structure=np.ones((3, 3), bool))
    area = np.bincount(comp.ravel()).astype(float)
    floor = np.full(int(lab_img.max()) + 1, big)
    for k, box in enumerate(ndimage.find_objects(lab_img), 1):
        if box is None:
            continue
        where = lab_img[box] == k
        a = float(area[np.bincount(comp[box][where]).argmax()])
        if a >= big:
            floor[k] = min(big, OUTLINE_PART_SHARE * a)
    return floor


def _shape_parts(lab_img: np.ndarray, count: int, min_part: float,
                 floor: np.ndarray | None = None) -> tuple[np.ndarray, int]:
    """The part labels ``lab_img`` (1..count) with every part split by shape
    (:func:`split_by_shape`, else
    :func:`~branchnb.dendrite.strike_notch.split_at_notches`), and their parts again; a
    part's sides hold at least ``floor[label]`` pixels (``min_part`` of the picture without
    ``floor``), and the floor of a part's sides is its own."""
    from .strike_notch import split_at_notches, split_round_hole

    big = min_part * lab_img.size
    if floor is None:
        floor = np.full(count + 1, big)
    floor = list(np.asarray(floor, float))
    out = lab_img.copy()
    # a piece with no neck may still come apart at its outline's notches (a 2 x 2 cluster of
    # discs, a bold word), and its sides again, at a neck or at notches (dendrite43)
    todo = [(k, 0) for k in range(1, count + 1)]
    while todo:
        k, depth = todo.pop()
        piece = out == k
        least = floor[k]
        if depth >= 8 or piece.sum() < 2 * least:
            continue
        box = ndimage.find_objects(piece.astype(np.int8))[0]
        # a ring round a hole first: the watershed merges two of its parts where its necks
        # are wide (strokes41)
        split = split_round_hole(piece[box], least)
        if split is None:
            split = split_by_shape(piece[box], least)
        if split is None:
            split = split_at_notches(piece[box], least)
            if split is None:
                continue
        sub = out[box]
        for j in range(2, int(split.max()) + 1):
            count += 1
            sub[split == j] = count
            floor.append(least)
            todo.append((count, depth + 1))
        todo.append((k, depth + 1))
    return out, count


#: Least colour difference (CIE Lab Delta E) between two regions of a part that
#: :func:`split_by_colour` splits.
COLOUR_SPLIT_DE = 20.0
#: Least steepness of their border: the Lab gradient (Gaussian, 1 px) along it over the two
#: regions' difference (a step blurred over ~2 px gives ~0.3; a shade across the object ~0).
COLOUR_SPLIT_STEP = 0.12


def split_by_colour(piece: np.ndarray, lab: np.ndarray, least: float) -> np.ndarray | None:
    """Labels (1, 2; 0 off ``piece``) of ``piece`` split into two regions of different colour
    meeting along a sharp border, or None when it is one colour (or a shade, or a texture).

    The piece's colours (CIE Lab, away from its 1-px rim where they blend with the ground)
    are cut in two by Otsu's threshold along their main axis; the cut stands when the two
    means differ by at least ``COLOUR_SPLIT_DE``, their border is a step (its Lab gradient at
    least ``COLOUR_SPLIT_STEP`` of that difference: a shade or a lit side is not) and each
    region holds a core of at least ``least`` pixels once opened (a texture's speckles do
    not). Every pixel of the piece then goes to the nearest core.

    Parameters
    ----------
    piece : (H, W) bool ndarray
        One connected part of a silhouette.
    lab : (H, W, 3) ndarray
        The picture in CIE Lab.
    least : float
        Least pixels of a region.

    Returns
    -------
    (H, W) int ndarray or None

    Examples
    --------
    >>> from skimage.color import rgb2lab
    >>> img = np.ones((40, 60, 3)); img[5:35, 5:30] = (0.8, 0.1, 0.1); img[5:35, 30:55] = (0.1, 0.2, 0.8)
    >>> m = np.zeros((40, 60), bool); m[5:35, 5:55] = True
    >>> out = split_by_colour(m, rgb2lab(img), 100)
    >>> int(out[20, 10]), int(out[20, 50])
    (1, 2)
    >>> img[5:35, 5:55] = np.linspace(0.2, 0.8, 50)[None, :, None]  # a shade: one part
    >>> split_by_colour(m, rgb2lab(img), 100) is None
    True
    """
    from skimage.filters import threshold_otsu

    inner = ndimage.binary_erosion(piece)
    if inner.sum() < 2 * least:
        return None
    x = lab[inner]
    mean = x.mean(0)
    _, _, vt = np.linalg.svd(x - mean, full_matrices=False)
    proj = (lab - mean) @ vt[0]
    pv = proj[inner]
    if np.ptp(pv) < COLOUR_SPLIT_DE:
        return None
    t = threshold_otsu(pv)
    hi = inner & (proj > t)
    lo = inner & (proj <= t)
    if not hi.any() or not lo.any():
        return None
    diff = float(np.linalg.norm(lab[hi].mean(0) - lab[lo].mean(0)))
    if diff < COLOUR_SPLIT_DE:
        return None
    border = hi & ndimage.binary_dilation(lo)
    grad = np.sqrt(sum(ndimage.gaussian_gradient_magnitude(lab[..., c], 1.0) ** 2 for c in range(3)))
    if float(np.median(grad[border])) < COLOUR_SPLIT_STEP * diff:
        return None
    r = max(1, int(round(0.25 * np.sqrt(least / np.pi))))
    disk = np.hypot(*np.mgrid[-r:r + 1, -r:r + 1]) <= r
    cores = np.zeros(piece.shape, np.int64)
    n = 0
    for side in (lo, hi):
        comp, k = ndimage.label(ndimage.binary_opening(side, disk), np.ones((3, 3), bool))
        sizes = np.bincount(comp.ravel())[1:]
        for i in np.flatnonzero(sizes >= least) + 1:
            n += 1
            cores[comp == i] = n
    if n < 2:
        return None
    _, (iy, ix) = ndimage.distance_transform_edt(cores == 0, return_indices=True)
    return np.where(piece, cores[iy, ix], 0)


def _colour_parts(lab_img: np.ndarray, count: int, rgb: np.ndarray,
                  min_part: float) -> tuple[np.ndarray, int]:
    """The part labels ``lab_img`` (1..count) with every part split by colour
    (:func:`split_by_colour`, again on the pieces, up to three times)."""
    from skimage.color import rgb2lab

    lab = rgb2lab(np.clip(rgb, 0.0, 1.0))
    least = min_part * lab_img.size
    out = lab_img.copy()
    todo = [(k, 0) for k in range(1, count + 1)]
    while todo:
        k, depth = todo.pop()
        piece = out == k
        if depth >= 3 or piece.sum() < 2 * least:
            continue
        box = ndimage.find_objects(piece.astype(np.int8))[0]
        split = split_by_colour(piece[box], lab[box], least)
        if split is None:
            continue
        sub = out[box]
        for j in range(2, int(split.max()) + 1):
            count += 1
            sub[split == j] = count
            todo.append((count, depth + 1))
        todo.append((k, depth + 1))
    return out, count


def _band(content: np.ndarray, parts: np.ndarray) -> np.ndarray:
    """The band inside the outlines (holes included) of the content within the parts."""
    inner = content & (parts > 0)
    depth = ndimage.distance_transform_edt(np.pad(inner, 1))[1:-1, 1:-1]
    reach = max(1.0, OUTLINE_BAND * float(np.hypot(*content.shape)))
    return inner & (depth <= reach)


def outline_weights(strike: np.ndarray, weights: np.ndarray, content: np.ndarray,
                    parts: np.ndarray) -> np.ndarray:
    """The bolt's weights ``strike`` (:func:`~branchnb.dendrite.main_channel.strike_weights`:
    its channel a highway, the outline band and the ground costly) with the band inside the
    parts' outlines at ``OUTLINE_DISCOUNT`` of the lattice's own ``weights`` instead.

    Parameters
    ----------
    strike : (h, w) ndarray
        The bolt's lattice weights.
    weights : (h, w) ndarray
        The lattice's own weights.
    content : (h, w) bool ndarray
        The objects' pixels on the lattice.
    parts : (h, w) int ndarray
        Their part labels (:func:`outline_parts`).

    Returns
    -------
    (h, w) ndarray
        The weights with the outline band discounted.

    Examples
    --------
    >>> c = np.zeros((30, 30), bool); c[5:25, 5:25] = True
    >>> w = outline_weights(np.full((30, 30), 9.0), np.ones((30, 30)), c, c.astype(int))
    >>> float(w[5, 15]), float(w[15, 15])
    (0.15, 9.0)
    """
    s = np.asarray(strike, np.float64)
    w = np.asarray(weights, np.float64)
    if s.shape != w.shape or s.shape != np.shape(content) or s.shape != np.shape(parts):
        raise ValueError(f"strike, weights, content and parts must share a shape, got "
                         f"{s.shape}, {w.shape}, {np.shape(content)}, {np.shape(parts)}")
    band = _band(np.asarray(content, bool), np.asarray(parts))
    out = s.copy()
    # the channel stays a highway where it crosses the band
    out[band] = np.where(s[band] == 0.0, 0.0, OUTLINE_DISCOUNT * w[band])
    return out


def outline_endpoints(content: np.ndarray, parts: np.ndarray, rng=None) -> np.ndarray:
    """Tips ``(x, y)`` along the outlines of the content within each part, one per
    ``OUTLINE_SPACING`` of the diagonal (at least 3 per part), greedily spread from a
    random order so that no two lie closer than the spacing.

    Parameters
    ----------
    content : (h, w) bool ndarray
        The objects' pixels.
    parts : (h, w) int ndarray
        Their part labels (:func:`outline_parts`).
    rng : int or numpy.random.Generator, optional
        Seed of the random order.

    Returns
    -------
    (E, 2) float ndarray
        Tips ``(x, y)``.

    Examples
    --------
    >>> c = np.zeros((100, 100), bool); c[10:40, 10:40] = c[60:90, 60:90] = True
    >>> e = outline_endpoints(c, outline_parts(c), rng=0)
    >>> len(e) >= 6, bool(np.all(c[e[:, 1].astype(int), e[:, 0].astype(int)]))
    (True, True)
    """
    gen = np.random.default_rng(rng)
    c = np.asarray(content, bool)
    spacing = max(2.0, OUTLINE_SPACING * float(np.hypot(*c.shape)))
    out = []
    for k in range(1, int(parts.max()) + 1):
        inner = c & (parts == k)
        edge = inner & ~ndimage.binary_erosion(inner)
        ys, xs = np.nonzero(edge)
        if xs.size == 0:
            continue
        order = gen.permutation(xs.size)
        gap = min(spacing, xs.size / 3.0)  # a small part's outline still gets ~3 tips
        # a tip blocks the disc of radius ``gap`` round it (painted on a mask: an outline of
        # thousands of pixels and a hundred tips)
        r = int(np.ceil(gap))
        disc = np.hypot(*np.mgrid[-r:r + 1, -r:r + 1]) < gap
        blocked = np.zeros((c.shape[0] + 2 * r, c.shape[1] + 2 * r), bool)
        chosen: list[tuple[float, float]] = []
        for i in order:
            x, y = int(xs[i]), int(ys[i])
            if blocked[y + r, x + r]:
                continue
            chosen.append((float(x), float(y)))
            blocked[y:y + 2 * r + 1, x:x + 2 * r + 1] |= disc
        out.extend(chosen)
    return np.asarray(out, np.float64).reshape(-1, 2)


def thin_on_ground(dendrite, objects: np.ndarray):
    """``dendrite`` (on the lattice of ``objects``) with its strokes across the ground between
    the objects no wider than its thinnest twig.

    Beyond the papers: the bolt's main path, widest, jumped from letter to letter across the
    paper, and the arcs between a row of icons took a quarter of the ink; drawn as thin as a
    twig they join the objects without hiding their outlines.

    Parameters
    ----------
    dendrite : Dendrite
        The traced bolt with its radii.
    objects : (h, w) bool ndarray
        The objects on the dendrite's lattice.

    Returns
    -------
    Dendrite
        The same dendrite with its ground strokes thinned.

    Examples
    --------
    >>> from branchnb.dendrite import build_dendrite, make_lattice, plan
    >>> d = build_dendrite(plan(make_lattice(np.ones((5, 20)), rng=0), (1, 2)), [(18, 2)])
    >>> d = d.with_radius(np.linspace(3, 1, d.n_nodes))
    >>> m = np.zeros((5, 20), bool); m[:, :4] = m[:, 15:] = True
    >>> r = thin_on_ground(d, m).radius; gap = (d.points[:, 0] > 5) & (d.points[:, 0] < 13)
    >>> float(r.max()), bool(gap.any() and np.all(r[gap] == 1.0))
    (3.0, True)
    """
    obj = np.asarray(objects, bool)
    if dendrite.n_nodes == 0 or not obj.any():
        return dendrite
    # a pixel of slack: the lattice's points round onto the outline's either side
    near = ndimage.binary_dilation(obj, iterations=1)
    xy = np.rint(dendrite.points).astype(int)
    x = np.clip(xy[:, 0], 0, obj.shape[1] - 1)
    y = np.clip(xy[:, 1], 0, obj.shape[0] - 1)
    r = np.asarray(dendrite.radius, np.float64).copy()
    ground = ~near[y, x]
    r[ground] = np.minimum(r[ground], float(r.min()))
    return dendrite.with_radius(r)
