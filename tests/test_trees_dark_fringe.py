"""Trees cut from dark mattes keep no dark fringe (issue 24): premultiplied / keyed edges."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.trees import TreeLibrary
from branchnb.trees._dark_matte_check import MATTES, fringe_pixels, matted_tree
from branchnb.trees.exemplar import normalize_exemplar


@pytest.mark.parametrize("matte", ["black", "blue", "green"])
@pytest.mark.parametrize("kind", ["flat", "watercolour"])
def test_keyed_dark_matte_leaves_no_fringe(matte, kind):
    src = matted_tree(kind, MATTES[matte], 500, 2.0, 1, keyed=True)
    norm = normalize_exemplar(src, size=512).image
    # main: 133-858 fringe pixels (rim pixels nearer the matte than any colour of the tree); now 0-51
    assert fringe_pixels(norm, MATTES[matte], [norm]) <= 60


def _rim_darkening(img):
    """Mean over the opaque 1-px rim of (inner colour - rim colour), inner = 6 px further in."""
    op = img[..., 3] >= 0.5
    rim = op & ~ndi.binary_erosion(op)
    inner = ndi.binary_erosion(op, iterations=6)
    _, (iy, ix) = ndi.distance_transform_edt(~inner, return_indices=True)
    return float((img[iy, ix, :3] - img[..., :3]).mean(-1)[rim].mean())


@pytest.mark.parametrize("side,soft", [(300, 1.0), (700, 3.0)])
def test_premultiplied_edges_are_not_darker(side, soft):
    src = matted_tree("flat", MATTES["black"], side, soft, 0)    # alpha = share: premultiplied RGBA
    norm = normalize_exemplar(src, size=512).image
    assert _rim_darkening(norm) < 0.03      # main: 0.16-0.19 (a dark line round the tree)


def test_mix_of_matted_trees_has_no_fringe():
    lib = TreeLibrary(size=256)
    for k in range(3):
        lib.add(matted_tree("flat", MATTES["black"], 400, 1.0 + k, 10 + k, keyed=k > 0), f"t{k}")
    mix = np.asarray(lib.variation(rng=0).image, np.float32)
    assert fringe_pixels(mix, MATTES["black"], [e.image for e in lib]) <= 10     # main: 607, now 3



@pytest.mark.parametrize("kind,size,pile", [("palm", 256, True), ("broadleaf", 256, False),
                                            ("conifer", 600, False), ("fruit", 1000, True)])
def test_drawn_outlines_over_cleared_black_are_no_matte(kind, size, pile):
    # A drawn ink line over cleared (black) pixels has the colours of a black-matte fringe; its
    # colour stays the same as alpha rises, so it is left (trees36's rule unmixed ~280 px per tree).
    from branchnb.trees.drawn import drawn_tree
    from branchnb.trees.exemplar import _defringe, tree_rgba

    for seed in (0, 1):
        img, opaque = tree_rgba(drawn_tree(kind, pile=pile, rng=seed, size=size))
        assert np.array_equal(_defringe(img, opaque), img)



@pytest.mark.parametrize("kind", ["palm", "broadleaf", "conifer", "fruit"])
@pytest.mark.parametrize("size", [96, 128])
def test_small_drawn_trees_keep_their_edges(kind, size):
    # below FRINGE_MIN_SIZE a drawn 1 px outline never reaches full alpha and reads as a matte:
    # unmixed, 96-128 px drawn trees lost 12-98 outline pixels each
    from branchnb.trees.drawn import drawn_tree
    from branchnb.trees.exemplar import _defringe, tree_rgba

    for seed in (0, 1):
        img, opaque = tree_rgba(drawn_tree(kind, pile=False, rng=seed, size=size))
        out = _defringe(img, opaque)
        changed = np.abs(out - img).max(axis=2) > 1e-6
        assert int(changed.sum()) == 0
