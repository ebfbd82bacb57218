"""The app's preview seed (no click) is the full update's: on a drawing whose ground is its
paper (neon on black, chalk on a board, ink on pink card) :meth:`Stylizer.default_seed` finds
it on the levelled picture, as :meth:`Stylizer.run` does (issue 25, dendrite42)."""

import cv2
import numpy as np
import pytest

from branchnb.dendrite import StylizeParams, Stylizer


def _drawing(size: int, ground, ink, where, seed: int):
    """A star outline and a small ring drawn off-centre (at ``where``, shares of the frame)."""
    rng = np.random.default_rng(seed)
    w, h = size, size * 3 // 4
    img = np.ones((h, w, 3), np.float32) * np.asarray(ground, np.float32)
    img += cv2.GaussianBlur(rng.normal(0, 0.03, (h, w)).astype(np.float32), (0, 0), 2)[..., None]
    lines = np.zeros((h, w), np.float32)
    t = max(2, w // 90)
    cx, cy, r = int(where[0] * w), int(where[1] * h), w // 7
    a = np.pi / 2 + np.arange(10) * np.pi / 5
    rr = np.where(np.arange(10) % 2 == 0, r, 0.45 * r)
    pts = np.stack([cx + rr * np.cos(a), cy - rr * np.sin(a)], 1)
    cv2.polylines(lines, [np.int32(pts)], True, 1.0, t, cv2.LINE_AA)
    cv2.circle(lines, (cx + int(1.3 * r), cy + int(0.9 * r)), r // 3, 1.0, t, cv2.LINE_AA)
    img = img * (1 - lines[..., None]) + lines[..., None] * np.asarray(ink, np.float32)
    return img.clip(0, 1)


CASES = [  # ground, ink, where; before the fix the seeds lay 1-2.4 % of the diagonal apart
    ((0.05, 0.06, 0.15), (0.4, 1.0, 1.0), (0.25, 0.3)),  # neon
    ((0.12, 0.2, 0.16), (0.9, 0.9, 0.9), (0.7, 0.35)),  # chalk
    ((0.85, 0.78, 0.82), (0.1, 0.1, 0.1), (0.3, 0.6)),  # pink card
]


@pytest.mark.parametrize("size", [160, 400])
@pytest.mark.parametrize("ground,ink,where", CASES, ids=["neon", "chalk", "pink card"])
def test_preview_seed_is_the_full_updates(size, ground, ink, where):
    img = _drawing(size, ground, ink, where, seed=size)
    st = Stylizer(img)
    p = StylizeParams()
    full = st.run(p, rng=0, metaphor="plain").seed
    pre = st.default_seed(p, metaphor="plain")
    assert np.hypot(*(pre - full)) <= 0.003 * np.hypot(*img.shape[:2])


def test_vines_and_white_paper_keep_the_picture_as_it_is():
    img = _drawing(200, (0.05, 0.06, 0.15), (0.4, 1.0, 1.0), (0.25, 0.3), seed=1)
    st, p = Stylizer(img), StylizeParams()
    assert np.array_equal(st.default_seed(p, metaphor="vines"), st._importance_seed(p))
    white = _drawing(200, (0.97, 0.97, 0.97), (0.1, 0.1, 0.1), (0.3, 0.6), seed=1)
    sw = Stylizer(white)
    assert np.array_equal(sw.default_seed(p), sw._importance_seed(p))
    with pytest.raises(ValueError, match="metaphor"):
        st.default_seed(p, metaphor="ink")


@pytest.mark.parametrize("metaphor", ["lightning", "vines"])
@pytest.mark.parametrize("ground,ink,where", CASES[:2] + [((0.97, 0.97, 0.97), (0.1, 0.1, 0.1), (0.3, 0.6))],
                         ids=["neon", "chalk", "white paper"])
def test_start_seed_is_where_run_starts(metaphor, ground, ink, where):
    # the app's preview asked default_seed for every metaphor: a bolt's preview trunk started 10-53 % of
    # the diagonal from the full update's (which starts at the top of the content), vines' 3-5 %
    img = _drawing(200, ground, ink, where, seed=3)
    st, p = Stylizer(img), StylizeParams()
    full = st.run(p, rng=0, metaphor=metaphor).seed
    assert np.allclose(st.start_seed(p, metaphor=metaphor), full)


def test_start_seed_checks_its_metaphor():
    st = Stylizer(_drawing(120, (0.97, 0.97, 0.97), (0.1, 0.1, 0.1), (0.3, 0.6), seed=1))
    assert np.array_equal(st.start_seed(StylizeParams(), "plain"), st.default_seed(StylizeParams(), "plain"))
    with pytest.raises(ValueError, match="metaphor"):
        st.start_seed(StylizeParams(), metaphor="ink")
