"""Start maps of a registration (step 1 of :mod:`branchnb.leaves.registration`).

A similarity (optionally affine) map of an exemplar's blade onto the
training blade from their moments, the rotation searched over the circle
and scored by the chamfer distance of the laminae outlines and of the
thin parts' roots; and the blade's parts it needs: lamina, thin parts
(petiole, drawn-out tips), base point.
"""

from __future__ import annotations

import hashlib
import threading

import cv2
import numpy as np
from scipy.ndimage import label as ndi_label
from scipy.spatial import cKDTree

from ..core.image import as_mask
from ..core.morphology import fill_holes as ndi_fill_holes
from ..core.validate import Choice, Int, Real, checked

__all__ = ["start_candidates", "start_alignment", "split_petiole"]


def _moments(mask: np.ndarray):
    ys, xs = np.nonzero(mask)
    pts = np.column_stack([xs, ys]).astype(np.float64)
    mu = pts.mean(0)
    cov = np.cov((pts - mu).T) + 1e-6 * np.eye(2)
    return mu, cov, float(len(pts))


def _sqrtm(c, inverse=False):
    vals, vecs = np.linalg.eigh(c)
    vals = np.maximum(vals, 1e-9)
    p = -0.5 if inverse else 0.5
    return (vecs * vals ** p) @ vecs.T


def _rot(theta):
    c, s = np.cos(theta), np.sin(theta)
    return np.array([[c, -s], [s, c]])


def _contour_points(mask: np.ndarray, n: int = 600) -> np.ndarray:
    contours, _ = cv2.findContours(mask.astype(np.uint8), cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    pts = np.vstack([c[:, 0, :] for c in contours]).astype(np.float64)
    if len(pts) > n:
        pts = pts[np.linspace(0, len(pts) - 1, n).astype(int)]
    return pts


class _Chamfer:
    """Mean distance of mapped points to a mask's outline (distance transform lookup)."""

    def __init__(self, mask: np.ndarray, region: bool = False):
        edge = np.ones(mask.shape, np.uint8)
        if region:  # distance to the region itself
            edge[mask] = 0
        else:  # distance to its outline
            edge[cv2.morphologyEx(mask.astype(np.uint8), cv2.MORPH_GRADIENT, np.ones((3, 3), np.uint8)) > 0] = 0
        self.dt = cv2.distanceTransform(edge, cv2.DIST_L2, 3)
        self.h, self.w = mask.shape

    def __call__(self, pts: np.ndarray) -> float:
        x, y = pts[:, 0], pts[:, 1]
        xc, yc = np.clip(x, 0, self.w - 1), np.clip(y, 0, self.h - 1)
        d = self.dt[np.round(yc).astype(int), np.round(xc).astype(int)]
        d = d + np.hypot(x - xc, y - yc)  # outside the image: at least this far
        return float(np.sqrt(np.mean(d * d)))

    def many(self, pts: np.ndarray) -> np.ndarray:
        """:meth:`__call__` of every point set of a stack ``pts`` (M, N, 2): (M,) values, the same numbers."""
        x, y = pts[..., 0], pts[..., 1]
        xc, yc = np.clip(x, 0, self.w - 1), np.clip(y, 0, self.h - 1)
        d = self.dt[np.round(yc).astype(int), np.round(xc).astype(int)]
        d = d + np.hypot(x - xc, y - yc)
        return np.sqrt(np.mean(d * d, axis=1))


def _opening_radius(mask: np.ndarray) -> int:
    return max(1, int(round(0.05 * np.sqrt(mask.sum()))))


_THIN_CACHE: dict = {}
_THIN_LOCK = threading.Lock()  # batch runs register leaves on several threads


def _thin_parts(mask: np.ndarray) -> np.ndarray:
    """:func:`_thin_parts_of`, remembered for the last few masks (a registration asks ~12 times per leaf)."""
    m = np.ascontiguousarray(mask, bool)
    key = (m.shape, hashlib.blake2b(np.packbits(m).tobytes(), digest_size=16).digest())
    with _THIN_LOCK:
        hit = _THIN_CACHE.get(key)
    if hit is None:
        hit = _thin_parts_of(m)
        with _THIN_LOCK:
            while len(_THIN_CACHE) >= 8:
                _THIN_CACHE.pop(next(iter(_THIN_CACHE)))
            _THIN_CACHE[key] = hit
    return hit.copy()


def _thin_parts_of(mask: np.ndarray) -> np.ndarray:
    """Thin protrusions of a blade (petiole, drawn-out tips): what an opening removes.

    Holes (insect damage) are filled first: the pixels around a hole are
    no protrusion of the outline.
    """
    filled = ndi_fill_holes(mask)
    r = _opening_radius(filled)
    k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    # The opening of the blade's bounding box (r + 1 beyond it, clipped to
    # the image): outside it the mask is empty and stays so.
    ys, xs = np.nonzero(filled.any(1))[0], np.nonzero(filled.any(0))[0]
    opened = np.zeros(mask.shape, bool)
    if len(ys):
        y0, y1 = max(0, ys[0] - r - 1), min(mask.shape[0], ys[-1] + r + 2)
        x0, x1 = max(0, xs[0] - r - 1), min(mask.shape[1], xs[-1] + r + 2)
        opened[y0:y1, x0:x1] = cv2.morphologyEx(filled[y0:y1, x0:x1].astype(np.uint8), cv2.MORPH_OPEN, k) > 0
    thin = mask & ~opened
    return thin if thin.sum() >= max(8, 0.002 * mask.sum()) else np.zeros_like(mask)


def _mask_key(*masks) -> tuple:
    """A key for a cache of results on boolean masks (their shapes and a hash of their bits)."""
    h = hashlib.blake2b(digest_size=16)
    for m in masks:
        m = np.ascontiguousarray(m, bool)
        h.update(repr(m.shape).encode())
        h.update(np.packbits(m).tobytes())
    return h.digest()


_PART_CACHE: dict = {}


def _cached(kind: str, key, make):
    """``make()``, remembered under ``(kind, key)`` for the last few masks (thread-safe, like ``_thin_parts``).

    The training leaf's parts are asked for again with every exemplar
    registered to it (and each exemplar's several times): a 1 MP blade's
    thin roots (a dilation by a disc of four opening radii) cost ~30 ms.
    """
    k = (kind, key)
    with _THIN_LOCK:
        hit = _PART_CACHE.get(k)
    if hit is None:
        hit = make()
        with _THIN_LOCK:
            while len(_PART_CACHE) >= 32:
                _PART_CACHE.pop(next(iter(_PART_CACHE)))
            _PART_CACHE[k] = hit
    return hit


def _thin_roots(mask: np.ndarray, thin: np.ndarray, lamina: np.ndarray) -> np.ndarray:
    """:func:`_thin_roots_of`, remembered for the last few masks (a copy)."""
    return _cached("roots", _mask_key(mask, thin, lamina), lambda: _thin_roots_of(mask, thin, lamina)).copy()


def _thin_roots_of(mask: np.ndarray, thin: np.ndarray, lamina: np.ndarray) -> np.ndarray:
    """Where the thin parts leave the lamina (within one opening radius of it).

    A petiole's length and bend vary from leaf to leaf (a long curved
    petiole would pull a whole-shape score towards a rotation that aligns
    petioles instead of blades), but where it joins the blade, the base of
    the leaf, is shared by every leaf of a kind; so are the roots of the
    lobe tips.
    """
    r = _opening_radius(mask)
    # Only the dilation at the thin pixels counts: dilate the window around
    # them (2 r beyond their bounding box), the same values as the whole image.
    ys, xs = np.nonzero(thin)
    near = np.zeros(mask.shape, bool)
    if len(ys):
        y0, y1 = max(0, ys.min() - 2 * r - 1), min(mask.shape[0], ys.max() + 2 * r + 2)
        x0, x1 = max(0, xs.min() - 2 * r - 1), min(mask.shape[1], xs.max() + 2 * r + 2)
        k = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (4 * r + 1, 4 * r + 1))
        near[y0:y1, x0:x1] = cv2.dilate(lamina[y0:y1, x0:x1].astype(np.uint8), k) > 0
    roots = thin & near
    return roots if roots.sum() >= 4 else thin


#: A thin part's stalk is where the blade is at most this fraction of the
#: opening's diameter wide (a petiole along its length; a tip near its end) ...
STALK_WIDTH = 0.5
#: ... and a stalk is even when the 25th percentile of its widths is at
#: least this share of the 75th (each plus 1 px): a petiole 0.6-1.0 (seven
#: sample maples; procedural willow, cordate, oak, clip-art leaves of
#: 200-900 px), a drawn-out tip, whose width grows from its point, 0.3-0.55.
STALK_EVEN = 0.6


def _stalks(mask: np.ndarray, lab: np.ndarray, n: int) -> tuple[np.ndarray, np.ndarray]:
    """Per thin part (labels 1..n of ``lab``): its stalk's length (midline pixels) and evenness.

    The stalk is the part's midline (skeleton) where the blade is at most
    :data:`STALK_WIDTH` of the opening's diameter wide; its evenness the
    25th over the 75th percentile of those widths (:data:`STALK_EVEN`).
    """
    from skimage.morphology import skeletonize

    r = _opening_radius(ndi_fill_holes(mask))
    ys, xs = np.nonzero(lab)
    y0, y1 = max(0, ys.min() - 2), min(mask.shape[0], ys.max() + 3)
    x0, x1 = max(0, xs.min() - 2), min(mask.shape[1], xs.max() + 3)
    sub = np.pad(mask[y0:y1, x0:x1], 1).astype(np.uint8)
    width = 2.0 * cv2.distanceTransform(sub, cv2.DIST_L2, 5)[1:-1, 1:-1]
    part = lab[y0:y1, x0:x1]
    sk = skeletonize(part > 0) & (width <= STALK_WIDTH * (2 * r + 1))
    length = np.bincount(part[sk], minlength=n + 1)[1:]
    even = np.zeros(n)
    ids, w = part[sk], width[sk]
    for k in np.flatnonzero(length >= 3):
        q25, q75 = np.percentile(w[ids == k + 1], [25, 75])
        # + 1 px: on the pixel grid a 2-3 px stalk reads 2.0-4.0
        even[k] = (q25 + 1.0) / (q75 + 1.0)
    return length, even


def _petiole_part(mask: np.ndarray, thin: np.ndarray):
    """Labels of the thin parts and the petiole's label (0: none).

    The paper's exemplars come cut out, petiole and all; which thin part
    is the petiole is ours to decide (beyond the paper). The thin part
    (what an opening removes) at least twice as large as any other was
    taken, so a leaf without a clear petiole gives none; but size alone
    took the drawn-out tip of narrow and heart-shaped leaves for the
    petiole (a willow-like lanceolate blade's tip outweighs its 4-5 px
    stalk, a cordate blade's acuminate tip its petiole, half hidden in the
    sinus). So first a petiole is a stalk of even width
    (:func:`_stalks`): among the thin parts whose stalk is even and at
    least the opening's radius long, one whose stalk is at least twice as
    long as the others'; only when there is none does size decide.
    """
    lab, n = ndi_label(thin, structure=np.ones((3, 3)))
    if n == 0:
        return lab, 0
    if n > 1:
        length, even = _stalks(mask, lab, n)
        cand = np.flatnonzero((even >= STALK_EVEN) & (length >= _opening_radius(mask)))
        if len(cand):
            best = cand[np.argmax(length[cand])]
            if len(cand) == 1 or length[best] >= 2 * np.sort(length[cand])[-2]:
                return lab, int(best) + 1
    sizes = np.bincount(lab.ravel())[1:]
    top = np.sort(sizes)[::-1]
    if n > 1 and top[0] < 2 * top[1]:
        return lab, 0
    return lab, int(np.argmax(sizes)) + 1


def _base_point(mask: np.ndarray, thin: np.ndarray, lamina: np.ndarray):
    """Where the dominant thin part (the petiole, :func:`_petiole_part`) joins the lamina, or None."""
    if not thin.any():
        return None
    lab, k = _petiole_part(mask, thin)
    if k == 0:
        return None
    roots = _thin_roots(mask, lab == k, lamina)
    ys, xs = np.nonzero(roots)
    return np.array([xs.mean(), ys.mean()])


def split_petiole(blade) -> tuple[np.ndarray, np.ndarray, np.ndarray | None]:
    """A blade's lamina, its petiole (the dominant thin protrusion) and the base where they meet.

    Parameters
    ----------
    blade : (H, W) bool array_like
        The leaf's silhouette (lamina and petiole).

    Returns
    -------
    lamina, petiole : (H, W) bool ndarray
        ``petiole`` is empty (and ``lamina`` the blade without thin parts)
        when no thin part is clearly the petiole: neither a stalk twice as
        long as any other thin part's nor twice as large (beyond the
        paper: a drawn-out tip is no petiole, see :func:`_petiole_part`).
    base : (2,) ndarray or None
        ``(x, y)`` where the petiole joins the lamina.

    Examples
    --------
    >>> import numpy as np
    >>> b = np.zeros((60, 40), bool); b[5:35, 5:35] = True; b[35:58, 19:21] = True
    >>> lam, pet, base = split_petiole(b)
    >>> bool(pet[50, 20]), bool(lam[20, 20]), base is not None
    (True, True, True)
    """
    mask = as_mask(blade, name="blade")
    thin = _thin_parts(mask)
    lamina = _lamina(mask)
    base = _base_point(mask, thin, lamina)
    if base is None:
        return lamina, np.zeros_like(mask), None
    lab, k = _petiole_part(mask, thin)
    return lamina, lab == k, base


class _StartSide:
    """What :class:`_StartScore` needs of one blade: outline points and chamfer, thin roots, base point."""

    def __init__(self, m: np.ndarray):
        lam = _lamina(m)
        self.out = _contour_points(lam)
        self.cham = _Chamfer(lam)
        t = _thin_parts(m)
        self.thin = bool(t.any())
        if self.thin:
            roots = _thin_roots(m, t, lam)
            pts = np.column_stack(np.nonzero(roots)[::-1]).astype(np.float64)
            self.thin_pts = pts[:: max(1, len(pts) // 300)]
            self.dt_thin = _Chamfer(roots, region=True)
        self.base = _base_point(m, t, lam)
        self.radius = float(np.sqrt(lam.sum() / np.pi))


class _StartScore:
    """Symmetric RMS chamfer distance of the laminae outlines (+ of the thin parts' roots) under an affine map.

    When both leaves have a dominant thin part (a petiole), the distance
    between their base points (where it joins the lamina) is added: a
    palmate blade fits itself well at every lobe's rotation, its base
    tells which one is right. Base distances below 0.3 blade radii are free.
    """

    def __init__(self, me: np.ndarray, mt: np.ndarray):
        # One side per blade, remembered: the training leaf's is the same for every exemplar.
        se = _cached("start side", _mask_key(me), lambda: _StartSide(me))
        st = _cached("start side", _mask_key(mt), lambda: _StartSide(mt))
        self.out_e, self.out_t = se.out, st.out
        self.cham_e, self.cham_t = se.cham, st.cham
        self.thin = se.thin and st.thin
        if self.thin:
            self.thin_e, self.thin_t = se.thin_pts, st.thin_pts
            self.dt_te, self.dt_tt = se.dt_thin, st.dt_thin
        self.base_e, self.base_t = se.base, st.base
        self.radius_t = st.radius

    def __call__(self, mat: np.ndarray) -> float:
        lin, off = mat[:, :2], mat[:, 2]
        inv = np.linalg.inv(lin)
        scale = np.sqrt(abs(np.linalg.det(lin)))
        c = self.cham_t(self.out_e @ lin.T + off) + self.cham_e((self.out_t - off) @ inv.T) * scale
        if self.thin:
            c += self.dt_tt(self.thin_e @ lin.T + off) + self.dt_te((self.thin_t - off) @ inv.T) * scale
        if self.base_e is not None and self.base_t is not None:
            # Only a gross mismatch counts (another lobe's rotation moves the
            # base by about a blade radius): the fine angle is the outlines'.
            c += max(0.0, float(np.hypot(*(self.base_e @ lin.T + off - self.base_t))) - 0.3 * self.radius_t)
        return c

    def many(self, mats: np.ndarray) -> np.ndarray:
        """:meth:`__call__` of a stack of maps (M, 2, 3) at once: (M,) scores.

        The rotation search scores ~70 maps per exemplar; one call each was
        Python overhead on small arrays (~1 s of the 8-exemplar analysis).
        """
        mats = np.asarray(mats, np.float64)
        lin, off = mats[:, :, :2], mats[:, :, 2]
        inv = np.linalg.inv(lin)
        scale = np.sqrt(np.abs(np.linalg.det(lin)))
        lin_t, inv_t = np.swapaxes(lin, 1, 2), np.swapaxes(inv, 1, 2)
        c = (self.cham_t.many(self.out_e @ lin_t + off[:, None])
             + self.cham_e.many((self.out_t - off[:, None]) @ inv_t) * scale)
        if self.thin:
            c = c + (self.dt_tt.many(self.thin_e @ lin_t + off[:, None])
                     + self.dt_te.many((self.thin_t - off[:, None]) @ inv_t) * scale)
        if self.base_e is not None and self.base_t is not None:
            gap = self.base_e @ lin_t + off - self.base_t
            c = c + np.maximum(0.0, np.hypot(gap[:, 0], gap[:, 1]) - 0.3 * self.radius_t)
        return c


def _affine_icp(mat: np.ndarray, src: np.ndarray, dst: np.ndarray, iterations: int = 15) -> np.ndarray:
    """Refine an affine map of outline points ``src`` onto ``dst`` (symmetric nearest points, trimmed)."""
    tree_d, tree_s = cKDTree(dst), None
    for _ in range(iterations):
        lin, off = mat[:, :2], mat[:, 2]
        ms = src @ lin.T + off
        d1, i1 = tree_d.query(ms)
        tree_s = cKDTree(ms)
        d2, i2 = tree_s.query(dst)
        a = np.vstack([src, src[i2]])
        b = np.vstack([dst[i1], dst])
        d = np.concatenate([d1, d2])
        keep = d <= np.percentile(d, 90)
        a_h = np.column_stack([a[keep], np.ones(keep.sum())])
        sol, *_ = np.linalg.lstsq(a_h, b[keep], rcond=None)
        new = sol.T
        if np.abs(new - mat).max() < 1e-4:
            mat = new
            break
        mat = new
    return mat


@checked(rotation_step=Real(0.5, 90.0), n=Int(1, 1000), start=Choice("similarity", "affine"))
def start_candidates(exemplar_blade, training_blade, *, start: str = "similarity",
                     rotation_step: float = 5.0, mirror: bool = False,
                     n: int = 3) -> list[tuple[np.ndarray, float]]:
    """The ``n`` best distinct start maps (2 x 3, exemplar px -> training px), best first, with their scores.

    Every candidate maps the exemplar blade's centroid onto the training
    blade's and scales it by the square root of the area ratio; rotations
    cover the circle ``rotation_step`` apart (optionally mirrored). The
    score is the symmetric RMS chamfer distance of the two outlines (in
    training pixels) plus that of their thin parts (petiole, drawn-out
    tips: what a morphological opening removes), which tell base from tip
    on an almost symmetric blade. Local minima of the score more than 30
    degrees apart are refined in steps of a tenth of ``rotation_step``;
    with ``start="affine"`` each is then refined to an affine map by
    trimmed symmetric ICP on the outlines.

    Parameters
    ----------
    exemplar_blade : (H_e, W_e) bool array_like
        The moving leaf's blade (at least 16 pixels).
    training_blade : (H_t, W_t) bool array_like
        The training leaf's blade (at least 16 pixels).
    start : {"similarity", "affine"}
        Family of start maps (default ``"similarity"``).
    rotation_step : float
        Degrees between the rotations tried, 0.5 to 90 (default 5).
    mirror : bool
        Also try mirrored maps (a leaf photographed from the back).
    n : int
        Number of candidates returned, at most (default 3).

    Returns
    -------
    list of ((2, 3) ndarray, float)
        Start maps and their chamfer scores (training pixels, lower is
        better), best first.
    """
    me = as_mask(exemplar_blade, name="exemplar_blade")
    mt = as_mask(training_blade, name="training_blade")
    for nm, m in (("exemplar_blade", me), ("training_blade", mt)):
        if m.sum() < 16:
            raise ValueError(f"{nm} has only {int(m.sum())} pixels: no leaf to align")
    if start not in ("similarity", "affine"):
        raise ValueError(f"start must be 'similarity' or 'affine', got {start!r}")
    if not 0 < rotation_step <= 180:
        raise ValueError(f"rotation_step must be in (0, 180], got {rotation_step}")
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"n must be a positive int, got {n!r}")
    # Centroids and areas of the laminae: a long petiole would shift them.
    mu_e, _, a_e = _moments(_lamina(me))
    mu_t, _, a_t = _moments(_lamina(mt))
    score = _StartScore(me, mt)
    sc = np.sqrt(a_t / a_e)

    def matrix(th, fl):
        lin = sc * _rot(th) @ fl
        return np.hstack([lin, (mu_t - lin @ mu_e)[:, None]])

    flips = [np.eye(2)] + ([np.diag([1.0, -1.0])] if mirror else [])
    step = np.deg2rad(rotation_step)
    thetas = np.arange(0, 2 * np.pi, step)
    found = []
    for fl in flips:
        costs = score.many(np.array([matrix(th, fl) for th in thetas]))
        m = len(costs)
        for idx in np.argsort(costs):
            # Keep local minima that are far from the ones kept.
            if costs[idx] > min(costs[(idx - 1) % m], costs[(idx + 1) % m]):
                continue
            th = thetas[idx]
            if any(f is fl and abs(_wrap_angle(th - t0)) < np.deg2rad(30) for _, f, t0 in found):
                continue
            found.append((costs[idx], fl, th))
    found.sort(key=lambda c: c[0])
    out = []
    for c, fl, th in found[:n]:
        best_c, best_th = c, th
        dths = np.linspace(-step, step, 21)
        for dth, c2 in zip(dths, score.many(np.array([matrix(th + dth, fl) for dth in dths]))):
            if c2 < best_c:
                best_c, best_th = c2, th + dth
        mat = matrix(best_th, fl)
        if start == "affine":
            mat = _affine_icp(mat, score.out_e, score.out_t)
            best_c = score(mat)
        out.append((mat, float(best_c)))
    out.sort(key=lambda c: c[1])
    return out


def _lamina(mask: np.ndarray) -> np.ndarray:
    """The blade without its thin parts (largest remaining component)."""
    lam = mask & ~_thin_parts(mask)
    lab, n = ndi_label(lam)
    if n > 1:
        sizes = np.bincount(lab.ravel())[1:]
        lam = lab == (int(np.argmax(sizes)) + 1)
    # An opening that eats much of the blade (a leaf riddled with holes) is
    # no petiole removal: keep the blade then.
    return lam if lam.sum() >= 0.75 * mask.sum() else mask


def _outline_samples(mask: np.ndarray, n: int) -> np.ndarray:
    """``n`` points evenly spaced along a blade's outer outline."""
    from .keypoints import _outline_points

    return _outline_points(mask, n)


def _interior_samples(mask: np.ndarray, n: int = 2000) -> np.ndarray:
    """About ``n`` pixel centres (x, y) spread evenly over ``mask``."""
    ys, xs = np.nonzero(mask)
    step = max(1, len(xs) // n)
    return np.column_stack([xs[::step], ys[::step]]).astype(np.float64)


def _jacobian_det(spline, points: np.ndarray) -> np.ndarray:
    """Determinant of ``spline``'s Jacobian at ``points`` (<= 0 where it turns orientation)."""
    jac = spline.jacobian(points)
    return jac[:, 0, 0] * jac[:, 1, 1] - jac[:, 0, 1] * jac[:, 1, 0]


def _outline_fit(mapped: np.ndarray, target: np.ndarray) -> float:
    """Symmetric RMS nearest-point distance of two point sets."""
    d1, _ = cKDTree(target).query(mapped)
    d2, _ = cKDTree(mapped).query(target)
    return float(np.sqrt(np.mean(d1 ** 2)) + np.sqrt(np.mean(d2 ** 2)))


def _wrap_angle(a):
    return (a + np.pi) % (2 * np.pi) - np.pi


@checked(rotation_step=Real(0.5, 90.0), start=Choice("similarity", "affine"))
def start_alignment(exemplar_blade, training_blade, *, start: str = "similarity", rotation_step: float = 5.0,
                    mirror: bool = False) -> tuple[np.ndarray, float]:
    """The best start map (2 x 3, exemplar pixels -> training pixels) and its blade overlap (IoU).

    See :func:`start_candidates` for how it is found.

    Parameters
    ----------
    exemplar_blade : (H_e, W_e) bool array_like
        The moving leaf's blade.
    training_blade : (H_t, W_t) bool array_like
        The training leaf's blade.
    start : {"similarity", "affine"}
        Family of start maps (default ``"similarity"``).
    rotation_step : float
        Degrees between the rotations tried (default 5).
    mirror : bool
        Also try mirrored maps.

    Returns
    -------
    matrix : (2, 3) ndarray
    iou : float
        Blade overlap after the map.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((60, 60), bool); a[10:50, 25:35] = True; a[10:20, 35:45] = True
    >>> b = np.rot90(a).copy()
    >>> m, score = start_alignment(a, b)
    >>> score > 0.9
    True
    """
    mat, _ = start_candidates(exemplar_blade, training_blade, start=start, rotation_step=rotation_step,
                              mirror=mirror, n=1)[0]
    return mat, _blade_iou(mat, as_mask(exemplar_blade), as_mask(training_blade))


def _blade_iou(mat, me, mt) -> float:
    warped = cv2.warpAffine(me.astype(np.float32), mat, mt.shape[::-1], flags=cv2.INTER_LINEAR) > 0.5
    union = np.logical_or(warped, mt).sum()
    return float(np.logical_and(warped, mt).sum() / union) if union else 0.0
