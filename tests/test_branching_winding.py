"""Structure synthesis never winds a branch into a spiral; a delta's channels fan out below its head;
the fitted example of the checks comes from one helper (issue 23, branching19)."""
import numpy as np
import pytest

from branchnb.branching import fit_model, growth, synthesize_structure
from branchnb.branching.domains import _Drain
from branchnb.branching.growth import WIND_BOUNDS_DEG, winding, winding_limit
from branchnb.core.structure import Branch, Structure


def _curly(n=3, turn_deg=250.0):
    """Arcs of a circle, each turning ``turn_deg``: copied end to end they close into spirals."""
    bs = []
    t = np.linspace(0, np.radians(turn_deg), 120)
    for i in range(n):
        c = np.array([60 + 80 * i, 100.0])
        bs.append(Branch(c + 40 * np.c_[np.cos(t), np.sin(t)], 2.0))
    return Structure(bs, image_shape=(240, 300))


def test_winding_of_known_turns():
    assert np.degrees(winding(np.radians([30.0, 30.0, -90.0, 10.0]))) == pytest.approx(90.0)
    assert winding([]) == 0.0
    spiral = np.full(100, np.radians(5.0))           # 500 degrees one way
    assert np.degrees(winding(spiral)) == pytest.approx(500.0)


def test_winding_limit_follows_the_example_within_bounds():
    lo, hi = WIND_BOUNDS_DEG
    assert np.degrees(winding_limit(_curly(turn_deg=100.0))) == pytest.approx(lo)       # 1.25 x 100 < floor
    assert np.degrees(winding_limit(_curly(turn_deg=200.0))) == pytest.approx(250.0, abs=5)
    assert np.degrees(winding_limit(_curly(turn_deg=250.0))) == pytest.approx(hi)
    straight = Structure([Branch(np.c_[np.linspace(0, 90, 30), np.full(30, 5.0)], 1.0)], image_shape=(20, 100))
    assert np.degrees(winding_limit(straight)) == pytest.approx(lo)


def test_curly_example_grows_no_spiral(monkeypatch):
    model = fit_model(_curly())
    hi = WIND_BOUNDS_DEG[1]
    after = []
    for seed in range(3):
        s = synthesize_structure(model, shape=(400, 400), rng=seed).structure
        after.append(max(np.degrees(winding(b.angles())) for b in s.branches if len(b.points) > 2))
    # measured: 297-300 degrees (limit 300); without the limit 367-376 (every seed a full turn and more)
    assert max(after) <= hi + 5.0, after
    monkeypatch.setattr(growth, "winding_limit", lambda ex: 1e9)
    s = synthesize_structure(model, shape=(400, 400), rng=0).structure
    before = max(np.degrees(winding(b.angles())) for b in s.branches if len(b.points) > 2)
    assert before > 360.0


def test_delta_way_down_fans_from_the_apex():
    dom = np.ones((200, 200), bool)
    dom[160:] = False                                  # the sea along the bottom
    d = _Drain(dom)
    left, right = np.array([30.0, 120.0]), np.array([170.0, 120.0])
    # the steepest descent alone is straight down on both sides: parallel channels
    assert abs(d.way_down(left)[0]) < 0.05 and abs(d.way_down(right)[0]) < 0.05
    d.apex = np.array([100.0, 0.0])
    wl, wr = d.way_down(left), d.way_down(right)
    assert wl[1] > 0.5 and wr[1] > 0.5                 # still toward the sea
    spread = np.degrees(np.arctan2(wr[1], wr[0]) - np.arctan2(wl[1], wl[0]))
    assert spread < -20.0                              # left heads down-left, right down-right
    assert np.allclose(np.hypot(*wl), 1.0)


def test_fitted_example_is_shared_and_cached(tmp_path):
    from branchnb.branching import _seed_check, _structure_check

    assert _structure_check.fitted_example is _seed_check.fitted_example
    img, dom, model = _seed_check.fitted_example("delta", 250, cache=str(tmp_path))
    assert img.shape[:2] == dom.shape == (250, 250) and model.example.total_length > 100
    again = _seed_check.fitted_example("delta", 250, cache=str(tmp_path))
    assert again[2].example.total_length == model.example.total_length
    assert (tmp_path / "delta_250.pkl").exists()


def test_delta_channel_bearing_heads_apart_from_its_parent():
    from branchnb.branching.domains import FAN_MAX, FAN_SPLIT

    dom = np.ones((200, 600), bool)                    # wide: a straight run 60 degrees off reaches the sea
    dom[160:] = False                                  # the sea along the bottom: descent is +y
    d = _Drain(dom)
    at = np.array([300.0, 80.0])

    def off(v):                                        # degrees off straight down, + toward -x
        return float(np.degrees(np.arctan2(-v[0], v[1])))

    # a child leaving the trunk almost along it gets at least FAN_SPLIT off it, on its own side
    b = d.bearing(at, np.array([-0.05, 1.0]))
    assert np.isclose(off(b), np.degrees(FAN_SPLIT), atol=0.5) and np.allclose(np.hypot(*b), 1.0)
    # a sideways (or upstream) heading is turned to at most FAN_MAX off the descent, never upstream
    b = d.bearing(at, np.array([1.0, -0.2]))
    assert np.isclose(off(b), -np.degrees(FAN_MAX), atol=0.5) and b[1] > 0
    # a grandchild leaving a fanned channel along its way down gets FAN_SPLIT off that, within FAN_MAX
    parent = d.bearing(at, np.array([-1.0, 0.0]))      # at +FAN_MAX
    ways = off(d.way_down(at, parent))
    assert 20.0 < ways < np.degrees(FAN_MAX)           # the parent's way down: between descent and bearing
    a = np.radians(ways)
    b = d.bearing(at, np.array([-np.sin(a), np.cos(a)]), parent_fan=parent)
    assert abs(abs(off(b) - ways) - np.degrees(FAN_SPLIT)) < 0.5 and abs(off(b)) <= np.degrees(FAN_MAX) + 1e-6


def test_delta_channels_fan_out_below_the_head():
    """A binary delta mask (procedural, :func:`._map_examples.delta_mask_example`): the channels reach the sea
    spread out like the example's, not side by side below its head (issue 23). Measured on 6 seeds at 512 px:
    median inland bearing spread 23 degrees before (every channel pulled toward the trunk's course), 29 after;
    example 50."""
    from branchnb.branching._seed_check import fitted_example
    from branchnb.branching._structure_check import sea_bearings_inland

    _img, dom, model = fitted_example("delta", 512)
    spread, n = [], []
    for seed in range(6):
        s = synthesize_structure(model, rng=seed).structure
        sp, k = sea_bearings_inland(s, dom)
        spread.append(sp)
        n.append(k)
    assert np.median(spread) >= 26.0, spread
    assert min(n) >= 3, n
