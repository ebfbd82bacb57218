"""Thin line layers in lazy snapping (:func:`branchnb.leaves.layers.grow_layers`; beyond the paper).

For a layer of 1-5 px veins: the scribbled pixels between its lines left
unpinned (:func:`_on_line_pins`) and the blade pixels that cannot be on a
line kept in the background colour model (:func:`_off_lines`).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage as ndi

from ..core.morphology import _binary_dilation, _binary_opening

__all__: list[str] = []

#: Line strength below which a pixel of a thin line layer's blade is off every line (background model).
_OFF_LINE = 0.05
#: Pixels this close (px, 4-connected steps) to a possible line pixel may still be layer (background model).
_OFF_LINE_REACH = 3
#: ... or within the square root of the blade's area over this many px (a large leaf's wide veins).
_OFF_LINE_SIDES = 25.0
#: A narrow part of the blade (a petiole) covers at least this many squares of its half width.
_NARROW_LONG = 6.0
#: A thin line layer's scribbled pixels between its lines are left unpinned (:func:`_on_line_pins`,
#: switched by ``branchnb.leaves.layers._ON_LINE_PINS``), kept where its strength is at least this
#: or the pixel stands out at least _ON_LINE_ABOVE times as much as the scribbled pixels do.
_ON_LINE = 0.25
_ON_LINE_ABOVE = 0.5
#: ... unless fewer than this share of the scribbled layer pixels are left (then all are kept).
_ON_LINE_KEEP = 0.3
#: ... and only where the lines (strength 0.5 or more) cover at least this share of the blade.
_DENSE_LINES = 0.15
#: Line strength from which a pixel joined to the grown thin line layer along a line joins it (:func:`_along_lines`).
_ALONG_LINE = 0.4
#: ... only for a grown layer this elongated (:func:`_elongation`): procedural vein layers grown at
#: 128-400 px measured 20.9-913, spot layers 5.1-9.9.
_ALONG_NETWORK = 15.0
#: ... unless the layer would then cover more than this share of the blade.
_ALONG_MOST = 0.5
#: ... within this many px of it (the 11-px box's half width, where a branch shares the vein's box).
_ALONG_GAP = 5


def _on_line_pins(fg_px: np.ndarray, line: np.ndarray, ridges: np.ndarray, blade: np.ndarray) -> np.ndarray:
    """The scribbled layer pixels of a thin line layer, without those between its lines (beyond lazy snapping).

    Radius-1 strokes over parallel veins 3-5 px apart (a 96-px strip)
    leave plain blade between the veins among the pixels :func:`_on_layer`
    keeps: its ring around each stroke is mostly other veins. Pinned to the
    layer, those pixels took the blade between the scribbled veins into it
    and into its colour model (faint veins, 20 % darker than the blade:
    training IoU 0.32-0.48, 9-16 % of the layer more than 1 px off every
    vein; induced on the other leaves 0.44-0.49). Kept: pixels on a line
    (strength at least :data:`_ON_LINE`) or standing out from the blade
    around them at least :data:`_ON_LINE_ABOVE` as much as the scribbled
    pixels do (the inside of a vein wider than the line filter). Only
    where the lines are dense (at least :data:`_DENSE_LINES` of the blade
    at half strength or more: small leaves, 14-29 % measured on 96-128 px
    strips, lobed and elliptic leaves): on a sparse venation
    the scribbles' off-line pixels are the flanks of wider veins the user
    meant (the sample maple, 8 %: its vein layer lost a quarter of its
    pixels and the induced veins' IoU with the hand tracing fell 0.48 ->
    0.32 without this). All are kept when under :data:`_ON_LINE_KEEP` of
    them would be left, or when the scribbles do not lie on lines (their
    median line strength under 0.5: strokes over a plain blade).
    """
    if float(np.count_nonzero((np.asarray(line) >= 0.5) & blade)) < _DENSE_LINES * max(np.count_nonzero(blade), 1):
        return fg_px
    # only scribbles that lie on the lines: strokes along veins painted out of a plain blade (median
    # line strength 0.00 on them, 0.70-1.00 on real veins) would keep only the grain's ridges they cross,
    # and the layer grew along those into one that stands out (structural where it is not)
    if float(np.median(np.asarray(line)[fg_px])) < 0.5:
        return fg_px
    k = 1 if np.median(ridges[..., 3][fg_px]) > np.median(ridges[..., 2][fg_px]) else 0
    above = ridges[..., 2 + k]
    lift = max(float(np.median(above[fg_px])), 1e-6)
    on = fg_px & ((np.asarray(line) >= _ON_LINE) | (above >= _ON_LINE_ABOVE * lift))
    if on.sum() < max(4, _ON_LINE_KEEP * fg_px.sum()):
        return fg_px
    return on


def _off_lines(line: np.ndarray, ridges: np.ndarray, fg_px: np.ndarray, blade: np.ndarray) -> np.ndarray:
    """Pixels that cannot be part of a thin line layer: off every line and not standing out as its lines do.

    Off a line: line strength below ``_OFF_LINE``. Standing out: at least
    half as much darker (lighter) than the blade around it (11 px) as the
    scribbled pixels are; the inside of a vein wider than the line filter
    (a 4-px midrib) answers no line filter but stands out, a pale rim of
    the layer's hue does neither.
    """
    k = 1 if np.median(ridges[..., 3][fg_px]) > np.median(ridges[..., 2][fg_px]) else 0
    above = ridges[..., 2 + k]
    lift = max(float(np.median(above[fg_px])), 1e-6)
    possible = (np.asarray(line) >= _OFF_LINE) | (above >= 0.5 * lift)
    # A vein fading below the line filter (its tip, a faint stretch) keeps
    # its colour out of the background model where it continues a line.
    # The reach grows with the leaf: a large leaf's main veins are wider
    # than the line filter, and their insides stand out less.
    reach = max(_OFF_LINE_REACH, int(round(np.sqrt(blade.sum()) / _OFF_LINE_SIDES)))
    # Narrow parts of the blade (a petiole, as wide as a vein and with no
    # blade around it to stand out from) are not sure either.
    half = max(2, reach // 2)
    disk = np.hypot(*np.mgrid[-half:half + 1, -half:half + 1]) <= half
    narrow = blade & ~_binary_opening(blade, disk)
    # Only long narrow parts: a sharp corner of the blade leaves a small
    # tip here (and a pale rim grown from it was the fault this rule mends).
    lab, n = ndi.label(narrow)
    if n:
        area = np.bincount(lab.ravel(), minlength=n + 1)
        long = area >= _NARROW_LONG * half * half
        long[0] = False
        narrow = long[lab]
    return ~(_binary_dilation(possible, iterations=reach) | narrow)



def _line_kind(ridges: np.ndarray, fg_px: np.ndarray) -> int:
    """0 if the scribbled pixels stand out lighter than the blade around them, 1 if darker."""
    return 1 if np.median(ridges[..., 3][fg_px]) > np.median(ridges[..., 2][fg_px]) else 0


def _elongation(mask: np.ndarray, fg_px: np.ndarray) -> float:
    """Area over squared widest half width of the grown pieces holding scribbled pixels (all of them together)."""
    lab, _ = ndi.label(mask, structure=np.ones((3, 3), bool))
    ids = np.unique(lab[fg_px & mask])
    ids = ids[ids > 0]
    if not len(ids):
        return 0.0
    half = np.maximum(np.asarray(ndi.maximum(ndi.distance_transform_edt(mask), lab, ids), float), 1.0)
    return float(np.sum(ndi.sum(mask, lab, ids)) / np.sum(half**2))


def _along_lines(mask: np.ndarray, ridges: np.ndarray, fg_px: np.ndarray, blade: np.ndarray,
                 exclude: np.ndarray | None = None, frac: float = _ALONG_LINE) -> np.ndarray:
    """The grown thin line layer plus the fainter lines running out of it (hysteresis; beyond lazy snapping).

    A pixel joins when it stands out (lighter or darker, as the scribbled
    pixels do) from the blade around it (an 11-px box) by at least ``frac``
    of what the scribbled pixels stand out, and its piece of such pixels
    comes within :data:`_ALONG_GAP` px of the grown layer: the first 3-4 px
    of a branch leaving a bold vein share their box with the vein and stand
    out less (the branch was cut off there). ``exclude``: pixels that never join.
    """
    k = _line_kind(ridges, fg_px)
    above = ridges[..., 2 + k]
    lift = max(float(np.median(above[fg_px])), 1e-6)
    # Not beside a line of the other kind standing out as much (a drawn leaf's ink outline: the fill
    # within its 11-px box is lighter than the box, and pale veins grew round the whole rim, IoU 0.81 -> 0.35).
    other = _binary_dilation(ridges[..., 3 - k] >= lift, iterations=_ALONG_GAP)
    weak = blade & ~mask & ~other & (above >= frac * lift)
    if exclude is not None:
        weak &= ~exclude
    lab, n = ndi.label(weak, structure=np.ones((3, 3), bool))
    if n == 0:
        return mask
    keep = np.zeros(n + 1, bool)
    keep[lab[_binary_dilation(mask, iterations=_ALONG_GAP) & weak]] = True
    keep[0] = False
    out = mask | keep[lab]
    # A line layer is never most of the blade: between dense parallel veins (a 192-px strip, veins 35 %
    # of it) the blade itself stood out and the layer took 81 % of the blade (vein IoU 0.46 -> 0.22).
    return mask if out.sum() > _ALONG_MOST * blade.sum() else out
