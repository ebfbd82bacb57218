"""Composing a gap patch or a fragment with the iterative gradient-domain solve (issue 23).

Steps 3 and 4 of image synthesis compose with
:func:`branchnb.core.blending.compose_piece` and ``solver="iterative"``:
their systems are well posed by construction (screened gap patches,
anchored fragments), so conjugate gradients (:mod:`branchnb.core.poisson_cg`)
replace the banded Cholesky factorisation, within a grey level of it.
"""

from __future__ import annotations

from ..core.blending import compose_piece
from ..core.poisson_cg import CG_MAX_ITER, CG_TOL, _cg_solve, screened_correction  # noqa: F401 (re-exported)

__all__: list[str] = []



def compose_patch(canvas, covered, piece, valid, origin, *, protect_canvas=None, protect_piece=None,
                  method="graphcut", poisson=True, anchored=True, anchor_weight=10.0, screen=0.0,
                  neutral_canvas=None):
    """:func:`branchnb.core.blending.compose_piece` with ``solver="iterative"`` (its correction by conjugate gradients).

    Parameters
    ----------
    canvas, covered, piece, valid, origin, protect_canvas, protect_piece, method, poisson, anchored, \
anchor_weight, screen, \
neutral_canvas
        As for ``compose_piece``.

    Returns
    -------
    Composition or None

    Examples
    --------
    >>> import numpy as np
    >>> canvas = np.zeros((16, 16, 3), np.float32)
    >>> covered = np.zeros((16, 16), bool); covered[:, :8] = True
    >>> c = compose_patch(canvas, covered, np.ones((16, 12, 3), np.float32), np.ones((16, 12), bool), (4, 0),
    ...                   screen=0.05)
    >>> bool(covered.all()), float(canvas[0, 15, 0]) > 0.5
    (True, True)
    """
    return compose_piece(canvas, covered, piece, valid, origin, protect_canvas=protect_canvas,
                         protect_piece=protect_piece, method=method, poisson=poisson, anchored=anchored,
                         anchor_weight=anchor_weight, screen=screen, solver="iterative",
                         neutral_canvas=neutral_canvas)
