"""Training layers: data model, JSON, bad input, lazy snapping on procedural leaves."""

import json

import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from branchnb.core.metrics import iou
from branchnb.leaves import leaf_family
from branchnb.leaves.layers import (
    Layer,
    LayerSet,
    Scribble,
    grow_layers,
    scribble_mask,
    simulate_scribbles,
)


def _strict(text):
    def bad(c):
        raise ValueError(f"non-strict JSON constant {c}")
    return json.loads(text, parse_constant=bad)


def test_layer_set_editing_and_json_round_trip():
    ls = LayerSet([Layer("veins", "#ff0000", 0), Layer("spots", "#0000ff", 1)])
    ls.add_scribble("veins", [(1, 2), (5, 6)], radius=1.5)
    ls.add_scribble("spots", [(3, 3)])
    ls.add_scribble("blade", [(9, 9), (12, 9)])
    ls.add("holes", "#00ff00")
    ls.move("holes", 0)
    assert ls.names() == ["holes", "veins", "spots"]
    ls.remove("veins")
    assert ls.names() == ["holes", "spots"] and [x.order for x in ls.ordered()] == [0, 1]
    text = ls.to_json()
    back = LayerSet.from_json(text)
    assert _strict(text) == back.to_dict() == ls.to_dict()
    assert back.get("spots").scribbles[0].points.tolist() == [[3.0, 3.0]]
    assert back.background[0].radius == 2.0


def test_bad_layer_definitions():
    with pytest.raises(ValueError, match="colour"):
        Layer("veins", "red")
    with pytest.raises(ValueError, match="reserved"):
        Layer("blade")
    with pytest.raises(ValueError, match="unique"):
        LayerSet([Layer("a"), Layer("a")])
    ls = LayerSet([Layer("veins")])
    with pytest.raises(ValueError, match="'spots' is not a layer"):
        ls.add_scribble("spots", [(1, 1), (2, 2)])
    with pytest.raises(ValueError, match="radius"):
        Scribble([(0, 0)], radius=0)
    with pytest.raises(ValueError, match="finite"):
        Scribble([(0, np.nan)])


@pytest.fixture(scope="module")
def leaf():
    return leaf_family(1, size=512, rng=3)[0]


def test_grow_layers_bad_input(leaf):
    blade = leaf.blade
    with pytest.raises(ValueError, match="no layers"):
        grow_layers(leaf.image, blade, LayerSet())
    with pytest.raises(ValueError, match="'veins' has no scribbles"):
        grow_layers(leaf.image, blade, LayerSet([Layer("veins")]))
    ls = LayerSet([Layer("veins", scribbles=[Scribble([(2, 2), (10, 2)])])])  # the corner is background
    with pytest.raises(ValueError, match=r"layers\['veins'\]\.scribbles\[0\] lies outside the leaf"):
        grow_layers(leaf.image, blade, ls)
    ls = LayerSet([Layer("veins", scribbles=[Scribble([(2, 2), (900, 2)])])])
    with pytest.raises(ValueError, match="leaves the image"):
        grow_layers(leaf.image, blade, ls)
    with pytest.raises(ValueError, match="blade has shape"):
        grow_layers(leaf.image, blade[1:], LayerSet([Layer("veins", scribbles=[[(1, 1)]])]))
    with pytest.raises(TypeError, match="layer_set"):
        grow_layers(leaf.image, blade, {"veins": []})


@settings(max_examples=25, deadline=None)
@given(st.lists(st.tuples(st.floats(-50, 80, allow_nan=False), st.floats(-50, 80, allow_nan=False)),
                min_size=1, max_size=5))
def test_any_scribble_is_grown_or_rejected_cleanly(points):
    img = np.full((32, 32, 3), (0.3, 0.6, 0.2), np.float32)
    img[:, 14:17] = (0.8, 0.8, 0.4)
    blade = np.zeros((32, 32), bool)
    blade[4:28, 4:28] = True
    ls = LayerSet([Layer("veins", scribbles=[Scribble(points, 1.0)])])
    try:
        r = grow_layers(img, blade, ls)
    except ValueError as exc:
        assert "scribbles[0]" in str(exc)
    else:
        assert r.masks["veins"].dtype == bool and not (r.masks["veins"] & ~blade).any()


def test_simulated_scribbles_stay_on_their_layer(leaf):
    for name in ("veins", "spots"):
        ss = simulate_scribbles(leaf.layers[name], 12, length=20, rng=0)
        assert len(ss) == 12
        m = scribble_mask(ss, leaf.blade.shape)
        assert (m & leaf.layers[name]).sum() >= 0.9 * m.sum()


def test_lazy_snapping_grows_short_scribbles_into_the_layers(leaf):
    """12 short scribbles per layer; IoU with the ground truth (measured 0.56-0.89 veins, 0.94-0.99 spots
    at 512 px over four seeds)."""
    ls = LayerSet([Layer("veins", "#ff0000", 0, simulate_scribbles(leaf.layers["veins"], 12, length=30, rng=1)),
                   Layer("spots", "#0000ff", 1, simulate_scribbles(leaf.layers["spots"], 12, length=12, rng=1))])
    r = grow_layers(leaf.image, leaf.blade, ls)
    assert iou(r.masks["spots"], leaf.layers["spots"]) >= 0.85
    assert iou(r.masks["veins"], leaf.layers["veins"]) >= 0.5
    assert not (r.masks["veins"] & r.masks["spots"]).any()
    assert np.array_equal(r.background, leaf.blade & ~r.masks["veins"] & ~r.masks["spots"])
    # The scribbles alone cover a small part of what they grow into.
    sm = scribble_mask(ls.get("veins").scribbles, leaf.blade.shape)
    assert r.masks["veins"].sum() > 3 * (sm & leaf.blade).sum()


def _grass_strip(h=100, w=240, light=True, rng=0):
    """A streaked grass blade lit from one side: a 5-px midrib and 1-px veins every 10 px, pale or dark.

    Radius-1 scribbles on the midrib and three thin veins, over a third of their length.
    """
    import cv2
    rng = np.random.default_rng(rng)
    streaks = cv2.GaussianBlur(rng.standard_normal((h, w)).astype(np.float32), (0, 0), sigmaX=8, sigmaY=0.7)
    shade = 1 + 0.08 * np.linspace(-1, 1, w, dtype=np.float32)[None]
    grey = shade * (1 + 0.12 * streaks) + 0.02 * rng.standard_normal((h, w)).astype(np.float32)
    img = np.array([0.42, 0.52, 0.33], np.float32) * grey[..., None]
    veins = np.zeros((h, w), bool)
    mid = h // 2
    veins[mid - 2:mid + 3] = True
    thin = [r for r in range(mid % 10 + 5, h - 4, 10) if abs(r - mid) > 6]
    veins[thin] = True
    sign = 1.0 if light else -1.0
    img[mid - 2:mid + 3] += sign * np.array([0.2, 0.2, 0.1], np.float32)
    img[thin] += sign * np.array([0.08, 0.08, 0.05], np.float32)
    img = cv2.GaussianBlur(np.clip(img, 0, 1), (0, 0), 0.6)
    blade = np.zeros((h, w), bool)
    blade[3:h - 3, 3:w - 3] = True
    ls = LayerSet([Layer("veins")])
    for r in [mid] + thin[1:4]:
        ls.add_scribble("veins", [(80, r), (160, r)], radius=1)
    return img, blade, veins & blade, ls


@pytest.mark.parametrize("light", [True, False])
def test_thin_parallel_veins_grow_at_their_own_width(light):
    """Issue 22: scribbles on a grass blade's 5-px midrib and 1-px veins grew 8-18 px blocks
    around the midrib and dashes of the thin veins (colour alone: IoU 0.15-0.41 over three seeds,
    pale and dark). Thin line layers get a ridge term and no superpixel prior: IoU 0.72-0.79,
    the midrib 5 px wide."""
    from branchnb.leaves.layers import SnapParams
    img, blade, veins, ls = _grass_strip(light=light, rng=1)
    grown = grow_layers(img, blade, ls).masks["veins"]
    assert iou(grown, veins) > 0.65
    mid = img.shape[0] // 2
    assert grown[mid - 10:mid + 11, 10:-10].sum(0).max() <= 7  # no block beside the midrib
    assert 0.7 * veins.sum() < grown.sum() < 1.3 * veins.sum()
    # The colour model alone (line_weight=0, lazy snapping as published) misses them.
    plain = grow_layers(img, blade, ls, SnapParams(line_weight=0.0)).masks["veins"]
    assert iou(plain, veins) < 0.45


def test_dense_parallel_veins_grow_as_lines():
    """Pale parallel veins covering a third of a grass-type strip (procedural strips, 35-37 %): ten
    short scribbles grew one vein or a block of blade (vein IoU 0.21-0.26, precision 0.35-0.59); the
    ridge strength of plain blade is now taken below the veins' share (0.50 / 0.42, precision
    0.80 / 0.58)."""
    from branchnb.core.metrics import iou
    from branchnb.leaves import Layer, LayerSet, grow_layers, simulate_scribbles
    from branchnb.leaves.procedural_strips import strip_family

    for seed in (0, 1):
        leaf = strip_family(1, size=192, rng=seed)[0]
        truth = leaf.layers["veins"]
        ls = LayerSet([Layer("veins", "#d62728", 0, simulate_scribbles(truth, 10, length=20, radius=1.0, rng=0))])
        grown = grow_layers(leaf.image[..., :3], leaf.blade, ls).masks["veins"]
        assert iou(grown, truth) > 0.38
        assert (grown & truth).sum() / grown.sum() > 0.5
