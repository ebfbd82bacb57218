"""The importance map of an input image (paper, section 4).

Importance says where the dendrite should show detail: dark regions and
edges. With the image's luminance ``L`` (float in [0, 1])::

    D = 1 - L                                   (darkness)
    G = min(|grad(G_sigma * L)| / g_ref, 1)     (gradient magnitude)
    I = (w_I * D + w_G * G) / (w_I + w_G)       in [0, 1]

with the gradient weighted three times the intensity by default
(``w_G = 3 w_I``, as in the paper). ``g_ref`` is the gradient that counts as
a full-strength edge: the 99th percentile of the image's gradient
magnitude, but never below ``min_edge`` so that the faint noise of a flat
image is not stretched into "edges".

Beyond the paper (issue 25, dendrite41): on a colour picture ``G`` also takes the gradient of
the two opponent colour channels at half weight (:data:`CHROMA_WEIGHT`), so a border between
two colours of one luminance (a red letter part next to a blue one) counts as an edge; the
paper's luminance gradient alone left it out of the drawing. Grey pictures are unchanged.

A constant image has ``G = 0`` and a constant ``I`` (0 for white): the
stylization then falls back to uniformly spread endpoints and uniform
thickness (see :func:`branchnb.dendrite.endpoints.place_endpoints`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage

from ..core.image import as_float_image, as_gray
from ..core.params import check_params, param
from ..core.validate import Real, checked

__all__ = ["ImportanceParams", "darkness", "gradient_strength", "importance_map"]


@dataclass
class ImportanceParams:
    """Weights of the importance map ``I = (w_I D + w_G G) / (w_I + w_G)``.

    Parameters
    ----------
    intensity_weight : float
        ``w_I``, weight of the darkness ``D = 1 - L`` (>= 0); 1 by default.
    gradient_weight : float
        ``w_G``, weight of the gradient term ``G`` (>= 0); 3 by default, three
        times ``w_I`` as in the paper.
    sigma : float
        Standard deviation (pixels) of the Gaussian applied before the
        gradient; 0 uses plain finite differences. 1 by default.
    min_edge : float
        Smallest gradient magnitude (luminance per pixel) that may count as a
        full-strength edge ``g_ref``; keeps the noise of a flat image from
        being stretched to 1. 0.05 by default.

    Examples
    --------
    >>> ImportanceParams().gradient_weight / ImportanceParams().intensity_weight
    3.0
    """

    intensity_weight: float = param(1.0, min=0.0, max=10.0, step=0.1,
                                    help="w_I: weight of darkness (1 - luminance)")
    gradient_weight: float = param(3.0, min=0.0, max=10.0, step=0.1,
                                   help="w_G: weight of gradient magnitude (paper: 3 x w_I)")
    sigma: float = param(1.0, min=0.0, max=8.0, step=0.25,
                         help="Gaussian pre-smoothing of the gradient (pixels)")
    min_edge: float = param(0.05, min=1e-4, max=1.0, step=0.01, log=True,
                            help="smallest gradient (per pixel) that may count as a full edge")


def darkness(image) -> np.ndarray:
    """``D = 1 - luminance`` as an (H, W) float32 array.

    Parameters
    ----------
    image : array_like
        Grey ``(H, W)`` or colour ``(H, W, C)`` image in [0, 1] (alpha ignored).

    Returns
    -------
    (H, W) float32 ndarray
        1 for black, 0 for white.

    Examples
    --------
    >>> darkness(np.array([[0.0, 0.25]])).tolist()
    [[1.0, 0.75]]
    """
    return (1.0 - as_gray(image)).astype(np.float32)


#: The luminance percentile taken as the picture's white (its paper).
PAPER_PERCENTILE = 99.5

#: At most this gain on a dark picture's luminance (a night picture's noise stays dark).
PAPER_MAX_GAIN = 4.0


def _to_paper_white(image) -> np.ndarray:
    """``image`` with its lightest tone (the :data:`PAPER_PERCENTILE` of the
    luminance) brought to white, gain at most :data:`PAPER_MAX_GAIN`.

    Beyond the paper, which takes ``D = 1 - L`` as it is: a pen drawing's
    lightest tone is the paper, and on a low-key picture (a dark object on a
    dark ground, a photo whose lightest part is a grey wall) ``1 - L`` left no
    room for the object: the dendrite inked the ground as densely as the
    object (a 0.12 cat on a 0.25 ground: mean ink 0.53 inside the cat, 0.51
    on the ground) and the object vanished. Scaling the luminance so the
    picture's white is paper keeps the tone ratios (a multiplicative gain, as
    an exposure change) and leaves pictures on white (gain 1) as they were.
    """
    img = np.asarray(image, dtype=np.float32)
    white = float(np.percentile(as_gray(img), PAPER_PERCENTILE))
    gain = min(1.0 / max(white, 1e-6), PAPER_MAX_GAIN)
    if gain <= 1.0:
        return img
    out = img.copy()
    colour = out[..., :3] if out.ndim == 3 else out
    np.clip(colour * gain, 0.0, 1.0, out=colour)
    return out


@checked(sigma=Real(0, 1e3), min_edge=Real(0, 1))
def gradient_strength(image, *, sigma: float = 1.0, min_edge: float = 0.05) -> np.ndarray:
    """``G``: Gaussian gradient magnitude scaled so strong edges reach 1 (see module doc).

    Parameters
    ----------
    image : array_like
        Grey or colour image in [0, 1] (converted to luminance).
    sigma : float
        Gaussian smoothing (pixels) before the gradient; 0 for plain central
        differences.
    min_edge : float
        Lower bound of the reference gradient ``g_ref`` (the 99th percentile of
        the magnitude), so a nearly flat image stays near 0.

    Returns
    -------
    (H, W) float32 ndarray
        ``G`` in [0, 1].

    Notes
    -----
    Beyond the paper, which takes the luminance's gradient: on a colour image the gradient
    is the larger of the luminance's and ``CHROMA_WEIGHT`` times that of the opponent
    channels ``(R - G) / sqrt 2``, ``(R + G - 2 B) / sqrt 6`` (:func:`_opponent`), both over
    the luminance's ``g_ref``. Where the luminance has a step the colour adds little; where
    two colours of one luminance meet (red next to blue, green next to magenta) it is the
    only edge. Measured with the defaults on isoluminant pairs (red/blue, green/magenta,
    orange/teal at luminance 0.35 and 0.6; a bold "Oak" split in two colours on cream, a
    disc split by a wavy line on white, stripes on a textured ground; 200 and 600 px): the
    share of the colour border within 2 px of ink 0.72-1.00 -> 0.97-1.00, and the ink in a
    1.5-px band along it over the ink 5 px inside the regions 0.82-1.54 (no line) -> 1.61-3.62
    (a drawn line, as a luminance edge's). Tests: ``tests/test_dendrite_colour_borders.py``.

    Examples
    --------
    >>> img = np.zeros((16, 16)); img[:, 8:] = 1.0
    >>> g = gradient_strength(img)
    >>> float(g[4, 0]), float(g[4, 8])
    (0.0, 1.0)
    """
    gray = as_gray(image).astype(np.float64)
    g = _magnitude(gray, sigma)
    # the reference is the luminance's alone: a picture without colour borders keeps its G
    ref = max(float(np.percentile(g, 99.0)), float(min_edge))
    chroma = _opponent(image)
    if chroma is not None:
        gc = np.hypot(_magnitude(chroma[0], sigma), _magnitude(chroma[1], sigma))
        g = np.maximum(g, CHROMA_WEIGHT * gc)
    return np.clip(g / ref, 0.0, 1.0).astype(np.float32)


#: Weight of the colour (opponent-channel) gradient against the luminance's in
#: :func:`gradient_strength`: a colour border counts where it is steeper than the luminance's
#: edge by ``1 / CHROMA_WEIGHT``.
CHROMA_WEIGHT = 0.5


def _magnitude(channel: np.ndarray, sigma: float) -> np.ndarray:
    if sigma > 0:
        return ndimage.gaussian_gradient_magnitude(channel, sigma)
    gy, gx = np.gradient(channel)
    return np.hypot(gx, gy)


def _opponent(image) -> np.ndarray | None:
    """The two opponent colour channels ``(R - G) / sqrt 2`` and ``(R + G - 2 B) / sqrt 6``
    of a colour image (orthogonal to grey, in the units of the luminance), or None for a grey
    one (a single channel or equal R, G, B)."""
    img = as_float_image(image).astype(np.float64)
    if img.shape[2] < 3:
        return None
    r, gr, b = img[..., 0], img[..., 1], img[..., 2]
    o1 = (r - gr) / np.sqrt(2.0)
    o2 = (r + gr - 2.0 * b) / np.sqrt(6.0)
    if not (np.ptp(o1) > 1e-6 or np.ptp(o2) > 1e-6):
        return None
    return np.stack([o1, o2])


@checked()
def importance_map(image, params: ImportanceParams | None = None) -> np.ndarray:
    """Importance ``I`` in [0, 1] of every pixel of ``image``.

    Parameters
    ----------
    image : array_like
        Grey or colour image (alpha ignored).
    params : ImportanceParams, optional
        Paper defaults if None.

    Returns
    -------
    (H, W) float32 in [0, 1]

    Raises
    ------
    ValueError
        Both weights zero, or a bad image.

    Examples
    --------
    >>> img = np.ones((32, 32)); img[:, 16:] = 0.0
    >>> imp = importance_map(img)
    >>> float(imp[5, 2]), float(imp[5, 30]), bool(imp[5, 16] > imp[5, 30])
    (0.0, 0.25, True)
    """
    p = check_params(params if params is not None else ImportanceParams())
    wi, wg = p.intensity_weight, p.gradient_weight
    if wi + wg <= 0:
        raise ValueError("params.intensity_weight and params.gradient_weight are both 0")
    d = darkness(image)
    g = gradient_strength(image, sigma=p.sigma, min_edge=p.min_edge) if wg > 0 else 0.0
    return np.clip((wi * d + wg * g) / (wi + wg), 0.0, 1.0).astype(np.float32)
