"""Short side veins of a thin coloured layer are induced where the colour term takes the whole blade
(issue 22).

There (:func:`branchnb.leaves.analysis_combine._over_induced`) only the snapped paths were induced, and
they carry the training layer's main structure: a drawn maple's 1 px yellow side veins on orange were
missed (``_measure_drawn`` maple colour o3 640 px: recall 0.75). The exemplar's own layer pixels
joined to the paths are now taken (:func:`branchnb.leaves.analysis_masks._exemplar_mask`).
"""

import numpy as np
from scipy import ndimage as ndi

from branchnb.leaves.analysis_masks import _exemplar_mask, _MaskSteps


def _steps():
    blade = np.zeros((80, 80), bool)
    blade[5:75, 5:75] = True
    user = np.zeros_like(blade)
    user[40, 10:70] = True                       # the training layer: one main vein
    snapped = np.zeros_like(blade)
    snapped[30, 10:70] = True                    # the exemplar's own main vein, snapped
    ridge = snapped.copy()
    ridge[31:45, 25] = True                      # a side vein leaving it
    ridge[31:45, 50] = True                      # another
    ridge[55:70, 60] = True                      # a ridge not joined to the paths (a stray line)
    n = [None, None]
    zone = blade & ~ndi.binary_erosion(blade, iterations=3)     # a drawn leaf's ink outline zone
    return blade, _MaskSteps(user, [blade, blade], 0, [None, snapped], None, n, [None, ridge], [None, ridge],
                             [None, (zone, np.zeros(blade.shape, np.float32))], n, False, False), snapped


def test_side_veins_joined_to_the_snapped_paths_are_taken():
    blade, steps, snapped = _steps()
    combined = np.where(blade, 0.1, 1.0).astype(np.float32)       # {D < delta}: the whole blade (over)
    m, _ = _exemplar_mask(steps, 1, combined, 0.5, 0.9, np.zeros_like(blade), lambda e: None)
    assert m[snapped].all()
    assert m[31:45, 25].all() and m[31:45, 50].all()              # main: not taken (recall 0.75 on the maple)
    assert not m[55:70, 60].any()                                 # a stray ridge stays out
    assert not m[50, 40]                                          # plain blade stays out


def test_not_over_induced_layer_unchanged():
    blade, steps, snapped = _steps()
    combined = np.where(snapped, 0.1, 1.0).astype(np.float32)    # {D < delta}: the layer's size
    # (training overlap below COLOUR_RELIABLE: the snapped paths alone, as before)
    m, _ = _exemplar_mask(steps, 1, combined, 0.5, 0.4, np.zeros_like(blade), lambda e: None)
    assert np.array_equal(m, snapped)
    assert not m[31:45, 25].any()
