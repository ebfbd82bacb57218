"""Faint parallel veins (20 % darker than the blade) on small strip leaves (issue 22).

Radius-1 strokes over four of a 96-px strip's five parallel veins, 3-5 px
apart: the scribbles' plain blade between the veins was pinned to the
layer, which grew over the blade between them (training layer 1.4-1.5
times the veins' area) and the induced layer followed (IoU 0.44-0.49 on
the other leaves at a75e4dd). Now only the scribbled pixels on a line are
pinned (``layers._on_line_pins``): 0.73-0.81.
"""

import sys
from pathlib import Path

import numpy as np
import pytest
from scipy import ndimage as ndi

sys.path.insert(0, str(Path(__file__).parent))
from test_leaves_small_training import _leaf, _strokes  # noqa: E402

from branchnb.leaves import analyze, grow_layers  # noqa: E402


@pytest.mark.parametrize("seed", [0, 1])
def test_faint_strip_training_layer_keeps_off_the_blade_between_veins(seed):
    img, blade, veins, lines = _leaf("strip", 96, seed, contrast=0.8)
    m = grow_layers(img, blade, _strokes(lines, blade, veins, seed), rng=0).masks["veins"]
    off = m & ~ndi.binary_dilation(veins)
    # a75e4dd: 0.16 / 0.09 of the layer more than 1 px off every vein (seed 0 / 1), IoU 0.42 / 0.32; now 0.00,
    # IoU 0.57 / 0.45.
    assert off.sum() <= 0.05 * m.sum(), off.sum() / m.sum()
    assert (m & veins).sum() / (m | veins).sum() >= 0.4


@pytest.mark.parametrize("seeds", [(0, 1, 2), (3, 4, 5)])
def test_faint_strip_veins_induced_on_the_other_leaves(seeds):
    fam = [_leaf("strip", 96, s, contrast=0.8) for s in seeds]
    a = analyze([np.dstack([f[0], f[1].astype(np.float32)]) for f in fam], 0,
                _strokes(fam[0][3], fam[0][1], fam[0][2], seeds[0]))
    for i in (1, 2):
        veins = fam[i][2]
        m = np.asarray(a.layers[0].masks[i], bool)
        dx, dy = (int(v) for v in a.offsets[i])
        truth = np.zeros(m.shape, bool)
        truth[dy:dy + 96, dx:dx + 96] = veins
        # a75e4dd: 0.44 / 0.44 and 0.45 / 0.49; now 0.81 / 0.80 and 0.74 / 0.73.
        assert (m & truth).sum() / (m | truth).sum() >= 0.6, (seeds, i)
