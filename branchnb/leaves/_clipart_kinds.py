"""Drawn (clip-art) leaves of several kinds with known veins, for the one-vein-system measure (issue 22).

``clip_leaf(kind, size, seed, vein_px, veins)`` draws one leaf in flat
colours on white paper with a grey drop shadow and a 2 px ink outline, as
:mod:`branchnb.leaves._unseen_kinds` does for its ``clipart`` kind, in
four shapes with their own venation: ``maple`` (five pointed toothed
lobes, palmate veins from the petiole with branches to the lobes' sides),
``oak`` (the lobed oak of ``_unseen_kinds``, one vein per lobe),
``elm`` (ovate, doubly serrate, alternate curved pinnate laterals with a
few forks) and ``palmate`` (three rounded lobes, three main veins and
their branches). The veins are drawn ``vein_px`` wide (midrib; branches
0.7 of it, at least 1 px) in one of three styles: ``pale`` (lighter than
the fill), ``colour`` (a hue of their own: red on green, yellow on red)
or ``black`` (the outline's ink). Every side vein starts on its parent
(a drawn vein network is connected). The result is an
:class:`branchnb.leaves._unseen_kinds.UnseenLeaf` (its ``plain`` is the
leaf drawn without veins).
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.render import coverage_polylines
from ._unseen_kinds import UnseenLeaf, _curve, _oak

CLIP_KINDS = ("maple", "oak", "elm", "palmate")
STYLES = ("pale", "colour", "black")
#: ``veins="none"``: plain fill, no veins drawn (the true veins returned as where the user scribbles).
NONE = "none"

_FILLS = {"maple": (0.86, 0.38, 0.12), "oak": (0.62, 0.52, 0.16), "elm": (0.40, 0.66, 0.24),
          "palmate": (0.30, 0.58, 0.30)}
_VEIN = {"pale": None, "colour": {"maple": (0.98, 0.82, 0.22), "oak": (0.72, 0.22, 0.12),
                                  "elm": (0.80, 0.20, 0.16), "palmate": (0.95, 0.90, 0.35)},
         "black": (0.10, 0.12, 0.08)}


def _polar_outline(centre, angles, lengths, widths, base, sharp, teeth, r, n=720):
    """Outline around ``centre`` (angles from straight up): lobes of ``lengths`` at ``angles``."""
    th = np.linspace(-np.pi, np.pi, n, endpoint=False)
    rad = np.full(n, base)
    for a, ln, w in zip(angles, lengths, widths):
        d = np.angle(np.exp(1j * (th - a)))
        rad = np.maximum(rad, base + (ln - base) * np.clip(1 - np.abs(d) / w, 0, 1) ** sharp)
    rad = rad * (1 + teeth * np.abs(np.sin(th * r.integers(28, 40))) ** 3)
    back = np.abs(np.angle(np.exp(1j * (th - np.pi)))) < 0.35  # the sinus at the petiole
    rad = np.where(back, np.minimum(rad, 0.04 + 0.3 * np.abs(np.angle(np.exp(1j * (th - np.pi))))), rad)
    return np.stack([centre[0] + rad * np.sin(th), centre[1] - rad * np.cos(th)], 1)


def _palmate_veins(centre, angles, lengths, r, mid_w, side_w, n_branch):
    veins, widths = [], []
    c = np.asarray(centre, float)
    for a, ln in zip(angles, lengths):
        end = c + 0.88 * ln * np.array([np.sin(a), -np.cos(a)])
        p = _curve(c, end, r.uniform(-0.04, 0.04), 24)
        veins.append(p)
        widths.append(np.linspace(mid_w, 0.6 * mid_w, len(p)))
        for f in np.linspace(0.3, 0.75, n_branch):
            q = p[int(f * (len(p) - 1))]
            for side in (-1, 1):
                b = a + side * np.radians(r.uniform(38, 50))
                dd = (1 - f) * ln * r.uniform(0.35, 0.5)
                br = _curve(q, q + dd * np.array([np.sin(b), -np.cos(b)]), -side * 0.1, 10)
                veins.append(br)
                widths.append(np.full(len(br), side_w))
    return veins, widths


def _maple(r):
    c = (0.0, -0.42)
    ang = np.radians([0, 52, -52, 108, -108]) + r.normal(0, 0.05, 5)
    ln = np.array([0.58, 0.52, 0.52, 0.34, 0.34]) * r.uniform(0.92, 1.08, 5)
    outline = _polar_outline(c, ang, ln, [0.5, 0.45, 0.45, 0.4, 0.4], 0.14, 1.6, 0.04, r)
    return outline, c, ang, ln, 2


def _palmate(r):
    c = (0.0, -0.4)
    ang = np.radians([0, 62, -62]) + r.normal(0, 0.05, 3)
    ln = np.array([0.6, 0.48, 0.48]) * r.uniform(0.92, 1.08, 3)
    outline = _polar_outline(c, ang, ln, [0.9, 0.85, 0.85], 0.3, 0.7, 0.0, r)
    return outline, c, ang, ln, 3


def _elm(r):
    hw = 0.3 * r.uniform(0.9, 1.1)
    n_teeth = int(r.integers(16, 22))
    asym = r.uniform(0.9, 1.1)

    def w(t, s=1.0):
        t = np.clip(t, 0, 1)
        base = hw * np.clip(np.sin(np.pi * t ** 0.7), 0, 1) ** 0.75
        tooth = np.abs(np.sin(np.pi * n_teeth * t)) ** 2 + 0.4 * np.abs(np.sin(2 * np.pi * n_teeth * t)) ** 2
        return base * (1 + 0.06 * (tooth - 0.6)) * s
    t = np.linspace(0, 1, 300)
    outline = np.concatenate([np.stack([w(t, asym), -t], 1), np.stack([-w(t), -t], 1)[::-1]])
    tt = np.linspace(0, 1, 40)
    mid = np.stack([0.0 * tt, -tt], 1)
    veins, kinds = [mid], [0]
    n = int(r.integers(7, 10))
    for tb in np.linspace(0.08, 0.8, n):
        for side in (-1, 1):
            tb2 = tb + (0.5 / n * 0.72 if side > 0 else 0.0)  # alternate
            if tb2 > 0.85:
                continue
            te = tb2 + 0.16
            end = (side * 0.85 * w(te, asym if side > 0 else 1.0), -te)
            p = _curve((0.0, -tb2), end, -side * 0.1, 14)
            veins.append(p)
            kinds.append(1)
            if r.random() < 0.4:  # a fork near the margin
                q = p[9]
                veins.append(_curve(q, (q[0] + side * 0.05, q[1] + 0.05), 0.0, 6))
                kinds.append(2)
    return outline, veins, kinds


def clip_leaf(kind: str, size: int = 512, seed: int = 0, vein_px: float = 2.0, veins: str = "pale", *,
              outline_px: int = 2, shadow: bool = True) -> UnseenLeaf:
    """One drawn leaf of ``kind`` (:data:`CLIP_KINDS`), veins ``vein_px`` wide in style ``veins`` (:data:`STYLES`).

    ``veins="none"`` draws no veins (plain fill; the true veins are still
    returned, as where a user would scribble them); ``outline_px`` is the
    ink outline's width, ``shadow`` the grey drop shadow on the paper.
    """
    if veins == "none":
        plain_fill = True
        veins = "black"
    else:
        plain_fill = False
    r = np.random.default_rng([CLIP_KINDS.index(kind), STYLES.index(veins), int(round(4 * vein_px)), int(seed)])
    mid_w, side_w = float(vein_px), max(1.0, 0.7 * float(vein_px))
    if kind in ("maple", "palmate"):
        outline, c, ang, ln, nb = (_maple if kind == "maple" else _palmate)(r)
        vlines, ws = _palmate_veins(c, ang, ln, r, 1.0, 0.5, nb)
        vkinds = [0 if w[0] > 0.9 else 1 for w in ws]  # main veins, branches
        pet_top, pet_len = np.array(c) + (0.0, 0.03), 0.3
    elif kind == "oak":
        outline, vlines, _, pet_len, _ = _oak(r)
        vkinds = [0] + [1] * (len(vlines) - 1)
        pet_top = np.array((0.0, -0.03))
    else:
        outline, vlines, vkinds = _elm(r)
        pet_top, pet_len = np.array((0.0, -0.03)), 0.12
    rot = np.radians(r.uniform(-12, 12))
    cs, sn = np.cos(rot), np.sin(rot)
    R = np.array([[cs, -sn], [sn, cs]])
    lo, hi = outline.min(0), outline.max(0)
    length = 0.72 * size / max(hi[1] - lo[1] + pet_len * 0.6, hi[0] - lo[0])
    centre = np.array([(lo[0] + hi[0]) / 2, (lo[1] + hi[1] + pet_len * 0.6) / 2])

    def px(p):
        return (np.asarray(p, float) - centre) @ R.T * length + size / 2
    shape = (size, size)
    blade_cov = np.zeros(shape, np.float32)
    cv2.fillPoly(blade_cov, [np.round(px(outline) * 16).astype(np.int32)], 1.0, cv2.LINE_AA, shift=4)
    blade_cov = np.clip(blade_cov, 0, 1)
    pet = np.array([pet_top, pet_top + (0.01 * r.normal(), pet_len)])
    pet_cov, _ = coverage_polylines(shape, [px(pet)], [max(0.012 * size, 2.0)])
    lam = blade_cov > 0.5
    lines = [px(v) for v in vlines]
    widths = [np.full(len(v), mid_w if k == 0 else side_w) for v, k in zip(lines, vkinds)]
    vcov, _ = coverage_polylines(shape, lines, widths)
    inner = ndi.binary_erosion(lam, iterations=max(3, int(outline_px) + 1))
    vcov = vcov * inner
    alpha = np.maximum(blade_cov, pet_cov)
    fill = np.array(_FILLS[kind], np.float32)
    vc = _VEIN[veins]
    vein_col = np.clip(0.45 * fill + 0.55, 0, 1) if vc is None else np.array(vc[kind] if isinstance(vc, dict) else vc,
                                                                               np.float32)
    ink = np.array((0.10, 0.12, 0.08), np.float32)
    paper = np.ones(shape + (3,), np.float32)
    off = int(round(0.025 * size))
    if shadow:
        sh = cv2.GaussianBlur(np.roll(alpha, (off, off), (0, 1)), (0, 0), 0.6)
        paper = paper * (1 - 0.35 * sh[..., None])
    leaf = np.broadcast_to(fill, shape + (3,)).copy()
    rim = lam & ~ndi.binary_erosion(lam, iterations=int(outline_px))
    plain = leaf.copy()
    plain[rim] = ink
    if not plain_fill:
        leaf = leaf * (1 - vcov[..., None]) + vein_col * vcov[..., None]
    leaf[rim] = ink
    a3 = alpha[..., None]
    img = np.clip(paper * (1 - a3) + leaf * a3, 0, 1).astype(np.float32)
    img_plain = np.clip(paper * (1 - a3) + plain * a3, 0, 1).astype(np.float32)
    order = np.argsort(vkinds, kind="stable")
    main = [lines[i] for i in order]
    return UnseenLeaf(img, alpha > 0.5, vcov >= 0.5, np.zeros(shape, bool), img_plain, kind, int(seed), main)
