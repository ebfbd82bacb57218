"""Guided synthesis: a guidance map G with a smooth valley along a user path.

``G = 1`` everywhere except along the user-drawn path, where a smooth
valley of width ``w`` goes down to ``1 - depth``:

    G(p) = 1 - depth * exp(-d(p, path)^2 / w^2).

Candidate probabilities are scaled the way space colonization scales
them, so branches prefer to run down the valley:

    Q*** = Q** / (G_c + eps),

where, as for the density, ``G_c`` is read along the candidate's growth
direction (PCA of the vertices it adds) up to three extension lengths
ahead -- here its mean, so a branch that drifted out of the valley sees
the candidates turning back into it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from ..core.image import as_points
from ..core.polyline import resample_uniform
from ..core.validate import COORD_LIMIT, Array, Int, Point, Real, Shape, checked, real_array

__all__ = ["Guidance", "guidance_map"]


#: A guidance path: finite points within the coordinate limit.
_PATH = Array(ndim=2, min=-COORD_LIMIT, max=COORD_LIMIT)


@checked(shape=Shape(), path=_PATH, width=Real(1e-3, 1e5), depth=Real(0, 1e3))
def guidance_map(shape, path, width: float = 40.0, depth: float = 1.0) -> np.ndarray:
    """The guidance map ``G`` (float32, ``(H, W)``) for a path.

    Parameters
    ----------
    shape : (H, W)
        Size of the synthesis domain in pixels.
    path : (N, 2) array_like
        User-drawn path (x, y), N >= 2.
    width : float, default 40.0
        Valley width ``w`` (pixels), as ``SynthesisParams.guidance_width``.
    depth : float, default 1.0
        Valley depth in (0, 1]; G = 1 - depth on the path.

    Returns
    -------
    (H, W) float32 ndarray
        G in [1 - depth, 1].

    Raises
    ------
    ValueError
        If ``shape`` is not positive, ``width`` not > 0, ``depth`` not in
        (0, 1], or ``path`` has zero length or lies outside the domain.

    Examples
    --------
    >>> G = guidance_map((40, 60), [(5, 20), (55, 20)], width=5)
    >>> float(G[20, 30]) < 0.01, float(G[2, 30]) > 0.99
    (True, True)
    """
    h, w = int(shape[0]), int(shape[1])
    if h <= 0 or w <= 0:
        raise ValueError(f"shape must be positive, got {shape}")
    p = as_points(path, name="path", min_points=2)
    if not width > 0:
        raise ValueError(f"width must be > 0, got {width}")
    if not 0 < depth <= 1:
        raise ValueError(f"depth must be in (0, 1], got {depth}")
    if not np.any(np.ptp(p, axis=0) > 0):
        raise ValueError("path has zero length: all its points coincide")
    dense = resample_uniform(p, 0.5, include_end=True)
    mask = np.ones((h, w), bool)
    c = np.clip(np.round(dense[:, 0]).astype(int), 0, w - 1)
    r = np.clip(np.round(dense[:, 1]).astype(int), 0, h - 1)
    inside = (dense[:, 0] > -0.5) & (dense[:, 0] < w - 0.5) & (dense[:, 1] > -0.5) & (dense[:, 1] < h - 0.5)
    if not inside.any():
        raise ValueError("path lies entirely outside the domain given by shape")
    mask[r[inside], c[inside]] = False
    d = ndi.distance_transform_edt(mask)
    return (1.0 - depth * np.exp(-(d ** 2) / width ** 2)).astype(np.float32)


@dataclass
class Guidance:
    """A guidance map plus the path it was made from.

    Build it with :meth:`from_path`; pass it to
    :func:`~branchnb.branching.synthesis.synthesize_structure`. If the
    synthesis has no explicit start, the root starts at the path's first
    point heading along it.

    Parameters
    ----------
    map : (H, W) array_like
        The guidance map G (finite, >= 0; 1 = no preference, lower = a
        valley that attracts branches), e.g. from :func:`guidance_map`.
    path : (N, 2) array_like, optional
        The path (x, y) the map was made from, N >= 2; None when the map was
        painted some other way (then the root start is not taken from it).

    Raises
    ------
    ValueError
        If ``map`` is not a non-empty 2-D array of finite values >= 0, or
        ``path`` has fewer than 2 points.

    Examples
    --------
    >>> g = Guidance.from_path((40, 60), [(5, 20), (55, 20)], width=5)
    >>> g.shape, g.start()
    ((40, 60), (5.0, 20.0, 0.0))
    """

    map: np.ndarray
    path: np.ndarray | None = None

    def __post_init__(self):
        g = real_array(self.map, "map", dtype=np.float32, allow_empty=True, finite=False)
        if g.ndim != 2 or g.size == 0:
            raise ValueError(f"guidance map must be a non-empty 2-D array, got shape {g.shape}")
        if not np.all(np.isfinite(g)) or g.min() < 0:
            raise ValueError("guidance map must be finite and >= 0")
        self.map = g
        if self.path is not None:
            self.path = as_points(self.path, name="path", min_points=2)

    @classmethod
    @checked(shape=Shape(), path=_PATH, width=Real(1e-3, 1e5), depth=Real(0, 1e3))
    def from_path(cls, shape, path, width: float = 40.0, depth: float = 1.0) -> Guidance:
        """Guidance with a valley of width ``width`` along ``path``.

        Parameters
        ----------
        shape : (H, W)
            Size of the synthesis domain in pixels.
        path : (N, 2) array_like
            User-drawn path (x, y), N >= 2.
        width : float, default 40.0
            Valley width ``w`` (pixels).
        depth : float, default 1.0
            Valley depth in (0, 1]; G = 1 - depth on the path.

        Returns
        -------
        Guidance
            The map of :func:`guidance_map` and the path.
        """
        return cls(guidance_map(shape, path, width, depth), as_points(path, name="path", min_points=2))

    @property
    def shape(self) -> tuple[int, int]:
        return self.map.shape

    def sample(self, points) -> np.ndarray:
        """G at points ``(..., 2)``; 1 outside the map.

        Parameters
        ----------
        points : (..., 2) array_like
            Positions (x, y) in pixels (rounded to the nearest pixel).

        Returns
        -------
        (...) float32 ndarray
            G at each point.
        """
        p = real_array(points, "points")
        if p.ndim < 1 or p.shape[-1] != 2:
            raise ValueError(f"points must have shape (..., 2), got {p.shape}")
        c = np.round(p[..., 0]).astype(np.int64)
        r = np.round(p[..., 1]).astype(np.int64)
        h, w = self.map.shape
        ok = (c >= 0) & (c < w) & (r >= 0) & (r < h)
        out = np.ones(p.shape[:-1], np.float32)
        out[ok] = self.map[r[ok], c[ok]]
        return out

    @checked(tip=Point(), directions=Array(ndim=2), length=Real(0, 1e5), n_samples=Int(1, 10_000))
    def along(self, tip, directions, length: float, n_samples: int = 16) -> np.ndarray:
        """Mean of G along rays from ``tip`` in ``directions`` ``(J, 2)`` up to ``length``.

        Parameters
        ----------
        tip : (2,) array_like
            Start (x, y) of every ray: the branch tip (pixels).
        directions : (J, 2) array_like
            Unit growth direction of each candidate.
        length : float
            Ray length in pixels (three extension lengths in synthesis).
        n_samples : int, default 16
            Samples per ray, evenly spaced up to ``length`` (the tip itself is
            not sampled).

        Returns
        -------
        (J,) float64 ndarray
            ``G_c``: the mean of G along each ray.

        Examples
        --------
        >>> g = Guidance.from_path((40, 60), [(5, 20), (55, 20)], width=5)
        >>> G_c = g.along((5, 20), [(1.0, 0.0), (0.0, 1.0)], 15)
        >>> bool(G_c[0] < 0.01 < 0.5 < G_c[1])
        True
        """
        t = np.linspace(length / n_samples, length, n_samples)
        tip = np.asarray(tip, np.float64)
        d = np.asarray(directions, np.float64)
        if d.shape[1:] != (2,) or np.abs(d).max(initial=0.0) > 1e6:
            raise ValueError(f"directions must be (J, 2) direction vectors of moderate length, got shape {d.shape}")
        pts = tip[None, None, :] + t[None, :, None] * np.asarray(directions, np.float64)[:, None, :]
        return self.sample(pts).astype(np.float64).mean(axis=1)

    def start(self) -> tuple[float, float, float] | None:
        """``(x, y, angle)`` at the path's start, heading along it."""
        if self.path is None:
            return None
        p = self.path
        j = 1
        while j < len(p) - 1 and np.hypot(*(p[j] - p[0])) < 1e-9:
            j += 1
        d = p[j] - p[0]
        return float(p[0, 0]), float(p[0, 1]), float(np.arctan2(d[1], d[0]))
