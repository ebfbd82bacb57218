"""The leaves pipeline on real images with the defaults: photographed maples, drawn leaves on white."""

import cv2
import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb import data
from branchnb.core.metrics import iou
from branchnb.leaves import LayerSet, analyze, leaf_exemplar, simulate_scribbles, start_alignment
from branchnb.leaves.layers import Layer
from branchnb.leaves.synthesis import colour_range_fraction, generate, leaf_distance

MAPLES = ("maple_leaf_01", "maple_leaf_03", "maple_leaf_05")


def _maple_layers() -> LayerSet:
    return LayerSet.from_json((data.DATA_DIR / "leaves" / "maple_leaf_01_layers.json").read_text())


def test_maple_starts_are_upright():
    """All maple photos are upright: the start rotation (lamina outline + petiole base) is near 0.

    Measured: within 8 degrees for the six leaves against maple_leaf_01 (before the petiole base
    and the laminae moments, the starts were 19-108 degrees off: the curved petiole of the
    training leaf pulled them, and a five-lobed outline fits itself at every lobe).
    """
    train = leaf_exemplar(data.load(MAPLES[0]))
    for name in MAPLES[1:3]:
        ex = leaf_exemplar(data.load(name))
        mat, _ = start_alignment(ex.blade, train.blade)
        angle = np.degrees(np.arctan2(mat[1, 0], mat[0, 0]))
        assert abs(angle) < 15, (name, angle)


@pytest.fixture(scope="module")
def maple_analysis():
    return analyze([data.load(n) for n in MAPLES], 0, _maple_layers())


def test_maple_layers_from_real_scribbles(maple_analysis):
    """Measured (3 maples): veins lambda 0.74, training IoU 0.64; spots lambda 0.04, training IoU 0.46.

    With thin line layers (issue 22: the maple's 1-2 px dark veins are one): veins lambda 0.42,
    training IoU 0.54; spots lambda 0.00, training IoU 0.35 (``SnapParams(line_weight=0)``:
    0.71 / 0.64 and 0.01 / 0.41).

    (Before: lambda 0 for both and training IoU 0.12: 1-px S_e windows and a liberal radius of
    about a pixel, far below the registration error.)
    """
    a = maple_analysis
    veins, spots = a.layer("veins"), a.layer("spots")
    assert veins.lam > 0.1 > spots.lam
    assert veins.training_overlap > 0.4 and spots.training_overlap > 0.2
    assert veins.neighbourhood == 3  # the faint 1-2 px veins need a histogram window
    # Veins are induced on every leaf, along the registered training veins.
    for e in range(1, len(MAPLES)):
        m = veins.masks[e]
        assert 200 < m.sum() < 0.15 * a.blades[e].sum()
        near = veins.distance[e][m] < 2 * max(veins.eps_px)
        assert near.mean() > 0.9


def test_new_maples_keep_their_colours(maple_analysis):
    """As many blade pixels inside the exemplars' colour range as the exemplar least inside it (- 0.01).

    Measured: the exemplars themselves 0.988, 0.986, 0.964 (a fixed 0.98 failed every new leaf
    whose background is the third maple's, at 0.966-0.974, as on main); new leaves 0.966-1.0.
    """
    ex = maple_analysis.exemplars
    floor = min(0.98, min(colour_range_fraction(e, ex) for e in ex) - 0.01)
    new = generate(maple_analysis, 2, rng=0)
    for leaf in new:
        assert colour_range_fraction(leaf.image, ex) >= floor
        assert min(leaf_distance(leaf.image, ex) for ex in maple_analysis.exemplars) > 0.0


def test_drawn_leaves_on_white_through_the_pipeline():
    """Two drawn maple-type leaves on white (no alpha): background model, analysis, synthesis, defaults.

    The ink (outline and veins, black) is the layer; the user is simulated by 12 scribbles
    on the training leaf's dark pixels. Measured at half size (~250 px): lambda 0.37, training
    IoU 0.90. Weak: these blades are made of brush strokes with a dashed outline, and their
    registration is poor (22 px median error at full size), so the ink induced on the other
    leaf matches its dark pixels with IoU 0.77 at full size but only 0.24-0.45 at half size.
    """
    ims = [cv2.resize(data.load(f"maple_sketch_leaf_{i}"), None, fx=0.5, fy=0.5, interpolation=cv2.INTER_AREA)
           for i in (1, 2)]
    ex = [leaf_exemplar(im) for im in ims]
    assert all(e.mask_source == "background" for e in ex)
    ink = (ex[0].rgb.max(2) < 0.25) & ex[0].blade
    ls = LayerSet([Layer("ink", "#d62728", 0, simulate_scribbles(ink, 12, length=20, rng=0))])
    a = analyze(ex, 0, ls)
    layer = a.layer("ink")
    assert layer.lam > 0.1 and layer.training_overlap > 0.7
    dark = (a.exemplars[1][..., :3].max(2) < 0.25) & a.blades[1]
    # 0.91 measured; 0.00 while the other sketch's own contrast direction (white paper
    # between its brush strokes) replaced the ink's colour model.
    assert iou(layer.masks[1], dark) > 0.6
    new = generate(a, 1, rng=0)[0]
    assert new.image.shape == a.exemplars[0].shape and new.blade.any()


def test_symmetric_maples_register_unmirrored_and_blend_into_leaf_shapes():
    """A near-symmetric outline also fits its mirror image; registration must keep orientation.

    Before the check, TPS-RPM turned maple_leaf_04 and _07 into reflections of the training leaf
    from unmirrored starts, and blending those inverse warps with the others gave new "leaves"
    that filled the canvas's width (one was a rectangle).
    """
    names = ("maple_leaf_01", "maple_leaf_04", "maple_leaf_07")
    a = analyze([data.load(n) for n in names], 0, _maple_layers())
    inside = np.argwhere(a.blades[0])[::40, ::-1].astype(float)
    for e in (1, 2):
        j = a.registrations[e].forward_jacobian(inside)
        det = j[:, 0, 0] * j[:, 1, 1] - j[:, 0, 1] * j[:, 1, 0]
        assert np.mean(det > 0) > 0.95, (names[e], np.median(det))
    union = cv2.dilate(np.logical_or.reduce(a.blades).astype(np.uint8), np.ones((9, 9), np.uint8)) > 0
    for leaf in generate(a, 3, rng=1):
        blade = leaf.blade
        assert blade.sum() > 0.5 * min(b.sum() for b in a.blades)
        # 0.96-0.97 measured: new leaves lie in the exemplars' mean pose (angles averaged), so
        # lobe tips and the donor's petiole, turned with the new leaf, reach a little past the union.
        # Since generate stratifies the leading exemplar over a batch (issue 22), every batch of 3
        # has a leaf led by maple_leaf_07, whose registration covers its blade at IoU 0.78 only
        # (maple_leaf_04: 0.88): 0.92 inside the union (a registration limit, not synthesis).
        assert (blade & union).sum() >= 0.9 * blade.sum(), leaf.seed


def test_new_maples_carry_their_donors_petiole(maple_analysis):
    """Each new leaf gets one exemplar's own petiole (length and bend), attached at its base.

    Measured (maples 01 and 05 have a petiole; 03's is not found): base-aligned, a new leaf's
    petiole lies 0.5-2.2 px (median) from its donor's and 26-28 px from the other one. Before,
    the shape blend carried the training leaf's petiole onto every new leaf.
    """
    from scipy.spatial import cKDTree

    from branchnb.leaves.registration import split_petiole

    def from_base(blade):
        _, pet, base = split_petiole(blade)
        ys, xs = np.nonzero(pet)
        return None if base is None else np.column_stack([xs, ys]) - base

    own = {e: from_base(b) for e, b in enumerate(maple_analysis.blades)}
    donors = {e for e, p in own.items() if p is not None}
    assert donors == {0, 2}
    got = set()
    for leaf in generate(maple_analysis, 6, rng=0):  # 6: both donors drawn (1/32 chance not)
        assert leaf.petiole in donors and leaf.record()["petiole"] == leaf.petiole
        got.add(leaf.petiole)
        # alpha > 0.25: a 1-2 px petiole resampled at a slant has pixels of alpha ~0.4-0.5 that
        # break it at 0.5 (split_petiole then finds no stalk on 2 of these 6 leaves).
        pet = from_base(leaf.image[..., 3] > 0.25)
        # A new leaf lies in the exemplars' mean pose, its petiole turned with it: compare
        # shapes up to a turn about the base of at most 15 degrees.
        turns = [np.array([[np.cos(t), -np.sin(t)], [np.sin(t), np.cos(t)]]) for t in np.radians(np.arange(-15, 16))]
        dist = {e: min(float(np.median(cKDTree(own[e]).query(pet @ r.T)[0])) for r in turns) for e in donors}
        other = min(d for e, d in dist.items() if e != leaf.petiole)
        # Since petioles are turned by the lamina axes (issue 22), both donors' petioles hang
        # alike from the base, so up to a 15-degree turn the other one lies about 1 px away too:
        # the donor's own stays nearest (0.6 px against 1.1 px measured).
        assert dist[leaf.petiole] < 4.0 and dist[leaf.petiole] < other, (leaf.seed, dist)
    assert got == donors  # the training leaf's petiole is not the only one


def test_new_maples_are_one_piece(maple_analysis):
    """No stray bits of leaf off the new one (every pixel with alpha > 0 in one 8-connected piece).

    Measured on the notebook's 7 maples: the old off-canvas sentinel,
    blended into the shape maps with weights of 0.001-0.02, put 1-228 px
    fragments beside 3 of 7 new leaves, and the training photo's faint
    petiole fringe (alpha < 0.02) 21-23 specks beside each; none now.
    """
    for leaf in generate(maple_analysis, 8, rng=3):
        _, pieces = ndi.label(leaf.image[..., 3] > 0, structure=np.ones((3, 3)))
        assert pieces == 1, (leaf.seed, pieces)
