"""Stroke editing of opaque pictures on plain or smooth grounds (issue 25).

An opaque image's object used to be the union of the patches copied round
the strokes: bending a twig of a branch photographed on white gave the bent
twig alone, on a sky with sky-coloured boxes round it. Now the object is cut
out with a soft matte (core.matte) and the edit is painted over the photo's
own ground, the vacated area filled: only the stroked part changes.
"""

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi
from test_core_matte import _ground

from branchnb import data
from branchnb.core.image import composite_over
from branchnb.strokes import StrokeEditParams, edit_structure
from branchnb.strokes.procedural import figure


def _branch(size, kind, jpeg=False):
    """A bark-textured branch leaving the frame, a side twig, its stroke and the twig bent the other way."""
    h, w = int(0.75 * size), size
    yy, xx = np.mgrid[:h, :w].astype(np.float32)
    twig = np.array([(0.45 * w, 0.585 * h), (0.55 * w, 0.4 * h), (0.62 * w, 0.2 * h)], np.float32)
    d = np.full((h, w), np.inf, np.float32)
    for pts, hw in ((np.float32([(-5, 0.62 * h), (0.5 * w, 0.58 * h), (0.95 * w, 0.5 * h)]), 0.03 * size),
                    (twig, 0.012 * size)):
        for a, b in zip(pts[:-1], pts[1:]):
            ab = b - a
            t = np.clip(((xx - a[0]) * ab[0] + (yy - a[1]) * ab[1]) / (ab @ ab), 0, 1)
            d = np.minimum(d, np.hypot(xx - a[0] - t * ab[0], yy - a[1] - t * ab[1]) - hw)
    alpha = np.clip(0.5 - d, 0, 1)
    bark = 0.5 + 0.5 * np.sin(xx / (0.012 * size) + np.sin(yy / 3.0))
    col = np.stack([0.32 + 0.15 * bark, 0.22 + 0.1 * bark, 0.12 + 0.05 * bark], -1)
    g = _ground(kind, h, w)
    img = (alpha[..., None] * col + (1 - alpha[..., None]) * g).astype(np.float32)
    if jpeg:
        _, buf = cv2.imencode(".jpg", (img[..., ::-1] * 255).astype(np.uint8), [cv2.IMWRITE_JPEG_QUALITY, 85])
        img = cv2.imdecode(buf, 1)[..., ::-1].astype(np.float32) / 255
    t = np.linspace(0, 1, 12)[:, None]
    bent = twig[0] + np.hstack([-0.25 * w * np.sin(1.2 * t), -0.38 * h * t])
    return img, alpha, g, twig, bent


def _measures(res, alpha_in, g, strokes, reach):
    h, w = alpha_in.shape
    near = np.zeros((h, w), np.uint8)
    for st in strokes:
        cv2.polylines(near, [np.round(st).astype(np.int32)], False, 1, int(2 * reach))
    far = near == 0
    a_in, a_out = alpha_in > 0.5, res.layer[..., 3] > 0.5
    iou = (a_in & a_out & far).sum() / max(((a_in | a_out) & far).sum(), 1)
    ground = ~ndi.binary_dilation(a_out | (res.layer[..., 3] > 0.02), iterations=2)
    err = np.abs(res.image[..., :3] - g)
    rms = float(np.sqrt(np.mean(err[ground] ** 2)))
    boxes = float(cv2.blur(np.where(ground, err.max(axis=2), 0).astype(np.float32), (15, 15)).max())
    return iou, rms, boxes


@pytest.mark.parametrize("size,kind,jpeg", [(200, "white", False), (400, "sky", False), (400, "white", True),
                                            (300, "diag", True), (240, "paper", False)])
def test_bending_a_twig_keeps_the_branch_and_the_ground(size, kind, jpeg):
    img, alpha, g, twig, bent = _branch(size, kind, jpeg)
    res = edit_structure(img, [twig], [bent])
    assert res.image.shape[2] == 4 and res.image[..., 3].min() >= 0.999  # painted over the photo's ground
    iou, rms, boxes = _measures(res, alpha, g, [twig, bent], 0.1 * size)
    assert iou >= 0.95           # the main branch is where it was
    assert rms <= 0.03           # the ground outside the object is the input's
    assert boxes <= 0.06         # no box of another ground colour round the moved twig
    # the bent twig is drawn along its stroke
    pts = np.round(bent[3:]).astype(int)
    assert (res.layer[pts[:, 1].clip(0, img.shape[0] - 1), pts[:, 0].clip(0, img.shape[1] - 1), 3] > 0.5).mean() >= 0.9
    # and the old twig is gone: its pixels show the ground again
    gone = (alpha > 0.5) & (res.layer[..., 3] < 0.02)
    assert gone.sum() >= 0.5 * 0.024 * size * 0.3 * size
    assert np.sqrt(np.mean((res.image[..., :3][gone] - g[gone]) ** 2)) <= 0.04


def test_paper_switch_keeps_the_opaque_behaviour():
    img, alpha, g, twig, bent = _branch(200, "sky")
    res = edit_structure(img, [twig], [bent], StrokeEditParams(separate_ground=False))
    iou, _, _ = _measures(res, alpha, g, [twig, bent], 20)
    assert iou <= 0.5            # the object is the copied patches only: the branch is gone


@pytest.mark.parametrize("kind", ["paper", "diag"])
def test_raising_a_drawn_figures_arm_on_a_ground(kind):
    obj = figure(200, rng=0)
    h, w = obj.image.shape[:2]
    g = _ground(kind, h, w)
    img = composite_over(obj.image, g)
    arm = obj.strokes[2]
    c, s = np.cos(0.9), np.sin(0.9)
    raised = (arm - arm[0]) @ np.array([[c, -s], [s, c]]).T + arm[0]
    res = edit_structure(img, [arm], [raised])
    ref = edit_structure(obj.image, [arm], [raised])   # the same object given with its alpha
    iou, rms, boxes = _measures(res, obj.image[..., 3], g, [arm, raised], 3 * obj.widths[2] + 14)
    assert iou >= 0.95 and rms <= 0.03 and boxes <= 0.06
    a, b = res.layer[..., 3] > 0.5, ref.layer[..., 3] > 0.5
    assert (a & b).sum() / (a | b).sum() >= 0.95


def test_busy_photo_keeps_todays_behaviour():
    img = data.load("chelsea")[100:200, 100:260]
    st = [[(20, 50), (140, 60)]]
    tgt = [[(20, 60), (140, 40)]]
    a = edit_structure(img, st, tgt, StrokeEditParams(patch_size=24))
    b = edit_structure(img, st, tgt, StrokeEditParams(patch_size=24, separate_ground=False))
    assert np.array_equal(a.image, b.image)
