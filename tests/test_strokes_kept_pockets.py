"""A pocket the source has stays open when a joint's closing is kept from it.

Found on a real fern frond (pinnae crowded at a bent tip): ``fill_joints``
made the pixels next to its new ones opaque without a colour where
``keep_open`` had kept them open, so black specks showed inside the object.
"""

import numpy as np

from branchnb.strokes.outline import fill_joints


def _slit_bar():
    layer = np.zeros((40, 40, 4), np.float32)
    layer[:, 10:20] = (0.5, 0.3, 0.1, 1.0)
    layer[14:24, 20:34] = (0.5, 0.3, 0.1, 1.0)
    layer[10:28, 18:20] = 0.0     # a slit along the bar, beside the arm's joint
    return layer


def test_kept_pocket_stays_open_and_nothing_turns_dark():
    layer = _slit_bar()
    upper = np.arange(40)[:, None] < 19
    out = fill_joints(layer, [(19, 19)], [10.0], keep_open=lambda r, c, k: r < 19)
    newly = (out[..., 3] > 0.5) & (layer[..., 3] <= 0.5)
    assert newly.sum() > 0                               # the lower slit is closed
    assert (newly & upper).sum() == 0                    # the kept pocket is not
    dark = (out[..., :3].max(-1) < 0.2) & (out[..., 3] > 0.5)
    assert dark.sum() == 0
