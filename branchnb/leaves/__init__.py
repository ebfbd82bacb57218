"""Leaf variations by structural layering (Assa & Cohen-Or, "More of the same", C&G 2012).

Analysis: exemplar normalisation (:mod:`.exemplar`), keypoints on strong
edges (:mod:`.keypoints`), non-rigid registration by TPS-RPM
(:mod:`.registration`), texture correction of strongly warped regions
(:mod:`.correction`). A procedural leaf family with ground truth for
measuring (:mod:`.procedural`).
"""

from .procedural import KINDS, PALETTES, ProceduralLeaf, leaf_family, procedural_leaf

__all__ = ["KINDS", "PALETTES", "ProceduralLeaf", "leaf_family", "procedural_leaf"]
