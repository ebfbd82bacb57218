"""Gallery pictures of image-based tree variations."""

from __future__ import annotations

import importlib.util
from pathlib import Path

from ..gallery import GalleryItem, SectionWriter

SECTION = "Image-based tree variations"


def render(outdir: Path) -> list[GalleryItem]:
    from .. import data
    from .exemplar import normalize_exemplar
    from .variations import TreeLibrary, tile_images

    outdir = Path(outdir)
    writer = SectionWriter(SECTION, outdir)
    save, items = writer.save, writer.items

    lib = TreeLibrary.from_data(size=512)
    ex = lib["tree_rpg_02"]
    save("trees_steps.png", tile_images([ex.contours.render(ex.image), ex.render_trunk(), ex.render()],
                                        cols=3, pad=4),
         "Exemplar processing",
         "tree_rpg_02 normalised to 512 x 512: exterior (green) and interior (blue) borders with the "
         "tree contour C (red); trunk (geometric stem estimate) and pin points B, R, L; resampled "
         "contour C_r (N = 2000) and simplified cage C_s (M = 20)")

    names = ["tree_rpg_01", "tree_rpg_03", "tree_rpg_06", "tree_rpg_10"]
    leafy = [f"tree_rpg_{i:02d}" for i in range(1, 11)]  # broadleaf and conifer sprites
    cells = []
    for a in names:
        for b in names:
            w = {a: 1.0} if a == b else {a: 0.5, b: 0.5}
            cells.append(lib.variation(w, use=names, colour_weights="shape").image)
    save("trees_combination_table.png", tile_images(cells, cols=len(names)),
         "Contour combination table",
         "row i, column j: 0.5 C_i + 0.5 C_j with colours mixed equally; diagonal: the exemplars")

    seq = lib.morph("tree_rpg_02", "tree_rpg_08", 6)
    save("trees_morph.png", tile_images([v.image for v in seq], cols=6), "Morph sequence",
         "weights (1 - t, t) for t = 0, 0.2, ..., 1; colour weights follow the shape weights")

    rand = [lib.variation(use=leafy, rng=i) for i in range(12)]
    save("trees_random.png", tile_images([v.image for v in rand], cols=6),
         "Random variations",
         "12 random variations of the broadleaf and conifer RPG sprites (01-10): 3 exemplars per draw, Dirichlet shape "
         "weights, colour concentration 0.3, M = 20")

    target = "tree_rpg_04"
    vs = lib.variations_of(target, 5, use=leafy, rng=2)
    save("trees_variations_of.png", tile_images([lib[target].image] + [v.image for v in vs], cols=6),
         "Variations of one tree",
         f"left: {target}; right: variations that keep at least half of its shape and colour weight, "
         "mixed with sprites 01-10")

    autumn = lib.variation({"tree_rpg_01": 0.5, "tree_rpg_03": 0.5}, use=names, rng=3,
                           reference="maple_leaf_03")
    plain = lib.variation({"tree_rpg_01": 0.5, "tree_rpg_03": 0.5}, use=names, rng=3)
    save("trees_histogram_transfer.png",
         tile_images([plain.image, normalize_exemplar(data.load("maple_leaf_03"), size=512).image,
                      autumn.image], cols=3),
         "Histogram transfer",
         "seasonal change: a variation, the reference (an autumn maple leaf photo, maple_leaf_03) and "
         "the variation with its per-channel histograms matched to the reference's opaque pixels")

    if importlib.util.find_spec(f"{__package__}._gallery_cloud") is not None:
        from . import _gallery_cloud

        items.extend(_gallery_cloud.gallery_items(outdir))
    return items


__all__ = ["render", "SECTION"]
