"""Which object a lightning bolt strikes and where its main channel ends (split from
:mod:`~branchnb.dendrite.main_channel`; beyond the papers): the separate object its seed lies
over (:func:`_seed_part`, dendrite34) and the foot of the stem it stands on (:func:`_stem_end`,
dendrite32). Used by :func:`~branchnb.dendrite.main_channel.strike_channel`.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

__all__: list[str] = []


def _seed_part(sil: np.ndarray, seed: tuple[int, int]) -> np.ndarray:
    """The connected part (8-connected) of the silhouette the seed lies in, or the one nearest
    to it: the object a lightning bolt strikes.

    Beyond the papers (dendrite34): on a picture of several separate objects (a street lamp
    and a toadstool) the main channel ran from the seed on one object to the bottom of
    another's wide part, straight across the empty sky between them.

    >>> m = np.zeros((20, 30), bool); m[2:18, 2:8] = True; m[5:18, 20:28] = True
    >>> int(_seed_part(m, (4, 3)).sum()), int(_seed_part(m, (15, 10)).sum())
    (96, 104)
    """
    if not sil.any():
        return sil
    lab, _ = ndimage.label(sil, structure=np.ones((3, 3), bool))
    x = min(max(int(seed[0]), 0), sil.shape[1] - 1)
    y = min(max(int(seed[1]), 0), sil.shape[0] - 1)
    if not lab[y, x]:
        _, (iy, ix) = ndimage.distance_transform_edt(lab == 0, return_indices=True)
        y, x = int(iy[y, x]), int(ix[y, x])
    return lab == lab[y, x]


#: Height of a stem (a tree's trunk) at the silhouette's bottom, as a share of its height,
#: from which the main channel runs down it (:func:`_stem_end`).
STEM_MIN_DEPTH = 0.06
#: Largest width of a stem's rows, as a share of the silhouette's widest row.
STEM_MAX_WIDTH = 0.35


def _stem_end(sil: np.ndarray, end: tuple[int, int]) -> tuple[int, int]:
    """The foot of the one thin stem (a tree's trunk, a flower's stalk) the silhouette
    stands on, or ``end`` (the wide part's bottom) when it has none.

    Beyond the papers: the main channel ended at the bottom of the object's wide part
    (:func:`wide_top` upside down) and the bolt's bright main path was the child with the
    most tips, so on a tree it filled the crown and never ran down the trunk, the tree's
    main axis. A stem is the run of bottom rows that each hold one stretch of the
    silhouette at most ``STEM_MAX_WIDTH`` of its widest row, over at least
    ``STEM_MIN_DEPTH`` of its height (a body on four legs has none: several stretches a row).

    >>> m = np.zeros((100, 80), bool); m[10:60, 10:70] = True; m[60:95, 36:44] = True
    >>> _stem_end(m, (40, 59))
    (40, 94)
    >>> m[60:95, 12:18] = True  # two legs: no stem
    >>> _stem_end(m, (40, 59))
    (40, 59)
    """
    rows = np.flatnonzero(sil.any(axis=1))
    if rows.size == 0:
        return end
    width = sil.sum(axis=1)
    runs = (sil[:, 1:] & ~sil[:, :-1]).sum(axis=1) + sil[:, 0]
    thin = (width <= STEM_MAX_WIDTH * width.max()) & (runs == 1)
    foot = int(rows[-1])
    top = foot
    while top > rows[0] and thin[top]:
        top -= 1
    if foot - top < STEM_MIN_DEPTH * (foot - rows[0] + 1):
        return end
    xs = np.flatnonzero(sil[foot])
    return int(xs[len(xs) // 2]), foot
