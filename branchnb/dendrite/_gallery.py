"""Gallery pictures of the dendrite technique."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..gallery import GalleryItem, SectionWriter

SECTION = "Dendritic structures by path planning"


def render(outdir: Path) -> list[GalleryItem]:
    from .. import data
    from .dendrite import build_dendrite
    from .endpoints import random_endpoints
    from .lattice import make_lattice
    from .metaphors import lightning, render_lightning
    from .pareidolia import pareidolia_tree
    from .planner import plan
    from .render import render_plain, visiting_order_image
    from .stylization import StylizeParams, Stylizer
    from .thickness import branch_thickness
    from .trees import grow_layers, grow_tree, render_layers

    outdir = Path(outdir)
    writer = SectionWriter(SECTION, outdir)
    save, items = writer.save, writer.items

    # the two metrics on the same random lattice and endpoints
    lat = make_lattice(np.zeros((256, 256)), noise=1.0, epsilon=1.0, rng=1)
    ends = random_endpoints(np.ones((256, 256), bool), 200, rng=2)
    tiles = []
    for metric in ("cumulative", "nonscalar"):
        res = plan(lat, (128, 128), metric=metric)
        d = branch_thickness(build_dendrite(res, ends), min_width=0.8, max_width=5)
        tiles.append(np.concatenate([render_plain(d).image, visiting_order_image(res)], 0))
    save("dendrite_metrics.png", np.concatenate(tiles, 1), "Cumulative vs non-scalar metric",
         "same lattice and 200 endpoints; left cumulative, right non-scalar (max edge, then sum); "
         "bottom: Dijkstra's visiting order as contour bands")

    for name in ("astronaut", "camera", "chelsea", "zelkova_leaf", "lightning_noaa"):
        st = Stylizer(data.load(name))
        out = st.run(StylizeParams(), rng=0)
        save(f"dendrite_stylized_{name}.png", out.rendering.image, f"Dendritic stylization: {name}",
             "defaults: 3,000 stippled endpoints, non-scalar metric, importance emphasis and tone; "
             "no endpoints on empty paper")
    st = Stylizer(data.load("chelsea"))
    cum = st.run(StylizeParams(metric="cumulative"), rng=0)
    save("dendrite_stylized_chelsea_cumulative.png", cum.rendering.image,
         "Stylization, cumulative metric", "same endpoints as above, cumulative metric")
    vines = st.run(StylizeParams(n_endpoints=250, min_width=1.0, max_width=5.0), rng=0,
                   metaphor="vines")
    save("dendrite_vines.png", vines.rendering.image, "Vines metaphor",
         "250 endpoints, smoothed stems, curls and leaves")
    bolt = render_lightning(lightning((400, 300), rng=3))
    save("dendrite_lightning.png", bolt.image, "Lightning",
         "non-scalar metric on a lattice where up/sideways edges cost more; glow rendering")
    tree = grow_tree((400, 360), rng=0)
    layers = grow_layers((400, 360), layers=3, rng=5)
    save("dendrite_trees.png", np.concatenate([tree.render().image, render_layers(layers).image], 1),
         "Trees by iterative growth", "4 iterations (cumulative trunk, then blended metric, "
         "shrinking radius); right: 3 trees from one trunk drawn back to front (occlusion)")
    par = pareidolia_tree(data.load("astronaut"), rng=0)
    leaf = pareidolia_tree(data.load("zelkova_leaf"), rng=0)
    save("dendrite_pareidolia.png", par.render().image, "Pareidolia tree",
         "astronaut hidden in the crown; the crown follows the picture, pipe-model trunk")
    save("dendrite_pareidolia_leaf.png", leaf.render().image, "Pareidolia tree: a leaf",
         "a leaf photo on white: a tree crown round the leaf, light twigs on its blank ground")
    return items
