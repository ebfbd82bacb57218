"""Pins at the concave corner where a crown narrowing onto its trunk meets it (issue 24)."""
import cv2
import numpy as np
import pytest

from branchnb.trees.contour import pin_points
from branchnb.trees.exemplar import extract_contours
from branchnb.trees.pin_corners import concave_turns
from branchnb.trees.pin_reference import pin_errors, source_pins
from branchnb.trees.processing import process_exemplar


def _disk(r):
    return cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))


def _flat_tree(kind: str, size: int, outline: bool, seed: int = 0):
    """A flat-colour tree drawn at 4x and shrunk: a trunk under a crown drawn over its top.

    Returns the RGBA image and the true pins: on the silhouette's border, the
    trunk's stretch is what lies away from the crown's drawn shape.
    """
    rng = np.random.default_rng(seed)
    s = 4 * size
    col = np.zeros((s, s, 3), np.float32)
    a = np.zeros((s, s), np.uint8)
    ow = max(2, int(0.012 * s)) if outline else 0
    cx, tw, ground, top = s // 2, int(s * rng.uniform(0.05, 0.08)), int(0.95 * s), int(0.55 * s)
    ys = np.linspace(ground, top, 20)
    t = (ground - ys) / (ground - top)
    bend = 0.12 * s if kind == "bent" else 0.0
    xc = cx + bend * t ** 2
    trunk = np.zeros((s, s), np.uint8)
    pts = np.concatenate([np.stack([xc - tw / 2, ys], 1), np.stack([xc + tw / 2, ys], 1)[::-1]])
    cv2.fillPoly(trunk, [np.round(pts).astype(np.int32)], 255)
    tx = int(xc[-1])
    crown = np.zeros((s, s), np.uint8)
    if kind == "ellipse":       # a poplar: its bottom narrows onto the trunk
        ry = int(0.34 * s)
        cv2.ellipse(crown, (tx, top + int(0.05 * s) - ry), (int(0.13 * s), ry), 0, 0, 360, 255, -1)
    elif kind == "taper":       # a crown tapering to a bottom 1.5x the trunk's width
        yb, yt, wt, wb = top + int(0.03 * s), int(0.06 * s), 0.3 * s, 0.75 * tw
        poly = np.array([[tx - wb, yb], [tx - wt, yt + 0.3 * (yb - yt)], [tx - 0.6 * wt, yt],
                         [tx + 0.6 * wt, yt], [tx + wt, yt + 0.3 * (yb - yt)], [tx + wb, yb]])
        cv2.fillPoly(crown, [np.round(poly).astype(np.int32)], 255)
    else:                       # "round", "bent": a disc over the trunk's top
        r = int(0.3 * s)
        cv2.circle(crown, (tx, top - int(0.6 * r)), r, 255, -1)
    drawn = {}
    for name, m, colour in (("trunk", trunk, (0.45, 0.28, 0.15)), ("crown", crown, (0.3, 0.62, 0.25))):
        mo = cv2.dilate(m, _disk(ow)) if ow else m
        col[mo > 0] = (0.08, 0.06, 0.05)
        col[m > 0] = colour
        a[mo > 0] = 255
        drawn[name] = mo
    cs, _ = cv2.findContours((a > 0).astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    c = max(cs, key=len)[:, 0, :].astype(float)
    near_crown = cv2.dilate(drawn["crown"], _disk(2)) > 0
    is_trunk = ~near_crown[c[:, 1].astype(int), c[:, 0].astype(int)]
    low = np.flatnonzero(c[:, 1] >= c[:, 1].max() - 1)
    ib = int(low[np.argmin(np.abs(c[low, 0] - c[low, 0].mean()))])
    ends = []
    for step in (1, -1):
        i = ib
        while is_trunk[(i + step) % len(c)]:
            i = (i + step) % len(c)
        ends.append(c[i])
    r, l = sorted(ends, key=lambda p: -p[0])
    pins = {k: (np.asarray(p, float) + 0.5) / 4 - 0.5 for k, p in (("B", c[ib]), ("R", r), ("L", l))}
    small = cv2.resize(np.dstack([col * (a[..., None] / 255.0), a / 255.0]).astype(np.float32),
                       (size, size), interpolation=cv2.INTER_AREA)
    rgb = small[..., :3] / np.maximum(small[..., 3:4], 1e-6)
    return np.dstack([np.clip(rgb, 0, 1), small[..., 3]]).astype(np.float32), pins


@pytest.mark.parametrize("kind,size,outline,trunk", [
    ("ellipse", 96, True, "stem"), ("ellipse", 192, False, "stem"), ("ellipse", 256, True, "stem"),
    ("taper", 96, True, "stem"), ("taper", 192, False, "stem"), ("taper", 256, True, "auto")])
def test_pins_of_a_crown_narrowing_onto_its_trunk_sit_at_the_corner(kind, size, outline, trunk):
    img, ref = _flat_tree(kind, size, outline)
    ex = process_exemplar(img, kind, size=size, trunk=trunk)
    err = pin_errors(source_pins(ex), ref, img[..., 3])
    # before: R and L 3.6-9.7 % of the height up the crown's sides (the trunk mask's neck); after <= 1.7 %
    assert max(err["R"], err["L"]) < 0.025, err


@pytest.mark.parametrize("kind", ["round", "bent"])
def test_pins_of_round_crowns_and_bent_trunks_stay_at_the_corner(kind):
    # a bent trunk's inner side is concave too, but turns far less than a junction
    img, ref = _flat_tree(kind, 192, True, seed=1)
    err = pin_errors(source_pins(process_exemplar(img, kind, size=192)), ref, img[..., 3])
    assert max(err["R"], err["L"]) < 0.03, err


def test_stem_mask_pins_leave_the_neck_to_the_crown():
    img, ref = _flat_tree("ellipse", 192, False)
    alpha = img[..., 3] >= 0.5
    pins = pin_points(extract_contours(alpha).tree, alpha)   # the geometric stem mask
    for p, key in ((pins.r, "R"), (pins.l, "L")):
        assert np.hypot(*(p - ref[key])) < 2.5, (p, ref[key])


def test_concave_turns_read_an_l_corner():
    m = np.zeros((60, 60), np.uint8)
    m[10:50, 10:30] = 1
    m[30:50, 10:50] = 1
    c = extract_contours(m > 0).tree
    t = concave_turns(c, 4.0)
    corner = np.argmin(np.hypot(c[:, 0] - 30, c[:, 1] - 30))
    assert 50 < t[corner] < 100   # smoothed over half the window
    assert np.argmax(t) in (np.arange(corner - 3, corner + 4) % len(c))
    # the five convex corners turn the other way
    assert (t < -60).sum() >= 5 and t[np.abs(c[:, 1] - 10) < 0.5].max() < 20

