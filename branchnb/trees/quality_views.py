"""Quality measures of billboard clouds seen from the side: flat-region speckle, flecks and stray ink.

Split from :mod:`branchnb.trees.quality` (every name is still importable from there).

Examples
--------
>>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
>>> from branchnb.trees.drawn import drawn_tree
>>> cloud = billboard_cloud(drawn_tree("conifer", rng=0, size=96), rng=0)
>>> 0.0 <= flat_region_speckle(cloud, 45.0) <= 1.0
True
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi
from scipy.spatial import cKDTree

from .quality import colour_span, dominant_palette

__all__ = ["flat_region_speckle", "side_view_figures"]


def flat_region_speckle(cloud, yaw: float, *, min_area: float = 0.01, busy: float = 0.15,
                        margin: int = 2) -> float:
    """Share of the front view's large flat regions that are busy in the view from ``yaw``.

    The flat regions are the crown pixels of the working image whose 5 x 5
    colour span is at most ``busy``, in 4-connected pieces of at least
    ``min_area`` times the crown's area, shrunk by ``margin`` pixels. Each
    such pixel is carried to the side view with the front billboard that
    shows it in the front view (axial billboards move as a whole); there
    it counts as speckled when the side view (over white, so sky showing
    through counts) spans more than ``busy`` in its 5 x 5 window. Both
    spans are measured over white, so a cloud that reproduces its input
    scores 0 at yaw 0. Pixels carried out of the frame are left out. The
    side view is rendered without the silhouette ink of drawn trees
    (``render_cloud(..., outline=False)``): an outline is no speckle.

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud (its ``image``, ``superpixels`` and front billboards).
    yaw : float
        Camera angle of the side view, degrees.
    min_area : float
        Smallest flat region kept, as a fraction of the crown's area.
    busy : float
        Largest 5 x 5 colour span of a flat pixel; a side-view pixel above
        it is speckled.
    margin : int
        Erosion of the flat regions in pixels (their edges are left out).

    Returns
    -------
    float
        Speckled share in [0, 1] (0 when there is no large flat region).

    Examples
    --------
    >>> from branchnb import data
    >>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
    >>> c = billboard_cloud(data.load("cartoon_tree"), params=BillboardParams(max_size=128), rng=0)
    >>> flat_region_speckle(c, 0.0) < 0.02
    True
    """
    from ..core.image import composite_over
    from .billboard import FRONT
    from .preview import project, render_cloud

    img = cloud.image
    H, W = img.shape[:2]
    crown = (cloud.superpixels > 0) & (img[..., 3] >= 0.99)
    if not crown.any():
        return 0.0
    # Flat as seen over white, like the side view: a soft rim pixel whose
    # straight colour matches its neighbours still shows as a grey edge.
    flat = crown & (colour_span(composite_over(img, (1.0, 1.0, 1.0))) <= busy)
    lab, n = ndi.label(flat)
    area = np.bincount(lab.ravel(), minlength=n + 1)
    big = np.flatnonzero(area >= min_area * crown.sum())
    big = big[big > 0]
    flat = np.isin(lab, big)
    if margin > 0:
        flat = ndi.binary_erosion(flat, iterations=margin)
    if not flat.any():
        return 0.0
    # Which front billboard shows each pixel in the front view (the nearest one).
    x0s, _ = project(cloud, 0.0)
    xs, _ = project(cloud, yaw)
    shift = np.full((H, W), np.nan)
    front = np.flatnonzero(cloud.layer == FRONT)
    for i in front[np.argsort(cloud.centers[front, 2], kind="stable")]:
        t = cloud.textures[cloud.texture[i]]
        h, w = t.shape[:2]
        bx, by = int(round(x0s[i] - 0.5 * w)), int(round(cloud.centers[i, 1] - 0.5 * h))
        on = t[..., 3] >= 0.5
        ys, xx = np.nonzero(on)
        ys, xx = ys + by, xx + bx
        ok = (ys >= 0) & (ys < H) & (xx >= 0) & (xx < W)
        dx = int(round(xs[i] - 0.5 * w)) - bx
        shift[ys[ok], xx[ok]] = dx
    ys, xx = np.nonzero(flat & np.isfinite(shift))
    if len(ys) == 0:
        return 0.0
    xx = xx + shift[ys, xx].astype(int)
    inside = (xx >= 0) & (xx < W)
    ys, xx = ys[inside], xx[inside]
    if len(ys) == 0:
        return 0.0
    side = composite_over(render_cloud(cloud, yaw, crop="image", outline=False), (1.0, 1.0, 1.0))
    return float((colour_span(side)[ys, xx] > busy).mean())


def side_view_figures(cloud, yaw: float, *, small: float = 0.003) -> dict:
    """How well a drawn tree's billboard cloud keeps its drawing in the view from ``yaw``.

    Measured on the default rendering (:func:`~branchnb.trees.preview.render_cloud`,
    silhouette ink included), against the same numbers in the front view:

    * ``flecks``: share of the opaque non-ink pixels that lie in small
      colour pieces: each pixel takes its nearest dominant colour of the
      front view (:func:`dominant_palette`; pixels farther than 0.12 from
      all of them, anti-aliased edges, are left out), and an 8-connected
      piece of one colour smaller than ``small`` times the tree's opaque
      area is a fleck (a fruit scattered into crumbs, a sliver of another
      shape's fill);
    * ``fragments``: share of the ink pixels (luminance at most the drawing's
      ink threshold) in 8-connected ink pieces smaller than ``small`` times
      the opaque area: loose stroke bits;
    * ``inner_ink``: ink pixels deeper than ``2 w + 1`` from the view's
      outer silhouette (``w`` the outline width), over the same count in the
      front view: the inner outlines kept (1: as many as drawn; smeared or
      lost outlines lower it, stroke bits piled up raise it).

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud of a drawn tree (its ``image`` gives the ink threshold,
        the outline width and the palette).
    yaw : float
        Camera angle of the view measured, degrees (a multiple of 360 is
        the front view).
    small : float
        Pieces smaller than this fraction of the view's opaque area are
        flecks or fragments (default 0.003).

    Returns
    -------
    dict
        ``{"flecks", "fragments", "inner_ink"}`` at ``yaw`` and
        ``{"flecks0", "fragments0"}`` of the front view.

    Examples
    --------
    >>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
    >>> from branchnb.trees.drawn import drawn_tree
    >>> c = billboard_cloud(drawn_tree("fruit", rng=0, size=128), params=BillboardParams(max_size=128))
    >>> f = side_view_figures(c, 0.0)
    >>> f["inner_ink"], f["flecks"] == f["flecks0"]
    (1.0, True)
    """
    from .outline import _depth, _ink_threshold, _is_ink, silhouette_outline
    from .preview import render_cloud

    img = cloud.image
    opaque0 = img[..., 3] >= 0.5
    thr = _ink_threshold(img[..., :3], opaque0)
    width = silhouette_outline(img).width
    palette = dominant_palette([img])

    def figures(view):
        op = view[..., 3] >= 0.5
        n_op = max(int(op.sum()), 1)
        ink = op & _is_ink(view[..., :3], thr)
        lim = small * n_op
        eight = np.ones((3, 3), bool)
        lab, n = ndi.label(ink, structure=eight)
        area = np.bincount(lab.ravel(), minlength=n + 1)
        area[0] = 0
        frag = float(area[area < lim].sum() / max(area.sum(), 1))
        fill = op & ~ink
        flecks = 0.0
        if len(palette) and fill.any():
            d, idx = cKDTree(palette).query(view[fill][:, :3])
            col = np.full(op.shape, -1)
            col[fill] = np.where(d <= 0.12, idx, -1)
            small_px = 0
            for c in np.unique(col[col >= 0]):
                lab, n = ndi.label(col == c, structure=eight)
                a = np.bincount(lab.ravel(), minlength=n + 1)
                a[0] = 0
                small_px += int(a[(a > 0) & (a < lim)].sum())
            flecks = small_px / max(int(fill.sum()), 1)
        deep = _depth(ndi.binary_fill_holes(op)) > 2 * width + 1
        return flecks, frag, int((ink & deep).sum())

    f0 = figures(render_cloud(cloud, 0.0, crop="fit"))
    f = f0 if float(yaw) % 360.0 == 0.0 else figures(render_cloud(cloud, yaw, crop="fit"))
    return {"flecks": f[0], "fragments": f[1], "inner_ink": f[2] / max(f0[2], 1),
            "flecks0": f0[0], "fragments0": f0[1]}
