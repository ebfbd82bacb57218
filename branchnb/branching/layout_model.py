"""Laying an example's flat regions out around other branches.

:func:`fit_region_layout` learns how the regions lie around the example's
branches, :func:`layout_regions` lays them out around any structure and
:func:`target_layout` does both. Moved out of :mod:`branchnb.branching.regions`
(which still imports every name).
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.structure import Structure
from .skeleton_map import PixelMap, SkeletonMap

__all__ = ["RegionLayoutModel", "fit_region_layout", "layout_regions", "target_layout"]

# ---------------------------------------------------------------------------
# Laying the example's regions out around other branches
#
# A region layout (land and sea of a map, floodplain along the rivers, the sea
# a delta drains into) is a function of where the branches are: the rivers lie
# in the land, their mouths on the coast, the sea beyond the mouths and away
# from every branch. The features below describe a pixel by its relation to a
# skeleton only, so the relation learnt on the example applies to any target.


def _tree_of(structure: Structure) -> np.ndarray:
    """Index of every branch's root branch."""
    out = np.arange(len(structure.branches))
    for i in range(len(out)):
        j = i
        while structure.branches[j].parent is not None:
            j = structure.branches[j].parent
        out[i] = j
    return out


def _source_rooted(structure: Structure) -> set:
    """Roots of the trees that flow from their root (a delta's inland channel, thicker than 2 x
    the median of its tips): their outlets are their tips, not their root."""
    kids = {b.parent for b in structure.branches}
    tree = _tree_of(structure)
    out = set()
    for i, b in enumerate(structure.branches):
        if b.parent is not None or len(b.points) < 2:
            continue
        tips = [float(c.thickness[-min(len(c.thickness), 4):].max()) for j, c in enumerate(structure.branches)
                if j not in kids and tree[j] == i and j != i]
        if len(tips) >= 2 and float(np.max(b.thickness[:4])) >= 2.0 * float(np.median(tips)):
            out.add(i)
    return out



def _add_heading(p: np.ndarray, pts: list, dirs: list, along: float = 8.0) -> None:
    """Append ``p``'s first point and its unit heading over the first ``along`` pixels (if it has one)."""
    arc = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
    k = int(np.clip(np.searchsorted(arc, along), 1, len(p) - 1))
    d = p[k] - p[0]
    n = float(np.hypot(*d))
    if n > 1e-9:
        pts.append(p[0])
        dirs.append(d / n)

def _root_starts(structure: Structure):
    """Start points ``(R, 2)`` and unit directions ``(R, 2)`` into the network of the outlets.

    An outlet is a root (a river's mouth) or, for a tree that flows from its
    root (a delta rooted at its inland channel), the tip farthest from that
    root (one of its mouths; going beyond the paper)."""
    pts, dirs = [], []
    src = _source_rooted(structure)
    kids = {b.parent for b in structure.branches}
    tree = _tree_of(structure)
    # one outlet per such tree, as a river has one mouth: its tip farthest from the source
    outlet, best = {}, {}
    for i, b in enumerate(structure.branches):
        t = int(tree[i])
        if t in src and i not in kids and i != t and len(b.points) >= 2:
            r = float(np.hypot(*(np.asarray(b.points[-1]) - structure.branches[t].points[0])))
            if r > best.get(t, -1.0):
                outlet[t], best[t] = i, r
    for i, b in enumerate(structure.branches):
        if len(b.points) < 2:
            continue
        if b.parent is None and i in src and i in outlet:
            continue
        if b.parent is not None:
            if outlet.get(int(tree[i])) != i:
                continue
            # from the tip, heading into the network
            _add_heading(np.asarray(b.points, np.float64)[::-1], pts, dirs)
            continue
        _add_heading(np.asarray(b.points, np.float64), pts, dirs)
    return np.asarray(pts, np.float64).reshape(-1, 2), np.asarray(dirs, np.float64).reshape(-1, 2)


def _hull_features(structure: Structure, q: np.ndarray) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """Where points ``q`` lie relative to the convex hull of the skeleton.

    Returns the signed distance to the hull (> 0 outside); how much the
    nearest hull edge faces the way the nearest root points out of the
    network; and the signed distance beyond the coast line at the nearest
    root (below). The hull's edges between river mouths follow the coast,
    the sea lies outside them in the direction the mouths point (a cosine
    of about 1); outside an edge that runs along a river (the land beside
    a delta's outer arm) the cosine is about 0.
    """
    pts = np.vstack([np.asarray(b.points, np.float64) for b in structure.branches])
    hull = cv2.convexHull(pts.astype(np.float32)).reshape(-1, 2).astype(np.float64)
    n = len(q)
    if len(hull) < 3:
        return np.zeros(n), np.zeros(n), np.zeros(n)
    a, b = hull, np.roll(hull, -1, axis=0)
    ab = b - a
    t = np.clip((((q[:, None, :] - a[None]) * ab[None]).sum(-1)) / np.maximum((ab ** 2).sum(-1), 1e-9), 0.0, 1.0)
    d = np.hypot(*(q[:, None, :] - (a[None] + t[..., None] * ab[None])).transpose(2, 0, 1))
    e = np.argmin(d, axis=1)
    dist = d[np.arange(n), e]
    # outward normals: the hull from cv2 is ordered, its centroid inside
    nrm = np.column_stack([ab[:, 1], -ab[:, 0]]) / np.maximum(np.hypot(ab[:, 0], ab[:, 1]), 1e-9)[:, None]
    if ((a + 0.5 * ab - hull.mean(0)) * nrm).sum(1).mean() < 0:
        nrm = -nrm
    inside = np.all(((q[:, None, :] - a[None]) * nrm[None]).sum(-1) <= 0.0, axis=1)
    signed = np.where(inside, -dist, dist)
    starts, heads = _root_starts(structure)
    if len(starts) == 0:
        return signed, np.zeros(n), np.zeros(n)
    from scipy.spatial import cKDTree

    _, k = cKDTree(starts).query(q)
    facing = -(nrm[e] * heads[k]).sum(1)
    # The coast line at each root: of the two hull edges at the hull vertex
    # nearest to the root, the one that faces away from the skeleton's centre
    # most (a root's own heading can run along the coast); how far a point
    # lies beyond that line, extended past the hull (the coast goes on
    # beyond the outermost mouth).
    v = np.argmin(np.hypot(*(starts[:, None, :] - hull[None]).transpose(2, 0, 1)), axis=1)
    cand = np.stack([v, (v - 1) % len(hull)], 1)
    away = starts - pts.mean(0)
    away /= np.maximum(np.hypot(away[:, 0], away[:, 1]), 1e-9)[:, None]
    face = (nrm[cand] * away[:, None, :]).sum(-1)
    coast = cand[np.arange(len(starts)), np.argmax(face, 1)]
    beyond = ((q - starts[k]) * nrm[coast[k]]).sum(1)
    return signed, facing, beyond


def _layout_features(structure: Structure, pm: PixelMap, sigma: float, stride: int) -> np.ndarray:
    """Per-pixel features ``(h', w', 9)`` on every ``stride``-th pixel, from the skeleton alone.

    Distance to the centre line and to the branch's edge, distance to the
    nearest root start, the cosine between the root's heading and the
    direction to the pixel (-1 behind a river mouth) and the offset along
    that heading, how one-sided the branches around the pixel are (the
    length of the mean offset to the skeleton pixels within ``sigma``,
    over ``sigma``: about 0 inside a branch network, about 0.8 beside it,
    e.g. in the sea off a coast), and the pixel's relation to the convex
    hull of the skeleton (see :func:`_hull_features`: the line between a
    delta's mouths is its coast).

    Nothing refers to the image frame: an example's sea may be 40 pixels
    deep along its bottom side, a target's 60; the trees would learn the
    frame distance, which separates the example perfectly and says nothing
    about a target of another size.
    """
    h, w = pm.dist.shape
    ys = np.arange(0, h, stride)
    xs = np.arange(0, w, stride)
    dist = pm.dist[np.ix_(ys, xs)]
    edge = dist - pm.radius[np.ix_(ys, xs)]
    yy, xx = np.meshgrid(ys.astype(np.float64), xs.astype(np.float64), indexing="ij")
    q = np.column_stack([xx.ravel(), yy.ravel()])
    starts, heads = _root_starts(structure)
    if len(starts):
        from scipy.spatial import cKDTree

        d_root, k = cKDTree(starts).query(q)
        off = q - starts[k]
        cos = (off * heads[k]).sum(1) / np.maximum(d_root, 1e-9)
        d_root = d_root.reshape(yy.shape)
        cos = np.where(d_root > 1e-9, cos.reshape(yy.shape), 1.0)
        along = (off * heads[k]).sum(1).reshape(yy.shape)
    else:
        d_root = np.full(yy.shape, float(np.hypot(h, w)))
        cos = np.zeros(yy.shape)
        along = np.zeros(yy.shape)
    skel = (pm.dist <= 0.75).astype(np.float64)
    gy_, gx_ = np.mgrid[0:h, 0:w].astype(np.float64)
    n = ndi.gaussian_filter(skel, sigma, mode="constant")
    mx = ndi.gaussian_filter(skel * gx_, sigma, mode="constant")
    my = ndi.gaussian_filter(skel * gy_, sigma, mode="constant")
    good = n > 1e-6
    ox = np.where(good, mx / np.maximum(n, 1e-12) - gx_, 0.0)
    oy = np.where(good, my / np.maximum(n, 1e-12) - gy_, 0.0)
    side = np.where(good, np.hypot(ox, oy) / sigma, 1.0)[np.ix_(ys, xs)]
    hull_d, facing, beyond = (a.reshape(yy.shape) for a in _hull_features(structure, q))

    def slog(v):
        return np.sign(v) * np.log1p(np.abs(v))

    return np.stack([np.log1p(dist), slog(edge), np.log1p(d_root), cos, slog(along), side,
                     slog(hull_d), facing, slog(beyond)], axis=-1)


@dataclass
class RegionLayoutModel:
    """How an example's flat regions lie around its branches (see :func:`fit_region_layout`).

    Parameters
    ----------
    labels : (K,) int ndarray
        The region labels.
    shares : (K,) ndarray
        Fraction of the example covered by each region.
    branch_region : int
        The region the branches lie in (the land of a river map).
    sigma : float
        Scale (pixels) of the one-sidedness feature.
    min_area : (K,) ndarray
        Smallest piece of each region in the example (pixels); smaller
        pieces of a target layout are absorbed by their surroundings.
    classifier : object, optional
        Predicts a pixel's region from its relation to the skeleton (None
        when the example has a single region).
    bearing : (K,) bool ndarray, optional
        Regions that hold a real share (>= 10 %) of the example's centre
        lines besides the branch region (a drawn tree's branches run on
        white ground and through a green crown); a target branch may lie in
        any of them. None: only in the branch region.
    bands : list of FrameBand, optional
        Regions tied to the image frame, not to the branches (a skyline or
        a floor along the bottom, :func:`~branchnb.branching.frame_regions.frame_bands`):
        laid out by the frame alone. None or empty: every region is laid
        out around the branches.
    """

    labels: np.ndarray
    shares: np.ndarray
    branch_region: int
    sigma: float
    min_area: np.ndarray
    classifier: object | None = None
    bearing: np.ndarray | None = None
    bands: list | None = None


def _stride(shape) -> int:
    return max(1, int(round(np.sqrt(shape[0] * shape[1]) / 160.0)))


def fit_region_layout(layout: np.ndarray, structure: Structure, pm: PixelMap | None = None
                      ) -> RegionLayoutModel:
    """Learn from an example how its regions relate to its branches.

    Parameters
    ----------
    layout : (H, W) int ndarray
        Region of every example pixel, branches relabelled to their
        surroundings (:func:`~branchnb.branching.flat_regions.region_layout`).
    structure : Structure
        The example's branches.
    pm : PixelMap, optional
        Its nearest-skeleton map on the layout's grid (computed if omitted).

    Returns
    -------
    RegionLayoutModel
        The learnt relation (without a classifier when the layout has a
        single region).

    Raises
    ------
    ValueError
        If ``layout`` is not a 2-D integer label map.

    Notes
    -----
    The region the branches lie in is the most common layout label on the
    centre lines. An ensemble of randomised trees learns every pixel's
    region from its relation to the skeleton (see ``_layout_features``):
    distance to the branches and to their edge, to the nearest root start
    and on which side of it, how one-sided the branches around it are, and
    how far outside the skeleton's convex hull (beyond the coast line
    through the mouths) it lies; never its distance to the image frame.

    Going beyond the paper (issue 23, branching96): a region tied to the
    frame rather than to the branches (a city skyline or a hill line along
    the bottom of a lightning photograph, the floor under a neon sign: a
    band along one side with a far edge running along it, holding no
    branch and no two branch ends spread along its edge as river mouths
    along a coast or a delta's mouths are) is kept as a
    :class:`~branchnb.branching.frame_regions.FrameBand` and laid out by
    the frame (:mod:`.frame_regions`). Laid out by the branches it came
    out as wedges and coast-like blobs (a neon sign's floor rectangle: IoU
    with the example's floor 0.00-0.05 at the example's size).
    """
    from sklearn.ensemble import ExtraTreesClassifier

    lay = np.asarray(layout)
    if lay.ndim != 2 or not np.issubdtype(lay.dtype, np.integer):
        raise ValueError(f"layout must be a 2-D integer label map, got {lay.dtype} {lay.shape}")
    if pm is None:
        pm = SkeletonMap(structure, 1.0).pixel_map(lay.shape)
    labels, counts = np.unique(lay, return_counts=True)
    shares = counts / lay.size
    on = lay[pm.dist <= 0.75]
    branch_region = int(np.bincount(on - labels.min()).argmax() + labels.min()) if on.size else int(labels[0])
    inside = (pm.dist < np.inf)
    reach = pm.dist[inside & (lay == branch_region)]
    sigma = float(np.clip(2.0 * np.percentile(reach, 90) if reach.size else 20.0, 8.0, 0.25 * max(lay.shape)))
    min_area = np.zeros(len(labels))
    for i, k in enumerate(labels):
        lab, n = ndi.label(lay == k)
        sizes = np.bincount(lab.ravel())[1:]
        sizes = sizes[sizes >= 16]
        min_area[i] = float(sizes.min()) if sizes.size else 16.0
    clf = None
    if len(labels) >= 2:
        st = _stride(lay.shape)
        feats = _layout_features(structure, pm, sigma, st)
        y = lay[::st, ::st][: feats.shape[0], : feats.shape[1]]
        X = feats.reshape(-1, feats.shape[-1])
        y = y.ravel()
        step = max(1, len(y) // 30000)
        # randomised trees: fast on one core, and their average gives soft boundaries
        # (every feature at every split: with a random third of them the trees
        # lean on weak features as often as on the one that separates)
        clf = ExtraTreesClassifier(n_estimators=12, max_depth=12, min_samples_leaf=10, max_features=None,
                                   n_jobs=1, random_state=0)
        clf.fit(X[::step], y[::step])
    on_share = np.array([np.mean(on == k) for k in labels]) if on.size else np.zeros(len(labels))
    bearing = (on_share >= 0.1) | (labels == branch_region)
    bands = None
    if len(labels) >= 2:
        from .frame_regions import frame_bands

        # every branch's last point is a free end (children start on their parent's vertices)
        ends = [np.asarray(br.points[0]) for br in structure.branches if br.parent is None] + \
            [np.asarray(br.points[-1]) for br in structure.branches]
        bands = frame_bands(lay, np.asarray(ends, np.float64).reshape(-1, 2), pm.radius, labels[bearing]) or None
    return RegionLayoutModel(labels, shares, branch_region, sigma, min_area, clf, bearing, bands)


def layout_regions(model: RegionLayoutModel, structure: Structure, shape, pm: PixelMap | None = None, *,
                   share_tolerance: float = 0.25) -> np.ndarray:
    """Lay the learnt regions out around ``structure`` on an ``(H, W)`` grid.

    The classifier's region probabilities (on a coarse grid, interpolated)
    get one bias per region, adjusted until every region covers the image
    within ``share_tolerance`` (relative) of the example's share; the branches and their bodies always lie in
    the branch region, and pieces of a region smaller than its smallest
    piece in the example are absorbed by their surroundings. The
    boundaries are smooth curves (iso-lines of distances), never block
    edges. Regions tied to the frame (``model.bands``, going beyond the
    paper) are placed by the frame first (their depth profile along their
    side, stretched to the grid: the example's own region at its size)
    and appear nowhere else; a target branch crossing one is drawn over it.

    Parameters
    ----------
    model : RegionLayoutModel
        From :func:`fit_region_layout`.
    structure : Structure
        The target branches (pixels of the new grid).
    shape : (H, W)
        Size of the target grid.
    pm : PixelMap, optional
        The structure's nearest-skeleton map on that grid (computed if
        omitted).
    share_tolerance : float, default 0.25
        Relative deviation from the example's share allowed to each region.

    Returns
    -------
    (H, W) int32 ndarray
        The example's region label of every pixel.
    """
    import cv2

    h, w = int(shape[0]), int(shape[1])
    if pm is None:
        pm = SkeletonMap(structure, 1.0).pixel_map((h, w))
    K = len(model.labels)
    br = int(np.flatnonzero(model.labels == model.branch_region)[0])
    if K < 2 or model.classifier is None:
        return np.full((h, w), model.labels[0], np.int32)
    st = _stride((h, w))
    feats = _layout_features(structure, pm, model.sigma, st)
    proba = np.zeros(feats.shape[:2] + (K,))
    cls = list(model.classifier.classes_)
    pr = model.classifier.predict_proba(feats.reshape(-1, feats.shape[-1]))
    for j, c in enumerate(cls):
        proba[..., int(np.flatnonzero(model.labels == c)[0])] = pr[:, j].reshape(feats.shape[:2])
    proba = proba.astype(np.float32)
    if st > 1:
        # coarse sample (i, j) sits on pixel (i st, j st)
        mx, my = np.meshgrid(np.arange(w, dtype=np.float32) / st, np.arange(h, dtype=np.float32) / st)
        proba = np.stack([cv2.remap(np.ascontiguousarray(proba[..., k]), mx, my, cv2.INTER_LINEAR,
                                    borderMode=cv2.BORDER_REPLICATE) for k in range(K)], -1)
    # the trees' thresholds leave a ragged edge: smooth it over a few pixels
    proba = np.stack([cv2.GaussianBlur(proba[..., k], (0, 0), 2.0) for k in range(K)], -1)
    logp = np.log(np.clip(proba, 1e-4, 1.0))
    body = pm.core(1.0, 1.5)
    # a branch lies in the branch region, or in another region where the example's branches also run
    # (going beyond the paper: a drawn tree's branches through its crown get no halo of ground)
    bearing = np.zeros(K, bool) if model.bearing is None else np.asarray(model.bearing, bool)
    bearing[br] = True
    several = bool(bearing.sum() >= 2)
    fixed = None
    if model.bands:
        # frame-tied regions lie where the frame puts them, and nowhere else (no islands of a skyline)
        from .frame_regions import place_bands

        fixed = place_bands(model.bands, (h, w))
        fixed_i = np.where(fixed >= 0, np.searchsorted(model.labels, np.maximum(fixed, model.labels.min())), -1)
        tied = np.zeros(K, bool)
        for b in model.bands:
            tied[int(np.flatnonzero(model.labels == b.label)[0])] = True
        body = body & (fixed < 0)
        logp[..., tied] = -1e3
    if several:
        on_body = logp[body]
        on_body[:, ~bearing] = -1e3
        logp[body] = on_body
    else:
        logp[body] = -1e3
        logp[body, br] = 0.0
    # One bias per region keeps the areas near the example's shares: within
    # ``share_tolerance`` of them the learnt relation decides (a target with
    # longer rivers has more floodplain), beyond it the biases pull back.
    bias = np.zeros(K, np.float32)
    lo = np.maximum(model.shares * (1.0 - share_tolerance) - 0.005, 0.0)
    hi = model.shares * (1.0 + share_tolerance) + 0.005
    for _ in range(40):
        lab = np.argmax(logp + bias, axis=-1)
        if fixed is not None:
            lab = np.where(fixed_i >= 0, fixed_i, lab)
        cur = np.bincount(lab.ravel(), minlength=K) / lab.size
        goal = np.clip(cur, lo, hi)
        if np.all(np.abs(cur - goal) < 0.002):
            break
        bias += 0.7 * np.log((goal + 1e-3) / (cur + 1e-3)).astype(np.float32)
    lab = np.argmax(logp + bias, axis=-1)
    lab[body] = np.where(bearing[lab[body]], lab[body], br) if several else br
    if fixed is not None:
        lab = np.where(fixed_i >= 0, fixed_i, lab)
    # Specks: pieces smaller than half the example's smallest piece of that
    # region, holding no branch, join their surroundings (a short river's
    # floodplain is small but stays).
    for k in range(K):
        if fixed is not None and tied[k]:
            continue
        pieces, n = ndi.label(lab == k)
        if n <= 1:
            continue
        sizes = np.bincount(pieces.ravel())
        small = (sizes < 0.5 * model.min_area[k])
        small[0] = False
        small[np.unique(pieces[body])] = False
        drop = small[pieces]
        if drop.any():
            _, (iy, ix) = ndi.distance_transform_edt(drop, return_indices=True)
            lab = np.where(drop, lab[iy, ix], lab)
    return model.labels[lab].astype(np.int32)


def target_layout(layout: np.ndarray, example_structure: Structure, target_structure: Structure, shape, *,
                  pm_example: PixelMap | None = None, pm_target: PixelMap | None = None) -> np.ndarray:
    """The example's region layout laid out around the target branches as in the example.

    ``fit_region_layout`` on the example, then ``layout_regions`` on the
    target (see both).

    Parameters
    ----------
    layout : (H, W) int ndarray
        The example's layout (:func:`~branchnb.branching.flat_regions.region_layout`).
    example_structure : Structure
        The example's branches.
    target_structure : Structure
        The target branches.
    shape : (H2, W2)
        Size of the target grid.
    pm_example, pm_target : PixelMap, optional
        Nearest-skeleton maps of the two structures on their grids (computed
        if omitted).

    Returns
    -------
    (H2, W2) int32 ndarray
        Region label of every target pixel.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> lay = np.zeros((96, 96), np.int32); lay[:, 80:] = 1       # land left, sea right of the mouth
    >>> ex = Structure([Branch([(78, 48), (10, 40)], 1.5)])
    >>> tgt = Structure([Branch([(78, 20), (10, 70)], 1.5)])
    >>> out = target_layout(lay, ex, tgt, (96, 96))
    >>> int(out[45, 40]), int(out[20, 92])
    (0, 1)
    """
    model = fit_region_layout(layout, example_structure, pm_example)
    return layout_regions(model, target_structure, shape, pm_target)
