"""Snapped veins centred on the exemplar's own vein: grown to the side it lies, at its own width."""

import numpy as np
import pytest

from branchnb.core.metrics import iou
from branchnb.leaves.snapping import _grow_to_width, snap_layer, vein_centre


def _rendered_vein(width, offset, size=(60, 120), slope=0.23):
    """Coverage of a straight vein ``width`` px wide whose centre line lies ``offset`` px off the pixel grid."""
    yy, xx = np.mgrid[:size[0], :size[1]].astype(float)
    # Supersampled 4 x 4 coverage of the band |distance to the centre line| <= width / 2.
    cov = np.zeros(size)
    for sy in (-0.375, -0.125, 0.125, 0.375):
        for sx in (-0.375, -0.125, 0.125, 0.375):
            d = ((yy + sy) - (25.0 + offset + slope * (xx + sx))) / np.hypot(1.0, slope)
            cov += np.abs(d) <= width / 2
    return cov / 16


@pytest.mark.parametrize("width,offset", [(2.0, 0.5), (2.0, 0.3), (1.5, 0.5), (3.0, 0.0), (1.0, 0.2)])
def test_snapped_vein_is_grown_to_the_side_its_vein_lies(width, offset):
    """A rendered vein (truth: coverage > 0.5), the carried-over branch 3 px beside it: the snapped path
    grown by the vein's own contrast covers the truth (2 px veins: IoU 0.60-0.67 grown evenly to 3 px,
    now >= 0.9); a vein narrower than the training width keeps its own."""
    cov = _rendered_vein(width, offset)
    truth = cov > 0.5
    ev = (cov / cov.max()).astype(np.float32)
    blade = np.ones(cov.shape, bool)
    xs = np.arange(10, 110)
    chain = np.column_stack([xs, np.round(25 + 0.23 * xs - 3)])
    lab = np.zeros(cov.shape + (3,))
    lab[..., 0] = 50 + 20 * cov
    centre = vein_centre(lab, blade, (1.0, 0.0, 0.0), width)
    box = np.zeros_like(truth)
    box[:, 15:105] = True
    got, kept = snap_layer(ev, blade, [chain], [width], 6.0, centre=centre)
    assert kept == 1.0
    assert iou(got & box, truth & box) >= 0.9, iou(got & box, truth & box)
    # Told the training leaf's wider width (3 px), a 2 px vein keeps its own width.
    if width == 2.0:
        wide, _ = snap_layer(ev, blade, [chain], [3.0], 6.0, centre=centre)
        assert iou(wide & box, truth & box) >= 0.85
        even, _ = snap_layer(ev, blade, [chain], [width], 6.0)
        assert iou(even & box, truth & box) < 0.75


def test_grow_to_width_checks_nothing_beyond_its_cap():
    path = np.zeros((9, 12), bool)
    path[4] = True
    score = np.ones((9, 12))
    grown = _grow_to_width(path, 2.0, score)
    assert grown.sum() == 24 and grown[4].all()
    assert (_grow_to_width(path, 1.0, score) == path).all()
