"""Where roots start: a small learned model of an example's roots.

An example may hold several trees (a river map: one tree per river, all
draining to the coast). :func:`fit_roots` learns, for every root of the
example,

* its **kind**: on the boundary of the domain (the image border, or the
  edge of a region the branches do not enter, such as the sea), or
  *inside* the domain;
* for a boundary root, which boundary it starts on (one of the four image
  sides, or the region edge) and the angle between its initial direction
  and the boundary's inward normal; for an inside root its direction;
* how many roots there are.

:meth:`RootModel.sample` draws new starts ``(x, y, angle)`` in any domain:
every new root copies the kind of one example root (cycling through them
in a random order), starts at a random place on the same boundary (or
inside), spaced from the other starts like the example's roots are, and
heads into the domain with the copied angle to the inward normal.
"""

from __future__ import annotations

import hashlib
from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from ..core.random import as_rng
from ..core.structure import Structure

__all__ = ["RootModel", "boundary_frame", "fit_roots", "outlet_starts"]

_SIDES = ("top", "bottom", "left", "right", "region", "inside")
#: Start places considered per root (a random subset of the band on big domains).
_MAX_CANDIDATES = 4000


def boundary_frame(domain: np.ndarray):
    """Distance to the domain's boundary, the inward normal and the boundary class of every pixel.

    The boundary is the image border plus the edge of the pixels outside
    ``domain``. Returns ``(dist, normal_x, normal_y, side)`` with ``side``
    an index into ``("top", "bottom", "left", "right", "region")``: which
    boundary is nearest.

    Parameters
    ----------
    domain : (H, W) bool array_like
        The synthesis domain (True inside).

    Returns
    -------
    dist : (H, W) ndarray
        Euclidean distance (pixels) of each pixel to the nearest boundary
        pixel (0 outside the domain).
    normal_x, normal_y : (H, W) ndarray
        Unit inward normal: the gradient of the smoothed distance.
    side : (H, W) int8 ndarray
        Nearest boundary: 0 top, 1 bottom, 2 left, 3 right, 4 region edge.

    Examples
    --------
    >>> import numpy as np
    >>> dist, nx, ny, side = boundary_frame(np.ones((20, 30), bool))
    >>> float(dist[0, 15]), int(side[0, 15]), int(side[10, 29])
    (1.0, 0, 3)
    """
    return _boundary_frame(np.asarray(domain, bool))


def _boundary_frame(d: np.ndarray):
    h, w = d.shape
    padded = np.pad(d, 1, constant_values=False)
    dist, (iy, ix) = ndi.distance_transform_edt(padded, return_indices=True)
    dist, iy, ix = dist[1:-1, 1:-1], iy[1:-1, 1:-1] - 1, ix[1:-1, 1:-1] - 1
    sm = ndi.gaussian_filter(dist, 2.0)
    gy, gx = np.gradient(sm)
    n = np.hypot(gx, gy) + 1e-12
    side = np.full((h, w), 4, np.int8)
    side[iy <= -1] = 0
    side[iy >= h] = 1
    side[ix <= -1] = 2
    side[ix >= w] = 3
    return dist, gx / n, gy / n, side


@dataclass
class RootModel:
    """The learnt roots of an example (see the module docstring).

    Parameters
    ----------
    n_roots : int
        Number of roots (trees) in the example.
    sides : (R,) int ndarray
        Per example root: 0-3 image side, 4 region edge, 5 inside.
    offsets : (R,) ndarray
        Initial direction minus the inward normal (radians), boundary roots.
    directions : (R,) ndarray
        Initial direction (radians), inside roots.
    positions : (R, 2) ndarray
        Start points as fractions of the example's width and height.
    depth : (R,) ndarray
        Distance of each start to the boundary (pixels).
    spacing : float
        Median distance from a root start to the nearest other start, as a
        fraction of the example's diagonal (inf for one root).
    lengths : (R,) ndarray
        Root lengths (pixels); a start is only drawn where the initial
        heading stays in the domain for half the median root length.
    """

    n_roots: int
    sides: np.ndarray
    offsets: np.ndarray
    directions: np.ndarray
    positions: np.ndarray
    depth: np.ndarray
    spacing: float
    lengths: np.ndarray | None = None

    def _reach(self, h: int, w: int) -> float:
        med = float(np.median(self.lengths)) if self.lengths is not None and len(self.lengths) else 0.0
        return max(min(0.5 * med, 0.3 * min(h, w)), 4.0)

    def _frame(self, dom: np.ndarray):
        """:func:`boundary_frame` of ``dom``, kept for the last domain this model sampled in.

        A slider re-synthesizes in the same domain many times; its frame (a
        distance transform, ~20-70 ms at 1 MP) is found once per model and domain.
        """
        key = (dom.shape, hashlib.blake2b(np.packbits(dom).tobytes(), digest_size=16).digest())
        hit = self.__dict__.get("_frame_cache")
        if hit is None or hit[0] != key:
            out = boundary_frame(dom)
            for a in out:
                a.setflags(write=False)
            hit = (key, out)
            self.__dict__["_frame_cache"] = hit
        return hit[1]

    def _pieces(self, dom: np.ndarray) -> tuple[np.ndarray, np.ndarray] | None:
        """The domain's pieces large enough to hold a tree (:func:`.growth_pieces.domain_pieces`) and, for
        every pixel, the label of the nearest one; None when there is only one (kept like :meth:`_frame`)."""
        from .growth_pieces import domain_pieces

        key = (dom.shape, hashlib.blake2b(np.packbits(dom).tobytes(), digest_size=16).digest())
        hit = self.__dict__.get("_pieces_cache")
        if hit is None or hit[0] != key:
            lab = domain_pieces(dom)
            out = None
            if lab is not None:
                _d, (iy, ix) = ndi.distance_transform_edt(lab == 0, return_indices=True)
                out = (lab, lab[iy, ix])
            hit = (key, out)
            self.__dict__["_pieces_cache"] = hit
        return hit[1]

    def sample(self, domain: np.ndarray, rng=None, n: int | None = None,
               min_depth: float = 2.0) -> list[tuple[float, float, float]]:
        """Draw ``n`` (default ``n_roots``) starts ``(x, y, angle)`` in ``domain`` ((H, W) bool).

        Parameters
        ----------
        domain : (H, W) bool array_like
            Where the new structure grows (True inside).
        rng : {numpy.random.Generator, int}, optional
            Random generator or seed.
        n : int, optional
            Number of starts; None = ``n_roots`` (the example's count).
        min_depth : float, default 2.0
            Smallest distance (pixels) of a start from the boundary.

        Returns
        -------
        list of (x, y, angle)
            Start position (pixels) and initial heading (radians) of each root;
            empty when ``n <= 0`` or the domain is empty.
        """
        rng = as_rng(rng)
        dom = np.asarray(domain, bool)
        h, w = dom.shape
        n = self.n_roots if n is None else int(n)
        if n <= 0 or not dom.any():
            return []
        dist, nx, ny, side = self._frame(dom)
        diag = float(np.hypot(h, w))
        spacing = self.spacing * diag if np.isfinite(self.spacing) else 0.0
        order = np.concatenate([rng.permutation(self.n_roots) for _ in range(n // self.n_roots + 1)])[:n]
        pieces = self._pieces(dom)
        starts: list[tuple[float, float, float]] = []
        for j in order:
            kind = int(self.sides[j])
            depth = max(float(self.depth[j]), min_depth)
            where = dom
            if pieces is not None:
                # a domain of separate pieces (islands): the root starts on the piece nearest to where
                # the example's did, so each island gets its own trees (beyond the paper, issue 23: a
                # broad pull towards the example's place put an island's tree on its neighbour, and
                # three islands 50 px apart at 512 px got 4, 1 and 0 trees for the example's 2, 1, 2)
                qx, qy = self.positions[j] * (w, h)
                where = pieces[0] == pieces[1][int(np.clip(qy, 0, h - 1)), int(np.clip(qx, 0, w - 1))]
            if kind == 5:
                band = where & (dist >= max(depth * 0.5, min_depth))
            else:
                band = where & (np.abs(dist - depth) <= 1.0) & (side == kind)
                if not band.any():  # that boundary does not exist here: any boundary
                    band = where & (np.abs(dist - depth) <= 1.0)
            ys, xs = np.nonzero(band)
            if len(ys) == 0:
                ys, xs = np.nonzero(where)
            if len(ys) > _MAX_CANDIDATES:
                # a random subset is as good a choice and keeps the spacing test cheap on big maps
                keep = rng.choice(len(ys), _MAX_CANDIDATES, replace=False)
                ys, xs = ys[keep], xs[keep]
            # Prefer places near the example root (relative position), more
            # spread the more roots share that kind; keep the spacing.
            same = max(int(np.sum(self.sides == kind)), 1)
            sig = 0.3 * diag / np.sqrt(same) if kind != 5 else 0.2 * diag / np.sqrt(same)
            if same == 1 and self.n_roots == 1:
                # one tree (a delta's trunk, a vessel tree): it enters about where the example's does
                # (within ~7 % of the diagonal; at 10 % a delta's trunk entering mid-side came in
                # next to a corner in one seed of six and ran down the land's edge)
                sig = 0.035 * diag
            px, py = self.positions[j] * (w, h)
            wgt = np.exp(-((xs - px) ** 2 + (ys - py) ** 2) / (2 * sig ** 2)) + 1e-9
            if starts:
                st = np.array([(x, y) for x, y, _ in starts])
                dmin = np.sqrt(((xs[:, None] - st[None, :, 0]) ** 2 +
                                (ys[:, None] - st[None, :, 1]) ** 2).min(1))
                far = dmin >= 0.8 * spacing
                if far.any():
                    wgt = wgt * far
                else:
                    wgt = wgt * (dmin / (dmin.max() + 1e-9)) ** 4 + 1e-12
            if kind == 5:
                ang = np.full(len(ys), float(self.directions[j]) + rng.normal(0, 0.2))
            else:
                ang = np.arctan2(ny[ys, xs], nx[ys, xs]) + self.offsets[j] + rng.normal(0, 0.1)
            # the heading must stay in the domain for a while (no root walks out at once)
            reach = self._reach(h, w)
            ok = np.ones(len(ys), bool)
            for f in (0.25, 0.5, 0.75, 1.0):
                px_ = np.rint(xs + f * reach * np.cos(ang)).astype(np.int64)
                py_ = np.rint(ys + f * reach * np.sin(ang)).astype(np.int64)
                inside = (px_ >= 0) & (px_ < w) & (py_ >= 0) & (py_ < h)
                ok &= inside
                ok[inside] &= dom[py_[inside], px_[inside]]
            if ok.any():
                wgt = wgt * ok + 1e-12 * ~ok
            k = int(rng.choice(len(ys), p=wgt / wgt.sum()))
            y, x = int(ys[k]), int(xs[k])
            starts.append((float(x), float(y), float(ang[k])))
        return starts


def fit_roots(structure: Structure, domain: np.ndarray | None = None, shape=None,
              boundary_distance: float | None = None) -> RootModel:
    """Learn the roots of ``structure`` (see :class:`RootModel`).

    Parameters
    ----------
    structure : Structure
        The example (vertices in pixels); its branches without a parent
        are the roots.
    domain : (H, W) bool ndarray, optional
        Where the branches may grow (default: the whole image).
    shape : (H, W), optional
        Default: ``structure.image_shape`` or its bounds.
    boundary_distance : float, optional
        A root starting closer than this to the boundary is a boundary
        root (default: ``max(12, 4 r0, 1.5 %`` of the diagonal``)`` pixels,
        ``r0`` its first radius: a drawn map's rivers end a few pixels short
        of the coast line; by default a root up to 1.5 x that far counts too
        when it is within 15 % of the domain's deepest point's depth).

    Notes
    -----
    Going beyond the paper, which roots every tree where its root branch
    starts: with a ``domain`` that has an edge inside the image (a map's
    coast), a tree rooted inland or at the frame whose branches reach that
    edge at one end is learnt as rooted at that end, heading back along its
    branch (see :func:`outlet_starts`): a tracer that split a drawn river
    network at its junctions roots some rivers at a source, and learnt as
    such they grew rivers floating inland that never met the coast.

    Examples
    --------
    >>> from branchnb.core.structure import Branch, Structure
    >>> s = Structure([Branch([(50, 1), (50, 60)], 2.0)], image_shape=(100, 100))
    >>> rm = fit_roots(s)
    >>> rm.n_roots, _SIDES[int(rm.sides[0])], round(float(rm.offsets[0]), 2)
    (1, 'top', 0.0)
    """
    if domain is not None:
        dom = np.asarray(domain, bool)
    else:
        if shape is None:
            shape = structure.image_shape
        if shape is None:
            _x0, _y0, x1, y1 = structure.bounds()
            shape = (int(np.ceil(y1)) + 2, int(np.ceil(x1)) + 2)
        dom = np.ones(tuple(int(v) for v in shape[:2]), bool)
    h, w = dom.shape
    dist, nx, ny, side = boundary_frame(dom)
    roots = [b for b in structure.branches if b.parent is None and len(b.points) >= 2]
    region = domain is not None and dom.any() and not dom.all()
    outlets = _outlet_ends(structure, dist, side, boundary_distance) if region else {}
    sides, offs, dirs, pos, depth = [], [], [], [], []
    for b in roots:
        if id(b) in outlets:
            # the tree's mouth is the end of one of its branches, not its root (see _outlet_ends)
            pts = outlets[id(b)]
        else:
            pts = b.points
        x, y = pts[0]
        ix, iy = int(np.clip(round(x), 0, w - 1)), int(np.clip(round(y), 0, h - 1))
        # initial direction over the first ~12 px
        arc = np.r_[0.0, np.cumsum(np.hypot(*np.diff(pts, axis=0).T))]
        k = int(np.clip(np.searchsorted(arc, 12.0), 1, len(pts) - 1))
        d = pts[k] - pts[0]
        ang = float(np.arctan2(d[1], d[0]))
        on_boundary = _on_boundary(float(dist[iy, ix]), float(b.thickness[0]), dist, boundary_distance)
        sides.append(int(side[iy, ix]) if on_boundary else 5)
        inward = float(np.arctan2(ny[iy, ix], nx[iy, ix]))
        offs.append(float(np.angle(np.exp(1j * (ang - inward)))))
        dirs.append(ang)
        pos.append((x / w, y / h))
        depth.append(float(dist[iy, ix]))
    pos_a = np.array(pos, float).reshape(-1, 2)
    if len(pos_a) > 1:
        pxy = pos_a * (w, h)
        dd = np.hypot(*(pxy[:, None] - pxy[None]).transpose(2, 0, 1))
        np.fill_diagonal(dd, np.inf)
        spacing = float(np.median(dd.min(1)) / np.hypot(h, w))
    else:
        spacing = float("inf")
    # a boundary root heads into the domain: never more than 80 degrees off the normal
    offs_a = np.clip(np.array(offs, float), -1.4, 1.4)
    return RootModel(len(roots), np.array(sides, np.int64), offs_a, np.array(dirs, float), pos_a,
                     np.array(depth, float), spacing, np.array([b.length for b in roots], float))


def _limit(r0: float, shape, boundary_distance) -> float:
    """How close to the boundary a root starts when it is a boundary root (see :func:`fit_roots`)."""
    h, w = shape
    return boundary_distance if boundary_distance is not None else \
        max(12.0, 4.0 * r0, 0.015 * float(np.hypot(h, w)))


def _on_boundary(d: float, r0: float, dist: np.ndarray, boundary_distance) -> bool:
    # a drawn map's rivers stop short of the coast line (its ink, the extraction's margin)
    lim = _limit(r0, dist.shape, boundary_distance)
    # a mouth a little past that limit is still a mouth when it is shallow for the domain
    # (its deepest point far inland): 12.4 px short of a bay's coast is no inside root
    return d <= lim or (boundary_distance is None and d <= min(1.5 * lim, 0.15 * float(dist.max())))


def _outlet_ends(structure: Structure, dist: np.ndarray, side: np.ndarray, boundary_distance) -> dict:
    """Trees rooted inland whose mouth is the end of one of their branches: ``{id(root): points}``,
    the points of that branch from its end back (the way the river flows out, reversed).

    Going beyond the paper: a tracer that splits a drawn river network at its junctions
    may root a tree at a source and reach the coast with a child (or the root's own far end).
    Such a tree is an outlet: rooted inland, it would teach synthesis to grow rivers that
    float inland and never reach the coast. A tree rooted inland or at the image frame with
    exactly one branch end at the region boundary is taken as that kind; one with several ends
    there drains at the one nearest the boundary when at least two thirds of the trees drain at
    the boundary (two rivers joined at a source), and is left as it is otherwise (a delta's
    trunk, whose distributaries end at the sea); one with none (a lake's river) is left as it is."""
    h, w = dist.shape

    def px(p):
        x, y = np.clip(np.rint(np.asarray(p, float)).astype(int), 0, [w - 1, h - 1])
        return y, x

    def at_edge(p, r):   # within reach of the region's edge (side 4), not of the frame
        return side[px(p)] == 4 and _on_boundary(float(dist[px(p)]), r, dist, boundary_distance)

    br = structure.branches
    inland = [i for i, b in enumerate(br) if b.parent is None and len(b.points) >= 2
              and not at_edge(b.points[0], float(b.thickness[0]))]
    if not inland:
        return {}
    tree = {}
    for i in range(len(br)):
        j, seen = i, 0
        while br[j].parent is not None and seen <= len(br):
            j, seen = br[j].parent, seen + 1
        tree.setdefault(j, []).append(i)
    out, several = {}, {}
    for i in inland:
        ends = [np.asarray(br[m].points, float) for m in tree.get(i, []) if len(br[m].points) >= 2]
        ends = [pts for pts, m in zip(ends, tree.get(i, []))
                if at_edge(pts[-1], float(br[m].thickness[-1]))]
        if len(ends) == 1:
            out[id(br[i])] = ends[0][::-1]
        elif ends:
            several[id(br[i])] = min(ends, key=lambda q: float(dist[px(q[-1])]))[::-1]
    # several ends at the edge: two rivers the tracer joined at a source, when (almost) every other
    # tree of the example drains at the edge (in a delta, where the trunk comes from inland, not)
    n_roots = sum(b.parent is None and len(b.points) >= 2 for b in br)
    if several and n_roots - len(inland) + len(out) >= 2 / 3 * n_roots:
        out.update(several)
    return out


def outlet_starts(structure: Structure, domain: np.ndarray) -> list[np.ndarray]:
    """Where every tree of ``structure`` drains: its root's first point, or for a tree rooted
    inland with exactly one branch end at the boundary of ``domain`` ((H, W) bool), that end
    (see :func:`fit_roots`); one (x, y) point per root, in the order of the roots.

    Parameters
    ----------
    structure : Structure
        The extracted or synthesized structure.
    domain : (H, W) bool ndarray
        The land (the region the rivers grow in); outside it is sea.

    Returns
    -------
    list of (2,) float ndarray
        The outlet (x, y) of each root tree, in the order of the roots.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.core.structure import Branch, Structure
    >>> dom = np.zeros((60, 60), bool); dom[:50] = True       # sea below y = 50
    >>> s = Structure([Branch([(30, 10), (30, 48)], 1.0)], image_shape=(60, 60))
    >>> [p.tolist() for p in outlet_starts(s, dom)]           # rooted at its source: the mouth
    [[30.0, 48.0]]
    """
    dom = np.asarray(domain, bool)
    dist, _nx, _ny, side = boundary_frame(dom)
    region = dom.any() and not dom.all()
    outlets = _outlet_ends(structure, dist, side, None) if region else {}
    return [np.asarray(outlets[id(b)][0] if id(b) in outlets else b.points[0], float)
            for b in structure.branches if b.parent is None]
