"""Starting branches in structure synthesis: roots, and children at furcations.

A new branch starts with the head of an input branch (:meth:`_Starts._start_branch`):
every candidate head is laid from the start point (a root's, or the parent's
vertex with the input furcation's angle ``beta``), scored by the Markov
quality ``Q`` of the furcation (children: the parent's non-causal window
against the input's, :meth:`~branchnb.branching.furcation.FurcationModel.child_quality`),
the global histogram factor and space colonization, and one of the ``c`` best
is drawn. Split from :mod:`branchnb.branching.growth` (the paper's
furcation step; the Markov steps stay there).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from . import _kernels, _loop_kernels
from .child_angles import _AngleMatch, _head_angles
from .domains import FAN_SPLIT, HEAD_PULL, MOUTH_TURN, fan_spread, head_share
from .fork_radii import FORK_RATIO_SKIP, FORK_RATIO_SPAN, fork_radius_rank, fork_ratios, head_fork_ratios  # noqa: F401
from .furcation import vertex_angles
from .scoring import _DIRECTION_BINS
from .tropism import _tropism_factor

__all__: list[str] = []

#: A delta (beyond the paper, issue 23): a channel leaving the trunk at or below the delta's head on the
#: side that already has more of them gets its score times this (the example's channels part to both
#: sides of its head; without it 2 of 3 seeds of a 1000 px delta sent every channel to one side).
FAN_OTHER_SIDE = 0.02
#: ... and one on the outer side of a turned trunk that is the example's outermost channel
#: (:data:`.drain.TAIL_OUTER`) this: at FAN_OTHER_SIDE, even at 1e-6, a head leaving outward still won in 2
#: of 5 seeds of a 512 px ``mean20`` delta (where the trunk meanders no head leaves inward), and its channel
#: ran outside the trunk to the sea; none starts there instead (the fan is completed elsewhere, ``_finish_fan``).
TAIL_OUTER_SIDE = 0.0
#: A delta's channel of a channel (beyond the paper, issue 23, branching74) whose bearing
#: (:meth:`.drain._Drain.bearing`)
#: lies less than this many radians from that of a channel already started, and whose start lies less than
#: :data:`FAN_BUNDLE_NEAR` x the frame's diagonal from that channel's line (its start along its bearing), is not
#: started: it would run beside it to the sea. The bearings of a trunk's channels bottom out at
#: :data:`.drain.FAN_SPLIT` off the descent and a channel's channel parting outward takes its parent's side
#: again, so a side's third channel or a channel's grandchild took an earlier channel's bearing and the fan
#: came out as a comb of two to four parallel channels on one side (``fan0`` 512 px, seed 3: bearings 54, 79,
#: 53 degrees from starts 19 px off one line). With :data:`FAN_TRAPPED`, pairs of channels running side by side
#: (chords < 10 degrees apart, one start < 5 % of the diagonal off the other's line; ``tests/
#: test_branching_delta_comb.py``) over seeds 0-8 at 512 px: ``fan0`` 5 -> 0, ``mean0`` 4 -> 0, ``delta`` 1 -> 1;
#: ``_delta_fan_check`` (same seeds; median / max): bearing error ``delta`` 8.8/17.4 -> 4.4/11.7, ``fan0``
#: 14.4/21.1 -> 14.1/23.5, ``mean0`` 13.5/26.0 -> 15.7/24.0, ``fan30`` 2.8/9.0 -> 2.4/8.8 degrees; fan spread
#: median / lowest seed ``mean0`` 30.7/21.0 -> 24.6/10.7 (example 34.9; worse), others within 1 degree.
#: branching79: the earlier channel's course (its chord so far, once 2 x FAN_BUNDLE_NEAR x the diagonal long)
#: counts as well as its bearing: a channel 15 degrees off its bearing took a grandchild's 21 degrees off it
#: beside it (``fan0`` 512 px, seeds 2 and 3 with the held trunk, :data:`.drain.STRAIGHT_HOLD`: 1 comb each -> 0).
FAN_BUNDLE = float(np.radians(10.0))
FAN_BUNDLE_NEAR = 0.05
#: ... nor a channel's channel that leaves its parent on one side while its bearing lies on the other (a
#: channel's channel parts toward the descent, :meth:`.drain._Drain.bearing`): it cannot cross its parent, so it
#: ran beside it on the outside, 41 degrees off its bearing (``fan0`` 512 px, seed 6).
FAN_TRAPPED = True
#: Score factor of a candidate that would leave a domain drawn round a line mask's lines (issue 23,
#: beyond the paper; :func:`.empty_ground._line_domain`): a strand turns to stay in its band instead of
#: ending at its edge (in the band alone the border vines came out 2-3.5 x as many branches, half as long)
LEAVE_BAND = 1e-3
#: Score factor of a child's candidate head whose copied vertices leave the frame, domain or frame band
#: before its end (issue 23, beyond the paper, which tests the first vertex only): the child would be cut
#: there, a bare head of 1-3 elements; 0 never draws such a head (no child starts there when every head is
#: such), 1 (the default for now) leaves the paper's rule. Rare while traced paths are rounded; with their
#: corners kept (:data:`.path_smoothing.KEEP_CORNERS`) parents run along the frame more often, and half
#: their mirrored candidates head out of it: the 300 x 450 crack of tests/test_branching_unborn.py grew 3
#: frame stubs in a seed along a parent 6 px off the bottom (0: none, seeds 0-11). Set it to 0 together
#: with KEEP_CORNERS: with corners rounded 0 moves other tests' figures (branching107: thin_children's
#: partial crack, image_style, unexamined). Not in a delta or at a shore, where a channel heads for the
#: sea beyond its domain.
LEAVE_FRAME = 1.0
#: Elements (of ``h`` px) straight on from a child's head end that must lie in the frame / domain too
#: (:data:`LEAVE_FRAME`): a head ending at the frame heading out is cut at its first Markov step.
LEAVE_AHEAD = 2
#: A delta: log-spaced radius bins over the example's range in which a new channel's radius is chosen
#: (:meth:`_Starts._channel_radius`).
CHANNEL_RADIUS_BINS = 8
#: Fewer than 3 input roots (any input branch's head may start a root): a head's weight is (its radius
#: over the input root's, or the inverse, at most 1) to this power (:meth:`_Starts._root_radius`).
ROOT_RADIUS_POWER = 2.0
#: A delta's trunk starts at least this share of its example trunk's radius away from the frame
#: (:func:`_inland_radius`).
INLAND_SHARE = 1.0


#: A child's head: the thickness term of its histogram factor compares the synthesized children's
#: thicknesses with the example's children's, not every branch's (:meth:`_Starts._child_radius_hist`;
#: beyond the paper, issue 23). False = the paper's global factor. Off by default (branching54): with
#: it, on the partial comb mask of ``test_branching_thin_children`` (300 px, seed 0) 0.22 of the output
#: length lies > 8 % of the short side from every example line (bound 0.2; 4 seeds: mean 0.13 -> 0.15 with
#: both rules), and the storm bolts' profile correlation drops to 0.96 in one seed (bound 0.97).
CHILD_RADIUS_HISTOGRAM = False
#: A child's head is scaled to start at its parent's radius there times the fork ratio of the input child
#: it was copied from (:func:`head_fork_ratios`; beyond the paper, issue 23, branching122), not at the
#: head's own radius (capped at the parent's). The histogram factor favours the many thin heads, so
#: children of thick parents started as twigs: winter-tree silhouettes' two biggest limbs came out a
#: median 0.51 x the example's (128-512 px, seeds 0-5; 0.96 x with it; the children's fork ratio median
#: 0.97 -> 0.87, example 0.78). Not in a delta (:meth:`_Starts._channel_start`), nor in a band (``keep_in``:
#: line-art strands of one width, where it only moved ``_child_check``'s figures, seed 0: children per
#: length L 1.84 -> 2.44, L+ 0.98 -> 2.30 x the example's). Only where the example's children inherit their
#: parent's thickness (:data:`CHILD_FORK_RANK`, branching123): applied to every example, it thickened heads
#: copied onto thick parents in examples whose children's width does not follow their parent's, and five
#: tests of other kinds failed (mud cracks' specks 19 > 12, a bolt's relit glow 0.98 x unrelit, a comb's
#: far share 0.31 > 0.18, a crack's short leaf heads 2 > 1).
CHILD_FORK_RATIO = True
#: :data:`CHILD_FORK_RATIO` applies where :func:`fork_radius_rank` (parent's fork radius vs. child's head
#: radius, rank correlation over the example's children) is at least this (branching123): winter-tree
#: silhouettes 0.71-0.92 (128-512 px, seeds 0-5; NaN for a 128-px one with under 3 children) and upright
#: trees 0.82-0.91 (256 px, seeds 0-2), against random-walk crack masks -0.12-0.63 (300 and 450 px, 16
#: seeds), mud cracks 0.04, a lightning bolt -0.60, a comb mask 0.10, a comb of one-width teeth NaN, and a
#: storm photo's two bolts 0.68 (at 0.67 the rule thickened their children and their brightness profile's
#: correlation with the example's fell to 0.96)
CHILD_FORK_RANK = 0.70


def _elem_bins(model) -> np.ndarray:
    """The thickness bin of every input element (:func:`._kernels.element_bins`), once per model."""
    got = model.__dict__.get("_elem_bins_r")
    if got is None or got[0] is not model.cum_r:
        got = model.__dict__["_elem_bins_r"] = (model.cum_r, _kernels.element_bins(model.cum_r))
    return got[1]


_E2, _E3 = np.zeros((1, 1), np.int16), np.zeros((2, 1, 1), np.int16)
_E_GRID = np.zeros((1, 1), np.float32)


def _head_rows(model, edges_a: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Every input head's angle and thickness bins (:func:`._kernels.head_rows`), once per model and
    angle bin edges."""
    key = (model.first_a, model.first_len, model.cum_r, edges_a.tobytes())
    got = model.__dict__.get("_head_rows")
    if got is None or any(a is not b for a, b in zip(got[0][:3], key[:3])) or got[0][3] != key[3]:
        rows = _kernels.head_rows(model.first_a, model.first_len, np.asarray(edges_a, np.float64), _elem_bins(model),
                                  model.head_start)
        got = model.__dict__["_head_rows"] = (key, rows)
    return got[1]


def _inland_radius(branch, head: dict, shape) -> float:
    """A delta's input root's radius away from the image frame (beyond the paper, issue 23).

    The median radius of the vertices of the root's first quarter (by arc length) that lie more than
    twice their radius from the frame; its head's ``max(r0, r1)`` when there are none. Where a channel
    enters through the frame its measured width shrinks (the frame cuts the half-contrast mask): a
    1000 px delta's trunk measured 21 px at the frame and 31 px past it, and the synthesized trunk,
    started at the head's 21, kept the whole delta at 0.51-0.62 x the example's median radius.
    """
    p = np.asarray(branch.points, np.float64)
    r = np.asarray(branch.thickness, np.float64)
    fallback = float(max(head["r0"], head["r1"]))
    if len(p) < 2:
        return fallback
    h, w = shape
    s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
    d = np.minimum(np.minimum(p[:, 0], w - 1 - p[:, 0]), np.minimum(p[:, 1], h - 1 - p[:, 1]))
    ok = (s <= 0.25 * s[-1]) & (d > 2.0 * r)
    return max(fallback, INLAND_SHARE * float(np.median(r[ok]))) if ok.any() else fallback


@dataclass
class _BranchState:
    points: list
    radii: list
    elem_a: list
    elem_r: list
    theta: float
    parent: int | None
    parent_vertex: int | None
    generation: int
    stop: str = ""
    target: float = np.inf
    #: input element each vertex appended by a Markov step was copied from (the last ones)
    src: list = field(default_factory=list)
    #: a coast root near its mouth: (lowest, highest) heading so far (radians); None = no limit
    mouth: tuple | None = None
    #: a branch grown into a hole (see ``_Filling._fill_far``): the hole's centre (x, y) it heads
    #: for until within ``rho`` of it; None = free growth
    goal: np.ndarray | None = None
    goal_kappa: float | None = None   # the goal's pull (None: filling.GOAL_KAPPA)
    #: (lowest, highest) heading along the branch so far (radians, unwrapped); None = not started
    heads: tuple | None = None
    #: a delta's channel that left its parent below the head: its own fan bearing (unit x, y,
    #: :meth:`.domains._Drain.bearing`); None = the descent alone (a trunk) or no delta
    fan: np.ndarray | None = None
    #: a root (not in a delta): the input root's radius by arc length ((arc lengths, radii)) its radii are
    #: drawn back to (:func:`~branchnb.branching.growth._pull_radii`); None = the copied pieces' radii
    profile: tuple | None = None
    #: the input branch whose head started this branch
    head_src: int = -1
    #: queued but never grown: the global stop (length, coverage) came before its turn, so it is only
    #: its copied head (see ``_Filling._drop_unborn``)
    unborn: bool = False
    #: a root the bearing stop ended (:func:`.frame_band.bearing_keep`): its tree's children crowd on
    #: less length, and those whose first Markov step was refused are dropped (``_Filling._drop_heads``)
    bearing_cut: bool = False
    #: an example that meanders (:mod:`.meander_hold`): the sine ``(base, omega, wavelength, phase)`` the
    #: branch's heading is held to, set at its first Markov step; None = not yet, or no meander
    meander: tuple | None = None
    #: a delta's channel: its start radius over its parent's at the fork (:data:`FORK_RATIO_SKIP`), which
    #: ``growth_bounds._thin_below_forks`` holds once the parent is thinned; None = not set
    fork_ratio: float | None = None


class _Starts:
    """The branch-starting half of ``growth._Grower`` (a mixin: it uses the grower's state)."""

    def _below_head(self, bi: int) -> np.ndarray | None:
        """A delta's trunk (a root, :class:`.domains._Drain`): which of its vertices lie at or below the
        delta's head, where its channels part (beyond the paper, see :func:`.domains.head_share`);
        None on any other branch or example. Finds the head (:meth:`.domains._Drain.set_head`) on first use."""
        st = self.branches[bi]
        if self.drain is None or st.parent is not None:
            return None
        share = self._head_share()
        if share <= 0:
            return None
        pts = np.asarray(st.points, np.float64)
        if not self.drain.head:
            self.drain.set_head(pts, share)
        dep = self.drain.depth_at(pts)
        return dep <= share * dep[0]

    def _fan_spread(self) -> float | None:
        """A delta: the bearing of the trunk's channels off the descent (:func:`.domains.fan_spread`)."""
        if "_spread" not in self.__dict__:
            m = self.model
            self.__dict__["_spread"] = None if m.domain is None else fan_spread(m.example, m.domain)
        return self.__dict__["_spread"]

    def _fan_need(self) -> int:
        """A delta: how many channels the example takes to the sea (branches ending within 10 % of the
        deepest depth of the sea, as in :func:`.domains._drains`), at least 2."""
        need = self.__dict__.get("_fan_n")
        if need is None:
            ex = self.model.example
            tips = [b.points[-1] for b in ex.branches if len(b.points)]
            deep = float(self.drain.depth.max())
            need = max(2, int(np.sum(self.drain.depth_at(np.asarray(tips)) < 0.1 * deep))) if tips else 2
            self.__dict__["_fan_n"] = need
        return need

    def _finish_fan(self) -> None:
        """A delta stopped by coverage or length: its trunks fan out to the sea all the same.

        Beyond the paper (issue 23): the global stops (coverage, total length) hold the example's
        density, but a delta's trunk that met them before it furcated (a small example, whose trunk
        alone covers as much as the whole example: 3 of 5 seeds of a 250 px delta) ran to the sea
        alone, and children started just before the stop stayed heads. Each trunk gets children below
        the delta's head until it and they make the example's number of channels at the sea
        (:meth:`_fan_need`), and every child of a trunk runs on to the sea (``grow`` past the stops).
        """
        if self.drain is None:
            return
        for bi in [i for i, st in enumerate(self.branches) if st.parent is None]:
            below = self._below_head(bi)
            if below is None or not below.any():
                continue
            kids = [i for i, st in enumerate(self.branches) if st.parent == bi]
            for c in kids:
                if not self.branches[c].stop:
                    self.grow(c)
            st = self.branches[bi]
            pts, rad = np.asarray(st.points, np.float64), np.asarray(st.radii, np.float64)
            tried = [self.branches[c].parent_vertex for c in kids]
            wet = sum(self._wet(c) for c in kids)
            while wet + 1 < self._fan_need():
                verts = self.model.furcation.choose(pts, rad, 1, min_spacing=self.p.min_spacing, existing=tried,
                                                    weights=below.astype(np.float64))
                if not verts:
                    break
                tried.append(int(verts[0]))
                c = self.start_child(bi, int(verts[0]))
                if c is not None:
                    self.grow(c)
                    wet += self._wet(c)

    def _wet(self, bi: int) -> bool:
        """Does branch ``bi`` (or a branch of its subtree) reach the sea (a delta; see ``_prune_dry``) from
        inland (it starts over 10 % of the deepest depth from the sea; not a stub at a mouth)?"""
        if float(self.drain.depth_at(self.branches[bi].points[0])[0]) < 0.1 * float(self.drain.depth.max()):
            return False
        todo = [bi]
        while todo:
            i = todo.pop()
            st = self.branches[i]
            if st.stop == "left the domain" or float(self.drain.depth_at(st.points[-1])[0]) <= 2.0 * self.p.h:
                return True
            todo.extend(j for j, b in enumerate(self.branches) if b.parent == i)
        return False

    def _child_radius_hist(self) -> tuple[np.ndarray, np.ndarray] | None:
        """``(p, counts)``: the example's thickness histogram over its child branches' vertices (the
        matcher's bins) and the running counts of the synthesized children's, or None
        (:data:`CHILD_RADIUS_HISTOGRAM` off, no histogram matching, a delta, or no child in the example).

        Beyond the paper (issue 23). The paper's factor weighs a head's thicknesses against the shares
        of every node grown so far, but growth is not in proportion: a tree's trunk grows first, so
        when its children start the running histogram is all trunk, every thick head is turned down,
        and by the time thin children have filled the histogram the thick junctions that could start a
        thick child are taken (a child never starts thicker than its parent's junction). On masks with
        3-4 px trunks and 1-px side cracks no child came out thicker than 0.9 px where the example's
        depth-1 children reach 1.9-2.3 px. Against the children's own histograms a child head is
        judged among children only: the first children start with no thickness term, later ones fill
        the bins the example's children fill. A delta's channels take their radius from
        ``_channel_radius`` and keep the paper's factor.
        """
        hm = self.matcher
        if not CHILD_RADIUS_HISTOGRAM or hm.wG <= 0 or self.drain is not None:
            return None
        cached = self.__dict__.get("_child_hist")
        if cached is None:
            r = [np.broadcast_to(np.asarray(b.thickness, np.float64), (len(b.points),))
                 for b in self.model.example.branches if b.parent is not None]
            r = np.concatenate(r) if r else np.zeros(0)
            if r.size == 0:
                cached = ()
            else:
                pc = np.bincount(hm.bin_radii(r), minlength=hm.bins).astype(np.float64)
                cached = (pc / pc.sum(), np.zeros(hm.bins))
            self.__dict__["_child_hist"] = cached
        return cached or None

    def _child_count(self, radii) -> None:
        """Count a synthesized child's new vertex thicknesses (:meth:`_child_radius_hist`)."""
        ch = self._child_radius_hist()
        if ch is not None and len(radii):
            ch[1][:] += np.bincount(self.matcher.bin_radii(np.asarray(radii, np.float64)), minlength=len(ch[1]))

    def _child_hist_args(self, use_hist: bool) -> tuple:
        """``(p_r, counts_r, r_scale)`` of a child's start (:func:`._kernels.start_scores`): its thickness
        term against the children's histograms (:data:`CHILD_RADIUS_HISTOGRAM`), else the matcher's."""
        hm = self.matcher
        ch = self._child_radius_hist() if use_hist else None
        if ch is None:
            return hm.p_r, hm.counts_r, -1.0
        return ch[0], ch[1], hm.wG * float(ch[1].sum()) / hm.m

    def _angle_match(self) -> _AngleMatch:
        """The example's child angles and the synthesized children's so far (:class:`.child_angles._AngleMatch`)."""
        got = self.__dict__.get("_angles")
        if got is None:
            got = self.__dict__["_angles"] = _AngleMatch(self.model.example)
        return got

    def _head_share(self) -> float:
        if self._head is None:
            m = self.model
            self._head = 0.0 if m.domain is None else head_share(m.example, m.domain)
        return self._head


    def _start_branch(self, x0, theta0, heads, Q, parent, parent_vertex, generation,
                      betas=None, mirror=None, r_cap: float | None = None, full: bool = False,
                      r_set: float | None = None) -> int | None:
        """Start a branch at ``x0`` with one of the candidate input heads (vectorised).

        ``r_cap`` (a child: the parent's radius at the junction) bounds the
        copied head's radii: a head taken from a thicker input branch is
        scaled down so the child never starts thicker than its parent.
        ``r_set`` (a delta's trunk) scales the copied head's radii so it starts
        that thick.
        """
        model, p = self.model, self.p
        heads = np.asarray(heads, np.int64)
        if len(heads) == 0:
            return None
        sub = None if full else self._share(len(heads))
        if sub is not None:
            every = (heads, Q, betas, mirror)
            heads, Q = heads[sub], np.asarray(Q)[sub]
            betas = None if betas is None else np.asarray(betas)[sub]
            mirror = None if mirror is None else np.asarray(mirror)[sub]
        x0 = np.asarray(x0, np.float64)
        H = len(heads)
        th0 = theta0 + (np.zeros(H) if betas is None else np.asarray(betas, np.float64))
        n = model.first_len[heads]
        # vertices after x0: x1 (first edge, no turn) then the n first elements
        sign = np.where(mirror, -1.0, 1.0) if mirror is not None else np.ones(H)
        valid = np.arange(p.m + 1)[None, :] <= n[:, None]
        # geometry, histogram factor, PCA directions and density profiles in one compiled pass
        hm = self.matcher
        use_hist = hm.wG > 0 and hm.n_nodes > 0
        dens = self.density
        length = 3.0 * p.m * p.h
        rows_a, rows_r = _head_rows(model, hm.edges_a) if use_hist else (_E3, _E2)
        p_r, counts_r, r_scale = self._child_hist_args(use_hist) if parent is not None else (hm.p_r, hm.counts_r, -1.0)
        new, th, score, dirs, dc = _kernels.start_scores(
            heads, th0, np.asarray(sign, np.float64), model.first_a, n, float(x0[0]), float(x0[1]), float(p.h),
            np.asarray(Q, np.float64), use_hist, rows_a, hm.p_a, hm.counts_a, rows_r, p_r, counts_r,
            hm.wG * hm.n_nodes / hm.m if use_hist else 0.0, dens is not None,
            dens.grid if dens is not None else np.zeros((1, 1), np.float32), dens.cell if dens is not None else 1.0,
            length, int(min(max(np.ceil(length / (dens.rho / 2.0)), 8), 48)) if dens is not None else 8, 0.02,
            _DIRECTION_BINS, float(p.eps), r_scale)
        if self.guidance is not None:
            score = score / (self.guidance.along(x0, dirs, length) + p.eps)
        if dens is not None and self.frame and parent is None:
            score = score * self._frame_factor(x0, dirs, dc)
        inside = self._inside(new[:, 0])
        score = np.where(inside, score, 0.0)
        if parent is not None:   # the whole head in the frame (LEAVE_FRAME)
            score = score * self._leave_factor(x0, new, n, score)
        if self.tropism is not None:   # a head heads where the example's lines head too (.tropism)
            score = score * self._head_tropism(x0, new, n)
        if self.drain is not None and parent is not None:  # downstream, not along or into the land's frame
            # a channel leaving the trunk at or below the delta's head heads apart by its furcation angle
            fan = self.drain.head and self.branches[parent].parent is None
            score = score * self.drain.factor(x0, new, n + 1, start=x0, pull=HEAD_PULL if self.drain.head else 1.0)
            outer, a_tail = self.drain.outer_side(x0) if fan else (0, 0.0)
            if outer:   # a turned trunk that is the fan's outermost channel: none beyond it (.drain.TAIL_OUTER)
                # its first edge too: a head that curved back inward after setting out outward was cut short
                # at the frame band and left its channel heading outward
                out = (self._fan_side(x0, a_tail, new, n) == outer) \
                    | (self._fan_side(x0, a_tail, new, np.ones_like(n)) == outer)
                score = np.where(out, score * TAIL_OUTER_SIDE, score)
            elif fan:   # and to the side of the trunk with fewer channels so far (both sides, like the example's)
                side = self._fan_side(x0, theta0, new, n)
                left, right = self._fan_count
                if left != right:
                    score = np.where(side == (1 if left < right else -1), score, score * FAN_OTHER_SIDE)
        if self.keep_in:   # a strand's head stays in its band (LEAVE_BAND)
            ins = self._inside(new.reshape(-1, 2)).reshape(new.shape[:2])
            k = min(ins.shape[1], valid.shape[1])
            score = np.where((ins[:, :k] | ~valid[:, :k]).all(1), score, score * LEAVE_BAND)
            score = score * self._core_factor(new, valid)
        match = self._angle_match() if parent is not None and self.strands else None
        if match is not None:   # a band's child leaves at the example's angles (.child_angles)
            ang = _head_angles(x0, theta0, new, n + 1, 0.0 if r_cap is None else float(r_cap))
            score = score * match.factor(ang)
        if self.drain is not None and parent is None:
            # beyond the paper (issue 23): a delta's trunk takes a head that stays in the land where one does
            # (a head running along the frame it starts on left the domain at its second vertex: nothing
            # grew in 3 of 3 attempts of 1 of 5 seeds of a 1000 x 1500 px delta)
            ins = self._inside(new.reshape(-1, 2)).reshape(new.shape[:2])
            k = min(ins.shape[1], valid.shape[1])
            stays = (ins[:, :k] | ~valid[:, :k]).all(1)
            score = np.where(stays, score, score * 1e-9)
            if self.drain.axis is not None or self.drain.trunk_axis is not None:
                # ... and heads for the example's mouths (beyond the paper, issue 23, branching58: a trunk entering
                # through a side of the frame took a head along it and could not turn to the sea)
                score = score * self.drain.trunk_hold(x0, new[np.arange(len(new)), np.maximum(n, 1) - 1])
        if self.shore is not None:
            score = score * self.shore.factor(x0, new, n + 1) * self.shore.along_factor(x0, new, n + 1)
        mouth = self.shore is not None and parent is None
        if mouth:
            span = np.where(valid, th, th[:, :1])
            score = np.where(np.ptp(span, axis=1) > MOUTH_TURN, score * 1e-9, score)
        j = self._pick(score, x0, new, n + 1)
        if j is not None and match is not None:
            match.add(float(ang[j]))
        if j is None:   # none of the share fits: all the heads (rare)
            if sub is None or not self._room_around(x0, length):
                return None
            return self._start_branch(x0, theta0, every[0], every[1], parent, parent_vertex, generation,
                                      every[2], every[3], r_cap, full=True, r_set=r_set)
        return self._make_branch(x0, theta0, j, heads, n, new, th, sign, parent, parent_vertex, generation,
                                 r_cap, r_set, mouth)

    def _make_branch(self, x0, theta0, j, heads, n, new, th, sign, parent, parent_vertex, generation,
                     r_cap, r_set, mouth) -> int | None:
        """The new branch of :meth:`_start_branch` with the chosen candidate head ``j`` (its first
        vertices ``new[j]``, headings ``th[j]``, ``n[j]`` copied elements, mirrored where ``sign[j]``
        is -1): its state, radii, length target and fan bearing, registered; returns its index (None: a
        delta channel with no bearing left on its side, :data:`FAN_BUNDLE`)."""
        model, p = self.model, self.p
        hd = int(heads[j])
        full = np.vstack([x0, new[j, : n[j] + 1]])
        cut = self._head_cut(full, parent is not None)
        pl = full[:cut]
        head = model.bending.heads[hd]
        ne = max(cut - 2, 0)
        ea = list(sign[j] * model.first_a[hd, :ne])
        er = list(model.first_r[hd, :ne])
        radii = [head["r0"], head["r1"]] + er
        if r_set is not None:
            f = r_set / max(max(radii[:3]), 1e-9)
            radii = [max(r * f, model.r_min) for r in radii]
            er = radii[2:]
        q = self._head_ratio(hd) if parent is not None and r_cap is not None and r_set is None else None
        if q is not None:   # the parent's radius there x the input child's fork ratio (CHILD_FORK_RATIO)
            f = r_cap * q / max(max(radii[:3]), 1e-9)
            radii = [max(r * f, model.r_min) for r in radii]
            er = radii[2:]
        if r_cap is not None:
            f = min(1.0, r_cap / max(max(radii[:3]), 1e-9))
            if f < 1.0:
                radii = [max(r * f, model.r_min) for r in radii]
                er = radii[2:]
        d = pl[-1] - pl[-2]
        st = _BranchState(points=list(pl), radii=radii, elem_a=ea, elem_r=er,
                          theta=float(np.arctan2(d[1], d[0])), parent=parent,
                          parent_vertex=parent_vertex, generation=generation, head_src=hd)
        if p.branch_end == "length":
            # beyond the paper: a delta's channel runs on to the sea (see ``grow``)
            st.target = np.inf if self.drain is not None else \
                model.sample_length(generation, float(np.mean(radii[:3])), self.rng)
        hs = th[j, : max(cut - 1, 1)]
        hs = hs + (st.theta - hs[-1])   # in the frame of st.theta (wrapped by arctan2; th is not)
        st.heads = (float(hs.min()), float(hs.max()))
        if mouth:
            st.mouth = (float(hs.min()), float(hs.max()))
        if cut < len(full):
            st.stop = "left the domain"
        elif n[j] < p.m and p.branch_end == "markov":
            st.stop = "end of input branch"
        if self.drain is not None and parent is not None and self.drain.head:
            spread = self._fan_spread()
            trunk = self.branches[parent].parent is None
            if trunk:
                side = int(self._fan_side(x0, theta0, new[j:j + 1], n[j:j + 1])[0])
                k = self._fan_count[0] if side > 0 else self._fan_count[1]
                if spread is not None and k:   # the k-th channel on a side: between the others and the descent
                    spread = max(spread / (k + 1), FAN_SPLIT)
            st.fan = self.drain.bearing(x0, pl[-1] - x0, self.branches[parent].fan, spread=spread)
            # (a trunk's channels keep their own rule, the k-th on a side below: refused there, a 300 px fan0
            # delta's fan came out lopsided)
            if (not trunk and self._bundled(x0, st.fan)) or self._trapped(pl[-1] - x0, self.branches[parent].fan,
                                                                          st.fan):
                return None
            if trunk:
                self._fan_count = (self._fan_count[0] + (side > 0), self._fan_count[1] + (side < 0))
        if parent is not None and self.radial and p.thickness_blend:
            # a hub's child tapers like the example's children of its generation (.radial._taper_profile)
            from .radial import _taper_profile

            st.profile = _taper_profile(model, generation, float(max(radii[:3])), st.target)
        self._register(pl, ea, radii)
        if parent is not None:
            self._child_count(radii)
        self.branches.append(st)
        return len(self.branches) - 1

    def _bundled(self, x0, fan: np.ndarray) -> bool:
        """Would a delta's channel from ``x0`` on bearing ``fan`` run beside one already started
        (:data:`FAN_BUNDLE`)?"""
        x0 = np.asarray(x0, np.float64)
        near = FAN_BUNDLE_NEAR * float(np.hypot(*self.drain.shape))
        cos_min = np.cos(FAN_BUNDLE)
        for b in self.branches:
            if b.fan is None or b.parent is None:
                continue
            ways = [np.asarray(b.fan, np.float64)]
            c = np.asarray(b.points[-1], np.float64) - np.asarray(b.points[0], np.float64)
            if float(np.hypot(*c)) >= 2.0 * near:
                # ... or on the course it took (branching79: a channel ran 15 degrees off its bearing, a
                # grandchild's bearing 21 degrees off that bearing lay on its course: a comb on fan0 512 px)
                ways.append(c / float(np.hypot(*c)))
            r = x0 - np.asarray(b.points[0], np.float64)
            for u in ways:
                if float(u @ fan) >= cos_min and abs(float(r[0] * u[1] - r[1] * u[0])) < near:
                    return True
        return False

    @staticmethod
    def _trapped(heading, parent_fan, fan) -> bool:
        """Would a delta's channel leaving its parent channel (bearing ``parent_fan``; None for a trunk) with
        ``heading`` have to cross it to take its own bearing ``fan`` (:data:`FAN_TRAPPED`)?"""
        if not FAN_TRAPPED or parent_fan is None:
            return False
        pf = np.asarray(parent_fan, np.float64)
        side_h = float(pf[0] * heading[1] - pf[1] * heading[0])
        side_b = float(pf[0] * fan[1] - pf[1] * fan[0])
        return side_h * side_b < 0.0

    def _head_ratio(self, hd: int) -> float | None:
        """The fork ratio a child copying input head ``hd`` starts at (:data:`CHILD_FORK_RATIO`,
        :func:`head_fork_ratios`); None: off, in a delta or a band (``keep_in``), in a hub example (its
        spokes leave a soma, not a parent's fork: on a neuron mask, 384 px seed 1, rank 0.86 from the spokes,
        the rule left a thick child's blunt end apart from its thin continuation, a gap in the flat drawing),
        where the example's children do not inherit their parent's thickness (:func:`fork_radius_rank` under
        :data:`CHILD_FORK_RANK`), or the head has none."""
        if not CHILD_FORK_RATIO or self.drain is not None or self.keep_in:
            return None
        if getattr(self.model.example, "hubs", None):
            return None
        q = self.__dict__.get("_head_ratios")
        if q is None:
            rank = fork_radius_rank(self.model)
            q = head_fork_ratios(self.model) if rank >= CHILD_FORK_RANK else np.zeros(0)
            self.__dict__["_head_ratios"] = q
        v = float(q[hd]) if 0 <= hd < len(q) else np.nan
        return v if np.isfinite(v) else None

    def _channel_start(self, r_parent: float) -> float | None:
        """A delta's new channel's start radius at a fork where its parent is ``r_parent`` thick (beyond the
        paper, issue 23, branching110): the median of the example's fork ratios (:func:`fork_ratios`) times
        ``r_parent``; :meth:`_channel_radius` where the example has no fork.

        :meth:`_channel_radius` alone, capped at the parent's radius, started most children as thick as
        their trunk (the thick bins lack most while the trunk grows): on procedural deltas whose children
        are 0.55 x their parent (``_delta_examples.delta_tree_mask``, 512 px) the synthesized children
        started at a median 0.85 x their parent, up to 1.8 x after the parent thinned below earlier forks.
        The median ratio alone, not capped by :meth:`_channel_radius` as well: with that cap the children
        started 0.05-0.2 thinner than the example's ratios (median over seeds 0-2 of bird-foot, braided,
        uneven and fan deltas at 256-1000 px), for no closer channel area. Not one of the ratios drawn at
        random, nor in turn: an example's few forks (2-4) include the extraction's odd ones (a braided mask's
        loop measures 0.93), and with them the seeds' fans and areas moved past the tests of other delta rules
        (``test_branching_delta_balance``, ``_curve``, ``_forks``, ``_comb``) on one seed or another.
        """
        ratios = self.__dict__.get("_fork_ratios")
        if ratios is None:
            ratios = self.__dict__["_fork_ratios"] = fork_ratios(self.model.example)
        if not len(ratios):   # no fork in the example: the radius histogram alone
            return self._channel_radius(float(r_parent))
        return float(r_parent) * float(np.median(ratios))

    def _channel_radius(self, r_cap: float) -> float | None:
        """A delta's new channel: the radius (at most ``r_cap``, its parent's there) where the synthesized
        channels' radii fall shortest of the example's (beyond the paper, issue 23).

        The radii (per vertex, the same step ``h`` in both) are binned in :data:`CHANNEL_RADIUS_BINS`
        log-spaced bins over the example's range; the channel starts at the example's median radius in
        the bin where the synthesized vertices so far fall furthest short of the example's count (at
        most ``r_cap``): the paper's global histogram matching, for the radius a head is copied at.
        Copied from a random head, the channels were as thin as the example's thinnest wherever its
        thinnest head was drawn (length-weighted median radius 0.28-0.54 x the example's in 5 of 5
        seeds of a 512 px delta; after this, the trunk's start (``start_root``) and
        :func:`~branchnb.branching.growth._radius_keep`: 0.89-1.24 x).
        """
        cache = self.__dict__.get("_ex_radius_bins")
        if cache is None:
            r = self.model.example.thicknesses()
            r = r[np.isfinite(r) & (r > 0)]
            if not len(r):
                return None
            edges = np.geomspace(r.min() * 0.999, r.max() * 1.001, CHANNEL_RADIUS_BINS + 1)
            b = np.clip(np.searchsorted(edges, r, side="right") - 1, 0, CHANNEL_RADIUS_BINS - 1)
            share = np.bincount(b, minlength=CHANNEL_RADIUS_BINS).astype(np.float64)
            med = np.array([np.median(r[b == k]) if (b == k).any() else np.nan for k in range(CHANNEL_RADIUS_BINS)])
            cache = self.__dict__["_ex_radius_bins"] = (edges, share, med)
        edges, share, med = cache
        out = np.concatenate([np.asarray(st.radii, np.float64) for st in self.branches]) if self.branches \
            else np.zeros(0)
        ob = np.clip(np.searchsorted(edges, out, side="right") - 1, 0, CHANNEL_RADIUS_BINS - 1)
        have = np.bincount(ob, minlength=CHANNEL_RADIUS_BINS)
        ok = np.isfinite(med) & (edges[:-1] <= r_cap)
        if not ok.any():
            return None
        return float(min(med[int(np.argmax(np.where(ok, share - have, -np.inf)))], r_cap))

    @staticmethod
    def _fan_side(x0, theta0: float, new: np.ndarray, n: np.ndarray) -> np.ndarray:
        """Side of the trunk (heading ``theta0`` at ``x0``) each candidate head ends on: +1 or -1."""
        end = new[np.arange(len(new)), np.maximum(n, 1) - 1] - np.asarray(x0, np.float64)
        cross = np.cos(theta0) * end[:, 1] - np.sin(theta0) * end[:, 0]
        return np.where(cross >= 0.0, 1, -1)

    def _room_around(self, x0, length: float) -> bool:
        """Does any direction from ``x0`` lead on without a crossing (every one of the density
        profile's direction bins, :data:`.scoring._DIRECTION_BINS`)? When none does, no head can
        start there and the retry with every head is skipped (it found a start in none of 477 such
        cases on a 1000 px crack example, and in 100 of the 237 others)."""
        dens = self.density
        if dens is None:
            return True
        if self._all_dirs is None:
            a = np.arange(_DIRECTION_BINS) * (2.0 * np.pi / _DIRECTION_BINS)
            self._all_dirs = np.ascontiguousarray(np.c_[np.cos(a), np.sin(a)])
        n_samples = int(min(max(np.ceil(length / (dens.rho / 2.0)), 8), 48))
        # any bin without a crossing (any D_c), ending at the first one
        return bool(_kernels.free_direction(dens.grid, dens.cell, float(x0[0]), float(x0[1]), self._all_dirs, 0.0,
                                            False, float(length), n_samples, 0.02, _DIRECTION_BINS, np.inf))

    def _root_profile(self, bi: int, like: int | None) -> None:
        """A new root (not in a delta) started from any input branch's head (fewer than 3 input roots)
        tapers like an input root (beyond the paper, issue 23): the one whose head it copied, else
        ``like``; its radii are drawn back to that root's radius at the same arc length
        (:func:`~branchnb.branching.growth._pull_radii`) instead of the copied pieces'. (Applied to
        every root it made NOAA's q90 0.73-0.89 -> 0.57-1.09 x over 8 seeds but a 4-root procedural
        bolt example's 3 -> 3.8 x: kept to examples with fewer than 3 roots.)

        The copied pieces come from anywhere along the input's branches, mostly their thin parts: a
        storm whose one bolt is 3-4 px thick for its first third grew every bolt thin within ~50 px
        (length-weighted 90th-percentile radius 0.61-0.99 px against the example's 2.33).
        """
        st = self.branches[bi]
        ex = self.model.example.branches
        src = st.head_src if 0 <= st.head_src < len(ex) and ex[st.head_src].parent is None else like
        if src is None:
            return
        b = ex[src]
        p = np.asarray(b.points, np.float64)
        if len(p) < 2:
            return
        s = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
        st.profile = (s, np.asarray(b.thickness, np.float64))

    def _root_radius(self, roots: list[int]) -> float:
        """The radius a new root starts at when any input branch's head may start it (fewer than 3
        input roots; beyond the paper, issue 23): the ``k``-th synthesized root takes the head radius
        of the ``k``-th longest input root (cyclically).

        A head drawn from every input branch is mostly a thin side branch's: a storm whose one bolt is
        3-4 px thick for its first third grew every bolt at the 0.5 px of a side branch's head (the
        radius is continued relative to the tip's, :func:`~branchnb.branching.scoring._continue_radii`,
        and drawn back to the copied pieces' only 5 % per element,
        :func:`~branchnb.branching.growth._pull_radii`): length-weighted 90th-percentile radius
        0.61-0.99 px against the example's 2.33.
        """
        ex, heads = self.model.example, self.model.bending.heads
        order = sorted(roots, key=lambda i: -ex.branches[i].length)
        k = self.__dict__.get("_roots_started", 0)
        self.__dict__["_roots_started"] = k + 1
        self.__dict__["_root_like"] = order[k % len(order)]
        h = heads[order[k % len(order)]]
        return float(max(h["r0"], h["r1"]))

    def start_root(self, x, y, theta) -> int | None:
        model = self.model
        nb = len(model.example.branches)
        usable = [i for i in range(nb) if model.first_len[i] > 0]
        roots = [i for i in usable if model.example.branches[i].parent is None]
        # With fewer than 3 input roots every new root would start with the same
        # copied head; then any input branch's head may start a root.
        pool = roots if len(roots) >= 3 else usable
        Q = np.ones(len(pool))
        # beyond the paper: a delta's trunk starts as thick as the example's (any branch's head may start
        # it, and a channel's head made the trunk of a 250-512 px delta 0.3-0.5 x the example's thickness)
        r_set = None
        if self.drain is not None and roots:
            shape = np.shape(model.domain)
            r_set = float(np.mean([_inland_radius(model.example.branches[i], model.bending.heads[i], shape)
                                   for i in roots]))
        elif pool is not roots and roots:
            # beyond the paper (issue 23): any branch's head may start the root, the ones as thick as an
            # input root's head likelier (see _root_radius)
            r_set = self._root_radius(roots)
            hr = np.array([max(model.bending.heads[i]["r0"], model.bending.heads[i]["r1"]) for i in pool])
            Q = (np.minimum(hr, r_set) / np.maximum(np.maximum(hr, r_set), 1e-9)) ** ROOT_RADIUS_POWER
        if self.drain is not None:
            self.drain.set_trunk_start((x, y))
        if self.drain is not None and (self.drain.axis is not None or self.drain.trunk_axis is not None):
            # a delta's trunk sets out for the example's mouths (beyond the paper, issue 23, branching58): the
            # copied heads leave at the root's heading, and one along the frame could not turn to the sea
            wd = self.drain.way_down((x, y))
            theta = float(np.arctan2(wd[1], wd[0]))
        if self.drain is not None and self.drain.tail_depth is None:
            share = self._head_share() if self.drain.tail_share is None else self.drain.tail_share
            if share > 0 and (self.drain.axis is not None or self.drain.tail is not None):
                self.drain.set_tail_depth(share * float(self.drain.depth_at((x, y))[0]))
        c = self._start_branch(np.array([x, y], float), float(theta), pool, Q, None, None, 0, r_set=r_set)
        if c is not None and pool is not roots and self.drain is None and self.p.thickness_blend:
            self._root_profile(c, self.__dict__.get("_root_like"))
        return c

    def start_child(self, parent: int, vertex: int, toward=None, full: bool = False) -> int | None:
        model, fm = self.model, self.model.furcation
        st = self.branches[parent]
        caps = getattr(self, "_gen_cap", None)
        cap = caps.get(st.generation + 1) if caps else None
        if cap is not None and sum(b.generation == st.generation + 1 for b in self.branches) >= cap:
            return None   # a hub's forest has as many children of this generation as the example's
        k = fm.k
        # the parent's non-causal window at the vertex (window_features of the vertices around it only)
        lo, hi = max(vertex - k - 1, 0), min(vertex + k + 2, len(st.points))
        pts = np.asarray(st.points[lo:hi], np.float64)
        rad = np.asarray(st.radii[lo:hi], np.float64)
        v = vertex - lo
        # window_features(vertex_angles(pts), rad, k)[:, v] without the whole branch's windows:
        # angles padded with 0 (straight), radii with the end values
        idx = np.arange(v - k, v + k + 1)
        inner = (idx > 0) & (idx < len(pts) - 1)
        wa = np.zeros(2 * k + 1)
        if inner.any():
            wa[inner] = vertex_angles(pts)[idx[inner]]
        wr = rad[np.minimum(np.maximum(idx, 0), len(pts) - 1)]
        if self._child_pool is None:
            heads = fm.child_index
            usable = np.flatnonzero(model.first_len[heads] > 0)
            betas = np.array([model.bending.heads[h]["beta"] or 0.0 for h in heads[usable]])
            self._child_pool = (usable, betas)
        usable, betas = self._child_pool
        # a random share of the input furcations on large examples (MAX_CANDIDATES, speed)
        from .growth import MAX_CANDIDATES  # growth imports this module

        sub = None if full else self._share(len(usable), MAX_CANDIDATES // (2 if self.p.mirror_children else 1))
        if sub is not None:
            usable, betas = usable[sub], betas[sub]
        if len(usable) == 0:
            return None
        mirror = bool(self.p.mirror_children)
        if self._plain_start() and (full or len(usable) * (1 + mirror) <= MAX_CANDIDATES):
            # the common case in one compiled call (the same numbers as below and _start_branch)
            return self._plain_child(parent, vertex, pts, rad, v, wa, wr, usable, betas, mirror, toward, sub)
        heads = fm.child_index[usable]
        # Q of every furcation, then (mirror_children) of the same reflected: parent window and child
        # angles negated (compiled, :func:`._kernels.child_quality`)
        Q = _kernels.child_quality(fm.parent_windows_a, fm.parent_windows_r, np.asarray(usable, np.int64),
                                   wa, wr, mirror)
        if mirror:
            heads = np.concatenate([heads, heads])
            betas = np.concatenate([betas, -betas])
            mirror = np.repeat(np.array([False, True]), len(usable))
        else:
            mirror = np.zeros(len(heads), bool)
        theta0 = self._child_heading(pts, v, toward)
        if toward is not None:   # a child grown into a hole starts toward it (``_Filling._fill_far``)
            betas = np.zeros(len(heads))
        r_set = self._channel_start(float(rad[v])) if self.drain is not None else None
        c = self._start_branch(pts[v], theta0, heads, Q, parent, vertex, st.generation + 1,
                               betas=betas, mirror=mirror, r_cap=float(rad[v]), full=full, r_set=r_set)
        if c is not None and r_set is not None and self.branches[c].fork_ratio is None:
            self.branches[c].fork_ratio = min(1.0, r_set / max(float(rad[v]), 1e-9))
        if c is None and sub is not None and self._room_around(pts[v], 3.0 * self.p.m * self.p.h):
            return self.start_child(parent, vertex, toward, full=True)   # none of the share fits: all (rare)
        return c

    def _head_cut(self, full: np.ndarray, child: bool) -> int:
        """How many vertices of a head ``full`` (its start, then the copied vertices) a branch keeps: up to the
        first out of the frame or domain, and for a ``child`` in the frame band (growth.FRAME_BAND)."""
        ok = self._inside(full)
        if self.frame_band > 0 and child and len(full) > 2:
            # a child's head keeps off the frame like its Markov steps (growth.FRAME_BAND), its first vertex always
            ok[2:] &= self._band_ok(full[1], full[2:], self._frame_dist(full[0]) >= self.frame_band)[0]
        return len(full) if ok.all() else int(np.argmin(ok))

    def _head_tropism(self, x0, new: np.ndarray, n: np.ndarray) -> np.ndarray:
        """The tropism's factor of candidate heads (first vertices ``new``, ``n`` copied elements), from
        ``x0`` to a head's last vertex; a head leaving the frame is never favoured (at most 1): pulled out
        of the picture at once it is a stub cut by the frame (a 200 x 300 crack mask growing up: a child
        8 px long at its parent's end by the top edge, left out of the drawing as a burr, a gap)."""
        f = _tropism_factor(self.tropism, x0, new, n + 1)
        valid = np.arange(new.shape[1])[None, :] <= np.asarray(n, np.int64)[:, None]
        ins = (self._inside(new.reshape(-1, 2)).reshape(new.shape[:2]) | ~valid).all(1)
        return np.where(ins, f, np.minimum(f, 1.0))

    def _leave_factor(self, x0, new: np.ndarray, n: np.ndarray, score: np.ndarray) -> np.ndarray | float:
        """Score factor of a child's candidate heads (first vertices ``new``, ``n`` copied elements):
        :data:`LEAVE_FRAME` where :meth:`_head_cut` would cut the head short, else 1 (see :meth:`_child_leave`).

        Only candidates with a positive ``score`` are tested, and the frame band only where the heads can
        reach it from ``x0`` (a head is at most ``m + 1`` steps of ``h``)."""
        leave = self._child_leave()
        if leave >= 1.0 or not len(new):
            return 1.0
        n = np.asarray(n, np.int64)
        valid = np.arange(new.shape[1])[None, :] <= n[:, None]
        ins = self._inside(new.reshape(-1, 2)).reshape(new.shape[:2])
        # ... and the LEAVE_AHEAD elements straight on from its end: a head that ends heading out of the frame
        # at its edge leaves it at its first Markov step, a bare head all the same
        rows = np.arange(len(new))
        end = new[rows, n]
        prev = np.where((n > 0)[:, None], new[rows, np.maximum(n - 1, 0)], np.asarray(x0, np.float64)[None, :])
        d = end - prev
        d = d / np.maximum(np.hypot(d[:, 0], d[:, 1]), 1e-9)[:, None]
        ahead = end[:, None, :] + d[:, None, :] * (self.p.h * np.arange(1, LEAVE_AHEAD + 1))[None, :, None]
        ins_ahead = self._inside(ahead.reshape(-1, 2)).reshape(len(new), LEAVE_AHEAD).all(1)
        f = np.where((ins | ~valid).all(1) & ins_ahead, 1.0, leave)
        h_, w_ = self.shape
        x0 = np.asarray(x0, np.float64)
        reach = (self.p.m + 1) * self.p.h + self.frame_band + 1.0
        if self.frame_band > 0 and min(x0[0], x0[1], w_ - 1 - x0[0], h_ - 1 - x0[1]) < reach:
            for k in np.flatnonzero((np.asarray(score) > 0) & (f >= 1.0)):
                full = np.vstack([x0, new[k, : n[k] + 1]])
                if self._head_cut(full, True) < len(full):
                    f[k] = leave
        return f

    def _child_leave(self) -> float:
        """Score factor of a child's head that leaves the frame or domain before its end: :data:`LEAVE_FRAME`,
        1 (no factor) in a delta or at a shore, whose channels head for the sea beyond the domain, and in a
        band (``keep_in``: :data:`LEAVE_BAND` already)."""
        return 1.0 if (self.drain is not None or self.shore is not None or self.keep_in) else LEAVE_FRAME

    def _plain_start(self) -> bool:
        """Is a child's start a plain one (:meth:`_plain_child`): no guidance, drain, shore or band factor?"""
        return self.drain is None and self.shore is None and self.guidance is None and not self.keep_in

    @staticmethod
    def _child_heading(pts: np.ndarray, v: int, toward) -> float:
        """The parent's heading at its vertex ``v`` (``core.polyline.tangents(pts)[v]``: central
        difference, one-sided at an end), or the heading toward ``toward`` (a hole) when given."""
        if toward is not None:
            return float(np.arctan2(toward[1] - pts[v][1], toward[0] - pts[v][0]))
        tg = pts[min(v + 1, len(pts) - 1)] - pts[max(v - 1, 0)]
        nrm = float(np.hypot(tg[0], tg[1]))
        tg = tg / (nrm if nrm != 0 else 1.0)
        return float(np.arctan2(tg[1], tg[0]))

    def _plain_child(self, parent, vertex, pts, rad, v, wa, wr, usable, betas, mirror, toward, sub) -> int | None:
        """:meth:`start_child` with no guidance, drain or shore (:func:`._loop_kernels.child_start`, up to
        the draw; the reference is :meth:`_start_branch`), from the parent's window ``wa``/``wr`` at its
        vertex ``v`` of ``pts``/``rad`` and the input furcations ``usable`` (``sub``: a share of them)."""
        model, fm, p = self.model, self.model.furcation, self.p
        theta0 = self._child_heading(pts, v, toward)
        x0 = pts[v]
        hm = self.matcher
        use_hist = hm.wG > 0 and hm.n_nodes > 0
        rows_a, rows_r = _head_rows(model, hm.edges_a) if use_hist else (_E3, _E2)
        p_r, counts_r, r_scale = self._child_hist_args(use_hist)
        dens = self.density
        length = 3.0 * p.m * p.h
        dom = self.domain
        st = self.store
        heads, n, new, th, sign, score, chosen = _loop_kernels.child_start(
            np.asarray(usable, np.int64), np.asarray(betas, np.float64), fm.child_index, fm.parent_windows_a,
            fm.parent_windows_r, wa, wr, mirror, theta0, toward is not None, float(x0[0]), float(x0[1]),
            model.first_a, model.first_len, float(p.h), use_hist, rows_a, hm.p_a, hm.counts_a, rows_r, p_r,
            counts_r, hm.wG * hm.n_nodes / hm.m if use_hist else 0.0, dens is not None,
            dens.grid if dens is not None else _E_GRID, dens.cell if dens is not None else 1.0, length,
            int(min(max(np.ceil(length / (dens.rho / 2.0)), 8), 48)) if dens is not None else 8, 0.02,
            _DIRECTION_BINS, float(p.eps), self.shape[0], self.shape[1], self._e_dom if dom is None else dom,
            dom is not None, st._head, st._next, st._seg, st.p0, st.p1, st.n, st.cell, self._cap(), int(p.c), 1e-9,
            r_scale)
        f = self._leave_factor(x0, new, n, score)
        if self.tropism is not None:   # a child heads where the example's lines head too (.tropism)
            f = f * self._head_tropism(x0, new, n)
        if not np.isscalar(f) and (f != 1.0).any():   # (LEAVE_FRAME, tropism): chosen again
            score = score * f
            chosen = _kernels.ranked_free(score, np.asarray(x0, np.float64), np.ascontiguousarray(new, np.float64),
                                          np.asarray(n + 1, np.int64), st._head, st._next, st._seg, st.p0, st.p1,
                                          st.n, st.cell, self._cap(), int(p.c), dens is not None, 1e-9)
        j = self._draw(score, chosen.tolist())
        if j is None:
            if sub is not None and self._room_around(x0, length):
                return self.start_child(parent, vertex, toward, full=True)   # none of the share fits: all (rare)
            return None
        return self._make_branch(x0, theta0, j, heads, n, new, th, sign, parent, vertex,
                                 self.branches[parent].generation + 1, float(rad[v]), None, False)

