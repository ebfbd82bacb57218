"""A drawn map whose coast ink is the commonest line colour: its rivers are traced by their own colour.

A fantasy map draws a thick brown coast with a thin second line offshore, blue rivers and small tree
glyphs (green crowns, brown trunks). Where the sea between the coast and the frame is narrow, the outline
test leaves much of the brown ink, and brightness ridges then traced the double coast and the glyphs as
rivers (extraction precision 0.75-0.81 on such maps).
"""

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import extract_structure
from branchnb.branching.ridges import _line_colour_and_width

COAST = (0.30, 0.20, 0.10)
RIVER = (0.20, 0.38, 0.62)
N_RIVERS = 3


def _fantasy_map(size: int, seed: int):
    """Parchment land reaching near the bottom frame, teal sea, double brown coast, blue rivers, glyphs."""
    rng = np.random.default_rng(seed)
    h = w = size
    yy, xx = np.mgrid[0:h, 0:w] / h
    # a blob pushed down so its south coast runs a few pixels from the bottom frame
    land = (np.hypot((xx - 0.5) / 1.1, (yy - 0.56) / 1.0) + 0.02 * np.sin(9 * np.arctan2(yy - 0.56, xx - 0.5))) < 0.41
    land = ndi.binary_fill_holes(land)
    img = np.empty((h, w, 3), np.float32)
    img[:] = (0.93, 0.85, 0.66)
    img += 0.03 * cv2.GaussianBlur(rng.normal(0, 1, (h, w)).astype(np.float32), (0, 0), 1.5)[..., None]
    img[~land] = (0.45, 0.66, 0.68)
    for _ in range(h * w // 900):   # wave dashes on the sea
        x, y = int(rng.integers(0, w)), int(rng.integers(0, h))
        if not land[y, x]:
            cv2.ellipse(img, (x, y), (4, 2), 0, 180, 360, (0.35, 0.55, 0.58), 1, cv2.LINE_AA)
    cnts, _ = cv2.findContours(land.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    cv2.drawContours(img, cnts, -1, COAST, max(2, h // 200), cv2.LINE_AA)
    dt_out = ndi.distance_transform_edt(~land)
    img[(dt_out > 5) & (dt_out < 6.2)] = COAST
    dt_in = ndi.distance_transform_edt(land)
    truth = np.zeros((h, w), np.uint8)
    cy, cx = 0.56 * h, 0.5 * w
    for k in range(N_RIVERS):  # rivers from the coast towards the centre, with a tributary each
        a = 2 * np.pi * k / N_RIVERS + rng.uniform(-0.3, 0.3)
        r_land = max(r for r in range(h) if 0 <= int(cy + r * np.sin(a)) < h and 0 <= int(cx + r * np.cos(a)) < w
                     and land[int(cy + r * np.sin(a)), int(cx + r * np.cos(a))] and dt_in[int(cy + r * np.sin(a)),
                     int(cx + r * np.cos(a))] >= 4)
        t = np.linspace(r_land, 0.5 * r_land, 40)
        wob = 0.08 * np.sin(np.linspace(0, 3 * np.pi, 40) + rng.uniform(0, 6))
        pts = np.stack([cx + t * np.cos(a + wob), cy + t * np.sin(a + wob)], -1)
        cv2.polylines(truth, [pts.astype(np.int32)], False, 1, 2)
        j = 15
        d = pts[j + 1] - pts[j]
        d = d / np.linalg.norm(d)
        s = rng.choice([-1, 1]) * 0.9
        d = np.array([d[0] * np.cos(s) - d[1] * np.sin(s), d[0] * np.sin(s) + d[1] * np.cos(s)])
        trib = pts[j] + np.outer(np.linspace(0, 0.25 * r_land, 12), d)
        cv2.polylines(truth, [trib.astype(np.int32)], False, 1, 1)
    truth &= (dt_in >= 3)
    img[truth > 0] = RIVER
    for _ in range(h * w // 1000):   # tree glyphs: green crown, brown trunk
        x, y = int(rng.integers(10, w - 10)), int(rng.integers(10, h - 10))
        if land[y, x] and dt_in[y, x] > 8 and not truth[max(0, y - 8):y + 8, max(0, x - 8):x + 8].any():
            cv2.fillPoly(img, [np.array([[x, y - 5], [x - 3, y + 2], [x + 3, y + 2]], np.int32)], (0.25, 0.40, 0.20))
            cv2.line(img, (x, y + 2), (x, y + 4), COAST, 1)
    return np.clip(img, 0, 1).astype(np.float32), truth > 0


def _precision_recall(img, truth, tol=3.0):
    s = extract_structure(img)
    h, w = truth.shape
    pts = np.concatenate([b.points for b in s.branches])
    ix = np.clip(np.round(pts[:, 0]).astype(int), 0, w - 1)
    iy = np.clip(np.round(pts[:, 1]).astype(int), 0, h - 1)
    precision = float(np.mean(ndi.distance_transform_edt(~truth)[iy, ix] <= tol))
    traced = np.zeros((h, w), np.uint8)
    for b in s.branches:
        cv2.polylines(traced, [np.round(b.points).astype(np.int32)], False, 1, 1)
    recall = float(np.mean(ndi.distance_transform_edt(traced == 0)[truth] <= tol))
    return precision, recall


@pytest.mark.parametrize("size,seed", [(256, 0), (320, 1)])
def test_coast_ink_does_not_outrank_river_colour(size, seed):
    img, _ = _fantasy_map(size, seed)
    colour, width = _line_colour_and_width(img)
    assert colour is not None and width is None
    assert np.abs(colour - np.array(RIVER)).max() <= 0.05


@pytest.mark.parametrize("size,seed", [(256, 0), (320, 1)])
def test_double_coast_near_frame_not_traced(size, seed):
    img, truth = _fantasy_map(size, seed)
    precision, recall = _precision_recall(img, truth)
    assert precision >= 0.95
    assert recall >= 0.85


def test_black_coast_and_black_rivers_keep_brightness_route():
    # one ink for coast and rivers: no other colour to prefer, the rivers are still traced
    img, truth = _fantasy_map(256, 2)
    ink = np.all(np.abs(img - np.array(RIVER)) < 0.02, -1) | np.all(np.abs(img - np.array(COAST)) < 0.02, -1)
    img[ink] = 0.05
    colour, _ = _line_colour_and_width(img)
    assert colour is None or np.abs(colour - np.array(RIVER)).max() > 0.1
    precision, recall = _precision_recall(img, truth)
    assert recall >= 0.8
