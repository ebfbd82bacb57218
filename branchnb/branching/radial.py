"""Radial synthesis (beyond the paper, issue 23): several primaries leaving each hub, and the hub drawn.

Extraction finds hubs (:mod:`.hubs`: a neuron's soma, a coral's centre, a crater) and roots the traced
tree at each hub's centre, its spokes the root and branches starting at its first vertex. Learnt as it
is, that is one root whose children sit at its start, and the paper's synthesis grew one main branch
with side branches from each root. Here, only when the example carries hubs (``structure.hubs``, set
by :func:`~branchnb.branching.extract_structure`):

- :func:`_fit_hubs` reads, per example hub, its radius and the directions of its spokes (the branches
  starting within half its radius of its centre, each read where it leaves the hub);
- :func:`_hub_starts` turns every synthesized root start into a hub: as many primaries as one of the
  example's hubs has, starting on the hub's rim, their angular gaps those of that hub (turned by the
  root's heading), and records the hub on the result (``structure.hubs``);
- :func:`_hub_view` reads the example's per-branch statistics (generation, children per branch) as if
  every spoke were a root: the synthesized primaries stand for the example's spokes (see there);
- :func:`_fork_weights`: a primary (and its children) fork where the example's do along their length;
- :func:`_hub_budget`: a hub's forest stops at the example's length per hub, not at its coverage
  (see there);
- :mod:`.radial_bearing`: the primaries and their children run outward from their hub as the
  example's lines do (the bearing relative to the nearest hub, learnt like :mod:`.tropism`);
- :func:`_paste_hubs` copies the example's hub blob (a feathered disc of its radius, scaled like the
  hub) onto every synthesized hub of the image.

Structures without hubs take none of these paths (their output is unchanged).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Spokes start within this share of the hub's radius from its centre.
SPOKE_START = 0.5
#: ... and their direction is read where they leave this multiple of the radius.
SPOKE_READ = 1.2
#: The pasted hub is opaque out to this multiple of its radius, and fades out over the next
#: :data:`HUB_FEATHER` x radius (beyond it: the lines' stubs, which the synthesized primaries replace).
HUB_OPAQUE = 0.9
HUB_FEATHER = 0.3


@dataclass
class _HubModel:
    """Per example hub: centre ``(x, y)`` and radius (pixels of the example) and the spokes' angular gaps
    (radians, in counter-clockwise order from the first spoke, summing to ``2 pi``)."""

    centres: list[tuple[float, float]]
    radii: list[float]
    gaps: list[np.ndarray]

    @property
    def counts(self) -> list[int]:
        return [len(g) for g in self.gaps]


def _hubs_of(structure) -> list[tuple[float, float, float]]:
    """The ``(x, y, radius)`` hubs a structure carries (``[]`` when none)."""
    hubs = getattr(structure, "hubs", None)
    return [] if not hubs else [tuple(map(float, h)) for h in hubs]


def _spoke_angles(structure, x: float, y: float, r: float) -> np.ndarray:
    """Directions (radians, image coordinates) of the branches leaving the hub ``(x, y, r)``."""
    out = []
    for b in structure.branches:
        d = np.hypot(b.points[:, 0] - x, b.points[:, 1] - y)
        if d[0] > SPOKE_START * r:
            continue
        far = np.flatnonzero(d > SPOKE_READ * r)
        if far.size and np.all(d[:far[0]] <= SPOKE_READ * r):
            p = b.points[far[0]]
            out.append(float(np.arctan2(p[1] - y, p[0] - x)))
    return np.sort(np.mod(out, 2 * np.pi))


def _fit_hubs(structure) -> _HubModel | None:
    """The hub model of an example structure, None without hubs (or when no hub has 2+ spokes)."""
    centres, radii, gaps = [], [], []
    for x, y, r in _hubs_of(structure):
        a = _spoke_angles(structure, x, y, r)
        if len(a) < 2:
            continue
        centres.append((x, y))
        radii.append(r)
        gaps.append(np.diff(np.r_[a, a[0] + 2 * np.pi]))
    return _HubModel(centres, radii, gaps) if gaps else None


def _hub_model(model) -> _HubModel | None:
    """:func:`_fit_hubs` of a :class:`~branchnb.branching.model.StructureModel`'s source, kept on it."""
    got = model.__dict__.get("_hub_model")
    if got is None or got[0] is not model.source:
        got = model.__dict__["_hub_model"] = (model.source, _fit_hubs(model.source))
    return got[1]


def _spokes(structure) -> np.ndarray:
    """``(n_branches,)`` bool: the branches starting within :data:`SPOKE_START` hub radii of a hub's centre
    (a hub's root and its spokes)."""
    out = np.zeros(len(structure.branches), bool)
    for x, y, r in _hubs_of(structure):
        for i, b in enumerate(structure.branches):
            if len(b.points) and np.hypot(b.points[0, 0] - x, b.points[0, 1] - y) <= SPOKE_START * r:
                out[i] = True
    return out


def _hub_view(model, hubs) -> None:
    """Read ``model``'s per-branch statistics as if every spoke of the example's ``hubs`` were a root
    (in place; beyond the paper, issue 23).

    Extraction roots a hub's tree at its centre: one spoke is the root and the others its children at
    its first vertex, so the spokes counted as generation 1 and the root as a branch with all of them
    as children. Synthesis turns every root start into a hub whose primaries are roots, and a root
    drew its target length among the example's roots only (all of a 7-armed star's primaries took
    its one root's length, the longest arm's) and its children among branches whose counts held the
    spokes. The primaries then took 0.8 of the total length where the example's take 0.66, the
    coverage stop came before their children grew, and a drawn brittle star's arms barely forked.
    Here a spoke is generation 0, every other branch one below its parent, and a branch's children
    at a hub (the spokes) are not counted as its children.
    """
    ex = model.example
    ex.hubs = hubs   # the resampled example reads the source's hubs
    spoke = _spokes(ex)
    if not spoke.any():
        return
    n = len(ex.branches)
    gen = np.full(n, -1, np.int64)

    def g(i: int) -> int:
        if gen[i] < 0:
            par = ex.branches[i].parent
            gen[i] = 0 if spoke[i] or par is None else g(par) + 1
        return int(gen[i])

    for i in range(n):
        g(i)
    model.branch_generation = gen
    # where along their parent (0: its start, 1: its end) the children of each generation's branches sit
    pos: dict[int, list[float]] = {}
    for i, b in enumerate(ex.branches):
        if b.parent is not None and not spoke[i] and len(ex.branches[b.parent].points) > 1:
            pos.setdefault(int(gen[b.parent]), []).append(b.parent_vertex / (len(ex.branches[b.parent].points) - 1))
    model.__dict__["_fork_positions"] = {k: np.asarray(v) for k, v in pos.items()}
    fm = model.furcation
    fm.branch_generations = gen.copy()
    counts = np.array(fm.children_per_branch, np.int64)
    for i, b in enumerate(ex.branches):
        if spoke[i] and b.parent is not None:
            counts[b.parent] -= 1
    fm.children_per_branch = np.maximum(counts, 0)


#: Bandwidth of :func:`_fork_weights` (share of the parent's length) and the weight where the example
#: has no fork (so a branch of another shape still forks where nothing else is left).
FORK_BANDWIDTH = 0.08
FORK_FLOOR = 0.02


def _fork_weights(model, generation: int, n: int) -> np.ndarray | None:
    """``(n,)`` weights on a branch's ``n`` vertices: where the example's branches of ``generation``
    (read as :func:`_hub_view`) carry their children, by the share of their length (a Gaussian kernel
    of :data:`FORK_BANDWIDTH`, at most 1, at least :data:`FORK_FLOOR`); None without a hub view or such
    children (beyond the paper, issue 23).

    The furcation SVM sees a vertex's neighbourhood and its distances to the neighbouring furcations,
    not where it lies along the branch. On a coral's arms forking at their outer ends it read flat
    (0.04-0.05 all along), and the greedy picks put a synthesized primary's children at 0.02-0.58 of its
    length, the example's at 0.57-0.92: short side branches beside the hub instead of tufts out in
    the arms.
    """
    pos = model.__dict__.get("_fork_positions")
    if not pos or n < 2:
        return None
    g = min(int(generation), max(pos))
    while g not in pos and g > 0:
        g -= 1
    if g not in pos:
        return None
    t = np.linspace(0.0, 1.0, n)
    w = np.exp(-0.5 * ((t[:, None] - pos[g][None, :]) / FORK_BANDWIDTH) ** 2).sum(1)
    return np.maximum(w / max(float(w.max()), 1e-12), FORK_FLOOR)


#: Relative arc lengths at which :func:`_taper_profile` reads the example's children's radii.
TAPER_SAMPLES = np.linspace(0.0, 1.0, 11)


def _taper_profile(model, generation: int, r0: float, target: float):
    """``(s, r)``: the radius a hub's child of ``generation`` starting at ``r0`` and ``target`` px long
    has at arc length ``s`` (pixels): ``r0`` times the median over the example's branches of that
    generation (read as :func:`_hub_view`; the deepest one if deeper) of their radius at the same share
    of their length over their first radius; None without a hub view (beyond the paper, issue 23).

    The synthesized radii follow the copied pieces' relative changes
    (:func:`~branchnb.branching.scoring._continue_radii`) from the radius the child started at, and
    pieces copied from anywhere along the example's branches pass on no taper of their own: the
    children of a coral's or a brittle star's arms kept their start width to the end (end / start
    radius ~1.0 where the example's thin to ~0.5), blunt ends where the example's taper to a point.
    The child's radii are drawn back to this profile (``growth.CHILD_PROFILE_PULL``) as a root's are
    to its input root's (``_Starts._root_profile``).
    """
    got = model.__dict__.get("_taper_profiles")
    if got is None:
        got = {}
        gen = getattr(model.furcation, "branch_generations", None)
        ex = model.example
        if gen is not None and len(gen) == len(ex.branches):
            for g in np.unique(gen[gen > 0]):
                rows = []
                for i in np.flatnonzero(gen == g):
                    b = ex.branches[i]
                    r = np.broadcast_to(np.asarray(b.thickness, np.float64), (len(b.points),))
                    if len(r) < 3 or r[0] <= 0:
                        continue
                    t = np.r_[0.0, np.cumsum(np.hypot(*np.diff(np.asarray(b.points, np.float64), axis=0).T))]
                    rows.append(np.interp(TAPER_SAMPLES * t[-1], t, r) / max(float(np.mean(r[:2])), 1e-9))
                if rows:
                    got[int(g)] = np.median(np.asarray(rows), axis=0)
        model.__dict__["_taper_profiles"] = got
    if not got or not np.isfinite(target) or target <= 0:
        return None
    g = min(int(generation), max(got))
    while g not in got and g > 1:
        g -= 1
    if g not in got:
        return None
    return TAPER_SAMPLES * float(target), r0 * np.minimum(got[g], 1.0)


def _generation_caps(model, n_primaries: int) -> dict[int, int]:
    """``{generation: most children}`` of a synthesis from ``n_primaries`` hub primaries: the example's
    branches of each generation below its spokes (read as :func:`_hub_view`) per spoke, times
    ``n_primaries``, rounded up; ``{}`` without a hub view (beyond the paper, issue 23).

    The length budget (:func:`_hub_budget`) is spent by whatever grows: where the synthesized
    branches came out shorter than the example's, the fill rounds furcated them again until the
    length was used, and a neuron's or coral's primaries carried 1.2-1.4 x the example's branch
    points (without the fill rounds 0.55-1.0 x). Capped, the fill rounds add children only up to
    the example's count, generation by generation.
    """
    gen = getattr(model.furcation, "branch_generations", None)
    if gen is None or model.__dict__.get("_fork_positions") is None:
        return {}
    gen = np.asarray(gen)
    n_sp = int((gen == 0).sum())
    if n_sp == 0:
        return {}
    top = int(gen.max(initial=0))
    return {g: int(np.ceil(float((gen == g).sum()) * n_primaries / n_sp - 1e-9)) for g in range(1, top + 2)}


#: A hub's primary is pulled toward the point this many hub radii out along its spoke (:func:`_spoke_goal`).
SPOKE_GOAL = 4.0
#: ... with candidates scored x ``exp(SPOKE_KAPPA (cos - 1))`` (``cos`` toward the goal; a hole's pull is 2).
SPOKE_KAPPA = 20.0


def _spoke_goal(hubs, x: float, y: float) -> np.ndarray | None:
    """The goal (``_BranchState.goal``, pulled toward as a branch grown into a hole is) of the primary
    starting at ``(x, y)`` on the rim of the nearest of ``hubs``: :data:`SPOKE_GOAL` radii out from the
    centre through the start; None off every rim (beyond the paper, issue 23).

    Started on the rim heading out, the primaries copy heads from anywhere in the example and turn
    as they do; nothing keeps neighbours apart before their lines are close, and two of them often
    ran side by side: the smallest gap between neighbouring primaries (over the even share) at 3
    radii was 0.17-0.39 where the example's spokes keep 0.63-0.81.
    """
    if not hubs:
        return None
    c = np.asarray([h[:2] for h in hubs], np.float64)
    r = np.asarray([h[2] for h in hubs], np.float64)
    d = np.hypot(c[:, 0] - x, c[:, 1] - y)
    j = int(np.argmin(d / np.maximum(r, 1e-9)))
    if d[j] > 1.5 * r[j] or d[j] <= 1e-9:
        return None
    return c[j] + (np.array([x, y]) - c[j]) * (SPOKE_GOAL * r[j] / d[j])


class _HubStarts(list):
    """The root starts :func:`_hub_starts` made (hub primaries), with ``hubs`` and ``scale`` on them so
    the grower knows its roots are primaries (:func:`_hub_budget`)."""

    hubs: list = []
    scale: float = 1.0


def _hub_budget(model, n_hubs: int, scale: float, n_primaries: int | None = None) -> float:
    """The total length at which the synthesis of ``n_hubs`` hubs (scaled ``scale`` x the example's)
    stops: the example's length per hub, times ``n_hubs``, times ``scale`` (beyond the paper,
    issue 23).

    The paper stops at the example's coverage. A hub's children hug their primaries (a brittle star's
    forks, a neuron's dendrite tufts): the example's 7 coral primaries covered 0.17 of the frame and
    their 32 children only 0.07 more, while the synthesized primaries grow first (breadth first) and
    with their children's copied heads already covered 0.22 of the 0.24 target; the coverage stop
    then came before the children grew and 16 of 28 were dropped as unborn heads (a 7-armed brittle
    star's arms barely forked). Stopped at the example's length instead, the children get the
    length they have in the example, and colonization still keeps them apart. The budget is the example's
    length per hub times :data:`~branchnb.branching.stopping.LENGTH_FACTOR` (the children's copied heads
    are counted before they grow), and the fill rounds reopen no tip: the length the dropped heads held
    went to primaries grown on past their drawn length (a 256 px neuron mask's 100 px arms to 176 px).
    Figures (``python -m branchnb.branching._radial_synth_check 0,1,2 all``): branch points per primary,
    example / main -> now, neuron 1.4/0.0 -> 1.4, coral 4.6/0.1 -> 3.9, neuron_dark 3.4/0.0 -> 3.9.

    With ``n_primaries`` (branching75) the budget is the example's length per spoke times the primaries
    that started: hubs copy one of the example's at random, and a neuron's three somas of 4, 5 and 9
    spokes drew 9, 4 and 9 primaries, whose children then shared the length of 18 spokes among 22
    (branch points per primary 0.6 x the example's).
    """
    from .stopping import LENGTH_FACTOR, example_length

    hm = _hub_model(model)
    if n_primaries is not None and hm is not None and sum(hm.counts) > 0:
        return LENGTH_FACTOR * example_length(model) / sum(hm.counts) * n_primaries * scale
    n_ex = max(len(hm.radii) if hm is not None else 1, 1)
    return LENGTH_FACTOR * example_length(model) / n_ex * n_hubs * scale


def _hub_starts(hm: _HubModel, starts, scale: float, shape, rng, domain=None):
    """``(starts, hubs)``: every root start ``(x, y, angle)`` of ``starts`` replaced by the primaries of
    a hub centred there, and the hubs ``[(x, y, radius)]``.

    Each hub copies one of the example's (drawn by ``rng``): its number of spokes, their angular gaps
    (from a random first spoke, turned by the start's angle) and its radius (x ``scale``). The centre is
    moved inside the frame by 1.5 radii; primaries start on the hub's rim (of one point, they would cut
    each other off at once), on the domain when it is given.
    """
    h, w = shape
    new, hubs = [], []
    for x, y, th in starts:
        j = int(rng.integers(len(hm.gaps)))
        g = hm.gaps[j]
        R = hm.radii[j] * scale
        m = min(1.5 * R, 0.25 * min(h, w))
        cx, cy = float(np.clip(x, m, w - 1 - m)), float(np.clip(y, m, h - 1 - m))
        k = int(rng.integers(len(g)))
        ang = th + np.cumsum(np.r_[0.0, np.roll(g, -k)[:-1]])
        hubs.append((cx, cy, R))
        for a in ang:
            px, py = cx + R * np.cos(a), cy + R * np.sin(a)
            if domain is not None:
                iy, ix = int(np.clip(round(py), 0, h - 1)), int(np.clip(round(px), 0, w - 1))
                if not domain[iy, ix]:
                    continue
            new.append((float(px), float(py), float(np.mod(a + np.pi, 2 * np.pi) - np.pi)))
    return new, hubs


#: A primary is drawn from this share of its hub's radius (under the pasted disc), see :func:`_into_hubs`.
DRAW_FROM = 0.5


def _into_hubs(structure):
    """A copy of ``structure`` whose roots starting on a hub's rim (within 1.1 radii of its centre) start
    :data:`DRAW_FROM` radii from the centre instead (one vertex put before their first, their children's
    ``parent_vertex`` moved on by one); ``structure`` itself without hubs. For drawing only (beyond the
    paper, issue 23): a primary's start was a free line end on the rim, drawn with a fragment of the
    example's line ends, and its cap showed beside the pasted disc as a hook or stub with a light fleck;
    from inside the disc, the pasted hub covers it.
    """
    from ..core.structure import Branch, Structure

    hubs = _hubs_of(structure)
    if not hubs:
        return structure
    moved = {}
    for i, b in enumerate(structure.branches):
        if b.parent is not None or len(b.points) < 2:
            continue
        for x, y, r in hubs:
            d = float(np.hypot(b.points[0, 0] - x, b.points[0, 1] - y))
            if DRAW_FROM * r < d <= 1.1 * r:
                q = np.array([x, y]) + (b.points[0] - np.array([x, y])) * (DRAW_FROM * r / d)
                moved[i] = q
                break
    if not moved:
        return structure
    out = []
    for i, b in enumerate(structure.branches):
        if i in moved:
            out.append(Branch(np.vstack([moved[i], b.points]), np.r_[b.thickness[0], b.thickness], None, None))
        elif b.parent in moved:
            out.append(Branch(b.points, b.thickness, b.parent, b.parent_vertex + 1))
        else:
            out.append(Branch(b.points, b.thickness, b.parent, b.parent_vertex))
    t = Structure(out, image_shape=structure.image_shape)
    t.hubs = list(structure.hubs)
    return t


def _hub_discs(hubs, shape) -> np.ndarray:
    """``(H, W)`` bool: the discs of :data:`HUB_OPAQUE` + :data:`HUB_FEATHER` radii round ``hubs``."""
    yy, xx = np.ogrid[:shape[0], :shape[1]]
    out = np.zeros(shape, bool)
    for x, y, r in hubs:
        out |= (xx - x) ** 2 + (yy - y) ** 2 <= ((HUB_OPAQUE + HUB_FEATHER) * r) ** 2
    return out


def _off_hubs(lib, hubs, *, keep: float = 0.5):
    """``lib`` (a :class:`~.fragments.FragmentLibrary`) without the fragments whose disk reaches into the
    :func:`_hub_discs` of ``hubs`` (those pixels are never copied, see ``synthesize_image``).

    A fragment centred in or beside an example's hub copied almost nothing (its skeleton runs in the
    hub disc), so the gap completion laid ground across the primary there and the line-contrast
    restoration painted a flat bar over it: pale and dark bands across a coral's arms every
    ``lambda 2 s`` (issue 23, branching116; :mod:`._hub_image_check`, ten hub examples 256-768 px:
    share of the arms' length with a bar 0.08-0.20 -> 0.00-0.02, the example's own 0.005-0.026).
    With fewer than ``keep`` of the fragments left, the fragments whose centre is outside the disc
    by half a disk radius are kept instead (else ``lib``).
    """
    from dataclasses import replace

    if len(lib) == 0 or not hubs:
        return lib
    h = np.asarray([tuple(v)[:3] for v in hubs], float)
    d = np.hypot(lib.center[:, 0, None] - h[None, :, 0], lib.center[:, 1, None] - h[None, :, 1])
    clear = d - (HUB_OPAQUE + HUB_FEATHER) * h[None, :, 2]
    for reach in (1.0, 0.5):
        ok = np.all(clear > reach * lib.radius[:, None], axis=1)
        if ok.all():
            return lib
        if ok.mean() >= keep:
            return replace(lib, branch=lib.branch[ok], arc=lib.arc[ok], sign=lib.sign[ok], child=lib.child[ok],
                           center=lib.center[ok], radius=lib.radius[ok])
    return lib


def _paste_hubs(canvas: np.ndarray, example: np.ndarray, ex_hubs, hubs, flat: bool = False) -> np.ndarray:
    """``canvas`` with the example's hub blob (hub ``i % len(ex_hubs)``) pasted on every hub of ``hubs``,
    scaled to its radius and feathered (:data:`HUB_OPAQUE`, :data:`HUB_FEATHER`).

    In the feather a canvas pixel closer to the hub's colour than the blend is kept: the synthesized
    primaries leave the hub there, and blended with the example's ground between its own spokes they
    came out lighter at the joint (branching69: lightest contrast along a primary 0.54-0.71 of the
    line's, the example's 0.97-1.2). ``flat`` (a flat drawing or a binary mask): nearest pixels and
    no feather, so no new colour appears.
    """
    import cv2

    H, W = canvas.shape[:2]
    out = canvas.copy()
    for i, (x, y, R) in enumerate(hubs):
        ex_x, ex_y, ex_r = ex_hubs[i % len(ex_hubs)]
        f = R / max(ex_r, 1e-6)
        half = int(np.ceil((HUB_OPAQUE + HUB_FEATHER) * R)) + 1
        yy, xx = np.mgrid[-half:half + 1, -half:half + 1].astype(np.float32)
        ty, tx = np.round(y).astype(int) + yy.astype(int), np.round(x).astype(int) + xx.astype(int)
        ok = (ty >= 0) & (ty < H) & (tx >= 0) & (tx < W)
        # the example's pixel under each target pixel (sub-pixel: the hub's centre is a float)
        mx = (ex_x + (tx - x) / f).astype(np.float32)
        my = (ex_y + (ty - y) / f).astype(np.float32)
        patch = cv2.remap(example, mx, my, cv2.INTER_NEAREST if flat else cv2.INTER_LINEAR,
                          borderMode=cv2.BORDER_REFLECT)
        patch = patch.reshape(patch.shape[:2] + (-1,))
        d = np.hypot(tx - x, ty - y) / R
        if flat:
            alpha = (d <= 1.0).astype(np.float64)[..., None]
        else:
            alpha = np.clip((HUB_OPAQUE + HUB_FEATHER - d) / HUB_FEATHER, 0.0, 1.0)[..., None]
        o = out[ty[ok], tx[ok]].reshape(-1, out.shape[2] if out.ndim == 3 else 1)
        pk = patch[ok][:, :o.shape[1]]
        blend = (1 - alpha[ok]) * o + alpha[ok] * pk
        colour = np.median(pk[d[ok] < 0.6], axis=0) if np.any(d[ok] < 0.6) else None
        if colour is not None:
            keep = (alpha[ok][:, 0] < 1) & (np.linalg.norm(o - colour, axis=1) < np.linalg.norm(blend - colour, axis=1))
            blend[keep] = o[keep]
        out[ty[ok], tx[ok]] = blend.reshape(out[ty[ok], tx[ok]].shape).astype(out.dtype)
    return out
