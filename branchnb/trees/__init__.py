"""Image-based tree variations (Argudo, Andujar, Chica, CGF 2020)."""

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
