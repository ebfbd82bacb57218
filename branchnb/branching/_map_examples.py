"""Procedural map-like examples with a known answer (tests, notebook, bench).

``river_map_example`` draws a drainage map: an island of flat land colour in
a flat sea, with many separate river trees that start at the coast and
climb inland, drawn with :func:`branchnb.core.render.draw_polylines` from a
procedurally grown forest, so the true structure (several roots on the
coast) is known. ``delta_mask_example`` draws a binary water mask of a
braided delta: white channels of very different widths on black, with a
white sea along the bottom, and returns the true centre lines and radii.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.polyline import resample_uniform
from ..core.random import as_rng
from ..core.render import draw_polylines
from ..core.structure import Branch, Structure

__all__ = ["LAND", "SEA", "RIVER", "FLOODPLAIN", "ATLAS_RIVER", "INK", "coast_mask", "country_map_example",
           "crack_pattern_example", "delta_mask_example",
           "floodplain_bands", "floodplain_map_example", "island_mask", "line_scores", "river_map_example",
           "terrain_map_example"]

LAND = (0.93, 0.89, 0.76)
SEA = (0.62, 0.80, 0.93)
RIVER = (0.08, 0.33, 0.72)
FLOODPLAIN = (0.74, 0.86, 0.58)
ATLAS_RIVER = (0.0, 0.55, 0.83)
INK = (0.0, 0.0, 0.0)


def island_mask(shape, rng, *, size: float = 0.36) -> np.ndarray:
    """A smooth irregular island (True) in the middle of the frame; the sea touches every border."""
    rng = as_rng(rng)
    h, w = shape
    yy, xx = np.mgrid[0:h, 0:w]
    cx, cy = w / 2 + rng.normal(0, 0.03 * w), h / 2 + rng.normal(0, 0.03 * h)
    ang = np.arctan2(yy - cy, xx - cx)
    rad = np.hypot((xx - cx) / w, (yy - cy) / h)
    edge = np.full(ang.shape, size)
    for k in (2, 3, 5):
        edge += rng.uniform(0.015, 0.035) * np.cos(k * ang + rng.uniform(0, 2 * np.pi))
    return rad < edge


def coast_mask(shape, rng, layout: str = "island") -> np.ndarray:
    """Land (True) of a drawn map: ``"island"`` (sea on every side), ``"coast"`` (land on top, a
    wavy coast, sea below) or ``"bay"`` (land on three sides around a bay opening to the bottom)."""
    rng = as_rng(rng)
    h, w = shape
    if layout == "island":
        return island_mask(shape, rng)
    yy, xx = np.mgrid[0:h, 0:w]
    if layout == "coast":
        t = xx / w
        y0 = 0.72 + sum(rng.uniform(0.02, 0.05) * np.sin(2 * np.pi * k * t + rng.uniform(0, 2 * np.pi))
                        for k in (1, 2, 3))
        return yy < y0 * h
    if layout == "bay":
        cx = w * (0.5 + rng.normal(0, 0.04))
        ang = np.arctan2(yy - h, xx - cx)
        rad = np.hypot((xx - cx) / w, (yy - h) / h)
        edge = 0.38 + sum(rng.uniform(0.01, 0.03) * np.cos(k * ang + rng.uniform(0, 2 * np.pi)) for k in (3, 5))
        return rad > edge
    raise ValueError(f"layout must be 'island', 'coast' or 'bay', got {layout!r}")


def _grow_river(rng, start, heading, length, inland, occupied, step=2.0, wiggle=0.12, pull=0.25):
    """Walk uphill (away from the coast) from ``start``; stop near the coast or another river."""
    h, w = inland.shape
    gy, gx = np.gradient(ndi.gaussian_filter(inland, 4.0))
    pts = [np.asarray(start, float)]
    th = heading
    for i in range(int(length / step)):
        x, y = pts[-1]
        ix, iy = int(np.clip(round(x), 0, w - 1)), int(np.clip(round(y), 0, h - 1))
        up = np.arctan2(gy[iy, ix], gx[iy, ix])
        d = np.angle(np.exp(1j * (up - th)))
        th += pull * d * 0.3 + rng.normal(0, wiggle)
        nxt = pts[-1] + step * np.array([np.cos(th), np.sin(th)])
        jx, jy = int(round(nxt[0])), int(round(nxt[1]))
        if not (0 <= jx < w and 0 <= jy < h) or inland[jy, jx] < 4.0:
            break
        if i > 3 and occupied[jy, jx]:
            break
        pts.append(nxt)
    return np.array(pts)


def _mark(occupied, pts, radius):
    h, w = occupied.shape
    r = int(np.ceil(radius))
    for x, y in pts[::2]:
        x0, x1 = max(int(x) - r, 0), min(int(x) + r + 1, w)
        y0, y1 = max(int(y) - r, 0), min(int(y) + r + 1, h)
        occupied[y0:y1, x0:x1] = True


def river_map_example(shape=(256, 256), rng=0, *, n_trees: int = 14, river_color=RIVER,
                      r_mouth: float = 1.8) -> tuple[np.ndarray, Structure, np.ndarray]:
    """A river map: flat land, flat sea around it, separate river trees draining to the coast.

    Returns
    -------
    image : (H, W, 3) float32
    structure : Structure
        The forest that was drawn (one root per river, its first vertex at the mouth).
    land : (H, W) bool
        The land (the domain the rivers grow in).

    Examples
    --------
    >>> img, s, land = river_map_example((128, 128), 0, n_trees=6)
    >>> sum(b.parent is None for b in s.branches) >= 4
    True
    """
    rng = as_rng(rng)
    land = island_mask(shape, rng)
    return _rivers_on(land, rng, n_trees, r_mouth, river_color)


def _rivers_on(land, rng, n_trees, r_mouth, river_color=RIVER):
    """Grow river trees from the coast of ``land`` inland; draw them on flat land and sea."""
    shape = land.shape
    h, w = shape
    inland = ndi.distance_transform_edt(land)
    coast = land & ndi.binary_dilation(~land)   # land next to sea, not next to the frame
    coast[:4] = coast[-4:] = False
    coast[:, :4] = coast[:, -4:] = False
    cy, cx = np.nonzero(coast)
    order = np.argsort(np.arctan2(cy - cy.mean(), cx - cx.mean()))
    cy, cx = cy[order], cx[order]
    occupied = np.zeros(shape, bool)
    branches: list[Branch] = []
    n = len(cy)
    offs = (np.arange(n_trees) + rng.uniform(0, 1)) / n_trees
    gy, gx = np.gradient(ndi.gaussian_filter(inland, 4.0))
    size = min(h, w)
    for o in offs:
        k = int(o * n) % n
        x, y = float(cx[k]), float(cy[k])
        head = np.arctan2(gy[int(y), int(x)], gx[int(y), int(x)]) + rng.normal(0, 0.25)
        x += 3 * np.cos(head)
        y += 3 * np.sin(head)
        if occupied[int(y), int(x)]:
            continue
        trunk = _grow_river(rng, (x, y), head, rng.uniform(0.25, 0.4) * size, inland, occupied)
        if len(trunk) < 8:
            continue
        r = np.linspace(r_mouth, 0.55 * r_mouth, len(trunk))
        root = len(branches)
        branches.append(Branch(trunk, r))
        _mark(occupied, trunk, 4.5)
        # tributaries: join the trunk from the side, thinner than the trunk where they join
        n_kids = rng.integers(1, 4)
        cand = np.arange(len(trunk) // 5, len(trunk) * 4 // 5)
        for v in np.sort(rng.choice(cand, min(n_kids, len(cand)), replace=False)):
            t = trunk[min(v + 1, len(trunk) - 1)] - trunk[max(v - 1, 0)]
            base = np.arctan2(t[1], t[0]) + rng.choice([-1, 1]) * rng.uniform(0.5, 1.0)
            kid = _grow_river(rng, trunk[v], base, rng.uniform(0.1, 0.22) * size, inland, occupied)
            if len(kid) < 6:
                continue
            r0 = 0.7 * r[v]
            branches.append(Branch(kid, np.linspace(r0, max(0.5 * r0, 0.6), len(kid)), root, int(v)))
            _mark(occupied, kid[4:], 4.5)
    img = np.empty(shape + (3,), np.float32)
    img[:] = SEA
    img[land] = LAND
    img = draw_polylines(img, [b.points for b in branches], widths=[2 * b.thickness for b in branches],
                         colors=river_color)
    return img, Structure(branches, image_shape=shape), land


def _drawn_rivers(shape, rng: np.random.Generator, layout: str, n_trees: int | None,
                  line_width: float | None) -> tuple[np.ndarray, Structure, float]:
    """The land of a drawn map and its rivers as hand-drawn polylines of one width: ``(land, structure,
    line width)`` (shared by :func:`country_map_example` and the two-country map)."""
    h, w = shape
    size = min(h, w)
    lw = float(line_width) if line_width is not None else max(1.5, 2.0 * size / 500)
    n = int(n_trees) if n_trees is not None else int(np.clip(size / 40, 8, 30))
    land = coast_mask(shape, rng, layout)
    # opened on an edge-padded copy: land running off the frame stays land (a zero border would
    # nibble the corners) and sea at the frame stays sea (a border of ones would grow a ring of land)
    land = ndi.binary_opening(np.pad(land, 4, mode="edge"), iterations=2)[4:-4, 4:-4]
    _img, s, _ = _rivers_on(land, rng, n, lw / 2)
    # drawn as straight pieces between hand-placed vertices (every ~3 % of the map), one width
    step = max(4, int(0.03 * size / 2))
    flat: list[Branch] = []
    for b in s.branches:
        keep = np.unique(np.r_[np.arange(0, len(b.points), step), len(b.points) - 1])
        pts = resample_uniform(b.points[keep], 1.0, include_end=True)
        pv = b.parent_vertex
        if b.parent is not None:
            ppts = flat[b.parent].points
            pv = int(np.argmin(np.hypot(*(ppts - b.points[0]).T)))
            pts = np.vstack([ppts[pv], pts[1:]])
        flat.append(Branch(pts, np.full(len(pts), lw / 2), b.parent, pv))
    s = Structure(flat, image_shape=tuple(shape))
    return land, s, lw


def country_map_example(shape=(512, 512), rng=0, *, layout: str = "island", n_trees: int | None = None,
                        line_width: float | None = None) -> tuple[np.ndarray, Structure, np.ndarray]:
    """A drawn country map: flat land and sea colours, black rivers and a black coastline.

    Every river is drawn at one width (``line_width``, default about 2 px
    per 500 px of map), as on a printed outline map, so the river's
    thickness says nothing about where it drains; the true roots are the
    river mouths on the coast. The coast is a black line of the same width
    along the land's boundary (not along the frame).

    Parameters
    ----------
    shape : (H, W)
    rng : int or Generator
    layout : {"island", "coast", "bay"}
        Where the sea is (see :func:`coast_mask`).
    n_trees : int, optional
        Rivers to try; default scales with the map's size.
    line_width : float, optional

    Returns
    -------
    image : (H, W, 3) float32
    structure : Structure
        The drawn rivers (one root per river, its first vertex at the mouth).
    land : (H, W) bool

    Examples
    --------
    >>> img, s, land = country_map_example((200, 200), 0, layout="coast")
    >>> bool(img[land].min() < 0.1), bool(land[:20].all())
    (True, True)
    """
    rng = as_rng(rng)
    h, w = shape
    land, s, lw = _drawn_rivers(shape, rng, layout, n_trees, line_width)
    img = np.empty(tuple(shape) + (3,), np.float32)
    img[:] = SEA
    img[land] = LAND
    from skimage import measure

    from ..core.render import coverage_polylines

    coast = []
    for c in measure.find_contours(land.astype(np.float32), 0.5):
        pts = c[:, ::-1]
        on_frame = (pts[:, 0] <= 0.5) | (pts[:, 1] <= 0.5) | (pts[:, 0] >= w - 1.5) | (pts[:, 1] >= h - 1.5)
        # split at the frame: a coast is drawn only where land meets sea
        cut = np.flatnonzero(np.diff(on_frame.astype(int)))
        for piece in np.split(np.arange(len(pts)), cut + 1):
            if len(piece) > 2 and not on_frame[piece].all():
                coast.append(pts[piece])
    pls = [b.points for b in s.branches] + coast
    cov, _ = coverage_polylines(tuple(shape), pls, [np.full(len(p), lw) for p in pls])
    img = img * (1 - cov[..., None]) + np.asarray(INK, np.float32) * cov[..., None]
    return img.astype(np.float32), s, land


def floodplain_bands(structure: Structure, shape, land: np.ndarray, width: float = 10.0) -> np.ndarray:
    """The land within ``width`` pixels of a river's centre line (the floodplain of
    :func:`floodplain_map_example`)."""
    from .skeleton_map import SkeletonMap

    return (SkeletonMap(structure, 1.0).pixel_map(shape).dist <= width) & np.asarray(land, bool)


def floodplain_map_example(shape=(256, 256), rng=0, *, n_trees: int = 12, width: float = 10.0
                           ) -> tuple[np.ndarray, Structure, np.ndarray]:
    """A map with three flat regions: sea, land, and a floodplain band along every river.

    The river map of :func:`river_map_example`, with the land within
    ``width`` pixels of a river's centre line painted in a floodplain
    colour (see :func:`floodplain_bands`): the rivers lie in the
    floodplain, the floodplain in the land, the land in the sea.

    Returns
    -------
    image : (H, W, 3) float32
    structure : Structure
    labels : (H, W) int8
        0 sea, 1 land, 2 floodplain (the rivers included).

    Examples
    --------
    >>> img, s, lab = floodplain_map_example((128, 128), 0, n_trees=6)
    >>> sorted(np.unique(lab).tolist())
    [0, 1, 2]
    """
    img, s, land = river_map_example(shape, rng, n_trees=n_trees)
    band = floodplain_bands(s, shape, land, width)
    labels = land.astype(np.int8) + band
    out = np.empty(tuple(shape) + (3,), np.float32)
    out[:] = SEA
    out[land] = LAND
    out[band] = FLOODPLAIN
    out = draw_polylines(out, [b.points for b in s.branches], widths=[2 * b.thickness for b in s.branches],
                         colors=RIVER)
    return out, s, labels


def terrain_map_example(shape=(256, 256), rng=0, *, relief: str = "levels", n_trees: int = 12,
                        river_color=ATLAS_RIVER, r_mouth: float = 1.3, noise: float = 0.02
                        ) -> tuple[np.ndarray, Structure, np.ndarray]:
    """A drawn river map over terrain shading, like a printed atlas map.

    The rivers of :func:`river_map_example` over a relief: ``"levels"``
    paints the land in four flat greys (white lowlands to dark grey
    mountains, thresholds of a smooth random height field), ``"shade"``
    in a continuous grey hill shading plus pixel noise of ``noise``
    (standard deviation). The default river colour is an atlas blue
    about as light as the mid greys (luminance 0.46 against 0.59-0.85):
    by brightness alone the rivers barely stand out of the relief. Outside the land is white, with a black
    border line along the coast. The rivers are the structure's
    polylines, so the right extraction is known.

    Returns
    -------
    image : (H, W, 3) float32
    structure : Structure
        The drawn rivers.
    rivers : (H, W) bool
        The river pixels (coverage above one half).

    Examples
    --------
    >>> img, s, riv = terrain_map_example((128, 128), 0, n_trees=6)
    >>> img.shape, bool(riv.any())
    ((128, 128, 3), True)
    """
    from ..core.render import coverage_polylines

    rng_ = as_rng(rng)
    _img, s, land = river_map_example(shape, rng_, n_trees=n_trees, r_mouth=r_mouth)
    h, w = shape
    height = ndi.gaussian_filter(rng_.normal(size=shape), 0.05 * min(h, w), mode="wrap")
    height = (height - height.mean()) / (height.std() + 1e-12)
    if relief == "levels":
        greys = np.array([1.0, 0.85, 0.68, 0.59], np.float32)
        lev = np.digitize(height, [0.0, 0.8, 1.4])
        ground = greys[lev]
    elif relief == "shade":
        gy, gx = np.gradient(ndi.gaussian_filter(height, 2.0) * 0.08 * min(h, w))
        shade = 0.75 + 0.18 * (gx - gy) / np.sqrt(1.0 + gx ** 2 + gy ** 2) - 0.08 * np.clip(height, 0, None)
        ground = np.clip(shade + rng_.normal(0.0, noise, shape), 0.0, 1.0).astype(np.float32)
    else:
        raise ValueError(f"relief must be 'levels' or 'shade', got {relief!r}")
    img = np.ones(tuple(shape) + (3,), np.float32)
    img[land] = ground[land, None]
    coast = land & ~ndi.binary_erosion(land, iterations=2)
    img[coast] = (0.13, 0.13, 0.15)
    pls = [b.points for b in s.branches]
    widths = [2 * b.thickness for b in s.branches]
    img = draw_polylines(img, pls, widths=widths, colors=river_color)
    cov, _ = coverage_polylines(tuple(shape), pls, widths)
    return img, s, cov > 0.5


def _curve(p0, p1, rng, bend: float, step: float = 1.0) -> np.ndarray:
    """A smooth cubic curve from p0 to p1 with random sideways control points."""
    p0, p1 = np.asarray(p0, float), np.asarray(p1, float)
    d = p1 - p0
    n = np.array([-d[1], d[0]]) / max(np.hypot(*d), 1e-9)
    c1 = p0 + d / 3 + n * rng.normal(0, bend)
    c2 = p0 + 2 * d / 3 + n * rng.normal(0, bend)
    m = max(int(np.hypot(*d) / step), 2)
    t = np.linspace(0, 1, m)[:, None]
    return ((1 - t) ** 3 * p0 + 3 * (1 - t) ** 2 * t * c1 + 3 * (1 - t) * t ** 2 * c2 + t ** 3 * p1)


def delta_mask_example(shape=(256, 256), rng=0) -> tuple[np.ndarray, list, np.ndarray]:
    """A binary water mask of a braided delta.

    One wide channel enters at the top, splits into two arms of different
    widths that rejoin (a cycle), splits again into three distributaries
    (wide, medium, thin) that reach a sea filling the bottom of the frame.

    Returns
    -------
    mask : (H, W) float32
        1 = water, 0 = land.
    channels : list of ((N, 2) ndarray, float)
        Each channel's centre line (x, y) and radius (half width), clipped to land.
    sea : (H, W) bool

    Examples
    --------
    >>> m, ch, sea = delta_mask_example((128, 128), 0)
    >>> set(np.unique(m).tolist()) == {0.0, 1.0}, len(ch)
    (True, 7)
    """
    rng = as_rng(rng)
    h, w = shape
    s = min(h, w) / 256.0
    sea_y = 0.84 * h + rng.normal(0, 0.01 * h)
    xs = lambda f: w * f + rng.normal(0, 0.02 * w)  # noqa: E731
    top, a = (xs(0.5), -2.0), (xs(0.5), 0.28 * h)
    join, b = (xs(0.5), 0.52 * h), (xs(0.5), 0.62 * h)
    specs = [
        (top, a, 8.0 * s),
        (a, (join[0] - 0.22 * w, 0.42 * h), 5.0 * s),
        (a, (join[0] + 0.2 * w, 0.40 * h), 2.5 * s),
        (b, (xs(0.18), sea_y + 8), 4.5 * s),
        (b, (xs(0.52), sea_y + 8), 2.2 * s),
        (b, (xs(0.85), sea_y + 8), 1.4 * s),
    ]
    lines = []
    for k, (p, q, r) in enumerate(specs):
        c = _curve(p, q, rng, 0.04 * w)
        if k in (1, 2):  # the two arms continue back to the join point
            c = np.vstack([c, _curve(q, join, rng, 0.03 * w)[1:]])
        lines.append((c, r))
    trunk2 = _curve(join, b, rng, 0.01 * w)
    lines[0] = (lines[0][0], lines[0][1])
    lines.insert(3, (trunk2, 6.0 * s))
    yy = np.arange(h)[:, None]
    sea = np.broadcast_to(yy >= sea_y, shape).copy()
    canvas = np.zeros(shape + (3,), np.float32)
    canvas = draw_polylines(canvas, [c for c, _ in lines], widths=[2 * r for _, r in lines], colors=(1, 1, 1))
    mask = (canvas[:, :, 0] > 0.5) | sea
    channels = []
    for c, r in lines:
        inside = (c[:, 1] < sea_y - r) & (c[:, 1] >= 0)
        channels.append((c[inside], float(r)))
    return mask.astype(np.float32), channels, sea


def crack_pattern_example(shape=(256, 256), rng=0) -> np.ndarray:
    """Dark cracks on a flat grey ground: one crack from each image side, each with three side cracks.

    Returns the (H, W, 3) float32 image (its structure comes from ``extract_structure``).

    Examples
    --------
    >>> img = crack_pattern_example((128, 128), 0)
    >>> img.shape, bool(img.min() < 0.3 < 0.7 < img.max())
    ((128, 128, 3), True)
    """
    from ._image_examples import _walk

    rng = as_rng(rng)
    h, w = shape
    img = np.full(tuple(shape) + (3,), 0.75, np.float32)
    lines = []
    starts = [((rng.uniform(0.1, 0.9) * w, 2), np.pi / 2), ((w - 3, rng.uniform(0.1, 0.9) * h), np.pi),
              ((rng.uniform(0.1, 0.9) * w, h - 3), -np.pi / 2), ((2, rng.uniform(0.1, 0.9) * h), 0.0)]
    for start, head in starts:
        trunk = _walk(rng, start, head + rng.normal(0, 0.2), 0.6 * w, step=2, wiggle=0.15)
        lines.append((trunk, 2.0))
        for v in rng.choice(np.arange(10, len(trunk) - 5), 3, replace=False):
            t = trunk[v + 1] - trunk[v - 1]
            turn = rng.choice([-1, 1]) * rng.uniform(0.8, 1.3)
            lines.append((_walk(rng, trunk[v], np.arctan2(t[1], t[0]) + turn, 0.3 * w, step=2, wiggle=0.2), 1.2))
    pls = [np.clip(pl, 0, [w - 1, h - 1]) for pl, _ in lines]
    return draw_polylines(img, pls, widths=[2 * r for _, r in lines], colors=(0.15, 0.12, 0.1))


def line_scores(structure: Structure, ref_mask: np.ndarray) -> tuple[float, float, float]:
    """How well a structure's centre lines follow reference line pixels.

    Precision is the share of centre-line vertices within 2 px of a
    reference pixel, recall the share of the reference's skeleton pixels
    within 2.5 px of a vertex, and the tolerance IoU combines the two as
    ``p * r / (p + r - p * r)``.

    Examples
    --------
    >>> img, s, land = river_map_example((96, 96), 0, n_trees=4)
    >>> from ..core.render import coverage_polylines
    >>> cov, _ = coverage_polylines((96, 96), [b.points for b in s.branches], [2 * b.thickness for b in s.branches])
    >>> [round(v, 2) for v in line_scores(s, cov > 0.3)]
    [1.0, 1.0, 1.0]
    """
    from skimage.morphology import skeletonize

    ref_mask = np.asarray(ref_mask, bool)
    h, w = ref_mask.shape
    pts = np.vstack([b.points for b in structure.branches])
    ix = np.clip(np.rint(pts[:, 0]).astype(int), 0, w - 1)
    iy = np.clip(np.rint(pts[:, 1]).astype(int), 0, h - 1)
    precision = float(np.mean(ndi.distance_transform_edt(~ref_mask)[iy, ix] <= 2.0))
    ext = np.zeros((h, w), bool)
    ext[iy, ix] = True
    recall = float(np.mean(ndi.distance_transform_edt(~ext)[skeletonize(ref_mask)] <= 2.5))
    return precision, recall, precision * recall / max(precision + recall - precision * recall, 1e-9)


# --------------------------------------------------------------------------- figures (python -m ...)
def _map_kind(name: str, seed: int, shape):
    """(image, structure, true region per pixel) of a map kind with a known answer."""
    if name == "river":
        img, s, land = river_map_example(shape, seed, n_trees=10)
        return img, s, land.astype(int)
    if name == "floodplain":
        img, s, lab = floodplain_map_example(shape, seed, n_trees=10)
        return img, s, lab.astype(int)
    from .extraction import extract_structure

    m, _ch, sea = delta_mask_example(shape, seed)
    return np.dstack([m] * 3), extract_structure(m, root="nearest_region"), sea.astype(int)


def layout_figures(seeds=(3, 5, 7), shapes=((224, 320), (288, 224), (256, 256))) -> list[str]:
    """Region layouts laid out around other maps' branches, against their true regions."""
    from .regions import colour_labels, fit_region_layout, flat_colour_regions, layout_regions, region_layout
    from .skeleton_map import SkeletonMap

    rows = []
    for kind in ("river", "floodplain", "delta"):
        img, ex, truth_ex = _map_kind(kind, 0, (256, 256))
        pm = SkeletonMap(ex, 1.0).pixel_map(img.shape[:2])
        lab, _ = flat_colour_regions(img, pm.core(1.5, 2.0))
        zone = pm.core(3.0, 4.0)
        lay = region_layout(colour_labels(img, lab, ~zone), zone, pm.core(1.0, 0.0))
        model = fit_region_layout(lay, ex, pm)
        to_label = {int(k): int(np.bincount(lay[truth_ex == k]).argmax()) for k in np.unique(truth_ex)}
        for seed, shape in zip(seeds, shapes):
            _t, tgt, truth = _map_kind(kind, seed, shape)
            truth = np.vectorize(to_label.get)(truth)
            out = layout_regions(model, tgt, shape)
            on = SkeletonMap(tgt, 1.0).pixel_map(shape).dist <= 0.75
            iou = [((out == k) & (truth == k)).sum() / max(((out == k) | (truth == k)).sum(), 1) for k in model.labels]
            share = [np.mean(out == k) for k in model.labels]
            rows.append(f"{kind:10s} seed {seed} {shape}: branch pixels in the branch region "
                        f"{np.mean(out[on] == model.branch_region):.3f}; shares {np.round(share, 3)} "
                        f"(example {np.round(model.shares, 3)}); IoU vs truth {np.round(iou, 3)}")
    return rows


def extraction_figures() -> list[str]:
    """Extracted centre lines against the drawn rivers: precision, recall, tolerance IoU."""
    from ..core.image import as_rgb
    from .extraction import extract_structure

    cases = []
    for i, (relief, colour) in enumerate([("levels", ATLAS_RIVER), ("shade", ATLAS_RIVER),
                                          ("levels", (0.1, 0.1, 0.15)), ("shade", (0.1, 0.1, 0.15))]):
        for seed in (0, 1):
            img, _s, riv = terrain_map_example((320, 320), 10 * i + seed, relief=relief, river_color=colour)
            cases.append((f"terrain {relief} {'blue' if colour == ATLAS_RIVER else 'dark'} seed {seed}", img, riv))
    from .. import data

    cz = data.load("czech_rivers_map")
    rgb = as_rgb(cz)
    cases.append(("czech_rivers_map", cz, (rgb[..., 2] - rgb[..., 0]) >= 0.3))
    rows = []
    for name, img, ref in cases:
        p, r, iou = line_scores(extract_structure(img, root="nearest_region"), ref)
        rows.append(f"{name:28s} precision {p:.3f} recall {r:.3f} tolerance IoU {iou:.3f}")
    return rows


if __name__ == "__main__":
    print("\n".join(layout_figures() + extraction_figures()))
