"""fit_model(progress=...): a cancel reaches the fit while the furcation SVM runs (issue 23)."""

import threading

import numpy as np
import pytest

from branchnb.branching import fit_model
from branchnb.branching import model as model_mod
from branchnb.core.structure import Branch, Structure


class Cancelled(Exception):
    pass


def _example() -> Structure:
    t = np.linspace(0, 6, 200)
    trunk = Branch(np.c_[20 * t, 10 * np.sin(t)] + 50, 2.0)
    side = Branch(np.c_[60 + 10 * t, 55 + 8 * t], 1.0, parent=0, parent_vertex=60)
    return Structure([trunk, side], image_shape=(200, 200))


def test_cancel_during_the_svm_stops_the_fit_before_the_svm_returns(monkeypatch):
    release, returned = threading.Event(), threading.Event()
    real = model_mod.FurcationModel.fit

    def slow_fit(*args, **kwargs):  # an SVM of seconds on a big example
        release.wait(5.0)
        out = real(*args, **kwargs)
        returned.set()
        return out

    monkeypatch.setattr(model_mod.FurcationModel, "fit", slow_fit)
    seen = []

    def progress(fraction, text):
        seen.append((fraction, text))
        if sum("SVM" in t for _f, t in seen) >= 3:
            raise Cancelled

    try:
        with pytest.raises(Cancelled):
            fit_model(_example(), progress=progress)
        assert not returned.is_set()  # stopped while the SVM was still running
        svm = [f for f, t in seen if "SVM" in t]
        assert len(svm) == 3 and all(0.1 <= f < 0.8 for f in svm) and np.all(np.diff(svm) > 0)
    finally:
        release.set()


def test_fit_with_progress_equals_the_fit_without():
    ex = _example()
    seen = []
    a = fit_model(ex, progress=lambda f, t: seen.append(t))
    b = fit_model(ex)
    assert seen[0] == "bending model" and seen[-1] == "fitted"
    # equal up to floating-point reduction order (BLAS threads may split sums differently under load)
    np.testing.assert_allclose(a.furcation.probabilities(ex.branches[0].points, ex.branches[0].thickness),
                               b.furcation.probabilities(ex.branches[0].points, ex.branches[0].thickness),
                               rtol=1e-9, atol=1e-12)


def test_an_error_in_the_svm_reaches_the_caller(monkeypatch):
    def broken(*args, **kwargs):
        raise RuntimeError("svm broke")

    monkeypatch.setattr(model_mod.FurcationModel, "fit", broken)
    with pytest.raises(RuntimeError, match="svm broke"):
        fit_model(_example(), progress=lambda f, t: None)
