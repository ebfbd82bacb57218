"""The ``"fan"`` kind of the procedural leaves: a ginkgo-like fan with dichotomous veins.

Step 1 and 3 of :mod:`branchnb.leaves.procedural` for a kind unlike the
others (no midrib, no lobe axes, no reticulate network):

* **Outline**: a fan about the blade's base, a wedge whose straight
  lateral edges open ``half_angle`` degrees either side of the tip
  direction up to an outer arc of radius ``length``, the shoulders
  rounded; a V cleft (``notch`` of the radius deep, ``notch_width``
  degrees wide) in the middle of the arc; a wavy (crenate) outer margin,
  ``teeth`` smooth waves per turn, ``tooth_depth`` deep, on the arc only.
  As every kind, it is a polar radius ``R(a)`` about ``centre`` (inside the
  blade, so every direction meets the outline once).
* **Veins**: dichotomous, as in Ginkgo biloba: from the base, veins fork
  in two ``levels`` times, at ``forks`` (fractions of the radius), and the
  ``2 ** levels`` last ones run nearly radially to the arc, spread over
  ``span`` of the fan's angle. No finer veins grow between them
  (``"fine": False``). Laid out in the base's polar frame, then carried
  as material points, so they move with the leaf's angle warp like the
  margin they end at; per leaf each fork moves a little (0.015 of the
  radius along the vein, 0.02 radians across).
"""

from __future__ import annotations

import numpy as np

__all__ = ["FAN"]

#: The kind's entry in :data:`branchnb.leaves.procedural.KINDS`.
FAN = {"lobes": (), "width": (), "sinus": 0.0, "centre": (0.0, -0.36),
       "fan": {"half_angle": 62.0, "length": 0.62, "shoulder": 0.12, "notch": 0.3, "notch_width": 9.0},
       "teeth": 44, "tooth_depth": 0.018, "petiole": 0.42,
       "dichotomous": {"levels": 4, "span": 0.86, "forks": (0.06, 0.24, 0.42, 0.6), "end": 0.93},
       "fine": False}

_CACHE: dict = {}


def _layout(kind: dict):
    """``(angles, radii, a_arc)``: the fan's plain outline (no cleft, no waves) about its centre, cached."""
    key = id(kind)
    if key in _CACHE:
        return _CACHE[key]
    f = kind["fan"]
    big_a, length = np.deg2rad(f["half_angle"]), f["length"]
    th = np.linspace(-big_a, big_a, 1441)
    arc = length * np.column_stack([np.sin(th), -np.cos(th)])
    t = np.linspace(0.0, 1.0, 400)[:, None]
    pts = np.vstack([arc[0] * t, arc, arc[-1] * t])  # the two straight edges and the arc
    c = np.asarray(kind["centre"], np.float64)
    d = pts - c
    ang = np.arctan2(d[:, 0], -d[:, 1])
    rad = np.hypot(d[:, 0], d[:, 1])
    # The radius per direction: the farthest outline point (a star-shaped fan
    # about the centre), on a regular grid, the shoulders and the base rounded
    # by a circular moving average of ``shoulder`` radians.
    grid = np.linspace(-np.pi, np.pi, 2048, endpoint=False)
    k = np.clip(((ang + np.pi) / (2 * np.pi) * 2048).astype(int), 0, 2047)
    r = np.zeros(2048)
    np.maximum.at(r, k, rad)
    ok = r > 0
    r = np.interp(grid, grid[ok], r[ok], period=2 * np.pi)
    w = max(int(f["shoulder"] / (2 * np.pi) * 2048), 1)
    kern = np.hanning(2 * w + 1)
    kern /= kern.sum()
    r = np.convolve(np.concatenate([r[-w:], r, r[:w]]), kern, mode="valid")
    da = arc[-1] - c
    a_arc = float(np.arctan2(da[0], -da[1]))
    _CACHE[key] = (grid, r, a_arc)
    return _CACHE[key]


def fan_radius(kind: dict, ac: np.ndarray, lobe_scale: np.ndarray, waves: bool) -> np.ndarray:
    """``R(a_c)`` of a fan kind (see the module docstring).

    Parameters
    ----------
    kind : dict
        The leaf kind (its ``"fan"`` entry, ``"teeth"``, ``"tooth_depth"``).
    ac : array_like
        Angles around the base, radians, 0 along the midline.
    lobe_scale : (2,) ndarray
        (size, cleft depth) factors of this leaf; empty for the kind's own.
    waves : bool
        Whether the arc gets its wavy teeth.

    Returns
    -------
    ndarray
        The blade's radius at each angle (canonical leaf frame).
    """
    ac = np.asarray(ac, np.float64)
    grid, r0, a_arc = _layout(kind)
    f = kind["fan"]
    r = np.interp(ac, grid, r0, period=2 * np.pi)
    s = lobe_scale if len(lobe_scale) else np.ones(2)
    r = r * s[0]
    depth = f["notch"] * (s[1] ** 3 if len(s) > 1 else 1.0)
    cleft = np.clip(1.0 - np.abs(ac) / np.deg2rad(f["notch_width"]), 0.0, None) ** 1.5
    r = r * (1.0 - min(depth, 0.6) * cleft)
    if waves:
        on_arc = np.clip((a_arc - np.abs(ac)) / 0.15, 0.0, 1.0)
        r = r * (1.0 - kind["tooth_depth"] * 0.5 * (1.0 - np.cos(kind["teeth"] * ac)) * on_arc)
    return r


def dichotomous_veins(kind: dict, rng: np.random.Generator, spacing: float):
    """Vein polylines (canonical leaf frame), parents before children.

    The two first ones start at the base; every other starts where its parent ends.

    Parameters
    ----------
    kind : dict
        The leaf kind (its ``"fan"`` and ``"dichotomous"`` entries).
    rng : numpy.random.Generator
        Jitter of the forks and of the veins' angles.
    spacing : float
        Point spacing along each vein (canonical units).

    Returns
    -------
    list of (ndarray, int)
        ``[(line, level), ...]``: each vein's (n, 2) polyline and its forking level.
    """
    f, dic = kind["fan"], kind["dichotomous"]
    big_a, length = np.deg2rad(f["half_angle"]), f["length"]
    levels = int(dic["levels"])
    n_end = 2 ** levels
    ends = np.linspace(-1.0, 1.0, n_end) * dic["span"] * big_a
    forks = np.asarray(dic["forks"], np.float64)
    forks = forks + rng.normal(0.0, 0.015, len(forks)) * (np.arange(len(forks)) > 0)
    out = []
    # A node: (level, first terminal, last terminal + 1); its angle the mean of its terminals'.
    todo = [((0, n_end // 2 * i, n_end // 2 * (i + 1)), (0.0, 0.0)) for i in range(2)]
    while todo:
        (lev, i0, i1), (s0, a0) = todo.pop(0)
        a1 = float(ends[i0:i1].mean()) + (rng.normal(0.0, 0.02) if i1 - i0 > 1 else 0.0)
        last = i1 - i0 == 1
        s1 = dic["end"] if last else float(forks[min(lev + 1, len(forks) - 1)])
        n = max(int((s1 - s0) * length / spacing), 3)
        t = np.linspace(0.0, 1.0, n)
        ease = t * t * (3.0 - 2.0 * t)
        s = s0 + (s1 - s0) * t
        a = a0 + (a1 - a0) * ease
        line = length * np.column_stack([s * np.sin(a), -s * np.cos(a)])
        out.append((line, lev))
        if not last:
            half = (i0 + i1) // 2
            todo += [((lev + 1, i0, half), (s1, a1)), ((lev + 1, half, i1), (s1, a1))]
    return out
