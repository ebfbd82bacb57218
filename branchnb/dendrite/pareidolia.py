"""Pareidolia trees: an image hidden in the branches of a tree (paper, section 9).

The tree grows as in :mod:`.trees`, but after the trunk its lattice is
guided by an input image:

* iteration 1 (trunk and main limbs) uses random weights only;
* later iterations use ``w = c (1 - I) + epsilon + noise(x) * U`` with the
  image's importance ``I``: the branches run along its dark regions and
  edges. The random contribution ``noise(x)`` rises linearly from
  ``noise_image`` on the image side to ``noise_random`` on the other side,
  so the picture dissolves into ordinary twigs across the crown;
* endpoints are stippled on the importance map over the image side, and
  about half as many (``random_ratio``) are uniform random points over the
  other side; they are added over the iterations in growing batches;
* thickness is the importance emphasis (rolling importance along the
  branches, :func:`~branchnb.dendrite.thickness.rolling_importance`) on
  top of the tree's own thickness (iteration thickening plus a pipe-model
  term for the trunk), or the tree thickness alone (``thickness="branch"``).

The canvas is the image with a blank strip of ``trunk_height`` below it:
the trunk rises from the bottom centre of the strip and the crown is an
ellipse over the image, so the picture sits in the crown.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np

from ..core.image import as_float_image, as_rgb
from ..core.io import encode_png
from ..core.params import check_params, param
from ..core.random import as_rng
from .dendrite import Dendrite, build_dendrite
from .endpoints import place_endpoints, random_endpoints
from .importance import ImportanceParams, importance_map
from .lattice import Lattice, node_weights
from .planner import plan
from .render import Rendering
from .thickness import rolling_importance
from .trees import TreeParams, crown_mask, grow_tree, iteration_metric, render_tree

__all__ = ["PareidoliaParams", "PareidoliaTree", "pareidolia_tree", "side_ramp"]


@dataclass
class PareidoliaParams:
    """Image-guided tree. Tree-growth fields as in :class:`TreeParams`."""

    side: str = param("left", options=("left", "right"), help="where the image shows")
    n_endpoints: int = param(1800, min=10, max=20000, step=50,
                             help="stippled endpoints on the image side")
    random_ratio: float = param(0.5, min=0.0, max=2.0, step=0.05,
                                help="random endpoints on the other side, per image endpoint")
    noise_image: float = param(0.25, min=0.0, max=5.0, step=0.05,
                               help="random weight amplitude on the image side")
    noise_random: float = param(1.5, min=0.0, max=5.0, step=0.05,
                                help="random weight amplitude on the far side")
    cost_weight: float = param(2.0, min=0.0, max=10.0, step=0.1,
                               help="c: weight of (1 - importance) in the lattice")
    epsilon: float = param(0.3, min=0.0, max=5.0, step=0.05, help="constant node weight")
    intensity_weight: float = param(1.0, min=0.0, max=10.0, step=0.1, help="w_I")
    gradient_weight: float = param(3.0, min=0.0, max=10.0, step=0.1, help="w_G (paper: 3 w_I)")
    endpoint_gamma: float = param(2.0, min=0.25, max=4.0, step=0.05,
                                  help="image endpoints density = importance ** gamma")
    iterations: int = param(4, min=2, max=8, help="growth iterations (1 = trunk)")
    trunk_endpoints: int = param(7, min=1, max=100, help="main limbs of iteration 1")
    blend_weight: float = param(1000.0, min=0.0, max=10000.0, log=True,
                                help="a of the last iteration's blend metric (paper: 1000)")
    thickness: str = param("importance", options=("importance", "branch"),
                           help="importance emphasis or tree thickness only")
    window: int = param(15, min=1, max=101, step=2, help="rolling importance window (nodes)")
    emphasis: float = param(4.0, min=0.0, max=20.0, step=0.1,
                            help="extra width at full importance (px)")
    tip_width: float = param(0.5, min=0.1, max=10.0, step=0.1, help="width of new twigs (px)")
    increment: float = param(0.9, min=0.0, max=20.0, step=0.1,
                             help="width added to existing nodes after each iteration (px)")
    pipe: float = param(0.2, min=0.0, max=5.0, step=0.05,
                        help="extra width * sqrt(tips carried): a thick trunk")
    trunk_height: float = param(0.4, min=0.1, max=2.0, step=0.05,
                                help="blank strip below the image for the trunk (x image height)")


@dataclass
class PareidoliaTree:
    """The result: ``dendrite`` (with thickness) on the canvas (image + trunk strip),
    the input image and its importance on that canvas, and the endpoints used."""

    image: np.ndarray
    importance: np.ndarray
    dendrite: Dendrite
    endpoints_image: np.ndarray
    endpoints_random: np.ndarray
    params: PareidoliaParams

    def render(self, **options) -> Rendering:
        """:func:`~branchnb.dendrite.trees.render_tree` of the tree."""
        options.setdefault("smooth", 2)
        return render_tree(self.dendrite, **options)

    def _repr_png_(self) -> bytes:
        return encode_png(self.render().image)


def side_ramp(shape, side: str = "left") -> np.ndarray:
    """0 on the image side edge, 1 on the opposite edge, linear in x: an (H, W) array."""
    h, w = int(shape[0]), int(shape[1])
    t = np.linspace(0.0, 1.0, w)
    if side == "right":
        t = t[::-1]
    elif side != "left":
        raise ValueError(f"side must be 'left' or 'right', got {side!r}")
    return np.broadcast_to(t, (h, w)).copy()


def pareidolia_tree(image, params: PareidoliaParams | None = None, *, rng=None) -> PareidoliaTree:
    """Grow a tree whose crown shows ``image`` on one side.

    Parameters
    ----------
    image : array_like
        The picture to hide (grey or colour); the canvas has its size.
    params : PareidoliaParams, optional
    rng : {numpy.random.Generator, int}, optional

    Returns
    -------
    PareidoliaTree

    Examples
    --------
    >>> img = np.ones((96, 96)); img[20:50, 10:40] = 0.0
    >>> t = pareidolia_tree(img, PareidoliaParams(n_endpoints=60, iterations=2), rng=0)
    >>> t.dendrite.is_tree()
    True
    """
    p = check_params(params if params is not None else PareidoliaParams())
    img0 = as_rgb(as_float_image(image, name="image"), name="image")
    hi, w = img0.shape[:2]
    if hi < 16 or w < 16:
        raise ValueError(f"image must be at least 16 x 16 pixels, got {w} x {hi}")
    rng = as_rng(rng)
    h = hi + round(p.trunk_height * hi)
    img = np.ones((h, w, 3), np.float32)
    img[:hi] = img0
    imp = np.zeros((h, w), np.float32)
    imp[:hi] = importance_map(img0, ImportanceParams(p.intensity_weight, p.gradient_weight))
    ramp = side_ramp((h, w), p.side)
    tp = TreeParams(iterations=1, trunk_endpoints=p.trunk_endpoints, epsilon=p.epsilon,
                    noise=1.0, tip_width=p.tip_width, increment=p.increment, pipe=0.0,
                    crown_top=0.0, crown_bottom=(hi + 0.5) / h, crown_width=1.0,
                    blend_weight=p.blend_weight)
    d = grow_tree((h, w), tp, rng=rng).dendrite  # iteration 1: random weights
    # endpoints: stippled on the image side, uniform random on the other side
    crown = crown_mask((h, w), tp)
    img_side = ramp < 0.5
    e_img = place_endpoints(imp, p.n_endpoints, gamma=p.endpoint_gamma, floor=0.005,
                            mask=img_side & crown, rng=rng)
    n_rand = round(p.random_ratio * p.n_endpoints)
    e_rand = (random_endpoints(crown & ~img_side, n_rand, rng=rng) if n_rand > 0
              else np.zeros((0, 2)))
    ends = np.vstack([e_img, e_rand])
    ends = ends[rng.permutation(len(ends))]
    # growing batches over iterations 2..n (each twice the previous)
    n_it = p.iterations - 1
    sizes = 2.0 ** np.arange(n_it)
    cuts = np.round(np.cumsum(sizes) / sizes.sum() * len(ends)).astype(int)
    cost = p.cost_weight * (1.0 - imp.astype(np.float64))
    noise = p.noise_image + (p.noise_random - p.noise_image) * ramp
    start = 0
    for k, i in enumerate(range(2, p.iterations + 1)):
        batch = ends[start:cuts[k]]
        start = cuts[k]
        if len(batch) == 0:
            continue
        metric, a = iteration_metric(i, dataclasses.replace(tp, iterations=p.iterations))
        lat = Lattice(node_weights(cost, epsilon=p.epsilon, noise=noise, rng=rng))
        seeds = np.zeros(h * w, bool)
        seeds[d.nodes] = True
        res = plan(lat, seeds.reshape(h, w), metric=metric, blend_weight=a)
        d = build_dendrite(res, batch, base=d.with_radius(d.radius + p.increment / 2),
                           radius=p.tip_width / 2, iteration=i)
    if p.pipe > 0:
        from .trees import _pipe_width

        d = d.with_radius(d.radius + _pipe_width(d, p.tip_width, p.pipe) / 2)
    if p.thickness == "importance":
        emph = rolling_importance(d, imp, p.window)
        ref = max(float(np.percentile(imp, 99.0)), 1e-3)
        d = d.with_radius(d.radius + 0.5 * p.emphasis * np.clip(emph / ref, 0, 1) ** 1.5)
    return PareidoliaTree(img, imp, d, e_img, e_rand, dataclasses.replace(p))
