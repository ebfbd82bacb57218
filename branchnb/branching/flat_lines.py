"""Lines of one flat colour on a textured ground, redrawn in that colour (beyond the paper, issue 23).

Pale roots of one paint on a soil with grain and pebbles, chalk lines on a blackboard, ink on paper
grain, white crack fill on asphalt: the ground is a texture (so the example goes the paper's fragment
path, not the flat drawing of :mod:`.output_regions`), but every line pixel has the same colour. Copied
fragment by fragment, such lines come out wrong in two ways:

* the gradient-domain correction of a seam that cuts a line spreads the line's colour across the seam:
  pale glowing halos at junctions and tips (roots 384 px: 7 % of the pixels 2-8 px off the lines as
  pale as a root, against 0 in the example);
* the bent fragments' edges do not follow the target's radii: ragged, bumpy lines of uneven width
  where the example's are crisp.

:func:`flat_line_colour` recognises such an example (the lines' core pixels spread far less than the
ground's, and far less than the contrast between the two), and :func:`redraw_flat_lines` takes the
finished output, quilts ground over its line pixels, their halos and whatever of the copied lines
strays off the target's lines (from the example's branch-free ground, the gap completion's patch loop),
then draws the target's lines anti-aliased in the example's line colour at the structure's radii times
the example's own width ratio (:func:`line_width_scale`). The ground stays the one the fragments and
the gap completion made (the Poisson correction keeps it seamless); only line pixels and their
neighbourhood change.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.render import coverage_polylines
from ..core.structure import Structure
from .skeleton_map import PixelMap

__all__ = ["flat_line_colour", "line_width_scale", "redraw_flat_lines"]

#: The lines' robust colour spread (core pixels) is at most this share of the ground's ...
SPREAD_RATIO = 0.5
#: ... and at most this share of the contrast between the lines' colour and the ground's.
SPREAD_CONTRAST = 0.12
#: The ground's own spread is at least this share of the contrast: a flatter ground is a drawing's.
GROUND_TEXTURE = 0.02
#: Fewest core pixels the lines' colour is measured on.
MIN_CORE = 60
#: An output pixel at least this far along from the ground's colour to the lines' is line paint.
PAINT = 0.35


def _spread(pixels: np.ndarray, centre: np.ndarray) -> float:
    """Robust spread (1.4826 x the median distance to ``centre``) of colour ``pixels``."""
    return float(1.4826 * np.median(np.linalg.norm(pixels - centre, axis=1)))


def flat_line_colour(image: np.ndarray, pm: PixelMap, unusable: np.ndarray | None = None
                     ) -> tuple[np.ndarray, np.ndarray] | None:
    """``(line colour, ground colour)`` of an example whose lines are one flat colour, or None.

    Parameters
    ----------
    image : (H, W, C) float ndarray
        The example (channels beyond the third are ignored).
    pm : PixelMap
        The example structure's pixel map.
    unusable : (H, W) bool ndarray, optional
        Example pixels to leave out of both measures (a matte).

    Returns
    -------
    (line, ground) : two (3,) float ndarrays, or None
        The medians of the lines' core pixels and of a ring 3-8 px off the lines, when the lines'
        spread is at most :data:`SPREAD_RATIO` of the ground's and :data:`SPREAD_CONTRAST` of their
        contrast, and the ground is textured (spread at least :data:`GROUND_TEXTURE` of the contrast).
    """
    rgb = np.asarray(image, np.float32)
    if rgb.ndim != 3 or rgb.shape[2] < 3:
        return None
    rgb = rgb[..., :3]
    ok = np.ones(pm.dist.shape, bool) if unusable is None else ~unusable
    core = ok & (pm.dist <= np.maximum(0.5 * pm.radius - 0.5, 0.5))
    ring = ok & (pm.dist >= pm.radius + 3.0) & (pm.dist <= pm.radius + 8.0)
    if core.sum() < MIN_CORE or ring.sum() < MIN_CORE:
        return None
    lp, gp = rgb[core], rgb[ring]
    line, ground = np.median(lp, axis=0), np.median(gp, axis=0)
    contrast = float(np.linalg.norm(line - ground))
    if contrast < 0.1:
        return None
    s_line, s_ground = _spread(lp, line), _spread(gp, ground)
    if s_line > SPREAD_RATIO * s_ground or s_line > SPREAD_CONTRAST * contrast \
            or s_ground < GROUND_TEXTURE * contrast:
        return None
    return line.astype(np.float32), ground.astype(np.float32)


def _paint_share(image: np.ndarray, line: np.ndarray, ground: np.ndarray) -> np.ndarray:
    """How far along from ``ground`` to ``line`` every pixel's colour lies (0 ground, 1 line)."""
    d = (line - ground).astype(np.float32)
    return ((image[..., :3] - ground) @ d) / float(d @ d)


def _coverage(structure: Structure, shape, scale: float) -> np.ndarray:
    polylines = [b.points for b in structure.branches]
    widths = [2.0 * scale * np.asarray(b.thickness, float) for b in structure.branches]
    return coverage_polylines(shape, polylines, widths)[0]


def line_width_scale(image: np.ndarray, structure: Structure, pm: PixelMap, line: np.ndarray,
                     ground: np.ndarray) -> float:
    """The example's painted line width over its structure's ``2 r`` (area ratio near the lines).

    Parameters
    ----------
    image : (H, W, C) float ndarray
        The example.
    structure : Structure
        Its structure.
    pm : PixelMap
        Its pixel map.
    line, ground : (3,) float ndarray
        Colours from :func:`flat_line_colour`.

    Returns
    -------
    float
        In [0.6, 1.6]: the painted area (paint share over 0.5 within ``2 r + 3`` px of the lines)
        over the area of the structure drawn at its radii.
    """
    near = pm.dist <= 2.0 * pm.radius + 3.0
    painted = float(np.sum((_paint_share(image, line, ground) >= 0.5) & near))
    drawn = float(np.sum(_coverage(structure, image.shape[:2], 1.0)[near]))
    return float(np.clip(painted / max(drawn, 1.0), 0.6, 1.6))


def redraw_flat_lines(canvas: np.ndarray, example: np.ndarray, forbidden: np.ndarray, structure: Structure,
                      pm: PixelMap, line: np.ndarray, ground: np.ndarray, scale: float, quilt,
                      known: np.ndarray | None = None) -> np.ndarray:
    """``canvas`` with its lines redrawn in the flat colour ``line`` at ``structure``'s radii (in place).

    Parameters
    ----------
    canvas : (H, W, C) float32 ndarray
        The synthesised output (modified and returned).
    example : (h, w, C) float32 ndarray
        The example (ground is quilted from it).
    forbidden : (h, w) bool ndarray
        Example pixels never copied (its lines with a margin).
    structure : Structure
        The output's structure.
    pm : PixelMap
        Its pixel map on the canvas.
    line, ground : (3,) float ndarray
        Colours from :func:`flat_line_colour`.
    scale : float
        Width scale from :func:`line_width_scale`.
    quilt : callable(canvas, covered, example, forbidden)
        Fills the canvas's uncovered pixels in place from the example's allowed pixels.
    known : (H, W) bool ndarray, optional
        Canvas pixels synthesised (fragments or gap completion; default all): only these are
        cleared and quilted (without gap completion the rest stays empty).

    Returns
    -------
    (H, W, C) float32 ndarray
        ``canvas``.

    Notes
    -----
    Cleared before the ground is quilted: every pixel the lines will cover, and every pixel within
    ``3 r + 4`` px of the lines (a fragment's reach) whose colour is at least :data:`PAINT` of the way
    to the line colour (halos, stray copied line edges), each with a 2 px margin so the patches'
    colour correction is anchored to clean ground.
    """
    H, W = canvas.shape[:2]
    cov = _coverage(structure, (H, W), scale)
    reach = pm.dist <= 3.0 * pm.radius + 4.0
    paint = reach & (_paint_share(canvas, line, ground) >= PAINT)
    if known is not None:
        paint &= known
    hole = ndi.binary_dilation((cov > 0) | paint, iterations=2)
    if known is not None:
        hole &= known
    covered = ~hole
    if hole.any() and covered.any():
        quilt(canvas, covered, example, forbidden)
    a = cov[..., None]
    n = min(3, canvas.shape[2])
    colour = line[:n] if n == 3 else np.array([float(line @ np.array([0.2126, 0.7152, 0.0722]))])
    canvas[..., :n] = canvas[..., :n] * (1.0 - a) + colour[None, None, :n] * a
    if canvas.shape[2] == 4:
        canvas[..., 3] = canvas[..., 3] + cov * (1.0 - canvas[..., 3])
    return canvas
