"""A photo's matte (a fundus's black surround) stays outside the output's domain (issue 23)."""

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import synthesize_image
from branchnb.branching._image_examples import random_tree, textured_ground
from branchnb.core.render import draw_polylines


def _disk(size, frac=0.46):
    yy, xx = np.mgrid[:size, :size]
    return (xx - size / 2) ** 2 + (yy - size / 2) ** 2 <= (frac * size) ** 2


def _fundus(size, seed, colour=0.0):
    """Vessels on a textured orange disk with a flat black (or white) matte around it."""
    rng = np.random.default_rng(seed)
    img = textured_ground((size, size), rng, colour=(0.85, 0.42, 0.18))
    s = random_tree((size, size), rng, n_children=3, r_root=2.5, r_child=1.8)
    img = draw_polylines(img, [b.points for b in s.branches], widths=[2 * b.thickness for b in s.branches],
                         colors=(0.45, 0.1, 0.05))
    dom = _disk(size)
    a = ndi.gaussian_filter(dom.astype(np.float32), 1.0)[..., None]
    img = img * a + colour * (1 - a)
    return np.clip(img, 0, 1).astype(np.float32), s, dom


def _clip_to(s, dom):
    """The target tree cut to the disk (what a structure grown in the domain looks like)."""
    from branchnb.core.structure import Branch, Structure

    out = []
    for b in s.branches:
        ij = np.clip(np.round(b.points).astype(int), 0, dom.shape[0] - 1)
        keep = dom[ij[:, 1], ij[:, 0]]
        if b.parent is None:
            idx = np.flatnonzero(keep)
            pts, r = b.points[idx[0]:idx[-1] + 1], np.asarray(b.thickness)[idx[0]:idx[-1] + 1]
            out.append(Branch(pts, r))
            off = idx[0]
        else:
            cut = np.flatnonzero(~keep)
            n = cut[0] if len(cut) else len(keep)
            pv = b.parent_vertex - off
            if n >= 4 and 0 <= pv < len(out[0].points):
                out.append(Branch(b.points[:n], np.asarray(b.thickness)[:n], 0, int(pv)))
    return Structure(out, dom.shape)


@pytest.mark.parametrize("seed,colour", [(0, 0.0), (1, 0.0), (2, 1.0)])
def test_matte_kept_outside_domain(seed, colour):
    size = 140
    ex, s_ex, dom = _fundus(size, seed, colour)
    target = _clip_to(random_tree((size, size), seed + 10, n_children=3, r_root=2.5, r_child=1.8), dom)
    res = synthesize_image(ex, s_ex, target, rng=seed, target_domain=dom)
    out = np.asarray(res.image)[..., :3]
    outside = ~ndi.binary_dilation(dom, iterations=3)
    kept = np.mean(np.max(np.abs(out[outside] - colour), axis=1) <= 0.1)
    assert kept >= 0.98
    # inside, the disk is still the example's texture (not painted over)
    core = ndi.binary_erosion(dom, iterations=6)
    assert abs(float(np.median(out[core][:, 0])) - float(np.median(ex[core][:, 0]))) < 0.1
    # the disk's edge is a soft step, not a drawn dark line: the rim just inside is as bright as the ground
    rim = dom & ~ndi.binary_erosion(dom, iterations=3) & ndi.binary_erosion(dom, iterations=1)
    if colour == 0.0:
        assert np.median(out[rim].mean(1)) > 0.6 * np.median(out[core].mean(1))


def test_example_domain_leaves_out_matte_slivers():
    # a fundus disk nearly touching the frame: the matte between it and the frame is a sliver
    # narrower than the flat-region disk, still no part of the domain
    from branchnb.branching import example_domain
    from branchnb.branching.regions import matte_mask

    size = 200
    rng = np.random.default_rng(4)
    img = textured_ground((size, size), rng, colour=(0.85, 0.42, 0.18))
    s = random_tree((size, size), rng, n_children=3, r_root=2.5, r_child=1.8)
    img = draw_polylines(img, [b.points for b in s.branches], widths=[2 * b.thickness for b in s.branches],
                         colors=(0.45, 0.1, 0.05))
    dom = _disk(size, 0.495)
    a = ndi.gaussian_filter(dom.astype(np.float32), 1.0)[..., None]
    img = np.clip(img * a, 0, 1).astype(np.float32)
    d = example_domain(img, s)
    matte = matte_mask(img, dilate=0)
    assert (d & matte).sum() <= 0.02 * matte.sum()
    assert np.mean(d[ndi.binary_erosion(dom, iterations=4)]) >= 0.99


def test_matte_edge_is_no_drawn_line_but_a_terrain_coast_is():
    # at 500 px a fundus disk's blurred rim passes the drawn-boundary test; it is the matte's edge
    # (a blend of ground and matte), so the output keeps the matte instead of drawing an arc
    from branchnb.branching._map_examples import terrain_map_example
    from branchnb.branching.drawn_domains import drawn_boundary
    from branchnb.branching.output_regions import _walls_off_matte
    from branchnb.branching.skeleton_map import SkeletonMap

    ex, s, _dom = _fundus(500, 0)
    b = drawn_boundary(ex, s, SkeletonMap(s, 1.0).pixel_map(ex.shape[:2]))
    assert b is not None and _walls_off_matte(b.domain, b.colour, ex)
    for seed in (0, 1):
        img, st, _riv = terrain_map_example((256, 256), seed)
        b = drawn_boundary(img, st, SkeletonMap(st, 1.0).pixel_map(img.shape[:2]))
        assert b is not None and not _walls_off_matte(b.domain, b.colour, img)
