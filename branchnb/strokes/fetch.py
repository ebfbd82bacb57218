"""Fetching source texture: samples along the target strokes, rotated patches from the source.

Each target stroke is sampled every ``h`` pixels of arc length, and every
control point is a sample too. A sample ``p`` between target control
points ``c_i`` and ``c_i+1`` maps to the point ``p'`` at the same
arc-length fraction between the corresponding source control points
(:meth:`~branchnb.strokes.strokes.StrokePair.source_arc_length`). The
texture around ``p'`` is copied to ``p``, rotated so that the source
stroke direction at ``p'`` lines up with the target stroke direction at
``p`` (:func:`branchnb.core.warp.transfer_patch`, circular patches of
radius ``r``).

Global texture sampling (:mod:`branchnb.strokes.sampling`) may move
``p'`` a little along (and across) the source stroke; the moves are the
*candidates* fetched here.

The source is prepared first (:mod:`~branchnb.strokes.source`: the
object's widths, the pixels each stroke may copy, cut ends, unstroked
parts); :func:`source_index` and :class:`SourceIndex` are importable from
here too.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.validate import COORD_LIMIT, Array, Int, Real, Shape, checked
from .samples import Samples, sample_pair
from .source import OPAQUE_RADIUS, SourceIndex, auto_radius, source_index  # noqa: F401  (re-exported)
from .strokes import Stroke  # noqa: F401  (the examples use it)

__all__ = ["SourceIndex", "Samples", "Fetched", "source_index", "sample_pair", "fetch",
           "OPAQUE_RADIUS"]

#: A patch copies pixels owned by its stroke within this many radii of its arc length.
_REACH = 1.5


#: Arc lengths and offsets along/across a stroke: finite and within the coordinate limit.
_OFFSETS = Array(ndim=(0, 1), min=-COORD_LIMIT, max=COORD_LIMIT)


@dataclass
class Fetched:
    """Candidate patches for one target sample, stacked.

    Parameters
    ----------
    pixels : (K, S, S, 4) float32 ndarray
        Premultiplied RGBA, in the target frame.
    valid : (K, S, S) bool ndarray
        Pixels the patch may contribute (inside the disk of radius ``r``,
        on the source image and allowed for the stroke near ``s'``).
    grad : (K, S, S) float32 ndarray
        Edge strength at the source location of each pixel.
    origin : (int, int)
        Target ``(x, y)`` of pixel ``[0, 0]``.
    source_points : (K, 2) ndarray
        ``p'`` of each candidate.
    source_s : (K,) ndarray
        Source arc length of each candidate.
    source_angles : (K,) ndarray
        Source stroke direction at each ``p'``.
    dst_point : (2,) ndarray
        The target sample ``p``.
    dst_angle : float
        Target direction at ``p``.
    radius : float
        Patch radius ``r``.
    mirror : bool
        The patches are mirror images (reflected across the target stroke,
        then rotated): the target stroke turns the other way than the source.
    """

    pixels: np.ndarray
    valid: np.ndarray
    grad: np.ndarray
    origin: tuple[int, int]
    source_points: np.ndarray
    source_s: np.ndarray
    source_angles: np.ndarray
    dst_point: np.ndarray
    dst_angle: float
    radius: float = 0.0
    mirror: bool = False

    def _candidate(self, k: int) -> None:
        if not 0 <= k < len(self.pixels):
            raise ValueError(f"k = {k} is not a candidate index (there are {len(self.pixels)})")

    @checked(k=Int(0))
    def take(self, k: int) -> Fetched:
        """The stack reduced to candidate ``k``.

        Parameters
        ----------
        k : int
            Candidate index in ``[0, K)``.

        Returns
        -------
        Fetched
            A stack of one (views into this one's arrays).
        """
        self._candidate(k)
        sl = slice(k, k + 1)
        return Fetched(self.pixels[sl], self.valid[sl], self.grad[sl], self.origin,
                       self.source_points[sl], self.source_s[sl], self.source_angles[sl],
                       self.dst_point, self.dst_angle, self.radius, self.mirror)

    @checked(k=Int(0), shape=Shape())
    def source_pixels(self, k: int, shape) -> tuple[np.ndarray, np.ndarray]:
        """``(rows, cols)`` of the source pixels candidate ``k`` copies (its valid pixels).

        Parameters
        ----------
        k : int
            Candidate index in ``[0, K)``.
        shape : tuple of int
            Source image shape ``(H, W, ...)``; indices are clipped to it.

        Returns
        -------
        rows, cols : (N,) int64 ndarray
            Nearest source pixel of each valid patch pixel.
        """
        self._candidate(k)
        sx, sy = _source_coords(self.source_points[k], self.source_angles[k], self.dst_point,
                                self.dst_angle, self.origin, self.valid.shape[1], self.mirror)
        v = self.valid[k]
        h, w = shape[:2]
        return (np.clip(np.rint(sy[v]).astype(np.int64), 0, h - 1),
                np.clip(np.rint(sx[v]).astype(np.int64), 0, w - 1))


def _source_coords(centre, angle: float, dst_point, dst_angle: float, origin, n: int, mirror: bool = False):
    """Source ``(x, y)`` of every pixel of an ``n`` x ``n`` patch at ``origin``.

    The inverse of the rotation :func:`~branchnb.core.warp.transfer_patch`
    applies: ``p = R(angle - dst_angle) (q - p_dst) + p'`` (mirrored:
    ``p = R(angle) F R(-dst_angle) (q - p_dst) + p'``, ``F`` the reflection across
    the stroke's direction).
    """
    u, v = np.meshgrid(np.arange(n) + origin[0] - float(dst_point[0]),
                       np.arange(n) + origin[1] - float(dst_point[1]))
    if mirror:
        ph = float(angle) + float(dst_angle)
        return np.cos(ph) * u + np.sin(ph) * v + centre[0], np.sin(ph) * u - np.cos(ph) * v + centre[1]
    th = float(angle) - float(dst_angle)
    sx = np.cos(th) * u - np.sin(th) * v + centre[0]
    sy = np.sin(th) * u + np.cos(th) * v + centre[1]
    return sx, sy


@checked(stroke_id=Int(0), source_s=_OFFSETS, across=_OFFSETS,
         dst_point=Array(ndim=1, min=-COORD_LIMIT, max=COORD_LIMIT), radius=Real(0, 1e4, low_open=True),
         window=Real(0, 1e4))
def fetch(index: SourceIndex, stroke_id: int, source_s, across, dst_point, dst_angle: float,
          radius: float, *, window: float) -> Fetched:
    """Fetch candidate patches for one target sample.

    Parameters
    ----------
    index : SourceIndex
        The prepared source image (:func:`source_index`).
    stroke_id : int
        Which source stroke (index into ``index.strokes``).
    source_s : (K,) array_like
        Source arc lengths ``s'`` of the candidates (clamped to the stroke).
    across : (K,) array_like
        Offsets of the candidates along the source normal (pixels).
    dst_point : (x, y)
        Target sample ``p``.
    dst_angle : float
        Target direction at ``p``.
    radius : float
        Patch radius ``r``.
    window : float
        Chord half-length used for the source orientation.

    Returns
    -------
    Fetched
        ``K`` candidates stacked on one ``(2 ceil(r) + 1)``-pixel square
        centred on ``p``.

    Examples
    --------
    >>> img = np.zeros((30, 60, 4), np.float32); img[10:20, 5:55] = (0.6, 0.4, 0.2, 1.0)
    >>> idx = source_index(img, [Stroke([(5, 15), (54, 15)])])
    >>> f = fetch(idx, 0, [20.0, 24.0], [0.0, 0.0], np.array([30.0, 30.0]), np.pi / 2, 8.0, window=4.0)
    >>> f.pixels.shape, f.origin
    ((2, 17, 17, 4), (22, 22))
    """
    index._stroke(stroke_id, "stroke_id")
    if dst_point.shape != (2,):
        raise ValueError(f"dst_point must be one (x, y) point, got shape {dst_point.shape}")
    return _fetch(index, stroke_id, source_s, across, dst_point, dst_angle, radius, window)


def _thin_map(index: SourceIndex) -> np.ndarray:
    """Source pixels of parts at most ~3 px wide (no pixel deeper than 2 px within 2 px); cached."""
    thin = index.__dict__.get("_thin")
    if thin is None or thin.shape != index.depth.shape:
        thin = (ndi.maximum_filter(index.depth, size=5) <= 2.0).astype(np.uint8)
        index.__dict__["_thin"] = thin
    return thin


def _keep_solid(pix: np.ndarray, premult: np.ndarray, thin: np.ndarray, mx: np.ndarray,
                my: np.ndarray) -> np.ndarray:
    """Bilinear ``pix`` with the nearest source pixel where that one is solid, on a
    thin part (``thin``), and ``pix`` is not.

    A part 1-2 px wide under a soft alpha (a tine's last third at 150 px:
    alpha ~0.66 on a one-pixel line) sampled between pixel centres is spread
    over two pixels at half its alpha: turned or moved, its thin end fell
    below the object's alpha 0.5, turned faint and was trimmed as background
    (tines ended blunt and short, their tips a faint ring). There the
    nearest source pixel's value is kept; the rims of wider parts are
    interpolated as before (smooth edges). Beyond the paper (which
    resamples bilinearly).
    """
    low = pix[..., 3] < 0.5
    if not low.any():
        return pix
    on_thin = cv2.remap(thin, mx, my, cv2.INTER_NEAREST, borderMode=cv2.BORDER_REPLICATE) > 0
    low &= on_thin
    if not low.any():
        return pix
    near = cv2.remap(premult, mx, my, cv2.INTER_NEAREST, borderMode=cv2.BORDER_REPLICATE)
    keep = low & (near[..., 3] > 0.5)
    pix[keep] = near[keep]
    return pix


def _fetch(index: SourceIndex, stroke_id: int, source_s, across, dst_point, dst_angle: float,
           radius: float, window: float, mirror: bool = False) -> Fetched:
    """:func:`fetch` on checked arguments (the edit's inner loop: one call per target sample);
    ``mirror``: mirror-image patches (see :class:`Fetched`)."""
    stroke = index.strokes[stroke_id]
    s = np.clip(np.atleast_1d(np.asarray(source_s, float)), 0.0, stroke.length)
    e = np.broadcast_to(np.asarray(across, float), s.shape)
    # (the unchecked methods: s is clipped float arc lengths, window a checked number)
    angles = stroke._angle_at(s, window)
    centres = stroke._point_at(s) + e[:, None] * np.stack([-np.sin(angles), np.cos(angles)], axis=-1)
    h, w = index.shape
    s_map, allowed = index.s_map[stroke_id], index.allowed[stroke_id]
    # All candidates at once: target pixel q -> source p = R(a_k - dst_angle) (q - p_dst) + c_k
    # (the rotation of core.warp.transfer_patch), bilinear, one remap for the whole stack.
    r = int(np.ceil(radius))
    dx, dy = float(dst_point[0]), float(dst_point[1])
    x0, y0 = int(round(dx)) - r, int(round(dy)) - r
    size = 2 * r + 1
    uu, vv = np.meshgrid(np.arange(size, dtype=np.float32) + np.float32(x0 - dx),
                         np.arange(size, dtype=np.float32) + np.float32(y0 - dy))
    disk = uu**2 + vv**2 <= radius**2
    k = len(s)
    if mirror:
        # reflected across the target direction, then rotated: R(a_k) F R(-dst_angle)
        ph = np.asarray(angles, float) + float(dst_angle)
        cos = np.cos(ph).astype(np.float32)[:, None, None]
        sin = np.sin(ph).astype(np.float32)[:, None, None]
        mx = (cos * uu + sin * vv + centres[:, 0, None, None].astype(np.float32)).reshape(k * size, size)
        my = (sin * uu - cos * vv + centres[:, 1, None, None].astype(np.float32)).reshape(k * size, size)
    else:
        th = np.asarray(angles, float) - float(dst_angle)
        cos = np.cos(th).astype(np.float32)[:, None, None]
        sin = np.sin(th).astype(np.float32)[:, None, None]
        mx = (cos * uu - sin * vv + centres[:, 0, None, None].astype(np.float32)).reshape(k * size, size)
        my = (sin * uu + cos * vv + centres[:, 1, None, None].astype(np.float32)).reshape(k * size, size)
    view = index.views.get(stroke_id)
    premult, grad = (index.premult, index.grad) if view is None else (view[0], view[2])
    pix = cv2.remap(premult, mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    if index.has_alpha:
        pix = _keep_solid(pix, premult, _thin_map(index), mx, my)
    wt = cv2.remap(index.weight[stroke_id], mx, my, cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    pix = pix.reshape(k, size, size, 4)
    pix *= wt.reshape(k, size, size, 1)
    inside = (mx >= -0.5) & (mx <= w - 0.5) & (my >= -0.5) & (my <= h - 0.5)
    flat = (np.clip(np.rint(my), 0, h - 1).astype(np.intp) * w
            + np.clip(np.rint(mx), 0, w - 1).astype(np.intp)).reshape(k, size, size)
    ok = disk[None] & inside.reshape(k, size, size) & allowed.ravel().take(flat)
    ok &= np.abs(s_map.ravel().take(flat) - s[:, None, None].astype(np.float32)) <= _REACH * radius
    return Fetched(pix, ok, grad.ravel().take(flat),
                   (x0, y0), centres, s, np.asarray(angles, float),
                   np.asarray(dst_point, float), float(dst_angle), float(radius), bool(mirror))
