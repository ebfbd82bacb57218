"""The iterative and pareidolia trees, exported from ``branchnb.dendrite``, check their inputs at
the door (issue 25, dendrite44): the fuzz sweep found 64 bad inputs ending in deep errors and 3
hangs (``grow_layers(layers=10**9)``)."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

import branchnb.dendrite as dd
from branchnb.dendrite import (
    PareidoliaParams,
    TreeParams,
    grow_layers,
    grow_tree,
    pareidolia_tree,
    render_layers,
    render_tree,
)

SMALL = TreeParams(iterations=2, radius=10)


def test_exported_at_package_level():
    for name in ("pareidolia_tree", "PareidoliaParams", "PareidoliaTree", "grow_tree", "grow_layers",
                 "render_tree", "render_layers", "GrownTree", "TreeParams"):
        assert name in dd.__all__ and hasattr(dd, name)


@pytest.mark.parametrize("shape", [(), (24,), None, 5, "bogus", (np.nan, 28), (np.inf, 28), ("a", "a"),
                                   (1e9, 1e9), (9000, 9000), (4, 40), (0, 30)])
def test_bad_shapes_name_the_shape(shape):
    for fn in (grow_tree, grow_layers):
        with pytest.raises((TypeError, ValueError), match="shape"):
            fn(shape, SMALL, rng=0)


def test_huge_canvas_gets_the_limit_in_the_message():
    with pytest.raises(ValueError, match=str(dd.trees.MAX_TREE_PIXELS)):
        grow_tree((9000, 9000), SMALL, rng=0)


@pytest.mark.parametrize("layers", [0, -1, 10**9, 2**63, 10**5000, 1.5, np.nan, "3", None],
                         ids=["0", "-1", "1e9", "2**63", "5000 digits", "1.5", "nan", "str", "None"])
def test_bad_layer_counts_are_refused_without_a_hang(layers):
    with pytest.raises((TypeError, ValueError), match="layers"):
        grow_layers((40, 32), SMALL, layers=layers, rng=0)


@pytest.mark.parametrize("base", [np.nan, -1, "bogus", np.ones((3, 2)) * 1j, np.full((4, 4), np.nan),
                                  (np.inf, 3.0), (100.0, 5.0)])
def test_bad_bases_name_the_base(base):
    with pytest.raises((TypeError, ValueError), match="base"):
        grow_tree((40, 32), SMALL, base=base, rng=0)
    with pytest.raises((TypeError, ValueError), match="base"):
        grow_layers((40, 32), SMALL, base=base, rng=0)


def test_a_base_tree_must_fit_the_canvas_and_the_iteration():
    t = grow_tree((40, 32), SMALL, rng=0)
    with pytest.raises(ValueError, match="base"):
        grow_tree((48, 32), SMALL, base=t, start_iteration=2, rng=0)
    with pytest.raises(ValueError, match="start_iteration"):
        grow_tree((40, 32), SMALL, base=t, start_iteration=1, rng=0)
    for bad in (0, 9, 1.5, "2", None):
        with pytest.raises((TypeError, ValueError), match="start_iteration"):
            grow_tree((40, 32), SMALL, start_iteration=bad, rng=0)
    # a continued tree still grows: its later iteration adds nodes to the same trunk
    big = TreeParams(iterations=3, radius=60)
    two = grow_tree((120, 100), dataclasses.replace(big, iterations=2), rng=0)
    more = grow_tree((120, 100), big, base=two, start_iteration=3, rng=1)
    assert more.dendrite.n_nodes > two.dendrite.n_nodes and int(more.dendrite.iteration.max()) == 3


def test_weights_must_be_a_callable_giving_clean_weights():
    with pytest.raises(TypeError, match="weights"):
        grow_tree((40, 32), SMALL, weights=np.ones((40, 32)), rng=0)
    for bad in (np.full((40, 32), np.nan), -np.ones((40, 32)), np.ones((40, 31)), np.ones((40, 32)) * 1j):
        with pytest.raises((TypeError, ValueError), match="weights"):
            grow_tree((40, 32), SMALL, weights=lambda i, r, bad=bad: bad, rng=0)


def test_endpoint_counts_at_the_fields_limits_stay_bounded():
    # 100 x 10 ** 7 endpoints in the last iteration: capped at the canvas's pixels, no memory blow-up
    p = TreeParams(iterations=8, trunk_endpoints=100, endpoint_growth=10.0, radius=10)
    t = grow_tree((24, 20), p, rng=0)
    assert t.dendrite.is_tree() and all(len(e) <= 24 * 20 for e in t.endpoints)


def test_render_functions_check_their_inputs():
    ts = grow_layers((40, 32), SMALL, layers=2, rng=0)
    other = grow_tree((48, 32), SMALL, rng=0)
    with pytest.raises(ValueError, match="trees"):
        render_layers([ts[0], other])
    with pytest.raises(ValueError, match="trees"):
        render_layers([])
    for bad in ("bogus", 5, [1, 2], None):
        with pytest.raises(TypeError, match="trees"):
            render_layers(bad)
    with pytest.raises(ValueError, match="background"):
        render_layers(ts, background=np.ones((10, 10, 3)))
    with pytest.raises((TypeError, ValueError), match="near"):
        render_layers(ts, near=(2.0, 0.0, 0.0))
    with pytest.raises((TypeError, ValueError), match="smooth"):
        render_tree(ts[0].dendrite, smooth=-1)
    with pytest.raises((TypeError, ValueError), match="color"):
        render_tree(ts[0].dendrite, color="bogus")
    with pytest.raises(TypeError, match="dendrite"):
        render_tree(ts[0])
    # the valid calls draw ink on white
    img = render_layers(ts).image
    assert img.shape == (40, 32, 3) and img.min() < 0.9 and np.isfinite(img).all()
    one = render_layers(ts[1]).image
    assert np.allclose(one, render_layers([ts[1]]).image)


def test_pareidolia_tree_checks_its_inputs():
    p = PareidoliaParams(n_endpoints=40, iterations=2, lattice_size=0)
    img = np.ones((40, 40))
    img[10:30, 10:30] = 0.0
    for bad in (np.ones((8, 8)), "bogus", np.full((40, 40), np.nan), np.ones((40, 40)) * 1j):
        with pytest.raises((TypeError, ValueError), match="image"):
            pareidolia_tree(bad, p, rng=0)
    with pytest.raises((TypeError, ValueError), match="n_endpoints"):
        pareidolia_tree(img, PareidoliaParams(n_endpoints=-5), rng=0)
    with pytest.raises((TypeError, ValueError), match="rng"):
        pareidolia_tree(img, p, rng="seed")
    t = pareidolia_tree(img, p, rng=0)
    assert t.dendrite.is_tree() and t.image.shape[:2] == t.dendrite.shape
