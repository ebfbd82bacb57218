"""Fixes found on leaf images the code had never seen (cut grass strips, clipart oaks, a zelkova photo).

Each test rebuilds the failure in a small synthetic input.
"""

import cv2
import numpy as np
import pytest
from hypothesis import given, settings
from hypothesis import strategies as st
from scipy import ndimage as ndi
from skimage.draw import ellipse

from branchnb.core.metrics import iou
from branchnb.leaves import (
    Layer,
    LayerSet,
    Scribble,
    SnapParams,
    analyze,
    blade_mask,
    generate,
    grow_layers,
    leaf_exemplar,
    procedural_leaf,
)
from branchnb.leaves.analysis import normalise_exemplars


def _strip_on_paper(h=120, w=160):
    img = np.full((h, w, 3), 0.95, np.float32)
    img[40:80, 20:140] = (0.35, 0.5, 0.25)
    return img


def test_red_scale_square_and_edge_card_are_not_leaf():
    """Photos of leaves on paper show a red 2 x 2 cm square and cards cut by the crop; neither is leaf.

    Before, both were kept as "pinnae" (components of at least 2 % of the leaf): blade IoU
    0.88-0.94 against a hand threshold on four of the seven grass photos, 0.98-0.99 after.
    """
    img = _strip_on_paper()
    leaf = blade_mask(img)
    img[2:20, 60:80] = (0.85, 0.1, 0.1)      # a red square inside the frame
    img[100:120, 100:150] = (0.35, 0.5, 0.25)  # a leaf-coloured card cut by the bottom edge
    got = blade_mask(img)
    assert iou(got, leaf) > 0.98
    assert not got[2:20, 60:80].any() and not got[105:, 100:150].any()


def test_parts_of_a_compound_leaf_stay():
    img = _strip_on_paper()
    img[90:105, 40:100] = (0.33, 0.52, 0.24)  # a second pinna, same colours, inside the frame
    got = blade_mask(img)
    assert got[95, 70] and got[60, 80]


def _shaded_blade_with_pale_veins(h=90, w=160):
    """A blade lit from one side, pale 1-px veins all across it: a vein on the dark side has
    the colour of plain blade on the bright side."""
    x = np.linspace(0.0, 1.0, w, dtype=np.float32)[None, :, None]
    dark, bright = np.array([0.25, 0.36, 0.2], np.float32), np.array([0.42, 0.55, 0.36], np.float32)
    img = np.broadcast_to(dark + (bright - dark) * x, (h, w, 3)).copy()
    veins = np.zeros((h, w), bool)
    veins[10:h - 10:8, 5:w - 5] = True
    img[veins] += 0.12
    return np.clip(img, 0, 1), veins


def test_thin_veins_on_a_shaded_blade_grow_as_lines():
    """Scribbles on 1-px veins grew blobs over a shaded blade.

    The half of a 3-px brush's pixels most unlike the blade around went into the layer's
    colour model (a third of them plain blade), and a superpixel crossed by a scribbled vein
    was pinned whole to the layer; the colour model alone cannot tell a vein on the dark side
    from bright plain blade (``local_contrast``).
    """
    img, veins = _shaded_blade_with_pale_veins()
    blade = np.ones(veins.shape, bool)
    rows = np.flatnonzero(veins.any(1))
    ls = LayerSet([Layer("veins")])
    for r in rows[::2]:
        ls.add_scribble("veins", [(10, r), (60, r)], radius=1)
    for r in rows[1::3]:
        ls.background.append(Scribble(np.array([[20.0, r + 4], [90.0, r + 4]]), 1.0))
    # The brush marks the vein, not the blade beside it (before: IoU 0.12, a blob over the dark side).
    default = grow_layers(img, blade, ls).masks["veins"]
    assert iou(default, veins) > 0.4 and default.sum() < 1.5 * veins.sum()
    # Colours relative to the blade around them find the veins on the bright side too.
    grown = grow_layers(img, blade, ls, SnapParams(local_contrast=1.0)).masks["veins"]
    assert iou(grown, veins) > 0.9


def test_leaves_lying_at_different_angles_blend_into_leaves():
    """A leaf photographed across the paper and one along it: new leaves are leaves, not swirls.

    The shape blend mixed each exemplar's inverse warp as it lay; with one turned by 90 degrees
    the blend of a map and its rotation swirled the blade into blobs. Measured on the
    seven grass strips (three lie across, four along): before, new blades covered 1.0-1.7 x the
    training blade in blobs; after, strips of 0.28-0.32 x the (wide) training blade. Here the
    new leaf is the training outline turned to its pose (best IoU over angles > 0.8).
    """
    leaf = procedural_leaf("elliptic", size=96, rng=3)
    turned = np.ascontiguousarray(np.rot90(leaf.image))
    layers = {"veins": leaf.layers["veins"]}
    a = analyze([leaf.image, turned], 0, layers)
    # The canvas holds the turned leaf upright as well.
    assert a.blades[0].shape[0] >= leaf.image.shape[1] and a.blades[0].shape[1] >= leaf.image.shape[0]
    ys, xs = np.nonzero(a.blades[0])
    centre = (float(xs.mean()), float(ys.mean()))
    h, w = a.blades[0].shape
    for new in generate(a, 3, rng=0):
        # The training outline, turned to the new leaf's pose (one exemplar's).
        best = max(iou(new.blade, cv2.warpAffine(a.blades[0].astype(np.float32),
                                                 cv2.getRotationMatrix2D(centre, ang, 1.0), (w, h)) > 0.5)
                   for ang in range(-90, 91, 5))
        assert best > 0.8, (new.seed, best)


def test_canvas_holds_every_blade_turned():
    """A long leaf must fit turned to another exemplar's pose (before: cut by the canvas edge)."""
    img = np.zeros((40, 120, 4), np.float32)
    rr, cc = ellipse(20, 60, 12, 55, shape=(40, 120))
    img[rr, cc] = (0.3, 0.5, 0.2, 1.0)
    # The same leaf at 45 degrees, cropped tight: as photographed, no canvas side needs 110 px.
    other = np.zeros((90, 90, 4), np.float32)
    rr, cc = ellipse(45, 45, 12, 55, shape=(90, 90), rotation=np.pi / 4)
    other[rr, cc] = (0.3, 0.5, 0.2, 1.0)
    images, blades, _ = normalise_exemplars([img, other])
    h, w = blades[0].shape
    assert min(h, w) >= 110


def _drawn_leaf(h=120, w=120):
    """Green strokes inside a dashed black outline, on white paper (the style of the sketched maples)."""
    img = np.ones((h, w, 3), np.float32)
    yy, xx = np.mgrid[0:h, 0:w]
    inside = ((xx - 60) / 45.0) ** 2 + ((yy - 60) / 35.0) ** 2 <= 1
    ring = inside & (((xx - 60) / 41.0) ** 2 + ((yy - 60) / 31.0) ** 2 > 1)
    dash = (np.degrees(np.arctan2(yy - 60, xx - 60)) % 30) < 24  # 4-5 px gaps
    img[ring & dash] = 0.0
    stripes = inside & ~ring & (((xx + yy) // 6) % 2 == 0)
    img[stripes] = (0.1, 0.4, 0.15)
    return img, inside


def test_leaf_drawn_as_strokes_in_a_dashed_outline_gets_its_silhouette():
    """The blade of a drawn leaf was its strokes (a lace: paper between them reaches the
    background through the outline's gaps) and registration matched strokes. Measured on the
    two sketched maples: registration blade IoU 0.62 -> 0.92, error 21 -> 16 px, ink induced on
    the second leaf IoU 0.85 -> 0.91 with its dark pixels."""
    img, inside = _drawn_leaf()
    got = blade_mask(img)
    assert iou(got, inside) > 0.93
    # A solid leaf's outline (notches included) is left alone.
    leaf = procedural_leaf("lobed", size=128, rng=7)
    a = leaf.image[..., 3:4]
    assert iou(blade_mask(leaf.image[..., :3] * a + (1 - a)), leaf.blade) > 0.93


def test_grow_layers_ignores_the_alpha():
    """grow_layers said it ignores the alpha but composited over white: a background-model
    exemplar's feathered rim turned its dark outline grey and the ink layer grew by half."""
    img, inside = _drawn_leaf()
    ex = leaf_exemplar(img)
    blade, rgba = ex.blade, ex.rgba
    ls = LayerSet([Layer("ink")])
    ls.add_scribble("ink", [(60, 26), (60, 28)], radius=1)
    ls.add_scribble("ink", [(102, 58), (102, 62)], radius=1)
    ls.background.append(Scribble(np.array([[60.0, 60.0], [61.0, 61.0]]), 1.0))  # on a green stroke
    a = grow_layers(ex.rgb, blade, ls).masks["ink"]
    b = grow_layers(rgba, blade, ls).masks["ink"]
    assert np.array_equal(a, b)


@settings(max_examples=30, deadline=None)
@given(st.integers(16, 60), st.integers(16, 60), st.floats(0.0, 1.0), st.integers(0, 2**16))
def test_blade_mask_on_random_drawings_returns_a_mask_or_a_clear_error(h, w, ink, seed):
    rng = np.random.default_rng(seed)
    img = np.ones((h, w, 3), np.float32)
    img[rng.random((h, w)) < 0.3 * ink] = (0.1, 0.4, 0.15)
    try:
        m = blade_mask(img)
    except ValueError:
        return
    assert m.shape == (h, w) and m.dtype == bool and m.any()


def test_paper_mixed_rim_takes_the_colours_inside():
    """The outermost blade pixels of a photo on paper are part paper, as pale as a vein:
    induction took every grass strip's outline for a vein (6-30 % of the induced vein pixels
    on the 1-px rim, 0.6-9 % after; the rim is 6 % of a blade)."""
    img = _strip_on_paper()
    img[39, 20:140] = img[80, 20:140] = (0.7, 0.77, 0.65)  # half leaf, half paper
    img[40:80, 19] = img[40:80, 140] = (0.7, 0.77, 0.65)
    ex = leaf_exemplar(img)
    rim = ex.blade & ~ndi.binary_erosion(ex.blade, structure=np.ones((3, 3), bool))
    assert rim.sum() > 100
    assert np.abs(ex.rgb[rim] - np.array([0.35, 0.5, 0.25])).max() < 0.02


def test_shape_maps_are_upright_even_when_the_start_sits_a_lobe_away():
    """Each exemplar's inverse warp, seen in the training pose, has no rotation left.

    The pose was first taken from the registration's start map; on a palmate leaf the start
    may sit a lobe away (exemplar 2 of this family: 6.5 degrees against the map's 42), which
    the spline turns back, so its "upright" map kept a 47-degree turn and blends grew
    malformed lobes. The pose is now the least-squares rotation of the whole map.
    """
    from branchnb.leaves import leaf_family, register
    from branchnb.leaves.analysis import IdentityRegistration
    from branchnb.leaves.synthesis import _Prepared

    fam = leaf_family(4, size=192, kind="lobed", rng=1)
    canvas, blades, _ = normalise_exemplars(fam)
    regs = [IdentityRegistration(blades[0].shape)]
    regs += [register(canvas[i], canvas[0], blades[i], blades[0]) for i in range(1, 4)]
    a = analyze(fam, 0, {"veins": fam[0].layers["veins"]}, registrations=regs)
    prep = _Prepared(a)
    ys, xs = np.nonzero(a.blades[0])
    y = np.column_stack([xs, ys]).astype(float)
    for e in range(1, 4):
        z = prep.shape_maps[e][ys, xs].astype(float)
        u, _, vt = np.linalg.svd((z - z.mean(0)).T @ (y - y.mean(0)))
        rot = u @ vt
        assert abs(np.degrees(np.arctan2(rot[1, 0], rot[0, 0]))) < 5.0, e
        # A blend of this exemplar alone gives back its own map.
        one = np.eye(4)[e]
        back = prep.posed(prep.shape_maps[e], one)
        assert np.median(np.hypot(*(back[ys, xs] - prep.from_exemplar[e][ys, xs]).T)) < 0.5


def _on_paper(leaf, paper):
    a = leaf.image[..., 3:]
    return np.clip(leaf.image[..., :3] * a + paper * (1 - a), 0, 1).astype(np.float32)


def test_paper_under_uneven_light_is_plain():
    """A phone photo's paper darkens towards one side: 0.95 -> 0.60 across the image, with noise.

    Before, the border's colours varied by Delta E 14.8 around one colour and the image was
    rejected as a busy background; with the lightness gradient fitted, blade IoU 0.993-0.999
    (lobed, elliptic; gradient, vignette, a cast shadow).
    """
    rng = np.random.default_rng(0)
    for kind in ("lobed", "elliptic"):
        leaf = procedural_leaf(kind, size=256, rng=5)
        h, w = leaf.blade.shape
        yy, xx = np.mgrid[0:h, 0:w] / max(h, w)
        for light in (0.95 - 0.35 * xx, 0.95 - 0.5 * ((xx - 0.5) ** 2 + (yy - 0.5) ** 2)):
            paper = light[..., None] * np.ones(3) + rng.normal(0, 0.015, (h, w, 3))
            ex = leaf_exemplar(_on_paper(leaf, paper))
            assert ex.mask_source == "background"
            assert iou(ex.blade, leaf.blade) > 0.98, kind


def test_a_mosaic_of_leaf_close_ups_is_still_busy():
    """Vertical strips of leaf colours edge to edge (like the grass close-up mosaic): no paper at all.

    A smooth lightness fit takes part of such a border's variation (the mosaic photo: 14.1 around
    one colour, 8.7 around the fit), so the fit must explain the border far better (< 6).
    """
    rng = np.random.default_rng(1)
    img = np.zeros((120, 160, 3), np.float32)
    edges = np.sort(rng.choice(np.arange(8, 152), 9, replace=False))
    for lo, hi in zip(np.r_[0, edges], np.r_[edges, 160]):
        img[:, lo:hi] = (rng.uniform(0.05, 0.35), rng.uniform(0.2, 0.6), rng.uniform(0.05, 0.3))
    with pytest.raises(ValueError, match="busy background"):
        leaf_exemplar(img)


def _frond(gap=2, size=160, seed=0):
    """A drawn pinnate frond: a rachis and pairs of pinnae, each drawn apart from it by ``gap`` px."""
    rng = np.random.default_rng(seed)
    img = np.zeros((size, size, 4), np.float32)
    blade = np.zeros((size, size), bool)
    cx = size // 2
    blade[10:size - 10, cx - 2:cx + 2] = True
    for y in range(18, size - 20, 14):
        ln = int(rng.integers(size // 5, size // 3))
        for side in (-1, 1):
            rr, cc = ellipse(y, cx + side * (2 + gap + ln // 2), 5, ln // 2, shape=blade.shape)
            blade[rr, cc] = True
    img[blade] = (0.35, 0.6, 0.25, 1.0)
    return img, blade


def test_a_compound_leaf_drawn_in_pieces_is_one_leaf():
    """A fern frond drawn as 33 pinnae with 4-8 px gaps (1.6 % of its size) was refused as
    "33 separate leaves"; pieces closer than 3 % of the leaf's size are one compound leaf."""
    fronds = [_frond(gap=2, seed=s)[0] for s in (0, 1)]
    canvas, blades, _ = normalise_exemplars(fronds)
    assert len(blades) == 2 and all(b.any() for b in blades)
    two = np.zeros((160, 320, 4), np.float32)
    two[:, :160] = fronds[0]
    two[:, 160:] = fronds[1]
    with pytest.raises(ValueError, match="separate leaves"):
        normalise_exemplars([two, fronds[0]])


def test_parallel_vein_strips_have_their_truth_and_induce_with_true_registrations():
    """The grass-strip family (pale parallel veins, cut ends, any angle): veins inside the blade, the
    same material keypoints on every strip; induction with true registrations finds every strip's own
    parallel veins (measured IoU 0.69-0.99 on seeds 0 and 1)."""
    from leaves_truth import TrueRegistration

    from branchnb.leaves.procedural_strips import strip_family

    fam = strip_family(3, size=160, rng=0)
    for leaf in fam:
        v = leaf.layers["veins"]
        assert not (v & ~leaf.blade).any() and 0.1 < v.sum() / leaf.blade.sum() < 0.5
        k = np.round(leaf.keypoints).astype(int)
        assert leaf.blade[k[:, 1], k[:, 0]].mean() > 0.95
    _, blades, offs = normalise_exemplars(fam)
    shape = blades[0].shape

    def on(m, o):
        out = np.zeros(shape, bool)
        out[o[1]:o[1] + m.shape[0], o[0]:o[0] + m.shape[1]] = m
        return out
    kps = [leaf.keypoints + np.array(o) for leaf, o in zip(fam, offs)]
    regs = [TrueRegistration(k, kps[0], shape) for k in kps]
    a = analyze(fam, 0, {"veins": fam[0].layers["veins"]}, registrations=regs)
    for e in (1, 2):
        assert iou(a.layer("veins").masks[e], on(fam[e].layers["veins"], offs[e])) > 0.6
