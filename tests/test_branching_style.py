"""Issue 23 (style, mouths, roots) on procedural examples with a known answer: extraction roots a
drawn map's rivers at their mouths; synthesized rivers keep the example's bends per length and
do not curl back just before their outlet."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import extract_structure
from branchnb.branching._map_examples import country_map_example


@pytest.mark.parametrize("size, seed, layout", [(384, 5, "island"), (448, 6, "bay")])
def test_extraction_roots_map_rivers_at_their_mouths(size, seed, layout):
    # before: 1 tree of each of these maps (2 of a 512 px island, seed 7) were rooted at their source
    # (103-158 px inland) and
    # reached the coast with their far end: the lines all have one width (a radius of 0.5 or
    # 0.9 px, quantised) so the thickest-end rule picked a source, or the mouth was no end of the
    # skeleton (a little loop left where the coast's outline was removed)
    img, _truth, land = country_map_example((size, size), seed, layout=layout)
    depth = ndi.distance_transform_edt(land)
    s = extract_structure(img)
    roots = [b for b in s.branches if b.parent is None]
    assert len(roots) >= 4
    for b in roots:
        x, y = np.rint(b.points[0]).astype(int)
        assert depth[y, x] <= 8.0, f"root at ({x}, {y}) is {depth[y, x]:.0f} px inland"
