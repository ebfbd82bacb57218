"""An edit moves what was stroked: the body a stroked part grows out of stays where it was.

Beyond the paper (which drops unstroked parts): unstroked parts follow the stroke they hang from, but
the body a tail or twig grows out of is moved with the stroke's start only, never turned by it
(bending a tail swung a whole lizard round its hip and off the canvas).
"""

import cv2
import numpy as np
import pytest

from branchnb.strokes import edit_structure


def _animal(size: int, turn: float):
    """An RGBA body (a textured ellipse, turned by ``turn`` degrees) with a tail leaving it."""
    img = np.zeros((size, size, 4), np.float32)
    body = np.zeros((size, size), np.uint8)
    c = (int(0.38 * size), int(0.36 * size))
    cv2.ellipse(body, c, (int(0.2 * size), int(0.11 * size)), turn, 0, 360, 1, -1)
    tail = np.array([(0.52, 0.44), (0.62, 0.55), (0.7, 0.68), (0.76, 0.84)]) * size
    tail_mask = np.zeros_like(body)
    cv2.polylines(tail_mask, [tail.astype(np.int32)], False, 1, max(3, int(0.05 * size)))
    yy, xx = np.mgrid[:size, :size]
    stripes = 0.5 + 0.5 * np.sin((xx + yy) / (0.03 * size))
    obj = (body | tail_mask) > 0
    img[obj, 0] = 0.3 + 0.3 * stripes[obj]
    img[obj, 1] = 0.45
    img[obj, 2] = 0.2
    img[obj, 3] = 1.0
    start = tail[0] - (tail[1] - tail[0]) * 0.35  # drawn from inside the body, as a user does
    return img, body > 0, np.vstack([start, tail])


@pytest.mark.parametrize("size,turn", [(160, 0.0), (320, 20.0), (480, -15.0)])
def test_bending_a_tail_keeps_the_body_in_place(size, turn):
    img, body, tail = _animal(size, turn)
    t = np.linspace(0.0, 1.0, 12)[:, None]
    # the tail swung to the other side: down and to the left
    bent = tail[0] + np.hstack([-0.35 * size * np.sin(1.3 * t), 0.4 * size * t])
    out = edit_structure(img, [tail], [bent], rng=0)
    alpha = np.asarray(out.layer)[..., 3] > 0.5
    # the body away from the hip (where the new tail leaves it) is where it was
    hip = np.hypot(*(np.mgrid[:size, :size][::-1] - tail[1][:, None, None])) < 0.12 * size
    far = body & ~hip
    assert alpha[far].mean() >= 0.97
    # and nothing of the object lies where the body was not and the new tail does not go
    tube = np.zeros((size, size), np.uint8)
    cv2.polylines(tube, [bent.astype(np.int32)], False, 1, int(0.12 * size))
    stray = alpha & ~ndi_dilate(body, 3) & (tube == 0) & ~hip
    assert stray.sum() <= 0.01 * body.sum()
    # the new tail is drawn along its stroke
    on = alpha[np.round(bent[2:, 1]).astype(int).clip(0, size - 1), np.round(bent[2:, 0]).astype(int).clip(0, size - 1)]
    assert on.mean() >= 0.9


def ndi_dilate(mask, r):
    from scipy import ndimage as ndi

    return ndi.binary_dilation(mask, iterations=r)


@pytest.mark.parametrize("size,turn", [(160, 20.0), (320, 0.0), (320, 20.0)])
def test_the_body_keeps_its_hip_where_the_tail_left(size, turn):
    """The tail's tube took the convex cap of the body's contour at the hip; once the tail swings
    away the body has it back (strokes.hips): no bite deeper than 2 px (main: 4.5 / 8.5 / 14.8 px)."""
    img, body, tail = _animal(size, turn)
    t = np.linspace(0.0, 1.0, 12)[:, None]
    bent = tail[0] + np.hstack([-0.35 * size * np.sin(1.3 * t), 0.4 * size * t])
    alpha = np.asarray(edit_structure(img, [tail], [bent], rng=0).layer)[..., 3] > 0.5
    hip = np.hypot(*(np.mgrid[:size, :size][::-1] - tail[1][:, None, None])) < 0.2 * size
    from scipy import ndimage as ndi

    missing = body & ~alpha & hip
    depth = float(ndi.distance_transform_edt(body)[missing].max()) if missing.any() else 0.0
    assert depth <= 2.0, f"a bite {depth:.1f} px deep at the hip"
    # and the body did not grow a stump of the old tail there (160 px: 20 px up to 4.5 px out)
    grown = alpha & ~body & hip & ~ndi.binary_dilation(body, iterations=3)
    tube = np.zeros((size, size), np.uint8)
    cv2.polylines(tube, [bent.astype(np.int32)], False, 1, int(0.12 * size))
    assert int((grown & (tube == 0)).sum()) <= 0.005 * body.sum()
