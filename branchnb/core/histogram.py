"""Shared-bin histograms of several samples and distances between them.

Comparisons like "angle histogram of the input vs the synthesized
structure" only make sense on identical bins, so every function here bins
all samples together.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .validate import Int, check_range_pair, checked, real_array

__all__ = [
    "shared_bins",
    "histograms",
    "l1_distance",
    "l2_squared_distance",
    "chi_square_distance",
    "emd_1d",
    "histogram_distance",
    "HistogramComparison",
    "compare_samples",
    "METRICS",
]

#: Number of histogram bins: at least one, and few enough to allocate.
_BINS = Int(1, 100_000)


def _sample(x, name: str) -> np.ndarray:
    a = real_array(x, name, allow_empty=True, finite=False).ravel()
    if a.size == 0:
        raise ValueError(f"{name} is empty")
    if not np.all(np.isfinite(a)):
        raise ValueError(f"{name} contains NaN or infinite values")
    return a


@checked(bins=_BINS)
def shared_bins(*samples, bins: int = 16, range: tuple[float, float] | None = None) -> np.ndarray:
    """Bin edges shared by all samples: ``bins`` equal bins over their joint range.

    Parameters
    ----------
    *samples : array_like
        Samples of any shape (flattened), finite values; may be omitted when
        ``range`` is given.
    bins : int
        Number of equal bins (>= 1).
    range : (float, float), optional
        ``(low, high)`` of the bins; the joint min..max of the samples by
        default. A zero-width range is widened to ``low - 0.5 .. high + 0.5``.

    Returns
    -------
    (bins + 1,) float ndarray
        Increasing bin edges.

    Raises
    ------
    ValueError
        If a sample is empty or not finite, there is neither a sample nor a
        range, or the range is too wide for float64.

    Examples
    --------
    >>> shared_bins([0, 1], [3], bins=3).tolist()
    [0.0, 1.0, 2.0, 3.0]
    """
    if not isinstance(bins, (int, np.integer)) or bins < 1:
        raise ValueError(f"bins must be a positive int, got {bins!r}")
    if range is None:
        if not samples:
            raise ValueError("samples: give at least one sample or an explicit range")
        arrs = [_sample(s, f"samples[{i}]") for i, s in enumerate(samples)]
        lo = min(a.min() for a in arrs)
        hi = max(a.max() for a in arrs)
    else:
        lo, hi = check_range_pair(range, "range")
    with np.errstate(over="ignore"):
        span = np.float64(hi) - np.float64(lo)
    if not np.isfinite(span):
        what = "range" if range is not None else "samples"
        raise ValueError(f"{what} spans {lo:.3g} .. {hi:.3g}: the width overflows float64, so no equal bins "
                         "exist; rescale the data")
    if hi == lo:
        lo, hi = lo - 0.5, hi + 0.5
    return np.linspace(lo, hi, int(bins) + 1)


@checked(bins=_BINS)
def histograms(*samples, bins: int = 16, range: tuple[float, float] | None = None,
               weights=None) -> tuple[np.ndarray, np.ndarray]:
    """Normalised histograms of several samples on shared bins.

    Values outside ``range`` are clipped into the first/last bin, so that
    every sample sums to 1 and distances stay comparable.

    Parameters
    ----------
    *samples : array_like
        One or more 1-D samples.
    bins : int
        Number of bins (16 in the branching-synthesis paper).
    range : (float, float), optional
        Histogram range; the joint min..max of the samples by default.
    weights : sequence of array_like, optional
        Per-sample weights (one array per sample).

    Returns
    -------
    hists : (len(samples), bins) ndarray
        Each row sums to 1.
    edges : (bins + 1,) ndarray

    Examples
    --------
    >>> h, e = histograms([0, 0, 1], [1], bins=2)
    >>> h.round(3).tolist()
    [[0.667, 0.333], [0.0, 1.0]]
    """
    if not samples:
        raise ValueError("samples: histograms needs at least one sample")
    arrs = [_sample(s, f"samples[{i}]") for i, s in enumerate(samples)]
    if weights is not None:
        if isinstance(weights, (str, bytes)) or not hasattr(weights, "__len__") or len(weights) != len(arrs):
            raise TypeError(f"weights must be one array per sample ({len(arrs)}), got {type(weights).__name__}")
        weights = [real_array(w, f"weights[{i}]", allow_empty=True, min=0).ravel() for i, w in enumerate(weights)]
    edges = shared_bins(*arrs, bins=bins, range=range)
    out = np.zeros((len(arrs), len(edges) - 1))
    for i, a in enumerate(arrs):
        w = None if weights is None else weights[i]
        if w is not None and w.shape != a.shape:
            raise ValueError(f"weights[{i}] must match samples[{i}] in length")
        idx = np.clip(np.searchsorted(edges, a, side="right") - 1, 0, len(edges) - 2)
        out[i] = np.bincount(idx, weights=w, minlength=len(edges) - 1)
        total = out[i].sum()
        if total <= 0:
            raise ValueError(f"samples[{i}] has zero total weight")
        out[i] /= total
    return out, edges


def _pair(p, q) -> tuple[np.ndarray, np.ndarray]:
    p = real_array(p, "p", ndim=1, min=0)
    q = real_array(q, "q", ndim=1, min=0)
    if p.shape != q.shape:
        raise ValueError(f"histograms p and q must have equal length, got {p.shape} and {q.shape}")
    return p, q


def l1_distance(p, q) -> float:
    """L1 distance ``sum |p - q|`` (0..2 for normalised histograms).

    Parameters
    ----------
    p, q : (B,) array_like
        Two histograms on the same bins (values >= 0, equal length).

    Returns
    -------
    float

    Examples
    --------
    >>> l1_distance([1, 0], [0, 1])
    2.0
    """
    p, q = _pair(p, q)
    return float(np.abs(p - q).sum())


def l2_squared_distance(p, q) -> float:
    """Mean squared difference ``(1/B) sum (p - q)^2`` (the branching paper's measure).

    Parameters
    ----------
    p, q : (B,) array_like
        Two histograms on the same bins (values >= 0, equal length).

    Returns
    -------
    float

    Examples
    --------
    >>> l2_squared_distance([1, 0], [0, 1])
    1.0
    """
    p, q = _pair(p, q)
    return float(np.mean((p - q) ** 2))


def chi_square_distance(p, q) -> float:
    """Symmetric chi-square distance ``1/2 sum (p - q)^2 / (p + q)`` (0..1).

    Bins empty in both histograms are left out of the sum.

    Parameters
    ----------
    p, q : (B,) array_like
        Two normalised histograms on the same bins (values >= 0, equal length).

    Returns
    -------
    float

    Examples
    --------
    >>> chi_square_distance([1, 0], [0, 1])
    1.0
    """
    p, q = _pair(p, q)
    s = p + q
    nz = s > 0
    return float(0.5 * np.sum((p[nz] - q[nz]) ** 2 / s[nz]))


def emd_1d(p, q, edges=None) -> float:
    """Earth mover's distance between two 1-D histograms on the same bins.

    In 1-D it is the L1 distance between the cumulative distributions,
    times the bin width (in units of the data if ``edges`` is given, of
    bins otherwise).

    Parameters
    ----------
    p, q : (B,) array_like
        Two histograms on the same bins (values >= 0, equal length); each is
        normalised to sum 1 first (unless it is all zero).
    edges : (B + 1,) array_like, optional
        Strictly increasing bin edges; None measures in bins.

    Returns
    -------
    float
        The work to move ``p`` onto ``q``.

    Raises
    ------
    ValueError
        If the histograms differ in length, ``edges`` has the wrong length or
        does not increase, or the distance overflows.

    Examples
    --------
    >>> emd_1d([1, 0, 0], [0, 0, 1])                 # all mass moves two bins
    2.0
    >>> emd_1d([1, 0, 0], [0, 0, 1], edges=[0, 10, 20, 30])
    20.0
    """
    p, q = _pair(p, q)
    p = p / p.sum() if p.sum() > 0 else p
    q = q / q.sum() if q.sum() > 0 else q
    if edges is None:
        width = np.ones(len(p))
    else:
        edges = real_array(edges, "edges", ndim=1)
        if len(edges) != len(p) + 1:
            raise ValueError(f"edges must have one more entry than the histograms ({len(p) + 1}), got {len(edges)}")
        with np.errstate(over="ignore"):
            width = np.diff(edges)
        if not np.all(np.isfinite(width)) or np.any(width <= 0):
            raise ValueError("edges must increase strictly, with finite bin widths")
    with np.errstate(over="ignore"):
        d = float(np.sum(np.abs(np.cumsum(p - q)) * width))
    if not np.isfinite(d):
        raise ValueError("edges: bins this wide make the distance overflow float64; rescale the data")
    return d


METRICS = {
    "l1": l1_distance,
    "l2sq": l2_squared_distance,
    "chi2": chi_square_distance,
    "emd": emd_1d,
}


def histogram_distance(p, q, metric: str = "l1", edges=None) -> float:
    """Distance between two histograms by name: ``l1``, ``l2sq``, ``chi2`` or ``emd``.

    Parameters
    ----------
    p, q : (B,) array_like
        Two histograms on the same bins (values >= 0, equal length).
    metric : {"l1", "l2sq", "chi2", "emd"}
        Key of :data:`METRICS`: :func:`l1_distance`,
        :func:`l2_squared_distance`, :func:`chi_square_distance` or
        :func:`emd_1d`.
    edges : (B + 1,) array_like, optional
        Bin edges, used only by ``"emd"`` (distance in data units).

    Returns
    -------
    float

    Raises
    ------
    ValueError
        If ``metric`` is unknown.

    Examples
    --------
    >>> histogram_distance([1, 0], [0, 1], "chi2")
    1.0
    """
    if metric not in METRICS:
        raise ValueError(f"metric must be one of {sorted(METRICS)}, got {metric!r}")
    if metric == "emd":
        return emd_1d(p, q, edges)
    return METRICS[metric](p, q)


@dataclass
class HistogramComparison:
    """Histograms of several samples on shared bins, with distances to the first.

    Parameters
    ----------
    hists : (K, B) ndarray
        One normalised histogram per sample (rows sum to 1).
    edges : (B + 1,) ndarray
        The shared bin edges.
    labels : list of str
        One name per sample.
    metric : str
        Name of the distance (a key of :data:`METRICS`).
    distances : (K,) ndarray
        Distance of each histogram to ``hists[0]`` (so ``distances[0] == 0``).

    Examples
    --------
    >>> c = compare_samples([0, 0, 1], [1, 1, 1], bins=2, labels=["input", "output"])
    >>> c.labels, c.hists.round(3).tolist(), c.distances.round(3).tolist()
    (['input', 'output'], [[0.667, 0.333], [0.0, 1.0]], [0.0, 1.333])
    """

    hists: np.ndarray
    edges: np.ndarray
    labels: list
    metric: str
    distances: np.ndarray


@checked(bins=_BINS)
def compare_samples(*samples, labels=None, bins: int = 16, range=None,
                    metric: str = "l1") -> HistogramComparison:
    """Bin samples together and measure each one's distance to the first.

    Parameters
    ----------
    *samples : array_like
        Two or more samples (flattened, finite); the first is the reference.
    labels : list of str, optional
        One name per sample; ``"sample 0"``, ``"sample 1"``, ... by default.
    bins : int
        Number of shared bins.
    range : (float, float), optional
        Histogram range; the joint min..max by default (see :func:`histograms`).
    metric : {"l1", "l2sq", "chi2", "emd"}
        Distance used (see :func:`histogram_distance`).

    Returns
    -------
    HistogramComparison

    Raises
    ------
    TypeError
        If ``labels`` is not a list or tuple.
    ValueError
        If ``labels`` has the wrong length, or as :func:`histograms`.

    Examples
    --------
    >>> c = compare_samples([0, 1, 2], [0, 1, 2], bins=3)
    >>> c.distances.tolist()
    [0.0, 0.0]
    """
    if labels is not None and (isinstance(labels, (str, bytes, dict)) or not isinstance(labels, (list, tuple))):
        raise TypeError(f"labels must be a list of {len(samples)} names, got {type(labels).__name__}")
    hists, edges = histograms(*samples, bins=bins, range=range)
    if labels is None:
        labels = [f"sample {i}" for i in np.arange(len(samples))]
    labels = [str(label) for label in labels]
    if len(labels) != len(samples):
        raise ValueError(f"labels must have {len(samples)} entries, got {len(labels)}")
    dist = np.array([histogram_distance(hists[0], h, metric, edges) for h in hists])
    return HistogramComparison(hists, edges, labels, metric, dist)
