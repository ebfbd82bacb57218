"""Issue 23, item 1: flat-colour drawings join every outlet to the region it drains into (a delta's
distributaries reach the sea, a map's mouths the coast line) and keep no lake the example lacks."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_image, synthesize_structure
from branchnb.branching._map_examples import country_map_example, delta_mask_example
from branchnb.branching.drawing import DrawingStyle, _to_outlets, draw_in_style
from branchnb.core.render import coverage_polylines
from branchnb.core.structure import Branch, Structure


def _end_gap(img: np.ndarray, water: np.ndarray, end) -> float:
    """Pixels between the drawn channel around ``end`` and the sea (``water`` outside the land)."""
    x, y = np.rint(end).astype(int)
    win = img[y - 15:y + 16, x - 15:x + 16] > 0.5
    lab, _ = ndi.label(win, np.ones((3, 3)))
    own = lab == lab[15, 15]
    sea = water[y - 15:y + 16, x - 15:x + 16]
    return 0.0 if (own & sea).any() else float(ndi.distance_transform_edt(~sea)[own].min())


@pytest.mark.parametrize("seed", [0, 1])
def test_delta_distributaries_reach_the_sea(seed):
    mask, _ch, _sea = delta_mask_example((192, 192), seed)
    ex = extract_structure(mask, root="nearest_region")
    res = synthesize_structure(fit_model(ex, domain=example_domain(mask)), rng=1)
    out = synthesize_image(np.dstack([mask] * 3), ex, res, rng=0)
    sea = out.labels != np.bincount(out.labels[res.domain]).argmax()
    depth = ndi.distance_transform_edt(~sea)
    img = out.image[..., 0]
    ends = [b.points[-1] for b in res.structure.branches
            if 16 <= b.points[-1][0] < 176 and 16 <= b.points[-1][1] < 176
            and depth[int(round(b.points[-1][1])), int(round(b.points[-1][0]))] <= 8]
    assert ends                                                      # some channels run to the sea
    assert max(_end_gap(img, sea & (img > 0.5), e) for e in ends) < 2.0
    lab, n = ndi.label(img > 0.5, np.ones((3, 3)))
    assert n == 1                                                    # channels and sea: one water body
    # the example's sea edge is one straight row: so is the output's, away from its own channels
    # (no bump of sea nor dent of land where the example's channels opened into it)
    top = np.argmax(sea, axis=0).astype(float)
    cov, _ = coverage_polylines(mask.shape, [b.points for b in res.structure.branches],
                                [2 * b.thickness + 12 for b in res.structure.branches])
    # columns whose channels do not come near the sea edge (a fan may cross every column further inland)
    edge = int(np.median(top))
    clear = ~(cov[max(edge - 12, 0):edge + 12] > 0.01).any(axis=0)
    assert clear.sum() >= 40
    # within 2 px: the bumps this guards against were 4-8 px (a notch per example mouth)
    assert np.abs(top[clear] - np.median(top[clear])).max() <= 2


def test_tips_extend_to_the_boundary_and_sources_keep_clear():
    inside = np.zeros((60, 60), bool)
    inside[:40] = True
    s = Structure([Branch([(30, 5), (30, 20), (30, 36)], 1.0)], image_shape=(60, 60))
    ext = _to_outlets(s, inside, 0.0, tip_reach=12.0)
    assert ext.branches[0].points[-1][1] >= 39.5 and len(ext.branches[0].points) == 4
    cut = _to_outlets(s, inside, 0.0, tip_reach=0.0, clear=6.0)
    assert cut.branches[0].points[-1][1] <= 34 and cut.branches[0].points[0][1] == 5


def test_style_reads_tip_outlets_from_the_example():
    mask, _ch, _sea = delta_mask_example((160, 160), 0)
    ex = extract_structure(mask, root="nearest_region")
    res = synthesize_structure(fit_model(ex, domain=example_domain(mask)), rng=0)
    out = synthesize_image(np.dstack([mask] * 3), ex, res, rng=0)
    from branchnb.branching.drawing import drawing_style
    from branchnb.branching.regions import colour_labels, region_layout
    from branchnb.branching.skeleton_map import SkeletonMap

    pm = SkeletonMap(ex, 1.0).pixel_map(mask.shape)
    img = np.dstack([mask] * 3).astype(np.float32)
    zone = pm.core(3.0, 4.0)
    lay = region_layout(colour_labels(img, out.example_labels, ~zone), zone, pm.core(1.0, 0.0))
    assert drawing_style(img, ex, lay, pm).tip_reach > 0                # a delta's ends meet the sea
    map_img, _truth, _land = country_map_example((192, 192), 0, layout="coast")
    mex = extract_structure(map_img, root="nearest_region")
    mpm = SkeletonMap(mex, 1.0).pixel_map(map_img.shape[:2])
    lab = (~_land).astype(np.int32)
    st = drawing_style(map_img, mex, lab, mpm)
    assert st.tip_reach == 0 and st.outlet_reach > 0                    # a map's sources lie inland
    assert isinstance(st, DrawingStyle)
    drawn = draw_in_style(st, mex, lab)
    assert drawn.shape == map_img.shape


def test_no_sea_in_the_land_where_the_example_has_none():
    img, _truth, land = country_map_example((224, 224), 2, layout="bay")
    ex = extract_structure(img, root="nearest_region")
    dom = example_domain(img, ex)
    dom[:30, :30] = False                                            # a land corner the domain left out
    res = synthesize_structure(fit_model(ex, domain=dom), rng=1)
    out = synthesize_image(img, ex, res, rng=0)
    sea_out = out.labels != np.bincount(out.labels[dom]).argmax()
    assert not sea_out[:30, :30][land[:30, :30]].any()


def test_a_river_traced_from_its_source_is_an_outlet():
    # land above y = 50; tree 0 rooted at its source with a child reaching the coast, tree 1 at the
    # coast already, tree 2 a delta-like trunk with two ends at the coast (left as it is)
    from branchnb.branching.roots import fit_roots, outlet_starts

    dom = np.zeros((100, 100), bool)
    dom[:50] = True
    s = Structure([Branch([(20, 10), (20, 25), (20, 30)], 1.0),
                   Branch([(20, 25), (12, 36), (10, 48)], 1.0, parent=0, parent_vertex=1),
                   Branch([(50, 49), (50, 20)], 1.0),
                   Branch([(80, 20), (80, 30)], 1.0),
                   Branch([(80, 30), (72, 48)], 1.0, parent=3, parent_vertex=1),
                   Branch([(80, 30), (88, 48)], 1.0, parent=3, parent_vertex=1)], image_shape=(100, 100))
    starts = outlet_starts(s, dom)
    assert starts[0].tolist() == [10.0, 48.0] and starts[1].tolist() == [50.0, 49.0]
    # two of three trees drain at the coast: the third, with two ends there, is two joined rivers
    assert starts[2].tolist() in ([72.0, 48.0], [88.0, 48.0])
    rm = fit_roots(s, dom)
    assert rm.sides.tolist() == [4, 4, 4]
    assert rm.depth[0] <= 2.0 and rm.directions[0] < 0   # heads up, into the land
    # alone, that tree is a delta: its trunk comes from inland and stays its root
    delta = Structure(s.branches[3:4] + [Branch(b.points, b.thickness, 0, 1) for b in s.branches[4:]],
                      image_shape=(100, 100))
    assert outlet_starts(delta, dom)[0].tolist() == [80.0, 20.0]
    assert fit_roots(delta, dom).sides.tolist() == [5]


@pytest.mark.parametrize("layout,size,seed", [("island", 256, 3), ("coast", 256, 1), ("island", 320, 1)])
def test_synthesized_map_rivers_reach_the_coast(layout, size, seed):
    img, _s, _land = country_map_example((size, size), seed, layout=layout)
    ex = extract_structure(img)
    res = synthesize_structure(fit_model(ex, domain=example_domain(img, ex)), rng=0)
    out = synthesize_image(img, ex, res, rng=0)
    land = out.labels == np.bincount(out.labels[res.domain]).argmax()
    dark = out.image.max(-1) < 0.35
    coast = dark & ndi.binary_dilation(land & ndi.binary_dilation(~land), iterations=3)
    coast[:2] = coast[-2:] = False
    coast[:, :2] = coast[:, -2:] = False
    lab, _n = ndi.label(dark, np.ones((3, 3)))
    on_coast = set(np.unique(lab[coast]).tolist()) - {0}
    s = res.structure
    for i, b in enumerate(s.branches):
        if b.parent is not None:
            continue
        x, y = np.clip(np.rint(b.points[0]).astype(int), 0, size - 1)
        if min(x, y, size - 1 - x, size - 1 - y) < 4:
            continue                              # a river coming in from beyond the frame
        # the drawn river around its root is one piece with the coast line
        assert lab[y, x] in on_coast, (i, x, y)
