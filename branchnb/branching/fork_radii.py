"""Fork ratios: how a child's radius at its start relates to its parent's at the fork.

Measured on the example (beyond the paper, issue 23) for the growth's starts
(:mod:`branchnb.branching.branch_starts`): a delta's channel ratios
(:func:`fork_ratios`), each input child's head over its parent
(:func:`head_fork_ratios`) and whether children's radii follow their parents'
at all (:func:`fork_radius_rank`). Split from ``branch_starts``, which re-exports
these names.
"""

from __future__ import annotations

import numpy as np

__all__ = ["fork_ratios", "head_fork_ratios", "fork_radius_rank"]


#: A delta's fork ratio (:func:`fork_ratios`): a channel's radius is measured from this many of its parent's
#: radii past the fork (the extraction's junction blob widens both at the fork itself) ...
FORK_RATIO_SKIP = 2.0
#: ... over this many of them, along the child (downstream) and the parent (upstream of the fork).
FORK_RATIO_SPAN = 6.0


def fork_ratios(example) -> np.ndarray:
    """The example's forks' radius ratios: thinner branch over thicker at each child's fork (beyond the
    paper, issue 23, branching110).

    Per child of the example, the median of its radii between :data:`FORK_RATIO_SKIP` and
    ``FORK_RATIO_SKIP + FORK_RATIO_SPAN`` x its parent's fork radius ``R`` from its start, over the median of
    the parent's radii as far upstream of the fork (the fork's own radius where that stretch is empty); a ratio
    over 1 (the extraction took the thicker channel for the child) is inverted, so every ratio lies in
    (0, 1]. Measured on the head radii alone the ratios came out 0.85 (median) against 0.55 drawn on a
    bird-foot delta mask, the junction blob widening the child's first vertices.

    Parameters
    ----------
    example : Structure
        The example structure (branches with parents, parent vertices and radii).

    Returns
    -------
    (n,) float ndarray
        One ratio per child of the example that has a parent vertex (empty when none).

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> trunk = Branch(np.c_[np.arange(0, 80, 2.0), np.zeros(40)], np.full(40, 4.0))
    >>> kid = Branch(np.c_[np.full(30, 40.0), np.arange(0, 60, 2.0)], np.r_[4.0, np.full(29, 2.0)], 0, 20)
    >>> fork_ratios(Structure([trunk, kid])).tolist()
    [0.5]
    """
    out = []
    for b in example.branches:
        if b.parent is None or b.parent_vertex is None or len(b.points) < 2:
            continue
        par = example.branches[int(b.parent)]
        pp, pr = np.asarray(par.points, np.float64), np.broadcast_to(np.asarray(par.thickness, np.float64),
                                                                      (len(par.points),))
        if not len(pp):
            continue
        v = min(int(b.parent_vertex), len(pp) - 1)
        r0 = float(pr[v])
        sp = np.r_[0.0, np.cumsum(np.hypot(*np.diff(pp, axis=0).T))]
        up = (sp <= sp[v] - FORK_RATIO_SKIP * r0) & (sp >= sp[v] - (FORK_RATIO_SKIP + FORK_RATIO_SPAN) * r0)
        big = float(np.median(pr[up])) if up.any() else r0
        cp = np.asarray(b.points, np.float64)
        cr = np.broadcast_to(np.asarray(b.thickness, np.float64), (len(cp),))
        sc = np.r_[0.0, np.cumsum(np.hypot(*np.diff(cp, axis=0).T))]
        on = (sc >= FORK_RATIO_SKIP * r0) & (sc <= (FORK_RATIO_SKIP + FORK_RATIO_SPAN) * r0)
        small = float(np.median(cr[on])) if on.any() else float(np.max(cr[:2]))
        if big > 0 and small > 0 and np.isfinite(big) and np.isfinite(small):
            q = small / big
            out.append(min(q, 1.0 / q))
    return np.asarray(out, np.float64)


def _fork_radii(model) -> tuple[np.ndarray, np.ndarray]:
    """Per input branch, its parent's radius at its fork and its head's start radius (the largest of its
    first three radii, as a child's head is capped in synthesis); NaN for a root or where either is not
    positive."""
    ex = model.example
    rp, rc = np.full(len(ex.branches), np.nan), np.full(len(ex.branches), np.nan)
    for i, b in enumerate(ex.branches):
        if b.parent is None or b.parent_vertex is None or i >= len(model.bending.heads):
            continue
        pr = np.broadcast_to(np.asarray(ex.branches[int(b.parent)].thickness, np.float64),
                             (len(ex.branches[int(b.parent)].points),))
        if not len(pr):
            continue
        p = float(pr[min(int(b.parent_vertex), len(pr) - 1)])
        hd = model.bending.heads[i]
        c = max(hd["r0"], hd["r1"], *(model.first_r[i, :1] if model.first_len[i] > 0 else ()))
        if p > 0 and c > 0 and np.isfinite(p) and np.isfinite(c):
            rp[i], rc[i] = p, c
    return rp, rc


def head_fork_ratios(model) -> np.ndarray:
    """Per input branch (head), the radius its head starts at over its parent's at its fork (beyond the
    paper, issue 23, branching122; ``branch_starts.CHILD_FORK_RATIO``).

    The head's start radius is the largest of its first three radii (as a child's head is capped in
    synthesis), the parent's that at the child's parent vertex; the ratio is clipped to (0, 1] (a child
    starts no thicker than its parent). NaN for a root or a branch whose fork has no positive radius.

    Parameters
    ----------
    model : StructureModel
        A fitted model (its ``example``, ``bending.heads``, ``first_r`` and ``first_len``).

    Returns
    -------
    (B,) float ndarray
        One ratio per branch of ``model.example``.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> from branchnb.branching import fit_model
    >>> trunk = Branch(np.c_[np.full(60, 50.0), np.arange(120, 0, -2.0)], np.linspace(4, 2, 60))
    >>> kid = Branch(np.c_[np.arange(50, 110, 2.0), np.linspace(80, 40, 30)], np.linspace(2, 1, 30), 0, 20)
    >>> q = head_fork_ratios(fit_model(Structure([trunk, kid])))
    >>> bool(np.isnan(q[0])), bool(0.4 < q[1] <= 1.0)
    (True, True)
    """
    rp, rc = _fork_radii(model)
    return np.minimum(rc / rp, 1.0)


def _ranks(a: np.ndarray) -> np.ndarray:
    """Ranks of ``a`` (0-based), ties given their mean rank."""
    order = np.argsort(a, kind="stable")
    r = np.empty(len(a), np.float64)
    r[order] = np.arange(len(a), dtype=np.float64)
    _, inv = np.unique(a, return_inverse=True)
    return (np.bincount(inv, r) / np.bincount(inv))[inv]


def fork_radius_rank(model) -> float:
    """How far the example's children inherit their thickness from their parent: the rank (Spearman)
    correlation, over the example's children, between the parent's radius at the fork and the child's head
    start radius (beyond the paper, issue 23, branching123; ``branch_starts.CHILD_FORK_RANK``).

    Near 1 on a tree whose limbs are thick off a thick trunk and twigs thin off thin limbs (pipe model);
    near 0 or below where a child's width does not follow its parent's (cracks, bolts, strands of one
    width). NaN with fewer than 3 children or when either radius is constant.

    Parameters
    ----------
    model : StructureModel
        A fitted model (as for :func:`head_fork_ratios`).

    Returns
    -------
    float
        The correlation in [-1, 1], or NaN.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> from branchnb.branching import fit_model
    >>> trunk = Branch(np.c_[np.full(60, 50.0), np.arange(120, 0, -2.0)], np.linspace(6, 2, 60))
    >>> kids = [Branch(np.c_[np.arange(50, 90, 2.0), np.full(20, 120.0 - 2 * v)],
    ...                np.full(20, 0.5 * (6 - 4 * v / 59)), 0, v) for v in (10, 25, 40, 55)]
    >>> round(fork_radius_rank(fit_model(Structure([trunk] + kids))), 2)
    1.0
    """
    rp, rc = _fork_radii(model)
    ok = np.isfinite(rp) & np.isfinite(rc)
    if ok.sum() < 3:
        return float("nan")
    a, b = _ranks(rp[ok]), _ranks(rc[ok])
    a, b = a - a.mean(), b - b.mean()
    den = float(np.sqrt((a * a).sum() * (b * b).sum()))
    return float((a * b).sum() / den) if den > 0 else float("nan")
