"""Global texture sampling: choose the sample correspondences by dynamic programming.

The arc-length mapping of :mod:`branchnb.strokes.fetch` gives each target
sample ``p_j`` a nominal source point ``p'_j``. Taken as is, neighbouring
patches often disagree where they overlap (the source texture is not
periodic in the stroke's arc length, and bending shears it), and the
graph cut then has no good seam. Global texture sampling lets each
sample's source point move within a small search window: candidates
``k`` shift ``p'_j`` by ``delta`` along and ``epsilon`` across the source
stroke. The candidates are chosen jointly along the stroke to minimise::

    E = sum_j  E_pair(P_j,k_j , P_j+1,k_j+1)  +  lambda * sum_j |shift_j| / W

where ``E_pair`` is the *pairwise compositing energy* of two neighbouring
patches: the graph-cut seam cost density of :mod:`branchnb.core.graphcut`,
``d(x) ** power / (G(x) + eps)`` with ``d`` the colour difference and
``G`` the edge strength of both patches, averaged over their overlap --
what any seam through the overlap costs per pixel. The second term is a
tie-breaker towards the arc-length mapping (``lambda`` small), so an
unchanged stroke reproduces its source exactly. Samples at control
points are pinned (one candidate, no shift).

The energy is a chain, so the exact minimum is found by dynamic
programming (Viterbi) in ``O(M K^2)`` for ``M`` samples and ``K``
candidates; the greedy baseline fixes one sample after the other, each
the best match for its predecessor.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..core.validate import MAX_COUNT, Array, Int, Real, checked, real_array
from .fetch import Fetched

__all__ = [
    "candidate_offsets",
    "pair_energies",
    "viterbi",
    "greedy",
    "chain_energy",
    "SamplingResult",
]

#: Regulariser of the division by the edge strength (as in branchnb.core.graphcut).
EPS = 1e-3


@checked(window=Real(0, 1e4), step=Real(0, 1e4, low_open=True), across=Real(0, 1e4))
def candidate_offsets(window: float, step: float, across: float = 0.0) -> np.ndarray:
    """Shifts ``(delta, epsilon)`` of the search window, the zero shift first.

    ``delta`` runs over ``-window .. window`` along the source stroke and
    ``epsilon`` over ``-across .. across`` across it, both every ``step``
    pixels.

    Parameters
    ----------
    window : float
        Half-length (pixels, >= 0) of the search along the source stroke.
    step : float
        Spacing of the candidates (pixels, > 0).
    across : float
        Half-width (pixels, >= 0) of the search across the stroke; 0 (along
        the stroke only) by default.

    Returns
    -------
    (K, 2) float64 ndarray
        Ordered by ``|delta| + |epsilon|``, so candidate 0 is ``(0, 0)``.

    Raises
    ------
    ValueError
        If the window holds more than ``MAX_COUNT`` candidates.

    Examples
    --------
    >>> candidate_offsets(2, 2).tolist()
    [[0.0, 0.0], [-2.0, 0.0], [2.0, 0.0]]
    """
    if (2 * window / step + 1) * (2 * across / step + 1) > MAX_COUNT:
        raise ValueError(f"window {window:g} and across {across:g} at step {step:g} give more than {MAX_COUNT} "
                         "candidate shifts: raise step")
    if step <= 0:
        raise ValueError(f"step must be > 0, got {step}")
    def axis(half):
        n = int(np.floor(half / step + 1e-9))
        return np.arange(-n, n + 1) * float(step)
    d, e = np.meshgrid(axis(window), axis(across), indexing="ij")
    off = np.column_stack([d.ravel(), e.ravel()])
    order = np.lexsort((off[:, 1], off[:, 0], np.abs(off).sum(axis=1)))
    return off[order]


def _overlap(a: Fetched, b: Fetched):
    (ax, ay), (bx, by) = a.origin, b.origin
    sa, sb = a.valid.shape[1], b.valid.shape[1]
    x0, y0 = max(ax, bx), max(ay, by)
    x1, y1 = min(ax + sa, bx + sb), min(ay + sa, by + sb)
    if x1 <= x0 or y1 <= y0:
        return None
    sl_a = (slice(None), slice(y0 - ay, y1 - ay), slice(x0 - ax, x1 - ax))
    sl_b = (slice(None), slice(y0 - by, y1 - by), slice(x0 - bx, x1 - bx))
    return sl_a, sl_b


@checked(power=Real(0, 16, low_open=True), stride=Int(1, 1000))
def pair_energies(a: Fetched, b: Fetched, *, power: float = 1.0,
                  gradient_weighted: bool = True, stride: int = 1) -> np.ndarray:
    """Pairwise compositing energy of every candidate of ``a`` with every candidate of ``b``.

    Parameters
    ----------
    a, b : Fetched
        Candidate stacks of two neighbouring samples (``Ka`` and ``Kb`` candidates).
    power : float
        Exponent on the colour difference ``d(x)``.
    gradient_weighted : bool
        Divide by the edge strength ``G(x) = |grad a(x)| + |grad b(x)|``.
    stride : int
        Evaluate every ``stride``-th pixel of the overlap in each direction (speed).

    Returns
    -------
    (Ka, Kb) ndarray
        Mean seam cost density over the pixels both patches cover; 0 for
        pairs that do not overlap.

    Examples
    --------
    >>> from branchnb.strokes.fetch import source_index, fetch
    >>> from branchnb.strokes.strokes import Stroke
    >>> img = np.zeros((30, 60, 4), np.float32); img[10:20, 5:55] = (0.6, 0.4, 0.2, 1.0)
    >>> idx = source_index(img, [Stroke([(5, 15), (54, 15)])])
    >>> a = fetch(idx, 0, [20.0], [0.0], np.array([20.0, 15.0]), 0.0, 8.0, window=4.0)
    >>> b = fetch(idx, 0, [26.0, 40.0], [0.0, 0.0], np.array([26.0, 15.0]), 0.0, 8.0, window=4.0)
    >>> e = pair_energies(a, b)
    >>> e.shape, float(e[0, 0])  # the same texture where they overlap: no seam cost
    ((1, 2), 0.0)
    """
    ov = _overlap(a, b)
    ka, kb = len(a.pixels), len(b.pixels)
    if ov is None:
        return np.zeros((ka, kb))
    sa, sb = ov
    st = (slice(None), slice(None, None, stride), slice(None, None, stride))
    va = a.valid[sa][st].reshape(ka, -1)
    vb = b.valid[sb][st].reshape(kb, -1)
    keep = va.any(axis=0) & vb.any(axis=0)
    if not keep.any():
        return np.zeros((ka, kb))
    va, vb = va[:, keep], vb[:, keep]
    pa = a.pixels[sa][st].reshape(ka, -1, 4)[:, keep]
    pb = b.pixels[sb][st].reshape(kb, -1, 4)[:, keep]
    # channel by channel into one (Ka, Kb, N) array (no (Ka, Kb, N, 4) temporaries; one
    # work array reused in place: the same values, ~30 % faster)
    d = np.zeros((ka, kb, pa.shape[1]), np.result_type(pa, pb, np.float32))
    work = np.empty_like(d)
    for c in range(pa.shape[2]):
        np.subtract(pa[:, None, :, c], pb[None, :, :, c], out=work)
        np.multiply(work, work, out=work)
        d += work
    np.sqrt(d, out=d)
    if power != 1.0:
        d = d**power
    if gradient_weighted:
        ga = a.grad[sa][st].reshape(ka, -1)[:, keep]
        gb = b.grad[sb][st].reshape(kb, -1)[:, keep]
        np.add(ga[:, None], gb[None], out=work)
        work += EPS
        d /= work
    both = va[:, None] & vb[None]
    n = both.sum(axis=2)
    d *= both  # (finite: the same as zeroing where either patch is empty)
    return np.where(n > 0, d.sum(axis=2) / np.maximum(n, 1), 0.0)


@checked()
def viterbi(unaries: list[np.ndarray], pairwise: list[np.ndarray]) -> tuple[np.ndarray, float]:
    """Exact minimum of a chain energy by dynamic programming.

    Parameters
    ----------
    unaries : list of (K_j,) arrays
        Cost of each candidate of sample ``j``.
    pairwise : list of (K_j, K_j+1) arrays
        Cost of each candidate combination of neighbours ``j``, ``j + 1``.

    Returns
    -------
    path : (M,) int ndarray
        The chosen candidate of each sample.
    energy : float
        Its total energy.

    Examples
    --------
    >>> import numpy as np
    >>> u = [np.zeros(2), np.array([0.0, 5.0]), np.zeros(2)]
    >>> p = [np.array([[0, 1], [1, 0]]), np.array([[3, 0], [0, 3]])]
    >>> path, e = viterbi(u, [np.asarray(x, float) for x in p])
    >>> path.tolist(), e
    ([0, 0, 1], 0.0)
    """
    _check_chain(unaries, pairwise)
    cost = np.asarray(unaries[0], float).copy()
    back = []
    for j, pw in enumerate(pairwise):
        tot = cost[:, None] + pw
        arg = np.argmin(tot, axis=0)
        back.append(arg)
        cost = tot[arg, np.arange(tot.shape[1])] + unaries[j + 1]
    path = np.empty(len(unaries), int)
    path[-1] = int(np.argmin(cost))
    for j in range(len(back) - 1, -1, -1):
        path[j] = back[j][path[j + 1]]
    return path, float(cost[path[-1]])


@checked()
def greedy(unaries: list[np.ndarray], pairwise: list[np.ndarray]) -> tuple[np.ndarray, float]:
    """Greedy baseline: each sample takes the best match for the one before it.

    The first sample takes its cheapest candidate; sample ``j + 1`` then
    minimises ``pairwise[j][k_j, k] + unaries[j + 1][k]``.

    Parameters
    ----------
    unaries : list of (K_j,) arrays
        Cost of each candidate of sample ``j`` (e.g. the shift prior).
    pairwise : list of (K_j, K_j+1) arrays
        ``E_pair`` of each candidate combination of neighbours ``j``, ``j + 1``.

    Returns
    -------
    path : (M,) int ndarray
        The chosen candidate of each sample.
    energy : float
        Its total chain energy (>= the :func:`viterbi` minimum).

    Examples
    --------
    >>> u = [np.zeros(2), np.array([0.0, 5.0]), np.zeros(2)]
    >>> p = [np.array([[0.0, 1.0], [1.0, 0.0]]), np.array([[3.0, 0.0], [0.0, 3.0]])]
    >>> path, e = greedy(u, p)
    >>> path.tolist(), e
    ([0, 0, 1], 0.0)
    """
    _check_chain(unaries, pairwise)
    path = np.empty(len(unaries), int)
    path[0] = int(np.argmin(unaries[0]))
    for j, pw in enumerate(pairwise):
        path[j + 1] = int(np.argmin(pw[path[j]] + unaries[j + 1]))
    return path, chain_energy(path, unaries, pairwise)


@checked(path=Array(ndim=1, dtype=np.int64, allow_empty=True))
def chain_energy(path, unaries: list[np.ndarray], pairwise: list[np.ndarray]) -> float:
    """Total energy of a choice of candidates.

    Parameters
    ----------
    path : (M,) array_like of int
        One candidate index per sample.
    unaries : list of (K_j,) arrays
        Cost of each candidate of sample ``j``.
    pairwise : list of (K_j, K_j+1) arrays
        Cost of each candidate combination of neighbours ``j``, ``j + 1``.

    Returns
    -------
    float
        ``sum_j unaries[j][path[j]] + sum_j pairwise[j][path[j], path[j + 1]]``.

    Raises
    ------
    ValueError
        If ``path`` does not pick one valid candidate per sample, or the tables
        do not form a chain.

    Examples
    --------
    >>> chain_energy(np.array([1, 0]), [np.array([0.0, 2.0]), np.zeros(1)], [np.array([[1.0], [4.0]])])
    6.0
    """
    _check_chain(unaries, pairwise)
    if len(path) != len(unaries):
        raise ValueError(f"path must choose one candidate per sample ({len(unaries)}), got {len(path)}")
    if np.any(path < 0) or np.any(path >= [len(u) for u in unaries]):
        raise ValueError("path picks a candidate index outside its sample's candidates")
    e = sum(float(u[k]) for u, k in zip(unaries, path))
    e += sum(float(pw[path[j], path[j + 1]]) for j, pw in enumerate(pairwise))
    return e


def _check_chain(unaries, pairwise):
    for name, seq, nd in (("unaries", unaries, 1), ("pairwise", pairwise, 2)):
        if isinstance(seq, (str, bytes, np.ndarray)) or not hasattr(seq, "__len__"):
            raise TypeError(f"{name} must be a list of arrays, got {type(seq).__name__}")
        for j, a in enumerate(seq):
            real_array(a, f"{name}[{j}]", ndim=nd, allow_inf=True)
    for j, pw in enumerate(pairwise):
        if j + 1 < len(unaries) and np.shape(pw) != (len(unaries[j]), len(unaries[j + 1])):
            raise ValueError(f"pairwise[{j}] must have shape ({len(unaries[j])}, {len(unaries[j + 1])}), "
                             f"got {np.shape(pw)}")
    if len(unaries) == 0 or len(pairwise) != len(unaries) - 1:
        raise ValueError(
            f"unaries and pairwise: a chain of {len(unaries)} samples needs "
            f"{max(len(unaries) - 1, 0)} pairwise tables, got {len(pairwise)}"
        )
    for j, pw in enumerate(pairwise):
        if pw.shape != (len(unaries[j]), len(unaries[j + 1])):
            raise ValueError(f"pairwise[{j}] has shape {pw.shape}, expected "
                             f"{(len(unaries[j]), len(unaries[j + 1]))}")


@dataclass
class SamplingResult:
    """Chosen candidates along one stroke.

    Parameters
    ----------
    choice : (M,) int ndarray
        Candidate index per sample.
    energy : float
        Total chain energy (pairwise + shift prior).
    pairwise : float
        The pairwise compositing energies alone, summed.
    edge_energies : (M - 1,) ndarray
        ``E_pair`` of each pair of neighbours as chosen.

    Examples
    --------
    >>> r = choose([np.zeros(2), np.zeros(2)], [np.array([[1.0, 0.0], [2.0, 3.0]])], "dp")
    >>> r.choice.tolist(), r.energy, r.edge_energies.tolist()
    ([0, 1], 0.0, [0.0])
    """

    choice: np.ndarray
    energy: float
    pairwise: float
    edge_energies: np.ndarray


def choose(unaries: list[np.ndarray], pairwise: list[np.ndarray], method: str) -> SamplingResult:
    """Pick the candidates with ``method`` in {"dp", "greedy", "none"} ("none" = zero shift).

    Parameters
    ----------
    unaries : list of (K_j,) arrays
        Cost of each candidate of sample ``j`` (the shift prior; 0 for the
        zero shift, which every sample has as candidate 0).
    pairwise : list of (K_j, K_j+1) arrays
        ``E_pair`` of neighbouring candidates (:func:`pair_energies`).
    method : {"dp", "greedy", "none"}
        "dp": the paper's global sampling, exact by :func:`viterbi`;
        "greedy": :func:`greedy`; "none": candidate 0 everywhere (the plain
        arc-length mapping).

    Returns
    -------
    SamplingResult

    Raises
    ------
    ValueError
        If ``method`` is not one of the three.

    Examples
    --------
    >>> u = [np.zeros(2), np.zeros(2)]
    >>> p = [np.array([[5.0, 1.0], [0.0, 9.0]])]
    >>> choose(u, p, "dp").energy, choose(u, p, "none").energy
    (0.0, 5.0)
    """
    if method == "dp":
        path, e = viterbi(unaries, pairwise)
    elif method == "greedy":
        path, e = greedy(unaries, pairwise)
    elif method == "none":
        path = np.zeros(len(unaries), int)  # candidate 0 is the zero shift
        e = chain_energy(path, unaries, pairwise)
    else:
        raise ValueError(f"sampling must be 'dp', 'greedy' or 'none', got {method!r}")
    edges = np.array([pw[path[j], path[j + 1]] for j, pw in enumerate(pairwise)], float)
    return SamplingResult(path, e, float(edges.sum()), edges)
