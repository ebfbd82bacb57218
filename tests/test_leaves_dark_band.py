"""Dark margin bands round a pale centre (issue 22, leaves88): an exemplar's own delta beside its snapped veins.

Procedural variegated leaves of ``tests/test_leaves_margin_band.py`` with a dark green band round a pale
centre, 256 px, seeds 40-43. main: vein IoU 0.984 / 0.491 / 0.848 / 0.548; exemplar 3 lost its midrib's
lower half: its ``D`` there (0.236) was over the training delta (0.155), under the exemplar's own (0.243),
which reached only beside its own ridge pixels, not the snapped midrib (then 0.533 / 0.868 / 0.892);
exemplar 1 had blobs along the band's inner edge, the pale side of its step taken for the exemplar's own
vein pixels. Now 0.984 / 0.841 / 0.866 / 0.908.
"""

import warnings

from test_leaves_margin_band import _layers, _variegated

from branchnb.core.metrics import iou
from branchnb.leaves import analyze
from branchnb.leaves._measure_unseen import _on_canvas


def test_dark_band_veins_keep_their_midrib():
    s = 256
    leaves = [_variegated(seed, s, "dark") for seed in range(40, 44)]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = analyze([im for im, _, _ in leaves], 0, _layers(leaves[0][1], leaves[0][2], s), mirror=False)
    veins, margin = a.layer("veins"), a.layer("margin")
    truth = [_on_canvas(leaves[e][2], a.offsets[e], a.blades[e].shape, a.mirrored[e]) for e in range(4)]
    band = [_on_canvas(leaves[e][1], a.offsets[e], a.blades[e].shape, a.mirrored[e]) for e in range(4)]
    got = [iou(veins.masks[e], truth[e]) for e in range(4)]
    assert got[3] >= 0.85, got  # main 0.548: the midrib's lower half
    assert min(got) >= 0.8, got  # main 0.491, the own delta beside the snapped veins alone 0.533
    assert min(iou(margin.masks[e], band[e]) for e in range(4)) >= 0.85


def test_own_vein_pixels_are_lines_not_the_pale_side_of_a_step():
    """main: 156 of the 200 pixels returned lay beside the band's edge, 44 on the vein; now 0 and 104."""
    import numpy as np

    from branchnb.leaves.own_contrast import exemplar_direction
    lab = np.zeros((60, 80, 3))
    lab[..., 0], lab[..., 2] = 80.0, 30.0
    lab[:, :20, 0] = 35.0  # a dark band along the left
    lab[:, 50:52, 0] = 92.0  # a pale vein in the pale centre
    blade = np.ones((60, 80), bool)
    prior = np.zeros_like(blade)
    prior[5:55, 48:50] = True  # the vein carried 2 px off
    prior[5:55, 22:24] = True  # a carried vein the exemplar lacks, next to the band
    _, _, pix = exemplar_direction(lab, blade, prior, 2.0, [1.0, 0, 0], radius=5.0, return_pixels=True)
    assert pix[:, 50:52].sum() >= 80
    assert not pix[:, 15:26].any()
