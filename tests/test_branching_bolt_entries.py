"""Issue 23 (branching87): bolts entering from the frame are rooted there and keep their bearing."""
import numpy as np
from scipy import ndimage as ndi

from branchnb.branching import extract_structure
from branchnb.branching._frame_hug_check import hug_example
from branchnb.branching.fragment_links import relink_fragments


def _pieces(sk):
    return int(ndi.label(sk, np.ones((3, 3)))[1])


def test_relink_joins_only_floating_pieces_to_the_frame():
    sk = np.zeros((120, 120), bool)
    sk[0:50, 60] = True                           # enters from the top
    sk[58:110, 60] = True                          # the rest of the line, cut off
    drop = np.zeros_like(sk)
    drop[50:58, 60] = True
    assert _pieces(relink_fragments(sk, drop, 30.0)) == 1
    # a floating piece shorter than the minimum stays alone (the structure drops it)
    assert _pieces(relink_fragments(sk, drop, 80.0)) == 2
    # nothing reaches the frame: nothing is linked
    inner = np.roll(sk, 5, axis=0)
    inner[:10] = False
    assert _pieces(relink_fragments(inner, np.roll(drop, 5, axis=0), 30.0)) == 2
    # a dropped stretch far longer than the piece it would link is a line of its own
    sk2 = np.zeros((260, 60), bool)
    sk2[0:20, 30] = True
    sk2[200:240, 30] = True
    drop2 = np.zeros_like(sk2)
    drop2[20:200, 30] = True
    assert _pieces(relink_fragments(sk2, drop2, 30.0)) == 2


def test_bolt_pieces_are_rooted_at_the_frame_entries():
    # a thin side branch leaves a 512 px bolt where its stretch beside the trunk reads one-sided; it
    # used to become a tree rooted 57 px from the left edge, 237 px down
    img, truth = hug_example("bolt", 512, 0)
    s = extract_structure(img)
    roots = [b for b in s.branches if b.parent is None]
    entries = [(p[0], float(r[0])) for p, r, g in truth if g == 0]
    for b in roots:
        d = min(np.hypot(*(b.points[0] - q)) - 2.0 * rr for q, rr in entries)
        assert d <= 4.0, f"root at {b.points[0]} is {d:.1f} px past 2 radii from every entry"
    for q, rr in entries:
        assert min(np.hypot(*(b.points[0] - q)) for b in roots) <= 4.0 + 2.0 * rr
