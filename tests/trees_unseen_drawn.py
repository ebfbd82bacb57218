"""Three drawn trees that are in no sample set (issue 24, trees25): shapes, strokes and palettes
that neither :mod:`branchnb.trees.drawn` nor the data draw.

* ``cypress``: a tall flame-shaped crown (a pointed ellipse) in blue-green with a 4 px plum-black
  outline, a short grey trunk, a few outlined scale arcs inside;
* ``apple``: a cloud crown (a union of seven discs) in yellow-green with a 1 px dark-green outline,
  red apples with a highlight, a forked trunk;
* ``fan_palm``: a fan of seven spiky leaves on a leaning ringed trunk, 3 px brown outline.
"""

from __future__ import annotations

import cv2
import numpy as np

SS = 4


def _draw(size, shapes):
    n = size * SS
    rgb = np.zeros((n, n, 3), np.float32)
    alpha = np.zeros((n, n), np.float32)
    for kind, geom, fill, ink, width in shapes:
        m = np.zeros((n, n), np.uint8)
        if kind == "poly":
            pts = [np.round(np.asarray(geom) * SS).astype(np.int32)]
            cv2.fillPoly(m, pts, 1)
        else:
            (cx, cy), r = geom
            cv2.circle(m, (int(cx * SS), int(cy * SS)), int(r * SS), 1, -1)
        mb = m.astype(bool)
        rgb[mb] = fill
        alpha[mb] = 1.0
        if width > 0:
            w = max(1, int(round(width * SS)))
            inner = cv2.erode(m, np.ones((2 * w + 1, 2 * w + 1), np.uint8)).astype(bool)
            rgb[mb & ~inner] = ink
    img = np.concatenate([rgb, alpha[..., None]], axis=2)
    img = cv2.resize(img, (size, size), interpolation=cv2.INTER_AREA)
    a = img[..., 3:4]
    img[..., :3] = np.where(a > 1e-6, img[..., :3] / np.maximum(a, 1e-6), 0.0) * a
    return np.clip(img, 0, 1).astype(np.float32)


def _ellipse_pts(cx, cy, rx, ry, n=90, tip=0.0):
    t = np.linspace(0, 2 * np.pi, n, endpoint=False)
    x = cx + rx * np.sin(t) * (1 - tip * (np.cos(t) > 0) * np.cos(t) ** 2)
    y = cy - ry * np.cos(t)
    return np.stack([x, y], 1)


def cypress(size: int = 256) -> np.ndarray:
    s = size / 256.0
    ink, w = (0.12, 0.03, 0.1), 2.0 * s
    crown = _ellipse_pts(128 * s, 110 * s, 46 * s, 98 * s, tip=0.6)
    trunk = np.array([[120, 195], [136, 195], [138, 250], [118, 250]]) * s
    shapes = [("poly", trunk, (0.55, 0.55, 0.58), ink, w), ("poly", crown, (0.15, 0.5, 0.45), ink, w)]
    for k, (y, dx) in enumerate(((70, -8), (105, 10), (140, -6), (170, 8))):
        arc = _ellipse_pts((128 + dx) * s, y * s, 22 * s, 14 * s)
        shapes.append(("poly", arc, (0.2, 0.6, 0.5) if k % 2 else (0.1, 0.42, 0.38), ink, 0.75 * w))
    return _draw(size, shapes)


def apple(size: int = 256) -> np.ndarray:
    s = size / 256.0
    ink, w = (0.05, 0.2, 0.05), 1.0 * s
    trunk = np.array([[118, 140], [124, 175], [110, 150], [104, 154], [120, 190], [122, 250],
                      [140, 250], [140, 185], [156, 150], [150, 146], [138, 172], [138, 140]]) * s
    shapes = [("poly", trunk, (0.45, 0.28, 0.12), ink, w)]
    crown = [((128, 80), 50), ((80, 100), 38), ((176, 100), 38), ((100, 60), 36), ((156, 60), 36),
             ((128, 120), 34), ((128, 42), 30)]
    m = np.zeros((size * SS, size * SS), np.uint8)
    for (cx, cy), r in crown:
        cv2.circle(m, (int(cx * s * SS), int(cy * s * SS)), int(r * s * SS), 1, -1)
    cnt, _ = cv2.findContours(m, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    pts = max(cnt, key=len)[:, 0].astype(float) / SS
    shapes.append(("poly", pts, (0.6, 0.78, 0.2), ink, w))
    rng = np.random.default_rng(3)
    for _ in range(9):
        cx, cy = 128 + rng.uniform(-70, 70), 85 + rng.uniform(-45, 40)
        shapes.append(("circle", ((cx * s, cy * s), 7 * s), (0.85, 0.1, 0.1), ink, w))
        shapes.append(("circle", (((cx - 2) * s, (cy - 2) * s), 2 * s), (1.0, 0.85, 0.85), ink, 0))
    return _draw(size, shapes)


def fan_palm(size: int = 256) -> np.ndarray:
    s = size / 256.0
    ink, w = (0.3, 0.15, 0.05), 1.5 * s
    trunk = np.array([[150, 250], [132, 250], [118, 150], [112, 92], [124, 92], [132, 150]]) * s
    shapes = [("poly", trunk, (0.7, 0.55, 0.35), ink, w)]
    for y in range(110, 245, 18):
        cx = 118 + (y - 92) * 23 / 158
        shapes.append(("poly", np.array([[cx - 5, y], [cx + 5, y], [cx + 5, y + 3], [cx - 5, y + 3]]) * s,
                       (0.5, 0.35, 0.2), ink, 0))
    hub = np.array([118.0, 92.0])
    for k, ang in enumerate(np.deg2rad(np.linspace(-170, -10, 7))):
        d = np.array([np.cos(ang), np.sin(ang)])
        nrm = np.array([-d[1], d[0]])
        L = 95 if k in (2, 3, 4) else 80
        pts = [hub]
        for j in range(1, 9):
            r = L * j / 8
            half = 14 * np.sin(np.pi * j / 8.5)
            pts.append(hub + d * r + nrm * half * (1 if j % 2 else 0.55))
        for j in range(8, 0, -1):
            r = L * j / 8
            half = 14 * np.sin(np.pi * j / 8.5)
            pts.append(hub + d * r - nrm * half * (1 if j % 2 else 0.55))
        shapes.append(("poly", np.array(pts) * s, (0.25, 0.62, 0.12) if k % 2 else (0.35, 0.72, 0.18), ink, w))
    return _draw(size, shapes)


UNSEEN = {"cypress": cypress, "apple": apple, "fan_palm": fan_palm}
