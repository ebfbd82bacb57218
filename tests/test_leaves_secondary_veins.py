"""Secondary veins an exemplar's colour term puts just above the training leaf's ``delta`` (issue 22).

Procedural trilobed family at 192 px, seed 3, training leaf 2: exemplar 0's darker blade, matched onto
the training leaf's statistics, lifted its veins' colour term (median ``S`` 0.127 against 0.086 on the
training leaf; plain blade 0.194 / 0.182 at its 10th percentile) above the training ``delta`` 0.145, and
only its midrib and the snapped paths were induced (vein IoU 0.43; a whole lobe's lateral lost). Its own
ridge pixels (found near the carried layer, 0.997 of them on true veins, 0.82 of the veins) now choose
its ``delta`` beside them (:func:`branchnb.leaves.analysis_masks._exemplar_mask`): IoU 0.74.
"""

import numpy as np

from branchnb.core.metrics import iou
from branchnb.leaves import Layer, LayerSet, analysis_masks, analyze, leaf_family, simulate_scribbles
from branchnb.leaves.analysis_masks import _exemplar_mask, _MaskSteps


def _on_canvas(m, offset, shape, mirrored):
    out = np.zeros(shape, bool)
    dx, dy = offset
    out[dy:dy + m.shape[0], dx:dx + m.shape[1]] = m
    return out[:, ::-1].copy() if mirrored else out


def test_an_exemplar_whose_veins_sit_above_the_training_delta_keeps_its_secondaries():
    assert analysis_masks._RIDGE_DELTA == 2  # on by default
    size = 192
    fam = leaf_family(3, size=size, kind="trilobed", rng=3)
    t = 2
    ls = LayerSet([Layer("veins", "#d62728", 0, simulate_scribbles(fam[t].layers["veins"], 10,
                                                                   length=0.06 * size, rng=0)),
                   Layer("spots", "#1f77b4", 1, simulate_scribbles(fam[t].layers["spots"], 10,
                                                                   length=0.025 * size, rng=0))])
    a = analyze(fam, t, ls)
    shape = a.blades[0].shape
    veins = [iou(a.layer("veins").masks[e], _on_canvas(fam[e].layers["veins"], a.offsets[e], shape, a.mirrored[e]))
             for e in range(3)]
    spots = [iou(a.layer("spots").masks[e], _on_canvas(fam[e].layers["spots"], a.offsets[e], shape, a.mirrored[e]))
             for e in range(3)]
    # before: 0.43 / 0.73, now 0.74 / 0.74 (the training leaf's grown layer 0.75 either way)
    assert veins[0] >= 0.7 and veins[1] >= 0.72
    # spots 0.95 / 0.96 before, 0.94 / 0.96 after
    assert min(spots[:2]) >= 0.9


def _steps(own_px=None, zones=None):
    blade = np.zeros((60, 60), bool)
    blade[5:55, 5:55] = True
    user = np.zeros_like(blade)
    user[30, 8:52] = True                        # the training layer: one vein
    snapped = np.zeros_like(blade)
    snapped[20, 8:52] = True                     # the exemplar's main vein, snapped
    ridge = snapped.copy()
    ridge[21:40, 30] = True                      # a side vein: its own ridge pixels
    n = [None, None]
    return blade, snapped, ridge, _MaskSteps(user, [blade, blade], 0, [None, snapped], [None, snapped], n,
                                             [None, own_px], [None, ridge], [None, zones], n, False, False)


def test_own_ridge_pixels_choose_the_delta_beside_them():
    blade, snapped, ridge, steps = _steps()
    combined = np.full(blade.shape, 0.8, np.float32)
    combined[20, 8:52] = 0.1                     # the main vein under the training delta
    combined[21:40, 30] = 0.35                   # the side vein just above it (0.3)
    combined[45, 10:20] = 0.35                   # a short line as faint, away from the exemplar's ridges
    flat = np.zeros(blade.shape, np.float32)     # the contrast map: no trim
    m, _ = _exemplar_mask(steps, 1, combined, 0.3, 0.8, np.zeros_like(blade), lambda e: flat)
    assert m[21:40, 30].all()                    # before: not one pixel of the side vein
    assert not m[45].any()                       # only beside the own pixels
    assert not m[10, 10] and not m[30, 20]       # plain blade stays out
    # The same D with the side vein under the training delta: nothing to raise, the same mask.
    combined[21:40, 30] = 0.2
    m2, c2 = _exemplar_mask(steps, 1, combined, 0.3, 0.8, np.zeros_like(blade), lambda e: None)
    assert c2 is None and m2[21:40, 30].all() and not m2[45].any()


def test_ridges_that_are_no_layer_keep_the_training_delta():
    # Ridges far above the training delta (a painted-out blade's noise ridges, 6.2x; a plain-fill
    # drawing's ink outline, 2.4x) or on a drawn exemplar (an ink outline zone: its ridges hold its
    # outline) leave the delta as it was.
    blade, snapped, ridge, steps = _steps()
    combined = np.full(blade.shape, 0.8, np.float32)
    combined[20, 8:52] = 0.1
    combined[21:40, 30] = 0.35
    flat = np.zeros(blade.shape, np.float32)
    m, _ = _exemplar_mask(steps, 1, combined, 0.3, 0.8, np.zeros_like(blade), lambda e: flat)
    assert m[21:40, 30].all()
    combined[21:40, 30] = 0.65                   # beyond RIDGE_RAISE_MAX (2) x delta
    combined[blade & (combined > 0.7)] = 0.9
    m, _ = _exemplar_mask(steps, 1, combined, 0.3, 0.8, np.zeros_like(blade), lambda e: flat)
    assert not m[21:40, 30].any() and m[20, 10:50].all()
    combined[blade & (combined > 0.7)] = 0.8     # in reach again, but on an exemplar with an ink outline zone
    combined[21:40, 30] = 0.35
    zone = np.zeros_like(blade)
    zone[5:8] = True
    _, _, _, steps = _steps(zones=(zone, 3.0))
    m, _ = _exemplar_mask(steps, 1, combined, 0.3, 0.8, np.zeros_like(blade), lambda e: flat)
    assert not m[21:40, 30].any()
