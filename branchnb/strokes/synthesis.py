"""Stage 2 of the edit: global texture sampling and composition (:func:`compose_patches`).

Steps 4 and 5 of :func:`~branchnb.strokes.edit.edit_structure`: the
correspondences chosen by dynamic programming, the patches stitched by
graph cut, the unstroked parts carried after all strokes, the joints
closed and the cut faces outlined.
"""

from __future__ import annotations

import dataclasses

import cv2
import numpy as np
from scipy import ndimage as ndi
from scipy.spatial import cKDTree

from .composition import PlacedPatch, compose, labelling_cost, seam_mask
from .crossings import crossed_over
from .crotches import _child_width, new_crotches, round_crotches
from .edit import FETCH_FIELDS, EditPatches, StrokeEditParams, StrokeEditResult, StrokeSamples, _check_edit_params
from .fanning import _fanned_maps
from .joints import _refill_vacated_roots, close_hairlines, hold_joint_bodies, joint_disks, joint_roots
from .junctions import far_side
from .outline import (
    _POCKET,
    _close_rim_cracks,
    _disk_closing,
    clear_stale_outline,
    close_cuts,
    drop_flecks,
    fill_joints,
    fill_pinholes,
    source_depth,
)
from .overlays import _overlaid_parts, _solid_cracks
from .parts import place_part, rigid_frame
from .sampling import choose, pair_energies
from .slits import _carried_slits, _fill_closed_off, _joint_zones, _open_stretches
from .tubes import _distance_map

__all__ = ["compose_patches"]


def compose_patches(patches: EditPatches, params: StrokeEditParams | None = None) -> StrokeEditResult:
    """Stage 2 of :func:`edit_structure`: choose the correspondences and stitch the patches.

    Parameters
    ----------
    patches : EditPatches
        From :func:`fetch_patches`.
    params : StrokeEditParams, optional
        Default: the parameters ``patches`` were fetched with. Others may
        differ only outside :data:`FETCH_FIELDS` (see
        :meth:`EditPatches.reusable_for`).

    Returns
    -------
    StrokeEditResult
        The same as :func:`edit_structure` with ``params`` gives.
    """
    if not isinstance(patches, EditPatches):
        raise TypeError(f"patches must be EditPatches (from fetch_patches), got {type(patches).__name__}")
    params = patches.params if params is None else _check_edit_params(params)
    if not patches.reusable_for(params):
        changed = [f for f in FETCH_FIELDS if getattr(params, f) != getattr(patches.params, f)]
        raise ValueError(f"params differ from the fetched patches' in {changed or ['sampling (none)']}: "
                         "call fetch_patches again")
    index, window, junctions = patches._index, patches._window, patches.junctions
    attached, extra, target_shape = patches.attached, patches._extra, patches.target_shape
    placed: list[PlacedPatch] = []
    # per patch: (stroke, target arc length, valid pixels or None) of a stroke's sample, None for a
    # carried part
    laid: list = []
    samples: list[StrokeSamples | None] = [None] * len(patches.pairs)
    e_total = e_pair = 0.0
    source_region = np.zeros(index.shape, bool)
    inside_cache: dict = {}
    across = {cand.index: _AcrossCheck(index, cand.index, attached[cand.index], cand.radii, target_shape)
              for cand in patches._strokes if not _rigid(attached[cand.index])}
    for cand in patches._strokes:
        i, smp, radii, fetched, offs = cand.index, cand.samples, cand.radii, cand.fetched, cand.offsets
        pair = attached[i]
        unaries = [params.shift_penalty * np.abs(off).sum(axis=1) / patches._scale for off in offs]
        pairwise = [pair_energies(fetched[j], fetched[j + 1], power=params.seam_power,
                                  gradient_weighted=params.gradient_weighted,
                                  stride=params.energy_stride)
                    for j in range(len(smp) - 1)]
        res = choose(unaries, pairwise, params.sampling)
        e_total += res.energy
        e_pair += res.pairwise
        # Junction handling for the child's patches near its attached ends.
        mine = [jn for jn in junctions if jn.child == i]
        for j, k in enumerate(res.choice):
            f = fetched[j]
            pin_core, keep = True, None
            for jn in mine:
                end_s = 0.0 if jn.end == 0 else pair.target.length
                near = abs(smp.s[j] - end_s) <= extra[i][jn.end] + f.radius
                if not near:
                    # farther along (a child leaving its parent at a slant), the patch
                    # still may not lay the child's pixels over its parent's interior
                    inside = _inside_parent(index, attached, jn, f.origin, f.valid.shape[1], inside_cache)
                    if inside.any():
                        keep = inside if keep is None else keep | inside
                    continue
                pin_core = False
                step = f.radius if jn.end == 0 else -f.radius
                into = pair.target.point_at(min(max(end_s + step, 0.0), pair.target.length)) \
                    - jn.point
                nrm = np.hypot(*into)
                if nrm > 1e-9:
                    fs = far_side(jn, attached[jn.parent].target, into / nrm, f.origin,
                                  f.valid.shape[1], window=window)
                    fs = fs | _inside_parent(index, attached, jn, f.origin, f.valid.shape[1], inside_cache)
                    keep = fs if keep is None else keep | fs
            valid = f.valid[k]
            whole = None
            if i in across:
                check = across[i]
                args = (f.origin, valid.shape[0], _patch_map(f, k), f.source_points[k],
                        float(f.source_angles[k]), float(f.source_s[k]))
                if check.t_map is not None:
                    # (without the target-side check: a pass crossing another turn of its own
                    # stroke is not folded over it, see crossings.py)
                    whole = valid & check(*args)
                valid = valid & check(*args, float(smp.s[j]))
            rows, cols = f.source_pixels(k, index.shape)
            behind = None
            if i in index.views:
                behind = np.zeros(valid.shape, bool)
                behind[f.valid[k]] = index.views[i][3][rows, cols]
                behind &= valid
                behind = behind if behind.any() else None
            placed.append(PlacedPatch(f.pixels[k], valid, f.origin, pin_core, keep,
                                      _patch_map(f, k), grow=not pin_core, stroke=i, behind=behind))
            laid.append((i, float(smp.s[j]), whole))
            source_region[rows, cols] = True
        samples[i] = StrokeSamples(
            target=smp.points, source=np.array([fetched[j].source_points[k]
                                                for j, k in enumerate(res.choice)]),
            source_s=np.array([fetched[j].source_s[k] for j, k in enumerate(res.choice)]),
            shift=np.array([offs[j][k] for j, k in enumerate(res.choice)]),
            radius=radii, pinned=smp.pinned, energy=res.energy, pairwise=res.pairwise)

    # Joints (closed after composition): junctions and the attachments of carried parts.
    joints = [(jn.point, 1.5 * float(index.half_width(jn.parent, attached[jn.parent].source_arc_length(
        jn.parent_s))) + 4.0, _pocket(index, jn) if _turned(attached, jn, window) else None, jn)
              for jn in junctions]
    # The parts nobody stroked, each carried rigidly by its stroke (after all strokes).
    # (turned apart about their attachments where the parent's bend makes them collide)
    notches, ends = [], _stroke_ends(index, attached)
    for (i, pi, s_t), fwd in zip(patches._carried, _fanned_maps(index, attached, patches._carried, window)):
        part, pair = index.parts[pi], attached[i]
        got = place_part(part, index.premult, fwd, target_shape)
        if got is None:
            continue
        pix, valid, _, origin, inverse = got
        keep = None
        if part.contact and not part.at_end and not part.body:
            # not over the far side of the parent's centre line (a body the stroke grows out of lies
            # on both sides of it)
            p, n = pair.target.point_at(s_t), pair.target.normal_at(s_t, window=window)
            yy, xx = np.mgrid[0:valid.shape[0], 0:valid.shape[1]]
            keep = ((xx + origin[0] - p[0]) * n[0] + (yy + origin[1] - p[1]) * n[1]) * part.side < -0.5
            # (over the parent only, near the attachment: a part reaching far round its parent
            # -- a flower's head and petals on the stem's end -- crosses the line of the
            # parent's centre line far beyond the parent, and a petal's tip there was cut
            # straight where a new leaf's transparent patch margin lay)
            reach = 2.0 * float(index.half_width(part.stroke, part.s)) + 2.0
            keep &= np.hypot(xx + origin[0] - p[0], yy + origin[1] - p[1]) <= reach
        placed.append(PlacedPatch(pix, valid, origin, True, keep, inverse, grow=True))
        laid.append(None)
        notch = _part_notches(pix, valid, keep, _notch_radius(part, ends))
        if part.body:
            # a body stays in place: where the moved stroke's patches left its own pixels transparent
            # (their margins won the seam across the slot the stroke's tube left in it) it shows itself
            own = valid & (pix[..., 3] > 0.5)
            notch = own if notch is None else notch | own
        notches.append((len(placed) - 1, notch))
        source_region[part.box] |= part.mask
        if part.contact:
            joints.append((pair.target.point_at(s_t),
                           1.5 * float(index.half_width(part.stroke, part.s)) + 4.0, None, None))
    comp = compose(placed, target_shape, method=params.composition, power=params.seam_power,
                   gradient_weighted=params.gradient_weighted)
    _refill_notches(comp, placed, notches)
    # For an opaque source the alpha is 1 on every copied pixel (less on the
    # anti-aliased edges of cut ends), 0 elsewhere: the object region is the
    # union of the patches.
    premult = comp.image
    alpha = premult[:, :, 3].copy()
    layer = np.zeros_like(premult)
    nz = alpha > 1e-6
    layer[nz, :3] = np.clip(premult[nz, :3] / alpha[nz, None], 0.0, 1.0)
    layer[:, :, 3] = alpha
    if index.has_alpha:
        layer = _close_rim_cracks(layer)
        style = patches._style if params.close_cuts else None
        wide = [j for j in joints if j[2] is not None]
        filled = None
        pockets = _SourcePockets(index, comp.labels, placed)
        # the parent's body at every junction stays with the parent (the notch a turned
        # child would tear out of it is filled from the parent's own source pixels)
        disks = joint_disks(index, attached, junctions, window)
        held_depth = np.zeros(layer.shape[:2], np.float32)
        layer, held = hold_joint_bodies(layer, index.premult, index.depth, disks, held_depth)
        # and every child's root tube stays with the child (no wedge left open between
        # a turned child's cut face and its parent's side)
        layer, held_roots = hold_joint_bodies(layer, index.premult, index.depth,
                                              joint_roots(index, attached, junctions, window), held_depth)
        held |= held_roots
        if wide:
            # wide joints first, their pockets filled with the parts' inner colours (not
            # the outline's); the new silhouette is then outlined like a cut face
            before = layer[:, :, 3] > 0.5
            old = layer
            layer = fill_joints(layer, [j[0] for j in wide], [j[1] for j in wide],
                                pockets=[j[2] for j in wide], keep_open=pockets,
                                inner=0 if style is None else int(np.ceil(style.width)) + 1)
            if layer is not old:
                # only the wedges along the children (no bridge to a neighbouring part)
                changed = layer[:, :, 3] != old[:, :, 3]
                away = changed & ~_along_children(wide, attached, old.shape[:2], changed, index)
                layer[away] = old[away]
            filled = (layer[:, :, 3] > 0.5) & ~before
        # crotches nobody drew (a new branch, a turned limb) rounded like the source's own
        tol = patches._auto.get("junction_tolerance", params.junction_tolerance)
        fresh, fillet = new_crotches(index, attached, junctions, tol)
        if fresh and fillet is not None and fillet > _POCKET:
            before = layer[:, :, 3] > 0.5
            layer = round_crotches(layer, fresh, attached, [j for j in joints if j[3] in fresh], fillet,
                                   inner=0 if style is None else int(np.ceil(style.width)) + 1,
                                   half_widths=[_child_width(index, jn.child) for jn in fresh])
            rounded = (layer[:, :, 3] > 0.5) & ~before
            filled = rounded if filled is None else filled | rounded
        if style is not None:
            depth = source_depth(comp.labels, [pp.source_map for pp in placed], index.depth)
            for k, view in index.views.items():
                # (a stroke whose hidden stretch was filled in: its own depth there)
                mine = np.array([pp.stroke == k for pp in placed] + [False])
                if mine.any():
                    depth = np.where(mine[comp.labels], source_depth(
                        comp.labels, [pp.source_map if pp.stroke == k else None for pp in placed], view[1]),
                        depth)
            depth = np.where(held, held_depth, depth)
            if filled is not None and filled.any():
                depth = np.where(filled, np.float32(_FILLED_DEPTH), depth)
            uncut = layer
            over = _overlap_rims(index, attached, junctions, placed, comp.labels, depth, style, layer)
            layer = close_cuts(layer, depth, style)
            inked = np.any(layer != uncut, axis=2) if layer is not uncut else None
            layer = clear_stale_outline(layer, depth, style, filled=filled)
        opened = layer[:, :, 3] <= 0.5
        if joints:
            layer = fill_joints(layer, [j[0] for j in joints], [j[1] for j in joints],
                                pockets=[_thin_closing(index, j[3]) for j in joints], keep_open=pockets)
        # (the source's own slits carried by the patches -- a turned petal's notch -- stay open)
        # (the whole of them for the slit pass: a notch whose mouth a rim-crack closing
        # shut stays a notch; its pieces under a pinhole's size are filled at the end)
        carried_all = _carried_slits(index, comp.labels, placed, layer[:, :, 3])
        layer = close_hairlines(layer, [(d[0], 1.5 * d[2] + 4.0) for d in disks],
                                keep_open=_open_stretches(carried_all, layer[:, :, 3]))
        if style is not None and (disks or joints):
            # rims the last closings buried inside the object (a kept arm's outline
            # running into a turned arm's root): interior ink, repainted
            # and cut faces outlined before those closings joined them to a neighbour
            # (also with no junction: a slit between two limbs' patches closed at a carried
            # part's joint, an octopus's head between its tentacles, was a dark column)
            late = opened & (layer[:, :, 3] > 0.5)
            if inked is not None:
                late |= inked
            layer = clear_stale_outline(layer, depth, style,
                                        filled=late if filled is None else late | filled)
        layer = _refill_vacated_roots(layer, index, attached, window, 1.0 if style is None else style.width)
        unplugged = layer
        layer = fill_pinholes(layer, 1.0 if style is None else style.width,
                              slits=True, outlined=style is not None,
                              zones=_joint_zones(layer.shape[:2], disks, 1.0 if style is None else style.width),
                              depth=None if style is not None else source_depth(
                                  comp.labels, [pp.source_map for pp in placed], index.depth),
                              source_alpha=index.premult[:, :, 3], carried=carried_all)
        if style is not None and layer is not unplugged:
            # a crack plugged with its nearest opaque colour -- the ink lining it -- and that
            # lining, now inside: a dark blob at a crotch where two limbs' patches met
            # (an octopus's straightened tentacle beside its neighbour), repainted as stale
            plugged = layer[:, :, 3] != unplugged[:, :, 3]
            if not (disks or joints):
                plugged |= opened & (layer[:, :, 3] > 0.5)
            layer = clear_stale_outline(layer, depth, style, filled=plugged)
        if style is not None and over is not None:
            # a part lying over another keeps its outline there (no joint)
            keep = over & (layer[:, :, 3] > 0.5)
            if keep.any():
                layer = layer.copy()
                layer[keep, :3] = uncut[keep, :3]
        # a part moved over another part is drawn over it, with its own outline
        layer = _overlaid_parts(layer, placed, junctions, index, attached,
                               0.0 if style is None else style.width)
        # a stroke crossing itself (or another stroke) on its way passes over it, outline and all
        layer = crossed_over(layer, placed, laid, comp.labels, attached, index, junctions,
                             _still(patches.pairs), 0.0 if style is None else style.width,
                             method=params.composition, power=params.seam_power,
                             gradient_weighted=params.gradient_weighted)
        # (the joints' closings leave cracks of their own)
        layer = _close_rim_cracks(layer)
        layer = drop_flecks(layer, index.premult[:, :, 3])
        layer = drop_flecks(layer, index.premult[:, :, 3], level=0.5)
        # (last: the closings above leave half-transparent pixels of their own)
        layer = _solid_cracks(layer, index.premult[:, :, 3])
        # (a carried slit's stretch those closings shut off is a pinhole: filled)
        layer = _fill_closed_off(layer, carried_all, 1.0 if style is None else style.width)
        alpha = layer[:, :, 3]
    mask = alpha > 0.5
    seams = seam_mask(comp.labels, alpha, min_alpha=0.1)
    energies = {
        "sampling": float(e_total),
        "sampling_pairwise": float(e_pair),
        "seam": labelling_cost(placed, comp.labels, power=params.seam_power,
                               gradient_weighted=params.gradient_weighted),
        "seam_steps": float(comp.step_costs.sum()),
    }
    background, bg_img = patches._background, patches._bg_img
    if background is None:
        out = layer.copy()
    elif bg_img is None:
        colour = np.asarray(background, np.float32)
        bg_rgba = np.broadcast_to(np.append(colour[:3], colour[3] if len(colour) == 4 else 1.0),
                                  (*target_shape, 4))
        out = _over(layer, bg_rgba)
    else:
        out = _over(layer, bg_img)
    return StrokeEditResult(
        image=np.clip(out, 0, 1).astype(np.float32), mask=mask, seams=seams, energies=energies,
        layer=layer, labels=comp.labels, samples=samples, pairs=attached, junctions=junctions,
        radius=patches.radius, source_region=source_region & index.object,
        params=dataclasses.replace(params), auto=dict(patches._auto))


#: A patch pixel lands at most this share of the patch radius (and 2 px) farther from or nearer
#: to its target stroke than its source pixel lies from the source stroke (see :class:`_AcrossCheck`).
_ACROSS_TOL = 0.06
#: ... judged only where its source stroke's nearest point lies more than this share of the
#: patch radius farther along (or back) than the pixel's own offset along the patch.
_BEND_TOL = 0.25
#: Turn (rad) within one patch radius past which a target stroke is a curl (see _AcrossCheck).
_CURL_TURN = 0.75


def _still(pairs) -> set:
    """Indices of the pairs whose target stroke is their source stroke (left where it was)."""
    return {k for k, p in enumerate(pairs) if p.source.points.shape == p.target.points.shape
            and np.array_equal(p.source.points, p.target.points)}


def _rigid(pair, tol: float = 1.0) -> bool:
    """Whether ``pair``'s target is its source moved rigidly (or mirrored), within ``tol`` px:
    points at matching arc lengths fitted by one rotation (or reflection) and translation."""
    s_s = np.linspace(0.0, pair.source.length, 33)
    a = pair.source.point_at(s_s)
    b = pair.target.point_at(np.interp(s_s, pair.control[:, 0], pair.control[:, 1]))
    a, b = a - a.mean(axis=0), b - b.mean(axis=0)
    u, _, vt = np.linalg.svd(a.T @ b)
    for flip in (1.0, -1.0):
        d = np.diag([1.0, flip * np.sign(np.linalg.det(u @ vt)) or 1.0])
        rot = u @ d @ vt
        if np.sqrt(np.mean(np.sum((a @ rot - b) ** 2, axis=1))) <= tol:
            return True
    return False


class _AcrossCheck:
    """``(origin, size, map) -> (size, size) bool``: the patch pixels that land about as far
    from the target stroke as their source pixels lie from the source stroke.

    A patch copies a rigid square of the source. Where the target stroke is not the
    source moved rigidly (lengthened, bent), pixels far along the patch that belong to
    another leg of the source stroke (the upright of an L-shaped arm seen from a patch on
    its horizontal leg) land beside the target's leg instead of on it: a lengthened
    cactus arm got a staircase of stale uprights on its inner side, each patch's a little
    farther out. Such a pixel lands much farther from (or nearer to) the target stroke than
    its source lies from the source stroke; the along-stroke error of a stretch moves
    pixels along the tube and is kept. Pixels off the source stroke's own tube (beyond
    twice the patch radius) are not judged. Beyond the paper (its patches are rigid
    copies, its strokes short).

    The same holds across a bend of the target stroke (``t0``, the sample's target arc
    length, given): on a target that curls tighter than about the patch radius
    (:data:`_CURL_TURN`), a patch pixel whose nearest target point lies much farther
    along than its offset along the patch and that lands nearer to the target stroke
    than its source pixel lies from the source stroke is folded over another turn (an
    octopus's tentacle re-stroked into a spiral: the tips knotted, outline scraps inside
    the curl) and is dropped; the patches centred nearer along the stroke cover it.
    """

    def __init__(self, index, stroke: int, pair, radii, shape):
        self.tol = max(2.0, _ACROSS_TOL * float(np.median(radii)))
        self.bend = _BEND_TOL * float(np.median(radii))
        self.s_map = index.s_map[stroke]
        self.length = float(index.strokes[stroke].length)
        reach = 2.0 * float(np.max(radii)) + 2.0

        def dist(stroke, shp):
            # distance to the stroke's polyline on a box round it (+ reach), as a full-size map
            h, w = shp
            lo = np.floor(stroke.points.min(axis=0) - reach).astype(int)
            hi = np.ceil(stroke.points.max(axis=0) + reach).astype(int) + 1
            x0, y0 = max(lo[0], 0), max(lo[1], 0)
            x1, y1 = min(hi[0], w), min(hi[1], h)
            out = np.full((h, w), np.inf, np.float32)
            if x0 >= x1 or y0 >= y1:
                return out
            canvas = np.full((y1 - y0, x1 - x0), 255, np.uint8)
            # (8 sub-pixel bits: the polyline is drawn to 1/256 px)
            line = np.rint((stroke.points - (x0, y0)) * 256.0).astype(np.int32)
            cv2.polylines(canvas, [line.reshape(-1, 1, 2)], False, 0, 1, cv2.LINE_8, 8)
            d = cv2.distanceTransform(canvas, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
            d[d > reach] = np.inf
            out[y0:y1, x0:x1] = d
            return out

        self.src = dist(pair.source, index.shape)
        self.tgt = dist(pair.target, shape)
        self.target = pair.target
        # the target-side check only where the target turns by over 0.75 rad within one
        # patch radius (a curl tighter than about 1.3 r): elsewhere no patch reaches
        # across a turn, and the result (and the cost) is the check's without it
        r = float(np.median(radii))
        grid = np.arange(0.0, pair.target.length + 0.5, 1.0)
        turn = np.unwrap(pair.target.angle_at(grid, window=2.0))
        span = max(1, int(round(r)))
        self.t_map = None
        if len(grid) > span and np.abs(turn[span:] - turn[:-span]).max() > _CURL_TURN:
            self.t_map = _distance_map(pair.target, shape, reach)[1]

    def __call__(self, origin, size: int, m: np.ndarray, centre, angle: float, s0: float,
                 t0: float | None = None) -> np.ndarray:
        x0, y0 = int(origin[0]), int(origin[1])
        yy, xx = np.mgrid[y0:y0 + size, x0:x0 + size]
        fx = m[0, 0] * xx + m[0, 1] * yy + m[0, 2]
        fy = m[1, 0] * xx + m[1, 1] * yy + m[1, 2]
        hs, ws = self.src.shape
        sx = np.clip(np.rint(fx).astype(np.intp), 0, ws - 1)
        sy = np.clip(np.rint(fy).astype(np.intp), 0, hs - 1)
        # only pixels reached across a bend of the source stroke: their nearest stroke point
        # lies much farther along (or back) than their offset along the patch's own axis
        along = (fx - centre[0]) * np.cos(angle) + (fy - centre[1]) * np.sin(angle)
        # (not beyond the stroke's ends, where the nearest point is the end itself: a tip)
        sig = self.s_map[sy, sx]
        bent = (np.abs(sig - s0 - along) > self.bend) & (sig > 0.5) & (sig < self.length - 0.5)
        ds = self.src[sy, sx]
        ht, wt = self.tgt.shape
        dt = self.tgt[np.clip(yy, 0, ht - 1), np.clip(xx, 0, wt - 1)]
        judged = bent & np.isfinite(ds) & np.isfinite(dt)
        keep = ~judged | (np.abs(dt - ds) <= self.tol)
        if t0 is None or self.t_map is None:
            return keep
        # the same across a bend of the target stroke (a tentacle re-stroked into a curl
        # tighter than its half width): a pixel whose nearest target point lies much
        # farther along (or back) than its offset along the patch, and that lands nearer
        # to the target stroke than its source pixel lies from the source stroke, is the
        # patch folded over another turn of the curl (the texture knotted at the tips);
        # the patches centred nearer along the stroke cover it. Pixels landing farther
        # out (the outside of a sharp corner) are kept: no other patch reaches them.
        # Beyond the paper.
        q = self.target.point_at(float(t0))
        a = float(self.target.angle_at(float(t0), window=3.0))
        along_t = (xx - q[0]) * np.cos(a) + (yy - q[1]) * np.sin(a)
        sig_t = self.t_map[np.clip(yy, 0, ht - 1), np.clip(xx, 0, wt - 1)]
        length_t = float(self.target.length)
        bent_t = (np.abs(sig_t - t0 - along_t) > self.bend) & (sig_t > 0.5) & (sig_t < length_t - 0.5)
        folded = bent_t & np.isfinite(ds) & np.isfinite(dt) & (dt < ds - self.tol)
        return keep & ~folded


def _stroke_ends(index, attached) -> list[tuple[int, np.ndarray, float]]:
    """``(stroke, point, half width)`` of every source stroke's ends."""
    out = []
    for k, p in enumerate(attached):
        w = index.half_width(k, np.array([0.0, p.source.length]))
        out += [(k, p.source.points[0], float(w[0])), (k, p.source.points[-1], float(w[1]))]
    return out


def _notch_radius(part, ends) -> int:
    """Radius (px) of the closing that finds the notches strokes' roots cut into ``part``: the
    widest half width of a stroke end within its half width (+ 2 px) of the part, the stroke it
    hangs from aside (0: none)."""
    ys, xs = np.nonzero(part.mask)
    if not len(ys):
        return 0
    pts = np.c_[xs + part.box[1].start, ys + part.box[0].start].astype(float)
    lo, hi = pts.min(axis=0), pts.max(axis=0)
    best = 0.0
    for k, q, hw in ends:
        if k == part.stroke or hw <= best or (q < lo - hw - 2.0).any() or (q > hi + hw + 2.0).any():
            continue
        if float(np.min(np.hypot(*(pts - q).T))) <= hw + 2.0:
            best = hw
    return int(np.ceil(best)) + 1 if best > 0 else 0


def _part_notches(pix: np.ndarray, valid: np.ndarray, keep, radius: int) -> np.ndarray | None:
    """Pixels of a carried part's square that close a notch in it: within its closing by a
    disk of ``radius`` px, not its own, opaque in the source there (None if none)."""
    if radius < 1 or not valid.any():
        return None
    # (a closing by a disk as two distance transforms: linear in the pixels, not in the disk's area)
    pad = radius + 2
    m = cv2.copyMakeBorder(valid.astype(np.uint8), pad, pad, pad, pad, cv2.BORDER_CONSTANT, value=0)
    grown = (cv2.distanceTransform(1 - m, cv2.DIST_L2, cv2.DIST_MASK_PRECISE) <= radius).astype(np.uint8)
    closed = cv2.distanceTransform(grown, cv2.DIST_L2, cv2.DIST_MASK_PRECISE)[pad:-pad, pad:-pad] > radius
    notch = closed & ~valid & (pix[..., 3] > 0.5)
    if keep is not None:
        notch &= keep
    return notch if notch.any() else None


def _refill_notches(comp, placed: list, notches: list) -> None:
    """Lay a carried part's notch pixels (:func:`_part_notches`) where the composition left no
    opaque pixel, in place (``comp``'s image and labels).

    A part nobody stroked hangs round the roots of the strokes that leave it (an
    octopus's head round its tentacles): the strokes' tubes take those root pixels,
    so the part has a notch there. When a stroke turns its part away, nothing lays
    the root's place: a transparent sliver opened in the head, which the cut-face
    outline then drew as a dark wedge. The part's own source pixels there (the
    flesh the root sat in) close it. Beyond the paper.
    """
    for i, notch in notches:
        if notch is None:
            continue
        pp = placed[i]
        win = pp.window(comp.image.shape)
        if win is None:
            continue
        canvas, patch, _ = win
        sub = notch[patch]
        open_ = sub & (comp.image[canvas][..., 3] < 0.5)
        if not open_.any():
            continue
        comp.image[canvas][open_] = pp.pixels[patch][open_]
        comp.labels[canvas][open_] = i
        comp.covered[canvas] |= open_


def _overlap_rims(index, attached, junctions, placed, labels, depth, style, layer) -> np.ndarray | None:
    """Pixels of a part's rim (and the band just inside it) where another part only lies
    under it, not joined to it: None if there are none.

    A stroke whose two ends both touch other strokes hangs from one and merely touches
    the other: a copy of an arm laid across the arm's tip, a curled tentacle's tip on
    its neighbour. :func:`~branchnb.strokes.junctions.find_junctions` still makes the
    second contact a junction, and the rim of the part touched, now inside the object's
    silhouette, was repainted as the stale rim of a joint (the copy's outline across
    the arm lost). Here, within the two parts' half widths + the outline's width + 2 px
    of such a contact, the touched part's own rim pixels (source depth up to the
    outline's width + 1.5 px) are kept as they were laid. The stroke is taken to hang
    from the part at its first point (strokes drawn from their roots): the contact at
    its last point is the touch. Beyond the paper.
    """
    ends: dict = {}
    for jn in junctions:
        ends.setdefault(jn.child, set()).add((jn.end, jn.parent))
    touch = [jn for jn in junctions
             if len({e for e, _ in ends[jn.child]}) == 2
             and any(e != jn.end and p != jn.parent for e, p in ends[jn.child])
             and jn.end == 1]
    if not touch:
        return None
    stroke_of = np.array([pp.stroke if pp.stroke is not None else -1 for pp in placed] + [-1])
    rim = (depth > 0) & (depth <= style.width + 1.5) & (layer[:, :, 3] > 0.02)
    h, w = labels.shape
    out = np.zeros((h, w), bool)
    for jn in touch:
        hw = float(index.half_width(jn.parent, attached[jn.parent].source_arc_length(jn.parent_s)))
        r = hw + _child_width(index, jn.child) + style.width + 2.0
        x, y = jn.point
        r0, r1 = max(int(y - r), 0), min(int(y + r) + 2, h)
        c0, c1 = max(int(x - r), 0), min(int(x + r) + 2, w)
        if r0 >= r1 or c0 >= c1:
            continue
        yy, xx = np.ogrid[r0:r1, c0:c1]
        box = (slice(r0, r1), slice(c0, c1))
        out[box] |= (np.hypot(xx - x, yy - y) <= r) & rim[box] & (stroke_of[labels[box]] == jn.parent)
    return out if out.any() else None


#: Parents with at most this many segments are measured exactly in :func:`_inside_points`.
_FEW_SEGMENTS = 16

#: Source depth given to pixels filled at joints (deep enough to be outlined as a cut face).
_FILLED_DEPTH = 100.0


class _SourcePockets:
    """``(rows, cols, k) -> bool``: result pixels copied from a pocket of the source itself.

    A pocket is what the joints' closing (a disk of ``k`` px) would fill in the
    source: the bottom of a narrow crotch. Such a pixel, copied by a patch from
    that very place, is the source's own shape, not a gap the edit opened (an
    identity edit of a finger drawn from inside its palm closed the crotches beside
    it with a thick dark notch and steps up the finger's sides). A pixel no patch
    laid (between the patches, deep in a crotch) is mapped by the patch of its
    nearest laid pixel (within ``2 k + 3`` px; none: it stays closable). The
    source's closing is computed on the box of the pixels asked about, grown by
    ``2 k + 3`` px (all the pixels it depends on).
    """

    def __init__(self, index, labels: np.ndarray, placed: list):
        self.obj = index.premult[:, :, 3] > 0.5
        self.labels, self.placed = labels, placed

    def __call__(self, rows: np.ndarray, cols: np.ndarray, k: int) -> np.ndarray:
        out = np.zeros(len(rows), bool)
        lab = self.labels[rows, cols].copy()
        g = 2 * int(k) + 3
        loose = lab < 0
        if loose.any():
            # the patch of the nearest laid pixel (on the loose pixels' box grown by g)
            lr, lc = rows[loose], cols[loose]
            H, W = self.labels.shape
            r0, r1 = max(int(lr.min()) - g, 0), min(int(lr.max()) + g + 1, H)
            c0, c1 = max(int(lc.min()) - g, 0), min(int(lc.max()) + g + 1, W)
            sub = self.labels[r0:r1, c0:c1]
            if (sub >= 0).any():
                dist, (ir, ic) = ndi.distance_transform_edt(sub < 0, return_indices=True)
                near = dist[lr - r0, lc - c0] <= g
                lab[np.flatnonzero(loose)[near]] = sub[ir[lr - r0, lc - c0], ic[lr - r0, lc - c0]][near]
        sx = np.full(len(rows), -1, np.intp)
        sy = np.full(len(rows), -1, np.intp)
        for i in np.unique(lab[lab >= 0]):
            m = self.placed[i].source_map
            if m is None:
                continue
            sel = lab == i
            x, y = cols[sel], rows[sel]
            sx[sel] = np.rint(m[0, 0] * x + m[0, 1] * y + m[0, 2]).astype(np.intp)
            sy[sel] = np.rint(m[1, 0] * x + m[1, 1] * y + m[1, 2]).astype(np.intp)
        h, w = self.obj.shape
        ok = (sx >= 0) & (sx < w) & (sy >= 0) & (sy < h)
        if not ok.any():
            return out
        r0, r1 = max(int(sy[ok].min()) - g, 0), min(int(sy[ok].max()) + g + 1, h)
        c0, c1 = max(int(sx[ok].min()) - g, 0), min(int(sx[ok].max()) + g + 1, w)
        sub = self.obj[r0:r1, c0:c1]
        pocket = _disk_closing(sub, int(k)) & ~sub
        out[ok] = pocket[sy[ok] - r0, sx[ok] - c0]
        return out


def _inside_parent(index, attached, jn, origin, size: int, cache: dict | None = None) -> np.ndarray:
    """Pixels of a ``size`` x ``size`` patch at ``origin`` inside the parent's silhouette
    (1.5 px in from its edge, the silhouette's half width at the junction): they keep
    the parent's texture, a child turned far does not lay its cut face over its parent.

    Only where the parent has flesh: the source silhouette carried by the parent's
    frame at the junction (a child added between two limbs that start at one centre,
    a starfish's sixth arm, is not held back over the empty background within the
    parent's width; that left it floating off the body). ``cache`` (a dict, one per
    edit) keeps the parent's geometry per junction: every patch near a junction
    asks the same question.
    """
    key = id(jn)
    got = None if cache is None else cache.get(key)
    if got is None:
        parent = attached[jn.parent]
        s_src = float(parent.source_arc_length(jn.parent_s))
        hw = float(index.edge_width(jn.parent, np.array([s_src]))[0])
        # where the child leaves along the parent's normal, the width across is the child's
        hw = min(hw, index.side_width.get((jn.child, jn.end, jn.parent), np.inf) + 1.0)
        # the parent's target stroke, densely sampled (0.25 px: distances exact to 0.01 px)
        st = parent.target
        pts = st.points if st.length < 1e-9 else \
            np.stack([np.interp(np.linspace(0.0, st.length, int(np.ceil(st.length / 0.25)) + 1), st.s,
                                st.points[:, c]) for c in (0, 1)], axis=1)
        fwd = rigid_frame(parent.source, parent.target, s_src, float(jn.parent_s), window=3.0)
        # a parent of a few segments (a starfish's disk, a figure's body): exact distances to
        # its segments, cheaper than the tree's nearest sample
        near = st.points if len(st.points) <= _FEW_SEGMENTS + 1 and st.length >= 1e-9 else cKDTree(pts)
        got = (near, hw, fwd, pts.min(axis=0), pts.max(axis=0))
        if cache is not None:
            cache[key] = got
    tree, hw, fwd, lo, hi = got[:5]
    reach = hw - 1.5
    if reach < 0 or (np.asarray(origin) + size < lo - reach).any() or (np.asarray(origin) > hi + reach).any():
        return np.zeros((size, size), bool)  # the patch's square is nowhere near the parent
    if cache is None:
        yy, xx = np.mgrid[0:size, 0:size]
        q = np.c_[xx.ravel() + origin[0], yy.ravel() + origin[1]].astype(float)
        return _inside_points(index, tree, reach, fwd, q).reshape(size, size)
    if len(got) == 5:
        # a map of the pixels that can be within reach of the parent, filled as patches ask
        # (they overlap: each pixel is computed once per junction, not once per patch)
        x0, y0 = (np.floor(lo - reach) - 1).astype(int)
        x1, y1 = (np.ceil(hi + reach) + 2).astype(int)
        got = cache[key] = (*got, (x0, y0), np.zeros((y1 - y0, x1 - x0), bool),
                            np.zeros((y1 - y0, x1 - x0), bool))
    (x0, y0), box, done = got[5], got[6], got[7]
    out = np.zeros((size, size), bool)
    ox, oy = int(origin[0]), int(origin[1])
    a0, a1 = max(oy, y0), min(oy + size, y0 + box.shape[0])
    b0, b1 = max(ox, x0), min(ox + size, x0 + box.shape[1])
    if a0 < a1 and b0 < b1:
        sub = (slice(a0 - y0, a1 - y0), slice(b0 - x0, b1 - x0))
        todo = ~done[sub]
        if todo.any():
            ty, tx = np.nonzero(todo)
            q = np.c_[tx + b0, ty + a0].astype(float)
            box[sub][ty, tx] = _inside_points(index, tree, reach, fwd, q)
            done[sub] = True
        out[a0 - oy:a1 - oy, b0 - ox:b1 - ox] = box[sub]
    return out


def _inside_points(index, tree, reach: float, fwd: np.ndarray, q: np.ndarray) -> np.ndarray:
    """:func:`_inside_parent` at the pixels ``q`` ((N, 2) ``(x, y)``); ``tree`` is a KD-tree
    of the parent's densely sampled stroke or its (few) vertices."""
    if isinstance(tree, np.ndarray):
        d = np.full(len(q), np.inf)
        for a, b in zip(tree[:-1], tree[1:]):
            ab = b - a
            n2 = float(ab @ ab)
            t = np.clip(((q - a) @ ab) / n2, 0.0, 1.0) if n2 > 0 else np.zeros(len(q))
            np.minimum(d, np.hypot(q[:, 0] - a[0] - t * ab[0], q[:, 1] - a[1] - t * ab[1]), out=d)
    else:
        d, _ = tree.query(q, distance_upper_bound=reach + 1e-9)
    inside = d <= reach
    if inside.any():
        src = (q[inside] - fwd[:, 2]) @ fwd[:, :2]  # the inverse rigid map, row-wise
        x, y = np.rint(src).astype(int).T
        hs, ws = index.shape
        ok = (x >= 0) & (x < ws) & (y >= 0) & (y < hs)
        flesh = np.zeros(len(x), bool)
        flesh[ok] = index.object[y[ok], x[ok]]
        inside[np.flatnonzero(inside)[~flesh]] = False
    return inside


def _along_children(wide, attached, shape, where: np.ndarray | None = None, index=None) -> np.ndarray:
    """Pixels within ``3 r`` (r: the joint's closing radius, half the child's half width,
    so 1.5 child widths) of a wide joint's child target stroke, near the joint (only
    among the pixels ``where``, if given: the others are False).

    With ``index``, only pixels whose source under the parent's frame at the junction
    was the object (within 2 px): the wedge a turned child leaves at its parent's side
    was flesh (the child's old root); the V between the child and a neighbour it was
    turned toward was not (a starfish's arm turned toward the next: the closing webbed
    the V, 215 px outside the silhouette at 1000 px).
    """
    h, w = shape
    out = np.zeros((h, w), bool)
    for point, reach, r, jn in wide:
        x, y = point
        m = int(np.ceil(2 * reach)) + 2 + int(np.ceil(r))
        r0, r1, c0, c1 = max(int(y) - m, 0), min(int(y) + m + 1, h), max(int(x) - m, 0), min(int(x) + m + 1, w)
        if r0 >= r1 or c0 >= c1:
            continue
        if where is None:
            yy, xx = np.mgrid[r0:r1, c0:c1]
        else:
            yy, xx = np.nonzero(where[r0:r1, c0:c1])
            yy, xx = yy + r0, xx + c0
        if not yy.size:
            continue
        q = np.c_[xx.ravel(), yy.ravel()].astype(float)
        _, d = attached[jn.child].target.project(q)
        ok = d <= 3.0 * r
        if index is not None and ok.any():
            parent = attached[jn.parent]
            fwd = rigid_frame(parent.source, parent.target, float(parent.source_arc_length(jn.parent_s)),
                              float(jn.parent_s), window=3.0)
            sx, sy = np.rint((q[ok] - fwd[:, 2]) @ fwd[:, :2]).astype(int).T
            ok[np.flatnonzero(ok)[~_near_object(index.object, sx, sy)]] = False
        out[yy, xx] |= ok.reshape(yy.shape)
    return out


def _near_object(obj: np.ndarray, x: np.ndarray, y: np.ndarray) -> np.ndarray:
    """Whether each pixel ``(x, y)`` lies within 2 px (city block) of ``obj`` (False off the image):
    ``binary_dilation(obj, iterations=2)`` read at those pixels only."""
    h, w = obj.shape
    out = np.zeros(len(x), bool)
    for dy in range(-2, 3):
        for dx in range(-2 + abs(dy), 3 - abs(dy)):
            xx, yy = x + dx, y + dy
            on = (xx >= 0) & (xx < w) & (yy >= 0) & (yy < h) & ~out
            out[on] = obj[yy[on], xx[on]]
    return out & (x >= 0) & (x < w) & (y >= 0) & (y < h)


#: Turn (radians) of a child at its joint, relative to its parent, below which the
#: joint keeps the usual small closing (see :func:`_turned`).
_POCKET_TURN = np.radians(5.0)


def _turned(attached, jn, window: float) -> bool:
    """Whether junction ``jn``'s child leaves its parent at another angle than in the source.

    The wide closing of :func:`_pocket` fills the wedge a turned child's cut face
    leaves at its parent's side. A child that only changes length (or bends further
    out) leaves no wedge, and the closing instead webbed the crotches beside its
    root: a finger lengthened 1.4x got a 2-3 px outward jog of its outline just
    above both crotches (1000 px; beyond the paper). The turn is the change of the
    child's direction at its joined end less the parent's own turn at the joint.
    """
    child, parent = attached[jn.child], attached[jn.parent]
    s_t = 0.0 if jn.end == 0 else child.target.length
    s_s = 0.0 if jn.end == 0 else child.source.length
    w = min(window, 0.5 * child.target.length, 0.5 * child.source.length)
    turn = float(child.target.angle_at(s_t, window=w)) - float(child.source.angle_at(s_s, window=w))
    ps = float(jn.parent_s)
    turn -= float(parent.target.angle_at(ps, window=window)) - float(
        parent.source.angle_at(float(parent.source_arc_length(ps)), window=window))
    return abs(float(np.angle(np.exp(1j * turn)))) >= _POCKET_TURN


def _thin_closing(index, jn) -> float | None:
    """The closing at junction ``jn`` (None: the usual :data:`_POCKET`, 2 px): 1 px
    where the child's typical half width is under twice that.

    A 2-px closing fills gaps up to ~4 px wide: a slit between two patches
    on a large object, but on a 150-px antler (tines 1-3 px in half width) the
    gap between a new tine and its neighbour, which merged into a blob.
    Beyond the paper (whose closing is not sized at all).
    """
    if jn is None or _child_width(index, jn.child) >= 2 * _POCKET:
        return None
    return 1.0


def _pocket(index, jn) -> float | None:
    """Radius of the closing at junction ``jn``: half the child's half width where
    it leaves its parent's silhouette (None: the usual small closing).

    A child turned far from its source direction (an arm raised by 50
    degrees) has its cut face turned with it, which leaves a wedge between
    the face and the parent's side; a 2-px closing fills only the wedge's
    tip, a closing of half the child's half width rounds the joint like a
    branch collar. (Beyond the paper, whose junctions keep the source angle.)
    """
    child, parent = index.strokes[jn.child], index.strokes[jn.parent]
    t = np.arange(0.0, child.length, 1.0)
    pts = child.point_at(t if jn.end == 0 else child.length - t)
    s_par, d = parent.project(pts)
    out = np.flatnonzero(d > index.edge_width(jn.parent, s_par) + 2.0)
    if not len(out):
        return None
    q = np.rint(pts[out[0]:out[0] + 6]).astype(int)
    h, w = index.shape
    q = q[(q[:, 0] >= 0) & (q[:, 0] < w) & (q[:, 1] >= 0) & (q[:, 1] < h)]
    if not len(q):
        return None
    r = float(index.depth[q[:, 1], q[:, 0]].min()) / 2.0
    return r if r > _POCKET else None


def _patch_map(f, k: int) -> np.ndarray:
    """Target ``(x, y)`` -> source ``(x, y)`` of candidate ``k`` of ``f`` (a rotation about the sample;
    for mirror-image patches a reflection)."""
    if getattr(f, "mirror", False):
        ph = float(f.source_angles[k]) + float(f.dst_angle)
        c, s = np.cos(ph), np.sin(ph)
        (cx, cy), (dx, dy) = f.source_points[k], f.dst_point
        return np.array([[c, s, cx - c * dx - s * dy], [s, -c, cy - s * dx + c * dy]])
    th = float(f.source_angles[k]) - float(f.dst_angle)
    c, s = np.cos(th), np.sin(th)
    (cx, cy), (dx, dy) = f.source_points[k], f.dst_point
    return np.array([[c, -s, cx - c * dx + s * dy], [s, c, cy - s * dx - c * dy]])


def _over(layer: np.ndarray, bg: np.ndarray) -> np.ndarray:
    """Straight-alpha RGBA ``layer`` over straight-alpha RGBA ``bg``."""
    a = layer[:, :, 3:4]
    b = bg[:, :, 3:4]
    out_a = a + b * (1 - a)
    rgb = layer[:, :, :3] * a + bg[:, :, :3] * b * (1 - a)
    rgb = np.where(out_a > 1e-6, rgb / np.maximum(out_a, 1e-6), 0.0)
    return np.dstack([rgb, out_a]).astype(np.float32)
