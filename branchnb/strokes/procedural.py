"""Procedural multi-part objects with known parts and skeleton strokes.

Test objects for stroke editing whose right answer is known: every pixel
carries the index of the part it belongs to, every part has its skeleton
stroke (starting on its parent's skeleton) and its parent. They are drawn
like clip art (flat colours with some texture, a dark outline around the
silhouette, none across the joints), at any size:

* :func:`twig`: a twig with leaves (petiole + blade with a midrib) and
  round fruits on stems, one fruit close enough to lie within the twig's
  patch band;
* :func:`bare_tree`: a trunk with limbs and twigs on the limbs;
* :func:`figure`: a body with a head, two arms and two legs;
* :func:`starfish`: five tapering arms round a disk (the disk wider than
  any arm, so a turned arm's root lies within the body);
* :func:`antlers`: a curved beam with four tines leaving it at narrow
  angles (sharp crotches);
* :func:`coral`: a trunk, three branches and a sub-branch on each
  (parts of parts), round tips and polyp dots.

>>> obj = twig(400, rng=0)
>>> obj.image.shape, obj.names[:3]
((240, 400, 4), ['twig', 'leaf 1', 'leaf 2'])
>>> obj.parents[:3]
[-1, 0, 0]
"""

from __future__ import annotations

import inspect
from dataclasses import dataclass

import numpy as np

from ..core.random import as_rng
from ..core.validate import Int, checked

__all__ = ["PartObject", "twig", "bare_tree", "figure", "starfish", "antlers", "coral"]

#: Outline colour of the procedural objects.
OUTLINE = (0.12, 0.09, 0.06)


@dataclass
class PartObject:
    """An RGBA object made of known parts.

    Parameters
    ----------
    image : (H, W, 4) float32 ndarray
        The object on a transparent background (straight alpha).
    labels : (H, W) int ndarray
        Part index of every pixel with alpha > 0.5 (-1 elsewhere); the
        outline belongs to the part it surrounds.
    strokes : list of (N, 2) ndarray
        One skeleton stroke per part, ``(x, y)`` pixels; a child's stroke
        starts on its parent's stroke.
    parents : list of int
        Parent part of every part (-1 for the root).
    names : list of str
        Name of every part (e.g. ``"leaf 1"``).
    widths : list of float
        Typical half width of every part (px).
    outline : float
        Outline width (px).

    Examples
    --------
    >>> obj = figure(128, rng=0)
    >>> len(obj.strokes) == len(obj.parents) == len(obj.names), int(obj.labels.max())
    (True, 5)
    """

    image: np.ndarray
    labels: np.ndarray
    strokes: list
    parents: list
    names: list
    widths: list
    outline: float

    def _repr_png_(self) -> bytes:
        from ..core.image import composite_over
        from ..core.io import encode_png

        return encode_png(composite_over(self.image))


def _seg_distance(px, py, pts: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """Distance of pixel centres to a polyline and the arc length of the nearest point."""
    best = np.full(px.shape, np.inf)
    best_s = np.zeros(px.shape)
    s0 = 0.0
    for a, b in zip(pts[:-1], pts[1:]):
        ab = b - a
        n2 = float(ab @ ab)
        if n2 < 1e-12:
            continue
        t = np.clip(((px - a[0]) * ab[0] + (py - a[1]) * ab[1]) / n2, 0.0, 1.0)
        d = np.hypot(px - a[0] - t * ab[0], py - a[1] - t * ab[1])
        closer = d < best
        best = np.where(closer, d, best)
        best_s = np.where(closer, s0 + t * np.sqrt(n2), best_s)
        s0 += np.sqrt(n2)
    return best, best_s


class _Canvas:
    """Parts as signed distance fields, composed into one clip-art object."""

    def __init__(self, h: int, w: int, outline: float, rng: np.random.Generator):
        self.h, self.w = h, w
        self.yy, self.xx = np.mgrid[0:h, 0:w].astype(np.float64)
        self.outline = outline
        self.rng = rng
        self.sdf = []     # per layer: signed distance (negative inside)
        self.colour = []  # per layer: (H, W, 3)
        self.order = []   # per layer: drawing priority (higher on top)
        # per part: its skeleton stroke, name, parent part and typical half width
        self.strokes, self.names, self.parents, self.widths = [], [], [], []

    def add(self, sdf: np.ndarray, colour: np.ndarray, order: int) -> int:
        self.sdf.append(sdf)
        self.colour.append(colour)
        self.order.append(order)
        return len(self.sdf) - 1

    def part(self, stroke, name: str, parent: int, width: float, layer=None) -> None:
        """Record a part: its stroke, name, parent and half width (and draw ``layer``,
        ``(sdf, colour, order)``, if given)."""
        if layer is not None:
            self.add(*layer)
        self.strokes.append(np.array(stroke))
        self.names.append(name)
        self.parents.append(parent)
        self.widths.append(width)

    def result(self) -> PartObject:
        """The rendered object with the recorded parts."""
        img, labels = self.render()
        return PartObject(img, labels, self.strokes, self.parents, self.names, self.widths, self.outline)

    def capsule(self, pts, half_width, *, taper: float = 1.0):
        """SDF of a tapered capsule along ``pts`` and the arc length map.

        Computed on the capsule's box grown by ``half_width + outline + 3`` px
        only: farther out the distance is set to ``1e6`` and the arc length to
        0 (no pixel there is drawn by this part, the rendered image is the
        same as with exact distances everywhere).
        """
        pts = np.asarray(pts, float)
        m = float(half_width) + self.outline + 3.0
        x0, y0 = np.maximum(np.floor(pts.min(axis=0) - m).astype(int), 0)
        x1, y1 = np.ceil(pts.max(axis=0) + m).astype(int) + 1
        box = (slice(y0, min(y1, self.h)), slice(x0, min(x1, self.w)))
        d = np.full((self.h, self.w), 1e6)
        s = np.zeros((self.h, self.w))
        d[box], s[box] = _seg_distance(self.xx[box], self.yy[box], pts)
        length = float(np.hypot(*np.diff(pts, axis=0).T).sum())
        hw = half_width * (1.0 - (1.0 - taper) * np.clip(s / max(length, 1e-9), 0, 1))
        return d - hw, s

    def render(self) -> tuple[np.ndarray, np.ndarray]:
        # Which part shows at each pixel: the highest drawing order among the
        # parts covering it (or the nearest part outside all of them); the
        # first part wins a tie. One part at a time (no stack of every part).
        union = self.sdf[0].copy()
        best = np.where(self.sdf[0] <= 0.0, float(self.order[0]), -1e9) - 1e-3 * self.sdf[0]
        top = np.zeros(union.shape, np.intp)
        for i in range(1, len(self.sdf)):
            sd = self.sdf[i]
            np.minimum(union, sd, out=union)
            score = np.where(sd <= 0.0, float(self.order[i]), -1e9) - 1e-3 * sd
            better = score > best
            best[better] = score[better]
            top[better] = i
        alpha = np.clip(0.5 - union, 0.0, 1.0)
        rgb = self.colour[0].copy()
        for i in range(1, len(self.colour)):
            m = top == i
            rgb[m] = self.colour[i][m]
        # A dark outline along the silhouette of the union only (none across joints).
        rim = np.clip(union + self.outline + 0.5, 0.0, 1.0)
        rgb = rgb * (1 - rim[..., None]) + np.asarray(OUTLINE)[None, None] * rim[..., None]
        img = np.dstack([np.clip(rgb, 0, 1), alpha]).astype(np.float32)
        img[alpha == 0, :3] = 0.0
        labels = np.where(alpha > 0.5, top, -1)
        return img, labels

    def noise(self, scale: float, amount: float) -> np.ndarray:
        """Smooth value noise in [-amount, amount] (bilinear upsampling of a coarse grid)."""
        import cv2

        gh, gw = max(2, int(self.h / scale) + 2), max(2, int(self.w / scale) + 2)
        g = self.rng.uniform(-amount, amount, (gh, gw)).astype(np.float32)
        return cv2.resize(g, (self.w, self.h), interpolation=cv2.INTER_CUBIC).astype(np.float64)


def _square_canvas(size: int, base: float, rng) -> tuple[_Canvas, int, float]:
    """A ``size x size`` canvas, its side ``n`` and scale ``k = n / base`` (outline ``max(1, 2 k)`` px)."""
    n = int(size)
    k = n / base
    return _Canvas(n, n, outline=max(1.0, 2.0 * k), rng=as_rng(rng)), n, k


_SQUARE_PARAMS = """Parameters
    ----------
    size : int
        Side of the square image in pixels (64 .. 8192); {default}.
    rng : int or numpy.random.Generator, optional
        Random generator or seed of the texture noise.

    Returns
    -------
    PartObject"""


def _square_doc(func):
    """Fill ``{square_params}`` in ``func``'s docstring (the shared Parameters and Returns
    of the square objects, with ``size``'s default)."""
    default = inspect.signature(func).parameters["size"].default
    func.__doc__ = func.__doc__.replace("{square_params}", _SQUARE_PARAMS.format(default=default))
    return func


def _bark(c: _Canvas, s: np.ndarray, d_signed: np.ndarray, base, period: float) -> np.ndarray:
    """Bark: stripes along the arc length with noise, a shading across."""
    stripe = 0.5 + 0.5 * np.sin(2 * np.pi * s / period + 3 * c.noise(period * 2, 1.0))
    shade = 1.0 - 0.25 * np.clip(d_signed, -1, 1)
    rgb = np.asarray(base)[None, None] * (0.8 + 0.3 * stripe)[..., None] * shade[..., None]
    return rgb + c.noise(period / 2, 0.04)[..., None]


def _side(c: _Canvas, pts: np.ndarray, s: np.ndarray, d: np.ndarray, half_width) -> np.ndarray:
    """Signed offset across a polyline, in half widths (-1 .. 1)."""
    pts = np.asarray(pts, float)
    seg = np.clip(np.searchsorted(np.concatenate([[0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))]),
                                  s) - 1, 0, len(pts) - 2)
    t = pts[seg + 1] - pts[seg]
    cross = t[..., 0] * (c.yy - pts[seg, 1]) - t[..., 1] * (c.xx - pts[seg, 0])
    return np.sign(cross) * d / np.maximum(half_width, 1e-6)


def _leaf(c: _Canvas, base, tip, half_width, petiole_start, petiole_hw, order, colour=(0.25, 0.55, 0.18)):
    """A leaf: a lens-shaped blade from ``base`` to ``tip`` and a petiole from the twig."""
    base, tip = np.asarray(base, float), np.asarray(tip, float)
    axis = tip - base
    length = float(np.hypot(*axis))
    u = axis / length
    rel_x = (c.xx - base[0]) * u[0] + (c.yy - base[1]) * u[1]
    rel_y = -(c.xx - base[0]) * u[1] + (c.yy - base[1]) * u[0]
    t = np.clip(rel_x / length, 0, 1)
    profile = half_width * np.sin(np.pi * t) ** 0.8
    blade = np.maximum(np.abs(rel_y) - profile, np.maximum(-rel_x, rel_x - length))
    pet, ps = c.capsule([petiole_start, base + 0.15 * axis], petiole_hw)
    sdf = np.minimum(blade, pet)
    vein = np.abs(rel_y) < max(0.6, 0.05 * half_width)
    side_veins = np.abs(np.sin(2 * np.pi * (rel_x - 0.7 * np.abs(rel_y)) / (0.18 * length))) < 0.12
    rgb = np.asarray(colour)[None, None] * (1.0 + 0.25 * rel_y / max(half_width, 1))[..., None]
    rgb = rgb + c.noise(half_width, 0.03)[..., None]
    light = np.asarray(colour) * 1.5 + 0.1
    rgb = np.where((vein | side_veins & (np.abs(rel_y) < 0.8 * profile))[..., None], light, rgb)
    rgb = np.where((pet < blade)[..., None], np.asarray(colour) * 0.8, rgb)
    return c.add(sdf, rgb, order), [np.asarray(petiole_start, float), base, base + 0.5 * axis,
                                    base + 0.92 * axis]


def _fruit(c: _Canvas, attach, centre, radius, stem_hw, order, colour=(0.78, 0.12, 0.10)):
    """A round fruit on a stem from ``attach``."""
    centre = np.asarray(centre, float)
    attach = np.asarray(attach, float)
    d = np.hypot(c.xx - centre[0], c.yy - centre[1])
    body = d - radius
    u = (centre - attach) / np.hypot(*(centre - attach))
    stem, _ = c.capsule([attach, centre - 0.8 * radius * u], stem_hw)
    sdf = np.minimum(body, stem)
    hx, hy = centre - 0.4 * radius * np.array([-u[1], u[0]]) - 0.35 * radius * u
    glow = np.exp(-((c.xx - hx) ** 2 + (c.yy - hy) ** 2) / (2 * (0.3 * radius) ** 2))
    rgb = np.asarray(colour)[None, None] * (0.75 + 0.25 * (1 - d / radius))[..., None]
    rgb = rgb + 0.6 * glow[..., None] + c.noise(radius / 2, 0.03)[..., None]
    rgb = np.where((stem < body)[..., None], np.array([0.35, 0.42, 0.15]), rgb)
    return c.add(sdf, rgb, order), [attach, centre, centre + 0.85 * radius * u]


@checked(size=Int(64, 8192))
def twig(size: int = 1000, *, rng=None) -> PartObject:
    """A twig with two leaves above and two fruits below it (``0.6 size x size``).

    Parts: ``twig``, ``leaf 1``, ``leaf 2``, ``fruit 1`` (on a long stem),
    ``fruit 2`` (on a short stem: within the twig's patch band).

    Parameters
    ----------
    size : int
        Width in pixels (64 .. 8192).
    rng : int or numpy.random.Generator, optional
        Texture noise.

    Examples
    --------
    >>> obj = twig(300, rng=1)
    >>> int(obj.labels.max()), len(obj.strokes)
    (4, 5)
    """
    rng = as_rng(rng)
    w, h = int(size), int(round(0.6 * size))
    k = size / 1000.0
    c = _Canvas(h, w, outline=max(1.0, 2.5 * k), rng=rng)
    x = np.linspace(0.06 * w, 0.94 * w, 40)
    spine = np.c_[x, 0.5 * h + 0.03 * h * np.sin((x - x[0]) / w * 2 * np.pi)]
    tw_hw = 16 * k
    sdf, s = c.capsule(spine, tw_hw, taper=0.55)
    d = sdf + tw_hw
    rgb = _bark(c, s, _side(c, spine, s, d, tw_hw), (0.45, 0.30, 0.17), 40 * k)
    c.part(spine, "twig", -1, tw_hw, (sdf, rgb, 3))

    def on_spine(frac):
        i = frac * (len(spine) - 1)
        j = int(i)
        return spine[j] + (i - j) * (spine[min(j + 1, len(spine) - 1)] - spine[j])

    for n, (frac, ang) in enumerate(((0.28, -2.2), (0.62, -1.0))):
        a = on_spine(frac)
        u = np.array([np.cos(ang), np.sin(ang)])
        base = a + 70 * k * u
        _, st = _leaf(c, base, base + 230 * k * u, 55 * k, a, 4.5 * k, 1)
        c.part(st, f"leaf {n + 1}", 0, 55 * k)
    for n, (frac, stem_len, rad) in enumerate(((0.44, 95, 42), (0.78, 22, 38))):
        a = on_spine(frac)
        centre = a + np.array([8 * k, (stem_len + rad) * k])
        _, st = _fruit(c, a, centre, rad * k, 3.5 * k, 2)
        c.part(st, f"fruit {n + 1}", 0, rad * k)
    return c.result()


@checked(size=Int(64, 8192))
@_square_doc
def bare_tree(size: int = 800, *, rng=None) -> PartObject:
    """A bare tree (``size x size``): a trunk, three limbs and a twig on each limb.

    Parts: ``trunk``, ``limb 1..3`` (children of the trunk), ``twig 1..3``
    (twig ``i`` on limb ``i``).

    {square_params}

    Examples
    --------
    >>> obj = bare_tree(200, rng=0)
    >>> obj.parents
    [-1, 0, 0, 0, 1, 2, 3]
    """
    c, n, k = _square_canvas(size, 800.0, rng)
    trunk = np.array([(0.5 * n, 0.95 * n), (0.49 * n, 0.7 * n), (0.51 * n, 0.45 * n), (0.5 * n, 0.2 * n)])
    bark = (0.40, 0.28, 0.18)
    parts = [(trunk, 26 * k, 0.45, -1)]
    limbs = [(0.62, -2.5, 0.30), (0.45, -0.55, 0.33), (0.30, -2.0, 0.22)]

    for frac, ang, length in limbs:
        a = _point_at(trunk, frac)
        u = np.array([np.cos(ang), np.sin(ang)])
        v = np.array([-u[1], u[0]])
        pts = np.array([a, a + 0.5 * length * n * u + 0.03 * n * v, a + length * n * u])
        parts.append((pts, 11 * k, 0.5, 0))
    for i, (_, ang, _) in enumerate(limbs):
        limb = parts[1 + i][0]
        a = _point_at(limb, 0.6)
        ang2 = ang + (0.7 if i % 2 == 0 else -0.7)
        u = np.array([np.cos(ang2), np.sin(ang2)])
        parts.append((np.array([a, a + 0.12 * n * u]), 5 * k, 0.5, 1 + i))
    for i, (pts, hw, taper, parent) in enumerate(parts):
        sdf, s = c.capsule(pts, hw, taper=taper)
        d = sdf + hw
        c.part(pts, "trunk" if i == 0 else f"limb {i}" if i <= 3 else f"twig {i - 3}", parent, hw,
               (sdf, _bark(c, s, _side(c, pts, s, d, hw), bark, 30 * k), 3 - (i > 0) - (i > 3)))
    return c.result()


@checked(size=Int(64, 8192))
@_square_doc
def figure(size: int = 600, *, rng=None) -> PartObject:
    """A figure (``size x size``): a body with a head, two arms and two legs.

    Parts: ``body``, ``head``, ``left arm``, ``right arm``, ``left leg``,
    ``right leg``; all children of the body, their strokes starting on the
    body's centre line.

    {square_params}

    Examples
    --------
    >>> figure(200, rng=0).names[1]
    'head'
    """
    c, n, k = _square_canvas(size, 600.0, rng)
    body = np.array([(0.5 * n, 0.62 * n), (0.5 * n, 0.32 * n)])
    cloth = (0.20, 0.35, 0.70)
    skin = (0.90, 0.70, 0.55)
    sdf, s = c.capsule(body, 55 * k)
    stripes = 0.5 + 0.5 * np.sin(2 * np.pi * s / (25 * k))
    c.part(body, "body", -1, 55 * k, (sdf, np.asarray(cloth)[None, None] * (0.8 + 0.3 * stripes)[..., None]
                                      + c.noise(20 * k, 0.03)[..., None], 3))
    head_c = np.array([0.5 * n, 0.17 * n])
    dh = np.hypot(c.xx - head_c[0], c.yy - head_c[1])
    face = np.asarray(skin)[None, None] * (1 - 0.15 * dh / (60 * k))[..., None]
    eyes = (np.hypot(np.abs(c.xx - head_c[0]) - 20 * k, c.yy - head_c[1] + 8 * k) < 6 * k)
    face = np.where(eyes[..., None], 0.1, face)
    neck, _ = c.capsule([body[1], head_c], 14 * k)
    c.part([body[1] + (0, 20 * k), head_c, head_c - (0, 50 * k)], "head", 0, 60 * k,
           (np.minimum(dh - 60 * k, neck), face, 2))
    limbs = [("left arm", body[1] + (0, 30 * k), (-0.25, 0.17), 16 * k, skin),
             ("right arm", body[1] + (0, 30 * k), (0.25, 0.10), 16 * k, skin),
             ("left leg", body[0] - (0, 10 * k), (-0.12, 0.32), 22 * k, cloth),
             ("right leg", body[0] - (0, 10 * k), (0.12, 0.32), 22 * k, cloth)]
    for name, start, (dx, dy), hw, col in limbs:
        end = start + np.array([dx * n, dy * n])
        mid = 0.5 * (start + end) + np.array([0.04 * n * np.sign(dx), 0])
        pts = np.array([start, mid, end])
        sdf, s = c.capsule(pts, hw, taper=0.8)
        d = sdf + hw
        c.part(pts, name, 0, hw, (sdf, _bark(c, s, _side(c, pts, s, d, hw), col, 30 * k) * 1.1, 1))
    return c.result()


@checked(size=Int(64, 8192))
@_square_doc
def starfish(size: int = 400, *, rng=None) -> PartObject:
    """A starfish (``size x size``): a disk and five tapering arms round it.

    Parts: ``disk`` (its stroke a short segment across the centre) and
    ``arm 1..5`` (children of the disk, their strokes from the centre to
    the tips, arm 1 pointing up, then clockwise). The disk (radius
    ``0.12 size``) is wider than the arms' roots (half width ``0.09
    size``): a turned arm's root lies inside the body.

    {square_params}

    Examples
    --------
    >>> obj = starfish(128, rng=0)
    >>> obj.names[:2], obj.parents
    (['disk', 'arm 1'], [-1, 0, 0, 0, 0, 0])
    """
    c, n, k = _square_canvas(size, 400.0, rng)
    centre = np.array([0.5 * n, 0.5 * n])
    orange = (0.88, 0.47, 0.20)
    rd, reach, hw = 0.12 * n, 0.42 * n, 0.09 * n
    # tubercles: light dots on a jittered grid, the same pattern on every part
    period = 14 * k
    jx, jy = c.noise(3 * period, 0.25 * period), c.noise(3 * period, 0.25 * period)
    gx, gy = (c.xx + jx) / period, (c.yy + jy) / period
    dots = np.hypot(gx - np.round(gx), gy - np.round(gy)) < 0.22
    dr = np.hypot(c.xx - centre[0], c.yy - centre[1])

    def skin(shade):
        rgb = np.asarray(orange)[None, None] * shade[..., None] + c.noise(8 * k, 0.04)[..., None]
        return np.where(dots[..., None], np.asarray(orange) * 1.25 + 0.05, rgb)

    c.part([centre - (0.5 * rd, 0), centre + (0.5 * rd, 0)], "disk", -1, rd,
           (dr - rd, skin(1.0 - 0.15 * np.clip(dr / rd, 0, 1)), 2))
    for i, a in enumerate(-np.pi / 2 + np.arange(5) * 2 * np.pi / 5):
        tip = centre + reach * np.array([np.cos(a), np.sin(a)])
        pts = np.linspace(centre, tip, 8)
        sdf, s = c.capsule(pts, hw, taper=0.2)
        c.part(pts, f"arm {i + 1}", 0, hw, (sdf, skin(0.95 - 0.2 * np.clip(s / reach, 0, 1)), 1))
    return c.result()


def _point_at(pts: np.ndarray, frac: float) -> np.ndarray:
    """The point at ``frac`` of a polyline's arc length."""
    s = np.concatenate([[0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    t = frac * s[-1]
    return np.array([np.interp(t, s, pts[:, 0]), np.interp(t, s, pts[:, 1])])


@checked(size=Int(64, 8192))
@_square_doc
def antlers(size: int = 600, *, rng=None) -> PartObject:
    """An antler (``size x size``): a curved beam and four tines off it.

    Parts: ``beam`` (from the burr at the bottom left, curving up to the
    right) and ``tine 1..4`` (children of the beam, leaving it at 35-55
    degrees: narrow, sharp crotches). Bone coloured with streaks along
    every part.

    {square_params}

    Examples
    --------
    >>> obj = antlers(160, rng=0)
    >>> obj.names[1], obj.parents
    ('tine 1', [-1, 0, 0, 0, 0])
    """
    c, n, k = _square_canvas(size, 600.0, rng)
    t = np.linspace(0.0, 1.0, 24)
    beam = np.c_[0.22 * n + 0.55 * n * t ** 1.3, 0.92 * n - 0.8 * n * np.sin(0.5 * np.pi * t) ** 1.1]
    bone = (0.86, 0.78, 0.60)
    hw0 = 19 * k
    sdf, s = c.capsule(beam, hw0, taper=0.4)
    c.part(beam, "beam", -1, hw0, (sdf, _bark(c, s, _side(c, beam, s, sdf + hw0, hw0), bone, 26 * k), 3))
    for i, (frac, turn, length) in enumerate(((0.16, 0.95, 0.22), (0.42, -0.75, 0.24), (0.63, -0.65, 0.2),
                                              (0.8, -0.8, 0.15))):
        a = _point_at(beam, frac)
        j = int(frac * (len(beam) - 1))
        d = beam[j + 1] - beam[j]
        ang = np.arctan2(d[1], d[0]) + turn
        u = np.array([np.cos(ang), np.sin(ang)])
        v = np.array([-u[1], u[0]])
        tt = np.linspace(0.0, 1.0, 8)[:, None]
        pts = a + length * n * (tt * u - 0.15 * tt ** 2 * v * np.sign(turn))
        hw = 12 * k
        sdf, s = c.capsule(pts, hw, taper=0.35)
        c.part(pts, f"tine {i + 1}", 0, hw, (sdf, _bark(c, s, _side(c, pts, s, sdf + hw, hw), bone, 20 * k) * 1.03, 2))
    return c.result()


@checked(size=Int(64, 8192))
@_square_doc
def coral(size: int = 600, *, rng=None) -> PartObject:
    """A branching coral (``size x size``): a trunk, three branches, a sub-branch on each.

    Parts: ``trunk``, ``branch 1..3`` (children of the trunk) and ``tip
    1..3`` (tip ``i`` a child of branch ``i``): parts of parts. Every
    part has a round end; light polyp dots on a jittered grid cover all.

    {square_params}

    Examples
    --------
    >>> coral(160, rng=0).parents
    [-1, 0, 0, 0, 1, 2, 3]
    """
    c, n, k = _square_canvas(size, 600.0, rng)
    pink = (0.93, 0.45, 0.42)
    period = 13 * k
    jx, jy = c.noise(3 * period, 0.25 * period), c.noise(3 * period, 0.25 * period)
    gx, gy = (c.xx + jx) / period, (c.yy + jy) / period
    dots = np.hypot(gx - np.round(gx), gy - np.round(gy)) < 0.2

    def skin(s, length):
        shade = 0.85 + 0.2 * np.clip(s / max(length, 1e-9), 0, 1)
        rgb = np.asarray(pink)[None, None] * shade[..., None] + c.noise(8 * k, 0.04)[..., None]
        return np.where(dots[..., None], np.minimum(np.asarray(pink) * 1.2 + 0.1, 1.0), rgb)

    trunk = np.array([(0.5 * n, 0.95 * n), (0.49 * n, 0.75 * n), (0.5 * n, 0.55 * n)])
    parts = [(trunk, 26 * k, -1)]
    for frac, ang, length in ((0.55, -2.35, 0.3), (1.0, -1.5, 0.32), (0.8, -0.6, 0.3)):
        a = _point_at(trunk, frac)
        u = np.array([np.cos(ang), np.sin(ang)])
        v = np.array([-u[1], u[0]])
        parts.append((np.array([a, a + 0.5 * length * n * u + 0.03 * n * v, a + length * n * u]), 17 * k, 0))
    for i, turn in enumerate((0.8, -0.7, -0.75)):
        limb = parts[1 + i][0]
        a = _point_at(limb, 0.55)
        d = limb[2] - limb[1]
        ang = np.arctan2(d[1], d[0]) + turn
        u = np.array([np.cos(ang), np.sin(ang)])
        parts.append((np.array([a, a + 0.09 * n * u, a + 0.17 * n * u]), 11 * k, 1 + i))
    for i, (pts, hw, parent) in enumerate(parts):
        sdf, s = c.capsule(pts, hw)
        c.part(pts, "trunk" if i == 0 else f"branch {i}" if i <= 3 else f"tip {i - 3}", parent, hw,
               (sdf, skin(s, float(np.hypot(*np.diff(pts, axis=0).T).sum())), 3 - (i > 0) - (i > 3)))
    return c.result()
