"""Issue 23: networks extracted as networks (closed cells) and terrain maps whose lowland has the outside's colour."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching._image_examples import cracked_mud_example
from branchnb.branching._map_examples import river_map_example, terrain_map_example
from branchnb.branching.extraction import example_domain, extract_structure, skeleton_to_structure
from branchnb.core.random import as_rng


def _interior_cells(mask: np.ndarray, min_area: int) -> tuple[np.ndarray, list[int]]:
    lab, n = ndi.label(~mask)
    border = set(np.unique(np.r_[lab[0], lab[-1], lab[:, 0], lab[:, -1]]).tolist())
    area = np.bincount(lab.ravel(), minlength=n + 1)
    return lab, [i for i in range(1, n + 1) if i not in border and area[i] >= min_area]


def _closed_share(img: np.ndarray, cracks: np.ndarray, **kw) -> float:
    """Share of the true interior cells that the extracted lines close (IoU >= 0.5 with a closed cell)."""
    cracks = cracks.copy()        # the frame's own crack (mirrored cells) is no wall to find
    cracks[:3] = cracks[-3:] = False
    cracks[:, :3] = cracks[:, -3:] = False
    t_lab, truth = _interior_cells(cracks, 30)
    s = extract_structure(img, **kw)
    e_lab, found = _interior_cells(s.render(img.shape[:2], min_width=2.0)[..., 0] < 0.5, 30)
    found = set(found)
    hits = 0
    for t in truth:
        m = t_lab == t
        ids, cnt = np.unique(e_lab[m], return_counts=True)
        hits += any(i in found and c / (m.sum() + (e_lab == i).sum() - c) >= 0.5 for i, c in zip(ids, cnt))
    return hits / len(truth)


@pytest.mark.parametrize("size, cells, width, seed", [(256, None, 2.5, 0), (384, 40, 2.5, 2), (384, 20, 4.0, 3)])
def test_crack_networks_come_out_with_closed_cells(size, cells, width, seed):
    img, cracks = cracked_mud_example((size, size), seed, cells=cells, width=width)
    assert _closed_share(img, cracks) >= 0.8
    if seed == 2:   # the tree alone (every cycle cut) closes few of them
        assert _closed_share(img, cracks, close_cycles=0.0) < 0.5


def test_cycle_joins_close_a_ring_and_keep_a_tree():
    ring = np.zeros((60, 60), bool)
    ring[10, 10:50] = ring[49, 10:50] = ring[10:50, 10] = ring[10:50, 49] = True
    r = np.full(ring.shape, 1.5)
    closed, cut = skeleton_to_structure(ring, r, close_cycles=40.0), skeleton_to_structure(ring, r)
    assert len(closed.branches) == len(cut.branches) + 1          # one join closes the one cell
    join = closed.branches[-1]
    assert join.parent is not None and join.parent < len(closed.branches) - 1
    # the join ends on a vertex of another branch: the cell is closed at the rendered width
    ends_on = min(np.hypot(*(b.points - join.points[-1]).T).min() for b in closed.branches[:-1])
    assert ends_on < 1e-9
    assert ndi.label(~(closed.render((60, 60))[..., 0] < 0.5))[1] == 2
    # a loop shorter than close_cycles stays cut; a tree has no cut to close
    assert len(skeleton_to_structure(ring, r, close_cycles=200.0).branches) == \
        len(skeleton_to_structure(ring, r).branches)
    line = np.zeros((40, 80), bool)
    line[20, 5:75] = True
    line[21:36, 40] = True
    assert len(skeleton_to_structure(line, np.full(line.shape, 2.0), min_component_length=20,
                                     close_cycles=40.0).branches) == 2


def _terrain(size: int, seed: int, relief: str):
    _img, _s, land = river_map_example((size, size), as_rng(seed), n_trees=12, r_mouth=1.3)
    img, _s, _riv = terrain_map_example((size, size), seed, relief=relief)
    return img, land


@pytest.mark.parametrize("relief, size, seed", [("levels", 256, 0), ("levels", 320, 1), ("shade", 256, 2)])
def test_terrain_domain_is_the_land_inside_the_coast(relief, size, seed):
    # the white lowland has the white outside's colour: the coast line, not the colour, bounds the land
    img, land = _terrain(size, seed, relief)
    dom = example_domain(img, extract_structure(img))
    assert (dom & land).sum() / (dom | land).sum() >= 0.97


@pytest.mark.parametrize("size", [320, 384])
def test_terrain_rivers_stay_on_land_and_the_coast_is_drawn(size):
    from branchnb.branching.image_synthesis import synthesize_image
    from branchnb.branching.synthesis import fit_model, synthesize_structure

    img, land = _terrain(size, 0, "levels")
    ex = extract_structure(img)
    res = synthesize_structure(fit_model(ex, domain=example_domain(img, ex)), rng=0)
    rivers = res.structure.render(img.shape[:2])[..., 0] < 0.5
    assert (rivers & land).sum() / rivers.sum() >= 0.98
    out = synthesize_image(img, ex, res, rng=0).image[..., :3].mean(axis=2)
    edge = res.domain & ~ndi.binary_erosion(res.domain)
    assert np.mean(ndi.minimum_filter(out, 5)[edge] < 0.4) >= 0.9
