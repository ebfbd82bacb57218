"""Image synthesis for branching structures: learn bending and branching from an example.

Rivers, cracks, lightning, blood vessels: a :class:`Structure` of branches
(polylines with a thickness per vertex) is extracted from an example
image (from clicks or automatically), its bending, thickness and
furcation statistics are learnt, and new structures are grown with a
Markov model, global histogram matching, a furcation SVM, space
colonization and optional guidance.

>>> from branchnb.branching import Structure, Branch, synthesize_structure
"""

from ..core.structure import Branch, Structure
from .extraction import (
                         branch_from_clicks,
                         estimate_thickness,
                         example_domain,
                         extract_structure,
                         structure_from_polylines,
)
from .guidance import Guidance, guidance_map
from .histogram_matching import histogram_distances
from .image_synthesis import ImageSynthesisParams, ImageSynthesisResult, synthesize_image
from .params import ClickParams, ExtractionParams, SynthesisParams
from .synthesis import (
                         StructureModel,
                         SynthesisResult,
                         extend_branch,
                         fit_model,
                         synthesize_structure,
)

__all__ = [
                         "Branch",
                         "ClickParams",
                         "ExtractionParams",
                         "Guidance",
                         "Structure",
                         "StructureModel",
                         "SynthesisParams",
                         "SynthesisResult",
                         "branch_from_clicks",
                         "estimate_thickness",
                         "example_domain",
                         "extend_branch",
                         "extract_structure",
                         "fit_model",
                         "guidance_map",
                         "histogram_distances",
                         "ImageSynthesisParams",
                         "ImageSynthesisResult",
                         "synthesize_image",
                         "structure_from_polylines",
                         "synthesize_structure",
]
