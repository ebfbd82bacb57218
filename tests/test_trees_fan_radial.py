"""Fans found by their radiating strokes, not by how much sky lies between the fronds (issue 24).

A palm whose broad fronds touch each other fills 0.69-0.9 of its convex hull and was taken as
a broadleaf crown: its fronds became cards that turn about their own centres and pile up on the
axis from the side (inner-line recall 0.77-0.85 on ``trees_unseen_drawn.fan_palm``), a fan
palm's leaf became a shredded superpixel cloud. The strokes of a fan point at one hub
(``billboard_shapes._radial_lines``); clumps, fruits and a conifer's tiers do not.
"""

import cv2
import numpy as np
import pytest
from trees_unseen_drawn import UNSEEN

from branchnb.trees.billboard import TRUNK_LAYER, BillboardParams, billboard_cloud
from branchnb.trees.billboard_shapes import _radial_lines
from branchnb.trees.lod import bake_side_outline
from branchnb.trees.side_lines import side_line_figures


def _canvas(n=160):
    return np.zeros((n, n), np.uint8)


def _disc_crown(n=160, r=60):
    crown = _canvas(n)
    cv2.circle(crown, (n // 2, n // 2), r, 1, -1)
    return crown.astype(bool)


def _outlined(crown, strokes):
    rim = crown & ~cv2.erode(crown.astype(np.uint8), np.ones((5, 5), np.uint8)).astype(bool)
    return strokes.astype(bool) | rim


def test_radial_strokes_make_a_fan_round_and_parallel_ones_do_not():
    crown = _disc_crown()
    hub = (80, 80)
    rays = _canvas()
    for a in np.deg2rad(np.arange(0, 360, 30) + 7):
        cv2.line(rays, hub, (int(80 + 58 * np.cos(a)), int(80 + 58 * np.sin(a))), 1, 2)
    assert _radial_lines(crown, _outlined(crown, rays), crown)
    circles = _canvas()                                  # clumps drawn over a crown
    for cx, cy, r in ((60, 60, 14), (100, 62, 16), (80, 95, 18), (55, 100, 12), (108, 100, 12)):
        cv2.circle(circles, (cx, cy), r, 1, 2)
    assert not _radial_lines(crown, _outlined(crown, circles), crown)
    tiers = _canvas()                                    # a conifer's tier edges run across
    for y in (50, 70, 90, 110):
        cv2.line(tiers, (35, y), (125, y + 4), 1, 2)
    assert not _radial_lines(crown, _outlined(crown, tiers), crown)
    one_way = _canvas()                                  # a trunk's sides: one or two rays
    cv2.line(one_way, (75, 80), (75, 135), 1, 2)
    cv2.line(one_way, (85, 80), (85, 135), 1, 2)
    assert not _radial_lines(crown, _outlined(crown, one_way), crown)


@pytest.mark.parametrize("size", [200, 320])
def test_fan_palm_with_touching_fronds_keeps_its_lines_from_the_side(size):
    img = cv2.resize(UNSEEN["fan_palm"](2 * size), (size, size), interpolation=cv2.INTER_AREA)
    cloud = billboard_cloud(img, params=BillboardParams(max_size=size), rng=0)
    assert (cloud.layer != TRUNK_LAYER).sum() == 1             # main: 8 / 7 frond cards
    baked = bake_side_outline(cloud)
    for yaw in (45.0, 90.0):
        f = side_line_figures(baked, yaw)
        assert f["recall"] >= 0.97, (size, yaw, f)              # main: 0.77-0.85
        assert f["smear"] <= 0.01


def test_fan_palm_leaf_and_rosette_are_one_billboard_broadleaf_is_not():
    from branchnb.trees._fan_family import FAN_KINDS, fan_crown
    from branchnb.trees.drawn import drawn_tree

    for kind in ("fan", "yucca"):                               # main: a superpixel cloud / cards
        img = fan_crown(kind, rng=FAN_KINDS.index(kind), size=128)
        cloud = billboard_cloud(img, params=BillboardParams(max_size=128), rng=0)
        assert (cloud.layer != TRUNK_LAYER).sum() == 1, kind
    for kind in ("broadleaf", "fruit"):
        cloud = billboard_cloud(drawn_tree(kind, rng=1, size=128), params=BillboardParams(max_size=128), rng=0)
        assert (cloud.layer != TRUNK_LAYER).sum() > 1, kind
