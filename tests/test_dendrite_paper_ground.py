"""The plain metaphor on a drawing whose paper is not white: a light drawing on a dark
ground (neon sign, chalk on a blackboard) is drawn in light ink on that ground, and a
grainy coloured paper stays clean (beyond the paper: ``foreground._paper_ground``)."""

import xml.etree.ElementTree as ET

import cv2
import numpy as np
import pytest
from scipy import ndimage

from branchnb.dendrite import stylize
from branchnb.dendrite.foreground import _paper_ground


def _drawing(size: int, ground, ink, grain: float, seed: int):
    """A sun and a house drawn with lines ``size // 90`` px wide on a grainy ground."""
    rng = np.random.default_rng(seed)
    w, h = size, size * 3 // 4
    img = np.ones((h, w, 3), np.float32) * np.asarray(ground, np.float32)
    img += cv2.GaussianBlur(rng.normal(0, grain, (h, w)).astype(np.float32), (0, 0), 2)[..., None]
    lines = np.zeros((h, w), np.float32)
    t = max(2, w // 90)
    cv2.circle(lines, (w // 3, h // 2), w // 6, 1.0, t, cv2.LINE_AA)
    for a in np.linspace(0, 2 * np.pi, 9)[:-1]:
        p0 = (int(w / 3 + np.cos(a) * w / 5), int(h / 2 + np.sin(a) * w / 5))
        p1 = (int(w / 3 + np.cos(a) * w / 3.6), int(h / 2 + np.sin(a) * w / 3.6))
        cv2.line(lines, p0, p1, 1.0, t, cv2.LINE_AA)
    cv2.rectangle(lines, (int(w * 0.62), int(h * 0.35)), (int(w * 0.9), int(h * 0.8)), 1.0, t, cv2.LINE_AA)
    img = img * (1 - lines[..., None]) + lines[..., None] * np.asarray(ink, np.float32)
    return img.clip(0, 1), lines > 0.5


def _ink(rendering, ground):
    """Pixels of the rendering that differ from its ground's colour."""
    return np.abs(rendering - np.asarray(ground, np.float32)).max(axis=-1) > 0.25


CASES = [  # (ground, ink, grain, kind)
    ((0.05, 0.06, 0.15), (0.4, 1.0, 1.0), 0.015, "neon"),
    ((0.12, 0.2, 0.16), (0.9, 0.9, 0.9), 0.04, "chalk"),
    ((0.85, 0.78, 0.82), (0.1, 0.1, 0.1), 0.04, "pink card"),
    ((0.62, 0.55, 0.42), (0.08, 0.06, 0.05), 0.03, "kraft"),
]


@pytest.mark.parametrize("size", [200, 480])
@pytest.mark.parametrize("ground,ink,grain,kind", CASES)
def test_ground_stays_clean_and_drawing_is_drawn(size, ground, ink, grain, kind):
    img, lines = _drawing(size, ground, ink, grain, seed=size)
    out = stylize(img, rng=0)
    g = _paper_ground(img)
    assert g is not None and g.dark == (kind in ("neon", "chalk"))
    dark = g.dark
    paper = np.asarray(ground) if dark else np.ones(3)
    drawn = _ink(out.rendering.image[..., :3], paper)
    far = ~ndimage.binary_dilation(lines, iterations=max(6, size // 40))
    # a75e4dd: 0.16-0.58 of the far ground inked (the ground's tone and grain drawn)
    assert drawn[far].mean() <= 0.02, kind
    near = ndimage.binary_dilation(drawn, iterations=2)
    assert near[lines].mean() >= 0.6, kind
    if dark:  # light ink on the ground's own colour, in the SVG too
        assert np.allclose(out.rendering.image[far & ~drawn].mean(axis=0), ground, atol=0.03)
        svg = ET.fromstring(out.rendering.svg)
        rect = svg.find("{http://www.w3.org/2000/svg}rect")
        fill = rect.get("fill").lstrip("#")
        assert np.allclose([int(fill[i:i + 2], 16) / 255 for i in (0, 2, 4)], ground, atol=0.03)


def test_white_paper_and_photos_keep_the_papers_rule():
    from skimage import data

    img, _ = _drawing(240, (0.97, 0.97, 0.97), (0.1, 0.1, 0.1), 0.01, seed=1)
    assert _paper_ground(img) is None
    for photo in (data.astronaut(), data.camera(), data.coffee()):
        photo = np.asarray(photo, np.float32) / 255
        photo = np.repeat(photo[..., None], 3, -1) if photo.ndim == 2 else photo
        assert _paper_ground(cv2.resize(photo, (256, 256), interpolation=cv2.INTER_AREA)) is None


def test_user_background_and_colour_win():
    img, _ = _drawing(200, (0.05, 0.06, 0.15), (0.4, 1.0, 1.0), 0.015, seed=3)
    out = stylize(img, rng=0, background=np.ones_like(img), color=(0.0, 0.0, 0.0))
    corner = out.rendering.image[:10, :10]
    assert np.allclose(corner, 1.0)
