"""Lightning on words and several separate objects (issue 25, dendrite40): the bolt traces
every letter's / object's outline instead of one horizontal bolt along the bottom of a word.

Procedural inputs with known masks: the "Oak" logo of the issue (bold red and blue letters
on cream with a drop shadow), a word on a dark ground, a row of blobs; one blob for
reference (its look is unchanged).
"""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from scipy import ndimage

from branchnb.dendrite import StylizeParams, Stylizer, stylize
from branchnb.dendrite.strike_outline import (
    OUTLINE_SPACING,
    outline_endpoints,
    outline_parts,
    outline_weights,
)


def _word(text, w, h, ground, ink, scale, thick, org, shadow=False):
    img = np.ones((h, w, 3), np.float32) * np.asarray(ground, np.float32)
    m = np.zeros((h, w), np.uint8)
    cv2.putText(m, text, org, cv2.FONT_HERSHEY_DUPLEX, scale, 255, thick, cv2.LINE_AA)
    mf = m.astype(np.float32) / 255
    if shadow:  # blurred copy offset by (4, 4) darkening the ground by 30 %
        sh = np.roll(cv2.GaussianBlur(mf, (0, 0), 3), (4, 4), (0, 1))
        img *= (1 - 0.3 * sh)[..., None]
    col = np.broadcast_to(np.asarray(ink[0], np.float32), img.shape).copy()
    if len(ink) > 1:  # left of x=192 the first colour, the rest the second
        col[:, 192:] = ink[1]
    img = img * (1 - mf[..., None]) + col * mf[..., None]
    return np.clip(img, 0, 1).astype(np.float32), mf > 0.5


def _blobs(w, h, ground, centres, r):
    img = np.ones((h, w, 3), np.float32) * np.asarray(ground, np.float32)
    yy, xx = np.mgrid[0:h, 0:w]
    mask = np.zeros((h, w), bool)
    for i, (cx, cy) in enumerate(centres):
        o = np.hypot(xx - cx * w, yy - cy * h) < r * min(w, h) * (1 + 0.12 * np.sin(3 * np.arctan2(
            yy - cy * h, xx - cx * w) + i))
        img[o] = ((0.85, 0.3, 0.1), (0.9, 0.7, 0.1), (0.3, 0.6, 0.1))[i % 3]
        mask |= o
    return img, mask


def _readability(mask, rendering):
    """Share of the ink within 3 px of the objects, and per object (>= 2 % of the picture)
    the share of its outline with ink within 4 px."""
    ink = np.asarray(rendering)[..., :3].mean(-1) > 0.5
    inside = ink[ndimage.binary_dilation(mask, iterations=3)].sum() / max(int(ink.sum()), 1)
    near = ndimage.distance_transform_edt(~ink) <= 4
    lab, n = ndimage.label(mask, np.ones((3, 3)))
    covers = []
    for i in range(1, n + 1):
        part = lab == i
        if part.sum() >= 0.02 * mask.size:
            covers.append(float(near[part & ~ndimage.binary_erosion(part)].mean()))
    return float(inside), covers


CASES = {
    # the issue's logo: before, one bolt along the letters' bottom (covers 0.25 / 0.08 / 0.33)
    "oak": lambda: _word("Oak", 480, 240, (0.96, 0.93, 0.85), [(0.75, 0.15, 0.1), (0.1, 0.35, 0.6)],
                         6.4, 12, (29, 180), shadow=True),
    # before: 0.06 / 0.09
    "hi_dark": lambda: _word("Hi", 300, 250, (0.08, 0.08, 0.12), [(0.95, 0.85, 0.3)], 5.5, 16, (20, 200)),
    # before: 0.15 / 0.04 / 0.04
    "fruits": lambda: _blobs(360, 240, (1, 1, 1), [(0.18, 0.55), (0.5, 0.45), (0.82, 0.55)], 0.2),
}


@pytest.mark.parametrize("name", list(CASES))
def test_lightning_traces_every_letter_and_object(name):
    img, mask = CASES[name]()
    out = stylize(img, metaphor="lightning", rng=0).rendering.image
    inside, covers = _readability(mask, out)
    assert len(covers) >= 2
    assert inside >= 0.85  # main: 0.86 / 0.97 / 0.84; branch 0.95 / 1.00 / 1.00
    assert min(covers) >= 0.4  # main: 0.08 / 0.06 / 0.04; branch 0.64 / 0.73 / 0.79


def test_one_object_keeps_the_papers_bolt():
    img, mask = _blobs(260, 220, (1, 1, 1), [(0.5, 0.5)], 0.3)
    st = Stylizer(img)
    out = st.run(StylizeParams(), metaphor="lightning", rng=0)
    assert st._traced_outlines(out.params) is None
    # the bolt forks inside the blob, off its outline
    inside, covers = _readability(mask, out.rendering.image)
    assert inside > 0.97 and covers[0] < 0.25


def test_outline_parts_split_at_a_thin_neck_only():
    m = np.zeros((100, 100), bool)
    m[20:80, 5:40] = m[20:80, 55:95] = True
    m[48:51, 40:55] = True  # a 3-px bridge (a shadow's or a blurred edge's)
    assert outline_parts(m).max() == 2
    m[30:70, 40:55] = True  # a wide waist: one object
    assert outline_parts(m).max() == 1
    m[2:4, 2:4] = True  # a speck is no part
    assert outline_parts(m).max() == 1


def test_outline_endpoints_lie_on_each_parts_outline():
    c = np.zeros((120, 200), bool)
    c[20:100, 10:80] = True
    c[40:60, 30:60] = False  # a hole: its outline counts too
    c[20:100, 120:190] = True
    parts = outline_parts(c)
    e = outline_endpoints(c, parts, rng=1)
    xy = e.astype(int)
    edge = c & ~ndimage.binary_erosion(c)
    assert edge[xy[:, 1], xy[:, 0]].all()
    per_part = np.bincount(parts[xy[:, 1], xy[:, 0]], minlength=3)[1:]
    assert per_part.min() >= 6
    on_hole = (xy[:, 0] >= 29) & (xy[:, 0] <= 60) & (xy[:, 1] >= 39) & (xy[:, 1] <= 60)
    assert on_hole.sum() >= 2  # its rim is 2 x (30 + 20) px long
    d = np.hypot(*(e[:, None] - e[None]).T)
    assert d[np.triu_indices(len(e), 1)].min() >= OUTLINE_SPACING * np.hypot(120, 200) - 1e-9


def test_outline_weights_checks_shapes():
    with pytest.raises(ValueError, match="share a shape"):
        outline_weights(np.ones((4, 4)), np.ones((4, 5)), np.ones((4, 4), bool), np.ones((4, 4), int))


def test_a_piece_of_small_cores_stays_one_part():
    m = np.zeros((100, 100), bool)
    m[10:90, 5:45] = True  # one object
    # another, whose two cores (joined by a 2-px neck) are each under 2 % of the picture
    m[40:52, 60:72] = m[40:52, 80:92] = True
    m[45:47, 72:80] = True
    assert outline_parts(m).max() == 2
