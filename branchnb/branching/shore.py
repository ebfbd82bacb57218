"""Rivers of a map keep off their coast and run inland from it (:class:`_Shore`, :func:`runs_inland`).

Beyond the paper: an example whose roots start at its domain's edge (rivers
from a coast) keeps its branches off that edge, and its roots may not hook
back at their mouth (``MOUTH_SHARE``, ``MOUTH_TURN``). Split from
:mod:`~branchnb.branching.domains`, which re-exports every name.
"""

from __future__ import annotations

from typing import TYPE_CHECKING

import numpy as np

from ..core.structure import Structure
from .drain import _Drain

if TYPE_CHECKING:
    from .model import StructureModel


SHORE_QUANTILE = 0.05
SHORE_SKIP = 12.0
#: No hooks at a mouth (beyond the paper): over the first ``MOUTH_SHARE`` of a coast root's
#: length its heading may span at most ``MOUTH_TURN`` radians (a candidate that would turn it
#: further is taken only when nothing else is left). Without it 2 of 3 rivers of a 1000 px coast
#: map curled back by > 120 degrees just before their mouth.
MOUTH_SHARE = 0.12
MOUTH_TURN = float(np.radians(105.0))



def _shore_margin(model: StructureModel) -> float:
    """Distance the example's branches keep from its domain's edge (0: none to keep).

    Used on examples whose roots start at the domain's edge (rivers from a
    coast); 0 when the example has no domain, drains, its roots lie inland
    (median depth over 15 % of the deepest), or its branches run along the
    edge themselves (the margin is under 3 px).
    """
    dom = model.region
    if dom is None or dom.all() or not dom.any() or model.drains:
        return 0.0
    cached = model.__dict__.get("_shore_margin")
    if cached is not None and cached[0] is dom:
        return cached[1]
    margin = _shore_margin_of(model, dom)
    model.__dict__["_shore_margin"] = (dom, margin)
    return margin


def _shore_margin_of(model: StructureModel, dom: np.ndarray) -> float:
    from scipy import ndimage as ndi

    depth = ndi.distance_transform_edt(dom)
    h, w = dom.shape
    roots = [b.points[0] for b in model.example.branches if b.parent is None]
    if not roots:
        return 0.0
    x, y = np.clip(np.rint(np.asarray(roots)).astype(int), 0, [w - 1, h - 1]).T
    if np.median(depth[y, x]) > 0.15 * depth.max():     # roots inland (vessels from a disc): no coast
        return 0.0
    vals = []
    for b in model.example.branches:
        p = b.points
        if b.parent is None:
            arc = np.r_[0.0, np.cumsum(np.hypot(*np.diff(p, axis=0).T))]
            p = p[arc > SHORE_SKIP]
        if len(p):
            x, y = np.clip(np.rint(p).astype(int), 0, [w - 1, h - 1]).T
            vals.append(depth[y, x])
    if not vals:
        return 0.0
    margin = float(np.quantile(np.concatenate(vals), SHORE_QUANTILE))
    return min(margin, 0.08 * min(h, w)) if margin >= 3.0 else 0.0


#: A map's rivers run inland from their coast (beyond the paper): within this share of the frame's diagonal of
#: the coast a candidate heading along it (chord at angle ``phi`` to the way inland) gets its score times
#: ``exp(-ALONG_KAPPA w (1 - |cos phi|))``, ``w`` fading from 1 at the coast to 0 at the band's edge ...
ALONG_BAND = 0.08
ALONG_KAPPA = 4.0
#: ... when the example's rivers themselves run along it for less than this share of their length in the
#: band (:func:`_along_share`; drawn maps 0.8-2 %).
ALONG_EXAMPLE_MAX = 0.2


def _along_share(example: Structure, domain: np.ndarray) -> float:
    """Share of the example's branch length within :data:`ALONG_BAND` x the diagonal of the domain's
    edge that runs along that edge (chord within 60 degrees of parallel to it)."""
    from scipy import ndimage as ndi

    dom = np.asarray(domain, bool)
    depth = ndi.distance_transform_edt(dom)
    gy, gx = np.gradient(ndi.gaussian_filter(depth, 4.0))
    n = np.hypot(gx, gy) + 1e-12
    gx, gy = gx / n, gy / n
    h, w = dom.shape
    band = ALONG_BAND * float(np.hypot(h, w))
    tot = along = 0.0
    for b in example.branches:
        p = np.asarray(b.points, np.float64)
        if len(p) < 2:
            continue
        v = np.diff(p, axis=0)
        seg = np.hypot(v[:, 0], v[:, 1])
        ix = np.clip(np.rint(0.5 * (p[1:] + p[:-1])).astype(np.int64), 0, [w - 1, h - 1])
        near = depth[ix[:, 1], ix[:, 0]] <= band
        c = np.abs(v[:, 0] * gx[ix[:, 1], ix[:, 0]] + v[:, 1] * gy[ix[:, 1], ix[:, 0]]) / np.maximum(seg, 1e-9)
        tot += float(seg[near].sum())
        along += float(seg[near & (c < 0.5)].sum())
    return along / tot if tot > 0 else 1.0


def runs_inland(model: StructureModel) -> bool:
    """Do the example's rivers run inland from their coast (:func:`_along_share` below
    :data:`ALONG_EXAMPLE_MAX`)? Cached on the model.

    Parameters
    ----------
    model : StructureModel
        A fitted model; without a domain (or with a domain that is everything) the answer
        is False.
    """
    dom = model.region
    if dom is None or dom.all() or not dom.any():
        return False
    cached = model.__dict__.get("_runs_inland")
    if cached is not None and cached[0] is dom:
        return cached[1]
    out = _along_share(model.example, dom) < ALONG_EXAMPLE_MAX
    model.__dict__["_runs_inland"] = (dom, out)
    return out


class _Shore:
    """Rivers of a map keep off its coast (beyond the paper).

    A candidate that comes closer to the edge of the domain (the coast)
    or runs along it, and ends within ``margin`` px of it (see
    :func:`_shore_margin`, the distance the example's rivers keep) gets
    its score times ``exp(-8 (1 - d / margin))``, and is forbidden when one
    of its new points comes within ``margin / 2``: such a river ends
    there. Heading inland
    (a root leaving the coast) is free. Without it a river that met the coast turned and ran
    along it (islands of 256 px: 5-20 % of the river length within 6 px
    of the coast against 1-1.5 % in the example).
    """

    def __init__(self, domain: np.ndarray, margin: float, inland: bool = False):
        from scipy import ndimage as ndi

        self.depth = ndi.distance_transform_edt(np.asarray(domain, bool)).astype(np.float32)
        self.margin = float(margin)
        #: rivers run inland near the coast (:meth:`along_factor`; None: no such rule)
        self.inward = None
        if inland:
            gy, gx = np.gradient(ndi.gaussian_filter(self.depth, 4.0))
            n = np.hypot(gx, gy) + 1e-12
            self.inward = np.stack([gx / n, gy / n], -1).astype(np.float32)
            self.band = ALONG_BAND * float(np.hypot(*self.depth.shape))

    def along_factor(self, tip, points: np.ndarray, n_new: np.ndarray) -> np.ndarray | float:
        """Score factor of candidates ``points`` ((C, M, 2), the first ``n_new`` new) from ``tip``
        that head along the coast within :data:`ALONG_BAND` of it (1 without the rule).

        Beyond the paper (issue 23): the shore's margin keeps a river off the coast, but on a
        1000 px map rivers turned along it beyond the margin and ran there side by side (7-22 % of
        the synthesized length within 5 % of the diagonal of the coast ran along it, against 0.8 % in
        the example)."""
        if self.inward is None:
            return 1.0
        tip = np.asarray(tip, np.float64)
        n = np.maximum(n_new, 1)
        end = points[np.arange(len(points)), n - 1]
        mid = 0.5 * (end + tip)
        h, w = self.depth.shape
        ix = np.clip(np.rint(mid[:, 0]).astype(np.int64), 0, w - 1)
        iy = np.clip(np.rint(mid[:, 1]).astype(np.int64), 0, h - 1)
        v = end - tip
        g = self.inward[iy, ix]
        c = np.abs(v[:, 0] * g[:, 0] + v[:, 1] * g[:, 1]) / np.maximum(np.hypot(v[:, 0], v[:, 1]), 1e-9)
        wt = np.clip(1.0 - self.depth[iy, ix] / self.band, 0.0, 1.0)
        return np.exp(-ALONG_KAPPA * wt * (1.0 - c))

    def _at(self, pts: np.ndarray) -> np.ndarray:
        h, w = self.depth.shape
        ix = np.clip(np.rint(pts[..., 0]).astype(np.int64), 0, w - 1)
        iy = np.clip(np.rint(pts[..., 1]).astype(np.int64), 0, h - 1)
        return self.depth[iy, ix]

    # the same hold as the drain's: the shore has an axis and a way down too
    trunk_hold = _Drain.trunk_hold

    def factor(self, tip, points: np.ndarray, n_new: np.ndarray) -> np.ndarray:
        """Score factor of candidates ``points`` ((C, M, 2), the first ``n_new`` new) from ``tip``."""
        n = np.maximum(n_new, 1)
        d = self._at(points)
        valid = np.arange(points.shape[1])[None, :] < n[:, None]
        closest = np.where(valid, d, np.inf).min(1)
        end = d[np.arange(len(points)), n - 1]
        tip = np.asarray(tip, np.float64)
        d_tip = float(self._at(tip))
        chord = np.hypot(*(points[np.arange(len(points)), n - 1] - tip).T)
        leaving = end - d_tip >= 0.5 * chord      # heading inland (within 60 degrees of straight)
        f = np.where(leaving, 1.0, np.exp(-8.0 * np.clip(1.0 - end / self.margin, 0.0, 1.0)))
        return np.where(~leaving & (closest < 0.5 * self.margin), 0.0, f)
