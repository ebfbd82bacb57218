"""Elbows: a source stroke's sharp bend lands where its target stroke bends.

Step 2 of :func:`~branchnb.strokes.edit.edit_structure`, beyond the paper.
The paper maps a target stroke to its source by arc-length fraction
between control points (the end points unless the user clicks more). An
L-shaped arm (a cactus arm: out from the trunk, then up) re-stroked as a
curve that bends at another fraction of its length got its elbow's patches
where the target runs straight: the inner corner's outline, copied along a
nearly straight stretch, stood off the rim as bumps and curls, and the
target's own bend was drawn with straight patches (kinks on both sides).
:func:`elbow_pin` adds one control pair, the source's sharpest bend to the
target's sharpest bend the same way, so the elbow's piece is drawn where
the target turns.

Measured on a saguaro cactus (the test's, arms
raised, drooped, mirrored and straightened, 150 / 400 / 800 px): see
:func:`elbow_pin` for the figures.
"""

from __future__ import annotations

import numpy as np

from .attachment import _rigid_copy, _with_pins
from .strokes import StrokePair

__all__: list[str] = []

#: Least turn (rad) of the source's bend, over chords of the edit's window on either side, for it to
#: count as an elbow: 0.6 rad (34 deg); the saguaro's L-shaped arms turn by 1.3-1.5 rad there.
_ELBOW_TURN = 0.6

#: Least turn (rad) of the target's bend the same way for the elbow to be put there (0.3 rad, 17 deg):
#: a straightened arm (no bend) keeps the arc-length mapping.
_BEND_TURN = 0.3

#: A bend counts only if it turns this many times more than the stroke's median turn: a stroke
#: curved evenly (a rope's arc) has no place its bend belongs.
_PEAK_RATIO = 2.5

#: A bend spans the arc lengths round its peak turning at least this share of the peak's turn.
_BEND_SPAN = 0.5

#: The elbow mapped within this many windows of the target's bend counts as lying in it (0.25:
#: the saguaro's arm moved to the trunk's other side lands 1.7 px past its bend at 400 px).
_SPAN_SLACK = 0.25

#: The pinned mapping may stretch or squeeze a stretch at most this many times more than the
#: pair's mapping without the pin does.
_MOST_STRETCH = 2.5


def _turn_profile(stroke, window: float, step: float = 1.0):
    """``(s, turn)``: the turn (rad, signed) between the chords before and after each ``s``."""
    n = max(int(np.ceil(stroke.length / step)) + 1, 2)
    s = np.linspace(0.0, stroke.length, n)
    before = stroke._angle_at(np.clip(s - window, 0.0, stroke.length), window)
    after = stroke._angle_at(np.clip(s + window, 0.0, stroke.length), window)
    turn = (after - before + np.pi) % (2.0 * np.pi) - np.pi
    # no bend is measured on a chord squeezed against a stroke end
    turn[(s < window) | (s > stroke.length - window)] = 0.0
    return s, turn


def _sharpest(stroke, window: float, sign: float = 0.0):
    """``(s, turn, s_lo, s_hi)`` of the stroke's sharpest bend (the way of ``sign`` if non-zero):
    its middle, its peak turn and the arc lengths it spans; None when it turns no more than
    :data:`_PEAK_RATIO` times its median turn."""
    if stroke.length <= 4.0 * window:
        return None
    s, turn = _turn_profile(stroke, window)
    score = turn * sign if sign else np.abs(turn)
    k = int(np.argmax(score))
    if score[k] <= _PEAK_RATIO * float(np.median(np.abs(turn))):
        return None
    # the middle of the bend, weighted by its turn: an elbow drawn as two corners close together
    # (an arm's outer corner cut off) bends between them, not at the one a pixel's noise makes sharper
    high = score >= _BEND_SPAN * score[k]
    lo, hi = k, k
    while lo > 0 and high[lo - 1]:
        lo -= 1
    while hi < len(s) - 1 and high[hi + 1]:
        hi += 1
    w = score[lo:hi + 1]
    return float(np.sum(s[lo:hi + 1] * w) / np.sum(w)), float(turn[k]), float(s[lo]), float(s[hi])


def elbow_pin(pair: StrokePair, window: float, mirror: bool = False):
    """The control pair ``(s_source, s_target)`` putting the source's elbow on the target's bend.

    The source stroke's sharpest bend (turning by over :data:`_ELBOW_TURN`
    between the chords of ``window`` before and after it) goes to the target
    stroke's sharpest bend the same way (the other way for a mirrored pair),
    if that turns by over :data:`_BEND_TURN`. None when either has no such
    bend, the pin would leave the order of the pair's control points or
    stretch a stretch over :data:`_MOST_STRETCH` times more than the
    mapping does, or the mapping already lays the source's bend within the
    target's (where each turns by at least :data:`_BEND_SPAN` of its peak, give
    or take :data:`_SPAN_SLACK` windows:
    an arm raised in a wide curve keeps the arc-length mapping; pinned to
    the bend's middle, its upright started early, a step in the outer rim).

    Beyond the paper. On the saguaro of issue 25 (both arms re-stroked, seeds
    0 and 1; rim bumps and distance as in the test) the right arm raised and longer
    had its upper rim ragged where the source's elbow landed past the
    target's bend (a curl of outline, bumps): with the pin the rim's largest
    distance from the cactus drawn along the target strokes went 5.7 -> 3.0 px
    at 400 px and 12.5 -> 5.0 px at 800 px, its bumps (pixels an opening by
    a disk of the outline's width removes) 30 -> 10 and 127 -> 60; arms
    straightened, mirrored or raised in a curve are unchanged.

    Parameters
    ----------
    pair : StrokePair
        The stroke pair with its control points (junction extensions and
        exit pins included).
    window : float
        Chord half-length (px) the stroke directions are measured over.
    mirror : bool
        The pair is drawn with mirror-image patches (its target bends the
        other way).

    Returns
    -------
    tuple of float or None

    Examples
    --------
    >>> from branchnb.strokes.strokes import Stroke
    >>> src = Stroke([(0, 0), (60, 0), (60, -60)])            # out, then up
    >>> dst = Stroke([(0, 0), (30, 0), (60, -30), (70, -100)])  # bends earlier
    >>> s_src, s_dst = elbow_pin(StrokePair(src, dst), 8.0)
    >>> round(s_src), round(s_dst)
    (60, 30)
    """
    src = _sharpest(pair.source, window)
    if src is None or abs(src[1]) < _ELBOW_TURN:
        return None
    dst = _sharpest(pair.target, window, -np.sign(src[1]) if mirror else np.sign(src[1]))
    if dst is None or abs(dst[1]) < _BEND_TURN:
        return None
    a, b = src[0], dst[0]
    ctl = pair.control
    lo, hi = np.interp([src[2], src[3]], ctl[:, 0], ctl[:, 1])
    slack = _SPAN_SLACK * window
    if lo >= dst[2] - slack and hi <= dst[3] + slack:
        # the mapping already lays the whole elbow within the target's bend: a bend drawn wider
        # than the source's (an arm raised in a curve) keeps it; pinned to the bend's middle, the
        # upright beyond the elbow started early (a step in the outer rim, 800 px raised arm)
        return None
    j = int(np.searchsorted(ctl[:, 0], a))
    if not (0 < j < len(ctl)) or not (ctl[j - 1, 1] < b < ctl[j, 1]):
        return None  # out of order with the pair's control points
    if min(a - ctl[j - 1, 0], ctl[j, 0] - a, b - ctl[j - 1, 1], ctl[j, 1] - b) < 1.0:
        return None
    scale = (ctl[j, 1] - ctl[j - 1, 1]) / (ctl[j, 0] - ctl[j - 1, 0])
    for ds, dt in ((a - ctl[j - 1, 0], b - ctl[j - 1, 1]), (ctl[j, 0] - a, ctl[j, 1] - b)):
        ratio = (dt / ds) / scale
        if not 1.0 / _MOST_STRETCH <= ratio <= _MOST_STRETCH:
            return None
    return a, b


def add_elbow_pins(pairs, attached, window: float, mirrored) -> dict:
    """Pin every pair's elbow on its target's bend (:func:`elbow_pin`; ``attached`` in place).

    Parameters
    ----------
    pairs : list of StrokePair
        The stroke pairs as given (a rigid copy of its source keeps its mapping).
    attached : list of StrokePair
        The same pairs with junction extensions and exit pins; replaced in place.
    window : float
        Chord half-length (px) the stroke directions are measured over.
    mirrored : callable
        ``mirrored(pair, window)``: whether a pair is drawn with mirror-image patches.

    Returns
    -------
    dict
        ``{pair index: target arc length of its elbow}``. The sample there is
        left free for global sampling: pinned (as control points' samples are)
        it kept the one patch the arc-length fraction gave, and on the saguaro
        at 400 px the rim's bumps went 15 -> 10 px and its largest distance
        from the reference 3.6 -> 3.0 px once it was free.

    Examples
    --------
    >>> from branchnb.strokes.strokes import Stroke
    >>> pair = StrokePair(Stroke([(0, 0), (60, 0), (60, -60)]), Stroke([(0, 0), (30, 0), (60, -30), (70, -100)]))
    >>> att = [pair]
    >>> pins = add_elbow_pins([pair], att, 8.0, lambda p, w: False)
    >>> {k: round(v) for k, v in pins.items()}, att[0].n_control
    ({0: 30}, 3)
    """
    out = {}
    for i, pair in enumerate(attached):
        if _rigid_copy(pairs[i]):
            continue
        pin = elbow_pin(pair, window, mirrored(pairs[i], window))
        if pin is not None:
            attached[i] = _with_pins(pair, [pin])
            out[i] = pin[1]
    return out
