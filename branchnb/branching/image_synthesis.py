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

Modules by paper step: :mod:`.fragments` and :mod:`.fragment_choice`
(step 1: fragments, costs ``S`` and ``C``, the copy rules),
:mod:`.fragment_placement` (steps 2-3: bending and composing every
fragment), :mod:`.gap_completion` (step 4), and :mod:`.output_regions`
(flat-colour examples: the output's regions and drawing in style).
"""

from __future__ import annotations

import time
from collections.abc import Callable
from dataclasses import dataclass, field

import cv2
import numpy as np

from ..core.image import as_float_image, as_mask, as_points, as_rgb
from ..core.io import encode_png
from ..core.params import check_params, param
from ..core.random import as_rng
from ..core.render import draw_polylines
from ..core.structure import Structure
from ..core.validate import Shape, checked
from .flat_regions import two_tone_lines
from .fragment_choice import _Context, _free_ends, _joined_at_region_edge
from .fragment_placement import _constraints, _synthesize_fragments
from .fragments import Fragment, source_fragments, target_fragments
from .gap_completion import _complete
from .output_regions import (
    _domain_labels,
    _draw_flat,
    _example_layout_for,
    _grew_in_example_layout,
    _keep_matte,
    _matte_colour,
    _walls_off_matte,
)
from .regions import (
    ExampleRegions,
    _flattened_if_shaded,
    colour_labels,
    example_regions,
    flat_colour_regions,
    region_layout,
)
from .skeleton_map import SkeletonMap

# (the paper's steps live in their own modules; these private names stay importable from here)
_REEXPORTED = (_constraints, _Context, _free_ends)

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
    flatten_shading : float, default 0.05
        Divide out the example's large-scale shading (vignetting, uneven light)
        before copying, so pieces from bright and dark parts match; Gaussian scale
        as a fraction of the example's size (0 = copy as is, the paper). Beyond
        the paper, on by default: copied as is, a fundus's vessels (which end in
        its dark rim) came out with dark dots at their tips, pale and dark halo
        streaks beside them (the gradient-domain correction spreading the steps
        in light) and in disconnected pieces (retina 512 px: 56 pieces, 20
        gaps, halo 0.20 of the vessel contrast -> 43, 14, 0.02). Applied only to photos whose ground light varies by
        more than 20 % (``regions.SHADED``) and whose lines are darker than
        their ground (absorbing lines, darkened with their ground): evenly lit
        examples, light lines (a bolt among clouds, whose "shading" is the
        clouds) and flat-colour drawings are copied as is. The pieces are
        composed evenly lit, then the example's light is put back.
    exclude_matte : bool, default True
        Never copy a flat black/white matte connected to the example's border (e.g.
        around a fundus photo); beyond the paper, with a ``target_domain`` the output
        keeps that matte, in its colour, outside the domain (a photo's surround is a
        region of its own, its edge no drawn line).
    flat_drawing : bool, default True
        Flat-colour examples (drawn maps, masks): draw the output the way the
        example is drawn (its region colours, its boundary line along the output's
        region boundary, branches as connected strokes of its line colour and
        measured width) instead of copying fragments (off: the paper's fragments).
        A line mask on one plain ground (binary or anti-aliased, either
        polarity, :func:`~branchnb.branching.flat_regions.two_tone_lines`)
        counts however thin its lines (beyond the paper: copied fragments
        turned its one-pixel lines into pale broken dashes); a binary mask
        gives a binary drawing.
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
    relight_fragments : bool, default True
        A fragment's ground is moved from the example's large-scale light where it
        comes from to the light where it goes (beyond the paper: a bolt taken from
        a bright cloud and placed in a dark sky brings no glowing tube of cloud;
        off: the paper's fragments).
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
    line_contrast : float, default 0.85
        Beyond the paper: after gap completion every pixel of the target's
        lines stands out from its local ground by at least this share of the
        example's median line profile (per radius and distance to the centre
        line, :mod:`~branchnb.branching.line_contrast`); pixels that fall
        short (softened, or half a pixel off, or a gap no fragment covered)
        move along the example's line colour; the others keep the
        fragments' texture. (The example's own weakest line pixels, e.g. at
        faint tips, are raised too: synthesizing an example's own structure
        reproduces it exactly only with 0.) Thin lines (cracks, capillaries) otherwise come out pale and
        broken. 0 = off (the paper).
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
    flatten_shading: float = param(0.05, min=0.0, max=0.5, step=0.01,
                                   help="divide out the example's large-scale shading (vignetting, "
                                        "uneven light) of shaded photos with dark lines before "
                                        "copying, so pieces from bright and dark parts match; "
                                        "Gaussian scale as a fraction of the example's size "
                                        "(0 = copy as is, the paper)")
    exclude_matte: bool = param(True, help="never copy a flat black/white matte connected to the "
                                           "example's border (e.g. around a fundus photo); with a "
                                           "target domain, keep it outside the domain")
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
    relight_fragments: bool = param(True, help="a fragment's ground is moved from the example's light "
                                               "where it comes from to the example's light where it goes "
                                               "(a bolt from a bright cloud placed in a dark sky brings no "
                                               "glowing tube of cloud; off: the paper's fragments)")
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
    line_contrast: float = param(0.85, min=0.0, max=1.5, step=0.05,
                                 help="every target line pixel stands out from its ground by at least "
                                      "this share of the example's median line profile (0 = off)")
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
        (:func:`~branchnb.branching.layout_model.target_layout`).
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
        # a line mask on one plain ground (its lines too thin to form a flat region of their own)
        mask = bool(flat_share >= 0.5 and labels_ex.max() == 0 and two_tone_lines(ex))
        cached = _EXAMPLE_CACHE[key] = {"sm_s": sm_s, "pm_s": pm_s, "labels_ex": labels_ex,
                                        "flat_share": flat_share, "mask": mask,
                                        "matte_colour": _matte_colour(ex) if p.exclude_matte else None}
    sm_s, pm_s, labels_ex, flat_share = (cached[k] for k in ("sm_s", "pm_s", "labels_ex", "flat_share"))
    sm_t = SkeletonMap(target_structure, 1.0)
    pm_t = sm_t.pixel_map((H, W))
    flat = bool(flat_share >= 0.5 and labels_ex.max() >= 1)
    if cached["mask"] and p.flat_drawing:
        return _draw_flat(ex, example_structure, target_structure, labels_ex, None, None,
                          pm_s, labels_ex, p, t_start, report, (H, W))
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
    boundary = None
    matte_edge = False
    if labels_t is None and target_domain is not None and not flat and target_domain.any() \
            and not target_domain.all():
        # beyond the paper: an example whose domain a drawn line walls off (a shaded terrain map):
        # land from land, outside from outside, and its line drawn along the output's domain
        from .drawn_domains import domain_labels, drawn_boundary

        if "drawn_boundary" not in cached:
            cached["drawn_boundary"] = drawn_boundary(ex, example_structure, pm_s)
        boundary = cached["drawn_boundary"]
        # the soft edge of a photo's matte (a fundus disk's rim) is no drawn line: its regions are
        # used, but the matte is kept as a region instead of drawing the line (beyond the paper)
        matte_edge = boundary is not None and cached["matte_colour"] is not None and \
            _walls_off_matte(boundary.domain, boundary.colour, ex)
        if boundary is not None:
            labels_t = domain_labels(target_domain)
            src_labels = domain_labels(boundary.domain, boundary.ink)
    # Line art on one plain background has a single flat region (so it is not
    # drawn in style like a map) but Poisson blending still smudges its ink.
    use_poisson = p.poisson and (flat_share < 0.5 or p.flat_poisson)
    geo = dict(lam=p.lam, scale=p.radius_scale, min_radius=p.min_radius, max_radius=p.max_radius)
    if "regions" not in cached:
        regions = example_regions(ex, pm_s, exclusion=p.exclusion, margin=p.exclusion_margin,
                                  threshold=p.branch_like if p.avoid_unannotated else None,
                                  matte=p.exclude_matte and not flat, example_mask=example_mask,
                                  salient=p.salient_z if p.avoid_salient else None)
        shading = None
        if p.flatten_shading > 0 and flat_share < 0.5:
            ex, shading = _flattened_if_shaded(ex, regions, pm_s, p.flatten_shading)
        excluded = regions.body | regions.branch_like
        if regions.salient is not None:
            excluded = excluded | regions.salient
        lib_b, lib_f = source_fragments(sm_s, density=p.source_density, reverse=p.reverse, **geo)
        from .crossings import without_crossings

        lib_b = without_crossings(lib_b, example_structure, ex.shape[:2])
        free_start, free_end = _free_ends(sm_s, pm_s)
        if labels_ex.max() >= 1:
            _joined_at_region_edge(sm_s, labels_ex, free_start, free_end)
        cached.update(regions=regions, ex=ex, excluded=excluded, shading=shading, lib_b=lib_b, lib_f=lib_f,
                      free_start=free_start, free_end=free_end, vec_cache={})
    regions, ex, excluded, lib_b, lib_f = (cached[k] for k in ("regions", "ex", "excluded", "lib_b", "lib_f"))
    if boundary is not None:
        from .drawn_domains import regions_by_domain

        if "regions_drawn" not in cached:
            cached["regions_drawn"] = regions_by_domain(ex, regions, boundary,
                                                        p.salient_z if p.avoid_salient else None)
        regions = cached["regions_drawn"]
        excluded = regions.body | regions.branch_like
        if regions.salient is not None:
            excluded = excluded | regions.salient
    free_start, free_end = cached["free_start"].copy(), cached["free_end"].copy()
    ctx = _Context(ex, sm_s, sm_t, pm_s, excluded, regions.unusable, p)
    free_t = _free_ends(sm_t, pm_t)
    if len(lib_b) == 0:
        raise ValueError("example_structure yields no source fragment (all branches have zero length)")
    # Without a furcation in the example, children start with ordinary fragments.
    targets = target_fragments(sm_t, furcations=len(lib_f) > 0, **geo)
    timings["prepare"] = time.perf_counter() - t_start

    t0 = time.perf_counter()
    frag_share = 0.6 if p.completion else 1.0
    light = None
    if p.relight_fragments and not flat and boundary is None:
        from .gap_completion import light_layout

        if "light" not in cached:
            cached["light"] = light_layout(ex, regions, p.patch_size)
        if cached["light"] is not None:
            light = (cached["light"], cv2.resize(cached["light"], (W, H), interpolation=cv2.INTER_LINEAR)
                     .reshape(H, W, -1))
    out = _synthesize_fragments(ctx, pm_t, targets, (H, W), lib_b, lib_f, free_start, free_end, free_t,
                                cached["vec_cache"], labels_t, src_labels, use_poisson, rng, report,
                                frag_share, light)
    timings["fragments"] = time.perf_counter() - t0
    fill, n_inpainted = _complete(out, ex, regions, p, flat, use_poisson, pm_s, pm_t, labels_t, src_labels,
                                  rng, report, frag_share, timings,
                                  domains=None if boundary is None else (boundary.domain, target_domain))
    canvas, source, frag_index, seams = out.canvas, out.source, out.frag_index, out.seams
    shown = cached["ex"]
    if cached["shading"] is not None:
        # the example's light put back where the pieces go (composed evenly lit: no halos, no dots);
        # the line contrast below is then the example's as shown
        n = cached["shading"].shape[2]
        canvas[..., :n] *= cv2.resize(cached["shading"], (W, H), interpolation=cv2.INTER_LINEAR).reshape(H, W, n)
        shown = as_float_image(example_image)
    if flat_share >= 0.5:
        # drawn examples: a branch the fragments left without ink is drawn in the example's style
        from .drawing import drawing_style
        from .stroke_repair import redraw_gaps

        if "style" not in cached:
            cached["style"] = drawing_style(cached["ex"], example_structure, layout, pm_s)
        style = cached["style"]
        canvas, _ = redraw_gaps(canvas, target_structure, style.line_colour,
                                style.region_colours[style.branch_region], style.width_scale)

    if boundary is not None and not matte_edge:
        from .drawn_domains import draw_boundary

        canvas = draw_boundary(canvas, target_domain, boundary.colour, boundary.width)
    if p.line_contrast > 0:
        # (after the drawn-style redraw: it draws the gaps of drawings in the full line colour)
        from .line_contrast import line_profile, restore_line_contrast

        if "profile" not in cached:
            cached["profile"] = line_profile(shown, pm_s, ~regions.unusable)
        if cached["profile"] is not None:
            canvas, _ = restore_line_contrast(canvas, pm_t, cached["profile"], p.line_contrast)
        # ... and no more than the example's either (lines bent exactly onto the target's centre
        # lines stand out more than an extracted example's, whose centre lines are a fraction of a
        # pixel off): the median centre-line contrast is brought back into 0.85-1.18x the example's
        # (lines of the example's colour that stand out only because their ground is darker or
        # lighter than the example's, e.g. a relit bolt, are not faded)
        from .line_contrast import centre_ring_colours, match_line_contrast

        if "centre_colours" not in cached:
            # one pass over the example: its contrast is the distance of these two colours
            colours = centre_ring_colours(shown, pm_s)
            cached["centre_colours"] = colours
            cached["centre_contrast"] = 0.0 if colours is None else float(np.linalg.norm(colours[0] - colours[1]))
        canvas, _ = match_line_contrast(canvas, pm_t, cached["centre_contrast"], colours=cached["centre_colours"])
    if cached["matte_colour"] is not None and (boundary is None or matte_edge) and not flat \
            and target_domain is not None and target_domain.any() and not target_domain.all():
        # beyond the paper: a photo's matte (a fundus's black surround) stays outside the domain
        canvas = _keep_matte(canvas, target_domain, cached["matte_colour"])
    fragment_mask = frag_index >= 0
    # Every stage keeps [0, 1]; this guards the contract (finite, in range) for any input.
    np.clip(np.nan_to_num(canvas, nan=0.0), 0.0, 1.0, out=canvas)
    timings["total"] = time.perf_counter() - t_start
    report(1.0, "done")
    return ImageSynthesisResult(canvas, fragment_mask, fill, source, frag_index, seams, out.matches,
                                out.total_seam, target_structure, regions, n_inpainted, timings, p,
                                example_labels=labels_ex, labels=labels_t)
