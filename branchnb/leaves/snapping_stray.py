"""Stray and side ridges: veins of the layer that no trace from the training layer reached (step 6 of
:mod:`branchnb.leaves.snapping`, beyond the paper)."""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.morphology import _binary_dilation, fill_holes

#: Ridge evidence (line-averaged, :func:`~branchnb.leaves.snapping_evidence.ridge_evidence`) of a stray vein
#: (:func:`~branchnb.leaves.snapping_stray._stray_ridges`); 0: off.
STRAY_LEVEL = 0.5
#: Shortest stray vein (skeleton length), as a fraction of the leaf size.
STRAY_LENGTH = 0.2


#: Ridge evidence of a branch the training layer lacks (:func:`~branchnb.leaves.snapping_stray._side_ridges`); 0: off.
SIDE_LEVEL = 0.35


def _side_ridges(evidence, blade, found, level: float, min_length: float) -> np.ndarray:
    """Long straight ridges that leave the snapped network: branches the training layer lacks (beyond the paper).

    A training leaf traced where its lobe is torn (sample maple 07) has no
    lateral there, so no trace follows that lateral on any exemplar. A
    piece of ``{evidence >= level}`` outside a 3 px ring around the found
    network that touches the ring (it starts at the network), is at least
    ``min_length`` px long (skeleton), nearly straight (principal axis, 4
    standard deviations, at least 0.8 of its skeleton) and reaches
    ``0.7 min_length`` from the network is taken, joined to the network
    through the ring. Measured: maple 07 as training leaf, onto maple 06
    0.49 -> 0.58 (mean 0.58 -> 0.60; other training maples unchanged);
    procedural colour families (``_measure_colours``) and same-coloured
    3-leaf families (2 vein widths off): vein IoU unchanged or +0.01-0.04.

    Parameters
    ----------
    evidence : (H, W) float ndarray
        Line-averaged ridge evidence of the exemplar, in [0, 1].
    blade : (H, W) bool ndarray
        Its blade.
    found : (H, W) bool ndarray
        The snapped layer so far.
    level : float
        Evidence level of a side branch's pixels.
    min_length : float
        Shortest side branch (px of skeleton): the layer's typical main branch.

    Returns
    -------
    (H, W) bool ndarray
    """
    from skimage.morphology import skeletonize
    ring = _binary_dilation(found, iterations=3)
    strong = (np.asarray(evidence) >= level) & blade & ~ring
    lab, n = ndi.label(strong, structure=np.ones((3, 3)))
    if n == 0:
        return np.zeros(blade.shape, bool)
    length = np.bincount(lab[skeletonize(strong)], minlength=n + 1)
    touch = np.bincount(lab[_binary_dilation(ring, iterations=2) & strong], minlength=n + 1)
    far = ndi.distance_transform_edt(~found)
    keep = (length >= min_length) & (touch > 0)
    keep[0] = False
    for k in np.nonzero(keep)[0]:
        ys, xs = np.nonzero(lab == k)
        span = 4.0 * np.sqrt(max(np.linalg.eigvalsh(np.cov(np.vstack([xs, ys]))).max(), 0.0))
        keep[k] = span >= max(min_length, 0.8 * length[k]) and far[ys, xs].max() >= 0.7 * min_length
    out = keep[lab]
    # Joined to the network across the ring.
    return out | (_binary_dilation(out, iterations=4) & ring & ~found & (np.asarray(evidence) >= level) & blade)


def _stray_ridges(evidence, blade, found, level: float, min_length: float) -> np.ndarray:
    """Long strong ridges of the layer's kind that no snapped branch reached (beyond the paper).

    A branch is traced from its junction (:func:`~branchnb.leaves.snapping_trace.trace_branches`); a vein
    that starts apart from the others on this exemplar (a drawn oak's lower
    lateral, drawn as a separate stroke 10-20 px off the midrib) is out of
    any trace's reach, stays in the residual and shows beside the donor's
    pasted veins on every new leaf. Such a vein stands out on its own: a
    connected piece of ``{evidence >= level}`` inside the blade, at least
    ``min_length`` px long (its skeleton) and nearly straight (its principal
    axis, four standard deviations of its pixels, spans at least 0.7 of its
    skeleton) that touches no found pixel (within 2 px) is taken as a vein
    of the layer.

    Parameters
    ----------
    evidence : (H, W) float ndarray
        Line-averaged ridge evidence of the exemplar, in [0, 1].
    blade : (H, W) bool ndarray
        Its blade.
    found : (H, W) bool ndarray
        The snapped layer so far.
    level : float
        Evidence level of a stray vein's pixels.
    min_length : float
        Shortest stray vein (px of skeleton).

    Returns
    -------
    (H, W) bool ndarray
        The stray veins (no pixel of ``found``).
    """
    from skimage.morphology import skeletonize
    strong = (np.asarray(evidence) >= level) & blade
    lab, n = ndi.label(strong, structure=np.ones((3, 3)))
    if n == 0:
        return np.zeros(blade.shape, bool)
    length = np.bincount(lab[skeletonize(strong)], minlength=n + 1)
    near = _binary_dilation(found, iterations=2)
    hit = np.bincount(lab[near], minlength=n + 1)
    keep = (length >= min_length) & (hit == 0)
    # A vein runs on nearly straight: its principal axis (4 standard
    # deviations of its pixels) spans most of its skeleton; a texture
    # blob's wiggly ridge (a photographed maple's mottling) does not.
    for k in np.nonzero(keep)[0]:
        ys, xs = np.nonzero(lab == k)
        span = 4.0 * np.sqrt(max(np.linalg.eigvalsh(np.cov(np.vstack([xs, ys]))).max(), 0.0))
        keep[k] = span >= max(min_length, 0.7 * length[k])
    keep[0] = False
    return keep[lab] & ~found



def _hole_rim(blade, rim: int, share: float, *, hessian=None, reach: float = 0.0) -> np.ndarray:
    """The pixels within ``rim`` px of a hole in ``blade``, or none when the holes are texture.

    A torn patch's edge is no vein (maple 07), but a speckled blade whose
    pale specks the segmentation left out (maple 04: 334 holes of 1-23 px)
    is no damaged one: their rims covered a quarter of the blade and took
    the ridge evidence from the veins running past the specks. Holes whose
    rims cover more than ``share`` of the blade
    (:data:`~branchnb.leaves.snapping.HOLE_SHARE`) are taken as texture.
    Measured (``_measure maples``, maple 04 as exemplar, the six other
    maples as training leaf): vein IoU 0.56 0.65 0.56 0.43 0.65 0.66 ->
    0.58 0.56 0.66 0.49 0.72 0.70 (mean 0.585 -> 0.618; training 02 loses);
    the other maples' holes cover 0-4 % and keep their rims.

    With ``hessian`` (:func:`~branchnb.leaves.snapping_fit.ridge_hessian`) and ``reach`` > 0, also
    the *one-sided* rim (:func:`_one_sided_rim`): pixels up to ``reach`` px from a hole whose ridge
    runs along it, the hole on one side.
    """
    b = np.asarray(blade, bool)
    if rim <= 0:
        return np.zeros_like(b)
    holes = fill_holes(b) & ~b
    out = _binary_dilation(holes, iterations=int(rim)) & b
    if out.sum() > share * max(int(b.sum()), 1):
        return np.zeros_like(b)
    if hessian is not None and reach > 0 and holes.any():
        out |= _one_sided_rim(b, holes, hessian, reach)
    return out


def _one_sided_rim(blade, holes, hessian, reach: float) -> np.ndarray:
    """Blade pixels whose ridge has a hole on one side within ``reach`` px: a rim, not a vein.

    A vein stands out *between* blade on both of its sides. The dark (or
    pale) tissue round a torn or eaten hole stands out too, but the hole
    lies on one side of it, across its ridge (maple 07's browned rim of a
    hole 20 px above its petiole junction is 2-6 px wide; the rim of
    :data:`~branchnb.leaves.snapping.HOLE_RIM` px leaves its outer part). Each pixel's ridge normal is the eigenvector
    of the Hessian's most negative eigenvalue (across a bright ridge of
    the projection); a pixel from which a step of 1..``reach`` px along
    either normal direction lands in a hole is one-sided. A vein crossing
    a hole is not a rim up to the hole (its normal runs beside it);
    a vein running along a hole within ``reach`` is (beyond the paper).
    Used to leave rims out of the induced layer
    (:func:`branchnb.leaves.analysis_induce.induce`); taking their ridge
    evidence away from the template fit and the paths lost on maple 07
    (:mod:`branchnb.leaves.snapping` notes).

    Parameters
    ----------
    blade, holes : (H, W) bool ndarray
        The blade and its holes.
    hessian : (3, H, W) ndarray
        :func:`~branchnb.leaves.snapping_fit.ridge_hessian` (``Hxx, Hxy, Hyy``).
    reach : float
        How far from a hole (px).

    Returns
    -------
    (H, W) bool ndarray
    """
    h, w = blade.shape
    near = (ndi.distance_transform_edt(~holes) <= reach) & blade
    ys, xs = np.nonzero(near)
    if not len(ys):
        return np.zeros_like(blade)
    hxx, hxy, hyy = (np.asarray(c, np.float64)[ys, xs] for c in hessian)
    lam = 0.5 * (hxx + hyy) - np.sqrt(0.25 * (hxx - hyy) ** 2 + hxy ** 2)
    # (hxy, lam - hxx) and (lam - hyy, hxy) both solve (H - lam) v = 0; the longer is the better conditioned.
    v1 = np.stack([hxy, lam - hxx])
    v2 = np.stack([lam - hyy, hxy])
    v = np.where(np.hypot(*v1) >= np.hypot(*v2), v1, v2)
    n = np.hypot(*v)
    flat = n < 1e-12
    v = v / np.where(flat, 1.0, n)
    hit = np.zeros(len(ys), bool)
    for k in range(1, int(np.ceil(reach)) + 1):
        for s in (-1.0, 1.0):
            yy = np.clip(np.round(ys + s * k * v[1]).astype(int), 0, h - 1)
            xx = np.clip(np.round(xs + s * k * v[0]).astype(int), 0, w - 1)
            hit |= holes[yy, xx]
    hit &= ~flat
    out = np.zeros_like(blade)
    out[ys[hit], xs[hit]] = True
    return out
