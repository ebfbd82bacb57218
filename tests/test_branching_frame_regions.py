"""Regions tied to the image frame (a floor or skyline along the bottom) keep their frame relation in the
output's layout, while regions tied to the branches (a coast map's sea) are laid out around them as
before (issue 23, branching96)."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching.frame_regions import frame_bands, place_bands
from branchnb.branching.layout_model import fit_region_layout, layout_regions
from branchnb.core.structure import Branch, Structure


def _bolt(rng, start, heading, n, step=6.0):
    pts = [np.array(start, float)]
    for _ in range(n):
        a = heading + rng.normal(0, 0.4)
        pts.append(pts[-1] + step * np.array([np.cos(a), np.sin(a)]))
    return pts


def _structure(rng, w, h, start, heading, n):
    def inside(pts):
        return np.clip(pts, 0, [w - 1, h - 1])

    trunk = inside(_bolt(rng, start, heading, n))
    kids = [Branch(inside(_bolt(rng, trunk[j], heading + s * 0.7, n // 3)), 1.5, parent=0, parent_vertex=j)
            for j, s in ((n // 3, 1), (2 * n // 3, -1))]
    return Structure([Branch(trunk, 2.0)] + kids, image_shape=(h, w))


def _skyline(w, h, rng):
    lay = np.zeros((h, w), np.int32)
    x = 0
    while x < w:
        bw, bh = rng.integers(w // 40 + 1, w // 15 + 2), rng.integers(h // 12, h // 5)
        lay[h - bh:, x:x + bw] = 1
        x += bw
    return lay


def _floor(w, h, rng):
    lay = np.zeros((h, w), np.int32)
    lay[int(h * rng.uniform(0.75, 0.85)):] = 1
    return lay


def _roughness(m):
    """Length of the band's far edge (sum of |steps| of its depth profile plus its width)."""
    d = m[::-1].argmin(axis=0)
    return (np.abs(np.diff(d)).sum() + m.shape[1]) / m.shape[1]


@pytest.mark.parametrize("kind, w, h, seed", [("floor", 256, 256, 0), ("skyline", 800, 200, 1),
                                              ("floor", 320, 480, 2), ("skyline", 400, 300, 3)])
def test_frame_band_keeps_its_place_and_shape(kind, w, h, seed):
    rng = np.random.default_rng(seed)
    lay = (_floor if kind == "floor" else _skyline)(w, h, rng)
    ex = _structure(rng, w, h, (0.1 * w, 0.3 * h), 0.2, int(0.8 * w / 6))
    tgt = _structure(rng, w, h, (0.5 * w, 0.05 * h), 1.2, int(0.7 * h / 6))   # a bolt from the top instead
    model = fit_region_layout(lay, ex)
    assert model.bands and model.bands[0].label == 1 and model.bands[0].side == "bottom"
    out = layout_regions(model, tgt, (h, w))
    a, b = lay == 1, out == 1
    assert (a & b).sum() / (a | b).sum() >= 0.85
    assert _roughness(b) <= 1.5 * _roughness(a)
    sizes = np.bincount(ndi.label(b)[0].ravel())[1:]
    assert sizes.sum() - sizes.max() <= 0.02 * sizes.sum()     # no islands of the floor
    # at another size the band keeps its side, depth share and shape
    half = Structure([Branch(np.asarray(b.points) * 0.5, 1.0, parent=b.parent, parent_vertex=b.parent_vertex)
                      for b in tgt.branches], image_shape=(h // 2, w // 2))
    out2 = layout_regions(model, half, (h // 2, w // 2))
    assert abs(np.mean(out2 == 1) - np.mean(a)) <= 0.02
    assert np.all(out2[-1] == 1)


def test_place_bands_other_sides_round_trip():
    lay = np.zeros((120, 90), np.int32)
    lay[:15] = 1                                         # a ceiling along the top
    lay[-25:] = 2                                        # a floor with a slanted edge
    lay[-40:, :] = np.where(np.arange(40)[:, None] >= 30 - np.arange(90)[None, :] // 6, 2, lay[-40:])
    t = np.zeros((100, 60), np.int32)
    t[:, 45:] = 3                                        # a wall band along the right side
    bands = frame_bands(lay, np.zeros((0, 2)), np.ones(lay.shape), [0])
    assert sorted((b.label, b.side) for b in bands) == [(1, "top"), (2, "bottom")]
    assert [(b.label, b.side) for b in frame_bands(t, np.zeros((0, 2)), np.ones(t.shape), [0])] == [(3, "right")]
    assert np.array_equal(np.where(place_bands(frame_bands(t, np.zeros((0, 2)), np.ones(t.shape), [0]), t.shape) >= 0,
                                   3, 0), t)
    placed = place_bands(bands, lay.shape)
    assert np.array_equal(np.where(placed >= 0, placed, 0), lay)


def test_coast_sea_with_river_mouths_stays_branch_tied():
    # the sea along the bottom holds three river mouths on its edge: laid out around the rivers
    rng = np.random.default_rng(4)
    w = h = 256
    lay = np.zeros((h, w), np.int32)
    lay[200:] = 1
    rivers = [Branch(_bolt(rng, (x, 199.0), -np.pi / 2, 20), 1.5) for x in (50.0, 128.0, 200.0)]
    ex = Structure(rivers, image_shape=(h, w))
    model = fit_region_layout(lay, ex)
    assert not model.bands
    assert not frame_bands(lay, np.array([[50.0, 199.0], [128.0, 199.0], [200.0, 199.0]]), np.ones((h, w)), [0])
    # two forks of a bolt striking the same band in one place leave it tied to the frame
    assert frame_bands(lay, np.array([[120.0, 199.0], [135.0, 198.0], [60.0, 40.0]]), np.ones((h, w)), [0])


def test_frame_bands_rejects_bad_layout():
    with pytest.raises(ValueError, match="layout"):
        frame_bands(np.zeros(5, np.int32), np.zeros((0, 2)), np.ones(5), [])
