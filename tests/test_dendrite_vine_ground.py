"""Vines on pictures without white paper (issue 25): the endpoint count follows the area
of the object that stands out from the picture's own ground, not the whole frame.

Procedural pictures with a known object mask: a shaded bottle on a grey wall and a
darker table, a charcoal cat on a dark textured ground, and a drawn ellipse on white.
"""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage
from skimage import draw

from branchnb.dendrite import StylizeParams, Stylizer, stylize
from branchnb.dendrite.stylization import effective_params
from branchnb.dendrite.stylize_params import _ground_threshold, _vine_sizes


def _bottle(n):
    h, w = n, int(0.8 * n)
    yy, xx = np.mgrid[0:h, 0:w] / n
    img = (0.62 + 0.08 * xx).astype(np.float32)  # grey wall
    table = yy > 0.72
    img[table] = 0.45 - 0.1 * (yy[table] - 0.72)
    cx = 0.4
    m = ((np.abs(xx - cx) < 0.11) & (yy > 0.35) & (yy < 0.78)) | (
        (np.abs(xx - cx) < 0.035) & (yy > 0.12) & (yy <= 0.35)) | (
        ((xx - cx) ** 2 / 0.11 ** 2 + (yy - 0.35) ** 2 / 0.08 ** 2 < 1) & (yy <= 0.35))
    img[m] = (0.15 + 0.5 * np.clip(1 - np.abs(xx - cx + 0.04) / 0.08, 0, 1) ** 2)[m]
    img += np.random.default_rng(0).normal(0, 0.015, img.shape).astype(np.float32)
    img = ndimage.gaussian_filter(img, n / 500)
    return np.clip(np.stack([img, 0.98 * img, 0.95 * img], -1), 0, 1).astype(np.float32), m


def _cat(n):
    rng = np.random.default_rng(1)
    yy, xx = np.mgrid[0:n, 0:n] / n
    tex = ndimage.gaussian_filter(rng.normal(0, 1, (n, n)), n / 150)
    img = (0.32 + 0.06 * tex / tex.std()).astype(np.float32)  # dark textured ground
    m = ((xx - 0.5) ** 2 / 0.2 ** 2 + (yy - 0.62) ** 2 / 0.16 ** 2 < 1) | (
        (xx - 0.5) ** 2 + (yy - 0.36) ** 2 < 0.11 ** 2)
    strokes = ndimage.gaussian_filter(rng.normal(0, 1, (n, n)), [n / 400, n / 80])
    img[m] = (0.1 + 0.05 * strokes / strokes.std())[m]  # charcoal
    img = ndimage.gaussian_filter(img, n / 600)
    return np.clip(np.stack([img] * 3, -1), 0, 1).astype(np.float32), m


def _on_white(n):
    img = np.ones((n, n), np.float32)
    m = np.zeros((n, n), bool)
    rr, cc = draw.ellipse(n // 2, n // 2, int(0.25 * n), int(0.18 * n), (n, n), rotation=0.4)
    m[rr, cc] = True
    img[m] = 0.35
    return np.stack([ndimage.gaussian_filter(img, n / 500)] * 3, -1), m


def _expected(img, mask):
    # tips for the object's area with leaves sized to it, at least one per leaf length of
    # its outline (stylize_params._vine_sizes)
    outline = float((mask & ~ndimage.binary_erosion(mask)).sum())
    return _vine_sizes(img.shape[:2], float(mask.sum()), outline)[1]


@pytest.mark.parametrize("make", [_bottle, _cat])
@pytest.mark.parametrize("n", [200, 400])
def test_vine_tips_follow_the_object_not_the_frame(make, n):
    img, mask = make(n)
    s = stylize(img, rng=0, metaphor="vines")
    expect = _expected(img, mask)
    # main: 5-7x the object's count (the whole frame passed the threshold)
    assert 0.6 * expect < len(s.endpoints) < 1.6 * expect



@pytest.mark.parametrize("n", [200, 400])
def test_vine_tips_lie_on_an_object_darker_than_its_ground(n):
    img, mask = _bottle(n)
    s = stylize(img, rng=0, metaphor="vines")
    # the tips lie on the bottle, not on the wall and table (main: 0.15-0.2)
    near = ndimage.binary_dilation(mask, iterations=max(1, n // 100))
    x, y = np.round(s.endpoints).astype(int).T
    assert near[y.clip(0, mask.shape[0] - 1), x.clip(0, mask.shape[1] - 1)].mean() > 0.8


@pytest.mark.parametrize("n", [200, 500])
def test_pictures_on_white_keep_the_papers_share(n):
    img, mask = _on_white(n)
    st = Stylizer(img)
    p = effective_params(StylizeParams(), float(np.sqrt(np.prod(st.scale(StylizeParams())))))
    imp = st.importance(p)
    assert _ground_threshold(imp, p.endpoint_threshold) == p.endpoint_threshold
    s = st.run(rng=0, metaphor="vines")
    assert s.params.endpoint_threshold == StylizeParams().endpoint_threshold
    assert 0.6 * _expected(img, mask) < len(s.endpoints) < 1.6 * _expected(img, mask)


def test_ground_shift_ramps_without_a_jump():
    """From a ground at half the threshold (paper) to one at the threshold the share falls
    smoothly: no jump in the tip count as a picture's ground darkens."""
    rng = np.random.default_rng(0)
    obj = np.zeros((100, 100), np.float32)
    obj[30:70, 30:70] = 0.4
    shares = []
    for g in np.linspace(0.0, 0.12, 49):
        imp = np.clip(obj + g + rng.uniform(-0.002, 0.002, obj.shape), 0, 1).astype(np.float32)
        shares.append(float((imp >= _ground_threshold(imp, 0.05)).mean()))
    shares = np.array(shares)
    assert shares[0] == pytest.approx(0.16, abs=1e-3)  # white: the object alone
    assert np.abs(np.diff(shares)).max() < 0.3  # no step from the object to the frame
    assert shares[-1] == pytest.approx(0.16, abs=1e-3)  # dark ground: the object again
