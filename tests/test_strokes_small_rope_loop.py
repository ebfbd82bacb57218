"""A rope re-stroked at 64 px behaves as at 256 px (issue 25, small images): the rest of the rope, a loop
touching the stroked piece at both cut ends, is no body the stroke grows out of (strokes.attachment._is_body).

At 64 px its contact at the stroke's start came out largest, so it was taken for the body and carried
unturned beside the new rope (opaque area 0.86 x length x width against 0.39-0.41 at 96-256 px)."""
import numpy as np
import pytest
from skimage.transform import resize

from branchnb import data
from branchnb.strokes import edit_structure


def _area_ratio(f: float) -> float:
    rope = data.load("rope_loop")
    r = resize(rope, (int(rope.shape[0] * f), int(rope.shape[1] * f)), anti_aliasing=True).astype(np.float32)
    src = np.array([(215, 515), (215, 815)], float) * f
    s = np.linspace(0, 1, 40)
    T = int(512 * f)
    tgt = np.column_stack([T / 2 + 0.27 * T * np.sin(2 * np.pi * s), 0.12 * T + 0.78 * T * s])
    e = edit_structure(r, [src], [tgt], target_shape=(T, T), rng=0)
    length = np.hypot(*np.diff(tgt, axis=0).T).sum()
    width = (r[..., 3] > 0.5)[int(515 * f):int(815 * f)].sum() / (300 * f)
    return float((e.image[..., 3] > 0.5).sum() / (length * width))


@pytest.fixture(scope="module")
def at_256():
    return _area_ratio(0.5)


@pytest.mark.parametrize("f", [0.125, 0.1875])
def test_small_rope_keeps_only_the_stroked_piece(f, at_256):
    assert abs(_area_ratio(f) - at_256) <= 0.15 * at_256
