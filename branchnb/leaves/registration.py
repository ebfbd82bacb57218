"""Non-rigid registration of an exemplar leaf to the training leaf: TPS-RPM.

The paper registers every exemplar to the training leaf with TPS-RPM
(Chui & Rangarajan 2003) on about 100 keypoints per leaf
(:func:`branchnb.leaves.keypoints.edge_keypoints`). No maintained Python 3
implementation exists; this is one, in numpy.

The steps live in modules of their own, all importable from here:
:mod:`~branchnb.leaves.starts` (step 1), :mod:`~branchnb.leaves.tps` and
:mod:`~branchnb.leaves.tpsrpm` (step 2), :mod:`~branchnb.leaves.warps`
(step 3, the :class:`Registration` result).

Steps
-----
1. **Start** (:func:`start_candidates`): a similarity of the exemplar's
   blade onto the training blade from their moments (centroids matched,
   scale from the areas). The rotation (the principal axes have a sign
   ambiguity, and round leaves such as maple have no reliable axis) is
   searched over the whole circle in ``rotation_step`` steps, optionally
   mirrored, scored by the symmetric chamfer distance of the outlines and
   of the thin parts; ``start="affine"`` refines each candidate to an
   affine map by trimmed ICP on the outlines.
2. **TPS-RPM**. Source points ``v_i`` (the exemplar's keypoints after the
   start map) and target points ``x_a`` (the training leaf's), in
   coordinates normalised by the training blade (centroid at 0, radius
   ``sqrt(area / pi)`` = 1), so the parameters do not depend on image size.
   Deterministic annealing from ``T_init`` (largest squared distance
   between the point sets) down to ``T_final`` (mean squared
   nearest-neighbour distance of the targets) at rate ``r``; at every
   temperature, ``iterations`` rounds of

   * softassign: ``m_ai = exp(-|x_a - f(v_i)|^2 / 2T) / T``, with an
     outlier row and column (``exp(-|x - centre|^2 / 2 T_init) / T_init``,
     the paper's outlier cluster at the centre of mass), points of
     different labels (outline / interior) never matched, then Sinkhorn
     normalisation of the inlier rows and columns;
   * the thin-plate spline ``f(v) = d^T [1, v] + sum_j w_j U(|v - v_j|)``,
     ``U(r) = r^2 log r``, fitted to the virtual targets
     ``y_i = sum_a m_ai x_a / sum_a m_ai`` with weights
     ``sum_a m_ai`` by minimising
     ``sum_i c_i |y_i - f(v_i)|^2 + lambda1 tr(w^T Phi w) + lambda2 |D - I|^2``
     (D: the linear part of ``d``; the translation is free), with the
     regularisers annealed as in the paper: ``lambda = lambda_init K T``.

   **Stages.** TPS-RPM runs first on ``outline_points`` samples of the
   two *laminae* outlines (the blade without thin parts such as the
   petiole, which bends and varies in length from leaf to leaf and is no
   shared shape), once from each of the ``n_starts`` best start maps; the
   run whose registered lamina outline lies closest to the training
   leaf's wins (this settles rotations that the outline cannot: a
   five-lobed blade looks alike every 72 degrees). When both leaves have
   a petiole, its root (the base) is a landmark of its own label, and so
   is the apex (the lamina outline point farthest from the base) when
   both have a clear one (15 % farther than any point a quarter of the
   outline away: an elliptic blade's tip, not one of a palmate blade's
   near-equal lobes).

   **Vein stage** (``veins=True``; off by default, see below). An outline without
   corners does not tell where a material point went along it; a leaf's
   main veins do (a pinnate blade's midrib and secondaries, a palmate
   blade's primaries: shared by every leaf of a kind, unlike the fine
   reticulum between them). :func:`~branchnb.leaves.keypoints.vein_keypoints`
   samples ``vein_points`` points along the long, nearly straight ridges
   of each lamina; TPS-RPM then refines the outline stage's spline with
   the outline samples and the vein points, each matched only to its own
   kind, from ``vein_t_init`` times the mean squared nearest-neighbour
   distance, ``vein_stiffness`` times stiffer, and with a softassign cost
   ``vein_orientation * sin^2`` of the angle between two vein points'
   directions (a secondary's point must not match a crossing fine vein).
   A leaf with fewer than 8 vein points keeps its outline registration.
   An optional further stage (``refine=True``) refines with all edge
   keypoints, interior edges included, from a low temperature and stiffer.

   **Measured defaults** (``python -m branchnb.leaves._measure
   registration``: mean true-keypoint error cut against the affine start,
   8 seeds x 2 pairs). The edge keypoints of the interior made the
   registration *worse* (elliptic 0.36 with ``refine``, against 0.51
   without): they lie on spots and fine veins that differ from leaf to
   leaf (figures in this paragraph with ``lambda1_init`` 10). The vein
   stage without the orientation cost did not help either
   (0.48: a fine vein's point pulled a secondary's); with it, at 192 px,
   elliptic 0.52 -> 0.55, trilobed 0.60 -> 0.61, lobed 0.55 -> 0.55, but
   at 384 px elliptic 0.49 -> 0.40 (two pairs locked onto the neighbouring
   secondaries; with ``lambda1_init`` 3, elliptic 0.59 -> 0.51 at 192 px
   and 0.57 -> 0.43 at 384 px, trilobed 0.61 -> 0.64, lobed 0.59 -> 0.57).
   So both ``veins`` and ``refine`` are off by default; the
   elliptic kind's serrate teeth make its outline observable instead.
   Because the points are normalised by the blade radius (Chui's data lie
   in the unit square), ``lambda1_init`` is measured, not Chui's: 3
   (cut at 192 / 384 px: lobed 0.59 / 0.60, trilobed 0.61 / 0.61,
   elliptic 0.59 / 0.57; with 10, the best before the teeth became
   material, 0.55 / 0.55, 0.60 / 0.59, 0.52 / 0.49; with 1, as good on
   the procedural leaves but one of six maples folded); ``T_final`` is a
   tenth of the mean squared nearest-neighbour distance (with Chui's
   value the final matches stay too soft and the outlines shrink
   inwards). A spline that still folds the lamina is refitted stiffer
   (``fold_retries``).

   **No slide across the axis** (beyond the paper, issue 22). An
   elongated lamina without landmarks (an ovate blade without a petiole)
   also fits its outline after sliding a quarter round along it; a start
   whose spline turns the lamina more than ``SLIDE_TURN`` across the two
   laminae's principal axes loses, and when every start does, the
   best-overlapping start along the axes is refitted with the spline's
   linear part held (``HELD_AFFINE``); see :func:`_slid`. Round laminae
   (the sample maples: all 42 pairs' maps unchanged) are not concerned.

   **Speed** (beyond the paper; issue 22). The annealing loop is compiled
   (numba; the numpy loop ``_anneal`` stays as the fallback and the
   reference). While ``T >= (0.7 * stride * spacing)^2`` it runs on every
   ``stride``-th point (8, 4, 2) of each label: the softassign blurs over
   ``sqrt(T)``, so closer points add nothing but cost. Sinkhorn stops
   when the rows sum to 1 within 1 %, and a temperature ends early once
   the spline moves less than ``0.01 sqrt(T_final)``. Measured (``python
   -m branchnb.leaves._measure registration``: identical summary; 6
   procedural and 12 maple pairs: maps within 0.03 px mean, 0.1 px at most,
   of the plain loop's, blade IoU unchanged to 3 decimals): 3.5 -> 0.7 s
   CPU per pair at ~250-370 px. The splines' values and Jacobians (the
   dense maps' Newton inverse) are compiled too: two registrations with
   the dense map to the training frame at 1000 px, 13.0 -> 4.2 s CPU.
   The first call compiles for ~15 s CPU (cached on disk afterwards).

3. **Dense maps**. ``forward`` (exemplar -> training) is the start map
   followed by the splines. ``inverse`` is a thin-plate spline fitted
   to forward-mapped samples of the exemplar, refined by Newton steps on
   the exact forward map, so ``inverse(forward(p))`` returns ``p``. Both
   are evaluated on a grid of ``grid_step`` pixels and interpolated
   bilinearly, which is fast at a megapixel and exact to a small
   fraction of a pixel for a smooth spline.

   **Speed at a megapixel** (issue 22; the same maps: within 1e-10 px of
   the previous code on procedural leaves at 700 px). The inverse's start
   spline is the interpolant ``scipy.interpolate.RBFInterpolator`` fitted,
   solved on one BLAS thread and evaluated compiled; a Newton step
   evaluates each spline once for value and Jacobian, and a point leaves
   the loop once its residual is below 1e-4 px; the grid is upsampled
   separably. The start scores' morphology (the opening that finds thin
   parts, the dilation around their roots) runs on the window around the
   blade / the thin parts only (identical masks), and the training leaf's
   keypoints are found once per analysis, not once per exemplar. One
   1 MP exemplar: registration and both dense maps 1.3-1.5 s CPU.

References
----------
H. Chui, A. Rangarajan, "A new point matching algorithm for non-rigid
registration", Computer Vision and Image Understanding 89 (2003) 114-141.
"""

from __future__ import annotations

import hashlib
import threading
from dataclasses import dataclass, replace

import cv2
import numpy as np
from scipy.spatial import cKDTree

from ..core.image import as_float_image, as_mask
from ..core.params import check_params, param
from ..core.validate import Instance, Int, checked
from .exemplar import Exemplar, leaf_exemplar
from .keypoints import OUTLINE, VEIN, Keypoints, edge_keypoints, vein_keypoints

# The steps live in their own modules; their names are importable from here as before.
from .starts import (  # noqa: F401
    _THIN_CACHE,
    _affine_icp,
    _base_point,
    _blade_iou,
    _Chamfer,
    _contour_points,
    _interior_samples,
    _jacobian_det,
    _lamina,
    _moments,
    _opening_radius,
    _outline_fit,
    _outline_samples,
    _rot,
    _sqrtm,
    _StartScore,
    _thin_parts,
    _thin_parts_of,
    _thin_roots,
    _wrap_angle,
    split_petiole,
    start_alignment,
    start_candidates,
)
from .tps import ThinPlateSpline, _points, _solve, _SplineSystem, _sqdist, _tps_eval_nb, _tps_kernel  # noqa: F401
from .tpsrpm import (  # noqa: F401
    _anneal,
    _anneal_compiled,
    _anneal_nb,
    _every,
    _softassign,
    _softassign_nb,
    _subsample_levels,
    tps_rpm,
)
from .warps import Registration, _apply, _bilinear_upsample, _coarse_grid  # noqa: F401

__all__ = ["RegistrationParams", "Registration", "register", "start_alignment", "start_candidates", "tps_rpm",
           "draw_registration", "ThinPlateSpline", "split_petiole"]


@dataclass
class RegistrationParams:
    """Parameters of :func:`register`; defaults are the papers' values.

    Where a default is measured rather than a paper's, the entry says so
    (:mod:`branchnb.leaves.registration` has the figures).

    Parameters
    ----------
    n_keypoints : int
        Keypoints per leaf (Assa & Cohen-Or: about 100).
    outline_fraction : float
        Fraction of them on the blade outline (default 0.35).
    anneal_rate : float
        Chui & Rangarajan's ``r`` (0.93).
    lambda1_init, lambda2_init : float
        Initial bending / affine regularisation (Chui & Rangarajan: 1 and
        0.01), multiplied by the number of points and the temperature.
        ``lambda1_init`` defaults to 3, measured for points normalised by
        the blade radius (Chui's data lie in the unit square).
    iterations : int
        Softassign / spline rounds per temperature (Chui & Rangarajan: 5).
    sinkhorn_iterations : int
        Row/column normalisation rounds per softassign (default 10; fewer
        once the rows sum to 1 within 1 %).
    t_final_scale : float
        ``T_final`` = this times the mean squared nearest-neighbour
        distance of the training keypoints (Chui & Rangarajan: 1; default
        0.1, measured: with 1 the final matches stay too soft and the
        outlines shrink inwards).
    use_labels : bool
        Match outline points only with outline points and interior points
        with interior points (default True).
    outline_points : int
        Lamina outline samples per leaf in the outline stage (default 150).
    n_starts : int
        Start maps tried by the outline stage; the best registered outline
        fit wins (default 3).
    fold_retries : int
        How many times an outline spline that folds the lamina (Jacobian
        determinant <= 0 somewhere on it) is refitted with ``lambda1``
        three times larger (default 3).
    apex : bool
        Also match the apexes as landmarks when both leaves have a clear
        one (default True).
    veins : bool
        Run the vein stage: refine with outline and main-vein points, each
        matched to its own kind (default False: it did not help on the
        measured families).
    vein_points : int
        Points along the main veins per leaf (default 60).
    vein_orientation : float
        Softassign cost of crossed vein directions, ``vein_orientation *
        sin^2`` of the angle, in squared blade radii (default 0.02).
    vein_t_init : float
        Vein stage start temperature over the mean squared
        nearest-neighbour distance (default 16).
    vein_stiffness : float
        ``lambda1`` of the vein stage over that of the outline stage
        (default 10).
    refine : bool
        Refine with all edge keypoints, interior ones included (default
        False: interior edge keypoints made registration worse).
    refine_t_init : float
        Refinement start temperature over the mean squared
        nearest-neighbour distance (default 16).
    refine_stiffness : float
        ``lambda1`` of the refinement over that of the outline stage
        (default 10).
    start : {"similarity", "affine"}
        Family of start maps (default ``"similarity"``; ``"affine"``
        refines each by trimmed ICP on the outlines).
    rotation_step : float
        Degrees between the start rotations tried (default 5).
    mirror : bool
        Also try mirrored starts (leaves photographed from the back).
    grid_step : int
        Spacing (pixels) of the grid the dense maps are evaluated on
        (default 8).
    """

    n_keypoints: int = param(100, min=10, max=400, help="keypoints per leaf (paper: about 100)")
    outline_fraction: float = param(0.35, min=0.0, max=1.0, step=0.05, help="share of keypoints on the outline")
    anneal_rate: float = param(0.93, min=0.5, max=0.99, step=0.01, help="annealing rate r (Chui: 0.93)")
    lambda1_init: float = param(3.0, min=1e-4, max=1000.0, log=True,
                                help="bending regulariser lambda1 (Chui: 1 for unit-square data)")
    lambda2_init: float = param(0.01, min=0.0, max=100.0, help="affine regulariser lambda2 (Chui: 0.01)")
    iterations: int = param(5, min=1, max=50, help="rounds per temperature (Chui: 5)")
    sinkhorn_iterations: int = param(10, min=1, max=500, help="Sinkhorn normalisation rounds")
    t_final_scale: float = param(0.1, min=0.01, max=100.0, log=True,
                                 help="T_final / mean squared nearest-neighbour distance")
    use_labels: bool = param(True, help="match outline with outline, interior with interior")
    outline_points: int = param(150, min=10, max=400, help="outline samples of the outline stage")
    n_starts: int = param(3, min=1, max=12, help="start maps tried (the best outline fit wins)")
    fold_retries: int = param(3, min=0, max=10, help="stiffer refits (lambda1 x 3 each) of a folding spline")
    apex: bool = param(True, help="match the apexes too, when both leaves have a clear one")
    veins: bool = param(False, help="refine with the main veins: outline and vein points, each matched to its own kind")
    vein_points: int = param(60, min=8, max=400, help="points along the main veins per leaf")
    vein_orientation: float = param(0.02, min=0.0, max=10.0,
                                    help="cost of crossed vein directions (squared blade radii)")
    vein_t_init: float = param(16.0, min=1.0, max=1000.0, log=True,
                               help="vein stage start temperature / mean squared nearest-neighbour distance")
    vein_stiffness: float = param(10.0, min=0.01, max=1000.0, log=True,
                                  help="lambda1 of the vein stage / lambda1 of the outline stage")
    refine: bool = param(False, help="refine the outline registration with all keypoints")
    refine_t_init: float = param(16.0, min=1.0, max=1000.0, log=True,
                                 help="refinement start temperature / mean squared nearest-neighbour distance")
    refine_stiffness: float = param(10.0, min=0.01, max=1000.0, log=True,
                                    help="lambda1 of the refinement / lambda1 of the outline stage")
    start: str = param("similarity", options=("similarity", "affine"), help="start map family")
    rotation_step: float = param(5.0, min=0.5, max=90.0, help="degrees between start rotations")
    mirror: bool = param(False, help="also try mirrored starts")
    grid_step: int = param(8, min=1, max=64, help="grid spacing of the dense maps (px)")


def _as_leaf(leaf, blade, name):
    if blade is not None:
        img = as_float_image(leaf.image if hasattr(leaf, "image") else leaf, name=name)
        m = as_mask(blade, shape=img.shape[:2], name=f"{name}_blade")
        if m.sum() < 16:
            raise ValueError(f"{name}_blade has only {int(m.sum())} pixels: no leaf to register")
        rgb = np.repeat(img, 3, axis=2) if img.shape[2] == 1 else img[:, :, :3]
        alpha = img[:, :, 3] if img.shape[2] == 4 else m.astype(np.float32)
        return Exemplar(np.ascontiguousarray(rgb), alpha, m, "given", name)
    if isinstance(leaf, Exemplar):
        return leaf
    if hasattr(leaf, "image") and hasattr(leaf, "blade"):  # ProceduralLeaf
        return _as_leaf(leaf.image, leaf.blade, name)
    return leaf_exemplar(leaf, name=name)


@checked()
def register(exemplar, training, exemplar_blade=None, training_blade=None, *,
             params: RegistrationParams | None = None, rng=None,
             exemplar_keypoints: Keypoints | None = None,
             training_keypoints: Keypoints | None = None) -> Registration:
    """Register ``exemplar`` to ``training`` (TPS-RPM on edge keypoints from a blade-moment start).

    Parameters
    ----------
    exemplar, training : Exemplar, ProceduralLeaf or image array_like
        Leaves (images without a blade are normalised by
        :func:`branchnb.leaves.exemplar.leaf_exemplar`).
    exemplar_blade, training_blade : (H, W) bool array_like, optional
        The leaves' blade masks, when known (they override the alpha).
    params : RegistrationParams, optional
        None: ``RegistrationParams()`` (the papers' and measured defaults).
    rng : optional
        Accepted for a uniform signature; registration is deterministic.
    exemplar_keypoints, training_keypoints : Keypoints, optional
        Precomputed keypoints (e.g. the training leaf's, shared by all exemplars).

    Returns
    -------
    Registration

    Examples
    --------
    >>> from branchnb.leaves import leaf_family
    >>> a, b = leaf_family(2, size=96, rng=0)
    >>> reg = register(b, a)
    >>> reg.map_to_training.shape
    (96, 96, 2)
    """
    prm = check_params(params if params is not None else RegistrationParams(), name="params")
    ex = _as_leaf(exemplar, exemplar_blade, "exemplar")
    tr = _as_leaf(training, training_blade, "training")
    kp_e = exemplar_keypoints or edge_keypoints(ex.rgb, ex.blade, prm.n_keypoints,
                                                outline_fraction=prm.outline_fraction)
    kp_t = training_keypoints or _training_keypoints(tr.rgb, tr.blade, prm.n_keypoints, prm.outline_fraction)
    for nm, kp in (("exemplar", kp_e), ("training", kp_t)):
        if len(kp) < 8:
            raise ValueError(f"{nm} has only {len(kp)} keypoints; registration needs at least 8")
    ys, xs = np.nonzero(tr.blade)
    centre = np.array([xs.mean(), ys.mean()])
    radius = float(np.sqrt(tr.blade.sum() / np.pi))

    def norm(p):
        return (p - centre) / radius

    # Stage 1: the outlines alone (the structure every leaf of a kind
    # shares), from each of the best start maps; the one whose registered
    # outline fits best wins.
    # The lamina's outline: thin protrusions (the petiole above all) bend
    # and vary in length from leaf to leaf and are no shared shape.
    lam_e, lam_t = _lamina(ex.blade), _lamina(tr.blade)
    cont_e = _outline_samples(lam_e, prm.outline_points)
    cont_t = _outline_samples(lam_t, prm.outline_points)
    dense_lam_t = _contour_points(lam_t, 2000)
    cands = start_candidates(ex.blade, tr.blade, start=prm.start, rotation_step=prm.rotation_step,
                             mirror=prm.mirror, n=prm.n_starts)
    base_e = _base_point(ex.blade, _thin_parts(ex.blade), lam_e)
    base_t = _base_point(tr.blade, _thin_parts(tr.blade), lam_t)
    # Landmarks when both leaves have a petiole: its root (the base) and the
    # lamina outline point farthest from it (the apex). They are matched
    # only to each other (their own labels), so an outline without corners
    # (an elliptic blade) cannot slide along itself.
    land_e = land_t = None
    if base_e is not None and base_t is not None:
        land_e, land_t = base_e[None], base_t[None]
        apex_e, apex_t = (_apex_point(lam, b) for lam, b in ((lam_e, base_e), (lam_t, base_t)))
        if prm.apex and apex_e is not None and apex_t is not None:
            land_e, land_t = np.vstack([land_e, apex_e]), np.vstack([land_t, apex_t])
        lab_src = np.r_[np.zeros(len(cont_e), int), 1 + np.arange(len(land_e))]
        lab_dst = np.r_[np.zeros(len(cont_t), int), 1 + np.arange(len(land_t))]
    def outline_spline(mat, prm_fit):
        ce = norm(cont_e @ mat[:, :2].T + mat[:, 2])
        if land_e is not None:
            src = np.vstack([ce, norm(land_e @ mat[:, :2].T + mat[:, 2])])
            return tps_rpm(src, np.vstack([norm(cont_t), norm(land_t)]), source_labels=lab_src,
                           target_labels=lab_dst, params=prm_fit)[0]
        return tps_rpm(ce, norm(cont_t), params=prm_fit)[0]

    # An elongated lamina's principal axis pins its turn up to a half turn (see _slid): a registration
    # turned far across it slid along the outline.
    inner_e = _interior_samples(lam_e)
    axis = _axis_turn(lam_e, lam_t)

    def slid(mat, f):
        return axis is not None and _slid(f, mat, axis, inner_e, norm)

    best = None
    for mat, _ in cands:
        f1 = outline_spline(mat, prm)
        dense_e = norm(_contour_points(lam_e, 2000) @ mat[:, :2].T + mat[:, 2])
        fit = _outline_fit(f1(dense_e), norm(dense_lam_t))
        if not prm.mirror:
            # A near-symmetric outline also fits its mirror image, and the
            # spline's affine part can turn into that reflection from an
            # unmirrored start; a mirrored map is no registration of an
            # unmirrored leaf (and its inverse cannot be blended with the
            # others' in synthesis), so it loses to any orientation-keeping one.
            if np.median(_jacobian_det(f1, dense_e)) <= 0:
                fit += 1e3
        if base_e is not None and base_t is not None:
            # The outline alone fits a palmate blade at another lobe's
            # rotation too; the base (petiole root) must land near the base.
            fb = f1(norm(base_e[None] @ mat[:, :2].T + mat[:, 2]))[0]
            fit += max(0.0, float(np.hypot(*(fb - norm(base_t)))) - 0.3)
        if slid(mat, f1):
            # A lamina turned across its axis slid along its outline (see _slid).
            fit += 1e3
        if best is None or fit < best[0]:
            best = (fit, mat, f1)
    if best[0] >= 1e3 and slid(best[1], best[2]):
        # Every start slid: the best-overlapping start along the axes, refitted with the spline's
        # linear part held near it (HELD_AFFINE; from a few times the final temperature it slid too).
        along = [c[0] for c in cands if not _across(_rotation_deg(inner_e, inner_e @ c[0][:, :2].T), axis)]
        if along:
            pin = max(along, key=lambda m: _blade_iou(m, ex.blade, tr.blade))
            f_loc = outline_spline(pin, replace(prm, lambda2_init=max(prm.lambda2_init, HELD_AFFINE)))
            if not slid(pin, f_loc):
                best = (0.0, pin, f_loc)
    _, start, f1 = best
    # A spline that folds the lamina over itself (Jacobian determinant <= 0)
    # is no correspondence and has no inverse: refit it stiffer until it
    # does not (seen on long grass strips at the paper's lambda1 scale).
    inner = norm(_interior_samples(lam_e) @ start[:, :2].T + start[:, 2])
    stiffer = prm
    for _ in range(prm.fold_retries):
        if (_jacobian_det(f1, inner) > 0).all():
            break
        stiffer = replace(stiffer, lambda1_init=stiffer.lambda1_init * 3.0)
        f1 = outline_spline(start, stiffer)
    start_iou = _blade_iou(start, ex.blade, tr.blade)
    splines = [f1]
    if prm.veins:
        f2 = _vein_stage(ex, tr, lam_e, lam_t, cont_e, cont_t, start, f1, norm, prm)
        if f2 is not None:
            splines.append(f2)
            f1 = _Composed(f1, f2)
    v = f1(norm(kp_e.points @ start[:, :2].T + start[:, 2]))
    x = norm(kp_t.points)
    labels = (kp_e.labels, kp_t.labels) if prm.use_labels else (None, None)
    if prm.refine:
        # Stage 2: all keypoints (interior edges too), a local refinement:
        # it starts at a few times the final temperature, stiffer.
        nn = cKDTree(x).query(x, k=2)[0][:, 1]
        t2 = prm.refine_t_init * float(np.mean(nn ** 2))
        stiff = replace(prm, lambda1_init=prm.lambda1_init * prm.refine_stiffness)
        f2, match = tps_rpm(v, x, source_labels=labels[0], target_labels=labels[1], params=stiff, t_init=t2)
        splines.append(f2)
    else:
        match = _softassign(x, v, labels[1], labels[0], 1e-2, 1.0, x.mean(0), v.mean(0), prm.sinkhorn_iterations)
    return Registration(start, start_iou, splines, centre, radius, kp_e, kp_t, match,
                        ex.blade.shape, tr.blade.shape, prm.grid_step)


#: A lamina whose principal axes' lengths differ by at least this factor has a clear axis (:func:`_axis_turn`).
PINNED_ASPECT = 1.3
#: ``lambda2_init`` of the outline stage refitted from a start along the axes when every start slid
#: (:func:`_slid`): the spline's linear part held near the start's.
HELD_AFFINE = 100.0
#: A registration turned more than this (degrees) across the laminae's axes slid along the outline (:func:`_slid`).
SLIDE_TURN = 45.0


def _rotation_deg(src: np.ndarray, dst: np.ndarray) -> float:
    """The least-squares rotation (Kabsch, degrees) taking the points ``src`` onto ``dst`` (any scale)."""
    u, _, vt = np.linalg.svd((dst - dst.mean(0)).T @ (src - src.mean(0)))
    if np.linalg.det(u @ vt) < 0:
        u[:, -1] *= -1
    r = u @ vt
    return float(np.degrees(np.arctan2(r[1, 0], r[0, 0])))


def _principal_axis(mask: np.ndarray):
    """The angle (degrees) of ``mask``'s long principal axis and its aspect (axis lengths' ratio)."""
    ys, xs = np.nonzero(mask)
    c = np.cov(np.vstack([xs, ys]).astype(np.float64))
    w, v = np.linalg.eigh(c)
    aspect = float(np.sqrt(max(w[1], 1e-12) / max(w[0], 1e-12)))
    return float(np.degrees(np.arctan2(v[1, 1], v[0, 1]))), aspect


def _axis_turn(lam_e: np.ndarray, lam_t: np.ndarray):
    """The turn (degrees, up to a half turn) taking the exemplar lamina's long axis onto the training
    lamina's, or None when either has no clear axis (:data:`PINNED_ASPECT`)."""
    a_e, r_e = _principal_axis(lam_e)
    a_t, r_t = _principal_axis(lam_t)
    if min(r_e, r_t) < PINNED_ASPECT:
        return None
    return a_t - a_e


def _across(turn: float, axis: float) -> bool:
    """Whether ``turn`` (degrees) lies more than :data:`SLIDE_TURN` from ``axis`` up to a half turn."""
    d = (turn - axis + 90.0) % 180.0 - 90.0
    return abs(d) > SLIDE_TURN


def _slid(spline, mat, axis, inner, norm) -> bool:
    """Whether the outline registration ``spline`` after the start ``mat`` turned the lamina's ``inner``
    points across the laminae's long axes (``axis``: :func:`_axis_turn`).

    Beyond the paper (issue 22). An outline without corners or landmarks
    (an ovate blade without a petiole) is carried onto itself by a whole
    family of maps that slide it along itself: the affine ``S R S^-1``
    turns an ellipse's points a quarter round while its outline stays in
    place, and the affine regulariser, annealed with the temperature, no
    longer weighs at the end. On procedural ovate leaves without petioles
    (variegated and plain, 240 px, leaves tilted by at most 14 degrees)
    every exemplar's TPS-RPM turned its lamina 87-108 degrees, its blade
    still overlapping the training blade at 0.97: every midrib was
    carried across its blade, the training veins warped onto the
    exemplars overlapped theirs at 0.05, the vein layer's liberal overlap
    was 0 and new leaves showed midribs across their blades. An elongated
    lamina's long axis (:data:`PINNED_ASPECT`) pins its turn up to a half
    turn (the start's search settles which end is the tip); a registration
    turned more than :data:`SLIDE_TURN` across it slid. Round laminae
    (maples, palmate blades whose start may sit a lobe away) have no axis
    and are left as they were.
    """
    pts = inner @ mat[:, :2].T + mat[:, 2]
    return _across(_rotation_deg(inner, np.asarray(spline(norm(pts)))), axis)


_KP_CACHE: dict = {}
_KP_LOCK = threading.Lock()  # batch runs register leaves on several threads


def _training_keypoints(rgb, blade, n: int, outline_fraction: float) -> Keypoints:
    """:func:`edge_keypoints` of the training leaf, remembered for the last few leaves.

    Every exemplar of an analysis registers to the same training leaf:
    its keypoints (deterministic) are found once, not once per exemplar.
    """
    rgb = np.ascontiguousarray(rgb)
    m = np.ascontiguousarray(blade, bool)
    h = hashlib.blake2b(digest_size=16)
    h.update(str((rgb.shape, rgb.dtype.str, n, float(outline_fraction))).encode())
    h.update(rgb.tobytes())
    h.update(np.packbits(m).tobytes())
    key = h.digest()
    with _KP_LOCK:
        hit = _KP_CACHE.get(key)
    if hit is None:
        hit = edge_keypoints(rgb, m, n, outline_fraction=outline_fraction)
        with _KP_LOCK:
            while len(_KP_CACHE) >= 4:
                _KP_CACHE.pop(next(iter(_KP_CACHE)))
            _KP_CACHE[key] = hit
    return Keypoints(hit.points.copy(), hit.labels.copy(), hit.strength.copy(),
                     None if hit.orientation is None else hit.orientation.copy())


def _apex_point(lamina: np.ndarray, base: np.ndarray, margin: float = 1.15):
    """The lamina outline point farthest from the base, when it is a clear apex (else None).

    Clear: at least ``margin`` times farther from the base than any outline
    point a quarter of the outline away from it (a palmate blade whose
    lobes reach about as far has no single apex).
    """
    pts = _contour_points(lamina, 720)
    d = np.hypot(*(pts - base).T)
    i = int(np.argmax(d))
    k = len(pts)
    far = np.abs(((np.arange(k) - i + k // 2) % k) - k // 2) > k // 8
    if not far.any() or d[i] < margin * d[far].max():
        return None
    return pts[i]


class _Composed:
    """Two splines in turn (the outline stage, then the vein stage)."""

    def __init__(self, first, second):
        self.first, self.second = first, second

    def __call__(self, p):
        return self.second(self.first(p))


def _vein_stage(ex, tr, lam_e, lam_t, cont_e, cont_t, start, f1, norm, prm):
    """Stage 2: refine the outline registration with outline and main-vein points, each matched to its own kind.

    The margin alone cannot pin material points that slide along a
    smooth outline; a leaf's main veins (midrib and secondaries of a
    pinnate blade, the primaries of a palmate one) are shared by every
    leaf of a kind and fix them. Returns None when either leaf has too
    few vein points (a leaf without visible veins keeps its outline fit).
    """
    ve = vein_keypoints(ex.rgb, lam_e, prm.vein_points)
    vt = vein_keypoints(tr.rgb, lam_t, prm.vein_points)
    if len(ve) < 8 or len(vt) < 8:
        return None
    src = f1(norm(np.vstack([cont_e, ve.points]) @ start[:, :2].T + start[:, 2]))
    dst = norm(np.vstack([cont_t, vt.points]))
    lab_s = np.r_[np.full(len(cont_e), OUTLINE), np.full(len(ve), VEIN)]
    lab_d = np.r_[np.full(len(cont_t), OUTLINE), np.full(len(vt), VEIN)]
    nn = cKDTree(dst).query(dst, k=2)[0][:, 1]
    t0 = prm.vein_t_init * float(np.mean(nn ** 2))
    stiff = replace(prm, lambda1_init=prm.lambda1_init * prm.vein_stiffness)
    cost = None
    if prm.vein_orientation > 0:
        # A vein point matches a vein point running the same way: the fine
        # reticulum between the main veins runs across them.
        u = np.column_stack([np.cos(ve.orientation), np.sin(ve.orientation)]) @ start[:, :2].T
        th_e = np.arctan2(u[:, 1], u[:, 0])
        sin2 = np.sin(vt.orientation[:, None] - th_e[None, :]) ** 2
        cost = np.zeros((len(dst), len(src)))
        cost[len(cont_t):, len(cont_e):] = prm.vein_orientation * sin2
    f2, _ = tps_rpm(src, dst, source_labels=lab_s, target_labels=lab_d, params=stiff, t_init=t0, pair_cost=cost)
    return f2


@checked(grid=Int(2, 256), registration=Instance("Registration"))
def draw_registration(registration: Registration, exemplar_image, training_image, *,
                      grid: int = 12, blade=None) -> np.ndarray:
    """A picture of a registration: the exemplar with the training grid warped onto it, and the training leaf.

    Left: the exemplar, its keypoints (red: outline, blue: interior) and
    the lines of a regular grid of the training frame mapped into it by
    :meth:`Registration.inverse`. Right: the training leaf with its
    keypoints (hollow) and the exemplar's keypoints mapped by
    :meth:`Registration.forward` (filled), matched pairs joined.

    Parameters
    ----------
    registration : Registration
        The registration to show.
    exemplar_image, training_image : array_like
        RGB(A) images of the two leaves (RGBA is shown over white).
    grid : int
        Number of grid lines across the training leaf's larger side.
    blade : (H_t, W_t) bool array_like, optional
        Only grid points inside this training mask (dilated) are drawn.

    Returns
    -------
    (max(H_e, H_t), W_e + W_t, 3) float32 ndarray
    """
    from ..core.image import as_rgb
    from ..core.render import draw_polylines

    reg = registration
    ex = as_rgb(exemplar_image, name="exemplar_image")
    tr = as_rgb(training_image, name="training_image")
    if ex.shape[:2] != tuple(reg.exemplar_shape) or tr.shape[:2] != tuple(reg.training_shape):
        raise ValueError("exemplar_image and training_image must have the registered leaves' shapes")
    ht, wt = reg.training_shape
    scale = max(ht, wt) / 512.0
    lw = max(1.0, 1.5 * scale)
    keep = None
    if blade is not None:
        keep = _dilate(as_mask(blade, shape=(ht, wt), name="blade"), int(max(ht, wt) / grid))
    lines = []
    ticks = np.linspace(0, 1, 4 * grid + 1)
    for g in np.linspace(0, 1, grid + 1):
        for pts in (np.column_stack([ticks * (wt - 1), np.full_like(ticks, g * (ht - 1))]),
                    np.column_stack([np.full_like(ticks, g * (wt - 1)), ticks * (ht - 1)])):
            if keep is not None:
                inside = keep[np.round(pts[:, 1]).astype(int), np.round(pts[:, 0]).astype(int)]
                # Split the line where it leaves the mask.
                runs = np.split(np.arange(len(pts)), np.flatnonzero(np.diff(inside.astype(int)) != 0) + 1)
                for r in runs:
                    if len(r) >= 2 and inside[r[0]]:
                        lines.append(reg.inverse(pts[r]))
            else:
                lines.append(reg.inverse(pts))
    left = draw_polylines(ex * 0.6 + 0.4, lines, widths=lw, colors=(0.1, 0.5, 0.1))
    kpe = reg.exemplar_keypoints
    cols = [(0.85, 0.1, 0.1) if lab == 0 else (0.1, 0.2, 0.85) for lab in kpe.labels]
    left = draw_polylines(left, [p[None] for p in kpe.points], widths=4 * lw, colors=cols)
    right = tr * 0.6 + 0.4
    kpt = reg.training_keypoints
    fwd = reg.forward(kpe.points)
    mt = reg.matches
    if len(mt):
        right = draw_polylines(right, [np.vstack([fwd[i], kpt.points[j]]) for i, j in mt],
                               widths=lw * 0.8, colors=(0.4, 0.4, 0.4))
    right = draw_polylines(right, [p[None] for p in kpt.points], widths=5 * lw, colors=(0.1, 0.1, 0.1))
    right = draw_polylines(right, [p[None] for p in kpt.points], widths=3 * lw, colors=(1.0, 1.0, 1.0))
    right = draw_polylines(right, [p[None] for p in fwd], widths=3 * lw, colors=cols)
    h = max(left.shape[0], right.shape[0])
    canvas = np.ones((h, left.shape[1] + right.shape[1], 3), np.float32)
    canvas[:left.shape[0], :left.shape[1]] = left
    canvas[:right.shape[0], left.shape[1]:] = right
    return canvas


def _dilate(mask: np.ndarray, radius: int) -> np.ndarray:
    k = 2 * max(radius, 0) + 1
    return cv2.dilate(mask.astype(np.uint8), np.ones((k, k), np.uint8)) > 0
