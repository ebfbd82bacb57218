"""A leaf kind no other test uses, end to end with the defaults: ginkgo-like fans with dichotomous veins."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.leaves import LayerSet, analyze, leaf_family
from branchnb.leaves.scribbles import Layer


def test_fan_leaves_have_a_cleft_fan_and_dichotomous_veins_only():
    from skimage.morphology import skeletonize

    fam = leaf_family(3, size=200, kind="fan", rng=4)
    for leaf in fam:
        veins = leaf.layers["veins"]
        sk = skeletonize(veins)
        nb = ndi.convolve(sk.astype(int), np.ones((3, 3), int), mode="constant") - 1
        ends = int((sk & (nb == 1)).sum())
        # 16 last veins reaching the arc (and the petiole's end), no network between them
        assert 14 <= ends <= 22
        # no network: nothing enclosed by veins but pixel gaps where two forks leave side by side
        holes, n = ndi.label(ndi.binary_fill_holes(veins) & ~veins)
        assert n == 0 or np.bincount(holes.ravel())[1:].max() <= 12
        # wider than long: a fan (lamina only, in the leaf's own axes)
        lam = leaf.blade & ~ndi.binary_opening(leaf.blade & ~ndi.binary_opening(leaf.blade, iterations=4))
        ys, xs = np.nonzero(lam)
        ev = np.linalg.eigvalsh(np.cov(np.vstack([xs, ys])))
        assert ev[1] / ev[0] > 1.3
    # the cleft: the outline's radius about the blade's centre dips in the middle of the arc
    from branchnb.leaves.procedural import KINDS, _canonical_radius
    a = np.linspace(-0.6, 0.6, 121)
    r = _canonical_radius(KINDS["fan"], a, np.ones(2), None)
    assert r[60] < 0.8 * r[[20, 100]].min()


def _scribbled(leaf, size):
    ls = LayerSet([Layer("veins", order=0), Layer("spots", "#1f77b4", 1)])
    lines = sorted(leaf.veins[1:], key=lambda p: -np.hypot(*np.diff(p, axis=0).T).sum())[:6]
    for p in lines:
        k = len(p)
        ls.add_scribble("veins", p[int(0.2 * k):max(int(0.8 * k), int(0.2 * k) + 2)].tolist(), radius=1)
    lab, n = ndi.label(leaf.layers["spots"])
    for i in range(1, min(n, 2) + 1):
        ys, xs = np.nonzero(lab == i)
        c = (float(xs.mean()), float(ys.mean()))
        ls.add_scribble("spots", [c, (c[0] + 1, c[1] + 1)], radius=1)
    return ls


@pytest.fixture(scope="module")
def fan_analysis():
    fam = leaf_family(4, size=200, kind="fan", palette="autumn", rng=0)
    return fam, analyze(fam, 0, _scribbled(fam[0], 200))


def test_fan_pipeline_with_the_defaults_meets_the_issue_figures(fan_analysis):
    """Measured (6 vein strokes and 2 spot dots on the first fan, 8 new leaves): 4 fans of 200 px:
    induced vein IoU 0.74-0.90, sharpness 1.19 of the exemplars', median pairwise blade IoU of new
    leaves 0.68 (exemplars 0.72), vein continuity 1.00; 6 of 256 px: 0.83-0.88, 1.02, 0.63 (0.64),
    0.99; 4 of 1000 px: 0.76-0.81, 1.03, 0.77 (0.80), 0.95; never a leaf cut, petioles within
    0.5 degrees of the exemplars' largest angle."""
    from branchnb.core.metrics import iou
    from branchnb.leaves._measure_synthesis import synthesis_row
    from branchnb.leaves.analysis import normalise_exemplars

    fam, a = fan_analysis
    _, _, offs = normalise_exemplars([f.image for f in fam])
    for e, (f, (dx, dy)) in enumerate(zip(fam, offs)):
        h, w = f.blade.shape
        gb = np.zeros(a.blades[e].shape, bool)
        gb[dy:dy + h, dx:dx + w] = f.blade
        gv = np.zeros_like(gb)
        gv[dy:dy + h, dx:dx + w] = f.layers["veins"]
        assert iou(a.blades[e], gb) > 0.97
        assert iou(a.layer("veins").masks[e], gv) >= 0.7
    r = synthesis_row(a, 8, seed=1)
    assert r["sharp"] >= 0.8
    assert r["iou_new"] <= r["iou_ex"] + 0.05
    assert r["cut"] == 0.0
    assert r["pet_dev"] <= 10.0
    assert r["vein_cont"] >= 0.85
