"""Issue 23: a river of about its ground's luminance, set apart by hue (aerial view over fields), is traced
on the opponent-colour channel (branchnb.branching.colour_contrast)."""
import cv2
import numpy as np
from scipy import ndimage as ndi

from branchnb.branching import extract_structure
from branchnb.branching.colour_contrast import colour_contrast_gray
from branchnb.core.polyline import resample_uniform

FIELDS = np.array([[0.45, 0.55, 0.25], [0.6, 0.6, 0.35], [0.3, 0.42, 0.2], [0.7, 0.62, 0.42], [0.22, 0.35, 0.18]])


def _fields(n, rng):
    pts = rng.uniform(0, n, (30, 2))
    yy, xx = np.mgrid[:n, :n]
    lab = np.argmin((xx[..., None] - pts[:, 0]) ** 2 + (yy[..., None] - pts[:, 1]) ** 2, -1)
    img = FIELDS[rng.integers(0, 5, 30)][lab].astype(np.float32)
    return img + cv2.GaussianBlur(rng.normal(0, 0.05, (n, n, 3)).astype(np.float32), (0, 0), 1.0)


def _aerial(n=320, seed=1):
    """A blue-grey river (luminance within the fields' range) with two tributaries over fields; its mask."""
    rng = np.random.default_rng(seed)
    img = _fields(n, rng)
    water = np.zeros((n, n), np.uint8)
    w = max(3, n // 40)
    main = np.c_[n * 0.5 + n * 0.12 * np.sin(np.linspace(0, 3, 60)), np.linspace(-2, n + 2, 60)]
    cv2.polylines(water, [np.round(main).astype(np.int32)], False, 1, w)
    for k, sign in ((18, -1), (38, 1)):
        t = np.linspace(0, 1, 30)[:, None]
        trib = main[k] + t * np.array([sign * n * 0.4, -n * 0.15]) + np.c_[0 * t, n * 0.04 * np.sin(6 * t)]
        cv2.polylines(water, [np.round(trib).astype(np.int32)], False, 1, max(2, w // 2))
    water = water.astype(bool)
    img[water] = np.array([0.34, 0.44, 0.52]) + rng.normal(0, 0.03, (water.sum(), 3))
    return np.clip(img, 0, 1).astype(np.float32), water


def _scores(s, water):
    h, w = water.shape
    pts = np.vstack([resample_uniform(b.points, 0.5, include_end=True) for b in s.branches if len(b.points) > 1])
    ix = np.clip(np.round(pts[:, 0]).astype(int), 0, w - 1)
    iy = np.clip(np.round(pts[:, 1]).astype(int), 0, h - 1)
    drawn = np.zeros_like(water)
    drawn[iy, ix] = True
    from skimage.morphology import skeletonize

    axis = skeletonize(water)
    recall = float((ndi.distance_transform_edt(~drawn)[axis] <= 2.0).mean())
    precision = float((ndi.distance_transform_edt(~water)[iy, ix] <= 2.0).mean())
    return recall, precision


def test_isoluminant_river_over_fields_is_traced():
    img, water = _aerial()
    # the premise: the water's luminance lies inside the fields' own range
    lum = img @ np.array([0.2126, 0.7152, 0.0722])
    assert np.percentile(lum[~water], 10) < np.median(lum[water]) < np.percentile(lum[~water], 90)
    recall, precision = _scores(extract_structure(img), water)
    assert recall >= 0.85 and precision >= 0.9, (recall, precision)


def test_hue_channel_darkens_the_river_only():
    img, water = _aerial(256, seed=2)
    g = colour_contrast_gray(img)
    assert g is not None
    inner = ndi.binary_erosion(water)
    far = ndi.distance_transform_edt(~water) > 4
    assert np.median(g[inner]) < 0.35 and np.median(g[far]) > 0.55


def test_no_hue_channel_without_coloured_lines():
    rng = np.random.default_rng(3)
    # grey image; fields alone; scattered blue spots (no network); a coloured region (no lines)
    assert colour_contrast_gray(np.full((64, 64), 0.5, np.float32)) is None
    fields = np.clip(_fields(200, rng), 0, 1)
    assert colour_contrast_gray(fields) is None
    spots = fields.copy()
    for x, y in rng.uniform(10, 190, (25, 2)).astype(int):
        cv2.circle(spots, (int(x), int(y)), 3, (0.34, 0.44, 0.52), -1)
    assert colour_contrast_gray(spots) is None
    blob = fields.copy()
    cv2.circle(blob, (100, 100), 35, (0.34, 0.44, 0.52), -1)
    assert colour_contrast_gray(blob) is None
