"""Leaf variations by structural layering (Assa & Cohen-Or, "More of the same", C&G 2012).

Analysis: exemplar normalisation (:mod:`.exemplar`), keypoints on strong
edges (:mod:`.keypoints`), non-rigid registration by TPS-RPM
(:mod:`.registration`), texture correction of strongly warped regions
(:mod:`.correction`). A procedural leaf family with ground truth for
measuring (:mod:`.procedural`).

Training layers scribbled on one leaf and grown by lazy snapping
(:mod:`.layers`), layer induction on every exemplar with residuals
(:mod:`.induction`, pipeline :func:`analyze` in :mod:`.analysis`) and
layered synthesis of new leaves (:mod:`.synthesis`).
"""

from .analysis import LayerInduction, LeafAnalysis, analyze
from .induction import InductionParams
from .layers import Layer, LayerSet, Scribble, SnapParams, TrainingLayers, grow_layers, simulate_scribbles
from .procedural import KINDS, PALETTES, ProceduralLeaf, leaf_family, procedural_leaf

__all__ = ["KINDS", "PALETTES", "ProceduralLeaf", "leaf_family", "procedural_leaf",
           "Layer", "LayerSet", "Scribble", "SnapParams", "TrainingLayers", "grow_layers",
           "simulate_scribbles", "InductionParams", "LayerInduction", "LeafAnalysis", "analyze"]
