"""The analysis's per-exemplar work in threads (:mod:`branchnb.core.threads`): the same results."""

import base64
import zlib

import numpy as np
import pytest
from leaves_threads_reference import REFERENCE

from branchnb.core.metrics import iou
from branchnb.core.threads import thread_count, thread_map
from branchnb.leaves import Layer, LayerSet, analyze, leaf_family, simulate_scribbles

CASES = (("lobed", 160, 3), ("elliptic", 192, 4))


def _case(kind, size, seed):
    fam = leaf_family(3, size=size, kind=kind, rng=seed)
    ls = LayerSet([Layer("veins", "#d62728", 0,
                         simulate_scribbles(fam[0].layers["veins"], 10, length=0.06 * size, rng=0)),
                   Layer("spots", "#1f77b4", 1,
                         simulate_scribbles(fam[0].layers["spots"], 10, length=0.025 * size, rng=0))])
    return fam, ls


def _reference(kind, layer, e):
    shape, text = REFERENCE[(kind, layer, e)]
    bits = np.frombuffer(zlib.decompress(base64.b64decode("".join(text) if not isinstance(text, str) else text)),
                         np.uint8)
    return np.unpackbits(bits)[:shape[0] * shape[1]].reshape(shape).astype(bool)


def test_thread_map_keeps_order_and_raises_the_first_error():
    assert thread_map(lambda x: x * x, range(7), threads=3) == [x * x for x in range(7)]
    assert thread_map(lambda x: x + 1, [4], threads=4) == [5]

    def boom(x):
        if x in (2, 5):
            raise KeyError(x)
        return x
    with pytest.raises(KeyError, match="2"):
        thread_map(boom, range(8), threads=4)
    with pytest.raises(ValueError, match="threads"):
        thread_map(abs, [1], threads=0)
    with pytest.raises(TypeError, match="fn"):
        thread_map(3, [1])


def test_thread_map_runs_blas_on_one_thread_and_restores_it():
    threadpoolctl = pytest.importorskip("threadpoolctl")

    def blas():
        return [i["num_threads"] for i in threadpoolctl.threadpool_info() if i["user_api"] == "blas"]
    before = blas()
    inside = thread_map(lambda _: blas(), range(3), threads=2)
    assert blas() == before
    assert all(n == 1 for x in inside for n in x)


def test_thread_count_follows_the_environment(monkeypatch):
    monkeypatch.setenv("BRANCHNB_THREADS", "1")
    assert thread_count(8) == 1
    monkeypatch.setenv("BRANCHNB_THREADS", "many")
    with pytest.raises(ValueError, match="BRANCHNB_THREADS"):
        thread_count(8)
    monkeypatch.delenv("BRANCHNB_THREADS")
    assert 1 <= thread_count(8) <= 8 and thread_count(1) == 1


@pytest.mark.parametrize("kind,size,seed", CASES)
def test_threaded_analysis_keeps_mains_masks(kind, size, seed):
    # Pinned against main's masks before the threads (IoU >= 0.98 per layer, pooled over the exemplars).
    fam, ls = _case(kind, size, seed)
    a = analyze(fam, 0, ls)
    for x in a.layers:
        inter = union = 0
        for e, m in enumerate(x.masks):
            ref = _reference(kind, x.name, e)
            assert m.shape == ref.shape
            inter += int((m & ref).sum())
            union += int((m | ref).sum())
            if ref.sum() >= 200:
                assert iou(m, ref) >= 0.95, (kind, x.name, e)
        assert inter / max(union, 1) >= 0.98, (kind, x.name, inter / max(union, 1))


def test_one_thread_and_several_give_the_same_analysis(monkeypatch):
    fam, ls = _case("lobed", 128, 7)
    monkeypatch.setenv("BRANCHNB_THREADS", "1")
    one = analyze(fam, 0, ls)
    monkeypatch.setenv("BRANCHNB_THREADS", "4")
    many = analyze(fam, 0, ls)
    for x, y in zip(one.layers, many.layers):
        for m1, m2 in zip(x.masks, y.masks):
            assert np.array_equal(m1, m2), x.name
    for r1, r2 in zip(one.residuals[-1], many.residuals[-1]):
        assert float(np.abs(r1 - r2).max()) == 0.0
    for r1, r2 in zip(one.registrations[1:], many.registrations[1:]):
        assert float(np.abs(r1.map_to_training - r2.map_to_training).max()) == 0.0


def test_closed_blade_is_remembered_per_blade_and_never_shared():
    from branchnb.core.distance import edt
    from branchnb.leaves import analysis_outline as ao
    b = leaf_family(1, size=200, rng=2)[0].blade
    b2 = b.copy()
    b2[60:64, 60:120] = False  # a gap between paint strokes, closed by _closed_of
    for m in (b, b2, b):
        closed = ao._closed_blade(m)
        assert np.array_equal(closed, ao._closed_of(m))
        assert np.array_equal(ao._closed_distance(m), edt(ao._closed_of(m)))
        closed[:] = False  # the caller's copy: the next call is not changed
    assert ao._closed_blade(b).sum() == ao._closed_of(b).sum() > 0
