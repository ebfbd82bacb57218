"""What two or more techniques share: image conventions, polylines, histograms,
rendering, skeleton structures, graph-cut seams, Poisson compositing, example-based
completion, warps, stippling, mattes of objects on smooth grounds and comparison
metrics.

Each concept lives in its own module; the most used functions are
re-exported here.
"""

from .graphcut import SeamComposition, compose_overlap, seam_cost, seam_cut
from .histogram import compare_samples, histogram_distance, histograms, shared_bins
from .image import (
    as_float_image,
    as_gray,
    as_mask,
    as_points,
    as_rgb,
    as_rgba,
    composite_over,
    extend_nearest,
    split_alpha,
    to_uint8,
)
from .matte import Matte, matte_from_background
from .metrics import iou, psnr
from .poisson import grid_laplacian, poisson_blend
from .polyline import (
    RigidTransform,
    arc_length,
    normals,
    polyline_length,
    resample_chord,
    resample_uniform,
    rigid_align,
    segments_intersect,
    tangents,
    turning_angles,
)
from .random import as_rng
from .render import coverage_polylines, draw_polylines
from .sampling import stipple
from .structure import Branch, Structure
from .svg import polylines_to_svg
from .warp import Patch, remap, transfer_patch

__all__ = [
    "Branch",
    "Structure",
    "Patch",
    "RigidTransform",
    "SeamComposition",
    "arc_length",
    "as_float_image",
    "as_gray",
    "as_mask",
    "as_points",
    "as_rgb",
    "as_rgba",
    "as_rng",
    "compare_samples",
    "compose_overlap",
    "composite_over",
    "extend_nearest",
    "coverage_polylines",
    "draw_polylines",
    "grid_laplacian",
    "histogram_distance",
    "histograms",
    "iou",
    "Matte",
    "matte_from_background",
    "normals",
    "poisson_blend",
    "polyline_length",
    "polylines_to_svg",
    "psnr",
    "remap",
    "resample_chord",
    "resample_uniform",
    "rigid_align",
    "seam_cost",
    "seam_cut",
    "segments_intersect",
    "shared_bins",
    "split_alpha",
    "stipple",
    "tangents",
    "to_uint8",
    "transfer_patch",
    "turning_angles",
]
