"""The blade's outline band in layer induction (beyond the paper): an inked outline is no vein.

Steps of :func:`branchnb.leaves.analysis_induce.induce` for thin layers on
drawn leaves: the outline band (:func:`_outline_band`, of the closed blade
:func:`_closed_blade`), whether the user's layer holds the outline
(:func:`_outline_in_layer`) or the training outline is inked in the
layer's colour (:func:`_inked_outline`), and the induced pieces that run
along the band (:func:`_outline_stretches`); a drawn leaf's ink outline
zone, no evidence for snapping and no place for a thin layer's long pieces
(:func:`_ink_zone`); and, before induction, the
outline stretches lazy snapping grew into a thin layer nobody scribbled
there (:func:`_unscribbled_outline`, called by
:func:`branchnb.leaves.layers.grow_layers`).
"""

from __future__ import annotations

import hashlib
import threading

import numpy as np
from scipy import ndimage as ndi

from ..core.distance import edt as _edt
from ..core.morphology import _binary_dilation, fill_holes


def _contrast(lab, layer, blade):
    ring = _binary_dilation(layer, iterations=4) & blade & ~layer
    if not ring.any() or not layer.any():
        return None
    return lab[layer].mean(0) - lab[ring].mean(0)


#: A thin layer's induced mask covering at least this share of the blade's
#: outline band is an inked outline taken as layer: the band is left out.
INKED_OUTLINE = 0.2


def _outline_band(blade, user):
    """The blade's outline band, as wide as a thin layer (2 px at least): never part of a vein layer.

    Ink drawn along a sketched leaf's edge has the veins' colour and was
    induced as vein (beyond the paper). Procedural dark-veined leaves with
    a 1.5 px ink outline of the same colour (``_measure_colours --colours
    dark --outline 1.5``): IoU min 0.53 -> 0.80, mean 0.62 -> 0.83; only
    where the induced mask covers :data:`INKED_OUTLINE` of the band (always
    left out, the vein ends at the margin cost 0.03 mean IoU on leaves
    without ink).
    """
    from .induction import layer_width
    reach = max(2.0, float(np.ceil(layer_width(user))))
    return blade & (_closed_distance(blade) <= reach)


#: A piece of a thin layer's induced mask inside the outline band that runs
#: along it for at least this many band depths is an inked outline stretch.
OUTLINE_STRETCH = 4.0


#: The training leaf's outline band, off the user's layer, holding the layer's
#: colour over at least this share is inked (a sketch's outline).
INKED_TRAINING = 0.3


def _inked_outline(lab, blade, user) -> bool:
    """Whether the training leaf's outline is drawn in the layer's colour (:data:`INKED_TRAINING` of its band).

    Only then are :func:`_outline_stretches` left out: on a leaf without ink
    the band's long pieces are veins running into narrow lobe tips
    (procedural families: 0.01-0.02 IoU lost on 14 of 18 pairs otherwise).
    A colour is the layer's within a third of the layer's contrast with
    the blade around it, as in :func:`_has_layer_colour`.
    """
    c = _contrast(lab, user, blade)
    if c is None:
        return False
    band = _outline_band(blade, user) & ~_binary_dilation(user, iterations=2)
    if not band.any():
        return False
    colour = np.median(lab[user], axis=0)
    tol = max(float(np.linalg.norm(c)) / 3.0, 1e-6)
    close = np.linalg.norm(lab[band] - colour, axis=-1) < tol
    return float(close.mean()) >= INKED_TRAINING


def _outline_stretches(in_band, user, reach=None):
    """The pieces of ``in_band`` (a thin layer's induced mask within the outline band) that run along the outline.

    Beyond the paper. A sketch's ink outline has the veins' colour; where
    the induced mask takes less than :data:`INKED_OUTLINE` of the band the
    band stays, and the outline's stretches stayed with it (maple sketch 1
    -> 2: 0.16 of the band, stretches of 20-120 px along the margin). A vein
    ending at the margin crosses the band: its piece there spans about one
    band depth (two or three when it meets the margin at a slant). A piece
    whose bounding box spans :data:`OUTLINE_STRETCH` band depths or more
    runs along the outline and is left out; the vein ends stay. Measured:
    maple sketch 1 -> 2 IoU 0.57 -> 0.69 (band's plain pixels taken 0.170 ->
    0.033); procedural dark-veined leaves with a 1.5 px ink outline
    (``_measure_colours --colours dark --outline 1.5 --sizes 192,320``)
    band taken max 0.075 -> 0.035, IoU mean 0.81 unchanged, one training
    leaf (trilobed 320 px) 0.57 / 0.64 -> 0.56 / 0.62 (a vein into a narrow
    lobe tip lies in the band); without ink (:func:`_inked_outline` false)
    nothing changes. ``reach``: the band's depth in px (default the
    layer's width, 2 px at least; :func:`_ink_zone` gives its own).
    """
    from .induction import layer_width
    if not in_band.any():
        return in_band
    if reach is None:
        reach = max(2.0, float(np.ceil(layer_width(user))))
    lab, n = ndi.label(in_band, structure=np.ones((3, 3), bool))
    out = np.zeros_like(in_band)
    for i, sl in enumerate(ndi.find_objects(lab)):
        if sl is not None and max(sl[0].stop - sl[0].start, sl[1].stop - sl[1].start) >= OUTLINE_STRETCH * reach:
            out[sl] |= lab[sl] == i + 1
    return out


#: Gaps between a drawn blade's paint strokes up to twice this share of the leaf size (``sqrt`` of its
#: area) are inside the leaf for :func:`_outline_band` (0: every blade edge is outline).
OUTLINE_GAP = 0.03


#: The last few blades' closed areas and distance maps, by the blade's digest: every layer asks for
#: each exemplar's again (7-11 times in a two-layer analysis of 4 exemplars, 0.1-0.2 s each at 1 MP).
_CLOSED_CACHE: dict = {}
_CLOSED_LOCK = threading.Lock()  # the exemplars are induced in threads


def _closed_cached(kind: str, blade, make):
    m = np.ascontiguousarray(blade, bool)
    key = (kind, m.shape, hashlib.blake2b(np.packbits(m).tobytes(), digest_size=16).digest())
    with _CLOSED_LOCK:
        hit = _CLOSED_CACHE.get(key)
    if hit is None:
        hit = np.array(make(m), copy=True)  # never the caller's own array
        with _CLOSED_LOCK:
            while len(_CLOSED_CACHE) >= 24:
                _CLOSED_CACHE.pop(next(iter(_CLOSED_CACHE)))
            _CLOSED_CACHE[key] = hit
    return hit.copy()


def _closed_distance(blade) -> np.ndarray:
    """Each pixel's distance (px) to the outside of :func:`_closed_blade` (remembered per blade)."""
    return _closed_cached("distance", blade, lambda m: _edt(_closed_blade(m)))


def _closed_blade(blade):
    """:func:`_closed_of`, remembered for the last few blades (a copy)."""
    return _closed_cached("closed", blade, _closed_of)


def _closed_of(blade):
    """The blade with the gaps between its paint strokes closed: the area inside its outline.

    A sketched leaf painted with brush strokes (``leaves_more`` maples)
    has white gaps all over its blade; the edges of those gaps are not its
    outline. Taken for it, the outline band spread over the whole blade, the
    induced veins never covered :data:`INKED_OUTLINE` of it, and the ink
    outline of maple sketch 1 was induced as vein on long stretches.
    """
    r = int(round(OUTLINE_GAP * np.sqrt(float(blade.sum()))))
    if r < 1:
        return blade
    import cv2
    disk = cv2.getStructuringElement(cv2.MORPH_ELLIPSE, (2 * r + 1, 2 * r + 1))
    pad = np.pad(blade.astype(np.uint8), r + 1)
    closed = cv2.morphologyEx(pad, cv2.MORPH_CLOSE, disk)[r + 1:-r - 1, r + 1:-r - 1].astype(bool)
    return fill_holes(closed | blade)


#: The user's layer covering at least this share of the training blade's
#: outline band holds the outline itself (:func:`_outline_in_layer`).
OUTLINE_IN_LAYER = 0.6


def _outline_in_layer(blade, user) -> bool:
    """Whether the user's layer on the training leaf holds the blade's outline (:data:`OUTLINE_IN_LAYER` of its band).

    Then the outline is part of what the user marked (all of a sketch's ink
    as one layer: 0.77 of the band on a drawn maple) and
    :func:`_outline_band` is not left out on the other exemplars: left
    out, the ink induced on a second drawn maple matched its dark pixels
    with IoU 0.37 instead of 0.91. Veins that reach the margin cover less
    (0.37-0.39 on a 128 px elliptic leaf).
    """
    band = _outline_band(blade, user)
    return bool((user & band).sum() >= OUTLINE_IN_LAYER * max(int(band.sum()), 1))


def _unscribbled_outline(grown, blade, scribbled, ink):
    """The stretches of a thin layer grown on the training leaf that run along its ink outline, unscribbled.

    Beyond the paper. On a drawn leaf the ink outline is a line like a
    vein, and lazy snapping grew short vein scribbles along it (a drawn
    maple with pale veins: 0.88 of the outline band in the grown vein
    layer). :func:`_outline_in_layer` then took the outline for part of
    what the user marked, and every exemplar's outline was induced as vein
    (``_measure_unseen --induce-only``, drawn maples: vein IoU 0.42 at
    every exemplar). Only when the blade's rim is ink (``ink``, from
    :func:`branchnb.leaves.flatart.drawn_outline`, empty on photos) the
    grown layer's :func:`_outline_stretches` (pieces running along the band
    for :data:`OUTLINE_STRETCH` band depths) are left out, unless the user
    scribbled the outline: :data:`SCRIBBLED_OUTLINE` of the scribbles'
    pixels in the band (a sketch's ink as one layer keeps it). Keeping
    only the stretches a scribble touches was tried: two lobes' outlines
    stayed on the drawn pale maple (training IoU 0.55 against 0.80). The
    vein ends crossing the band stay.

    Measured (``python -m branchnb.leaves._measure_unseen --kinds K --sizes S
    --seeds 0,1 --induce-only``), mean induced vein IoU over the four
    exemplars: drawn maples 384 px pale-2 0.42 / 0.41 -> 0.85 / 0.84,
    colour-2 0.39 -> 0.90, colour-3 0.48 / 0.88 -> 0.91 / 0.88, black-2
    0.43 / 0.44 -> 0.77 / 0.78; 512 px pale-2 0.42 -> 0.83, colour-2 0.39
    -> 0.87, black-1 0.28 -> 0.72; 256 px black-1 0.29 -> 0.76 (pale-2,
    colour-2 at 256 px unchanged 0.85 / 0.90: nothing grew along the
    outline there); drawn oak, elm and palmate (384 px, two seeds)
    unchanged. Photos, the sample maples and drawn oaks, and the procedural
    families have no inked rim: nothing changes on them.
    """
    if not ink.any() or not grown.any():
        return np.zeros_like(grown)
    band = _outline_band(blade, grown)
    if (scribbled & band).sum() >= SCRIBBLED_OUTLINE * max(int(scribbled.sum()), 1):
        return np.zeros_like(grown)
    return _outline_stretches(grown & band, grown)


#: A thin layer's scribbles with at least this share of their pixels in the outline band mark the outline.
SCRIBBLED_OUTLINE = 0.3


#: The ink outline zone reaches this many px past the ink's mean width, and at least the layer's width
#: (:func:`_ink_zone`): a ridge filter on a line the blade's edge cuts off peaks on the line's inner side.
INK_ZONE_PAD = 2.0


def _ink_zone(rgb, blade, layer_px: float) -> tuple[np.ndarray, float]:
    """A drawn leaf's ink outline and the strip just inside it: no evidence of a thin layer (empty on photos).

    Beyond the paper. On a drawn leaf (an ink rim all round,
    :func:`branchnb.leaves.flatart.drawn_outline`; photographed and
    shaded leaves have none) the outline is a dark line following the
    blade's boundary, like a vein. Snapping pulled the carried template's
    margin-side paths onto it and the colour term took it where a drawn
    vein had the ink's colour: given a vein layer on plain fill, the
    outline of the other exemplars was induced as vein in a strip 2-4 px
    inside the blade's edge, outside :func:`_outline_band` (as wide as the
    layer, 2 px). The zone is the ink and the blade within
    :data:`INK_ZONE_PAD` and the layer's width ``layer_px`` of it (measured
    from the ink, not the blade's edge: a narrow sinus between two oak
    lobes, closed by :func:`_closed_blade`, has ink on both sides, a dark
    line deep inside the closed blade); returned with its depth, the ink's
    mean width (ink pixels per rim pixel of the closed blade) plus that
    reach. A drawn vein ending at the outline crosses the zone: only pieces
    running along it are taken out (:func:`_outline_stretches` with the
    zone's depth).

    Measured (``python -m branchnb.leaves._measure_drawn --shapes maple,oak
    --outlines 1,3 --shadows 1 --sizes 200,384,640,1000 --cycle``, and
    ``--shapes elm,palmate --outlines 2,4 --shadows 0``; 24 cases of 4
    drawn leaves), share of the outline zone taken as vein mean / max:
    plain fill 0.321 / 0.532 -> 0.004 / 0.014; black drawn veins 0.122 /
    0.332 -> 0.020 / 0.144 (precision mean / min 0.779 / 0.438 -> 0.973 /
    0.883, recall 0.938 -> 0.940); coloured veins unchanged. Photos and
    the procedural shaded families have no ink rim: nothing changes
    (real-maple pairs, ``_measure_unseen`` willow, cordate, oak identical).
    """
    from .flatart import drawn_outline
    ink = drawn_outline(rgb, blade)
    if not ink.any():
        return ink, 0.0
    closed = _closed_blade(blade)
    inner = closed & ~_binary_dilation(~closed, iterations=1)
    n_rim = max(int(np.count_nonzero(closed)) - int(np.count_nonzero(inner)), 1)
    pad = INK_ZONE_PAD + max(1.0, float(layer_px))
    return blade & (_edt(~ink) <= pad), float(np.count_nonzero(ink)) / n_rim + pad
