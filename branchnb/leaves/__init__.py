"""Leaf variations by structural layering (Assa & Cohen-Or, "More of the same", C&G 2012).

Analysis: exemplar normalisation (:mod:`.exemplar`), keypoints on strong
edges (:mod:`.keypoints`), non-rigid registration by TPS-RPM
(:mod:`.registration`), texture correction of strongly warped regions
(:mod:`.correction`). A procedural leaf family with ground truth for
measuring (:mod:`.procedural`).

Training layers scribbled on one leaf and grown by lazy snapping
(:mod:`.layers`), layer induction on every exemplar with residuals
(:mod:`.induction`, pipeline :func:`analyze` in :mod:`.analysis`), thin
layers snapped to each exemplar's own ridges (:mod:`.snapping`, beyond the
paper) and layered synthesis of new leaves (:mod:`.synthesis`). Whether
an induced layer is structural, and the warnings :func:`analyze` emits
(:class:`NonStructuralLayerWarning`, :class:`ShadowAsLeafWarning`), in
:mod:`.structural`. Hand-traced
veins of the sample maples for measuring (:mod:`.reference`).
"""

from .analysis import IdentityRegistration, LayerInduction, LeafAnalysis, analyze, normalise_exemplars, warp_mask
from .correction import TextureCorrection, correct_texture, distorted_pixels, jacobian_singular_values
from .exemplar import Exemplar, blade_mask, leaf_exemplar, prepare_exemplars
from .induction import InductionParams
from .keypoints import Keypoints, edge_keypoints, edge_strength
from .layers import Layer, LayerSet, SnapParams, TrainingLayers, grow_layers, scribble_mask, simulate_scribbles
from .procedural import KINDS, PALETTES, ProceduralLeaf, leaf_family, procedural_leaf
from .reference import reference_vein_names, reference_veins
from .registration import (
    Registration,
    RegistrationParams,
    ThinPlateSpline,
    draw_registration,
    register,
    split_petiole,
    start_alignment,
    start_candidates,
    tps_rpm,
)
from .scribbles import Scribble
from .structural import (
    MAX_STRUCTURAL_REACH,
    MIN_FOUND,
    MIN_STANDOUT,
    MIN_STRUCTURAL_LAMBDA,
    LeafAnalysisWarning,
    NonStructuralLayerWarning,
    ShadowAsLeafWarning,
    is_structural,
    layer_standout,
    layer_warnings,
    shadow_share,
    spatial_reach,
    warn_analysis,
)
from .synthesis import GeneratedLeaf, SynthesisParams, generate, save_leaves

__all__ = [
    "Layer", "LayerSet", "Scribble", "SnapParams", "TrainingLayers", "grow_layers", "scribble_mask",
    "simulate_scribbles",
    "MAX_STRUCTURAL_REACH", "MIN_FOUND", "MIN_STANDOUT", "MIN_STRUCTURAL_LAMBDA", "LeafAnalysisWarning",
    "NonStructuralLayerWarning", "ShadowAsLeafWarning", "is_structural", "layer_standout", "layer_warnings",
    "shadow_share", "spatial_reach", "warn_analysis",
    "InductionParams", "LayerInduction", "LeafAnalysis", "analyze", "IdentityRegistration",
    "normalise_exemplars", "warp_mask", "reference_veins", "reference_vein_names", "split_petiole",
    "SynthesisParams", "GeneratedLeaf", "generate", "save_leaves",
    "KINDS",
    "PALETTES",
    "Exemplar",
    "Keypoints",
    "ProceduralLeaf",
    "Registration",
    "RegistrationParams",
    "TextureCorrection",
    "ThinPlateSpline",
    "blade_mask",
    "correct_texture",
    "distorted_pixels",
    "draw_registration",
    "edge_keypoints",
    "edge_strength",
    "jacobian_singular_values",
    "leaf_exemplar",
    "leaf_family",
    "prepare_exemplars",
    "procedural_leaf",
    "register",
    "start_alignment",
    "start_candidates",
    "tps_rpm",
]
