"""Hand-traced vein masks of the sample maples: a ground truth for layer induction on real leaves.

``data/leaves/maple_leaf_veins.json`` holds, for each ``maple_leaf_0k``
sample, the centrelines of its five primary veins (midrib, two laterals,
two basal veins) in the leaf image's own pixels. They were traced by hand
between placed base, waypoint and end points along a ridge filter, and
checked by eye on a 4x render (the file says how). A vein mask is the
centreline grown by ``grow`` pixels (4-neighbours), about 3 px wide, the
width of a main vein in these ~250 px photographs.
"""

from __future__ import annotations

import json
from functools import lru_cache

import numpy as np
from scipy import ndimage as ndi

__all__ = ["reference_veins", "reference_vein_names"]

_FILE = "maple_leaf_veins.json"


@lru_cache(maxsize=1)
def _table() -> dict:
    from ..data import DATA_DIR
    path = DATA_DIR / "leaves" / _FILE
    if not path.is_file():
        raise FileNotFoundError(f"the reference vein file {_FILE} is missing from the sample data")
    return json.loads(path.read_text())


def reference_vein_names() -> list[str]:
    """Sample leaves with a hand-traced vein mask (names for :func:`branchnb.data.load`)."""
    return sorted(_table()["veins"])


def reference_veins(name: str) -> np.ndarray:
    """The hand-traced primary-vein mask of a sample maple, in its own pixels.

    Parameters
    ----------
    name : str
        A sample name from :func:`reference_vein_names` (``"maple_leaf_01"`` ...).

    Returns
    -------
    (H, W) bool ndarray
        Same shape as ``branchnb.data.load(name)``.

    Examples
    --------
    >>> from branchnb import data
    >>> m = reference_veins("maple_leaf_02")
    >>> m.shape == data.load("maple_leaf_02").shape[:2], bool(m.any())
    (True, True)
    """
    from ..data import load
    table = _table()
    if not isinstance(name, str) or name not in table["veins"]:
        raise ValueError(f"name must be one of {reference_vein_names()}, got {name!r:.60}")
    h, w = load(name).shape[:2]
    out = np.zeros((h, w), bool)
    for line in table["veins"][name]:
        p = np.asarray(line, int).reshape(-1, 2)
        out[np.clip(p[:, 1], 0, h - 1), np.clip(p[:, 0], 0, w - 1)] = True
    grow = int(table.get("grow", 1))
    if grow > 0:
        out = ndi.binary_dilation(out, iterations=grow)
    return out
