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

    On 12 drawn trees of every kind (``python -m branchnb.trees._measure
    engine``) the rim ink share of the engine's view of the full level at
    90 degrees went from 0.83 (baked, min 0.60) to 0.98 (min 0.88), at 270
    from 0.81 to 0.97, as in the in-memory render (0.98, 0.97); the reduced
    level's from 0.96 to 1.00. Seen obliquely the cards add 0.3 % (45
    degrees) to 0.5 % (135, at most 1.4 %) of the opaque pixels as ink
    inside the crown, and leave the rim ink at 45 degrees where the bake
    put it (0.81; in memory 0.97). Cards at 45 degrees too
    (``sides=(45, 90, 135, 225, 270, 315)``, their texels that the front
    view would show dropped) raise it to 0.90 on 4 of the trees, but with 4
    times the cards and 1.3 % stray ink at 90 degrees. The cards add 22 %
    to the full level's triangles (0 to 80 cards a tree; a 6-billboard
    conifer gets 12).

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
    from .preview import _outline_style, project

    _check_cloud(cloud)
    try:
        sides = np.asarray(sides, float).reshape(-1)
        offset = float(offset)
    except (TypeError, ValueError) as exc:
        raise TypeError("sides and offset must be numbers (degrees, pixels)") from exc
    if not np.all(np.isfinite(sides)):
        raise ValueError("sides must be finite yaws in degrees")
    if not np.isfinite(offset) or offset <= 0:
        raise ValueError(f"offset must be > 0, got {offset}")
    if baked is None:
        baked = cloud
    elif type(baked) is not type(cloud):
        raise TypeError(f"baked must be a BillboardCloud, got {type(baked).__name__}")
    if len(baked.textures) != len(cloud.textures):
        raise ValueError("baked must have the cloud's textures (bake_side_outline of it)")
    style = _outline_style(cloud, ink, width)
    if style is None:
        return _empty()
    ink, width = style
    starts = np.concatenate([[0], np.cumsum([t.shape[0] * t.shape[1] for t in cloud.textures])])
    colours = np.concatenate([t[..., :3].reshape(-1, 3) for t in baked.textures])
    inked = np.linalg.norm(colours - ink[None], axis=1) <= 0.15
    texels = _opaque_texels(cloud)
    ids0, _ = _view_ids(cloud, 0.0, texels)
    zbuf0 = np.where(ids0 >= 0, project(cloud, 0.0)[1][np.maximum(ids0, 0)], -np.inf)
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
        front = (zbuf0,) if np.cos(t) > 1e-6 else None  # a quad the front camera sees
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
            centre = np.array([xz[0], c[1] + dv, xz[1]])
            if front is not None:
                hit = _card_hits(cloud, centre, tex, yaw, 0.0, front[0].shape)
                if hit is not None:
                    rows, cols, vv, uu, dd = hit
                    seen = (tex[vv, uu, 3] >= 0.5) & (dd > front[0][rows, cols])
                    tex[vv[seen], uu[seen], 3] = 0.0     # would show in the front view
                    if not (tex[..., 3] >= 0.5).any():
                        continue
            centers.append(centre)
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
    from .preview import project

    out = np.array(view, np.float32, copy=True)
    if cards.n == 0:
        return out
    ids, _ = _view_ids(cloud, float(yaw))
    _, bdepth = project(cloud, float(yaw))
    zbuf = np.where(ids >= 0, bdepth[np.maximum(ids, 0)], -np.inf)
    for k in range(cards.n):
        hit = _card_hits(cloud, cards.centers[k], cards.textures[k], cards.turn[k], yaw, out.shape[:2])
        if hit is None:
            continue
        rows, cols, vv, uu, dd = hit
        on = cards.textures[k][vv, uu, 3] >= 0.5
        rows, cols, vv, uu, dd = rows[on], cols[on], vv[on], uu[on], dd[on]
        front = dd > zbuf[rows, cols]
        rows, cols, vv, uu, dd = rows[front], cols[front], vv[front], uu[front], dd[front]
        out[rows, cols, :3] = cards.textures[k][vv, uu, :3]
        out[rows, cols, 3] = 1.0
        zbuf[rows, cols] = dd
    return out


def _card_hits(cloud, centre, tex, turn: float, yaw: float, shape):
    """Pixels a fixed quad covers from ``yaw`` in the ``crop="fit"`` frame (None: culled or off frame).

    Returns ``(rows, cols, v, u, depth)``: per covered pixel, its row and column, the texel
    sampled (nearest) and the quad's depth there (larger is nearer the camera).
    """
    from .preview import _extent

    H, Wc = shape
    th, phi = np.deg2rad(float(yaw)), np.deg2rad(float(turn))
    c = np.cos(th - phi)
    if c <= 1e-6:
        return None                                    # edge-on or seen from behind: culled
    h, w = tex.shape[:2]
    r, _ = _extent(cloud)
    ox = int(np.ceil(max(cloud.axis, r))) + 1 - int(round(cloud.axis))
    X, Y, Z = centre[0] - cloud.axis, centre[1], centre[2]
    xc = cloud.axis + X * np.cos(th) + Z * np.sin(th) + ox
    dc = -X * np.sin(th) + Z * np.cos(th)
    cols = np.arange(max(int(np.floor(xc - 0.5 * w * c)), 0), min(int(np.ceil(xc + 0.5 * w * c)) + 1, Wc))
    a = (cols + 0.5 - xc) / c                          # offset along the quad's right vector
    u = np.floor(a + 0.5 * w).astype(int)
    ok = (u >= 0) & (u < w)
    cols, a, u = cols[ok], a[ok], u[ok]
    y0 = int(round(Y - 0.5 * h))
    v = np.arange(h)
    okv = (y0 + v >= 0) & (y0 + v < H)
    v = v[okv]
    if cols.size == 0 or v.size == 0:
        return None
    depth = dc + a * np.sin(phi - th)
    vv, uu = np.meshgrid(v, u, indexing="ij")
    rows = (y0 + vv).ravel()
    return (rows, np.broadcast_to(cols, vv.shape).ravel(), vv.ravel(), uu.ravel(),
            np.broadcast_to(depth, vv.shape).ravel())
