import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st

from branchnb.core.polyline import (
    arc_length,
    normals,
    resample_chord,
    resample_uniform,
    rigid_align,
    segments_intersect,
    tangents,
    turning_angles,
)


def test_resample_uniform_step_and_values():
    pts, vals = resample_uniform([(0, 0), (10, 0), (10, 10)], 2.0, values=[0, 10, 20])
    assert len(pts) == 11
    assert np.allclose(np.hypot(*np.diff(pts, axis=0).T)[[0, 1, 2, 3, 5, 6, 7, 8]], 2.0)
    assert np.allclose(vals, np.arange(0, 21, 2))


def test_resample_uniform_bad_input():
    with pytest.raises(ValueError, match="h must be"):
        resample_uniform([(0, 0), (1, 0)], 0)
    with pytest.raises(ValueError, match="zero length"):
        resample_uniform([(1, 1), (1, 1)], 1.0)
    with pytest.raises(ValueError, match="values"):
        resample_uniform([(0, 0), (1, 0)], 0.5, values=[1, 2, 3])


def test_resample_chord_closed_square():
    sq = [(0, 0), (4, 0), (4, 4), (0, 4)]
    out = resample_chord(sq, 8, closed=True)
    assert out.shape == (8, 2)
    assert np.allclose(out[:3], [(0, 0), (2, 0), (4, 0)])
    d = np.hypot(*np.diff(np.vstack([out, out[:1]]), axis=0).T)
    assert np.allclose(d, 2.0)


def test_turning_angles_signs():
    # y points down: a right-hand turn on screen is positive.
    assert np.allclose(turning_angles([(0, 0), (1, 0), (1, 1)]), [np.pi / 2])
    assert np.allclose(turning_angles([(0, 0), (1, 0), (1, -1)]), [-np.pi / 2])
    assert np.allclose(turning_angles([(0, 0), (1, 0), (2, 0)]), [0.0])


def test_tangents_normals_orthonormal():
    t = np.linspace(0, 2 * np.pi, 50)
    pts = np.column_stack([np.cos(t), np.sin(t)]) * 10
    tg, nm = tangents(pts), normals(pts)
    assert np.allclose(np.hypot(*tg.T), 1) and np.allclose(np.einsum("ij,ij->i", tg, nm), 0)


@settings(max_examples=40, deadline=None)
@given(st.floats(-np.pi, np.pi), st.floats(-50, 50), st.floats(-50, 50), st.integers(0, 10_000))
def test_rigid_align_recovers_transform(angle, tx, ty, seed):
    p = np.random.default_rng(seed).normal(size=(12, 2)) * 20
    r = np.array([[np.cos(angle), -np.sin(angle)], [np.sin(angle), np.cos(angle)]])
    q = p @ r.T + [tx, ty]
    T = rigid_align(p, q)
    assert np.allclose(T(p), q, atol=1e-6)
    assert np.isclose(np.cos(T.angle - angle), 1.0)


def test_rigid_align_never_reflects():
    p = np.array([(0, 0), (1, 0), (0, 1)], float)
    T = rigid_align(p, p * [-1, 1])
    assert np.isclose(np.linalg.det(T.rotation), 1.0)


def test_segments_intersect_matches_brute_force():
    rng = np.random.default_rng(1)
    a0, a1, b0, b1 = (rng.uniform(0, 10, (15, 2)) for _ in range(4))
    got = segments_intersect(a0, a1, b0, b1)

    def cross(p, q, r):
        return (q[0] - p[0]) * (r[1] - p[1]) - (q[1] - p[1]) * (r[0] - p[0])

    for i in range(15):
        for j in range(15):
            want = (cross(a0[i], a1[i], b0[j]) * cross(a0[i], a1[i], b1[j]) < 0
                    and cross(b0[j], b1[j], a0[i]) * cross(b0[j], b1[j], a1[i]) < 0)
            assert got[i, j] == want
    # touching at an end point is not a crossing
    assert not segments_intersect([(0, 0)], [(1, 1)], [(1, 1)], [(2, 0)])[0, 0]


def test_arc_length_closed():
    assert arc_length([(0, 0), (3, 0), (3, 4)], closed=True)[-1] == pytest.approx(12.0)
