"""The template starts compared on their template scores, only the winner posed branch by branch (issue 22
speed pass): the same fits as posing every start fully (the rule before, kept here as the reference)."""

import numpy as np

from branchnb.leaves import analyze, leaf_family
from branchnb.leaves import snapping_place as sp
from branchnb.leaves.snapping_basal import ANCHOR_MOVE, ANCHOR_REACH, ANCHOR_SHARE, _junction_of
from branchnb.leaves.snapping_carry import _affine_carry, _moment_carry
from branchnb.leaves.snapping_fit import _fit_each, _fit_template, fit_branches


def _reference_start(registration, blade_t, b_full, chains, carried, off, ev, b, hess, omaps, *, fit_reach,
                     registration_start, only_start, anchor, star):
    """``_template_start`` at a75e4dd: every start fitted fully."""
    best = None
    starts = [[c - off for c in _affine_carry(registration, blade_t, chains)],
              [c - off for c in _moment_carry(blade_t, b_full, chains)]]
    if registration_start > 0:
        starts.append(carried)
    for k, start in enumerate(starts):
        if only_start is not None and k != only_start:
            continue
        got, score = fit_branches(start, ev, b, reach=fit_reach * np.sqrt(float(b.sum())),
                                  return_score=True, hessian=hess, maps=omaps)
        if k == 2:
            score = score / registration_start
        if best is None or score > best[1]:
            best = (got, score)
    if anchor is not None and best is not None and ANCHOR_SHARE > 0 and only_start is None:
        jc = _affine_carry(registration, blade_t, [anchor[0][None]])[0][0] - off
        held = [c + (anchor[1] - jc) for c in starts[0]]
        got, score = fit_branches(held, ev, b, reach=ANCHOR_REACH * np.sqrt(float(b.sum())),
                                  return_score=True, hessian=hess, maps=omaps)
        moved = np.hypot(*(_junction_of(best[0], star) - _junction_of(got, star)))
        if score >= ANCHOR_SHARE * best[1] and moved > ANCHOR_MOVE * np.sqrt(float(b.sum())):
            best = (got, score)
    return None if best is None else best[0]


def test_split_fit_is_fit_branches():
    rng = np.random.default_rng(0)
    ev = np.zeros((90, 90), np.float32)
    ev[45, 10:80] = 1.0
    ev[20:45, 30] = 0.8
    ev += 0.05 * rng.random(ev.shape).astype(np.float32)
    chains = [np.column_stack([np.arange(12, 78), 40 + 0.05 * np.arange(66)]),
              np.column_stack([np.full(20, 34.0), np.arange(22, 42)])]
    blade = np.ones(ev.shape, bool)
    ref, s_ref = fit_branches(chains, ev, blade, reach=10.0, return_score=True)
    fit = _fit_template(chains, ev, blade, reach=10.0)
    got = _fit_each(fit)
    assert fit.score == s_ref
    for a, b in zip(ref, got):
        assert np.array_equal(a, b)


def test_induced_layers_as_with_every_start_fitted(monkeypatch):
    fam = leaf_family(3, size=160, kind="lobed", rng=4)
    layers = {"veins": fam[0].layers["veins"]}
    new = analyze(fam, 0, layers)
    monkeypatch.setattr(sp, "_template_start", _reference_start)
    old = analyze(fam, 0, layers)
    for e in range(3):
        assert np.array_equal(np.asarray(new.layers[0].masks[e]), np.asarray(old.layers[0].masks[e])), e
    # The fits matter here: the snapped layer differs from the carried one on every exemplar.
    assert all(new.layers[0].snapped[e] is not None for e in (1, 2))
