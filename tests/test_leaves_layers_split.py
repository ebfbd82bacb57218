"""layers.py and prepared.py split by step (issue 22): old import paths, and the speed pass's shortcuts
give the values of the code they replaced."""

import numpy as np
import pytest

from branchnb.leaves import (
    Layer,
    LayerSet,
    layers,
    layers_colours,
    layers_cuts,
    layers_lines,
    layers_scribbles,
    leaf_family,
    prepared,
    prepared_fill,
    prepared_layers,
    prepared_petioles,
    simulate_scribbles,
)
from branchnb.leaves.layers import grow_layers

MOVED = {
    layers_scribbles: ("scribble_mask", "simulate_scribbles", "_check_scribbles", "_on_layer", "_RING_SPLIT",
                       "MAX_SCRIBBLES"),
    layers_colours: ("_local_contrast", "_kmeans", "_nearest", "_nearest_nb"),
    layers_cuts: ("_superpixel_graph", "_beta", "_refine", "_HARD", "_LINE_PENALTY"),
    layers_lines: ("_on_line_pins", "_off_lines", "_OFF_LINE", "_OFF_LINE_REACH", "_OFF_LINE_SIDES", "_NARROW_LONG",
                   "_ON_LINE", "_ON_LINE_ABOVE", "_ON_LINE_KEEP", "_DENSE_LINES"),
}
MOVED_PREPARED = {
    prepared_fill: ("_bleed", "_stored", "_completed", "_without_knobs", "_smooth_fill", "_soft_rim", "_SOFT_RIM"),
    prepared_layers: ("_removed_extension", "_without_specks", "_refilled_rims", "_leftover_layer", "_completeness",
                      "_SPECK_SIDE"),
}


@pytest.mark.parametrize("old, moved", [(layers, MOVED), (prepared, MOVED_PREPARED)])
def test_every_moved_name_is_importable_from_its_old_module(old, moved):
    for mod, names in moved.items():
        for name in names:
            assert getattr(old, name) is getattr(mod, name), (old.__name__, name)
    if old is prepared:
        assert issubclass(prepared._Prepared, prepared_petioles._PetioleSteps)
        for meth in ("_prepare_petioles", "petiole_layer", "_lamina_axis"):
            assert hasattr(prepared._Prepared, meth)


def _refine_inputs(seed, line):
    rng = np.random.default_rng(seed)
    h, w = 70, 90
    yy, xx = np.mgrid[:h, :w]
    blade = ((yy - 35) / 30.0) ** 2 + ((xx - 45) / 40.0) ** 2 < 1
    feat = (0.4 + 0.05 * rng.standard_normal((h, w, 3))).astype(np.float32)
    vein = blade & (np.abs(yy - 35) <= 1)
    feat[vein] -= 0.2
    mask = vein | (blade & (np.abs(yy - 35) <= 3) & (xx % 7 == 0))
    fg_px = vein & (xx > 30) & (xx < 50)
    bg_px = blade & (np.abs(yy - 35) > 12) & (xx % 11 == 0)
    fg_c = feat[fg_px][:4]
    bg_c = feat[bg_px][:6]
    prior = 0.3 * rng.random((h, w))
    strength = np.where(vein, 0.9, 0.05 * rng.random((h, w))).astype(np.float32) if line else None
    return mask, feat, blade, fg_px, bg_px, fg_c, bg_c, prior, strength


@pytest.mark.parametrize("seed, line", [(0, False), (1, True), (2, True)])
def test_refine_with_the_callers_distances_gives_the_same_cut(seed, line):
    mask, feat, blade, fg_px, bg_px, fg_c, bg_c, prior, strength = _refine_inputs(seed, line)
    own = layers_cuts._refine(mask, feat, blade, fg_px, bg_px, fg_c, bg_c, prior, 1.0, strength, 1.0)
    d = (layers_colours._nearest(feat[blade], fg_c), layers_colours._nearest(feat[blade], bg_c))
    given = layers_cuts._refine(mask, feat, blade, fg_px, bg_px, fg_c, bg_c, prior, 1.0, strength, 1.0,
                                distances=d)
    assert own.sum() > 20 and not own.all()  # a real cut, not an empty or full one
    np.testing.assert_array_equal(given, own)


def test_superpixels_are_numbered_one_to_n_on_the_blade():
    leaf = leaf_family(2, size=160, rng=4)[0]
    ls = LayerSet([Layer("veins", "#d62728", 0, simulate_scribbles(leaf.layers["veins"], 8, length=20, rng=0))])
    r = grow_layers(leaf.image, leaf.blade, ls)
    sp = r.superpixels
    labels = np.unique(sp[r.blade])
    np.testing.assert_array_equal(labels, np.arange(1, len(labels) + 1))
    assert not sp[~r.blade].any()
    assert len(labels) > 0.5 * r.blade.sum() / 25  # about one per 5 x 5 px of blade (SnapParams default)
