"""edit_structure in two stages: fetch_patches (kept by apps) and compose_patches (seam-only changes)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from branchnb.strokes import (
    FETCH_FIELDS,
    EditPatches,
    StrokeEditParams,
    compose_patches,
    edit_structure,
    fetch_patches,
)


def _bar(opaque: bool = False):
    h, w = 60, 160
    img = np.zeros((h, w, 4), np.float32)
    x = np.arange(10, w - 10)
    img[22:38, 10:w - 10, 0] = 0.5 + 0.4 * np.sin(x / 4.0)
    img[22:38, 10:w - 10, 1] = np.linspace(0.2, 0.8, len(x))[None, :] + np.linspace(0, 0.15, 16)[:, None]
    img[22:38, 10:w - 10, 2] = 0.3
    img[22:38, 10:w - 10, 3] = 1.0
    if opaque:
        img[..., 3] = 1.0
        img[img[..., 0] == 0, :3] = (0.9, 0.85, 0.8)
    return img


SRC = np.array([(14, 30), (80, 30), (146, 30)], float)
TRUNK = np.array([(10, 60), (80, 62), (150, 60)], float)
BRANCH = np.array([(80, 62), (110, 30), (130, 8)], float)


@pytest.fixture(scope="module")
def staged():
    img = _bar()
    kw = dict(target_shape=(90, 160), control_points=[(np.array([(80, 30)]), np.array([(80, 62)])), None])
    return img, kw, fetch_patches(img, [SRC, SRC], [TRUNK, BRANCH], **kw)


@pytest.mark.parametrize("change", [
    {}, {"seam_power": 2.5}, {"gradient_weighted": False}, {"shift_penalty": 1.0},
    {"sampling": "greedy"}, {"composition": "overlay"}, {"energy_stride": 1},
])
def test_second_stage_equals_the_whole_edit(staged, change):
    img, kw, patches = staged
    p = dataclasses.replace(StrokeEditParams(), **change)
    assert patches.reusable_for(p)
    got = compose_patches(patches, p)
    want = edit_structure(img, [SRC, SRC], [TRUNK, BRANCH], p, **kw)
    assert len(got.junctions) == 1
    for name in ("image", "mask", "seams", "labels", "layer", "source_region"):
        assert np.array_equal(getattr(got, name), getattr(want, name)), name
    assert got.energies == want.energies and got.params == p


def test_seam_power_changes_the_result_and_the_patches_stay_as_fetched(staged):
    _, _, patches = staged
    a = compose_patches(patches)
    b = compose_patches(patches, StrokeEditParams(seam_power=4.0))
    assert not np.array_equal(a.labels, b.labels)
    again = compose_patches(patches)  # composing does not change the fetched patches
    assert np.array_equal(again.image, a.image) and again.energies == a.energies


def test_fetch_parameters_need_a_new_fetch(staged):
    _, _, patches = staged
    for f in FETCH_FIELDS:
        v = getattr(StrokeEditParams(), f)
        if isinstance(v, str):
            new = next(o for o in StrokeEditParams.__dataclass_fields__[f].metadata["options"] if o != v)
        else:
            new = (not v) if isinstance(v, bool) else v + 2
        p = dataclasses.replace(StrokeEditParams(), **{f: new})
        assert not patches.reusable_for(p), f
        with pytest.raises(ValueError, match=f):
            compose_patches(patches, p)
    assert not patches.reusable_for(StrokeEditParams(sampling="none"))  # one candidate per sample


def test_opaque_source_with_a_background_colour():
    img = _bar(opaque=True)
    p = StrokeEditParams(seam_power=2.0)
    patches = fetch_patches(img, [SRC], [TRUNK], target_shape=(90, 160), background=(0.1, 0.2, 0.3))
    got = compose_patches(patches, p)
    want = edit_structure(img, [SRC], [TRUNK], p, target_shape=(90, 160), background=(0.1, 0.2, 0.3))
    assert np.array_equal(got.image, want.image)
    assert np.allclose(got.image[2, 2], (0.1, 0.2, 0.3, 1.0))


def test_bad_arguments():
    with pytest.raises(TypeError, match="patches must be EditPatches"):
        compose_patches("not patches")
    img = _bar()
    with pytest.raises(TypeError, match="params"):
        fetch_patches(img, [SRC], [TRUNK], params="fast")
    with pytest.raises(ValueError, match="zero length"):
        fetch_patches(img, [[(50, 30), (50, 30)]], [TRUNK])
    patches = fetch_patches(img, [SRC], [SRC])
    assert isinstance(patches, EditPatches) and patches.n_candidates > len(patches.pairs)
    with pytest.raises(TypeError, match="params"):
        compose_patches(patches, params=3)
