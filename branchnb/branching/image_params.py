"""Parameters of image synthesis (:func:`~branchnb.branching.image_synthesis.synthesize_image`).

The paper's ``lambda``, ``s = 3 r`` and ``wS`` and this implementation's
settings of every step: fragments and their costs, bending, seams and
colours, gap completion, and the steps beyond the paper (flat-colour
drawing, relighting, line contrast).
"""

from __future__ import annotations

from dataclasses import dataclass

from ..core.params import param

__all__ = ["ImageSynthesisParams"]


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
        gives a binary drawing. Lines of one flat colour on a textured ground
        (roots on soil, chalk on a blackboard, :mod:`~branchnb.branching.flat_lines`)
        keep the fragments' ground but are redrawn in that colour at the
        target's radii on re-quilted ground (beyond the paper: the seams' colour
        correction left pale halos at junctions and tips, roots 1000 px: 4.5 % of
        the pixels 2-8 px off the lines -> 0).
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
