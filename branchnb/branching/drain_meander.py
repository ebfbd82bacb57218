"""A delta trunk's meander (beyond the paper; issue 23, branching85 and branching88): read off the example's
longest root (:func:`_meander_of`) and the slope of the faded sine the synthesized trunk follows
(:func:`_faded_slope`; :meth:`.drain._Drain._meander_way`). Split from :mod:`.drain`, which re-exports every name.
"""

from __future__ import annotations

import numpy as np

#: A trunk held to its way (:data:`.drain.TRUNK_HOLD`, :data:`.drain.STRAIGHT_HOLD`) whose example's trunk
#: meanders
#: (:func:`_meander_of`: the example's longest root above half its start's depth has a sinuosity of at least
#: this and swings to either side of its chord at least 3 times) is pulled and held to a sine about that way
#: instead: as many lobes as the example's over the trunk's own straight run down to :data:`MEANDER_DEPTH`,
#: its slope from the example's sinuosity, fading at both ends as the example's (beyond the paper, issue 23,
#: branching85). Held to the straight way the meandering trunk came out ruler-straight; held by its chord from
#: its start it drifted to one side (bearing error median 1.1 -> 12.4 degrees, sinuosity 1.035) without
#: meandering: the matching alone does not swing it. ``_delta_fan_check`` (512 px, sea bottom/left, 3 seeds,
#: medians; without -> with): trunk sinuosity ``mean0`` 1.002/1.003 -> 1.108/1.080 (example 1.161/1.159),
#: ``mean20`` 1.025/1.015 -> 1.059/1.064 (1.098/1.094); bearing error 1.1/0.8 -> 2.2/5.8 and 8.3/5.4 ->
#: 2.1/2.3 degrees; ``mean0`` at 1000 px (2 seeds): 1.001 -> 1.096 (1.198), bearing error 1.4 -> 7.2, but its
#: fan spread 37.0 -> 22.9 degrees (one seed's channels all on one side: 10.3). Other kinds: no meander,
#: byte-identical.
MEANDER_SIN = 1.05
#: ... held to it this firmly (as :data:`.drain.TRUNK_HOLD`; at 8 the trunk swung half as far: sinuosity 1.03-1.10)
MEANDER_HOLD = 16.0
#: ... measured and followed down to this share of the trunk's start's depth.
MEANDER_DEPTH = 0.5
#: ... a lobe of the meander: a run to one side of the trunk's chord past this share of its largest offset
#: (a meander that grows from the frame: ``mean0``'s first lobe is 0.21 x its largest).
MEANDER_LOBE = 0.15
#: ... its slope solved for the faded sine the trunk follows (:func:`_faded_slope`), not a plain sine's
#: ``2 sqrt(sinuosity - 1)``: the swings fade toward the run's ends (:meth:`.drain._Drain._meander_way`), so with the
#: plain sine's slope the trunk's path was shorter than the example's (beyond the paper, issue 23,
#: branching88). ``_delta_fan_check bottom,left 512 5 ... mean0,mean20``, trunk sinuosity median, sea at the
#: bottom/left: ``mean0`` 1.108/1.083 -> 1.172/1.094 (example 1.161/1.159), ``mean20`` 1.062/1.062 ->
#: 1.101/1.107 (1.098/1.094); ``mean0`` at 1024 px 1.106/1.104 -> 1.190/1.157 (1.189/1.179). No crossings.
MEANDER_FADED = True


def _meander_of(example, dom: np.ndarray) -> tuple[float, float, float] | None:
    """``(slope, lobes, sign)`` of the meander of ``example``'s trunk (its longest root from its start
    down to :data:`MEANDER_DEPTH` x its start's depth in ``dom``): a sine ``e(s) = sign A sin(2 pi s / L)``
    off its chord whose largest slope ``2 pi A / L`` gives the trunk's sinuosity (``1 + slope**2 / 4``);
    ``L`` twice the chord over the number of its ``lobes`` (runs to one side of the chord past
    :data:`MEANDER_LOBE` x its largest offset), ``sign`` the side of the first. None when the sinuosity is under
    :data:`MEANDER_SIN` or the trunk swings to either side fewer than 3 times (a bend, not a meander)."""
    from scipy import ndimage as ndi

    roots = [np.asarray(b.points, np.float64) for b in example.branches if b.parent is None and len(b.points) >= 3]
    if not roots:
        return None
    p = max(roots, key=lambda q: float(np.hypot(*np.diff(q, axis=0).T).sum()))
    d = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    ix = np.clip(np.rint(p).astype(np.int64), 0, [w - 1, h - 1])
    dep = d[ix[:, 1], ix[:, 0]]
    below = np.flatnonzero(dep <= MEANDER_DEPTH * dep[0])
    p = p[: (int(below[0]) + 1 if below.size else len(p))]
    if len(p) < 3:
        return None
    c = p[-1] - p[0]
    chord = float(np.hypot(*c))
    sin = float(np.hypot(*np.diff(p, axis=0).T).sum()) / max(chord, 1e-9)
    if sin < MEANDER_SIN:
        return None
    e = (p - p[0]) @ (np.array([-c[1], c[0]]) / chord)
    sg = np.sign(e[np.abs(e) > MEANDER_LOBE * float(np.abs(e).max())])
    lobes = 1 + int(np.count_nonzero(sg[1:] != sg[:-1]))
    if lobes < 3:
        return None
    return _faded_slope(sin, lobes) if MEANDER_FADED else 2.0 * float(np.sqrt(sin - 1.0)), float(lobes), float(sg[0])


def _faded_slope(sin: float, lobes: int) -> float:
    """The largest slope ``k`` of the faded sine :meth:`_Drain._meander_way` turns a trunk by (heading
    ``arctan(k sqrt(sin(pi u)) cos(pi lobes u))`` at ``u`` of its run) whose path over its run is ``sin`` x
    as long (:data:`MEANDER_FADED`).

    Examples
    --------
    >>> round(_faded_slope(1.0, 3), 3)
    0.0
    >>> 2.0 * np.sqrt(0.16) < _faded_slope(1.16, 3) < 1.3
    True
    """
    if sin <= 1.0:
        return 0.0
    u = (np.arange(400) + 0.5) / 400.0
    g = np.sqrt(np.sin(np.pi * u)) * np.cos(np.pi * lobes * u)
    lo, hi = 0.0, 1.0
    while float(np.mean(np.sqrt(1.0 + (hi * g) ** 2))) < sin and hi < 1e3:
        hi *= 2.0
    for _ in range(50):
        mid = 0.5 * (lo + hi)
        lo, hi = (mid, hi) if float(np.mean(np.sqrt(1.0 + (mid * g) ** 2))) < sin else (lo, mid)
    return 0.5 * (lo + hi)
