"""Issue 23 (branching88): a tilted delta fans evenly on both sides of its trunk's line.

``mean20`` of :mod:`.._delta_fan_check` (a meandering trunk 20 degrees off the way down, its root turning
into the outermost of four channels at the head: :data:`.drain.TAIL_OUTER`); a meandering trunk's slope
(:data:`.drain.MEANDER_FADED`)."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._delta_examples import MEANDER_KINDS, delta_fan_mask
from branchnb.branching._delta_fan_check import crossings, side_share, turned
from branchnb.branching.domains import _Drain
from branchnb.branching.drain import _faded_slope


def _fitted(kind: str, side: str, size: int):
    t, c, f, n, a = MEANDER_KINDS[kind]
    m = delta_fan_mask((size, size), 3 + size, t, c, f, n, meander=a)[0]
    img = np.dstack([turned(m, side)] * 3)
    ex = extract_structure(img)
    dom = example_domain(img, ex)
    return dom, fit_model(ex, domain=dom)


@pytest.fixture(scope="module")
def mean20():
    return _fitted("mean20", "bottom", 512)


def test_a_turned_trunk_into_the_outermost_channel_has_none_beyond_it(mean20):
    dom, model = mean20
    d = _Drain(dom)
    d.set_axis(model.example, dom)
    assert d.tail is not None and d.tail_outer                   # the root turns into the outermost channel
    d.set_tail_depth(0.45 * float(d.depth.max()))
    below = (256.0, float(dom.shape[0]) - 0.3 * float(d.depth.max()))
    side, a = d.outer_side(below)
    assert side == (1 if d.tail > 0 else -1)
    assert abs(np.angle(np.exp(1j * (a - np.arctan2(d.descent(below)[1], d.descent(below)[0]) - d.tail)))) < 1e-6
    assert d.outer_side((256.0, 5.0))[0] == 0                    # above the head any side


def test_a_tilted_delta_fans_on_both_sides_of_its_trunk(mean20):
    dom, model = mean20
    ex = side_share(model.example, dom)
    # seeds 1 and 2 put every channel on the turned trunk's outer side on main (side share 0.00 and 0.14)
    got = []
    for seed in (1, 2):
        s = synthesize_structure(model, rng=seed).structure
        got.append(side_share(s, dom))
        assert crossings(s) == 0
    # 0.26 / 0.36 against the example's 0.42
    assert min(got) >= ex - 0.2 and np.mean(got) >= ex - 0.12, (got, ex)


def test_the_meander_slope_gives_the_examples_sinuosity_on_the_faded_sine():
    # the trunk follows arctan(k sqrt(sin(pi u)) cos(pi n u)) (drain._Drain._meander_way): its path over the
    # run must be the example's sinuosity x as long; the plain sine's 2 sqrt(sin - 1) fell 0.04-0.07 short
    u = (np.arange(4000) + 0.5) / 4000.0
    for sin in (1.1, 1.2, 1.5, 2.0):
        for n in (3, 4, 6):
            k = _faded_slope(sin, n)
            g = np.sqrt(np.sin(np.pi * u)) * np.cos(np.pi * n * u)
            assert abs(float(np.mean(np.sqrt(1.0 + (k * g) ** 2))) - sin) < 2e-3
            plain = 2.0 * np.sqrt(sin - 1.0)
            assert float(np.mean(np.sqrt(1.0 + (plain * g) ** 2))) < sin - 0.03


def test_a_tilted_turned_trunk_heads_for_the_examples_head(mean20):
    # drain.HEAD_HOLD (branching94): above its turn the trunk of mean20 ran straight down the descent, its
    # channels parted inland of the example's and the mouths' mean moved with them (trunk bearing error,
    # start to the mouths' mean, seeds 1 / 2: 6.7 / 11.1 deg before, 2.8 / 2.4 after)
    from branchnb.branching._delta_fan_check import bearing_error, trunk_bearing

    dom, model = mean20
    d = _Drain(dom)
    d.set_axis(model.example, dom)
    assert d.trunk_target is not None and d.tail_outer
    ex = trunk_bearing(model.example, dom)
    errs = [bearing_error(trunk_bearing(synthesize_structure(model, rng=seed).structure, dom), ex)
            for seed in (1, 2)]
    assert max(errs) <= 5.0, errs
