"""The part of a line mask's frame its lines leave empty (issue 23, beyond the paper).

:func:`~branchnb.branching.example_domain` leaves it out of a one-region line mask's domain, and
:func:`~branchnb.branching.fit_model` reads it as ground, not as a coast or a hole
(``StructureModel.ground``, :func:`.domains._ground`). Split from :mod:`.backgrounds`.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

EMPTY_DISK = 0.2     #: a disk this share of the frame's short side fits in the empty part
EMPTY_MARGIN = 0.75  #: the domain reaches this share of the disk's radius beyond the outermost lines
EMPTY_AREA = 0.05    #: an empty part covers at least this share of the frame


def _empty_part(lines) -> np.ndarray:
    """The part of the frame a line network leaves empty: where a large line-free disk fits.

    The union of the disks of radius :data:`EMPTY_DISK` x the frame's short side that lie inside
    the frame and touch no line (the complement of the lines' closing, the frame counted as a
    line), less a margin of :data:`EMPTY_MARGIN` x that radius along the lines; pieces under
    :data:`EMPTY_AREA` of the frame are dropped. Beyond the paper (issue 23): a crack mask that
    covers the lower half of its frame grew over the whole frame (48-75 % of the synthesized
    length more than 8 % of the short side from every example line); a network that fills its
    frame (mud, a retina's vessels, drawn cracks whose cells are smaller than the disk) has none.

    Parameters
    ----------
    lines : (H, W) bool array_like
        The network's pixels.

    Returns
    -------
    (H, W) bool ndarray
        The empty part (all False when there is none).

    Examples
    --------
    >>> m = np.zeros((100, 150), bool); m[70, 5:145] = True; m[60:95, 40] = True
    >>> e = _empty_part(m)
    >>> bool(e[10, 75]), bool(e[70, 75]), bool(e[85, 75])
    (True, False, False)
    """
    lines = np.asarray(lines, bool)
    H, W = lines.shape
    out = np.zeros((H, W), bool)
    if not lines.any():
        return out
    R = EMPTY_DISK * min(H, W)
    pad = np.pad(lines, 1, constant_values=True)        # the frame counts as a line: disks stay inside
    d = ndi.distance_transform_edt(~pad)
    centres = d > R
    if not centres.any():
        return out
    empty = (ndi.distance_transform_edt(~centres) <= R)[1:-1, 1:-1]    # the union of the empty disks
    empty &= ndi.distance_transform_edt(~lines) > EMPTY_MARGIN * R
    lab, n = ndi.label(empty)
    if n:
        size = np.bincount(lab.ravel(), minlength=n + 1)
        keep = size >= EMPTY_AREA * H * W
        keep[0] = False
        out = keep[lab]
    return out
