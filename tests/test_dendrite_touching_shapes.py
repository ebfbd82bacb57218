"""Objects of one colour touching along a wide stretch are split by shape, each traced by the
bolt (issue 25, dendrite42: :func:`split_by_shape`); single convex or elongated objects are not
split."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from scipy import ndimage

from branchnb.dendrite import stylize
from branchnb.dendrite.strike_outline import outline_parts, split_by_shape


def _discs(n: int, kind: str):
    """Label image of touching objects: ``discs`` (2, centres 1.4 radii apart), ``row3`` (3,
    1.5 apart), ``snowman`` (radii 1.3 and 1, 1.9 apart), ``pebbles`` (two bumpy ovals)."""
    h, w = int(0.7 * n), n
    yy, xx = np.mgrid[0:h, 0:w]
    if kind == "discs":
        r = 0.22 * n
        objs = [(w / 2 - 0.7 * r, h / 2, r, r), (w / 2 + 0.7 * r, h / 2, r, r)]
    elif kind == "row3":
        r = 0.15 * n
        objs = [(w / 2 + (i - 1) * 1.5 * r, h / 2, r, r) for i in range(3)]
    elif kind == "snowman":
        r = 0.2 * h
        objs = [(w / 2, h / 2 + 0.9 * r, 1.3 * r, 1.3 * r), (w / 2, h / 2 - r, r, r)]
    else:
        r = 0.18 * n
        objs = [(w / 2 - 0.8 * r, h / 2, 1.15 * r, r), (w / 2 + 0.8 * r, h / 2 + 0.1 * r, 1.04 * r, 0.9 * r)]
    lab = np.zeros((h, w), int)
    for i, (cx, cy, rx, ry) in enumerate(objs, 1):
        ang = np.arctan2(yy - cy, xx - cx)
        bump = 1 + sum(0.04 * np.sin(k * ang + 2 * i + k) for k in range(2, 6))
        m = np.hypot((xx - cx) / rx, (yy - cy) / ry) < bump
        lab[m & (lab == 0)] = i
    return lab


def _iou_best(parts, lab):
    return min(max(((parts == j) & (lab == k)).sum() / ((parts == j) | (lab == k)).sum()
                   for j in range(1, parts.max() + 1)) for k in range(1, lab.max() + 1))


@pytest.mark.parametrize("n", [128, 400, 1000])
@pytest.mark.parametrize("kind", ["discs", "row3", "snowman", "pebbles"])
def test_touching_objects_of_one_colour_are_split_at_their_neck(kind, n):
    lab = _discs(n, kind)
    parts = outline_parts(lab > 0)
    assert parts.max() == lab.max()
    # (row3: the ground truth gives both overlaps to the outer discs, the split halves them)
    assert _iou_best(parts, lab) >= 0.8


def _singles(n: int, seed: int):
    rng = np.random.default_rng(seed)
    h, w = int(0.7 * n), n
    yy, xx = np.mgrid[0:h, 0:w]
    cx, cy = w / 2, h / 2
    ang = np.arctan2(yy - cy, xx - cx)
    out = {"disc": np.hypot(xx - cx, yy - cy) < 0.3 * h,
           "ellipse": np.hypot((xx - cx) / 3, yy - cy) < 0.13 * w,
           "square": (np.abs(xx - cx) < 0.3 * h) & (np.abs(yy - cy) < 0.3 * h)}
    bump = sum(rng.uniform(0, 0.08) * np.sin(k * ang + rng.uniform(0, 6)) for k in range(2, 7))
    out["blob"] = np.hypot(xx - cx, yy - cy) < 0.3 * h * (1 + bump)
    cap = np.zeros((h, w), np.uint8)
    cv2.line(cap, (int(0.15 * w), int(0.3 * h)), (int(0.85 * w), int(0.7 * h)), 1, int(0.15 * h))
    out["capsule"] = cap > 0
    worm = np.zeros((h, w), np.uint8)  # a thick stroke whose width jumps between 8 and 12 %
    pts = np.stack([np.linspace(0.1, 0.9, 40) * w, (0.5 + 0.1 * np.sin(np.linspace(0, 7, 40))) * h], 1)
    for (x0, y0), (x1, y1), t in zip(pts[:-1], pts[1:], rng.uniform(0.08, 0.12, 39) * h):
        cv2.line(worm, (int(x0), int(y0)), (int(x1), int(y1)), 1, int(t))
    out["worm"] = worm > 0
    arc = np.zeros((h, w), np.uint8)
    cv2.ellipse(arc, (int(cx), int(cy + 0.3 * h)), (int(0.35 * w), int(0.5 * h)), 0, 200, 340, 1,
                max(3, int(0.08 * h)))
    out["banana"] = arc > 0
    return out


@pytest.mark.parametrize("n", [128, 300, 1000])
def test_single_convex_or_elongated_objects_stay_one_part(n):
    for seed in (0, 1):
        for name, m in _singles(n, seed).items():
            assert outline_parts(m).max() == 1, (name, seed)
    m = _singles(200, 0)["disc"]
    assert split_by_shape(m, 0.02 * m.size) is None


def test_lightning_traces_each_of_two_touching_discs():
    lab = _discs(300, "discs")
    img = np.ones((*lab.shape, 3), np.float32)
    img[lab > 0] = (0.15, 0.15, 0.2)
    pic = np.asarray(stylize(img, metaphor="lightning", rng=0).rendering.image)[..., :3]
    near = ndimage.distance_transform_edt(~(pic.mean(-1) > 0.5)) <= 4
    covers = [near[(lab == k) & ~ndimage.binary_erosion(lab == k)].mean() for k in (1, 2)]
    assert min(covers) >= 0.6  # before: 0.03-0.08 (one bolt through both)
