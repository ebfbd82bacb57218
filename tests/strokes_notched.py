"""The procedural flower with a notch cut along each petal (shared by the slit and carried-notch tests)."""

import numpy as np

from branchnb.strokes.procedural_more import flower


def notched_flower(size):
    """The flower with a 2 px notch along each petal's axis over its outer 45 %.

    Returns ``(obj, image, mids)``: ``mids[k]`` are petal ``k``'s notch middle pixels (within 0.5 px of
    the axis, not its last 2 px inwards).
    """
    obj = flower(size, rng=0)
    img = obj.image.copy()
    yy, xx = np.mgrid[0:img.shape[0], 0:img.shape[1]]
    mids = {}
    for k, name in enumerate(obj.names):
        if not name.startswith("petal"):
            continue
        c, e = obj.strokes[k][0], obj.strokes[k][-1]
        length = float(np.hypot(*(e - c)))
        u = (e - c) / length
        along = (xx - c[0]) * u[0] + (yy - c[1]) * u[1]
        across = np.abs((yy - c[1]) * u[0] - (xx - c[0]) * u[1])
        # (on the petal only: the axis runs on across a leaf)
        cut = np.clip(1.5 - across, 0.0, 1.0) * ((along > 0.55 * length) & (obj.labels == k))
        img[..., 3] *= (1.0 - cut).astype(np.float32)
        mids[k] = (across <= 0.5) & (along > 0.55 * length + 2) & (obj.labels == k)
    return obj, img, mids
