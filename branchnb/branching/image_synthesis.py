"""Image synthesis for a branching structure: the example's texture on a new skeleton.

Given an example image with its structure (the *source*) and a new
structure (the *target*, e.g. from :mod:`branchnb.branching.synthesis`),
:func:`synthesize_image` produces the image of the target structure:

1. **Fragments** (:mod:`.fragments`): the target skeleton is covered by
   disks of radius ``s = 3 r`` every ``lambda (s_i + s_{i+1})`` and at every
   furcation, visited root first, generation by generation. For each, every
   source fragment gets the shape cost ``S = sum ||R p - q||^2 + wS |mu - nu|^2``
   after its closed-form rigid alignment; the ``shortlist`` of lowest ``S``
   also get the colour cost ``C`` on the overlap with what is already
   synthesised, and one of the ``c`` lowest ``S + wC C`` is drawn.
   A target tip is never copied from a source end that runs into another
   branch (no tip there).
2. **Displacement** (:mod:`.displacement`): a smooth bi-Laplacian field
   bends the fragment so that its skeleton and edges fall exactly on the
   target's.
3. **Seams and colours** (:mod:`.blending`): a graph cut through the
   overlap with what is already synthesised, then a gradient-domain
   correction anchored to the fragment's own colours (no drift). At a
   furcation the parent's fragments are cleared around the branching
   point before the furcation fragment and the child are synthesised.
   Source pixels of other branches (annotated or merely branch-like, see
   :mod:`.regions`) are never copied, nor the fragment's own branch past
   the part that lands on the target skeleton.
4. **Gap completion** (:mod:`.completion`): the rest of the image is
   quilted from branch-free example pixels with graph-cut seams, so no
   pseudo-branch appears.

The parameters not given by the paper (``wC``, the shortlist, the density
of source fragments, the gap-completion settings) are documented in
:class:`ImageSynthesisParams`.
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import cv2
import numba
import numpy as np
from scipy import ndimage as ndi

from ..core.blending import compose_piece
from ..core.completion import complete_gaps
from ..core.image import as_float_image, as_mask, as_points, as_rgb
from ..core.io import encode_png
from ..core.params import check_params, param
from ..core.polyline import RigidTransform
from ..core.random import as_rng
from ..core.render import draw_polylines
from ..core.structure import Structure
from ..core.validate import Shape, checked
from .displacement import backward_map, displacement_field
from .fragments import (
    Fragment,
    FragmentLibrary,
    ShapeBank,
    choose_among_best,
    shape_vectors,
    source_fragments,
    target_fragments,
)
from .regions import ExampleRegions, colour_labels, example_regions, flat_colour_regions, flatten_shading, region_layout
from .skeleton_map import PixelMap, SkeletonMap

__all__ = ["ImageSynthesisParams", "ImageSynthesisResult", "FragmentMatch", "synthesize_image"]


@dataclass
class ImageSynthesisParams:
    """Parameters of :func:`synthesize_image`.

    The paper gives ``lambda = 0.75``, ``s = 3 r`` and ``wS = 2``; the rest
    (``k``, ``wC``, ``c``, the shortlist, the gap completion, which the paper
    did by hand) are this implementation's choices, tuned on the sample
    images.

    Parameters
    ----------
    lam : float, default 0.75
        ``lambda``: fragment centres are ``lambda * (s_i + s_{i+1})`` apart (paper:
        0.75).
    radius_scale : float, default 3.0
        Fragment radius ``s = radius_scale * r``, r the local thickness (paper: 3).
    min_radius : float, default 6.0
        Smallest fragment radius in pixels (for hairline branches).
    max_radius : float, default 64.0
        Largest fragment radius in pixels.
    k : int, default 9
        ``k``: skeleton samples per shape vector.
    w_s : float, default 2.0
        ``wS``: weight of the thickness difference ``|mu - nu|^2`` in S (paper: 2).
    w_c : float, default 1000.0
        ``wC``: weight of the colour cost C (mean squared colour difference on the
        overlap, branch and background pixels weighted equally) against S (squared
        pixels).
    c : int, default 2
        ``c``: choose at random among the c best source fragments (1 = greedy).
    shortlist : int, default 64
        Source fragments of lowest S whose colour cost C is evaluated.
    source_density : float, default 2.0
        Source fragment centres per paper spacing (1 = the paper's tiling; more =
        more candidates).
    reverse : bool, default True
        Also use source fragments read tip-to-root.
    displacement : bool, default True
        Bend fragments onto the target skeleton with the bi-Laplacian displacement
        field.
    match_thickness : bool, default True
        Also constrain the branch edges (r along the normal) so the displacement
        fixes the width too.
    displacement_step : int, default 2
        Grid step of the displacement solve (pixels).
    seams : {'graphcut', 'overlay'}, default 'graphcut'
        Graph-cut seams through overlaps, or plain overlay (baseline).
    poisson : bool, default True
        Gradient-domain (Poisson) photometric correction.
    anchors : bool, default True
        Extra boundary constraints of the Poisson correction (tie uncovered pixels
        to the fragment's colours: no drift).
    anchor_weight : float, default 10.0
        Weight of the Poisson anchor constraints.
    furcation_clear : float, default 0.6
        Fraction of a furcation fragment's radius cleared of the parent's fragments
        before the child is synthesised.
    exclusion : float, default 1.5
        Source pixels within exclusion * r + margin of a branch count as that branch
        (never copied for another branch or a gap).
    exclusion_margin : float, default 2.0
        Margin (pixels) added to the branch body.
    avoid_unannotated : bool, default True
        Also treat unannotated branch-like example pixels (faint branches the
        structure misses) as branches.
    avoid_salient : bool, default True
        Never copy salient spots (blobs much darker or brighter than their
        surroundings, e.g. a retina's optic disc and fovea) into gaps or for another
        branch: repeated, they would stand out.
    salient_z : float, default 6.0
        Robust z-score above which a spot counts as salient.
    branch_like : float, default 0.1
        Branch-likeness threshold: fraction of the way from the local background
        colour to the branch colour.
    flatten_shading : float, default 0.0
        Divide out the example's large-scale shading (vignetting, uneven light)
        before copying, so pieces from bright and dark parts match; Gaussian scale
        as a fraction of the example's size, e.g. 0.05 (0 = copy as is, the paper).
    exclude_matte : bool, default True
        Never copy a flat black/white matte connected to the example's border (e.g.
        around a fundus photo).
    flat_drawing : bool, default True
        Flat-colour examples (drawn maps, masks): draw the output the way the
        example is drawn (its region colours, its boundary line along the output's
        region boundary, branches as connected strokes of its line colour and
        measured width) instead of copying fragments (off: the paper's fragments).
    keep_regions : bool, default True
        Flat-colour examples (maps, masks): segment the example into its flat
        regions (land, sea), lay them out in the output as in the example, and fill
        every output pixel only from example pixels of its own region (seams follow
        region boundaries).
    flat_poisson : bool, default False
        Also run the Poisson correction on flat-colour examples (off: it would blur
        their flat colours into halos). Line art on one plain background (an
        ornament, a traced lightning bolt: at least half the pixels off the
        branches are one flat colour) counts as flat here, though its fragments
        are still copied (beyond the paper: the paper's Poisson step spread the
        strokes' ink into grey smudges around junctions and gap patches).
    completion : bool, default True
        Fill the gaps between branches automatically.
    relight_completion : bool, default True
        Gap completion copies the example's texture with its large-scale shading
        taken out and lights it like the fragments around it (a vignetted photo
        gives no square patches of another brightness; off: copy as is).
    patch_size : int, default 32
        Gap completion: patch side (pixels).
    patch_overlap : float, default 0.25
        Gap completion: overlap of neighbouring patches, as a fraction of the patch
        side.
    completion_tolerance : float, default 0.1
        Gap completion: windows within (1 + tol) of the best match are equally
        likely.
    completion_screen : float, default 0.05
        Gap completion: screening weight of the Poisson correction (corrections fade
        within ~1/sqrt(w) px of a seam; 0 = anchors only).
    completion_rim : int, default 3
        Gap completion: width (pixels) of the fragments' outer rim a patch's seam
        may cut into.
    min_free : float, default 0.0
        Gap completion: shrink patches until this fraction of the example's windows
        is wholly branch-free.
    forbid_weight : float, default 5.0
        Gap completion: penalty (in typical match costs) for windows whose branch
        pixels (never copied) would leave holes.

    Examples
    --------
    >>> ImageSynthesisParams(c=1, completion=False).lam
    0.75
    """

    lam: float = param(0.75, min=0.3, max=1.5, step=0.05, label="lambda",
                       help="lambda: fragment centres are lambda * (s_i + s_i+1) apart (paper: 0.75)")
    radius_scale: float = param(3.0, min=1.5, max=6.0, step=0.25,
                                help="fragment radius s = scale * local thickness r (paper: 3)")
    min_radius: float = param(6.0, min=2.0, max=32.0, step=1.0,
                              help="smallest fragment radius in pixels (for hairline branches)")
    max_radius: float = param(64.0, min=8.0, max=256.0, step=1.0,
                              help="largest fragment radius in pixels")
    k: int = param(9, min=3, max=33, step=1, help="k: skeleton samples per shape vector")
    w_s: float = param(2.0, min=0.0, max=20.0, step=0.1, label="wS",
                       help="wS: weight of the thickness difference |mu - nu|^2 in S (paper: 2)")
    w_c: float = param(1000.0, min=0.0, max=1e5, log=True, label="wC",
                       help="wC: weight of the colour cost C (mean squared colour difference "
                            "on the overlap, branch and background pixels weighted equally) "
                            "against S (squared pixels)")
    c: int = param(2, min=1, max=10, step=1,
                   help="c: choose at random among the c best source fragments (1 = greedy)")
    shortlist: int = param(64, min=1, max=256, step=1,
                           help="source fragments of lowest S whose colour cost C is evaluated")
    source_density: float = param(2.0, min=1.0, max=8.0, step=0.5,
                                  help="source fragment centres per paper spacing "
                                       "(1 = the paper's tiling; more = more candidates)")
    reverse: bool = param(True, help="also use source fragments read tip-to-root")
    displacement: bool = param(True, help="bend fragments onto the target skeleton with the "
                                          "bi-Laplacian displacement field")
    match_thickness: bool = param(True, help="also constrain the branch edges (r along the normal) "
                                             "so the displacement fixes the width too")
    displacement_step: int = param(2, min=1, max=8, step=1,
                                   help="grid step of the displacement solve (pixels)")
    seams: str = param("graphcut", options=("graphcut", "overlay"),
                       help="graph-cut seams through overlaps, or plain overlay (baseline)")
    poisson: bool = param(True, help="gradient-domain (Poisson) photometric correction")
    anchors: bool = param(True, help="extra boundary constraints of the Poisson correction "
                                     "(tie uncovered pixels to the fragment's colours: no drift)")
    anchor_weight: float = param(10.0, min=0.0, max=1000.0, log=True,
                                 help="weight of the Poisson anchor constraints")
    furcation_clear: float = param(0.6, min=0.0, max=1.0, step=0.05,
                                   help="fraction of a furcation fragment's radius cleared of the "
                                        "parent's fragments before the child is synthesised")
    exclusion: float = param(1.5, min=1.0, max=4.0, step=0.1,
                             help="source pixels within exclusion * r + margin of a branch count "
                                  "as that branch (never copied for another branch or a gap)")
    exclusion_margin: float = param(2.0, min=0.0, max=16.0, step=0.5,
                                    help="margin (pixels) added to the branch body")
    avoid_unannotated: bool = param(True, help="also treat unannotated branch-like example pixels "
                                               "(faint branches the structure misses) as branches")
    avoid_salient: bool = param(True, help="never copy salient spots (blobs much darker or brighter "
                                           "than their surroundings, e.g. a retina's optic disc and "
                                           "fovea) into gaps or for another branch: repeated, they "
                                           "would stand out")
    salient_z: float = param(6.0, min=2.0, max=20.0, step=0.5,
                             help="robust z-score above which a spot counts as salient")
    branch_like: float = param(0.1, min=0.02, max=2.0, step=0.05,
                               help="branch-likeness threshold: fraction of the way from the local "
                                    "background colour to the branch colour")
    flatten_shading: float = param(0.0, min=0.0, max=0.5, step=0.01,
                                   help="divide out the example's large-scale shading (vignetting, "
                                        "uneven light) before copying, so pieces from bright and "
                                        "dark parts match; Gaussian scale as a fraction of the "
                                        "example's size, e.g. 0.05 (0 = copy as is, the paper)")
    exclude_matte: bool = param(True, help="never copy a flat black/white matte connected to the "
                                           "example's border (e.g. around a fundus photo)")
    flat_drawing: bool = param(True, help="flat-colour examples (drawn maps, masks): draw the output the way "
                                          "the example is drawn (its region colours, its boundary line "
                                          "along the output's region boundary, branches as connected "
                                          "strokes of its line colour and measured width) instead of "
                                          "copying fragments (off: the paper's fragments)")
    keep_regions: bool = param(True, help="flat-colour examples (maps, masks): segment the example into "
                                          "its flat regions (land, sea), lay them out in the output as in "
                                          "the example, and fill every output pixel only from example "
                                          "pixels of its own region (seams follow region boundaries)")
    flat_poisson: bool = param(False, help="also run the Poisson correction on flat-colour examples (off: "
                                           "it would blur their flat colours into halos)")
    completion: bool = param(True, help="fill the gaps between branches automatically")
    relight_completion: bool = param(True, help="gap completion copies the example's texture with its "
                                                "large-scale shading taken out and lights it like the "
                                                "fragments around it (a vignetted photo gives no square "
                                                "patches of another brightness; off: copy as is)")
    patch_size: int = param(32, min=8, max=128, step=2,
                            help="gap completion: patch side (pixels)")
    patch_overlap: float = param(0.25, min=0.1, max=0.5, step=0.05,
                                 help="gap completion: overlap of neighbouring patches")
    completion_tolerance: float = param(0.1, min=0.0, max=1.0, step=0.05,
                                        help="gap completion: windows within (1 + tol) of the best "
                                             "match are equally likely")
    completion_screen: float = param(0.05, min=0.0, max=1.0, step=0.01,
                                     help="gap completion: screening weight of the Poisson "
                                          "correction (corrections fade within ~1/sqrt(w) px of a "
                                          "seam; 0 = anchors only)")
    completion_rim: int = param(3, min=0, max=16, step=1,
                                help="gap completion: width (pixels) of the fragments' outer rim "
                                     "a patch's seam may cut into")
    min_free: float = param(0.0, min=0.0, max=0.5, step=0.005,
                            help="gap completion: shrink patches until this fraction of the "
                                 "example's windows is wholly branch-free")
    forbid_weight: float = param(5.0, min=0.0, max=50.0, step=0.5,
                                 help="gap completion: penalty (in typical match costs) for windows "
                                      "whose branch pixels (never copied) would leave holes")


@dataclass
class FragmentMatch:
    """One synthesised target fragment and the source fragment chosen for it.

    Parameters
    ----------
    target, source : Fragment
        The target fragment (on the synthesised skeleton) and the source
        fragment (on the example's) copied into it.
    shape_cost : float
        ``S`` of the chosen candidate.
    colour_cost : float
        ``C`` of the chosen candidate.
    angle : float
        Rotation of the rigid alignment (radians).
    max_displacement : float
        Largest skeleton correction the displacement field applied (pixels).
    pixels : int
        Output pixels the fragment ended up providing.
    """

    target: Fragment
    source: Fragment
    shape_cost: float
    colour_cost: float
    angle: float
    max_displacement: float
    pixels: int


@dataclass
class ImageSynthesisResult:
    """Result of :func:`synthesize_image`.

    Parameters
    ----------
    image : (H, W, C) float32 ndarray
        The synthesised image (same channels as the example).
    fragment_mask : (H, W) bool ndarray
        Pixels provided by skeleton fragments.
    fill_mask : (H, W) bool ndarray
        Pixels provided by gap completion.
    source : (H, W, 2) float ndarray
        Example pixel (x, y) each output pixel was copied from (before the
        photometric correction); NaN where none.
    fragment_index : (H, W) int ndarray
        Index into ``fragments`` of the fragment that provided each pixel
        (-1 for gap completion).
    seams : (H, W) bool ndarray
        Seam pixels of all compositions (fragments and patches).
    fragments : list of FragmentMatch
        The source chosen for every target fragment, in synthesis order.
    seam_cost : float
        Sum of the seam costs of every composition.
    target : Structure
        The target structure (as given).
    example_regions : ExampleRegions
        Branch body, branch-like and unusable masks of the example.
    n_inpainted : int
        Output pixels no patch could fill (diffusion-inpainted; normally 0).
    timings : dict
        Seconds spent per stage.
    params : ImageSynthesisParams
        The parameters used.
    example_labels, labels : (H, W) int ndarray or None
        Flat-colour regions of the example and of the output
        (``params.keep_regions``).
    """

    image: np.ndarray
    fragment_mask: np.ndarray
    fill_mask: np.ndarray
    source: np.ndarray
    fragment_index: np.ndarray
    seams: np.ndarray
    fragments: list
    seam_cost: float
    target: Structure
    example_regions: ExampleRegions | None = None
    n_inpainted: int = 0
    timings: dict = field(default_factory=dict)
    params: ImageSynthesisParams | None = None
    #: Flat-colour regions of the example ((h, w) int; all 0 when it is not flat-coloured).
    example_labels: np.ndarray | None = None
    #: Region of every output pixel (None when regions were not kept).
    labels: np.ndarray | None = None

    def overlay(self, *, skeleton: bool = True, seams: bool = True) -> np.ndarray:
        """The image with the target skeleton (red) and the seams (yellow) drawn over it.

        Parameters
        ----------
        skeleton : bool, default True
            Draw the target skeleton in red.
        seams : bool, default True
            Draw the seams in yellow.

        Returns
        -------
        (H, W, 3) ndarray
            An RGB copy of the image with the overlays.
        """
        img = as_rgb(self.image) if self.image.shape[2] != 3 else self.image
        img = img.copy()
        if seams:
            img[self.seams] = 0.6 * img[self.seams] + 0.4 * np.array([1.0, 0.9, 0.0], np.float32)
        if skeleton:
            img = draw_polylines(img, [b.points for b in self.target.branches], widths=1.0,
                                 colors=(0.9, 0.1, 0.1))
        return img

    def _repr_png_(self) -> bytes:
        return encode_png(self.image)


# ---------------------------------------------------------------------------
# validation


def _check_structure(s, name: str, image_shape=None) -> Structure:
    if not isinstance(s, Structure):
        raise TypeError(f"{name} must be a branchnb.branching.Structure, got {type(s).__name__}")
    if not s.branches:
        raise ValueError(f"{name} is empty: it has no branches")
    if s.total_length <= 0:
        raise ValueError(f"{name} has zero total length: every branch is a single point")
    if image_shape is not None:
        for i, b in enumerate(s.branches):
            try:
                as_points(b.points, name=f"{name}.branches[{i}].points", image_shape=image_shape)
            except ValueError as exc:
                raise ValueError(f"{exc} (the example_image)" if name == "example_structure" else str(exc)) from None
    return s


# ---------------------------------------------------------------------------
# per-fragment helpers


@dataclass
class _Context:
    ex: np.ndarray
    sm_s: SkeletonMap
    sm_t: SkeletonMap
    pm_s: PixelMap
    excluded: np.ndarray   # example pixels of some branch (body or branch-like)
    unusable: np.ndarray   # example pixels never copied
    p: ImageSynthesisParams


def _sample(ex: np.ndarray, mx: np.ndarray, my: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Bilinear samples of ``ex`` at ``(mx, my)`` and where they lie inside it.

    Same as :func:`branchnb.core.warp.remap` on an already validated image,
    but only the example's region under the maps is handed to OpenCV.
    """
    h, w = ex.shape[:2]
    valid = (mx >= -0.5) & (mx <= w - 0.5) & (my >= -0.5) & (my <= h - 0.5)
    if not valid.any():
        return np.zeros(mx.shape + (ex.shape[2],), np.float32), valid
    x0 = int(np.clip(np.floor(mx.min()) - 1, 0, w - 1))
    x1 = int(np.clip(np.ceil(mx.max()) + 2, x0 + 1, w))
    y0 = int(np.clip(np.floor(my.min()) - 1, 0, h - 1))
    y1 = int(np.clip(np.ceil(my.max()) + 2, y0 + 1, h))
    roi = ex[y0:y1, x0:x1]
    out = cv2.remap(roi, mx - np.float32(x0), my - np.float32(y0), interpolation=cv2.INTER_LINEAR,
                    borderMode=cv2.BORDER_REPLICATE)
    if out.ndim == 2:
        out = out[:, :, None]
    return out, valid


def _free_ends(sm: SkeletonMap, pm: PixelMap) -> tuple[np.ndarray, np.ndarray]:
    """Which branch ends of the example are free tips.

    An end is *joined* (no tip) when it is a furcation (a child's start)
    or when another branch's body lies within ``2 r + 4`` pixels of it: the
    annotation (or the extraction) stopped the branch where it runs into
    another one. A target tip must not be copied from a joined end, or it
    would carry a piece of junction instead of a tip.
    """
    n = sm.n_branches
    h, w = pm.dist.shape
    other_body = pm.dist <= pm.radius + 1.0
    free = np.zeros((n, 2), bool)
    for b in range(n):
        for k, arc in enumerate((0.0, float(sm.lengths[b]))):
            if k == 0 and sm.parent(b) is not None:
                continue
            x, y = sm.position(b, arc)
            rad = 2.0 * float(sm.thickness(b, arc)) + 4.0
            x0, x1 = max(int(x - rad), 0), min(int(x + rad) + 2, w)
            y0, y1 = max(int(y - rad), 0), min(int(y + rad) + 2, h)
            if x0 >= x1 or y0 >= y1:
                continue
            yy, xx = np.mgrid[y0:y1, x0:x1]
            disk = (xx - x) ** 2 + (yy - y) ** 2 <= rad * rad
            blk = (y0, y1, x0, x1)
            others = other_body[blk[0]:blk[1], blk[2]:blk[3]] & (pm.branch[blk[0]:blk[1], blk[2]:blk[3]] != b)
            free[b, k] = not (disk & others).any()
    return free[:, 0], free[:, 1]


def _joined_at_region_edge(sm: SkeletonMap, labels: np.ndarray, free_start: np.ndarray,
                           free_end: np.ndarray) -> None:
    """An example end where the branch meets another flat region (a channel's mouth at the
    sea) is no tip either: copied as one it would carry a piece of that region (a blob)."""
    h, w = labels.shape
    for b in range(sm.n_branches):
        xm, ym = sm.position(b, 0.5 * float(sm.lengths[b]))
        own = labels[int(np.clip(round(ym), 0, h - 1)), int(np.clip(round(xm), 0, w - 1))]
        for arr, arc in ((free_start, 0.0), (free_end, float(sm.lengths[b]))):
            if not arr[b]:
                continue
            x, y = sm.position(b, arc)
            rad = 2.0 * float(sm.thickness(b, arc)) + 4.0
            x0, x1 = max(int(x - rad), 0), min(int(x + rad) + 2, w)
            y0, y1 = max(int(y - rad), 0), min(int(y + rad) + 2, h)
            if x0 < x1 and y0 < y1 and np.any(labels[y0:y1, x0:x1] != own):
                arr[b] = False


def _tip_penalty(sm_t: SkeletonMap, tf: Fragment, lib: FragmentLibrary, lengths: np.ndarray,
                 free_start: np.ndarray, free_end: np.ndarray, free_t) -> np.ndarray:
    """Rule out source windows that end at a joined end where the target window ends at a free tip."""
    R = tf.radius
    L_t = float(sm_t.lengths[tf.branch])
    pen = np.zeros(len(lib))
    tip_fwd = tf.arc + R > L_t and free_t[1][tf.branch]
    tip_bwd = tf.arc - R < 0 and free_t[0][tf.branch]
    if not (tip_fwd or tip_bwd):
        return pen
    L = lengths[lib.branch]
    fwd = lib.sign > 0
    # Ends reached when reading forward / backward from the candidate's centre.
    end_fwd_free = np.where(fwd, free_end[lib.branch], free_start[lib.branch])
    end_bwd_free = np.where(fwd, free_start[lib.branch], free_end[lib.branch])
    clamps_fwd = np.where(fwd, lib.arc + R > L, lib.arc - R < 0)
    clamps_bwd = np.where(fwd, lib.arc - R < 0, lib.arc + R > L)
    bad = np.zeros(len(lib), bool)
    if tip_fwd:
        bad |= clamps_fwd & ~end_fwd_free
    if tip_bwd:
        bad |= clamps_bwd & ~end_bwd_free
    pen[bad] = 1e6
    return pen


def _target_window(sm: SkeletonMap, branch: int, arc: float, radius: float):
    """Offsets range ``[lo, hi]`` of the target disk that lies on ``branch``."""
    L = float(sm.lengths[branch])
    lo = -arc if arc - 1.5 * radius < 0 else -np.inf
    hi = L - arc if arc + 1.5 * radius > L else np.inf
    return lo, hi


def _allowed(ctx: _Context, mx, my, lib: FragmentLibrary, idx, tgt: Fragment) -> np.ndarray:
    """Source pixels fragments may copy: not the matte, not any other branch
    (annotated body or branch-like), nor their own branch beyond the part
    that lands on the target skeleton.

    ``mx, my`` are ``(N, h, w)`` source coordinates of candidates ``idx`` of ``lib``.
    """
    h, w = ctx.pm_s.dist.shape
    ix = np.clip(np.rint(mx).astype(np.int64), 0, w - 1)
    iy = np.clip(np.rint(my).astype(np.int64), 0, h - 1)
    excl = ctx.excluded[iy, ix]
    owner = ctx.pm_s.branch[iy, ix]
    arc = ctx.pm_s.arc[iy, ix]
    slack = 0.5
    idx = np.atleast_1d(idx)

    def in_window(branch_s, centre_s, sign, lo, hi):
        a, b = centre_s + sign * lo, centre_s + sign * hi
        lo_s = np.minimum(a, b)[:, None, None] - slack
        hi_s = np.maximum(a, b)[:, None, None] + slack
        return (owner == branch_s[:, None, None]) & (arc >= lo_s) & (arc <= hi_s)

    lo, hi = _target_window(ctx.sm_t, tgt.branch, tgt.arc, tgt.radius)
    ok = in_window(lib.branch[idx], lib.arc[idx], lib.sign[idx], lo, hi)
    if tgt.kind == "furcation":
        Lc = float(ctx.sm_t.lengths[tgt.child])
        zero = np.zeros(len(idx))
        ok |= in_window(lib.child[idx], zero, zero + 1.0, -np.inf,
                        Lc if Lc < 1.5 * tgt.radius else np.inf)
    return (~excl | ok) & ~ctx.unusable[iy, ix]


@numba.njit(cache=True)
def _colour_cost_kernel(ex, xs, ys, rot, trans, excluded, owner, arcmap, unusable, win_b, win_lo, win_hi,
                        ref, on_body):
    """Colour cost of every candidate on the overlap pixels ``(xs, ys)`` (see :func:`_colour_costs`).

    Per candidate and pixel: the rigid backward map (float32, as :func:`~.displacement.backward_map`),
    the rules of :func:`_allowed` and bilinear sampling with a replicated border (as ``cv2.remap``),
    without building the ``(candidates, pixels)`` arrays.
    """
    h, w, C = ex.shape
    n, P = rot.shape[0], xs.shape[0]
    out = np.zeros(n)
    for k in range(n):
        s_on, s_off, n_on, n_off = 0.0, 0.0, 0, 0
        for p in range(P):
            X = np.float64(xs[p]) - trans[k, 0]
            Y = np.float64(ys[p]) - trans[k, 1]
            mx = np.float32(rot[k, 0, 0] * X + rot[k, 1, 0] * Y)
            my = np.float32(rot[k, 0, 1] * X + rot[k, 1, 1] * Y)
            if not (mx >= -0.5 and mx <= w - 0.5 and my >= -0.5 and my <= h - 0.5):
                continue
            ix = min(max(int(np.rint(mx)), 0), w - 1)
            iy = min(max(int(np.rint(my)), 0), h - 1)
            if unusable[iy, ix]:
                continue
            if excluded[iy, ix]:
                ok = False
                for t in range(win_b.shape[1]):
                    if owner[iy, ix] == win_b[k, t] and win_lo[k, t] <= arcmap[iy, ix] <= win_hi[k, t]:
                        ok = True
                if not ok:
                    continue
            fx0, fy0 = np.floor(mx), np.floor(my)
            x0, y0 = int(fx0), int(fy0)
            fx, fy = mx - fx0, my - fy0
            xa, xb = min(max(x0, 0), w - 1), min(max(x0 + 1, 0), w - 1)
            ya, yb = min(max(y0, 0), h - 1), min(max(y0 + 1, 0), h - 1)
            d = 0.0
            for c in range(C):
                v = ((1 - fy) * ((1 - fx) * ex[ya, xa, c] + fx * ex[ya, xb, c])
                     + fy * ((1 - fx) * ex[yb, xa, c] + fx * ex[yb, xb, c]))
                e = v - ref[p, c]
                d += e * e
            if on_body[p]:
                s_on += d
                n_on += 1
            else:
                s_off += d
                n_off += 1
        if n_on > 0 and n_off > 0:
            out[k] = 0.5 * (s_on / n_on + s_off / n_off)
        elif n_on > 0:
            out[k] = s_on / n_on
        elif n_off > 0:
            out[k] = s_off / n_off
    return out


def _colour_costs(ctx: _Context, lib: FragmentLibrary, idx, rot, trans, tgt: Fragment,
                  origin, size: int, disk, ex_win, cov_win, body_win) -> np.ndarray:
    """Colour cost ``C`` of candidates ``idx`` (rigidly placed by ``rot, trans``) on the overlap.

    The mean over the overlap pixels on the target branch body and the
    mean over the others count half each, so that the few branch pixels
    weigh as much as the background around them: a candidate whose
    branch does not continue the previous fragment's is not outscored by
    a blank one that merely matches the background.

    Only the window pixels inside the disk that are already synthesised
    can be in an overlap: the candidates are sampled there only, each
    source pixel under the rules of :func:`_allowed`.
    """
    idx = np.atleast_1d(idx)
    n = len(idx)
    rr, cc = np.nonzero(disk & cov_win)
    if n == 0 or len(rr) == 0:
        return np.zeros(n)
    # the source windows of :func:`_allowed` (own branch; for a furcation also the child)
    slack = 0.5
    lo, hi = _target_window(ctx.sm_t, tgt.branch, tgt.arc, tgt.radius)
    wins = [(lib.branch[idx], lib.arc[idx], lib.sign[idx], lo, hi)]
    if tgt.kind == "furcation":
        Lc = float(ctx.sm_t.lengths[tgt.child])
        zero = np.zeros(n)
        wins.append((lib.child[idx], zero, zero + 1.0, -np.inf, Lc if Lc < 1.5 * tgt.radius else np.inf))
    win_b = np.stack([w[0] for w in wins], 1).astype(np.int64)
    ends = [(w[1] + w[2] * w[3], w[1] + w[2] * w[4]) for w in wins]
    win_lo = np.stack([np.minimum(a, b) - slack for a, b in ends], 1)
    win_hi = np.stack([np.maximum(a, b) + slack for a, b in ends], 1)
    ex = ctx.ex if ctx.ex.flags.c_contiguous else np.ascontiguousarray(ctx.ex)
    return _colour_cost_kernel(ex, cc.astype(np.float32) + np.float32(origin[0]),
                               rr.astype(np.float32) + np.float32(origin[1]),
                               np.ascontiguousarray(rot, np.float64), np.ascontiguousarray(trans, np.float64),
                               ctx.excluded, ctx.pm_s.branch, ctx.pm_s.arc, ctx.unusable, win_b, win_lo, win_hi,
                               np.ascontiguousarray(ex_win[rr, cc], np.float32), body_win[rr, cc])


def _constraints(ctx: _Context, src: Fragment, tgt: Fragment, rot, trans):
    """Target points ``q`` and displacements ``q - (R p + t)`` of the skeleton (and edges)."""
    sm_s, sm_t = ctx.sm_s, ctx.sm_t
    R = tgt.radius
    step = max(1.0, float(ctx.p.displacement_step))
    o = np.arange(-R, R + 1e-9, step)
    o = o[~sm_t.clamped(np.full(len(o), tgt.branch), tgt.arc + o)]
    parts = [(tgt.branch, tgt.arc, src.branch, src.arc, src.sign, o)]
    if tgt.kind == "furcation":
        oc = np.arange(step, R + 1e-9, step)
        oc = oc[~sm_t.clamped(np.full(len(oc), tgt.child), oc)]
        parts.append((tgt.child, 0.0, src.child, 0.0, 1.0, oc))
    parts = [pt for pt in parts if len(pt[5])]
    if not parts:
        return np.zeros((0, 2)), np.zeros((0, 2))
    # All queries of both structures in one batch per map (the skeleton
    # queries are elementwise: same values as one call per part, far
    # fewer calls per fragment).
    bt = np.concatenate([np.full(len(pt[5]), pt[0], np.int64) for pt in parts])
    at = np.concatenate([pt[1] + pt[5] for pt in parts])
    bs = np.concatenate([np.full(len(pt[5]), pt[2], np.int64) for pt in parts])
    sg = np.concatenate([np.full(len(pt[5]), float(pt[4])) for pt in parts])
    as_ = np.concatenate([pt[3] + pt[4] * pt[5] for pt in parts])
    if ctx.p.match_thickness:
        # positions, thicknesses and tangents in one batch per map (the same values)
        q_all, rt_all, tt_all = sm_t._frame(bt, at, 1.0)
        p_all, rs_all, ts_all = sm_s._frame(bs, as_, sg)
    else:
        q_all = sm_t.position(bt, at)
        p_all = sm_s.position(bs, as_)
    qs, ds = [], []
    i0 = 0
    for pt in parts:
        sl = slice(i0, i0 + len(pt[5]))
        i0 += len(pt[5])
        q, pp = q_all[sl], p_all[sl]
        qs.append(q)
        ds.append(q - (pp @ rot.T + trans))
        if ctx.p.match_thickness:
            rt, rs, tt, ts = rt_all[sl], rs_all[sl], tt_all[sl], ts_all[sl]
            nt = np.stack([-tt[:, 1], tt[:, 0]], 1)
            ns = np.stack([-ts[:, 1], ts[:, 0]], 1)
            for side in (1.0, -1.0):
                qe = q + side * rt[:, None] * nt
                pe = pp + side * rs[:, None] * ns
                qs.append(qe)
                ds.append(qe - (pe @ rot.T + trans))
    if not qs:
        return np.zeros((0, 2)), np.zeros((0, 2))
    return np.vstack(qs), np.vstack(ds)


# ---------------------------------------------------------------------------
# the public entry


#: The example side of the last call (its skeleton and pixel maps, regions, fragment library and
#: shape vectors) is kept for the next call with the same example, structure, mask and parameters:
#: a second render of one example (the app, the bench's repeats, several targets) skips it.
_EXAMPLE_CACHE: dict = {}


def _example_key(ex: np.ndarray, example_structure: Structure, example_mask, p) -> tuple:
    import hashlib

    h = hashlib.blake2b(np.ascontiguousarray(ex).view(np.uint8).ravel(), digest_size=16)
    if example_mask is not None:
        h.update(np.ascontiguousarray(example_mask).view(np.uint8).ravel())
    # the structure by its arrays (what the cached maps and fragments depend on; no JSON text)
    for b in example_structure.branches:
        pts = np.ascontiguousarray(b.points, np.float64)
        h.update(repr((pts.shape, b.parent, b.parent_vertex)).encode())
        h.update(pts.view(np.uint8).ravel())
        h.update(np.ascontiguousarray(np.broadcast_to(np.asarray(b.thickness, np.float64), pts.shape[:1])
                                      ).view(np.uint8).ravel())
    return (ex.shape, str(ex.dtype), example_mask is not None, h.hexdigest(),
            len(example_structure.branches), repr(example_structure.image_shape), repr(p))


@checked(shape=Shape())
def synthesize_image(example_image, example_structure: Structure, target_structure,
                     params: ImageSynthesisParams | None = None, rng=None,
                     progress: Callable[[float, str], None] | None = None, *,
                     shape: tuple[int, int] | None = None,
                     example_mask=None, target_regions=None, target_domain=None) -> ImageSynthesisResult:
    """Synthesise the image of ``target_structure`` with the texture of an example.

    Parameters
    ----------
    example_image : (H, W[, C]) array_like
        The example. Grayscale gives a grayscale result; RGBA images are
        synthesised with alpha as a fourth channel (so transparent
        examples give transparent results).
    example_structure : Structure
        The example's branches (every vertex inside the example image).
    target_structure : Structure or SynthesisResult
        The branches to synthesise. Parts outside the output are cropped;
        at least one vertex must lie inside. A
        :class:`~branchnb.branching.SynthesisResult` also gives the domain
        its structure grew in (``target_domain``).
    params : ImageSynthesisParams, optional
        Fragment, seam, correction and gap-completion settings; None = the
        defaults (the paper's ``lambda``, ``s = 3 r``, ``wS``).
    rng : int or numpy.random.Generator, optional
        Seed for the random choices (same seed, same image).
    progress : callable(fraction: float, text: str), optional
        Called as the synthesis advances (e.g. a progress bar).
    shape : (H, W), optional
        Output size: ``target_structure.image_shape``, else the example's.
    example_mask : (H, W) bool array_like, optional
        Example pixels that may be copied at all (default: all but a flat
        black/white matte, see ``params.exclude_matte``).
    target_regions : (H, W) int array_like, optional
        Region label of every output pixel (labels of
        ``ImageSynthesisResult.example_labels``), for flat-colour examples
        with ``params.keep_regions``; default: the example's regions laid
        out around the target branches as they lie around the example's
        (:func:`~branchnb.branching.regions.target_layout`).
    target_domain : (H, W) bool array_like, optional
        Where the target structure grew (``SynthesisResult.domain``): for
        flat-colour examples the output's branch region (the land) is
        exactly this domain and every other pixel takes the region that
        lies outside the example's branch region (the sea).

    Returns
    -------
    ImageSynthesisResult

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.core.structure import Structure, Branch
    >>> rng = np.random.default_rng(0)
    >>> img = (0.6 + 0.1 * rng.random((64, 64, 3))).astype(np.float32)
    >>> img[30:34, 4:60] = 0.1                                    # a dark horizontal branch
    >>> src = Structure([Branch([(4, 31.5), (59, 31.5)], 2.0)])
    >>> tgt = Structure([Branch([(31.5, 4), (31.5, 59)], 2.0)])   # the same, vertical
    >>> out = synthesize_image(img, src, tgt, rng=0)
    >>> bool(out.image[30, 31, 0] < 0.3 and out.image[10, 10, 0] > 0.5)
    True
    """
    t_start = time.perf_counter()
    if params is None:
        params = ImageSynthesisParams()
    if not isinstance(params, ImageSynthesisParams):
        raise TypeError(f"params must be ImageSynthesisParams, got {type(params).__name__}")
    p = check_params(params)
    rng = as_rng(rng)
    if progress is not None and not callable(progress):
        raise TypeError("progress must be a callable(fraction, text) or None")
    from .synthesis import SynthesisResult

    if isinstance(target_structure, SynthesisResult):
        if target_domain is None:
            target_domain = target_structure.domain
        target_structure = target_structure.structure
    ex = as_float_image(example_image, name="example_image")
    _check_structure(example_structure, "example_structure", ex.shape[:2])
    _check_structure(target_structure, "target_structure")
    if example_mask is not None:
        example_mask = as_mask(example_mask, shape=ex.shape[:2], name="example_mask")
    if shape is None:
        shape = target_structure.image_shape or ex.shape[:2]
    H, W = int(shape[0]), int(shape[1])
    if H < 1 or W < 1:
        raise ValueError(f"shape must be positive, got {shape}")
    pts = np.vstack([b.points for b in target_structure.branches])
    inside = (pts[:, 0] >= -0.5) & (pts[:, 0] <= W - 0.5) & (pts[:, 1] >= -0.5) & (pts[:, 1] <= H - 0.5)
    if not inside.any():
        raise ValueError(f"target_structure lies entirely outside the {W} x {H} output (shape)")

    def report(frac, text):
        if progress is not None:
            progress(float(min(max(frac, 0.0), 1.0)), text)

    report(0.0, "preparing fragments")
    timings = {}
    key = _example_key(ex, example_structure, example_mask, p)
    cached = _EXAMPLE_CACHE.get(key)
    if cached is None:
        _EXAMPLE_CACHE.clear()
        sm_s = SkeletonMap(example_structure, 1.0)
        pm_s = sm_s.pixel_map(ex.shape[:2])
        # Flat-colour examples (maps, masks): their regions, and no matte / Poisson.
        labels_ex, flat_share = flat_colour_regions(ex, pm_s.core(p.exclusion, p.exclusion_margin))
        cached = _EXAMPLE_CACHE[key] = {"sm_s": sm_s, "pm_s": pm_s, "labels_ex": labels_ex,
                                        "flat_share": flat_share}
    sm_s, pm_s, labels_ex, flat_share = (cached[k] for k in ("sm_s", "pm_s", "labels_ex", "flat_share"))
    sm_t = SkeletonMap(target_structure, 1.0)
    pm_t = sm_t.pixel_map((H, W))
    flat = bool(flat_share >= 0.5 and labels_ex.max() >= 1)
    labels_t = None
    src_labels = labels_ex
    layout = labels_ex
    if target_domain is not None:
        target_domain = as_mask(target_domain, shape=(H, W), name="target_domain")
    if flat and (p.keep_regions or p.flat_drawing):
        # a source pixel's region is its colour's (a white rim is water wherever it lies)
        zone = pm_s.core(2.0 * p.exclusion, 2.0 * p.exclusion_margin)
        src_labels = colour_labels(ex, labels_ex, ~zone)
        # the example's land and sea around its branches (not its channels)
        layout = region_layout(src_labels, zone, pm_s.core(1.0, 0.0))
        if target_regions is not None:
            labels_t = np.asarray(target_regions)
            if labels_t.shape != (H, W) or not np.issubdtype(labels_t.dtype, np.integer):
                raise ValueError(f"target_regions must be an integer (H, W) = {(H, W)} label map")
        elif target_domain is not None:
            labels_t = _domain_labels(layout, pm_s, target_domain, src_labels)
        elif _grew_in_example_layout(layout, pm_s, pm_t):
            labels_t = _example_layout_for(layout, pm_s, pm_t)
        else:
            # laid out around the target's branches as they lie around the example's
            from .regions import target_layout

            labels_t = target_layout(layout, example_structure, target_structure, (H, W),
                                     pm_example=pm_s, pm_target=pm_t)
    if flat and p.flat_drawing:
        return _draw_flat(ex, example_structure, target_structure, layout, labels_t, target_domain,
                          pm_s, labels_ex, p, t_start, report, (H, W))
    # Line art on one plain background has a single flat region (so it is not
    # drawn in style like a map) but Poisson blending still smudges its ink.
    use_poisson = p.poisson and (flat_share < 0.5 or p.flat_poisson)
    geo = dict(lam=p.lam, scale=p.radius_scale, min_radius=p.min_radius, max_radius=p.max_radius)
    if "regions" not in cached:
        regions = example_regions(ex, pm_s, exclusion=p.exclusion, margin=p.exclusion_margin,
                                  threshold=p.branch_like if p.avoid_unannotated else None,
                                  matte=p.exclude_matte and not flat, example_mask=example_mask,
                                  salient=p.salient_z if p.avoid_salient else None)
        if p.flatten_shading > 0:
            bg = ~(regions.forbidden | ndi.binary_dilation(regions.body | regions.branch_like, iterations=3))
            ex = flatten_shading(ex, bg, p.flatten_shading * max(ex.shape[:2]))
        excluded = regions.body | regions.branch_like
        if regions.salient is not None:
            excluded = excluded | regions.salient
        lib_b, lib_f = source_fragments(sm_s, density=p.source_density, reverse=p.reverse, **geo)
        free_start, free_end = _free_ends(sm_s, pm_s)
        if labels_ex.max() >= 1:
            _joined_at_region_edge(sm_s, labels_ex, free_start, free_end)
        cached.update(regions=regions, ex=ex, excluded=excluded, lib_b=lib_b, lib_f=lib_f,
                      free_start=free_start, free_end=free_end, vec_cache={})
    regions, ex, excluded, lib_b, lib_f = (cached[k] for k in ("regions", "ex", "excluded", "lib_b", "lib_f"))
    free_start, free_end = cached["free_start"].copy(), cached["free_end"].copy()
    ctx = _Context(ex, sm_s, sm_t, pm_s, excluded, regions.unusable, p)
    free_t = _free_ends(sm_t, pm_t)
    if len(lib_b) == 0:
        raise ValueError("example_structure yields no source fragment (all branches have zero length)")
    # Without a furcation in the example, children start with ordinary fragments.
    targets = target_fragments(sm_t, furcations=len(lib_f) > 0, **geo)
    timings["prepare"] = time.perf_counter() - t_start

    C = ex.shape[2]
    canvas = np.zeros((H, W, C), np.float32)
    covered = np.zeros((H, W), bool)
    owner = np.full((H, W), -1, np.int64)  # target branch whose fragment provided the pixel
    source = np.full((H, W, 2), np.nan)
    frag_index = np.full((H, W), -1, np.int64)
    seams = np.zeros((H, W), bool)
    body = pm_t.core(1.0, 1.0)
    matches: list[FragmentMatch] = []
    total_seam = 0.0
    t0 = time.perf_counter()
    frag_share = 0.6 if p.completion else 1.0
    # Shape vectors of the source library depend on the target radius only
    # through the sampling offsets: cache them per radius.
    vec_cache: dict = {}
    banks: dict = cached["vec_cache"]  # across calls, by exact radius (a call's first radius per key)
    if len(banks) > 512:
        banks.clear()
    # The targets' own shape vectors, one batched query per (kind, radius)
    # (elementwise skeleton queries: the values of one call per fragment).
    tgt_vec: list = [None] * len(targets)
    groups: dict = {}
    for i, tf in enumerate(targets):
        groups.setdefault((tf.kind, tf.radius), []).append(i)
    for (kind, R), ids in groups.items():
        tq, tnu = shape_vectors(sm_t, [targets[i].branch for i in ids], [targets[i].arc for i in ids],
                                np.ones(len(ids)), R, p.k,
                                [targets[i].child for i in ids] if kind == "furcation" else None)
        for j, i in enumerate(ids):
            tgt_vec[i] = (tq[j], tnu[j])
    for i, tf in enumerate(targets):
        if i % 8 == 0:
            report(frag_share * i / max(len(targets), 1), f"fragment {i + 1} / {len(targets)}")
        R = tf.radius
        pad = 2
        x0 = int(np.floor(tf.center[0] - R)) - pad
        y0 = int(np.floor(tf.center[1] - R)) - pad
        size = int(np.ceil(2 * R)) + 2 * pad + 2
        if x0 + size <= 0 or y0 + size <= 0 or x0 >= W or y0 >= H:
            continue
        lib: FragmentLibrary = lib_f if tf.kind == "furcation" else lib_b
        q0, nu0 = tgt_vec[i]
        key = (tf.kind, round(R, 2))
        if key not in vec_cache:
            exact = (tf.kind, float(R))
            if exact not in banks:
                banks[exact] = ShapeBank(*shape_vectors(sm_s, lib.branch, lib.arc, lib.sign, R, p.k,
                                                        lib.child if tf.kind == "furcation" else None))
            vec_cache[key] = banks[exact]
        bank = vec_cache[key]
        S = bank.costs(q0, nu0, p.w_s)
        if tf.kind == "branch":
            S = S + _tip_penalty(sm_t, tf, lib_b, sm_s.lengths, free_start, free_end, free_t)
        n_short = min(p.shortlist, len(S))
        short = np.argpartition(S, n_short - 1)[:n_short] if n_short < len(S) else np.arange(len(S))
        short = short[np.argsort(S[short], kind="stable")]
        rot, trans = bank.fit(short, q0)
        yy, xx = np.arange(size)[:, None], np.arange(size)[None, :]   # (broadcast: no full grids)
        disk = (xx + x0 - tf.center[0]) ** 2 + (yy + y0 - tf.center[1]) ** 2 <= R * R
        # Existing canvas under the window (zero outside the image).
        ex_win, cov_win = _window(canvas, covered, x0, y0, size)
        costs_c = np.zeros(len(short))
        if p.w_c > 0 and cov_win.any():
            costs_c = _colour_costs(ctx, lib, short, rot, trans, tf, (x0, y0), size, disk,
                                    ex_win, cov_win, _crop(body, x0, y0, size, False))
        j = choose_among_best(S[short] + p.w_c * costs_c, p.c, rng)
        pick = int(short[j])
        src = lib[pick]
        # the shortlist's closed-form alignment (what rigid_align gives, to rounding)
        T = RigidTransform(rotation=rot[j], translation=trans[j])
        fld = None
        max_disp = 0.0
        if p.displacement:
            qc, dc = _constraints(ctx, src, tf, T.rotation, T.translation)
            if len(qc):
                max_disp = float(np.hypot(*dc.T).max())
                fld = displacement_field((size, size), qc - (x0, y0), dc,
                                         step=p.displacement_step)
        mx, my = backward_map((x0, y0), (size, size), T.rotation, T.translation, fld)
        pix, inimg = _sample(ex, mx, my)
        mine = [tf.branch] if tf.kind == "branch" else [tf.branch, tf.child]
        b_win = _crop(pm_t.branch, x0, y0, size, -1)
        body_win = _crop(body, x0, y0, size, False)
        own_body = body_win & _one_of(b_win, mine)
        if tf.kind == "branch":
            lo, hi = _target_window(sm_t, tf.branch, tf.arc, R)
            a_win = _crop(pm_t.arc, x0, y0, size, 0.0)
            own_body &= (a_win >= tf.arc + max(lo, -R) - 1) & (a_win <= tf.arc + min(hi, R) + 1)
        # The fragment's own branch body is always taken from it (even where
        # the source shows a neighbouring branch there: branch texture in a
        # branch beats a hole filled with background later).
        allowed = _allowed(ctx, mx[None], my[None], lib, pick, tf)[0]
        src_ok = ~ctx.unusable[np.clip(np.rint(my).astype(np.int64), 0, ex.shape[0] - 1),
                               np.clip(np.rint(mx).astype(np.int64), 0, ex.shape[1] - 1)]
        valid = disk & inimg & (allowed | (own_body & src_ok))
        if labels_t is not None:
            # background pixels only from the target pixel's own region (land from land)
            src_lab = src_labels[np.clip(np.rint(my).astype(np.int64), 0, ex.shape[0] - 1),
                                np.clip(np.rint(mx).astype(np.int64), 0, ex.shape[1] - 1)]
            valid &= (src_lab == _crop(labels_t, x0, y0, size, -1)) | own_body
        own_win = _crop(owner, x0, y0, size, -1)
        protect_piece = own_body & ~_one_of(own_win, mine) & valid
        protect_canvas = body_win & ~_one_of(b_win, mine)
        if tf.kind == "furcation" and p.furcation_clear > 0:
            clear = ((xx + x0 - tf.center[0]) ** 2 + (yy + y0 - tf.center[1]) ** 2
                     <= (p.furcation_clear * R) ** 2) & valid & ~protect_canvas
            _uncover(covered, clear, x0, y0)
        comp = compose_piece(canvas, covered, pix, valid, (x0, y0), protect_canvas=protect_canvas,
                             protect_piece=protect_piece, method=p.seams, poisson=use_poisson,
                             anchored=p.anchors, anchor_weight=p.anchor_weight)
        n_pix = 0
        if comp is not None:
            wr, wc = comp.window
            tk = comp.take
            n_pix = int(tk.sum())
            total_seam += comp.cost
            seams[wr, wc] |= comp.seam
            o_sub = owner[wr, wc]
            if tf.kind == "furcation":
                o_sub[tk] = np.where(pm_t.branch[wr, wc][tk] == tf.child, tf.child, tf.branch)
            else:
                o_sub[tk] = tf.branch
            frag_index[wr, wc][tk] = len(matches)
            sm_x, sm_y = mx[comp.sub], my[comp.sub]
            source[wr, wc, 0][tk] = sm_x[tk]
            source[wr, wc, 1][tk] = sm_y[tk]
        matches.append(FragmentMatch(tf, src, float(S[pick]), float(costs_c[j]), T.angle,
                                     max_disp, n_pix))
    # Pixels a later fragment uncovered (furcation clearing) and nobody retook.
    frag_index[~covered] = -1
    source[~covered] = np.nan
    timings["fragments"] = time.perf_counter() - t0

    fill = np.zeros((H, W), bool)
    n_inpainted = 0
    if p.completion and not covered.all():
        t1 = time.perf_counter()

        def sub_progress(frac, text):
            report(frag_share + (1.0 - frag_share) * frac, text)

        # Patches may only cut into a thin rim of the fragments (to hide the
        # disks' edges), never into the branches.
        rim = int(p.completion_rim)
        inner = ndi.binary_erosion(covered, iterations=rim, border_value=1) if rim > 0 else covered
        relit = None
        if p.relight_completion and not flat:
            relit = _relight_setup(ex, canvas, covered, regions, body, p.patch_size, pm_s.dist, pm_t.dist)
            if relit is not None:
                ex_fill, canvas, offset_t = relit
        comp = complete_gaps(canvas, covered, ex if relit is None else ex_fill, regions.forbidden,
                             patch_size=p.patch_size,
                             overlap=p.patch_overlap, protect=(body & covered) | inner,
                             tolerance=p.completion_tolerance, forbid_weight=p.forbid_weight,
                             min_free=p.min_free,
                             method=p.seams, poisson=use_poisson, anchored=p.anchors,
                             anchor_weight=p.anchor_weight,
                             screen=p.completion_screen if p.anchors else 0.0,
                             rng=rng, progress=sub_progress, regions=labels_t,
                             example_regions=src_labels if labels_t is not None else None, fast=True)
        if relit is not None:
            canvas += offset_t      # back to the output's own light (fragments: exactly as before)
        fill = comp.filled
        source[fill] = comp.source[fill]
        frag_index[fill] = -1
        seams |= comp.seams
        total_seam += comp.seam_cost
        n_inpainted = comp.n_inpainted
        timings["completion"] = time.perf_counter() - t1
    fragment_mask = frag_index >= 0
    # Every stage keeps [0, 1]; this guards the contract (finite, in range) for any input.
    np.clip(np.nan_to_num(canvas, nan=0.0), 0.0, 1.0, out=canvas)
    timings["total"] = time.perf_counter() - t_start
    report(1.0, "done")
    return ImageSynthesisResult(canvas, fragment_mask, fill, source, frag_index, seams, matches,
                                total_seam, target_structure, regions, n_inpainted, timings, p,
                                example_labels=labels_ex, labels=labels_t)


def _relight_setup(ex: np.ndarray, canvas: np.ndarray, covered: np.ndarray, regions: ExampleRegions,
                   body: np.ndarray, patch_size: int, dist: np.ndarray, dist_t: np.ndarray,
                   prior: float = 0.25):
    """Shading-free example and canvas for gap completion (going beyond the paper).

    The paper fills the gaps by hand. Copied automatically, square patches
    of a vignetted or unevenly lit photo (a fundus image) carry the light of
    the place they come from: bright and dark squares side by side that no
    seam hides. Here the example's background is shifted by its own
    large-scale shading (Gaussian, ``sigma = 2 * patch_size``: larger than a
    patch, so the texture inside a patch is kept) to its mean level, and the
    canvas by the shading of the fragments already in place (their
    background, averaged at the same scale; far from every fragment, their
    mean). The patches are chosen and blended on these level images; adding
    the canvas shading back lights every patch like the fragments around it,
    while pixels no patch touched come back exactly. (Additive, not a gain:
    a gain would amplify the noise of dark corners.)

    Away from the fragments the output's light tends (with weight ``prior``
    against the fragments' local coverage) to the example's light at the
    same distance from its branches: flat under vignetting, a glow that
    fades away from the bolts on a lit sky (``lightning_noaa``), so the light
    that is the subject is kept. Returns ``(example, canvas, offset)`` or
    None when there is no background to measure the light on.
    """
    n = min(ex.shape[2], 3)   # colour channels only (alpha is copied as is)
    bg_ex = ~(regions.forbidden | ndi.binary_dilation(regions.body | regions.branch_like, iterations=3))
    bg_t = covered & ~ndi.binary_dilation(body, iterations=3)
    if np.count_nonzero(bg_ex) < 64 or np.count_nonzero(bg_t) < 64:
        return None
    sigma = 2.0 * float(patch_size)
    from .regions import _normalized_blur

    shade_ex = _normalized_blur(ex[..., :n].astype(np.float64), bg_ex.astype(np.float64), sigma)
    logd = np.log1p(dist[bg_ex])
    mean = ex[..., :n][bg_ex].mean(axis=0)
    # the example's light as a function of the distance to its branches (a glow around lightning;
    # flat under vignetting): what the output's light tends to away from its fragments
    edges = np.linspace(0.0, float(logd.max()) + 1e-6, 17)
    k = np.clip(np.digitize(logd, edges) - 1, 0, 15)
    cnt = np.bincount(k, minlength=16)
    prof = np.stack([np.bincount(k, weights=shade_ex[..., c][bg_ex], minlength=16) for c in range(n)], 1)
    ok = cnt > 0
    prof = prof[ok] / cnt[ok, None]
    mid = 0.5 * (edges[:-1] + edges[1:])[ok]
    lt = np.log1p(dist_t)
    g = np.stack([np.interp(lt, mid, prof[:, c]) for c in range(n)], -1)
    # the fragments' light where they are (their background averaged at sigma), weighted by how
    # much of it lies around (coarse grid: smooth at that scale anyway)
    blur_t = _normalized_blur(canvas[..., :n].astype(np.float64), bg_t.astype(np.float64), sigma)
    H, W = bg_t.shape
    f = max(int(sigma // 6), 1)
    small = cv2.resize(bg_t.astype(np.float32), (max(W // f, 1), max(H // f, 1)), interpolation=cv2.INTER_AREA)
    den = cv2.resize(ndi.gaussian_filter(small, sigma / f, mode="nearest"), (W, H),
                     interpolation=cv2.INTER_LINEAR).astype(np.float64)[..., None]
    shade_t = (blur_t * den + prior * g) / (den + prior)
    ex_flat = ex.copy()
    ex_flat[..., :n] = ex[..., :n] + (mean - shade_ex)
    offset = np.zeros(canvas.shape, np.float32)
    offset[..., :n] = (shade_t - mean).astype(np.float32)
    return ex_flat.astype(np.float32), (canvas - offset).astype(np.float32), offset


def _grew_in_example_layout(layout: np.ndarray, pm_s: PixelMap, pm_t: PixelMap,
                            share: float = 0.98) -> bool:
    """True when the output has the example's size and the target's centre lines lie (``share`` of
    them) in the example's branch region, which is not (almost) all of it: it grew in the
    example's domain (``fit_model(..., domain=example_domain(...))``), like a delta's
    distributaries that stop at the example's sea."""
    lay = np.asarray(layout)
    if lay.shape != pm_t.dist.shape:
        return False
    on_s = lay[pm_s.dist <= 0.5]
    on_t = pm_t.dist <= 0.5
    if on_s.size == 0 or not on_t.any():
        return False
    inner = int(np.bincount(on_s - lay.min()).argmax() + lay.min())
    if np.mean(lay == inner) > 0.9:   # (almost) no other region: nothing to keep
        return False
    return bool(np.mean(lay[on_t] == inner) >= share)


def _example_layout_for(layout: np.ndarray, pm_s: PixelMap, pm_t: PixelMap) -> np.ndarray:
    """The example's own layout for a target that grew in its domain; the target's bodies lie in the
    branch region (going beyond the paper: a classifier of the skeleton's surroundings cannot tell
    a delta's sea from its land when the trunk comes from inland, and slants the coast)."""
    lay = np.asarray(layout).astype(np.int32).copy()
    on_s = lay[pm_s.dist <= 0.5]
    inner = int(np.bincount(on_s - lay.min()).argmax() + lay.min())
    lay[pm_t.core(1.0, 1.5)] = inner
    return lay


def _domain_labels(layout: np.ndarray, pm_s: PixelMap, domain: np.ndarray,
                   colours: np.ndarray | None = None) -> np.ndarray:
    """Output regions from the domain the target grew in: the example's branch region inside it,
    the region most of the example's other pixels have outside it (going beyond the paper: small
    pieces outside the domain that lie on the example's branch region, e.g. a land corner between
    rivers at the frame that the domain left out, stay in the branch region: no lake or inlet the
    example does not have). ``colours``: the example's colour labels; when its branches have the
    outer region's colour (a delta's water channels), a domain taken from the example
    (:func:`~branchnb.branching.extraction.example_domain`) has a notch of sea at every example
    mouth: the coast is drawn straight across it."""
    lay = np.asarray(layout)
    k = int(lay.max()) + 1
    inner = int(np.bincount(lay[pm_s.dist <= 0.5], minlength=k).argmax())
    rest = lay[lay != inner]
    outer = int(np.bincount(rest, minlength=k).argmax()) if rest.size else inner
    dom = np.asarray(domain, bool)
    if dom.shape == lay.shape and dom.any() and not dom.all():
        if colours is not None:
            c = np.asarray(colours)[pm_s.dist <= 0.5]
            c = c[c >= 0]
            if c.size and int(np.bincount(c).argmax()) == outer:
                dom = _across_example_mouths(dom, pm_s)
        # small pieces outside the domain lying (almost) wholly on the example's branch region are
        # no sea of the example (a flat land corner between rivers at the frame): they stay land
        pieces, n = ndi.label(~dom)
        if n:
            area = np.bincount(pieces.ravel(), minlength=n + 1)
            on_inner = np.bincount(pieces.ravel(), weights=(lay == inner).ravel(), minlength=n + 1)
            fill = (area < 0.05 * dom.size) & (on_inner >= 0.9 * area)
            fill[0] = False
            dom = dom | fill[pieces]
    return np.where(dom, inner, outer).astype(np.int32)


def _across_example_mouths(domain: np.ndarray, pm_s: PixelMap) -> np.ndarray:
    """``domain`` with the outer region's edge carried straight across the example's channels.

    The outer region is taken without the example's channel bodies (a tube
    of ``1.5 r + 4`` pixels) and closed with a disk wider than the tube, so it
    grows back into the tubes only as far as its edge on both sides reaches;
    the rest of the tubes (the notch each mouth cut into the coast) is
    inside the domain."""
    zone = pm_s.dist <= 1.5 * pm_s.radius + 4.0
    out = ~domain
    if not (out & zone).any():
        return domain
    R = 3 * int(np.ceil(1.5 * float(np.max(pm_s.radius[zone & out])) + 6.0))   # (a wide disk dips little)
    yy, xx = np.mgrid[-R:R + 1, -R:R + 1]
    disk = xx ** 2 + yy ** 2 <= R * R
    pad = R + 1
    closed = ndi.binary_closing(np.pad(out & ~zone, pad, mode="edge"), disk)[pad:-pad, pad:-pad]
    return domain | (out & zone & ~closed)


def _draw_flat(ex, example_structure, target_structure, layout, labels_t, target_domain, pm_s, labels_ex,
               p: ImageSynthesisParams, t_start: float, report, shape) -> ImageSynthesisResult:
    """``synthesize_image`` for flat-colour examples: draw the target in the example's style."""
    from .drawing import draw_in_style, drawing_style

    report(0.1, "measuring the example's drawing style")
    style = drawing_style(ex, example_structure, layout, pm_s)
    H, W = shape
    if labels_t is None:
        labels_t = _domain_labels(layout, pm_s, target_domain) if target_domain is not None else \
            np.full((H, W), style.branch_region, np.int32)
    report(0.5, "drawing")
    img = draw_in_style(style, target_structure, labels_t)
    report(1.0, "done")
    z = np.zeros((H, W), bool)
    return ImageSynthesisResult(img, z, z.copy(), np.full((H, W, 2), np.nan), np.full((H, W), -1, np.int64),
                                z.copy(), [], 0.0, target_structure, None, 0,
                                {"total": time.perf_counter() - t_start}, p,
                                example_labels=labels_ex, labels=labels_t)


def _one_of(arr: np.ndarray, values) -> np.ndarray:
    """``np.isin(arr, values)`` for the one or two branch indices of a fragment (without its sort)."""
    out = arr == values[0]
    for v in values[1:]:
        out |= arr == v
    return out


def _window(canvas, covered, x0, y0, size):
    H, W = covered.shape
    img = np.zeros((size, size, canvas.shape[2]), np.float32)
    cov = np.zeros((size, size), bool)
    r0, r1 = max(y0, 0), min(y0 + size, H)
    c0, c1 = max(x0, 0), min(x0 + size, W)
    if r0 < r1 and c0 < c1:
        img[r0 - y0:r1 - y0, c0 - x0:c1 - x0] = canvas[r0:r1, c0:c1]
        cov[r0 - y0:r1 - y0, c0 - x0:c1 - x0] = covered[r0:r1, c0:c1]
    return img, cov


def _crop(arr, x0, y0, size, fill):
    H, W = arr.shape[:2]
    out = np.full((size, size) + arr.shape[2:], fill, dtype=arr.dtype)
    r0, r1 = max(y0, 0), min(y0 + size, H)
    c0, c1 = max(x0, 0), min(x0 + size, W)
    if r0 < r1 and c0 < c1:
        out[r0 - y0:r1 - y0, c0 - x0:c1 - x0] = arr[r0:r1, c0:c1]
    return out


def _uncover(covered, mask, x0, y0):
    H, W = covered.shape
    size = mask.shape[0]
    r0, r1 = max(y0, 0), min(y0 + size, H)
    c0, c1 = max(x0, 0), min(x0 + size, W)
    if r0 < r1 and c0 < c1:
        covered[r0:r1, c0:c1] &= ~mask[r0 - y0:r1 - y0, c0 - x0:c1 - x0]
