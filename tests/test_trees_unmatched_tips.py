"""Tips held by one source only in a mix (issue 24, trees44): kept whole or dropped, not bumps."""

from __future__ import annotations

import cv2
import numpy as np
import pytest
from scipy.ndimage import gaussian_filter1d

from branchnb.trees import TreeLibrary, corners


def _star_tree(n: int, h: int, seed: int) -> np.ndarray:
    """A flat star-crowned tree with ``n`` points (two tones, brown trunk), ``h`` px tall, drawn 4x
    and area-averaged."""
    r = np.random.default_rng(seed)
    w = int(round(h * 0.75))
    ss = 4
    top, bottom = 0.05 * h, 0.75 * h
    cx, cy, ro = 0.5 * w, 0.5 * (top + bottom), 0.5 * (bottom - top)
    a = -np.pi / 2 + np.arange(2 * n) * np.pi / n + r.uniform(-0.05, 0.05)
    rad = np.where(np.arange(2 * n) % 2 == 0, ro, 0.55 * ro)
    star = np.stack([cx + rad * np.cos(a) * min(1.0, 0.45 * w / ro), cy + rad * np.sin(a)], 1)
    big = np.zeros((h * ss, w * ss, 4), np.float32)
    tw = w * 0.05
    trunk = np.array([[cx - tw, 0.6 * h], [cx + tw, 0.6 * h], [cx + tw, 0.97 * h], [cx - tw, 0.97 * h]])
    cv2.fillPoly(big, [np.int32(trunk * ss)], (0.42, 0.27, 0.15, 1.0))
    crown = np.zeros(big.shape[:2], np.uint8)
    cv2.fillPoly(crown, [np.int32(star * ss)], 1)
    big[crown > 0] = (0.1, 0.38, 0.22, 1.0)
    big[(crown > 0) & (np.arange(big.shape[1])[None, :] > cx * ss)] = (0.15, 0.55, 0.3, 1.0)
    small = cv2.resize(big, (w, h), interpolation=cv2.INTER_AREA)
    al = small[..., 3:]
    rgb = np.where(al > 1e-4, small[..., :3] / np.maximum(al, 1e-4), 1.0)
    return np.dstack([np.clip(rgb, 0, 1), al]).astype(np.float32)


def _tips(alpha: np.ndarray) -> np.ndarray:
    """Lengths (share of the height) of the silhouette's tips turning more than 80 deg (interior
    angle under 100 deg) above the trunk's feet: the tip's distance to the chord between the most
    concave points towards its neighbouring tips."""
    cs, _ = cv2.findContours((alpha >= 0.5).astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    c = max(cs, key=cv2.contourArea)[:, 0].astype(np.float64)
    cc = np.vstack([c, c[:1]])
    s = np.concatenate([[0], np.cumsum(np.hypot(*np.diff(cc, axis=0).T))])
    n = 1200
    u = np.linspace(0, s[-1], n, endpoint=False)
    p = np.stack([np.interp(u, s, cc[:, 0]), np.interp(u, s, cc[:, 1])], 1)
    h = float(np.ptp(p[:, 1]))
    step = s[-1] / n
    sm = np.stack([gaussian_filter1d(p[:, k], max(0.004 * h / step, 0.5), mode="wrap") for k in range(2)], 1)
    d = max(2, int(round(0.03 * h / step)))
    back, ahead = sm - np.roll(sm, d, 0), np.roll(sm, -d, 0) - sm
    turn = np.degrees(np.arctan2(back[:, 0] * ahead[:, 1] - back[:, 1] * ahead[:, 0], (back * ahead).sum(1)))
    area = 0.5 * np.sum(p[:, 0] * np.roll(p[:, 1], -1) - np.roll(p[:, 0], -1) * p[:, 1])
    turn = turn if area >= 0 else -turn
    win = np.lib.stride_tricks.sliding_window_view(np.pad(turn, d, mode="wrap"), 2 * d + 1)
    idx = np.flatnonzero((turn >= win.max(1)) & (turn > 80.0) & (p[:, 1] < p[:, 1].min() + 0.85 * h))
    if idx.size > 1:
        idx = idx[np.concatenate([[True], np.diff(idx) > d])]
    out = []
    for t in idx:
        others = idx[idx != t]
        fwd = min(((o - t) % n for o in others), default=n // 2)
        bwd = min(((t - o) % n for o in others), default=n // 2)
        a_ = [(t - k) % n for k in range(1, max(bwd, 2))]
        b_ = [(t + k) % n for k in range(1, max(fwd, 2))]
        q, r = p[a_[int(np.argmin(turn[a_]))]], p[b_[int(np.argmin(turn[b_]))]]
        dd = r - q
        out.append(abs(dd[0] * (p[t, 1] - q[1]) - dd[1] * (p[t, 0] - q[0])) / max(np.hypot(*dd), 1e-9) / h)
    return np.array(out)


@pytest.mark.parametrize("counts, heights", [((5, 7), (200, 280)), ((4, 6), (140, 360))])
def test_unmatched_star_tips_stay_tips(counts, heights):
    lib = TreeLibrary(size=256)
    for i, (n, h) in enumerate(zip(counts, heights, strict=True)):
        lib.add(_star_tree(n, h, i), f"star{n}")
    src = [_tips(e.alpha) for e in lib.exemplars]
    v = lib.variation([0.4, 0.6], rng=0)
    mix = _tips(v.image[..., 3])
    # main: the unmatched points scaled into stubs (9 tips of 5..7, four of them 0.03 of the
    # height) or cut off by the colour transfer's alpha (1 tip of 3..5)
    assert min(len(t) for t in src) <= len(mix) <= max(len(t) for t in src)
    assert mix.min() >= 0.7 * np.concatenate(src).mean()


def test_unmatched_tips_kept_whole_on_the_contours():
    """Two crowns as contours: tips only one holds are carried whole by the other."""
    t = np.linspace(0, 2 * np.pi, 400, endpoint=False)
    base = np.stack([100 + 50 * np.cos(t), 100 + 50 * np.sin(t)], 1)
    spiky = base.copy()
    k = np.arange(400)
    for centre in (150, 250):        # two spikes on the crown (indices 40..360)
        bump = np.clip(1 - np.abs(k - centre) / 12.0, 0, None)
        spiky += (spiky - 100) / 50 * 40 * bump[:, None]
    out, matched, spans = corners._tip_matched([spiky, base], [0.8, 0.2], (0, 40, 360))
    mix = 0.8 * out[0] + 0.2 * out[1]
    r = np.hypot(*(mix - 100).T)
    # round(0.8 * 2 + 0.2 * 0) = 2 tips kept, each 40 px above the rim (scaled: 82 px)
    assert len(spans) == 2
    for c in (150, 250):
        assert r[c - 3:c + 4].max() >= 50 + 0.95 * 40
    assert np.array_equal(matched[1], base)
