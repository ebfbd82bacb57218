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

Which source pixels a patch may copy
------------------------------------
Every source pixel is owned by its nearest source-stroke point (stroke
index and arc length: a Voronoi partition computed with a distance
transform). A patch fetched around ``p'`` on source stroke ``k`` at arc
length ``s'`` copies only the pixels owned by stroke ``k`` at arc lengths
within ``1.5 r`` of ``s'``: so it never drags along the part of the
object drawn by another stroke, nor a part of the same stroke that folds
back nearby (a loop of rope). The transparent pixels around an RGBA
object belong to the patches too: they carry the silhouette, and the
graph cut decides between "object" and "background" like between any
two textures.

The *object region* is where the source is opaque (alpha > 0.5) for an
RGBA image; for an opaque image it is the union of the copied patches.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from ..core.graphcut import _gradmag  # the edge strength of the seam energy
from ..core.image import as_rgba
from ..core.warp import transfer_patch
from .strokes import Stroke, StrokePair

__all__ = ["SourceIndex", "Samples", "Fetched", "source_index", "sample_pair", "fetch"]

#: Scale of the gradient-magnitude channel carried along with the patches.
_GMAX = 4.0
#: A patch copies pixels owned by its stroke within this many radii of its arc length.
_REACH = 1.5


@dataclass
class SourceIndex:
    """The source image prepared for fetching.

    Attributes
    ----------
    premult : (H, W, 4) float32 ndarray
        Premultiplied RGBA (so that interpolation and colour differences
        treat transparent pixels consistently).
    aux : (H, W, 3) float32 ndarray
        ``x / (W - 1)``, ``y / (H - 1)`` and gradient magnitude ``/ 4``:
        warped with the texture to know where each patch pixel came from
        and how strong the edges are there.
    grad : (H, W) float32 ndarray
        Gradient magnitude ``|grad|`` of ``premult`` (Sobel, summed over channels).
    object : (H, W) bool ndarray
        The object region.
    owner : (H, W) int32 ndarray
        Source stroke owning each pixel (its nearest stroke).
    owner_s : (H, W) float32 ndarray
        Arc length of the owning stroke point.
    half_width : (H, W) float32 ndarray
        Distance to the nearest non-object pixel (``inf``-free; the image
        border counts as outside only for RGBA images).
    has_alpha : bool
        Whether the object region came from an alpha channel.
    """

    premult: np.ndarray
    aux: np.ndarray
    grad: np.ndarray
    object: np.ndarray
    owner: np.ndarray
    owner_s: np.ndarray
    half_width: np.ndarray
    has_alpha: bool

    @property
    def shape(self) -> tuple[int, int]:
        return self.object.shape

    def width_along(self, stroke: Stroke, s) -> np.ndarray:
        """Half width of the object at arc lengths ``s`` of a source stroke (pixels)."""
        p = stroke.point_at(s)
        h, w = self.shape
        c = np.clip(np.round(p[..., 0]).astype(int), 0, w - 1)
        r = np.clip(np.round(p[..., 1]).astype(int), 0, h - 1)
        return self.half_width[r, c]


def source_index(image, source_strokes: list[Stroke]) -> SourceIndex:
    """Prepare ``image`` for fetching along ``source_strokes``.

    Parameters
    ----------
    image : (H, W, C) array_like
        The source image (RGBA objects on a transparent background, or opaque).
    source_strokes : list of Stroke
    """
    rgba = as_rgba(image)
    h, w = rgba.shape[:2]
    alpha = rgba[:, :, 3]
    has_alpha = bool((alpha < 0.999).any())
    premult = rgba.copy()
    premult[:, :, :3] *= alpha[:, :, None]
    grad = _gradmag(premult).astype(np.float32)
    yy, xx = np.mgrid[0:h, 0:w].astype(np.float32)
    aux = np.dstack([xx / max(w - 1, 1), yy / max(h - 1, 1),
                     np.clip(grad / _GMAX, 0.0, 1.0)]).astype(np.float32)
    obj = alpha > 0.5 if has_alpha else np.ones((h, w), bool)
    # Seeds: the strokes rasterised every half pixel.
    seed_id = np.full((h, w), -1, np.int32)
    seed_s = np.zeros((h, w), np.float32)
    for k, st in enumerate(source_strokes):
        s = np.linspace(0.0, st.length, max(2, int(np.ceil(st.length * 2)) + 1))
        p = st.point_at(s)
        c = np.clip(np.round(p[:, 0]).astype(int), 0, w - 1)
        r = np.clip(np.round(p[:, 1]).astype(int), 0, h - 1)
        seed_id[r, c] = k
        seed_s[r, c] = s
    _, (ir, ic) = ndi.distance_transform_edt(seed_id < 0, return_indices=True)
    owner = seed_id[ir, ic].astype(np.int32)
    owner_s = seed_s[ir, ic].astype(np.float32)
    if has_alpha:
        half = ndi.distance_transform_edt(np.pad(obj, 1))[1:-1, 1:-1]
    else:
        half = np.full((h, w), np.inf)
    return SourceIndex(premult, aux, grad, obj, owner, owner_s,
                       half.astype(np.float32), has_alpha)


@dataclass
class Samples:
    """Samples along one target stroke.

    Attributes
    ----------
    s : (M,) ndarray
        Target arc lengths.
    points : (M, 2) ndarray
        Target positions ``p``.
    angles : (M,) ndarray
        Target stroke direction at ``p`` (radians).
    source_s : (M,) ndarray
        Nominal source arc lengths of ``p'`` (arc-length fraction between
        control points).
    pinned : (M,) bool ndarray
        Samples at control points (their correspondence is fixed).
    """

    s: np.ndarray
    points: np.ndarray
    angles: np.ndarray
    source_s: np.ndarray
    pinned: np.ndarray

    def __len__(self) -> int:
        return len(self.s)


def sample_pair(pair: StrokePair, spacing: float, *, window: float) -> Samples:
    """Sample the target stroke of ``pair`` every ``spacing`` pixels (about).

    Each stretch between consecutive target control points is divided
    into equal steps no longer than ``spacing``, so the control points
    themselves are samples (and are pinned).

    Examples
    --------
    >>> from branchnb.strokes.strokes import Stroke, StrokePair
    >>> pair = StrokePair(Stroke([(0, 0), (20, 0)]), Stroke([(0, 0), (0, 10)]))
    >>> smp = sample_pair(pair, 4.0, window=2.0)
    >>> smp.s.tolist(), smp.source_s.tolist()
    ([0.0, 3.3333333333333335, 6.666666666666667, 10.0], [0.0, 6.666666666666667, 13.333333333333334, 20.0])
    """
    if not (np.isfinite(spacing) and spacing > 0):
        raise ValueError(f"spacing must be > 0, got {spacing}")
    ct = pair.control[:, 1]
    parts = [np.array([ct[0]])]
    pinned = [True]
    for t0, t1 in zip(ct[:-1], ct[1:]):
        n = max(1, int(np.ceil((t1 - t0) / spacing - 1e-9)))
        parts.append(np.linspace(t0, t1, n + 1)[1:])
        pinned.extend([False] * (n - 1) + [True])
    s = np.concatenate(parts)
    return Samples(
        s=s,
        points=pair.target.point_at(s),
        angles=pair.target.angle_at(s, window=window),
        source_s=pair.source_arc_length(s),
        pinned=np.array(pinned, bool),
    )


@dataclass
class Fetched:
    """Candidate patches for one target sample, stacked.

    Attributes
    ----------
    pixels : (K, S, S, 4) float32 ndarray
        Premultiplied RGBA, in the target frame.
    valid : (K, S, S) bool ndarray
        Pixels the patch may contribute (inside the disk of radius ``r``,
        on the source image and owned by the stroke near ``s'``).
    grad : (K, S, S) float32 ndarray
        Gradient magnitude at the source location of each pixel.
    origin : (int, int)
        Target ``(x, y)`` of pixel ``[0, 0]``.
    source_points : (K, 2) ndarray
        ``p'`` of each candidate.
    source_s : (K,) ndarray
        Source arc length of each candidate.
    """

    pixels: np.ndarray
    valid: np.ndarray
    grad: np.ndarray
    origin: tuple[int, int]
    source_points: np.ndarray
    source_s: np.ndarray

    def take(self, k: int) -> Fetched:
        """The stack reduced to candidate ``k``."""
        sl = slice(k, k + 1)
        return Fetched(self.pixels[sl], self.valid[sl], self.grad[sl], self.origin,
                       self.source_points[sl], self.source_s[sl])


def fetch(index: SourceIndex, stroke_id: int, stroke: Stroke, source_s, across,
          dst_point, dst_angle: float, radius: float, *, window: float) -> Fetched:
    """Fetch candidate patches for one target sample.

    Parameters
    ----------
    index : SourceIndex
    stroke_id : int
        Index of ``stroke`` among the source strokes (for ownership).
    stroke : Stroke
        The source stroke.
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
    """
    s = np.clip(np.atleast_1d(np.asarray(source_s, float)), 0.0, stroke.length)
    e = np.broadcast_to(np.asarray(across, float), s.shape)
    centres = stroke.point_at(s) + e[:, None] * stroke.normal_at(s, window=window)
    angles = stroke.angle_at(s, window=window)
    h, w = index.shape
    pix, valid, grad = [], [], []
    origin = None
    for c, a, sk in zip(centres, angles, s):
        patch = transfer_patch(index.premult, c, a, dst_point, dst_angle, radius, circular=True)
        aux = transfer_patch(index.aux, c, a, dst_point, dst_angle, radius).pixels
        origin = patch.origin
        col = np.clip(np.rint(aux[:, :, 0] * (w - 1)).astype(np.int64), 0, w - 1)
        row = np.clip(np.rint(aux[:, :, 1] * (h - 1)).astype(np.int64), 0, h - 1)
        ok = (patch.valid & (index.owner[row, col] == stroke_id)
              & (np.abs(index.owner_s[row, col] - sk) <= _REACH * radius))
        pix.append(patch.pixels)
        valid.append(ok)
        grad.append(aux[:, :, 2] * _GMAX)
    return Fetched(np.stack(pix), np.stack(valid), np.stack(grad).astype(np.float32),
                   origin, centres, s)
