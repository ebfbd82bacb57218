"""Hub examples' thin twigs and tips (issue 23, branching119): a fragment's gradient-domain correction
no longer takes its boundary from an older line's edge that the fragment has as ground (or the other
way round; faded thin twigs and light specks at tips and junctions)."""
import cv2
import numpy as np
import pytest

from branchnb.branching import extract_structure, fit_model, synthesize_image, synthesize_structure
from branchnb.branching._radial_examples import radial_example
from branchnb.core.blending import compose_piece


def _compose(neutral: bool) -> np.ndarray:
    canvas = np.full((16, 16, 1), 0.8, np.float32)
    canvas[5:11, 6:8] = 0.1  # an older line's edge beside the seam
    covered = np.zeros((16, 16), bool)
    covered[:, :8] = True
    piece = np.full((16, 12, 1), 0.8, np.float32)
    valid = np.zeros((16, 12), bool)
    valid[:, 4:] = True  # canvas columns 8-15
    nc = None
    if neutral:
        nc = np.zeros((16, 12), bool)
        nc[5:11, 2:4] = True
    compose_piece(canvas, covered, piece, valid, (4, 0), neutral_canvas=nc)
    return canvas[..., 0]


def test_neutral_canvas_pixels_do_not_constrain_the_correction():
    plain, neutral = _compose(False), _compose(True)
    # the dark edge pulls the new ground down to 0.23 beside it; neutral, the piece keeps its 0.8
    assert plain[8, 8] < 0.4
    assert np.abs(neutral[:, 8:] - 0.8).max() < 1e-4
    with pytest.raises(ValueError, match="neutral_canvas"):
        compose_piece(np.zeros((4, 4, 1), np.float32), np.zeros((4, 4), bool), np.zeros((4, 4, 1), np.float32),
                      np.ones((4, 4), bool), (0, 0), neutral_canvas=np.zeros((2, 2), bool))


def _specks(out: np.ndarray, ex: np.ndarray) -> int:
    """Blobs of the output (3 x 3 mean) brighter or darker than 99.9 % of the example's by 0.02."""
    sm = lambda a: cv2.blur(a, (3, 3))  # noqa: E731
    hi, lo = np.percentile(sm(ex), 99.9), np.percentile(sm(ex), 0.1)
    bad = (sm(out) > hi + 0.02) | (sm(out) < lo - 0.02)
    return cv2.connectedComponents(bad.astype(np.uint8))[0] - 1


def test_no_light_specks_at_a_dark_neurons_tips():
    rgb, _centre, _lines, _hubs = radial_example("neuron_dark", 384, 1)
    s = extract_structure(rgb)
    res = synthesize_structure(fit_model(s), rng=1)
    out = np.asarray(synthesize_image(rgb, s, res, rng=1).image)[..., :3].mean(-1)
    assert _specks(rgb.mean(-1), rgb.mean(-1)) == 0
    # main: 14 light specks (white sparkles at tips and junctions); now 4
    assert _specks(out, rgb.mean(-1)) <= 7
