"""A procedural family of cut grass-type leaf strips with parallel veins, and its ground truth.

The leaf kind of the grass photos in the shared data (``leaves_photo_grass``):
a cut segment of a monocot blade, a long narrow strip, slightly bent, lying at
any angle, with pale parallel veins along it (one of them sometimes a wider
midrib) and ragged cut ends. Nothing of it is in :mod:`branchnb.leaves.procedural`
(branching venation on lobed and elliptic blades). Every leaf is drawn from
material coordinates ``(u, v)`` (``u`` along the strip in ``[0, 1]``, ``v``
across it in ``[-1, 1]``), so the same material point is known on every leaf
of the family (:attr:`ProceduralLeaf.keypoints`) and its veins lie at the same
``v`` on every leaf.

Measured (4 strips at 192 px, seeds 0 and 1, the training strip's true
veins as the user's layer, true registrations; ``tests/test_leaves_unseen.py``):
induced vein IoU 0.69-0.99 on every other strip, vein lambda 0.36-0.42;
new leaves show one system of parallel veins. As a user would (10 short
scribbles of radius 1 from :func:`~branchnb.leaves.simulate_scribbles` on
the training strip's veins, :func:`~branchnb.leaves.analyze` with its own
registrations): induced vein IoU 0.68-0.88 on seed 0 and 0.61-0.80 on
seed 1 but for one strip whose registration fails (42 px, IoU 0.05);
before the lazy-snapping fix of :func:`branchnb.leaves._lines._plain_level`
0.07-0.10 and 0.03-0.51. Registrations of a strip often run end to end
(77 px mean keypoint error with vein IoU 0.8: a strip is nearly symmetric).
On the real grass photos, with scribbles mostly on the midrib, the faint
fine veins still grow and induce as fragments (vein lambda 0.00-0.04).
"""

from __future__ import annotations

import numpy as np

from ..core.random import as_rng
from .procedural import ProceduralLeaf

__all__ = ["strip_leaf", "strip_family"]

#: Across-strip positions (``v``) of the parallel veins, the midrib (``v = 0``) included.
VEIN_V = np.linspace(-0.8, 0.8, 7)


def _check(size, n_keypoints):
    if isinstance(size, bool) or not isinstance(size, (int, np.integer)) or not 48 <= size <= 4096:
        raise ValueError(f"size must be an int in [48, 4096], got {size!r}")
    if isinstance(n_keypoints, bool) or not isinstance(n_keypoints, (int, np.integer)) or not 4 <= n_keypoints <= 4096:
        raise ValueError(f"n_keypoints must be an int in [4, 4096], got {n_keypoints!r}")


def strip_leaf(size: int = 192, *, n_keypoints: int = 48, rng=None) -> ProceduralLeaf:
    """One cut grass-type leaf strip with pale parallel veins, and its ground truth.

    Parameters
    ----------
    size : int
        Canvas side in pixels, 48 to 4096 (default 192).
    n_keypoints : int
        True corresponding points, 4 to 4096 (default 48): a grid of
        material points ``(u, v)``, the same on every leaf.
    rng : {numpy.random.Generator, int}, optional
        Draws the strip's length, width, bend, angle, colours and vein
        contrast.

    Returns
    -------
    ProceduralLeaf
        ``kind`` ``"strip"``; ``layers["veins"]`` the parallel veins,
        ``layers["spots"]`` empty; ``veins`` their centre lines.

    Examples
    --------
    >>> leaf = strip_leaf(96, rng=0)
    >>> leaf.image.shape, bool((leaf.layers["veins"] & ~leaf.blade).any())
    ((96, 96, 4), False)
    """
    _check(size, n_keypoints)
    seed = int(as_rng(rng).integers(2**31 - 1)) if not isinstance(rng, (int, np.integer)) else int(rng)
    g = np.random.default_rng(seed)
    length = size * g.uniform(0.7, 0.88)
    width = length * g.uniform(0.16, 0.26)
    bend = g.uniform(-0.35, 0.35) / length  # centre line y' = bend * x'^2
    angle = g.uniform(0, np.pi)
    c, s = np.cos(angle), np.sin(angle)
    cx = cy = (size - 1) / 2.0
    yy, xx = np.mgrid[:size, :size].astype(np.float64)
    xp = c * (xx - cx) + s * (yy - cy)
    yp = -s * (xx - cx) + c * (yy - cy)
    u = xp / length + 0.5
    v = (yp - bend * xp ** 2) / (width / 2)
    # Ragged cut ends: the end lines wobble by up to 0.8 % of the length.
    ph = g.uniform(0, 2 * np.pi, 2)
    rag = 0.008 * np.sin(3 * np.pi * v[..., None] + ph) * np.array([1.0, -1.0])
    d_across = (1 - np.abs(v)) * width / 2
    d_along = np.minimum(u - rag[..., 0], 1 - u + rag[..., 1]) * length
    alpha = np.clip(np.minimum(d_across, d_along) + 0.5, 0, 1).astype(np.float32)
    blade = alpha > 0.5
    base = np.array([g.uniform(0.3, 0.6), g.uniform(0.45, 0.65), g.uniform(0.2, 0.35)])
    shade = 1.0 + 0.06 * np.sin(2 * np.pi * (u * g.uniform(0.5, 1.5) + g.uniform()))  # uneven light
    grain = 1.0 + 0.03 * g.standard_normal((size, size))
    rgb = base[None, None] * (shade * grain)[..., None]
    veins = np.zeros((size, size), bool)
    lines, widths = [], []
    lift = g.uniform(0.08, 0.16)
    ts = np.linspace(0, 1, 32)
    for vk in VEIN_V:
        w_px = 2.5 if vk == 0 else 1.3
        on = blade & (np.abs(v - vk) * width / 2 <= w_px / 2)
        veins |= on
        rgb[on] = rgb[on] + lift * (1.4 if vk == 0 else 1.0)
        xs = (ts - 0.5) * length
        ys = vk * width / 2 + bend * xs ** 2
        lines.append(np.stack([c * xs - s * ys + cx, s * xs + c * ys + cy], 1))
        widths.append(np.full(len(ts), w_px))
    img = np.dstack([np.clip(rgb, 0, 1) * blade[..., None], alpha]).astype(np.float32)
    nu = max(2, int(round(np.sqrt(n_keypoints * 4))))
    nv = max(2, int(np.ceil(n_keypoints / nu)))
    uu, vv = np.meshgrid(np.linspace(0.05, 0.95, nu), np.linspace(-0.9, 0.9, nv))
    uu, vv = uu.ravel()[:n_keypoints], vv.ravel()[:n_keypoints]
    kx = (uu - 0.5) * length
    ky = vv * width / 2 + bend * kx ** 2
    kps = np.stack([c * kx - s * ky + cx, s * kx + c * ky + cy], 1)
    return ProceduralLeaf(img, blade, {"veins": veins, "spots": np.zeros_like(veins)}, kps, seed, "strip", "green",
                          dict(length=length, width=width, bend=bend, rotation=float(np.degrees(angle))),
                          lines, widths)


def strip_family(n: int, *, size: int = 192, n_keypoints: int = 48, rng=None) -> list:
    """``n`` cut grass-type leaf strips of one kind (see :func:`strip_leaf`).

    Parameters
    ----------
    n : int
        Number of leaves, 1 to 10000.
    size : int
        Canvas side in pixels (default 192).
    n_keypoints : int
        True corresponding points per leaf (default 48).
    rng : {numpy.random.Generator, int}, optional
        Draws the ``n`` distinct leaf seeds.

    Returns
    -------
    list of ProceduralLeaf

    Examples
    --------
    >>> fam = strip_family(2, size=64, rng=0)
    >>> len(fam), fam[0].keypoints.shape
    (2, (48, 2))
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or not 1 <= n <= 10000:
        raise ValueError(f"n must be an int in [1, 10000], got {n!r}")
    _check(size, n_keypoints)
    seeds = as_rng(rng).choice(2**31 - 1, size=int(n), replace=False)
    return [strip_leaf(size, n_keypoints=n_keypoints, rng=int(s)) for s in seeds]
