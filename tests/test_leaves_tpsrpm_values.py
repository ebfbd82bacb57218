"""TPS-RPM's rounds solved for the spline's values at its centres give the normal equations' registrations.

The normal equations in the spline's coefficients (``A^T C A z = ...``) stay in the compiled loop as
the fallback (``cond(A) > _VALUES_COND``): forcing it gives the reference the values form must match.
"""

import numpy as np
import pytest

from branchnb.leaves import leaf_family, register, tps_rpm
from branchnb.leaves import tpsrpm as tpsrpm_mod
from branchnb.leaves.tps import _SplineSystem


def _outline(n=150, lobes=5, seed=0):
    rng = np.random.default_rng(seed)
    s = np.linspace(0, 2 * np.pi, n, endpoint=False)
    r = 1 + 0.2 * np.cos(lobes * s + rng.uniform(0, 2 * np.pi))
    x = np.column_stack([np.cos(s) * r, 0.7 * np.sin(s) * r])
    v = 1.1 * x @ np.array([[0.98, -0.2], [0.2, 0.98]]) + 0.05 * np.sin(2 * x[:, ::-1]) + (0.1, -0.05)
    return x, v


def _reference(monkeypatch):
    """Force the normal equations (the form before) for every later fit."""
    monkeypatch.setattr(tpsrpm_mod, "_VALUES_COND", 0.0)


@pytest.mark.parametrize("n, labelled, cost", [(150, False, False), (60, True, False), (40, False, True)])
def test_values_form_matches_the_normal_equations(monkeypatch, n, labelled, cost):
    x, v = _outline(n, seed=n)
    kw = {}
    if labelled:
        lab = (np.arange(n) % 7 == 0).astype(int)
        kw = dict(source_labels=lab, target_labels=lab)
    if cost:
        kw["pair_cost"] = 0.01 * np.abs(np.subtract.outer(np.arange(n), np.arange(n))) / n
    f_new, m_new = tps_rpm(v, x, **kw)
    _reference(monkeypatch)
    f_ref, m_ref = tps_rpm(v, x, **kw)
    grid = np.stack(np.meshgrid(np.linspace(-1.5, 1.5, 31), np.linspace(-1.5, 1.5, 31)), -1).reshape(-1, 2)
    # Blade radii (normalised units); measured ~1e-12.
    assert np.abs(f_new(grid) - f_ref(grid)).max() < 1e-7
    assert np.abs(m_new - m_ref).max() < 1e-7
    assert np.hypot(*(f_new(v) - x).T).mean() < 0.01  # and it still registers


def test_registration_points_and_maps_match_the_normal_equations(monkeypatch):
    """Whole registrations of procedural leaves (two kinds, two sizes): keypoints within 0.05 px
    (measured ~1e-9 px), dense maps within 0.05 px (measured ~1e-5 px, their float32 rounding)."""
    pairs = []
    for kind, size, seed in (("trilobed", 128, 7), ("elliptic", 96, 2)):
        fam = leaf_family(2, size=size, kind=kind, rng=seed)
        pairs.append((fam[1], fam[0]))
    new = [register(a, b) for a, b in pairs]
    _reference(monkeypatch)
    ref = [register(a, b) for a, b in pairs]
    for r_new, r_ref in zip(new, ref):
        p = r_new.exemplar_keypoints.points
        assert np.abs(r_new.forward(p) - r_ref.forward(p)).max() < 0.05
        assert np.abs(r_new.map_to_training - r_ref.map_to_training).max() < 0.05


def test_fit_space_falls_back_on_a_singular_basis():
    """Repeated centres make A singular: no values form (the normal equations' own fallbacks take over)."""
    from branchnb.leaves import RegistrationParams

    x, v = _outline(30)
    prm = RegistrationParams()
    ainv, reg0 = tpsrpm_mod._fit_space(_SplineSystem(v), prm)
    assert ainv.shape == reg0.shape == (30, 30)
    assert np.allclose(ainv @ _SplineSystem(v).a, np.eye(30), atol=1e-8)
    assert np.allclose(reg0, reg0.T)
    v2 = np.vstack([v, v[:3]])
    ainv, reg0 = tpsrpm_mod._fit_space(_SplineSystem(v2), prm)
    assert ainv.shape == (0, 0)
    f, m = tps_rpm(v2, np.vstack([x, x[:3]]))
    assert np.isfinite(f(v2)).all()
