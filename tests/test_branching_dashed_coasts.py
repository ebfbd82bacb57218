"""Dotted and dashed coasts of drawn maps: recognised as a coast and drawn with their rhythm (issue 23)."""

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import synthesize_image
from branchnb.branching.drawn_dashes import coast_dashes, dashed_coast, paint_dashes
from branchnb.branching.skeleton_map import SkeletonMap
from branchnb.core.structure import Branch, Structure

LAND, SEA, INK = (0.92, 0.86, 0.68), (0.55, 0.72, 0.86), (0.25, 0.18, 0.12)


def _land(n, seed):
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[:n, :n] / n
    noise = cv2.GaussianBlur(rng.normal(0, 1, (n, n)).astype(np.float32), (0, 0), n / 12)
    land = (0.42 - np.hypot(xx - 0.5, yy - 0.5) + noise / noise.std() * 0.08) > 0.08
    lab, k = ndi.label(land)
    return ndi.binary_fill_holes(lab == 1 + np.argmax(ndi.sum(land, lab, range(1, k + 1))))


def _dashed_map(n, seed, period, dash, width):
    """Flat land and sea, the coast dashed (``dash`` px every ``period`` px; dots when dash <= width)."""
    land = _land(n, seed)
    img = np.where(land[..., None], np.float32(LAND), np.float32(SEA)).astype(np.float32)
    c = cv2.findContours(land.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)[0][0][:, 0]
    s = np.r_[0, np.cumsum(np.hypot(*np.diff(c.astype(float), axis=0).T))]
    for start in np.arange(0, s[-1], period):
        k0, k1 = np.searchsorted(s, [start, start + max(dash - width, 0)])
        seg = c[k0:min(k1, len(c) - 1) + 1]
        cv2.polylines(img, [np.int32(seg if len(seg) > 1 else seg[[0, 0]])], False, INK, width, cv2.LINE_AA)
    return img, land


def _coast_share(img, land, reach, period):
    """Share of the coast (edge of ``land``, not the frame) within ``reach`` of ink, and the number of
    separate pieces of ink along it per ``period`` of its length (1 for dashes, ~0 for a solid line)."""
    edge = land & ~ndi.binary_erosion(land)
    edge[:3] = edge[-3:] = False
    edge[:, :3] = edge[:, -3:] = False
    ink = np.linalg.norm(img[..., :3] - INK, axis=-1) < 0.25
    d = ndi.distance_transform_edt(~ink)
    pieces = ndi.label(ink & (ndi.distance_transform_edt(~edge) <= 4), np.ones((3, 3)))[1]
    length = sum(cv2.arcLength(c, True) for c in cv2.findContours(land.astype(np.uint8), cv2.RETR_EXTERNAL,
                                                                 cv2.CHAIN_APPROX_NONE)[0])
    return float(np.mean(d[edge] <= reach)), pieces * period / max(length, 1.0)


@pytest.mark.parametrize("n, seed, period, dash, width", [(200, 0, 7, 2, 2), (256, 1, 10, 6, 2), (600, 2, 12, 7, 3),
                                                          (900, 3, 9, 3, 3)])
def test_dash_rhythm_read_and_redrawn(n, seed, period, dash, width):
    img, land = _dashed_map(n, seed, period, dash, width)
    usable = np.ones(land.shape, bool)
    drawn = np.linalg.norm(img - INK, axis=-1) < 0.2
    found = coast_dashes(land, drawn, usable, width)
    assert found is not None
    assert abs(found[0] - period) <= 0.15 * period
    # drawn along another shape: ink within half a period everywhere, gaps between the dashes
    other = _land(n, seed + 10)
    out = paint_dashes(np.where(other[..., None], np.float32(LAND), np.float32(SEA)), other, INK, width, *found)
    reach_share, dashes = _coast_share(out, other, found[0] / 2 + 1.5, period)
    assert reach_share >= 0.9
    assert 0.7 <= dashes <= 1.2


def test_solid_and_hatched_coasts_are_no_dashes():
    n = 256
    land = _land(n, 4)
    img = np.where(land[..., None], np.float32(LAND), np.float32(SEA)).astype(np.float32)
    solid = img.copy()
    cnts = cv2.findContours(land.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)[0]
    cv2.drawContours(solid, cnts, -1, INK, 2, cv2.LINE_AA)
    assert coast_dashes(land, np.linalg.norm(solid - INK, axis=-1) < 0.2, np.ones((n, n), bool), 2.0) is None
    # a sea hatched with dashes everywhere (its coast undrawn) is marked, not drawn along its coast
    hatched = img.copy()
    rng = np.random.default_rng(0)
    for x, y in rng.integers(0, n, (600, 2)):
        if not land[y, x]:
            cv2.line(hatched, (int(x), int(y)), (int(x) + 4, int(y)), INK, 1)
    pm = SkeletonMap(Structure([Branch(np.array([[0.0, 0.0], [1.0, 1.0]]), 1.0)], image_shape=(n, n)),
                     1.0).pixel_map((n, n))
    cols = np.array([SEA, LAND], np.float32)
    off = np.linalg.norm(hatched - cols[land.astype(int)], axis=-1)
    assert dashed_coast(hatched, land, pm, 5.0, off, cols, 0.2) is None


def test_dotted_map_drawn_dotted():
    """A drawn map with a dotted coast: the output's coast is dotted all along (it was missing)."""
    n = 256
    img, land = _dashed_map(n, 5, 8, 2, 2)
    dt = ndi.distance_transform_edt(land)
    cy, cx = np.unravel_index(np.argmax(dt), dt.shape)
    rivers = []
    for ang in (0.3, 2.4, 4.2):
        pts = np.array([[cx + t * np.cos(ang), cy + t * np.sin(ang)] for t in np.arange(0, n, 2.0)])
        inside = land[np.clip(pts[:, 1].astype(int), 0, n - 1), np.clip(pts[:, 0].astype(int), 0, n - 1)]
        pts = pts[:np.argmin(inside) - 6] if not inside.all() else pts
        cv2.polylines(img, [np.int32(pts * 4)], False, (0.2, 0.4, 0.7), 2, cv2.LINE_AA, shift=2)
        rivers.append(Branch(pts, 1.0))
    structure = Structure(rivers, image_shape=(n, n))
    out = synthesize_image(img, structure, structure, rng=0).image[..., :3]
    landish = ndi.binary_fill_holes(ndi.binary_opening(np.linalg.norm(out - SEA, axis=-1) >= 0.12, iterations=2))
    assert (landish & land).sum() / (landish | land).sum() > 0.95
    reach_share, dots = _coast_share(out, landish, 8 / 2 + 1.5, 8)
    assert reach_share >= 0.9          # drawn all along (the undetected dotted coast drew none: 0 %)
    assert 0.7 <= dots <= 1.2          # one dot per period (a solid line: ~0)
