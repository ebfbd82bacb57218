"""Leaf analysis steps that work on the blade's box: the same answers on a padded canvas (issue 22, memory)."""

import numpy as np
import pytest
from leaves_truth import TrueRegistration
from test_leaves_snapping import _star

from branchnb.core.metrics import iou
from branchnb.leaves import induction, induction_colour, induction_residual
from branchnb.leaves.induction import remove_layer
from branchnb.leaves.snapping import blade_box


def _pad(a, p):
    widths = [(p, p), (p, p)] + [(0, 0)] * (a.ndim - 2)
    return np.pad(a, widths)


def test_every_induction_name_is_importable_from_induction_after_the_split():
    for mod in (induction_colour, induction_residual):
        for name in mod.__all__:
            assert getattr(induction, name) is getattr(mod, name), name
    assert set(induction.__all__) >= set(induction_colour.__all__) | set(induction_residual.__all__)


def test_blade_box_is_the_padded_bounding_box_clipped_to_the_image():
    b = np.zeros((50, 60), bool)
    b[10:20, 30:45] = True
    assert blade_box(b, 4) == (6, 24, 26, 49)
    assert blade_box(b, 100) == (0, 50, 0, 60)
    assert blade_box(np.zeros((5, 6), bool), 2) == (0, 5, 0, 6)


@pytest.mark.parametrize("pad", [60, 200])
def test_vein_residual_does_not_depend_on_the_canvas_around_the_blade(pad):
    """The vein fill (Telea on the nearest-colour extension) reads the blade only: the residual of a
    star on a canvas padded by 20 px equals the one padded by ``pad`` px (max difference 0) away from
    the junction, where the veins meet in a blob filled by random patch quilting."""
    img, blade, veins = _star([-90, -120, -60, -155, -25])
    near = remove_layer(_pad(img, 20), _pad(blade, 20), _pad(veins, 20))[20:-20, 20:-20]
    far = remove_layer(_pad(img, pad), _pad(blade, pad), _pad(veins, pad))
    diff = np.abs(far[pad:-pad, pad:-pad] - near).max(-1)
    yy, xx = np.mgrid[:140, :140]
    junction = np.hypot(xx - 70, yy - 120) < 20
    assert diff[~junction].max() < 1e-6
    assert not far[:pad].any()                              # outside the blade: unchanged (0)
    # The veins are gone: their pixels now read as the blade around them.
    green = np.array([0.25, 0.5, 0.15])
    assert np.abs(near[veins] - green).mean() < 0.05 < np.abs(img[veins] - green).mean()


def test_snapping_on_a_padded_canvas_finds_the_same_veins():
    """snap_to_exemplars works on each exemplar's blade box: a star snapped onto another on a canvas
    padded by 20 px and by 120 px gives the same layer (IoU 1) and finds the exemplar's veins (IoU >= 0.7)."""
    from skimage.color import rgb2lab

    from branchnb.leaves.snapping import snap_to_exemplars
    img_t, blade_t, veins_t = _star([-90, -115, -65, -150, -30])
    img_e, blade_e, veins_e = _star([-90, -125, -55, -160, -20])
    blade = blade_t | blade_e
    got = []
    for p in (20, 120):
        s = 140 + 2 * p
        ident = np.array([[0, 0], [s - 1, 0], [0, s - 1], [s - 1, s - 1.]])
        reg = TrueRegistration(ident, ident, (s, s))
        labs = [rgb2lab(_pad(img_t, p)), rgb2lab(_pad(img_e, p))]
        masks, _ = snap_to_exemplars(labs, [_pad(blade, p)] * 2, 0, _pad(veins_t, p), [None, reg],
                                     tolerance=0.0)
        got.append(masks[1][p:p + 140, p:p + 140])
        assert masks[1].sum() == got[-1].sum()          # nothing outside the leaf's own box
    assert iou(got[0], got[1]) == 1.0
    assert iou(got[0], veins_e) >= 0.7 and iou(got[1], veins_e) >= 0.7
