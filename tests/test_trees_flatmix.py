"""Flat-art mixes that read as one drawing (issue 24: clip-art mixes looked like collages)."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.trees.drawn import drawn_tree
from branchnb.trees.mvc import transfer_colour
from branchnb.trees.quality import (
    crossfade_fraction,
    crown_sources,
    dark_rim_fraction,
    foreign_patches,
    outline_continuity,
    seam_through_flat,
    stray_ink,
)
from branchnb.trees.variations import TreeLibrary, exemplar_outline, make_variation

S = 128


@pytest.fixture(scope="module")
def drawn_lib():
    lib = TreeLibrary(size=S)
    for i, (kind, pile) in enumerate([("broadleaf", False), ("palm", True), ("conifer", False),
                                      ("fruit", True)]):
        lib.add(drawn_tree(kind, pile=pile, rng=10 + i, size=2 * S), f"{kind}{'_pile' * pile}")
    return lib


def _disc(size=40, r=15, ring=2):
    yy, xx = np.mgrid[:size, :size]
    d = np.hypot(yy - size / 2, xx - size / 2)
    img = np.zeros((size, size, 4), np.float32)
    img[d <= r] = (0.0, 0.0, 0.0, 1.0)
    img[d <= r - ring, :3] = (0.3, 0.7, 0.2)
    return img, yy, xx


def test_stray_ink_counts_open_strokes_not_whole_rings():
    img, yy, xx = _disc(60, 27)
    d = np.hypot(yy - 30, xx - 30)
    fruit = np.hypot(yy - 30, xx - 24) <= 6
    img[fruit, :3] = (1.0, 0.5, 0.0)
    img[fruit & (np.hypot(yy - 30, xx - 24) > 4.5), :3] = 0.0     # a whole outlined fruit
    assert stray_ink(img) == 0
    cut = img.copy()
    cut[:, 22:, :3] = np.where(fruit[:, 22:, None], (0.3, 0.7, 0.2), cut[:, 22:, :3])
    cut[(d > 25) & (d <= 27), :3] = 0.0                           # the silhouette outline stays
    assert stray_ink(cut) == 1                                    # half a ring: an open fragment
    blob = img.copy()
    blob[fruit, :3] = 0.0                                         # a solid dark shape is no stroke
    assert stray_ink(blob) == 0


def test_stray_ink_reads_resampled_rings_as_whole():
    # At 96-200 px a warp lightens a 1 px ring in places (half ink, half fill): still a whole
    # fruit, not an open stroke; the exemplars themselves scored 3-8 strays before.
    img, yy, xx = _disc(60, 27)
    r = np.hypot(yy - 30, xx - 24)
    ring = (r > 4.5) & (r <= 5.6)
    img[r <= 5.6, :3] = (1.0, 0.5, 0.0)
    img[ring, :3] = 0.0
    soft = ring & ((yy + xx) % 3 == 0)                           # resampled: every third pixel half-light
    img[soft, :3] = 0.5 * np.array([1.0, 0.5, 0.0], np.float32)
    assert stray_ink(img) == 0
    half = img.copy()
    half[:, 24:, :3] = np.where((r <= 5.6)[:, 24:, None], (0.3, 0.7, 0.2), half[:, 24:, :3])
    assert stray_ink(half) == 1                                   # a real half ring is still stray


def test_outline_continuity_seam_and_foreign_patch_measures():
    img, _, _ = _disc()
    assert outline_continuity(img, (0, 0, 0)) == 1.0
    bare = img.copy()
    bare[:, 20:, :3] = np.where(img[:, 20:, 3:] > 0, (0.3, 0.7, 0.2), 0.0)
    assert 0.4 < outline_continuity(bare, (0, 0, 0)) < 0.6
    src = np.where(img[..., 3] > 0, 0, -1)
    src[:, 20:] = np.where(src[:, 20:] >= 0, 1, -1)               # cut straight through the fill
    assert seam_through_flat(img, src) > 0.7                       # (not beside the outline ring)
    along = img.copy()
    along[:, 19:21, :3] = 0.0                                     # the cut runs along a stroke
    assert seam_through_flat(along, src) == 0.0
    src2 = np.where(img[..., 3] > 0, 0, -1)
    src2[18:21, 18:21] = 1                                        # 9 px of another tree
    assert foreign_patches(src2) == 1 and crown_sources(src2) == 1
    assert foreign_patches(src) == 0 and crown_sources(src) == 2
    with pytest.raises(ValueError, match="sources"):
        seam_through_flat(img, src[:5])
    with pytest.raises(ValueError, match="ink"):
        outline_continuity(img, (0, 0))
    with pytest.raises(ValueError, match="share"):
        foreign_patches(src, share=2.0)


def _figures(lib, v):
    op = (v.image[..., 3] >= 0.5) & (v.sources >= 0)
    used = np.unique(v.sources[op])
    trunk = np.unique(v.sources[op & (v.parts == 2)])
    ink = exemplar_outline(lib[v.names[int(np.bincount(v.sources[op]).argmax())]]).ink
    return dict(stray=stray_ink(v.image), foreign=foreign_patches(v.sources, v.parts),
                styles=crown_sources(v.sources, v.parts), trunks=len(trunk), used=len(used),
                outline=outline_continuity(v.image, ink), seam=seam_through_flat(v.image, v.sources))


def test_drawn_mixes_read_as_one_drawing(drawn_lib):
    # Default "choose by parts": one crown style, whole strokes, a continuous outline, one trunk.
    gen = np.random.default_rng(7)
    vs = [make_variation(drawn_lib, rng=gen) for _ in range(4)] + drawn_lib.variations_of("fruit_pile", 3, rng=gen)
    figs = [_figures(drawn_lib, v) for v in vs]
    assert all(f["stray"] == 0 for f in figs), figs
    assert all(f["foreign"] == 0 for f in figs), figs
    assert all(f["styles"] == 1 and f["trunks"] == 1 for f in figs), figs
    assert min(f["outline"] for f in figs) >= 0.95, figs
    assert max(f["seam"] for f in figs) <= 0.1, figs
    for v in vs:
        assert crossfade_fraction(v.image, [drawn_lib[n].image for n in v.names]) <= 0.03
        assert dark_rim_fraction(v.image, v.mask) == 0.0
    # Two trees with equal colour weights: the former random regions paste pieces of both
    # into the crown (what users saw as collages); parts keep one crown style.
    figs = {by: [_figures(drawn_lib, make_variation(drawn_lib, [0.5, 0.5], use=["broadleaf", "fruit_pile"],
                                                    colour_weights=[0.5, 0.5], choose_by=by, rng=r))
                 for r in range(3)] for by in ("regions", "parts")}
    assert sum(f["foreign"] + f["stray"] for f in figs["regions"]) >= 3, figs["regions"]
    assert all(f["foreign"] == f["stray"] == 0 and f["styles"] == 1 for f in figs["parts"]), figs["parts"]


def test_parts_take_whole_trunks_of_matching_width(drawn_lib):
    # A trunk of another tree replaces the crown's own only when they overlap (IoU >= 1/2).
    trunks = []
    for r in range(6):
        v = make_variation(drawn_lib, [0.5, 0.5], use=["broadleaf", "fruit_pile"], colour_weights=[0.5, 0.5],
                           rng=r)
        op = (v.image[..., 3] >= 0.5) & (v.sources >= 0)
        crown = np.bincount(v.sources[op & (v.parts == 1)], minlength=2)
        trunk = np.bincount(v.sources[op & (v.parts == 2)], minlength=2)
        assert np.count_nonzero(crown > 0.02 * crown.sum()) == 1
        assert np.count_nonzero(trunk) == 1
        trunks.append(int(trunk.argmax()) != int(crown.argmax()))
    assert any(trunks) or not all(trunks)


def test_parts_mode_needs_layers_and_checks_groups():
    img = np.zeros((12, 12, 4), np.float32)
    img[2:10, 2:10] = (0.2, 0.6, 0.2, 1.0)
    cage = np.array([(0, 0), (11, 0), (11, 11), (0, 11)], float)
    m = img[..., 3] > 0
    with pytest.raises(ValueError, match="layers"):
        transfer_colour([img, img], [cage, cage], cage, m, colour_weights=[0.5, 0.5], mode="parts")
    with pytest.raises(ValueError, match="groups"):
        transfer_colour([img, img], [cage, cage], cage, m, colour_weights=[0.5, 0.5], mode="parts",
                        layers=[m, m], groups=[0])
    out, _ = transfer_colour([img, img], [cage, cage], cage, m, colour_weights=[0.5, 0.5], mode="parts",
                          layers=[np.zeros_like(m)] * 2, groups=[1, 1], rng=0)
    assert np.allclose(out, img)


def test_photographs_blend_whatever_choose_by_says():
    lib = TreeLibrary.from_data(["tree_cutout_broadleaf", "tree_rpg_05"], size=64)
    a = make_variation(lib, [0.5, 0.5], colour_weights=[0.5, 0.5], colour_mode="blend", rng=0)
    b = make_variation(lib, [0.5, 0.5], colour_weights=[0.5, 0.5], colour_mode="blend", rng=0,
                       choose_by="regions")
    assert a.colour_mode == "blend" and np.array_equal(a.image, b.image)


def test_a_mix_of_unlike_shapes_is_a_whole_tree():
    """A palm pulled into a palm/fruit-tree contour covers 40 % of it with a torn trunk: the crown
    then comes from a source that covers the contour, so the mix is one piece filling its shape."""
    from scipy import ndimage as ndi

    lib = TreeLibrary(size=256)
    lib.add(drawn_tree("fruit", rng=20, size=512), "fruit")
    lib.add(drawn_tree("palm", pile=True, rng=21, size=512), "palm")
    for seed in (1, 2, 3):
        v = lib.variation([0.5, 0.5], use=["palm", "fruit"], colour_weights=[0.5, 0.5], colour_mode="choose",
                          rng=seed)
        opaque = v.image[..., 3] >= 0.5
        lab, n = ndi.label(opaque, structure=np.ones((3, 3)))
        assert n == 1
        # The palm now warps whole (its cage's R and L found, see simplify_contour) and may give
        # the crown: it covers 0.78 of the contour, the rest is its own frond gaps (0.94 with
        # the fruit tree's crown).
        assert (opaque & v.mask).sum() >= 0.75 * v.mask.sum()


def test_more_like_this_keeps_the_targets_drawing(drawn_lib):
    """"More like this" of a drawn tree: new shapes, the target's own crown (it holds most of the colour)."""
    for k, name in enumerate(drawn_lib.names):
        for v in drawn_lib.variations_of(name, 3, rng=4):
            crown = (v.sources >= 0) & (v.parts == 1)
            assert np.bincount(v.sources[crown], minlength=len(drawn_lib.names)).argmax() == k, name


def _simple_tree(crown, bark, size=96, rx=30, ry=24, seed=0):
    import cv2

    g = np.random.default_rng(seed)
    img = np.zeros((size, size, 4), np.float32)
    cx = size // 2 + int(g.integers(-3, 4))
    cv2.rectangle(img, (cx - 4, size // 2), (cx + 4, size - 3), (*bark, 1.0), -1)
    cv2.ellipse(img, (cx, size // 2 - ry // 2), (rx + int(g.integers(-4, 5)), ry), 0, 0, 360, (*crown, 1.0), -1)
    return img


def test_silhouette_keeps_its_own_trunk():
    # A one-colour silhouette takes no brown trunk from a coloured tree (nor gives its black one).
    from branchnb.trees.flat_art import _drawing_group

    lib = TreeLibrary(size=96)
    lib.add(_simple_tree((0.05, 0.05, 0.06), (0.05, 0.05, 0.06)), "silhouette")
    lib.add(_simple_tree((0.2, 0.6, 0.2), (0.45, 0.3, 0.15)), "flat")
    assert [_drawing_group(e) for e in lib] == [2, 0]
    for cw in ((0.6, 0.4), (0.4, 0.6)):
        for r in range(4):
            v = make_variation(lib, [0.5, 0.5], colour_weights=cw, rng=r)
            op = (v.image[..., 3] >= 0.5) & (v.sources >= 0)
            crown = np.bincount(v.sources[op & (v.parts == 1)], minlength=2)
            trunk = np.bincount(v.sources[op & (v.parts == 2)], minlength=2)
            assert trunk.sum() > 0 and trunk.argmax() == crown.argmax() and trunk.min() == 0, (cw, r)


def test_more_like_this_of_a_palm_silhouette_keeps_its_trunk_and_thin_fronds():
    # The palm's thin trunk under a wide crown put the border point nearest R after the one
    # nearest L; its cage then gave the whole border to the crown, and every "more like this"
    # squashed the trunk to ~0.78 of the height (fronds merged into a blob at 256 px).
    from scipy import ndimage as ndi

    S2 = 128
    lib = TreeLibrary.from_data(["palm_silhouette", "cartoon_tree", "evergreen", "arbre_modern"], size=S2)

    def half_thickness(a):
        return ndi.distance_transform_cdt(a, metric="chessboard")[a].mean()

    own = half_thickness(lib["palm_silhouette"].alpha)
    for v in lib.variations_of("palm_silhouette", 4, rng=0):
        a = v.image[..., 3] >= 0.5
        assert np.flatnonzero(a.any(axis=1)).max() >= 0.97 * (S2 - 1)       # the trunk reaches the foot
        assert half_thickness(a) <= 1.3 * own                              # fronds stay thin


def _line_art(size=48):
    """A flat disc with two 1 px dark strokes inside: a chord and a diagonal."""
    img, yy, xx = _disc(size, r=20, ring=0)
    img[(yy == 16) & (xx >= 12) & (xx <= 36), :3] = 0.0
    img[(yy - xx == 6) & (xx >= 14) & (xx <= 28), :3] = 0.0
    return img


@pytest.mark.parametrize("scale,shift", [(1.0, 0.5), (0.7, 0.3), (0.55, 0.5), (1.15, 0.25)])
def test_flat_modes_keep_thin_strokes_whole_under_a_warp(scale, shift):
    img = _line_art()
    t = np.linspace(0, 2 * np.pi, 24, endpoint=False)
    cage = np.stack([24 + 21 * np.cos(t), 24 + 21 * np.sin(t)], 1)
    tcage = 24 + scale * (cage - 24) + shift
    yy, xx = np.mgrid[:48, :48]
    mask = np.hypot(yy - 24 - shift, xx - 24 - shift) <= 20 * scale + 0.5
    own = ndi.label((img[..., 3] >= 0.5) & (img[..., :3].mean(axis=2) < 0.2), np.ones((3, 3), bool))[1]
    out = transfer_colour(img, cage, tcage, mask, mode="choose")
    op = out[..., 3] >= 0.5
    ink = op & (out[..., :3].mean(axis=2) < 0.2)
    assert ndi.label(ink, np.ones((3, 3), bool))[1] == own == 2   # no stroke broken into dashes
    assert 0.8 * 40 * scale <= ink.sum() <= 2.0 * 40 * scale       # ... nor drawn twice as thick
    # no dark fringe: every pixel that is not ink keeps the fill colour
    assert np.abs(out[op & ~ink, :3] - (0.3, 0.7, 0.2)).max() < 0.05
