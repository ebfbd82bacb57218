"""A thin layer's induced pieces running along the outline band are an ink outline, not veins (issue 22)."""

import numpy as np

from branchnb.leaves.analysis_induce import _outline_band, _outline_stretches


def _leaf(size=200):
    yy, xx = np.mgrid[0:size, 0:size]
    blade = ((xx - size / 2) / (0.42 * size)) ** 2 + ((yy - size / 2) / (0.3 * size)) ** 2 <= 1
    return blade, yy, xx


def test_outline_stretch_is_removed_and_vein_ends_stay():
    blade, yy, xx = _leaf()
    user = np.zeros_like(blade)
    user[98:101, 20:180] = True                       # a 3 px midrib on the training leaf
    band = _outline_band(blade, user)
    # Induced on an exemplar: the midrib (crossing the band at both ends), two
    # slanted laterals reaching the margin, and the upper-left quarter of the outline.
    m = np.zeros_like(blade)
    m[98:101, :] = True
    for s in (-1, 1):
        m |= (np.abs((yy - 100) - s * 0.7 * (xx - 100)) <= 1.5) & (xx > 100)
    m &= blade
    ink = band & (xx < 100) & (yy < 100)
    m |= ink
    gone = _outline_stretches(m & band, user)
    # The outline stretch (~100 px: far beyond OUTLINE_STRETCH band depths) goes whole ...
    assert (gone & ink).sum() / ink.sum() >= 0.95
    # ... the vein ends crossing the band (midrib and laterals, right half) stay.
    ends = m & band & (xx > 100)
    assert not (gone & ends).any()


def test_nothing_in_band_is_nothing_removed():
    blade, _, _ = _leaf(120)
    user = np.zeros_like(blade)
    user[59:61, 20:100] = True
    empty = np.zeros_like(blade)
    assert not _outline_stretches(empty, user).any()
