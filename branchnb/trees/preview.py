"""Software preview of a billboard cloud from any yaw angle.

An orthographic camera turns about the cloud's vertical axis by ``yaw``
degrees (0 = the input view, 180 = from behind). Billboards are drawn
back to front (painter's algorithm on the rotated depth) with
premultiplied alpha compositing. The pixels of a cloud's line art
(``cloud.line_masks``: the drawn outlines of clip art) are drawn in a first
pass, behind every other pixel, so that from the side they show only along
the silhouette (the front view is the same either way). Two billboard
modes:

* ``facing="camera"`` (default, as the paper's billboard clouds are drawn):
  axial billboards, each quad turned about its vertical axis to face the
  camera; only its centre moves with the yaw.
* ``facing="fixed"``: quads stay parallel to the image plane, as a generic
  glTF/OBJ viewer shows the exported file: they shrink horizontally by
  ``|cos(yaw)|`` (drawn with an OpenCV resize) and show their mirrored
  back side beyond 90 degrees.

Examples
--------
>>> from branchnb import data
>>> from branchnb.trees.billboard import billboard_cloud
>>> cloud = billboard_cloud(data.load("tree_rpg_03"), rng=0)
>>> render_cloud(cloud, 0.0, crop="image").shape == cloud.image.shape
True
"""

from __future__ import annotations

import cv2
import numpy as np

from ..core.image import composite_over
from ..core.validate import Array, Choice, Colour, Instance, Int, Real, checked

__all__ = ["render_cloud", "render_views", "project"]


def project(cloud, yaw: float) -> tuple[np.ndarray, np.ndarray]:
    """Screen ``x`` and depth of the billboard centres for ``yaw`` degrees.

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud; its ``centers`` (x, y, z) in working pixels turn about the
        vertical line ``x = cloud.axis``.
    yaw : float
        Camera angle about the vertical axis, degrees (0 = the input view,
        180 = from behind).

    Returns
    -------
    x, depth : (K,) float arrays
        ``x`` in working pixels (the axis stays at ``cloud.axis``); larger
        depth is nearer the camera. ``y`` does not change with the yaw.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> x, depth = project(cloud, 180.0)  # from behind: mirrored about the axis
    >>> bool(np.allclose(x - cloud.axis, cloud.axis - cloud.centers[:, 0]))
    True
    """
    t = np.deg2rad(float(yaw))
    X = cloud.centers[:, 0] - cloud.axis
    Z = cloud.centers[:, 2]
    x = cloud.axis + X * np.cos(t) + Z * np.sin(t)
    depth = -X * np.sin(t) + Z * np.cos(t)
    return x, depth


def _premultiplied(cloud):
    """Per texture, ``(line part, fill part)`` premultiplied (the line part None if it has none)."""
    cache = getattr(cloud, "_premul_cache", None)
    if cache is None or len(cache) != len(cloud.textures):
        cache = []
        masks = getattr(cloud, "line_masks", None) or [None] * len(cloud.textures)
        for t, m in zip(cloud.textures, masks):
            a = t[:, :, 3:4]
            pre = np.concatenate([t[:, :, :3] * a, a], axis=2).astype(np.float32)
            if m is None:
                cache.append((None, pre))
            else:
                on = m[:, :, None]
                cache.append((np.where(on, pre, 0.0).astype(np.float32), np.where(on, 0.0, pre).astype(np.float32)))
        try:
            object.__setattr__(cloud, "_premul_cache", cache)
        except Exception:  # pragma: no cover
            pass
    return cache


def _extent(cloud) -> tuple[float, float]:
    """Half width about the axis that holds every yaw, and the image's offsets."""
    X = np.abs(cloud.centers[:, 0] - cloud.axis)
    r = np.hypot(X, cloud.centers[:, 2]) + 0.5 * cloud.sizes[:, 0]
    return float(r.max()) if len(r) else 1.0, float(cloud.image.shape[1])


#: The cloud argument of the previews.
_CLOUD = Instance("BillboardCloud")


def _side_view_outline(cloud):
    """``(ink, width)`` of a drawn cloud's silhouette outline, or None (no line art, not outlined)."""
    from .outline import silhouette_outline

    lines = getattr(cloud, "lines", None)
    if lines is None or not np.any(lines):
        return None
    o = silhouette_outline(cloud.image)
    return (o.ink, o.width) if o.outlined else None


def _outline_style(cloud, ink=None, width=None):
    """``(ink, width)`` for a cloud's side-view outline: the given values, else the drawn ones; None if neither.

    Raises ValueError naming ``ink`` or ``width`` when a value is not 3 finite RGB values or a width >= 1.
    """
    drawn = _side_view_outline(cloud)
    if drawn is None and (ink is None or width is None):
        return None
    ink = np.asarray(drawn[0] if ink is None else ink, np.float32)
    width = int(drawn[1] if width is None else width)
    if ink.shape != (3,) or not np.all(np.isfinite(ink)):
        raise ValueError(f"ink must be 3 finite RGB values, got shape {ink.shape}")
    if width < 1:
        raise ValueError(f"width must be >= 1, got {width}")
    return ink, width


def _ink_view(out: np.ndarray, ink, width: int) -> np.ndarray:
    """Ink a rendered view's outer silhouette (gaps between billboards are no drawn holes);
    its soft rim (0 < alpha < 0.5) and its outermost opaque ring take the ink colour too."""
    from scipy import ndimage as ndi

    from .outline import _depth, ink_silhouette

    out = ink_silhouette(out, ink, width, holes=False)
    a = out[:, :, 3]
    soft = (a > 0) & (a < 0.5)
    out[soft, :3] = ink
    # The outermost ring in ink throughout: the drawn shapes' own anti-aliased outlines
    # reach the silhouette of a side view too, and their half-tone rim pixels would break it.
    op = a >= 0.5
    if op.any():
        out[op & (_depth(ndi.binary_fill_holes(op)) == 1), :3] = ink
    return out


@checked(cloud=_CLOUD, yaw=Real(-1e6, 1e6), facing=Choice("camera", "fixed"), height=Int(8, 4096))
def render_cloud(cloud, yaw: float = 0.0, *, facing: str = "camera", crop: str = "fit",
                 background=None, height: int | None = None, outline: bool = True) -> np.ndarray:
    """Render a :class:`~branchnb.trees.billboard.BillboardCloud` from ``yaw`` degrees.

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud to draw (from :func:`~branchnb.trees.billboard.billboard_cloud`).
    yaw : float
        Camera angle about the vertical axis, degrees (0 = input view).
    facing : {"camera", "fixed"}
        Axial billboards facing the camera, or quads fixed parallel to the
        image plane (what a generic viewer shows of the exported file).
    crop : {"fit", "image"}
        ``"image"``: the working image's frame (yaw 0 then lines up with
        the input pixel for pixel); ``"fit"``: a frame wide enough for
        every yaw, centred on the axis (stable for animations).
    background : RGB tuple, optional
        Composite over this colour and return RGB; RGBA if None.
    height : int, optional
        Resize the result to this height.
    outline : bool
        Beyond the paper, for drawn trees (line art found and an outlined
        silhouette, :func:`~branchnb.trees.outline.silhouette_outline`):
        ink the silhouette of views other than the front view, in the
        drawing's ink colour and stroke width. The strokes that outline
        the drawing's silhouette stay on the front billboards; from the
        side, the crown's new rim is made of fills and would show no
        outline. The front view (yaw a multiple of 360) is left as it is.

    Returns
    -------
    (H, W', 4) or (H, W', 3) float32 ndarray
        Straight RGBA (or RGB over ``background``) in [0, 1]; ``H`` is the
        working image's height (or ``height``), ``W'`` its width for
        ``crop="image"``.

    Raises
    ------
    ValueError
        Unknown ``facing`` or ``crop``, or a yaw that is not finite.

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> render_cloud(cloud, 0.0, crop="image").shape, render_cloud(cloud, 90.0, background=(1, 1, 1)).shape[2]
    ((64, 64, 4), 3)
    """
    if facing not in ("camera", "fixed"):
        raise ValueError(f"facing must be 'camera' or 'fixed', got {facing!r}")
    if crop not in ("fit", "image"):
        raise ValueError(f"crop must be 'fit' or 'image', got {crop!r}")
    yaw = float(yaw)
    if not np.isfinite(yaw):
        raise ValueError(f"yaw must be finite, got {yaw}")
    H, W = cloud.image.shape[:2]
    if crop == "image":
        ox, Wc = 0, W
    else:
        r, _ = _extent(cloud)
        left = int(np.ceil(max(cloud.axis, r))) + 1
        right = int(np.ceil(max(W - cloud.axis, r))) + 1
        ox, Wc = left - int(round(cloud.axis)), left + right
    canvas = np.zeros((H, Wc, 4), np.float32)
    xs, depth = project(cloud, yaw)
    c = np.cos(np.deg2rad(yaw))
    texs = _premultiplied(cloud)
    order = np.argsort(depth, kind="stable")
    draws = [(i, 0) for i in order if texs[cloud.texture[i]][0] is not None] + [(i, 1) for i in order]
    for i, part in draws:
        tex = texs[cloud.texture[i]][part]
        h, w = tex.shape[:2]
        if facing == "fixed":
            nw = int(round(w * abs(c)))
            if nw < 1:
                continue
            if nw != w:
                tex = cv2.resize(tex, (nw, h), interpolation=cv2.INTER_AREA if nw < w else cv2.INTER_LINEAR)
            if c < 0:
                tex = tex[:, ::-1]
            w = nw
        x0 = int(round(xs[i] - 0.5 * w)) + ox
        y0 = int(round(cloud.centers[i, 1] - 0.5 * h))
        ax0, ay0 = max(x0, 0), max(y0, 0)
        ax1, ay1 = min(x0 + w, Wc), min(y0 + h, H)
        if ax1 <= ax0 or ay1 <= ay0:
            continue
        src = tex[ay0 - y0: ay1 - y0, ax0 - x0: ax1 - x0]
        tint = float(cloud.tint[i])
        dst = canvas[ay0:ay1, ax0:ax1]
        a = src[:, :, 3:4]
        dst[:, :, :3] = src[:, :, :3] * tint + dst[:, :, :3] * (1.0 - a)
        dst[:, :, 3:4] = a + dst[:, :, 3:4] * (1.0 - a)
    a = canvas[:, :, 3:4]
    rgb = np.where(a > 1e-6, canvas[:, :, :3] / np.maximum(a, 1e-6), 0.0)
    out = np.concatenate([rgb, a], axis=2).clip(0, 1).astype(np.float32)
    if outline and yaw % 360.0 != 0.0:
        drawn = _side_view_outline(cloud)
        if drawn is not None:
            out = _ink_view(out, *drawn)
    if background is not None:
        out = composite_over(out, background).astype(np.float32)
    if height is not None and height != out.shape[0]:
        nw = max(1, round(out.shape[1] * height / out.shape[0]))
        out = cv2.resize(out, (nw, int(height)), interpolation=cv2.INTER_AREA)
    return out


@checked(cloud=_CLOUD, yaws=Array(ndim=1, min=-1e6, max=1e6), height=Int(8, 4096), gap=Int(0, 1000),
         background=Colour())
def render_views(cloud, yaws=(0.0, 60.0, 120.0), *, height: int = 256, facing: str = "camera",
                 background=(1.0, 1.0, 1.0), gap: int = 4) -> np.ndarray:
    """Side-by-side RGB previews from several yaw angles (a contact strip).

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud to draw.
    yaws : (V,) array_like
        Camera angles in degrees, one view each, left to right.
    height : int
        Height of every view in pixels (widths keep the aspect ratio).
    facing : {"camera", "fixed"}
        Billboard mode, as in :func:`render_cloud`.
    background : RGB tuple
        Colour the views are composited over and the gaps are filled with.
    gap : int
        Pixels between neighbouring views.

    Returns
    -------
    (height, W, 3) float32 ndarray
        The views side by side, each a ``crop="fit"`` render (the same
        width for every yaw).

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> render_views(cloud, (0, 90), height=32, gap=2).shape
    (32, 70, 3)
    """
    views = [render_cloud(cloud, y, facing=facing, background=background, height=height) for y in yaws]
    bg = np.asarray(background, np.float32)
    strip = [views[0]]
    for v in views[1:]:
        strip.append(np.broadcast_to(bg, (height, gap, 3)))
        strip.append(v)
    return np.concatenate(strip, axis=1).astype(np.float32)
