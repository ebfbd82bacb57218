"""Issue 23, item 2: gap completion on an unevenly lit example gives no square patches of another
brightness (a procedural vignetted texture with a known smooth light)."""

from __future__ import annotations

import numpy as np
import pytest
from scipy import ndimage as ndi

from branchnb.branching import ImageSynthesisParams, synthesize_image
from branchnb.branching._image_examples import random_tree
from branchnb.core.render import coverage_polylines


def _vignetted(n: int, seed: int):
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[0:n, 0:n] / n
    noise = ndi.gaussian_filter(rng.random((n, n)), 1.5)
    noise = (noise - noise.mean()) / noise.std()
    light = 0.25 + 0.6 * np.exp(-((xx - 0.45) ** 2 + (yy - 0.55) ** 2) / 0.12)
    img = np.clip(light * (1 + 0.12 * noise), 0, 1)
    tree = random_tree((n, n), seed + 3, n_children=4, grandchildren=0)
    cov, _ = coverage_polylines((n, n), [b.points for b in tree.branches], [2 * b.thickness for b in tree.branches])
    img = img * (1 - 0.6 * cov)
    return np.dstack([img, 0.8 * img, 0.6 * img]).astype(np.float32), tree


def _patchiness(out, structure, ps: int) -> float:
    """RMS of the background's brightness between the scales ps/4 and 2 ps (patch-sized blotches)."""
    cov, _ = coverage_polylines(out.shape[:2], [b.points for b in structure.branches],
                                [2 * b.thickness + 8 for b in structure.branches])
    w = (cov < 0.01).astype(np.float64)
    g = out[..., :3].mean(-1).astype(np.float64)

    def nb(s):
        return ndi.gaussian_filter(g * w, s) / np.maximum(ndi.gaussian_filter(w, s), 1e-6)

    band = nb(ps / 4) - nb(2 * ps)
    m = (w > 0) & (ndi.gaussian_filter(w, ps / 4) > 0.5)
    return float(np.sqrt(np.mean(band[m] ** 2)))


@pytest.mark.parametrize("seed", [2, 5])
def test_completion_on_a_vignetted_texture_is_not_blocky(seed):
    img, src = _vignetted(192, seed)
    tgt = random_tree((192, 192), seed + 11, n_children=4, grandchildren=0)
    # (no line-contrast floor: it reads the ground around the lines, which the completion changes)
    p = ImageSynthesisParams(patch_size=24, line_contrast=0.0)
    on = synthesize_image(img, src, tgt, p, rng=0)
    off = synthesize_image(img, src, tgt, ImageSynthesisParams(patch_size=24, relight_completion=False,
                                                               line_contrast=0.0), rng=0)
    b_on, b_off = _patchiness(on.image, tgt, 24), _patchiness(off.image, tgt, 24)
    assert b_on < 0.85 * b_off, (b_on, b_off)
    # the fragments (the branches) are left as they were
    frag = on.fragment_mask & off.fragment_mask & ~on.fill_mask & ~off.fill_mask
    assert np.abs(on.image[frag] - off.image[frag]).max() < 1e-4
