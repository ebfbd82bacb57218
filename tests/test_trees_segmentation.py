"""Crown/trunk segmentation of tree images (branchnb.trees.segmentation)."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb import data
from branchnb.trees import (
    evaluate_reference,
    load_reference_masks,
    load_reference_scribbles,
    reference_from_scribbles,
    segment_tree,
    segmentation_iou,
)
from branchnb.trees.segmentation import (
    CROWN,
    IGNORE,
    TRUNK,
    SegmentParams,
    mean_iou,
    rasterize_scribbles,
)

# Measured: 0.986 mean IoU of the automatic segmenter over the 23 hand-corrected
# reference masks (the paper's network: 0.672 on its own data set).
MIOU_THRESHOLD = 0.95


def _disc_tree(h=96, w=80, trunk=True):
    """Green disc crown on a brown stem, RGBA."""
    img = np.zeros((h, w, 4), np.float32)
    yy, xx = np.mgrid[:h, :w]
    crown = (xx - w / 2) ** 2 + (yy - 34) ** 2 < 28 ** 2
    img[crown] = (0.15, 0.6, 0.15, 1.0)
    if trunk:
        stem = (np.abs(xx - w / 2) < 5) & (yy >= 55) & (yy < h - 4)
        img[stem & ~crown] = (0.45, 0.28, 0.1, 1.0)
    return img


def test_reference_masks_cover_every_sample_tree():
    masks = load_reference_masks()
    assert sorted(masks) == data.names("trees")
    for name, m in masks.items():
        img = data.load(name)
        assert m.shape == img.shape[:2]
        assert set(np.unique(m).tolist()) <= {0, CROWN, TRUNK, IGNORE}
        # Labels exactly on the opaque pixels.
        assert np.array_equal(m > 0, img[:, :, 3] >= 0.5)


def test_reference_mask_files_have_distinct_names_and_licence_line():
    readme = (data.DATA_DIR / "README.md").read_text()
    for name in load_reference_masks():
        assert f"{name}_mask.png" in readme
        assert data.path(f"{name}_mask").name == f"{name}_mask.png"


def test_automatic_segmenter_mean_iou_on_reference_masks():
    scores = evaluate_reference()
    miou = scores.pop("mIoU")["mean"]
    assert len(scores) == len(data.names("trees"))
    assert miou >= MIOU_THRESHOLD, miou
    assert miou == pytest.approx(np.mean([v["mean"] for v in scores.values()]))
    # The palm fronds and the photographed crown are the hardest; no image fails outright.
    # tree_branches_and_roots: its reference calls the roots below the grass line trunk,
    # the ground cut (split_ground) calls grass and roots ground (measured: 0.70).
    assert min(v["mean"] for n, v in scores.items() if n != "tree_branches_and_roots") > 0.8
    assert scores["tree_branches_and_roots"]["mean"] > 0.6
    # The images whose automatic result the labeller had to correct (measured: 0.954).
    corrected = [n for n in scores if any(d["label"] != "ignore" for d in load_reference_scribbles(n))]
    assert len(corrected) == 7
    assert np.mean([scores[n]["mean"] for n in corrected if n != "tree_branches_and_roots"]) >= 0.92


def test_mean_iou_of_lists():
    a = np.array([[1, 2]])
    assert mean_iou([a, a], [a, np.array([[1, 1]])]) == pytest.approx((1.0 + 0.25) / 2)


@pytest.mark.parametrize("name", ["tree_rpg_13", "arbre_modern"])
def test_reference_rebuilt_from_stored_scribbles(name):
    stored = load_reference_masks(name)[name]
    rebuilt = reference_from_scribbles(name)
    assert np.mean(rebuilt == stored) > 0.995
    if name == "arbre_modern":       # the ground patch is ignored
        assert (stored == IGNORE).sum() > 1000


def test_scribbles_change_labels_where_drawn():
    img = data.load("tree_rpg_01")
    auto = segment_tree(img, rng=0)
    # A trunk stroke across the crown and a crown stroke on the trunk base.
    trunk_line = np.array([[120.0, 150.0], [280.0, 150.0]])
    crown_line = np.array([[215.0, 470.0], [240.0, 470.0]])
    assert auto.crown[150, 130:270].all() and auto.trunk[470, 218:238].all()
    seg = segment_tree(img, scribbles=[("trunk", trunk_line), {"label": "crown", "points": crown_line}], rng=0)
    assert seg.trunk[150, 130:270].all()
    assert seg.crown[470, 218:238].all()
    # Seeds record the scribbles; far from them the result barely moves.
    assert (seg.seeds[150, 130:270] == TRUNK).all()
    far = np.zeros(img.shape[:2], bool)
    far[250:, :] = True
    far[440:, :] = False
    same = (seg.labels == auto.labels)[far & (img[:, :, 3] >= 0.5)]
    assert same.mean() > 0.9


def test_scribbles_as_label_mask_and_as_canvas_shapes():
    from branchnb.widgets.model import Shape

    img = _disc_tree()
    mask = np.zeros(img.shape[:2], np.uint8)
    mask[30:38, 30:50] = TRUNK
    a = segment_tree(img, scribbles=mask)
    assert a.trunk[30:38, 30:50].all()
    shape = Shape("scribble", np.array([[30.0, 34.0], [50.0, 34.0]]), np.array([3.0, 3.0]), "trunk")
    b = segment_tree(img, scribbles=[shape])
    assert b.trunk[33:36, 32:48].all()
    lab = rasterize_scribbles([shape], img.shape[:2])
    assert lab[34, 40] == TRUNK and lab[20, 40] == 0


def test_input_of_any_size_keeps_its_shape():
    img = data.load("tree_rpg_05")
    big = segment_tree(img, params=SegmentParams(work_size=128), rng=0)
    full = segment_tree(img, params=SegmentParams(work_size=1024), rng=0)
    assert big.labels.shape == full.labels.shape == img.shape[:2]
    assert segmentation_iou(big.labels, full.labels)["mean"] > 0.8
    assert not (big.crown & big.trunk).any()
    assert np.array_equal(big.crown | big.trunk, img[:, :, 3] >= 0.5)


def test_disc_tree_and_no_trunk():
    seg = segment_tree(_disc_tree())
    assert seg.has_trunk and seg.trunk[80, 40] and seg.crown[34, 40]
    no_trunk = segment_tree(_disc_tree(trunk=False))
    assert not no_trunk.has_trunk and no_trunk.crown.sum() > 2000


def test_bare_wood_is_all_trunk():
    img = np.zeros((80, 80, 4), np.float32)
    img[10:75, 35:45] = (0.4, 0.25, 0.1, 1.0)
    seg = segment_tree(img)
    assert seg.trunk.sum() == 650 and not seg.crown.any()


def test_iou_against_small_reference():
    pred = np.array([[1, 1, 2, 0], [2, 2, 1, 255]])
    ref = np.array([[1, 2, 2, 0], [2, 1, 1, 255]])
    out = segmentation_iou(pred, ref)
    assert out["crown"] == pytest.approx(2 / 4)       # {00, 12} over {00, 01, 11, 12}
    assert out["trunk"] == pytest.approx(2 / 4)       # {02, 10} over {01, 02, 10, 11}
    assert out["mean"] == pytest.approx(0.5)
    ign = segmentation_iou(np.array([[1, 2]]), np.array([[1, IGNORE]]))
    assert ign["crown"] == 1.0 and np.isnan(ign["trunk"]) and ign["mean"] == 1.0


def test_repr_png():
    png = segment_tree(_disc_tree())._repr_png_()
    assert png[:8] == b"\x89PNG\r\n\x1a\n"


@pytest.mark.parametrize(
    "image, match",
    [
        (np.ones((20, 20, 3), np.float32), "must be RGBA"),
        (np.zeros((20, 20, 4), np.float32), "fully transparent"),
        (np.ones((20, 20, 4), np.float32), "fully opaque"),
    ],
)
def test_bad_images(image, match):
    with pytest.raises(ValueError, match=match):
        segment_tree(image)


def test_bad_scribbles():
    img = _disc_tree()
    with pytest.raises(ValueError, match="label 'leaf'"):
        segment_tree(img, scribbles=[("leaf", [(1, 1), (5, 5)])])
    with pytest.raises(ValueError, match=r"points must be an \(N, 2\)"):
        segment_tree(img, scribbles=[("trunk", [1, 2, 3])])
    with pytest.raises(ValueError, match="scribbles mask has shape"):
        segment_tree(img, scribbles=np.zeros((5, 5), np.uint8))
    with pytest.raises(TypeError, match="scribbles must be"):
        segment_tree(img, scribbles="trunk")
    with pytest.raises(ValueError, match="no stored scribbles"):
        load_reference_scribbles("astronaut")
    with pytest.raises(ValueError, match="no reference mask"):
        load_reference_masks(["astronaut"])


def test_segmentation_on_masks_made_without_the_segmenter():
    """mIoU on trunk polygons placed by eye on grid renders (data/trees_masks_independent)."""
    from branchnb.trees.mask_reference import evaluate_independent, load_independent_masks

    refs = load_independent_masks()
    assert len(refs) >= 6
    for ref in refs.values():
        assert (ref == 1).any() and (ref == 2).any()
    scores = evaluate_independent()
    # measured: mean 0.94 over 6 (lowest tree_rpg_05, 0.88: the trunk top under the crown's
    # brown outline band); the paper's DeepLabv3+: 0.672 on its photographs
    assert scores["mean"] >= 0.9, scores
    assert min(v["mean"] for k, v in scores.items() if k != "mean") >= 0.8, scores
