"""Global histogram matching.

The Markov model only sees a short history, so over a long synthesis the
distributions of turning angles and thicknesses can drift from the
input's. The paper keeps 16-bin histograms of both over the input's
min..max range and favours candidates that bring the synthesized
histograms closer to the input's:

    Q* = Q * exp(wG * (dA + dR) * n_t / m),

where ``dX`` is the *improvement* of the histogram distance
``(1/B) sum_b (p_b - q_b)^2`` if the candidate's ``m`` elements were
added, ``n_t`` is the number of nodes synthesized so far (the factor
``n_t / m`` undoes the shrinking influence of ``m`` new elements on a
growing histogram) and ``wG = 50``.
"""

from __future__ import annotations

import numpy as np

from ..core.histogram import histograms, l2_squared_distance
from ..core.validate import Instance, Int, checked

__all__ = ["HistogramMatcher", "histogram_distances"]


def _bin_index(values: np.ndarray, edges: np.ndarray) -> np.ndarray:
    return np.minimum(np.maximum(np.searchsorted(edges, values, side="right") - 1, 0), len(edges) - 2)


class HistogramMatcher:
    """Input histograms plus running counts of the synthesized structure.

    Parameters
    ----------
    input_angles, input_radii : array_like
        All turning angles and thicknesses of the (resampled) input.
    bins : int
        Number of bins B (16 in the paper).
    wG : float
        Global weight (50 in the paper; 0 switches matching off).
    m : int
        Elements appended per step.

    Examples
    --------
    >>> hm = HistogramMatcher([0.0, 0.1, -0.1], [1.0, 2.0, 3.0], bins=4, wG=50, m=1)
    >>> hm.add([0.0], [2.0]); hm.n_nodes
    1
    """

    def __init__(self, input_angles, input_radii, *, bins: int = 16, wG: float = 50.0, m: int = 4):
        a = np.asarray(input_angles, np.float64).ravel()
        r = np.asarray(input_radii, np.float64).ravel()
        if a.size == 0:
            a = np.zeros(1)
        if r.size == 0:
            raise ValueError("the input has no thickness values")
        self.bins, self.wG, self.m = int(bins), float(wG), int(m)
        (pa,), self.edges_a = histograms(a, bins=self.bins)
        (pr,), self.edges_r = histograms(r, bins=self.bins)
        self.p_a, self.p_r = pa, pr
        self.counts_a = np.zeros(self.bins)
        self.counts_r = np.zeros(self.bins)
        self.n_nodes = 0

    # -- bookkeeping -------------------------------------------------------
    def bin_angles(self, a) -> np.ndarray:
        """Histogram bin of each turning angle (values outside the input's range go to the end bins).

        Parameters
        ----------
        a : array_like
            Turning angles alpha (radians).

        Returns
        -------
        int ndarray
            Bin index in ``0 .. B - 1`` of each angle, same shape as ``a``.
        """
        return _bin_index(np.asarray(a, np.float64), self.edges_a)

    def bin_radii(self, r) -> np.ndarray:
        """Histogram bin of each thickness (values outside the input's range go to the end bins).

        Parameters
        ----------
        r : array_like
            Thicknesses r (pixels).

        Returns
        -------
        int ndarray
            Bin index in ``0 .. B - 1`` of each thickness, same shape as ``r``.
        """
        return _bin_index(np.asarray(r, np.float64), self.edges_r)

    def add(self, angles=(), radii=()) -> None:
        """Count synthesized angles and vertex thicknesses (one node per radius).

        Parameters
        ----------
        angles : array_like, default ()
            Turning angles alpha (radians) of the newly synthesized elements.
        radii : array_like, default ()
            Thicknesses r (pixels) of the new vertices; each one counts as a node
            in ``n_t`` (``n_nodes``).
        """
        a = np.asarray(angles, np.float64).ravel()
        r = np.asarray(radii, np.float64).ravel()
        if a.size:
            self.counts_a += np.bincount(self.bin_angles(a), minlength=self.bins)
        if r.size:
            self.counts_r += np.bincount(self.bin_radii(r), minlength=self.bins)
            self.n_nodes += int(r.size)

    def distances(self) -> tuple[float, float]:
        """Current ``(1/B) sum (p - q)^2`` for angles and thicknesses."""
        qa = self.counts_a / max(self.counts_a.sum(), 1)
        qr = self.counts_r / max(self.counts_r.sum(), 1)
        return l2_squared_distance(self.p_a, qa), l2_squared_distance(self.p_r, qr)

    # -- the paper's factor ------------------------------------------------
    @staticmethod
    def _improvement(p, counts, cc, cc_sq=None) -> np.ndarray:
        """``d_old - d_new`` for every candidate, with ``d = (1/B) sum (q - p)^2``.

        Expanded so that the only per-step work over all candidates is a
        matrix-vector product: with ``C`` the counts, ``c`` a candidate's
        counts and ``N' = N + sum c``,
        ``B d_new = (|C|^2 + 2 C.c + |c|^2) / N'^2 - 2 p.(C + c) / N' + |p|^2``.
        """
        B = len(p)
        n = counts.sum()
        q_old = counts / n if n > 0 else np.zeros_like(counts)
        d_old = np.mean((q_old - p) ** 2)
        if cc_sq is None:
            cc_sq = np.einsum("ij,ij->i", cc, cc)
        nc = cc.sum(axis=1)
        n_new = n + nc
        safe = np.where(n_new > 0, n_new, 1.0)
        cC = cc @ counts
        cp = cc @ p
        d_new = ((counts @ counts + 2 * cC + cc_sq) / safe ** 2
                 - 2 * (p @ counts + cp) / safe + p @ p) / B
        return np.where(n_new > 0, d_old - d_new, 0.0)

    def factors(self, cand_counts_a: np.ndarray, cand_counts_r: np.ndarray,
                sq_a: np.ndarray | None = None, sq_r: np.ndarray | None = None) -> np.ndarray:
        """``exp(wG (dA + dR) n_t / m)`` for every candidate.

        Parameters
        ----------
        cand_counts_a, cand_counts_r : (J, B) ndarray
            Bin counts of each candidate's appended angles / thicknesses.
        sq_a, sq_r : (J,) ndarray, optional
            Precomputed squared norms of those rows (speed only).
        """
        J = cand_counts_a.shape[0]
        if self.wG == 0 or self.n_nodes == 0:
            return np.ones(J)
        da = self._improvement(self.p_a, self.counts_a, cand_counts_a, sq_a)
        dr = self._improvement(self.p_r, self.counts_r, cand_counts_r, sq_r)
        x = self.wG * (da + dr) * self.n_nodes / self.m
        return np.exp(np.clip(x, -50, 50))


@checked(example=Instance("Structure"), structure=Instance("Structure"), bins=Int(1, 100_000))
def histogram_distances(example, structure, *, bins: int = 16,
                        metric: str = "l2sq") -> dict[str, float]:
    """Angle and thickness histogram distances of a structure to an example.

    Bins span the example's min..max (values outside fall into the end
    bins), as in the paper's evaluation. ``metric`` is ``"l2sq"`` (the
    paper's ``(1/B) sum (p - q)^2``) or another metric of
    :func:`branchnb.core.histogram.histogram_distance` (``l1``, ``chi2``, ``emd``).

    Parameters
    ----------
    example : Structure
        The input structure; its min..max sets the bins.
    structure : Structure
        The synthesized structure to compare.
    bins : int, default 16
        Number of bins B (16 in the paper).
    metric : str, default "l2sq"
        Histogram distance: ``"l2sq"`` (the paper's), ``"l1"``, ``"chi2"`` or
        ``"emd"``.

    Returns
    -------
    dict
        ``{"angle": dA, "thickness": dR, "sum": dA + dR}``.

    Raises
    ------
    ValueError
        If the example or the structure has no turning angle (no branch of
        >= 3 vertices).

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> s = Structure([Branch([(0, 0), (4, 1), (8, 0), (12, 1)], [3.0, 2.5, 2.0, 1.5])])
    >>> histogram_distances(s, s)["sum"]
    0.0
    """
    return _distances(example.angles(), example.thicknesses(), structure.angles(), structure.thicknesses(),
                      bins, metric)


def _distances(ea, er, sa, sr, bins: int = 16, metric: str = "l2sq") -> dict[str, float]:
    """:func:`histogram_distances` of the example's and the structure's angles and thicknesses."""
    from ..core.histogram import histogram_distance

    if ea.size == 0 or sa.size == 0:
        raise ValueError("example and structure both need at least one turning angle (a branch of >= 3 vertices)")
    out = {}
    for key, x, y in (("angle", ea, sa), ("thickness", er, sr)):
        rng = (float(x.min()), float(x.max()))
        (p, q), _ = histograms(x, y, bins=bins, range=rng)
        out[key] = histogram_distance(p, q, metric)
    out["sum"] = out["angle"] + out["thickness"]
    return out
