"""Regions tied to the image frame, not to the branches (beyond the paper, issue 23, branching96).

:func:`~branchnb.branching.layout_model.layout_regions` lays a region out by each pixel's relation
to the nearest branch, which is right for a map's land round its rivers or the sea beyond a delta's
mouths. Some regions are tied to the frame instead: a city skyline or a hill line along the bottom
of a lightning photograph, the floor under a neon sign, a lawn under a vine on a fence. Laid out by
the branches they came out as wedges, coast-like blobs and islands with curved edges where the
example's are straight. :func:`frame_bands` finds such regions in an example's layout and
:func:`place_bands` puts them in an output by the frame alone, as the example has them.

A region is frame-tied to one side when (all on the example):

* it covers that side along :data:`SIDE_COVER` of its length, and (almost) all of it
  (:data:`BAND_SHARE`) lies in one run from that side in every row/column: a band with one far edge;
* it is a band, not the whole image: mean depth at most :data:`MAX_DEPTH` of the image across it;
* its far edge runs along the side: the depth profile's spread (std) is at most :data:`EDGE_SPREAD`
  of the image across the side (a skyline's steps, a hill line, a horizon are; a coast that runs
  from one corner deep into the image is not);
* the branches do not explain it: no branch runs in it (it is no branch-bearing region), and fewer
  than :data:`MAX_OUTLETS` of the branches' ends (roots and tips) lie on its edge, or those that do
  lie close together (spread along the side over less than :data:`END_SPAN` of it). A coast map's
  sea along a side holds its river mouths all along the coast, a delta's sea its distributaries'
  mouths: both stay branch-tied (laid out round the target's mouths); the forks of a bolt that
  strike a hill line or the sea horizon hit it in one place (span 0.04-0.10 of the side on the
  examples of :mod:`branchnb` issue 23, against 0.60-0.76 for drawn maps' and deltas' coasts).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

__all__ = ["FrameBand", "frame_bands", "place_bands"]

#: Share of the side's length a frame-tied region covers.
SIDE_COVER = 0.9
#: Share of the region lying in one run from its side (every row/column).
BAND_SHARE = 0.97
#: Largest mean depth of a band, as a share of the image across its side.
MAX_DEPTH = 0.5
#: Largest std of a band's depth profile, as a share of the image across its side.
EDGE_SPREAD = 0.12
#: A region with this many branch ends (roots, tips) on its edge is tied to the branches.
MAX_OUTLETS = 2
#: A branch end lies on the edge when within this many pixels (plus the branch's radius) of it.
OUTLET_REACH = 6.0
#: Ends on a region's edge spread along its side over at least this share of it make it branch-tied.
END_SPAN = 0.3

_SIDES = ("bottom", "top", "right", "left")


@dataclass
class FrameBand:
    """One frame-tied region of an example.

    Parameters
    ----------
    label : int
        Its region label.
    side : str
        The frame side it lies along (``"bottom"``, ``"top"``, ``"right"`` or ``"left"``).
    depth : (N,) ndarray
        Its depth from that side at every pixel along it, as a share of the image across the side.
    """

    label: int
    side: str
    depth: np.ndarray


def _to_bottom(a: np.ndarray, side: str) -> np.ndarray:
    """``a`` turned so that ``side`` is its bottom row."""
    if side == "bottom":
        return a
    if side == "top":
        return a[::-1]
    if side == "right":
        return a.T
    return a.T[::-1]


def _from_bottom(a: np.ndarray, side: str) -> np.ndarray:
    """Inverse of :func:`_to_bottom`."""
    if side == "bottom":
        return a
    if side == "top":
        return a[::-1]
    if side == "right":
        return a.T
    return a[::-1].T


def _run_depth(m: np.ndarray) -> np.ndarray:
    """Length of the run of ``m`` from the bottom row up, per column."""
    up = m[::-1]
    stop = np.where(up.all(axis=0), up.shape[0], np.argmin(up, axis=0))
    return stop.astype(np.int64)


def frame_bands(layout: np.ndarray, ends: np.ndarray, radius: np.ndarray, exclude) -> list[FrameBand]:
    """The frame-tied regions of an example's layout (see the module's doc).

    Parameters
    ----------
    layout : (H, W) int ndarray
        The example's region layout.
    ends : (R, 2) ndarray
        The branches' ends (x, y): every root's first point and every tip.
    radius : (H, W) ndarray
        Radius of the nearest branch at every pixel (only read at the ends).
    exclude : iterable of int
        Labels never frame-tied (the branch region and regions the branches run in).

    Returns
    -------
    list of FrameBand
        One per frame-tied region (none tied to two sides).
    """
    lay = np.asarray(layout)
    if lay.ndim != 2:
        raise ValueError(f"layout must be 2-D, got shape {lay.shape}")
    excl = {int(e) for e in exclude}
    ends = np.asarray(ends, np.float64).reshape(-1, 2)
    out = []
    for k in np.unique(lay):
        if int(k) in excl:
            continue
        m = lay == k
        for side in _SIDES:
            mb = _to_bottom(m, side)
            across = mb.shape[0]
            if mb[-1].mean() < SIDE_COVER:
                continue
            d = _run_depth(mb)
            if d.sum() < BAND_SHARE * mb.sum():
                continue
            rel = d / across
            if rel.mean() > MAX_DEPTH or rel.std() > EDGE_SPREAD:
                continue
            if len(ends):
                # an end on the region's edge has both the region and another one within reach
                along = []
                for x, y in ends:
                    xi, yi = int(np.clip(round(x), 0, m.shape[1] - 1)), int(np.clip(round(y), 0, m.shape[0] - 1))
                    r = int(np.ceil(OUTLET_REACH + float(radius[yi, xi]) if np.isfinite(radius[yi, xi])
                                    else OUTLET_REACH))
                    win = m[max(0, yi - r): yi + r + 1, max(0, xi - r): xi + r + 1]
                    if win.any() and not win.all():
                        along.append(x / m.shape[1] if side in ("bottom", "top") else y / m.shape[0])
                if len(along) >= MAX_OUTLETS and np.ptp(along) >= END_SPAN:
                    continue
            out.append(FrameBand(int(k), side, rel.astype(np.float64)))
            break
    return out


def place_bands(bands: list[FrameBand], shape) -> np.ndarray:
    """Where each frame-tied region lies in an ``(H, W)`` output: its depth profile along its side,
    stretched to the output's side and scaled to the image across it (the example's shape and share
    of the image; the example's own region when the sizes match).

    Parameters
    ----------
    bands : list of FrameBand
        From :func:`frame_bands`.
    shape : (H, W)
        The output's size.

    Returns
    -------
    (H, W) int32 ndarray
        A band's label where it lies, -1 elsewhere (a later band wins where two overlap).
    """
    h, w = int(shape[0]), int(shape[1])
    out = np.full((h, w), -1, np.int32)
    for b in bands:
        base = _to_bottom(out, b.side)
        across, n = base.shape
        src = (np.arange(len(b.depth)) + 0.5) / len(b.depth)
        dst = (np.arange(n) + 0.5) / n
        # the profile's steps stay steps (a skyline's walls): nearest sample, not a ramp
        idx = np.clip(np.searchsorted(src, dst), 0, len(b.depth) - 1)
        prev = np.clip(idx - 1, 0, len(b.depth) - 1)
        idx = np.where(np.abs(src[prev] - dst) < np.abs(src[idx] - dst), prev, idx)
        depth = np.round(b.depth[idx] * across).astype(np.int64)
        rows = np.arange(across)[:, None]
        band = rows >= across - depth[None, :]
        placed = _from_bottom(np.where(band, b.label, base), b.side)
        out = np.where(_from_bottom(band, b.side), placed, out)
    return out
