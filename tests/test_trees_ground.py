"""Tree variations on exemplars nobody tuned them on: ground clutter at the
trunk foot, broad flat fronds, outlines. Pins against hand-placed references
and procedural truths, segmentation on masks not made from this segmenter,
no ghosting, one piece, billboard side views."""

from __future__ import annotations

import itertools

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb import data
from branchnb.trees import (
    BillboardParams,
    TreeLibrary,
    billboard_cloud,
    make_variation,
    process_exemplar,
    segment_tree,
    segmentation_iou,
)
from branchnb.trees.ground import neck_profile, split_ground
from branchnb.trees.pin_reference import load_reference_pins, pin_errors, source_pins
from branchnb.trees.preview import render_cloud
from branchnb.trees.quality import foreign_colour_fraction, large_holes, pieces, soft_alpha_fraction
from branchnb.trees.synthetic import SYNTHETIC_KINDS, synthetic_tree, synthetic_trees
from branchnb.trees.variations import exemplar_largest_hole


@pytest.fixture(scope="module")
def synth():
    return synthetic_trees(1, rng=5, size=192)


# ------------------------------------------------------------------ ground split
def test_ground_is_cut_off_the_real_trees_with_something_at_the_foot():
    for name in ("palm_island", "tree_on_hill", "christmas_tree_in_tray", "conifer_on_base",
                 "arbre_modern"):
        s = split_ground(data.load(name))
        assert s.has_ground, name
        assert s.stem.any() and s.foot is not None
    # a flared trunk base and clean cut-outs keep everything
    for name in ("christmas_tree_root_flare", "tree_rpg_01", "tree_rpg_13", "evergreen"):
        assert not split_ground(data.load(name)).has_ground, name


def test_ground_matches_the_procedural_truth(synth):
    scores = {}
    for t in synth:
        truth = t.labels == 255
        got = split_ground(t.image).ground
        if truth.any():
            scores[t.kind] = (got & truth).sum() / (got | truth).sum()
        else:
            assert not got.any(), t.kind
    # measured on this draw: 6 of 7 clutter kinds found (the outlined pile is missed)
    assert sum(v > 0.7 for v in scores.values()) >= 6, scores


def test_outlined_cartoon_leaves_at_the_foot_are_ground():
    """Each leaf with its own outline, some leaning on the trunk, some lying apart."""
    ious = []
    for seed in range(4):
        t = synthetic_tree("leaf_pile_outlined", rng=seed, size=192)
        s = split_ground(t.image)
        truth = t.labels == 255
        ious.append((s.ground & truth).sum() / (s.ground | truth).sum())
        assert not (s.ground & (t.labels == 1)).any()           # no crown cut off
    # measured: 0.89-0.97 on seeds 0-11 (shape alone: 0 on 7 of 12, the pile is no wider than
    # the trunk and loose leaves were taken for the bottom)
    assert min(ious) >= 0.8, ious


def test_neck_ignores_a_rock_beside_the_trunk():
    m = np.zeros((30, 20), bool)
    m[2:14, 2:18] = True
    m[14:24, 9:11] = True
    m[24:28, 1:19] = True
    m[18:24, 1:5] = True
    c = neck_profile(m)
    assert c[20] == 2 and c[26] == 18


def test_split_ground_rejects_bad_input():
    with pytest.raises(ValueError, match="RGBA"):
        split_ground(np.ones((10, 10, 3), np.float32))
    with pytest.raises(ValueError, match="no opaque"):
        split_ground(np.zeros((10, 10), bool))


# ------------------------------------------------------------------ pins
def test_pins_within_5_percent_of_hand_placed_ones():
    refs = load_reference_pins()
    assert len(refs) >= 14
    ok = []
    for name, ref in refs.items():
        img = data.load(name)
        ex = process_exemplar(img, name, size=256)
        err = pin_errors(source_pins(ex), ref, img[..., 3])
        ok.append(max(err.values()) <= 0.05)
    # measured at 256: 11 of 14 (B at the middle of a two-footed base; misses: the hill
    # silhouette's long side branch, a branch tip outlined like the crown, rpg_01's left twigs)
    assert sum(ok) >= 11, sum(ok)


def test_hand_placed_pins_lie_on_the_outline():
    """R and L are outline points by definition (B may sit inside ground clutter)."""
    import cv2

    for name, ref in load_reference_pins().items():
        a = (data.load(name)[..., 3] >= 0.5).astype(np.uint8)
        cs, _ = cv2.findContours(a, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
        pts = np.vstack([c[:, 0, :] for c in cs]).astype(float)
        height = ref["B"][1] - np.flatnonzero(a.any(axis=1))[0]
        for k in ("R", "L"):
            assert np.hypot(*(pts - ref[k]).T).min() <= 0.035 * height, (name, k)


def test_pins_within_5_percent_of_procedural_truth(synth):
    ok = []
    for t in synth:
        ex = process_exemplar(t.image, t.kind, size=192)
        err = pin_errors(source_pins(ex), {k: np.asarray(v) for k, v in t.pins.items()},
                         t.image[..., 3])
        ok.append(max(err.values()) <= 0.05)
    assert sum(ok) >= 5, dict(zip(SYNTHETIC_KINDS, ok))


def test_leaf_pile_no_longer_becomes_the_trunk():
    t = synthetic_tree("leaf_pile", rng=11, size=192)
    keep = process_exemplar(t.image, "pile", size=192, ground="keep")
    cut = process_exemplar(t.image, "pile", size=192)
    truth = {k: np.asarray(v) for k, v in t.pins.items()}
    e_cut = pin_errors(source_pins(cut), truth, t.image[..., 3])
    e_keep = pin_errors(source_pins(keep), truth, t.image[..., 3])
    assert max(e_cut.values()) <= 0.05
    assert e_keep["B"] > 0.05          # the pile's bottom was taken for the trunk foot
    assert cut.ground is not None and keep.ground is None


# ------------------------------------------------------------------ segmentation
def test_segmentation_on_procedural_masks(synth):
    scores = [segmentation_iou(segment_tree(t.image, rng=0).labels, t.labels)["mean"] for t in synth]
    # measured: 0.921 on these 8 (one palm 0.44: fronds taken for trunk), 0.989 on 16 others
    # (the paper's DeepLabv3+: 0.672 on its photographs)
    assert np.mean(scores) >= 0.9 and sorted(scores)[1] >= 0.9, scores


def test_segmentation_marks_ground_as_not_tree():
    seg = segment_tree(data.load("palm_island"), rng=0)
    assert seg.ground is not None and (seg.labels == 255).sum() == seg.ground.sum() > 0
    assert not (seg.ground & (seg.crown | seg.trunk)).any()


# ------------------------------------------------------------------ variations
@pytest.fixture(scope="module")
def mixed_lib():
    lib = TreeLibrary(size=128)
    for n in ("palm_island", "tree_on_hill", "tree_rpg_13", "palm_silhouette", "tree_rpg_03"):
        lib.add(data.load(n), n)
    for kind, seed in (("leaf_pile", 11), ("palm_outlined", 12), ("grass", 13)):
        lib.add(synthetic_tree(kind, rng=seed, size=192).image, kind)
    return lib


def test_no_ghosting_clean_cutout_and_no_zero_weight_colour(mixed_lib):
    for a, b in itertools.combinations(mixed_lib.names, 2):
        v = make_variation(mixed_lib, [0.5, 0.5], use=[a, b], colour_weights=[1.0, 0.0], rng=0)
        assert soft_alpha_fraction(v.image) == 0.0
        # partial alpha only on the anti-aliased rim (rim_alpha.py): the pixel either side of the edge
        op = v.image[..., 3] >= 0.5
        edge = ndi.binary_dilation(op, np.ones((3, 3), bool)) & ~ndi.binary_erosion(op, np.ones((3, 3), bool))
        assert set(np.unique(v.image[..., 3][~edge])) <= {0.0, 1.0}
        assert foreign_colour_fraction(v.image, [mixed_lib[a].image]) < 0.01, (a, b)


def test_variations_are_one_piece_without_new_holes(mixed_lib):
    for a, b in itertools.combinations(mixed_lib.names, 2):
        v = make_variation(mixed_lib, [0.5, 0.5], use=[a, b], colour_weights=[0.5, 0.5], rng=0)
        own = max(pieces(mixed_lib[a].alpha), pieces(mixed_lib[b].alpha))
        assert pieces(v.image[..., 3]) <= own, (a, b)
        limit = max(exemplar_largest_hole(mixed_lib[a]), exemplar_largest_hole(mixed_lib[b]))
        assert large_holes(v.image[..., 3], limit) == 0, (a, b)


# ------------------------------------------------------------------ billboard clouds
def _busy(rgba):
    """Share of interior pixels whose 5 x 5 neighbourhood spans more than 0.15 in a channel."""
    a = rgba[..., 3] >= 0.5
    rgb = rgba[..., :3]
    span = (ndi.maximum_filter(rgb, size=(5, 5, 1)) - ndi.minimum_filter(rgb, size=(5, 5, 1))).max(axis=2)
    core = ndi.binary_erosion(a, iterations=3)
    return float((span > 0.15)[core].mean())


@pytest.mark.parametrize("kind, seed", [("palm", 3), ("grass", 4), ("palm_outlined", 5),
                                        ("palm_island", None)])
def test_side_views_keep_crown_attached_and_flat_colour_flat(kind, seed):
    image = data.load(kind) if seed is None else synthetic_tree(kind, rng=seed, size=192).image
    c = billboard_cloud(image, params=BillboardParams(max_size=192), rng=0)
    front = _busy(render_cloud(c, 0.0))
    for yaw in (45.0, 90.0):
        r = render_cloud(c, yaw)
        a = r[..., 3] >= 0.5
        lab, _ = ndi.label(a, structure=np.ones((3, 3)))
        assert np.bincount(lab.ravel())[1:].max() >= 0.97 * a.sum(), (kind, yaw)
        # measured before the fix: 0.22-0.32 at 45/90 degrees for front 0.03-0.06;
        # palm_island's trunk broke in two at 90 degrees (largest piece 0.81) before the
        # ground's soft rim left the trunk strips
        assert _busy(r) <= front + 0.12, (kind, yaw, front, _busy(r))


def test_no_more_pieces_than_the_most_broken_up_exemplar():
    # tree_branches_and_roots is 12 pieces at 128 px; warped with colour weights (1, 0)
    # onto a bare tree its thin roots crumbled into 17 (all pairs of the library: 20
    # variations with more pieces than their exemplars before the cap, 0 after).
    lib = TreeLibrary(size=128)
    for n in ("tree_branches_and_roots", "tree_rpg_11", "tree_rpg_12"):
        lib.add(data.load(n), n)
    own = max(pieces(e.alpha) for e in lib)
    for other in ("tree_rpg_11", "tree_rpg_12"):
        v = make_variation(lib, [0.5, 0.5], use=["tree_branches_and_roots", other],
                           colour_weights=[1.0, 0.0], rng=0)
        assert 1 <= pieces(v.image[..., 3]) <= own, other


@pytest.mark.parametrize("kind,seed", [("broadleaf", 1), ("fruit", 3), ("broadleaf", 6)])
def test_leaf_pile_narrower_than_the_crown_is_ground(kind, seed):
    # A pile narrower than the crown's 45 % is one band with the trunk; its tapering
    # tail (narrower than the trunk) is no trunk: the foot ends the trunk's narrow run.
    from branchnb.trees.drawn import drawn_tree

    img = drawn_tree(kind, pile=True, rng=seed, size=192)
    split = split_ground(img)
    assert split.has_ground
    y_f = int(split.foot[1])
    assert not split.tree[y_f + 2:].any()
    width = split.tree[y_f - 10:y_f + 1].sum(axis=1).max()
    assert width <= 1.6 * split.trunk_width + 4
    cut = split.cut(img)
    assert cut[y_f + 3:, :, 3].max() == 0.0        # no faint rim of the pile either
