"""Dendritic structures by path planning.

Long & Mould, "Dendritic stylization" (The Visual Computer 25, 2009), built
on Xu & Mould, "Modeling dendritic structures using path planning" (GRAPP
2007): least-cost paths from a seed to many endpoints on a randomly weighted
lattice merge into a dendrite; a partial non-scalar path metric (maximum
edge cost first, cumulative cost second) makes the branches jagged and
lightning-like. Trees grow by iterative path planning (:func:`grow_tree`,
:func:`grow_layers`) and from a picture's tones (:func:`pareidolia_tree`).
"""

from .compare import MetricComparison, compare_metrics
from .dendrite import Dendrite, PathStats, build_dendrite, path_statistics
from .endpoints import place_endpoints, random_endpoints
from .importance import ImportanceParams, importance_map
from .lattice import Lattice, direction_factors, make_lattice, node_weights
from .metaphors import LightningParams, lightning, render_lightning, render_vines
from .pareidolia import PareidoliaTree, pareidolia_tree
from .pareidolia_params import PareidoliaParams
from .planner import METRICS, PlanResult, plan
from .render import Rendering, cost_image, draw_points, render_plain, visiting_order_image
from .stylization import Stylization, StylizeParams, Stylizer, stylize
from .thickness import branch_thickness, importance_thickness, rolling_importance
from .trees import GrownTree, TreeParams, grow_layers, grow_tree, render_layers, render_tree

__all__ = [
    "METRICS",
    "Dendrite",
    "GrownTree",
    "ImportanceParams",
    "Lattice",
    "LightningParams",
    "MetricComparison",
    "PareidoliaParams",
    "PareidoliaTree",
    "PathStats",
    "PlanResult",
    "Rendering",
    "Stylization",
    "StylizeParams",
    "Stylizer",
    "TreeParams",
    "branch_thickness",
    "compare_metrics",
    "build_dendrite",
    "cost_image",
    "direction_factors",
    "draw_points",
    "grow_layers",
    "grow_tree",
    "importance_map",
    "importance_thickness",
    "lightning",
    "make_lattice",
    "node_weights",
    "pareidolia_tree",
    "path_statistics",
    "place_endpoints",
    "plan",
    "random_endpoints",
    "render_layers",
    "render_lightning",
    "render_plain",
    "render_tree",
    "render_vines",
    "rolling_importance",
    "stylize",
    "visiting_order_image",
]
