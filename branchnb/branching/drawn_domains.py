"""Photographed-looking examples with a drawn region boundary: land from land, and the coast drawn.

A printed terrain map (grey hill shading with pixel noise, rivers, a black
coastline around the land on white) is not flat-colour, so it is synthesised
the paper's way, with fragments and gap completion. Copied fragments carry
the shading around the rivers, but no fragment carries the coast, and gap
completion fills the land with whatever texture matches best (the white
outside): the output is rivers in white with no coastline (coast share
0.04-0.13 on procedural shaded terrain maps).

Going beyond the paper (which has no regions): when the example's domain
(:func:`~branchnb.branching.backgrounds.example_domain`) is walled off by a
drawn line (:func:`drawn_boundary`) and the output's domain is known (the
``SynthesisResult.domain`` its structure grew in), fragments and gap
completion take the land from the example's land and the outside from its
outside (region labels :func:`domain_labels`), and the example's boundary
line is drawn along the output's domain boundary (:func:`draw_boundary`).
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from scipy import ndimage as ndi

from ..core.render import coverage_polylines
from ..core.structure import Structure
from .skeleton_map import PixelMap

__all__ = ["DrawnBoundary", "domain_labels", "draw_boundary", "drawn_boundary"]


@dataclass
class DrawnBoundary:
    """The example's domain and the line drawn along its boundary.

    Parameters
    ----------
    domain : (h, w) bool ndarray
        The example's domain (where its branches live).
    colour : (C,) ndarray
        Colour of the boundary line.
    width : float
        Its width in pixels.
    ink : (h, w) bool ndarray
        The example's boundary-line pixels (never copied into a region).
    """

    domain: np.ndarray
    colour: np.ndarray
    width: float
    ink: np.ndarray


def drawn_boundary(image: np.ndarray, structure: Structure, pm: PixelMap) -> DrawnBoundary | None:
    """The example's domain and its drawn boundary line, or None when no line walls it off.

    Parameters
    ----------
    image : (h, w, C) float32 ndarray
        The example.
    structure : Structure
        Its branches.
    pm : PixelMap
        The structure's pixel map on the example.

    Returns
    -------
    DrawnBoundary or None
        None when the domain is (almost) the whole image or nothing, or when
        less than half of its boundary away from the branches and the frame
        is drawn in a colour unlike both sides (a photograph's sky, a fundus
        matte: no line).

    Notes
    -----
    The line's colour and width are read as for drawn maps
    (:func:`~branchnb.branching.drawing.drawing_style`), with the domain as
    the branch region.

    Examples
    --------
    >>> from branchnb.branching._map_examples import terrain_map_example
    >>> from branchnb.branching.skeleton_map import SkeletonMap
    >>> img, s, _ = terrain_map_example((128, 128), 0, relief="shade", n_trees=6)
    >>> b = drawn_boundary(img, s, SkeletonMap(s, 1.0).pixel_map((128, 128)))
    >>> b is not None and bool(b.colour.max() < 0.3)
    True
    """
    from .backgrounds import example_domain
    from .drawing import drawing_style

    img = np.asarray(image, np.float32)
    if img.shape[2] not in (1, 3, 4):
        return None
    rgb = img[..., :3] if img.shape[2] >= 3 else np.repeat(img, 3, axis=2)
    dom = np.asarray(example_domain(rgb, structure), bool)
    if not 0.02 < dom.mean() < 0.98:
        return None
    style = drawing_style(img, structure, dom.astype(np.int64), pm)
    if style.boundary_colour is None or style.branch_region != 1:
        return None
    col = style.boundary_colour
    # the line's pixels: near the domain's boundary, in the line's colour, off the branches
    edge = dom & ndi.binary_dilation(~dom) | ~dom & ndi.binary_dilation(dom)
    near = ndi.binary_dilation(edge, iterations=int(np.ceil(style.boundary_width)) + 2)
    ink = near & (np.linalg.norm(img - col, axis=-1) < 0.35) & (pm.dist > pm.radius + 1.0)
    ink = ndi.binary_dilation(ink, iterations=1) & near
    return DrawnBoundary(dom, col.astype(np.float32), float(style.boundary_width), ink)


def domain_labels(domain: np.ndarray, ink: np.ndarray | None = None) -> np.ndarray:
    """Region labels of a domain: 1 inside, 0 outside, 2 on ``ink`` (a label no output pixel has).

    Parameters
    ----------
    domain : (H, W) array_like of bool
        Inside of the domain.
    ink : (H, W) array_like of bool, optional
        The drawn boundary line's pixels.

    Examples
    --------
    >>> import numpy as np
    >>> domain_labels(np.array([[True, False]]), np.array([[False, True]])).tolist()
    [[1, 2]]
    """
    lab = np.asarray(domain, bool).astype(np.int64)
    if ink is not None:
        lab[np.asarray(ink, bool)] = 2
    return lab


def draw_boundary(image: np.ndarray, inside: np.ndarray, colour, width: float) -> np.ndarray:
    """Draw a line of ``colour`` and ``width`` along the boundary of ``inside`` (not the frame).

    Parameters
    ----------
    image : (H, W, C) float32 ndarray
        Drawn on (a copy is returned).
    inside : (H, W) bool ndarray
        The region whose boundary is drawn.
    colour : (C,) array_like
        Line colour.
    width : float
        Line width in pixels (anti-aliased).

    Returns
    -------
    (H, W, C) float32 ndarray

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((20, 20), bool); m[5:15, 5:15] = True
    >>> out = draw_boundary(np.ones((20, 20, 3), np.float32), m, (0, 0, 0), 2.0)
    >>> float(out[5, 10, 0]) < 0.5, float(out[10, 10, 0])
    (True, 1.0)
    """
    from skimage import measure

    img = np.array(image, np.float32, copy=True)
    m = np.asarray(inside, bool)
    h, w = m.shape
    if not m.any() or m.all():
        return img
    lines = []
    pad = np.pad(m.astype(np.float32), 1, mode="edge")
    for c in measure.find_contours(pad, 0.5):
        pts = c[:, ::-1] - 1.0
        on_frame = (pts[:, 0] <= 0) | (pts[:, 1] <= 0) | (pts[:, 0] >= w - 1) | (pts[:, 1] >= h - 1)
        cut = np.flatnonzero(np.diff(on_frame.astype(int)))
        for piece in np.split(np.arange(len(pts)), cut + 1):
            if len(piece) >= 2 and not on_frame[piece].all():
                lines.append(pts[piece])
    if lines:
        cov, _ = coverage_polylines((h, w), lines, [np.full(len(p), float(width)) for p in lines])
        col = np.asarray(colour, np.float32)[: img.shape[2]]
        img *= 1 - cov[..., None]
        img += cov[..., None] * col
    return img


def regions_by_domain(image: np.ndarray, regions, boundary: DrawnBoundary, z: float | None):
    """``regions`` with its salient spots found inside each side of the drawn boundary on its own.

    Found over the whole example, the land of a shaded map stands out of the
    white outside (the spot statistics of the outside are tight): its dark
    hills become salient spots and gap completion leaves them out (output
    land 0.80 against the example's 0.70 median grey on a shaded terrain
    map). Each side's spots are measured against that side's own texture.

    Parameters
    ----------
    image : (h, w, C) float32 ndarray
        The example.
    regions : ExampleRegions
        Its masks (:func:`~branchnb.branching.regions.example_regions`).
    boundary : DrawnBoundary
        Its domain and boundary line (:func:`drawn_boundary`).
    z : float or None
        Salient z-score (``ImageSynthesisParams.salient_z``); None = no spots.

    Returns
    -------
    ExampleRegions
    """
    from dataclasses import replace

    from .regions import salient_mask

    if z is None:
        return replace(regions, salient=None)
    near = ndi.binary_dilation(regions.body | regions.branch_like, iterations=3)
    free = ~near & ~regions.unusable & ~boundary.ink
    spots = np.zeros(free.shape, bool)
    for side in (boundary.domain, ~boundary.domain):
        sel = side & ~boundary.ink
        if np.count_nonzero(free & sel) >= 64:
            spots |= salient_mask(image, free & sel, z=z) & sel
    spots &= ~regions.body & ~regions.unusable
    return replace(regions, salient=spots)
