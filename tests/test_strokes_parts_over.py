"""A carried part drawn over the stroke it hangs from stays over it (issue 25, strokes46).

A cartoon flower's leaves are drawn over the stem, their bases across it. With the
stem's tube bridged over the leaves (strokes45), the stem's patches laid the clean
stem over the carried leaf's base: the leaf came out tucked behind the stem, the
stem's outline across it. The leaf now takes its pixels over the stem
(``Part.over``) and is carried over it; a leaf drawn under the stem stays under.
"""
import cv2
import numpy as np
import pytest

from branchnb.strokes import edit_structure
from branchnb.strokes.edit import fetch_patches
from branchnb.strokes.fanning import _fanned_maps
from branchnb.strokes.synthesis import compose_patches

INK = np.array([25, 25, 25]) / 255.0


def _flower(size, seed, under):
    """(image, stem stroke, stem width, outline px, {leaf: (fill, ring)}) of an outlined stem with two
    leaves drawn over it (or under it)."""
    rng = np.random.default_rng(seed)
    S = size / 400
    col = np.zeros((size, size, 3))
    a = np.zeros((size, size))
    k = max(1, int(round(2.5 * S)))
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * k + 1, 2 * k + 1))
    x = size // 2 + int(rng.integers(-10, 10) * S)
    top, bot, w = int(120 * S), int(380 * S), max(2, int(7 * S))
    tilt = float(rng.uniform(20, 40))
    leaves = {}

    def draw(name, fn, colour):
        m = np.zeros((size, size), np.uint8)
        fn(m)
        outer = cv2.dilate(m, disk) > 0
        col[outer], a[outer] = INK, 1.0
        col[m > 0] = np.array(colour) / 255.0
        leaves[name] = (m > 0, outer & (m == 0))

    stem = ("stem", lambda m: cv2.line(m, (x, bot), (x, top), 255, w), (60, 150, 50))
    pair = [("leaf1", lambda m: cv2.ellipse(m, (x - int(30 * S), int(300 * S)), (int(32 * S), int(11 * S)),
                                            -tilt, 0, 360, 255, -1), (70, 170, 60)),
            ("leaf2", lambda m: cv2.ellipse(m, (x + int(30 * S), int(240 * S)), (int(32 * S), int(11 * S)),
                                            tilt, 0, 360, 255, -1), (70, 170, 60))]
    for item in (pair + [stem] if under else [stem] + pair):
        draw(*item)
    del leaves["stem"]
    img = np.dstack([col, a]).astype(np.float32)
    return img, np.array([(x, bot - 2 * S), (x, top + 30 * S)], float), w, k, leaves


def _render(stroke, w, k, colour, shape):
    """The stem drawn alone along ``stroke``, outlined (RGBA)."""
    m = np.zeros(shape, np.uint8)
    cv2.polylines(m, [np.rint(stroke).astype(np.int32).reshape(-1, 1, 2)], False, 255, w)
    outer = cv2.dilate(m, cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * k + 1, 2 * k + 1))) > 0
    out = np.zeros((*shape, 4), np.float32)
    out[outer, :3], out[outer, 3] = INK, 1.0
    out[m > 0, :3] = colour
    return out


def _on_top(out, part, parent):
    """Share of the pixels where the part's and the parent's renders overlap and differ that
    ``out`` shows the part's (1: the part over the parent)."""
    m = (part[..., 3] > 0.5) & (parent[..., 3] > 0.5) & (out[..., 3] > 0.5) \
        & (np.linalg.norm(part[..., :3] - parent[..., :3], axis=-1) > 0.15)
    dp = np.linalg.norm(out[..., :3] - part[..., :3], axis=-1)
    dq = np.linalg.norm(out[..., :3] - parent[..., :3], axis=-1)
    return float((dp[m] < dq[m]).mean())


def _shares(size, seed, amp, under):
    img, src, w, k, leaves = _flower(size, seed, under)
    S = size / 400
    s = np.linspace(0, 1, 30)
    tgt = np.c_[src[0, 0] + amp * S * np.sin(np.pi * s), src[0, 1] - (src[0, 1] - src[1, 1]) * 0.95 * s]
    patches = fetch_patches(img, [src], [tgt], target_shape=(size, size))
    res = compose_patches(patches)
    index = patches._index
    maps = _fanned_maps(index, patches.attached, patches._carried, patches._window)
    stem = _render(tgt, w, k, np.array([60, 150, 50]) / 255.0, (size, size))
    out = {}
    for name, (fill, ring) in leaves.items():
        alone = np.zeros((size, size, 4), np.float32)
        alone[ring, :3], alone[fill, :3], alone[fill | ring, 3] = INK, np.array([70, 170, 60]) / 255.0, 1.0
        # the carried part holding most of the leaf
        parts = [index.parts[pi] for _, pi, _ in patches._carried]
        best = max(range(len(maps)), key=lambda j: int((alone[parts[j].box][..., 3] > 0)[parts[j].mask].sum()))
        part = cv2.warpAffine(alone, maps[best], (size, size), flags=cv2.INTER_NEAREST)
        out[name] = _on_top(res.image, part, stem)
    over = [getattr(p, "over", None) is not None for p in index.parts]
    return out, over


@pytest.mark.parametrize("size,seed,amp,least", [(400, 0, 60, 0.9), (400, 0, -60, 0.9), (200, 0, 60, 0.78),
                                                  (200, 1, -60, 0.78)])
def test_a_leaf_drawn_over_its_stem_stays_over_it(size, seed, amp, least):
    shares, over = _shares(size, seed, amp, under=False)
    # before: leaf1 / leaf2 0.71 / 0.76, 0.58 / 0.58, 0.76 / 0.38, 0.46 / 0.83;
    # now 0.99 / 0.94, 0.95 / 0.92, 0.82 / 0.81, 0.92 / 0.83
    assert min(shares.values()) >= least, shares
    assert sum(over) == 2, over  # the two leaves (not the stem's top beyond its stroke)


@pytest.mark.parametrize("size,seed,amp", [(400, 0, 60), (800, 1, -60)])
def test_a_leaf_drawn_under_its_stem_stays_under_it(size, seed, amp):
    shares, over = _shares(size, seed, amp, under=True)
    # 0.08 / 0.13 and 0.00 / 0.00, before as now
    assert max(shares.values()) <= 0.2, shares
    assert not any(over), over


def test_identity_edit_keeps_a_leaf_over_its_stem():
    img, src, *_ = _flower(300, 2, under=False)
    res = edit_structure(img, [src], [src])
    # (a leaf's flesh next to what it takes back may come out in the stem's green, 0.08 away: 20 px)
    d = np.abs(res.image - img)[..., :3].max(axis=2)[img[..., 3] > 0.5]
    assert int((d > 0.1).sum()) <= 3 and int((d > 0.05).sum()) <= 40
