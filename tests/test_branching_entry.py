"""Structures entering from the frame (issue 23, branching72): a root system hanging from a crown at the
top edge is traced from the frame, grows down from it, and its image has no glow dots."""
import numpy as np
import pytest

from branchnb.branching import extract_structure, fit_model, synthesize_image, synthesize_structure
from branchnb.branching._entry_check import _inward_share, entry_example, glow_dots
from branchnb.branching.tropism import _fit_tropism
from branchnb.core.structure import Branch, Structure


@pytest.mark.parametrize("size, seed", [(256, 0), (512, 0)])
def test_root_system_traced_from_its_crown_at_the_frame(size, seed):
    # main: the traced root 0.13 x 256 px and 0.13 x 512 px from the entry, inside the crown
    img, _truth, entry, _side, _bright = entry_example("roots", size, seed)
    s = extract_structure(img)
    roots = [b for b in s.branches if b.parent is None]
    d = min(float(np.hypot(*(np.asarray(b.points[0]) - entry))) for b in roots)
    assert d <= 0.03 * size, (d, [b.points[0] for b in roots])
    assert min(float(b.points[0][1]) for b in roots) <= 2.0


def test_root_system_grows_down_from_the_top():
    # main 512 px seed 0: output root 0.21 x 512 px from the top, 58 % of its length going down
    # against the example's 92 %
    img, _truth, _entry, _side, _bright = entry_example("roots", 512, 0)
    s = extract_structure(img)
    m = fit_model(s)
    assert m.tropism is not None
    shares = []
    for rng in (0, 1):
        t = synthesize_structure(m, rng=rng).structure
        roots = [b for b in t.branches if b.parent is None]
        assert max(float(b.points[0][1]) for b in roots) <= 0.05 * 512
        shares.append(_inward_share(t, "top"))
    assert min(shares) >= 0.8 * _inward_share(s, "top"), shares


def test_tropism_only_for_a_structure_entering_from_one_side():
    down = Structure([Branch([(50, 1), (52, 40), (50, 90)], 2.0),
                      Branch([(52, 40), (70, 80)], 1.0, parent=0, parent_vertex=1)], image_shape=(100, 100))
    w = _fit_tropism(down, [0])
    assert w is not None and w.shape == (16,) and abs(float(w.mean()) - 1.0) < 0.1
    assert int(np.argmax(w)) in (11, 12)                  # bearing +90 deg (down the image)
    assert _fit_tropism(down, [5]) is None               # a root inside
    assert _fit_tropism(down, [0, 2]) is None            # roots on two sides
    sideways = Structure([Branch([(1, 50), (30, 52), (60, 49), (90, 51)], 2.0)], image_shape=(100, 100))
    assert _fit_tropism(sideways, [0]) is None           # lines run along the entry side, not away


def test_root_system_image_has_no_glow_dots():
    # main: 12 glow dots (5-8 px halos up to 0.2 brighter than the lines) at junctions and the crown
    img, truth, _entry, _side, bright = entry_example("roots", 256, 0)
    s = extract_structure(img)
    t = synthesize_structure(fit_model(s), rng=0).structure
    out = np.asarray(synthesize_image(img, s, t, rng=0).image)
    assert glow_dots(out, np.median(img[truth > 0], axis=0), bright) == 0
    flat = img.reshape(-1, 3)
    assert np.all(out[..., :3] <= flat.max(0) + 1e-6) and np.all(out[..., :3] >= flat.min(0) - 1e-6)
