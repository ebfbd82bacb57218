"""Procedural leaf families with known answers: layers and true correspondences.

The paper has no public data and no ground truth. This generator makes
leaves *of one kind* that differ the way real leaves of one tree do, and
returns for every leaf what a measurement needs: the blade mask, the vein
and spot layers, and keypoints that are the *same material point* on
every leaf of a family.

How a leaf is made
------------------
1. **Outline.** Each kind has a canonical outline in a leaf frame
   (base of the blade at the origin, tip towards -y, blade length about 1):
   a polar radius ``R(a)`` around a centre, ``a`` the angle from the tip
   direction. ``"lobed"`` (palmate, maple-like, 5 pointed lobes) and
   ``"trilobed"`` (3 lobes) are soft maxima of pointed lobe profiles;
   ``"elliptic"`` is an ovate blade with an acuminate tip; ``"fan"`` a
   ginkgo-like fan with a cleft and a wavy arc, whose veins fork
   dichotomously with no network between them
   (:mod:`branchnb.leaves.procedural_fan`). Margins carry
   small teeth: a regular sawtooth in the angle on the lobed kinds;
   serrate teeth (a long convex basal flank, a steep apical one, the tip
   pointing to the apex, about 2 % of the blade length deep) on the
   elliptic kind, one where each secondary vein ends (see 3).
2. **Per-leaf variation** (scaled by ``variation``): each lobe's length,
   a smooth monotone re-parametrisation of the angle
   ``a = h(a_c) = a_c + sum_m eps_m sin(m a_c)`` (lobes move sideways),
   the aspect ratio, a bend of the midrib, then a rotation and a scale
   on the canvas. A *material point* is ``(a_c, rho)``: canonical angle
   and relative radius; it lies at ``c + rho R_i(a_c) dir(h_i(a_c))`` in
   leaf ``i``'s frame, then goes through the bend and the similarity.
   ``keypoints`` are a fixed set of material points (a golden-angle
   spiral in ``(a_c, rho)``), so keypoint ``k`` is the same point of every
   leaf: the ground truth for registration.
3. **Venation** by the open venation process of Runions et al. (2005):
   the blade grows uniformly (about its base) from ``0.2`` of its final
   size; at each growth stage auxin sources are added by dart throwing
   (birth distance ``b`` to sources and veins), every source attracts its
   nearest vein node, a node grows one step ``D`` towards the mean
   direction of its sources, sources are removed once a vein comes within
   the kill distance ``d_k`` (open venation), and long vein segments
   stretched by growth are subdivided. Widths follow the pipe model
   (Murray's law ``w^2.5 = sum of the children's w^2.5``), so veins
   widen towards the base; they are drawn with
   :func:`branchnb.core.render.draw_polylines`. The petiole continues the
   main vein below the blade.

   The process starts from the kind's *primary* veins, present from the
   first stage and stretched by growth like everything else: one along
   each lobe axis of the lobed kinds; on the elliptic kind a midrib and a
   fixed set of secondaries (8 pairs, alternate, leaving the midrib at
   58 degrees near the base to 38 near the apex, curving towards the apex,
   each ending at a tooth). That is *craspedodromous* pinnate venation, as
   in beech, elm, chestnut and the Zelkova leaf in
   ``data/leaves/zelkova_leaf.jpg``: every secondary runs nearly straight
   from the midrib to a tooth, and the leaves of one tree have about the
   same number at about the same places. Primaries are laid out in
   *material* coordinates, so they move with the leaf's angle warp like
   the lobes and teeth they end at; per leaf they are jittered a little
   (secondaries: their origin on the midrib by 0.012, their bend by 0.008
   leaf units). The finer veins between them grow anew on every leaf.
   Why the elliptic kind needs them: its angle warp slides material
   points *along* a smooth outline, and with only a midrib (at
   ``a_c = 0, pi``, where the warp is the identity), randomly regrown
   secondaries and sub-pixel teeth, nothing in the image showed where a
   material point had gone: the ground truth of a registration was not
   observable (registration cut the true keypoint error by 36 %, against
   74 % through the true outline correspondences).
4. **Spots**: a few irregular blobs at random material points.
5. **Colour texture**: a palette (``"green"``, ``"autumn"``) modulated by
   multi-octave value noise, veins lighter than the blade, spots darker.

Layers are exclusive: a pixel of ``layers["veins"]`` (veins and petiole)
is never in ``layers["spots"]``; the blade (``blade``, lamina *and*
petiole: the leaf's silhouette, alpha > 0.5) is what remains.

References
----------
A. Runions, M. Fuhrer, B. Lane, P. Federl, A.-G. Rolland-Lagan,
P. Prusinkiewicz, "Modeling and visualization of leaf venation patterns",
ACM Trans. Graph. 24(3), 2005.
"""

from __future__ import annotations

from dataclasses import dataclass, field

import cv2
import numpy as np

from ..core.image import to_uint8
from ..core.random import as_rng
from ..core.render import coverage_polylines
from ..core.validate import Int, Real, Seq, brief, check_int, checked, real_array
from .procedural_fan import FAN, dichotomous_veins, fan_radius
from .procedural_venation import _grow_venation, _smooth_line, _vein_polylines

__all__ = ["ProceduralLeaf", "procedural_leaf", "leaf_family", "KINDS", "PALETTES"]

#: Canonical lobes per kind: (angle from the tip in degrees, length), plus
#: the radius at the petiole sinus, and the centre of the polar outline.
KINDS = {
    "lobed": {"lobes": ((0.0, 0.62), (52.0, 0.56), (-52.0, 0.56), (108.0, 0.36), (-108.0, 0.36)),
              "width": (46.0, 44.0, 44.0, 40.0, 40.0), "sinus": 0.09, "centre": (0.0, 0.0),
              "teeth": 34, "tooth_depth": 0.025, "petiole": 0.28},
    "trilobed": {"lobes": ((0.0, 0.62), (62.0, 0.48), (-62.0, 0.48)),
                 "width": (44.0, 44.0, 44.0), "sinus": 0.12, "centre": (0.0, 0.0),
                 "teeth": 28, "tooth_depth": 0.02, "petiole": 0.25},
    "elliptic": {"lobes": (), "width": (), "sinus": 0.0, "centre": (0.0, -0.5),
                 "half_width": 0.24, "half_length": 0.5, "teeth": 46, "tooth_depth": 0.09,
                 "petiole": 0.18,
                 # Pinnate, craspedodromous: pairs of secondaries from the midrib,
                 # each ending at a tooth; (base, apex) angles to the midrib.
                 "secondaries": {"pairs": 8, "span": (0.1, 0.82), "angle": (58.0, 38.0),
                                 "curve": 12.0, "alternate": True, "extra_teeth": (1, 3)}},
    # Ginkgo-like: a fan with a cleft and a wavy arc, dichotomous veins (branchnb.leaves.procedural_fan).
    "fan": FAN,
}

#: Colours (RGB in [0, 1]) of blade, second blade tone (mottling), veins and spots.
PALETTES = {
    "green": {"blade": (0.28, 0.50, 0.16), "mottle": (0.42, 0.58, 0.18),
              "veins": (0.62, 0.74, 0.36), "spots": (0.42, 0.28, 0.12)},
    "autumn": {"blade": (0.90, 0.66, 0.12), "mottle": (0.82, 0.42, 0.08),
               "veins": (0.97, 0.86, 0.46), "spots": (0.40, 0.20, 0.06)},
}


@dataclass
class ProceduralLeaf:
    """One generated leaf and its ground truth.

    Parameters
    ----------
    image : (H, W, 4) float32 ndarray
        RGBA, transparent background (soft anti-aliased alpha).
    blade : (H, W) bool ndarray
        The leaf's silhouette (lamina and petiole), ``alpha > 0.5``.
    layers : dict of str to (H, W) bool ndarray
        ``"veins"`` (veins and petiole) and ``"spots"``; exclusive, inside ``blade``.
    keypoints : (K, 2) float ndarray
        True corresponding points (x, y): row ``k`` is the same material
        point on every leaf generated with the same ``kind`` and ``n_keypoints``.
    seed : int
        ``procedural_leaf(..., rng=seed)`` with the same arguments gives this leaf again.
    kind, palette : str
        The family (a key of :data:`KINDS`) and colours (a key of
        :data:`PALETTES`) it was made with.
    shape : dict
        The leaf's drawn shape parameters (lobe lengths, angular warp,
        aspect, bend, rotation in degrees, pixels per leaf unit).
    veins : list of (N_i, 2) ndarray
        Vein polylines in image coordinates (the petiole first).
    vein_widths : list of (N_i,) ndarray
        Their per-vertex widths in pixels.
    """

    image: np.ndarray
    blade: np.ndarray
    layers: dict
    keypoints: np.ndarray
    seed: int
    kind: str = "lobed"
    palette: str = "green"
    shape: dict = field(default_factory=dict)
    veins: list = field(default_factory=list, repr=False)
    vein_widths: list = field(default_factory=list, repr=False)

    def on_white(self) -> np.ndarray:
        """The leaf composited over white: (H, W, 3) float32, opaque."""
        a = self.image[:, :, 3:4]
        return (self.image[:, :, :3] * a + (1.0 - a)).astype(np.float32)

    def _repr_png_(self) -> bytes:
        ok, buf = cv2.imencode(".png", cv2.cvtColor(to_uint8(self.on_white()), cv2.COLOR_RGB2BGR))
        return buf.tobytes()


# ---------------------------------------------------------------------------
# outline

def _wrap(a):
    return (np.asarray(a) + np.pi) % (2 * np.pi) - np.pi


def _canonical_radius(kind: dict, ac: np.ndarray, lobe_scale: np.ndarray, teeth_phase: float | None) -> np.ndarray:
    """``R(a_c)``: the outline radius at canonical angle ``a_c`` (radians from the tip)."""
    ac = np.asarray(ac, np.float64)
    if "fan" in kind:
        return fan_radius(kind, ac, lobe_scale, teeth_phase is not None)
    if kind["lobes"]:
        q = 8.0  # soft maximum: sinuses stay sharp-ish but smooth
        acc = np.full(ac.shape, kind["sinus"] ** q)
        for (ang, length), width, s in zip(kind["lobes"], kind["width"], lobe_scale):
            t = np.abs(_wrap(ac - np.deg2rad(ang))) / np.deg2rad(width)
            prof = np.clip(1.0 - t ** 1.25, 0.0, None)
            acc += (length * s * prof) ** q
        r = acc ** (1.0 / q)
    else:
        hw, hl = kind["half_width"], kind["half_length"]
        hw = hw * lobe_scale[0] if len(lobe_scale) else hw
        # Ovate: wider towards the base; acuminate: a drawn-out tip.
        a_half = hw * (1.0 - 0.18 * np.cos(ac))
        r = 1.0 / np.sqrt((np.sin(ac) / a_half) ** 2 + (np.cos(ac) / hl) ** 2)
        r *= 1.0 + 0.12 * np.clip(np.cos(ac), 0, None) ** 24
    if teeth_phase is None:
        return r
    fade = np.clip((np.pi - np.abs(ac)) / 0.6, 0, 1)
    if "secondaries" in kind:
        # Serrate teeth at the kind's tooth tips (where the secondaries end),
        # pointing to the apex: a long basal flank, a steep apical one.
        saw = _serration(kind, ac)
        return r - kind["tooth_depth"] * kind["half_width"] * saw * fade
    # Teeth: a sawtooth along the angle, fading near the petiole.
    n = kind["teeth"]
    saw = np.abs(((ac * n / (2 * np.pi) + teeth_phase) % 1.0) - 0.5) * 2.0  # 0 at tooth tip
    return r * (1.0 - kind["tooth_depth"] * saw * fade)


def _serration(kind: dict, ac: np.ndarray, steep: float = 0.3) -> np.ndarray:
    """Tooth profile (0 at a tip, 1 in a sinus) of a pinnate kind, at canonical angles ``ac``."""
    lay = _pinnate_layout(kind)
    out = np.zeros(np.shape(ac))
    for side, tips in ((1.0, lay["tips_right"]), (-1.0, lay["tips_left"])):
        on = (np.sign(ac) == side) & (np.abs(ac) >= tips[0]) & (np.abs(ac) <= tips[-1])
        k = np.interp(np.abs(ac[on]), tips, np.arange(len(tips), dtype=np.float64))
        u = k - np.floor(k)  # 0 at the apical tip of a gap, 1 at the basal one
        # The basal flank bulges (convex), the apical one drops steeply into the sinus.
        out[on] = np.where(u < 1.0 - steep, (u / (1.0 - steep)) ** 1.6, (1.0 - u) / steep)
    return out


_LAYOUTS: dict = {}


def _pinnate_layout(kind: dict) -> dict:
    """Tooth tips and secondary veins of a pinnate kind, in the canonical leaf frame (cached per kind).

    The secondaries' ends are evenly spaced by arc length along each half
    of the canonical margin (``span``: fractions from the base to the
    apex), alternate sides offset by half a spacing; each ends at a tooth
    tip, and ``extra_teeth`` (basal, apical) more teeth continue the series.
    A secondary is a quadratic Bezier from the midrib to just inside its
    tooth, leaving the midrib ``curve`` degrees more open than its chord
    (the chord's angle to the midrib runs from ``angle[0]`` at the base to
    ``angle[1]`` at the apex), so it curves towards the apex.
    """
    key = id(kind)
    if key in _LAYOUTS:
        return _LAYOUTS[key]
    sec = kind["secondaries"]
    centre = np.asarray(kind["centre"], np.float64)
    a = np.linspace(1e-3, np.pi - 1e-3, 4001)
    r = _canonical_radius(kind, a, np.ones(1), None)
    pts = centre + np.column_stack([r * np.sin(a), -r * np.cos(a)])
    arc = np.concatenate([[0.0], np.cumsum(np.hypot(*np.diff(pts, axis=0).T))])
    frac = 1.0 - arc / arc[-1]  # 1 at the apex (a = 0), 0 at the base (a = pi)
    n, (s0, s1) = int(sec["pairs"]), sec["span"]
    gap = (s1 - s0) / max(n - 1, 1)
    ends = {1.0: s0 + gap * np.arange(n)}
    ends[-1.0] = ends[1.0] + (0.5 * gap if sec["alternate"] else 0.0)
    n_basal, n_apical = sec["extra_teeth"]
    lay = {"veins": []}
    for side, e in ends.items():
        extra = np.concatenate([e[0] - gap * np.arange(n_basal, 0, -1), e, e[-1] + gap * np.arange(1, n_apical + 1)])
        extra = extra[(extra > 0.03) & (extra < 0.97)]
        tips = np.interp(extra, frac[::-1], a[::-1])
        lay["tips_right" if side > 0 else "tips_left"] = np.sort(tips)
        for j, s_end in enumerate(e):
            a_end = float(np.interp(s_end, frac[::-1], a[::-1]))
            r_end = float(np.interp(a_end, a, r))
            end = centre + 0.96 * r_end * np.array([side * np.sin(a_end), -np.cos(a_end)])
            theta = np.deg2rad(np.interp(j, [0, max(n - 1, 1)], sec["angle"]))
            start_y = np.clip(end[1] + abs(end[0]) / np.tan(theta), centre[1] - 0.9 * kind["half_length"], -0.04)
            lay["veins"].append((side, np.array([0.0, start_y]), end, np.deg2rad(sec["curve"]) + theta))
    _LAYOUTS[key] = lay
    return lay


def _angle_warp(ac, eps):
    """``h(a_c) = a_c + sum_m eps_m sin(m a_c)``: monotone while ``sum m |eps_m| < 1``."""
    out = np.array(ac, np.float64, copy=True)
    for m, e in enumerate(eps, start=1):
        out = out + e * np.sin(m * ac)
    return out


class _Shape:
    """A leaf's outline and its map from the leaf frame to the canvas."""

    def __init__(self, kind_name: str, size: int, variation: float, rotation: float,
                 scale: tuple[float, float], rng: np.random.Generator):
        kind = KINDS[kind_name]
        self.kind = kind
        self.kind_name = kind_name
        n_lobes = 2 if "fan" in kind else max(len(kind["lobes"]), 1)  # a fan: its size and cleft
        v = variation
        self.lobe_scale = np.exp(rng.normal(0.0, 0.09 * v, n_lobes))
        eps = rng.normal(0.0, 0.05 * v, 3)
        limit = 0.55
        total = float(np.sum(np.arange(1, 4) * np.abs(eps)))
        if total > limit:
            eps *= limit / total
        self.eps = eps
        self.teeth_phase = 0.0  # teeth are part of the kind: material points keep their place
        self.aspect = float(np.exp(rng.normal(0.0, 0.07 * v)))
        self.bend = float(rng.normal(0.0, 0.12 * v))
        self.centre = np.array(kind["centre"], np.float64)
        self.rotation = float(rng.uniform(-rotation, rotation))
        fill = float(rng.uniform(*scale))
        # Inverse of the angle warp, as a table.
        grid = np.linspace(-np.pi, np.pi, 4097)
        self._ac_grid, self._a_grid = grid, _angle_warp(grid, eps)
        # Petiole in the leaf frame: slightly curved, below the base.
        t = np.linspace(0.0, 1.0, 12)
        pl = kind["petiole"] * float(np.exp(rng.normal(0, 0.1 * v)))
        self.petiole = np.column_stack([0.06 * v * rng.normal(0, 1.0) * t ** 2 * pl, -0.04 + t * (pl + 0.04)])
        # Similarity: fit the rotated, bent leaf into ``fill`` of the canvas.
        # (the outline without teeth, so the fit does not depend on their phase)
        ac = np.linspace(-np.pi, np.pi, 720, endpoint=False)
        a = _angle_warp(ac, eps)
        r = _canonical_radius(kind, ac, self.lobe_scale, None)
        outline = self.centre + np.column_stack([r * np.sin(a), -r * np.cos(a)])
        pts = np.vstack([outline, self.petiole])
        q = self._pre(pts)
        lo, hi = q.min(0), q.max(0)
        self.px = fill * size / float(max(hi - lo))
        self.offset = np.array([size / 2.0, size / 2.0]) - self.px * (lo + hi) / 2.0

    # leaf frame <-> canvas --------------------------------------------------
    def _rot(self):
        b = np.deg2rad(self.rotation)
        return np.array([[np.cos(b), -np.sin(b)], [np.sin(b), np.cos(b)]])

    def _pre(self, p):
        """Bend, aspect and rotation (no scale or shift)."""
        p = np.asarray(p, np.float64)
        x = (p[:, 0] + self.bend * (p[:, 1] + 0.5) ** 2) * self.aspect
        return np.column_stack([x, p[:, 1]]) @ self._rot().T

    def to_canvas(self, p):
        return self._pre(p) * self.px + self.offset

    def from_canvas(self, q):
        u = (np.asarray(q, np.float64) - self.offset) / self.px
        u = u @ self._rot()
        y = u[:, 1]
        x = u[:, 0] / self.aspect - self.bend * (y + 0.5) ** 2
        return np.column_stack([x, y])

    # material points -----------------------------------------------------------
    def radius(self, ac):
        return _canonical_radius(self.kind, ac, self.lobe_scale, self.teeth_phase)

    def material(self, ac, rho):
        """Leaf-frame position of material points ``(a_c, rho)``."""
        ac = np.asarray(ac, np.float64)
        a = _angle_warp(ac, self.eps)
        r = np.asarray(rho) * self.radius(ac)
        return self.centre + np.column_stack([r * np.sin(a), -r * np.cos(a)])

    def primaries(self, rng, spacing: float):
        """Primary veins (leaf frame, final size): one per lobe axis, or the midrib."""
        lines = []
        if "dichotomous" in self.kind:
            return [ln for ln, lev in self._dichotomous(rng, spacing) if lev == 0]
        if self.kind["lobes"]:
            axes = [np.deg2rad(ang) for ang, _ in self.kind["lobes"]]
            for ac in axes:
                length = float(np.hypot(*self.material([ac], [0.92])[0]))
                n = max(int(length / spacing), 3)
                rho = np.linspace(0.03, 0.92, n)
                wig = 0.03 * np.sin(np.pi * rho * rng.uniform(1, 2.5) + rng.uniform(0, 2 * np.pi))
                lines.append(self.material(ac + wig, rho))
        else:
            c_len = float(np.hypot(*self.centre))
            n0 = max(int(c_len / spacing), 3)
            lower = self.material(np.full(n0, np.pi), np.linspace(0.97, 0.0, n0, endpoint=False))
            n1 = max(int(0.5 / spacing), 3)
            rho = np.linspace(0.0, 0.93, n1)
            wig = 0.02 * np.sin(np.pi * rho * rng.uniform(1, 2) + rng.uniform(0, 2 * np.pi))
            lines.append(np.vstack([lower, self.material(wig, rho)]))
        return lines

    def secondaries(self, rng, spacing: float):
        """Secondary veins of a pinnate kind (leaf frame, final size), each ending at its tooth.

        They are laid out in the canonical frame (:func:`_pinnate_layout`),
        jittered a little per leaf, and carried to this leaf as material
        points ``(a_c, rho)``, so they move with its angle warp and aspect
        like the margin they end at.
        """
        if "dichotomous" in self.kind:
            # Each fork of a dichotomous kind starts where its parent ends.
            return [ln for ln, lev in self._dichotomous(rng, spacing) if lev > 0]
        if "secondaries" not in self.kind:
            return []
        lines = []
        centre = np.asarray(self.kind["centre"], np.float64)
        for side, start, end, open_angle in _pinnate_layout(self.kind)["veins"]:
            s = start + np.array([0.0, rng.normal(0.0, 0.012)])
            length = float(np.hypot(*(end - s)))
            ctrl = s + 0.5 * length * np.array([side * np.sin(open_angle), -np.cos(open_angle)])
            ctrl = ctrl + rng.normal(0.0, 0.008, 2)
            t = np.linspace(0.0, 1.0, max(int(length / spacing), 4))[:, None]
            p = (1 - t) ** 2 * s + 2 * t * (1 - t) * ctrl + t ** 2 * end
            d = p - centre
            ac = np.arctan2(d[:, 0], -d[:, 1])
            rho = np.hypot(d[:, 0], d[:, 1]) / _canonical_radius(self.kind, ac, np.ones(1), 0.0)
            lines.append(self.material(ac, rho))
        return lines

    def _dichotomous(self, rng, spacing: float):
        """The dichotomous veins of a fan kind (leaf frame), drawn once per leaf, as material points."""
        if getattr(self, "_dich", None) is None:
            centre = np.asarray(self.kind["centre"], np.float64)
            out = []
            for line, lev in dichotomous_veins(self.kind, rng, spacing):
                d = line - centre
                ac = np.arctan2(d[:, 0], -d[:, 1])
                rho = np.minimum(np.hypot(d[:, 0], d[:, 1]) / _canonical_radius(self.kind, ac, np.ones(2), 0.0), 0.95)
                out.append((self.material(ac, rho), lev))
            self._dich = out
        return self._dich

    def outline(self, n=720):
        ac = np.linspace(-np.pi, np.pi, n, endpoint=False)
        return self.material(ac, np.ones(n))

    def inside_depth(self, p):
        """Radial depth inside the blade (leaf units; > 0 inside) of leaf-frame points."""
        d = np.asarray(p, np.float64) - self.centre
        a = np.arctan2(d[:, 0], -d[:, 1])
        ac = np.interp(a, self._a_grid, self._ac_grid)
        return self.radius(ac) - np.hypot(d[:, 0], d[:, 1])


# ---------------------------------------------------------------------------
# texture

def _value_noise(shape, cell: float, rng: np.random.Generator) -> np.ndarray:
    h, w = shape
    gh, gw = max(int(np.ceil(h / cell)) + 2, 2), max(int(np.ceil(w / cell)) + 2, 2)
    g = rng.standard_normal((gh, gw)).astype(np.float32)
    up = cv2.resize(g, (int(gw * cell), int(gh * cell)), interpolation=cv2.INTER_CUBIC)
    up = up[:h, :w]
    return (up - up.mean()) / max(float(up.std()), 1e-6)


def _size_spec(value, name, allow_none):
    """``size`` is checked with the other arguments in :func:`_check_args` (a ValueError for 64.5 too)."""
    return value


def _check_args(kind, size, palette, variation, rotation, scale, n_keypoints):
    if kind not in KINDS:
        raise ValueError(f"kind must be one of {sorted(KINDS)}, got {kind!r}")
    if palette not in PALETTES:
        raise ValueError(f"palette must be one of {sorted(PALETTES)}, got {palette!r}")
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or not 32 <= size <= 4096:
        raise ValueError(f"size must be an int in [32, 4096], got {brief(size)}")
    if not (np.isfinite(variation) and 0.0 <= variation <= 3.0):
        raise ValueError(f"variation must be in [0, 3], got {variation!r}")
    if not (np.isfinite(rotation) and 0.0 <= rotation <= 180.0):
        raise ValueError(f"rotation must be in [0, 180] degrees, got {rotation!r}")
    sc = tuple(float(v) for v in real_array(scale, "scale", ndim=1, allow_empty=True))
    if len(sc) != 2 or not (0.1 <= sc[0] <= sc[1] <= 1.0):
        raise ValueError(f"scale must be (low, high) with 0.1 <= low <= high <= 1, got {scale!r}")
    if isinstance(n_keypoints, bool) or not isinstance(n_keypoints, (int, np.integer)) or n_keypoints < 1:
        raise ValueError(f"n_keypoints must be a positive int, got {n_keypoints!r}")
    return sc


def material_keypoints(n: int) -> tuple[np.ndarray, np.ndarray]:
    """The canonical material points ``(a_c, rho)`` behind ``keypoints``: a golden-angle spiral.

    Parameters
    ----------
    n : int
        Number of points (``n_keypoints`` of :func:`procedural_leaf`).

    Returns
    -------
    a_c : (n,) float ndarray
        Canonical angle from the tip direction, radians in ``[-pi, pi)``.
    rho : (n,) float ndarray
        Relative radius in ``(0.08, 0.94)`` (0: the outline's centre, 1: the
        outline), growing with the point's index.

    Examples
    --------
    >>> ac, rho = material_keypoints(5)
    >>> ac.shape, bool(rho.max() < 1)
    ((5,), True)
    """
    k = np.arange(n) + 0.5
    rho = 0.08 + 0.86 * np.sqrt(k / n)
    ac = _wrap(k * np.pi * (3.0 - np.sqrt(5.0)))
    return ac, rho


@checked(variation=Real(0.0, 3.0), rotation=Real(0.0, 180.0), n_keypoints=Int(1, 10_000),
         scale=Seq(), n_spots=Seq(), size=_size_spec)
def procedural_leaf(kind: str = "lobed", *, size: int = 512, palette: str = "green",
                    variation: float = 1.0, rotation: float = 30.0,
                    scale: tuple[float, float] = (0.72, 0.9), n_spots: tuple[int, int] = (2, 5),
                    n_keypoints: int = 64, rng=None) -> ProceduralLeaf:
    """One procedural leaf of ``kind`` on a ``size`` x ``size`` canvas.

    Parameters
    ----------
    kind : {"lobed", "trilobed", "elliptic", "fan"}
        The family (see :data:`KINDS`; ``"fan"``: ginkgo-like, dichotomous
        veins, :mod:`branchnb.leaves.procedural_fan`).
    size : int
        Canvas side in pixels (1000 gives a 1-megapixel leaf).
    palette : {"green", "autumn"}
        Colours of blade, mottling, veins and spots (see :data:`PALETTES`).
    variation : float
        Scales the per-leaf shape variation (0: every leaf has the
        canonical outline, only rotation/scale/venation/spots differ).
    rotation : float
        Rotations are drawn uniformly in ``[-rotation, rotation]`` degrees.
    scale : (float, float)
        The leaf's larger extent is drawn in this range, as a fraction of ``size``.
    n_spots : (int, int)
        Inclusive range of the number of spots.
    n_keypoints : int
        Number of true corresponding points.
    rng : {numpy.random.Generator, int}, optional
        The leaf's seed is drawn from it (or is the int itself).

    Returns
    -------
    ProceduralLeaf

    Examples
    --------
    >>> leaf = procedural_leaf("elliptic", size=96, rng=1)
    >>> leaf.image.shape, leaf.keypoints.shape
    ((96, 96, 4), (64, 2))
    >>> bool((leaf.layers["veins"] & leaf.layers["spots"]).any())
    False
    """
    sc = _check_args(kind, size, palette, variation, rotation, scale, n_keypoints)
    n_spots = tuple(check_int(v, "n_spots", 0, 50) for v in n_spots)
    if len(n_spots) != 2 or not n_spots[0] <= n_spots[1]:
        raise ValueError(f"n_spots must be (low, high) with 0 <= low <= high <= 50, got {n_spots!r}")
    if isinstance(rng, (int, np.integer)) and not isinstance(rng, bool):
        if rng < 0:
            raise ValueError(f"rng seed must be non-negative, got {rng}")
        seed = int(rng)
    else:
        seed = int(as_rng(rng).integers(0, 2**31 - 1))
    gen = np.random.default_rng(seed)
    size = int(size)
    shape = _Shape(kind, size, float(variation), float(rotation), sc, gen)

    # Blade: radial depth of every pixel, anti-aliased over one pixel.
    ys, xs = np.mgrid[0:size, 0:size]
    pix = np.column_stack([xs.ravel(), ys.ravel()]).astype(np.float64)
    local = shape.from_canvas(pix)
    depth = shape.inside_depth(local).reshape(size, size)
    lamina = np.clip(depth * shape.px + 0.5, 0.0, 1.0).astype(np.float32)

    # Venation and petiole, in canvas pixels.
    nodes, parent = _grow_venation(shape, gen)
    lines, rel_w = _vein_polylines(nodes, parent)
    max_rel = max(float(max(w.max() for w in rel_w)), 1.0) if rel_w else 1.0
    base_px = max(0.011 * shape.px, 1.2)  # main vein at the base
    # Veins are drawn at least 1.5 px wide: a thinner line leaves no pixel
    # more than half covered on diagonals, so its truth (coverage > 0.5)
    # breaks into dots nobody could scribble (at 256 px, 80 % of the vein
    # length was below 1 px). A photographed vein thinner than a pixel is
    # likewise either blurred to ~1.5 px or not visible at all.
    tip_px = max(0.0018 * shape.px, 1.5)
    base_px = max(base_px, tip_px)
    vein_px, vein_w = [], []
    pet_w = base_px * 1.15
    petiole = shape.to_canvas(shape.petiole)
    vein_px.append(petiole)
    vein_w.append(np.linspace(pet_w, pet_w * 0.85, len(petiole))[::-1])
    for line, w in zip(lines, rel_w):
        pts = _smooth_line(shape.to_canvas(line))
        wid = tip_px + (base_px - tip_px) * (np.interp(np.linspace(0, 1, len(pts)),
                                                       np.linspace(0, 1, len(w)), w) - 1.0) / max(max_rel - 1.0, 1e-9)
        vein_px.append(pts)
        vein_w.append(wid)
    vein_cov, _ = coverage_polylines((size, size), vein_px, vein_w)
    pet_cov, _ = coverage_polylines((size, size), [petiole], [vein_w[0]])
    alpha = np.maximum(lamina, pet_cov)
    vein_cov = np.minimum(vein_cov, alpha)

    # Spots at random material points.
    lo_n, hi_n = int(n_spots[0]), int(n_spots[1])
    n_sp = int(gen.integers(lo_n, hi_n + 1))
    spot_cov = np.zeros((size, size), np.float32)
    for _ in range(n_sp):
        c = shape.material(gen.uniform(-2.6, 2.6, 1), gen.uniform(0.25, 0.8, 1))[0]
        rad = gen.uniform(0.018, 0.045)
        harm = gen.normal(0, 0.18, 4)
        ph = gen.uniform(0, 2 * np.pi, 4)
        d = local - c
        ang = np.arctan2(d[:, 1], d[:, 0])
        wobble = 1.0 + sum(harm[m] * np.sin((m + 2) * ang + ph[m]) for m in range(4))
        sdist = (rad * wobble - np.hypot(d[:, 0], d[:, 1])) * shape.px
        spot_cov = np.maximum(spot_cov, np.clip(sdist / 2.0 + 0.5, 0, 1).reshape(size, size))
    spot_cov = np.minimum(spot_cov, lamina)

    # Colour texture.
    pal = {k: np.asarray(v, np.float32) for k, v in PALETTES[palette].items()}
    n_low = _value_noise((size, size), size / 5.0, gen)
    n_mid = _value_noise((size, size), size / 22.0, gen)
    n_fine = gen.standard_normal((size, size)).astype(np.float32)
    mottle = np.clip(0.5 + 0.35 * n_low, 0, 1)[:, :, None]
    rgb = pal["blade"] * (1 - mottle) + pal["mottle"] * mottle
    rgb = rgb * (1.0 + 0.07 * n_mid + 0.03 * n_fine)[:, :, None]
    vein_rgb = pal["veins"] * (1.0 + 0.05 * n_mid + 0.03 * n_fine)[:, :, None]
    spot_rgb = pal["spots"] * (1.0 + 0.12 * n_mid + 0.05 * n_fine)[:, :, None]
    sc_ = spot_cov[:, :, None]
    rgb = rgb * (1 - sc_) + spot_rgb * sc_
    vc = vein_cov[:, :, None]
    rgb = rgb * (1 - vc) + vein_rgb * vc
    rgb = np.clip(rgb, 0, 1)
    image = np.dstack([rgb * (alpha[:, :, None] > 0), alpha]).astype(np.float32)

    blade = alpha > 0.5
    veins = (vein_cov > 0.5) & blade
    spots = (spot_cov > 0.5) & blade & ~veins
    ac, rho = material_keypoints(int(n_keypoints))
    keypoints = shape.to_canvas(shape.material(ac, rho))
    info = {"lobe_scale": shape.lobe_scale.tolist(), "angle_warp": shape.eps.tolist(),
            "aspect": shape.aspect, "bend": shape.bend, "rotation": shape.rotation,
            "pixels_per_unit": shape.px, "n_spots": n_sp, "n_vein_nodes": int(len(nodes))}
    return ProceduralLeaf(image, blade, {"veins": veins, "spots": spots}, keypoints, seed,
                          kind, palette, info, vein_px, vein_w)


@checked(n=Int(1, 10_000), variation=Real(0.0, 3.0), rotation=Real(0.0, 180.0),
         n_keypoints=Int(1, 10_000), scale=Seq(), n_spots=Seq(), size=_size_spec)
def leaf_family(n: int, *, size: int = 512, kind: str = "lobed", palette: str = "green",
                variation: float = 1.0, rotation: float = 30.0,
                scale: tuple[float, float] = (0.72, 0.9), n_spots: tuple[int, int] = (2, 5),
                n_keypoints: int = 64, rng=None) -> list[ProceduralLeaf]:
    """``n`` leaves of one kind: a family of exemplars with known answers.

    Every leaf gets its own seed drawn from ``rng``; see
    :func:`procedural_leaf` for the parameters. Keypoint ``k`` is the same
    material point on every leaf of the family.

    Parameters
    ----------
    n : int
        Number of leaves, 1 to 10000.
    size : int
        Canvas side in pixels, 32 to 4096 (default 512).
    kind : {"lobed", "trilobed", "elliptic", "fan"}
        The family (see :data:`KINDS`); one kind for all leaves.
    palette : {"green", "autumn"}
        Colours (see :data:`PALETTES`).
    variation : float
        Scale of the per-leaf shape variation, 0 to 3 (default 1; 0: the
        canonical outline on every leaf).
    rotation : float
        Each leaf is rotated by a uniform angle in ``[-rotation, rotation]``
        degrees (default 30).
    scale : (float, float)
        Range of the leaf's larger extent, as a fraction of ``size``
        (default ``(0.72, 0.9)``).
    n_spots : (int, int)
        Inclusive range of spots per leaf (default ``(2, 5)``).
    n_keypoints : int
        True corresponding points per leaf (default 64).
    rng : {numpy.random.Generator, int}, optional
        Draws the ``n`` distinct leaf seeds.

    Returns
    -------
    list of ProceduralLeaf

    Examples
    --------
    >>> fam = leaf_family(2, size=80, rng=0)
    >>> len(fam), fam[0].seed != fam[1].seed
    (2, True)
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= 10000:
        raise ValueError(f"n must be an int in [1, 10000], got {n!r}")
    _check_args(kind, size, palette, variation, rotation, scale, n_keypoints)
    gen = as_rng(rng)
    seeds = gen.choice(2**31 - 1, size=int(n), replace=False)
    return [procedural_leaf(kind, size=size, palette=palette, variation=variation, rotation=rotation,
                            scale=scale, n_spots=n_spots, n_keypoints=n_keypoints, rng=int(s))
            for s in seeds]
