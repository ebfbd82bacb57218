"""Stage 2 of the edit: global texture sampling and composition (:func:`compose_patches`).

Steps 4 and 5 of :func:`~branchnb.strokes.edit.edit_structure`: the
correspondences chosen by dynamic programming, the patches stitched by
graph cut, the unstroked parts carried after all strokes, the joints
closed and the cut faces outlined. Which pixels a patch may lay is
:mod:`~branchnb.strokes.patch_checks`'s; the joints' masks and closings are
:mod:`~branchnb.strokes.joint_closing`'s.
"""

from __future__ import annotations

import dataclasses

import numpy as np

from .composition import PlacedPatch, compose, labelling_cost, seam_mask
from .crossings import crossed_over
from .crotches import _child_width, new_crotches, round_crotches
from .edit import FETCH_FIELDS, EditPatches, StrokeEditParams, StrokeEditResult, StrokeSamples, _check_edit_params
from .fanning import _fanned_maps
from .joint_closing import (
    _along_children,
    _notch_radius,
    _overlap_rims,
    _part_notches,
    _pocket,
    _refill_notches,
    _SourcePockets,
    _stroke_ends,
    _thin_closing,
    _turned,
)
from .joints import _refill_vacated_roots, close_hairlines, hold_joint_bodies, joint_disks, joint_roots
from .junctions import far_side
from .outline import (
    _POCKET,
    _close_rim_cracks,
    clear_stale_outline,
    close_cuts,
    drop_flecks,
    fill_joints,
    fill_pinholes,
    source_depth,
)
from .overlays import _overlaid_parts, _solid_cracks
from .parts import place_part
from .patch_checks import _AcrossCheck, _inside_parent, _patch_map
from .sampling import choose, pair_energies
from .slits import _carried_slits, _fill_closed_off, _joint_zones, _open_stretches

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


#: Source depth given to pixels filled at joints (deep enough to be outlined as a cut face).
_FILLED_DEPTH = 100.0


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


def _over(layer: np.ndarray, bg: np.ndarray) -> np.ndarray:
    """Straight-alpha RGBA ``layer`` over straight-alpha RGBA ``bg``."""
    a = layer[:, :, 3:4]
    b = bg[:, :, 3:4]
    out_a = a + b * (1 - a)
    rgb = layer[:, :, :3] * a + bg[:, :, :3] * b * (1 - a)
    rgb = np.where(out_a > 1e-6, rgb / np.maximum(out_a, 1e-6), 0.0)
    return np.dstack([rgb, out_a]).astype(np.float32)
