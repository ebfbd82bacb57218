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
    _, kept, got = snap_layer(ev, blade, [chain], [width], 6.0, centre=centre)
    assert kept == 1.0
    assert iou(got & box, truth & box) >= 0.9, iou(got & box, truth & box)
    # Told the training leaf's wider width (3 px), a 2 px vein keeps its own width.
    if width == 2.0:
        _, _, wide = snap_layer(ev, blade, [chain], [3.0], 6.0, centre=centre)
        assert iou(wide & box, truth & box) >= 0.85
        even, _ = snap_layer(ev, blade, [chain], [width], 6.0)
        assert iou(even & box, truth & box) < 0.75


def test_grow_to_width_stops_at_its_cap():
    from branchnb.leaves.snapping import GROW_CAP
    path = np.zeros((9, 12), bool)
    path[4] = True
    score = np.ones((9, 12))
    grown = _grow_to_width(path, 2.0, score)
    assert grown.sum() == round(2.0 * GROW_CAP * 12) and grown[4].all()
    assert (_grow_to_width(path, 1.0, score) == path).all()


def test_induced_side_veins_lie_on_the_exemplars_own():
    """The issue's worst case: an elliptic family at 192 px, seed 2, training leaf 2 -> exemplar 3,
    registration perturbed by twice the vein width. The snapped layer sat on the true veins' skeleton but
    3 px wide on 1.7 px veins (precision 0.60) and the induced side veins ran one pixel beside the true
    ones: IoU 0.64. Now the centred snapped layer's precision >= 0.85 and the induced IoU >= 0.69."""
    from branchnb.leaves._measure import _family_on_canvas, _Perturbed, _TrueRegistration, main_vein_width
    from branchnb.leaves.analysis import analyze

    fam, gt, kps, shape = _family_on_canvas("elliptic", 192, 4, 2)
    t, e = 2, 3
    amp = 2.0 * float(np.median([main_vein_width(g["veins"]) for g in gt]))
    rng = np.random.default_rng((2, t))
    regs = [_TrueRegistration(k, kps[t], shape) for k in kps]
    regs = [r if i == t else _Perturbed(r, amp, rng) for i, r in enumerate(regs)]
    a = analyze(fam, t, {"veins": fam[t].layers["veins"]}, registrations=regs)
    layer = a.layer("veins")
    truth = gt[e]["veins"]
    snapped = layer.centred[e]
    assert (snapped & truth).sum() >= 0.85 * snapped.sum()
    assert iou(layer.masks[e], truth) >= 0.69, iou(layer.masks[e], truth)
