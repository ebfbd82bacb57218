"""An even silhouette outline round flat-art mixes (issue 24: 1 px upper left, 3-4 px lower right)."""

import numpy as np
import pytest

from branchnb.trees.drawn import drawn_tree
from branchnb.trees.outline import even_outline
from branchnb.trees.quality import crossfade_fraction, outline_width_spread, stray_ink
from branchnb.trees.variations import TreeLibrary, make_variation

S = 256


def _disc(size=64, r=26):
    yy, xx = np.mgrid[:size, :size]
    d = np.hypot(yy - size / 2, xx - size / 2)
    img = np.zeros((size, size, 4), np.float32)
    img[d <= r] = (0.0, 0.0, 0.0, 1.0)
    # the stroke drifts: 1 px on the left, 5 px on the right (a warped outline)
    ring = 1.0 + 4.0 * np.clip((xx - size / 2 + r) / (2 * r), 0, 1)
    img[d <= r - ring, :3] = (0.3, 0.7, 0.2)
    return img, yy, xx, d


def test_even_outline_evens_a_drifting_stroke():
    img, _, _, _ = _disc()
    q10, _, q90 = outline_width_spread(img, (0, 0, 0))
    assert q90 / q10 > 3.0
    out = even_outline(img, (0, 0, 0), 2)
    q10, q50, q90 = outline_width_spread(out, (0, 0, 0))
    assert 1.9 <= q10 and q90 <= 3.2 and q90 / q10 <= 1.6
    assert np.array_equal(out[..., 3], img[..., 3])


def test_even_outline_keeps_fruit_rings_and_dark_fills():
    img, yy, xx, d = _disc()
    img[d <= 26, :3] = 0.0
    img[d <= 24, :3] = (0.3, 0.7, 0.2)
    fruit = np.hypot(yy - 32, xx - 50) <= 5                     # a fruit ring beside the rim, fill between
    img[fruit, :3] = 0.0
    img[np.hypot(yy - 32, xx - 50) <= 3.5, :3] = (1.0, 0.5, 0.0)
    trunk = (xx >= 28) & (xx < 36) & (yy >= 40)                 # a dark trunk, as dark as the ink
    img[trunk & (d <= 26), :3] = (0.05, 0.03, 0.02)
    out = even_outline(img, (0, 0, 0), 2)
    assert np.allclose(out[fruit], img[fruit])
    assert np.allclose(out[trunk & (d <= 22)], img[trunk & (d <= 22)])
    assert stray_ink(out) == stray_ink(img)


def test_even_outline_bad_input():
    img, _, _, _ = _disc()
    with pytest.raises(ValueError, match="ink"):
        even_outline(img, (0, 0), 2)
    with pytest.raises(ValueError, match="width"):
        even_outline(img, (0, 0, 0), 0)


@pytest.fixture(scope="module")
def lib():
    lib = TreeLibrary(size=S)
    for kind, seed in (("palm", 21), ("broadleaf", 22), ("fruit", 23)):
        lib.add(drawn_tree(kind, rng=seed, size=2 * S), f"{kind}{seed}")
    return lib


def test_drawn_mixes_have_an_even_outline(lib):
    # Before: q90 / q10 up to 2.5 at 256 px on these trees (the sources 1.5-1.8); now within the
    # sources' spread, and the outline as wide as theirs (median).
    src = [outline_width_spread(e.image) for e in lib.exemplars]
    worst = max(q[2] / q[0] for q in src)
    gen = np.random.default_rng(0)
    for _ in range(3):
        v = make_variation(lib, rng=gen)
        q10, q50, q90 = outline_width_spread(v.image)
        assert q90 / q10 <= worst + 0.05, (q10, q90, src)
        assert min(q[1] for q in src) - 0.5 <= q50 <= max(q[1] for q in src) + 0.5
        assert crossfade_fraction(v.image, [lib[n].image for n in v.names]) <= 0.03
