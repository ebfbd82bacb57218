"""Structure editing with user strokes.

The user draws strokes along the skeleton of an object in an image
(source strokes) and corresponding strokes in an output domain (target
strokes); the object's texture is re-synthesized along the target
strokes: rotated patches fetched along the strokes, sample
correspondences chosen by dynamic programming (global texture sampling),
overlaps stitched with graph-cut seams, branches joined at junctions.

>>> import numpy as np
>>> from branchnb.strokes import edit_structure
>>> img = np.zeros((40, 60, 4), np.float32); img[15:25, 5:55] = (0.6, 0.4, 0.2, 1.0)
>>> res = edit_structure(img, [[(8, 20), (52, 20)]], [[(30, 5), (30, 35)]])
>>> res.mask.shape
(40, 60)
"""

from .composition import Composition, PlacedPatch, compose, labelling_cost, seam_mask
from .display import PAIR_COLORS, draw_strokes, pair_color, pair_color_hex, stroke_markers
from .edit import (
    FETCH_FIELDS,
    EditPatches,
    StrokeEditParams,
    StrokeEditResult,
    StrokeSamples,
    compose_patches,
    edit_structure,
    fetch_patches,
)
from .evaluation import compare_colours, object_colours
from .fetch import Fetched, Samples, SourceIndex, fetch, sample_pair, source_index
from .junctions import Junction, attach, far_side, find_junctions, stroke_order
from .sampling import SamplingResult, candidate_offsets, chain_energy, greedy, pair_energies, viterbi
from .strokes import Stroke, StrokePair, make_pairs

__all__ = [
    "FETCH_FIELDS",
    "PAIR_COLORS",
    "Composition",
    "EditPatches",
    "Fetched",
    "Junction",
    "PlacedPatch",
    "Samples",
    "SamplingResult",
    "SourceIndex",
    "Stroke",
    "StrokeEditParams",
    "StrokeEditResult",
    "StrokePair",
    "StrokeSamples",
    "attach",
    "candidate_offsets",
    "chain_energy",
    "compare_colours",
    "compose",
    "compose_patches",
    "draw_strokes",
    "edit_structure",
    "far_side",
    "fetch",
    "fetch_patches",
    "find_junctions",
    "greedy",
    "labelling_cost",
    "make_pairs",
    "object_colours",
    "pair_color",
    "pair_color_hex",
    "pair_energies",
    "sample_pair",
    "seam_mask",
    "source_index",
    "stroke_markers",
    "stroke_order",
    "viterbi",
]
