"""Billboard clouds, steps 1-2: superpixels with natural outlines.

Part of :func:`~branchnb.trees.billboard.billboard_cloud`; the steps are described in
:mod:`branchnb.trees.billboard`.
"""

from __future__ import annotations

import cv2
import numpy as np
from scipy import ndimage as ndi

from ..core.random import as_rng


def crown_superpixels(rgb: np.ndarray, crown: np.ndarray, *, n_segments: int = 256,
                      compactness: float = 0.35) -> np.ndarray:
    """SLIC superpixels of the crown pixels.

    Parameters
    ----------
    rgb : (H, W, 3) float array
        Colours in [0, 1] (straight, not premultiplied).
    crown : (H, W) bool array
        The pixels to segment; the rest gets label 0. An empty crown gives
        all zeros.
    n_segments : int
        Approximate number of superpixels (paper: 256).
    compactness : float
        On colours scaled to [0, 1] (paper: 0.35); scikit-image receives
        ``100 * compactness`` because it measures colour in CIELAB.

    Returns
    -------
    labels : (H, W) int32
        1..K on the crown (each label one 4-connected piece), 0 elsewhere.

    Examples
    --------
    >>> import numpy as np
    >>> rgb = np.zeros((32, 32, 3)); rgb[:, 16:] = (0.1, 0.6, 0.1)
    >>> lab = crown_superpixels(rgb, np.ones((32, 32), bool), n_segments=4)
    >>> int(lab.min()) >= 1, len(np.unique(lab)) >= 2
    (True, True)
    """
    from skimage.segmentation import slic

    crown = np.asarray(crown, bool)
    if not crown.any():
        return np.zeros(crown.shape, np.int32)
    n = max(1, min(int(n_segments), int(crown.sum()) // 4))
    lab = slic(np.asarray(rgb, np.float64), n_segments=n, compactness=100.0 * compactness,
               mask=crown, start_label=1, enforce_connectivity=True, channel_axis=-1)
    lab = np.where(crown, lab, 0).astype(np.int32)
    # Split labels that came out in several pieces; relabel 1..K.
    out = np.zeros_like(lab)
    k = 0
    for sl_i, sl in enumerate(ndi.find_objects(lab)):
        if sl is None:
            continue
        comp, nc = ndi.label(lab[sl] == sl_i + 1)
        for c in range(1, nc + 1):
            k += 1
            out[sl][comp == c] = k
    # Pixels of the crown missed by SLIC (tiny specks) join their nearest label.
    miss = crown & (out == 0)
    if miss.any() and k:
        _, (iy, ix) = ndi.distance_transform_edt(out == 0, return_indices=True)
        out[miss] = out[iy[miss], ix[miss]]
    return out


def _silhouette_contours(mask: np.ndarray, min_len: int = 16) -> list[np.ndarray]:
    cs, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    return [c[:, 0, :].astype(np.float64) for c in cs if len(c) >= min_len]


def _edges(labels: np.ndarray):
    """Shared boundaries of 4-adjacent labels: {(a, b): (points (N, 2), dir a->b (2,))}."""
    out = {}
    pts, keys, dirs = [], [], []
    h, w = labels.shape
    ys, xs = np.mgrid[0:h, 0:w]
    for dy, dx in ((0, 1), (1, 0)):
        a = labels[: h - dy, : w - dx]
        b = labels[dy:, dx:]
        ok = (a != b) & (a > 0) & (b > 0)
        la, lb = a[ok], b[ok]
        px = xs[: h - dy, : w - dx][ok] + 0.5 * dx
        py = ys[: h - dy, : w - dx][ok] + 0.5 * dy
        swap = la > lb
        k1 = np.where(swap, lb, la)
        k2 = np.where(swap, la, lb)
        sgn = np.where(swap, -1.0, 1.0)
        keys.append(np.stack([k1, k2], 1))
        pts.append(np.stack([px, py], 1))
        dirs.append(np.stack([sgn * dx, sgn * dy], 1))
    if not keys:
        return out
    keys = np.concatenate(keys)
    if len(keys) == 0:
        return out
    pts = np.concatenate(pts)
    dirs = np.concatenate(dirs)
    uk, inv = np.unique(keys, axis=0, return_inverse=True)
    inv = inv.ravel()
    order = np.argsort(inv, kind="stable")
    bounds = np.searchsorted(inv[order], np.arange(len(uk) + 1))
    for i, (ka, kb) in enumerate(uk):
        sel = order[bounds[i]: bounds[i + 1]]
        out[(int(ka), int(kb))] = (pts[sel], dirs[sel].mean(axis=0))
    return out


def _straight_edge(p: np.ndarray, straightness: float, min_len: float):
    """End points of a near-straight edge, or None."""
    if len(p) < 3:
        return None
    c = p.mean(axis=0)
    q = p - c
    _, _, vt = np.linalg.svd(q, full_matrices=False)
    d = vt[0]
    t = q @ d
    p0, p1 = p[np.argmin(t)], p[np.argmax(t)]
    length = float(np.hypot(*(p1 - p0)))
    if length < min_len:
        return None
    u = (p1 - p0) / length
    dev = np.abs((p - p0) @ np.array([-u[1], u[0]]))
    if dev.max() > max(1.5, straightness * length):
        return None
    # One connected run of crack points (no gap longer than 2 px along the chord).
    s = np.sort((p - p0) @ u)
    if np.diff(s).max(initial=0.0) > 2.0:
        return None
    return p0, p1, length


def _find_piece(contours, lengths_cache, length: float, tol: float, rng):
    """A silhouette piece (M, 2) with chord ~ length, all on one side of its chord."""
    kmin = max(3, int(np.ceil(1.05 * length)))
    kmax = max(kmin + 1, int(np.ceil(2.5 * length)))
    order = rng.permutation(len(contours))
    for ci in order:
        c = contours[ci]
        n = len(c)
        if n < kmin + 2:
            continue
        starts = rng.choice(n, size=min(n, 96), replace=False)
        ks = np.arange(kmin, min(kmax, n - 1) + 1)
        if len(ks) == 0:
            continue
        ends = (starts[:, None] + ks[None, :]) % n
        chord = np.hypot(*(c[ends] - c[starts][:, None, :]).transpose(2, 0, 1))
        good = np.argwhere(np.abs(chord - length) <= tol * length)
        if len(good) == 0:
            continue
        good = good[rng.permutation(len(good))[:24]]
        for gi, gk in good:
            i, k = int(starts[gi]), int(ks[gk])
            idx = (i + np.arange(k + 1)) % n
            piece = c[idx]
            a, b = piece[0], piece[-1]
            ch = b - a
            L = float(np.hypot(*ch))
            if L < 1e-6:
                continue
            nrm = np.array([-ch[1], ch[0]]) / L
            dist = (piece - a) @ nrm
            lo, hi = dist.min(), dist.max()
            bulge = max(hi, -lo)
            if not (lo >= -0.5 or hi <= 0.5):
                continue           # crosses its chord
            if bulge < 1.0 or bulge > 0.6 * L:
                continue
            return piece
    return None


def replace_straight_edges(labels: np.ndarray, silhouette: np.ndarray, *, straightness: float = 0.08,
                           min_edge_length: float = 8.0, chord_tolerance: float = 0.1,
                           rng=None) -> tuple[np.ndarray, list[np.ndarray]]:
    """Replace near-straight superpixel edges by pieces of the silhouette.

    Parameters
    ----------
    labels : (H, W) int array
        Superpixels (0 = outside).
    silhouette : (H, W) bool array
        The tree (or crown) silhouette whose contour supplies the pieces.
    straightness, min_edge_length, chord_tolerance : float
        See :class:`BillboardParams`.
    rng : int or numpy.random.Generator
        Picks the pieces and the side they bulge to.

    Returns
    -------
    labels : (H, W) int32
        New labels: the pixels between each replaced edge and its new curve
        moved to the other superpixel (still a partition of the same pixels).
    curves : list of (M, 2) float arrays
        The new curves, in pixel coordinates.

    Examples
    --------
    >>> import numpy as np
    >>> yy, xx = np.mgrid[:80, :80]
    >>> disc = (xx - 40) ** 2 + (yy - 40) ** 2 < 35 ** 2
    >>> halves = np.where(disc, 1 + (xx >= 40), 0)        # cut by a straight vertical edge
    >>> new, curves = replace_straight_edges(halves, disc, rng=0)
    >>> len(curves), bool(((new > 0) == disc).all()), sorted(np.unique(new).tolist())
    (1, True, [0, 1, 2])
    """
    rng = as_rng(rng)
    lab = np.array(labels, dtype=np.int32, copy=True)
    contours = _silhouette_contours(np.asarray(silhouette, bool))
    if not contours:
        return lab, []
    curves = []
    H, W = lab.shape
    count = np.bincount(lab.ravel()).astype(np.int64)
    for (a, b), (pts, dir_ab) in sorted(_edges(lab).items()):
        st = _straight_edge(pts, straightness, min_edge_length)
        if st is None:
            continue
        p0, p1, length = st
        piece = _find_piece(contours, None, length, chord_tolerance, rng)
        if piece is None:
            continue
        # Similarity taking the piece's chord onto the edge (p0 -> p1).
        s0, s1 = piece[0], piece[-1]
        v_src, v_dst = s1 - s0, p1 - p0
        ang = np.arctan2(v_dst[1], v_dst[0]) - np.arctan2(v_src[1], v_src[0])
        sc = np.hypot(*v_dst) / np.hypot(*v_src)
        R = sc * np.array([[np.cos(ang), -np.sin(ang)], [np.sin(ang), np.cos(ang)]])
        curve = (piece - s0) @ R.T + p0
        u = v_dst / np.hypot(*v_dst)
        nrm = np.array([-u[1], u[0]])
        if rng.random() < 0.5:             # bulge to the other side: reflect across the chord
            d = (curve - p0) @ nrm
            curve = curve - 2.0 * d[:, None] * nrm[None, :]
        side = float(np.mean((curve - p0) @ nrm))
        # The bulge lies in b when it points along a -> b.
        into = b if side * float(dir_ab @ nrm) > 0 else a
        other = a if into == b else b
        poly = np.round(np.vstack([curve, [p1, p0]]) - 0.5).astype(np.int32)
        x0, y0 = np.maximum(poly.min(axis=0) - 1, 0)
        x1, y1 = np.minimum(poly.max(axis=0) + 2, [W, H])
        if x1 <= x0 or y1 <= y0:
            continue
        region = np.zeros((y1 - y0, x1 - x0), np.uint8)
        cv2.fillPoly(region, [poly - [x0, y0]], 1)
        sub = lab[y0:y1, x0:x1]
        move = (region > 0) & (sub == into)
        n_move = int(move.sum())
        if n_move == 0 or n_move >= count[into]:
            continue                       # never swallow a whole superpixel
        sub[move] = other
        count[into] -= n_move
        count[other] += n_move
        curves.append(curve)
    if curves:
        lab = _merge_fragments(lab)
    return lab, curves


def _merge_fragments(lab: np.ndarray) -> np.ndarray:
    """Keep each label's largest 4-connected piece; stray pieces join their nearest other label.

    Curves of neighbouring edges can overlap and cut a few pixels off a
    superpixel; such islands would stretch its billboard's bounding box.
    """
    out = lab.copy()
    stray = np.zeros(lab.shape, bool)
    for k, sl in enumerate(ndi.find_objects(lab), start=1):
        if sl is None:
            continue
        comp, nc = ndi.label(lab[sl] == k)
        if nc <= 1:
            continue
        sizes = np.bincount(comp.ravel())
        sizes[0] = 0
        stray[sl] |= (comp > 0) & (comp != int(np.argmax(sizes)))
    if not stray.any():
        return out
    out[stray] = 0
    _, (iy, ix) = ndi.distance_transform_edt(out == 0, return_indices=True)
    out[stray] = out[iy[stray], ix[stray]]
    return out
