"""A scattered layer's own-colour pixels against the layers above's colours too (layer_coloured ``above``)."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.leaves.induction_scatter import layer_coloured, refine_edges

BLADE, SPOT, VEIN = np.array([50.0, -30.0, 40.0]), np.array([30.0, 20.0, 30.0]), np.array([70.0, 25.0, 45.0])


def _leaf(size):
    # A dark spot with a paler orange vein across it (an autumn leaf); the vein's soft edge
    # (each side, 2 px) mixes the two.
    yy, xx = np.mgrid[:size, :size]
    c = size / 2
    spot = np.hypot(yy - c, xx - c) < size / 6
    dist = np.abs(xx - c)
    vein_cov = np.clip(1.75 - dist / 2, 0, 1)  # full within 1 px, 3/4 at 2 px, 1/4 at 3 px
    base = np.where(spot[..., None], SPOT, BLADE)
    lab = base * (1 - vein_cov[..., None]) + VEIN * vein_cov[..., None]
    truth = spot & (vein_cov <= 0.5)
    return lab, np.ones((size, size), bool), truth, vein_cov >= 0.5


@pytest.mark.parametrize("size", [64, 200])
def test_vein_edge_over_a_spot_is_not_the_spots(size):
    lab, blade, truth, vein = _leaf(size)
    before = layer_coloured(lab, blade, SPOT, vein)
    after = layer_coloured(lab, blade, SPOT, vein, above=[VEIN])
    wrong = lambda m: int((m & ~truth).sum())  # noqa: E731
    assert wrong(before) > 0
    assert wrong(after) < wrong(before)
    # The mix at over half vein is the vein's; the spot's own pixels all stay.
    assert int((after & (truth & ~vein)).sum()) >= int((truth & ~vein).sum()) - 2 * size // 50
    m = refine_edges(truth, after, blade & ~vein)
    assert (m & truth).sum() / (m | truth).sum() >= 0.95


def test_above_colours_are_checked():
    lab, blade, _, _ = _leaf(32)
    with pytest.raises(ValueError, match="above"):
        layer_coloured(lab, blade, SPOT, above=[[1.0, 2.0]])
    # No layers above: as before.
    assert np.array_equal(layer_coloured(lab, blade, SPOT, above=[]), layer_coloured(lab, blade, SPOT))


@pytest.mark.parametrize("size", [96, 400])
def test_local_colours_keep_a_spots_edge_off_the_blade_beside_it(size):
    # A blade darker round the spot than elsewhere (mottling) and a spot redder than the training colour:
    # its edge pixels, a third spot, were nearer the training colour than the whole blade's median.
    yy, xx = np.mgrid[:size, :size]
    c, r = size / 2, size / 10
    d = np.hypot(yy - c, xx - c)
    cov = np.clip(r + 0.5 - d, 0, 1)
    dark = np.hypot(yy - c, xx - c) < 3 * r
    blade_lab = np.where(dark[..., None], [40.0, -20.0, 35.0], [60.0, -35.0, 45.0])
    own_spot, trained = np.array([25.0, 50.0, 25.0]), np.array([34.0, 9.0, 30.0])
    lab = blade_lab * (1 - cov[..., None]) + own_spot * cov[..., None]
    blade, truth = np.ones((size, size), bool), cov > 0.5
    found = ndi.binary_dilation(truth)
    iou = lambda m: (m & truth).sum() / (m | truth).sum()  # noqa: E731
    plain = refine_edges(found, layer_coloured(lab, blade, trained), blade)
    local = refine_edges(found, layer_coloured(lab, blade, trained, local=True), blade)
    assert iou(local) > iou(plain) + 0.02, (iou(local), iou(plain))
    assert iou(local) >= 0.97
