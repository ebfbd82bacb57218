"""Side outline cards: the side silhouette's ink for an engine, on quads edge-on to the front view.

Beyond the paper. :func:`~branchnb.trees.lod.bake_side_outline` inks the
texels an engine shows on a side view's rim, but only those hidden in the
front view: from 90 degrees half of the rim is made of the front
billboards' edge texels, which the front view shows, so baking them would
draw ink lines across the front view. An axial billboard cannot tell the
two views apart (it turns to face every camera), but a quad fixed in the
scene can: seen from the front, a quad turned by 90 degrees is edge-on and
draws nothing. :func:`side_outline_cards` puts the missing ink on such
quads, one per billboard and side (90 and 270 degrees), each a copy of its
billboard's texels that the side view shows on its rim, in the ink colour,
alpha-masked, half a pixel in front of the billboard and single sided (so
from the other side it is culled). glTF 2.0 core holds them as plain quads
with their own single-sided material (:func:`~branchnb.trees.lod.export_lod_gltf`).

Between the views a card is seen obliquely and its ink lands nearer the
billboard's centre; :func:`cards_view` draws what a depth-buffered engine
shows (per-pixel depth along the slanted card).

Examples
--------
>>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
>>> from branchnb.trees.drawn import drawn_tree
>>> cloud = billboard_cloud(drawn_tree("fruit", rng=0, size=96), params=BillboardParams(max_size=96), rng=0)
>>> cards = side_outline_cards(cloud)
>>> cards.n > 0, sorted(set(cards.turn.tolist()))
(True, [90.0, 270.0])
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

__all__ = ["SideCards", "side_outline_cards", "cards_view"]


@dataclass(eq=False)
class SideCards:
    """Fixed (not camera-facing), single-sided quads in working pixels.

    Parameters
    ----------
    centers : (n, 3) float array
        Quad centres ``(x, y, z)`` as :attr:`BillboardCloud.centers`.
    sizes : (n, 2) float array
        Width and height of each quad in pixels (its texture's).
    textures : list of (h, w, 4) float32 arrays
        Straight RGBA, alpha 0 or 1.
    turn : (n,) float array
        Yaw in degrees of the camera each quad faces (its front side).

    Examples
    --------
    >>> import numpy as np
    >>> SideCards(np.zeros((0, 3)), np.zeros((0, 2)), [], np.zeros(0)).n
    0
    """

    centers: np.ndarray
    sizes: np.ndarray
    textures: list
    turn: np.ndarray

    @property
    def n(self) -> int:
        """Number of quads."""
        return len(self.textures)

    @property
    def triangles(self) -> int:
        """Triangles drawn (two per quad)."""
        return 2 * self.n


def _empty() -> SideCards:
    return SideCards(np.zeros((0, 3)), np.zeros((0, 2)), [], np.zeros(0))


def side_outline_cards(cloud, *, sides=(90.0, 270.0), ink=None, width=None, offset: float = 0.5,
                       baked=None) -> SideCards:
    """Quads edge-on to the front view that carry the side views' rim ink (beyond the paper).

    For every yaw of ``sides`` this finds the texels an axial,
    depth-buffered engine shows in the view's outermost ring (``width``
    pixels from its silhouette, holes filled) that are not ink already (in
    ``baked``, e.g. :func:`~branchnb.trees.lod.bake_side_outline` of the
    cloud), and copies them per billboard, in the ink colour, onto a quad
    that faces that side's camera, ``offset`` pixels in front of the
    billboard. From the front (and the back) the quads are edge-on and
    draw nothing, so the front view stays exactly as drawn.

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud as an engine draws it (axial billboards); not modified.
    sides : sequence of float
        Yaws of the side views, degrees (default 90 and 270: the quads are
        then edge-on at 0 and 180).
    ink : (3,) array_like, optional
        Outline colour (default: the drawing's,
        :func:`~branchnb.trees.outline.silhouette_outline`).
    width : int, optional
        Stroke width in pixels (default: the drawing's).
    offset : float
        Pixels a card stands in front of its billboard (> 0).
    baked : BillboardCloud, optional
        The cloud with the textures the engine gets (default ``cloud``);
        texels already within 0.15 of the ink are left out.

    Returns
    -------
    SideCards
        The quads (none for a cloud without line art or an outlined
        silhouette, unless ``ink`` and ``width`` are given).

    Raises
    ------
    ValueError
        ``ink`` not 3 finite values, ``width`` < 1, ``offset`` not > 0, or
        a side yaw not finite.

    Examples
    --------
    >>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
    >>> from branchnb.trees.drawn import drawn_tree
    >>> cloud = billboard_cloud(drawn_tree("palm", rng=0, size=96), params=BillboardParams(max_size=96), rng=0)
    >>> cards = side_outline_cards(cloud)
    >>> cards.triangles == 2 * cards.n
    True
    """
    from .export import _check_cloud
    from .lod import _opaque_texels, _view_ids
    from .outline import _depth
    from .preview import _side_view_outline

    _check_cloud(cloud)
    sides = np.asarray(sides, float).reshape(-1)
    if not np.all(np.isfinite(sides)):
        raise ValueError("sides must be finite yaws in degrees")
    if not np.isfinite(offset) or offset <= 0:
        raise ValueError(f"offset must be > 0, got {offset}")
    baked = cloud if baked is None else baked
    if len(baked.textures) != len(cloud.textures):
        raise ValueError("baked must have the cloud's textures (bake_side_outline of it)")
    drawn = _side_view_outline(cloud)
    if drawn is None and (ink is None or width is None):
        return _empty()
    ink = np.asarray(drawn[0] if ink is None else ink, np.float32)
    width = int(drawn[1] if width is None else width)
    if ink.shape != (3,) or not np.all(np.isfinite(ink)):
        raise ValueError(f"ink must be 3 finite RGB values, got shape {ink.shape}")
    if width < 1:
        raise ValueError(f"width must be >= 1, got {width}")
    starts = np.concatenate([[0], np.cumsum([t.shape[0] * t.shape[1] for t in cloud.textures])])
    colours = np.concatenate([t[..., :3].reshape(-1, 3) for t in baked.textures])
    inked = np.linalg.norm(colours - ink[None], axis=1) <= 0.15
    texels = _opaque_texels(cloud)
    centers, sizes, textures, turn = [], [], [], []
    for yaw in sides:
        ids, texel = _view_ids(cloud, float(yaw), texels)
        op = ids >= 0
        if not op.any():
            continue
        ring = op & (_depth(ndi.binary_fill_holes(op)) <= width)
        sel = ring & ~inked[texel]
        if not sel.any():
            continue
        bb, tx = ids[sel], texel[sel]
        t = np.deg2rad(yaw)
        toward = np.array([-np.sin(t), np.cos(t)])       # (X, Z) towards the camera of ``yaw``
        right = np.array([np.cos(t), np.sin(t)])
        for i in np.unique(bb):
            ti = int(cloud.texture[i])
            h, w = cloud.textures[ti].shape[:2]
            flat = tx[bb == i] - starts[ti]
            vv, uu = flat // w, flat % w
            v0, v1, u0, u1 = vv.min(), vv.max() + 1, uu.min(), uu.max() + 1
            tex = np.zeros((v1 - v0, u1 - u0, 4), np.float32)
            tex[vv - v0, uu - u0, :3] = ink
            tex[vv - v0, uu - u0, 3] = 1.0
            # The crop's centre, along the quad's right vector and down the rows.
            du = 0.5 * (u0 + u1) - 0.5 * w
            dv = 0.5 * (v0 + v1) - 0.5 * h
            c = cloud.centers[i]
            xz = np.array([c[0], c[2]]) + du * right + offset * toward
            centers.append([xz[0], c[1] + dv, xz[1]])
            sizes.append([u1 - u0, v1 - v0])
            textures.append(tex)
            turn.append(float(yaw))
    if not textures:
        return _empty()
    return SideCards(np.asarray(centers, float), np.asarray(sizes, float), textures, np.asarray(turn, float))


def cards_view(view: np.ndarray, cloud, cards: SideCards, yaw: float) -> np.ndarray:
    """Draw ``cards`` into an engine's view of ``cloud`` from ``yaw`` (depth-tested, culled).

    Parameters
    ----------
    view : (H, W', 4) ndarray
        :func:`~branchnb.trees.lod.engine_view` of ``cloud`` from ``yaw``
        (``crop="fit"``, full height); not modified.
    cloud : BillboardCloud
        The axial billboards (their depths test the cards' texels).
    cards : SideCards
        Fixed quads (:func:`side_outline_cards`).
    yaw : float
        Camera yaw, degrees.

    Returns
    -------
    ndarray
        A copy of ``view`` with the cards' opaque texels drawn where they
        face the camera and lie in front of the billboards.

    Examples
    --------
    >>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
    >>> from branchnb.trees.drawn import drawn_tree
    >>> from branchnb.trees.lod import engine_view
    >>> cloud = billboard_cloud(drawn_tree("fruit", rng=0, size=96), params=BillboardParams(max_size=96), rng=0)
    >>> cards = side_outline_cards(cloud)
    >>> v = engine_view(cloud, 0.0)
    >>> bool((cards_view(v, cloud, cards, 0.0) == v).all())   # edge-on from the front
    True
    """
    from .lod import _view_ids
    from .preview import _extent, project

    out = np.array(view, np.float32, copy=True)
    if cards.n == 0:
        return out
    H, Wc = out.shape[:2]
    ids, _ = _view_ids(cloud, float(yaw))
    _, bdepth = project(cloud, float(yaw))
    zbuf = np.where(ids >= 0, bdepth[np.maximum(ids, 0)], -np.inf)
    r, _ = _extent(cloud)
    ox = int(np.ceil(max(cloud.axis, r))) + 1 - int(round(cloud.axis))
    th = np.deg2rad(float(yaw))
    for k in range(cards.n):
        phi = np.deg2rad(cards.turn[k])
        c = np.cos(th - phi)
        if c <= 1e-6:
            continue                                   # edge-on or seen from behind: culled
        tex = cards.textures[k]
        h, w = tex.shape[:2]
        X, Y, Z = cards.centers[k, 0] - cloud.axis, cards.centers[k, 1], cards.centers[k, 2]
        xc = cloud.axis + X * np.cos(th) + Z * np.sin(th) + ox
        dc = -X * np.sin(th) + Z * np.cos(th)
        p0 = int(np.floor(xc - 0.5 * w * c))
        p1 = int(np.ceil(xc + 0.5 * w * c))
        cols = np.arange(max(p0, 0), min(p1 + 1, Wc))
        if cols.size == 0:
            continue
        a = (cols + 0.5 - xc) / c                       # offset along the quad's right vector
        u = np.floor(a + 0.5 * w).astype(int)
        ok = (u >= 0) & (u < w)
        cols, a, u = cols[ok], a[ok], u[ok]
        depth = dc + a * np.sin(phi - th)
        y0 = int(round(Y - 0.5 * h))
        for v in range(h):
            row = y0 + v
            if not 0 <= row < H:
                continue
            on = tex[v, u, 3] >= 0.5
            if not on.any():
                continue
            pc, dd, uu = cols[on], depth[on], u[on]
            front = dd > zbuf[row, pc]
            pc, uu = pc[front], uu[front]
            out[row, pc, :3] = tex[v, uu, :3]
            out[row, pc, 3] = 1.0
            zbuf[row, pc] = dd[front]
    return out
