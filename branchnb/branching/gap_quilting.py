"""Step 4 of image synthesis, the patch loop: quilting the gaps faster (issue 23).

:func:`branchnb.core.completion.complete_gaps` (shared with the leaves)
with a cheaper window search, for image synthesis only:

* the coarse search runs on a copy of the example whose long side is at
  most :data:`SEARCH_SIZE` = 128 px (core: 192), then is refined at full
  resolution around the chosen window as before;
* the coarse correlations (an 8 x 8 template at that scale) are direct
  (``cv2.filter2D``) instead of OpenCV's ``matchTemplate``, which pays a DFT
  for every call: about 2.5 times less work per window search.

The chosen windows differ (a coarser first look, float32 rounding), the
quilting does not: same cells, order, seams and colour correction (the
screened correction solved iteratively, :mod:`.gap_blend`). Region
labels (maps) are passed on to ``complete_gaps`` unchanged.
"""

from __future__ import annotations

import cv2
import numpy as np

from ..core.completion import CompletionResult, _Matcher, _quilt
from ..core.random import as_rng
from .gap_blend import compose_patch

__all__: list[str] = []

#: Long side (pixels) of the reduced example the windows are first searched on.
SEARCH_SIZE = 128


def _corr(img: np.ndarray, tpl: np.ndarray) -> np.ndarray:
    """``cv2.matchTemplate(img, tpl, TM_CCORR)`` by a direct correlation (small templates)."""
    h, w = img.shape[0] - tpl.shape[0] + 1, img.shape[1] - tpl.shape[1] + 1
    return cv2.filter2D(img, -1, tpl, anchor=(0, 0), borderType=cv2.BORDER_CONSTANT)[:h, :w]


def _ssd_direct(planes, tpl: np.ndarray, mask: np.ndarray) -> np.ndarray:
    """Masked SSD of :func:`branchnb.core.completion._masked_ssd_planes` by direct correlations."""
    t = tpl if tpl.ndim == 3 else tpl[:, :, None]
    m = np.ascontiguousarray(mask, np.float32)
    mt = m[:, :, None] * t
    const = float((mt.astype(np.float64) * t).sum())
    res = _corr(planes[-1], m)
    for c in range(t.shape[2]):
        res -= 2.0 * _corr(planes[c], np.ascontiguousarray(mt[:, :, c]))
    return np.maximum(res + np.float32(const), 0.0)


class _QuickMatcher(_Matcher):
    """:class:`branchnb.core.completion._Matcher` (``fast``) whose coarse search correlates directly."""

    def __init__(self, *args, **kwargs):
        super().__init__(*args, **kwargs)
        self._coarse_ssd = _ssd_direct
        self._coarse_corr = _corr


def quilt_gaps(canvas: np.ndarray, covered: np.ndarray, example: np.ndarray, forbidden: np.ndarray, *,
               patch_size: int, overlap: float, protect: np.ndarray | None, tolerance: float,
               forbid_weight: float, method: str, poisson: bool, anchored: bool, anchor_weight: float,
               screen: float, min_free: float, rng: np.random.Generator, progress=None,
               reuse_weight: float = 1.0, max_passes: int = 4) -> CompletionResult:
    """:func:`branchnb.core.completion.complete_gaps` (no regions, ``fast``) with :class:`_QuickMatcher`.

    The same patch loop (``core.completion._quilt``) with the quicker window
    search and the iterative colour correction of :mod:`.gap_blend`.

    ``canvas`` and ``covered`` are modified in place (all covered on return).

    Parameters
    ----------
    canvas, covered, example, forbidden
        As for ``complete_gaps``.
    patch_size, overlap, protect, tolerance, forbid_weight, method, poisson, anchored, anchor_weight, \
screen, min_free, rng, progress, reuse_weight, max_passes
        As for ``complete_gaps`` (``rng`` a Generator).

    Returns
    -------
    CompletionResult

    Examples
    --------
    >>> import numpy as np
    >>> ex = np.random.default_rng(0).random((40, 40, 3)).astype(np.float32)
    >>> canvas = np.zeros((24, 24, 3), np.float32); canvas[:, :12] = ex[:24, :12]
    >>> covered = np.zeros((24, 24), bool); covered[:, :12] = True
    >>> r = quilt_gaps(canvas, covered, ex, np.zeros((40, 40), bool), patch_size=8, overlap=0.25,
    ...                protect=None, tolerance=0.1, forbid_weight=5.0, method="graphcut", poisson=True,
    ...                anchored=True, anchor_weight=10.0, screen=0.05, min_free=0.0,
    ...                rng=np.random.default_rng(0))
    >>> bool(covered.all()), r.patch_size
    (True, 8)
    """
    return _quilt(canvas, covered, example, forbidden, patch_size=patch_size, overlap=overlap, protect=protect,
                  tolerance=tolerance, method=method, poisson=poisson, anchored=anchored,
                  anchor_weight=anchor_weight, screen=screen, min_free=min_free, rng=as_rng(rng),
                  progress=progress, max_passes=max_passes, outside=None, covered_in=None,
                  matcher=lambda size, margin: _QuickMatcher(example, forbidden, size, margin, SEARCH_SIZE,
                                                             forbid_weight, reuse_weight, True),
                  compose=compose_patch)
