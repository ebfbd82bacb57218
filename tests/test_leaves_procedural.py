"""The procedural leaf family: ground truth that registration and induction are measured on."""

import numpy as np
import pytest

from branchnb.core.metrics import iou
from branchnb.leaves import KINDS, leaf_family, procedural_leaf


@pytest.mark.parametrize("kind", sorted(KINDS))
def test_leaf_layers_and_keypoints(kind):
    leaf = procedural_leaf(kind, size=160, rng=3)
    img = leaf.image
    assert img.shape == (160, 160, 4) and img.dtype == np.float32
    assert 0.0 <= img.min() and img.max() <= 1.0
    alpha = img[..., 3]
    # Transparent background, opaque blade.
    assert alpha[0, 0] == 0.0 and leaf.blade.mean() > 0.1
    assert np.array_equal(leaf.blade, alpha > 0.5)
    veins, spots = leaf.layers["veins"], leaf.layers["spots"]
    assert veins.any() and not (veins & ~leaf.blade).any()
    assert not (spots & ~leaf.blade).any() and not (veins & spots).any()
    # Keypoints are material points inside the blade (relative radius < 0.95).
    kx, ky = np.round(leaf.keypoints).astype(int).T
    assert leaf.blade[ky, kx].mean() > 0.95
    white = leaf.on_white()
    assert white.shape == (160, 160, 3) and np.allclose(white[0, 0], 1.0)


def test_same_seed_same_leaf_and_different_seeds_differ():
    a = procedural_leaf(size=96, rng=11)
    b = procedural_leaf(size=96, rng=11)
    c = procedural_leaf(size=96, rng=12)
    assert np.array_equal(a.image, b.image) and np.array_equal(a.keypoints, b.keypoints)
    assert iou(a.blade, c.blade) < 0.95
    fam1 = leaf_family(3, size=64, rng=5)
    fam2 = leaf_family(3, size=64, rng=5)
    assert [f.seed for f in fam1] == [f.seed for f in fam2]


def test_keypoints_are_the_same_material_point():
    # Without shape variation, rotation or scale variation two leaves have
    # identical outlines and keypoints (only venation, spots, texture differ).
    fam = leaf_family(2, size=128, variation=0.0, rotation=0.0, scale=(0.8, 0.8), rng=2)
    assert np.allclose(fam[0].keypoints, fam[1].keypoints)
    assert iou(fam[0].blade, fam[1].blade) > 0.97
    assert not np.array_equal(fam[0].layers["veins"], fam[1].layers["veins"])
    # With variation, keypoints move with the blade: a rotation of the leaf
    # rotates its keypoints about the canvas.
    var = leaf_family(4, size=128, rng=2)
    spread = np.std([v.keypoints for v in var], axis=0).mean()
    assert spread > 2.0


def test_one_megapixel_leaf():
    leaf = procedural_leaf("lobed", size=1000, rng=0)
    assert leaf.image.shape == (1000, 1000, 4)
    # Veins widen towards the base: the widest vertex is far wider than the tips.
    widths = np.concatenate(leaf.vein_widths)
    assert widths.max() > 4 * np.median(widths)


@pytest.mark.parametrize("kwargs, match", [
    ({"kind": "oak"}, "kind"),
    ({"size": 8}, "size"),
    ({"size": 64.5}, "size"),
    ({"palette": "blue"}, "palette"),
    ({"variation": -1}, "variation"),
    ({"rotation": 400}, "rotation"),
    ({"scale": (0.9, 0.5)}, "scale"),
    ({"n_keypoints": 0}, "n_keypoints"),
    ({"n_spots": (3, 1)}, "n_spots"),
])
def test_bad_arguments(kwargs, match):
    with pytest.raises(ValueError, match=match):
        procedural_leaf(**kwargs)
    with pytest.raises(TypeError, match="rng"):
        procedural_leaf(size=64, rng="seed")
    with pytest.raises(ValueError, match="n must"):
        leaf_family(0)
