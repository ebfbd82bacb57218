"""Carried parts fanned apart where their parent bends (beyond the paper).

A part nobody stroked follows its parent rigidly: the frame of the source
stroke at its attachment goes to the target stroke's frame there
(:func:`~branchnb.strokes.parts.rigid_frame`). Where the target bends a
stroke more than the source did, the parts on the inner side of the bend
turn towards each other: long parts close together (a fern's pinnae, the
leaves along a twig) cross and pile into one overlapping cluster.

Here each carried part is turned further about its attachment point (so
it stays joined to its parent) by an angle ``a_k``; the angles are as
small and as even along each chain of siblings as the parts allow
(as-rigid-as-possible over the chain)::

    minimise   sum_k a_k^2 + MU * sum_(k, l consecutive siblings) (a_k - a_l)^2
    subject to sigma_kl a_k + sigma_lk a_l >= g_kl      (every pair near each other)
               lo_k <= a_k <= hi_k

``sigma_kl`` is the sign that turns part ``k`` away from part ``l`` and
``g_kl`` the turn of ``k`` away from ``l`` at which their pixels stop
coming within :data:`_CLEAR` px of each other (or as close as they were in
the source, if closer), negative where they have room (how far ``k`` may
turn towards ``l``); it is found on the parts' own pixels over a fan of
turns. The constraints are kept as a stiff penalty (a crowded bend with no
room left settles on a compromise) and the problem is solved by
semi-smooth Newton steps; the overlaps are measured again, and a round's
step (or half or a quarter of it) is kept only if it lessens them, for a
few rounds. A part turns at most halfway towards lying along its parent
(``lo``, ``hi``). Parts that do not collide in the rigid placement are
left as they were (an edit without collisions keeps its output).

Beyond the paper (which drops unstroked parts). Measured by
``python -m branchnb.strokes._fan_check``: procedural fronds and twigs
(300-1000 px, 2 seeds, bent 100 degrees both ways) and a real fern frond.
Not handled: a part lying over its parent's re-synthesized tube (a fern's
apex turned into its own top lobes), and a bend with no angular room left
(the compromise keeps some overlap).
"""

from __future__ import annotations

import cv2
import numpy as np

from .parts import carry_frame

__all__: list[str] = []

#: Most points of a part's pixels the overlap test looks at.
_POINTS = 600
#: Share of a part's pixels that may come within the clearance of another (beyond the source's) before
#: they collide.
_OVERLAP = 0.01
#: Clearance (px) neighbours keep (or what they had in the source, if less).
_CLEAR = 2
_DISK = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * _CLEAR + 1, 2 * _CLEAR + 1))
#: Weight of evenness along a chain of siblings against the size of the turns.
_MU = 1.0
#: Largest extra turn (rad) of a part.
_MOST = np.radians(60.0)
#: Share of the way towards lying along its parent a part may turn.
_HALFWAY = 0.5
#: Weight of a constraint's squared excess (rad^2) against the turns.
_STIFF = 1000.0
#: Shares of a round's step tried in turn until one lessens the overlaps.
_BACKTRACK = (1.0, 0.5, 0.25)
#: Rounds of linearise-solve-measure.
_ROUNDS = 4
#: Turns tried at once for a pair's separating turn (over [-_MOST, _MOST]), then within the bracket.
_COARSE = 25
_FINE = 12


class _Placed:
    """One carried part: its points, pivot, rigid map and current extra turn."""

    def __init__(self, part, forward: np.ndarray, pivot: np.ndarray, tangent: float):
        (rs, cs) = part.box
        m = part.mask
        ys, xs = np.nonzero(m)
        step = max(1, int(np.ceil(len(xs) / _POINTS)))
        src = np.c_[xs[::step] + cs.start, ys[::step] + rs.start].astype(float)
        self.src = src
        self.mask = m
        self.origin = (cs.start, rs.start)
        self.forward = forward
        self.pivot = np.asarray(pivot, float)
        self.rel = src @ forward[:, :2].T + forward[:, 2] - self.pivot  # target points about the pivot
        self.n = len(self.rel)
        self.weight = len(xs) / max(self.n, 1)  # pixels a point stands for
        self.radius = float(np.hypot(*self.rel.T).max()) if self.n else 0.0
        self.centroid = self.rel.mean(axis=0) if self.n else np.zeros(2)
        self.angle = 0.0
        self._pts = self._grid = None
        self._allowed: dict = {}
        phi = (np.arctan2(self.centroid[1], self.centroid[0]) - tangent + np.pi) % (2 * np.pi) - np.pi
        if np.hypot(*self.centroid) < 1e-6:
            phi = 0.0
        # turn at most halfway towards lying along the parent (either way)
        if abs(phi) < np.radians(20.0) or abs(phi) > np.radians(160.0):
            lo, hi = -np.radians(30.0), np.radians(30.0)  # a part at a stroke's end: no side
        elif phi > 0:
            lo, hi = -_HALFWAY * phi, _HALFWAY * (np.pi - phi)
        else:
            lo, hi = -_HALFWAY * (np.pi + phi), _HALFWAY * -phi
        self.lo, self.hi = max(lo, -_MOST), min(hi, _MOST)

    def points(self, extra: float = 0.0) -> np.ndarray:
        """Target points with the current turn plus ``extra`` (rad) about the pivot."""
        a = self.angle + extra
        if extra == 0.0 and self._pts is not None and self._pts[0] == a:
            return self._pts[1]
        c, s = np.cos(a), np.sin(a)
        out = self.rel @ np.array([[c, s], [-s, c]]) + self.pivot
        if extra == 0.0:
            self._pts = (a, out)
        return out

    def grid(self):
        """``(box, raster)``: its pixels grown by :data:`_CLEAR` px with the current turn on their box
        (cached per turn)."""
        if self._grid is None or self._grid[0] != self.angle:
            pts = self.points()
            x0, y0 = np.floor(pts.min(axis=0)).astype(int) - 2 - _CLEAR
            x1, y1 = np.ceil(pts.max(axis=0)).astype(int) + 3 + _CLEAR
            box = (int(x0), int(y0), int(x1 - x0), int(y1 - y0))
            self._grid = (self.angle, (box, self.raster(box)))
        return self._grid[1]

    def raster(self, box, m=None) -> np.ndarray:
        """Its pixels grown by :data:`_CLEAR` px, placed by ``m`` (default: :meth:`map`) on ``box`` =
        ``(x0, y0, w, h)``."""
        x0, y0, w, h = box
        m = self.map() if m is None else m.copy()
        m[:, 2] += m[:, :2] @ np.array(self.origin, float) - (x0, y0)
        out = cv2.warpAffine(self.mask.astype(np.uint8), m, (w, h), flags=cv2.INTER_NEAREST,
                             borderMode=cv2.BORDER_CONSTANT, borderValue=0)
        return cv2.dilate(out, _DISK).astype(bool)

    def source_overlap(self, other) -> int:
        """Its source points on ``other``'s grown source pixels (what the parts had in the source)."""
        ident = np.array([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0]])
        x0, y0 = np.floor(other.src.min(axis=0)).astype(int) - 2 - _CLEAR
        x1, y1 = np.ceil(other.src.max(axis=0)).astype(int) + 3 + _CLEAR
        ras = other.raster((int(x0), int(y0), int(x1 - x0), int(y1 - y0)), ident)
        q = np.rint(self.src - (x0, y0)).astype(np.intp)
        ok = (q[:, 0] >= 0) & (q[:, 0] < ras.shape[1]) & (q[:, 1] >= 0) & (q[:, 1] < ras.shape[0])
        return int(ras[q[ok, 1], q[ok, 0]].sum())

    def map(self) -> np.ndarray:
        """The 2 x 3 forward map: the rigid one turned by :attr:`angle` about the pivot."""
        c, s = np.cos(self.angle), np.sin(self.angle)
        rot = np.array([[c, -s], [s, c]])
        lin = rot @ self.forward[:, :2]
        t = rot @ (self.forward[:, 2] - self.pivot) + self.pivot
        return np.hstack([lin, t[:, None]])


def _fanned_maps(index, attached, carried, window: float) -> list[np.ndarray]:
    """Forward maps (2 x 3, source -> target) of the carried parts ``(pair, part, s_target)``.

    Rigid (:func:`~branchnb.strokes.parts.rigid_frame`) unless two parts
    overlap there; then every part of the chains involved is turned about
    its attachment (see the module's docstring).
    """
    placed = []
    for i, pi, s_t in carried:
        part, pair = index.parts[pi], attached[i]
        fwd = carry_frame(part, pair.source, pair.target, part.s, s_t, window=window)
        pivot = pair.target._point_at(s_t)
        tangent = float(pair.target._angle_at(s_t, window))
        placed.append(_Placed(part, fwd, pivot, tangent))
    rigid = [p.forward for p in placed]
    if not placed:
        return rigid
    near = _near_pairs(placed, carried)
    over, excess = _colliding(placed, near)
    if not over:
        return rigid
    # the chains of siblings (one carrying pair, one side, by attachment) holding a collision
    chains = _chains(index, carried)
    involved = {k for pair in over for k in pair}
    links = []
    for chain in chains:
        if involved & set(chain):
            links += list(zip(chain[:-1], chain[1:]))
    links = [(k, l) for k, l in links if (k, l) in near or (l, k) in near]
    active = sorted({k for pair in over + links for k in pair})
    cons = {tuple(sorted(p)) for p in over + links}
    for _ in range(_ROUNDS):
        rows = []
        for k, l in sorted(cons):
            sk, sl = _away(placed[k], placed[l]), _away(placed[l], placed[k])
            g = _separation(placed[k], placed[l], sk)
            rows.append((k, l, sk, sl, g))
        before = np.array([p.angle for p in placed])
        _solve(placed, active, rows, links)
        step = np.array([p.angle for p in placed]) - before
        # the linearised step, or a part of it, only where it lessens the overlaps (many parts
        # crowded on a strong bend: the full step swung some into others)
        for frac in _BACKTRACK:
            for p, a in zip(placed, before + frac * step):
                p.angle = float(a)
            still, now = _colliding(placed, near)
            if now < excess:
                break
        else:
            for p, a in zip(placed, before):  # no part of the step helps: undone
                p.angle = float(a)
            break
        excess = now
        if not still:
            break
        new = {tuple(sorted(p)) for p in still} - cons
        cons |= new
        active = sorted(set(active) | {k for pair in new for k in pair})
    return [p.map() for p in placed]


def _near_pairs(placed, carried) -> list[tuple[int, int]]:
    """Pairs of placed parts (of different source parts) whose reach round their pivots meets."""
    piv = np.array([p.pivot for p in placed])
    rad = np.array([p.radius for p in placed])
    d = np.hypot(*(piv[:, None] - piv[None]).transpose(2, 0, 1))
    ks, ls = np.nonzero(np.triu(d <= rad[:, None] + rad[None] + 2.0, 1))
    return [(int(k), int(m)) for k, m in zip(ks, ls) if carried[k][1] != carried[m][1]
            and placed[k].n and placed[m].n]


def _chains(index, carried) -> list[list[int]]:
    """Carried parts grouped by carrying pair and side, in order of attachment."""
    groups: dict = {}
    for k, (i, pi, s_t) in enumerate(carried):
        part = index.parts[pi]
        groups.setdefault((i, part.side), []).append((s_t, k))
    return [[k for _, k in sorted(g)] for g in groups.values() if len(g) > 1]


def _overlap(a: _Placed, b: _Placed, extra=0.0, grid=None) -> np.ndarray:
    """Points of ``a`` (turned by ``extra`` more: one turn or an array of them) on ``b``'s pixels."""
    box, ras = b.grid() if grid is None else grid
    ext = np.atleast_1d(np.asarray(extra, float)) + a.angle
    c, s = np.cos(ext), np.sin(ext)
    x, y = a.rel[:, 0], a.rel[:, 1]
    qx = np.rint(c[:, None] * x - s[:, None] * y + (a.pivot[0] - box[0])).astype(np.intp)
    qy = np.rint(s[:, None] * x + c[:, None] * y + (a.pivot[1] - box[1])).astype(np.intp)
    ok = (qx >= 0) & (qx < box[2]) & (qy >= 0) & (qy < box[3])
    hit = np.zeros(qx.shape, bool)
    hit[ok] = ras[qy[ok], qx[ok]]
    out = hit.sum(axis=1)
    return out if np.ndim(extra) else int(out[0])


def _allowed(a: _Placed, b: _Placed) -> float:
    """How many of ``a``'s points may lie within the clearance of ``b``: a share of them, and as many
    as in the source (parts packed closer than the clearance there stay as close)."""
    got = a._allowed.get(id(b))
    if got is None:
        got = a._allowed[id(b)] = _OVERLAP * a.n + a.source_overlap(b)
    return got


def _colliding(placed, pairs) -> tuple[list[tuple[int, int]], float]:
    """The ``pairs`` of placed parts that collide, and the pixels closer than allowed summed over them
    (both ways)."""
    if not pairs:
        return [], 0.0
    counts = _counts(placed)
    out, excess = [], 0.0
    for i, j in pairs:
        a, b = placed[i], placed[j]
        if counts[i, j] <= _OVERLAP * a.n and counts[j, i] <= _OVERLAP * b.n:
            continue  # (no more than any pair may have: the source's share is not needed)
        ea = counts[i, j] - _allowed(a, b)
        eb = counts[j, i] - _allowed(b, a)
        if ea > 0 or eb > 0:
            out.append((i, j))
            excess += max(ea, 0.0) * a.weight + max(eb, 0.0) * b.weight
    return out, excess


def _counts(placed) -> np.ndarray:
    """``c[k, l]``: points of part ``k`` within the clearance of part ``l`` (all pairs at once: each
    part's grown pixels are one bit of a shared canvas, 63 parts a canvas)."""
    n = len(placed)
    pts = [p.points() for p in placed]
    allp = np.vstack(pts)
    x0, y0 = np.floor(allp.min(axis=0)).astype(int) - 3 - _CLEAR
    x1, y1 = np.ceil(allp.max(axis=0)).astype(int) + 4 + _CLEAR
    box = (int(x0), int(y0), int(x1 - x0), int(y1 - y0))
    out = np.zeros((n, n), np.int64)
    q = [np.rint(p - (x0, y0)).astype(np.intp) for p in pts]
    for g0 in range(0, n, 63):
        group = range(g0, min(g0 + 63, n))
        bits = np.zeros((box[3], box[2]), np.int64)
        for j in group:
            p = placed[j]
            lo = np.floor(pts[j].min(axis=0)).astype(int) - 2 - _CLEAR
            hi = np.ceil(pts[j].max(axis=0)).astype(int) + 3 + _CLEAR
            sub = (int(lo[0]), int(lo[1]), int(hi[0] - lo[0]), int(hi[1] - lo[1]))
            ras = p.raster(sub)
            r0, c0 = sub[1] - y0, sub[0] - x0
            bits[r0:r0 + sub[3], c0:c0 + sub[2]] |= ras.astype(np.int64) << (j - g0)
        shifts = np.arange(len(group), dtype=np.int64)
        for k in range(n):
            vals = bits[q[k][:, 1], q[k][:, 0]]
            out[k, g0:g0 + len(group)] = ((vals[:, None] >> shifts) & 1).sum(axis=0)
    np.fill_diagonal(out, 0)
    return out


def _away(a: _Placed, b: _Placed) -> float:
    """+1 or -1: the sign of a turn of ``a`` about its pivot that moves it away from ``b``."""
    ca = a.points().mean(axis=0)
    cb = b.points().mean(axis=0)
    r = ca - a.pivot
    v = float(-r[1] * (ca - cb)[0] + r[0] * (ca - cb)[1])
    return 1.0 if v >= 0 else -1.0


def _separation(a: _Placed, b: _Placed, sign: float) -> float:
    """Least turn ``t`` (rad) of ``a`` away from ``b`` (by ``sign * t``) at which they no longer collide.

    Negative when they have room (``a`` may turn ``-t`` towards ``b``); in
    ``[-_MOST, _MOST]``. Found on a coarse fan of turns, then a fine one
    within the bracket (both evaluated at once).
    """
    grid_b = b.grid()
    tol_a = _allowed(a, b)
    t = np.linspace(-_MOST, _MOST, _COARSE)
    bad = _overlap(a, b, sign * t, grid_b) > tol_a
    if not bad.any():
        return float(-_MOST)
    last = int(np.flatnonzero(bad)[-1])
    if last == len(t) - 1:
        return float(_MOST)
    fine = np.linspace(t[last], t[last + 1], _FINE)
    bad = _overlap(a, b, sign * fine, grid_b) > tol_a
    return float(fine[int(np.flatnonzero(bad)[-1]) + 1])


def _solve(placed, active, rows, links) -> None:
    """Set the turns of the ``active`` parts (in place): the programme of the module, its constraints
    as a stiff penalty (squared excess, weight :data:`_STIFF`) so that parts with no room left (an
    infeasible system) settle on a compromise instead of swinging to their bounds."""
    pos = {k: j for j, k in enumerate(active)}
    lo = np.array([placed[k].lo for k in active])
    hi = np.array([placed[k].hi for k in active])
    lk = np.array([(pos[k], pos[m]) for k, m in links if k in pos and m in pos], int).reshape(-1, 2)
    A = np.zeros((len(rows), len(active)))
    b = np.zeros(len(rows))
    for r, (k, m, sk, sm, g) in enumerate(rows):
        A[r, pos[k]] += sk
        A[r, pos[m]] += sm
        b[r] = g + sk * placed[k].angle + sm * placed[m].angle

    n = len(active)
    q = np.eye(n)
    for a, c in lk:
        q[a, a] += _MU
        q[c, c] += _MU
        q[a, c] -= _MU
        q[c, a] -= _MU
    # semi-smooth Newton on the squared hinge: the violated constraints' normal equations, again
    # until the violated set settles; parts at a bound stay there
    x = np.clip([placed[k].angle for k in active], lo, hi)
    free = np.ones(n, bool)
    seen = None
    for _ in range(30):
        on = (b - A @ x) > 0.0
        key = (on.tobytes(), free.tobytes())
        if key == seen:
            break
        seen = key
        h = q + _STIFF * A[on].T @ A[on]
        rhs = _STIFF * A[on].T @ b[on]
        y = x.copy()
        fixed = ~free
        rhs_f = rhs[free] - h[np.ix_(free, fixed)] @ x[fixed]
        y[free] = np.linalg.solve(h[np.ix_(free, free)], rhs_f)
        out = (y < lo) | (y > hi)
        free &= ~out
        x = np.clip(y, lo, hi)
    for k, v in zip(active, x):
        placed[k].angle = float(v)
