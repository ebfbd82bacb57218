"""Evaluation: colour histograms of the source object region and the result.

A re-synthesized object should be made of the same colours as the part
of the source it copies: the histograms of each colour channel over the
source object region (:attr:`StrokeEditResult.source_region`) and over
the result's object mask, on shared bins, with their distance
(:func:`branchnb.core.histogram.compare_samples`).
"""

from __future__ import annotations

import numpy as np

from ..core.histogram import HistogramComparison, compare_samples
from ..core.image import as_mask, as_rgba
from ..core.validate import Instance, checked

__all__ = ["CHANNELS", "object_colours", "compare_colours"]

#: Channel names of :func:`compare_colours`.
CHANNELS = ("red", "green", "blue")


@checked()
def object_colours(image, mask) -> np.ndarray:
    """``(N, 3)`` straight RGB colours of ``image`` under ``mask`` (pixels with alpha > 0.5).

    Parameters
    ----------
    image : (H, W, C) array_like
        Grey, RGB or RGBA image in [0, 1]; RGBA colours are un-premultiplied
        straight colours.
    mask : (H, W) bool array_like
        Region to read (e.g. the source object region or the result's mask).

    Returns
    -------
    (N, 3) float64 ndarray
        One row per pixel of ``mask`` whose alpha exceeds 0.5.

    Examples
    --------
    >>> img = np.zeros((2, 2, 4)); img[0, 0] = (1, 0.5, 0, 1)
    >>> object_colours(img, np.ones((2, 2), bool)).tolist()
    [[1.0, 0.5, 0.0]]
    """
    rgba = as_rgba(image)
    m = as_mask(mask, shape=rgba.shape[:2], like="image") & (rgba[:, :, 3] > 0.5)
    return rgba[m][:, :3].astype(np.float64)


@checked(result=Instance("StrokeEditResult"))
def compare_colours(image, result, *, bins: int = 16, metric: str = "l1") -> list[HistogramComparison]:
    """Per-channel histograms of the source object region vs the result's object.

    Parameters
    ----------
    image : (H, W, C) array_like
        The source image given to :func:`~branchnb.strokes.edit_structure`.
    result : StrokeEditResult
        The edit of ``image``; its ``source_region`` and ``mask`` are compared.
    bins : int
        Number of histogram bins on [0, 1]; 16.
    metric : str
        See :func:`branchnb.core.histogram.histogram_distance`.

    Returns
    -------
    list of HistogramComparison
        One per channel of :data:`CHANNELS`, labels ``["source object",
        "result"]``, on the range [0, 1].

    Raises
    ------
    ValueError
        If ``result`` has no ``source_region`` or either region is empty.

    Examples
    --------
    >>> from branchnb.strokes import edit_structure
    >>> img = np.zeros((30, 50, 4), np.float32); img[10:20, 5:45] = (0.6, 0.4, 0.2, 1.0)
    >>> res = edit_structure(img, [[(8, 15), (42, 15)]], [[(8, 15), (42, 15)]])
    >>> cmp = compare_colours(img, res)  # an identity edit: the same colours
    >>> [c.labels for c in cmp][0], [round(float(c.distances[-1]), 3) for c in cmp]
    (['source object', 'result'], [0.0, 0.0, 0.0])
    """
    if result.source_region is None:
        raise ValueError("result has no source_region (not made by edit_structure)")
    src = object_colours(image, result.source_region)
    out = object_colours(result.layer, result.mask)
    if not len(src) or not len(out):
        raise ValueError("the source region or the result is empty: nothing to compare")
    return [compare_samples(src[:, c], out[:, c], labels=["source object", "result"], bins=bins,
                            range=(0.0, 1.0), metric=metric) for c in range(3)]
