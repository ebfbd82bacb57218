"""Leaf kinds the package had never seen (issue 22): willow, cordate, deeply lobed oak, clip art.

Each test rebuilds a failure found running the whole workflow with the
defaults on :mod:`branchnb.leaves._unseen_kinds` (``python -m
branchnb.leaves._measure_unseen``).
"""

import numpy as np
import pytest

from branchnb.leaves import split_petiole
from branchnb.leaves._unseen_kinds import unseen_leaf


def _bottom(blade):
    return np.nonzero(blade)[0].max()


@pytest.mark.parametrize("kind,size", [("willow", 240), ("willow", 480), ("cordate", 300), ("cordate", 640)])
@pytest.mark.parametrize("seed", [0, 1])
def test_a_drawn_out_tip_is_no_petiole(kind, size, seed):
    """The base is where the petiole (at the bottom) meets the lamina, not the acuminate tip.

    Before, the thin part that was largest was the petiole: a willow's
    tapering tip (160-760 px) outweighed its 4-8 px stalk, so no base was
    found (None), and a cordate leaf's tip was taken as the petiole (base
    at the top, y 42-91 of 275-592).
    """
    leaf = unseen_leaf(kind, size, seed)
    lam, pet, base = split_petiole(leaf.blade)
    assert base is not None
    length = _bottom(leaf.blade) - np.nonzero(leaf.blade)[0].min()
    # the petiole hangs below the base: the base lies in the lowest quarter of the leaf
    assert base[1] > _bottom(leaf.blade) - 0.25 * length
    assert pet.any() and np.nonzero(pet)[0].mean() > base[1] - 2


def test_a_blade_with_a_stalk_and_a_long_tip():
    """An ellipse drawn out into a long tapering tip, with an even 3 px stalk: the stalk is the petiole.

    Before, neither thin part was twice as large as the other: no petiole, no base.
    """
    yy, xx = np.mgrid[:340, :240]
    blade = ((xx - 120) / 60.0) ** 2 + ((yy - 160) / 100.0) ** 2 < 1
    blade |= (np.abs(xx - 120) < 0.2 * yy) & (yy < 80)
    blade[250:320, 119:122] = True
    lam, pet, base = split_petiole(blade)
    assert base is not None and base[1] > 240
    assert pet[300, 120] and not pet[20, 120]


def test_a_clip_art_petiole_keeps_its_own_colours():
    """New clip-art leaves keep the exemplars' fill-coloured petiole; the new ink outline is the lamina's.

    Before, the outline was drawn along the whole new blade, and a 2-3 px
    petiole came out solid ink (share of petiole pixels nearer the ink
    than the fill 0.56-1.00 on new leaves, 0.00 on the exemplars).
    """
    from scipy import ndimage as ndi

    from branchnb.leaves import analyze, generate, leaf_exemplar
    from branchnb.leaves._measure_unseen import user_scribbles

    ink, fill = np.array((0.10, 0.22, 0.08)), np.array((0.42, 0.70, 0.28))
    leaves = [unseen_leaf("clipart", 300, k) for k in range(3)]
    a = analyze([leaf_exemplar(x.image) for x in leaves], 0, user_scribbles(leaves[0]))
    shares = []
    for leaf in generate(a, 2, rng=0):
        lam, pet, base = split_petiole(leaf.blade)
        pet &= ~ndi.binary_dilation(lam, iterations=3)
        assert pet.sum() >= 5
        px = leaf.image[..., :3][pet]
        shares.append(float((np.linalg.norm(px - ink, axis=1) < np.linalg.norm(px - fill, axis=1)).mean()))
    assert max(shares) < 0.2, shares
