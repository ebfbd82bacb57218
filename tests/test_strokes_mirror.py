"""A bent part copied as its mirror image (issue 25, unseen kinds): a candelabra cactus's arm
copied to the trunk's other side, drawn mirrored.

With rotated patches only (the paper's) the outer side of the source's elbow
landed on the inner side of the copy's, an X of cut faces across the elbow;
mirror-image patches draw the arm's mirror image. Measured right of the trunk,
where only the new arm lies: its pixels against the source arm reflected.
"""
import numpy as np
import pytest
from scipy import ndimage as ndi
from strokes_unseen_objects import edit_cactus

from branchnb.strokes import Stroke, StrokePair, edit_structure
from branchnb.strokes.edit import _mirrored


def _expected_copy(obj, src_arm, tgt_arm, shape):
    """The source arm's pixels reflected and moved onto the copy's stroke (looked up from each
    output pixel: the inverse map)."""
    yy, xx = np.mgrid[0:shape[0], 0:shape[1]]
    x = np.rint(src_arm[0][0] - (xx - tgt_arm[0][0])).astype(int)
    y = np.rint(src_arm[0][1] + (yy - tgt_arm[0][1])).astype(int)
    ok = (x >= 0) & (x < obj.labels.shape[1]) & (y >= 0) & (y < obj.labels.shape[0])
    out = np.zeros(shape, bool)
    out[ok] = obj.labels[y[ok], x[ok]] == 3
    return out


@pytest.mark.parametrize("n", [300, 600])
def test_mirrored_arm_copy(n):
    obj, src, tgt, _, _ = edit_cactus(n)
    res = edit_structure(obj.image, src, tgt)
    a = res.image[..., 3] > 0.5
    want = _expected_copy(obj, src[5], tgt[5], a.shape)
    # right of the trunk (its half width 40/600 of the side, 4 px more), below the right arm's elbow
    x_trunk = obj.strokes[0][0][0] + 40 * n / 600 + 4
    y_top = tgt[5][:, 1].min() - 30 * n / 600
    region = np.zeros(a.shape, bool)
    region[int(y_top):, int(np.ceil(x_trunk)):] = True
    region &= ~ndi.binary_dilation(obj.labels == 2, iterations=3)  # the kept right arm
    got, exp = a & region, want & region
    iou = (got & exp).sum() / max((got | exp).sum(), 1)
    extra = (got & ~ndi.binary_dilation(exp, iterations=2)).sum()
    # rotated patches (before): IoU 0.57 / 0.65 at 300 / 600 px (0.57 at 1000), 935 / 2974 px outside
    # (the X; 11933 at 1000); mirror images: IoU 0.94 / 0.99 (1.00), none outside
    assert iou > 0.9, iou
    assert extra < 0.01 * exp.sum(), (extra, exp.sum())


def test_mirror_only_for_opposite_bends():
    L = Stroke([(0, 0), (40, 0), (40, -30)])
    mirrored = Stroke([(0, 0), (-40, 0), (-40, -30)])
    turned = Stroke([(0, 0), (0, -40), (-30, -40)])  # the same bend, rotated a quarter turn
    straight = Stroke([(0, 0), (70, 0)])
    assert _mirrored(StrokePair(L, mirrored), 8.0)
    assert not _mirrored(StrokePair(L, turned), 8.0)
    assert not _mirrored(StrokePair(L, straight), 8.0)
    assert not _mirrored(StrokePair(straight, Stroke([(0, 0), (-70, 0)])), 8.0)
