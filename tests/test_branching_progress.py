"""synthesize_structure(progress=...): partial skeletons while the structure grows."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import Branch, Structure, SynthesisParams, fit_model, synthesize_structure


def _example() -> Structure:
    t = np.linspace(0, 1, 80)
    trunk = np.c_[15 + 270 * t, 100 + 25 * np.sin(7 * t)]
    s = Structure([Branch(trunk, np.linspace(4, 2, len(t)))], image_shape=(200, 300))
    for v, side in ((20, -1), (45, 1)):
        u = np.linspace(0, 1, 25)[:, None]
        s.add_branch(trunk[v] + u * 70 * np.array([0.6, side * 0.8]), 1.5, parent=0, parent_vertex=v)
    return s


def _is_prefix(part: Structure, full: Structure) -> bool:
    if len(part.branches) > len(full.branches):
        return False
    for a, b in zip(part.branches, full.branches):
        n = len(a.points)
        if n > len(b.points) or (a.parent, a.parent_vertex) != (b.parent, b.parent_vertex):
            return False
        if not (np.array_equal(a.points, b.points[:n]) and np.array_equal(a.thickness, b.thickness[:n])):
            return False
    return True


@pytest.fixture(scope="module")
def model():
    return fit_model(_example(), SynthesisParams())


def test_partial_skeletons_are_parts_of_the_result(model):
    reports = []
    res = synthesize_structure(model, rng=3, progress=lambda g: reports.append(
        (g.attempt, g.fraction, g.done, g.steps, g.structure())))
    plain = synthesize_structure(model, rng=3)
    assert res.structure.to_json() == plain.structure.to_json()  # watching changes nothing
    assert len(reports) > 5 and reports[-1][2] and reports[-1][1] == 1.0
    assert not any(done for _, _, done, _, _ in reports[:-1])
    assert reports[-1][4].to_json() == res.structure.to_json()
    final_attempt = res.diagnostics["attempts"]
    mine = [r for r in reports[:-1] if r[0] == final_attempt]
    assert mine and all(_is_prefix(r[4], res.structure) for r in mine)
    sizes = [r[4].n_vertices for r in mine]
    assert sizes == sorted(sizes) and sizes[0] < res.structure.n_vertices
    fr = [r[1] for r in mine]
    assert all(0.0 <= f < 1.0 for f in fr) and fr == sorted(fr)
    steps = [r[3] for r in mine]
    assert steps == sorted(steps)


def test_raising_in_progress_stops_the_synthesis(model):
    class Stop(Exception):
        pass

    seen = []

    def stop_at_ten(g):
        seen.append(g.steps)
        if g.steps >= 10:
            raise Stop

    with pytest.raises(Stop):
        synthesize_structure(model, rng=0, progress=stop_at_ten)
    assert max(seen) == 10


def test_progress_must_be_callable(model):
    with pytest.raises(TypeError, match="progress"):
        synthesize_structure(model, rng=0, progress=3)
