"""Procedural examples with a known answer: drawn maps, river maps, a delta mask, cracks.

Every generator returns the image together with the truth it was drawn
from (the structure, the land or sea), so a result can be measured (see
:mod:`~branchnb.branching.measures`), not only looked at.

- :func:`country_map_example`: flat land and sea colours, black rivers of
  one width as straight polyline pieces, a black coastline; layouts
  ``"island"``, ``"coast"`` and ``"bay"``.
- :func:`river_map_example`: blue tapered river trees on an island.
- :func:`delta_mask_example`: a binary water mask of a braided delta (one
  inland trunk, a cycle, distributaries into a sea).
- :func:`crack_pattern_example`: dark cracks on grey.

Examples
--------
>>> from branchnb.branching.examples import country_map_example
>>> img, truth, land = country_map_example((128, 128), 0)
>>> img.shape, land.dtype
((128, 128, 3), dtype('bool'))
"""

from ._map_examples import (
    coast_mask,
    country_map_example,
    crack_pattern_example,
    delta_mask_example,
    river_map_example,
)

__all__ = ["coast_mask", "country_map_example", "crack_pattern_example", "delta_mask_example",
           "river_map_example"]
