"""Stroke-based structure editing: strokes, fetching, global sampling, composition, branching."""

from __future__ import annotations

import dataclasses
import itertools

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb import data
from branchnb.core.metrics import psnr
from branchnb.strokes import (
    PlacedPatch,
    Stroke,
    StrokeEditParams,
    StrokePair,
    compose,
    edit_structure,
    find_junctions,
    make_pairs,
    sample_pair,
    source_index,
    stroke_order,
    viterbi,
)
from branchnb.strokes.sampling import chain_energy, greedy


# --------------------------------------------------------------------------
# a small textured object: a band along a wave with stripes across it
# --------------------------------------------------------------------------
def band_object(shape=(90, 200), half_width=9.0, period=14.0, seed=0):
    """RGBA band along a gentle wave; its skeleton polyline and the band's end caps.

    The colour depends on the arc length (stripes with a random phase per
    stripe) and on the signed offset across the band (a shading), so that
    every stretch of the band looks different, like a lizard tail.
    """
    h, w = shape
    rng = np.random.default_rng(seed)
    x = np.linspace(20, w - 20, 160)
    skel = np.c_[x, h / 2 + 12 * np.sin((x - 20) / 35.0)]
    st = Stroke(skel)
    yy, xx = np.mgrid[0:h, 0:w]
    pts = np.c_[xx.ravel(), yy.ravel()].astype(float)
    s, d = st.project(pts)
    s, d = s.reshape(h, w), d.reshape(h, w)
    # signed offset: which side of the skeleton
    foot = st.point_at(s.ravel()).reshape(h, w, 2)
    nrm = st.normal_at(s.ravel(), window=2.0).reshape(h, w, 2)
    side = np.sign(((np.dstack([xx, yy]) - foot) * nrm).sum(axis=2))
    t = side * d / half_width
    # round end caps: distance to the end points beyond the skeleton ends
    alpha = np.clip(half_width + 0.5 - d, 0.0, 1.0)
    k = np.floor(s / period).astype(int)
    phase = rng.uniform(0, 1, k.max() + 2)[k]
    stripe = 0.5 + 0.5 * np.cos(2 * np.pi * (s / period + 0.3 * t + phase))
    rgb = np.dstack([0.25 + 0.5 * stripe, 0.35 + 0.25 * (1 - stripe) + 0.1 * t,
                     0.2 + 0.15 * (t + 1)])
    rgb += rng.normal(0, 0.03, rgb.shape)
    img = np.dstack([np.clip(rgb, 0, 1), alpha]).astype(np.float32)
    img[alpha == 0, :3] = 0.0
    return img, skel




def premult(img):
    return img[..., :3] * img[..., 3:4]


@pytest.fixture(scope="module")
def band():
    return band_object()


# --------------------------------------------------------------------------
# strokes and control points
# --------------------------------------------------------------------------
def test_stroke_geometry():
    st = Stroke([(0, 0), (10, 0), (10, 0), (10, 10)])
    assert st.length == 20.0 and len(st.points) == 3  # repeated vertex dropped
    assert np.allclose(st.point_at([5, 15]), [[5, 0], [10, 5]])
    assert np.isclose(st.angle_at(15.0), np.pi / 2)
    s, d = st.project([(4, 3), (12, 7)])
    assert np.allclose(s, [4, 17]) and np.allclose(d, [3, 2])
    assert np.allclose(st.reversed().points[0], (10, 10))


def test_control_points_map_by_arc_length_fraction():
    pair = StrokePair(Stroke([(0, 0), (100, 0)]), Stroke([(0, 50), (0, 0)]))
    assert np.allclose(pair.source_arc_length([0, 25, 50]), [0, 50, 100])
    # a control pair: source s = 80 <-> target s = 10
    pair = pair.with_control([(80, 3)], [(1, 40)])
    assert pair.n_control == 3
    assert np.allclose(pair.control, [[0, 0], [80, 10], [100, 50]])
    # between c_0 and c_1: fraction of [0, 10] -> [0, 80]; between c_1 and c_2: [10, 50] -> [80, 100]
    assert np.allclose(pair.source_arc_length([5, 10, 30, 50]), [40, 80, 90, 100])
    smp = sample_pair(pair, 7.0, window=2.0)
    assert smp.pinned.sum() == 3 and np.allclose(smp.s[smp.pinned], [0, 10, 50])
    assert np.all(np.diff(smp.s) <= 7.0 + 1e-9)


def test_variable_spacing_follows_the_step_function():
    pair = StrokePair(Stroke([(0, 0), (100, 0)]), Stroke([(0, 0), (100, 0)]))
    smp = sample_pair(pair, lambda s: np.where(s < 50, 2.0, 10.0), window=2.0)
    steps = np.diff(smp.s)
    assert steps[:10].max() < 3.0 and steps[-3:].min() > 8.0


# --------------------------------------------------------------------------
# bad input
# --------------------------------------------------------------------------
IMG = np.zeros((40, 60, 4), np.float32)
IMG[15:25, 5:55] = (0.6, 0.4, 0.2, 1.0)
GOOD = [(8, 20), (52, 20)]


@pytest.mark.parametrize("src, tgt, kw, match", [
    ([GOOD, GOOD], [GOOD], {}, "pair up one to one: got 2 source and 1 target"),
    ([], [], {}, "empty"),
    ([[(8, 20)]], [GOOD], {}, r"source_strokes\[0\] needs at least 2"),
    ([GOOD], [[(8, 20), (8, 20), (8.2, 20)]], {}, r"target_strokes\[0\] has zero length"),
    ([[(8, 20), (80, 20)]], [GOOD], {}, r"source_strokes\[0\] leaves the 60 x 40 source image"),
    ([GOOD], [[(100, 100), (150, 100)]], {}, r"target_strokes\[0\] lies entirely outside"),
    ([GOOD], [GOOD], {"control_points": [([(20, 20), (40, 20)], [(40, 20), (20, 20)])]},
     "out of order along the source stroke"),
    ([GOOD], [GOOD], {"control_points": [([(20, 20)], [(40, 20), (20, 20)])]}, "they come in pairs"),
    ([GOOD], [GOOD], {"control_points": [None, None]}, "one entry per stroke pair"),
    ([GOOD], [[(8, 20), (np.nan, 20)]], {}, "NaN"),
    ([GOOD], [GOOD], {"background": (1, 0)}, "background"),
    ([GOOD], [GOOD], {"background": np.ones((10, 10, 3)), "target_shape": (40, 60)}, "differs"),
    ([GOOD], [GOOD], {"target_shape": (0, 5)}, "target_shape"),
])
def test_bad_input_raises_clear_errors(src, tgt, kw, match):
    with pytest.raises(ValueError, match=match):
        edit_structure(IMG, src, tgt, **kw)


def test_bad_types_and_params():
    with pytest.raises(TypeError, match="list of strokes"):
        edit_structure(IMG, np.array(GOOD, float), [GOOD])
    with pytest.raises(TypeError, match="StrokeEditParams"):
        edit_structure(IMG, [GOOD], [GOOD], params={"patch_size": 8})
    with pytest.raises(ValueError, match="patch_size"):
        edit_structure(IMG, [GOOD], [GOOD], StrokeEditParams(patch_size=-2))
    with pytest.raises(ValueError, match="sampling"):
        edit_structure(IMG, [GOOD], [GOOD], StrokeEditParams(sampling="random"))
    with pytest.raises(ValueError, match="image"):
        edit_structure(np.zeros((5, 5, 2)), [GOOD], [GOOD])


def test_target_stroke_partly_outside_is_clipped():
    res = edit_structure(IMG, [GOOD], [[(30, 20), (74, 20)]])
    assert res.mask[:, 30:].any() and res.image.shape == (40, 60, 4)


# --------------------------------------------------------------------------
# identity edit
# --------------------------------------------------------------------------
def test_identity_edit_reproduces_the_object(band):
    img, skel = band
    res = edit_structure(img, [skel], [skel])
    obj = img[..., 3] > 0.5
    assert psnr(premult(res.image), premult(img), obj) >= 30.0
    # the object region comes back whole (IoU of the masks)
    iou = (res.mask & obj).sum() / (res.mask | obj).sum()
    assert iou > 0.98
    assert res.energies["sampling_pairwise"] == pytest.approx(0.0, abs=1e-5)  # float32 sample coordinates


def test_identity_edit_on_the_lizard_tail():
    img = data.load("lizard")[400:925, 420:1024]
    tail = np.array([[52, 65], [96, 114], [126, 164], [146, 214], [168, 264], [184, 314],
                     [208, 364], [245, 414], [293, 459], [343, 486], [393, 501], [443, 505],
                     [493, 499], [543, 487], [588, 460]], float)
    res = edit_structure(img, [tail], [tail], StrokeEditParams(search_window=4))
    assert psnr(premult(res.image), premult(img), res.mask) >= 30.0
    # the tail (object pixels within 80 % of the local half width, between
    # the stroke ends) is all there
    st = Stroke(tail)
    index = source_index(img, [st])
    obj = np.argwhere(img[..., 3] > 0.5)
    s, d = st.project(obj[:, ::-1])
    core = (d <= 0.8 * index.half_width(0, s)) & (s > 1) & (s < st.length - 1)
    rows, cols = obj[core].T
    assert res.mask[rows, cols].mean() > 0.98


def test_identity_on_an_opaque_image():
    img = data.load("chelsea")[100:200, 100:260]
    st = [[(20, 50), (140, 60)]]
    res = edit_structure(img, st, st, StrokeEditParams(patch_size=24))
    # the object region of an opaque image is the union of the patches
    assert res.mask.sum() > 0.9 * 24 * 120
    assert res.mask[50, 80] and not res.mask[5, 80]
    assert psnr(res.image[..., :3], img, res.mask) >= 30.0


# --------------------------------------------------------------------------
# fetching: radius, ownership, cut ends
# --------------------------------------------------------------------------
def test_patch_radius_follows_the_width(band):
    img, skel = band
    index = source_index(img, [Stroke(skel)])
    w = index.half_width(0, np.linspace(20, 100, 5))
    assert np.all(np.abs(w - 9.0) <= 1.5)
    r = index.radius(0, [50.0])
    assert 1.2 * 9 + 3 <= r[0] <= 1.2 * 11 + 5
    assert index.radius(0, [50.0], patch_size=30)[0] == 15.0


def test_cut_ends_and_tips(band):
    img, skel = band
    # stroked to the tips: the object ends there
    assert source_index(img, [Stroke(skel)]).cut_ends[0] == (False, False)
    # a stroke in the middle of the band: both ends cut straight
    st = Stroke(skel[40:120])
    index = source_index(img, [st])
    assert index.cut_ends[0] == (True, True)
    res = edit_structure(img, [skel[40:120]], [skel[40:120]], StrokeEditParams(unstroked="drop"))
    # nothing copied beyond the cut: the end patch stops at the line through the end point
    p, u = st.points[-1], st.points[-1] - st.points[-2]
    u = u / np.hypot(*u)
    rows, cols = np.nonzero(res.mask)
    ahead = (cols - p[0]) * u[0] + (rows - p[1]) * u[1]
    assert ahead.max() <= 1.5
    # by default the unstroked rest of the band follows (here: stays where it is)
    whole = edit_structure(img, [skel[40:120]], [skel[40:120]])
    obj = img[..., 3] > 0.5
    assert (whole.mask & obj).sum() / (whole.mask | obj).sum() > 0.97


def test_repeated_source_stroke_feeds_two_targets(band):
    img, skel = band
    part = skel[30:90]
    t1 = part - (0, 25)
    t2 = part + (0, 25)
    res = edit_structure(img, [part, part], [t1, t2], StrokeEditParams(unstroked="drop"),
                         target_shape=(140, 200))
    top, bottom = res.mask[:70].sum(), res.mask[70:].sum()
    assert top > 500 and abs(top - bottom) < 0.1 * top


# --------------------------------------------------------------------------
# global texture sampling
# --------------------------------------------------------------------------
@pytest.mark.parametrize("seed", range(4))
def test_viterbi_is_the_exact_minimum(seed):
    rng = np.random.default_rng(seed)
    ks = rng.integers(1, 4, size=5)
    un = [rng.random(k) for k in ks]
    pw = [rng.random((ks[j], ks[j + 1])) for j in range(len(ks) - 1)]
    path, e = viterbi(un, pw)
    brute = min(chain_energy(p, un, pw) for p in itertools.product(*[range(k) for k in ks]))
    assert e == pytest.approx(brute) and chain_energy(path, un, pw) == pytest.approx(brute)
    assert greedy(un, pw)[1] >= e - 1e-12


def _bent(skel, amount=25.0):
    x = skel[:, 0]
    return np.c_[x, 45 + amount * np.sin((x - 20) / 22.0)]


def test_dp_sampling_has_lower_energy_than_greedy(band):
    img, skel = band
    tgt = _bent(skel)
    base = StrokeEditParams(search_window=10, search_step=2)
    dp = edit_structure(img, [skel], [tgt], base)
    gr = edit_structure(img, [skel], [tgt], dataclasses.replace(base, sampling="greedy"))
    assert dp.energies["sampling"] < gr.energies["sampling"]
    assert dp.energies["sampling"] <= edit_structure(
        img, [skel], [tgt], dataclasses.replace(base, sampling="none")).energies["sampling"]
    shifts = np.abs(dp.samples[0].shift[:, 0])
    assert shifts.max() > 0  # the search window is used


def test_graphcut_has_lower_seam_cost_than_overlay(band):
    img, skel = band
    tgt = _bent(skel)
    gc = edit_structure(img, [skel], [tgt])
    ov = edit_structure(img, [skel], [tgt], StrokeEditParams(composition="overlay"))
    assert gc.energies["seam"] < 0.8 * ov.energies["seam"]
    # same patches either way, only the labelling differs
    assert np.array_equal(gc.samples[0].source, ov.samples[0].source)


def test_compose_pins_the_overlap_boundary():
    a = PlacedPatch(np.full((9, 9, 4), 0.2, np.float32), np.ones((9, 9), bool), (0, 0))
    b = PlacedPatch(np.full((9, 9, 4), 0.8, np.float32), np.ones((9, 9), bool), (5, 0))
    for method in ("graphcut", "overlay"):
        c = compose([a, b], (9, 14), method=method)
        assert (c.labels[:, :5] == 0).all() and (c.labels[:, 9:] == 1).all()
        assert (c.labels[:, 5] == 0).all()  # the overlap pixels next to a-only are pinned to a
        assert (c.labels[:, 8] == 1).all()


def test_compose_gives_pixels_laid_under_keep_to_a_later_patch():
    """A branch's patch keeps its parent's pixels (keep_a) but fills them where the
    canvas is empty; a later patch (the parent's carried part) takes them back."""
    keep = np.zeros((9, 9), bool)
    keep[:, :4] = True
    branch = PlacedPatch(np.full((9, 9, 4), 0.8, np.float32), np.ones((9, 9), bool), (0, 0), keep_a=keep)
    part = PlacedPatch(np.full((9, 9, 4), 0.2, np.float32), np.ones((9, 9), bool), (-5, 0))
    for method in ("graphcut", "overlay"):
        c = compose([branch, part], (9, 12), method=method)
        assert (c.labels[:, :4] == 1).all()  # the kept pixels go to the part
        assert (c.labels[:, 5:9] == 0).all()
        alone = compose([branch], (9, 12), method=method)
        assert (alone.labels[:, :9] == 0).all()  # nothing else came: no hole


# --------------------------------------------------------------------------
# branching
# --------------------------------------------------------------------------
def test_junctions_and_order():
    trunk = Stroke([(0, 0), (0, 100)])
    branch = Stroke([(2, 50), (40, 20)])
    twig = Stroke([(40, 21), (60, 0)])
    js = find_junctions([branch, trunk, twig], tolerance=4)
    assert {(j.child, j.parent) for j in js} == {(0, 1), (2, 0)}
    assert stroke_order(3, js) == [1, 0, 2]


def test_a_branch_grows_out_of_its_parent(band):
    img, skel = band
    part = skel[20:140]
    trunk = np.c_[np.linspace(20, 180, 60), np.full(60, 100.0)]
    start = trunk[25]
    branch = np.c_[np.linspace(start[0], start[0] + 60, 30), np.linspace(100, 30, 30)]
    shape = (150, 200)
    drop = StrokeEditParams(unstroked="drop")  # the strokes alone, as in the paper
    alone = edit_structure(img, [part], [trunk], drop, target_shape=shape)
    res = edit_structure(img, [part, part], [trunk, branch], drop, target_shape=shape)
    assert len(res.junctions) == 1 and res.junctions[0].parent == 0
    lab, n = ndi.label(res.mask)
    assert n == 1  # one connected object
    # the far side of the parent is untouched by the branch
    far = np.zeros(shape, bool)
    far[103:, :] = True
    assert np.array_equal(res.labels[far] >= 0, alone.labels[far] >= 0)
    assert np.allclose(res.image[far], alone.image[far])
    # the branch is there, next to the junction too
    assert res.mask[40:80, 90:130].sum() > 200
    assert res.mask[80:92, start.astype(int)[0]:start.astype(int)[0] + 25].mean() > 0.5


# --------------------------------------------------------------------------
# result object
# --------------------------------------------------------------------------
def test_result_background_and_png(band):
    img, skel = band
    tgt = _bent(skel, 10.0)
    res = edit_structure(img, [skel], [tgt])
    assert res.image.dtype == np.float32 and res.image.shape == img.shape
    assert (res.image[~res.mask & (res.layer[..., 3] == 0), 3] == 0).all()  # transparent
    col = edit_structure(img, [skel], [tgt], background=(0.0, 0.0, 1.0))
    assert np.allclose(col.image[0, 0], (0, 0, 1, 1))
    bg = np.full((90, 200, 3), 0.5, np.float32)
    over = edit_structure(img, [skel], [tgt], background=bg)
    assert np.allclose(over.image[0, 0], (0.5, 0.5, 0.5, 1))
    assert np.allclose(over.image[over.mask & (res.layer[..., 3] > 0.999)],
                       np.dstack([res.layer[..., :3], np.ones(img.shape[:2])])[
                           over.mask & (res.layer[..., 3] > 0.999)], atol=1e-3)
    assert res._repr_png_()[:8] == b"\x89PNG\r\n\x1a\n"
    shown = res.show(seams=True)
    assert shown.shape == (90, 200, 3) and res.seams.any()
    # deterministic
    again = edit_structure(img, [skel], [tgt], rng=5)
    assert np.array_equal(again.image, res.image)


def test_make_pairs_accepts_stroke_objects():
    pairs = make_pairs([Stroke(GOOD)], [np.array(GOOD) + (0, 5)])
    assert pairs[0].target.points[0].tolist() == [8.0, 25.0]


def test_bench_quick_row():
    from branchnb.strokes._bench import rows

    (row,) = rows(quick=True)
    assert "512 x 512" in row.name and row.seconds > 0 and row.anchor_seconds > 0
    assert "greedy" in row.anchor


def test_draw_strokes_colours_pairs():
    from branchnb.strokes import draw_strokes, pair_color

    img = draw_strokes(np.ones((30, 60, 3)), [[(5, 10), (50, 10)], [(5, 22), (50, 22)]], width=3)
    assert np.allclose(img[10, 25], pair_color(0), atol=0.05)
    assert np.allclose(img[22, 25], pair_color(1), atol=0.05)
    assert np.allclose(img[2, 2], 1.0)


def test_source_region_and_colour_histograms(band):
    from branchnb.strokes import compare_colours

    img, skel = band
    ident = edit_structure(img, [skel], [skel])
    obj = img[..., 3] > 0.5
    assert (ident.source_region & obj).sum() > 0.98 * obj.sum()
    cmp = compare_colours(img, ident)
    assert [c.labels for c in cmp] == [["source object", "result"]] * 3
    assert max(c.distances[1] for c in cmp) < 0.05
    # a bent copy of half the band: same colours, a different object than a far-off colour
    half = edit_structure(img, [skel[:80]], [_bent(skel)[:80]])
    assert max(c.distances[1] for c in compare_colours(img, half)) < 0.3
    blue = img.copy()
    blue[..., :3] = (0.1, 0.1, 0.9)
    other = edit_structure(blue, [skel], [skel])
    assert min(c.distances[1] for c in compare_colours(img, other)) > 0.5


def test_a_branch_copied_from_the_trunk_leaves_the_trunk_behind():
    # a wide trunk (half width 20) with a thin branch (half width 5) growing from its centre line
    img = np.zeros((120, 200, 4), np.float32)
    img[10:110, 30:70] = (0.4, 0.25, 0.1, 1.0)
    img[55:65, 50:190] = (0.5, 0.3, 0.1, 1.0)
    img[55:65, 120:190, 1] = np.linspace(0.3, 0.8, 70)  # some texture along the branch
    trunk, branch = [(50, 105), (50, 15)], [(50, 60), (185, 60)]
    index = source_index(img, [Stroke(trunk), Stroke(branch)])
    assert index.cut_ends[1] == (True, False)  # joined to the trunk at its start
    assert index.half_width(1, 2.0) < 8  # the branch's own width, not the trunk's
    # copy the branch alone, vertically, into an empty domain
    res = edit_structure(img, [trunk, branch], [[(20, 110), (20, 20)], [(100, 10), (100, 145)]],
                         target_shape=(150, 200))
    rows = res.mask[10:140, 60:140]
    widths = rows.sum(axis=1)
    assert widths.max() <= 15 and np.median(widths) >= 9


def test_cut_end_inside_a_wider_body_stays_within_the_tube():
    # a thin tail (half width 5) leaving a wide body (half width 25); the
    # stroke starts inside the body, so its start is cut straight across --
    # only across the tail's tube, not along the whole body (a line of
    # half-transparent body pixels along the cut once leaked out).
    img = np.zeros((100, 200, 4), np.float32)
    img[25:75, 10:60] = (0.3, 0.3, 0.3, 1.0)
    img[45:55, 60:190] = (0.6, 0.4, 0.2, 1.0)
    img[45:55, 60:190, 1] = np.linspace(0.2, 0.7, 130)
    tail = [(40, 50), (180, 50)]
    assert source_index(img, [Stroke(tail)]).cut_ends[0] == (True, False)
    res = edit_structure(img, [tail], [[(100, 10), (100, 150)]],
                         StrokeEditParams(patch_size=60, unstroked="drop"), target_shape=(160, 200))
    rows, cols = np.nonzero(res.image[..., 3] > 0.01)
    assert rows.min() >= 9  # nothing beyond the cut
    assert np.abs(cols - 100).max() <= 5 + 2 + 2  # half width + opaque margin + ramp


def test_disk_closing_matches_the_morphological_closing():
    """fill_joints' closing from distance transforms: the same pixels as a dilation and
    an erosion by the disk (which cost grows with its area: 0.7 s of a 1000-px figure edit)."""
    from scipy import ndimage as ndi

    from branchnb.strokes.outline import _disk_closing

    rng = np.random.default_rng(1)
    for _ in range(12):
        h, w = rng.integers(8, 60, 2)
        k = int(rng.integers(1, 12))  # morphology up to 5, distance transforms beyond
        m = ndi.gaussian_filter(rng.random((h, w)), 3.0) > 0.5
        yy, xx = np.mgrid[-k:k + 1, -k:k + 1]
        disk = xx**2 + yy**2 <= k * k
        ref = ndi.binary_erosion(ndi.binary_dilation(np.pad(m, k + 1), disk), disk)[k + 1:-k - 1, k + 1:-k - 1]
        assert np.array_equal(_disk_closing(m, k), ref)
