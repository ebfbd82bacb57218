"""Measures of a synthesized structure or image against its example (numbers, not looks).

- :func:`far_share`: share of the domain far (> 5 % of its diameter) from
  every branch (coverage; compare with the example's);
- :func:`root_boundary_distance`: where roots start relative to the
  domain's boundary (outlets at a coast have depth ~0);
- :func:`thick_end_share`: branches ending more than 2 x thicker than
  they start (radii should change smoothly);
- :func:`straight_runs`: turning angles and straight-run lengths (a drawn
  polyline map has long straight runs);
- :func:`line_pieces`: 8-connected line pieces per tree and specks in a
  synthesized image (one piece per tree = connected);
- :func:`boundary_drawn_share`: how much of a region boundary carries the
  drawn boundary line (a coast);
- :func:`line_contrast`: how far the centre lines stand out from the
  ground beside them (compare the synthesized image's with the example's).

``python -m branchnb.branching.measures`` runs the default workflow
(``extract_structure``, ``example_domain``, ``fit_model``,
``synthesize_structure``, ``synthesize_image``) on drawn maps of three
layouts and two sizes and on binary delta masks (:mod:`.examples`), and
prints these figures per seed (the issue-23 report).

Examples
--------
>>> from branchnb.core.structure import Branch, Structure
>>> import numpy as np
>>> s = Structure([Branch([(0, 50), (99, 50)], 1.0)])
>>> dom = np.ones((100, 100), bool)
>>> round(far_share(s, dom), 2)     # beyond 7 px of the line: all but a 15 px band
0.85
"""

from __future__ import annotations

import time

import numpy as np
from scipy import ndimage as ndi

from ..core.render import coverage_polylines
from ..core.structure import Structure

__all__ = ["far_share", "line_pieces", "root_boundary_distance", "straight_runs", "thick_end_share",
           "boundary_drawn_share", "line_contrast", "relative_line_pieces", "run_kind"]


def far_share(structure: Structure, domain: np.ndarray) -> float:
    """Share of ``domain`` farther than 5 % of its diameter from every branch.

    Parameters
    ----------
    structure : Structure
        The branches (vertices in pixels of ``domain``).
    domain : (H, W) bool array_like
        The synthesis domain (True inside).

    Returns
    -------
    float
        Fraction of the domain's pixels, in [0, 1] (compare with the
        example's own value on its domain).
    """
    dom = np.asarray(domain, bool)
    ys, xs = np.nonzero(dom)
    diam = float(np.hypot(np.ptp(xs), np.ptp(ys)))
    cov, _ = coverage_polylines(dom.shape, [b.points for b in structure.branches],
                                [np.full(len(b.points), 1.0) for b in structure.branches])
    d = ndi.distance_transform_edt(cov < 0.25)
    return float(np.mean(d[dom] > 0.05 * diam))


def root_boundary_distance(structure: Structure, domain: np.ndarray) -> np.ndarray:
    """Distance (pixels) of each root's first vertex to the outside of ``domain``.

    Parameters
    ----------
    structure : Structure
        The branches (vertices in pixels of ``domain``).
    domain : (H, W) bool array_like
        The synthesis domain (True inside).

    Returns
    -------
    (n_roots,) ndarray
        Euclidean distance (pixels) from each root's start to the nearest
        pixel outside the domain (0 for a start outside).
    """
    dom = np.asarray(domain, bool)
    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    out = []
    for b in structure.branches:
        if b.parent is None:
            x, y = np.clip(np.rint(b.points[0]).astype(int), 0, [w - 1, h - 1])
            out.append(d[y, x])
    return np.asarray(out)


def thick_end_share(structure: Structure) -> float:
    """Share of branches whose last radius is more than 2 x their first.

    Parameters
    ----------
    structure : Structure
        The branches (radii in pixels).

    Returns
    -------
    float
        Fraction of branches with >= 2 vertices, in [0, 1]; 0 when there are
        none.
    """
    bs = [b for b in structure.branches if len(b.points) > 1]
    return float(np.mean([b.thickness[-1] > 2 * b.thickness[0] for b in bs])) if bs else 0.0


def straight_runs(structure: Structure, h: float = 4.0, tol_deg: float = 6.0) -> tuple[float, float]:
    """(median absolute turning angle in degrees, mean straight-run length in pixels) at step ``h``.

    Parameters
    ----------
    structure : Structure
        The branches (vertices in pixels); branches shorter than ``3 h`` are
        skipped.
    h : float, default 4.0
        Resampling step h (pixels).
    tol_deg : float, default 6.0
        A vertex turning by less than this (degrees) continues a straight
        run.

    Returns
    -------
    median_angle : float
        Median absolute turning angle (degrees); 0 without any branch.
    mean_run : float
        Mean length of the straight runs (pixels); 0 without any.
    """
    from ..core.polyline import resample_uniform, turning_angles

    angles, runs = [], []
    for b in structure.branches:
        if b.length < 3 * h:
            continue
        p = resample_uniform(b.points, h, include_end=True)
        a = np.abs(np.degrees(turning_angles(p)))
        angles.append(a)
        straight = np.r_[False, a < tol_deg, False]
        edges = np.flatnonzero(np.diff(straight.astype(int)))
        runs.extend((edges[1::2] - edges[::2] + 1) * h)
    a = np.concatenate(angles) if angles else np.zeros(1)
    return float(np.median(a)), float(np.mean(runs)) if runs else 0.0


def _ink(image, colour, ground, share: float = 0.4) -> np.ndarray:
    """Pixels at least ``share`` of the way from the ``ground`` colour to the line ``colour``."""
    img = np.asarray(image, np.float32)[..., :3]
    c, g = np.asarray(colour, np.float32)[:3], np.asarray(ground, np.float32)[:3]
    v = c - g
    return ((img - g) @ v) / max(float(v @ v), 1e-9) >= share


def line_pieces(image: np.ndarray, structure: Structure, colour, ground) -> dict:
    """Line pixels (at least 40 % of the way from ``ground`` to ``colour``) near the structure:
    8-connected pieces per tree, specks (pieces under 10 px).

    Parameters
    ----------
    image : (H, W, C) array_like
        Synthesized image, float in [0, 1] (the first 3 channels are used).
    structure : Structure
        The synthesized structure drawn in ``image``.
    colour : (3,) array_like
        Colour of the drawn lines.
    ground : (3,) array_like
        Colour of the ground the lines are drawn on.

    Returns
    -------
    dict
        ``trees`` (number of roots), ``pieces_per_tree`` (mean),
        ``max_pieces`` and ``specks`` (pieces under 10 pixels in the whole
        image).
    """
    ink = _ink(image, colour, ground)
    trees = {}
    for i, b in enumerate(structure.branches):
        r = i
        while structure.branches[r].parent is not None:
            r = structure.branches[r].parent
        trees.setdefault(r, []).append(b)
    lab, n = ndi.label(ink, structure=np.ones((3, 3)))
    sizes = np.bincount(lab.ravel(), minlength=n + 1)
    pieces = []
    for bs in trees.values():
        cov, _ = coverage_polylines(ink.shape, [b.points for b in bs], [np.full(len(b.points), 1.0) for b in bs])
        near = ndi.binary_dilation(cov > 0.3, iterations=2)
        ids = np.unique(lab[near & ink])
        pieces.append(len(ids[ids > 0]))
    specks = int(np.sum((sizes[1:] > 0) & (sizes[1:] < 10)))
    return {"trees": len(trees), "pieces_per_tree": float(np.mean(pieces)) if pieces else 0.0,
            "max_pieces": int(max(pieces)) if pieces else 0, "specks": specks}


def _line_gaps(branches, line: np.ndarray) -> int:
    """Gaps of >= 2 px along the branches' polylines (1 px steps) where no ``line`` pixel lies within
    one pixel; points outside the image are no gap."""
    near = ndi.binary_dilation(line, structure=np.ones((3, 3), bool))
    h, w = line.shape
    gaps = 0
    for b in branches:
        pts = np.asarray(b.points, float)
        arc = np.r_[0.0, np.cumsum(np.linalg.norm(np.diff(pts, axis=0), axis=1))]
        if arc[-1] < 2:
            continue
        t = np.arange(0.0, arc[-1], 1.0)
        x, y = np.interp(t, arc, pts[:, 0]), np.interp(t, arc, pts[:, 1])
        ok = (x >= 0) & (x < w) & (y >= 0) & (y < h)
        miss = ~near[np.clip(np.rint(y).astype(int), 0, h - 1), np.clip(np.rint(x).astype(int), 0, w - 1)] & ok
        edges = np.diff(np.r_[0, miss.astype(np.int8), 0])
        gaps += int(np.sum(np.flatnonzero(edges == -1) - np.flatnonzero(edges == 1) >= 2))
    return gaps


def relative_line_pieces(example: np.ndarray, example_structure: Structure, image: np.ndarray,
                         structure: Structure, share: float = 0.4) -> dict:
    """:func:`line_pieces` for photographs: line pixels judged against their *local* ground.

    On a photograph (a retina, cracks in mud) neither the lines nor the
    ground have one colour, so a global threshold cuts the example's own
    vessels into dozens of pieces. Here a pixel within ``r + 1`` of the
    structure's centre lines is line when it stands out from its local
    ground (:func:`~branchnb.branching.line_contrast.local_ground`) along the
    example's line colour direction by at least ``share`` of the example's
    median amplitude at its radius (:func:`~branchnb.branching.line_contrast.line_profile`).

    Parameters
    ----------
    example : (H, W, C) array_like
        The example image, float in [0, 1] (RGBA is composited over white).
    example_structure : Structure
        Its branches (for the line profile).
    image : (H', W', C) array_like
        The synthesized image.
    structure : Structure
        The structure drawn in ``image``.
    share : float, default 0.4
        Share of the example's amplitude a line pixel reaches.

    Returns
    -------
    dict
        ``trees``, ``pieces_per_tree`` (mean), ``max_pieces``, ``gaps``
        (runs of >= 2 px along a branch with no line pixel within 1 px) and
        ``specks`` (line pieces under 10 px); all 0 when the example's lines
        do not stand out (no profile).

    Examples
    --------
    >>> from branchnb.core.structure import Branch
    >>> img = np.full((40, 40, 3), 0.8, np.float32); img[19:21, 2:38] = 0.3
    >>> s = Structure([Branch([(2, 19.5), (37, 19.5)], 1.0)])
    >>> gap = img.copy(); gap[19:21, 18:24] = 0.8
    >>> relative_line_pieces(img, s, gap, s)["max_pieces"]
    2
    """
    from .line_contrast import _ground_sigma, line_profile, local_ground
    from .skeleton_map import SkeletonMap

    def opaque(a):
        # RGBA over white (a transparent outside is no dark ground); grey as one channel
        a = np.asarray(a, np.float32)
        if a.ndim == 2:
            return a[..., None]
        return a[..., :3] * a[..., 3:4] + (1.0 - a[..., 3:4]) if a.shape[2] == 4 else a[..., :3]

    ex = opaque(example)
    prof = line_profile(ex, SkeletonMap(example_structure, 1.0).pixel_map(ex.shape[:2]))
    if prof is None:
        return {"trees": 0, "pieces_per_tree": 0.0, "max_pieces": 0, "gaps": 0, "specks": 0}
    img = opaque(image)
    pm = SkeletonMap(structure, 1.0).pixel_map(img.shape[:2])
    finite = np.isfinite(pm.dist) & (pm.radius > 0)
    r = np.where(finite, pm.radius, 0.0)
    body = finite & (pm.dist <= 1.5 * np.maximum(r, 0.5) + 1.5)
    ground = local_ground(img, body, _ground_sigma(r[finite & (pm.dist <= 0.5)]))
    amp = np.interp(np.maximum(r, 0.5), prof.radii, prof.amplitude)
    line = ((img - ground) @ prof.direction >= share * amp) & finite & (pm.dist <= np.maximum(r, 0.5) + 1.0)
    roots = np.arange(len(structure.branches))
    for i in range(len(roots)):
        while structure.branches[roots[i]].parent is not None:
            roots[i] = structure.branches[roots[i]].parent
    tree = np.where(finite, roots[np.clip(pm.branch, 0, len(roots) - 1)], -1)
    lab, n = ndi.label(line, structure=np.ones((3, 3)))
    sizes = np.bincount(lab.ravel(), minlength=n + 1)
    pieces = []
    for t in np.unique(roots):
        ids = np.unique(lab[line & (tree == t)])
        pieces.append(int(np.count_nonzero(ids)))
    gaps = _line_gaps(structure.branches, line)
    return {"trees": len(pieces), "pieces_per_tree": float(np.mean(pieces)) if pieces else 0.0,
            "max_pieces": max(pieces) if pieces else 0, "gaps": gaps,
            "specks": int(np.sum((sizes[1:] > 0) & (sizes[1:] < 10)))}


def boundary_drawn_share(image: np.ndarray, region: np.ndarray, colour, ground) -> float:
    """Share of the boundary of ``region`` (not on the frame) with a line of ``colour`` within 2 px.

    Parameters
    ----------
    image : (H, W, C) array_like
        Image, float in [0, 1] (the first 3 channels are used).
    region : (H, W) bool array_like
        The region whose boundary is checked (e.g. the land of a map).
    colour : (3,) array_like
        Colour of the drawn boundary line.
    ground : (3,) array_like
        Colour of the ground the line is drawn on.

    Returns
    -------
    float
        Fraction of the boundary pixels in [0, 1]; 1 when the region has no
        boundary inside the frame.
    """
    reg = np.asarray(region, bool)
    edge = reg & ndi.binary_dilation(~reg)
    edge[0] = edge[-1] = False
    edge[:, 0] = edge[:, -1] = False
    ink = _ink(image, colour, ground)
    near = ndi.binary_dilation(ink, iterations=2)
    return float(np.mean(near[edge])) if edge.any() else 1.0


def line_contrast(image: np.ndarray, structure: Structure) -> float:
    """Colour distance between the median centre-line pixel and the median ground pixel beside the lines.

    Centre-line pixels lie within ``max(0.5, 0.4 r)`` of the structure's
    centre lines, ground pixels ``r + 3`` to ``r + 7`` from them.

    Parameters
    ----------
    image : (H, W, C) array_like
        Image, float in [0, 1] (the first 3 channels are used).
    structure : Structure
        The branches drawn in ``image``.

    Returns
    -------
    float
        Euclidean distance of the two median colours (0 = the lines do not
        show).

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> img = np.full((30, 30, 3), 0.8, np.float32); img[14:16, 2:28] = 0.3
    >>> round(line_contrast(img, Structure([Branch([(2, 14.5), (27, 14.5)], 1.0)])), 2)
    0.87
    """
    from .line_contrast import centre_ring_contrast
    from .skeleton_map import SkeletonMap

    return centre_ring_contrast(image, SkeletonMap(structure, 1.0).pixel_map(np.asarray(image).shape[:2]))


def _kinds(sizes=(512, 1000)):
    from ._map_examples import country_map_example, delta_mask_example

    for lay in ("island", "coast", "bay"):
        for sz in sizes:
            img, s, land = country_map_example((sz, sz), sz + len(lay), layout=lay)
            yield f"map {lay} {sz}", img, land
    for sz in (512, 1000):
        m, _ch, sea = delta_mask_example((sz, sz), 3)
        yield f"delta {sz}", np.dstack([m] * 3), ~sea


def run_kind(name: str, img: np.ndarray, truth_domain=None, seeds=(0, 1, 2), image: bool = True) -> list[str]:
    """Measure one example through the default workflow; one text row per seed.

    Parameters
    ----------
    name : str
        Label of the example in the rows.
    img : (H, W, C) array_like
        The example image, float in [0, 1].
    truth_domain : (H, W) bool array_like, optional
        The known domain, to report the IoU of :func:`example_domain`'s
        estimate; None = no such row.
    seeds : sequence of int, default (0, 1, 2)
        Seeds ``rng`` of the synthesis runs, one row each.
    image : bool, default True
        Also synthesize and measure the image (slower); False = structures
        only.

    Returns
    -------
    list of str
        Text rows: the example's figures, then one per seed.
    """
    from . import example_domain, extract_structure, fit_model, synthesize_image, synthesize_structure

    ex = extract_structure(img)
    dom = example_domain(img, ex)
    rows = []
    if truth_domain is not None:
        iou = (dom & truth_domain).sum() / max((dom | truth_domain).sum(), 1)
        rows.append(f"{name}: example domain IoU {iou:.3f}")
    model = fit_model(ex, domain=dom)
    f_ex = far_share(model.example, dom)
    rb_ex = np.median(root_boundary_distance(ex, dom))
    a_ex, run_ex = straight_runs(ex)
    te_ex = thick_end_share(ex)
    rows.append(f"{name}: example far {f_ex:.3f}, root depth median {rb_ex:.1f} px, |angle| median "
                f"{a_ex:.1f} deg, straight run {run_ex:.1f} px, thick ends {te_ex:.3f}, "
                f"{sum(b.parent is None for b in ex.branches)} roots")
    for seed in seeds:
        t0 = time.perf_counter()
        res = synthesize_structure(model, rng=seed)
        ts = time.perf_counter() - t0
        s = res.structure
        a, run = straight_runs(s)
        row = (f"  seed {seed}: structure {ts:.2f} s, far {far_share(s, dom):.3f} "
               f"({far_share(s, dom) / max(f_ex, 1e-3):.2f}x), root depth median "
               f"{np.median(root_boundary_distance(s, dom)):.1f} px, |angle| {a:.1f} deg, run {run:.1f} px, "
               f"thick ends {thick_end_share(s):.3f}, {sum(b.parent is None for b in s.branches)} roots")
        if image:
            t0 = time.perf_counter()
            out = synthesize_image(img, ex, res, rng=seed)
            ti = time.perf_counter() - t0
            lc, ground = _line_colour(img, ex, dom)
            lp = line_pieces(out.image, s, lc, ground)
            extra = ""
            if out.labels is not None and res.domain is not None:
                land = out.labels == np.bincount(out.labels[res.domain]).argmax()
                iou = (land & res.domain).sum() / max((land | res.domain).sum(), 1)
                extra = (f", region IoU {iou:.3f}, boundary drawn "
                         f"{boundary_drawn_share(out.image, res.domain, lc, ground):.3f} "
                         f"(example {boundary_drawn_share(img, dom, lc, ground):.3f})")
            row += (f"; image {ti:.1f} s, pieces/tree {lp['pieces_per_tree']:.2f} (max {lp['max_pieces']}), "
                    f"specks {lp['specks']}" + extra)
        rows.append(row)
    return rows


def _line_colour(img, ex, dom) -> tuple[np.ndarray, np.ndarray]:
    """(line colour, ground colour) of an example: medians on the centre lines and far from them."""
    from .skeleton_map import SkeletonMap

    pm = SkeletonMap(ex, 1.0).pixel_map(img.shape[:2])
    rgb = np.asarray(img, np.float32)[..., :3]
    return np.median(rgb[pm.dist <= 0.5], axis=0), np.median(rgb[(pm.dist > 8) & dom], axis=0)


if __name__ == "__main__":
    import sys

    image = "--no-image" not in sys.argv
    for name, img, dom in _kinds():
        for r in run_kind(name, img, dom, image=image):
            print(r, flush=True)
