"""Levels of detail of one billboard cloud, exported as glTF (beyond the paper).

Game engines (SpeedTree, ez-tree) draw a tree with a chain of ever cheaper
representations as it moves away from the camera. From one
:class:`~branchnb.trees.billboard.BillboardCloud` this module derives

0. ``full``: the whole cloud (two triangles per billboard);
1. ``reduced``: the front view as one billboard at the back, before it
   the billboards that carry most of the picture (front and trunk first,
   by opaque area), ``reduced_share`` of them;

   on drawn trees both carry the side views' outline baked into their
   textures (:func:`bake_side_outline`) where the front view hides the
   texels, and the rest of it from 45, 90, 135, 225, 270 and 315 degrees
   on side cards, fixed quads hidden in the front view
   (:func:`~branchnb.trees.lod_cards.side_outline_cards`): an engine draws
   no silhouette ink of its own;
2. ``crossed``: two perpendicular quads (four triangles), the front view
   on one and the side view from 90 degrees on the other
   (:func:`crossed_impostor`), rendered as the in-memory side views are:
   a drawn tree's side view keeps its inked silhouette outline;
3. ``single``: one quad (two triangles), an impostor whose texture holds
   the views from 8 yaws (:func:`impostor_frames`, every 45 degrees,
   rendered as the in-memory side views are, with a drawn tree's inked
   silhouette outline); the quad shows the front view, and
   ``extras.impostor`` lists each frame's yaw and texture rectangle, so
   that an engine's impostor shader can show the frame nearest to the
   camera's direction.

:func:`export_lod_gltf` writes them as one self-contained glTF 2.0 file
with the ``MSFT_lod`` extension (the first node holds the full cloud and
lists the coarser nodes; ``extras.MSFT_screencoverage`` gives the screen
coverage below which each level hands over to the next), or one file per
level (``mode="files"``). Every level uses the same units, axes and origin
as :func:`~branchnb.trees.export.export_gltf`.

Examples
--------
>>> import tempfile, pathlib, json
>>> from branchnb import data
>>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
>>> cloud = billboard_cloud(data.load("tree_rpg_03"), params=BillboardParams(max_size=128), rng=0)
>>> chain = lod_chain(cloud)
>>> [lv.name for lv in chain], [lv.triangles for lv in chain][2:]
(['full', 'reduced', 'crossed', 'single'], [4, 2])
>>> out = export_lod_gltf(cloud, pathlib.Path(tempfile.mkdtemp()) / "tree.gltf")
>>> json.loads(out[0].read_text())["nodes"][0]["extensions"]["MSFT_lod"]["ids"]
[1, 2, 3]
"""

from __future__ import annotations

import base64
from dataclasses import dataclass
from pathlib import Path

import numpy as np
from scipy import ndimage as ndi

from ..core.io import encode_png
from ..core.jsonio import dumps_strict
from ..core.validate import Choice, Real, checked
from .export import _HEIGHT, _YAW, _accessors, _check_cloud, _level_arrays, _out_path, _pack, texture_atlas

__all__ = ["LOD_LEVELS", "LodLevel", "reduce_cloud", "impostor_cloud", "crossed_impostor",
           "impostor_frames", "engine_view", "bake_side_outline", "lod_chain", "export_lod_gltf",
           "validate_gltf"]

#: The levels of :func:`lod_chain`, finest first.
LOD_LEVELS = ("full", "reduced", "crossed", "single")

#: Default screen coverage (share of the screen height) below which a level hands over to the next.
SCREEN_COVERAGE = (0.5, 0.2, 0.05, 0.0)


@dataclass(eq=False)
class LodLevel:
    """One level of detail.

    Parameters
    ----------
    name : str
        ``"full"``, ``"reduced"``, ``"crossed"`` or ``"single"``.
    cloud : BillboardCloud
        The billboards of this level.
    crossed : bool
        Two perpendicular quads per billboard.
    turn : (K,) float array or None
        Per billboard, degrees its quad is turned by (the crossed impostor's
        side view: 90).
    yaws : tuple of float or None
        Impostor frames: the yaw of each texture of ``cloud`` (the quad shows
        the first).
    cards : SideCards or None
        Fixed, single-sided quads drawn with the level
        (:func:`~branchnb.trees.lod_cards.side_outline_cards`: the side
        views' rim ink of a drawn tree), or None.

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> LodLevel("full", cloud).triangles == 2 * cloud.n_billboards
    True
    """

    name: str
    cloud: object
    crossed: bool = False
    turn: object = None
    yaws: object = None
    cards: object = None

    @property
    def quads(self) -> int:
        n = 0 if self.cards is None else self.cards.n
        return self.cloud.n_billboards * (2 if self.crossed else 1) + n

    @property
    def triangles(self) -> int:
        """Triangles drawn (two per quad)."""
        return 2 * self.quads


def _subset(cloud, keep: np.ndarray):
    from .billboard import BillboardCloud

    keep = np.asarray(keep, int)
    used = np.unique(cloud.texture[keep])
    remap = np.full(len(cloud.textures), -1)
    remap[used] = np.arange(len(used))
    lines = [cloud.line_masks[i] for i in used] if len(cloud.line_masks) == len(cloud.textures) else []
    return BillboardCloud(cloud.centers[keep], cloud.sizes[keep], remap[cloud.texture[keep]],
                          cloud.tint[keep], cloud.layer[keep], keep.copy(),
                          [cloud.textures[i] for i in used], cloud.axis, cloud.image,
                          cloud.superpixels, cloud.depth, cloud.replaced, cloud.scale, cloud.lines, lines)


@checked(share=Real(0, 1, low_open=True))
def reduce_cloud(cloud, share: float = 0.3):
    """A cheaper cloud: the front view as one billboard at the back plus ``ceil(share K)`` billboards.

    Of the ``K`` billboards, front and trunk ones come first (they carry
    the silhouette and the drawing), each group ordered by opaque texel
    count. Behind them all stands the impostor (:func:`impostor_cloud`),
    so the gaps left by the dropped billboards show the tree's own front
    view instead of sky: from the front the level looks like the full
    cloud, from the side the kept billboards still give depth.

    Parameters
    ----------
    cloud : BillboardCloud
        The full cloud (``K`` billboards); not modified.
    share : float
        Share of the billboards kept, in (0, 1] (default 0.3; at least one
        is kept). Billboards behind the axis (``z < 0``) are dropped first,
        as the impostor would hide them. Kept billboards that float off the
        impostor in a side view (every 15 degrees; a piece of outline
        hanging under the crown) are dropped again, so there may be fewer.

    Returns
    -------
    BillboardCloud
        At most ``ceil(share K) + 1`` billboards, the impostor first.

    Raises
    ------
    ValueError
        If ``share`` is outside (0, 1] or ``cloud`` has no billboards.
    TypeError
        If ``cloud`` is not a ``BillboardCloud``.

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> cloud.n_billboards, reduce_cloud(cloud, 0.3).n_billboards
    (642, 194)
    """
    from .billboard import FRONT, TRUNK_LAYER, BillboardCloud

    _check_cloud(cloud)
    k = cloud.n_billboards
    n = max(1, int(np.ceil(share * k)))
    area = np.array([float((cloud.textures[t][..., 3] >= 0.5).sum()) for t in cloud.texture])
    first = np.isin(cloud.layer, (FRONT, TRUNK_LAYER))
    order = np.lexsort((-area, ~first))            # front/trunk first, then by area
    order = order[cloud.centers[order, 2] >= 0]    # those behind the axis would be hidden
    if order.size == 0:
        order = np.lexsort((-area, ~first))
    sub = _subset(cloud, np.sort(order[:n]))
    imp = impostor_cloud(cloud)
    # On the vertical axis (z = 0): seen from the side it stays centred behind the
    # front billboards it backs.
    back = imp.centers.copy()
    t0 = len(sub.textures)
    out = BillboardCloud(np.vstack([back, sub.centers]), np.vstack([imp.sizes, sub.sizes]),
                         np.concatenate([[t0], sub.texture]), np.concatenate([[1.0], sub.tint]),
                         np.concatenate([[FRONT], sub.layer]), np.concatenate([[-1], sub.source]),
                         sub.textures + imp.textures, cloud.axis, cloud.image, cloud.superpixels,
                         cloud.depth, cloud.replaced, cloud.scale, cloud.lines,
                         sub.line_masks + [None] if sub.line_masks else [])
    return _drop_floating_billboards(out)


def _drop_floating_billboards(cloud, yaws=tuple(range(15, 360, 15))):
    """A reduced cloud without the kept billboards that float in a side view (issue 24).

    From the side a kept billboard moves with its depth, off the impostor at the back (billboard
    0): a piece of the crown's outline then hangs below or beside the tree. Billboards with
    texels in an 8-connected piece of a view of ``yaws`` that holds none of the impostor's
    pixels and is not the view's largest piece are dropped (the impostor shows the same texels
    in the front view, so that stays as it was).
    """
    if cloud.n_billboards < 2:
        return cloud
    texels = _opaque_texels(cloud)
    drop = np.zeros(cloud.n_billboards, bool)
    eight = np.ones((3, 3), bool)
    for yaw in yaws:
        ids, _ = _view_ids(cloud, float(yaw), texels)
        op = ids >= 0
        lab, n = ndi.label(op, structure=eight)
        if n < 2:
            continue
        size = np.bincount(lab.ravel(), minlength=n + 1)
        size[0] = 0
        anchored = np.zeros(n + 1, bool)
        anchored[int(np.argmax(size))] = True
        anchored[np.unique(lab[ids == 0])] = True
        anchored[0] = True
        loose = ~anchored[lab]
        if loose.any():
            drop[np.unique(ids[loose])] = True
    drop[0] = False
    if not drop.any():
        return cloud
    return _subset_keep_sources(cloud, np.flatnonzero(~drop))


def _subset_keep_sources(cloud, keep):
    """:func:`_subset` keeping the billboards' ``source`` (the impostor's stays -1)."""
    sub = _subset(cloud, keep)
    sub.source = cloud.source[np.asarray(keep, int)].copy()
    return sub


def impostor_cloud(cloud):
    """The cloud's front view as one billboard (its working image, cropped to the tree).

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud whose ``image`` (the working RGBA) becomes the texture.

    Returns
    -------
    BillboardCloud
        One billboard on the vertical axis (``z = 0``), sized to the
        opaque bounding box, untinted.

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> impostor_cloud(cloud).n_billboards
    1
    """
    from .billboard import FRONT, BillboardCloud

    _check_cloud(cloud)
    img = cloud.image
    a = img[..., 3] >= 0.5
    ys, xs = np.nonzero(a)
    y0, y1, x0, x1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
    tex = np.ascontiguousarray(img[y0:y1, x0:x1])
    centre = np.array([[0.5 * (x0 + x1), 0.5 * (y0 + y1), 0.0]])
    return BillboardCloud(centre, np.array([[x1 - x0, y1 - y0]], float), np.zeros(1, int),
                          np.ones(1), np.array([FRONT]), np.zeros(1, int), [tex], cloud.axis, img,
                          cloud.superpixels, cloud.depth, [], cloud.scale, cloud.lines, [])


def impostor_frames(cloud, yaws=tuple(range(0, 360, 45))):
    """One quad whose textures are the cloud seen from several yaws (an impostor atlas).

    Every frame is :func:`~branchnb.trees.preview.render_cloud` from one yaw
    (with a drawn tree's silhouette ink beyond the front view), all cropped
    to the same rectangle of the ``crop="fit"`` frame (centred on the
    vertical axis), so the frames line up on one quad. The quad's texture is
    the first frame.

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud to render.
    yaws : sequence of float
        Camera angles in degrees, one frame each (default every 45 degrees,
        8 frames); not empty.

    Returns
    -------
    cloud : BillboardCloud
        One billboard, ``len(yaws)`` textures.
    yaws : tuple of float
        The frames' yaws, in texture order.

    Raises
    ------
    ValueError
        If ``yaws`` is empty.

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> frames, yaws = impostor_frames(cloud, (0, 90))
    >>> len(frames.textures), yaws
    (2, (0.0, 90.0))
    """
    from .billboard import FRONT, BillboardCloud
    from .preview import _extent, render_cloud

    yaws = tuple(float(y) for y in yaws)
    if not yaws:
        raise ValueError("yaws must not be empty")
    views = [render_cloud(cloud, y, crop="fit") for y in yaws]
    a = np.any([v[..., 3] >= 0.5 for v in views], axis=0)
    ys, xs = np.nonzero(a)
    y0, y1, x0, x1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
    frames = [np.ascontiguousarray(v[y0:y1, x0:x1]) for v in views]
    r, _ = _extent(cloud)
    ox = int(np.ceil(max(cloud.axis, r))) + 1 - int(round(cloud.axis))   # canvas x - world x
    centre = np.array([[0.5 * (x0 + x1) - ox, 0.5 * (y0 + y1), 0.0]])
    out = BillboardCloud(centre, np.array([[x1 - x0, y1 - y0]], float), np.zeros(1, int), np.ones(1),
                         np.array([FRONT]), np.zeros(1, int), frames, cloud.axis, cloud.image,
                         cloud.superpixels, cloud.depth, [], cloud.scale, cloud.lines, [])
    return out, yaws


def engine_view(cloud, yaw: float, *, cards=None, **kwargs) -> np.ndarray:
    """What an engine shows of an exported cloud from ``yaw``: axial quads in depth order, the
    line art drawn in place (no pass behind the fills) and no silhouette ink added.

    :func:`~branchnb.trees.preview.render_cloud` draws a drawn tree's
    silhouette strokes behind every fill and inks each side view's
    silhouette afterwards; a depth-buffered engine does neither. Compare the
    two to see what the exported full and reduced levels lack from the side.

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud as exported; not modified (its line masks are dropped on
        a copy).
    yaw : float
        Camera angle about the vertical axis, degrees.
    cards : SideCards, optional
        Fixed, single-sided quads exported with the cloud
        (:attr:`LodLevel.cards`), drawn depth-tested
        (:func:`~branchnb.trees.lod_cards.cards_view`); only with the
        default ``crop="fit"``, no ``height`` and no ``background``.
    **kwargs
        Passed to :func:`~branchnb.trees.preview.render_cloud` (``facing``,
        ``crop``, ``background``, ``height``).

    Returns
    -------
    ndarray
        The view, RGBA (RGB with ``background``), float32 in [0, 1].

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> engine_view(cloud, 90.0).shape
    (64, 67, 4)
    """
    from .lod_cards import SideCards, cards_view
    from .preview import render_cloud

    if cards is not None:
        if not isinstance(cards, SideCards):
            raise TypeError(f"cards must be SideCards or None, got {type(cards).__name__}")
        if set(kwargs) - {"facing"} or kwargs.get("facing", "camera") != "camera":
            raise ValueError("cards: only with axial billboards, crop='fit', no height or background")
    bare = _subset(cloud, np.arange(cloud.n_billboards))
    bare.line_masks = [None] * len(bare.textures)
    view = render_cloud(bare, yaw, outline=False, **kwargs)
    if cards is not None and cards.n:
        view = cards_view(view, cloud, cards, yaw)
    return view


def _view_ids(cloud, yaw: float, texels=None):
    """Which billboard texel an axial, depth-buffered engine shows at each pixel from ``yaw``.

    The frame and placement are :func:`~branchnb.trees.preview.render_cloud`'s (``crop="fit"``);
    texels with alpha >= 0.5 are opaque (the exported material's ``alphaCutoff``).
    ``texels`` (from :func:`_opaque_texels`) saves finding them again for every view.

    Returns ``(ids, texel)``: (H, W') billboard index per pixel (-1: none) and the flat index of
    the texel shown into the concatenation of ``cloud.textures`` (``_texel_offsets``).
    """
    from .preview import _extent, project

    H, W = cloud.image.shape[:2]
    r, _ = _extent(cloud)
    left = int(np.ceil(max(cloud.axis, r))) + 1
    right = int(np.ceil(max(W - cloud.axis, r))) + 1
    ox, Wc = left - int(round(cloud.axis)), left + right
    ids = np.full(H * Wc, -1, np.int64)
    texel = np.zeros(H * Wc, np.int64)
    texels = _opaque_texels(cloud) if texels is None else texels
    xs, depth = project(cloud, yaw)
    for i in np.argsort(depth, kind="stable"):
        t = int(cloud.texture[i])
        h, w = cloud.textures[t].shape[:2]
        vv, uu, flat = texels[t]
        x0 = int(round(xs[i] - 0.5 * w)) + ox
        y0 = int(round(cloud.centers[i, 1] - 0.5 * h))
        py, px = vv + y0, uu + x0
        if x0 < 0 or y0 < 0 or x0 + w > Wc or y0 + h > H:
            ok = (py >= 0) & (py < H) & (px >= 0) & (px < Wc)
            py, px, f = py[ok], px[ok], flat[ok]
        else:
            f = flat
        at = py * Wc + px
        ids[at] = i
        texel[at] = f
    return ids.reshape(H, Wc), texel.reshape(H, Wc)


def _opaque_texels(cloud) -> list:
    """Per texture, the rows, columns and flat indices (``_texel_offsets``) of its opaque texels."""
    offsets = _texel_offsets(cloud)
    out = []
    for t, tex in enumerate(cloud.textures):
        vv, uu = np.nonzero(tex[:, :, 3] >= 0.5)
        out.append((vv, uu, offsets[t] + vv * tex.shape[1] + uu))
    return out


def _texel_offsets(cloud) -> np.ndarray:
    """Start of each texture in the concatenation of all the cloud's texels."""
    n = [t.shape[0] * t.shape[1] for t in cloud.textures]
    return np.concatenate([[0], np.cumsum(n)]).astype(np.int64)


def _pinholes_filled(op: np.ndarray, width: int) -> np.ndarray:
    """``op`` with its holes filled but the drawn ones: a hole that holds a disc of radius
    ``width + 1`` (between a crown and its branches) keeps its rim, gaps between billboards
    (thinner) are filled."""
    filled = ndi.binary_fill_holes(op)
    holes = filled & ~op
    if not holes.any():
        return filled
    lab, n = ndi.label(holes)
    deep = ndi.maximum(ndi.distance_transform_edt(holes), lab, np.arange(1, n + 1))
    keep = np.concatenate([[False], np.asarray(deep) >= width + 1])
    return filled & ~keep[lab]


def bake_side_outline(cloud, *, yaws=tuple(range(15, 360, 15)), ink=None, width=None):
    """Bake a drawn tree's side-view outline into the textures an engine shows (beyond the paper).

    :func:`~branchnb.trees.preview.render_cloud` inks the silhouette of
    every side view after drawing it; an engine draws the exported quads as
    they are, so the crown's side silhouette, made of fills cut by the
    superpixels, shows no outline (:func:`engine_view`). From every yaw of
    ``yaws`` this finds the texels an axial, depth-buffered engine shows in
    the view's outermost ring (``width`` pixels from its silhouette, holes
    filled) and paints them in the ink colour, but only texels that

    * are hidden in the front view (behind another billboard's opaque
      texel), so the front view stays exactly as drawn, and
    * show nowhere deeper than ``2 width + 1`` inside any view of
      ``yaws``, so no ink line appears inside a crown, and no stroke
      floats: the ink is painted on texels already on the silhouette.

    Not every ring pixel can be inked so: from a side, half of the
    silhouette is made of front billboards whose edge texels show in the
    front view (and the rear layer's edges show inside the back view).
    On 12 drawn trees of every kind (``python -m branchnb.trees._measure
    engine``) the rim ink share of the engine's view of the full level at
    90 degrees went from 0.74 (min 0.38) to 0.83 (min 0.60), at 45 degrees
    from 0.74 to 0.80 (the reduced level: 0.95 to 0.96, min 0.80 to 0.88);
    the in-memory render's is 0.98; the side cards of
    :func:`~branchnb.trees.lod_cards.side_outline_cards` (fixed quads hidden
    in the front view) carry the rest (45, 90, 135, 270 degrees: 0.96,
    0.99, 0.96, 0.98). A
    1024 px cloud takes about 5 s. Clouds without line art or an outlined silhouette
    (:func:`~branchnb.trees.outline.silhouette_outline`) are returned
    unchanged.

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud; not modified.
    yaws : sequence of float
        Views whose silhouettes are inked and checked (default every 15
        degrees but the front view).
    ink : (3,) array_like, optional
        Outline colour (default: the drawing's, ``silhouette_outline``).
    width : int, optional
        Stroke width in pixels (default: the drawing's).

    Returns
    -------
    BillboardCloud
        A copy with new textures (the same billboards; line masks kept).

    Examples
    --------
    >>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
    >>> from branchnb.trees.drawn import drawn_tree
    >>> from branchnb.trees.outline import rim_ink_share, silhouette_outline
    >>> cloud = billboard_cloud(drawn_tree("fruit", rng=0, size=128), params=BillboardParams(max_size=128), rng=0)
    >>> baked = bake_side_outline(cloud)
    >>> ink = silhouette_outline(cloud.image).ink
    >>> float(abs(engine_view(baked, 0.0) - engine_view(cloud, 0.0)).max()) < 1e-3   # front view as drawn
    True
    >>> rim_ink_share(engine_view(baked, 90.0), ink) > rim_ink_share(engine_view(cloud, 90.0), ink)
    True
    """
    from .outline import _depth
    from .preview import _outline_style

    _check_cloud(cloud)
    out = _subset(cloud, np.arange(cloud.n_billboards))
    style = _outline_style(cloud, ink, width)
    if style is None:
        return out
    ink, width = style
    offsets = _texel_offsets(cloud)
    want = np.zeros(int(offsets[-1]), bool)
    bad = np.zeros(int(offsets[-1]), bool)
    texels = _opaque_texels(cloud)
    ids, texel = _view_ids(cloud, 0.0, texels)
    bad[texel[ids >= 0]] = True
    for yaw in yaws:
        if float(yaw) % 360.0 == 0.0:
            continue
        ids, texel = _view_ids(cloud, float(yaw), texels)
        op = ids >= 0
        if not op.any():
            continue
        d = _depth(ndi.binary_fill_holes(op))
        want[texel[op & (_depth(_pinholes_filled(op, width)) <= width)]] = True
        bad[texel[op & (d > 2 * width + 1)]] = True
    paint = want & ~bad
    texs = []
    for t, tex in enumerate(out.textures):
        p = paint[offsets[t]:offsets[t + 1]].reshape(tex.shape[:2])
        if p.any():
            tex = tex.copy()
            tex[p, :3] = ink
        texs.append(tex)
    out.textures = texs
    return out


def crossed_impostor(cloud, *, side_yaw: float = 90.0):
    """Front view and side view of a cloud on two perpendicular quads: ``(cloud, turn)``.

    The first billboard is :func:`impostor_cloud`'s front view; the second
    the cloud rendered from ``side_yaw`` degrees
    (:func:`~branchnb.trees.preview.render_cloud`, with the silhouette ink
    of drawn trees), cropped to the tree, centred on the vertical axis and
    turned by ``side_yaw`` degrees, so that seen from that side it shows
    what the full cloud shows there. Generic engines draw crossed quads
    fixed (not turned to the camera), so each view is seen from its own
    side (the other from its edge).

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud to render.
    side_yaw : float
        Yaw of the side view in degrees (default 90).

    Returns
    -------
    cloud : BillboardCloud
        Two billboards.
    turn : (2,) float array
        ``[0, side_yaw]`` (``[0]`` and only the front quad when nothing is
        visible from the side).

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> crossed, turn = crossed_impostor(cloud)
    >>> crossed.n_billboards, turn.tolist()
    (2, [0.0, 90.0])
    """
    from .billboard import FRONT, BillboardCloud
    from .preview import _extent, render_cloud

    front = impostor_cloud(cloud)
    view = render_cloud(cloud, side_yaw, crop="fit")
    a = view[..., 3] >= 0.5
    if not a.any():
        return front, np.zeros(1)
    ys, xs = np.nonzero(a)
    y0, y1, x0, x1 = ys.min(), ys.max() + 1, xs.min(), xs.max() + 1
    tex = np.ascontiguousarray(view[y0:y1, x0:x1])
    # Where render_cloud(crop="fit") puts the axis: the screen x of depth 0.
    r, _ = _extent(cloud)
    left = int(np.ceil(max(cloud.axis, r))) + 1
    z_c = 0.5 * (x0 + x1) - left
    t = np.deg2rad(side_yaw)
    # The turned quad's centre lies on the camera's right axis (cos t, sin t) at z_c.
    centre = [[cloud.axis + z_c * np.cos(t), 0.5 * (y0 + y1), z_c * np.sin(t)]]
    out = BillboardCloud(np.vstack([front.centers, centre]),
                         np.vstack([front.sizes, [[x1 - x0, y1 - y0]]]), np.array([0, 1]),
                         np.ones(2), np.array([FRONT, FRONT]), np.array([0, 0]),
                         front.textures + [tex], cloud.axis, cloud.image, cloud.superpixels,
                         cloud.depth, [], cloud.scale, cloud.lines, [])
    return out, np.array([0.0, float(side_yaw)])


@checked(reduced_share=Real(0, 1, low_open=True))
def lod_chain(cloud, *, reduced_share: float = 0.3) -> list[LodLevel]:
    """The four levels of detail of one cloud (:data:`LOD_LEVELS`), finest first.

    Parameters
    ----------
    cloud : BillboardCloud
        The full cloud (the ``full`` level: its billboards, with the side
        outline of a drawn tree baked in by :func:`bake_side_outline` and
        the rest of it on side cards,
        :func:`~branchnb.trees.lod_cards.side_outline_cards`).
    reduced_share : float
        Share of the billboards the ``reduced`` level keeps (:func:`reduce_cloud`).

    Returns
    -------
    list of LodLevel
        ``full`` (the cloud), ``reduced`` (both baked with
        :func:`bake_side_outline`, and with side cards for drawn trees,
        :attr:`LodLevel.cards`), ``crossed``
        (:func:`crossed_impostor`) and ``single`` (:func:`impostor_frames`,
        8 frames).

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> [(lv.name, lv.triangles) for lv in lod_chain(cloud)]
    [('full', 1284), ('reduced', 388), ('crossed', 4), ('single', 2)]
    """
    from .lod_cards import side_outline_cards

    _check_cloud(cloud)
    single, yaws = impostor_frames(cloud)
    crossed, turn = crossed_impostor(cloud)
    out = []
    for name, c in (("full", cloud), ("reduced", reduce_cloud(cloud, reduced_share))):
        baked = bake_side_outline(c)
        out.append(LodLevel(name, baked, cards=side_outline_cards(c, baked=baked)))
    return out + [LodLevel("crossed", crossed, turn=turn), LodLevel("single", single, yaws=yaws)]


def _material(name: str, texture: int, double_sided: bool = True) -> dict:
    return {"name": name,
            "pbrMetallicRoughness": {"baseColorTexture": {"index": texture}, "metallicFactor": 0.0,
                                     "roughnessFactor": 1.0},
            "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": bool(double_sided),
            "extensions": {"KHR_materials_unlit": {}}}


def _cards_cloud(cards, cloud):
    """Side cards as a BillboardCloud (for the exported arrays)."""
    from .billboard import FRONT, BillboardCloud

    n = cards.n
    return BillboardCloud(np.asarray(cards.centers, float), np.asarray(cards.sizes, float), np.arange(n),
                          np.ones(n), np.full(n, FRONT), np.full(n, -1), list(cards.textures), cloud.axis,
                          cloud.image, cloud.superpixels, cloud.depth, [], cloud.scale, cloud.lines, [])


def _document(levels: list[LodLevel], *, yaw: float, height: float, lod: bool,
              coverage=SCREEN_COVERAGE) -> dict:
    """A self-contained glTF document (embedded buffer and textures) of some levels."""
    data = bytearray()
    views, accessors, meshes, materials, textures, images, nodes = [], [], [], [], [], [], []
    atlases: dict[int, int] = {}                     # id(cloud) -> image index
    for i, lv in enumerate(levels):
        atlas, pos, uv, col, idx = _level_arrays(lv.cloud, yaw=yaw, height=height, crossed=lv.crossed,
                                                 turn=lv.turn)
        first = len(views)
        v, data = _pack([pos.tobytes(), uv.tobytes(), col.tobytes(), idx.tobytes()],
                        [34962, 34962, 34962, 34963], data)
        views += v
        acc0 = len(accessors)
        accessors += _accessors(first, pos, uv, col, idx)
        key = id(lv.cloud)
        if key not in atlases:
            v, data = _pack([encode_png(atlas)], [None], data)
            images.append({"bufferView": len(views), "mimeType": "image/png"})
            views += v
            textures.append({"source": len(images) - 1, "sampler": 0})
            materials.append(_material(f"{lv.name}_atlas", len(textures) - 1))
            atlases[key] = len(materials) - 1
        extras = {"triangles": lv.triangles, "crossed": lv.crossed}
        if lv.turn is not None:
            extras["turn_degrees"] = [float(t) for t in lv.turn]
        if lv.yaws is not None:
            _, rects = texture_atlas(lv.cloud.textures)
            Ha, Wa = atlas.shape[:2]
            extras["impostor"] = {
                "frames": [{"yaw": float(y), "uv": [float(x / Wa), float(yy / Ha), float((x + w) / Wa),
                                                    float((yy + h) / Ha)]}
                           for y, (x, yy, w, h) in zip(lv.yaws, rects.tolist())],
                "note": "the quad shows frame 0; show the frame whose yaw is nearest to the camera's"}
        prims = [{"attributes": {"POSITION": acc0, "TEXCOORD_0": acc0 + 1, "COLOR_0": acc0 + 2},
                  "indices": acc0 + 3, "material": atlases[key], "mode": 4}]
        if lv.cards is not None and lv.cards.n:
            # Side cards: fixed quads facing their side's camera, single sided (culled from behind).
            cc = _cards_cloud(lv.cards, lv.cloud)
            atlas, pos, uv, col, idx = _level_arrays(cc, yaw=yaw, height=height, crossed=False,
                                                     turn=np.asarray(lv.cards.turn) - yaw)
            first = len(views)
            v, data = _pack([pos.tobytes(), uv.tobytes(), col.tobytes(), idx.tobytes()],
                            [34962, 34962, 34962, 34963], data)
            views += v
            acc1 = len(accessors)
            accessors += _accessors(first, pos, uv, col, idx)
            v, data = _pack([encode_png(atlas)], [None], data)
            images.append({"bufferView": len(views), "mimeType": "image/png"})
            views += v
            textures.append({"source": len(images) - 1, "sampler": 0})
            materials.append(_material(f"{lv.name}_side_cards", len(textures) - 1, double_sided=False))
            prims.append({"attributes": {"POSITION": acc1, "TEXCOORD_0": acc1 + 1, "COLOR_0": acc1 + 2},
                          "indices": acc1 + 3, "material": len(materials) - 1, "mode": 4})
            extras["side_cards"] = {
                "primitive": 1, "quads": lv.cards.n, "turn_degrees": [float(t) for t in lv.cards.turn],
                "note": "fixed quads (not turned to the camera), single sided: the side views' outline, "
                        "hidden from the front (edge-on, or the texels it would show left out)"}
        meshes.append({"name": lv.name, "primitives": prims, "extras": extras})
        nodes.append({"mesh": i, "name": f"tree_lod{i}_{lv.name}"})
    ext = ["KHR_materials_unlit"]
    if lod and len(levels) > 1:
        nodes[0]["extensions"] = {"MSFT_lod": {"ids": list(range(1, len(levels)))}}
        nodes[0]["extras"] = {"MSFT_screencoverage": [float(c) for c in coverage[:len(levels)]]}
        ext = ["KHR_materials_unlit", "MSFT_lod"]
    doc = {
        "asset": {"version": "2.0", "generator": "branchnb.trees level-of-detail chain"},
        "extensionsUsed": ext,
        "scene": 0,
        "scenes": [{"nodes": [0] if lod else list(range(len(levels)))}],
        "nodes": nodes, "meshes": meshes, "materials": materials, "textures": textures,
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071}],
        "images": images,
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(data)).decode()}],
        "bufferViews": views, "accessors": accessors,
    }
    return doc


@checked(yaw=_YAW, height=_HEIGHT, mode=Choice("msft_lod", "files"),
         reduced_share=Real(0, 1, low_open=True))
def export_lod_gltf(cloud, path, *, mode: str = "msft_lod", yaw: float = 0.0, height: float = 10.0,
                    reduced_share: float = 0.3) -> list[Path]:
    """Write the level-of-detail chain of a cloud as glTF 2.0 (self-contained ``.gltf`` files).

    Parameters
    ----------
    cloud : BillboardCloud
        The full cloud; the chain is :func:`lod_chain` of it.
    path : str or Path
        Output ``.gltf`` file. ``mode="files"`` writes ``<stem>_lod0.gltf``
        ... ``<stem>_lod3.gltf`` beside it instead.
    mode : {"msft_lod", "files"}
        One file whose first node carries the ``MSFT_lod`` extension (its
        ``ids`` are the coarser levels' nodes; ``extras.MSFT_screencoverage``
        the hand-over coverages 0.5, 0.2, 0.05), or one file per level.
    yaw, height
        As in :func:`~branchnb.trees.export.export_gltf`.
    reduced_share : float
        Share of the billboards the ``reduced`` level keeps.

    Returns
    -------
    list of Path
        The file(s) written.

    Notes
    -----
    Triangles per level: ``2 K`` (full, ``K`` billboards),
    ``2 ceil(0.3 K) + 2`` (reduced), 4 (crossed), 2 (single); a drawn
    tree's full and reduced levels add 2 per side card (a second
    primitive with a single-sided material; on 12 drawn trees 0 to about
    180 cards, 94 % more triangles on the full level, ``extras.side_cards``),
    which ``extras.triangles`` counts. At 96 px (4 drawn kinds, 2 RPG
    sprites, 6 clip-art samples, 2 trees on a base) the full level has
    10-1580 triangles (cards included; 256 superpixels make a 29 x 96 px
    tree's full level 1272), the reduced 6-510, and no billboard or card
    is empty. Every file passes the Khronos glTF
    validator with no error or warning (checked with ``npx gltf-validator``;
    :func:`validate_gltf` checks the structure without it).

    Examples
    --------
    >>> import os, tempfile
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> out = tempfile.mkdtemp()
    >>> [p.name for p in export_lod_gltf(cloud, os.path.join(out, "t.gltf"), mode="files")]
    ['t_lod0.gltf', 't_lod1.gltf', 't_lod2.gltf', 't_lod3.gltf']
    """
    path = _out_path(path, ".gltf")
    _check_cloud(cloud)
    levels = lod_chain(cloud, reduced_share=reduced_share)
    path.parent.mkdir(parents=True, exist_ok=True)
    if mode == "msft_lod":
        path.write_text(dumps_strict(_document(levels, yaw=yaw, height=height, lod=True),
                                     name="glTF document"))
        return [path]
    out = []
    for i, lv in enumerate(levels):
        p = path.with_name(f"{path.stem}_lod{i}.gltf")
        p.write_text(dumps_strict(_document([lv], yaw=yaw, height=height, lod=False),
                                  name="glTF document"))
        out.append(p)
    return out


def export_full_gltf(cloud, path, *, yaw: float = 0.0, height: float = 10.0) -> Path:
    """Write a cloud as one glTF 2.0 file with a drawn tree's side outline (the ``full`` level alone).

    The billboards carry the side outline baked into their textures
    (:func:`bake_side_outline`) and the rest of it on single-sided side
    cards (:func:`~branchnb.trees.lod_cards.side_outline_cards`, a second
    primitive), as the ``full`` level of :func:`export_lod_gltf`, without
    building the coarser levels. A photographed tree gets neither.

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud to write.
    path : str or Path
        Output ``.gltf`` file (self-contained: embedded buffer and PNG textures).
    yaw : float
        Turn of the tree about its axis in the file (degrees).
    height : float
        Height of the tree in metres (> 0).

    Returns
    -------
    Path
        The written file.

    Examples
    --------
    >>> import os, tempfile
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> p = export_full_gltf(cloud, os.path.join(tempfile.mkdtemp(), "t.gltf"))
    >>> validate_gltf(p)
    []
    """
    from .lod_cards import side_outline_cards

    if isinstance(yaw, bool) or not isinstance(yaw, (int, float, np.integer, np.floating)):
        raise TypeError(f"yaw must be a number (degrees), got {type(yaw).__name__}")
    if not np.isfinite(yaw):
        raise ValueError(f"yaw must be finite, got {yaw}")
    if isinstance(height, bool) or not isinstance(height, (int, float, np.integer, np.floating)):
        raise TypeError(f"height must be a number (metres), got {type(height).__name__}")
    if not (np.isfinite(height) and height > 0):
        raise ValueError(f"height must be a positive number, got {height}")
    path = _out_path(path, ".gltf")
    _check_cloud(cloud)
    baked = bake_side_outline(cloud)
    level = LodLevel("full", baked, cards=side_outline_cards(cloud, baked=baked))
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(dumps_strict(_document([level], yaw=float(yaw), height=float(height), lod=False),
                                 name="glTF document"))
    return path


_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
_SIZES = {5126: 4, 5125: 4, 5123: 2, 5121: 1}


def validate_gltf(path) -> list[str]:
    """Structural checks of a self-contained ``.gltf`` file (the validator's main rules).

    Checks the asset version, that every index (scene, node, mesh,
    material, texture, image, accessor, buffer view) points at an existing
    object, that buffer views lie inside the decoded buffer and accessors
    inside their views, that 4-byte components are 4-byte aligned, that
    ``POSITION`` has its ``min``/``max`` equal to the data's, that indices
    address existing vertices, that ``MSFT_lod`` ids are nodes outside the
    scene and that the extension is declared, and that embedded images are
    PNG.

    Parameters
    ----------
    path : str or Path
        A ``.gltf`` JSON file with its buffers embedded as ``data:`` URIs
        (as :func:`export_lod_gltf` writes them).

    Returns
    -------
    list of str
        The problems found (empty: valid).

    Examples
    --------
    >>> import os, tempfile
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> (path,) = export_lod_gltf(cloud, os.path.join(tempfile.mkdtemp(), "t.gltf"))
    >>> validate_gltf(path)
    []
    """
    import json

    doc = json.loads(Path(path).read_text())
    errs = []
    if doc.get("asset", {}).get("version") != "2.0":
        errs.append("asset.version is not 2.0")
    bufs = []
    for b in doc.get("buffers", []):
        uri = b.get("uri", "")
        if not uri.startswith("data:"):
            errs.append("buffer is not embedded")
            bufs.append(b"")
            continue
        raw = base64.b64decode(uri.split(",", 1)[1])
        if len(raw) != b["byteLength"]:
            errs.append(f"buffer byteLength {b['byteLength']} != data {len(raw)}")
        bufs.append(raw)
    views = doc.get("bufferViews", [])
    for i, v in enumerate(views):
        if not 0 <= v["buffer"] < len(bufs) or v["byteOffset"] + v["byteLength"] > len(bufs[v["buffer"]]):
            errs.append(f"bufferView {i} out of its buffer")
    n = {k: len(doc.get(k, [])) for k in ("nodes", "meshes", "materials", "textures", "images",
                                          "accessors", "samplers")}
    data = {}
    for i, a in enumerate(doc.get("accessors", [])):
        if not 0 <= a["bufferView"] < len(views):
            errs.append(f"accessor {i}: no bufferView {a['bufferView']}")
            continue
        v = views[a["bufferView"]]
        size = _SIZES[a["componentType"]]
        length = a["count"] * _COMPONENTS[a["type"]] * size
        if length > v["byteLength"]:
            errs.append(f"accessor {i} longer than its bufferView")
            continue
        if (v["byteOffset"] + a.get("byteOffset", 0)) % size:
            errs.append(f"accessor {i} misaligned")
        dt = {5126: "<f4", 5125: "<u4", 5123: "<u2", 5121: "u1"}[a["componentType"]]
        raw = bufs[v["buffer"]][v["byteOffset"]:v["byteOffset"] + length]
        data[i] = np.frombuffer(raw, dtype=dt).reshape(a["count"], _COMPONENTS[a["type"]])
        if not np.all(np.isfinite(data[i])):
            errs.append(f"accessor {i} has non-finite values")
    for mi, m in enumerate(doc.get("meshes", [])):
        for prim in m["primitives"]:
            att = prim["attributes"]
            for k, ai in list(att.items()) + [("indices", prim.get("indices", 0))]:
                if not 0 <= ai < n["accessors"]:
                    errs.append(f"mesh {mi}: {k} accessor {ai} missing")
            pos = data.get(att.get("POSITION"))
            acc = doc["accessors"][att["POSITION"]] if att.get("POSITION", -1) < n["accessors"] else {}
            if pos is not None and (not np.allclose(acc.get("min"), pos.min(0))
                                    or not np.allclose(acc.get("max"), pos.max(0))):
                errs.append(f"mesh {mi}: POSITION min/max do not match the data")
            idx = data.get(prim.get("indices"))
            if idx is not None and pos is not None and idx.size and idx.max() >= len(pos):
                errs.append(f"mesh {mi}: index beyond the vertices")
            if idx is not None and idx.size % 3:
                errs.append(f"mesh {mi}: indices not a whole number of triangles")
            if not 0 <= prim.get("material", 0) < n["materials"]:
                errs.append(f"mesh {mi}: material missing")
    for ti, t in enumerate(doc.get("textures", [])):
        if not 0 <= t["source"] < n["images"] or not 0 <= t.get("sampler", 0) < n["samplers"]:
            errs.append(f"texture {ti}: image or sampler missing")
    for ii, im in enumerate(doc.get("images", [])):
        if "uri" in im:
            if not (Path(path).parent / im["uri"]).is_file():
                errs.append(f"image {ii}: file {im['uri']} missing")
            continue
        v = views[im["bufferView"]] if im.get("bufferView", -1) < len(views) else None
        if v is None or bufs[v["buffer"]][v["byteOffset"]:v["byteOffset"] + 8] != b"\x89PNG\r\n\x1a\n":
            errs.append(f"image {ii} is not an embedded PNG")
    in_scene = set()
    for s in doc.get("scenes", []):
        for ni in s["nodes"]:
            if not 0 <= ni < n["nodes"]:
                errs.append(f"scene node {ni} missing")
            in_scene.add(ni)
    for ni, node in enumerate(doc.get("nodes", [])):
        if not 0 <= node.get("mesh", 0) < n["meshes"]:
            errs.append(f"node {ni}: mesh missing")
        lod = node.get("extensions", {}).get("MSFT_lod")
        if lod is not None:
            if "MSFT_lod" not in doc.get("extensionsUsed", []):
                errs.append("MSFT_lod used but not declared")
            for j in lod["ids"]:
                if not 0 <= j < n["nodes"] or j in in_scene:
                    errs.append(f"MSFT_lod id {j} is not a node outside the scene")
    return errs
