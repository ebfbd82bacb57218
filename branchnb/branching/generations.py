"""Generations: roots, furcations and fill rounds, breadth first (mixin of :class:`.growth._Grower`).

Every root starts with the head of an input branch (:meth:`_Generations.run`); a finished branch
furcates (:meth:`_Generations.furcate`: the number of children drawn from the example, their
vertices by the furcation model), its children grow the same way, generation by generation; then
the domain is filled round after round (:meth:`_Generations._fill_rounds`). Split from
:mod:`branchnb.branching.growth` (issue 23, branching103).
"""

from __future__ import annotations

import numpy as np

from .frame_band import _frame_sides


class _Generations:
    """The breadth-first generations of :class:`.growth._Grower` (a mixin: it uses the grower's state)."""

    def _child_vertices(self, bi: int) -> list:
        """The parent vertices of branch ``bi``'s children, in the order they were started (an index
        kept up to date as branches are added, rebuilt when the list is replaced)."""
        if self._kids_of is None or self._kids_of[0] is not self.branches:
            self._kids_of = (self.branches, 0, {})
        lst, done, kids = self._kids_of
        for b in lst[done:]:
            if b.parent is not None:
                kids.setdefault(b.parent, []).append(b.parent_vertex)
        self._kids_of = (lst, len(lst), kids)
        return list(kids.get(bi, ()))
    def furcate(self, bi: int, extra: bool = False) -> list[int]:
        st, p = self.branches[bi], self.p
        if st.generation >= p.max_generations or not self.model.furcation.can_branch:
            return []
        if st.stop == "existing":
            return []
        if self.strands and st.generation > int(self.model.branch_generation.max(initial=0)):
            # a band's strands: no generation deeper than the example's + 1, even when the fill rounds
            # fill past the child quota (quota_off; with the roots in the band's core a 512 px vine grew
            # twigs 3 deep where the example has 1)
            return []
        pts = np.asarray(st.points)
        rad = np.asarray(st.radii)
        length = (len(pts) - 1) * p.h
        weights = None
        head = self._below_head(bi)
        # a band's strands (one-pen line art): d among the example's branches of the same generation, and the fill
        # rounds never take a branch past its generation's children per length (child_quota; issue 23)
        # a hub's branches too (radial): drawn among all, a dendrite twig took a primary's count and
        # its children twigs of their own (.radial._hub_view; issue 23)
        fm, gen = self.model.furcation, (st.generation if self.strands or self.radial else None)
        if extra:
            d = 1
            existing = self._child_vertices(bi)
            if gen is not None and not self.quota_off and len(existing) >= fm._child_quota(length, gen):
                return []
            weights = self._room(pts) if self._empty_dt is not None else None
            if head is not None:
                weights = head * (1.0 if weights is None else weights)
            if weights is not None and not weights.any():
                return []
        else:
            d = p.d if p.d >= 0 else fm.sample_d(length, self.rng, generation=gen)
            existing = ()
            if head is not None and head.any():
                weights = head.astype(np.float64)
        if self.radial:   # a hub's branches fork where the example's do along them (.radial._fork_weights)
            from .radial import _fork_weights

            fw = _fork_weights(self.model, st.generation, len(pts))
            if fw is not None:
                weights = fw if weights is None else weights * fw
        if self.frame_band > 0:   # no child starts in the frame's band, where it could only run along it
            clear = _frame_sides(pts, self.shape)[0] >= self.frame_band
            if not clear.all():
                weights = clear.astype(np.float64) if weights is None else weights * clear
        verts = self.model.furcation.choose(pts, rad, d, min_spacing=p.min_spacing, existing=existing,
                                            weights=weights)
        kids = []
        for v in verts:
            if self.global_stop():
                break
            c = self.start_child(bi, v)
            if c is not None:
                kids.append(c)
        return kids

    def run(self, starts) -> None:
        if getattr(starts, "hubs", None) and self.p.max_total_length <= 0 and self.p.max_coverage <= 0:
            # a hub's primaries: the example's length per hub, not its coverage (.radial._hub_budget)
            from .radial import _generation_caps, _hub_budget

            self.max_total = _hub_budget(self.model, len(starts.hubs), starts.scale, len(starts))
            self.coverage_target, self.radial = 1.0, True
            self._gen_cap = _generation_caps(self.model, len(starts))
            from . import radial_bearing

            if radial_bearing.RADIAL_BEARING:   # and they run outward as the example's lines do
                self.radial_bearing = radial_bearing._radial_weights(self.model)
                self.hub_array = np.asarray([tuple(map(float, h[:3])) for h in starts.hubs], np.float64)
        queue = []
        for (x, y, th) in starts:
            if self.global_stop():
                break
            r = self.start_root(x, y, th)
            if r is not None:
                if self.radial:   # a hub's primary heads out along its spoke first (.radial._spoke_goal)
                    from .radial import SPOKE_KAPPA, _spoke_goal

                    self.branches[r].goal = _spoke_goal(starts.hubs, x, y)
                    self.branches[r].goal_kappa = SPOKE_KAPPA
                queue.append(r)
        self._drain(queue)
        self._fill_rounds()
        if not self.stop_reason:
            self.stop_reason = "no branch can grow" if queue else "no root could start"

    def _fill_rounds(self) -> None:
        # Everything stopped before the domain is as dense as the example:
        # furcate the grown branches once more (highest furcation probability
        # away from their children), round after round.
        # (Not in guided synthesis: the user's path, not the domain, says where to grow.)
        for _ in range(self.p.fill_rounds if self.guidance is None else 0):
            if self.global_stop() or self.density is None or not self.branches:
                break
            before = len(self.branches)
            self._update_room()
            rooms = self._max_rooms()
            # tips that ended at their drawn length with free space ahead grow on; in an output with
            # fewer branches than the example (_min_branches) after new children, not before (a small
            # example's trunk ran on across the frame and took the length the children needed)
            few = len(self.branches) < self.min_branches
            if not few:
                self._drain(self._reopen_tips())
            for bi in np.argsort(rooms, kind="stable")[::-1]:
                if self.global_stop() or rooms[bi] <= 0:
                    break
                self._drain(self.furcate(int(bi), extra=True))
            if few and not self.global_stop():
                self._drain(self._reopen_tips())
            self._empty_dt = None
            if len(self.branches) == before:
                break
            self.fill_rounds += 1

