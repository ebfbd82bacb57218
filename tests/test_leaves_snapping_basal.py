"""Branches of the petiole junction the snapping lost, found by rays (:mod:`branchnb.leaves.snapping_basal`)."""

import numpy as np
import pytest

from branchnb.core.metrics import iou
from branchnb.leaves.analysis import IdentityRegistration
from branchnb.leaves.snapping import snap_to_exemplars
from branchnb.leaves.snapping_basal import junction_star, leaving_directions

H = W = 200
JUNCTION = np.array([100.0, 150.0])


def _star(angles, lengths, width=2.0):
    """A vein star from the junction: angles (degrees, 0 = up, positive to the right) and lengths."""
    yy, xx = np.mgrid[0:H, 0:W]
    m = np.zeros((H, W), bool)
    for a, n in zip(angles, lengths):
        d = np.array([np.sin(np.radians(a)), -np.cos(np.radians(a))])
        v = np.stack([xx - JUNCTION[0], yy - JUNCTION[1]], -1)
        t = np.clip(v @ d, 0, n)
        dist = np.hypot(*(v - t[..., None] * d).transpose(2, 0, 1))
        m |= dist <= width / 2
    return m


def _blade():
    yy, xx = np.mgrid[0:H, 0:W]
    return ((xx - 100) / 95.0) ** 2 + ((yy - 100) / 90.0) ** 2 <= 1.0


def _lab(veins, blade, seed):
    rng = np.random.default_rng(seed)
    lab = np.zeros((H, W, 3), np.float32)
    lab[..., 0] = np.where(blade, 62.0, 90.0) + rng.normal(0, 1.0, (H, W))
    lab[..., 0] -= 12.0 * veins
    lab[..., 1] = -20.0
    lab[..., 2] = 30.0
    return lab


ANG_T = (0, 45, -45, 65, -65)        # training: basal veins at 65 degrees from the midrib
LEN = (120, 85, 85, 60, 60)


def _snap(exemplar_angles, basal):
    blade = _blade()
    user = _star(ANG_T, LEN) & blade
    truth = _star(exemplar_angles, LEN) & blade
    labs = [_lab(user, blade, 0), _lab(truth, blade, 1)]
    regs = [IdentityRegistration((H, W))] * 2
    masks, _ = snap_to_exemplars(labs, [blade, blade], 0, user, regs, tolerance=2.0, basal=basal)
    return masks[1], truth


def test_junction_star_counts_the_branches_leaving_the_junction():
    s = junction_star([np.array([JUNCTION, JUNCTION + r * np.array([np.sin(np.radians(a)), -np.cos(np.radians(a))])])
                       for a, r in zip(ANG_T, LEN)], _blade())
    assert s is not None and len(s["index"]) == 5
    assert np.allclose(np.sort(np.degrees(s["angles"])) - np.sort(np.degrees(s["angles"]))[2],
                       np.sort(ANG_T), atol=3)


def test_leaving_directions_of_a_star():
    m = _star((0, 60, -60), (80, 60, 60))
    got = np.sort(np.degrees(leaving_directions(m, JUNCTION, -np.pi / 2, 120.0)))
    assert np.allclose(got, [-60, 0, 60], atol=3)


def test_basal_veins_missed_by_the_prior_are_found(monkeypatch):
    # The exemplar's basal veins open 35 degrees wider than the training leaf's: the carried prior
    # misses them by more than its tube; the rays from the junction find them. Side ridges off: since
    # the carried basal paths over plain blade are dropped as too faint (snapping.RELATIVE_EVIDENCE),
    # the side-ridge step finds these straight basal veins too (recall 1.0 without the rays).
    import branchnb.leaves.snapping as snapping
    monkeypatch.setattr(snapping, "SIDE_LEVEL", 0.0)
    angles = (0, 45, -45, 100, -100)
    off, truth = _snap(angles, basal=False)
    on, _ = _snap(angles, basal=True)
    basal = _star((100, -100), (60, 60)) & ~_star((0,), (20,)) & _blade()
    rec_off = (off & basal).sum() / basal.sum()
    rec_on = (on & basal).sum() / basal.sum()
    assert rec_off < 0.5
    assert rec_on > 0.8
    assert iou(on, truth) > iou(off, truth) + 0.1
    assert iou(on, truth) > 0.7


def test_no_vein_invented_where_the_training_leaf_has_none():
    # The exemplar has a basal pair the training leaf lacks: nothing is searched for it, and where
    # the exemplar lacks the training leaf's basal pair nothing is added.
    blade = _blade()
    user = _star(ANG_T[:3], LEN[:3]) & blade
    truth = _star((0, 45, -45, 100, -100), LEN) & blade
    labs = [_lab(user, blade, 0), _lab(truth, blade, 1)]
    regs = [IdentityRegistration((H, W))] * 2
    on = snap_to_exemplars(labs, [blade, blade], 0, user, regs, tolerance=2.0, basal=True)[0][1]
    off = snap_to_exemplars(labs, [blade, blade], 0, user, regs, tolerance=2.0, basal=False)[0][1]
    assert np.array_equal(on, off)
    # No basal veins on the exemplar, four branches (with them) on the training leaf.
    user = _star(ANG_T, LEN) & blade
    truth = _star(ANG_T[:3], LEN[:3]) & blade
    labs = [_lab(user, blade, 0), _lab(truth, blade, 1)]
    on = snap_to_exemplars(labs, [blade, blade], 0, user, regs, tolerance=2.0, basal=True)[0][1]
    off = snap_to_exemplars(labs, [blade, blade], 0, user, regs, tolerance=2.0, basal=False)[0][1]
    assert (on & ~off).sum() == 0


@pytest.mark.parametrize("angles", [(0, 45, -45, 65, -65), (0, 50, -50, 70, -70)])
def test_nothing_changes_when_every_branch_is_found(angles):
    off, _ = _snap(angles, basal=False)
    on, _ = _snap(angles, basal=True)
    assert np.array_equal(on, off)


def test_no_basal_vein_searched_beside_a_lost_lateral():
    # The exemplar's left lateral is not found at the junction: its side of the junction is not
    # credible, so its left basal vein is not searched for; the right one still is.
    blade = _blade()
    user = _star(ANG_T, LEN) & blade
    truth = _star((0, 45, 100, -100), (120, 85, 60, 60)) & blade
    labs = [_lab(user, blade, 0), _lab(truth, blade, 1)]
    regs = [IdentityRegistration((H, W))] * 2
    on = snap_to_exemplars(labs, [blade, blade], 0, user, regs, tolerance=2.0, basal=True)[0][1]
    off = snap_to_exemplars(labs, [blade, blade], 0, user, regs, tolerance=2.0, basal=False)[0][1]
    new = on & ~off
    assert new[:, :int(JUNCTION[0]) - 6].sum() == 0
    right = _star((100,), (60,)) & ~_star((0,), (20,)) & blade
    assert (on & right).sum() > 0.8 * right.sum()
