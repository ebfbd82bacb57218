"""Procedural leaf families whose veins differ in colour from leaf to leaf, with ground truth.

The case of drawn and photographed leaves the package has never seen: a
training leaf with dark or pale veins and exemplars whose veins are red
(clip-art oaks), pale (photographed maples) or dark ink (sketched maples).
The leaves are those of :func:`~branchnb.leaves.procedural.leaf_family`
(same seeds, shapes, venation, spots and keypoints); only each leaf's vein
pixels are repainted, by their true coverage, in its own vein colour
(:data:`VEIN_COLOURS`, taken in turn). Induction that follows the training
layer's *colour* finds nothing of a red vein system from a pale-veined
training leaf; induction that follows its *role* (a thin ridge near where
the warped layer lands) finds it.
"""

from __future__ import annotations

import numpy as np

from ..core.render import coverage_polylines
from ..core.validate import check_int
from .procedural import PALETTES, ProceduralLeaf, leaf_family

__all__ = ["VEIN_COLOURS", "recolour_veins", "vein_colour_family"]

#: Vein colours (RGB in [0, 1]) of the families: the green palette's pale
#: veins, red veins (the clip-art oaks) and dark veins (ink, dark-veined photos).
VEIN_COLOURS = {
    "pale": PALETTES["green"]["veins"],
    "red": (0.66, 0.14, 0.10),
    "dark": (0.10, 0.20, 0.05),
}


def recolour_veins(leaf: ProceduralLeaf, colour, *, outline: float = 0.0) -> ProceduralLeaf:
    """``leaf`` with its veins repainted in ``colour`` (by their true coverage).

    Parameters
    ----------
    leaf : ProceduralLeaf
        A leaf of :func:`~branchnb.leaves.procedural.procedural_leaf`.
    colour : str or (3,) sequence of float
        A name of :data:`VEIN_COLOURS` or an RGB triple in [0, 1].
    outline : float
        Width (px) of an ink outline drawn in the vein colour along the
        blade's edge, as on a sketch (0, default: none). It is no vein: the
        layers are unchanged.

    Returns
    -------
    ProceduralLeaf
        A copy; layers, keypoints and blade are the leaf's own.

    Examples
    --------
    >>> from branchnb.leaves.procedural import procedural_leaf
    >>> leaf = procedural_leaf("elliptic", size=96, rng=1)
    >>> red = recolour_veins(leaf, "red")
    >>> v = red.layers["veins"]
    >>> bool(red.image[v, 0].mean() > red.image[v, 1].mean())
    True
    """
    if not isinstance(leaf, ProceduralLeaf):
        raise TypeError(f"leaf must be a ProceduralLeaf, got {type(leaf).__name__}")
    if isinstance(colour, str):
        if colour not in VEIN_COLOURS:
            raise ValueError(f"colour must be one of {sorted(VEIN_COLOURS)} or an RGB triple, got {colour!r}")
        colour = VEIN_COLOURS[colour]
    rgb_new = np.asarray(colour, np.float64).ravel()
    if rgb_new.shape != (3,) or not np.all(np.isfinite(rgb_new)) or rgb_new.min() < 0 or rgb_new.max() > 1:
        raise ValueError(f"colour must be an RGB triple in [0, 1], got {colour!r}")
    if not np.isfinite(outline) or not 0 <= outline <= 20:
        raise ValueError(f"outline must be in [0, 20] px, got {outline!r}")
    h, w = leaf.image.shape[:2]
    cov, _ = coverage_polylines((h, w), leaf.veins, leaf.vein_widths)
    cov = np.minimum(cov, leaf.image[..., 3])[..., None]
    old = np.asarray(PALETTES[leaf.palette]["veins"], np.float32)
    image = leaf.image.copy()
    image[..., :3] = np.clip(image[..., :3] + cov * (rgb_new.astype(np.float32) - old), 0.0, 1.0)
    if outline > 0:
        from scipy import ndimage as ndi
        depth = ndi.distance_transform_edt(leaf.blade)
        ink = np.clip(outline + 0.5 - depth, 0.0, 1.0)[..., None].astype(np.float32)
        image[..., :3] = image[..., :3] * (1 - ink) + rgb_new.astype(np.float32) * ink
    image[..., :3] *= image[..., 3:] > 0
    return ProceduralLeaf(image, leaf.blade, dict(leaf.layers), leaf.keypoints, leaf.seed, leaf.kind,
                          leaf.palette, dict(leaf.shape), leaf.veins, leaf.vein_widths)


def vein_colour_family(n: int, *, size: int = 192, kind: str = "lobed", colours=("pale", "red", "dark"),
                       outline: float = 0.0, rng=None) -> list:
    """``n`` leaves of one kind, leaf ``i`` with veins of ``colours[i % len(colours)]``.

    Parameters
    ----------
    n : int
        Number of leaves, 1 to 100.
    size : int
        Canvas side in pixels (see :func:`~branchnb.leaves.procedural.leaf_family`).
    kind : {"lobed", "trilobed", "elliptic"}
        The family.
    colours : sequence of (str or RGB triple)
        Vein colours taken in turn (names of :data:`VEIN_COLOURS`).
    outline : float
        Width (px) of an ink outline in each leaf's vein colour (see :func:`recolour_veins`).
    rng : {numpy.random.Generator, int}, optional
        Draws the leaf seeds (the same leaves as ``leaf_family(n, rng=rng)``).

    Returns
    -------
    list of ProceduralLeaf

    Examples
    --------
    >>> fam = vein_colour_family(2, size=80, kind="elliptic", colours=("pale", "red"), rng=0)
    >>> [bool(f.image[f.layers["veins"], 0].mean() > 0.5) for f in fam]
    [True, True]
    """
    n = check_int(n, "n", 1, 100)
    if isinstance(colours, str) or len(colours) == 0:
        raise ValueError(f"colours must be a non-empty sequence of colours, got {colours!r}")
    fam = leaf_family(n, size=size, kind=kind, rng=rng)
    return [recolour_veins(leaf, colours[i % len(colours)], outline=outline) for i, leaf in enumerate(fam)]
