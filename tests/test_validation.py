"""Regression tests of issue 13, one group per class of failure the fuzzing found.

1 process crashes, 2 endless loops and runaway sizes, 3 validation holes,
4 invalid files, 6 JSON import, 7 reproducibility; plus the core validation
helpers every door goes through. The crash-prone calls run in a subprocess
(or the fuzz worker) and the test checks its exit code.
"""

from __future__ import annotations

import dataclasses
import json
import os
import shutil
import signal
import subprocess
import sys
import time
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np
import pytest

sys.path.insert(0, str(Path(__file__).resolve().parent))
import fuzzkit  # noqa: E402

from branchnb.core import (  # noqa: E402
    Branch,
    Structure,
    as_float_image,
    compose_overlap,
    composite_over,
    coverage_polylines,
    draw_polylines,
    polylines_to_svg,
    psnr,
    seam_cut,
    stipple,
)
from branchnb.core.jsonio import MAX_JSON_DEPTH, dumps_strict, loads_strict  # noqa: E402
from branchnb.core.params import check_params  # noqa: E402
from branchnb.core.random import as_seed  # noqa: E402
from branchnb.core.validate import (  # noqa: E402
    COORD_LIMIT,
    as_colour,
    check_int,
    check_real,
    checked,
    real_array,
)

ROOT = Path(__file__).resolve().parent.parent


def _python(code: str, timeout: float = 120) -> subprocess.CompletedProcess:
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    return subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=timeout,
                          env=env, cwd=str(ROOT))


@pytest.fixture(scope="module")
def pool():
    p = fuzzkit.Pool(30.0)
    yield p
    p.close()


def _run(pool, target, arg, value, kind="regression"):
    return pool.run(fuzzkit.Case(target, arg, kind, value))


# ----------------------------------------------------------------------- 1. process crashes
def test_rasteriser_survives_far_coordinates_even_past_validation():
    """The numba rasteriser clamps before converting to int: no segfault (rc 139) on 1e20."""
    code = """
import numpy as np
from branchnb.core.render import _rasterise, coverage_polylines
try:
    coverage_polylines((9, 3), [[(0, 5), (0, 1e20)]])
except ValueError as e:
    assert "polylines[0]" in str(e), e
else:
    raise SystemExit("no error")
cov = np.zeros((9, 3), np.float32); idx = np.full((9, 3), -1, np.int64)
segs = np.array([[0.0, 5.0, 1.0, 0.0, 1e20, 1.0], [-1e300, -1e300, 2.0, 1e300, 1e300, 2.0]])
_rasterise(segs, np.zeros(2, np.int64), 9, 3, cov, idx)
assert np.isfinite(cov).all() and cov.max() <= 1
print("ok")
"""
    r = _python(code)
    assert r.returncode == 0 and "ok" in r.stdout, (r.returncode, r.stderr[-2000:])


def test_loaded_far_structure_is_rejected_and_display_survives():
    text = json.dumps({"branches": [{"points": [[0, 5], [0, 1e20]], "thickness": [1, 1]}]})
    with pytest.raises(ValueError, match=r"points.*beyond"):
        Structure.from_json(text)
    code = """
from branchnb.core import Branch, Structure
s = Structure([Branch([(0.0, 5.0), (0.0, 10.0)], 1.0)])
s.branches[0].points[1, 1] = 1e20      # mutated after construction
assert s._repr_png_() is None          # the notebook falls back to the text repr
try:
    s.render()
except ValueError as e:
    assert "branches[0].points" in str(e), e
print("ok")
"""
    r = _python(code)
    assert r.returncode == 0 and "ok" in r.stdout, (r.returncode, r.stderr[-2000:])


def test_interrupting_stipple_never_crashes_the_process():
    """Jupyter's "interrupt kernel" is a SIGINT: five interrupts at random moments, five clean exits."""
    code = """
import sys, numpy as np
from branchnb.core import stipple
d = np.random.default_rng(0).random((160, 160)) + 0.1
print("ready", flush=True)
try:
    while True:
        stipple(d, 800, iterations=30, rng=0)
except KeyboardInterrupt:
    print("interrupted", flush=True)
    sys.exit(3)
"""
    rng = np.random.default_rng(1)
    env = dict(os.environ, PYTHONPATH=str(ROOT))
    for _ in range(5):
        p = subprocess.Popen([sys.executable, "-c", code], stdout=subprocess.PIPE, stderr=subprocess.PIPE,
                             text=True, env=env)
        assert p.stdout.readline().strip() == "ready"
        time.sleep(float(rng.uniform(0.2, 1.0)))
        p.send_signal(signal.SIGINT)
        out, err = p.communicate(timeout=60)
        assert p.returncode == 3 and "interrupted" in out, (p.returncode, err[-2000:])


# ------------------------------------------------------------- 2. endless loops and runaway sizes
@pytest.mark.parametrize("target", ["core:seam_cut", "core:compose_overlap", "core:seam_cost"])
def test_nan_power_raises_instead_of_hanging(pool, target):
    o = _run(pool, target, "power", float("nan"))
    assert o.status == "raised" and "power" in o.detail, o.detail


def test_nan_power_direct():
    a = np.zeros((4, 4, 3))
    with pytest.raises(ValueError, match="power"):
        seam_cut(a, a, np.ones((4, 4), bool), np.zeros((4, 4), bool), np.zeros((4, 4), bool), power=np.nan)
    with pytest.raises(ValueError, match="power"):
        compose_overlap(a, np.ones((4, 4), bool), a, np.ones((4, 4), bool), power=float("nan"))


def test_parent_cycle_made_after_construction_raises(pool):
    from branchnb.branching import extend_branch

    s = fuzzkit._cyclic_structure()
    with pytest.raises(ValueError, match="cycle"):
        extend_branch(s, 1, fuzzkit._structure(), n_steps=2, rng=0)
    with pytest.raises(ValueError, match="cycle"):
        s.generation(1)
    o = _run(pool, "branching:extend_branch", "structure", fuzzkit._Cyclic())
    assert o.status == "raised", o.detail


@pytest.mark.parametrize("target,arg,value", [
    ("trees:tree_variations", "n", 10**6),
    ("trees:morph_sequence", "steps", 10**9),
    ("core:stipple", "iterations", 10**9),
    ("core:stipple", "n_points", 10**9),
    ("dendrite:render_vines", "leaf_spacing", 1e-9),
    ("dendrite:render_plain", "smooth", 10**9),
    ("core:resample_uniform", "h", 1e-12),
    ("strokes:candidate_offsets", "step", 1e-9),
    ("trees:fill_contour", "shape", (10**9, 10**9)),
    ("core:coverage_polylines", "shape", (10**6, 10**6)),
])
def test_size_guards_raise_quickly(pool, target, arg, value):
    o = _run(pool, target, arg, value)
    assert o.status == "raised" and arg in o.detail and o.seconds < 20, o.detail


@pytest.mark.parametrize("params_cls,field,value", [
    ("ClickParams", "sigma", 1e6), ("ClickParams", "smooth", 10**9),
    ("SynthesisParams", "max_generations", 10**9),
])
def test_size_fields_of_parameter_dataclasses_are_bounded(params_cls, field, value):
    import branchnb.branching as br

    p = getattr(br, params_cls)()
    object.__setattr__(p, field, value)
    with pytest.raises(ValueError, match=rf"params\.{field} must be <="):
        check_params(p)


# ------------------------------------------------------------------------- 3. validation holes
def test_check_params_types_none_nan_and_normalisation():
    from branchnb.branching import SynthesisParams
    from branchnb.dendrite import StylizeParams

    with pytest.raises(TypeError, match=r"params\.svm_C must be a real number"):
        check_params(SynthesisParams(svm_C="1"))
    with pytest.raises(TypeError, match=r"params\.max_coverage must not be None"):
        check_params(SynthesisParams(max_coverage=None))
    with pytest.raises(ValueError, match=r"params\.epsilon must be a finite number"):
        check_params(StylizeParams(epsilon=float("nan")))
    with pytest.raises(TypeError, match=r"params\.k must be an int"):
        check_params(SynthesisParams(k=2.5))
    p = check_params(SynthesisParams(k=12.0))
    assert type(p.k) is int and p.k == 12


def test_parameter_dataclasses_are_checked_at_every_stage():
    """A method that takes the params (a pipeline stage) checks them too, naming the field."""
    from branchnb.dendrite import StylizeParams

    st = fuzzkit._stylizer()
    with pytest.raises(TypeError, match="cost_weight"):
        st.lattice(StylizeParams(cost_weight="x"), 0)


@pytest.mark.parametrize("call", [
    lambda: as_float_image(np.ones((4, 4), complex)),
    lambda: draw_polylines(np.ones((8, 8, 3)), [np.array([(1, 1), (5, 5)], complex)]),
    lambda: psnr(np.ones((4, 4), complex), np.ones((4, 4))),
    lambda: stipple(np.ones((8, 8), complex), 4, rng=0),
])
def test_complex_arrays_are_rejected(call):
    with pytest.raises(TypeError, match="real-valued"):
        call()


def test_empty_tree_library_says_so():
    from branchnb.trees import TreeLibrary, make_variation, tree_variations

    with pytest.raises(ValueError, match="library is empty"):
        make_variation(TreeLibrary(size=64), rng=0)
    with pytest.raises(ValueError, match="library is empty"):
        tree_variations(TreeLibrary(size=64), 0, rng=0)


@pytest.mark.parametrize("background,match", [
    ((2.0, 0.0, 0.0), r"background components must lie in \[0, 1\]"),
    ((np.nan, 0.0, 0.0), "background contains NaN"),
    ((1.0, 0.0), "3 components"),
    ("white", "background must be an RGB triple"),
])
def test_composite_over_checks_its_colour(background, match):
    with pytest.raises((ValueError, TypeError), match=match):
        composite_over(np.ones((3, 3, 4)), background)


def test_psnr_validates_and_stays_finite_for_huge_values():
    with pytest.raises(ValueError, match="a contains NaN"):
        psnr(np.full((4, 4), np.nan), np.zeros((4, 4)))
    with pytest.raises(ValueError, match="data_range"):
        psnr(np.zeros((4, 4)), np.ones((4, 4)), data_range=0)
    with pytest.raises(ValueError, match="same shape"):
        psnr(np.zeros((4, 4)), np.zeros((4, 5)))
    assert psnr(np.zeros((4, 4)), np.full((4, 4), 0.1)) == pytest.approx(20.0)
    big = psnr(np.zeros((4, 4)), np.full((4, 4), 1e200), data_range=1e200)
    assert big == pytest.approx(0.0, abs=1e-9)
    assert np.isfinite(psnr(np.zeros((4, 4)), np.full((4, 4), 0.1), data_range=1e-300))


# --------------------------------------------------------------------------- 4. invalid files
@pytest.fixture(scope="module")
def cloud():
    return fuzzkit._cloud()


@pytest.mark.parametrize("writer,suffix", [("export_obj", ".obj"), ("export_gltf", ".gltf")])
@pytest.mark.parametrize("kw", [{"yaw": float("nan")}, {"height": float("inf")}, {"height": 0.0}])
def test_exports_refuse_non_finite_frames_and_write_nothing(cloud, tmp_path, writer, suffix, kw):
    import branchnb.trees as trees

    out = tmp_path / f"tree{suffix}"
    with pytest.raises(ValueError, match=next(iter(kw))):
        getattr(trees, writer)(cloud, out, **kw)
    assert not out.exists()


def _gltf_validator():
    """The Khronos glTF validator (npm ``gltf-validator``) in a cache folder, or None without node/npm."""
    node, npm = shutil.which("node"), shutil.which("npm")
    if node is None:
        return None
    cache = Path(os.environ.get("XDG_CACHE_HOME", Path.home() / ".cache")) / "branchnb-tests" / "gltf-validator"
    module = cache / "node_modules" / "gltf-validator"
    if not module.is_dir() and npm is not None:
        cache.mkdir(parents=True, exist_ok=True)
        subprocess.run([npm, "install", "--no-audit", "--no-fund", "--prefix", str(cache), "gltf-validator"],
                       capture_output=True, timeout=300)
    return module if module.is_dir() else None


_VALIDATE_JS = r"""
const fs = require("fs"), path = require("path");
const validator = require(process.argv[2]);
const file = process.argv[3];
validator.validateBytes(new Uint8Array(fs.readFileSync(file)), {
  uri: path.basename(file),
  externalResourceFunction: (uri) => new Promise((resolve, reject) => {
    try { resolve(new Uint8Array(fs.readFileSync(path.join(path.dirname(file), decodeURIComponent(uri))))); }
    catch (e) { reject(e.toString()); }
  }),
}).then((r) => console.log(JSON.stringify(r.issues))).catch((e) => { console.error(e); process.exit(2); });
"""


@pytest.mark.parametrize("embed,crossed", [(False, False), (True, True)])
def test_exported_gltf_passes_the_khronos_validator(cloud, tmp_path, embed, crossed):
    from branchnb.trees import export_gltf

    module = _gltf_validator()
    if module is None:
        pytest.skip("node or the npm package gltf-validator is not available")
    out = export_gltf(cloud, tmp_path / "tree.gltf", embed_texture=embed, crossed=crossed, yaw=33.0)
    loads_strict(out.read_text())  # strict JSON first
    js = tmp_path / "validate.js"
    js.write_text(_VALIDATE_JS)
    r = subprocess.run(["node", str(js), str(module), str(out)], capture_output=True, text=True, timeout=120)
    assert r.returncode == 0, r.stderr[-2000:]
    issues = json.loads(r.stdout)
    assert issues["numErrors"] == 0, [m for m in issues["messages"] if m["severity"] == 0]
    assert issues["numWarnings"] == 0, [m for m in issues["messages"] if m["severity"] == 1]


def test_obj_export_has_only_finite_numbers(cloud, tmp_path):
    from branchnb.trees import export_obj

    out = export_obj(cloud, tmp_path / "tree.obj", yaw=123.0, crossed=True)
    nums = [float(t) for line in out.read_text().splitlines() if line[:2] in ("v ", "vt")
            for t in line.split()[1:]]
    assert nums and np.all(np.isfinite(nums))


@pytest.mark.parametrize("kw,match", [
    ({"widths": float("nan")}, "widths"),
    ({"widths": [[1.0, np.inf]]}, "widths"),
    ({"colors": (1.5, 0, 0)}, "colors"),
    ({"colors": "red"}, "colors"),
    ({"colors": (np.nan, 0, 0)}, "colors"),
    ({"background": (0, 0)}, "background"),
    ({"size": (np.nan, 10)}, r"size\[0\]"),
    ({"size": (10, 0)}, r"size\[1\]"),
])
def test_svg_writer_refuses_what_would_be_invalid(kw, match):
    args = dict(widths=1.0, size=(20, 10))
    args.update(kw)
    with pytest.raises((ValueError, TypeError), match=match):
        polylines_to_svg([[(0, 0), (10, 5)]], **args)


def test_svg_output_parses_with_finite_numbers():
    svg = polylines_to_svg([[(0, 0), (10, 5), (12, 9)], [(3, 3)]], widths=[[1, 2, 3], 2.0],
                           colors=[(0.1, 0.2, 0.3), (1, 1, 1)], size=(20.5, 10), background=(1, 1, 1))
    root = ET.fromstring(svg)
    values = [v for el in root.iter() for k, v in el.attrib.items() if k not in ("xmlns", "stroke", "fill",
                                                                              "stroke-linecap", "stroke-linejoin")]
    nums = [float(t) for v in values for t in v.replace(",", " ").split()]
    assert nums and np.all(np.isfinite(nums))


def test_strict_json_everywhere():
    with pytest.raises(ValueError, match=r"meta\['x'\]\[1\] is nan"):
        dumps_strict({"x": [1.0, float("nan")]}, name="meta")
    s = Structure([Branch([(0, 0), (10, 0)], 2.0)])
    s.branches[0].thickness[1] = np.inf  # mutated after construction
    with pytest.raises(ValueError, match="JSON has no NaN or infinity"):
        s.to_json()
    assert dumps_strict({"a": np.float32(0.5), "b": np.arange(2)}) == '{"a": 0.5, "b": [0, 1]}'


# ---------------------------------------------------------------------------- 6. JSON import
_GOOD = {"version": 1, "image_shape": [20, 30],
         "branches": [{"points": [[1, 2], [10, 4], [18, 9]], "thickness": [2, 1.5, 1], "parent": None,
                       "parent_vertex": None}]}


def _with(**branch):
    d = json.loads(json.dumps(_GOOD))
    d["branches"][0].update(branch)
    return d


@pytest.mark.parametrize("text,exc,match", [
    ('{"branches": [{"points": [[0, 1e400], [1, 1]], "thickness": [1, 1]}]}', ValueError, "floating-point range"),
    ("[" * 5000 + "]" * 5000, ValueError, "nests deeper"),
    ('{"branches": [{"points": [[0, NaN], [1, 1]], "thickness": [1, 1]}]}', ValueError, "non-standard JSON"),
    (json.dumps(_with(thickness=None) | {}).replace(', "thickness": null', ""), ValueError, "lacks 'thickness'"),
    (json.dumps({**_GOOD, "version": 7}), ValueError, r"\['version'\] = 7 is not supported"),
    (json.dumps(_with(points=[["1", "2"], ["3", "4"], ["5", "6"]])), TypeError, r"\['points'\] must be an array"),
    (json.dumps(_with(points="1,2;3,4")), TypeError, r"\['points'\]"),
    (json.dumps(_with(parent="0", parent_vertex=0)), TypeError, r"\['parent'\] must be an int"),
    (json.dumps(_with(extra=1)), ValueError, "unknown field"),
    (json.dumps({**_GOOD, "image_shape": [0, 5]}), ValueError, r"image_shape'\]\[0\] must be >= 1"),
    (b"\xff\xfe", ValueError, "not valid JSON"),
    (3, TypeError, "text must be a JSON string"),
])
def test_structure_json_import_rejects_bad_files(text, exc, match):
    with pytest.raises(exc, match=match):
        Structure.from_json(text)


def test_structure_json_round_trip_is_versioned_and_strict():
    s = Structure.from_json(json.dumps(_GOOD))
    d = json.loads(s.to_json())
    assert d["version"] == 1 and Structure.from_json(s.to_json()).to_dict() == s.to_dict()
    assert MAX_JSON_DEPTH >= 8


# ------------------------------------------------------------------------- 7. reproducibility
def test_render_vines_same_for_seed_and_generator():
    from branchnb.dendrite import render_vines

    d = fuzzkit._dendrite()
    a = render_vines(d, rng=5).image
    b = render_vines(d, rng=np.random.default_rng(5)).image
    np.testing.assert_array_equal(a, b)
    assert not np.array_equal(a, render_vines(d, rng=6).image)


def test_stylize_and_compare_metrics_take_a_generator():
    from branchnb.dendrite import StylizeParams, compare_metrics, stylize

    img = np.ones((32, 32))
    img[8:24, 8:24] = 0.0
    p = StylizeParams(n_endpoints=30, stipple_iterations=2)
    a = stylize(img, p, rng=np.random.default_rng(3), metaphor=None)
    b = stylize(img, p, rng=np.random.default_rng(3), metaphor=None)
    np.testing.assert_array_equal(a.endpoints, b.endpoints)
    assert compare_metrics(fuzzkit._stylizer(), p, rng=np.random.default_rng(0), metaphor=None).first
    with pytest.raises(ValueError, match="rng seed must be non-negative"):
        stylize(img, p, rng=-1)
    with pytest.raises(ValueError, match="rng seed must be non-negative"):
        compare_metrics(fuzzkit._stylizer(), p, rng=-1)
    assert as_seed(7) == 7 and as_seed(np.random.default_rng(1)) == as_seed(np.random.default_rng(1))


def test_morph_sequence_uses_rng_only_for_random_colours():
    """Documented: the default morph is fully determined by a, b and steps; colour="random" uses rng."""
    from branchnb.trees import morph_sequence

    lib = fuzzkit._library()
    a = morph_sequence(lib, "a", "b", 3, rng=0)
    b = morph_sequence(lib, "a", "b", 3, rng=1)
    for va, vb in zip(a, b):
        np.testing.assert_array_equal(va.image, vb.image)
    r0 = morph_sequence(lib, "a", "b", 3, colour="random", rng=0)
    r0b = morph_sequence(lib, "a", "b", 3, colour="random", rng=np.random.default_rng(0))
    r1 = morph_sequence(lib, "a", "b", 3, colour="random", rng=1)
    np.testing.assert_array_equal(r0[1].image, r0b[1].image)
    assert not np.array_equal(r0[1].colour_weights, r1[1].colour_weights)


def test_edit_structure_is_deterministic_whatever_the_rng():
    """Documented: the stroke edit (DP sampling + graph cuts) has no random step; rng is validated only."""
    from branchnb.strokes import edit_structure

    img, sk = fuzzkit._band_rgba(), fuzzkit._band_skeleton()
    a = edit_structure(img, [sk], [sk + (0, 3.0)], rng=0)
    b = edit_structure(img, [sk], [sk + (0, 3.0)], rng=np.random.default_rng(99))
    np.testing.assert_array_equal(a.image, b.image)
    with pytest.raises(ValueError, match="rng"):
        edit_structure(img, [sk], [sk], rng=-1)


# --------------------------------------------------------------------- the validation helpers
def test_check_real_and_int_messages_name_the_argument():
    assert check_real(3, "x", 0, 5) == 3.0 and isinstance(check_real(np.float32(1), "x"), float)
    for bad, exc in [("1", TypeError), (None, TypeError), (1j, TypeError), (True, TypeError),
                     (np.nan, ValueError), (np.inf, ValueError), (np.ones(2), TypeError)]:
        with pytest.raises(exc, match="^sigma "):
            check_real(bad, "sigma")
    with pytest.raises(ValueError, match="sigma must be > 0"):
        check_real(0, "sigma", 0, low_open=True)
    assert check_int(4.0, "n") == 4 and check_int(np.int64(2), "n", 0, 3) == 2
    for bad in (2.5, "3", None, np.nan, True):
        with pytest.raises(TypeError, match="^n must be an int"):
            check_int(bad, "n")
    with pytest.raises(ValueError, match="n must be <= 10"):
        check_int(11, "n", 0, 10)


def test_real_array_and_colour():
    with pytest.raises(TypeError, match="weights must be real-valued"):
        real_array([1j], "weights")
    with pytest.raises(TypeError, match="weights must be an array of numbers"):
        real_array(["a"], "weights")
    with pytest.raises(ValueError, match="weights is empty"):
        real_array([], "weights")
    assert real_array([1, np.inf], "w", allow_inf=True)[1] == np.inf
    with pytest.raises(ValueError, match="w contains NaN"):
        real_array([1, np.nan], "w", allow_inf=True)
    with pytest.raises(TypeError, match="must hold integers"):
        real_array([1.5], "idx", dtype=np.int64)
    assert as_colour((1, 0, 0, 0.5)).shape == (4,)


def test_checked_decorator_checks_annotations_rng_params_and_classes():
    from branchnb.branching import SynthesisParams

    @checked()
    def f(structure: Structure, n: int = 2, scale: float = 1.0, flag: bool = False, rng=None,
          params: SynthesisParams | None = None):
        return n

    s = fuzzkit._structure()
    assert f(s, 3.0) == 3
    with pytest.raises(TypeError, match="structure must be Structure"):
        f("s")
    with pytest.raises(TypeError, match="^n must be an int"):
        f(s, "3")
    with pytest.raises(ValueError, match="^scale must be a finite number"):
        f(s, scale=float("inf"))
    with pytest.raises(TypeError, match="^flag must be a bool"):
        f(s, flag=1)
    with pytest.raises(ValueError, match="^rng seed must be non-negative"):
        f(s, rng=-1)
    with pytest.raises(ValueError, match=r"^params\.m must be >= 1"):
        f(s, params=dataclasses.replace(SynthesisParams(), m=0))
    with pytest.raises(ValueError, match="^structure: .*cycle"):
        f(fuzzkit._cyclic_structure())
    with pytest.raises(TypeError, match="f\\(\\): missing a required argument"):
        f()


def test_coordinate_limit_is_far_beyond_any_image_and_enforced():
    assert COORD_LIMIT >= 1e6
    with pytest.raises(ValueError, match="polylines"):
        coverage_polylines((4, 4), [[(0, 0), (COORD_LIMIT * 2, 0)]])


# ----------------------------------------------------------------------------- issue 27: hostile image files


def _png_declaring(w: int, h: int, *, valid: bool = True) -> bytes:
    """A grey PNG of ``w x h`` zero pixels: a few hundred KB that decode to ``w * h`` bytes (or more)."""
    import struct
    import zlib

    def chunk(tag, body):
        return struct.pack(">I", len(body)) + tag + body + struct.pack(">I", zlib.crc32(tag + body) & 0xFFFFFFFF)

    comp = zlib.compressobj(9)
    row = bytes(w + 1)
    idat = b"".join(comp.compress(row) for _ in range(h)) + comp.flush() if valid else b"\x78\x9c"
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", w, h, 8, 0, 0, 0, 0))
            + chunk(b"IDAT", idat) + chunk(b"IEND", b""))


def _jpeg_declaring(w: int, h: int) -> bytes:
    import struct

    import cv2

    ok, buf = cv2.imencode(".jpg", np.zeros((16, 16, 3), np.uint8))
    b = bytearray(buf.tobytes())
    i = b.index(b"\xff\xc0")
    b[i + 5:i + 9] = struct.pack(">HH", h, w)
    return bytes(b)


def test_image_readers_refuse_oversized_files_before_decoding(tmp_path):
    from branchnb.core.io import MAX_IMAGE_PIXELS, image_size, imdecode, imread

    png = tmp_path / "bomb.png"
    png.write_bytes(_png_declaring(12000, 12000))         # 144 MP of zeros in ~150 KB
    jpg = tmp_path / "bomb.jpg"
    jpg.write_bytes(_jpeg_declaring(60000, 50000))
    assert image_size(png) == (12000, 12000) and image_size(jpg) == (60000, 50000)
    assert 12000 * 12000 > MAX_IMAGE_PIXELS
    for path, size in ((png, "12000 x 12000"), (jpg, "60000 x 50000")):
        with pytest.raises(ValueError, match=f"refusing to decode .*{path.name}.*{size}"):
            imread(path)
        with pytest.raises(ValueError, match=f"upload.png: it declares {size}"):
            imdecode(path.read_bytes(), name="upload.png")
    # the limit is configurable per call, and a small image passes
    with pytest.raises(ValueError, match="above the limit of 100"):
        imread(png, max_pixels=100)
    ok = tmp_path / "ok.png"
    ok.write_bytes(_png_declaring(40, 30))
    assert imread(ok).shape == (30, 40, 1)
    with pytest.raises(ValueError, match="max_pixels must be an int"):
        imread(ok, max_pixels=0)
    # peak memory stays bounded for a refused file (measured in a fresh process)
    code = ("import resource; from branchnb.core.io import imread\n"
            "before = resource.getrusage(resource.RUSAGE_SELF).ru_maxrss\n"
            f"try:\n    imread({str(png)!r})\nexcept ValueError:\n    pass\n"
            "print((resource.getrusage(resource.RUSAGE_SELF).ru_maxrss - before) / 1024)")
    run = _python(code)
    assert run.returncode == 0, run.stderr
    assert float(run.stdout) < 50                          # MB on top of the imports (decoding: > 140 MB)
    # the environment variable sets the default, in workers too
    code = f"from branchnb.core.io import imread; print(imread({str(ok)!r}).shape)"
    run = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, timeout=60, cwd=str(ROOT),
                         env=dict(os.environ, PYTHONPATH=str(ROOT), BRANCHNB_MAX_IMAGE_PIXELS="1000"))
    assert "refusing to decode" in run.stderr and "1,200 pixels" in run.stderr


@pytest.mark.parametrize("content, why", [
    (None, "No such file"), (b"", "the file is empty"), (b"hello world", "not an image format"),
    (b"\x89PNG\r\n\x1a\n\x00\x00", "without its IHDR"), ("folder", "it is a folder"),
    ("truncated", "damaged, truncated"),
])
def test_unreadable_image_messages_say_why(tmp_path, content, why):
    from branchnb.core.io import imdecode, imread

    path = tmp_path / "x.png"
    if content == "folder":
        path.mkdir()
    elif content == "truncated":
        path.write_bytes(_png_declaring(64, 64, valid=False))
    elif content is not None:
        path.write_bytes(content)
    with pytest.raises(ValueError, match=f"could not read an image from .*x.png: .*{why}"):
        imread(path)
    if isinstance(content, bytes):
        with pytest.raises(ValueError, match=why):
            imdecode(content, name="x.png")
    with pytest.raises(TypeError, match="path must be a file path"):
        imread(3)


# ------------------------------------------------- issue 27, items 4-5: each case is in the sweep and answered

#: (target, argument, kind of bad value) of every case issue 27 found: the sweep's generators make each one now.
ISSUE_27_CASES = [
    ("leaves:grow_layers", "layer_set", "scribble radius 1e5"),
    ("leaves:grow_layers", "layer_set", "one stroke in two layers"),
    ("leaves:grow_layers", "layer_set", "one stroke in a layer and the background"),
    ("leaves:analyze", "layers", "layer named blade"),
    ("leaves:analyze", "layers", "layer with an empty name"),
    ("leaves:analyze", "exemplars", "two leaves in one exemplar"),
    ("leaves:generate", "progress", "string"),
    ("dendrite:path_statistics", "plan_result", "another lattice's plan"),
    ("dendrite:plan", "graph", "lattice with a NaN weight"),
    ("dendrite:make_lattice", "cost", "all inf"),
    ("core:segments_intersect", "a0", "one shorter"),
    ("core:Structure", "branches", "incomplete dicts"),
    ("core:compare_samples", "labels", "int"),
    ("core:histogram_distance", "edges", "nan edges"),
    ("core:histograms", "samples", "+-1e308 sample"),
    ("trees:make_variation", "**overrides", "unknown keyword"),
    ("strokes:PlacedPatch", "pixels", "nan"),
    ("strokes:PlacedPatch", "origin", "nan entry"),
    ("dendrite:Stylizer.lattice", "rng_seed", "5000 digits"),
    ("core:Structure.children", "index", "5000 digits"),
]


@pytest.mark.parametrize("target, arg, kind", ISSUE_27_CASES)
def test_issue_27_cases_are_swept_and_get_a_clear_error(pool, target, arg, kind):
    t = next(t for t in fuzzkit.discover([target.split(":")[0]]) if t.id == target)
    cases = [c for c in fuzzkit.cases_for(t, valid=False) if c.arg == arg and c.kind == kind]
    assert cases, f"the sweep makes no {kind!r} case for {target}({arg})"
    o = pool.run(cases[0])
    assert o.status == "raised", o.detail


def test_huge_ints_and_seeds_are_refused_by_name():
    from branchnb.batch import BatchSpec
    from branchnb.core.random import as_rng, as_seed

    big = 10**5000
    for call, name in [(lambda: check_int(big, "n", 0, 10), "n must fit in 64 bits"),
                       (lambda: check_real(big, "sigma"), "sigma must be a finite number"),
                       (lambda: as_rng(big, name="seed"), "seed seed must be below 2"),
                       (lambda: as_seed(big), "rng seed must be below 2"),
                       (lambda: BatchSpec("dendrite_tree", count=1, seed=big), "seed must be below 2")]:
        with pytest.raises(ValueError, match=name):
            call()


def test_a_trunk_mask_of_another_shape_is_named():
    from branchnb.trees import process_exemplar

    img = fuzzkit._tree_rgba()
    for bad in (np.ones((3, 3), bool), [[1]]):
        with pytest.raises(ValueError, match="trunk_mask has shape"):
            process_exemplar(img, "a", trunk_mask=bad, exemplar_params=fuzzkit._ex_params())
