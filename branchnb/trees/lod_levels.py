"""Levels of detail, the cheaper levels: a reduced cloud, the crossed impostor and the impostor
frames (beyond the paper, issue 24).

Part of :mod:`branchnb.trees.lod` (split from it; every name is importable from there too).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.validate import Real, checked
from .export import _check_cloud
from .lod_view import _opaque_texels, _subset, _view_ids

__all__ = ["reduce_cloud", "impostor_cloud", "impostor_frames", "crossed_impostor"]


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
    >>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> img = synthetic_tree("clean", rng=0, size=64).image   # the paper's cloud, not drawn cards
    >>> cloud = billboard_cloud(img, params=BillboardParams(drawn_cards=False), rng=0)
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
    # Its texels below the alpha cutoff (0.5, as exported) go: behind the kept billboards' own
    # anti-aliased rim they stacked a second soft, darker layer (resampled RGBA is dark where
    # alpha is low) and turned the rim's ink darker (tree_rpg_05 at 96 px: rim ink share of the
    # level 0.89 at 0, 45 and 90 degrees, 0.97-1.0 without them); an engine with the cutoff
    # drops them anyway.
    tex = imp.textures[0].copy()
    tex[tex[..., 3] < 0.5] = 0.0
    imp.textures[0] = tex
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
    """:func:`~branchnb.trees.lod_view._subset` keeping the billboards' ``source`` (the impostor's stays -1)."""
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

