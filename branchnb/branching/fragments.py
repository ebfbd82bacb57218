"""Fragments: disks of texture centred on the skeleton, matched by shape and colour.

Section "fragment-based synthesis" of the paper. The example image is cut
into *source fragments*: disks centred on the source skeleton with radius
``s = 3 r`` (three times the local thickness ``r``), placed along every
branch so that consecutive centres are ``lambda * (s_i + s_{i+1})`` apart
(``lambda = 0.75``), plus one fragment at every furcation. The target
skeleton is covered the same way by *target fragments*, visited root to
tip and generation by generation.

For a target fragment, every source fragment is scored by

* the shape cost ``S = sum_j ||R p_j + t - q_j||^2 + wS |mu - nu|^2`` where
  ``p``/``q`` are the ``k`` skeleton positions resampled across the source
  and target disks, ``mu``/``nu`` their thicknesses and ``(R, t)`` the
  closed-form rigid alignment of ``p`` onto ``q`` (one 2-D ICP step);
* the colour cost ``C``: the squared colour difference between the
  rigidly placed candidate and what is already synthesised under it (the
  previous target fragment), computed in
  :mod:`branchnb.branching.image_synthesis` for a shortlist of the
  candidates of lowest ``S``.

The choice is greedy: among the ``c`` candidates of lowest ``S + wC C``
one is drawn at random.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from .skeleton_map import SkeletonMap

__all__ = [
    "Fragment",
    "FragmentLibrary",
    "fragment_radius",
    "place_along_branch",
    "target_fragments",
    "source_fragments",
    "shape_vectors",
    "rigid_fit_batch",
    "shape_cost",
    "ShapeBank",
    "choose_among_best",
]


@dataclass
class Fragment:
    """One fragment: a disk on the skeleton.

    Parameters
    ----------
    kind : {"branch", "furcation"}
        A disk along one branch, or the disk at a furcation covering the
        parent around the child's start and the child's first stretch.
    branch : int
        Branch the centre lies on (the parent, for a furcation).
    arc : float
        Arc length of the centre along ``branch`` (pixels).
    center : (2,) ndarray
        Centre (x, y).
    radius : float
        Disk radius ``s`` (pixels).
    sign : int
        Direction of travel along ``branch``: +1 root to tip, -1 reversed
        (source fragments may be read backwards).
    child : int or None
        For a furcation: the child branch that starts at the centre.
    """

    kind: str
    branch: int
    arc: float
    center: np.ndarray
    radius: float
    sign: int = 1
    child: int | None = None


@dataclass
class FragmentLibrary:
    """All source fragments of one kind as parallel arrays (for vectorised scoring).

    Parameters
    ----------
    kind : {"branch", "furcation"}
        The kind of all its fragments.
    branch : (n,) int ndarray
        Branch of each centre (the parent, for a furcation).
    arc : (n,) ndarray
        Arc length of each centre along its branch (pixels).
    sign : (n,) ndarray
        Direction of travel, +1 root to tip or -1.
    child : (n,) int ndarray
        Child branch of each furcation fragment, -1 for none.
    center : (n, 2) ndarray
        Centres (x, y).
    radius : (n,) ndarray
        Disk radii ``s`` (pixels).

    Examples
    --------
    >>> import numpy as np
    >>> lib = FragmentLibrary.from_list("branch", [Fragment("branch", 0, 5.0, np.array([5.0, 0.0]), 6.0)])
    >>> len(lib), lib[0].arc, lib[0].child
    (1, 5.0, None)
    """

    kind: str
    branch: np.ndarray
    arc: np.ndarray
    sign: np.ndarray
    child: np.ndarray
    center: np.ndarray
    radius: np.ndarray

    def __len__(self) -> int:
        return len(self.branch)

    def __getitem__(self, i: int) -> Fragment:
        ch = int(self.child[i])
        return Fragment(self.kind, int(self.branch[i]), float(self.arc[i]), self.center[i].copy(),
                        float(self.radius[i]), int(self.sign[i]), ch if ch >= 0 else None)

    @classmethod
    def from_list(cls, kind: str, frags: list[Fragment]) -> FragmentLibrary:
        """Stack a list of fragments into parallel arrays.

        Parameters
        ----------
        kind : {"branch", "furcation"}
            The kind of the library.
        frags : list of Fragment
            The fragments (may be empty).

        Returns
        -------
        FragmentLibrary
            One array entry per fragment, in list order.
        """
        n = len(frags)
        return cls(
            kind,
            np.array([f.branch for f in frags], np.int64).reshape(n),
            np.array([f.arc for f in frags], float).reshape(n),
            np.array([f.sign for f in frags], float).reshape(n),
            np.array([-1 if f.child is None else f.child for f in frags], np.int64).reshape(n),
            np.array([f.center for f in frags], float).reshape(n, 2),
            np.array([f.radius for f in frags], float).reshape(n),
        )


def fragment_radius(r, scale: float = 3.0, min_radius: float = 4.0,
                    max_radius: float = 64.0) -> np.ndarray:
    """Fragment radius ``s = scale * r``, clipped to ``[min_radius, max_radius]``.

    Parameters
    ----------
    r : float or array_like
        Local thickness r (pixels).
    scale : float, default 3.0
        Paper: ``s = 3 r``.
    min_radius : float, default 4.0
        Smallest radius (pixels), for hairline branches.
    max_radius : float, default 64.0
        Largest radius (pixels).

    Returns
    -------
    ndarray
        ``s`` (pixels), shaped like ``r``.

    Examples
    --------
    >>> fragment_radius([0.5, 3.0, 40.0]).tolist()
    [4.0, 9.0, 64.0]
    """
    return np.clip(scale * np.asarray(r, float), min_radius, max_radius)


def place_along_branch(sm: SkeletonMap, branch: int, start: float, *, lam: float = 0.75,
                       scale: float = 3.0, min_radius: float = 4.0, max_radius: float = 64.0,
                       prev_radius: float | None = None, density: float = 1.0) -> np.ndarray:
    """Arc lengths of fragment centres along ``branch``.

    Consecutive centres are ``lambda * (s_i + s_{i+1}) / density`` apart,
    ``s`` being the fragment radius at each centre. The first centre is
    at ``start``, or one spacing after ``start`` if ``prev_radius`` (the
    radius of a fragment already at ``start``, e.g. a furcation) is given.
    The tip is covered: a last centre is added at the end of the branch if
    the previous disk stops short of it.

    Parameters
    ----------
    sm : SkeletonMap
        The skeleton.
    branch : int
        The branch to tile.
    start : float
        Arc length (pixels) where the tiling starts.
    lam : float, default 0.75
        ``lambda``: consecutive centres are ``lambda * (s_i + s_{i+1})``
        apart (paper: 0.75).
    scale : float, default 3.0
        Fragment radius ``s = scale * r`` (paper: 3).
    min_radius, max_radius : float, default 4.0, 64.0
        Clip of the fragment radius (pixels).
    prev_radius : float, optional
        Radius of a fragment already centred at ``start``; None = none (the
        first centre is at ``start``).
    density : float, default 1.0
        Divides the spacing (1 = the paper's tiling, 2 = twice as many
        centres).

    Returns
    -------
    ndarray
        Increasing arc lengths (pixels) of the centres.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> from branchnb.branching.skeleton_map import SkeletonMap
    >>> sm = SkeletonMap(Structure([Branch([(0, 0), (40, 0)], 2.0)]))
    >>> place_along_branch(sm, 0, 0.0).tolist()   # s = 6: centres 0.75 * 12 = 9 px apart
    [0.0, 9.0, 18.0, 27.0, 36.0, 40.0]
    """
    L = float(sm.lengths[branch])

    def rad(s):
        # fragment_radius of one arc length (scalar min/max: the same value, without array overhead)
        return float(min(max(scale * sm.thickness_at(branch, s), min_radius), max_radius))

    def step_from(s, rs):
        nxt = s + lam * (rs + rs) / density
        for _ in range(3):  # fixed point of s' = s + lam (s_i + s(s')) / density
            nxt = s + lam * (rs + rad(min(nxt, L))) / density
        return nxt

    arcs = []
    if prev_radius is None:
        s = float(start)
    else:
        s = step_from(float(start), float(prev_radius))
    while s <= L + 1e-9:
        arcs.append(s)
        s = step_from(s, rad(s))
    if L > 0:
        last = arcs[-1] if arcs else float(start)
        last_r = rad(last) if arcs else (prev_radius or rad(last))
        if L - last > 0.5 * last_r:
            arcs.append(L)
    return np.array(arcs, float)


def _branch_order(sm: SkeletonMap) -> list[int]:
    st = sm.structure
    return sorted(range(sm.n_branches), key=lambda i: (st.generation(i), i))


def target_fragments(sm: SkeletonMap, *, lam: float = 0.75, scale: float = 3.0,
                     min_radius: float = 4.0, max_radius: float = 64.0,
                     furcations: bool = True) -> list[Fragment]:
    """Target fragments in synthesis order.

    Roots first, then generation by generation; along each branch from
    its start to its tip. A child branch begins with the furcation
    fragment centred at its start on the parent (with ``furcations=False``,
    e.g. when the example has no furcation, with an ordinary fragment).

    Parameters
    ----------
    sm : SkeletonMap
        The target skeleton (the synthesized structure).
    lam : float, default 0.75
        ``lambda``: consecutive centres are ``lambda * (s_i + s_{i+1})``
        apart (paper: 0.75).
    scale : float, default 3.0
        Fragment radius ``s = scale * r`` (paper: 3).
    min_radius, max_radius : float, default 4.0, 64.0
        Clip of the fragment radius (pixels).
    furcations : bool, default True
        Start every child with a furcation fragment (False: an ordinary
        fragment at its start, e.g. when the example has no furcation).

    Returns
    -------
    list of Fragment
        In synthesis order.
    """
    out: list[Fragment] = []
    for b in _branch_order(sm):
        parent = sm.parent(b)
        prev = None
        if furcations and parent is not None and sm.lengths[b] > 0:
            s_p = sm.parent_arc(b)
            r = max(float(sm.thickness(parent, s_p)), float(sm.thickness(b, 0.0)))
            R = float(fragment_radius(r, scale, min_radius, max_radius))
            out.append(Fragment("furcation", parent, s_p, sm.position(parent, s_p), R, 1, b))
            prev = R
        arcs = place_along_branch(sm, b, 0.0, lam=lam, scale=scale, min_radius=min_radius,
                                  max_radius=max_radius, prev_radius=prev)
        radii = fragment_radius(sm.thickness(b, arcs), scale, min_radius, max_radius)
        for s, R, c in zip(arcs, radii, sm.position(b, arcs)):
            out.append(Fragment("branch", b, float(s), c.copy(), float(R)))
    return out


def source_fragments(sm: SkeletonMap, *, lam: float = 0.75, scale: float = 3.0,
                     min_radius: float = 4.0, max_radius: float = 64.0, density: float = 1.0,
                     reverse: bool = True) -> tuple[FragmentLibrary, FragmentLibrary]:
    """Source fragments: ``(branch library, furcation library)``.

    Parameters
    ----------
    sm : SkeletonMap
        The source skeleton (the example's structure).
    lam : float, default 0.75
        ``lambda``: consecutive centres are ``lambda * (s_i + s_{i+1})``
        apart (paper: 0.75).
    scale : float, default 3.0
        Fragment radius ``s = scale * r`` (paper: 3).
    min_radius, max_radius : float, default 4.0, 64.0
        Clip of the fragment radius (pixels).
    density : float, default 1.0
        Candidate centres per paper spacing ``lambda (s_i + s_{i+1})``
        (1 = the paper's tiling; more adds candidates between its centres).
    reverse : bool, default True
        Also offer every fragment read tip-to-root (``sign = -1``).

    Returns
    -------
    branch_library, furcation_library : FragmentLibrary
        Fragments along the branches (at the paper's tiling, at the
        positions a child's target tiling uses, and the denser ones), and
        one per furcation (per reading direction each).
    """
    signs = (1, -1) if reverse else (1,)
    branch, furc = [], []
    for b in range(sm.n_branches):
        if sm.lengths[b] <= 0:
            continue
        arcs = place_along_branch(sm, b, 0.0, lam=lam, scale=scale, min_radius=min_radius,
                                  max_radius=max_radius)
        parent = sm.parent(b)
        if parent is not None and sm.lengths[parent] > 0:
            # A child's target tiling starts one spacing after its furcation
            # fragment: offer the same positions.
            r_f = max(float(sm.thickness(parent, sm.parent_arc(b))), float(sm.thickness(b, 0.0)))
            after = place_along_branch(sm, b, 0.0, lam=lam, scale=scale, min_radius=min_radius,
                                       max_radius=max_radius,
                                       prev_radius=float(fragment_radius(r_f, scale, min_radius,
                                                                         max_radius)))
            arcs = np.concatenate([arcs, after[np.min(np.abs(after[:, None] - arcs[None]), axis=1) > 0.25]])
            arcs.sort()
        if density > 1:
            # The paper's tiling plus denser candidates in between.
            more = place_along_branch(sm, b, 0.0, lam=lam, scale=scale, min_radius=min_radius,
                                      max_radius=max_radius, density=density)
            arcs = np.concatenate([arcs, more[np.min(np.abs(more[:, None] - arcs[None]), axis=1) > 0.25]])
            arcs.sort()
        # (one query per branch for all its centres: the values of one query per centre)
        radii = fragment_radius(sm.thickness(b, arcs), scale, min_radius, max_radius)
        centres = sm.position(b, arcs)
        for s, R, c in zip(arcs, radii, centres):
            for sg in signs:
                branch.append(Fragment("branch", b, float(s), c.copy(), float(R), sg))
        if parent is not None and sm.lengths[parent] > 0:
            s_p = sm.parent_arc(b)
            r = max(float(sm.thickness(parent, s_p)), float(sm.thickness(b, 0.0)))
            R = float(fragment_radius(r, scale, min_radius, max_radius))
            for sg in signs:
                furc.append(Fragment("furcation", parent, s_p, sm.position(parent, s_p), R, sg, b))
    return FragmentLibrary.from_list("branch", branch), FragmentLibrary.from_list("furcation", furc)


def shape_vectors(sm: SkeletonMap, branch, arc, sign, radius: float, k: int,
                  child=None) -> tuple[np.ndarray, np.ndarray]:
    """Shape vectors of fragments: ``k`` skeleton positions and thicknesses.

    For a branch fragment the positions are taken at arc offsets
    ``linspace(-s, s, k)`` around the centre (read in direction ``sign``);
    for a furcation the ``k`` positions of the parent window are followed
    by ``k`` positions along the child at offsets ``linspace(0, s, k)``.
    Positions past a branch end are clamped to it, so tips match tips.

    Parameters
    ----------
    sm : SkeletonMap
        The skeleton the fragments lie on.
    branch, arc, sign : (N,) array_like
        Each fragment's branch, centre arc length (pixels) and direction
        of travel (+1 root to tip, -1 reversed).
    radius : float
        The *target* fragment radius ``s``: source and target vectors are
        sampled at the same offsets so that they correspond point by point.
    k : int
        Samples per shape vector (per part, for a furcation).
    child : (N,) array_like, optional
        Child branches (furcations only).

    Returns
    -------
    p : (N, k or 2k, 2) ndarray
        Skeleton positions (x, y).
    mu : (N, k or 2k) ndarray
        Thickness r at those positions (pixels).
    """
    b = np.atleast_1d(np.asarray(branch, np.int64))[:, None]
    s = np.atleast_1d(np.asarray(arc, float))[:, None]
    sg = np.atleast_1d(np.asarray(sign, float))[:, None]
    o = np.linspace(-radius, radius, k)[None, :]
    p = sm.position(b, s + sg * o)
    mu = sm.thickness(b, s + sg * o)
    if child is not None:
        c = np.atleast_1d(np.asarray(child, np.int64))[:, None]
        oc = np.linspace(0.0, radius, k)[None, :]
        p = np.concatenate([p, sm.position(c, oc + 0 * s)], axis=1)
        mu = np.concatenate([mu, sm.thickness(c, oc + 0 * s)], axis=1)
    return p, mu


def rigid_fit_batch(p: np.ndarray, q: np.ndarray):
    """Least-squares rigid alignment of many point sets onto one (2-D Kabsch, closed form).

    Parameters
    ----------
    p : (N, K, 2) ndarray
        Candidate point sets.
    q : (K, 2) ndarray
        The target point set.

    Returns
    -------
    residual : (N,) ndarray
        ``min_{R, t} sum_j ||R p_j + t - q_j||^2``.
    rotation : (N, 2, 2) ndarray
        Rotation R of each candidate.
    translation : (N, 2) ndarray
        Translation t of each candidate.

    Notes
    -----
    Same result as :func:`branchnb.core.polyline.rigid_align` for each
    candidate, for all candidates at once: with centred points,
    ``theta = atan2(sum p x q, sum p . q)`` and the residual is
    ``sum |p|^2 + sum |q|^2 - 2 sqrt(a^2 + b^2)``.
    """
    mp = p.mean(axis=1)
    mq = q.mean(axis=0)
    pc = p - mp[:, None, :]
    qc = q - mq
    a = (pc[..., 0] * qc[None, :, 0] + pc[..., 1] * qc[None, :, 1]).sum(axis=1)
    b = (pc[..., 0] * qc[None, :, 1] - pc[..., 1] * qc[None, :, 0]).sum(axis=1)
    th = np.arctan2(b, a)
    c, s = np.cos(th), np.sin(th)
    rot = np.empty(c.shape + (2, 2))   # [[c, -s], [s, c]] (no stacking: called per fragment)
    rot[:, 0, 0] = c
    rot[:, 0, 1] = -s
    rot[:, 1, 0] = s
    rot[:, 1, 1] = c
    trans = mq[None, :] - np.einsum("nij,nj->ni", rot, mp)
    res = (pc**2).sum(axis=(1, 2)) + (qc**2).sum() - 2.0 * np.hypot(a, b)
    return np.maximum(res, 0.0), rot, trans


def shape_cost(p: np.ndarray, mu: np.ndarray, q: np.ndarray, nu: np.ndarray,
               w_s: float = 2.0):
    """Shape cost ``S = sum_j ||R p_j + t - q_j||^2 + wS |mu - nu|^2`` of every candidate.

    Parameters
    ----------
    p, mu : (N, K, 2), (N, K) ndarray
        Source shape vectors (positions, thicknesses).
    q, nu : (K, 2), (K,) ndarray
        Target shape vector.
    w_s : float
        Weight ``wS`` of the thickness term (paper: 2).

    Returns
    -------
    S : (N,) ndarray
        Shape cost of each candidate.
    rotation : (N, 2, 2) ndarray
        Rotation R of its rigid alignment.
    translation : (N, 2) ndarray
        Translation t of its rigid alignment.
    """
    res, rot, trans = rigid_fit_batch(p, q)
    return res + w_s * ((mu - nu[None, :]) ** 2).sum(axis=1), rot, trans


class ShapeBank:
    """Source shape vectors prepared for scoring against many targets.

    :func:`shape_cost` for every candidate, with the parts that depend
    only on the sources (centred positions, their squared norms, the
    thickness norms) computed once: scoring one target fragment against
    thousands of sources is then two matrix-vector products.

    Parameters
    ----------
    p : (N, K, 2) ndarray
        Source positions.
    mu : (N, K) ndarray
        Source thicknesses.
    """

    def __init__(self, p: np.ndarray, mu: np.ndarray):
        self.p = p
        self.mu = mu
        self.mean = p.mean(axis=1)
        pc = p - self.mean[:, None, :]
        self.flat = pc.reshape(len(p), -1)                       # (x0, y0, x1, y1, ...)
        self.flat_perp = np.stack([-pc[..., 1], pc[..., 0]], -1).reshape(len(p), -1)
        self.norm2 = (pc**2).sum(axis=(1, 2))
        self.mu2 = (mu**2).sum(axis=1)

    def __len__(self) -> int:
        return len(self.p)

    def costs(self, q: np.ndarray, nu: np.ndarray, w_s: float = 2.0) -> np.ndarray:
        """``S`` of every source against target ``(q, nu)`` (same values as :func:`shape_cost`).

        Parameters
        ----------
        q : (K, 2) ndarray
            Target skeleton positions.
        nu : (K,) ndarray
            Target thicknesses (pixels).
        w_s : float, default 2.0
            Weight ``wS`` of the thickness term (paper: 2).

        Returns
        -------
        (N,) ndarray
            Shape cost ``S`` of every source.
        """
        qc = (q - q.mean(axis=0)).ravel()
        a = self.flat @ qc                   # sum p . q
        b = self.flat_perp @ qc              # sum p x q
        res = np.maximum(self.norm2 + qc @ qc - 2.0 * np.hypot(a, b), 0.0)
        thick = self.mu2 - 2.0 * (self.mu @ nu) + nu @ nu
        return res + w_s * np.maximum(thick, 0.0)

    def fit(self, idx, q: np.ndarray):
        """Rotations and translations aligning sources ``idx`` onto ``q``.

        Parameters
        ----------
        idx : int or array_like of int
            Indices of the sources to align.
        q : (K, 2) ndarray
            Target skeleton positions.

        Returns
        -------
        rotation : (n, 2, 2) ndarray
            Rotation R of each selected source.
        translation : (n, 2) ndarray
            Translation t of each selected source.
        """
        _, rot, trans = rigid_fit_batch(self.p[np.atleast_1d(idx)], q)
        return rot, trans


def choose_among_best(total: np.ndarray, c: int, rng: np.random.Generator) -> int:
    """Index of one of the ``c`` lowest costs, drawn uniformly (the paper's greedy choice).

    Parameters
    ----------
    total : (N,) array_like
        Cost of every candidate (``S + wC C``), lower is better.
    c : int
        How many of the best to draw from (clipped to ``[1, N]``).
    rng : numpy.random.Generator
        Random generator.

    Returns
    -------
    int
        Index into ``total``.

    Raises
    ------
    ValueError
        If ``total`` is empty.

    Examples
    --------
    >>> import numpy as np
    >>> choose_among_best([5.0, 1.0, 3.0], 1, np.random.default_rng(0))
    1
    """
    total = np.asarray(total, float)
    if total.size == 0:
        raise ValueError("no candidates to choose from")
    c = int(min(max(c, 1), total.size))
    best = np.argsort(total, kind="stable")[:c]
    return int(best[rng.integers(c)])
