"""Issue 23, ornaments (branching70): a band's children stay in the band its example's strands sweep, a
band the user paints gets a core too, and children leave at the example's angles (no angle bin filled
past its share).

Known answers: procedural interlaced bands (:func:`branchnb.branching._band_examples.band_envelope`: the
strands' centre path and swing are known; :func:`branchnb.branching._child_check.painted_band`).
"""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._child_check import envelope_figures, example_envelope, example_image, painted_band
from branchnb.branching.child_angles import _AngleMatch
from branchnb.branching.growth import _core
from branchnb.core.structure import Branch, Structure


def _fitted(kind, size, seed):
    img = example_image(kind, size, seed)
    ex = extract_structure(img)
    return img, fit_model(ex, domain=example_domain(img, ex))


@pytest.mark.parametrize("kind,size,seed,bound", [("frame", 512, 0, 0.2), ("S", 256, 0, 0.3)])
def test_band_children_stay_in_the_swept_band(kind, size, seed, bound):
    _img, model = _fitted(kind, size, seed)
    out = synthesize_structure(model, rng=seed).structure
    f = envelope_figures(out, example_envelope(kind, size, seed))
    # main: length outside the band frame 0.45, S 0.42
    assert f["lout"] <= bound, f
    assert out.total_length >= 0.8 * model.example.total_length


def test_painted_band_gets_the_examples_proportions():
    from branchnb.branching.empty_ground import _painted_core  # main: none

    ex = np.zeros((100, 200), bool)
    ex[20:60] = True
    core = np.zeros((100, 200), bool)
    core[30:50] = True                              # the strands fill half the example's band domain
    user = np.zeros((150, 150), bool)
    user[:, 40:100] = True                          # a 60 px band: its middle 30 px
    c = _painted_core(ex, core, user)
    cols = np.flatnonzero(c[75])
    assert 29 <= len(cols) <= 33 and abs(cols.mean() - 69.5) < 1.0


def test_painted_band_domain_has_a_core_and_strands_keep_to_it():
    img, model = _fitted("paint", 512, 1)
    dom, env = painted_band(img, model.domain, 512, 1)
    got = _core(model, dom)
    assert got is not None                          # main: None (no core off the model's own domain)
    core = got[0]
    assert core.sum() < 0.7 * dom.sum() and (core & env).sum() > 0.6 * core.sum()
    out = synthesize_structure(model, rng=1, domain=dom).structure
    # main: 0.52 of the length outside the painted band's middle
    assert envelope_figures(out, env)["lout"] <= 0.35


def test_a_full_angle_bin_is_refused():
    t = np.arange(0.0, 200.0)
    par = Branch(np.c_[t, np.full(200, 100.0)], 2.0)
    kids = [Branch(np.c_[x + t[:30] * np.cos(a), 100 + t[:30] * np.sin(a)], 1.0, parent=0, parent_vertex=int(x))
            for x, a in [(30, 0.7), (60, 0.72), (90, 0.74), (120, 2.1)]]   # three at 40-42 deg, one at 120
    m = _AngleMatch(Structure([par] + kids))
    assert m.ok
    m.add(41.0)
    m.add(121.0)
    f = m.factor(np.array([41.0, 121.0, 170.0]))
    # the backward bin holds its share (1 of 4) already, the 165-180 bin none of the example's
    assert f[1] < 1e-3 * f[0] and f[2] < 1e-3 * f[0]
    # main: 121 deg scored 0.0025 x 41 deg, 170 deg 0.05 x
