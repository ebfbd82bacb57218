"""How much of a drawn tree's inner line work a side view of its billboard cloud keeps (issue 24).

Beyond the paper. A drawn tree's crown is flat fills bounded by thin dark
strokes; the strokes inside the silhouette (between two clumps, round a
fruit, along a conifer's tiers) are its *inner outlines*. Seen from the
side, a billboard cloud moves its billboards apart in depth: the strokes
travel on the billboards that carry them, and are kept when the side view
still shows those texels; where nearer billboards with plain fill cover
them, the crown becomes a smeared flat blob.

:func:`side_line_figures` scores a side view as an engine draws it
(:func:`~branchnb.trees.lod.engine_view`, axial billboards, depth
buffered) with two numbers:

* ``recall``: the share of the front view's inner-outline pixels
  (:func:`~branchnb.trees.billboard_lines.line_art` minus the strokes along
  the silhouette) that the side view still draws. The side view is undone
  billboard by billboard: every pixel it shows is a texel of one
  billboard, which sits at a known place of the front image; a stroke
  pixel counts as kept when a texel at most ``tol`` pixels from it, in its
  stroke colour (within 0.15 RGB), is shown. This undoes the horizontal
  squeeze and the parallax of every billboard exactly, so a drawing whose
  billboards all kept their strokes scores 1 whatever its depth.
* ``smear``: the share of the side view's flat pixels whose colour is
  farther than 0.12 from every dominant colour of the front view
  (:func:`~branchnb.trees.quality.crossfade_fraction`): blended or
  resampled colours the drawing does not have.

Examples
--------
>>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
>>> from branchnb.trees.drawn import drawn_tree
>>> cloud = billboard_cloud(drawn_tree("fruit", rng=0, size=96), params=BillboardParams(max_size=96), rng=0)
>>> f = side_line_figures(cloud, 0.0)
>>> f["recall"] > 0.95, f["smear"] < 0.01
(True, True)
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

__all__ = ["inner_lines", "side_line_figures"]


def inner_lines(cloud) -> np.ndarray:
    """The inner outlines of a cloud's drawing: its line art off the silhouette.

    Parameters
    ----------
    cloud : BillboardCloud
        A billboard cloud (:func:`~branchnb.trees.billboard.billboard_cloud`).

    Returns
    -------
    (H, W) bool ndarray
        Stroke pixels of ``cloud.lines`` farther than about one stroke
        width from the silhouette (all False for a photograph).

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.drawn import drawn_tree
    >>> cloud = billboard_cloud(drawn_tree("conifer", rng=0, size=96), rng=0)
    >>> bool(inner_lines(cloud).any())
    True
    """
    from .billboard_lines import _outer_lines

    lines = getattr(cloud, "lines", None)
    if lines is None:
        raise TypeError("cloud must be a BillboardCloud")
    lines = np.asarray(lines, bool)
    opaque = cloud.image[..., 3] >= 0.5
    return lines & opaque & ~_outer_lines(lines, opaque)


def _front_positions(cloud, ids: np.ndarray, texel: np.ndarray):
    """Front-image ``(x, y)`` of the texel shown at each pixel (ids >= 0)."""
    from .lod import _texel_offsets

    offsets = _texel_offsets(cloud)
    shown = ids >= 0
    b = ids[shown]
    f = texel[shown]
    t = np.searchsorted(offsets, f, side="right") - 1
    widths = np.array([tx.shape[1] for tx in cloud.textures])
    local = f - offsets[t]
    v, u = local // widths[t], local % widths[t]
    w = cloud.sizes[b, 0]
    h = cloud.sizes[b, 1]
    x0 = np.round(cloud.centers[b, 0] - 0.5 * w).astype(np.int64)
    y0 = np.round(cloud.centers[b, 1] - 0.5 * h).astype(np.int64)
    return shown, x0 + u, y0 + v, t, local


def side_line_figures(cloud, yaw: float, *, tol: int = 1, view=None) -> dict:
    """Inner-outline recall and colour smear of a drawn cloud's side view (see the module).

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud as an engine draws it (e.g. after
        :func:`~branchnb.trees.lod.bake_side_outline`); not modified.
    yaw : float
        Camera angle about the vertical axis, degrees.
    tol : int
        Pixels (in the front image) a kept stroke texel may lie from the
        stroke pixel it stands for.
    view : (H, W', 4) array_like, optional
        The side view to score for ``smear`` (default
        :func:`~branchnb.trees.lod.engine_view` of ``cloud`` at ``yaw``).

    Returns
    -------
    dict
        ``recall`` (float in [0, 1]; 1 when the drawing has no inner
        outline), ``smear`` (float in [0, 1]), ``lines`` (number of inner
        outline pixels of the front view).

    Raises
    ------
    ValueError
        ``yaw`` not finite or ``tol`` negative.

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.drawn import drawn_tree
    >>> cloud = billboard_cloud(drawn_tree("conifer", rng=0, size=96), rng=0)
    >>> sorted(side_line_figures(cloud, 45.0))
    ['lines', 'recall', 'smear']
    """
    from .lod import _view_ids, engine_view
    from .quality import crossfade_fraction

    yaw = float(yaw)
    if not np.isfinite(yaw):
        raise ValueError(f"yaw must be finite, got {yaw}")
    if int(tol) != tol or tol < 0:
        raise ValueError(f"tol must be an integer >= 0, got {tol}")
    tol = int(tol)
    img = cloud.image
    H, W = img.shape[:2]
    want = inner_lines(cloud)
    n = int(want.sum())
    if view is None:
        view = engine_view(cloud, yaw)
    smear = float(crossfade_fraction(view, [img]))
    if n == 0:
        return {"recall": 1.0, "smear": smear, "lines": 0}
    ids, texel = _view_ids(cloud, yaw)
    shown, fx, fy, t, local = _front_positions(cloud, ids, texel)
    colours = np.concatenate([tx[..., :3].reshape(-1, 3) for tx in cloud.textures])
    from .lod import _texel_offsets

    col = colours[_texel_offsets(cloud)[t] + local]
    inside = (fx >= 0) & (fx < W) & (fy >= 0) & (fy < H)
    fx, fy, col = fx[inside], fy[inside], col[inside]
    on = want[fy, fx] & (np.linalg.norm(col - img[fy, fx, :3], axis=1) <= 0.15)
    kept = np.zeros((H, W), bool)
    kept[fy[on], fx[on]] = True
    if tol:
        kept = ndi.binary_dilation(kept, np.ones((2 * tol + 1, 2 * tol + 1), bool))
    return {"recall": float((kept & want).sum() / n), "smear": smear, "lines": n}
