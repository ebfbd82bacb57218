"""A training layer completed by the leaf's bilateral symmetry before it is snapped (step 3 of
:mod:`branchnb.leaves.snapping`, beyond the paper).

A user traces the veins he sees on the training leaf, not always all of
them: maple 06's hand trace has its right basal vein and no left one (it
is faint on that photograph), so every exemplar induced from it lost its
left basal vein. A leaf's primary venation is bilaterally symmetric about
its midrib. :func:`mirror_missing` finds the branch whose line best
mirrors the others onto one another (the midrib), and adds the mirror
image of every branch that has no counterpart on the other side as a
*candidate* branch. A candidate is snapped like the user's branches and,
like them, dropped on an exemplar where no ridge runs along it
(:func:`~branchnb.leaves.snapping.snap_layer`'s ``min_evidence``), and kept
only where it found a vein no branch of the user's took. A midrib traced
short (maple 07's, which stops at its torn lobe) is carried on to the
blade's margin; the polar trace ends it where its ridge fades.

Measured (``python -m branchnb.leaves._measure maples``, every sample maple
as the training leaf, mean induced-vein IoU over the six others): 0.70 0.69
0.69 0.61 0.65 0.65 0.70 for maples 01-07 (before: 0.70 0.69 0.69 0.61 0.65
0.60 0.60); only 06 and 07 have a branch without counterpart or a short
midrib, the others are unchanged. Procedural families
(``_measure snapping --seeds 3``): their layers are complete, at most one
candidate in 24 leaves; min IoU per kind and size (lobed, trilobed,
elliptic at 192 / 384 px) 0.74 / 0.70, 0.66 / 0.67, 0.64 / 0.60, means
0.79-0.84, against 0.74 / 0.71, 0.66 / 0.66, 0.64 / 0.60 and the same
means before.
A maple-like star without its left basal vein
(``tests/test_leaves_mirror.py``): that vein's recall 0.00-0.07 -> 0.94-1.00.

A completion is a hypothesis: on each exemplar it may add veins, not move
the user's (:func:`adds_only`, beyond the paper). Where the template fit
with the completed layer kept less than 90 % of the user's layer placed
alone and added less than twice what it lost, the user's layer alone is
placed. Measured (issue 22): maple 06 as the training leaf 0.65 -> 0.67
(06 -> 05 0.46 -> 0.57, the five others unchanged), the other maples
unchanged (0.70 0.69 0.69 0.61 0.65 . 0.70); procedural families
(``_measure snapping --seeds 3``) min IoU per kind at 192 / 384 px: lobed
0.74 / 0.74, trilobed 0.71 / 0.74, elliptic 0.73 / 0.72.
"""

from __future__ import annotations

import numpy as np

from ..core.distance import edt as _edt
from ..core.image import as_mask
from ..core.morphology import fill_holes
from .snapping_fit import _densify, _pivot_ends

__all__ = ["adds_only", "mirror_missing"]


def _outwards(chain, pivot) -> np.ndarray:
    c = np.asarray(chain, np.float64)
    return c if np.hypot(*(c[0] - pivot)) <= np.hypot(*(c[-1] - pivot)) else c[::-1]


def _same_branch(a, b, tol: float) -> bool:
    """Two branches (each from its junction outwards) run together over the shorter one's length."""
    da, la = _densify(a)
    db, lb = _densify(b)
    n = int(min(len(da), len(db)))
    if n < 2:
        return False
    # Arc-length samples of both over the shorter length (a truncated counterpart still matches).
    k = np.linspace(0, n - 1, min(n, 32)).astype(int)
    return float(np.hypot(*(da[k] - db[k]).T).mean()) < tol


def _inside(chain, whole):
    """The part of ``chain`` from its first point inside ``whole`` up to where it leaves it (None: none)."""
    h, w = whole.shape
    ix, iy = np.round(chain[:, 0]).astype(int), np.round(chain[:, 1]).astype(int)
    ok = (ix >= 0) & (ix < w) & (iy >= 0) & (iy < h)
    inside = ok & whole[np.clip(iy, 0, h - 1), np.clip(ix, 0, w - 1)]
    if not inside.any():
        return None
    first = int(np.argmax(inside))
    after = ~inside[first:]
    stop = first + int(np.argmax(after)) if after.any() else len(chain)
    return chain[first:stop] if stop - first >= 2 else None


#: Least share of the user's layer alone (placed on an exemplar) the completed
#: layer must keep (within ``reach`` px): its candidates may add veins, not move the user's.
ADDS_ONLY = 0.9
#: ... unless it adds at least this many times the centre line it loses.
ADDS_GAIN = 2.0


def adds_only(alone, completed, reach: float, share: float | None = None, gain: float | None = None) -> bool:
    """Whether a completed layer only adds to the user's layer on an exemplar.

    The template fit poses all branches together, so a completion that
    finds no vein of its own can drag the user's branches off theirs
    (maple 06 as the training leaf: its lengthened branch moved maple 05's
    whole star, induced-vein IoU 0.57 -> 0.46). ``alone`` is the user's
    layer placed without the completion. The completed layer is kept when
    at least ``share`` (default :data:`ADDS_ONLY`, 0.9) of ``alone``'s
    centre line lies within ``reach`` px of it, or when the centre line it
    adds (farther than ``reach`` from ``alone``) is at least ``gain``
    (default :data:`ADDS_GAIN`, 2) times the length it loses: a vein found
    anew is worth a shifted branch. Measured on the sample maples (each as
    the training leaf, 18 exemplar pairs with a completion): kept share
    0.85 for 06 -> 05 (adds 53 px, loses 45 px: the user's layer alone is
    placed), 0.94-1.00 for the other 17; a star whose user layer lacks a
    basal vein (``tests/test_leaves_mirror.py``): kept share 0.74, adds
    136 px, loses 57 px (the completion is kept: vein IoU 0.72, alone 0.59).

    Parameters
    ----------
    alone, completed : (H, W) bool ndarray
        The user's layer placed alone and the completed layer, on one exemplar.
    reach : float
        Largest distance (px) of a kept centre-line pixel.
    share : float, optional
        Least share kept; default :data:`ADDS_ONLY`.
    gain : float, optional
        Least ratio of added to lost centre-line length; default :data:`ADDS_GAIN`.

    Returns
    -------
    bool
        True when ``alone`` is empty.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((20, 40), bool); a[10, 5:35] = True
    >>> more = a.copy(); more[2:18, 20] = True
    >>> adds_only(a, more, 3.0), adds_only(a, np.roll(a, 6, axis=0), 3.0)
    (True, False)
    """
    from skimage.morphology import skeletonize
    a = as_mask(alone, name="alone")
    c = as_mask(completed, shape=a.shape, name="completed")
    share = ADDS_ONLY if share is None else float(share)
    gain = ADDS_GAIN if gain is None else float(gain)
    sk = skeletonize(a)
    if not sk.any():
        return True
    if not c.any():
        return False
    lost = _edt(~c)[sk] > float(reach)
    if np.mean(~lost) >= share:
        return True
    added = _edt(~a)[skeletonize(c)] > float(reach)
    return bool(added.sum() >= gain * lost.sum())


def mirror_missing(chains, widths, blade, *, match: float = 0.1, min_inside: float = 0.6,
                   min_symmetry: float = 0.75, short: float = 0.6, primary: float = 0.3,
                   axis_to_margin: bool = True):
    """Branches of a symmetric layer with no counterpart, mirrored about its axis, as candidates.

    The axis is the line from a branch's junction through its far end
    (a branch a quarter of the longest at least) that mirrors the blade
    best onto itself (the share of blade pixels whose mirror image is
    blade); below ``min_symmetry`` the leaf is not symmetric and nothing
    is added. A mirrored branch *matches* when it runs within ``match``
    of the leaf size of a branch of the layer (itself included: a branch
    on the axis) over the shorter one's length; with no matched branch
    the layer shows no symmetry and nothing is added. Each unmatched branch's mirror
    image, cut where it leaves the training blade, is added (when at
    least ``min_inside`` of it lies inside) with the branch's width.

    Parameters
    ----------
    chains : list of (N, 2) ndarray
        The layer's main branches on the training leaf (x, y), e.g. from
        :func:`~branchnb.leaves.snapping.main_branches`.
    widths : list of float
        Their widths.
    blade : (H, W) bool ndarray
        The training leaf's blade.
    match : float
        Largest mean distance of two matching branches, as a fraction of
        the leaf size (``sqrt`` of the blade area), default 0.1.
    min_inside : float
        Shortest candidate, as a fraction of its branch's length inside
        the blade, default 0.6.
    min_symmetry : float
        Least share of the blade the axis mirrors onto the blade, default 0.75.
    short : float
        A counterpart shorter than this fraction of its branch is traced
        short: it is continued as the branch's mirror image runs (default 0.6).
    primary : float
        Only branches from the axis's junction (within 0.1 of the leaf
        size) and at least this fraction of the longest branch are
        mirrored (default 0.3): secondary veins are grown anew on every
        leaf and have no counterpart to keep.
    axis_to_margin : bool
        Carry the axis (the midrib) on straight to the blade's margin when
        it stops more than 0.1 of the leaf size before it (default True).

    Returns
    -------
    chains : list of (N, 2) float ndarray
    widths : list of float
        The input branches followed by the candidates.
    n_added : int
        How many candidates were added.

    Examples
    --------
    >>> import numpy as np
    >>> ray = lambda deg, n: np.array([50.0, 90.0]) + np.arange(n)[:, None] * [
    ...     np.cos(np.radians(deg)), np.sin(np.radians(deg))]
    >>> layer = [ray(-90, 84), ray(-45, 40), ray(-135, 40), ray(-10, 35)]   # no left basal vein
    >>> blade = np.zeros((100, 100), bool); blade[10:95, 5:96] = True
    >>> out, w, n = mirror_missing(layer, [2.0] * 4, blade)
    >>> n, np.round(out[-1][-1]).tolist()                                    # its mirror image
    (1, [17.0, 84.0])
    """
    cs = [np.asarray(c, np.float64) for c in chains]
    ws = list(widths)
    if len(cs) != len(ws):
        raise ValueError(f"widths must have one value per chain ({len(cs)}), got {len(ws)}")
    b = as_mask(blade, name="blade")
    if len(cs) < 3:
        return cs, ws, 0
    size = np.sqrt(float(b.sum()))
    tol = float(match) * size
    pe = _pivot_ends(cs)
    lengths = np.array([_densify(c)[1] if len(c) > 1 else 0.0 for c in cs])
    whole = fill_holes(b)
    h, w = b.shape
    ys, xs = np.nonzero(whole[::2, ::2])
    pts = np.column_stack([xs, ys]).astype(np.float64) * 2
    best = None
    for i, (p, f) in enumerate(pe):
        if lengths[i] < 0.25 * lengths.max() or np.hypot(*(f - p)) < 1e-6:
            continue
        u = (f - p) / np.hypot(*(f - p))
        refl = 2.0 * np.outer(u, u) - np.eye(2)
        # How well the line mirrors the blade onto itself: the leaf's axis mirrors it best.
        q = np.round((pts - p) @ refl.T + p).astype(int)
        ok = (q[:, 0] >= 0) & (q[:, 0] < w) & (q[:, 1] >= 0) & (q[:, 1] < h)
        sym = float(np.mean(ok & whole[np.clip(q[:, 1], 0, h - 1), np.clip(q[:, 0], 0, w - 1)]))
        if best is None or sym > best[0]:
            best = (sym, i, p, refl)
    if best is None or best[0] < min_symmetry:
        return cs, ws, 0
    _, i, p, refl = best
    out = [_outwards(c, pe[j][0]) for j, c in enumerate(cs)]
    mirrored = [(c - p) @ refl.T + p for c in out]
    # The layer's own pixels: a candidate mostly on them is there already
    # (a vein cut into pieces at a crossing).
    drawn = np.zeros((h, w), bool)
    for c in out:
        d, _ = _densify(c)
        drawn[np.clip(np.round(d[:, 1]).astype(int), 0, h - 1), np.clip(np.round(d[:, 0]).astype(int), 0, w - 1)] = True
    near = _edt(~drawn) <= max(3.0, 0.06 * size)

    def new(c):
        d, _ = _densify(c)
        on = near[np.clip(np.round(d[:, 1]).astype(int), 0, h - 1), np.clip(np.round(d[:, 0]).astype(int), 0, w - 1)]
        return float(on.mean()) < 0.5
    n_added = 0
    for j in range(len(out)):
        # Only the primaries of the axis's junction (a palmate leaf's star, a
        # midrib's base): secondaries are grown anew on every leaf.
        if j == i or lengths[j] < primary * lengths.max() or np.hypot(*(pe[j][0] - p)) > 0.1 * size:
            continue
        ks = [k for k in range(len(out)) if k != i and _same_branch(mirrored[j], out[k], tol)]
        if not ks:
            cut = _inside(mirrored[j], whole)
            if cut is not None and _densify(cut)[1] >= min_inside * lengths[j] and new(cut):
                cs.append(cut)
                ws.append(ws[j])
                n_added += 1
            continue
        k = max(ks, key=lambda k: lengths[k])
        if k == j or lengths[k] >= short * lengths[j]:
            continue
        # A counterpart traced short (a stub, a torn lobe's lateral): it runs
        # on as its mirror image does, from where it stops.
        dm, _ = _densify(mirrored[j])
        n_k = len(_densify(out[k])[0])
        if n_k >= len(dm):
            continue
        tail = dm[n_k:] - dm[n_k - 1] + out[k][-1]
        if len(tail) < 2 or not new(tail):
            continue
        longer = _inside(np.vstack([out[k], tail]), whole)
        if longer is not None and _densify(longer)[1] > lengths[k] + 1.0:
            cs[k] = longer
            n_added += 1
    if axis_to_margin:
        # The midrib runs on to the blade's tip: a midrib traced short is
        # carried on straight to the margin (the trace ends it where its
        # ridge fades on each exemplar).
        a = out[i]
        u = (a[-1] - a[0]) / max(np.hypot(*(a[-1] - a[0])), 1e-9)
        steps = np.arange(1.0, 2.0 * size)
        ray = a[-1] + steps[:, None] * u
        tail = _inside(np.vstack([a[-1:], ray]), whole)
        if tail is not None and _densify(tail)[1] > 0.1 * size:
            cs[i] = np.vstack([a, tail[1:]])
            n_added += 1
    return cs, ws, n_added
