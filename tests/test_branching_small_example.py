"""Small examples (icons, thumbnails): fitted at a finer step instead of refused (beyond the paper)."""
import warnings

import cv2
import numpy as np
import pytest

from branchnb.branching import (
    Branch,
    Structure,
    SynthesisParams,
    extract_structure,
    fit_model,
    synthesize_image,
    synthesize_structure,
)


def _small_tree(scale=1.0):
    """A 60 px trunk with two 25 px children: too short for k + m = 16 steps of 4 px."""
    t = np.linspace(0, 1, 30)[:, None]
    trunk = np.hstack([10 + 60 * t, 40 + 6 * np.sin(3 * t)]) * scale
    s = Structure([Branch(trunk, 2.0 * scale)], image_shape=(int(80 * scale), int(80 * scale)))
    for i, sign in ((10, 1), (20, -1)):
        p0 = trunk[i]
        s.add_branch(p0 + np.hstack([18 * t, sign * 18 * t]) * scale, 1.2 * scale, parent=0, parent_vertex=i)
    return s


def test_a_short_example_is_fitted_at_a_finer_step_with_a_warning():
    ex = _small_tree()
    with pytest.warns(UserWarning, match="small example"):
        model = fit_model(ex)
    p = SynthesisParams()
    assert model.requested_h == p.h
    assert 1.0 <= model.params.h < p.h
    longest = max(len(b.points) for b in model.example.branches)
    assert longest >= p.k + p.m + 2
    # the default parameters are still "compatible": no refit (which would warn again) per synthesis
    assert model.compatible(p)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        res = synthesize_structure(model, rng=0)
        res2 = synthesize_structure(model, p, rng=0)
    assert res.structure.n_vertices > 10
    assert res.structure.n_vertices == res2.structure.n_vertices
    # synthesis walks at the model's step, not at the paper's 4 px
    steps = np.concatenate([np.hypot(*np.diff(b.points, axis=0).T) for b in res.structure.branches
                            if len(b.points) > 2])
    assert abs(float(np.median(steps)) - model.params.h) < 0.25 * model.params.h


def test_an_example_long_enough_is_unchanged():
    ex = _small_tree(scale=3.0)
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        model = fit_model(ex)
    assert model.requested_h is None and model.params.h == SynthesisParams().h


def test_a_96px_river_goes_through_the_default_workflow():
    n = 96
    img = np.zeros((n, n, 3), np.float32) + (0.55, 0.75, 0.45)
    pts = np.int32([[48, 95], [45, 80], [52, 62], [48, 42]])
    cv2.polylines(img, [pts], False, (0.25, 0.45, 0.85), 4, cv2.LINE_AA)
    cv2.line(img, (50, 64), (30, 48), (0.25, 0.45, 0.85), 2, cv2.LINE_AA)
    ex = extract_structure(img)
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", UserWarning)
        model = fit_model(ex)
        tgt = synthesize_structure(model, rng=1).structure
        out = synthesize_image(img, ex, tgt, rng=1).image
    assert tgt.n_vertices > 5
    blue = (out[..., 2] > out[..., 1] + 0.1)
    assert 20 < int(blue.sum()) < 0.2 * n * n
