"""Step 3 of :mod:`branchnb.leaves.synthesis`: a new leaf's shape map, its size and its petiole.

:func:`_shape_map` blends the exemplars' upright inverse warps with one
leaf's random weights and turns the blend to one exemplar's pose;
:func:`_fit_with_petiole` gives it its size on the canvas and picks the
exemplar whose own petiole (step 5) stays inside the canvas.
"""

from __future__ import annotations

import numpy as np

from .shaping import _border_alpha, _fit_size, shape_weights
from .synthesis_draws import _exemplar_draws


def _shape_map(p, params, seed: int, rng):
    """The blended shape map in the chosen pose: ``(m, wts, size_from)``.

    ``wts`` are the per-pixel weights ``a_i`` (n, H, W); ``size_from`` the
    exemplar whose size the leaf takes (-1: the blend's).
    """
    n, shape = p.n, p.shape
    # The shape first: a convex blend of the inverse registration warps.
    wts = shape_weights(shape, n, params.shape_grid, params.shape_sigma * p.size, rng,
                        params.shape_concentration, params.shape_spread)
    pose_from, size_from, lead = _exemplar_draws(int(seed), n)
    if n > 1:
        # The exemplar leading the shape (largest mean weight) is drawn
        # from a stream of its own, so generate() can stratify it (see
        # _stratified_seeds): the Dirichlet draw's weights are permuted to
        # put its largest on ``lead`` (the same distribution).
        top = int(np.argmax(wts.mean((1, 2))))
        if top != lead:
            wts[[top, lead]] = wts[[lead, top]]
    # Only exemplars whose shape is compatible with the leading one's are
    # blended (see SynthesisParams.shape_compatible).
    comp = p.compatible(lead, params.shape_compatible) if n > 1 else np.ones(n, bool)
    if not comp.all():
        wts[~comp] = 0.0
        wts /= np.maximum(wts.sum(0), 1e-12)
    n_c = int(comp.sum())
    gain = float(np.sqrt(n_c * params.shape_concentration + 1.0)) if params.restore_spread and n_c > 1 else 1.0
    m = np.zeros(shape + (2,), np.float32)
    for i in np.flatnonzero(comp):
        # With the spread restored: the blend's departure from the
        # exemplars' mean shape scaled by ``gain`` (an affine, no longer
        # convex, combination; see SynthesisParams.restore_spread).
        w_i = wts[i] if gain == 1.0 else np.float32(1.0 / n_c) + np.float32(gain) * (wts[i] - np.float32(1.0 / n_c))
        m += w_i[..., None] * p.shape_maps[i]
    # The pose of one exemplar: new leaves lie as variously as the
    # exemplars do (the weighted mean pose gave every new leaf nearly the
    # same angle: median pairwise blade IoU 0.80 against the exemplars' 0.58
    # on a procedural family). It is the pose of the shape's leading
    # exemplar (see _exemplar_draws; a pose drawn independently of the shape
    # put one exemplar's outline at another's angle, more alike than either),
    # and generate() stratifies the leading exemplars over a batch (drawn
    # independently per leaf, leaves of one dominant exemplar all lay alike:
    # IoU 0.76 against 0.51 on 3 trilobed exemplars).
    # A smoothed bootstrap of the pose (beyond the paper): one exemplar's,
    # turned by a Gaussian kernel of Silverman's bandwidth over the
    # exemplars' poses, cut at 1.5 bandwidths (from a stream of its own).
    # Drawn from the exemplars' poses alone, two new leaves lay alike one
    # time in n: more alike than the exemplars (median pairwise blade IoU
    # 0.71 against 0.58 on a procedural trilobed family). (The same kernel
    # on the log size took a fifth of the Laplacian variance the size's
    # resampling costs and no variety: not kept.)
    # The kernel's width is ``pose_kernel`` times that bandwidth (see
    # SynthesisParams.pose_kernel: with the leading exemplars stratified
    # over a batch, a batch of 8 new leaves swung by up to +-0.1 in median
    # pairwise blade IoU around the exemplars' with the full one).
    z_pose = float(np.clip(np.random.default_rng((int(seed), 5)).standard_normal(), -1.5, 1.5)) \
        if params.smooth_bootstrap else 0.0
    m = p.posed(m, np.eye(n)[pose_from], z_pose * params.pose_kernel * p.pose_bandwidth)
    # The size of the leading exemplar (see _exemplar_draws and _fit_size);
    # that exemplar gives the background too, so its texture is seen at its
    # own scale (a small exemplar's residual blown up to a large one's size
    # came out blurred).
    size_from = size_from if params.own_size and n > 1 else -1
    return m, wts, size_from


def _fit_with_petiole(p, params, seed: int, m, size_from: int):
    """The shape map ``m`` at its size on the canvas and the petiole: ``(m, pet, pet_j)``.

    ``pet`` is exemplar ``pet_j``'s petiole (RGBA, output frame) or None (``pet_j`` -1).
    """
    # One exemplar's own petiole, drawn from a stream of its own (the main
    # one's use depends on the data: texture correction draws per replaced
    # patch). A petiole the canvas would cut is exchanged for the next
    # donor's (seeded order) that stays inside; if every one is cut, the
    # leaf is made a little smaller (at most three times).
    order = [int(e) for e in np.random.default_rng((int(seed), 1)).permutation(p.petiole_exemplars)]
    # Smoothed bootstrap of the size too (from a stream of its own): the
    # lead's size times exp of a Gaussian of the log sizes' bandwidth.
    z_size = float(np.clip(np.random.default_rng((int(seed), 7)).standard_normal(), -1.5, 1.5)) \
        if params.smooth_bootstrap and size_from >= 0 else 0.0
    m0, pet, pet_j = m, None, -1
    for attempt in range(4):
        m = _fit_size(p, m0, size_from, 0.9 ** attempt, float(np.exp(z_size * p.size_bandwidth)))
        pet, pet_j, best = None, -1, np.inf
        for cand in order:
            layer = p.petiole_layer(cand, m)
            if layer is None:
                continue
            cut = _border_alpha(layer[..., 3])
            if cut < best:
                pet, pet_j, best = layer, cand, cut
            if cut == 0:
                break
        if pet is None or best == 0:
            break
    return m, pet, pet_j
