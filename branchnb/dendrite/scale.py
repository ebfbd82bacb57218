"""Image-size awareness: lengths given for a 512 x 512 image scale with the diagonal.

Every length default of the dendrite technique (stroke widths, smoothing
scales, vine leaves and curls, lightning glow) is stated for a 512 x 512
image and multiplied by :func:`length_scale` of the actual image, so a
256-px and a 1024-px input give the same picture at their own resolution.
Counts (endpoints, iterations) do not scale: the same number of branches
at any size is what keeps the results alike.
"""

from __future__ import annotations

import math
import numbers

import numpy as np

__all__ = ["REFERENCE_DIAGONAL", "SMALL_LATTICE_RATIO", "length_scale", "lattice_shape", "planning_size",
           "resample_to_lattice", "scaled"]

#: Diagonal (px) of the 512 x 512 image the length defaults are given for.
REFERENCE_DIAGONAL = math.hypot(512.0, 512.0)


def length_scale(shape) -> float:
    """``diagonal(shape) / diagonal(512 x 512)``.

    Parameters
    ----------
    shape : (int, int, ...)
        Image shape; only ``(H, W)`` is used.

    Returns
    -------
    float
        Factor to multiply a length given for 512 x 512 pixels by.

    Examples
    --------
    >>> length_scale((512, 512)), length_scale((1024, 1024))
    (1.0, 2.0)
    """
    h, w = int(shape[0]), int(shape[1])
    return math.hypot(h, w) / REFERENCE_DIAGONAL


def scaled(value, shape, default: float) -> float:
    """``value`` if given (pixels), else ``default`` (pixels at 512 x 512) scaled to ``shape``.

    Parameters
    ----------
    value : float or None
        A length the user gave in pixels of the actual image; used as is.
    shape : (int, int, ...)
        Image shape ``(H, W, ...)`` the default is scaled to.
    default : float
        The length in pixels at 512 x 512, used when ``value`` is None.

    Returns
    -------
    float
        The length in pixels.

    Examples
    --------
    >>> scaled(None, (1024, 1024), 3.0), scaled(5, (1024, 1024), 3.0)
    (6.0, 5.0)
    """
    if value is not None:
        return float(value)
    return float(default) * length_scale(shape)


def lattice_shape(shape, lattice_size: int) -> tuple[int, int]:
    """``shape`` resized so its diagonal is that of a ``lattice_size`` square (0: as is).

    Parameters
    ----------
    shape : (int, int, ...)
        Image shape; only ``(H, W)`` is used.
    lattice_size : int
        Side (px) of the square whose diagonal the result gets; 0 keeps
        ``shape``. The aspect ratio is kept and each side is at least 2.

    Returns
    -------
    (int, int)
        ``(H', W')`` of the lattice.

    Examples
    --------
    >>> lattice_shape((1024, 1024), 512), lattice_shape((300, 400), 0)
    ((512, 512), (300, 400))
    """
    h, w = int(shape[0]), int(shape[1])
    if lattice_size == 0:
        return h, w
    f = lattice_size / math.sqrt(0.5 * (h * h + w * w))
    return max(2, round(h * f)), max(2, round(w * f))


#: A picture is planned on a lattice at most this many times its own size (the side of the
#: square of its diagonal; :func:`planning_size`).
SMALL_LATTICE_RATIO = 2.4


def planning_size(shape, lattice_size: int) -> int:
    """The lattice size a picture of ``shape`` is really planned on: ``lattice_size``, or on a
    picture smaller than ``lattice_size / SMALL_LATTICE_RATIO`` (the side of the square of its
    diagonal) ``SMALL_LATTICE_RATIO`` times that side.

    Parameters
    ----------
    shape : (int, int, ...)
        Image shape; only ``(H, W)`` is used.
    lattice_size : int
        The lattice size asked for (0: the picture's own pixels, returned as is).

    Returns
    -------
    int
        At most ``lattice_size`` and at least 16 (or 0).

    Notes
    -----
    Beyond the paper (issue 25, dendrite45): a 64-160 px picture was planned on the 512-px
    lattice, upsampled 3-9x, and took as long as a 500-px one (0.7-2.8 s CPU, 3-12 s on a loaded
    machine). Lengths of :class:`~branchnb.dendrite.stylize_params.StylizeParams` are pixels of
    the ``lattice_size`` lattice and :class:`~branchnb.dendrite.stylization.Stylizer` converts
    them to the smaller one, so the drawing keeps its look; 2.4 times the picture's size keeps
    every picture from ~215 px (a 250 x 187 one) on the 512 lattice, bit for bit as before, and
    the lattice's steps (under half an image pixel) stay below what the drawing shows.

    Examples
    --------
    >>> planning_size((600, 800), 512), planning_size((48, 64), 512), planning_size((48, 64), 0)
    (512, 136, 0)
    """
    if isinstance(lattice_size, bool) or not isinstance(lattice_size, numbers.Real):
        raise TypeError(f"lattice_size must be a number, got {type(lattice_size).__name__}")
    if not math.isfinite(lattice_size):
        raise ValueError(f"lattice_size must be finite, got {lattice_size!r}")
    if lattice_size <= 0:
        return int(lattice_size)
    h, w = int(shape[0]), int(shape[1])
    side = SMALL_LATTICE_RATIO * math.sqrt(0.5 * (h * h + w * w))
    return int(lattice_size) if side >= lattice_size else max(16, min(int(lattice_size), round(side)))


def resample_to_lattice(image: np.ndarray, lattice_size: int) -> np.ndarray:
    """An (H, W, C) image resampled to :func:`lattice_shape` (bilinear, anti-aliased
    when shrinking).

    Parameters
    ----------
    image : (H, W, C) ndarray
        Float image.
    lattice_size : int
        See :func:`lattice_shape`; 0 returns ``image`` itself.

    Returns
    -------
    (H', W', C) float32 ndarray
        ``image`` unchanged (same object) when the shape already fits.

    Examples
    --------
    >>> resample_to_lattice(np.zeros((64, 64, 3), np.float32), 32).shape
    (32, 32, 3)
    """
    shape = lattice_shape(image.shape[:2], lattice_size)
    if shape == tuple(image.shape[:2]):
        return image
    from skimage.transform import resize

    shrink = shape[0] < image.shape[0]
    return resize(image, (*shape, image.shape[2]), order=1, anti_aliasing=shrink,
                  preserve_range=True).astype(np.float32)
