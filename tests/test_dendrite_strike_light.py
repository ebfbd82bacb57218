"""Issue 25, dendrites: a lightning strike is a light source. The zelkova leaf photo at
200 px was taken for a lightning photo (its midrib a bright zigzag whose 0.85-px jag the
straight-edge test cannot resolve); so was the white ground between a horse
silhouette's tail and leg."""

import numpy as np
import pytest
from skimage.transform import resize

from branchnb import data
from branchnb.branching._storm_examples import storm_example
from branchnb.core import as_gray
from branchnb.dendrite.photo_strike import strike_origin
from branchnb.dendrite.scale import resample_to_lattice
from branchnb.dendrite.stylization import Stylizer


def _fit(img, n):
    s = n / max(img.shape[:2])
    shape = (round(img.shape[0] * s), round(img.shape[1] * s)) + img.shape[2:]
    return np.clip(resize(img, shape, anti_aliasing=True), 0, 1).astype(np.float32)


def _lum(img):
    # on the 512 lattice these rules were measured on (a picture under ~215 px is planned on a
    # smaller one since dendrite45: the 200-px zelkova's on 480, where even without the rank
    # rule its vein is no strike)
    return as_gray(resample_to_lattice(Stylizer(img).image, 512))


def test_a_leaf_vein_is_no_strike():
    # measured (before -> after): false strikes on 12 photos x 200-800 px and a skyline
    # 4 -> 0 (zelkova 200 px; skimage's horse 200/240/320 px); the piece's median
    # luminance is above 0.34 of the picture (the paper around the leaf is brighter)
    lum = _lum(_fit(data.load("zelkova_leaf"), 200))
    assert strike_origin(lum, min_rank=0.0) is not None  # the rule off: a strike
    assert strike_origin(lum) is None
    import skimage.data as skdata

    horse = _lum(_fit(np.asarray(skdata.horse(), np.float32), 240))
    assert strike_origin(horse) is None
    with pytest.raises(ValueError, match="min_rank"):
        strike_origin(lum, min_rank=1.5)


@pytest.mark.parametrize("n_bolts,seed", [(1, 3), (3, 0)])
def test_bolts_under_a_lit_cloud_keep_their_strike(n_bolts, seed):
    # the lowest-ranked bolts of the 35-picture lightning set (0.93-0.96: a lit cloud
    # brighter than the bolt covers much of the picture) keep their strike and origin
    img = storm_example((200, 260), seed, n_bolts=n_bolts)[0]
    lum = _lum(img)
    assert strike_origin(lum) == strike_origin(lum, min_rank=0.0) is not None
