"""Issue 23 (branching85): a delta's sea is one more frame side its channels end at.

The frame band (``frame_band.band_keep``) was off for every example that drains to a sea, since it cut
the distributaries heading for the sea where the coast meets a side frame. The coast is now a side where
the example's lines end: a step in the band heading for the sea as steeply as one heading out of the
frame is kept, and the band stays on for the delta's other sides.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._delta_examples import delta_fan_mask
from branchnb.branching._delta_fan_check import frame_share, n_to_sea, turned
from branchnb.branching.frame_band import FRAME_BAND, FRAME_HUG_SHARE, _frame_share, band_keep


def _sea_left(shape=(100, 100), coast=30):
    """Distance to a sea filling the columns left of ``coast``."""
    land = np.ones(shape, bool)
    land[:, :coast] = False
    return ndi.distance_transform_edt(land)


def test_a_step_along_a_side_frame_is_kept_only_toward_the_sea():
    depth = _sea_left()
    closed = np.full(4, np.inf)                      # no side where the example's lines leave the frame
    toward = np.array([[44.0, 3.0], [38.0, 3.0], [32.0, 2.5]])     # along the top side, into the sea
    away = toward * [-1, 1] + [100, 0]              # the same along the top side, away from it
    tip = (50.0, 10.0)
    assert not band_keep(tip, toward, True, (100, 100), FRAME_BAND, closed)[0].any()   # as before
    assert band_keep(tip, toward, True, (100, 100), FRAME_BAND, closed, depth)[0].all()
    assert not band_keep(tip, away, True, (100, 100), FRAME_BAND, closed, depth)[0].any()
    with pytest.raises(ValueError, match="sea_depth"):
        band_keep(tip, toward, True, (100, 100), FRAME_BAND, closed, depth[:50])


@pytest.mark.parametrize("side, seed", [("left", 1), ("right", 2)])
def test_delta_keeps_off_its_side_frames_and_reaches_the_sea(side, seed):
    # a 30-deg tilted fan at 256 px with its sea on a side: the band is on (the example keeps off its
    # frame), the channels still reach the sea as many as the example's and keep off the other sides
    m = turned(delta_fan_mask((256, 256), 3 + seed, 30.0, 20.0, 70.0, 4)[0], side)
    img = np.dstack([m] * 3)
    ex = extract_structure(img)
    dom = example_domain(img, ex)
    model = fit_model(ex, domain=dom)
    assert _frame_share(model.example, FRAME_BAND) <= FRAME_HUG_SHARE
    s = synthesize_structure(model, rng=seed).structure
    assert n_to_sea(s, dom) >= n_to_sea(model.example, dom)
    assert frame_share(s, dom.shape, side) <= 0.01
