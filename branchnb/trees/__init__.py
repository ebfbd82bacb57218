"""Image-based tree variations (Argudo, Andujar, Chica, CGF 2020).

New tree images from a small library of RGBA trees: contour morphing with
pinned resampling, mean-value-coordinate colour transfer and histogram
transfer (:mod:`branchnb.trees.variations` strings the steps together), the
crown/trunk segmentation (:mod:`branchnb.trees.segmentation`) and billboard
clouds (:mod:`branchnb.trees.billboard`) with their level-of-detail chains
(:mod:`branchnb.trees.lod`). Drawn trees are mixed by choosing one exemplar
per region instead of blending (``VariationParams.colour_mode``).
"""

from .billboard import BillboardCloud, BillboardParams, billboard_cloud  # noqa: F401
from .contour import ContourParams, PinPoints, TreeContour, stem_trunk_mask, tree_contour
from .drawn import DRAWN_KINDS, drawn_tree  # noqa: F401
from .exemplar import ExemplarParams, alpha_from_background, extract_contours, normalize_exemplar, tree_rgba
from .export import export_gltf, export_obj  # noqa: F401
from .histogram_transfer import histogram_transfer
from .lod import export_lod_gltf, lod_chain  # noqa: F401
from .morph import combine_shapes, dirichlet_weights, fill_contour
from .mvc import mean_value_coordinates, transfer_colour
from .preview import render_cloud, render_views  # noqa: F401
from .quality import crossfade_fraction  # noqa: F401
from .segmentation import (  # noqa: F401
    Segmentation,
    SegmentParams,
    evaluate_reference,
    load_reference_masks,
    load_reference_scribbles,
    reference_from_scribbles,
    segment_tree,
    segmentation_iou,
)
from .variations import (
    RPG_TREES,
    Exemplar,
    TreeLibrary,
    Variation,
    VariationParams,
    make_variation,
    morph_sequence,
    process_exemplar,
    similar_variations,
    tree_variations,
)

__all__ = [
    "ContourParams", "PinPoints", "TreeContour", "stem_trunk_mask", "tree_contour",
    "ExemplarParams", "alpha_from_background", "extract_contours", "normalize_exemplar", "tree_rgba",
    "histogram_transfer",
    "combine_shapes", "dirichlet_weights", "fill_contour",
    "mean_value_coordinates", "transfer_colour",
    "RPG_TREES", "Exemplar", "TreeLibrary", "Variation", "VariationParams",
    "make_variation", "morph_sequence", "process_exemplar", "similar_variations",
    "tree_variations",
    "Segmentation", "SegmentParams", "evaluate_reference", "load_reference_masks",
    "load_reference_scribbles", "reference_from_scribbles", "segment_tree", "segmentation_iou",
    "BillboardCloud", "BillboardParams", "billboard_cloud", "export_gltf", "export_obj",
    "render_cloud", "render_views",
    "DRAWN_KINDS", "drawn_tree", "export_lod_gltf", "lod_chain", "crossfade_fraction",
]
