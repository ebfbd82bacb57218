"""Importance emphasis: the thickness of the dendrite (paper, section 6).

**Importance thickness.** Each node's radius follows a rolling average
of the importance sampled along its branch, over a window of ``window``
nodes centred on the node. Toward the root the window continues into the
parent branch (through the junction; only at the root of the whole tree
does it shrink); toward the tip it is allowed to overshoot the branch end,
where the importance counts as zero, so the last ``window / 2`` nodes of
every branch taper off and tips thin out naturally:

    r(i) = r_min + (r_max - r_min) * mean(I over the window of i)

**Branch thickness.** Without an image, the radius comes from the tree
itself: ``"subtree"`` uses the pipe model (Leonardo's rule),
``r = r_tip * n_tips ** (1 / exponent)`` with ``n_tips`` the number of
endpoints the node carries (``exponent = 2``: cross-section areas add up
at forks); ``"distance"`` thins linearly with the path length from the
root (the trunk).

**Tone.** Importance emphasis alone draws edges; the paper's figures also
keep the picture's tone: dark regions read dark. :func:`tone_thickness`
rescales the widths so the local amount of ink matches the image's local
darkness. With ``A(x)`` the ink per unit area of the current strokes
(width x length of every edge, Gaussian-blurred over ``sigma``) and ``T(x)``
the blurred darkness, lines of total area ``A`` cover about
``1 - exp(-A)`` of the paper (strokes combine by maximum coverage), so
every node's width is multiplied by ``(-ln(1 - T) / A) ** strength`` a few
times, clipped to ``[min_width, max_width]``. Both blurs run on a grid
``sigma / 4`` times coarser than the lattice (:func:`_smooth_at`; within a few
percent of the full blur, which cost most of a small image's run). ``strength = 0`` keeps the
importance emphasis, ``1`` matches the tone; in between the edges stay
thicker than their surroundings while dark regions fill in.
"""

from __future__ import annotations

import numba
import numpy as np
from scipy import ndimage

from ..core.random import as_rng
from ..core.validate import Array, Int, Real, checked
from .dendrite import Dendrite

__all__ = ["branch_thickness", "importance_thickness", "rolling_importance", "tone_thickness",
           "twigs_within_ink"]


@numba.njit(cache=True)
def _rolling(values, parent, nxt, half):
    n = values.shape[0]
    out = np.empty(n)
    for i in range(n):
        acc = values[i]
        count = 1 + half  # the tip side always counts its full half window
        # toward the root (through junctions into parent branches); the window
        # shrinks at the root itself, so the trunk base keeps its width
        j = i
        for _ in range(half):
            j = parent[j]
            if j < 0:
                break
            acc += values[j]
            count += 1
        # toward the tip; past the tip the window overshoots into zeros
        j = i
        for _ in range(half):
            j = nxt[j]
            if j < 0:
                break
            acc += values[j]
        out[i] = acc / count
    return out


@checked(importance=Array(ndim=2), window=Int(1, 10_000))
def rolling_importance(dendrite: Dendrite, importance, window: int = 15) -> np.ndarray:
    """Rolling mean of ``importance`` along the branches (see the module docstring).

    Parameters
    ----------
    dendrite : Dendrite
        The tree whose branches the window runs along (through junctions
        toward the root, past the tips into zeros).
    importance : (H, W) array_like or (M,) per-node values
        Importance map on the dendrite's lattice (sampled at the nodes), or
        one value per tree node.
    window : int
        Window length in nodes (odd; an even value is rounded up).

    Returns
    -------
    (M,) float64

    Examples
    --------
    >>> from branchnb.dendrite import plan, make_lattice, build_dendrite
    >>> d = build_dendrite(plan(make_lattice(np.zeros((1, 20)), noise=0.0), (0, 0)), [(19, 0)])
    >>> r = rolling_importance(d, np.ones((1, 20)), window=5)
    >>> float(r[0]), float(r[10]), float(r[-1])  # the root keeps its width, the tip tapers
    (1.0, 1.0, 0.6)
    """
    if not isinstance(dendrite, Dendrite):
        raise TypeError("dendrite must be a Dendrite")
    if isinstance(window, bool) or not isinstance(window, (int, np.integer)) or window < 1:
        raise ValueError(f"window must be a positive int, got {window!r}")
    imp = np.asarray(importance, dtype=np.float64)
    if imp.ndim == 2:
        if dendrite.shape is None or imp.shape != tuple(dendrite.shape):
            raise ValueError(f"importance has shape {imp.shape}, expected {dendrite.shape}")
        vals = imp.ravel()[dendrite.nodes]
    elif imp.shape == (dendrite.n_nodes,):
        vals = imp
    else:
        raise ValueError("importance must be an (H, W) map or one value per tree node")
    if not np.all(np.isfinite(vals)):
        raise ValueError("importance contains NaN or infinite values")
    # sums of values near the float64 limit overflow: average them in units of the largest
    scale = float(np.max(np.abs(vals))) if vals.size else 1.0
    scale = scale if scale > 1e150 else 1.0
    return _rolling(vals / scale, dendrite.parent, dendrite.next_in_branch(), int(window) // 2) * scale


@checked(importance=Array(ndim=2), window=Int(1, 10_000), min_width=Real(0, 1e4), max_width=Real(0, 1e4),
         contrast=Real(0, 1e3), reference=Real(0, low_open=True))
def importance_thickness(dendrite: Dendrite, importance, *, window: int = 15,
                         min_width: float = 0.4, max_width: float = 4.0,
                         contrast: float = 1.0, reference: float | None = None) -> Dendrite:
    """Radius from the rolling importance ``A`` (see the module docstring):

        width = w_min + (w_max - w_min) * clip(A / reference, 0, 1) ** contrast

    Parameters
    ----------
    dendrite : Dendrite
        The tree to thicken; not modified.
    importance : (H, W) array_like or (M,) per-node values
        Importance on the dendrite's lattice (sampled at the nodes) or one
        value per node, see :func:`rolling_importance`.
    window : int
        Rolling-average window (nodes); 15 by default. The last
        ``window / 2`` nodes of each branch taper toward the tip.
    min_width, max_width : float
        Stroke widths (pixels) for ``A = 0`` and ``A >= reference``.
    contrast : float
        Exponent on the normalised importance (> 1 thins the unimportant
        strokes further).
    reference : float, optional
        The importance that gets the full width: 1 by default (importance in
        [0, 1]). :class:`~branchnb.dendrite.stylization.Stylizer` passes the
        image's 99th percentile so strong features always reach ``max_width``.
        A constant importance gives a constant width, except the tapering tips.

    Returns
    -------
    Dendrite
        A copy with the new radius (half the width).

    Examples
    --------
    >>> from branchnb.dendrite import plan, make_lattice, build_dendrite
    >>> res = plan(make_lattice(np.zeros((40, 40)), rng=0), (20, 39))
    >>> d = importance_thickness(build_dendrite(res, [(3, 3)]), np.ones((40, 40)))
    >>> bool(d.radius[d.tips[0]] < d.radius[len(d.radius) // 2])
    True
    """
    _check_widths(min_width, max_width)
    if not np.isfinite(contrast) or contrast <= 0:
        raise ValueError(f"contrast must be > 0, got {contrast}")
    ref = 1.0 if reference is None else float(reference)
    if not np.isfinite(ref) or ref <= 0:
        raise ValueError(f"reference must be > 0, got {reference}")
    avg = np.clip(rolling_importance(dendrite, importance, window) / ref, 0.0, 1.0)
    return dendrite.with_radius(0.5 * (min_width + (max_width - min_width) * avg ** contrast))


def tone_thickness(dendrite: Dendrite, darkness, *, sigma: float = 8.0, min_width: float = 0.2,
                   max_width: float = 4.0, strength: float = 1.0, black: float = 0.7,
                   iterations: int = 4) -> Dendrite:
    """Rescale the widths so the local ink follows ``darkness`` (see the module docstring).

    Parameters
    ----------
    dendrite : Dendrite
        With its current widths (e.g. from :func:`importance_thickness`).
    darkness : (H, W) array_like
        Target tone in [0, 1] on the dendrite's lattice (1 = black).
    sigma : float
        Blur (pixels) over which ink and darkness are compared; larger
        than the spacing of the branches.
    min_width, max_width : float
        Clip range of the widths (pixels).
    strength : float
        Exponent on the correction (0 = no change, 1 = match the tone).
    black : float
        Ink coverage that stands for black: the target coverage is
        ``black * darkness`` (pen and ink leaves paper between strokes, and a
        linear tone scale keeps dark regions apart from black ones).
    iterations : int
        Correction passes (clipping makes one pass inexact).

    Returns
    -------
    Dendrite
        A copy with the new radius.

    Examples
    --------
    >>> from branchnb.dendrite import plan, make_lattice, build_dendrite, random_endpoints
    >>> res = plan(make_lattice(np.zeros((60, 60)), rng=0), (30, 30))
    >>> d = build_dendrite(res, random_endpoints(np.ones((60, 60), bool), 80, rng=0))
    >>> dark = np.zeros((60, 60)); dark[:, :30] = 0.8
    >>> t = tone_thickness(d.with_radius(np.full(d.n_nodes, 0.5)), dark, sigma=4)
    >>> left = t.points[:, 0] < 25
    >>> bool(t.radius[left].mean() > 3 * t.radius[t.points[:, 0] > 35].mean())
    True
    """
    if not isinstance(dendrite, Dendrite):
        raise TypeError("dendrite must be a Dendrite")
    if dendrite.shape is None:
        raise ValueError("tone_thickness needs a dendrite on an image lattice")
    _check_widths(min_width, max_width)
    dark = np.asarray(darkness, dtype=np.float64)
    if dark.shape != tuple(dendrite.shape):
        raise ValueError(f"darkness has shape {dark.shape}, expected {tuple(dendrite.shape)}")
    if not np.all(np.isfinite(dark)):
        raise ValueError("darkness contains NaN or infinite values")
    if not np.isfinite(sigma) or sigma <= 0:
        raise ValueError(f"sigma must be > 0, got {sigma}")
    if not np.isfinite(strength) or strength < 0:
        raise ValueError(f"strength must be >= 0, got {strength}")
    if not np.isfinite(black) or not 0 < black <= 1:
        raise ValueError(f"black must be in (0, 1], got {black}")
    return _tone_fit(dendrite, dark, sigma, min_width, max_width, strength, black, iterations)


def _tone_fit(dendrite: Dendrite, dark: np.ndarray, sigma: float, min_width: float,
              max_width: float, strength: float, black: float, iterations: int,
              target_sigma: float | None = None, keep=None) -> Dendrite:
    """:func:`tone_thickness` on checked arguments; the darkness may be blurred by its own
    ``target_sigma`` (the ink by ``sigma``).

    Beyond the paper: a small input's branches are spaced wider, so its ink is compared
    over a wider blur (:func:`~branchnb.dendrite.stylize_params._spacing_growth`); its
    target blurred as wide lost the detail the 512-px picture's keeps, a drawn outline's
    darkness spread over the fill: a light fill in a dark outline at 250 px had an outline
    band 1.75x as inked as its interior against 2.2x at 750 px. Blurred by the 512-px
    picture's ``target_sigma``, the target keeps the outline's share and the wider ink
    blur matches it on average; ``keep`` (per node, in [0, 1]) says how much of that
    sharper target a node takes (a step between regions keeps the wide blur's).
    """
    width = 2.0 * dendrite.radius
    if strength == 0 or dendrite.n_nodes == 0:
        return dendrite.with_radius(0.5 * np.clip(width, min_width, max_width))
    h, w = dendrite.shape
    has = dendrite.parent >= 0
    seg = np.zeros(dendrite.n_nodes)
    step = dendrite.points[has] - dendrite.points[dendrite.parent[has]]
    seg[has] = np.hypot(step[:, 0], step[:, 1])
    target = _smooth_at(np.clip(dark, 0.0, 1.0), dendrite.nodes, sigma)
    if target_sigma is not None:
        sharp = _smooth_at(np.clip(dark, 0.0, 1.0), dendrite.nodes, target_sigma)
        target = target + (1.0 if keep is None else keep) * (sharp - target)
    # ink area needed for coverage black * T with randomly overlapping strokes
    need = -np.log1p(-np.clip(black * target, 0.0, 0.95))
    tiny = 1e-4
    for _ in range(int(iterations)):
        have = _ink_blur_at(dendrite.nodes, width * seg, (h, w), sigma)
        width = np.clip(width * ((need + tiny) / (have + tiny)) ** strength, min_width, max_width)
    return dendrite.with_radius(0.5 * width)


@checked(min_width=Real(0, 1e4), max_width=Real(0, 1e4), exponent=Real(0, 100, low_open=True))
def branch_thickness(dendrite: Dendrite, *, mode: str = "subtree", min_width: float = 0.6,
                     max_width: float | None = 8.0, exponent: float = 2.0) -> Dendrite:
    """Radius from the tree structure alone.

    Parameters
    ----------
    dendrite : Dendrite
        The tree to thicken; not modified.
    mode : {"subtree", "share", "distance"}
        ``"subtree"``: pipe model ``width = min_width * n_tips ** (1 / exponent)``,
        clipped at ``max_width``. ``"share"``: the share of all tips a node
        carries, ``width = min_width + (max_width - min_width) * ((n_tips - 1) /
        (N - 1)) ** (1 / exponent)`` with ``N`` the root's tips, so only the
        channel that carries everything (a lightning bolt's main channel) is
        ``max_width`` wide (the pipe model clipped at ``max_width`` made every
        channel with more than ``(max_width / min_width) ** exponent`` tips as
        wide as the root). ``"distance"``: linear from ``max_width``
        at the root to ``min_width`` at the farthest tip.
    min_width : float
        Width (pixels) of a tip (``"subtree"``) or of the farthest tip
        (``"distance"``); 0.6 by default.
    max_width : float or None
        Largest width (pixels); 8 by default. None leaves the pipe model
        unclipped (``"share"`` and ``"distance"`` need a value).
    exponent : float
        Pipe-model exponent (2: da Vinci's rule; ~2.5-3 for Murray's law).

    Returns
    -------
    Dendrite
        A copy with the new radius.

    Raises
    ------
    ValueError
        An unknown ``mode``, ``max_width < min_width``, or ``"distance"``
        without ``max_width``.

    Examples
    --------
    >>> from branchnb.dendrite import plan, make_lattice, build_dendrite
    >>> res = plan(make_lattice(np.zeros((30, 30)), rng=0), (15, 29))
    >>> d = branch_thickness(build_dendrite(res, [(2, 2), (27, 2), (15, 3), (5, 20)]))
    >>> float(d.radius[d.tips].min()), bool(d.radius[0] > d.radius[d.tips].max())
    (0.3, True)
    """
    _check_widths(min_width, max_width if max_width is not None else min_width)
    if mode == "subtree":
        if not np.isfinite(exponent) or exponent <= 0:
            raise ValueError(f"exponent must be > 0, got {exponent}")
        w = min_width * np.maximum(dendrite.leaf_count(), 1.0) ** (1.0 / exponent)
        if max_width is not None:
            w = np.minimum(w, max_width)
    elif mode == "share":
        if max_width is None:
            raise ValueError("mode='share' needs max_width")
        if not np.isfinite(exponent) or exponent <= 0:
            raise ValueError(f"exponent must be > 0, got {exponent}")
        n = np.maximum(dendrite.leaf_count(), 1.0)
        top = float(n.max()) if n.size else 1.0
        w = min_width + (max_width - min_width) * ((n - 1.0) / max(top - 1.0, 1.0)) ** (1.0 / exponent)
    elif mode == "distance":
        if max_width is None:
            raise ValueError("mode='distance' needs max_width")
        d = dendrite.arc_depth()
        t = d / d.max() if d.size and d.max() > 0 else np.zeros_like(d)
        w = max_width + (min_width - max_width) * t
    else:
        raise ValueError(f"mode must be 'subtree', 'share' or 'distance', got {mode!r}")
    return dendrite.with_radius(0.5 * w)


def _reflected(n: int, r: int) -> np.ndarray:
    """Indices of positions ``-r .. n - 1 + r`` of a line of ``n`` values in scipy's "reflect" mode."""
    p = np.arange(-r, n + r) % (2 * n)
    return np.where(p < n, p, 2 * n - 1 - p)


@numba.njit(cache=True)
def _first_pass_sparse(img, urows, wts, where):
    """scipy's blur along axis 0 of a mostly empty ``img``, at rows ``urows`` only.

    scipy starts each output at ``x[i] * w[0]`` and adds ``(x[i - d] + x[i + d]) * w[d]``
    for ``d = r .. 1``; adding a pair of zeros changes no bit, so only the pairs
    holding ink are added, in that order. ``where`` maps the extended line's
    positions ``-r .. h - 1 + r`` to rows (:func:`_reflected`). The ink is gathered
    column by column from a row-major scan (a column-wise scan read a cache line per
    pixel), and the window's bounds only move forward as the row grows.
    """
    h, w = img.shape
    r = wts.size - 1
    L = where.size
    # ink of the extended lines, column by column (CSR over columns, q order), from a
    # row-major scan (the column-wise scan read a cache line per pixel)
    cnt = np.zeros(w + 1, np.int64)
    for q in range(L):
        row = where[q]
        for c in range(w):
            if img[row, c] != 0.0:
                cnt[c + 1] += 1
    for c in range(w):
        cnt[c + 1] += cnt[c]
    fill = cnt[:w].copy()
    allpos = np.empty(cnt[w], np.int64)
    allval = np.empty(cnt[w])
    for q in range(L):
        row = where[q]
        for c in range(w):
            v = img[row, c]
            if v != 0.0:
                j = fill[c]
                allpos[j] = q - r
                allval[j] = v
                fill[c] = j + 1
    first = np.zeros((urows.size, w))
    for c in range(w):
        base = cnt[c]
        m = cnt[c + 1] - base
        if m == 0:
            continue
        pos = allpos[base:base + m]
        val = allval[base:base + m]
        lo = 0
        mid = 0
        hi = 0
        for k in range(urows.size):
            i = urows[k]
            while lo < m and pos[lo] < i - r:
                lo += 1
            if mid < lo:
                mid = lo
            while mid < m and pos[mid] < i:
                mid += 1
            if hi < mid:
                hi = mid
            while hi < m and pos[hi] <= i + r:
                hi += 1
            acc = img[i, c] * wts[0]
            a, b = lo, hi - 1
            # skip the node's own row in the right half
            while a < mid or (b >= mid and pos[b] > i):
                dl = i - pos[a] if a < mid else -1
                dr = pos[b] - i if b >= mid and pos[b] > i else -1
                if dl == dr:
                    acc += (val[a] + val[b]) * wts[dl]
                    a += 1
                    b -= 1
                elif dl > dr:
                    acc += val[a] * wts[dl]
                    a += 1
                else:
                    acc += val[b] * wts[dr]
                    b -= 1
            first[k, c] = acc
    return first


@numba.njit(cache=True)
def _second_pass_at(ext, k_of, cols, wts):
    """scipy's blur along axis 1 at ``(k_of[n], cols[n])`` of rows extended by ``r`` each side."""
    r = wts.size - 1
    out = np.empty(cols.size)
    for n in range(cols.size):
        k, c = k_of[n], cols[n] + r
        acc = ext[k, c] * wts[0]
        for d in range(r, 0, -1):
            acc += (ext[k, c - d] + ext[k, c + d]) * wts[d]
        out[n] = acc
    return out


#: :func:`_blur_at` adds only the ink of a map below this density x share of rows read.
_SPARSE_BELOW = 0.06


def _blur_at(image, nodes, sigma: float) -> np.ndarray:
    """``ndimage.gaussian_filter(image, sigma).ravel()[nodes]``, bit for bit, computed on less.

    The same kernel and the same sums in the same order as scipy's separable
    filter (axis 0, then axis 1), but only what the nodes read: the first pass
    at the rows holding a node (adding only the ink of a sparse map), the
    second at the nodes. About a tenth of the work on an ink map.
    """
    img = np.ascontiguousarray(image, dtype=np.float64)
    nodes = np.asarray(nodes, np.int64)
    if nodes.size == 0:
        return np.zeros(0)
    h, w = img.shape
    r = int(4.0 * float(sigma) + 0.5)  # gaussian_filter's radius (truncate = 4)
    impulse = np.zeros(2 * r + 1)
    impulse[r] = 1.0
    wts = ndimage.gaussian_filter1d(impulse, float(sigma))[r:]  # scipy's own w[0], ..., w[r]
    rows, cols = np.divmod(nodes, w)
    urows, k_of = np.unique(rows, return_inverse=True)
    # scipy's own first pass unless the map is sparse over the rows read: the sparse
    # pass's branchy loop costs ~8x scipy's per term, and the stylization's ink maps (9 %
    # of the pixels, a node in every row, sigma 14 px) took 1.5x scipy's time with it
    if np.count_nonzero(img) / img.size * urows.size / h > _SPARSE_BELOW:
        first = ndimage.gaussian_filter1d(img, float(sigma), axis=0)[urows]
    else:
        first = _first_pass_sparse(img, urows, wts, _reflected(h, r))
    # take() keeps the rows contiguous (first[:, idx] came out column-major and
    # np.ascontiguousarray then copied it again, a tenth of this function's time)
    ext = first.take(_reflected(w, r), axis=1)
    return _second_pass_at(np.ascontiguousarray(ext), k_of.astype(np.int64), cols, wts)


#: :func:`_smooth_at` blurs on a grid this many times coarser than ``sigma / _COARSE``.
_COARSE = 4.0


def _smooth_at(image, nodes, sigma: float) -> np.ndarray:
    """``ndimage.gaussian_filter(image, sigma).ravel()[nodes]`` within about 1 % of the
    blur's range, on a grid ``f = sigma // _COARSE`` times coarser (exact below ``f = 2``).

    The ink maps of the tone match and of the twig pruning are blurred over the branch
    spacing, 8-15 lattice px, several times per run (28 times on a small image, which
    then took 1.3-1.7x the CPU of a 750-px one). Block means of ``f x f`` pixels, blurred
    by ``sigma / f`` less the blocks' and the bilinear read-back's own spread, and read
    back bilinearly at the nodes cost a few percent of the full blur.
    """
    f = int(float(sigma) // _COARSE)
    if f < 2:
        return _blur_at(image, nodes, sigma)
    img = np.asarray(image, dtype=np.float64)
    nodes = np.asarray(nodes, np.int64)
    if nodes.size == 0:
        return np.zeros(0)
    h, w = img.shape
    # scipy's "reflect" border, wide enough that the coarse blur's own never shows
    m = f * int(np.ceil(4.0 * float(sigma) / f))
    big = np.pad(img, ((m, m + -h % f), (m, m + -w % f)), mode="symmetric")
    coarse = big.reshape(big.shape[0] // f, f, big.shape[1] // f, f).mean(axis=(1, 3))
    # a block mean spreads by (f^2 - 1) / 12, the bilinear read-back by f^2 / 6 (px^2)
    s = np.sqrt(max(float(sigma) ** 2 - (f * f - 1) / 12.0 - f * f / 6.0, 0.25)) / f
    coarse = ndimage.gaussian_filter(coarse, s, mode="reflect")
    rows, cols = np.divmod(nodes, w)
    at = (np.stack([rows, cols]).astype(np.float64) + m - 0.5 * (f - 1)) / f
    return ndimage.map_coordinates(coarse, at, order=1, mode="nearest")


def _ink_blur_at(nodes, area, shape, sigma: float) -> np.ndarray:
    """:func:`_smooth_at` of the map holding ``area`` at ``nodes`` (summed), without the map.

    The ink goes straight into the coarse grid, with its mirror images across the borders
    (scipy's "reflect") within the blur's reach, so a sparse ink map costs its nodes, not
    its pixels (a small image's pruning rounds blur one 43 times).
    """
    f = int(float(sigma) // _COARSE)
    nodes = np.asarray(nodes, np.int64)
    h, w = int(shape[0]), int(shape[1])
    if f < 2 or nodes.size == 0:
        ink = np.bincount(nodes, weights=area, minlength=h * w).reshape(h, w)
        return _smooth_at(ink, nodes, sigma)
    m = f * int(np.ceil(4.0 * float(sigma) / f))
    rows, cols = np.divmod(nodes, w)
    a = np.asarray(area, np.float64)
    # each node and its reflections across the four borders, kept where the blur reaches
    rr = np.stack([rows, -1 - rows, 2 * h - 1 - rows])
    cc = np.stack([cols, -1 - cols, 2 * w - 1 - cols])
    H, W = -(-(h + 2 * m) // f), -(-(w + 2 * m) // f)
    grid = np.zeros(H * W)
    for i in range(3):
        ok_r = (rr[i] >= -m) & (rr[i] < h + m)
        for j in range(3):
            ok = ok_r & (cc[j] >= -m) & (cc[j] < w + m)
            if ok.any():
                k = ((rr[i][ok] + m) // f) * W + (cc[j][ok] + m) // f
                grid += np.bincount(k, weights=a[ok], minlength=H * W)
    coarse = grid.reshape(H, W) / (f * f)
    s = np.sqrt(max(float(sigma) ** 2 - (f * f - 1) / 12.0 - f * f / 6.0, 0.25)) / f
    coarse = ndimage.gaussian_filter(coarse, s, mode="constant")
    at = (np.stack([rows, cols]).astype(np.float64) + m - 0.5 * (f - 1)) / f
    return ndimage.map_coordinates(coarse, at, order=1, mode="nearest")


def _ink_map(dendrite: Dendrite, width, sigma: float, select=None) -> np.ndarray:
    """Stroke area (width x length of every edge) blurred over ``sigma``, at each node."""
    h, w = dendrite.shape
    has = dendrite.parent >= 0
    seg = np.zeros(dendrite.n_nodes)
    step = dendrite.points[has] - dendrite.points[dendrite.parent[has]]
    seg[has] = np.hypot(step[:, 0], step[:, 1])
    area = np.asarray(width, float) * seg
    if select is not None:
        area = np.where(select, area, 0.0)
    return _ink_blur_at(dendrite.nodes, area, (h, w), sigma)


@checked(reference_radius=Array(ndim=1, min=0), sigma=Real(0, 1e4, low_open=True))
def twigs_within_ink(dendrite: Dendrite, reference_radius, *, sigma: float = 8.0,
                     rng=None) -> np.ndarray:
    """Which tips to keep so the strokes carry no more ink than a reference drawing.

    Beyond the paper. A width floor (no stroke thinner than a pixel of a small
    output) makes every stroke carry at least that much ink, so where many thin
    twigs share a light region (the few pixels of a thin outline, a pale fill)
    the drawing gets darker than the same object drawn larger. Where the ink of
    ``dendrite`` (width x length, blurred over ``sigma``) exceeds that of the
    same tree drawn with ``reference_radius`` by a share ``x``, each terminal
    twig (a branch with no side branch) is dropped with probability ``x / t``,
    ``t`` the share of the local ink such twigs carry, so on average the ink left
    matches the reference; twigs elsewhere are kept, and so are lines of the
    picture: twigs longer than ``2 sigma`` with less than a quarter of the ink
    within ``sigma / 4`` from other strokes (a leaf's stem, a lone line of a
    drawing). Called again on the pruned tree, it thins a band of parallel
    strokes (a thin outline traced by several branches) down to one.

    Parameters
    ----------
    dendrite : Dendrite
        With its drawn widths (``radius``) and a lattice ``shape``.
    reference_radius : (M,) array_like
        The radius each node would have without the floor.
    sigma : float
        Blur (lattice px) over which the inks are compared; 8.
    rng : {numpy.random.Generator, int}, optional
        Which twigs go.

    Returns
    -------
    (E,) bool ndarray
        True for each of ``dendrite.tips`` to keep.

    Examples
    --------
    >>> from branchnb.dendrite import plan, make_lattice, build_dendrite, random_endpoints
    >>> res = plan(make_lattice(np.zeros((60, 60)), rng=0), (30, 30))
    >>> d = build_dendrite(res, random_endpoints(np.ones((60, 60), bool), 80, rng=0))
    >>> d = d.with_radius(np.full(d.n_nodes, 1.0))
    >>> bool(twigs_within_ink(d, np.full(d.n_nodes, 1.0), rng=0).all())
    True
    >>> bool(twigs_within_ink(d, np.full(d.n_nodes, 0.5), rng=0).mean() < 0.8)
    True
    """
    if not isinstance(dendrite, Dendrite):
        raise TypeError("dendrite must be a Dendrite")
    if dendrite.shape is None:
        raise ValueError("twigs_within_ink needs a dendrite on an image lattice")
    ref = np.asarray(reference_radius, float)
    if ref.shape != (dendrite.n_nodes,):
        raise ValueError(f"reference_radius must have one value per node ({dendrite.n_nodes}), "
                         f"got shape {ref.shape}")
    rng = as_rng(rng)
    keep = np.ones(len(dendrite.tips), bool)
    if dendrite.n_nodes == 0 or len(dendrite.tips) == 0:
        return keep
    n_children = np.bincount(dendrite.branch_parent[dendrite.branch_parent >= 0],
                             minlength=dendrite.n_branches)
    terminal = np.flatnonzero((n_children == 0) & (dendrite.branch_parent >= 0))
    own = np.full(dendrite.n_nodes, -1, np.int64)
    for b in terminal:
        own[dendrite.branches[b][1:]] = b
    width = 2.0 * dendrite.radius
    # a long twig with no other stroke alongside is a line of the picture (a leaf's
    # stem), not texture: kept
    near = _ink_map(dendrite, width, sigma / 4.0)
    others = np.clip(1.0 - _ink_map(dendrite, width, sigma / 4.0, own >= 0) / (near + 1e-9), 0, 1)
    for b in terminal:
        nodes = dendrite.branches[b]
        if (np.hypot(*np.diff(dendrite.points[nodes], axis=0).T).sum() > 2.0 * sigma
                and others[nodes[1:]].mean() < 0.25):
            own[nodes[1:]] = -1
    have = _ink_map(dendrite, width, sigma)
    want = _ink_map(dendrite, 2.0 * ref, sigma)
    twig = _ink_map(dendrite, 2.0 * dendrite.radius, sigma, own >= 0)
    tiny = 1e-9
    excess = np.clip(1.0 - want / (have + tiny), 0.0, 1.0)
    drop = np.clip(excess / (twig / (have + tiny) + tiny), 0.0, 1.0)
    # one probability per twig: the mean over its nodes
    sums = np.bincount(own[own >= 0], weights=drop[own >= 0], minlength=dendrite.n_branches)
    counts = np.bincount(own[own >= 0], minlength=dendrite.n_branches)
    p = np.zeros(dendrite.n_branches)
    p[terminal] = sums[terminal] / np.maximum(counts[terminal], 1)
    tip_branch = own[dendrite.tips]
    has = tip_branch >= 0
    keep[has] = rng.random(int(has.sum())) >= p[tip_branch[has]]
    return keep


def _check_widths(lo, hi):
    for name, v in (("min_width", lo), ("max_width", hi)):
        if not np.isfinite(v) or v < 0:
            raise ValueError(f"{name} must be finite and >= 0, got {v}")
    if hi < lo:
        raise ValueError(f"max_width ({hi}) must be >= min_width ({lo})")
