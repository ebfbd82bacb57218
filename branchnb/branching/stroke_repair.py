"""Connected strokes in a synthesized drawing: redraw where the fragments left a branch without ink.

Going beyond the paper. Its image synthesis covers the target skeleton
with copied fragments, but on line art a source fragment brings only the
part of its disk that holds no other branch: in a dense drawing (a crack
network, a vessel mask) most disks hold a junction, so the copied pieces
are short and gap completion fills the rest with clean background. The
branches then come out dashed. For drawn (flat-colour) examples every run
of a target centre line that carries no ink after synthesis is drawn in the
example's own style (line colour and width, :mod:`.drawing`), so each tree
renders as one connected line; where the fragments did bring ink, their
texture stays.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.polyline import resample_uniform
from ..core.render import coverage_polylines
from ..core.structure import Structure

__all__ = ["redraw_gaps"]


def _runs(flags: np.ndarray) -> list[tuple[int, int]]:
    """Start and end (inclusive) of every run of True in a 1-D bool array."""
    d = np.diff(np.concatenate([[0], flags.astype(np.int8), [0]]))
    return list(zip(np.flatnonzero(d == 1), np.flatnonzero(d == -1) - 1))


def redraw_gaps(image, structure: Structure, line_colour, background_colour, width_scale: float = 1.0, *,
                pad: float = 2.0) -> tuple[np.ndarray, int]:
    """Draw the parts of ``structure``'s centre lines that carry no ink in ``image``.

    A centre-line point carries ink when some pixel within one pixel of it
    is nearer to ``line_colour`` than to ``background_colour`` (halfway
    between them or closer). Each run without ink is drawn, ``pad`` pixels
    longer at both ends so it joins the ink around it, with the line
    colour at width ``max(width_scale * 2 r, 1)``.

    Parameters
    ----------
    image : (H, W, C) array_like
        The synthesized drawing, float in [0, 1].
    structure : Structure
        Its branches (pixels of ``image``).
    line_colour, background_colour : (C,) array_like
        The example's line colour and the colour around its lines.
    width_scale : float, default 1.0
        Drawn width over ``2 r`` (:attr:`~.drawing.DrawingStyle.width_scale`).
    pad : float, default 2.0
        Overlap (pixels) of a redrawn run with the ink at its ends.

    Returns
    -------
    image : (H, W, C) float32 ndarray
        The drawing with its gaps drawn (a new array).
    n_runs : int
        Number of runs redrawn.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb.core.structure import Branch, Structure
    >>> img = np.ones((20, 40, 3), np.float32); img[9:11, 2:15] = 0; img[9:11, 25:38] = 0   # a dashed line
    >>> s = Structure([Branch([(2, 10), (37, 10)], 1.0)])
    >>> out, n = redraw_gaps(img, s, (0, 0, 0), (1, 1, 1))
    >>> n, float(out[10, 20].max()) < 0.5
    (1, True)
    """
    img = np.array(image, dtype=np.float32, copy=True)
    if img.ndim == 2:
        img = img[..., None]
    h, w = img.shape[:2]
    line = np.asarray(line_colour, np.float32).reshape(-1)[: img.shape[2]]
    bg = np.asarray(background_colour, np.float32).reshape(-1)[: img.shape[2]]
    span = float(np.linalg.norm(line - bg))
    if span < 0.1:
        return img, 0
    to_line = np.linalg.norm(img - line, axis=-1)
    inked = ndi.minimum_filter(to_line, 3) <= 0.5 * span
    polys, widths = [], []
    step = 1.0
    k = max(int(round(pad / step)), 0)
    for b in structure.branches:
        pts = np.asarray(b.points, np.float64)
        if len(pts) < 2 or float(np.hypot(*np.diff(pts, axis=0).T).sum()) < 1.0:
            continue
        q, r = resample_uniform(pts, step, values=np.asarray(b.thickness, np.float64), include_end=True)
        ix = np.clip(np.rint(q[:, 0]).astype(np.int64), 0, w - 1)
        iy = np.clip(np.rint(q[:, 1]).astype(np.int64), 0, h - 1)
        inside = (q[:, 0] >= -0.5) & (q[:, 0] <= w - 0.5) & (q[:, 1] >= -0.5) & (q[:, 1] <= h - 0.5)
        gap = ~inked[iy, ix] & inside
        for a, e in _runs(gap):
            a, e = max(a - k, 0), min(e + k, len(q) - 1)
            if e > a:
                polys.append(q[a:e + 1])
                widths.append(np.maximum(width_scale * 2.0 * r[a:e + 1], 1.0))
    if not polys:
        return img, 0
    cov, _ = coverage_polylines((h, w), polys, widths)
    img = img * (1.0 - cov[..., None]) + cov[..., None] * line
    return np.clip(img, 0.0, 1.0).astype(np.float32), len(polys)
