"""Leaf variations by structural layering (Assa & Cohen-Or, "More of the same", C&G 2012).

Analysis: exemplar normalisation (:mod:`.exemplar`), keypoints on strong
edges (:mod:`.keypoints`), non-rigid registration by TPS-RPM
(:mod:`.registration`), texture correction of strongly warped regions
(:mod:`.correction`). A procedural leaf family with ground truth for
measuring (:mod:`.procedural`).
"""

from .correction import TextureCorrection, correct_texture, distorted_pixels, jacobian_singular_values
from .exemplar import Exemplar, blade_mask, leaf_exemplar, prepare_exemplars
from .keypoints import Keypoints, edge_keypoints, edge_strength
from .procedural import KINDS, PALETTES, ProceduralLeaf, leaf_family, procedural_leaf
from .registration import (
    Registration,
    RegistrationParams,
    ThinPlateSpline,
    draw_registration,
    register,
    start_alignment,
    start_candidates,
    tps_rpm,
)

__all__ = [
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
