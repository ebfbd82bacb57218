"""Small leaves (96-200 px): a thin vein layer grown from scribbles stays on the veins.

On a 128 px ginkgo-like fan (1-px dark veins running into a yellow rim) lazy
snapping left the rim's own colour out of the background model (the 15 %
of the blade most like the layer) and the vein layer grew over the rim:
training vein IoU 0.47, induced IoU on the other leaves 0.41-0.49, and a
NonStructuralLayerWarning. A thin line layer now keeps plain blade off every
line in the background model (``layers._OFF_LINE``).
"""

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.leaves import Layer, LayerSet, grow_layers, simulate_scribbles


def _fan(rng, S):
    """A ginkgo-like leaf: fan blade, notch, green base to yellow rim, dichotomous 1-px veins, petiole."""
    img = np.ones((S, S, 3), np.float32)
    base = np.array([S * 0.5 + rng.normal(0, S * 0.02), S * 0.7])
    half = rng.uniform(0.75, 1.15)
    R = S * rng.uniform(0.40, 0.47)
    notch = rng.uniform(0.1, 0.35)
    th = np.linspace(-half, half, 200)
    r = R * (1 - notch * np.exp(-(th / 0.08) ** 2)) * (1 + 0.05 * np.sin(th * rng.uniform(6, 11) + rng.uniform(0, 6)))
    ang = -np.pi / 2 + th
    pts = np.stack([base[0] + r * np.cos(ang), base[1] + r * np.sin(ang)], 1)
    blade = np.zeros((S, S), np.uint8)
    cv2.fillPoly(blade, [np.concatenate([[base], pts]).astype(np.int32)], 1)
    blade = cv2.morphologyEx(blade, cv2.MORPH_OPEN, np.ones((3, 3), np.uint8))
    pet = np.zeros((S, S), np.uint8)
    cv2.line(pet, tuple(np.int32(base)), tuple(np.int32(base + [rng.normal(0, S * 0.03), S * 0.2])), 1,
             max(2, S // 80))
    yy, xx = np.mgrid[:S, :S]
    g = np.clip(np.hypot(xx - base[0], yy - base[1]) / R, 0, 1)[..., None]
    col = np.array([0.55, 0.7, 0.2]) * (1 - g) + np.array([0.85, 0.8, 0.25]) * g
    col = col + 0.03 * cv2.GaussianBlur(rng.normal(0, 1, (S, S)).astype(np.float32), (0, 0), 2)[..., None]
    veins = np.zeros((S, S), np.uint8)

    def vein(p, a, depth):
        q = p.copy()
        L = R * (0.25 + 0.1 * rng.random())
        while True:
            nq = q + 2 * np.array([np.cos(a), np.sin(a)])
            if np.hypot(*(nq - base)) > R * 1.2 or not (0 <= nq[0] < S and 0 <= nq[1] < S):
                break
            cv2.line(veins, tuple(np.int32(q)), tuple(np.int32(nq)), 1, 1)
            q = nq
            L -= 2
            if L <= 0 and depth < 4:
                vein(q, a - 0.12 * half, depth + 1)
                vein(q, a + 0.12 * half, depth + 1)
                return

    vein(base.copy(), -np.pi / 2 - half * 0.5, 0)
    vein(base.copy(), -np.pi / 2 + half * 0.5, 0)
    veins = (veins > 0) & (blade > 0)
    col = np.where(veins[..., None], col * 0.82, col)
    col = np.where(pet[..., None] > 0, np.array([0.45, 0.55, 0.2]), col)
    leaf = (blade | pet) > 0
    img = np.where(leaf[..., None], np.clip(col, 0, 1), 1.0).astype(np.float32)
    return img, leaf, veins, blade > 0


@pytest.mark.parametrize("size,seed,index", [(128, 7, 1), (128, 7, 0), (96, 0, 1), (160, 3, 0)])
def test_small_fan_vein_layer_stays_on_veins(size, seed, index):
    rng = np.random.default_rng(seed)
    img, leaf, veins, blade = [_fan(rng, size) for _ in range(index + 1)][index]
    scr = simulate_scribbles(veins, 10, length=max(8, size // 20), rng=0)
    m = grow_layers(img, leaf, LayerSet([Layer("veins", "#d62728", 0, scr)]), rng=0).masks["veins"]
    # The petiole (a stalk as dark as a vein) may go either way: judged on the blade.
    m = m & blade
    near = ndi.binary_dilation(veins, np.ones((3, 3), bool))
    iou = (m & near).sum() / max(1, (m | veins).sum())
    # main (128 px, seed 7, leaf 1): IoU 0.47, the yellow rim taken as vein.
    assert iou >= 0.75, iou
    assert (m & ~ndi.binary_dilation(veins, np.ones((5, 5), bool))).sum() <= 0.05 * veins.sum()
