"""More procedural multi-part objects: a flower and a hand.

Like :mod:`~branchnb.strokes.procedural` (every pixel labelled with its
part, one skeleton stroke per part starting on its parent's stroke), for
shapes the first set does not cover:

* :func:`flower`: a curved stem, two leaves on petioles, a round head and
  six petals round the head (parts of parts: the petals hang from the
  head, which hangs from the stem; the petals lie *under* the head, so
  a petal's root is hidden by its parent);
* :func:`hand`: a forearm, a palm much wider than the forearm, four
  fingers off the palm's top and a thumb leaving its side at a wide angle
  (parts of parts; each finger with a nail near its tip).

>>> obj = flower(200, rng=0)
>>> obj.names[:4], obj.parents[:4]
(['stem', 'leaf 1', 'leaf 2', 'head'], [-1, 0, 0, 0])
"""

from __future__ import annotations

import numpy as np

from ..core.validate import Int, checked
from .procedural import PartObject, _bark, _leaf, _point_at, _side, _square_canvas, _square_doc

__all__ = ["flower", "hand"]


@checked(size=Int(64, 8192))
@_square_doc
def flower(size: int = 600, *, rng=None) -> PartObject:
    """A flower (``size x size``): a stem, two leaves, a head and six petals.

    Parts: ``stem`` (from the ground up, gently curved), ``leaf 1``,
    ``leaf 2`` (children of the stem, on petioles, one each side),
    ``head`` (a disk at the stem's top, its stroke the stem's last stretch
    continued across the disk) and ``petal 1..6`` (children of the head,
    their strokes from the head's centre out; drawn under the head).

    {square_params}

    Examples
    --------
    >>> obj = flower(160, rng=0)
    >>> len(obj.strokes), obj.parents[4:]
    (10, [3, 3, 3, 3, 3, 3])
    """
    c, n, k = _square_canvas(size, 600.0, rng)
    t = np.linspace(0.0, 1.0, 16)
    stem = np.c_[0.5 * n + 0.05 * n * np.sin(1.4 * np.pi * t), 0.96 * n - 0.6 * n * t]
    hw = 9 * k
    sdf, s = c.capsule(stem, hw, taper=0.8)
    c.part(stem, "stem", -1, hw, (sdf, _bark(c, s, _side(c, stem, s, sdf + hw, hw), (0.30, 0.55, 0.20), 24 * k), 2))
    for i, (frac, ang) in enumerate(((0.3, -2.6), (0.5, -0.45))):
        a = _point_at(stem, frac)
        u = np.array([np.cos(ang), np.sin(ang)])
        base = a + 30 * k * u
        _, st = _leaf(c, base, base + 140 * k * u, 34 * k, a, 3.5 * k, 1, colour=(0.22, 0.50, 0.16))
        c.part(st, f"leaf {i + 1}", 0, 34 * k)
    top = stem[-1]
    d = stem[-1] - stem[-2]
    u = d / np.hypot(*d)
    rh = 42 * k
    centre = top + 0.6 * rh * u
    dh = np.hypot(c.xx - centre[0], c.yy - centre[1])
    seeds = 0.5 + 0.5 * np.sin(dh / (4 * k)) * np.sin(np.arctan2(c.yy - centre[1], c.xx - centre[0]) * 13)
    head_rgb = np.asarray((0.45, 0.25, 0.08))[None, None] * (0.8 + 0.35 * seeds)[..., None]
    c.part([top - 12 * k * u, centre, centre + 0.8 * rh * u], "head", 0, rh,
           (dh - rh, head_rgb + c.noise(6 * k, 0.03)[..., None], 3))
    reach, phw = 120 * k, 26 * k
    a0 = np.arctan2(u[1], u[0])
    for i in range(6):
        a = a0 + (i + 0.5) * 2 * np.pi / 6
        v = np.array([np.cos(a), np.sin(a)])
        pts = np.linspace(centre, centre + reach * v, 6)
        sdf, s = c.capsule(pts, phw, taper=0.75)
        # a petal widens away from the head: a lens (narrow root, round tip)
        rel = np.clip(s / reach, 0, 1)
        sdf = sdf + phw * 0.55 * (1 - np.sin(np.pi * (0.15 + 0.85 * rel)) ** 0.6)
        streak = 0.5 + 0.5 * np.cos(2 * np.pi * _side(c, pts, s, sdf + phw, phw) * 1.5)
        rgb = np.asarray((0.98, 0.80, 0.15))[None, None] * (0.85 + 0.2 * streak - 0.1 * rel)[..., None]
        c.part(pts, f"petal {i + 1}", 3, phw, (sdf, rgb + c.noise(10 * k, 0.03)[..., None], 1))
    return c.result()


@checked(size=Int(64, 8192))
@_square_doc
def hand(size: int = 600, *, rng=None) -> PartObject:
    """A hand (``size x size``): a forearm, a palm, four fingers and a thumb.

    Parts: ``forearm`` (from the bottom edge up to the wrist), ``palm``
    (a child of the forearm, its stroke from the wrist to the knuckles;
    ``1.6x`` the forearm's width), ``finger 1..4`` (children of the
    palm, their strokes from the knuckle line inside the palm up, slightly
    fanned out: they start inside their parent, not on its stroke, as a
    user draws them) and ``thumb`` (a child of the palm, its stroke from
    the palm's stroke, leaving the palm's side at ~20 degrees). Each finger and
    the thumb has a pale nail near its tip.

    {square_params}

    Examples
    --------
    >>> obj = hand(160, rng=0)
    >>> obj.names[-1], obj.parents
    ('thumb', [-1, 0, 1, 1, 1, 1, 1])
    """
    c, n, k = _square_canvas(size, 600.0, rng)
    skin = np.asarray((0.88, 0.66, 0.50))
    sleeve = np.asarray((0.30, 0.45, 0.35))
    fore = np.array([(0.46 * n, 0.97 * n), (0.47 * n, 0.82 * n), (0.48 * n, 0.66 * n)])
    fhw = 34 * k
    sdf, s = c.capsule(fore, fhw)
    c.part(fore, "forearm", -1, fhw, (sdf, _bark(c, s, _side(c, fore, s, sdf + fhw, fhw), sleeve, 22 * k), 2))
    palm = np.array([fore[-1], (0.485 * n, 0.55 * n), (0.49 * n, 0.44 * n)])
    phw = 55 * k
    sdf, s = c.capsule(palm, phw)
    lines = np.abs(np.sin((c.xx + 0.6 * c.yy) / (9 * k))) < 0.06
    rgb = skin[None, None] * (1 - 0.12 * np.clip(np.abs(c.xx - 0.485 * n) / phw, 0, 1))[..., None]
    rgb = np.where(lines[..., None], skin * 0.85, rgb) + c.noise(12 * k, 0.03)[..., None]
    c.part(palm, "palm", 0, phw, (sdf, rgb, 3))

    def digit(start, ang, length, hw, name):
        u = np.array([np.cos(ang), np.sin(ang)])
        v = np.array([-u[1], u[0]])
        tt = np.linspace(0.0, 1.0, 7)[:, None]
        pts = start + length * (tt * u + 0.06 * tt ** 2 * v)
        sdf, s = c.capsule(pts, hw, taper=0.85)
        side = _side(c, pts, s, sdf + hw, hw)
        shade = 1 - 0.18 * np.abs(side) ** 2
        creases = np.abs(np.sin(np.pi * s / (0.33 * length))) < 0.08
        rgb = skin[None, None] * shade[..., None]
        rgb = np.where((creases & (s > 0.2 * length))[..., None], skin * 0.8, rgb)
        nail = (s > length - 0.33 * hw - 0.45 * length * 0.3) & (s < length) & (np.abs(side) < 0.55)
        rgb = np.where(nail[..., None], np.array([0.97, 0.86, 0.82]), rgb)
        c.part(pts, name, 1, hw, (sdf, rgb + c.noise(8 * k, 0.03)[..., None], 1))

    knuckles = palm[-1]
    for i, (dx, ang, length) in enumerate(((-0.66, -1.85, 120), (-0.22, -1.65, 140), (0.22, -1.5, 132),
                                           (0.64, -1.3, 100))):
        digit(knuckles + np.array([dx * phw, 0.1 * phw]), ang, length * k, 15 * k, f"finger {i + 1}")
    # the thumb's stroke starts on the palm's (its first stretch hidden under the palm)
    digit(_point_at(palm, 0.45), -0.35, 115 * k + 0.5 * phw, 17 * k, "thumb")
    return c.result()
