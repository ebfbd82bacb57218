"""One vein system per new leaf (issue 22): the background's own veins beside a pasted donor vein go."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.leaves.leftover import layer_strength, own_lines, parallel_lines, ridge_strength


def _blade(h=90, w=90, seed=0):
    rng = np.random.default_rng(seed)
    img = np.full((h, w, 3), 0.5, np.float32) + rng.normal(0, 0.01, (h, w, 1)).astype(np.float32)
    return np.clip(img, 0, 1), np.ones((h, w), bool)


def test_own_lines_finds_and_fills_a_vein_left_in_the_background():
    bg, blade = _blade()
    bg[10:80, 40:42] -= 0.15  # a dark vein the induction missed
    layer = bg.copy()
    layer[10:80, 60:63] -= 0.2  # the induced layer's own vein (the reference strength)
    mask = np.zeros(blade.shape, bool)
    mask[10:80, 60:63] = True
    lab, filled, ref = own_lines(bg, blade, layer, mask, -1.0, 3.0)
    assert ref == pytest.approx(layer_strength(layer, mask, -1.0, 3.0))
    assert lab.max() == 1 and lab[45, 40] > 0 and lab[45, 20] == 0
    r_before = ridge_strength(bg.mean(-1), [1.0], -1.0)
    r_after = ridge_strength(filled.mean(-1), [1.0], -1.0)
    plain = np.percentile(r_before[:, 5:30], 95)
    assert r_before[20:70, 40:42].mean() > 5 * plain
    assert r_after[20:70, 40:42].mean() < 1.5 * plain
    # the blade's grain is kept in the filled strip (not a smooth band)
    assert filled[20:70, 40:42, 0].std() > 0.4 * bg[20:70, 5:30, 0].std()


def test_parallel_lines_takes_the_doubled_vein_not_a_crossing_one_nor_a_far_one():
    lab = np.zeros((100, 100), np.int32)
    lab[10:90, 40:42] = 1   # 7 px beside the pasted vein, parallel: the same vein moved
    lab[60:62, 55:95] = 2   # a crossing vein beside it but across
    lab[10:90, 80:82] = 3   # parallel but far
    foot = np.zeros((100, 100), bool)
    foot[10:90, 47:50] = True
    out = parallel_lines(lab, foot, 10.0)
    assert out[lab == 1].mean() == 1.0
    assert out[lab == 2].mean() < 0.2
    assert out[lab == 3].sum() == 0
    assert not parallel_lines(lab, np.zeros_like(foot), 10.0).any()


def test_bad_inputs_give_nothing_rather_than_fail():
    bg, blade = _blade(30, 30)
    lab, filled, ref = own_lines(bg, blade, bg, np.zeros_like(blade), -1.0, 2.0)
    assert ref == 0.0 and not lab.any() and np.array_equal(filled, bg)


@pytest.fixture(scope="module")
def under_induced():
    """A procedural lobed family whose induction misses veins: true registrations moved by two vein
    widths, no snapping (the exemplars' residuals keep pieces of their veins)."""
    from branchnb.leaves._measure import _family_on_canvas, _Perturbed, _TrueRegistration, main_vein_width
    from branchnb.leaves.analysis import analyze
    from branchnb.leaves.induction import InductionParams

    fam, gt, kps, shape = _family_on_canvas("lobed", 160, 3, 0)
    regs = [_TrueRegistration(k, kps[0], shape) for k in kps]
    amp = 2.0 * float(np.median([main_vein_width(g["veins"]) for g in gt]))
    rng = np.random.default_rng((0, 0))
    regs = [r if e == 0 else _Perturbed(r, amp, rng) for e, r in enumerate(regs)]
    a = analyze(fam, 0, {"veins": fam[0].layers["veins"]}, registrations=regs, params=InductionParams(snap=False))
    return a, [g["veins"] for g in gt]


def _own_ratio(a, veins, params, seeds):
    from branchnb.leaves._measure import vein_system_scores
    rows = vein_system_scores(a, veins, seeds=seeds, near=2, params=params)
    v = np.array([r["bg_own"] for r in rows])
    n = np.array([r["n_own"] for r in rows], float)
    ok = np.isfinite(v) & (n > 0)
    return float(np.average(v[ok], weights=n[ok]))


def test_new_leaves_of_an_under_induced_family_show_one_vein_system(under_induced):
    """Ridge response at the backgrounds' own true veins, apart from the donor's veins and pasted layer
    (2 px), over plain blade as far from them (pixel-weighted over 6 new leaves): 1.12 -> 1.07.

    Since the leftover lines are read on the residual with the blade's colours past its outline
    (leftover._rimless), the background alone leaves 1.067 (1.109 before; more of its leftover veins are
    flattened with the prepared stage), and one_system 1.066 (1.059 before): little is left to remove.

    With the default pose kernel 0.15 (leaves66; new leaves nearer their background's pose, its leftover
    pieces resampled sharper) 1.150 (off 1.163); with the stubs beside the induced veins flattened too
    (prepared._NEAR_LEVEL) 1.056 (off 1.053), and 1.010 at pose kernel 1."""
    from branchnb.leaves.synthesis import SynthesisParams

    a, veins = under_induced
    assert any(_prepared_lines(a, e) for e in (1, 2))  # the residuals keep vein pieces
    off = _own_ratio(a, veins, SynthesisParams(one_system=0.0), range(6))
    on = _own_ratio(a, veins, SynthesisParams(), range(6))
    assert on <= off + 0.005
    assert on <= 1.08


def _bg_ratio(a, p, veins, e):
    """Ridge response of exemplar ``e``'s background at its true veins over plain blade (4 px from them)."""
    from branchnb.leaves._measure import _ridge
    blade = ndi.binary_erosion(a.blades[e], iterations=3)
    r = _ridge(np.asarray(p.stage[-1][e], np.float32))
    return float(r[veins[e] & blade].mean() / r[blade & ~ndi.binary_dilation(veins[e], iterations=4)].mean())


def test_backgrounds_keep_no_stubs_beside_their_induced_veins(under_induced, monkeypatch):
    """Issue 22 (leaves66): the stubs and rims of veins the induction cut short, right beside the induced
    layer, leave the background (prepared._NEAR_LEVEL). Ridge response of the under-induced exemplars'
    backgrounds at their true veins over plain blade: 1.25 and 1.20 without the pass, 1.01 and 1.05 with
    it (exemplar 0, fully induced, 0.77 -> 0.78; the exemplars themselves 2.2-2.4)."""
    from branchnb.leaves import prepared
    from branchnb.leaves.synthesis import _prepared

    a, veins = under_induced
    after = [_bg_ratio(a, _prepared(a), veins, e) for e in (1, 2)]
    monkeypatch.setattr(prepared, "_NEAR_LEVEL", None)
    p0 = prepared._Prepared(a)  # built afresh, outside the analysis' cache
    before = [_bg_ratio(a, p0, veins, e) for e in (1, 2)]
    assert max(after) <= 1.1, after
    assert min(before) >= max(after) + 0.1, (before, after)


def _prepared_lines(a, e):
    from branchnb.leaves.synthesis import _prepared
    return _prepared(a).own_lines(e) is not None


@pytest.fixture(scope="module")
def fan_family():
    """A procedural fan family (densely forking veins), true registrations, and its leaves without veins."""
    from branchnb.leaves._measure import _family_on_canvas, _TrueRegistration, plain_exemplars
    from branchnb.leaves.analysis import analyze

    fam, gt, kps, shape = _family_on_canvas("fan", 256, 3, 2)
    regs = [_TrueRegistration(k, kps[0], shape) for k in kps]
    a = analyze(fam, 0, {"veins": fam[0].layers["veins"], "spots": fam[0].layers["spots"]}, registrations=regs)
    return a, [g["veins"] for g in gt], [g["spots"] for g in gt], plain_exemplars("fan", 256, 3, 2)


def test_plain_exemplars_are_the_leaves_without_veins(fan_family):
    a, veins, spots, plain = fan_family
    for img, p, v in zip(a.exemplars, plain, veins):
        assert p.shape == img.shape
        np.testing.assert_array_equal(p[..., 3], img[..., 3])
        far = ~ndi.binary_dilation(v, iterations=2) & (img[..., 3] > 0.99)
        assert np.abs(p[..., :3] - img[..., :3])[far].max() < 1e-6   # texture and spots unchanged
        assert np.abs(p[..., :3] - img[..., :3]).max(-1)[v].mean() > 0.1  # the veins are gone


def _weighted(rows, key, n_key):
    v = np.array([r[key] for r in rows])
    n = np.array([r[n_key] for r in rows], float)
    ok = np.isfinite(v) & (n > 0)
    return float(np.average(v[ok], weights=n[ok]))


def test_background_veins_leave_no_more_ridge_than_a_leaf_that_never_had_them(fan_family):
    """Issue 22, one vein system: at the background's true veins (2 px from the donor's) a new leaf answers
    the ridge filter as the same leaf made on the background rendered without veins (pixel-weighted over 6
    fan leaves, 309 px: 1.05), while the old ratio to plain blade elsewhere reads 1.56 (its pixels lie in
    the halo of the donor's veins). With the backgrounds' veins left in (each exemplar instead of its
    residual) the same measure reads 3.98."""
    from branchnb.leaves._measure import vein_system_scores
    from branchnb.leaves.prepared import _bleed, _stored
    from branchnb.leaves.synthesis import _prepared

    a, veins, spots, plain = fan_family
    rows = vein_system_scores(a, veins, spots, seeds=range(6), plain=plain)
    rel = _weighted(rows, "own_rel", "n_own")
    assert rel <= 1.1
    assert np.nanmean([r["bg"] for r in rows]) > 1.3   # the old measure: the donor's halo
    p = _prepared(a)
    stage = p.stage[-1]
    try:
        # the backgrounds' veins never removed: each exemplar itself
        p.stage[-1] = [_stored(_bleed(x, b)) for x, b in zip(a.exemplars, a.blades)]
        p._own.clear()
        p.__dict__.pop("_details", None)
        left = vein_system_scores(a, veins, spots, seeds=range(6), plain=plain)
    finally:
        p.stage[-1] = stage
        p._own.clear()
        p.__dict__.pop("_details", None)
    assert _weighted(left, "own_rel", "n_own") > rel + 0.5
