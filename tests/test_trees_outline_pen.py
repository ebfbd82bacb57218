"""Mixes of outlined trees keep the sources' pen (issue 24): as wide as theirs, on crown and trunk.

Before, the silhouette of a mix was inked as a band of whole pixels ``width`` deep in chessboard
distance, ``width`` an integer read off one source: a 3-px anti-aliased pen came out 10 % thinner
on average, the trunk's outline a pixel thinner than the sources' (3.0-3.2 px against 4.0).
"""

import numpy as np

from branchnb.trees._measure_pen import pen_tree, pen_widths
from branchnb.trees.outline_pen import _pen_outline, _pen_profile, _pen_width
from branchnb.trees.variations import TreeLibrary


def _ring(size=80, r=30, pen=3.0, drift=0.0):
    """A green disc stroked in black, ``pen`` px wide (``drift``: wider to the right by that much)."""
    yy, xx = np.mgrid[:size, :size]
    d = r - np.hypot(yy - size / 2 + 0.5, xx - size / 2 + 0.5)   # depth inside the rim
    img = np.zeros((size, size, 4), np.float32)
    inside = d > -0.5
    w = pen + drift * np.clip((xx - size / 2 + r) / (2 * r), 0, 1)
    cov = np.clip(w - d, 0, 1)[..., None]                       # an anti-aliased inner edge
    img[..., :3] = cov * 0.0 + (1 - cov) * np.array([0.3, 0.7, 0.2])
    img[..., 3] = inside
    img[~inside] = 0
    return img


def test_pen_profile_reads_the_pen_width():
    widths = []
    for pen in (1.0, 2.0, 3.0, 5.0):
        prof = _pen_profile(_ring(pen=pen), np.zeros(3), max(1, int(pen)))
        grid = 1 + 0.5 * np.arange(len(prof))
        # full ink to the pen's depth, none a pixel beyond it
        assert prof[grid <= max(pen - 0.5, 1.0)].min() >= 0.9, (pen, prof)
        assert prof[grid >= pen + 1.5].max() <= 0.1, (pen, prof)
        widths.append(_pen_width(prof))
    assert np.allclose(np.diff(widths), (1, 1, 2), atol=0.6), widths


def test_draw_pen_evens_a_drifting_stroke():
    prof = _pen_profile(_ring(pen=3.0), np.zeros(3), 3)
    out = _pen_outline(_ring(pen=1.0, drift=4.0), np.zeros(3), 3, prof)
    w, _ = pen_widths(out, np.zeros(3))
    ref, _ = pen_widths(_ring(pen=3.0), np.zeros(3))
    assert abs(np.median(w) - np.median(ref)) <= 0.75
    w0, _ = pen_widths(_ring(pen=1.0, drift=4.0), np.zeros(3))
    assert np.quantile(w0, 0.9) / np.quantile(w0, 0.1) >= 4.0
    assert np.quantile(w, 0.9) / np.quantile(w, 0.1) <= np.quantile(ref, 0.9) / np.quantile(ref, 0.1) + 0.15
    assert np.array_equal(out[..., 3], _ring()[..., 3])      # the silhouette stays


def test_mixes_keep_the_sources_pen_on_crown_and_trunk():
    # main: mean 3.58 / 3.68 px where the sources' (by colour weight) are 3.98 / 3.95; the
    # trunk's median 3.16 / 3.0 px against 4.0-4.5 px on every source
    lib = TreeLibrary(size=256)
    for k in range(3):
        lib.add(pen_tree(10 * k + 17, 320, 3, (0.02, 0.02, 0.02), True), f"t{k}")
    src = [pen_widths(e.image)[0] for e in lib.exemplars]
    for seed in (0, 1):
        v = lib.variation(rng=seed)
        w, parts = pen_widths(v.image, parts=v.parts)
        expected = np.average([x.mean() for x in src], weights=v.colour_weights)
        assert w.mean() >= 0.95 * expected, (w.mean(), expected)
        assert np.median(w[parts == 2]) >= min(np.median(x) for x in src) - 0.25
        assert np.quantile(w, 0.9) / np.quantile(w, 0.1) <= 1.5
