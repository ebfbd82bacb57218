"""Image-based tree variations (Argudo, Andujar, Chica, CGF 2020)."""

from .billboard import BillboardCloud, BillboardParams, billboard_cloud  # noqa: F401
from .export import export_gltf, export_obj  # noqa: F401
from .preview import render_cloud, render_views  # noqa: F401
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
