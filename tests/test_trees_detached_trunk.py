"""Icon-style trees whose trunk is drawn apart from the crown keep their trunk (issue 24)."""

import cv2
import numpy as np
import pytest

from branchnb.trees.detached_trunk import _detached_trunk, _join_detached_trunk
from branchnb.trees.library import TreeLibrary

OUTLINE = (0.1, 0.08, 0.05, 1.0)


def _icon(kind: str, gap: int, size: int, seed: int) -> np.ndarray:
    """Flat outlined tree, a rectangular trunk ``gap`` px below the crown (4x supersampled)."""
    r = np.random.default_rng(seed)
    ss = 4
    n = size * ss
    img = np.zeros((n, n, 4), np.float32)
    cx = n // 2
    tw, th = int(n * r.uniform(0.07, 0.11)), int(n * r.uniform(0.18, 0.28))
    foot = int(n * 0.95)
    ttop = foot - th
    bottom = ttop - gap * ss
    lw = max(ss, int(n * 0.008))
    green = (0.2, 0.55 + 0.2 * r.random(), 0.2, 1.0)
    cv2.rectangle(img, (cx - tw // 2, ttop), (cx + tw // 2, foot), (0.5, 0.28, 0.12, 1.0), -1)
    cv2.rectangle(img, (cx - tw // 2, ttop), (cx + tw // 2, foot), OUTLINE, lw)
    if kind == "conifer":
        w, top = int(n * 0.32), int(n * 0.05)
        for k in range(3):
            yb = bottom - k * (bottom - top) // 4
            pts = np.array([[cx - w + k * w // 5, yb], [cx + w - k * w // 5, yb], [cx, top]], np.int32)
            cv2.fillPoly(img, [pts], green)
            cv2.polylines(img, [pts], True, OUTLINE, lw)
    else:
        rad = int(n * 0.2)
        cy = bottom - rad
        blobs = [(cx, cy, rad, rad)] + [
            (cx + int(r.uniform(-0.6, 0.6) * rad), cy + int(r.uniform(-0.6, 0.2) * rad),
             int(rad * r.uniform(0.5, 0.8)), int(rad * r.uniform(0.5, 0.8)))
            for _ in range(int(r.integers(2, 5)))]
        for x, y, a, b in blobs:
            b = min(b, bottom - y)
            cv2.ellipse(img, (x, y), (a, b), 0, 0, 360, green, -1)
            cv2.ellipse(img, (x, y), (a, b), 0, 0, 360, OUTLINE, lw)
        if kind == "apple":
            for _ in range(6):
                p = (cx + int(r.uniform(-0.7, 0.7) * rad), cy + int(r.uniform(-0.7, 0.5) * rad))
                cv2.circle(img, p, int(n * 0.02), (0.85, 0.1, 0.1, 1.0), -1)
    img = cv2.resize(img, (size, size), interpolation=cv2.INTER_AREA)
    a = img[:, :, 3:]
    img[:, :, :3] = np.where(a > 0, img[:, :, :3] / np.maximum(a, 1e-6), 0.0)
    return np.clip(img, 0.0, 1.0)


@pytest.mark.parametrize("kind,gap,size,seed", [
    ("round", 3, 200, 0), ("round", 8, 350, 1), ("round", 15, 500, 2),
    ("apple", 8, 200, 3), ("apple", 15, 300, 4), ("conifer", 3, 200, 5), ("conifer", 12, 400, 6),
])
def test_gap_keeps_trunk(kind, gap, size, seed):
    lib = TreeLibrary(size=128)
    ex = lib.add(_icon(kind, gap, size, seed), "icon")
    alpha = ex.image[:, :, 3] > 0.5
    # The trunk reaches the bottom edge, is found as trunk, and the pins sit above it.
    assert ex.contour.pins.has_trunk
    bottom = np.flatnonzero(alpha[-1])
    assert 0 < bottom.size < 0.2 * 128
    assert ex.trunk[-3:].sum() >= 0.8 * alpha[-3:].sum()
    assert ex.contour.pins.l[1] < 128 - 15 and ex.contour.pins.r[1] < 128 - 15
    # One region: crown and trunk joined across the gap.
    assert cv2.connectedComponents(alpha.astype(np.uint8), connectivity=8)[0] == 2


def test_no_gap_is_unchanged():
    img = _icon("round", 0, 256, 7)
    assert np.array_equal(_join_detached_trunk(img), img)


def _clutter(kind: str) -> np.ndarray:
    img = _icon("round", 0, 300, 8)
    if kind == "sun":
        cv2.circle(img, (270, 40), 20, (1.0, 0.85, 0.1, 1.0), -1)
        return img
    if kind == "disc":   # a ground disc apart below the trunk
        img[281:] = 0.0
        cv2.ellipse(img, (150, 292), (110, 6), 0, 0, 360, (0.3, 0.6, 0.2, 1.0), -1)
        return img
    img[img[:, :, 0] > 0.35] = 0.0          # the trunk goes: a crown alone
    low = int(np.flatnonzero(img[:, :, 3].max(axis=1) > 0.5)[-1])
    if kind == "pile":
        cv2.ellipse(img, (150, low + 20), (40, 10), 0, 0, 360, (0.8, 0.3, 0.1, 1.0), -1)
    else:                # a pebble
        cv2.circle(img, (150, low + 12), 6, (0.5, 0.5, 0.5, 1.0), -1)
    return img


@pytest.mark.parametrize("kind", ["sun", "disc", "pile", "pebble"])
def test_clutter_is_not_a_trunk(kind):
    img = _clutter(kind)
    assert _detached_trunk(img[:, :, 3] >= 0.5) is None
    assert np.array_equal(_join_detached_trunk(img), img)


def test_bridge_is_trunk_coloured():
    img = _icon("round", 10, 300, 9)
    out = _join_detached_trunk(img)
    changed = np.abs(out - img).max(axis=2) > 0.05
    ys, xs = np.nonzero(changed)
    assert ys.size > 0
    # The bridge is in the gap above the trunk's top, within the trunk's columns, in its fill colour.
    trunk_cols = np.flatnonzero(img[-30, :, 3] > 0.5)
    assert xs.min() >= trunk_cols[0] - 1 and xs.max() <= trunk_cols[-1] + 1
    fill = img[-30, int(np.median(trunk_cols)), :3]
    inner = changed & (out[:, :, 3] > 0.99)
    inner[:, :trunk_cols[0] + 4] = False
    inner[:, trunk_cols[-1] - 3:] = False
    assert np.abs(out[inner][:, :3] - fill).max() < 0.1


def test_given_trunk_mask_keeps_detached_trunk():
    img = _icon("round", 10, 256, 10)
    brown = (img[:, :, 3] > 0.5) & (img[:, :, 0] > 0.35) & (img[:, :, 1] < 0.4)
    ex = TreeLibrary(size=128).add(img, "icon", trunk_mask=brown)
    assert ex.trunk_source == "mask"
    assert ex.trunk[-3:].sum() > 0 and ex.contour.pins.has_trunk
