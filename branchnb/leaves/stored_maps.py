"""Per-exemplar maps of a :class:`~branchnb.leaves.analysis_induce.LayerInduction`, kept small.

An analysis keeps, per layer and exemplar, the colour term ``S_e``, the
distance ``||x, c||`` and the combined term ``D`` for
:meth:`~branchnb.leaves.analysis.LeafAnalysis.retune` and for display: at
4 exemplars of 1.1 MP and 2 layers, 108 MB of full-canvas float32 maps
(issue 22: 447 MB held in all). Each list here reads like a list of
full-size arrays (``maps[e]``, ``len``, iteration) with the same values,
but stores less:

* :class:`BoxedMaps`: ``S_e`` is 1 off the blade, so only the blade's box is
  stored (a padded canvas is 2-5x larger than a leaf's box);
* :class:`DistanceMaps`: ``||x, c||`` is the distance transform of the
  registered layer (kept as a bool mask), recomputed when read;
* :class:`CombinedMaps`: ``D = lambda F + S_e`` from the two above.

The last map read is kept, so a loop reading ``maps[e]`` twice pays once.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np

from ..core.distance import edt as _edt

__all__ = ["BoxedMaps", "CombinedMaps", "DistanceMaps"]


class _Cached(Sequence):
    """A read-only sequence of full-size maps computed by ``_make(e)``; the last one read is kept."""

    _last: tuple | None = None

    def _make(self, e: int) -> np.ndarray:  # pragma: no cover - abstract
        raise NotImplementedError

    def __getitem__(self, e):
        if isinstance(e, slice):
            return [self[i] for i in range(*e.indices(len(self)))]
        e = int(e)
        if e < 0:
            e += len(self)
        if not 0 <= e < len(self):
            raise IndexError(f"exemplar index {e} out of range ({len(self)} maps)")
        if self._last is None or self._last[0] != e:
            out = self._make(e)
            out.setflags(write=False)
            self._last = (e, out)
        return self._last[1]

    def __getstate__(self):
        state = dict(self.__dict__)
        state.pop("_last", None)
        return state


class BoxedMaps(_Cached):
    """Full-size maps stored on each one's box, ``fill`` elsewhere.

    Parameters
    ----------
    maps : list of (H, W) ndarray
        The maps.
    masks : list of (H, W) bool ndarray
        Where each map may differ from ``fill`` (e.g. the blades).
    fill : float
        The value of every map off its mask.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.ones((6, 8), np.float32); m[2:4, 3:5] = 0.25
    >>> maps = BoxedMaps([m], [m < 1], 1.0)
    >>> maps[0].shape, bool(np.array_equal(maps[0], m)), maps.stored_bytes
    ((6, 8), True, 16)
    """

    def __init__(self, maps, masks, fill: float):
        if len(maps) != len(masks):
            raise ValueError(f"maps and masks must have one entry per exemplar, got {len(maps)} and {len(masks)}")
        self.fill = float(fill)
        self._items = []
        for k, (m, b) in enumerate(zip(maps, masks)):
            m = np.asarray(m)
            b = np.asarray(b, bool)
            if m.shape != b.shape:
                raise ValueError(f"maps[{k}] has shape {m.shape}, masks[{k}] {b.shape}")
            rows, cols = np.flatnonzero(b.any(1)), np.flatnonzero(b.any(0))
            if not len(rows):
                y0 = y1 = x0 = x1 = 0
            else:
                y0, y1, x0, x1 = int(rows[0]), int(rows[-1]) + 1, int(cols[0]), int(cols[-1]) + 1
            crop = m[y0:y1, x0:x1].copy()
            rest = np.ones(m.shape, bool)
            rest[y0:y1, x0:x1] = False
            if not np.all(m[rest] == self.fill):
                crop, y0, x0 = m.copy(), 0, 0  # not constant off the box: kept whole
            self._items.append((m.shape, m.dtype, y0, x0, crop))

    def __len__(self) -> int:
        return len(self._items)

    def _make(self, e: int) -> np.ndarray:
        shape, dtype, y0, x0, crop = self._items[e]
        out = np.full(shape, self.fill, dtype)
        out[y0:y0 + crop.shape[0], x0:x0 + crop.shape[1]] = crop
        return out

    @property
    def stored_bytes(self) -> int:
        """Bytes of the stored boxes."""
        return int(sum(c.nbytes for *_, c in self._items))


class DistanceMaps(_Cached):
    """``||x, c||``: each pixel's distance (px, float32) to its layer, 1e6 everywhere for an empty one.

    Parameters
    ----------
    layers : list of (H, W) bool ndarray
        The registered layers (kept, not copied).

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((5, 5), bool); m[2, 2] = True
    >>> float(DistanceMaps([m])[0][2, 4])
    2.0
    """

    def __init__(self, layers):
        self.layers = list(layers)

    def __len__(self) -> int:
        return len(self.layers)

    def _make(self, e: int) -> np.ndarray:
        ru = np.asarray(self.layers[e], bool)
        if not ru.any():
            return np.full(ru.shape, 1e6, np.float32)
        return _edt(~ru)


class CombinedMaps(_Cached):
    """``D = lambda F + S_e`` (eq. 4) from the stored colour terms and distances.

    Parameters
    ----------
    lam : float
        ``lambda_c``.
    colour, distance : sequences of (H, W) float32 ndarray
        ``S_e`` and ``||x, c||`` per exemplar.
    eps_px : list of float
        The scaled ``eps`` per exemplar.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((4, 4), bool); m[1, 1] = True
    >>> d = CombinedMaps(0.5, [np.zeros((4, 4), np.float32)], DistanceMaps([m]), [2.0])[0]
    >>> float(d[1, 1]), round(float(d[1, 3]), 4)
    (0.5, 1.3591)
    """

    def __init__(self, lam: float, colour, distance, eps_px):
        if not (len(colour) == len(distance) == len(eps_px)):
            raise ValueError("colour, distance and eps_px must have one entry per exemplar")
        self.lam, self.colour, self.distance, self.eps_px = float(lam), colour, distance, list(eps_px)

    def __len__(self) -> int:
        return len(self.colour)

    def _make(self, e: int) -> np.ndarray:
        from .induction import spatial_term
        f = spatial_term(self.distance[e], self.colour[e], self.eps_px[e])
        return (np.float32(self.lam) * f + self.colour[e]).astype(np.float32)
