"""Side outline cards: the side silhouette's ink for an engine, on fixed quads hidden in the front view.

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
shows (per-pixel depth along the slanted card). The oblique sides (45,
135, 225 and 315 degrees) get cards too; a card there is seen by the
front camera or by the next side's, so every texel is checked in every
view (every 15 degrees) and dropped where it would show in the front view,
deeper than ``2 width + 1`` inside a silhouette or more than
``2 width + 1`` outside it. Each card may face another way than its view
(turned by up to 75 degrees, its texture stretched by ``1 / cos`` of the
turn so that its texels still land on the rim from its own view): single
sided, it is culled in the views where it would show in the wrong place,
and of the turns tried the one keeping most texels wins (up to three
cards per billboard and side take what the previous left).

Examples
--------
>>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
>>> from branchnb.trees.drawn import drawn_tree
>>> cloud = billboard_cloud(drawn_tree("fruit", rng=0, size=96), params=BillboardParams(max_size=96), rng=0)
>>> cards = side_outline_cards(cloud)
>>> cards.n > 0, {90.0, 270.0} <= set(cards.turn.tolist())
(True, True)
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


def side_outline_cards(cloud, *, sides=(45.0, 90.0, 135.0, 225.0, 270.0, 315.0), ink=None, width=None,
                       offset: float = 0.5, baked=None) -> SideCards:
    """Fixed quads, hidden in the front view, that carry the side views' rim ink (beyond the paper).

    For every yaw of ``sides`` this finds the texels an axial,
    depth-buffered engine shows in the view's outermost ring (``width``
    pixels from its silhouette, holes filled) that are not ink already (in
    ``baked``, e.g. :func:`~branchnb.trees.lod.bake_side_outline` of the
    cloud), and copies them per billboard, in the ink colour, onto a quad
    that faces that side's camera, ``offset`` pixels in front of the
    billboard. Sides edge-on to the front view (90, 270) get one card per
    billboard, checked against the front view only; from the front (and
    the back) they are edge-on and draw nothing. The oblique sides' cards
    are checked in every view (every 15 degrees: dropped where the front
    view would show them, or deeper than ``2 width + 1`` inside a
    silhouette or more than that outside it) and may turn by up to 75
    degrees away from their view (texture stretched to match), so that
    they are culled where they would stray; the front view stays exactly
    as drawn.

    On 12 drawn trees of every kind (``python -m branchnb.trees._measure
    engine``) the rim ink share of the engine's view of the full level
    (baked, then with these cards) went at 45 degrees from 0.82 to 0.96
    (min 0.82; cards at 90 and 270 only: 0.82), at 90 from 0.85 to 0.99,
    at 135 from 0.84 to 0.96 (min 0.90), at 270 from 0.84 to 0.98, as in
    the in-memory render (0.99, 0.99, 0.99, 0.98); the reduced level's to
    0.99-1.00. The 90 and 270 degree cards, seen obliquely, add 0.25 % (45
    degrees, at most 0.5 %) and 0.5 % (135, at most 1.4 %) of the opaque
    pixels as ink inside the crown; the oblique sides' cards none. The
    cards add 94 % to the full level's triangles (108 % to the reduced
    level's; a 6-billboard conifer gets up to 47 cards, a 450-billboard
    broadleaf about 180): ``extras.triangles`` of the exported levels
    counts them. Oblique cards checked against the front view only reach
    0.94 at 45 degrees but add 2.6 % stray ink at 180 degrees.

    Issue 24: the rear billboards on a broadleaf's 45 degree rim show deep
    inside the views from 90 to 210 degrees, so their cards lost most
    texels to those views' checks (a drawn broadleaf at 384 px: 0.82). The
    turns are now tried every 15 degrees (was 30) and a card's ink may
    show up to ``3 width + 1`` inside another view's silhouette (was
    ``2 width + 1``; it stays by the rim there, a slightly thicker
    outline): at 45 degrees that broadleaf went from 0.82 to 0.90, the
    drawn trees of ``python -m branchnb.trees._measure_sides 96,200 45
    drawn`` from mean 0.965 (min 0.87, 2 of 23 below 0.9) to 0.98 (min 0.92,
    none below 0.9), and on 5 drawn trees the ink deeper than ``2 width +
    1`` at 90 degrees from 0 to 0.1-0.3 % of the opaque pixels (at 45 and
    135 unchanged); 15-50 % more CPU time for the cards.

    Issue 24, floating fragments: card ink allowed just outside another
    view's silhouette showed there as loose dots and dashes beside the crown
    (:func:`~branchnb.trees.outline.floating_ink`). Texels that form, in
    a checked view, a piece touching no billboard piece of at least 2 % of
    the largest are dropped, and the ring is found with only the pinholes
    between billboards filled (a drawn hole between crown and branches keeps
    its rim). ``python -m branchnb.trees._measure_sides 96,200 45
    rpg,clip,ground`` with the crumbs of
    :func:`~branchnb.trees.billboard_crumbs.adopt_crumbs` and the reduced
    level's check in :func:`~branchnb.trees.lod.reduce_cloud`: floating
    pieces in the full and reduced levels' 45 degree views 28 in 10 of 50
    trees -> 0; rim ink at 45 degrees tree_rpg_01 at 96 px 0.919 -> 0.952,
    arbre_modern at 512 px 0.920 -> 0.909 (the dropped fragments were ink).

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud as an engine draws it (axial billboards); not modified.
    sides : sequence of float
        Yaws of the side views, degrees (default every 45 degrees but the
        front and back views; cards of 90 and 270 are edge-on at 0 and 180).
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
    from .lod import _opaque_texels, _pinholes_filled, _view_ids
    from .outline import _depth
    from .preview import _outline_style

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
    checks = _check_views(cloud, texels, width)
    centers, sizes, textures, turn = [], [], [], []
    for yaw in sides:
        ids, texel = _view_ids(cloud, float(yaw), texels)
        op = ids >= 0
        if not op.any():
            continue
        ring = op & (_depth(_pinholes_filled(op, width)) <= width)
        sel = ring & ~inked[texel]
        if not sel.any():
            continue
        bb, tx = ids[sel], texel[sel]
        # Edge-on to the front view (90, 270 degrees): cards facing the side, checked against the
        # front view only; oblique sides: every view checked (see the docstring).
        strict = abs(np.cos(np.deg2rad(yaw))) > 1e-6
        for i in np.unique(bb):
            ti = int(cloud.texture[i])
            h, w = cloud.textures[ti].shape[:2]
            flat = tx[bb == i] - starts[ti]
            vv, uu = flat // w, flat % w
            v0, v1, u0, u1 = vv.min(), vv.max() + 1, uu.min(), uu.max() + 1
            need = np.zeros((v1 - v0, u1 - u0), bool)
            need[vv - v0, uu - u0] = True
            # The crop's centre, along the billboard's right vector and down the rows.
            du = 0.5 * (u0 + u1) - 0.5 * w
            dv = 0.5 * (v0 + v1) - 0.5 * h
            for _ in range(_MAX_CARDS if strict else 1):
                best = None
                for turn_by in (_TURNS if strict else (0.0,)):
                    card = _card(cloud, i, float(yaw), float(yaw) + turn_by, du, dv, need, ink, offset,
                                 checks, strict)
                    if card is not None and (best is None or card[3] > best[3]):
                        best = card
                if best is None or best[3] < _MIN_TEXELS:
                    break
                centre, size, tex, n, facing = best
                centers.append(centre)
                sizes.append(size)
                textures.append(tex)
                turn.append(facing)
                need &= tex[..., 3] < 0.5
                if not need.any():
                    break
    if not textures:
        return _empty()
    cards = SideCards(np.asarray(centers, float), np.asarray(sizes, float), textures, np.asarray(turn, float))
    return _drop_floating(cloud, cards, checks)


def _drop_floating(cloud, cards: SideCards, checks, passes: int = 2) -> SideCards:
    """Drop card texels that float: in some view of ``checks`` they form, with the other cards'
    ink there, an 8-connected piece that touches no billboard piece of at least 2 % of the
    largest one's area (issue 24: loose stroke fragments beside the crown). Cards left without
    texels are removed."""
    eight = np.ones((3, 3), bool)
    texs = [t.copy() for t in cards.textures]
    for _ in range(passes):
        dropped = False
        for vyaw, zbuf, _bad in checks:
            H, Wc = zbuf.shape
            hits = []
            drawn = np.zeros(H * Wc, bool)
            for k, tex in enumerate(texs):
                hit = _card_hits(cloud, cards.centers[k], tex, cards.turn[k], vyaw, (H, Wc),
                                 stretch=float(cards.sizes[k][0]) / tex.shape[1])
                if hit is None:
                    continue
                rows, cols, vv, uu, dd = hit
                on = (tex[vv, uu, 3] >= 0.5) & (dd > zbuf[rows, cols])
                if on.any():
                    at = rows[on] * Wc + cols[on]
                    drawn[at] = True
                    hits.append((k, at, vv[on], uu[on]))
            if not hits:
                continue
            body = np.isfinite(zbuf).ravel()
            card_only = drawn & ~body
            if not card_only.any():
                continue
            # Anchors: the billboards' own pieces of at least 2 % of the largest one's area (a card's
            # ink on a crumb of fill beside the crown is a floating stroke as well).
            blab, nb = ndi.label(body.reshape(H, Wc), structure=eight)
            area = np.bincount(blab.ravel(), minlength=nb + 1)
            area[0] = 0
            anchor = (area >= 0.02 * area.max())[blab.ravel()]
            lab, n = ndi.label((drawn | body).reshape(H, Wc), structure=eight)
            touch = np.zeros(n + 1, bool)
            touch[np.unique(lab.ravel()[anchor])] = True
            loose = (~touch[lab.ravel()]) & drawn
            if not loose.any():
                continue
            for k, at, vv, uu in hits:
                m = loose[at]
                if m.any():
                    texs[k][vv[m], uu[m], 3] = 0.0
                    dropped = True
        if not dropped:
            break
    keep = [k for k, t in enumerate(texs) if (t[..., 3] >= 0.5).any()]
    if not keep:
        return _empty()
    return SideCards(cards.centers[keep], cards.sizes[keep], [texs[k] for k in keep], cards.turn[keep])


#: A card's ink may show at most ``_IN_K width + 1`` inside and ``_OUT_K width + 1`` outside the
#: silhouette of another view (:func:`_check_views`).
_OUT_K = 2
_IN_K = 3
#: Turns (degrees) of a card from the view it inks that are tried; the one keeping most texels wins.
_TURNS = (0.0, 15.0, -15.0, 30.0, -30.0, 45.0, -45.0, 60.0, -60.0, 75.0, -75.0)
#: Cards per billboard and side view at most (each takes the texels the previous ones left).
_MAX_CARDS = 3
_MIN_TEXELS = 1


def _card(cloud, i: int, yaw: float, facing: float, du: float, dv: float, need, ink, offset: float, checks,
          strict: bool = True):
    """One card for billboard ``i``'s texels ``need`` (a crop at ``du``, ``dv`` from its centre) seen
    from ``yaw``, facing ``facing``: ``(centre, size, texture, texels kept, facing)`` or None.

    The texture is stretched by ``1 / cos(facing - yaw)`` along the card so that from ``yaw`` every
    texel lands where the billboard's does, and the card stands in front of the billboard there;
    texels that would show where ``checks`` forbid ink are dropped (``strict=False``: only
    those the front view would show).
    """
    c = np.cos(np.deg2rad(facing - yaw))
    if c <= 0.2:
        return None
    k = 1.0 / c
    t, f = np.deg2rad(yaw), np.deg2rad(facing)
    toward = np.array([-np.sin(t), np.cos(t)])           # (X, Z) towards the camera of ``yaw``
    right = np.array([np.cos(t), np.sin(t)])
    hw = 0.5 * need.shape[1]
    # Depth along the card from ``yaw`` spans +-hw tan(facing - yaw): stand clear of the billboard.
    lift = offset + hw * abs(np.tan(f - t))
    ctr = cloud.centers[i]
    xz = np.array([ctr[0], ctr[2]]) + du * right + lift * toward
    centre = np.array([xz[0], ctr[1] + dv, xz[1]])
    tex = np.zeros(need.shape + (4,), np.float32)
    tex[need, :3] = ink
    tex[need, 3] = 1.0
    for vyaw, zbuf, bad in checks:
        if abs(((vyaw - yaw) + 180.0) % 360.0 - 180.0) < 1e-6:
            continue                                     # its own view: the ring, by construction
        if not strict and vyaw % 360.0 != 0.0:
            continue
        hit = _card_hits(cloud, centre, tex, facing, vyaw, zbuf.shape, stretch=k)
        if hit is None:
            continue
        rows, cols, hv, hu, dd = hit
        drop = (tex[hv, hu, 3] >= 0.5) & (dd > zbuf[rows, cols]) & bad[rows, cols]
        tex[hv[drop], hu[drop], 3] = 0.0
    n = int((tex[..., 3] >= 0.5).sum())
    if n == 0:
        return None
    return centre, [k * need.shape[1], need.shape[0]], tex, n, float(facing) % 360.0


def _check_views(cloud, texels, width: int, yaws=None) -> list:
    """Per view of ``yaws``: ``(yaw, zbuf, bad)``, the billboards' depth at each pixel and where
    a card's ink must not show (anywhere in the front view; elsewhere deeper than ``2 width + 1``
    inside the filled silhouette, or farther than ``width`` outside it)."""
    from .lod import _view_ids
    from .outline import _depth
    from .preview import project

    out = []
    for yaw in (range(0, 360, 15) if yaws is None else yaws):
        ids, _ = _view_ids(cloud, float(yaw), texels)
        op = ids >= 0
        zbuf = np.where(op, project(cloud, float(yaw))[1][np.maximum(ids, 0)], -np.inf)
        if float(yaw) % 360.0 == 0.0:
            bad = np.ones(op.shape, bool)
        else:
            filled = ndi.binary_fill_holes(op)
            bad = (_depth(filled) > _IN_K * width + 1) | (ndi.distance_transform_edt(~filled) > _OUT_K * width + 1)
        out.append((float(yaw), zbuf, bad))
    return out


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
        tex = cards.textures[k]
        hit = _card_hits(cloud, cards.centers[k], tex, cards.turn[k], yaw, out.shape[:2],
                         stretch=float(cards.sizes[k][0]) / tex.shape[1])
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


def _card_hits(cloud, centre, tex, turn: float, yaw: float, shape, stretch: float = 1.0):
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
    ww = w * stretch                                   # the quad's width in pixels
    r, _ = _extent(cloud)
    ox = int(np.ceil(max(cloud.axis, r))) + 1 - int(round(cloud.axis))
    X, Y, Z = centre[0] - cloud.axis, centre[1], centre[2]
    xc = cloud.axis + X * np.cos(th) + Z * np.sin(th) + ox
    dc = -X * np.sin(th) + Z * np.cos(th)
    cols = np.arange(max(int(np.floor(xc - 0.5 * ww * c)), 0), min(int(np.ceil(xc + 0.5 * ww * c)) + 1, Wc))
    a = (cols + 0.5 - xc) / c                          # offset along the quad's right vector
    u = np.floor((a + 0.5 * ww) / stretch).astype(int)
    ok = (u >= 0) & (u < w)
    cols, a, u = cols[ok], a[ok], u[ok]
    y0 = int(round(Y - 0.5 * h))
    v = np.arange(h)
    okv = (y0 + v >= 0) & (y0 + v < H)
    v = v[okv]
    if cols.size == 0 or v.size == 0:
        return None
    depth = dc + a * np.sin(phi - th)
    # Row-major over (v, u), as meshgrid(v, u, indexing="ij") raveled, without its overhead.
    nv, nu = v.size, u.size
    vv = np.repeat(v, nu)
    return y0 + vv, np.tile(cols, nv), vv, np.tile(u, nv), np.tile(depth, nv)
