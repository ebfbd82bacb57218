"""Drawn leaves: a vein layer given on plain fill does not take the other exemplars' ink outline as vein (issue 22).

The notebook's last figure: clip-art leaves with an ink outline and plain
fill, the true veins of the first given as its vein layer. On main the
snapping pulled the template onto the outline and a strip 2-4 px inside
the blade's edge was induced as vein on the other exemplars.
"""

import warnings

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.leaves._clipart_kinds import clip_leaf
from branchnb.leaves._measure_drawn import _zone
from branchnb.leaves._measure_unseen import _on_canvas
from branchnb.leaves.analysis import analyze
from branchnb.leaves.analysis_outline import _ink_zone
from branchnb.leaves.exemplar import leaf_exemplar


def _shares(shape, style, outline_px, size, user=None, n=3):
    leaves = [clip_leaf(shape, size, k, 1.0, style, outline_px=outline_px) for k in range(n)]
    ex = [leaf_exemplar(x.image) for x in leaves]
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        a = analyze(ex, 0, {"veins": leaves[0].veins if user is None else user(leaves[0])})
    L = a.layer("veins")
    out = []
    for e in range(1, n):
        truth = _on_canvas(leaves[e].veins, a.offsets[e], a.blades[0].shape, a.mirrored[e])
        blade = _on_canvas(leaves[e].blade, a.offsets[e], a.blades[0].shape, a.mirrored[e])
        near = ndi.binary_dilation(truth)
        zone = _zone(blade, outline_px, size) & ~near
        m = L.masks[e]
        out.append(((m & zone).sum() / zone.sum(), (truth & ndi.binary_dilation(m)).sum() / truth.sum()))
    return np.array(out)


@pytest.mark.parametrize("shape,outline_px", [("palmate", 2), ("maple", 3)])
def test_plain_fill_outline_is_not_induced(shape, outline_px):
    # main: up to 0.07 (palmate, 2 px ink) and 0.36 (maple, 3 px) of the outline zone taken
    shares = _shares(shape, "none", outline_px, 320)
    assert shares[:, 0].max() < 0.05


def test_drawn_black_veins_still_induced_beside_a_thick_outline():
    shares = _shares("elm", "black", 4, 320)  # main: 0.38 of the outline zone taken
    assert shares[:, 0].max() < 0.05
    assert shares[:, 1].min() > 0.7


def test_outline_scribbled_as_vein_stays_induced():
    # The user's layer holds the outline: it is what they marked, on every exemplar.
    def with_outline(leaf):
        return leaf.veins | (leaf.blade & ~ndi.binary_erosion(leaf.blade, iterations=2))
    shares = _shares("palmate", "none", 2, 320, user=with_outline)
    assert shares[:, 0].min() > 0.3


def test_ink_zone_only_on_drawn_leaves():
    leaf = clip_leaf("oak", 256, 0, 2.0, "colour", outline_px=3)
    ex = leaf_exemplar(leaf.image)
    zone, depth = _ink_zone(ex.rgba[..., :3], ex.blade, 1.0)
    assert 5.5 <= depth <= 7.5  # 3 px of ink, 2 px pad, 1 px layer
    d = ndi.distance_transform_edt(ex.blade)
    # the ink and 3 px beside it (deeper only where the ink crosses the petiole's root)
    assert zone[(d > 0) & (d <= 3)].mean() > 0.95 and (d[zone] > 7).mean() < 0.02 and not zone[d > 12].any()
    photo = ex.rgba[..., :3].copy()
    photo[ex.blade] = (0.3, 0.6, 0.2)  # no ink rim
    assert not _ink_zone(photo, ex.blade, 1.0)[0].any()
