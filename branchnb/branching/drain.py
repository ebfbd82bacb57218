"""The downstream pull of a delta that drains (:class:`_Drain`) and its fan's spread (:func:`fan_spread`).

Beyond the paper (issue 23): an example whose roots lie far inland and whose
tips end at the region outside its domain drains (:func:`.domains._drains`);
its channels are pulled downstream, keep off the frame where it cuts the
land, and hold a fan of bearings. The delta tail rules (``TRUNK_TAIL``,
``STRAIGHT_TAIL``) act on its trunk. Split from :mod:`~branchnb.branching.domains`,
which re-exports every name.
"""

from __future__ import annotations

import numpy as np

from .drain_meander import (  # noqa: F401
    MEANDER_DEPTH,
    MEANDER_FADED,
    MEANDER_HOLD,
    MEANDER_LOBE,
    MEANDER_SIN,
    _faded_slope,
    _meander_of,
)

#: Strength of the pull toward the sea of an example that drains (``exp(kappa cos)``).
DRAIN_KAPPA = 2.0
#: An example that drains: the way down is this share the direction away from the delta's apex (when one
#: is set) and the rest the steepest descent to the sea. The descent alone is parallel near a straight
#: coast, so the channels ran side by side to the sea (bearings at the sea spread 7-8 degrees on a 512 px
#: delta against its example's 45; issue 23, branching19). The grower sets no apex any more: the direction
#: away from it is a branch's own heading where it leaves the trunk (it kept the trunk on whatever course
#: it took and ran children beside it); each channel has its own bearing instead (:meth:`_Drain.bearing`).
FAN_WEIGHT = 0.5
#: An example that drains: a step heading back inland (cosine to the way down below this) is forbidden.
UPSTREAM_COS = -0.25
#: An example that drains: the pull's strength (x ``kappa``) on the first head of a channel that leaves the
#: trunk below the delta's head. There the way down is the trunk's own direction, so the full pull
#: (``e^kappa`` against a sideways start) turned every furcation down the trunk and the channels ran
#: side by side to the sea (their bearings 5 % of the diagonal inland spread 13-16 degrees on a 1000 px delta
#: against its example's 41, issue 23); without it the example's furcation angles (``beta``) decide.
HEAD_PULL = 0.0
#: An example that drains: a channel leaving its parent below the delta's head keeps its own bearing (the
#: heading of its first head, at most this many radians off the descent) as the fan direction of its way
#: down. The direction away from the apex is its parent's own direction where it leaves the trunk (or a
#: channel) below the head, so children ran beside their parents to the sea.
FAN_MAX = float(np.radians(60.0))
#: ... and at least this many radians off its parent's way down where it leaves it (half the smallest
#: furcation angle of the 250-1000 px delta examples, 46-91 degrees): a bearing close to its parent's ran the
#: child beside it to the sea.
FAN_SPLIT = float(np.radians(25.0))
#: ... and its way down is this share its bearing, the rest the descent (was 0.5: near a straight coast the
#: descent turned every channel straight down, and the channels of 250-1000 px deltas reached the sea with
#: headings 5 % of the diagonal inland spread 6-44 degrees against the example's 41-50; the bearing is kept
#: off the frame, :meth:`_Drain._to_sea`) ...
BEARING_WEIGHT = 1.0
#: ... and a channel with its own bearing follows it this many times more firmly (``kappa``) than a trunk
#: follows the descent.
FAN_KAPPA_GAIN = 2.0
#: ... and, beyond the paper, a candidate whose chord runs ``a`` radians off that bearing gets its score times
#: ``exp(-FAN_HOLD a)``. ``exp(kappa cos a)`` is flat near the bearing (30 degrees off cost a factor 1.7
#: at ``kappa`` 4), weaker than the spread of the matching scores (a factor 2-3 between the best and the
#: median candidate), so a channel kept the heading it left its parent with and ran up to 30-40 degrees off
#: its bearing; the linear term makes that cost a factor ``e^(FAN_HOLD pi / 6)`` ~ 500 (issue 23, branching43:
#: headings 5 % of the diagonal inland spread 16-47 degrees, median 30, over 3 delta shapes x 512/1000 px x
#: 3 seeds, now 28-57, median 38; the examples' 41-50; 4 and 8 gave medians 32 and 36).
FAN_HOLD = 12.0
#: ... the chord that hold measures runs from the channel's point this share of the frame's diagonal back
#: along it (or its start when shorter) to the candidate's end, not from the tip: held step by step the
#: channels kept their bearing but ran ruler-straight (deviation from their chord 0.7-4.9 % of its length
#: against the examples' 3.4-10 %); over a window a step may wander and the channel curve, while its mean
#: heading over the window keeps the bearing (beyond the paper; issue 23, branching45: deviation median 2.2 ->
#: 3.9 % over 3 delta shapes x 512/1000 px x 6 seeds, fan spread median 34.9 -> 33.9 degrees, lowest seed
#: 21.7 -> 21.4; a window of 0.08-0.15 x the diagonal down to the sea gave the curve but the fan 3 degrees
#: narrower, and alone (without FAN_WHOLE) it let a channel drift: lowest seed 8-17 degrees) ...
FAN_WINDOW = 0.08
#: ... up to where the channel's depth (distance to the sea) falls to this share of its start's; below it
#: the chord runs from the tip again, so the channel reaches the sea on its bearing.
FAN_STRAIGHT = 0.6
#: ... and a candidate is off its bearing by the larger of its windowed chord's angle and this x that of the
#: chord from the channel's start (a channel may curve about its bearing but not drift off it).
FAN_WHOLE = 1.0
#: A frame guard for channels that curve (beyond the paper; issue 23, branching47): within this many x
#: :attr:`_Drain.margin` of a side of the frame that cuts the land the hold is step by step again (the chord
#: from the tip, no window, no whole chord) ... With the guard, :data:`FRAME_POWER` and :data:`FAN_CHILD`
#: (``python -m branchnb.branching._delta_fan_check bottom,top,left,right 320,512 3 OUT CACHE -,4,9``: 4 sea
#: sides x 3 masks x 3 seeds; 1000 px: 4 sides x 3 seeds; main -> this): deviation from the chord median
#: 320 px 0.054 -> 0.069, 512 px 0.040 -> 0.051, 1000 px 0.021 -> 0.036 (examples 0.037-0.122); frame share
#: mean 0.0121 -> 0.0103 / 0.0013 -> 0.0014 / 0.0037 -> 0.0058 (max 0.129 -> 0.084 / 0.016 -> 0.029 /
#: 0.029 -> 0.035, the 1000 px one the trunk's, which has no bearing); fan spread median 32.8 -> 33.6 /
#: 34.3 -> 35.5 / 31.0 -> 32.5; no crossings; far share and channels reaching the sea unchanged.
FAN_FRAME_GUARD = 2.0
#: ... and a channel with its own bearing takes the frame factor (:meth:`_Drain.frame_factor`) to this
#: power. ``exp(-10 (1 - d / margin))`` costs a candidate 8 px from the frame a factor ~100 on a 256 px
#: delta, less than the hold's 30 degrees off the bearing (~500): a bearing that passes near a corner
#: pinned its channel along the frame there, and curving about it (``FAN_WINDOW``, ``FAN_WHOLE``) did so
#: more (a sea-left 256 px delta's frame share, mean over 6 seeds: 0.016 -> 0.032, the CI's limit 0.03;
#: with the guard and this power 0.014; masks 0, 4, 1: 0.014/0.016/0.020 on main -> 0.011/0.014/0.010).
FRAME_POWER = 3.0
#: A channel's channel (its parent has its own bearing) takes a bearing this share of the way from its
#: parent's way down toward the descent (at least :data:`FAN_SPLIT` off its parent's; beyond the paper,
#: issue 23, branching47). It took the descent itself (it parts toward it at its furcation angle, 46-91
#: degrees, more than its parent's bearing is off the descent), so the channels of channels and the trunk
#: all reached the sea straight down, which capped the fan's spread (34-38 degrees against the
#: examples' 41-50).
FAN_CHILD = 0.5
#: A trunk of a delta with an axis (:meth:`_Drain.set_axis`): a candidate whose chord runs ``a`` radians off
#: the way to the example's mouths gets its score times ``exp(-TRUNK_HOLD a)`` (beyond the paper; issue 23,
#: branching58). ``exp(kappa cos a)`` alone let a trunk entering through a side of the frame run along it.
TRUNK_HOLD = 8.0
#: ... only when the axis runs at least this far off the descent's mean direction along it (radians): on
#: deltas whose trunk runs down the descent (the ``delta`` and ``fan0`` kinds, 1-10 degrees) the axis rules left
#: a seed's channels on one side of the trunk or in one bundle (fan 1 degree against 45) and thinned trunks, so
#: there the descent's rules stay (byte-identical structures).
AXIS_MIN = float(np.radians(15.0))
#: ... and a channel takes one of the example's headings at the sea at least 0.9 x the smallest gap between
#: them off its parent's (at most FAN_SPLIT, at least this): with FAN_SPLIT alone a trunk's children could
#: take only the outermost of headings 17-22 degrees apart and bunched there (fan 38 against 21 degrees).
FAN_SPLIT_MIN = float(np.radians(10.0))
#: ... and below the delta's head (:func:`.delta_fan.head_share` of its start's depth) the trunk runs on the
#: example's root's heading at the sea (:func:`.delta_fan.root_offset`), as the example's root goes on as one
#: of its channels: run on along the axis, the trunk added a channel in the fan's middle the example did not
#: have (a 512 px delta: headings at the sea -42/0/22/48 degrees off the axis against the example's -56/22/58).
#: Off by default: on (``_delta_fan_check bottom,left 300/512 3``) the fan of the ``delta`` kind at 512 px rose
#: 36.5/33.8 -> 46.9/47.4 degrees (example 50.0/50.2) and fan0 300 px 43.2 -> 34.7 (35.2), but a trunk whose
#: example root reaches the sea at a shallow angle ran along the coast with a hook at its mouth (fan55 300 px,
#: spread 23.8 -> 16.5 against 24.0, lowest seed 7.3) and the trunk bearing error of fan0/delta 300 px rose
#: 3.6/9.1 -> 11.1/12.6 degrees.
TRUNK_TAIL = False
#: A delta whose trunk runs down the descent (no axis, :data:`AXIS_MIN`): below the depth where the example's
#: longest root lets its first channel that reaches the sea part (:func:`.delta_fan._tail_share` of its start's
#: depth) the trunk turns into one of the fan's channels, on the example's root's heading at the sea off the
#: descent (:func:`.delta_fan.root_offset`), held to it as an axis trunk is (:data:`TRUNK_HOLD`) and re-aimed at
#: the sea from where it is when a straight run would meet the frame first (:meth:`_to_sea`). Beyond the paper
#: (issue 23, branching65): the trunk went on down the descent in the fan's middle, a channel the example does not
#: have. ``python -m branchnb.branching._delta_fan_check bottom 300,512,1024 3 OUT CACHE - delta,fan0`` (fan
#: spread median / lowest seed, degrees): ``delta`` 28.2/25.5, 28.1/27.3, 31.4/27.2 -> 37.0/32.5, 45.7/14.8,
#: 41.5/34.9 (examples 38.9, 50.0, 45.8); ``fan0`` 36.6/34.2, 40.6/9.2, 33.2/1.5 -> 29.2/26.7, 33.4/24.1, 37.2/36.8
#: (examples 35.2, 34.8, 38.7). The channels keep the descent's bearings about it: the fan is lopsided in some
#: seeds (trunk bearing error median 4-9 -> 5-14 degrees; all channels of a 300 px ``fan0`` on the trunk's
#: side). Only when the example's root reaches the sea at least :data:`FAN_SPLIT_MIN` off the descent (a root
#: that carries on in the middle keeps the old rule), the heading capped at :data:`TAIL_MAX` off the descent so
#: the trunk meets the coast steeply (``_delta_fan_check``'s coast share 0 on every kind and seed).
#: branching68: only where the example's trunk itself turns at its head (:func:`.delta_fan._trunk_turns`: its
#: thickest channel there >= :data:`.delta_fan.TURN_WIDTH` x as wide as the one carrying its line on; a root
#: that merely follows an outer channel is no turn), and a channel leaving the turned trunk on the descent's
#: side takes the fan's other half (far side, then middle; :meth:`bearing`). Same command, ``side``: the
#: smaller share of channel length below the head on one side of the trunk line: ``fan0`` identical to main
#: again (fan 36.6/40.6/33.2, bearing error median 6.3/9.4/7.1 against branching65's 13.0/14.3/11.4);
#: ``delta`` fan median / lowest seed 37.0/32.5, 45.7/43.8, 41.5/34.7 (512 px lowest seed 14.8 -> 43.8, all
#: its channels had left on the trunk's side), side median / lowest 0.41/0.37, 0.36/0.31, 0.30/0.15
#: (examples 0.41, 0.37, 0.42; main 0.29/0.28, 0.32/0.18, 0.38/0.19); bearing error median 5.0/10.0/6.2
#: (main 7.4/3.9/5.5: the turned trunk's start-to-mouths chord is off the example's in some seeds).
STRAIGHT_TAIL = True
#: A delta whose trunk runs down the descent (no axis, :data:`AXIS_MIN`) and carries on past its head (no turn,
#: :data:`STRAIGHT_TAIL`): its trunk heads for the example's mouths (moved as far as its start lies from the
#: example's, :meth:`_Drain.set_trunk_start`) and is held to that way as an axis trunk is (:data:`TRUNK_HOLD`;
#: beyond the paper, issue 23, branching79). With the pull of the descent alone the matching steered the trunk
#: and it drifted toward a corner of the frame, the mouths' mean with it (``_delta_fan_check bottom,left 512 5
#: ... fan0,mean0``, sea at the bottom/left: trunk bearing error mean over 5 seeds 4.4/5.7/3.6/2.3 degrees, median
#: 14.1/10.3/15.7/20.6 -> 4.8/5.0/3.9/1.2; the smaller side's share of the channels below the head, median
#: 0.19/0.30/0.35/0.06 -> 0.41/0.34/0.39/0.41, example 0.40; ``_delta_tree_check`` with
#: :func:`.delta_fan._even_fork`). A trunk that turns (the ``delta`` kind) keeps main's rule above its turn:
#: held there together with other changes its bearing error median went 5.0/9.5 -> 7.1/4.2, no clear gain.
STRAIGHT_HOLD = True
TAIL_MAX = float(np.radians(60.0))
#: A straight delta's trunk that turns at its head (:data:`STRAIGHT_TAIL`) into the example's outermost
#: channel on its side (no heading of the example's channels at the sea, :func:`.delta_fan.fan_offsets` off the
#: descent, lies beyond its root's): no channel leaves the synthesized trunk on the outer side of its turn at
#: or below the delta's head (:meth:`_Drain.outer_side`; within :data:`TAIL_OUTER_HEAD` x the tail's depth), its
#: channels take the fan's other half (:meth:`_Drain.bearing`). Beyond the paper (issue 23, branching88): on a
#: delta whose trunk runs 20 degrees off the descent (``mean20``) the trunk turned 35 degrees to one side and
#: its first channel left it on the same side, even further out; every channel below the head lay on one side
#: of the trunk's line. ``_delta_fan_check bottom,left 512 5 ... mean20`` (sea at the bottom/left; with
#: :attr:`_Drain.tail_offsets`): the smaller side's share of the channel length below the head, median (lowest
#: seed) 0.24 (0.00) / 0.24 (0.19) -> 0.37 (0.27) / 0.46 (0.43), examples 0.42 / 0.39; fan spread median
#: 27.5/27.1 -> 28.9/27.1 degrees (21.2/21.1); but the trunk's bearing error median 5.0/3.5 -> 8.9/9.8 degrees
#: (twice the example's channels reach the sea, on the inner side now, and the mouths' mean moves inward).
TAIL_OUTER = True
#: A turned trunk that is the example's outermost channel (:data:`TAIL_OUTER`) heads above its turn for the
#: example's head (where the example's longest root reaches the tail's depth share; moved as far as its start
#: lies from the example's, :meth:`_Drain.set_trunk_start`) and is held to that way (:data:`TRUNK_HOLD`) as a
#: straight delta's trunk is (:data:`STRAIGHT_HOLD`). Beyond the paper (issue 23, branching94): with the
#: descent alone the trunk of a delta tilted 20 degrees (``mean20``) ran straight down to its head, its channels
#: parted that far inland of the example's and the mouths' mean moved with them.
HEAD_HOLD = True
#: ... only where the example's trunk turns at its head, where its first channel parts (its tail's depth share,
#: :func:`.delta_fan._tail_share`, at least this x its first furcation's, :func:`.delta_fan.head_share`):
#: where it turns further down (the ``delta`` kind: 0.27 against 0.66) channels below the turn lie on both
#: sides of it, and without them the fan of a 300 px ``delta`` narrowed (test_branching_delta_tail: spread
#: median 22.8 degrees against the example's 38.9).
TAIL_OUTER_AT_HEAD = 0.8
#: ... from this share above the tail's depth down (the head on the synthesized trunk is found at its first
#: vertex at or below that depth; a channel may leave a vertex or two above it)
TAIL_OUTER_HEAD = 1.05


class _Drain:
    """Downstream pull for examples that drain (a delta, see ``StructureModel.drains``).

    A candidate heading at angle ``phi`` to the way down to the region
    outside the domain (the steepest descent of the distance to it) gets
    its score times ``exp(kappa cos phi)``: heading to the sea is
    ``e^(2 kappa)`` ~ 55 x likelier than heading back inland, sideways
    ``e^kappa`` less than straight down. Going beyond the paper, whose
    Markov chain alone has no notion of downstream: without it a delta's
    trunk wanders and rarely reaches the sea. The pull alone still let
    side channels head back inland (a delta with its sea on the left or
    top: 5-26 % of the branch length in some seeds), so a step heading
    back inland (cosine below ``UPSTREAM_COS``) or bringing a branch's tip
    upstream of its start is forbidden, children's first steps included.

    Also beyond the paper, the image frame where it cuts the land (every
    side of the frame but the sea's) is no place for a channel: a
    candidate that ends within ``margin`` pixels of such a side
    (``max(8, 6 %`` of the image's smaller side``)``) gets its score times
    ``exp(-10 (1 - d / margin))`` (``d`` the distance of its end), so of two
    candidates the one farther from the frame wins, and none that touches
    it (any new point within 3 px) is kept. New roots are exempt (they
    start at the frame and head inward).
    Without it the sea's pull drags branches along or into the frame where
    it runs downstream (a delta whose sea is on the left: branches along
    the bottom edge); the example's channels only leave through it where
    they enter (the trunk), and a root heading inward moves away from it.
    """

    def __init__(self, domain: np.ndarray, kappa: float = DRAIN_KAPPA):
        from scipy import ndimage as ndi

        dom = np.asarray(domain, bool)
        #: distance (px) of every pixel to the region outside the domain (the sea)
        self.depth = ndi.distance_transform_edt(dom).astype(np.float32)
        depth = ndi.gaussian_filter(self.depth, 4.0)
        gy, gx = np.gradient(-depth)
        n = np.hypot(gx, gy) + 1e-12
        self.down = np.stack([gx / n, gy / n], -1).astype(np.float32)
        self.kappa = float(kappa)
        h, w = dom.shape
        self.shape = (h, w)
        self.margin = max(8.0, 0.06 * min(h, w))
        # the sides of the frame that cut the land (most of the side in the domain), not the sea's
        sides = (dom[0], dom[-1], dom[:, 0], dom[:, -1])
        self.cut = tuple(bool(side.mean() >= 0.5) for side in sides)
        #: a fan's apex (x, y) for :meth:`way_down` without a bearing; None (the grower's) = descent only
        self.apex: np.ndarray | None = None
        #: the delta's head on the trunk (x, y) once found (:meth:`set_head`)
        self.head_at: np.ndarray | None = None
        self.head = False
        #: the example's axis (unit x, y, :func:`.delta_fan.delta_axis`), the mean of its mouths (x, y; None
        #: when the synthesis frame is not the example's), the headings of its channels at the sea off the
        #: axis (radians, :func:`.delta_fan.fan_offsets`) and how often each was given (:meth:`set_axis`);
        #: None = the descent alone
        self.axis: np.ndarray | None = None
        self.target: np.ndarray | None = None
        #: a delta whose trunk runs down the descent: the example's axis and mouths' mean all the same, for
        #: its trunk alone (:data:`STRAIGHT_HOLD`; the channels keep the descent's rules)
        self.trunk_axis: np.ndarray | None = None
        self.trunk_target: np.ndarray | None = None
        self._trunk_from: np.ndarray | None = None
        self.offsets: np.ndarray | None = None
        self.used: np.ndarray | None = None
        #: the example's root's heading at the sea off the axis (radians; None: it ends at the head), and the
        #: depth below which the synthesized trunk takes it (:meth:`set_tail_depth`; None: not yet known)
        self.tail: float | None = None
        self.tail_depth: float | None = None
        #: the example's trunk's meander (:func:`_meander_of`), else None
        self.meander: tuple[float, float, float] | None = None
        self._meander_len: dict = {}   # per trunk start: the straight way's run down to MEANDER_DEPTH
        self._tail_dir: np.ndarray | None = None
        #: where the trunk takes ``tail`` as a share of its start's depth (None: the delta's head,
        #: :func:`.delta_fan.head_share`; :data:`STRAIGHT_TAIL`)
        self.tail_share: float | None = None
        #: channels given the fan's other half below a straight delta's turned trunk so far (:meth:`bearing`)
        self._tail_kids = 0
        #: the turned trunk's tail is the example's outermost channel on its side (:data:`TAIL_OUTER`), the
        #: example's other channels' headings at the sea off the descent and how often each was given
        self.tail_outer = False
        self.tail_offsets: np.ndarray | None = None
        self.tail_used: np.ndarray | None = None

    def set_tail_depth(self, depth: float) -> None:
        """Below ``depth`` (the delta's head on the synthesized trunk) the trunk takes the example's root's
        heading at the sea (:data:`TRUNK_TAIL`)."""
        self.tail_depth = float(depth)
        self._tail_dir = None

    def set_axis(self, example, domain) -> None:
        """Learn the delta's axis and its channels' headings from ``example`` grown in ``domain``.

        Beyond the paper (issue 23, branching58): the trunk heads for the example's mouths
        (:meth:`way_down`) instead of down the steepest descent, and each channel's bearing is one of the
        example's headings at the sea off that axis (:meth:`bearing`). With the descent the trunk always
        reached the sea straight across the coast: a delta whose trunk enters 55 degrees off it ran its
        trunk along the frame and its channels in one bundle (fan spread 0-3 degrees against 24).
        """
        from .delta_fan import delta_axis, fan_offsets, root_offset

        dom = np.asarray(domain, bool)
        ax = delta_axis(example, dom)
        if ax is None:
            return
        start, target = ax
        self.meander = _meander_of(example, dom)
        v = target - start
        axis = v / float(np.hypot(*v))
        # the descent's mean direction along the axis (at the trunk's start alone a corner turns it)
        dn = np.mean([self.descent(start + t * v) for t in np.linspace(0.0, 1.0, 17)], axis=0)
        dn = dn / max(float(np.hypot(*dn)), 1e-9)
        if float(np.arccos(np.clip(axis @ dn, -1.0, 1.0))) < AXIS_MIN:
            # a trunk along the descent: the descent's rules (tuned on such deltas) stay, but the trunk
            # turns into one of the fan's channels below the delta's head (STRAIGHT_TAIL); one that carries
            # on heads for the example's mouths (STRAIGHT_HOLD)
            if STRAIGHT_TAIL:
                self._straight_tail(example, dom, dn)
            if HEAD_HOLD and self.tail_outer and dom.shape == self.shape:
                self._hold_to_head(example, dom, start)
            if STRAIGHT_HOLD and self.tail is None:
                self.trunk_axis = axis
                self.trunk_target = target if dom.shape == self.shape else None
                self._trunk_from = start
            return
        self.axis = axis
        self.target = target if dom.shape == self.shape else None
        off = fan_offsets(example, dom, self.axis)
        if len(off):
            self.offsets = off
            self.used = np.zeros(len(off))
            # the trunk's own way to the sea: the example's root's heading there (its tail, below the head)
            tail = root_offset(example, dom, self.axis) if TRUNK_TAIL else None
            self.tail = tail
            self.used[int(np.argmin(np.abs(off - (0.0 if tail is None else tail))))] += 1.0

    def _straight_tail(self, example, dom: np.ndarray, dn: np.ndarray) -> None:
        """:data:`STRAIGHT_TAIL`: the example's root's heading at the sea, off the
        descent's mean direction ``dn`` along the axis, and the depth share where the trunk takes the former."""
        from .delta_fan import _tail_share, _trunk_turns, fan_offsets, head_share, root_offset

        tail = root_offset(example, dom, dn)
        share = _tail_share(example, dom)
        if tail is None or abs(tail) < FAN_SPLIT_MIN or share <= 0.0:
            return
        if not _trunk_turns(example, dom):
            # the example's trunk carries on straight past its head (its root merely follows an outer
            # channel): the old rule, channels on both sides of a straight trunk (branching68)
            return
        # the channels keep the descent's bearings (spread about it): taken from the example's headings
        # (set_axis) they bunched on one side of the trunk, and parting at the trunk's turn (not at the
        # example's first furcation) squashed the fan against the coast
        self.tail = float(np.clip(tail, -TAIL_MAX, TAIL_MAX))
        self.tail_share = share
        if TAIL_OUTER and share >= TAIL_OUTER_AT_HEAD * head_share(example, dom):
            offs = fan_offsets(example, dom, dn)
            self.tail_outer = bool(len(offs) and (tail >= offs.max() - 1e-6 if tail > 0 else tail <= offs.min() + 1e-6))
            if self.tail_outer and len(offs) > 1:
                # the other channels' headings at the sea, the trunk's (the outermost) left out
                self.tail_offsets = np.delete(offs, int(np.argmin(np.abs(offs - tail))))
                self.tail_used = np.zeros(len(self.tail_offsets))

    def _hold_to_head(self, example, dom: np.ndarray, start: np.ndarray) -> None:
        """:data:`HEAD_HOLD`: above its turn a turned outermost trunk heads for the example's head (where its
        longest root reaches the tail's depth share), held to that way as a straight delta's trunk is."""
        roots = [b for b in example.branches if b.parent is None and len(b.points) >= 2]
        if not roots or self.tail_share is None:
            return
        root = max(roots, key=lambda b: float(np.hypot(*np.diff(np.asarray(b.points, float), axis=0).T).sum()))
        p = np.asarray(root.points, np.float64)
        d = self.depth_at(p)
        below = np.flatnonzero(d <= self.tail_share * float(d[0]))
        if not below.size or below[0] == 0:
            return
        head = p[int(below[0])]
        v = head - p[0]
        n = float(np.hypot(*v))
        if n < 1.0:
            return
        self.trunk_axis = v / n
        self.trunk_target = head
        self._trunk_from = p[0].copy()

    def outer_side(self, at) -> tuple[int, float]:
        """The side of a turned trunk no channel may leave it on at ``at`` (:data:`TAIL_OUTER`; +1: at a
        positive angle off the second value, the tail's heading there, image frame); 0 where any may.

        The side is taken off the tail's heading (the descent turned by the example's root's heading at the
        sea), not the trunk's own there: a trunk that meanders down to its head headed 40 degrees off its
        tail at some vertices, and a head leaving it inward of its own heading ran outside the tail."""
        if not self.tail_outer or self.tail is None or self.tail_depth is None:
            return 0, 0.0
        if self.depth_at(at)[0] > TAIL_OUTER_HEAD * self.tail_depth:
            return 0, 0.0
        return (1 if self.tail > 0 else -1), self._ref(at) + self.tail

    def _in_tail(self, at) -> bool:
        """Is ``at`` below the depth where a trunk takes the example's root's heading (:meth:`way_down`)?"""
        return self.tail is not None and self.tail_depth is not None and self.depth_at(at)[0] <= self.tail_depth

    def set_trunk_start(self, at) -> None:
        """A straight delta's trunk starts at ``at`` (:data:`STRAIGHT_HOLD`): its target moves as far as
        its start lies from the example's, so it runs on the example's bearing.

        The one tree of a delta enters within ~3.5 % of the diagonal of the example's entry
        (:meth:`.roots.RootModel.sample`); aimed at the example's mouths from there, the trunk ran up to
        4-6 degrees off the example's bearing on 256-1024 px deltas. Only the first trunk moves it."""
        if self.trunk_target is None or self._trunk_from is None:
            return
        h, w = self.shape
        shift = np.asarray(at, np.float64) - self._trunk_from
        self.trunk_target = np.clip(self.trunk_target + shift, 0.0, [w - 1.0, h - 1.0])
        self._trunk_from = None

    def held(self, at) -> bool:
        """Is a trunk at ``at`` held to a way to the sea (:data:`TRUNK_HOLD`): an axis, a straight delta's
        (:data:`STRAIGHT_HOLD`) or its tail?"""
        return self.axis is not None or self.trunk_axis is not None or self._in_tail(at)

    def _ref(self, at) -> float:
        """Angle of the direction the fan's bearings are measured from: the axis, else the descent."""
        d = self.descent(at) if self.axis is None else self.axis
        return float(np.arctan2(d[1], d[0]))

    def _pick_offset(self, at, off: float, a_p: float, trunk: bool) -> float | None:
        """:func:`.delta_fan.pick_offset` of the example's headings (None without them), counted as used."""
        if self.offsets is None:
            return None
        from .delta_fan import pick_offset

        # channels parting less than FAN_SPLIT where the example's headings lie closer (its smallest gap)
        gaps = np.diff(self.offsets)
        split = float(np.clip(0.9 * gaps.min(), FAN_SPLIT_MIN, FAN_SPLIT)) if len(gaps) else FAN_SPLIT
        k = pick_offset(self.offsets, self.used, off, a_p, trunk, split)
        if k is None:
            return None
        self.used[k] += 1.0
        return float(self.offsets[k])

    def frame_distance(self, pts: np.ndarray) -> np.ndarray:
        """Distance of ``pts`` ((..., 2) x, y) to the nearest side of the frame that cuts the land."""
        h, w = self.shape
        x, y = pts[..., 0], pts[..., 1]
        d = np.full(x.shape, np.inf)
        for cut, v in zip(self.cut, (y, h - 1 - y, x, w - 1 - x)):
            if cut:
                d = np.minimum(d, v)
        return d

    def frame_factor(self, tip, points: np.ndarray, n_new: np.ndarray) -> np.ndarray:
        """Score factor of candidates ``points`` ((C, M, 2), the first ``n_new`` new) from ``tip``."""
        if not any(self.cut):
            return np.ones(len(points))
        fd = self.frame_distance(points)
        n = np.maximum(n_new, 1)
        valid = np.arange(points.shape[1])[None, :] < n[:, None]
        closest = np.where(valid, fd, np.inf).min(1)
        end = fd[np.arange(len(points)), n - 1]
        f = np.exp(-10.0 * np.clip(1.0 - end / self.margin, 0.0, 1.0))
        return np.where(closest < 3.0, 0.0, f)

    def descent(self, at) -> np.ndarray:
        """Unit direction (x, y) of the steepest descent to the sea at ``at``."""
        h, w = self.down.shape[:2]
        x, y = np.clip(np.rint(np.asarray(at, np.float64)).astype(int), 0, [w - 1, h - 1])
        return self.down[y, x].astype(np.float64)

    def bearing(self, at, heading, parent_fan=None, spread: float | None = None) -> np.ndarray:
        """A channel's own fan bearing: the unit ``heading`` it left its parent with, at least
        :data:`FAN_SPLIT` radians off its parent's way down there (``parent_fan``: the parent's own
        bearing, None for a trunk) and at most :data:`FAN_MAX` off the descent at ``at`` (never
        upstream); where that limit would lay it along its parent's, it takes the parent's other side.
        ``spread`` (radians, the example's outer channels', :func:`fan_spread`): a trunk's child's
        bearing is this far off the descent on the side of ``heading``; a channel's child parts
        toward the descent, :data:`FAN_CHILD` of the way from its parent's way down.

        With an axis learned from the example (:meth:`set_axis`; beyond the paper, issue 23, branching58) the
        angles are taken off the axis instead of the descent, and the bearing is one of the example's own
        headings at the sea (:meth:`_pick_offset`, the least used so far) when one fits the side and
        :data:`FAN_SPLIT`; the rule above (``spread`` at most the example's widest heading) only otherwise.
        Over 3 delta kinds whose trunk runs 25-40 degrees off the descent (fan30, fanm40, fan55) x 2 sea sides
        x 300/512/1024 px x 3 seeds (``python -m branchnb.branching._delta_fan_check bottom,left 300,512,1024 3
        OUT CACHE - fan30,fanm40,fan55``, 54 structures) the trunk's bearing error (start to the mouths' mean,
        against the example's) fell from median 12.7 / max 22.1 to 3.8 / 16.4 degrees and the fan spread's
        distance from the example's from median 6.4 / max 28.4 to 3.8 / 19.9 (lowest seed per kind 0-10 ->
        18-22 degrees; a trunk entering through a side of the frame no longer runs along it). Deltas whose
        trunk runs down the descent (:data:`AXIS_MIN`) are unchanged."""
        a_d = self._ref(at)
        wrap = lambda v: float(np.angle(np.exp(1j * v)))  # noqa: E731
        off = wrap(float(np.arctan2(heading[1], heading[0])) - a_d)
        if self.offsets is not None:
            # the example's headings at the sea, off its axis (set_axis)
            pd = self.way_down(at, parent_fan)
            pick = self._pick_offset(at, off, wrap(float(np.arctan2(pd[1], pd[0])) - a_d), parent_fan is None)
            if pick is not None:
                return self._to_sea(at, a_d, pick)
            if spread is not None and len(self.offsets):
                # no heading fits: the old rule, but no wider than the example's widest off the axis
                spread = min(spread, float(np.abs(self.offsets).max()))
        if parent_fan is None and spread is not None and self.axis is None and self._in_tail(at):
            # STRAIGHT_TAIL: the trunk took one of the fan's outer headings; a channel leaving it on the
            # descent's side takes the fan's other half in turn (the far side, then the middle): sided
            # off the descent alone they all took the trunk's side and ran beside it
            if self.tail_offsets is not None:
                # TAIL_OUTER: each channel takes the example's heading given least so far (the nearest among
                # equals), as an axis delta's (_pick_offset): the far side then the middle put the mouths' mean
                # off the example's (trunk bearing error median 3 -> 11 degrees on mean20 512 px)
                u = np.flatnonzero(self.tail_used == self.tail_used.min())
                k = int(u[np.argmin(np.abs(self.tail_offsets[u] - off))])
                self.tail_used[k] += 1.0
                return self._to_sea(at, a_d, float(self.tail_offsets[k]))
            sgn = 1.0 if self.tail >= 0 else -1.0
            if wrap(off - self.tail) * sgn < 0:
                k = self._tail_kids
                self._tail_kids += 1
                return self._to_sea(at, a_d, -sgn * spread if k % 2 == 0 else 0.0)
        if parent_fan is None and spread is not None:
            return self._to_sea(at, a_d, spread if off >= 0 else -spread)
        pd = self.way_down(at, parent_fan)
        a_p = wrap(float(np.arctan2(pd[1], pd[0])) - a_d)
        rel = wrap(off - a_p)
        if parent_fan is not None and spread is not None and abs(a_p) >= FAN_SPLIT:
            # a channel's channel parts toward the descent, between its parent and the trunk (the
            # example's does; toward the outside they ran side by side, nearly along the coast), part of
            # the way (FAN_CHILD)
            rel = -float(np.sign(a_p)) * float(np.clip(min(abs(rel), FAN_CHILD * abs(a_p)), FAN_SPLIT, abs(a_p)))
        if abs(rel) < FAN_SPLIT:
            rel = FAN_SPLIT if rel >= 0 else -FAN_SPLIT
        off = a_p + rel
        if abs(off) > FAN_MAX:
            off = float(np.clip(off, -FAN_MAX, FAN_MAX))
            if abs(off - a_p) < FAN_SPLIT:       # the fan's edge: the other side of the parent
                off = float(np.clip(a_p - np.sign(rel) * FAN_SPLIT, -FAN_MAX, FAN_MAX))
        return self._to_sea(at, a_d, off)

    def _to_sea(self, at, a_d: float, off: float) -> np.ndarray:
        """The unit bearing ``a_d + off``, turned toward ``a_d`` (in 12 steps) until a straight run
        from ``at`` along it reaches the sea before the margin of a side of the frame that cuts the
        land (beyond the paper: a channel leaving a 1000 px delta's head 59 degrees off the descent
        met the frame and ran down along it)."""
        at = np.asarray(at, np.float64)
        offs = np.linspace(off, 0.0, 13)
        a = a_d + offs
        h, w = self.shape
        t = np.arange(1, int(np.hypot(h, w) / 4.0) + 2) * 4.0
        pts = at[None, None, :] + t[None, :, None] * np.stack([np.cos(a), np.sin(a)], -1)[:, None, :]
        inside = (pts[..., 0] >= 0) & (pts[..., 0] <= w - 1) & (pts[..., 1] >= 0) & (pts[..., 1] <= h - 1)
        sea = (self.depth_at(pts.reshape(-1, 2)).reshape(inside.shape) <= 1.0) & inside
        near = (self.frame_distance(pts) < 0.5 * self.margin) | ~inside
        first_sea = np.where(sea.any(1), np.argmax(sea, 1), len(t))
        first_frame = np.where(near.any(1), np.argmax(near, 1), len(t))
        ok = first_sea < first_frame
        k = int(np.argmax(ok)) if ok.any() else len(offs) - 1
        return np.array([np.cos(a[k]), np.sin(a[k])])

    def way_down(self, at, fan=None) -> np.ndarray:
        """Unit direction (x, y) downstream at ``at``: the steepest descent to the sea, blended
        (:data:`FAN_WEIGHT`) with the channel's own bearing ``fan`` (:meth:`bearing`) when given,
        else with the direction away from the apex once one is set."""
        at = np.asarray(at, np.float64)
        if fan is None and self._in_tail(at):
            # below the delta's head a trunk runs on the example's root's heading at the sea (TRUNK_TAIL,
            # STRAIGHT_TAIL); turned toward the descent from where it is now when a straight run would meet
            # the frame first (taken once at the head, a 256 px delta's trunk drifted into a corner of the
            # frame and its last channel left it upstream)
            if self.axis is None:
                return self._to_sea(at, self._ref(at), self.tail)
            if self._tail_dir is None:
                self._tail_dir = self._to_sea(at, self._ref(at), self.tail)
            return self._tail_dir.copy()
        axis, target = (self.axis, self.target) if self.axis is not None else (self.trunk_axis, self.trunk_target)
        if fan is None and axis is not None:
            # a trunk heads for the example's mouths (set_axis, STRAIGHT_HOLD), along its axis once near them
            if target is not None:
                r = target - at
                n = float(np.hypot(*r))
                if n > 0.1 * float(np.hypot(*self.shape)):
                    return r / n
            return axis.copy()
        d = self.descent(at)
        if fan is not None:
            d = (1.0 - BEARING_WEIGHT) * d + BEARING_WEIGHT * np.asarray(fan, np.float64)
            return d / max(float(np.hypot(*d)), 1e-9)
        if self.apex is not None:
            r = at - self.apex
            n = float(np.hypot(*r))
            if n > 1.0:
                # upstream of the apex (a child started above the delta's head) the descent alone
                w = FAN_WEIGHT * float(np.clip(4.0 * (r @ d) / n, 0.0, 1.0) if self.head else 1.0)
                d = (1.0 - w) * d + w * r / n
                d = d / max(float(np.hypot(*d)), 1e-9)
        return d

    def depth_at(self, pts) -> np.ndarray:
        """Depth (distance to the sea, px) at points ``(N, 2)`` (x, y)."""
        h, w = self.shape
        p = np.asarray(pts, np.float64).reshape(-1, 2)
        x = np.clip(np.rint(p[:, 0]).astype(np.int64), 0, w - 1)
        y = np.clip(np.rint(p[:, 1]).astype(np.int64), 0, h - 1)
        return self.depth[y, x].astype(np.float64)

    def set_head(self, trunk: np.ndarray, share: float) -> None:
        """Find the delta's head on the trunk: its first vertex whose depth is at most ``share`` x the
        trunk start's (the example's first furcation, :func:`head_share`); the channels leave the trunk
        below it, each with its own bearing (:meth:`bearing`)."""
        trunk = np.asarray(trunk, np.float64)
        if len(trunk) < 2 or not 0.0 < share < 1.0:
            return
        dep = self.depth_at(trunk)
        below = np.flatnonzero(dep <= share * dep[0])
        if below.size:
            self.head_at = trunk[int(below[0])].copy()
            self.head = True

    def _cos(self, at, vec: np.ndarray, fan=None) -> np.ndarray:
        return (vec @ self.way_down(at, fan)) / np.maximum(np.hypot(vec[:, 0], vec[:, 1]), 1e-9)

    def hold_from(self, points, h: float) -> np.ndarray | None:
        """The point of a channel ``points`` (its vertices, ``h`` px apart) :data:`FAN_WINDOW` x the frame's
        diagonal back from its tip (its first when shorter): where the chord held to the bearing starts;
        the tip itself once the channel's depth is at most :data:`FAN_STRAIGHT` x its start's; None (the
        hold step by step, :meth:`factor`) within :data:`FAN_FRAME_GUARD` x the margin of the frame."""
        back = int(FAN_WINDOW * float(np.hypot(*self.shape)) / max(float(h), 1e-9))
        d0, d1 = self.depth_at([points[0], points[-1]])
        if float(self.frame_distance(np.asarray(points[-1], np.float64))) < FAN_FRAME_GUARD * self.margin:
            return None
        if d1 <= FAN_STRAIGHT * d0:
            return np.asarray(points[-1], np.float64)
        return np.asarray(points[max(0, len(points) - 1 - back)], np.float64)

    def trunk_hold(self, tip, end: np.ndarray, pull: float = 1.0, start=None) -> np.ndarray:
        """Score factor of a trunk's candidates ending at ``end`` ((C, 2)) from ``tip`` when the delta has
        an axis (:meth:`set_axis`): ``exp(-TRUNK_HOLD a)``, ``a`` the angle of the chord off the way to the
        example's mouths (1 without an axis); with the trunk's first point ``start`` and a meandering
        example (:data:`MEANDER_SIN`), off that way turned by the meander's slope there."""
        tip = np.asarray(tip, np.float64)
        if not (self.held(tip) or self._meandering(tip, start)) or TRUNK_HOLD <= 0:
            return np.ones(len(end))
        wd = self._meander_way(tip, self.way_down(tip), start)
        chord = np.asarray(end, np.float64) - tip
        off = np.abs(np.arctan2(chord[:, 1] * wd[0] - chord[:, 0] * wd[1], chord @ wd))
        hold = MEANDER_HOLD if self._meandering(tip, start) else TRUNK_HOLD
        return np.exp(-pull * hold * off)

    def _meandering(self, tip, start) -> bool:
        """Does a trunk from ``start`` at ``tip`` follow the example's meander (:data:`MEANDER_SIN`)?"""
        if self.meander is None or start is None or self._in_tail(tip):
            return False
        d0, d1 = self.depth_at([start, tip])
        return bool(d1 > MEANDER_DEPTH * d0)

    def _meander_way(self, tip: np.ndarray, wd: np.ndarray, start) -> np.ndarray:
        """``wd`` turned by the slope of the example's meander (:func:`_meander_of`) at ``tip``'s way along
        it from ``start``; ``wd`` itself without a meander or start, in the tail, or below half the start's
        depth (where the example's was measured)."""
        if not self._meandering(tip, start):
            return wd
        start = np.asarray(start, np.float64)
        k, lobes, sign = self.meander
        u = self.way_down(start)
        key = (float(start[0]), float(start[1]))
        if key not in self._meander_len:
            # as many lobes as the example's over the straight way's run down to MEANDER_DEPTH: the trunk
            # ends its meander on its line, as the example's does (the example's wavelength left it up to a
            # lobe's amplitude aside, its bearing 7-9 degrees off)
            t = np.arange(0.0, float(np.hypot(*self.shape)), 2.0)
            q = start + t[:, None] * u
            inside = (q[:, 0] >= 0) & (q[:, 1] >= 0) & (q[:, 0] <= self.shape[1] - 1) & (q[:, 1] <= self.shape[0] - 1)
            low = np.flatnonzero(~inside | (self.depth_at(np.clip(q, 0, [self.shape[1] - 1, self.shape[0] - 1]))
                                             <= MEANDER_DEPTH * float(self.depth_at(start)[0])))
            self._meander_len[key] = float(t[low[0]] if low.size else t[-1])
        run = max(self._meander_len[key], 1.0)
        at = float((tip - start) @ u)
        # the swings fade toward the run's ends, as the example's do (a sine's slope is largest where its
        # offset is 0: at full slope there the trunk reached the head heading 40 deg off its way and every
        # channel of a 1000 px mean0 delta left it on one side, fan 37 -> 10 deg, mouth share 0.5 -> 0)
        fade = float(np.sqrt(np.sin(np.pi * np.clip(at / run, 0.0, 1.0))))
        theta = sign * float(np.arctan(k * fade * np.cos(np.pi * lobes * at / run)))
        n = np.array([-wd[1], wd[0]])
        return np.cos(theta) * wd + np.sin(theta) * n

    def factor(self, tip, points: np.ndarray, n_new: np.ndarray, start=None, pull: float = 1.0,
               fan=None, hold_from=None) -> np.ndarray:
        """Score factor of candidates ``points`` ((C, M, 2), the first ``n_new`` new) from ``tip``.

        ``start`` (the branch's first point): a candidate that heads back
        inland (over ``UPSTREAM_COS`` off the way down) or brings the
        branch's tip back upstream of its start is forbidden (0).
        ``pull``: the downstream pull's strength as a share of ``kappa``
        (:data:`HEAD_PULL` for a channel's first head below the delta's head).
        ``fan``: the channel's own bearing (:meth:`bearing`), None for a trunk.
        ``hold_from``: where the chord held to ``fan`` (:data:`FAN_HOLD`) starts (:meth:`hold_from`); when
        None, at ``tip`` and without the whole chord (:data:`FAN_WHOLE`). A channel with a ``fan`` takes the
        frame factor to the power :data:`FRAME_POWER`.
        """
        tip = np.asarray(tip, np.float64)
        end = points[np.arange(len(points)), np.maximum(n_new, 1) - 1]
        if fan is None and self._meandering(tip, start):
            # a meandering trunk is pulled along its meander too (held to it alone, the pull down the
            # straight way flattened its swings: sinuosity 1.03-1.07 against the example's 1.16)
            v = end - tip
            cos = (v @ self._meander_way(tip, self.way_down(tip), start)) / np.maximum(np.hypot(v[:, 0], v[:, 1]),
                                                                                        1e-9)
        else:
            cos = self._cos(tip, end - tip, fan)
        k = self.kappa * (FAN_KAPPA_GAIN if fan is not None else 1.0)
        ff = self.frame_factor(tip, points, n_new)
        if fan is not None and FRAME_POWER != 1.0:
            ff = ff ** FRAME_POWER
        f = np.exp(pull * k * cos) * ff
        if fan is not None and FAN_HOLD > 0:
            fv = np.asarray(fan, np.float64)
            chord = end - (tip if hold_from is None else np.asarray(hold_from, np.float64))
            off = np.abs(np.arctan2(chord[:, 1] * fv[0] - chord[:, 0] * fv[1], chord @ fv))
            if hold_from is not None and start is not None and FAN_WHOLE > 0:
                # ... and no drift: the whole channel's chord is held too (see FAN_WHOLE)
                c2 = end - np.asarray(start, np.float64)
                o2 = np.abs(np.arctan2(c2[:, 1] * fv[0] - c2[:, 0] * fv[1], c2 @ fv))
                o2 = np.where(np.hypot(c2[:, 0], c2[:, 1]) > 4.0, o2, 0.0)
                off = np.maximum(off, FAN_WHOLE * o2)
            f = f * np.exp(-pull * FAN_HOLD * off)
        elif (self.held(tip) or self._meandering(tip, start)) and TRUNK_HOLD > 0:
            # a straight delta's trunk is held to its tail too (STRAIGHT_TAIL): the pull alone let the
            # matching keep it on the descent (fan0 512 px: 6-22 degrees off it at the sea against 48)
            f = f * self.trunk_hold(tip, end, pull, start)
        f = np.where(cos < UPSTREAM_COS, 0.0, f)
        if start is not None:
            net = end - np.asarray(start, np.float64)
            far = np.hypot(net[:, 0], net[:, 1]) > 4.0
            f = np.where(far & (self._cos(start, net, fan) < 0.0), 0.0, f)
        return f


#: A map's rivers keep off the coast: the margin is this quantile of the depths (distance to the region


def fan_spread(example, domain) -> float | None:
    """How far a delta's outer channels run off the way down to the sea (radians).

    Beyond the paper (issue 23): the largest angle between the chord (start to end) of a channel of
    the example that leaves another branch and reaches the sea (its end within 10 % of the deepest
    depth) and the steepest descent at its start; None when there is no such channel. The trunk's
    channels take it as their bearing (:meth:`_Drain.bearing`): with their own heading where they
    left the trunk (25-60 degrees off the descent) the channels of 250-1000 px deltas reached the
    sea 6-34 degrees apart (circular spread of their headings 5 % of the diagonal inland) against
    the example's 41-50; the example's outer channels run 55-61 degrees off the descent.

    Parameters
    ----------
    example : Structure
        The example's structure.
    domain : (H, W) array_like of bool
        Where it may grow (the land).

    Returns
    -------
    float or None
        The angle, in [0, pi / 2].

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> dom = np.zeros((100, 100), bool); dom[:80] = True
    >>> s = Structure([Branch([(50, 0), (50, 40)], 2.0), Branch([(50, 40), (10, 80)], 1.0, 0, 1)])
    >>> round(float(np.degrees(fan_spread(s, dom))))
    45
    """
    drain = _Drain(domain)
    deep = float(drain.depth.max())
    out = []
    for b in example.branches:
        p = np.asarray(b.points, np.float64)
        if b.parent is None or len(p) < 2 or drain.depth_at(p[-1])[0] >= 0.1 * deep:
            continue
        d = drain.descent(p[0])
        c = p[-1] - p[0]
        cos = float(c @ d) / max(float(np.hypot(*c)), 1e-9)
        out.append(float(np.arccos(np.clip(cos, -1.0, 1.0))))
    return min(max(out), np.pi / 2) if out else None
