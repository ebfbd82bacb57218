"""The outline steps after composition run on the object's box (issue 25: edit speed) with the same result.

A small clip-art object on a large canvas with everything those steps act on:
cut faces (interior source depth at the silhouette), a stale rim inside,
pinholes, a fleck, and a hole open to the background; each step on the box
gives exactly what it gives on the whole canvas.
"""
import numpy as np
import pytest

from branchnb.strokes.outline import (
    _BOX_MARGIN,
    OutlineStyle,
    clear_stale_outline,
    close_cuts,
    drop_flecks,
    fill_pinholes,
)


def _scene(h=300, w=420, at=(120, 200)):
    layer = np.zeros((h, w, 4), np.float32)
    y, x = at
    layer[y:y + 60, x:x + 90] = (0.3, 0.6, 0.2, 1.0)
    layer[y + 20:y + 40, x + 88:x + 130] = (0.3, 0.6, 0.2, 1.0)   # an arm reaching right
    layer[y + 10, x + 30:x + 50, :3] = 0.05                       # a stale dark rim inside
    layer[y + 30, x + 10, 3] = 0.4                                # a pinhole
    layer[y + 45:y + 47, x + 60:x + 62, 3] = 0.0                  # a 2 x 2 hole
    layer[y + 50:y + 60, x + 20:x + 24, 3] = 0.0                  # a notch open to the background
    layer[y - 6, x + 40:x + 42] = (0.1, 0.1, 0.1, 1.0)            # a fleck
    depth = np.full((h, w), 9.0, np.float32)
    depth[y:y + 2, x:x + 90] = 1.0                                # the source rim along the top
    depth[y + 10, x + 30:x + 50] = 1.0
    filled = np.zeros((h, w), bool)
    filled[y + 12:y + 16, x + 40:x + 44] = True
    src_alpha = np.zeros((80, 80), np.float32)
    src_alpha[10:70, 10:70] = 1.0
    return layer, depth, filled, src_alpha


@pytest.mark.parametrize("at", [(120, 200), (0, 0), (240, 200), (120, 0)])
def test_steps_on_the_box_equal_the_whole_canvas(at):
    layer, depth, filled, src_alpha = _scene(at=at)
    style = OutlineStyle((0.05, 0.05, 0.05), 2.0)
    runs = [
        (close_cuts, (layer, depth, style), {}),
        (clear_stale_outline, (layer, depth, style), {"filled": filled}),
        (clear_stale_outline, (layer, depth, style), {}),
        (fill_pinholes, (layer, 2.0), {}),
        (drop_flecks, (layer, src_alpha), {}),
        (drop_flecks, (layer, src_alpha), {"level": 0.5}),
    ]
    for func, args, kw in runs:
        boxed = func(*args, **kw)
        whole = func.__wrapped__(*args, **kw)
        assert boxed.shape == whole.shape
        assert np.array_equal(boxed, whole), func.__name__
    # and each step did something on this scene (the comparison is not vacuous)
    assert not np.array_equal(close_cuts(layer, depth, style), layer)
    assert not np.array_equal(fill_pinholes(layer, 2.0), layer)
    assert not np.array_equal(drop_flecks(layer, src_alpha), layer)
    assert not np.array_equal(clear_stale_outline(layer, depth, style, filled=filled), layer)


def test_box_keeps_the_errors_and_empty_layers():
    layer, depth, filled, _ = _scene()
    style = OutlineStyle((0.05, 0.05, 0.05), 2.0)
    with pytest.raises(ValueError, match="filled"):
        clear_stale_outline(layer, depth, style, filled=filled[:-1])
    empty = np.zeros((50, 60, 4), np.float32)
    assert close_cuts(empty, np.zeros((50, 60), np.float32), style) is empty
    assert _BOX_MARGIN >= 1
