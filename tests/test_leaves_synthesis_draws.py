"""Issue 22 synthesis: petioles in the leaf's own direction, stratified exemplar draws, sharp pale veins."""

import numpy as np
import pytest
from leaves_truth import normalised_true_registrations

from branchnb.leaves import leaf_family
from branchnb.leaves._measure_synthesis import laplacian_variance, petiole_angle
from branchnb.leaves.analysis import analyze
from branchnb.leaves.synthesis import _exemplar_draws, generate, generate_leaf


@pytest.fixture(scope="module", params=["lobed", "elliptic"])
def family_analysis(request):
    fam = leaf_family(4, size=192, kind=request.param, rng=3)
    regs = normalised_true_registrations(fam)
    return analyze(fam, 0, {"veins": fam[0].layers["veins"], "spots": fam[0].layers["spots"]},
                   registrations=regs)


@pytest.fixture(scope="module")
def new_leaves(family_analysis):
    return generate(family_analysis, 8, rng=2)


def test_petioles_keep_their_angle_to_the_lamina_and_stay_on_the_canvas(family_analysis, new_leaves):
    """Angle between petiole and lamina axis within the exemplars' largest (+3 degrees).

    Measured (issue 22, 8 leaves, ``_measure_synthesis``): the petiole turned by the local Jacobian of
    the shape map at the base went up to 11 degrees (procedural lobed) and 18-20 degrees (sample
    maples) past the exemplars' largest; turned by the lamina axes, 0-3.3 and 0.
    """
    ex = [v for v in (petiole_angle(b) for b in family_analysis.blades) if v is not None]
    new = [v for v in (petiole_angle(x.blade) for x in new_leaves) if v is not None]
    assert ex and len(new) >= 6
    assert max(new) <= max(ex) + 3.0
    for x in new_leaves:
        al = x.image[..., 3]
        assert max(al[0].max(), al[-1].max(), al[:, 0].max(), al[:, -1].max()) < 0.5


def test_a_batch_runs_through_the_exemplars(family_analysis, new_leaves):
    """Each block of n leaves takes every exemplar once as its lead (pose, shape) and once as its size."""
    n = len(family_analysis.exemplars)
    draws = np.array([_exemplar_draws(x.seed, n) for x in new_leaves])
    for block in (draws[:n], draws[n:2 * n]):
        assert sorted(block[:, 2]) == list(range(n)) and sorted(block[:, 1]) == list(range(n))
    assert np.array_equal(draws[:, 0], draws[:, 2])  # the pose is the lead's
    # Still one leaf per seed, and a shorter batch is the start of a longer one.
    short = generate(family_analysis, 3, rng=2)
    assert [x.seed for x in short] == [x.seed for x in new_leaves[:3]]
    again = generate_leaf(family_analysis, new_leaves[5].seed)
    assert np.array_equal(again.image, new_leaves[5].image)


def test_new_blades_keep_most_of_the_exemplars_detail(family_analysis, new_leaves):
    """Laplacian variance inside the new blades over the exemplars' mean.

    Measured (issue 22): 0.77-0.80 with the layer's contrast clipped to the blade's 0.5-99.5th
    percentiles (pale veins' crests cut), 0.80-0.9 after (target 0.8; one Lanczos resampling at half a
    pixel alone keeps 0.81).
    """
    a = family_analysis
    ex = np.mean([laplacian_variance(e, b) for e, b in zip(a.exemplars, a.blades)])
    new = np.mean([laplacian_variance(x.image, x.blade) for x in new_leaves])
    assert new / ex >= 0.75
