"""A domain of separate pieces (the islands of a map): each piece is filled on its own (beyond the paper).

The paper grows until the density covers the example's share of the
domain, counted over the whole domain. On a map of several islands that
count let one island's trees fill the quota of all: on three islands 50 px
apart at 512 px the output put 1140, 744 and 0 px of rivers on islands the
example gives 536, 562 and 597 px (issue 23). :class:`_Pieces` tells the
growth loop (:meth:`.growth._Grower.step`) when the piece a branch grows
in is covered to the target: that branch stops there (``"density"``),
and the loop goes on in the pieces still short of it.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

__all__: list[str] = []

#: A separate piece of the domain with at least this share of its area holds trees of its own (an island of
#: a map); smaller pieces (islets, slivers between lines) are neither a place for a root nor filled on
#: their own (islands of 384-1024 px maps: 15-50 % each; slivers under 1 %).
PIECE_SHARE = 0.05
#: The pieces' coverage is counted again once this share of the domain's density cells was newly covered
#: (a count per Markov step cost ~2 ms on a 768 px map, up to a second per synthesis).
RECOUNT_SHARE = 0.002


def domain_pieces(dom: np.ndarray, share: float = PIECE_SHARE) -> np.ndarray | None:
    """Labels (1..n) of the pieces of ``dom`` holding at least ``share`` of its area (0 elsewhere);
    None when fewer than two pieces are that large.

    Parameters
    ----------
    dom : (H, W) bool ndarray
        The domain.
    share : float, default PIECE_SHARE
        Smallest share of the domain's area of a piece.

    Returns
    -------
    (H, W) int ndarray or None

    Examples
    --------
    >>> import numpy as np
    >>> d = np.zeros((40, 40), bool); d[2:18, 2:38] = True; d[22:38, 2:38] = True
    >>> int(domain_pieces(d).max()), domain_pieces(d[:20])
    (2, None)
    """
    lab, n = ndi.label(np.asarray(dom, bool))
    if n < 2:
        return None
    area = np.bincount(lab.ravel(), minlength=n + 1)
    big = area >= share * area[1:].sum()
    big[0] = False
    if big.sum() < 2:
        return None
    ids = np.zeros(n + 1, np.int64)
    ids[big] = np.arange(1, int(big.sum()) + 1)
    return ids[lab]


class _Pieces:
    """The domain's pieces on the density grid and which of them are covered to the target."""

    def __init__(self, labels: np.ndarray, density) -> None:
        import cv2

        gh, gw = density.grid.shape
        lab = cv2.resize(labels.astype(np.int32), (gw, gh), interpolation=cv2.INTER_NEAREST)
        self.labels = np.where(density.domain, lab, 0)
        self.cells = np.maximum(np.bincount(self.labels.ravel()), 1)
        self.density = density
        self.step = max(int(RECOUNT_SHARE * density.domain.sum()), 1)
        self._seen = -self.step - 1
        self._full = np.zeros(len(self.cells), bool)

    def full(self, target: float) -> np.ndarray:
        """Per piece label, whether its covered share reached ``target``."""
        d = self.density
        if abs(d._n_above - self._seen) >= self.step:
            cov = np.bincount(self.labels[d.grid > d.level], minlength=len(self.cells)) / self.cells
            self._full = cov >= target
            self._full[0] = False
            self._seen = d._n_above
        return self._full

    def at(self, p) -> int:
        """The piece label under point ``p`` (x, y) in pixels (0 outside every piece)."""
        c = self.density.cell
        gh, gw = self.labels.shape
        r = int(np.clip(np.floor((p[1] + 0.5) / c), 0, gh - 1))
        k = int(np.clip(np.floor((p[0] + 0.5) / c), 0, gw - 1))
        return int(self.labels[r, k])


def _grid_pieces(region: np.ndarray | None, density) -> _Pieces | None:
    """:class:`_Pieces` of ``region`` on ``density``'s grid, or None (one piece, no density)."""
    if region is None or density is None:
        return None
    lab = domain_pieces(region)
    return None if lab is None else _Pieces(lab, density)
