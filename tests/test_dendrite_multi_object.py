"""A lightning bolt over several separate objects (issue 25, dendrite34): it strikes the object
its seed lies over and jumps to the others along jagged paths, never in a straight line
through the empty ground."""

import numpy as np
import pytest
from scipy import ndimage

from branchnb.dendrite import stylize
from branchnb.dendrite._multi_bolt_check import case, chains, straight_run
from branchnb.dendrite.channel_jag import _ground
from branchnb.dendrite.main_channel import main_path, strike_channel
from branchnb.dendrite.strike_part import _seed_part


def _pole_and_cap():
    """A thin pole with a head (left) and a wide cap on a stem (right): the wide part of the
    pair lies in the right one."""
    m = np.zeros((100, 120), bool)
    m[10:95, 14:18] = True
    m[6:16, 10:22] = True
    m[40:60, 50:115] = True
    m[60:95, 78:88] = True
    return m


def test_seed_part_is_the_seeds_object_or_the_nearest():
    m = _pole_and_cap()
    assert _seed_part(m, (16, 8)).sum() == ndimage.label(m)[0][m].tolist().count(1)
    near = _seed_part(m, (40, 50))  # off both: the cap is nearer
    assert near[50, 100] and not near[50, 16]


def test_ground_grows_off_the_objects_and_never_undercuts():
    m = _pole_and_cap()
    g = _ground(m, 1.8, 0)
    assert g.min() >= 1.0
    d = ndimage.distance_transform_edt(~m)
    assert np.median(g[d > 15]) > 5 * np.median(g[(d > 0) & (d <= 3)])


def test_channel_stays_on_the_struck_object():
    m = _pole_and_cap()
    path = strike_channel(np.ones(m.shape), m, (16, 8), rng=0)
    assert m[path[:, 1], path[:, 0]].mean() > 0.97
    assert path[-1, 0] < 30 and path[-1, 1] > 85  # the pole's foot, not the cap's


@pytest.mark.parametrize("rng", [0, 1])
def test_lamp_and_toadstool_bolt_has_no_straight_run_across_the_sky(rng):
    img, obj = case("lamp", 250, rng)
    d = stylize(img, rng=rng, metaphor="lightning").dendrite
    diag = float(np.hypot(*obj.shape))
    tol = max(2.0, 0.005 * diag)
    outside = ndimage.distance_transform_edt(~obj) > 2
    main = d.points[main_path(d)]
    q = np.rint(main).astype(int)
    # the main channel runs through the struck object (on main: 0.62-0.75 of it)
    assert obj[np.clip(q[:, 1], 0, obj.shape[0] - 1), np.clip(q[:, 0], 0, obj.shape[1] - 1)].mean() > 0.9
    # no straight stretch of it in the sky (on main: 44-70 px straight across)
    assert straight_run(main, outside, tol) < 0.05 * diag
    # and no branch crosses the sky in a straight line (on main: 44-70 px; a bolt on a
    # plain canvas of this size: 28-35 px)
    assert max(straight_run(c, outside, tol) for c in chains(d)) < 0.12 * diag


@pytest.mark.parametrize("width", [6, 10])
def test_channel_zigzags_down_a_thin_pole(width):
    from branchnb.dendrite._bolt_shape_check import turning

    m = np.zeros((240, 160), bool)
    m[20:230, 80 - width // 2:80 + width - width // 2] = True
    m[10:30, 70:90] = True
    for rng in range(3):
        p = strike_channel(np.ones(m.shape), m, (80, 12), rng=rng)
        assert m[p[:, 1], p[:, 0]].all()
        # on main: 0.6-4.8 deg per 10 px, straight down the pole's middle
        assert turning(p, 10.0) > 9.0
        assert np.ptp(p[p[:, 1] > 40, 0]) >= width // 2 + 1
