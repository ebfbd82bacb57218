"""Filling the domain after growth (the paper's stop rule, then beyond it).

When every branch has stopped before the density covers the domain as
much as the example's, the free space is filled round after round: tips
that ended at their drawn length with room ahead grow on, branches with
room beside them furcate once more (:meth:`_Filling._room`). Beyond the
paper, holes the example does not have are filled last: branches are grown
into the largest hole left until holes are as rare as the example's
(:meth:`_Filling._fill_far`, :func:`_hole_map`), then branches beside the
holes still left furcate toward them (:meth:`_Filling._fill_holes`). A mixin of the grower
(:class:`.growth._Grower`); split from :mod:`.synthesis`.
"""

from __future__ import annotations

import numpy as np

from .domains import _frame

#: A hole is domain farther than this share of the domain's diameter from every branch (issue 23).
HOLE_DISTANCE = 0.05

#: Holes are filled (``_Filling._fill_far``) until their share is at most this x the example's.
FAR_TARGET = 1.2

#: Branches started into holes by ``_Filling._fill_far``, at most.
FAR_MAX_TRIES = 40

#: A child grown toward a hole's centre that stopped short but grew at least this x the hole distance
#: rules out only the goal's neighbourhood (``_Filling._fill_far``), not the whole hole.
PART_GROWN = 1.0

#: Largest ``(H - 1)^2 + (W - 1)^2`` for which :func:`_edt` takes OpenCV's exact distance transform:
#: below it every squared distance is recovered exactly from its float32 distance.
EDT_CV2_LIMIT = 2 ** 22
#: One-pen strands in a band (``_Grower.strands``) whose coverage ends below this share of the target
#: start another strand from the root model (:meth:`_Filling._more_strands`), at most :data:`MORE_STRANDS` times.
STRAND_SHARE = 0.7
MORE_STRANDS = 4


def _edt(mask: np.ndarray, float32: bool = False) -> np.ndarray:
    """``scipy.ndimage.distance_transform_edt(mask)`` of a 2-d mask, the same numbers, faster.

    OpenCV's precise L2 transform (Felzenszwalb's exact algorithm) returns float32 distances
    (not always the float32 nearest to them) of whole squared distances ``n``; ``n`` is recovered
    exactly (``rint(d^2)``, while below :data:`EDT_CV2_LIMIT`) and its float64 square root is
    scipy's value to the bit (``float32``: that cast to float32). A mask without a zero, or a frame
    too large, goes to scipy. The grow loop took two of these per fill round on a 1000 x 1000 grid
    (issue 23).

    Examples
    --------
    >>> m = np.ones((3, 5), bool); m[1, 2] = False
    >>> _edt(m)[1].tolist(), _edt(m, float32=True).dtype.name
    ([2.0, 1.0, 0.0, 1.0, 2.0], 'float32')
    """
    import cv2
    from scipy import ndimage as ndi

    m = np.asarray(mask, bool)
    h, w = m.shape
    if (h - 1) ** 2 + (w - 1) ** 2 >= EDT_CV2_LIMIT or m.all():
        d = ndi.distance_transform_edt(m)
        return d.astype(np.float32) if float32 else d
    d = cv2.distanceTransform(m.view(np.uint8), cv2.DIST_L2, cv2.DIST_MASK_PRECISE)
    d = np.sqrt(np.rint(np.square(d, dtype=np.float64)))
    return d.astype(np.float32) if float32 else d


#: Coverage may exceed its target by this factor while holes are filled.
FILL_COVERAGE = 1.25

#: Pull of a branch grown into a hole toward its centre: candidates score x exp(kappa (cos - 1)).
GOAL_KAPPA = 2.0
#: rounds of growing on after the never-grown heads are dropped (``_Filling._drop_unborn``)
UNBORN_ROUNDS = 3
#: stop reasons of a child's first Markov step that leave it a bare copied head (dropped in a tree the
#: bearing stop cut short, ``_Filling._drop_heads``)
_STILLBORN = ("density", "blocked")
#: Whether :meth:`_Filling._drop_heads` drops such stillborn heads in every tree (True) or only in a tree the
#: bearing stop cut short (False, the default for now; True belongs with :data:`.path_smoothing.KEEP_CORNERS`
#: and :data:`.branch_starts.LEAVE_FRAME` 0, see ``_drop_heads``).
STILLBORN_EVERYWHERE = False


def _hole_map(polylines, domain: np.ndarray, cell: float) -> tuple[float, np.ndarray, float]:
    """(share of ``domain`` in holes, distance to the nearest branch per grid cell, hole distance).

    Computed on a grid of ``cell`` pixels: the cells holding a branch vertex
    are the branches; a hole is a domain cell farther than
    :data:`HOLE_DISTANCE` x the domain's diameter from all of them.
    """
    dom = np.asarray(domain, bool)
    k = max(int(cell), 1)
    grid = dom[::k, ::k]
    gh, gw = grid.shape
    occ = np.zeros((gh, gw), bool)
    pl = [np.asarray(q, np.float64).reshape(-1, 2) for q in polylines]
    if pl:   # every vertex of every branch at once
        pts = np.concatenate(pl)
        c = np.clip(np.floor((pts[:, 0] + 0.5) / k).astype(np.int64), 0, gw - 1)
        r = np.clip(np.floor((pts[:, 1] + 0.5) / k).astype(np.int64), 0, gh - 1)
        occ[r, c] = True
    ys, xs = np.nonzero(dom)
    diam = float(np.hypot(np.ptp(xs), np.ptp(ys))) if len(ys) else 0.0
    gap = HOLE_DISTANCE * diam
    if not occ.any() or not grid.any():
        return 1.0, np.full((gh, gw), np.inf), gap
    dist = _edt(~occ) * k   # scipy's distance_transform_edt, the same numbers
    return float(np.mean(dist[grid] > gap)), dist, gap


class _Filling:
    """The domain-filling methods of :class:`.growth._Grower`."""

    def _update_room(self) -> None:
        """Distance (pixels) from every density cell to the nearest covered cell (D > level)."""
        dm = self.density
        empty = dm.domain & (dm.grid <= dm.level)
        if self.region is not self.domain and self.domain is not None:
            # room only where branches may grow: not in the ground the example keeps away from
            grow = self.__dict__.get("_grow_grid")
            if grow is None:
                import cv2

                gh, gw = dm.grid.shape
                grow = self._grow_grid = cv2.resize(self.domain.astype(np.uint8), (gw, gh),
                                                    interpolation=cv2.INTER_NEAREST) > 0
            empty &= grow
        # scipy's distance_transform_edt cast to float32, the same numbers (_edt)
        self._empty_dt = _edt(empty, float32=True) * dm.cell

    def _room(self, pts: np.ndarray) -> np.ndarray:
        """Free space beside each vertex, ``(N,)`` pixels (0 = none).

        A child starting at a vertex grows into the space beside its
        parent: the room on a side is the free radius of the uncovered
        region ``2 rho`` away along the normal (one example gap further),
        kept only while that point is still uncovered and the region there
        is at least ``rho / 2`` wide; the larger of the two sides counts.
        """
        if len(pts) < 3:
            return np.zeros(len(pts))
        # core.polyline.tangents(pts) without its input checks (once per furcation)
        t = np.empty_like(pts)
        t[1:-1] = pts[2:] - pts[:-2]
        t[0] = pts[1] - pts[0]
        t[-1] = pts[-1] - pts[-2]
        norm = np.hypot(t[:, 0], t[:, 1])
        norm[norm == 0] = 1.0
        return self._room_at(pts, t / norm[:, None])

    def _max_rooms(self) -> list[float]:
        """The largest :meth:`_room` of every branch (all branches' vertices in one pass)."""
        pl = [np.asarray(b.points, np.float64) for b in self.branches]
        n = np.array([len(q) for q in pl], np.int64)
        out = np.zeros(len(pl))
        use = n >= 3
        if not use.any():
            return out.tolist()
        P = np.concatenate([q for q, u in zip(pl, use) if u])
        lens = n[use]
        starts = np.r_[0, np.cumsum(lens)[:-1]]
        ends = starts + lens - 1
        # core.polyline.tangents of each branch: central differences, one-sided at its ends
        t = np.empty_like(P)
        t[1:-1] = P[2:] - P[:-2]
        t[starts] = P[starts + 1] - P[starts]
        t[ends] = P[ends] - P[ends - 1]
        norm = np.hypot(t[:, 0], t[:, 1])
        norm[norm == 0] = 1.0
        out[use] = np.maximum.reduceat(self._room_at(P, t / norm[:, None]), starts)
        return np.maximum(out, 0.0).tolist()

    def _room_at(self, pts: np.ndarray, tg: np.ndarray) -> np.ndarray:
        """:meth:`_room` of vertices ``pts`` with unit tangents ``tg``."""
        dm, dt = self.density, self._empty_dt
        nrm = np.c_[-tg[:, 1], tg[:, 0]]
        best = np.zeros(len(pts))
        gh, gw = dt.shape
        for side in (-1.0, 1.0):
            q = pts + side * 2.0 * self.rho * nrm
            c = np.floor((q[:, 0] + 0.5) / dm.cell).astype(np.int64)
            r = np.floor((q[:, 1] + 0.5) / dm.cell).astype(np.int64)
            ok = (c >= 0) & (c < gw) & (r >= 0) & (r < gh)
            room = np.zeros(len(pts))
            room[ok] = dt[r[ok], c[ok]]
            room[dm.sample(q) > dm.level] = 0.0
            best = np.maximum(best, room)
        best[best < 0.5 * self.rho] = 0.0
        return best

    def _reopen_tips(self) -> list[int]:
        """Branches that stopped at their drawn length with uncovered space ahead, reopened.

        Each gets a new length target: its length plus one more draw for its
        generation (still bounded by ``max_branch_factor``).
        """
        dm, dt = self.density, self._empty_dt
        out = []
        if self.radial:   # a hub's branches keep their drawn lengths (.radial._hub_budget)
            return out
        for bi, st in enumerate(self.branches):
            if st.stop != "branch length" or len(st.points) < 2:
                continue
            tip = np.asarray(st.points[-1])
            q = tip + 2.0 * self.rho * np.array([np.cos(st.theta), np.sin(st.theta)])
            c, r = int(np.floor((q[0] + 0.5) / dm.cell)), int(np.floor((q[1] + 0.5) / dm.cell))
            if not (0 <= r < dt.shape[0] and 0 <= c < dt.shape[1]) or dt[r, c] < 0.5 * self.rho:
                continue
            length = (len(st.points) - 1) * self.p.h
            if length >= self.max_branch_len:
                continue
            st.stop = ""
            st.target = length + self.model.sample_length(st.generation, float(st.radii[-1]), self.rng)
            out.append(bi)
        return out

    def _drain(self, queue: list[int]) -> None:
        """Grow the queued branches breadth first, queueing their children."""
        qi = 0
        while qi < len(queue):
            bi = queue[qi]
            qi += 1
            if self.global_stop():
                self._mark_unborn(queue[qi - 1:])
                self._finish_fan()
                return
            self.grow(bi)
            if self.global_stop():
                self._mark_unborn(queue[qi:])
                self._finish_fan()
                return
            queue.extend(self.furcate(bi))

    def _mark_unborn(self, queued: list[int]) -> None:
        """Flag queued children that never took a Markov step (see :meth:`_drop_unborn`)."""
        for bi in queued:
            st = self.branches[bi]
            if st.parent is not None and not st.stop and not st.src:
                st.unborn = True

    def _drop_unborn(self, resume: bool = True) -> None:
        """Drop children queued but never grown (beyond the paper, issue 23).

        Children are started (their first segment copied from an input head) when their parent
        furcates and grown later, breadth first; when the total length or the coverage target is
        reached first, the children still queued keep only their copied head, ``m`` elements: a
        row of short stubs along the last parents grown, a comb the example does not have (the
        unseen 300 x 450 crack mask: 4 of 6 short thick children of a seed were such heads). Leaf
        children that took no Markov step are removed (a child that later furcated is kept).

        ``resume``: the density map is rebuilt without them, the branches the stop cut short grow
        on and the fill rounds (``_Grower._fill_rounds``) run again, up to :data:`UNBORN_ROUNDS`
        times (the heads queued then dropped again), so the length and coverage the heads held go
        to grown branches: dropped alone, a thin crack mask's output lost up to 22 % of its length.
        """
        for _ in range(UNBORN_ROUNDS if resume else 1):
            if not self._drop_heads():
                return
            if self.density is not None:
                self._rebuild_density()
            if not resume or self.stop_reason not in ("density (coverage)", "total length"):
                return
            queue = [i for i, st in enumerate(self.branches) if not st.stop and st.src]
            self.stop_reason = ""
            if self.global_stop():
                return
            self._drain(queue)
            self._fill_rounds()
        if self._drop_heads() and self.density is not None:
            self._rebuild_density()

    def _drop_heads(self) -> bool:
        """Remove leaf children flagged ``unborn`` that took no step, and leaf children whose first step was
        refused (:data:`_STILLBORN`); True when any was removed.

        The second rule applies in trees whose root the bearing stop cut short (``bearing_cut``), in every
        tree with :data:`STILLBORN_EVERYWHERE`: with corners kept in the traced paths
        (:data:`.path_smoothing.KEEP_CORNERS`) such bare heads came in uncut trees too
        (tests/test_branching_unborn.py's crack, seeds 0-11: 2 inside the frame, 1 in seed 2 alone;
        length ratio 0.94-0.99 of the example's with them dropped)."""
        if len(self.branches) < 2:
            return False
        kids = np.zeros(len(self.branches), np.int64)
        for st in self.branches:
            if st.parent is not None:
                kids[st.parent] += 1
        # a tree whose root the bearing stop cut short (.frame_band.bearing_keep) furcates on less length:
        # children crowd, and heads whose first Markov step the density refused stay bare stubs
        # (test_branching_unborn's crack, seed 0: 3 such heads on a root cut at 70 of 160 vertices)
        cut = np.zeros(len(self.branches), bool)
        for i, st in enumerate(self.branches):   # a parent comes before its children
            cut[i] = STILLBORN_EVERYWHERE or (st.bearing_cut if st.parent is None else cut[st.parent])
        keep = np.array([not (not st.src and kids[i] == 0 and st.parent is not None
                              and (st.unborn or (cut[i] and st.stop in _STILLBORN)))
                         for i, st in enumerate(self.branches)])
        for i in np.flatnonzero(~keep):   # the histograms counted them when they were started
            self._uncount(self.branches[i])
        self._keep_branches(keep)
        return not keep.all()

    def _uncount(self, st) -> None:
        """Take a removed head's angles and radii out of the running histograms (global matching)."""
        hm, a, r = self.matcher, np.asarray(st.elem_a, np.float64), np.asarray(st.radii, np.float64)
        if a.size:
            hm.counts_a -= np.bincount(hm.bin_angles(a), minlength=hm.bins)
            self.bends.counts -= np.bincount(self.bends.bin_angles(a), minlength=self.bends.bins)
        if r.size:
            hm.counts_r -= np.bincount(hm.bin_radii(r), minlength=hm.bins)
            hm.n_nodes -= int(r.size)

    def _rebuild_density(self) -> None:
        """The density map of the branches kept (after some were removed)."""
        self.density._rebuild([st.points for st in self.branches])

    def _holes(self) -> tuple[float, np.ndarray, float]:
        # the ground outside the domain the example keeps away from counts (region): it is no hole to
        # fill, the example's share has it too
        dom = self.region if self.region is not None else np.ones(self.shape, bool)
        return _hole_map([st.points for st in self.branches], dom, self.density.cell)

    def _example_holes(self) -> float:
        """The example's hole share on the density grid (computed once per model and cell size)."""
        m = self.model
        cache = m.__dict__.setdefault("_example_holes", {})
        key = (id(m.example), len(m.example.branches), float(self.density.cell))
        if key not in cache:
            dom = m.region if m.region is not None else np.ones(_frame(m.source), bool)
            cache[key] = _hole_map([b.points for b in m.example.branches], dom, self.density.cell)[0]
        return cache[key]

    def _fill_holes(self) -> None:
        """Grow into holes the example does not have (beyond the paper).

        The coverage target counts the domain within ``rho`` of a branch, not
        where the rest lies: a forest can reach it with branches crowded in
        the middle and wide empty lobes along a coast. When the share of
        the domain farther than :data:`HOLE_DISTANCE` x its diameter from
        every branch exceeds :data:`FAR_TARGET` x the example's (after
        :meth:`_fill_far`, which fills holes with less length: run first,
        the retina at 512 px ended at 1.4 x its example's length per area
        instead of 1.24-1.29 x), branches beside the holes
        furcate once more toward them (one child each, grown without
        further furcations) and tips ending before a hole grow on, past the
        coverage target, until the share is that or no branch can
        reach a hole (at most ``fill_rounds`` rounds; coverage at most
        1.25 x the target). Only in a domain of the user's (a map's land, a
        mask's region; a free image frame has no coast to reach: there the
        roots read the frame as density instead, see ``_frame_factor``;
        filling its holes too pushed coverage to 1.1-1.3 x the target on
        the retina, lightning and crack samples), not with a
        ``max_coverage`` of the user's, guidance, or ``fill_rounds = 0``.
        """
        if self.guidance is not None or self.density is None or not self.branches or \
                self.region is None or self.region.all() or \
                self.p.fill_rounds == 0 or self.p.max_coverage > 0 or \
                self.stop_reason not in ("", "density (coverage)", "no branch can grow"):
            return
        share, dist, gap = self._holes()
        target = FAR_TARGET * self._example_holes() + 1e-3
        if share <= target:
            return
        saved, reason = self.coverage_target, self.stop_reason
        # past the target, within bounds: 25 % more coverage at most
        self.coverage_target, self.stop_reason = min(1.0, 1.25 * saved), ""
        dm = self.density
        for _ in range(self.p.fill_rounds):
            before = len(self.branches)
            self._update_room()
            # room counts only in and around the holes
            gd = dm.grid
            k = max(int(dm.cell), 1)
            # the hole grid (step k) and the density grid (step cell) differ: sample by position
            ry = np.minimum((np.arange(gd.shape[0]) * dm.cell / k).astype(np.int64), dist.shape[0] - 1)
            rx = np.minimum((np.arange(gd.shape[1]) * dm.cell / k).astype(np.int64), dist.shape[1] - 1)
            near = dist[np.ix_(ry, rx)] > 0.5 * gap
            self._empty_dt = np.where(near, self._empty_dt, 0.0).astype(np.float32)
            for bi in self._reopen_tips():
                self.grow(bi)
            rooms = self._max_rooms()
            for bi in np.argsort(rooms, kind="stable")[::-1]:
                if rooms[bi] <= 0 or self.stop_reason:
                    break
                for c in self.furcate(int(bi), extra=True):
                    self.grow(c)
                share, dist, gap = self._holes()
                if share <= target:
                    break
            self._empty_dt = None
            share, dist, gap = self._holes()
            if share <= target or len(self.branches) == before or self.stop_reason:
                break
        self.coverage_target = saved
        if not self.stop_reason or self.stop_reason == "density (coverage)":
            self.stop_reason = reason

    def _goal_factor(self, st, tip, pts: np.ndarray, n_arr: np.ndarray) -> np.ndarray:
        """Score factor of a branch grown into a hole: ``exp(GOAL_KAPPA (cos - 1))`` toward its goal.

        ``cos`` is the cosine between a candidate's chord and the direction
        to the hole's centre; the pull ends (and the branch grows on freely)
        once its tip is within ``rho`` of the centre.
        """
        d = np.asarray(st.goal, np.float64) - tip
        dist = float(np.hypot(*d))
        if dist < self.rho:
            st.goal = None
            return np.ones(len(n_arr))
        end = pts[np.arange(len(n_arr)), np.maximum(n_arr, 1) - 1] - tip
        cos = (end @ d) / np.maximum(np.hypot(end[:, 0], end[:, 1]) * dist, 1e-9)
        kappa = GOAL_KAPPA if st.goal_kappa is None else st.goal_kappa
        return np.where(n_arr > 0, np.exp(kappa * (cos - 1.0)), 1.0)

    def _grow_into(self, goal: np.ndarray) -> bool:
        """Start a child at the branch vertex nearest to ``goal`` heading there, and grow it (with its children).

        Vertices of branches at the maximum generation, and the first and
        last two of a branch, do not furcate; the four nearest other
        branches are tried in turn. True if a child started.
        """
        cand = []
        for bi, st in enumerate(self.branches):
            if st.generation >= self.p.max_generations or len(st.points) < 5:
                continue
            if self.strands and not self.quota_off and len(self._child_vertices(bi)) >= \
                    self.model.furcation._child_quota((len(st.points) - 1) * self.p.h, st.generation):
                continue   # a band's strand with as many children as its generation's (see growth furcate)
            pts = np.asarray(st.points[1:-2], np.float64)
            d = np.hypot(*(pts - goal).T)
            head = self._below_head(bi)   # a delta's trunk parts at its head only
            if head is not None:
                d = np.where(head[1:-2], d, np.inf)
                if not np.isfinite(d).any():
                    continue
            v = int(np.argmin(d))
            cand.append((float(d[v]), bi, v + 1))
        cand.sort()
        for dist, bi, v in cand[:4]:
            c = self.start_child(bi, v, toward=goal)
            if c is None:
                continue
            st = self.branches[c]
            st.goal = np.asarray(goal, np.float64)
            st.target = min(max(st.target, dist + 2.0 * self.rho), self.max_branch_len)
            if not st.stop:
                self._drain([c])
            return True
        return False

    def _fill_far(self) -> None:
        """Grow branches into the largest hole, one after another, until holes are as rare as the example's.

        Beyond the paper: the paper's stop rule (coverage within ``rho``)
        leaves, on some
        seeds, regions farther than :data:`HOLE_DISTANCE` x the domain's
        diameter from every branch covering 1.5-8 x the example's share
        (retina, drawn maps, deltas: branches crowd in one part while
        another stays empty). Here the centre of the largest hole (the
        domain cell farthest from every branch) is found, a child starts at
        the nearest branch vertex heading there (its head and length from
        the furcation and bending models) and is pulled toward the centre
        (:meth:`_goal_factor`) until it arrives, then grows and furcates
        freely; repeated until the hole share is at most :data:`FAR_TARGET`
        x the example's (at most :data:`FAR_MAX_TRIES` holes; coverage at
        most :data:`FILL_COVERAGE` x its target). Also in a free frame. Not
        with guidance, a ``max_coverage`` of the user's, or
        ``fill_rounds = 0``.
        """
        if self.guidance is not None or self.density is None or not self.branches or \
                self.p.fill_rounds == 0 or self.p.max_coverage > 0 or \
                self.stop_reason not in ("", "density (coverage)", "no branch can grow"):
            return
        share, dist, gap = self._holes()
        target = FAR_TARGET * self._example_holes() + 1e-3
        if share <= target:
            return
        dom = self.domain if self.domain is not None else np.ones(self.shape, bool)
        k = max(int(self.density.cell), 1)
        grid = dom[::k, ::k]
        tried = np.zeros(grid.shape, bool)
        yy, xx = np.mgrid[: grid.shape[0], : grid.shape[1]]
        saved, reason = self.coverage_target, self.stop_reason
        # targeted growth: up to (FILL_COVERAGE - 1) x the target more than now (_fill_holes may have used
        # its own margin already: retina seed 0 stopped at 1.6 x the example's hole share)
        self.coverage_target = min(1.0, max(FILL_COVERAGE * saved,
                                            self.density.coverage() + (FILL_COVERAGE - 1.0) * saved))
        self.stop_reason = ""
        for _ in range(FAR_MAX_TRIES):
            free = np.where(grid & ~tried & (dist > gap), dist, -1.0)
            r, c = np.unravel_index(int(np.argmax(free)), free.shape)
            if free[r, c] < 0:
                break
            goal = np.array([c * k, r * k], np.float64)
            length = self.total_length
            self._grow_into(goal)
            grown = self.total_length - length
            if grown < 0.5 * float(dist[r, c]):
                # nothing reached it: leave this hole. A child that grew part of the way (it left the
                # domain or met a branch on a corner goal) leaves only the goal's own neighbourhood:
                # the rest of the hole is tried from elsewhere (ruling out the whole hole after one
                # short child left 0.56 of a frame empty where the example leaves 0.11)
                reach = float(dist[r, c]) if grown < PART_GROWN * gap else 0.0
                tried |= np.hypot(yy - r, xx - c) * k <= max(reach, gap)
            if self.stop_reason:
                break
            share, dist, gap = self._holes()
            if share <= target:
                break
        self.coverage_target = saved
        if not self.stop_reason or self.stop_reason == "density (coverage)":
            self.stop_reason = reason

    def _more_strands(self, starts) -> None:
        """Start another strand while a band of one-pen strands covers less than :data:`STRAND_SHARE` of
        its target (beyond the paper, issue 23).

        A band's children follow the example's per generation and length (``FurcationModel._child_quota``),
        so the fill rounds no longer hide a root that left its band early under bushes of twigs: an
        interlaced L band whose root left after 100 px ended at 0.34 of the example's length. Another
        root (drawn from the root model like the first, ``starts(rng)``) grows a strand of its own.
        """
        if not getattr(self, "strands", False) or not callable(starts) or self.density is None or \
                not 0 < self.coverage_target < 1 or self.stop_reason not in ("", "no branch can grow"):
            return
        saved = self.stop_reason
        for _ in range(MORE_STRANDS):
            if self.density.coverage() >= STRAND_SHARE * self.coverage_target:
                break
            self.stop_reason = ""
            for x, y, th in starts(self.rng):
                c = self.start_root(x, y, th)
                if c is not None:
                    self._drain([c])
            if self.stop_reason:
                break
        if not self.stop_reason and self.density.coverage() < STRAND_SHARE * self.coverage_target:
            # no strand found room either: the fill rounds fill the band as the paper's do, past the quota
            # (an L band's roots left it within 100-150 px in 2 of 2 seeds; bushes, but the band's length)
            self.quota_off = True
            self._fill_rounds()
        if not self.stop_reason or self.stop_reason == "density (coverage)":
            self.stop_reason = saved

    def _prune_dry(self) -> None:
        """Drop a delta's channels that end inland (beyond the paper; :class:`.domains._Drain` only).

        A channel blocked by another (every candidate crosses it or is too
        dense) stops in the middle of the land, a dry stub the example does
        not have: its distributaries all run to the sea. Leaf branches (not
        roots) whose tip is farther than ``2 h`` from the region outside the
        domain are removed, again while removing one leaves its parent a
        dry leaf.
        """
        if self.drain is None or self.domain is None:
            return
        self._finish_fan()
        if len(self.branches) < 2:
            return
        from scipy import ndimage as ndi

        depth = ndi.distance_transform_edt(self.domain)
        h, w = self.shape
        keep = np.ones(len(self.branches), bool)
        while True:
            kids = np.zeros(len(self.branches), np.int64)
            for i, st in enumerate(self.branches):
                if keep[i] and st.parent is not None:
                    kids[st.parent] += 1
            dry = []
            for i, st in enumerate(self.branches):
                if not keep[i] or kids[i] or st.parent is None or st.stop == "left the domain":
                    continue
                x, y = np.clip(np.rint(st.points[-1]).astype(int), 0, [w - 1, h - 1])
                if depth[y, x] > 2.0 * self.p.h:
                    dry.append(i)
            if not dry:
                break
            keep[dry] = False
        self._keep_branches(keep)

    def _keep_branches(self, keep: np.ndarray) -> None:
        """Keep the branches where ``keep`` holds (their parents must be kept too), renumbering parents."""
        if keep.all():
            return
        new_index = np.cumsum(keep) - 1
        out = []
        for i, st in enumerate(self.branches):
            if keep[i]:
                if st.parent is not None:
                    st.parent = int(new_index[st.parent])
                out.append(st)
        self.branches = out
        self.total_length = float(sum(np.hypot(*np.diff(np.asarray(st.points, np.float64), axis=0).T).sum()
                                      for st in out if len(st.points) > 1))
