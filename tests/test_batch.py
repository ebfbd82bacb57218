"""branchnb.batch on a real Dask LocalCluster: reproducible items, resume, failures, valid files."""

from __future__ import annotations

import hashlib
import json
import os
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import cv2
import numpy as np
import pytest

distributed = pytest.importorskip("distributed")

from branchnb import data  # noqa: E402
from branchnb.batch import (  # noqa: E402
    BatchSpec,
    ItemOutput,
    Job,
    load_spec,
    read_manifest,
    register_job,
    run_batch,
    save_spec,
    spec_from_params,
)
from branchnb.core.io import imread, imsave  # noqa: E402
from branchnb.trees import VariationParams  # noqa: E402


def _quiet_cluster(n):
    import logging

    return distributed.LocalCluster(n_workers=n, threads_per_worker=1, processes=True, host="127.0.0.1",
                                    dashboard_address="127.0.0.1:0", silence_logs=logging.ERROR)


@pytest.fixture(scope="module")
def client2():
    with _quiet_cluster(2) as cluster, distributed.Client(cluster) as client:
        yield client


@pytest.fixture(scope="module")
def library_dir(tmp_path_factory):
    """Three small RGBA exemplars in a folder (the 'library folder' input)."""
    folder = tmp_path_factory.mktemp("library")
    for name in ("tree_rpg_01", "tree_rpg_03", "tree_rpg_06"):
        img = data.load(name)
        h, w = img.shape[:2]
        s = 110 / max(h, w)
        imsave(folder / f"{name}.png", cv2.resize(img, (round(w * s), round(h * s)), interpolation=cv2.INTER_AREA))
    return folder


def _tree_spec(library_dir, count=20, **extra) -> BatchSpec:
    return BatchSpec("tree_variations", count=count, seed=11,
                     inputs={"library": str(library_dir), "size": 96, "trunk": "stem"}, **extra)


def _digests(folder: Path, pattern: str) -> dict[str, str]:
    return {p.name: hashlib.sha256(p.read_bytes()).hexdigest() for p in sorted(folder.glob(pattern))}


def _valid_png(path: Path) -> None:
    img = imread(path)
    assert img.ndim == 3 and np.isfinite(img).all()


@pytest.fixture(scope="module")
def twenty(tmp_path_factory, library_dir, client2):
    """20 tree variations on 2 workers (chunks of 3, so several tasks finish in any order)."""
    out = tmp_path_factory.mktemp("two_workers")
    summary = run_batch(_tree_spec(library_dir), out, client=client2, chunk=3, progress=None)
    return out, summary


def test_two_workers_give_the_same_files_as_one(twenty, library_dir, tmp_path):
    out2, s2 = twenty
    assert (s2.done, s2.failed, s2.skipped, s2.workers) == (20, 0, 0, 2)
    s1 = run_batch(_tree_spec(library_dir), tmp_path, n_workers=1, chunk=7, progress=None)
    assert (s1.done, s1.workers) == (20, 1)
    d1, d2 = _digests(tmp_path, "tree_*.png"), _digests(out2, "tree_*.png")
    assert len(d1) == 20 and d1 == d2                      # byte-identical PNGs
    assert len(set(d1.values())) == 20                     # and 20 different trees
    for p in list(tmp_path.glob("tree_*.png"))[:3]:
        _valid_png(p)
    m = read_manifest(out2)
    assert sorted(m) == list(range(20))
    assert {r["status"] for r in m.values()} == {"done"}
    seeds = [m[i]["seed"] for i in range(20)]
    expected = [int(c.generate_state(1, np.uint64)[0] >> np.uint64(1))
                for c in np.random.SeedSequence(11).spawn(20)]
    assert seeds == expected                               # SeedSequence.spawn of the spec seed
    r = m[4]
    assert r["files"][0]["name"] == "tree_00004.png" and r["params"]["variation"]["m_points"] == 20
    assert abs(sum(r["info"]["weights"]) - 1) < 1e-5 and r["time"] > 0 and r["error"] is None


def test_resume_recomputes_exactly_the_deleted_items(twenty, library_dir, client2):
    out, _ = twenty
    before = _digests(out, "tree_*.png")
    mtimes = {p.name: p.stat().st_mtime_ns for p in out.glob("tree_*.png")}
    deleted = ["tree_00002.png", "tree_00005.png", "tree_00011.png", "tree_00017.png", "tree_00019.png"]
    for name in deleted:
        (out / name).unlink()
    seen = []
    s = run_batch(_tree_spec(library_dir), out, client=client2, progress=lambda done, total: seen.append(done))
    assert (s.done, s.skipped, s.failed) == (5, 15, 0)
    assert len(seen) == 5 and seen == sorted(seen) and seen[-1] == 20   # computed items only, resumed counted
    assert _digests(out, "tree_*.png") == before
    changed = {p.name for p in out.glob("tree_*.png") if p.stat().st_mtime_ns != mtimes.get(p.name)}
    assert changed == set(deleted)
    # a damaged file is recomputed too, and so is an item whose parameters changed
    (out / "tree_00003.png").write_bytes(b"\x89PNG\r\n\x1a\nbroken")
    s = run_batch(_tree_spec(library_dir), out, client=client2, progress=None)
    assert (s.done, s.skipped) == (1, 19)
    assert _digests(out, "tree_*.png") == before
    lines = (out / "manifest.jsonl").read_text().splitlines()
    assert len(lines) == 20                                # compacted: one record per item
    changed = _tree_spec(library_dir, items={"7": {"variation.m_points": 24}})
    s = run_batch(changed, out, client=client2, progress=None)
    assert (s.done, s.skipped) == (1, 19)
    assert read_manifest(out)[7]["params"]["variation"]["m_points"] == 24


def test_invalid_item_fails_clearly_and_the_rest_finish(library_dir, client2, tmp_path):
    spec = _tree_spec(library_dir, count=6, items={"2": {"variation.m_points": 3},
                                                    "4": {"target": "no_such_tree"}})
    s = run_batch(spec, tmp_path, client=client2, progress=None)
    assert (s.done, s.failed) == (4, 2)
    m = read_manifest(tmp_path)
    assert m[2]["status"] == "failed" and m[2]["files"] == []
    assert "m_points must be >= 6" in m[2]["error"] and m[2]["error"].startswith("ValueError")
    assert m[4]["status"] == "failed" and "no_such_tree" in m[4]["error"]
    assert sorted(p.name for p in tmp_path.glob("*.png")) == [f"tree_{i:05d}.png" for i in (0, 1, 3, 5)]
    assert "4 done" in str(s) and "2 failed" in str(s) and "items/s" in str(s)


def test_a_job_registered_in_a_few_lines_runs_on_the_cluster(client2, tmp_path):
    from dataclasses import dataclass

    from branchnb.core.io import encode_png
    from branchnb.core.params import param

    @dataclass
    class NoiseParams:
        level: float = param(0.5, min=0.0, max=1.0)

    def make(shared, params, inputs, rng, stem):
        img = np.full((8, 8, 3), params["noise"].level, np.float32) * rng.random((8, 8, 1), np.float32)
        if params["noise"].level > 0.9:
            raise RuntimeError("too loud")
        return ItemOutput({f"{stem}.png": encode_png(img)}, {"mean": float(img.mean())})

    register_job(Job("noise_test", sections={"noise": NoiseParams}, inputs={}, stem="noise",
                     prepare=lambda inputs, base_dir, params: None, make=make), replace=True)
    spec = BatchSpec("noise_test", count=9, vary={"noise.level": [0.2, 0.5, 0.95]})
    s = run_batch(spec, tmp_path, client=client2, progress=None)
    assert (s.done, s.failed) == (6, 3)
    m = read_manifest(tmp_path)
    assert [m[i]["params"]["noise"]["level"] for i in range(3)] == [0.2, 0.5, 0.95]
    assert m[5]["error"] == "RuntimeError: too loud"


def test_cloud_dendrite_and_branching_jobs_write_valid_files(client2, library_dir, tmp_path):
    from branchnb.core.structure import Branch, Structure

    cloud = BatchSpec("billboard_cloud", count=2, inputs={"library": str(library_dir), "from_variations": False},
                      params={"billboard": {"n_segments": 32, "n_interior": 8, "max_size": 128}})
    s = run_batch(cloud, tmp_path / "cloud", client=client2, progress=None)
    assert s.done == 2, read_manifest(tmp_path / "cloud")
    doc = json.loads((tmp_path / "cloud" / "cloud_00001.gltf").read_text(),
                     parse_constant=lambda c: pytest.fail(f"non-standard JSON {c}"))
    assert doc["asset"]["version"] == "2.0" and doc["images"][0]["uri"] == "cloud_00001_atlas.png"
    _valid_png(tmp_path / "cloud" / "cloud_00001_atlas.png")

    den = BatchSpec("dendrite_tree", count=2, inputs={"shape": [72, 64]},
                    params={"tree": {"iterations": 2, "radius": 12}})
    assert run_batch(den, tmp_path / "den", client=client2, progress=None).done == 2
    root = ET.parse(tmp_path / "den" / "dendrite_00000.svg").getroot()
    assert root.tag.endswith("svg") and len(list(root.iter())) > 10
    _valid_png(tmp_path / "den" / "dendrite_00000.png")

    t = np.linspace(0, 1, 60)
    trunk = np.c_[10 + 140 * t, 50 + 10 * np.sin(9 * t)]
    twig = np.c_[80 + 30 * t, trunk[34, 1] + 30 * t]
    twig[0] = trunk[34]
    ex = Structure([Branch(trunk, 2.5), Branch(twig, 1.5, parent=0, parent_vertex=34)], image_shape=(100, 160))
    (tmp_path / "example.json").write_text(ex.to_json())
    spec = BatchSpec.from_dict({"job": "branching", "count": 2, "inputs": {"example": "example.json"}},
                               base_dir=tmp_path)
    s = run_batch(spec, tmp_path / "br", client=client2, progress=None)
    assert s.done == 2, read_manifest(tmp_path / "br")
    st = Structure.from_json((tmp_path / "br" / "branching_00000.json").read_text())
    assert st.n_vertices > 10
    ET.parse(tmp_path / "br" / "branching_00000.svg")


def test_specs_round_trip_and_bad_specs_name_the_problem(tmp_path, library_dir):
    spec = spec_from_params("tree_variations", VariationParams(keep=0.7, n_mix=2), count=50, seed=3,
                            library=str(library_dir), size=96, target="tree_rpg_03",
                            vary={"variation.keep": [0.6, 0.8]})
    for suffix in (".json", ".toml"):
        path = save_spec(spec, tmp_path / f"spec{suffix}")
        again = load_spec(path)
        assert again.to_dict() == spec.to_dict()
        assert again.item_params(1)["variation"].keep == 0.8
    assert spec_from_params("tree_variations", VariationParams(keep=0.7), count=1,
                            only_changed=True).params == {"variation": {"keep": 0.7}}
    bad = [
        ({"job": "nope", "count": 1}, "unknown job 'nope'"),
        ({"job": "tree_variations", "count": 0}, "count must lie in"),
        ({"job": "tree_variations", "count": 2, "params": {"variation": {"kep": 1}}}, "unknown field(s) ['kep']"),
        ({"job": "tree_variations", "count": 2, "params": {"variation": {"keep": 2.0}}}, "keep must be <= 1"),
        ({"job": "tree_variations", "count": 2, "inputs": {"libary": "x"}}, "unknown input(s) ['libary']"),
        ({"job": "tree_variations", "count": 2, "vary": {"size": [1, 2]}}, "not an item input"),
        ({"job": "tree_variations", "count": 2, "items": {"5": {}}}, "outside 0 .. 1"),
        ({"job": "tree_variations"}, "needs a 'count'"),
    ]
    for d, message in bad:
        with pytest.raises((ValueError, TypeError)) as exc:
            BatchSpec.from_dict(d)
        assert message in str(exc.value), (d, str(exc.value))
    (tmp_path / "nan.json").write_text('{"job": "dendrite_tree", "count": 2, "params": {"tree": {"noise": NaN}}}')
    with pytest.raises(ValueError, match="nan.json is not valid JSON: non-standard JSON number NaN"):
        load_spec(tmp_path / "nan.json")
    (tmp_path / "broken.toml").write_text("job = \n")
    with pytest.raises(ValueError, match="not valid TOML"):
        load_spec(tmp_path / "broken.toml")


def test_command_line_batch_on_a_scheduler_and_ctrl_c_keeps_the_manifest(client2, tmp_path):
    spec = tmp_path / "spec.toml"
    spec.write_text('job = "dendrite_tree"\ncount = 400\nseed = 5\n\n[inputs]\nshape = [40, 36]\nsvg = false\n\n'
                    '[params.tree]\niterations = 2\nradius = 8.0\n')
    out = tmp_path / "out"
    cmd = [sys.executable, "-m", "branchnb.cli", "batch", str(spec), str(out), "--no-progress", "--chunk", "1",
           "--scheduler", client2.scheduler.address]
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    manifest = out / "manifest.jsonl"
    deadline = time.time() + 60
    while time.time() < deadline and (not manifest.is_file() or len(manifest.read_text().splitlines()) < 3):
        time.sleep(0.1)
    proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=60)
    assert proc.returncode == 130, stderr
    assert "interrupted" in stdout and "Traceback" not in stderr
    records = read_manifest(out)
    assert 3 <= len(records) < 400
    for r in records.values():                             # every recorded item is intact
        assert r["status"] == "done"
        for f in r["files"]:
            assert hashlib.sha256((out / f["name"]).read_bytes()).hexdigest() == f["sha256"]
    assert not list(out.glob(".*.part"))
    # resuming with a smaller count finishes the batch without recomputing the recorded items
    count = len(records) + 2
    kept = sum(1 for i in records if i < count)
    run = subprocess.run(cmd[:-2] + ["--count", str(count), "--scheduler", client2.scheduler.address],
                         capture_output=True, text=True, timeout=120)
    assert run.returncode == 0, run.stderr
    assert f"{count - kept} done, {kept} already complete, 0 failed of {count}" in run.stdout
    assert "start-up" in run.stdout and "s per item" in run.stdout and "on 2 workers" in run.stdout
    bad = subprocess.run([sys.executable, "-m", "branchnb.cli", "batch", str(tmp_path / "missing.json"),
                          str(tmp_path / "o2")], capture_output=True, text=True, timeout=60)
    assert bad.returncode == 1 and "Traceback" not in bad.stderr and "missing.json" in bad.stderr
    assert os.path.isdir(tmp_path / "o2")


def _json_values():
    from hypothesis import strategies as st

    scalars = st.one_of(st.none(), st.booleans(), st.integers(-10**6, 10**12),
                        st.floats(allow_nan=True, allow_infinity=True), st.text(max_size=8))
    return st.recursive(scalars, lambda inner: st.one_of(st.lists(inner, max_size=3),
                                                         st.dictionaries(st.text(max_size=6), inner, max_size=3)),
                        max_leaves=8)


def test_any_malformed_spec_gives_a_clear_error():
    from hypothesis import given, settings
    from hypothesis import strategies as st

    keys = st.sampled_from(["job", "count", "seed", "inputs", "params", "vary", "items", "other"])
    jobs = st.sampled_from(["tree_variations", "billboard_cloud", "dendrite_tree", "branching", "x"])
    sections = st.dictionaries(st.sampled_from(["variation", "tree", "billboard", "synthesis", "image", "zz"]),
                               st.dictionaries(st.sampled_from(["keep", "m_points", "iterations", "radius",
                                                                "n_segments", "h", "nope"]), _json_values(),
                                               max_size=3), max_size=2)

    @settings(max_examples=80, deadline=None)
    @given(st.dictionaries(keys, _json_values(), max_size=5), jobs, st.one_of(st.integers(-3, 30), _json_values()),
           sections)
    def check(d, job, count, params):
        d = dict(d, job=job, count=count)
        if params:
            d["params"] = params
        try:
            spec = BatchSpec.from_dict(d)
        except (ValueError, TypeError) as exc:
            assert str(exc)
            return
        for i in range(min(spec.count, 3)):               # items: valid, or a clear per-item error
            try:
                spec.item_params(i)
            except (ValueError, TypeError) as exc:
                assert f"item {i}" in str(exc)

    check()


def test_leaf_variations_job(client2, tmp_path):
    """Runs once branchnb.leaves (layered synthesis) is in the tree."""
    pytest.importorskip("branchnb.leaves.synthesis")
    from branchnb.leaves import leaf_family

    fam = leaf_family(3, size=160, rng=1)
    (tmp_path / "ex").mkdir()
    for i, leaf in enumerate(fam):
        imsave(tmp_path / "ex" / f"leaf_{i}.png", leaf.image)
    for k in ("veins", "spots"):
        imsave(tmp_path / f"{k}.png", np.repeat(fam[0].layers[k][..., None].astype(np.float32), 3, 2))
    spec = BatchSpec.from_dict({"job": "leaf_variations", "count": 3, "seed": 2,
                                "inputs": {"exemplars": "ex", "layers": {"veins": "veins.png", "spots": "spots.png"}}},
                               base_dir=tmp_path)
    s = run_batch(spec, tmp_path / "out", client=client2, progress=None)
    assert s.done == 3, read_manifest(tmp_path / "out")
    leaves = [imread(p) for p in sorted((tmp_path / "out").glob("leaf_*.png"))]
    assert all(im.shape[2] == 4 and (im[..., 3] > 0.5).mean() > 0.1 for im in leaves)
    assert len({hashlib.sha256(p.read_bytes()).hexdigest() for p in (tmp_path / "out").glob("leaf_*.png")}) == 3


# ----------------------------------------------------------------------------- issue 27: batch edge cases

ROOT = Path(__file__).resolve().parent.parent
_SAMPLES = ["tree_rpg_01", "tree_rpg_03", "tree_rpg_06"]


def _env():
    return dict(os.environ, PYTHONPATH=str(ROOT) + os.pathsep + os.environ.get("PYTHONPATH", ""))


def _cli(*args):
    return [sys.executable, "-m", "branchnb.cli", "batch", *map(str, args)]


def test_a_batch_survives_the_loss_of_its_only_worker(tmp_path):
    import logging
    import threading

    with distributed.LocalCluster(n_workers=1, threads_per_worker=1, processes=True, host="127.0.0.1",
                                  dashboard_address="127.0.0.1:0", silence_logs=logging.CRITICAL) as cluster, \
            distributed.Client(cluster) as client:
        spec = BatchSpec("tree_variations", count=16, seed=3, inputs={"library": _SAMPLES, "size": 64, "trunk": "stem"})
        result = {}
        thread = threading.Thread(target=lambda: result.setdefault(
            "s", run_batch(spec, tmp_path, client=client, chunk=2, progress=None)))
        thread.start()
        manifest = tmp_path / "manifest.jsonl"
        deadline = time.time() + 120
        while time.time() < deadline and (not manifest.is_file() or len(manifest.read_text().splitlines()) < 2):
            time.sleep(0.05)
        for pid in client.run(os.getpid).values():         # the only worker, holding the scattered library
            os.kill(pid, signal.SIGKILL)
        thread.join(300)
    s = result["s"]
    assert (s.done, s.failed) == (16, 0), read_manifest(tmp_path)
    assert any("sent again" in n for n in s.notes)
    assert {r["status"] for r in read_manifest(tmp_path).values()} == {"done"}


def _first_item_then_ctrl_c_twice(count: int, scheduler: str, tmp_path: Path):
    """Run a ``count``-item spec of a trivial job; at its first recorded item: seconds, client RSS (MB); then
    Ctrl-C, and a second one during the shutdown. Returns ``(seconds, rss, returncode, stdout, stderr)``."""
    import psutil

    spec = tmp_path / f"big{count}.json"
    spec.write_text(json.dumps({"job": "dendrite_tree", "count": count, "seed": 1,
                                "inputs": {"shape": [32, 32], "svg": False},
                                "params": {"tree": {"iterations": 1, "radius": 6}}}))
    out = tmp_path / f"out{count}"
    t0 = time.time()
    proc = subprocess.Popen(_cli(spec, out, "--scheduler", scheduler), env=_env(),
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
    manifest = out / "manifest.jsonl"
    while time.time() - t0 < 120 and not (manifest.is_file() and manifest.read_text().count("\n") >= 3):
        time.sleep(0.05)
    first = time.time() - t0
    rss = psutil.Process(proc.pid).memory_info().rss / 2**20
    proc.send_signal(signal.SIGINT)
    time.sleep(0.3)
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)                    # a second Ctrl-C during the shutdown
    stdout, stderr = proc.communicate(timeout=120)
    return first, rss, proc.returncode, stdout, stderr


def test_ten_million_items_start_at_once_and_ctrl_c_twice_is_clean(client2, tmp_path):
    results = {n: _first_item_then_ctrl_c_twice(n, client2.scheduler.address, tmp_path) for n in (1000, 10_000_000)}
    for n, (first, _rss, code, stdout, stderr) in results.items():
        assert first < 60, f"{n} items: no item after {first:.0f} s"   # was: 25 s of set-up per 200k items
        assert code == 130 and "Traceback" not in stderr, stderr
        assert "interrupted" in stdout and f"of {n}" in stdout
        assert stderr.startswith("branchnb batch: reading")  # output from the first second
        assert "connecting to the Dask scheduler" in stderr
    # bounded client memory: 10^7 items cost what 10^3 cost (measured 193 MB both; before: 540 MB per 200k items)
    assert results[10_000_000][1] - results[1000][1] < 60, {n: r[1] for n, r in results.items()}
    assert results[10_000_000][1] < 600


def test_ctrl_c_while_the_cluster_starts_is_clean(tmp_path):
    spec = tmp_path / "s.json"
    spec.write_text(json.dumps({"job": "dendrite_tree", "count": 4, "inputs": {"shape": [32, 32]}}))
    proc = subprocess.Popen(_cli(spec, tmp_path / "out", "--workers", "1"), env=_env(), stdout=subprocess.PIPE,
                            stderr=subprocess.PIPE, text=True)
    line = ""
    while "starting a local Dask cluster" not in line:
        line = proc.stderr.readline()
        assert line, proc.communicate()
    proc.send_signal(signal.SIGINT)
    time.sleep(0.2)
    if proc.poll() is None:
        proc.send_signal(signal.SIGINT)
    stdout, stderr = proc.communicate(timeout=120)
    assert proc.returncode == 130 and "Traceback" not in stderr, stderr
    assert "interrupted" in stdout


def test_specs_are_parsed_strictly(tmp_path):
    (tmp_path / "dup.json").write_text('{"job": "dendrite_tree", "count": 2, "count": 999999}')
    with pytest.raises(ValueError, match="duplicate key 'count'"):
        load_spec(tmp_path / "dup.json")
    (tmp_path / "dup.toml").write_text('job = "dendrite_tree"\ncount = 2\ncount = 999999\n')
    with pytest.raises(ValueError, match="not valid TOML"):
        load_spec(tmp_path / "dup.toml")
    deep = '{"job": "dendrite_tree", "count": 2, "inputs": {"shape": ' + "[" * 3000 + "]" * 3000 + "}}"
    (tmp_path / "deep.json").write_text(deep)
    with pytest.raises(ValueError, match="nests deeper than 64"):
        load_spec(tmp_path / "deep.json")
    (tmp_path / "deep.toml").write_text('job = "dendrite_tree"\ncount = 2\n[inputs]\nshape = '
                                        + "[" * 3000 + "]" * 3000 + "\n")
    with pytest.raises(ValueError, match="deep"):
        load_spec(tmp_path / "deep.toml")
    nested: list = []
    for _ in range(3000):
        nested = [nested]
    with pytest.raises(ValueError, match="nests deeper"):
        BatchSpec("dendrite_tree", count=2, inputs={"shape": nested})
    unused = [
        ({"job": "billboard_cloud", "count": 2, "inputs": {"image": 1}}, "inputs.image is not used"),
        ({"job": "billboard_cloud", "count": 2, "vary": {"image": [0, 1]}}, "inputs.image is not used"),
        ({"job": "billboard_cloud", "count": 2, "inputs": {"from_variations": False, "target": "tree_rpg_01"}},
         "inputs.target is not used"),
        ({"job": "billboard_cloud", "count": 2, "inputs": {"from_variations": False},
          "params": {"variation": {"keep": 0.5}}}, "params.variation is not used"),
        ({"job": "tree_variations", "count": 2, "inputs": {"target": "tree_rpg_01", "weights": [0.5, 0.5]}},
         "inputs.weights is not used"),
        ({"job": "branching", "count": 2, "inputs": {"example": "x.json", "render_image": False}},
         "inputs.render_image is not used"),
    ]
    for d, message in unused:
        with pytest.raises(ValueError, match=message):
            BatchSpec.from_dict(d)
    BatchSpec.from_dict({"job": "billboard_cloud", "count": 2, "inputs": {"image": 1, "from_variations": False}})


def test_manifest_problems_are_reported_and_the_folder_is_locked(client2, tmp_path):
    from branchnb.batch._guards import OutdirBusyError, OutdirLock

    spec = BatchSpec("dendrite_tree", count=4, inputs={"shape": [32, 32], "svg": False},
                     params={"tree": {"iterations": 1, "radius": 6}})
    (tmp_path / "a" / "manifest.jsonl").mkdir(parents=True)
    with pytest.raises(ValueError, match="manifest.jsonl is a folder"):
        run_batch(spec, tmp_path / "a", client=client2, progress=None)
    run = subprocess.run(_cli(tmp_path / "none.json", tmp_path / "a"), capture_output=True, text=True, env=_env())
    assert run.returncode == 1 and "Traceback" not in run.stderr
    out = tmp_path / "b"
    assert run_batch(spec, out, client=client2, progress=None).done == 4
    lines = (out / "manifest.jsonl").read_bytes().splitlines()
    lines[2] = lines[2].replace(b'"status"', b'"st\xffatus"')     # one byte that is not UTF-8, in item 2's line
    (out / "manifest.jsonl").write_bytes(b"\n".join(lines) + b"\n")
    s = run_batch(spec, out, client=client2, progress=None)
    assert (s.done, s.skipped) == (1, 3)
    assert any("manifest.jsonl line 3: not UTF-8" in n and "item 2 is recomputed" in n for n in s.notes)
    assert sorted(read_manifest(out)) == [0, 1, 2, 3]
    with OutdirLock(out):                                  # another run holds the folder
        with pytest.raises(OutdirBusyError, match="in use by another branchnb batch .*process"):
            run_batch(spec, out, client=client2, progress=None)
    assert run_batch(spec, out, client=client2, progress=None).skipped == 4


def test_a_hostile_image_fails_clearly_through_the_command_line(tmp_path):
    from test_validation import _png_declaring

    lib = tmp_path / "lib"
    lib.mkdir()
    imsave(lib / "a.png", data.load("tree_rpg_01"))       # decoded first if the headers were not checked first
    (lib / "b.png").write_bytes(_png_declaring(30000, 30000, valid=False))
    spec = tmp_path / "s.json"
    spec.write_text(json.dumps({"job": "tree_variations", "count": 5, "inputs": {"library": "lib", "size": 64}}))
    run = subprocess.run(["/usr/bin/time", "-f", "%M", *_cli(spec, tmp_path / "out", "--workers", "1")],
                         capture_output=True, text=True, env=_env(), timeout=300)
    assert run.returncode == 1 and "Traceback" not in run.stderr, run.stderr
    assert "b.png: it declares 30000 x 30000" in run.stderr and "no item was run" in run.stderr
    assert "starting a local Dask cluster" not in run.stderr       # refused before any cluster starts
    # the manifest says why, once for the run (not 5 identical failed items), and holds no item
    [line] = (tmp_path / "out" / "manifest.jsonl").read_text().splitlines()
    rec = json.loads(line)
    assert rec["run"] == "failed" and rec["items_not_run"] == 5 and "b.png: it declares 30000 x 30000" in rec["error"]
    assert read_manifest(tmp_path / "out") == {}
    # the refusal costs < 200 MB over the imports it needs (decoding was 4.6 GB); the imports alone are
    # 170-280 MB depending on the environment, so they are measured in the same environment
    imports = subprocess.run(["/usr/bin/time", "-f", "%M", sys.executable, "-c",
                              "import branchnb.cli, branchnb.batch, branchnb.trees, branchnb.core.io"],
                             capture_output=True, text=True, env=_env(), timeout=300)
    baseline = int(imports.stderr.strip().splitlines()[-1])
    assert int(run.stderr.strip().splitlines()[-1]) - baseline < 200_000


def test_a_hostile_library_image_costs_little_memory_and_the_next_run_forgets_it(client2, tmp_path):
    from test_validation import _png_declaring

    from branchnb.batch.manifest import Manifest

    lib = tmp_path / "lib"
    lib.mkdir()
    imsave(lib / "a.png", cv2.resize(data.load("tree_rpg_01"), (60, 73), interpolation=cv2.INTER_AREA))
    imsave(lib / "c.png", cv2.resize(data.load("tree_rpg_03"), (60, 73), interpolation=cv2.INTER_AREA))
    (lib / "b.png").write_bytes(_png_declaring(50000, 50000, valid=False))   # OpenCV alone raised cv2.error
    code = f"""
import resource
from branchnb.batch import BatchSpec, run_batch
spec = BatchSpec("tree_variations", count=3, inputs={{"library": {str(lib)!r}, "size": 64}})
before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss
try:
    run_batch(spec, {str(tmp_path / "m")!r}, n_workers=1, progress=None)
except ValueError as exc:
    print(exc)
print((resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024)
"""
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, env=_env(), timeout=300)
    assert run.returncode == 0 and "Traceback" not in run.stderr, run.stderr
    message, peak = run.stdout.strip().splitlines()
    assert "b.png: it declares 50000 x 50000 = 2,500,000,000 pixels" in message
    assert float(peak) < 200, peak                         # MB for the refusal, on top of the imports
    spec = BatchSpec("tree_variations", count=3, inputs={"library": str(lib), "size": 64, "trunk": "stem"})
    with pytest.raises(ValueError, match=r"inputs.library: refusing to decode .*b.png.*no item was run"):
        run_batch(spec, tmp_path / "out", client=client2, progress=None)
    assert "b.png" in Manifest(tmp_path / "out").run_failure["error"]
    (lib / "b.png").unlink()                               # fixed: the next run makes every item
    s = run_batch(spec, tmp_path / "out", client=client2, progress=None)
    assert (s.done, s.failed) == (3, 0)
    lines = [json.loads(x) for x in (tmp_path / "out" / "manifest.jsonl").read_text().splitlines()]
    assert [r.get("item") for r in lines] == [0, 1, 2] and Manifest(tmp_path / "out").run_failure is None


def test_no_listener_of_a_local_batch_binds_a_public_address(tmp_path):
    code = r"""
import json, sys, threading, time, psutil
from branchnb.batch import BatchSpec, run_batch
if __name__ == "__main__":
    spec = BatchSpec("dendrite_tree", count=6, inputs={"shape": [48, 48], "svg": False},
                     params={"tree": {"iterations": 2, "radius": 8}})
    for dashboard in (False, True):
        seen, done = set(), []
        t = threading.Thread(target=lambda: done.append(run_batch(spec, sys.argv[1] + str(dashboard),
                             n_workers=2, chunk=1, progress=None, dashboard=dashboard)))
        t.start()
        while t.is_alive():
            me = psutil.Process()
            for p in [me] + me.children(recursive=True):
                try:
                    seen |= {c.laddr.ip for c in p.net_connections("inet") if c.status == psutil.CONN_LISTEN}
                except psutil.Error:
                    pass
            time.sleep(0.1)
        print(json.dumps([dashboard, sorted(seen), done[0].done]))
"""
    script = tmp_path / "listen.py"
    script.write_text(code)
    run = subprocess.run([sys.executable, str(script), str(tmp_path / "out")], capture_output=True, text=True,
                         env=_env(), timeout=300)
    assert run.returncode == 0, run.stderr
    results = [json.loads(line) for line in run.stdout.splitlines()]
    assert [r[0] for r in results] == [False, True]
    for dashboard, ips, done in results:
        assert done == 6 and ips and set(ips) <= {"127.0.0.1", "::1"}, (dashboard, ips)


def test_the_readme_batch_example_runs_as_written(client2, tmp_path):
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    section = readme[readme.index("## At scale"):]
    block = section[section.index("```json") + 7:]
    (tmp_path / "trees.json").write_text(block[:block.index("```")])
    commands = section[section.index("```bash"):]
    assert "branchnb batch trees.json out/" in commands
    assert all(name in data.names() for name in _SAMPLES) and "sample name" in section
    run = subprocess.run(_cli("trees.json", "out/", "--count", "3", "--scheduler", client2.scheduler.address),
                         capture_output=True, text=True, env=_env(), cwd=tmp_path, timeout=300)
    assert run.returncode == 0, run.stderr
    assert "3 done, 0 already complete, 0 failed of 3" in run.stdout
    m = read_manifest(tmp_path / "out")
    assert [m[i]["params"]["variation"]["keep"] for i in range(3)] == [0.4, 0.6, 0.8]
    assert all(imread(tmp_path / "out" / f"tree_{i:05d}.png").shape[2] == 4 for i in range(3))
    again = subprocess.run(_cli("trees.json", "out/", "--count", "3", "--scheduler", client2.scheduler.address),
                           capture_output=True, text=True, env=_env(), cwd=tmp_path, timeout=300)
    assert "0 done, 3 already complete" in again.stdout and "nothing computed" in again.stdout
    assert "workers" not in again.stdout and again.stderr.count("%|") == 0   # no bar when nothing is computed


def test_chunks_adapt_to_the_item_time_and_shrink_at_the_end():
    from branchnb.batch.runner import _ChunkSizer

    left = [1000]
    sizer = _ChunkSizer(None, 2, lambda: left[0])
    assert sizer() == 1                                    # nothing measured yet: one item per task
    for _ in range(4):
        sizer.observe(0.05)
    assert sizer() == 4                                    # ~0.2 s of work per task
    sizer.observe(1e-6)
    for _ in range(100):
        sizer.observe(0.0)
    assert sizer() == 16                                   # cheap items: at most 16 per task
    left[0] = 40
    assert sizer() == 5                                    # 4 chunks per worker left at most
    left[0] = 7
    assert sizer() == 1                                    # the tail: one item per task, no idle worker
    assert _ChunkSizer(3, 2, lambda: 0)() == 3             # a given chunk is kept
