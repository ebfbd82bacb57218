"""Automatic extraction (beyond the paper): lines that stand out from their ground by hue, not brightness.

The ridge filters of :mod:`.ridges` read luminance. A river seen from the
air over a patchwork of green and tan fields has about the fields'
luminance; what sets it apart is its colour (blue against green / tan),
while the fields' own luminance steps are far stronger than the river's.
:func:`colour_contrast_gray` finds the opponent-colour direction (CIE Lab
``a``/``b`` plane) in which a small share of the image stands out most
from the rest, and when that separation clearly beats the luminance's it
returns that channel as a grey image, the lines dark on a light ground,
for the usual ridge / wide-line pipeline of
:func:`~branchnb.branching.extraction.extract_structure`.
"""

from __future__ import annotations

import numpy as np

from ..core.image import as_rgb

__all__ = ["colour_contrast_gray"]

#: Robust z-score (distance to the median in MADs) beyond which a pixel stands out in a channel.
OUTLIER_Z = 3.0
#: Share of the image the standing-out pixels may cover: lines are a minority, a field colour is not.
MIN_SHARE, MAX_SHARE = 0.003, 0.25
#: Smallest Lab distance (chroma units) between the lines' and the ground's median colour.
MIN_CHROMA = 12.0
#: Largest half width of the lines (90th percentile of the distance to their edge), as a share of the
#: image's shorter side: a blob of colour (a crown, a flower) is no line network.
MAX_HALF_WIDTH = 0.02
#: Smallest centre-line length of the largest standing-out piece, as a share of the image's longer side:
#: scattered spots of colour (baubles, flowers) are no network.
MIN_NETWORK = 0.4
#: The chroma direction's separation must beat the luminance's by this factor.
GAIN = 1.5


def _separation(v: np.ndarray) -> tuple[float, float, int]:
    """``(strength, share, side)`` of the pixels of ``v`` standing out on one side of its median:
    strength = their median robust z-score (0 when their share is outside MIN_SHARE..MAX_SHARE)."""
    med = float(np.median(v))
    mad = 1.4826 * float(np.median(np.abs(v - med))) + 1e-6
    z = (v - med) / mad
    best = (0.0, 0.0, 1)
    for side in (1, -1):
        out = side * z > OUTLIER_Z
        share = float(out.mean())
        if MIN_SHARE <= share <= MAX_SHARE:
            s = float(np.median(side * z[out]))
            if s > best[0]:
                best = (s, share, side)
    return best


def colour_contrast_gray(image, *, angles: int = 12) -> np.ndarray | None:
    """A grey image in which lines that differ from their ground by hue are dark, or None.

    The image is converted to CIE Lab; for each direction ``u`` of the
    ``a``/``b`` plane (``angles`` of them over 180 degrees) and for ``L``,
    the pixels more than :data:`OUTLIER_Z` robust standard deviations
    (MAD) from the channel's median on one side are the *standing-out*
    pixels. Their share must be that of lines (:data:`MIN_SHARE` ..
    :data:`MAX_SHARE`), and the channel's strength is their median
    z-score. The best chroma direction wins when it is at least
    :data:`GAIN` times as strong as the luminance and its standing-out
    pixels are at least :data:`MIN_CHROMA` Lab units away from the
    median colour and thin (90 % of them within
    :data:`MAX_HALF_WIDTH` x the image's shorter side + 2 px of their
    edge: a network of lines, not a coloured region), and their largest
    8-connected piece has a centre line at least :data:`MIN_NETWORK` x
    the image's longer side (not scattered spots of colour).

    Parameters
    ----------
    image : (H, W, 3 or 4) array_like
        The example, float in [0, 1] or integer (grey images give None).
    angles : int, default 12
        Chroma directions examined.

    Returns
    -------
    (H, W) float32 ndarray or None
        The projection on the winning direction, mapped so the ground's
        median is 0.7 and the lines' median 0.2 (clipped to [0, 1]); None
        when luminance separates the lines as well (then extraction reads
        luminance, as the paper).

    Notes
    -----
    Beyond the paper (issue 23): the paper extracts by hand; the automatic
    path's ridge filters read luminance, which fails on near-isoluminant
    colour lines on a ground of strong luminance steps (a river over
    fields). The median / MAD statistics are over the whole image, so a
    ground of several colours (fields) widens the spread; the rule assumes
    the lines are one hue apart from all of the ground's colours.

    Examples
    --------
    >>> import numpy as np
    >>> rng = np.random.default_rng(0)
    >>> img = np.zeros((96, 96, 3), np.float32); img[:, :48] = (0.45, 0.55, 0.25); img[:, 48:] = (0.7, 0.62, 0.42)
    >>> img += rng.normal(0, 0.02, img.shape).astype(np.float32)
    >>> img[40:46] = (0.38, 0.5, 0.62)                    # a blue river of about the fields' luminance
    >>> g = colour_contrast_gray(img.clip(0, 1))
    >>> bool(g[43, 20] < 0.35 and g[20, 20] > 0.55 and g[20, 70] > 0.55)
    True
    """
    from skimage.color import rgb2lab

    if np.ndim(image) != 3:
        return None
    rgb = as_rgb(image)[..., :3].astype(np.float32)
    h, w = rgb.shape[:2]
    step = max(1, int(np.ceil(max(h, w) / 384)))
    lab = rgb2lab(np.clip(rgb, 0, 1)).astype(np.float32)
    sub = lab[::step, ::step].reshape(-1, 3)
    lum_strength = _separation(sub[:, 0])[0]
    best = None
    for th in np.linspace(0.0, np.pi, angles, endpoint=False):
        u = np.array([np.cos(th), np.sin(th)], np.float32)
        s, share, side = _separation(sub[:, 1:] @ u)
        if s > 0 and (best is None or s > best[0]):
            best = (s, side * u)
    if best is None or best[0] < GAIN * max(lum_strength, OUTLIER_Z):
        return None
    u = best[1]
    proj = sub[:, 1:] @ u
    med = float(np.median(proj))
    mad = 1.4826 * float(np.median(np.abs(proj - med))) + 1e-6
    lines = proj > med + OUTLIER_Z * mad
    line_med = float(np.median(proj[lines]))
    if line_med - med < MIN_CHROMA:
        return None
    # lines, not regions: a coloured crown or a sky standing out of a white or grey ground is no network
    # (luminance or the binary path trace those); the standing-out pixels must be thin and one long network
    from scipy import ndimage as ndi
    from skimage.morphology import skeletonize

    out = ndi.binary_opening((proj > med + OUTLIER_Z * mad).reshape(lab[::step, ::step].shape[:2]))
    if not out.any():
        return None
    half = ndi.distance_transform_edt(out)[out] * step
    if np.percentile(half, 90) > MAX_HALF_WIDTH * min(h, w) + 2.0:
        return None
    pieces, n = ndi.label(out, np.ones((3, 3), bool))
    axis_len = np.bincount(pieces[skeletonize(out)], minlength=n + 1)[1:] * step
    if axis_len.max() < MIN_NETWORK * max(h, w):
        return None
    full = lab[..., 1:] @ u
    g = 0.7 - 0.5 * (full - med) / (line_med - med)
    return np.clip(g, 0.0, 1.0).astype(np.float32)

