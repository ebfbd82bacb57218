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
   branch (no tip there), and a target line under 1.5 px radius takes a
   source line of a like radius first (beyond the paper:
   :func:`.fragment_choice._thin_penalty`).
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
   pseudo-branch appears. A ground of flat patches with sharp borders
   (fields seen from the air, a city's blocks: :mod:`.patchwork`) is
   copied as it is, in patches half a field across, with no relighting,
   no shading put back and no gradient-domain correction of the gap
   patches (beyond the paper: those blurred its fields into one another).

The parameters not given by the paper (``wC``, the shortlist, the density
of source fragments, the gap-completion settings) are documented in
:class:`ImageSynthesisParams`.

Modules by paper step: :mod:`.fragments` and :mod:`.fragment_choice`
(step 1: fragments, costs ``S`` and ``C``, the copy rules),
:mod:`.fragment_placement` (steps 2-3: bending and composing every
fragment), :mod:`.gap_completion` (step 4), and :mod:`.output_regions`
(flat-colour examples: the output's regions and drawing in style), :mod:`.glow`
(glowing lines on a flat ground, lightning or neon: drawn with the example's glow, beyond the paper),
:mod:`.flat_lines` (lines of one flat colour on a textured ground: redrawn in that colour, beyond the paper).
The settings are :class:`~branchnb.branching.image_params.ImageSynthesisParams`,
the result :class:`~branchnb.branching.image_result.ImageSynthesisResult`; the
example side of the last call is kept in :mod:`.example_cache`.
"""

from __future__ import annotations

import time
from collections.abc import Callable

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_float_image, as_mask, as_points
from ..core.params import check_params
from ..core.random import as_rng
from ..core.structure import Structure
from ..core.validate import Shape, checked
from .example_cache import _EXAMPLE_CACHE, _example_key
from .flat_regions import two_tone_lines
from .fragment_choice import _Context, _free_ends, _joined_at_region_edge
from .fragment_placement import _constraints, _synthesize_fragments
from .fragments import source_fragments, target_fragments
from .gap_completion import _complete
from .image_params import ImageSynthesisParams
from .image_result import FragmentMatch, ImageSynthesisResult
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


# ---------------------------------------------------------------------------
# validation


def _flat_hubs(result: ImageSynthesisResult, example: np.ndarray, example_structure, target_structure,
               given=None):
    """``result`` of a flat drawing or a line mask with the example's hubs pasted on the target's (beyond
    the paper, issue 23; without hubs ``result`` itself): :func:`.radial._paste_hubs` with ``flat``, as
    the textured path does, which a drawn mask's somas lacked; ``result.target`` set to ``given``."""
    if given is not None:
        result.target = given
    if not (getattr(target_structure, "hubs", None) and getattr(example_structure, "hubs", None)):
        return result
    from .radial import _paste_hubs

    result.image = _paste_hubs(result.image, example, example_structure.hubs, target_structure.hubs, flat=True)
    return result


def _in_example_range(canvas: np.ndarray, example: np.ndarray) -> np.ndarray:
    """``canvas`` with every channel clipped to the range the example's takes (in place)."""
    n = min(canvas.shape[2], example.shape[2]) if canvas.ndim == 3 and example.ndim == 3 else 0
    if n:
        flat = example[..., :n].reshape(-1, n)
        np.clip(canvas[..., :n], flat.min(0), flat.max(0), out=canvas[..., :n])
    return canvas


def _grainy_glow(ex: np.ndarray, pm_s, p, cached: dict) -> None:
    """Beyond the paper (issue 23): glowing lines on a grainy ground (noise, film grain, stars in a night
    sky) -- no flat region, so they went the textured path and came out as broken, dim pieces. When the
    example smoothed (:func:`~.glow.calm_example`) is flat and its lines glow, ``cached`` takes the
    smoothed example (``calm``), its regions and the glow model (measured on the grainy example, whose
    ground keeps the grain) and the example is drawn as a flat glowing one."""
    from .glow import calm_example, glow_model

    calm = calm_example(ex, pm_s)
    if calm is None:
        return
    labels, share = flat_colour_regions(calm, pm_s.core(p.exclusion, p.exclusion_margin))
    if share < 0.5:
        return
    glow = glow_model(ex, pm_s, labels)
    if glow is None:
        return
    cached.update(calm=calm, labels_ex=labels, flat_share=share, flat_glow=glow)


def _flat_lines(canvas, cached: dict, example_structure, target_structure, pm_s, pm_t, regions, p,
                use_poisson: bool, rng, known):
    """``canvas`` with lines of one flat colour on a textured ground redrawn (:mod:`.flat_lines`); the
    example's measures are kept in ``cached``; other examples' ``canvas`` unchanged."""
    from .flat_lines import flat_line_colour, line_width_scale, redraw_flat_lines

    if "flat_lines" not in cached:
        ex = cached["ex"]
        found = flat_line_colour(ex, pm_s, regions.unusable)
        if found is None and cached.get("silhouette") is not None:
            # a silhouette's ink is solid by its own test (.smooth_ground) even where its twigs are all
            # anti-aliased rim, which the lines' spread test above reads as a second colour; its ground is
            # the ring's median
            ring = (pm_s.dist >= pm_s.radius + 3.0) & (pm_s.dist <= pm_s.radius + 8.0)
            if regions.unusable is not None:
                ring &= ~regions.unusable
            if ring.any():
                found = (cached["silhouette"][0], np.median(ex[..., :3][ring], axis=0).astype(np.float32))
        if found is not None:
            found = found + (line_width_scale(ex, example_structure, pm_s, *found),)
        cached["flat_lines"] = found
    if cached["flat_lines"] is None:
        return canvas
    from .gap_quilting import quilt_gaps

    line, ground, scale = cached["flat_lines"]

    def quilt(c, covered, example, forbidden):
        # (the ground around is kept as it is: patches fill the cleared band only)
        quilt_gaps(c, covered, example, forbidden, patch_size=max(8, p.patch_size // 2), overlap=p.patch_overlap,
                   protect=covered.copy(), tolerance=p.completion_tolerance, forbid_weight=p.forbid_weight,
                   method=p.seams,
                   poisson=use_poisson, anchored=p.anchors, anchor_weight=p.anchor_weight,
                   screen=p.completion_screen if p.anchors else 0.0, min_free=p.min_free, rng=rng)

    if cached.get("silhouette") is not None:
        # a silhouette's ground is one smooth shading (.smooth_ground): the whole ground is that shading (patches
        # quilted from elsewhere in a sky gradient left pale blotches, a membrane through the band's rim
        # smeared the fragments' stray ink into dark ones)
        shading = cached["silhouette"][1]
        if shading.shape[:2] != canvas.shape[:2]:
            shading = cv2.resize(shading, (canvas.shape[1], canvas.shape[0]), interpolation=cv2.INTER_LINEAR)
        canvas = canvas.copy()
        n = min(3, canvas.shape[2])
        canvas[..., :n] = shading[..., :n]

        def fill(c, covered, example, forbidden):
            c[..., :n][covered] = shading[..., :n][covered]
    else:
        fill = quilt

    return redraw_flat_lines(canvas, cached["ex"], regions.forbidden, target_structure, pm_t, line, ground, scale,
                             fill, known)


def _two_colours(image: np.ndarray) -> bool:
    """Whether every pixel of ``image`` has one of at most two colours (a binary mask)."""
    flat = np.ascontiguousarray(image.reshape(-1, image.shape[2]) if image.ndim == 3 else image.reshape(-1, 1))
    first = flat[0]
    other = np.any(flat != first, axis=1)
    if not other.any():
        return True
    second = flat[np.argmax(other)]
    return bool(np.all(~other | np.all(flat == second, axis=1)))


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
# the public entry


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

    given = target_structure
    if getattr(target_structure, "hubs", None) and getattr(example_structure, "hubs", None):
        # primaries drawn from inside their hub (beyond the paper, issue 23; .radial._into_hubs)
        from .radial import _into_hubs

        target_structure = _into_hubs(target_structure)

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
        # (a strictly two-colour image is flat however densely its lines cover it: a 128 px crack mask
        # with 3-4 px trunks has under half its pixels in flat cells, and copied fragment by fragment it
        # fell apart into 3-6 pieces with grey smudges; beyond the paper, issue 23)
        mask = bool((flat_share >= 0.5 or _two_colours(ex)) and labels_ex.max() == 0 and two_tone_lines(ex))
        cached = _EXAMPLE_CACHE[key] = {"sm_s": sm_s, "pm_s": pm_s, "labels_ex": labels_ex,
                                        "flat_share": flat_share, "mask": mask,
                                        "matte_colour": _matte_colour(ex) if p.exclude_matte else None}
        if p.flat_drawing and flat_share < 0.5 and not getattr(example_structure, "hubs", None):
            _grainy_glow(ex, pm_s, p, cached)
    sm_s, pm_s, labels_ex, flat_share = (cached[k] for k in ("sm_s", "pm_s", "labels_ex", "flat_share"))
    # a grainy sky's glowing example is drawn from its smoothed self (its glow model keeps the grain)
    ex = cached.get("calm", ex)
    sm_t = SkeletonMap(target_structure, 1.0)
    pm_t = sm_t.pixel_map((H, W))
    flat = bool(flat_share >= 0.5 and labels_ex.max() >= 1)
    if cached["mask"] and p.flat_drawing:
        return _flat_hubs(_draw_flat(ex, example_structure, target_structure, labels_ex, None, None,
                                     pm_s, labels_ex, p, t_start, report, (H, W), cache=cached),
                          ex, example_structure, target_structure, given)
    if not flat and p.flat_drawing and flat_share >= 0.5 and labels_ex.max() == 0 \
            and not getattr(example_structure, "hubs", None):
        # beyond the paper (issue 23): glowing lines on one flat ground (a fluorescent cell on black, neon
        # on a plain wall) are drawn with the example's glow (.glow); copied fragment by fragment, the
        # glow reached only as far as the fragments' disks (3 r) and ended in a step to the ground
        if "flat_glow" not in cached:
            from .glow import glow_model

            cached["flat_glow"] = glow_model(ex, pm_s, labels_ex)
        if cached["flat_glow"] is not None:
            return _flat_hubs(_draw_flat(ex, example_structure, target_structure, labels_ex, None, None,
                                         pm_s, labels_ex, p, t_start, report, (H, W), cache=cached),
                              ex, example_structure, target_structure, given)
    labels_t = None
    src_labels = labels_ex
    layout = labels_ex
    if target_domain is not None:
        target_domain = as_mask(target_domain, shape=(H, W), name="target_domain")
    if flat and (p.keep_regions or p.flat_drawing):
        if "layout" not in cached:
            # a source pixel's region is its colour's (a white rim is water wherever it lies)
            zone = pm_s.core(2.0 * p.exclusion, 2.0 * p.exclusion_margin)
            cached["src_labels"] = colour_labels(ex, labels_ex, ~zone)
            # the example's land and sea around its branches (not its channels)
            cached["layout"] = region_layout(cached["src_labels"], zone, pm_s.core(1.0, 0.0))
        src_labels, layout = cached["src_labels"], cached["layout"]
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
        return _flat_hubs(_draw_flat(ex, example_structure, target_structure, layout, labels_t, target_domain,
                                     pm_s, labels_ex, p, t_start, report, (H, W), cache=cached),
                          ex, example_structure, target_structure, given)
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
        patchwork = 0.0   # the ground's typical patch diameter when it is a patchwork
        if flat_share < 0.5:
            # a patchwork of flat fields or blocks (beyond the paper, issue 23): its patches are no light
            # to divide out and put back (that made blurred blobs of field colours), nor seams to
            # correct in the gradient domain (that smeared each field into the next)
            from .patchwork import is_patchwork

            ground = ~(regions.forbidden | ndi.binary_dilation(regions.body | regions.branch_like, iterations=3))
            if is_patchwork(ex, ground):
                from .patchwork import patch_diameter

                patchwork = patch_diameter(ex, ground)
        # one solid ink on a smooth shaded ground (a tree against the sky): the shading is the ground's own
        # gradient, kept as it is; its lines are redrawn flat below (.smooth_ground, .flat_lines)
        from .smooth_ground import silhouette_colours

        # (colour examples: the line redrawing works in RGB)
        silhouette = silhouette_colours(ex) if flat_share < 0.5 and not patchwork and ex.shape[2] >= 3 else None
        if p.flatten_shading > 0 and flat_share < 0.5 and not patchwork and silhouette is None:
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
                      patchwork=patchwork, silhouette=silhouette,
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
    if cached.get("silhouette") is not None and p.flat_drawing and boundary is None and not flat \
            and not getattr(example_structure, "hubs", None):
        # one solid ink on a smooth shaded ground (.smooth_ground): the ground is the example's shading and the
        # lines are drawn in the ink (below, .flat_lines); the fragments and the completion would all be
        # painted over (their ground at 512 px took about two thirds of the time)
        report(0.5, "drawing the silhouette")
        canvas = np.zeros((H, W, ex.shape[2]), np.float32)
        if ex.shape[2] == 4:
            canvas[..., 3] = 1.0
        known = np.ones((H, W), bool)
        canvas = _flat_lines(canvas, cached, example_structure, target_structure, pm_s, pm_t, regions, p,
                             use_poisson, rng, known)
    if cached.get("silhouette") is not None and cached.get("flat_lines") is not None and p.flat_drawing \
            and boundary is None and not flat and not getattr(example_structure, "hubs", None):
        np.clip(np.nan_to_num(canvas, nan=0.0), 0.0, 1.0, out=canvas)
        z = np.zeros((H, W), bool)
        timings["total"] = time.perf_counter() - t_start
        report(1.0, "done")
        return ImageSynthesisResult(canvas, z, z.copy(), np.full((H, W, 2), np.nan), np.full((H, W), -1, np.int64),
                                    z.copy(), [], 0.0, given, regions, 0, timings, p,
                                    example_labels=labels_ex, labels=labels_t)
    free_start, free_end = cached["free_start"].copy(), cached["free_end"].copy()
    # a salient spot (a retina's optic disc) is copied by no fragment, not even its own branch's
    # beyond that branch's body: carried along, it made pale copies of the disc at junctions
    unusable = regions.unusable if regions.salient is None else regions.unusable | (regions.salient & ~regions.body)
    line_margin = None
    neutral_tol = 0.0
    if getattr(target_structure, "hubs", None) and getattr(example_structure, "hubs", None):
        # nor the example's hubs (drawn whole at the output's hubs): copied along a spoke, their fill
        # made fat wedges on the primaries beside the hub (beyond the paper, issue 23)
        from .radial import _hub_discs, _off_hubs

        unusable = unusable | _hub_discs(example_structure.hubs, unusable.shape)
        # ... so no source fragment reaching into them either (it copied almost nothing: bars across the
        # primaries every fragment), and the lines' soft edges stay out of the gaps' correction (glowing
        # or blurred dark tips; branching116)
        lib_b, lib_f = _off_hubs(lib_b, example_structure.hubs), _off_hubs(lib_f, example_structure.hubs)
        from .gap_completion import HUB_LINE_MARGIN, HUB_SEAM_MISMATCH

        line_margin = HUB_LINE_MARGIN
        from .line_contrast import centre_ring_colours

        if "hub_colours" not in cached:
            cached["hub_colours"] = centre_ring_colours(ex, pm_s)
        if cached["hub_colours"] is not None:
            neutral_tol = HUB_SEAM_MISMATCH * float(np.abs(np.subtract(*cached["hub_colours"])).max())
    ctx = _Context(ex, sm_s, sm_t, pm_s, excluded, unusable, p)
    free_t = _free_ends(sm_t, pm_t)
    if len(lib_b) == 0:
        raise ValueError("example_structure yields no source fragment (all branches have zero length)")
    # Without a furcation in the example, children start with ordinary fragments.
    targets = target_fragments(sm_t, furcations=len(lib_f) > 0, **geo)
    timings["prepare"] = time.perf_counter() - t_start

    t0 = time.perf_counter()
    frag_share = 0.6 if p.completion else 1.0
    light = None
    if p.relight_fragments and not flat and boundary is None and not cached.get("patchwork", 0.0):
        from .gap_completion import light_layout

        if "light" not in cached:
            cached["light"] = light_layout(ex, regions, p.patch_size)
        if cached["light"] is not None:
            light = (cached["light"], cv2.resize(cached["light"], (W, H), interpolation=cv2.INTER_LINEAR)
                     .reshape(H, W, -1))
    out = _synthesize_fragments(ctx, pm_t, targets, (H, W), lib_b, lib_f, free_start, free_end, free_t,
                                cached["vec_cache"], labels_t, src_labels, use_poisson, rng, report,
                                frag_share, light,
                                neutral_lines=None if line_margin is None else pm_t.core(1.0, line_margin),
                                neutral_tol=neutral_tol)
    timings["fragments"] = time.perf_counter() - t0
    if cached.get("patchwork", 0.0) and p.completion and not flat:
        # a patchwork ground (beyond the paper, issue 23): a fragment's disk carried its own field's
        # colour along the branch, a band of it beside the river over whatever fields the output lays
        # there (aerial fields: a chain of dark beads along the river); the fragments keep their
        # branch and its bank only, the fields beside it are completed with the ground around
        from .patchwork import bank_only

        bank_only(out, pm_t)
    fill, n_inpainted = _complete(out, ex, regions, p, flat, use_poisson, pm_s, pm_t, labels_t, src_labels,
                                  rng, report, frag_share, timings,
                                  domains=None if boundary is None else (boundary.domain, target_domain),
                                  patchwork=cached.get("patchwork", 0.0), line_margin=line_margin)
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
    if p.flat_drawing and not flat and flat_share < 0.5 and boundary is None and cached["shading"] is None \
            and not cached.get("patchwork", 0.0) and not getattr(example_structure, "hubs", None):
        # beyond the paper (issue 23): lines of one flat colour on a textured ground (roots on soil, chalk
        # on a blackboard) are redrawn in that colour at the target's radii on re-quilted ground: the
        # seams' colour correction made pale halos at junctions and tips, the bent fragments ragged edges
        # (before a photo's matte is put back outside its domain: lines drawn to the edge crossed it)
        canvas = _flat_lines(canvas, cached, example_structure, target_structure, pm_s, pm_t, regions, p,
                             use_poisson, rng, (out.frag_index >= 0) | fill)
    if cached["matte_colour"] is not None and (boundary is None or matte_edge) and not flat \
            and target_domain is not None and target_domain.any() and not target_domain.all():
        # beyond the paper: a photo's matte (a fundus's black surround) stays outside the domain
        canvas = _keep_matte(canvas, target_domain, cached["matte_colour"])
    if getattr(target_structure, "hubs", None) and getattr(example_structure, "hubs", None):
        # beyond the paper (issue 23): a radial structure's hubs (somas, a coral's centre) drawn from the example's
        from .radial import _paste_hubs

        canvas = _paste_hubs(canvas, as_float_image(example_image), example_structure.hubs, target_structure.hubs)
    # beyond the paper (issue 23): the gradient-domain correction overshoots where seams meet at a
    # junction or a tip (glow dots of 5-8 px, 0.1-0.2 brighter than a root system's lines); every output
    # colour is one of the example's, so no channel leaves the example's range
    canvas = _in_example_range(canvas, as_float_image(example_image))
    fragment_mask = frag_index >= 0
    # Every stage keeps [0, 1]; this guards the contract (finite, in range) for any input.
    np.clip(np.nan_to_num(canvas, nan=0.0), 0.0, 1.0, out=canvas)
    timings["total"] = time.perf_counter() - t_start
    report(1.0, "done")
    return ImageSynthesisResult(canvas, fragment_mask, fill, source, frag_index, seams, out.matches,
                                out.total_seam, given, regions, n_inpainted, timings, p,
                                example_labels=labels_ex, labels=labels_t)
