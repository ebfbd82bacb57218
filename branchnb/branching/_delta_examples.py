"""Procedural delta masks whose trunk runs at a known bearing and whose channels fan by a known angle
(issue 23, branching58).

:func:`delta_fan_mask` draws one trunk entering through the frame, running at ``trunk_deg`` off the
straight way down to a sea along the bottom, and ``n`` distributaries leaving its head at offsets
spread evenly over ``fan_deg`` about the trunk's bearing, so the true trunk bearing (from where the
trunk enters to the mean of the mouths) is known and not the descent of the land to the sea.
"""

from __future__ import annotations

import numpy as np

from ..core.random import as_rng
from ..core.render import draw_polylines
from ._map_examples import _curve

#: the kinds of :mod:`._delta_fan_check` (name: (trunk degrees off the way down, fan degrees, channels))
#: (name: (trunk degrees off the way down, the fan's centre in degrees off the way down, fan degrees, channels))
FAN_KINDS = {"fan0": (0.0, 0.0, 90.0, 3), "fan30": (30.0, 20.0, 70.0, 4), "fanm40": (-40.0, -20.0, 70.0, 3),
             "fan55": (55.0, 25.0, 60.0, 3)}
#: meandering trunks (name: FAN_KINDS' four figures and the meander's amplitude as a share of the width,
#: :func:`delta_fan_mask`'s ``meander``; issue 23, branching71)
MEANDER_KINDS = {"mean0": (0.0, 0.0, 90.0, 3, 0.05), "mean20": (20.0, 10.0, 70.0, 4, 0.04),
                 "mean0n2": (0.0, 0.0, 50.0, 2, 0.06)}


def delta_fan_mask(shape=(256, 256), rng=0, trunk_deg: float = 30.0, centre_deg: float = 20.0, fan_deg: float = 70.0,
                   n: int = 3, meander: float = 0.0):
    """A binary delta mask (1 = water) with its sea at the bottom: (mask, channels, sea, entry, mouths).

    The trunk runs ``trunk_deg`` degrees off straight down (positive toward +x) from the frame to the
    delta's head at 0.45 x the height; ``n`` channels leave the head at ``centre_deg + o`` for ``o`` evenly
    over [-fan_deg / 2, fan_deg / 2] (at most 65 degrees off straight down) and reach the sea. ``entry`` is
    where the trunk enters (x, y), ``mouths`` (n, 2) where the channels meet the sea. ``meander`` > 0
    (a share of the width): the trunk swings sideways by a sine of that amplitude, 1.5 waves from its
    entry to the head (no random draw: the other figures are those of ``meander=0``).

    Examples
    --------
    >>> m, ch, sea, entry, mouths = delta_fan_mask((128, 128), 0, 30.0, 20.0, 70.0, 3)
    >>> m.shape, len(ch), mouths.shape
    ((128, 128), 4, (3, 2))
    """
    rng = as_rng(rng)
    h, w = shape
    s = min(h, w) / 256.0
    sea_y = 0.85 * h + rng.normal(0, 0.01 * h)
    apex_y = 0.45 * h + rng.normal(0, 0.02 * h)
    t = np.radians(trunk_deg + rng.normal(0, 2.0))
    offs = np.radians(np.linspace(-fan_deg / 2, fan_deg / 2, n) + rng.normal(0, 3.0, n))
    ang = np.clip(np.radians(centre_deg) + offs, -np.radians(65), np.radians(65))
    drop = sea_y - apex_y
    dx = drop * np.tan(ang)
    # the head where the mouths' mean lies mid-frame, the mouths inside the frame
    lo, hi = 0.08 * w - dx.min(), 0.92 * w - dx.max()
    apex_x = float(np.clip(0.5 * w - dx.mean(), lo, hi)) if lo <= hi else 0.5 * w - 0.5 * (dx.max() + dx.min())
    apex = np.array([apex_x, apex_y])
    mouths = np.c_[np.clip(apex_x + dx, 0.04 * w, 0.96 * w), np.full(n, sea_y + 8 * s)]
    # the trunk back from the head to the frame (top, or a side when it runs steeply)
    back = -np.array([np.sin(t), np.cos(t)])
    lim = [apex_y / max(-back[1], 1e-9)]
    if back[0] < 0:
        lim.append(apex_x / -back[0])
    elif back[0] > 0:
        lim.append((w - 1 - apex_x) / back[0])
    entry = apex + back * (min(lim) + 3.0)
    trunk = _curve(entry, apex, rng, 0.02 * w)
    if meander > 0:
        d = apex - entry
        nrm = np.array([-d[1], d[0]]) / max(float(np.hypot(*d)), 1e-9)
        u = np.linspace(0.0, 1.0, len(trunk))[:, None]
        trunk = trunk + nrm * meander * w * np.sin(1.5 * 2 * np.pi * u) * np.sin(np.pi * u) ** 0.5
    lines = [(trunk, 7.0 * s)]
    radii = np.linspace(4.5, 1.6, n) * s
    for k in rng.permutation(n):
        lines.append((_curve(apex, mouths[k], rng, 0.03 * w), float(radii[k])))
    canvas = np.zeros(tuple(shape) + (3,), np.float32)
    canvas = draw_polylines(canvas, [c for c, _ in lines], widths=[2 * r for _, r in lines], colors=(1, 1, 1))
    sea = np.broadcast_to(np.arange(h)[:, None] >= sea_y, tuple(shape)).copy()
    mask = (canvas[:, :, 0] > 0.5) | sea
    channels = [(c[(c[:, 1] < sea_y - r) & (c[:, 1] >= 0) & (c[:, 0] >= 0) & (c[:, 0] <= w - 1)], float(r))
                for c, r in lines]
    entry = np.clip(entry, 0, [w - 1, h - 1])
    mouths[:, 1] = sea_y
    return mask.astype(np.float32), channels, sea, entry, mouths


def delta_tree_mask(shape=(256, 256), rng=0, fan_deg: float = 90.0, orders: int = 2, radius: float = 4.0,
                    tributaries: int = 0):
    """A balanced binary delta mask (1 = water), sea at the bottom: (mask, entry, mouths, head).

    Beyond :func:`delta_fan_mask`'s one order of channels (issue 23, branching79): a trunk of ``radius`` px
    enters through the top near the middle and runs to the delta's head; there it splits in two, and each
    channel splits again, ``orders`` times in all (2 ** ``orders`` mouths), the offsets halving at each order
    so the outer channels run ``fan_deg / 2`` off straight down, symmetric about the trunk (the radius 0.55 x
    at each order, at least 1 px). The head lies as deep as lets the outer channels reach the sea inside
    the frame, so the example is balanced: as many channels and as much channel length on either side of
    the trunk, the mouths' mean below the entry.

    ``tributaries`` (0-3; issue 23, branching85): as many tributaries (0.6 x the trunk's radius) entering
    through the left and right sides in turn and joining the trunk upstream of the head, at 25 %, 50 % and
    70 % of its length, heading downstream; drawn after the rest, so the example is otherwise the same.

    Examples
    --------
    >>> m, entry, mouths, head = delta_tree_mask((128, 128), 0, 90.0, 2, 3.0)
    >>> m.shape, mouths.shape
    ((128, 128), (4, 2))
    """
    rng = as_rng(rng)
    h, w = shape
    if orders < 1:
        raise ValueError(f"orders must be >= 1, got {orders}")
    if not 0 <= int(tributaries) <= 3:
        raise ValueError(f"tributaries must be 0-3, got {tributaries}")
    sea_y = 0.85 * h + rng.normal(0, 0.01 * h)
    half = np.radians(min(max(fan_deg, 10.0), 170.0) / 2.0)
    # offsets of the orders, halving, summing to the half fan
    steps = half * 2.0 ** -np.arange(orders) / (2.0 - 2.0 ** (1 - orders))
    # the outer channel's sideways run per px of drop: the head as deep as keeps it 0.44 x the width
    drop = min(0.45 * h, 0.44 * w / max(float(np.mean(np.tan(np.cumsum(steps)))), 1e-3))
    apex = np.array([0.5 * w + rng.normal(0, 0.02 * w), sea_y - drop])
    entry = np.array([apex[0] + rng.normal(0, 0.02 * w), -3.0])
    lines = [(_curve(entry, apex, rng, 0.02 * w), float(radius))]
    nodes = [(apex, 0.0, float(radius))]
    mouths = []
    for k in range(orders):
        seg = drop / orders
        nxt = []
        for p, a, r in nodes:
            for sgn in (-1.0, 1.0):
                b = a + sgn * steps[k] + rng.normal(0, np.radians(2.0))
                rc = max(0.55 * r, 1.0)
                if k == orders - 1:
                    q = np.array([p[0] + (sea_y + 6 - p[1]) * np.tan(b), sea_y + 6])
                else:
                    q = p + seg * np.array([np.tan(b), 1.0])
                q[0] = np.clip(q[0], 0.03 * w, 0.97 * w)
                lines.append((_curve(p, q, rng, 0.02 * w), rc))
                nxt.append((q, b, rc))
                if k == orders - 1:
                    mouths.append([q[0], sea_y])
        nodes = nxt
    trunk = lines[0][0]
    for k, f in enumerate((0.25, 0.5, 0.7)[: int(tributaries)]):
        j = trunk[int(f * (len(trunk) - 1))]
        # from a side, 0.12-0.2 x the height upstream of the junction: joining at 35-60 deg off the trunk
        src = np.array([-3.0 if k % 2 == 0 else w + 2.0, max(j[1] - rng.uniform(0.12, 0.2) * h, 0.02 * h)])
        lines.append((_curve(src, j, rng, 0.015 * w), max(0.6 * radius, 1.0)))
    canvas = np.zeros(tuple(shape) + (3,), np.float32)
    canvas = draw_polylines(canvas, [c for c, _ in lines], widths=[2 * r for _, r in lines], colors=(1, 1, 1))
    sea = np.arange(h)[:, None] >= sea_y
    mask = (canvas[:, :, 0] > 0.5) | np.broadcast_to(sea, tuple(shape))
    return mask.astype(np.float32), entry, np.asarray(mouths, np.float64), apex


#: the sides a river enters from, and how :func:`delta_river_mask` turns its top-entry drawing there
RIVER_SIDES = ("top", "bottom", "left", "right")


def delta_river_mask(shape=(256, 256), rng=0, side: str = "top", radius: float = 4.0, sea: bool = True,
                     splits: int = 3):
    """An uneven binary river delta (1 = water) whose trunk enters through the frame's ``side``:
    (mask, entry, mouths).

    Unlike :func:`delta_tree_mask` (issue 23, branching83): the trunk of ``radius`` px enters at a random
    place on ``side`` and winds to the delta's head (0.3-0.5 x the way across); there ``splits`` times in
    all a channel forks into two of random, unequal widths (0.45-0.8 x its radius, at least 1 px) and
    angles (15-40 degrees off its heading), the fork taken at a random open channel, so some channels
    reach the sea at once and others fork again. ``sea``: a sea fills the far side (0.84-0.9 x the way
    across) and the channels end in it; else they run out through the far frame edge. ``entry`` is where
    the trunk enters (x, y, in the frame), ``mouths`` (k, 2) where the channels end.

    Examples
    --------
    >>> m, entry, mouths = delta_river_mask((128, 128), 0, "left", 3.0, True, 2)
    >>> m.shape, mouths.shape, bool(entry[0] == 0)
    ((128, 128), (3, 2), True)
    """
    if side not in RIVER_SIDES:
        raise ValueError(f"side must be one of {RIVER_SIDES}, got {side!r}")
    if splits < 1:
        raise ValueError(f"splits must be >= 1, got {splits}")
    rng = as_rng(rng)
    h0, w0 = shape
    # drawn entering from the top: a transposed frame for the left and right sides
    h, w = (w0, h0) if side in ("left", "right") else (h0, w0)
    far = (rng.uniform(0.84, 0.9) * h) if sea else h + 6.0
    head = np.array([rng.uniform(0.35, 0.65) * w, rng.uniform(0.3, 0.5) * h])
    entry = np.array([np.clip(head[0] + rng.normal(0, 0.1 * w), 0.15 * w, 0.85 * w), -3.0])
    lines = [(_curve(entry, head, rng, 0.04 * w), float(radius))]
    # open channels: (start, heading off straight down, radius); a fork ends one and opens two
    open_ = [(head, rng.normal(0, np.radians(8.0)), float(radius))]
    for _k in range(splits):
        # (open_ runs left to right; the new channels keep between their neighbours' headings: no crossing)
        i = int(rng.integers(len(open_)))
        p, a, r = open_.pop(i)
        if _k:
            # the channel runs some way before it forks
            q = p + rng.uniform(0.25, 0.45) * (far - p[1]) * np.array([np.tan(a), 1.0])
            q[0] = np.clip(q[0], 0.05 * w, 0.95 * w)
            lines.append((_curve(p, q, rng, 0.02 * w), r))
            p = q
        lo = open_[i - 1][1] + np.radians(8.0) if i > 0 else -np.radians(55.0)
        hi = open_[i][1] - np.radians(8.0) if i < len(open_) else np.radians(55.0)
        spread = np.radians(rng.uniform(15.0, 40.0, 2))
        shares = rng.uniform(0.45, 0.8, 2)
        kids = [(p, float(np.clip(a + sgn * da, lo, hi)), max(sh * r, 1.0))
                for sgn, da, sh in zip((-1.0, 1.0), spread, shares)]
        open_[i:i] = kids
    mouths = []
    for p, a, r in open_:
        q = np.array([p[0] + (far + 6.0 - p[1]) * np.tan(a), far + 6.0])
        q[0] = np.clip(q[0], 0.03 * w, 0.97 * w)
        lines.append((_curve(p, q, rng, 0.02 * w), r))
        mouths.append([q[0], min(far, h - 1.0)])
    canvas = np.zeros((h, w, 3), np.float32)
    canvas = draw_polylines(canvas, [c for c, _ in lines], widths=[2 * r for _, r in lines], colors=(1, 1, 1))
    mask = (canvas[:, :, 0] > 0.5) | (np.arange(h)[:, None] >= far)
    entry = np.array([entry[0], 0.0])
    mouths = np.asarray(mouths, np.float64)
    # turned so the trunk enters through ``side`` ((x, y) follow the pixels)
    if side == "bottom":
        mask = mask[::-1]
        entry[1], mouths[:, 1] = h - 1 - entry[1], h - 1 - mouths[:, 1]
    elif side == "left":
        mask = mask.T
        entry, mouths = entry[::-1].copy(), mouths[:, ::-1].copy()
    elif side == "right":
        mask = mask.T[:, ::-1]
        entry, mouths = entry[::-1].copy(), mouths[:, ::-1].copy()
        entry[0], mouths[:, 0] = h - 1 - entry[0], h - 1 - mouths[:, 0]
    return np.ascontiguousarray(mask).astype(np.float32), entry, mouths
