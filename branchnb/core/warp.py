"""Warps: rotated patch transfer and dense remapping (OpenCV underneath).

Both the fragments of branching synthesis and the stroke-aligned patches
of stroke editing copy texture from around a source point, rotated so a
source direction lines up with a target direction.
"""

from __future__ import annotations

from dataclasses import dataclass

import cv2
import numpy as np

from .image import as_float_image
from .validate import Real, as_point, check_shape, checked, real_array

__all__ = ["Patch", "transfer_patch", "remap"]


@dataclass
class Patch:
    """Texture copied into a target frame (what :func:`transfer_patch` returns).

    Parameters
    ----------
    pixels : (h, w, C) float32 ndarray
        The copied texture, in [0, 1].
    valid : (h, w) bool ndarray
        Pixels whose source location lay inside the source image (and, for
        a circular patch, inside the disk).
    origin : (int, int)
        Target ``(x, y)`` of ``pixels[0, 0]``, in pixels (may be negative:
        the patch may stick out of the target image).

    Examples
    --------
    >>> import numpy as np
    >>> p = transfer_patch(np.zeros((20, 20, 3)), (10, 10), 0.0, (2, 2), 0.0, radius=3)
    >>> p.pixels.shape, p.origin
    ((7, 7, 3), (-1, -1))
    """

    pixels: np.ndarray
    valid: np.ndarray
    origin: tuple[int, int]

    def placed(self, shape) -> tuple[np.ndarray, np.ndarray]:
        """The patch pasted on an empty canvas of ``shape`` (H, W[, C]): ``(image, mask)``.

        Parameters
        ----------
        shape : sequence of int
            ``(H, W)`` of the target canvas (a trailing channel count is
            ignored; the patch keeps its own channels).

        Returns
        -------
        image : (H, W, C) float32 ndarray
            Zeros, with the patch at ``origin`` (clipped to the canvas).
        mask : (H, W) bool ndarray
            The patch's ``valid`` pixels that land on the canvas.

        Examples
        --------
        >>> import numpy as np
        >>> p = Patch(np.ones((2, 2, 3), np.float32), np.ones((2, 2), bool), (-1, 0))
        >>> int(p.placed((3, 3))[1].sum())
        2
        """
        h, w = check_shape(shape, "shape")
        img = np.zeros((h, w, self.pixels.shape[2]), np.float32)
        mask = np.zeros((h, w), bool)
        x0, y0 = self.origin
        ph, pw = self.valid.shape
        r0, r1 = max(y0, 0), min(y0 + ph, h)
        c0, c1 = max(x0, 0), min(x0 + pw, w)
        if r0 < r1 and c0 < c1:
            sub = (slice(r0 - y0, r1 - y0), slice(c0 - x0, c1 - x0))
            img[r0:r1, c0:c1] = self.pixels[sub]
            mask[r0:r1, c0:c1] = self.valid[sub]
        return img, mask


@checked(radius=Real(0, 4096, low_open=True), scale=Real(1e-3, 1e3))
def transfer_patch(image, src_center, src_angle: float, dst_center, dst_angle: float,
                   radius: float, *, scale: float = 1.0, circular: bool = False) -> Patch:
    """Copy the texture around ``src_center`` to a patch around ``dst_center``.

    The patch is rotated so that the direction ``src_angle`` at the source
    becomes ``dst_angle`` at the target (angles in radians, measured from
    +x towards +y, i.e. clockwise on screen), and optionally scaled.
    Sampling is bilinear.

    Parameters
    ----------
    image : (H, W, C) array_like
        The source texture (any layout :func:`as_float_image` accepts).
    src_center : (x, y)
        Centre of the copied texture in ``image`` (pixels).
    src_angle : float
        Direction at the source (radians) that is turned onto ``dst_angle``.
    dst_center : (x, y)
        Centre of the patch in the target frame; rounded to whole pixels.
    dst_angle : float
        Direction at the target (radians).
    radius : float
        Half size of the target patch (pixels, in (0, 4096]); the patch is
        ``2 ceil(radius) + 1`` pixels square.
    scale : float
        Target size / source size (1e-3 .. 1e3); 2 magnifies the texture.
    circular : bool
        Mark only the disk of ``radius`` as valid.

    Returns
    -------
    Patch
        Source locations outside ``image`` sample its nearest border pixel
        and are marked invalid.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.random.default_rng(0).random((32, 32, 3))
    >>> p = transfer_patch(img, (16, 16), 0.0, (16, 16), 0.0, 4)
    >>> np.allclose(p.pixels, img[12:21, 12:21])
    True
    """
    img = as_float_image(image)
    if not (np.isfinite(radius) and radius > 0):
        raise ValueError(f"radius must be > 0, got {radius}")
    if not (np.isfinite(scale) and scale > 0):
        raise ValueError(f"scale must be > 0, got {scale}")
    sx, sy = as_point(src_center, "src_center")
    dx, dy = as_point(dst_center, "dst_center")
    r = int(np.ceil(radius))
    cx, cy = int(round(dx)), int(round(dy))
    x0, y0 = cx - r, cy - r
    size = 2 * r + 1
    # Map target pixel q to source: p = s + (1/scale) R(src - dst) (q - d).
    theta = float(src_angle) - float(dst_angle)
    c, s = np.cos(theta) / scale, np.sin(theta) / scale
    rot = np.array([[c, -s], [s, c]])
    # q = (x0 + u, y0 + v)  ->  p = rot @ (q - d) + src
    offset = rot @ (np.array([x0, y0], float) - [dx, dy]) + [sx, sy]
    m = np.hstack([rot, offset[:, None]]).astype(np.float64)
    n_ch = img.shape[2]
    warped = cv2.warpAffine(img, m, (size, size), flags=cv2.INTER_LINEAR | cv2.WARP_INVERSE_MAP,
                            borderMode=cv2.BORDER_REPLICATE)
    if warped.ndim == 2:
        warped = warped[:, :, None]
    warped = warped[:, :, :n_ch]
    u, v = np.meshgrid(np.arange(size), np.arange(size))
    px = m[0, 0] * u + m[0, 1] * v + m[0, 2]
    py = m[1, 0] * u + m[1, 1] * v + m[1, 2]
    h, w = img.shape[:2]
    valid = (px >= -0.5) & (px <= w - 0.5) & (py >= -0.5) & (py <= h - 0.5)
    if circular:
        valid &= (u + x0 - dx) ** 2 + (v + y0 - dy) ** 2 <= radius**2
    return Patch(np.ascontiguousarray(warped, dtype=np.float32), valid, (x0, y0))


def remap(image, map_x, map_y) -> tuple[np.ndarray, np.ndarray]:
    """Sample ``image`` at ``(map_x, map_y)`` (bilinear): ``out[r, c] = image(map_x[r, c], map_y[r, c])``.

    Parameters
    ----------
    image : (H, W, C) array_like
        The image to sample (any layout :func:`as_float_image` accepts).
    map_x, map_y : (H', W') array_like
        Source x (column) and y (row) of every output pixel, in pixels of
        ``image``; finite. Locations outside repeat the border pixel.

    Returns
    -------
    out : (H', W', C) float32 ndarray
    valid : (H', W') bool ndarray
        Where the sample location lay inside the image.

    Raises
    ------
    ValueError
        If the maps are not 2-D of equal shape or hold NaN/inf.

    Examples
    --------
    >>> import numpy as np
    >>> img = np.arange(4, dtype=float).reshape(2, 2) / 3
    >>> out, valid = remap(img, np.array([[0.5, 5.0]]), np.array([[0.0, 0.0]]))
    >>> [round(float(v), 3) for v in out[0, :, 0]], valid.tolist()
    ([0.167, 0.333], [[True, False]])
    """
    img = as_float_image(image)
    mx = real_array(map_x, "map_x", dtype=np.float32, finite=False)
    my = real_array(map_y, "map_y", dtype=np.float32, finite=False)
    if mx.shape != my.shape or mx.ndim != 2:
        raise ValueError(f"map_x and map_y must be 2-D with equal shapes, got {mx.shape} and {my.shape}")
    if not (np.all(np.isfinite(mx)) and np.all(np.isfinite(my))):
        raise ValueError("map_x/map_y contain NaN or infinite values")
    out = cv2.remap(img, mx, my, interpolation=cv2.INTER_LINEAR, borderMode=cv2.BORDER_REPLICATE)
    if out.ndim == 2:
        out = out[:, :, None]
    h, w = img.shape[:2]
    valid = (mx >= -0.5) & (mx <= w - 0.5) & (my >= -0.5) & (my <= h - 0.5)
    return out.astype(np.float32), valid


#: OpenCV's remap asserts each side of its output is under SHRT_MAX.
_REMAP_ROW = 4096


def _remap_points(image, xs, ys, *, interpolation: int = cv2.INTER_LINEAR,
                  border_mode: int = cv2.BORDER_REPLICATE, border_value: float = 0.0) -> np.ndarray:
    """``cv2.remap`` of ``image`` at N points ``(xs[i], ys[i])``, any N.

    The points are laid out as rows of :data:`_REMAP_ROW` (one row of N
    failed OpenCV's SHRT_MAX assertion past 32766 points: a 2 MP leaf's
    carried contour). Returns ``(N,)`` or ``(N, C)`` like ``cv2.remap``'s
    single-row output.
    """
    xs = np.asarray(xs, np.float32).ravel()
    ys = np.asarray(ys, np.float32).ravel()
    n = xs.size
    if n == 0:
        img = np.asarray(image)
        return np.zeros((0,) + img.shape[2:3], img.dtype)
    if n <= _REMAP_ROW:
        out = cv2.remap(image, xs[None], ys[None], interpolation, borderMode=border_mode, borderValue=border_value)
        return out[0]
    rows = -(-n // _REMAP_ROW)
    pad = rows * _REMAP_ROW - n
    mx = np.concatenate([xs, np.zeros(pad, np.float32)]).reshape(rows, _REMAP_ROW)
    my = np.concatenate([ys, np.zeros(pad, np.float32)]).reshape(rows, _REMAP_ROW)
    out = cv2.remap(image, mx, my, interpolation, borderMode=border_mode, borderValue=border_value)
    return out.reshape((rows * _REMAP_ROW,) + out.shape[2:])[:n]

