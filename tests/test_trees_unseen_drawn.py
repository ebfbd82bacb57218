"""The whole tree pipeline with the defaults on three drawn trees in no sample set (issue 24).

A flame-shaped cypress with a 4 px outline, a cloud-crowned apple tree with a 1 px outline and
red fruit, a fan palm with a 3 px brown outline (``trees_unseen_drawn``, drawn at twice the
working size): pins, mixes, ``variations_of``, billboard-cloud side views and the LOD export.
"""

import cv2
import numpy as np
import pytest
from trees_unseen_drawn import UNSEEN

from branchnb.trees.billboard import BillboardParams, billboard_cloud
from branchnb.trees.lod import bake_side_outline, engine_view
from branchnb.trees.lod_cards import side_outline_cards
from branchnb.trees.lod_gltf import export_lod_gltf, validate_gltf
from branchnb.trees.outline import floating_ink, rim_ink_share, silhouette_outline
from branchnb.trees.quality import crossfade_fraction, dark_rim_fraction, outline_width_spread
from branchnb.trees.side_lines import side_line_figures
from branchnb.trees.variations import TreeLibrary, make_variation

S = 128
#: Where each drawing's trunk enters its crown (share of the height).
TRUNK_TOP = {"cypress": 0.81, "apple": 0.59, "fan_palm": 0.37}


@pytest.fixture(scope="module")
def lib():
    lib = TreeLibrary(size=S)
    for name, draw in UNSEEN.items():
        lib.add(draw(2 * S), name)
    return lib


def test_unseen_pins_sit_where_the_trunk_enters_the_crown(lib):
    for name, top in TRUNK_TOP.items():
        p = lib[name].contour.pins
        assert p.has_trunk
        for q in (p.r, p.l):
            assert abs(q[1] / S - top) <= 0.06, (name, p)
        assert p.b[1] >= 0.95 * (S - 1)


def test_unseen_mixes_choose_colours_and_keep_an_even_outline(lib):
    src = [outline_width_spread(e.image) for e in lib.exemplars]
    gen = np.random.default_rng(0)
    vs = [make_variation(lib, rng=gen) for _ in range(3)] + lib.variations_of("apple", 2, rng=gen)
    for v in vs:
        assert crossfade_fraction(v.image, [lib[n].image for n in v.names]) <= 0.03
        assert dark_rim_fraction(v.image, v.mask) == 0.0
        if silhouette_outline(v.image).outlined:
            q10, _, q90 = outline_width_spread(v.image)
            assert q90 / q10 <= max(q[2] / q[0] for q in src) + 0.1


# The palm's 3 px (at 512) outline is under a pixel at 128 px and reads as no outline there.
@pytest.mark.parametrize("name,size", [("cypress", 112), ("fan_palm", 160)])
def test_unseen_side_views_and_lod_export(name, size, tmp_path):
    img = cv2.resize(UNSEEN[name](2 * size), (size, size), interpolation=cv2.INTER_AREA)
    cloud = billboard_cloud(img, params=BillboardParams(max_size=size), rng=0)
    baked = bake_side_outline(cloud)
    o = silhouette_outline(cloud.image)
    assert o.outlined
    side = engine_view(baked, 45.0, cards=side_outline_cards(cloud, baked=baked))
    assert rim_ink_share(side, o.ink) >= 0.9
    assert floating_ink(side, o.ink) <= floating_ink(cloud.image, o.ink)
    f = side_line_figures(baked, 45.0)
    assert f["smear"] <= 0.01
    assert f["recall"] >= 0.75
    paths = export_lod_gltf(cloud, tmp_path / f"{name}.gltf", mode="files")
    assert len(paths) == 4
    assert all(validate_gltf(p) == [] for p in paths)
