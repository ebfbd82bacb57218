"""Synthesized branches do not hug the canvas frame (issue 23, branching82): trees painted entering from
one frame edge (:func:`branchnb.branching._frame_hug_check.hug_example`) grow trunks and children that
keep off the frame's band once they have left it (``growth.FRAME_BAND``)."""
import numpy as np
import pytest

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_structure
from branchnb.branching._frame_hug_check import frame_share, hug_example
from branchnb.branching.frame_band import FRAME_BAND, FRAME_HUG_SHARE, _frame_ends, _frame_share
from branchnb.core.structure import Branch, Structure


@pytest.mark.parametrize("kind, seed", [("roots", 1), ("river", 2), ("bolt", 1)])
def test_output_keeps_off_the_frame_like_the_example(kind, seed):
    # main (256 px, map workflow): share of length within 6 px of the frame 0.040 / 0.035 / 0.038 (bounds
    # 0.010 / 0.010 / 0.024 from the example's); branching82: 0.000 / 0.000 / 0.005
    img, truth = hug_example(kind, 256, seed)
    ex = extract_structure(img)
    m = fit_model(ex, domain=example_domain(img, ex))
    t = synthesize_structure(m, rng=seed).structure
    fx = frame_share([(p, r, None if g == 0 else 1) for p, r, g in truth], img.shape[:2])
    fq = frame_share([(b.points, b.thickness, b.parent) for b in t.branches], img.shape[:2])
    assert fq <= 2.0 * fx + 0.01, (fq, fx)
    assert sum(b.length for b in t.branches) >= 0.5 * sum(b.length for b in ex.branches)


def test_band_rule_only_where_the_example_keeps_off_its_frame():
    inside = Structure([Branch([(50, 0), (52, 40), (50, 90)], 2.0),
                        Branch([(52, 40), (80, 70)], 1.0, parent=0, parent_vertex=1)], image_shape=(100, 100))
    assert _frame_share(inside, FRAME_BAND) <= FRAME_HUG_SHARE       # the trunk's entry is left out
    border = Structure([Branch([(50, 0), (52, 40), (50, 90)], 2.0),
                        Branch([(52, 40), (97, 45), (97, 95)], 1.0, parent=0, parent_vertex=1)],
                       image_shape=(100, 100))
    assert _frame_share(border, FRAME_BAND) > FRAME_HUG_SHARE       # a line drawn along the right side
    # lines leave the frame through the sides where the example's end, not where its roots enter
    leaving = Structure([Branch([(50, 1), (52, 40), (50, 99)], 2.0),
                         Branch([(52, 40), (99.5, 60)], 1.0, parent=0, parent_vertex=1)], image_shape=(100, 100))
    assert _frame_ends(leaving, 2.0).tolist() == [False, False, True, True]
    assert not _frame_ends(inside, 2.0).any()


def test_children_of_a_trunk_reaching_the_far_side_do_not_run_along_it():
    # a straight trunk with straight side branches, synthesized on a frame half as tall: whatever reaches
    # the bottom stops there instead of turning along it
    pts = np.c_[np.full(60, 60.0), np.linspace(0, 150, 60)]
    kids = [Branch([(60, y), (60 + s * 30, y + 30), (60 + s * 45, y + 60)], 1.0, parent=0,
                   parent_vertex=int(round(y / 150 * 59))) for y, s in ((40, 1), (70, -1), (100, 1))]
    ex = Structure([Branch(pts, np.linspace(3, 1.5, 60))] + kids, image_shape=(180, 120))
    m = fit_model(ex)
    for seed in (0, 1, 2):
        t = synthesize_structure(m, rng=seed, shape=(90, 120)).structure
        fq = frame_share([(b.points, b.thickness, b.parent) for b in t.branches], (90, 120))
        assert fq <= 0.01, (seed, fq)   # main: 0.038, 0.019, 0.038
