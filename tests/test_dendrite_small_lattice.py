"""Small pictures (64-160 px) are planned on a lattice about their own size, with the look of the
512-px lattice (issue 25, dendrite45): the same ink and solid ink on the object, strokes at least
a pixel wide, the vines' tips; pictures from ~215 px up keep the 512 lattice, bit for bit."""

import numpy as np
import pytest
from scipy import ndimage as ndi
from skimage.transform import resize

from branchnb.dendrite import StylizeParams, Stylizer, stylize
from branchnb.dendrite import scale as scale_mod
from branchnb.dendrite.scale import lattice_shape, planning_size


def _blob(width: int, kind: str) -> tuple[np.ndarray, np.ndarray]:
    """A wobbly blob (mid-grey fill, or a light fill in a dark outline) on white, drawn at 800 px
    and resized to ``width``; its mask at ``width``."""
    n, h = 800, 600
    y, x = np.mgrid[0:h, 0:n] / n
    th = np.arctan2(y - 0.375, x - 0.5)
    rad = np.hypot((x - 0.5) / 0.33, (y - 0.375) / 0.24)
    body = rad < 1 + 0.12 * np.sin(3 * th + 1.0) + 0.06 * np.sin(7 * th)
    img = np.where(body, 0.45 if kind == "mid" else 0.7, 1.0)
    if kind == "outlined":
        img[body & ~ndi.binary_erosion(body, iterations=10)] = 0.05
    shape = (round(h * width / n), width)
    small = resize(img, shape, order=1, anti_aliasing=True).astype(np.float32)
    return small, resize(body.astype(float), shape, order=1, anti_aliasing=True) > 0.5


def _on_512(monkeypatch):
    # the former rule: every picture on the 512 lattice
    monkeypatch.setattr(scale_mod, "SMALL_LATTICE_RATIO", 1e9)


def test_planning_size_rule():
    assert planning_size((188, 250), 512) == 512  # from ~215 px (square of the diagonal) up
    assert planning_size((1500, 2000), 512) == 512
    for w in (64, 96, 160):
        h = round(0.75 * w)
        side = np.sqrt(0.5 * (h * h + w * w))
        assert 2.0 * side <= planning_size((h, w), 512) <= 2.5 * side
    assert planning_size((48, 64), 0) == 0 and planning_size((4, 4), 512) == 16
    assert planning_size((48, 64), 100) == 100  # never above the size asked for
    st = Stylizer(np.ones((72, 96)))
    assert st.working_image(StylizeParams()).shape[:2] == lattice_shape((72, 96), planning_size((72, 96), 512))
    assert st.size_scale(StylizeParams()) == pytest.approx(np.sqrt(72 * 96) / np.sqrt(
        np.prod(lattice_shape((72, 96), 512))), rel=0.02)


@pytest.mark.parametrize("width, kind", [(64, "mid"), (96, "outlined"), (160, "mid")])
def test_small_lattice_keeps_the_look(width, kind, monkeypatch):
    img, m = _blob(width, kind)
    new = stylize(img, rng=0)
    _on_512(monkeypatch)
    old = stylize(img, rng=0)
    assert max(new.importance.shape) < 2.6 * width < max(old.importance.shape)
    ink_new, ink_old = (1.0 - r.rendering.image.mean(axis=2) for r in (new, old))
    # measured: ink 0.94 / 0.84 / 1.01 and solid ink 0.94 / 0.81 / 1.01 of the 512-lattice
    # result (the issue asks 250 against 750 px for 20 % and 0.6x)
    assert ink_new[m].mean() == pytest.approx(ink_old[m].mean(), rel=0.2)
    assert (ink_new[m] > 0.5).mean() >= 0.7 * (ink_old[m] > 0.5).mean()
    assert 2.0 * new.dendrite.radius.min() >= 0.99  # no stroke thinner than a pixel
    # ink on the paper round the object stays as rare as before
    far = ~ndi.binary_dilation(m, iterations=3)
    assert ink_new[far].mean() <= ink_old[far].mean() + 0.02


def test_small_lattice_vines_keep_their_tips(monkeypatch):
    img, m = _blob(96, "mid")
    new = stylize(img, rng=0, metaphor="vines")
    _on_512(monkeypatch)
    old = stylize(img, rng=0, metaphor="vines")
    assert abs(len(new.dendrite.tips) - len(old.dendrite.tips)) <= 0.25 * len(old.dendrite.tips) + 2
    green = lambda r: (r.rendering.image[..., 1] - r.rendering.image[..., 0] > 0.15)  # noqa: E731
    assert green(new).mean() == pytest.approx(green(old).mean(), rel=0.3)


def test_pictures_from_250_px_are_unchanged(monkeypatch):
    img, _ = _blob(250, "mid")
    new = stylize(img, rng=0)
    _on_512(monkeypatch)
    old = stylize(img, rng=0)
    assert new.importance.shape == old.importance.shape
    assert np.array_equal(new.rendering.image, old.rendering.image)
