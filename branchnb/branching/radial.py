"""Radial synthesis (beyond the paper, issue 23): several primaries leaving each hub, and the hub drawn.

Extraction finds hubs (:mod:`.hubs`: a neuron's soma, a coral's centre, a crater) and roots the traced
tree at each hub's centre, its spokes the root and branches starting at its first vertex. Learnt as it
is, that is one root whose children sit at its start, and the paper's synthesis grew one main branch
with side branches from each root. Here, only when the example carries hubs (``structure.hubs``, set
by :func:`~branchnb.branching.extract_structure`):

- :func:`_fit_hubs` reads, per example hub, its radius and the directions of its spokes (the branches
  starting within half its radius of its centre, each read where it leaves the hub);
- :func:`_hub_starts` turns every synthesized root start into a hub: as many primaries as one of the
  example's hubs has, starting on the hub's rim, their angular gaps those of that hub (turned by the
  root's heading), and records the hub on the result (``structure.hubs``);
- :func:`_paste_hubs` copies the example's hub blob (a feathered disc of its radius, scaled like the
  hub) onto every synthesized hub of the image.

Structures without hubs take none of these paths (their output is unchanged).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: Spokes start within this share of the hub's radius from its centre.
SPOKE_START = 0.5
#: ... and their direction is read where they leave this multiple of the radius.
SPOKE_READ = 1.2
#: The pasted hub is opaque out to this multiple of its radius, and fades out over the next
#: :data:`HUB_FEATHER` x radius (beyond it: the lines' stubs, which the synthesized primaries replace).
HUB_OPAQUE = 0.9
HUB_FEATHER = 0.3


@dataclass
class _HubModel:
    """Per example hub: centre ``(x, y)`` and radius (pixels of the example) and the spokes' angular gaps
    (radians, in counter-clockwise order from the first spoke, summing to ``2 pi``)."""

    centres: list[tuple[float, float]]
    radii: list[float]
    gaps: list[np.ndarray]

    @property
    def counts(self) -> list[int]:
        return [len(g) for g in self.gaps]


def _hubs_of(structure) -> list[tuple[float, float, float]]:
    """The ``(x, y, radius)`` hubs a structure carries (``[]`` when none)."""
    hubs = getattr(structure, "hubs", None)
    return [] if not hubs else [tuple(map(float, h)) for h in hubs]


def _spoke_angles(structure, x: float, y: float, r: float) -> np.ndarray:
    """Directions (radians, image coordinates) of the branches leaving the hub ``(x, y, r)``."""
    out = []
    for b in structure.branches:
        d = np.hypot(b.points[:, 0] - x, b.points[:, 1] - y)
        if d[0] > SPOKE_START * r:
            continue
        far = np.flatnonzero(d > SPOKE_READ * r)
        if far.size and np.all(d[:far[0]] <= SPOKE_READ * r):
            p = b.points[far[0]]
            out.append(float(np.arctan2(p[1] - y, p[0] - x)))
    return np.sort(np.mod(out, 2 * np.pi))


def _fit_hubs(structure) -> _HubModel | None:
    """The hub model of an example structure, None without hubs (or when no hub has 2+ spokes)."""
    centres, radii, gaps = [], [], []
    for x, y, r in _hubs_of(structure):
        a = _spoke_angles(structure, x, y, r)
        if len(a) < 2:
            continue
        centres.append((x, y))
        radii.append(r)
        gaps.append(np.diff(np.r_[a, a[0] + 2 * np.pi]))
    return _HubModel(centres, radii, gaps) if gaps else None


def _hub_model(model) -> _HubModel | None:
    """:func:`_fit_hubs` of a :class:`~branchnb.branching.model.StructureModel`'s source, kept on it."""
    got = model.__dict__.get("_hub_model")
    if got is None or got[0] is not model.source:
        got = model.__dict__["_hub_model"] = (model.source, _fit_hubs(model.source))
    return got[1]


def _hub_starts(hm: _HubModel, starts, scale: float, shape, rng, domain=None):
    """``(starts, hubs)``: every root start ``(x, y, angle)`` of ``starts`` replaced by the primaries of
    a hub centred there, and the hubs ``[(x, y, radius)]``.

    Each hub copies one of the example's (drawn by ``rng``): its number of spokes, their angular gaps
    (from a random first spoke, turned by the start's angle) and its radius (x ``scale``). The centre is
    moved inside the frame by 1.5 radii; primaries start on the hub's rim (of one point, they would cut
    each other off at once), on the domain when it is given.
    """
    h, w = shape
    new, hubs = [], []
    for x, y, th in starts:
        j = int(rng.integers(len(hm.gaps)))
        g = hm.gaps[j]
        R = hm.radii[j] * scale
        m = min(1.5 * R, 0.25 * min(h, w))
        cx, cy = float(np.clip(x, m, w - 1 - m)), float(np.clip(y, m, h - 1 - m))
        k = int(rng.integers(len(g)))
        ang = th + np.cumsum(np.r_[0.0, np.roll(g, -k)[:-1]])
        hubs.append((cx, cy, R))
        for a in ang:
            px, py = cx + R * np.cos(a), cy + R * np.sin(a)
            if domain is not None:
                iy, ix = int(np.clip(round(py), 0, h - 1)), int(np.clip(round(px), 0, w - 1))
                if not domain[iy, ix]:
                    continue
            new.append((float(px), float(py), float(np.mod(a + np.pi, 2 * np.pi) - np.pi)))
    return new, hubs


def _hub_discs(hubs, shape) -> np.ndarray:
    """``(H, W)`` bool: the discs of :data:`HUB_OPAQUE` + :data:`HUB_FEATHER` radii round ``hubs``."""
    yy, xx = np.ogrid[:shape[0], :shape[1]]
    out = np.zeros(shape, bool)
    for x, y, r in hubs:
        out |= (xx - x) ** 2 + (yy - y) ** 2 <= ((HUB_OPAQUE + HUB_FEATHER) * r) ** 2
    return out


def _paste_hubs(canvas: np.ndarray, example: np.ndarray, ex_hubs, hubs) -> np.ndarray:
    """``canvas`` with the example's hub blob (hub ``i % len(ex_hubs)``) pasted on every hub of ``hubs``,
    scaled to its radius and feathered (:data:`HUB_OPAQUE`, :data:`HUB_FEATHER`)."""
    import cv2

    H, W = canvas.shape[:2]
    out = canvas.copy()
    for i, (x, y, R) in enumerate(hubs):
        ex_x, ex_y, ex_r = ex_hubs[i % len(ex_hubs)]
        f = R / max(ex_r, 1e-6)
        half = int(np.ceil((HUB_OPAQUE + HUB_FEATHER) * R)) + 1
        yy, xx = np.mgrid[-half:half + 1, -half:half + 1].astype(np.float32)
        ty, tx = np.round(y).astype(int) + yy.astype(int), np.round(x).astype(int) + xx.astype(int)
        ok = (ty >= 0) & (ty < H) & (tx >= 0) & (tx < W)
        # the example's pixel under each target pixel (sub-pixel: the hub's centre is a float)
        mx = (ex_x + (tx - x) / f).astype(np.float32)
        my = (ex_y + (ty - y) / f).astype(np.float32)
        patch = cv2.remap(example, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REFLECT)
        patch = patch.reshape(patch.shape[:2] + (-1,))
        d = np.hypot(tx - x, ty - y) / R
        alpha = np.clip((HUB_OPAQUE + HUB_FEATHER - d) / HUB_FEATHER, 0.0, 1.0)[..., None]
        o = out[ty[ok], tx[ok]].reshape(-1, out.shape[2] if out.ndim == 3 else 1)
        blend = (1 - alpha[ok]) * o + alpha[ok] * patch[ok][:, :o.shape[1]]
        out[ty[ok], tx[ok]] = blend.reshape(out[ty[ok], tx[ok]].shape)
    return out
