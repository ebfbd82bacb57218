"""Hand-placed reference pins and the pin error of an exemplar against them.

``data/trees_pins/pins.json`` holds pin points ``B``, ``R``, ``L`` placed by
eye on sample trees (source pixels; how they were made is in the file's
``note``). :func:`pin_errors` measures how far the automatic pins of
:func:`~branchnb.trees.variations.process_exemplar` are from them, as a
fraction of the tree height (``B`` to the top of the tree).
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np

__all__ = ["PINS_FILE", "load_reference_pins", "source_pins", "pin_errors"]

#: The hand-placed pins.
PINS_FILE = Path(__file__).resolve().parent.parent.parent / "data" / "trees_pins" / "pins.json"


def load_reference_pins() -> dict[str, dict[str, np.ndarray]]:
    """name -> {"B", "R", "L"} -> (x, y) in source-image pixels.

    Examples
    --------
    >>> sorted(load_reference_pins()["plain_tree"])
    ['B', 'L', 'R']
    """
    table = json.loads(PINS_FILE.read_text())["pins"]
    return {n: {k: np.asarray(v, float) for k, v in d.items()} for n, d in table.items()}


def source_pins(exemplar) -> dict[str, np.ndarray]:
    """An exemplar's pins ``B``, ``R``, ``L`` mapped back to its source image.

    Parameters
    ----------
    exemplar : branchnb.trees.variations.Exemplar
        A processed exemplar: its ``contour.pins`` live in the working
        image, ``normalized`` holds the crop box, scale and offset that made
        it.

    Returns
    -------
    dict of str to (2,) float64 ndarray
        ``"B"``, ``"R"``, ``"L"`` -> (x, y) in source-image pixels (the
        inverse of :meth:`~branchnb.trees.exemplar.Normalized.to_working`),
        comparable with :func:`load_reference_pins`.

    Examples
    --------
    >>> from branchnb import data
    >>> from branchnb.trees.variations import process_exemplar
    >>> ex = process_exemplar(data.load("plain_tree"), "plain_tree", size=128)
    >>> err = pin_errors(source_pins(ex), load_reference_pins()["plain_tree"], data.load("plain_tree")[..., 3])
    >>> max(err.values()) < 0.05   # every pin within 5 % of the tree height
    True
    """
    nz = exemplar.normalized
    x0, y0 = nz.box[:2]
    out = {}
    p = exemplar.contour.pins
    for k, pt in (("B", p.b), ("R", p.r), ("L", p.l)):
        out[k] = (np.asarray(pt, float) - np.asarray(nz.offset) + 0.5) / nz.scale - 0.5 + (x0, y0)
    return out


def pin_errors(found: dict, reference: dict, alpha) -> dict[str, float]:
    """Distance of each found pin to its reference, over the tree height.

    The height runs from the reference ``B`` up to the top opaque row of
    ``alpha`` (the source image's opacity).

    Parameters
    ----------
    found : dict
        ``"B"``, ``"R"``, ``"L"`` -> (x, y) found automatically, in source
        pixels (e.g. :func:`source_pins`).
    reference : dict
        The same keys placed by hand (an entry of :func:`load_reference_pins`).
    alpha : (H, W) array_like
        Opacity of the source image; pixels >= 0.5 are the tree.

    Returns
    -------
    dict of str to float
        ``"B"``, ``"R"``, ``"L"`` -> Euclidean error over the tree height
        (at least 1 px), so 0.02 means 2 % of the height.

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((110, 50)); a[10:101, 20:30] = 1
    >>> ref = {"B": np.array([25.0, 100.0]), "R": np.array([29.0, 60.0]), "L": np.array([20.0, 60.0])}
    >>> found = {"B": (25.0, 91.0), "R": (29.0, 60.0), "L": (20.0, 60.0)}
    >>> pin_errors(found, ref, a)["B"]
    0.1
    """
    a = np.asarray(alpha) >= 0.5
    top = int(np.flatnonzero(a.any(axis=1))[0])
    height = max(float(reference["B"][1]) - top, 1.0)
    return {k: float(np.hypot(*(np.asarray(found[k]) - reference[k])) / height) for k in ("B", "R", "L")}
