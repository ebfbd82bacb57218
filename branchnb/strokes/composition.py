"""Graph-cut composition of the overlapping copied textures.

The patches are laid down one after the other (stroke by stroke, parents
before the branches that start on them, samples in stroke order). When a
patch ``b`` lands on the canvas ``a`` built so far, the pixels of their
overlap are labelled by a graph cut (:func:`branchnb.core.graphcut.seam_cut`,
PyMaxflow):

* data term: the overlap pixels bordering the part only ``a`` covers are
  pinned to ``a``, those bordering the part only ``b`` covers are pinned
  to ``b`` (hard constraints), so the composite has no seam on the
  overlap's boundary;
* smoothness term: cutting between neighbours ``x``, ``y`` costs
  ``(d(x) + d(y)) / G(x, y)`` with ``d = ||a - b|| ** power`` and
  ``G(x, y) = |grad a(x)| + |grad b(x)| + |grad a(y)| + |grad b(y)|``,
  so seams run where the two textures agree and along image edges.

A patch lying entirely on already covered pixels (a stroke crossing
another one) has no "only b" part; its central disk of radius ``r / 2``
is then pinned to ``b`` so it shows on top, except for the patches of a
branch at its junction (``pin_core=False``), which may vanish under the
parent. Junction patches can also protect canvas pixels (``keep_a``) the
branch must not paint over.

``method="overlay"`` is the baseline: same pins, but ``b`` simply covers
the rest of the overlap.

Colours are premultiplied RGBA throughout, so the silhouette is cut like
any other texture edge.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from ..core.graphcut import _pair_costs, _seam_cost, _seam_cut
from ..core.validate import Array, Choice, Int, Real, Shape, checked

__all__ = ["PlacedPatch", "Composition", "compose", "labelling_cost", "seam_mask"]


@dataclass
class PlacedPatch:
    """One copied texture in the target frame.

    Parameters
    ----------
    pixels : (S, S, 4) float32 ndarray
        Premultiplied RGBA.
    valid : (S, S) bool ndarray
        Pixels the patch covers.
    origin : (int, int)
        Target ``(x, y)`` of ``pixels[0, 0]``.
    pin_core : bool
        Pin the central disk to the patch when nothing else pins it.
    keep_a : (S, S) bool ndarray or None
        Pixels that must keep what the canvas has there (if covered). Where
        the canvas is still empty the patch fills them, but only until a
        later patch without ``keep_a`` there covers them (see :func:`compose`).
    source_map : (2, 3) ndarray or None
        Where the patch came from: target ``(x, y)`` -> source ``(x, y)``.
    grow : bool
        The patch's object pixels win over the canvas's transparent ones
        (a branch or a carried part joins its parent: it adds to the
        silhouette, the seam may not cut it short at the parent's margin).
    stroke : int
        Index of the stroke (part) the patch belongs to, -1 for none. Where
        it overlaps pixels another stroke laid, the two bodies are united:
        opaque wins over transparent either way (a part moved over another
        part leaves no hole in either; beyond the paper, whose patches are
        opaque texture).
    behind : (S, S) bool ndarray or None
        Pixels copied from where another part hid the stroke in the source
        (filled in, see :mod:`~branchnb.strokes.hidden`): they lie under
        every other stroke's or part's opaque pixels, whichever is laid first.

    Examples
    --------
    >>> p = PlacedPatch(np.ones((4, 4, 4), np.float32), np.ones((4, 4), bool), (-2, 1))
    >>> canvas, pix, val, keep = p.placed((10, 10))
    >>> canvas, pix.shape, int(val.sum())
    ((slice(1, 5, None), slice(0, 2, None)), (4, 2, 4), 8)
    """

    pixels: np.ndarray
    valid: np.ndarray
    origin: tuple[int, int]
    pin_core: bool = True
    keep_a: np.ndarray | None = None
    source_map: np.ndarray | None = None
    grow: bool = False
    stroke: int = -1
    behind: np.ndarray | None = None

    def __post_init__(self):
        px = np.asarray(self.pixels)
        if px.ndim != 3 or px.shape[2] != 4 or px.shape[0] != px.shape[1] or px.dtype.kind not in "fiub":
            raise ValueError(f"pixels must be a real (S, S, 4) array, got {px.dtype} {px.shape}")
        if not np.isfinite(px).all():
            raise ValueError("pixels contain NaN or inf")
        if np.shape(self.valid) != px.shape[:2]:
            raise ValueError(f"pixels {px.shape[:2]} and valid {np.shape(self.valid)} must cover the same S x S square")
        if self.keep_a is not None and np.shape(self.keep_a) != px.shape[:2]:
            raise ValueError(f"keep_a must have shape {px.shape[:2]}, got {np.shape(self.keep_a)}")
        if self.behind is not None and np.shape(self.behind) != px.shape[:2]:
            raise ValueError(f"behind must have shape {px.shape[:2]}, got {np.shape(self.behind)}")
        for flag in ("pin_core", "grow"):
            if not isinstance(getattr(self, flag), (bool, np.bool_)):
                raise TypeError(f"{flag} must be a bool, got {type(getattr(self, flag)).__name__}")
        if not isinstance(self.stroke, (int, np.integer)) or isinstance(self.stroke, bool) or self.stroke < -1:
            raise TypeError(f"stroke must be an int >= -1, got {self.stroke!r}")
        if self.source_map is not None:
            sm = np.asarray(self.source_map)
            if sm.shape != (2, 3) or sm.dtype.kind not in "fiu" or not np.isfinite(sm).all():
                raise ValueError(f"source_map must be a finite (2, 3) affine map or None, got {sm.dtype} {sm.shape}")
        o = self.origin
        if (not isinstance(o, (tuple, list, np.ndarray)) or len(o) != 2
                or not all(isinstance(v, (int, np.integer)) and not isinstance(v, bool) for v in o)):
            raise ValueError(f"origin must be two ints (x, y), got {o!r}")
        if max(abs(int(v)) for v in o) > 10**7:
            raise ValueError(f"origin lies too far away: {o!r}")

    @checked(shape=Shape(), margin=Int(0, 10_000))
    def window(self, shape, margin: int = 0):
        """Slices of the canvas and of the patch for the patch's box grown by ``margin``.

        Returns ``(canvas_slices, patch_slices, box_shape, offset)`` where
        the patch pixels land at ``offset`` inside the box.

        Parameters
        ----------
        shape : tuple of int
            Canvas shape ``(H, W, ...)``.
        margin : int
            Pixels (>= 0) to grow the box by on each side (clipped to the canvas).

        Returns
        -------
        tuple or None
            ``(canvas_slices, patch_slices, inner_slices)``: where the box lies on
            the canvas, which part of the patch lands on the canvas, and where
            that part lies inside the box; None when the patch misses the canvas.
        """
        h, w = shape[:2]
        x0, y0 = self.origin
        s = self.valid.shape[0]
        r0, r1 = max(y0 - margin, 0), min(y0 + s + margin, h)
        c0, c1 = max(x0 - margin, 0), min(x0 + s + margin, w)
        if r0 >= r1 or c0 >= c1:
            return None
        pr0, pr1 = max(r0, y0), min(r1, y0 + s)
        pc0, pc1 = max(c0, x0), min(c1, x0 + s)
        canvas = (slice(r0, r1), slice(c0, c1))
        patch = (slice(pr0 - y0, pr1 - y0), slice(pc0 - x0, pc1 - x0))
        inner = (slice(pr0 - r0, pr1 - r0), slice(pc0 - c0, pc1 - c0))
        return canvas, patch, inner

    @checked(canvas_shape=Shape(), margin=Int(0, 10_000))
    def placed(self, canvas_shape, margin: int = 0):
        """``(box_slices, pixels, valid, keep_a)`` of the patch on its (clipped) box.

        Parameters
        ----------
        canvas_shape : tuple of int
            Canvas shape ``(H, W, ...)``.
        margin : int
            Pixels (>= 0) the box extends beyond the patch (for the graph cut's
            neighbourhood); empty there.

        Returns
        -------
        tuple or None
            ``(box_slices, pixels (h, w, 4) float32, valid (h, w) bool, keep_a
            (h, w) bool)``; None when the patch misses the canvas.
        """
        win = self.window(canvas_shape, margin)
        if win is None:
            return None
        canvas, patch, inner = win
        bh = canvas[0].stop - canvas[0].start
        bw = canvas[1].stop - canvas[1].start
        pix = np.zeros((bh, bw, 4), np.float32)
        val = np.zeros((bh, bw), bool)
        keep = np.zeros((bh, bw), bool)
        pix[inner] = self.pixels[patch]
        val[inner] = self.valid[patch]
        if self.keep_a is not None:
            keep[inner] = self.keep_a[patch]
        return canvas, pix, val, keep

    def _behind_on(self, canvas, box_shape) -> np.ndarray | None:
        """:attr:`behind` on the box :meth:`placed` returned (``canvas`` its slices)."""
        if self.behind is None:
            return None
        out = np.zeros(box_shape, bool)
        x0, y0 = self.origin
        s = self.valid.shape[0]
        r0, c0 = canvas[0].start, canvas[1].start
        pr0, pr1 = max(r0, y0), min(canvas[0].stop, y0 + s)
        pc0, pc1 = max(c0, x0), min(canvas[1].stop, x0 + s)
        out[pr0 - r0:pr1 - r0, pc0 - c0:pc1 - c0] = self.behind[pr0 - y0:pr1 - y0, pc0 - x0:pc1 - x0]
        return out


@dataclass
class Composition:
    """The composed canvas.

    Parameters
    ----------
    image : (H, W, 4) float32 ndarray
        Premultiplied RGBA.
    covered : (H, W) bool ndarray
        Pixels some patch covers.
    labels : (H, W) int ndarray
        Index of the patch each pixel comes from (-1 where none).
    step_costs : (P,) ndarray
        Seam cost of each patch's cut against the canvas when it was laid.

    Examples
    --------
    >>> a = PlacedPatch(np.ones((3, 3, 4), np.float32), np.ones((3, 3), bool), (0, 0))
    >>> c = compose([a], (4, 4))
    >>> int(c.covered.sum()), int(c.labels[3, 3]), c.step_costs.tolist()
    (9, -1, [0.0])
    """

    image: np.ndarray
    covered: np.ndarray
    labels: np.ndarray
    step_costs: np.ndarray


@checked(shape=Shape(), method=Choice("graphcut", "overlay"), power=Real(0, 16, low_open=True))
def compose(patches: list[PlacedPatch], shape, *, method: str = "graphcut",
            power: float = 1.0, gradient_weighted: bool = True) -> Composition:
    """Lay ``patches`` down in order on an empty canvas of ``shape`` (H, W).

    Parameters
    ----------
    patches : list of PlacedPatch
        In laying order (parents before their branches, samples along each
        stroke); patch ``i`` gets label ``i``.
    shape : tuple of int
        Canvas ``(H, W, ...)``; parts of patches outside it are dropped.
    method : {"graphcut", "overlay"}
        "graphcut" (the paper's composition): a minimum seam through each
        overlap; "overlay": the new patch covers the unpinned overlap.
    power : float
        Exponent on the colour difference ``d = ||a - b|| ** power`` (> 0); 1.
    gradient_weighted : bool
        Divide the seam cost by the edge strength ``G`` (seams follow edges).

    Returns
    -------
    Composition
        ``step_costs[i]`` is 0 for a patch without overlap.

    Notes
    -----
    Beyond the paper: pixels a patch laid under its ``keep_a`` (the
    canvas was empty there) are given up to the next patch that covers
    them without ``keep_a`` -- a branch's turned cut face fills its
    parent's interior only where none of the parent's own pixels (e.g. a
    carried part's, laid later) come.

    Examples
    --------
    >>> import numpy as np
    >>> a = PlacedPatch(np.zeros((5, 5, 4), np.float32), np.ones((5, 5), bool), (0, 0))
    >>> b = PlacedPatch(np.ones((5, 5, 4), np.float32), np.ones((5, 5), bool), (3, 0))
    >>> c = compose([a, b], (5, 8))
    >>> c.labels[0].tolist()
    [0, 0, 0, 0, 1, 1, 1, 1]
    """
    if method not in ("graphcut", "overlay"):
        raise ValueError(f"composition must be 'graphcut' or 'overlay', got {method!r}")
    h, w = shape[:2]
    image = np.zeros((h, w, 4), np.float32)
    covered = np.zeros((h, w), bool)
    labels = np.full((h, w), -1, np.int64)
    weak = np.zeros((h, w), bool)  # laid under keep_a on an empty canvas: later patches take them
    owner = np.full((h, w), -1, np.int64)  # the stroke whose patch laid each pixel
    under = np.zeros((h, w), bool)  # laid from a stroke's hidden stretch (PlacedPatch.behind)
    costs = np.zeros(len(patches))
    for i, patch in enumerate(patches):
        pl = patch.placed((h, w), margin=1)
        if pl is None:
            continue
        box, b, vb, keep = pl
        a = image[box]
        cov = covered[box]
        overlap = cov & vb
        only_a = cov & ~vb
        only_b = vb & ~cov
        if not overlap.any():
            take_b = only_b
        else:
            yield_ = overlap & weak[box] & ~keep
            pin_a = ((ndi.binary_dilation(only_a) & overlap) | (keep & overlap)) & ~yield_
            pin_b = (ndi.binary_dilation(only_b) & overlap & ~pin_a) | yield_
            union = overlap if patch.grow else None
            if patch.stroke >= 0:
                # two parts overlapping (one moved over the other): their union
                own = owner[box]
                cross = overlap & (own >= 0) & (own != patch.stroke)
                union = cross if union is None else union | cross
            if union is not None and union.any():
                # a joint is the union of the two: opaque wins over transparent either way
                pin_a |= union & (a[..., 3] > 0.5) & (b[..., 3] < 0.02) & ~pin_b
                pin_b |= union & (b[..., 3] > 0.5) & (a[..., 3] < 0.5) & ~pin_a
            bh = patch._behind_on(box, vb.shape)
            if bh is not None or under[box].any():
                # what another part hid in the source stays under that part's (or any other
                # stroke's) opaque pixels, whichever comes first
                opaque_a, opaque_b = a[..., 3] > 0.5, b[..., 3] > 0.5
                give = overlap & under[box] & opaque_b
                hold = overlap & opaque_a & ~under[box] & (owner[box] != patch.stroke) if bh is not None \
                    else np.zeros_like(overlap)
                if bh is not None:
                    give &= ~bh
                    hold &= bh
                pin_a = (pin_a & ~give) | hold
                pin_b = (pin_b & ~hold) | give
            if not only_b.any() and patch.pin_core:
                pin_b = _core(vb) & overlap & ~pin_a
            # (pair_costs' own conversion -- float32, clipped to [0, 1] -- without its checks:
            # the canvas and the patches are float images already; the same values)
            pc = _pair_costs(np.clip(np.asarray(a, np.float32), 0.0, 1.0),
                             np.clip(np.asarray(b, np.float32), 0.0, 1.0), power, gradient_weighted)
            if method == "overlay":
                take_b = only_b | (overlap & ~pin_a)
            else:
                # (seam_cut's checks skipped: bool masks of the box's shape, the pins
                # disjoint by construction and kept within the overlap here)
                take_b = only_b | _seam_cut(*pc, overlap, pin_a & overlap, pin_b & overlap)
            costs[i] = _seam_cost(*pc, take_b, overlap)
        image[box][take_b] = b[take_b]
        labels[box][take_b] = i
        weak[box][take_b] = keep[take_b]
        owner[box][take_b] = patch.stroke
        if patch.behind is not None or under[box].any():
            bh = patch._behind_on(box, vb.shape)
            under[box][take_b] = False if bh is None else bh[take_b]
        covered[box] |= vb
    return Composition(image, covered, labels, costs)


def _core(valid: np.ndarray) -> np.ndarray:
    depth = ndi.distance_transform_edt(valid)
    return depth > depth.max() / 2


@checked(labels=Array(ndim=2, dtype=np.int64), alpha=Array(ndim=2), min_alpha=Real(0, 1))
def seam_mask(labels: np.ndarray, alpha: np.ndarray | None = None,
              min_alpha: float = 0.1) -> np.ndarray:
    """Pixels next to a 4-neighbour from another patch (seams), optionally only on the object.

    A pair of neighbours counts if both are covered and, when ``alpha``
    is given, at least one of them has ``alpha > min_alpha`` (seams through
    empty background are invisible).

    Parameters
    ----------
    labels : (H, W) int ndarray
        Patch index per pixel, -1 where uncovered (:attr:`Composition.labels`).
    alpha : (H, W) ndarray, optional
        Object opacity; with it, seams with both sides below ``min_alpha``
        are dropped.
    min_alpha : float
        Opacity in [0, 1] from which a pixel counts as object; 0.1.

    Returns
    -------
    (H, W) bool ndarray
        Both pixels of every cut neighbour pair are True.

    Examples
    --------
    >>> lab = np.array([[0, 0, 1], [0, 0, 1]])
    >>> seam_mask(lab).astype(int).tolist()
    [[0, 1, 1], [0, 1, 1]]
    """
    lab = labels
    out = np.zeros(lab.shape, bool)
    if alpha is not None and alpha.shape != lab.shape:
        raise ValueError(f"alpha must have the shape of labels {lab.shape}, got {alpha.shape}")
    vis = np.ones(lab.shape, bool) if alpha is None else alpha > min_alpha
    for ax in (0, 1):
        a = lab.take(range(lab.shape[ax] - 1), axis=ax)
        b = lab.take(range(1, lab.shape[ax]), axis=ax)
        va = vis.take(range(lab.shape[ax] - 1), axis=ax)
        vb = vis.take(range(1, lab.shape[ax]), axis=ax)
        cut = (a != b) & (a >= 0) & (b >= 0) & (va | vb)
        if ax == 0:
            out[:-1] |= cut
            out[1:] |= cut
        else:
            out[:, :-1] |= cut
            out[:, 1:] |= cut
    return out


@checked(labels=Array(ndim=2, dtype=np.int64), power=Real(0, 16, low_open=True))
def labelling_cost(patches: list[PlacedPatch], labels: np.ndarray, *, power: float = 1.0,
                   gradient_weighted: bool = True) -> float:
    """Total seam cost of the final labelling (history independent).

    For every pair of patches ``i``, ``j`` whose pixels touch in
    ``labels``, the cost of their common seam is
    :func:`branchnb.core.graphcut.seam_cost` between the two patches,
    counted on the neighbour pairs both patches cover. This is the
    measure graph-cut and overlay composition are compared with.

    Parameters
    ----------
    patches : list of PlacedPatch
        The patches ``labels`` refers to (non-empty).
    labels : (H, W) int ndarray
        Patch index per pixel, -1 where uncovered.
    power : float
        Exponent on the colour difference (> 0); 1.
    gradient_weighted : bool
        Divide by the edge strength, as in :func:`compose`.

    Returns
    -------
    float
        Sum over touching patch pairs; 0 for a single patch.

    Raises
    ------
    ValueError
        If ``patches`` is empty or ``labels`` names a patch that is not there.

    Examples
    --------
    >>> a = PlacedPatch(np.zeros((5, 5, 4), np.float32), np.ones((5, 5), bool), (0, 0))
    >>> b = PlacedPatch(np.ones((5, 5, 4), np.float32), np.ones((5, 5), bool), (3, 0))
    >>> c = compose([a, b], (5, 8))
    >>> bool(labelling_cost([a, b], c.labels) > 0), labelling_cost([a, a], c.labels)
    (True, 0.0)
    """
    lab = np.asarray(labels)
    h, w = lab.shape
    if not len(patches):
        raise ValueError("patches is empty")
    if lab.size and lab.max() >= len(patches):
        raise ValueError(f"labels refer to patch {int(lab.max())} but there are {len(patches)} patches")
    pairs = set()
    for a, b in ((lab[:, :-1], lab[:, 1:]), (lab[:-1, :], lab[1:, :])):
        m = (a != b) & (a >= 0) & (b >= 0)
        if m.any():
            lo = np.minimum(a[m], b[m])
            hi = np.maximum(a[m], b[m])
            pairs.update(zip(lo.tolist(), hi.tolist()))
    total = 0.0
    for i, j in pairs:
        pi, pj = patches[i], patches[j]
        (xi, yi), (xj, yj) = pi.origin, pj.origin
        si, sj = pi.valid.shape[0], pj.valid.shape[0]
        x0, y0 = max(xi, xj, 0), max(yi, yj, 0)
        x1, y1 = min(xi + si, xj + sj, w), min(yi + si, yj + sj, h)
        if x1 - x0 < 1 or y1 - y0 < 1:
            continue
        a = pi.pixels[y0 - yi:y1 - yi, x0 - xi:x1 - xi]
        b = pj.pixels[y0 - yj:y1 - yj, x0 - xj:x1 - xj]
        va = pi.valid[y0 - yi:y1 - yi, x0 - xi:x1 - xi]
        vb = pj.valid[y0 - yj:y1 - yj, x0 - xj:x1 - xj]
        sub = lab[y0:y1, x0:x1]
        region = va & vb & ((sub == i) | (sub == j))
        # only the i-j seam's pixels count: the cost is taken on their box grown by
        # 2 px (the Sobel edge strength needs 1 px round a pixel: the same values)
        take = sub == j
        cut = np.zeros(take.shape, bool)
        hz = (take[:, :-1] != take[:, 1:]) & region[:, :-1] & region[:, 1:]
        vt = (take[:-1, :] != take[1:, :]) & region[:-1, :] & region[1:, :]
        cut[:, :-1] |= hz
        cut[:, 1:] |= hz
        cut[:-1, :] |= vt
        cut[1:, :] |= vt
        rs, cs = np.nonzero(cut)
        if not len(rs):
            continue
        box = (slice(max(rs.min() - 2, 0), rs.max() + 3), slice(max(cs.min() - 2, 0), cs.max() + 3))
        # (seam_cost's conversion -- float32, clipped to [0, 1] -- without its checks, as in
        # compose: the patches are float images already; the same values)
        pc = _pair_costs(np.clip(np.asarray(a[box], np.float32), 0.0, 1.0),
                         np.clip(np.asarray(b[box], np.float32), 0.0, 1.0), power, gradient_weighted)
        total += _seam_cost(*pc, take[box], region[box])
    return total
