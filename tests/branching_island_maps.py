"""Drawing of procedural island maps shared by the island and strait tests (issue 23)."""
import numpy as np
from scipy import ndimage as ndi

from branchnb.core.render import coverage_polylines


def ink_map(land, rivers, colours, lw):
    """Sea and land colours with the coast line and ``rivers`` (polylines, ``lw`` px wide) inked over.

    ``colours`` is ``(land, sea, ink)``; returns a float32 (H, W, 3) image.
    """
    land_c, sea_c, ink_c = colours
    shape = land.shape
    img = np.empty(shape + (3,), np.float32)
    img[:] = sea_c
    img[land] = land_c
    edge = land & ndi.binary_dilation(~land)
    cov, _ = coverage_polylines(shape, rivers, [np.full(len(p), lw) for p in rivers])
    ink = np.maximum(cov, edge.astype(np.float32))
    return (img * (1 - ink[..., None]) + np.asarray(ink_c, np.float32) * ink[..., None]).astype(np.float32)
