"""Issue 23: a 256 px terrain map keeps its coast (as at 512 and 1000 px). Its white lowlands have
the colour of the white outside and its rivers lie mostly in a grey relief level, so the branch
region by colour is that level, with no line along it: the coast is read along the example's
domain instead (measured: coast share 0.12 -> 1.00 on seed 0)."""

from __future__ import annotations

import numpy as np
import pytest

from branchnb.branching import example_domain, extract_structure, fit_model, synthesize_image, synthesize_structure
from branchnb.branching._map_examples import terrain_map_example
from branchnb.branching.measures import boundary_drawn_share


@pytest.mark.parametrize("size,seed", [(256, 0), (256, 1)])
def test_small_terrain_maps_keep_their_coast(size, seed):
    img, _s, _riv = terrain_map_example((size, size), seed)
    ex = extract_structure(img)
    dom = example_domain(img, ex)
    res = synthesize_structure(fit_model(ex, domain=dom), rng=0)
    out = synthesize_image(img, ex, res, rng=0)
    ink, ground = np.array([0.13, 0.13, 0.15]), np.ones(3)
    assert boundary_drawn_share(img, dom, ink, ground) >= 0.9
    assert boundary_drawn_share(out.image, res.domain, ink, ground) >= 0.9
