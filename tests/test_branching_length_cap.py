"""Issue 23, structure stage: the length cap follows the example; a delta's distributaries reach the sea."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import SynthesisParams, example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._map_examples import crack_pattern_example, delta_mask_example
from branchnb.branching.growth import FILL_LENGTH_FACTOR, LENGTH_BOUND, LENGTH_FACTOR, length_cap
from branchnb.core.structure import Branch, Structure


def _line_example(shape=(100, 100)):
    pts = np.c_[np.linspace(2, shape[1] - 3, 60), np.full(60, shape[0] / 2)]
    return Structure([Branch(pts, 2.0)], image_shape=shape)


def test_auto_length_cap_scales_with_the_domain_area():
    ex = _line_example()
    m = fit_model(ex)
    L = m.example.total_length
    p = SynthesisParams()
    assert p.max_total_length == 0.0   # auto
    for shape in [(100, 100), (200, 100), (300, 300)]:
        assert length_cap(m, p, shape, None) == pytest.approx(LENGTH_FACTOR * L * shape[0] * shape[1] / 1e4)
    # a domain counts its own pixels
    dom = np.zeros((200, 200), bool)
    dom[:100] = True
    assert length_cap(m, p, (200, 200), dom) == pytest.approx(LENGTH_FACTOR * L * 2.0)
    # an explicit cap wins; the safety bound holds against an example denser than it
    assert length_cap(m, dataclasses.replace(p, max_total_length=123.0), (300, 300), None) == 123.0
    dense = fit_model(Structure([Branch(np.c_[np.full(40, 3.0 + 2 * i), np.linspace(2, 80, 40)], 1.0)
                                 for i in range(45)], image_shape=(100, 100)))
    assert length_cap(dense, p, (1000, 1000), None) == pytest.approx(LENGTH_BOUND * 1e6)


def test_synthesized_length_per_area_follows_the_example_at_another_size():
    # before: a fixed 20000 px cap (a 1000 px retina or cracked mud stopped short of the example's
    # density; a small example could grow 20000 px). Now the output's length per area is the example's
    ex = extract_structure(crack_pattern_example((160, 160), 2))
    model = fit_model(ex)
    per_area = model.example.total_length / (160 * 160)
    for shape in [(160, 160), (240, 240)]:
        for rng in (0, 1):
            r = synthesize_structure(model, shape=shape, rng=rng)
            ratio = r.structure.total_length / (shape[0] * shape[1]) / per_area
            assert 0.7 <= ratio <= 1.3 + 1e-6, (shape, rng, ratio)
            # the cap in force at the end: the hole fills' (the growth stopped at LENGTH_FACTOR x)
            assert r.diagnostics["max_total_length"] == pytest.approx(
                FILL_LENGTH_FACTOR * per_area * shape[0] * shape[1])


def _sea_share(structure, domain, tol):
    """Share of the leaf branches (no children) whose tip lies within ``tol`` px of the sea."""
    depth = ndi.distance_transform_edt(domain)
    h, w = domain.shape
    parents = {b.parent for b in structure.branches}
    ends = []
    for i, b in enumerate(structure.branches):
        if i not in parents:
            x, y = np.clip(np.rint(b.points[-1]).astype(int), 0, [w - 1, h - 1])
            ends.append(depth[y, x] <= tol)
    return float(np.mean(ends))


@pytest.mark.parametrize("size, seed", [(192, 0), (256, 1), (320, 2)])
def test_every_delta_distributary_reaches_the_sea(size, seed):
    # before: 17-60 % of the leaf channels at 512 px, 50-83 % after letting channels run on, ended
    # inland (stopped at a drawn length, by the coverage stop mid-way, or blocked by another channel)
    mask, _ch, _sea = delta_mask_example((size, size), seed)
    ex = extract_structure(mask)
    dom = example_domain(mask, ex)
    model = fit_model(ex, domain=dom)
    assert model.drains
    for rng in (0, 1):
        s = synthesize_structure(model, rng=rng).structure
        assert len(s.branches) >= 2
        assert _sea_share(s, dom, 2.0 * 4.0) == 1.0
