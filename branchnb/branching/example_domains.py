"""Automatic extraction, step 3 (beyond the paper): the domain of an example (where its branches live).

The image minus its large branch-free flat (or unlike) regions, see
:func:`example_domain`. Split from :mod:`.backgrounds` (which re-exports
every name).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.structure import Structure
from ..core.validate import Image, checked
from .backgrounds import binary_channels, flat_background, is_binary, unlike_background
from .clicks import _RADIUS, gray_for_extraction

__all__ = ["example_domain"]


@checked(image=Image(), radius=_RADIUS)
def example_domain(image, structure: Structure | None = None, *, radius: float = 12.0) -> np.ndarray:
    """Where an example's branches live: the image minus its large branch-free flat regions.

    For a binary mask, the foreground regions far wider than the channels
    (the sea of a delta, see :func:`binary_channels`) are outside; for any
    other image, the large flat-colour regions that touch the border and
    hold no branch (the sea around a river map's land, see
    :func:`flat_background`; the branches are ``structure`` if given).
    Pass the result to :func:`~branchnb.branching.fit_model` as ``domain``.

    Beyond the paper (issue 23): a line mask on one plain ground (binary, or
    anti-aliased in two tones) leaves out the part of the frame its lines
    leave empty (:func:`.empty_ground._empty_part`), so the output keeps to the occupied
    part, and keeps within the lines' own line-to-line spacing of them
    (:func:`.empty_ground._line_domain`: a vine along two borders of its frame
    grows along those borders, not as a bush over a region twice the band's
    width). :func:`~branchnb.branching.fit_model` reads the rest as ground, not
    as a coast or a hole (``StructureModel.ground``), and the output's strands
    turn to stay in the domain (``branch_starts.LEAVE_BAND``).

    Parameters
    ----------
    image : (H, W) or (H, W, C) array_like
        The example: grey, RGB or RGBA (composited over white), float in [0, 1] or integer.
    structure : Structure, optional
        Its branches; None = judge regions by the image alone.
    radius : float, default 12.0
        Flat regions must be wider than a disk of this radius (pixels).

    Returns
    -------
    (H, W) bool ndarray
        True where the branches may grow.

    Examples
    --------
    >>> import numpy as np
    >>> m = np.zeros((100, 100)); m[70:] = 1; m[:70, 48:52] = 1   # a channel into a sea
    >>> d = example_domain(m)
    >>> bool(d[10, 50]), bool(d[90, 50])
    (True, False)
    """
    gray = gray_for_extraction(image)
    if structure is not None and structure.branches:
        # an engraved map: its sea is drawn as parallel hatching (.hatched_seas, beyond the paper); its
        # paper is the land's too, so no flat-colour rule below applies
        from ..core.render import coverage_polylines
        from .hatched_seas import hatched_background

        cov, _ = coverage_polylines(gray.shape, [b.points for b in structure.branches],
                                    [2 * b.thickness + 2 for b in structure.branches])
        sea = hatched_background(gray, cov > 0.5)
        if sea.any():
            opaque = _opaque_part(image)
            return ~sea if opaque is None else ~sea & opaque
    if is_binary(gray):
        ch, region, _sk, _r = binary_channels(gray)
        if not region.any():
            # one region (lines on a plain ground): the ground the network leaves empty is no domain
            from .empty_ground import _line_domain

            return _line_domain(ch)
        return ~region
    opaque = _opaque_part(image)
    branches = np.zeros(gray.shape, bool)
    if structure is not None and structure.branches:
        from ..core.render import coverage_polylines

        cov, _ = coverage_polylines(gray.shape, [b.points for b in structure.branches],
                                    [2 * b.thickness + 2 for b in structure.branches])
        branches = cov > 0.5
    bg = flat_background(gray, branches, radius)
    if not bg.any() and branches.any() and np.ndim(image) == 3:
        from .empty_ground import _line_domain
        from .flat_regions import two_tone_lines

        if two_tone_lines(np.asarray(image, np.float32)):
            # an anti-aliased line mask on one plain ground: like a binary one (above)
            lo, hi = np.percentile(gray, [1, 99])
            fg = gray > 0.5 * (lo + hi)
            return _line_domain(fg if fg.mean() < 0.5 else ~fg)
    if not bg.any() and branches.any():
        # a photograph: no flat background, but a textured ground of another colour (a table round a leaf)
        bg = unlike_background(image, branches, radius)
    if bg.any():
        # the flat test leaves a 2 px rim of the background's colour along its edge (windows that
        # reach the coast line): the background takes it, up to the drawn line (beyond the paper)
        g = np.asarray(gray, np.float64)
        like = np.abs(g - float(np.median(g[bg]))) <= 0.1
        bg = ndi.binary_dilation(bg, iterations=4, mask=like | bg)
        bg = _smooth_edge(bg, like, branches, radius)
        matte = None
        if np.ndim(image) == 3:
            # a photo's flat black/white matte is outside wholly, also its slivers narrower than
            # ``radius`` where a fundus disk nears the frame (beyond the paper)
            from .regions import matte_mask

            rgb = np.asarray(image, np.float32)
            if np.issubdtype(np.asarray(image).dtype, np.integer):
                rgb = rgb / float(np.iinfo(np.asarray(image).dtype).max)
            matte = matte_mask(rgb, dilate=0)
            matte = matte if matte.any() and (bg & matte).sum() >= 0.5 * matte.sum() else None
        if matte is None:
            # (a photo's matte has no straits: its vignetted rim is no arm of it)
            bg = _sea_channels(bg, like, branches, np.abs(g - float(np.median(g[bg]))))
        else:
            bg |= matte
    dom = ~bg
    return dom if opaque is None else dom & opaque


def _opaque_part(image) -> np.ndarray | None:
    """The opaque part of an RGBA example (a map whose land is drawn and outside transparent), or None.

    Beyond the paper. Composited over white, a transparent outside has the
    colour of a map's white lowlands, so no flat-region rule can tell them
    apart; the alpha channel does. None when there is no alpha channel or
    when it is (nearly) all opaque or all transparent (under 5 % either way).
    """
    a = np.asarray(image)
    if a.ndim != 3 or a.shape[2] != 4:
        return None
    alpha = a[..., 3].astype(np.float64)
    if np.issubdtype(a.dtype, np.integer):
        alpha /= float(np.iinfo(a.dtype).max)
    opaque = alpha >= 0.5
    share = float(opaque.mean())
    if not 0.05 <= share <= 0.95:
        return None
    # the land's own holes (a transparent lake drawn as a gap) stay in the domain
    return ndi.binary_fill_holes(opaque)


#: A piece of the background's colour joins it when under this share of its rim is a branch: a strait's
#: rim is the two coast lines (0-10 % branch, at the river mouths, on 2-4 island maps of 384-1024 px);
#: a slot between two branches of a tree is walled by the branches (90-100 %).
SEA_RIM_BRANCH = 0.5
#: ... and when no branch runs deeper than this (pixels) into it: a river's end pokes 1-3 px past the
#: coast line into the strait; land behind a gap in a dotted coast holds its rivers far inland.
SEA_HELD_DEPTH = 4.0
#: ... and when it is flat: mean luminance off the background's at most this (a drawn strait: 0-0.01;
#: the vignetted rim of a fundus photo next to its black matte: fades over 0-0.1).
SEA_FLAT = 0.02


def _sea_channels(bg: np.ndarray, like: np.ndarray, branches: np.ndarray, off: np.ndarray) -> np.ndarray:
    """``bg`` with the narrow arms of the background's colour that run off it between drawn lines.

    Beyond the paper (issue 23): the flat test keeps only what a disk of
    ``radius`` fits in, so a sea strait between two islands narrower than
    the disk (12-50 px on maps of 384-768 px) stayed in the domain: the
    islands became one piece, a tree grew across the strait and the
    output's land filled it (domain IoU with the land 0.90-0.95). A piece
    of the background's colour (4-connected, so a 1 px coast line walls
    it) that touches the background joins it when its rim is mostly not a
    branch (:data:`SEA_RIM_BRANCH`: walled by coast lines, not by the
    branches of a tree), no branch runs into it (:data:`SEA_HELD_DEPTH`) and
    it is as flat as a drawn sea (``off``, each pixel's luminance off the
    background's, at most :data:`SEA_FLAT` on average: the vignetted rim
    of a fundus photo, dark like its matte, fades and stays).
    """
    cand = like & ~bg
    lab, n = ndi.label(cand)
    if n == 0:
        return bg
    touch = np.zeros(n + 1, bool)
    touch[lab[ndi.binary_dilation(bg) & cand]] = True
    grown = ndi.grey_dilation(lab, footprint=np.ones((3, 3), bool))
    rim = (lab == 0) & ~bg & (grown > 0)
    br = np.asarray(branches, bool)
    rim_n = np.bincount(grown[rim], minlength=n + 1)
    rim_b = np.bincount(grown[rim & br], minlength=n + 1)
    held = np.zeros(n + 1, bool)
    held[lab[br & (ndi.distance_transform_edt(cand) > SEA_HELD_DEPTH)]] = True
    flat = ndi.mean(off, lab, np.arange(n + 1)) <= SEA_FLAT
    join = touch & ~held & flat & (rim_b < SEA_RIM_BRANCH * np.maximum(rim_n, 1))
    join[0] = False
    if not join.any():
        return bg
    out = bg | join[lab]
    # what the joined arms cut off from the domain and left in the sea holds no branch (a wave dash beside
    # a pocket of a marked sea, which the pocket tied to the domain): sea too
    old, n_old = ndi.label(~bg)
    new, n_new = ndi.label(~out)
    if n_new <= n_old:
        return out
    old_of = ndi.maximum(old, new, np.arange(1, n_new + 1)).astype(np.int64)
    area_old = np.bincount(old.ravel(), minlength=n_old + 1)
    area_new = np.bincount(new.ravel(), minlength=n_new + 1)[1:]
    holds = np.zeros(n_new + 1, bool)
    holds[new[br]] = True
    cut = np.r_[False, (area_new < area_old[old_of]) & ~holds[1:]]
    # only the smaller pieces of a split one: the land it was cut from stays
    biggest = np.zeros(n_old + 1, np.int64)
    np.maximum.at(biggest, old_of, area_new)
    cut[1:] &= area_new < biggest[old_of]
    return out | cut[new]


def _smooth_edge(bg: np.ndarray, like: np.ndarray, branches: np.ndarray, radius: float) -> np.ndarray:
    """``bg`` with the pockets and marks along its edge that the flat test left to the domain.

    Beyond the paper (issue 23): the flat test keeps only what a disk of
    ``radius`` fits in, so beside every mark of a marked sea (the wave dashes
    of a fantasy map) that lies near the coast a pocket of the sea's colour
    up to ``radius`` deep stayed in the domain, and the dash itself with it:
    the domain's coast, and the output's coast drawn along it, had a bite or
    a spike at every such dash (a smooth coast came out scalloped, 4.2 sign
    changes of curvature per 100 px against the example's 1.3). The
    background now takes the pixels of its colour within ``radius + 2`` that
    its closing with that disk covers (the pockets between its lobes; the
    land behind a gap in a dotted coast is not enclosed by the sea and stays
    out), and then every piece of the domain narrower than 5 px (no disk of
    radius 2 fits) that touches it and holds no branch pixel (a dash, a
    pocket's rim).
    """
    import cv2

    r = max(int(round(radius)), 1)
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    closed = cv2.morphologyEx(bg.astype(np.uint8), cv2.MORPH_CLOSE, disk, borderType=cv2.BORDER_REPLICATE) > 0
    bg = ndi.binary_dilation(bg, iterations=r + 2, mask=bg | (like & closed))
    dom = ~bg
    opened = cv2.morphologyEx(dom.astype(np.uint8), cv2.MORPH_OPEN,
                              cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (5, 5)),
                              borderType=cv2.BORDER_REPLICATE) > 0
    lab, n = ndi.label(dom & ~opened, structure=np.ones((3, 3), bool))
    if n == 0:
        return bg
    touch = np.zeros(n + 1, bool)
    touch[lab[ndi.binary_dilation(bg)]] = True
    held = np.zeros(n + 1, bool)
    held[lab[np.asarray(branches, bool)]] = True
    drop = touch & ~held
    drop[0] = False
    return bg | drop[lab]
