"""Two path metrics side by side on the same image, lattice and endpoints.

The paper's comparison (Long & Mould 2009, Fig. 3): the cumulative metric's
smooth paths against the partial non-scalar metric's jagged ones, planned on one
lattice from one seed to one set of endpoints, with per-endpoint path
statistics for histograms.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..core.io import encode_png
from ..core.params import check_params
from ..core.random import as_seed
from ..core.validate import Choice, checked
from .dendrite import PathStats, path_statistics
from .planner import METRICS
from .stylization import Stylization, StylizeParams, Stylizer

__all__ = ["MetricComparison", "compare_metrics"]

#: A planner metric name.
_METRIC = Choice(*METRICS)


@dataclass
class MetricComparison:
    """The same image, seed, lattice and endpoints planned with two metrics.

    Parameters
    ----------
    first, second : Stylization
        The two runs, usually the cumulative and the non-scalar result.
    stats_first, stats_second : PathStats
        Per-endpoint tortuosity and maximum edge cost of each, one entry per
        endpoint in the same order.
    """

    first: Stylization
    second: Stylization
    stats_first: PathStats
    stats_second: PathStats

    def _repr_png_(self) -> bytes:
        a, b = self.first, self.second
        imgs = [x.rendering.image if x.rendering is not None else x.dendrite.render()
                for x in (a, b)]
        return encode_png(np.concatenate(imgs, axis=1))


@checked(first=_METRIC, second=_METRIC)
def compare_metrics(stylizer: Stylizer, params: StylizeParams | None = None, *, seed=None,
                    rng: int | np.random.Generator = 0, first: str = "cumulative", second: str | None = None,
                    metaphor: str | None = "plain", **render_options) -> MetricComparison:
    """Run the stylization twice on the same endpoints: ``first`` and ``second`` metric.

    ``second`` defaults to ``params.metric`` (or ``"nonscalar"`` when that is
    the same as ``first``). Both runs share the cached importance, lattice
    and endpoints of ``stylizer``.

    Parameters
    ----------
    stylizer : Stylizer
        The image's pipeline; its caches are shared by both runs.
    params : StylizeParams, optional
        Common parameters (defaults if None); only the metric differs.
    seed : (x, y), optional
        Start of both dendrites (image pixels); see :meth:`~branchnb.dendrite.stylization.Stylizer.run`.
    rng : int or numpy.random.Generator
        Seed of the lattice noise and the stippling, shared by both runs; 0.
    first : {"cumulative", "nonscalar", "blend"}
        Metric of the first run; "cumulative".
    second : {"cumulative", "nonscalar", "blend"}, optional
        Metric of the second run (see above).
    metaphor : {"plain", "vines", "lightning", None}
        Rendering metaphor of both runs.
    **render_options
        Passed to the metaphor's render function.

    Returns
    -------
    MetricComparison
        Both stylizations and per-endpoint path statistics of every endpoint,
        in the same order for both.

    Examples
    --------
    >>> img = np.ones((40, 40)); img[10:30, 10:30] = 0.0
    >>> c = compare_metrics(Stylizer(img), StylizeParams(n_endpoints=30), rng=0)
    >>> c.second.params.metric, bool((c.stats_second.max_edge <= c.stats_first.max_edge).all())
    ('nonscalar', True)
    """
    p = check_params(params if params is not None else StylizeParams())
    rng = as_seed(rng)  # both runs share one seed, so they share the endpoints
    if second is None:
        second = p.metric if p.metric != first else "nonscalar"
    a = stylizer.run(dataclasses.replace(p, metric=first), seed=seed, rng=rng, metaphor=metaphor,
                     **render_options)
    b = stylizer.run(dataclasses.replace(p, metric=second), seed=seed, rng=rng,
                     metaphor=metaphor, **render_options)
    # per endpoint, in the same order for both (endpoints lying on the structure included)
    return MetricComparison(a, b, _endpoint_stats(a), _endpoint_stats(b))


def _endpoint_stats(s: Stylization) -> PathStats:
    hl, wl = s.lattice.shape
    lat_ends = np.clip((s.endpoints + 0.5) / s.scale - 0.5, 0, [wl - 1, hl - 1])
    nodes = np.unique(s.lattice.node_index(lat_ends))
    d = s.dendrite
    where = np.full(s.plan.n_nodes, -1, np.int64)
    where[d.nodes] = np.arange(d.n_nodes)
    every_end = dataclasses.replace(d, tips=where[nodes])
    return path_statistics(every_end, s.plan)
