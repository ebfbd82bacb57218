"""Issue 25, dendrites: a lightning bolt's side branches stay in its own region and fork
downwards. On a night photo without a strike (the rocket at 640 px) branches left the
bolt's top and wandered across the whole sky to the lights on the ground."""

import numpy as np
import pytest
import skimage.data as skdata
from skimage.transform import resize
from test_dendrite_straight_edges import _launch_pad

from branchnb.dendrite import stylize
from branchnb.dendrite._side_spread import side_spread
from branchnb.dendrite.photo_side import strike_region


@pytest.mark.parametrize("picture", ["pad", "rocket"])
def test_side_branches_stay_near_the_bolt(picture):
    # measured (before -> after): the share of the side branches' length outside a
    # 60-degree cone below their fork on the main channel, launch pad 320 px seeds 0/1
    # 0.36/0.37 -> 0.07/0.08, the rocket photo at 400/640 px 0.64/0.67 -> 0.04/0.04 (the
    # procedural storms' own side branches 0.14); their mean lateral reach from the fork
    # (share of the diagonal) 0.207/0.211 -> 0.098/0.055, rocket 0.192/0.185 -> 0.120/0.110
    if picture == "pad":
        img = _launch_pad(320, 0)[0]
    else:
        img = resize(skdata.rocket() / 255.0, (267, 400), anti_aliasing=True).astype(np.float32)
    d = stylize(img, rng=0, metaphor="lightning").dendrite
    out, reach = side_spread(d)
    assert out < 0.3 and reach < 0.15
    # nothing above the bolt's top
    top = d.points[d.main, 1].min()
    assert (d.points[:, 1] >= top - 3).all()


def test_strike_region_is_a_cone_below_the_channel():
    path = np.column_stack([np.r_[np.full(30, 40), np.arange(40, 60)], np.arange(10, 60)])
    r = strike_region(path, (100, 120), angle=30.0, margin=0.0)
    assert not r[:10].any()
    assert r[10].sum() == 1 and r[10, 40]
    half = np.tan(np.radians(30.0)) * 50
    assert r[60, 59 - int(half) + 1] and not r[60, 59 - int(half) - 1]  # about the channel
    assert r[99].sum() > r[60].sum()  # widening below the channel's end
    with pytest.raises(ValueError, match="angle"):
        strike_region(path, (100, 120), angle=90.0)
    with pytest.raises(ValueError, match="margin"):
        strike_region(path, (100, 120), margin=-1.0)


@pytest.mark.parametrize("picture", ["pad0", "pad1", "rocket"])
def test_side_branches_are_short_as_a_real_bolts(picture):
    # a real bolt's side branches are short beside its main channel (the procedural
    # storms' 0.19-0.37 of their trunk, lateral reach ~0.03 of the diagonal); forking at
    # the channel's top they ran down beside it to the ground. Measured (before -> after),
    # launch pad seeds 0/1 and the rocket at 400 px: longest side branch / main channel
    # 0.79 / 0.61 / 1.36 -> 0.30 / 0.30 / 0.30; the rocket's mean lateral reach 0.120 -> 0.035
    from branchnb.dendrite._side_spread import side_lengths

    if picture.startswith("pad"):
        img = _launch_pad(320, int(picture[-1]))[0]
    else:
        img = resize(skdata.rocket() / 255.0, (267, 400), anti_aliasing=True).astype(np.float32)
    d = stylize(img, rng=0, metaphor="lightning").dendrite
    out, reach = side_spread(d)
    v = side_lengths(d)
    assert len(v) >= 1 and v.max() <= 0.35 and out < 0.3
    if picture == "rocket":
        assert len(v) >= 5 and reach < 0.06  # still a branching bolt, whose branches stay near
