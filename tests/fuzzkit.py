# ruff: noqa: E501  (the example tables read best one call per line)
"""Fuzzing harness for the public API: every name in every package's ``__all__``.

The harness finds its targets itself (``pkgutil`` over ``branchnb``): every
function and class in each subpackage's ``__all__`` (for ``widgets`` only the
pure models, not the ipywidgets), plus the public methods of instances it can
build. For each target it makes a *valid* call from a table of small example
values (by argument name, ``function.argument`` or annotation) and then
breaks one argument at a time with a bad or edge-case value of the right
family (NaN, inf, empty, 1 x 1, huge, wrong dtype/shape, complex, string,
None, out-of-range parameter-dataclass fields, a structure with a parent
cycle, ...).

Every call runs in a forked worker process with a time limit, so a segfault
or an endless loop is caught as such. A case passes when the call

* returns a result with no NaN/inf (unless the valid call's result had them)
  and no invalid file (JSON must be strict, SVG parse as XML), or
* raises ``ValueError``/``TypeError`` whose message names the argument.

Run ``python tests/fuzzkit.py`` for the full deterministic sweep with a
table of failures per package (``--help`` for options); ``tests/test_fuzz.py``
drives the same cases from hypothesis.
"""

from __future__ import annotations

import copy
import dataclasses
import functools
import importlib
import inspect
import json
import multiprocessing as mp
import os
import pkgutil
import re
import sys
import tempfile
import time
import traceback
import warnings
import xml.etree.ElementTree as ET
from pathlib import Path

import numpy as np

ROOT = Path(__file__).resolve().parent.parent
if str(ROOT) not in sys.path:
    sys.path.insert(0, str(ROOT))

import branchnb  # noqa: E402

NAN, INF = float("nan"), float("inf")


# =============================================================================================== targets
@dataclasses.dataclass(frozen=True)
class Target:
    package: str  # "core", "branching", ...
    qualname: str  # "seam_cut", "Structure", "Structure.render"
    kind: str  # "function", "class", "method", "params"

    @property
    def id(self) -> str:
        return f"{self.package}:{self.qualname}"


def packages() -> list[str]:
    """Every public subpackage of branchnb that declares ``__all__`` (new ones are picked up automatically;
    private ones such as ``branchnb._docs``, the documentation build, are not public API)."""
    out = []
    for info in pkgutil.iter_modules(branchnb.__path__):
        if not info.ispkg or info.name.startswith("_"):
            continue
        mod = importlib.import_module(f"branchnb.{info.name}")
        if getattr(mod, "__all__", None):
            out.append(info.name)
    return out


def _is_widget(obj) -> bool:
    try:
        import ipywidgets
    except ImportError:  # pragma: no cover
        return False
    return inspect.isclass(obj) and issubclass(obj, ipywidgets.Widget)


def _is_params(cls) -> bool:
    return dataclasses.is_dataclass(cls) and cls.__name__.endswith("Params")


def _is_container(cls) -> bool:
    """A result dataclass: plain data, built by the library, not an input door."""
    return dataclasses.is_dataclass(cls) and "__post_init__" not in vars(cls) and not _is_params(cls)


def _public_methods(cls) -> list[str]:
    names = []
    for klass in cls.__mro__:
        if klass is object or klass.__module__.split(".")[0] != "branchnb":
            continue
        for k, v in vars(klass).items():
            if k.startswith("_") and k != "_repr_png_":
                continue
            if inspect.isfunction(v) or isinstance(v, (classmethod, staticmethod)):
                if k not in names:
                    names.append(k)
    return names


def resolve(target: Target):
    mod = importlib.import_module(f"branchnb.{target.package}")
    head, _, meth = target.qualname.partition(".")
    obj = getattr(mod, head)
    return obj, meth


def discover(pkgs=None) -> list[Target]:
    out, seen = [], set()
    for pkg in pkgs or packages():
        mod = importlib.import_module(f"branchnb.{pkg}")
        for name in mod.__all__:
            obj = getattr(mod, name)
            if _is_widget(obj) or (inspect.isclass(obj) and issubclass(obj, BaseException)):
                continue  # ipywidgets and exception types are not input doors
            if inspect.isclass(obj):
                kind = "params" if _is_params(obj) else "class"
                out.append(Target(pkg, name, kind))
                for m in _public_methods(obj):
                    out.append(Target(pkg, f"{name}.{m}", "method"))
            elif callable(obj):
                key = (obj.__module__, obj.__qualname__)
                out.append(Target(pkg, name, "function"))
                seen.add(key)
    return out


# =========================================================================================== examples
# Small valid values, built once per process and copied for each call.

def _img(h=24, w=28, c=3, seed=0):
    rng = np.random.default_rng(seed)
    yy, xx = np.mgrid[:h, :w]
    base = 0.5 + 0.4 * np.sin(xx / 3.0)[..., None] * np.cos(yy / 4.0)[..., None]
    img = np.clip(base + 0.05 * rng.standard_normal((h, w, c)), 0, 1).astype(np.float32)
    return img if c > 1 else img[..., 0]


def _tree_rgba(h=64, w=56, trunk=True):
    img = np.zeros((h, w, 4), np.float32)
    yy, xx = np.mgrid[:h, :w]
    crown = (xx - w / 2) ** 2 + (yy - 0.35 * h) ** 2 <= (0.3 * h) ** 2
    shade = 0.4 + 0.3 * np.sin(xx / 3.0) * np.cos(yy / 5.0)
    img[crown] = np.stack([0.1 + 0 * shade, shade, 0.1 + 0 * shade, np.ones_like(shade)], -1)[crown]
    if trunk:
        stem = (np.abs(xx - w / 2) <= 2) & (yy >= 0.6 * h) & (yy <= h - 3)
        img[stem & ~crown] = (0.4, 0.25, 0.1, 1.0)
    return img


def _band_rgba(h=48, w=96):
    yy, xx = np.mgrid[:h, :w]
    cy = h / 2 + 6 * np.sin(xx / 15.0)
    d = np.abs(yy - cy)
    alpha = np.clip(7.5 - d, 0, 1) * ((xx > 6) & (xx < w - 6))
    rgb = np.dstack([0.3 + 0.5 * (0.5 + 0.5 * np.cos(xx / 3.0)), 0.4 + 0.02 * d, 0.3 + 0 * xx])
    img = np.dstack([np.clip(rgb, 0, 1), alpha]).astype(np.float32)
    img[alpha == 0, :3] = 0
    return img


def _band_skeleton(w=96, h=48):
    x = np.linspace(10, w - 10, 30)
    return np.c_[x, h / 2 + 6 * np.sin(x / 15.0)]


def _structure():
    """A small tree whose branches are long enough for the learnt models (k + m + 2 vertices at h = 4)."""
    from branchnb.core import Branch, Structure

    t = np.linspace(0, 1, 24)
    trunk = np.c_[20 + 10 * t + 4 * np.sin(6 * t), 92 - 84 * t]
    s = Structure([Branch(trunk, 3.0 - 1.6 * t)], image_shape=(96, 64))
    for vertex, sign in ((8, 1), (14, -1)):
        base = trunk[vertex]
        u = np.linspace(0, 1, 20)[:, None]
        pts = base + u * np.array([sign * 16.0, -30.0]) + np.sin(4 * u) * np.array([0, 3.0])
        s.add_branch(pts, 1.6 - 0.6 * u[:, 0], parent=0, parent_vertex=vertex)
    return s


def _cyclic_structure():
    """A valid structure mutated after construction so that its parents form a cycle."""
    s = _structure()
    s.branches[0].parent, s.branches[0].parent_vertex = 1, 3
    return s


def _example_image():
    s = _structure()
    img = np.ones((96, 64, 3), np.float32) * np.array([0.9, 0.85, 0.7], np.float32)
    return s.render(background=img, color=(0.3, 0.2, 0.1))


@functools.cache
def example(key: str):
    """The example value called ``key`` (built once; callers get a deep copy)."""
    return _EXAMPLES[key]()


def _lazy(module, attr, *args, **kwargs):
    def make():
        obj = getattr(importlib.import_module(module), attr)
        args2 = [a() if callable(a) and getattr(a, "_example", False) else a for a in args]
        kw2 = {k: (v() if callable(v) and getattr(v, "_example", False) else v) for k, v in kwargs.items()}
        return obj(*args2, **kw2)
    return make


def ref(key):
    """A reference to another example (resolved when the example is built)."""
    def get():
        return example(key)
    get._example = True
    return get


def _dendrite():
    from branchnb.dendrite import build_dendrite, make_lattice, plan

    cost = 1.0 - _img(24, 24, 1)
    lat = make_lattice(cost, rng=0)
    pr = plan(lat, [(12, 2)])
    return build_dendrite(pr, [(3, 20), (20, 21), (12, 18), (6, 10)])


def _plan_result():
    from branchnb.dendrite import make_lattice, plan

    return plan(make_lattice(1.0 - _img(24, 24, 1), rng=0), [(12, 2)])


def _library():
    from branchnb.trees import TreeLibrary

    lib = TreeLibrary(size=128)
    lib.add(_tree_rgba(), "a")
    lib.add(_tree_rgba(60, 64), "b")
    lib.add(_tree_rgba(70, 50, trunk=False), "c")
    return lib


def _variation():
    from branchnb.trees import make_variation

    return make_variation(example("library"), rng=0)


def _cloud():
    from branchnb.trees import BillboardParams, billboard_cloud

    return billboard_cloud(_tree_rgba(), None, BillboardParams(n_segments=24, n_interior=8, max_size=96), rng=0)


def _strokes():
    from branchnb.strokes import Stroke

    return [Stroke(_band_skeleton(), name="a")]


def _target_strokes():
    from branchnb.strokes import Stroke

    sk = _band_skeleton()
    return [Stroke(sk + np.array([0, 3.0]), name="b")]


def _pair():
    from branchnb.strokes import make_pairs

    return make_pairs([_band_skeleton()], [_band_skeleton() + np.array([0, 3.0])])[0]


def _source_index():
    from branchnb.strokes import source_index

    return source_index(_band_rgba(), example("strokes"))


def _fetched():
    from branchnb.strokes import fetch

    return fetch(example("source_index"), 0, 30.0, 0.0, (40.0, 24.0), 0.0, 8.0, window=8.0)


def _placed():
    from branchnb.strokes import PlacedPatch

    rng = np.random.default_rng(0)
    pix = rng.random((12, 12, 4)).astype(np.float32)
    pix[..., 3] = 1.0
    return [PlacedPatch(pix, np.ones((12, 12), bool), (2, 2)),
            PlacedPatch(pix[::-1].copy(), np.ones((12, 12), bool), (8, 4))]


def _unaries():
    rng = np.random.default_rng(0)
    return [rng.random(k) for k in (3, 4, 2)]


def _pairwise():
    rng = np.random.default_rng(1)
    return [rng.random((3, 4)), rng.random((4, 2))]


def _junctions():
    from branchnb.strokes import find_junctions

    return find_junctions(example("junction_strokes"), 3.0)


def _junction_strokes():
    from branchnb.strokes import Stroke

    return [Stroke([(10, 20), (80, 20)], name="p"), Stroke([(40, 21), (50, 40)], name="c")]


def _exemplar():
    from branchnb.trees import process_exemplar

    return process_exemplar(_tree_rgba(), "a", exemplar_params=_ex_params())


def _ex_params():
    from branchnb.trees import ExemplarParams

    return ExemplarParams(size=128)


def _grown_tree():
    from branchnb.dendrite import TreeParams, grow_tree

    return grow_tree((40, 32), TreeParams(iterations=2, radius=10), rng=0)


def _tree_layers():
    from branchnb.dendrite import TreeParams, grow_layers

    return grow_layers((40, 32), TreeParams(iterations=2, radius=10), layers=2, rng=0)


def _pareidolia_params():
    from branchnb.dendrite import PareidoliaParams

    return PareidoliaParams(n_endpoints=40, iterations=2, lattice_size=0)


def _pareidolia():
    from branchnb.dendrite import pareidolia_tree

    return pareidolia_tree(_img(), _pareidolia_params(), rng=0)


def _stylizer():
    from branchnb.dendrite import Stylizer

    img = np.ones((32, 32))
    img[8:24, 8:24] = 0.0
    return Stylizer(img)


def _stylize_params():
    from branchnb.dendrite import StylizeParams

    return StylizeParams(n_endpoints=30, stipple_iterations=2)


def _model():
    from branchnb.branching import fit_model

    return fit_model(_structure())


def _guidance():
    from branchnb.branching import Guidance

    return Guidance.from_path((48, 48), [(4, 40), (40, 8)])


def _annotation_model():
    from branchnb.widgets import AnnotationModel, Shape

    return AnnotationModel([Shape("polyline", np.array([(1.0, 2.0), (5.0, 6.0)]), closed=False)])


# ---- leaves: one tiny procedural family (64 px) and everything built from it, cached per process
def _leaf_family():
    from branchnb.leaves import leaf_family

    return leaf_family(3, size=64, rng=0)


def _fast_reg_params():
    from branchnb.leaves import RegistrationParams

    return RegistrationParams(n_keypoints=16, iterations=1, sinkhorn_iterations=5, outline_points=16, n_starts=1,
                              refine=False, anneal_rate=0.5, rotation_step=45.0)


def _leaf_layer_set():
    from branchnb.leaves import Layer, LayerSet, simulate_scribbles

    leaf = example("leaf_family")[0]
    return LayerSet([Layer("veins", "#ff0000", 0, simulate_scribbles(leaf.layers["veins"], 3, length=8.0, rng=1)),
                     Layer("spots", "#0000ff", 1, simulate_scribbles(leaf.layers["spots"], 3, length=6.0, rng=1))])


def _leaf_registration():
    from branchnb.leaves import register

    fam = example("leaf_family")
    return register(fam[1].image, fam[0].image, exemplar_blade=fam[1].blade, training_blade=fam[0].blade,
                    params=example("leaf_reg_params"), rng=0)


def _leaf_masks():
    leaf = example("leaf_family")[0]
    return {"veins": leaf.layers["veins"], "spots": leaf.layers["spots"]}


def _leaf_analysis():
    from branchnb.leaves import analyze

    return analyze(example("leaf_family"), 0, _leaf_masks(), registration_params=example("leaf_reg_params"), rng=0)


def _leaf_generated():
    from branchnb.leaves import generate

    return generate(example("leaf_analysis"), n=1, rng=0)[0]


def _leaf_tps():
    from branchnb.leaves import ThinPlateSpline

    src = np.array([(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (0.5, 0.4)])
    return ThinPlateSpline.fit(src, src * 1.1 + 0.05, lambda1=0.01)


def _leaf_warp_map(h=32, w=32):
    """The right third squeezed (texture stretched): correct_texture has something to correct."""
    yy, xx = np.mgrid[:h, :w].astype(np.float64)
    return np.dstack([np.where(xx < 20, xx, 20 + 0.3 * (xx - 20)), yy])


_EXAMPLES = {
    "image": lambda: _img(),
    "gray": lambda: _img(c=1),
    "rgba": _tree_rgba,
    "band_rgba": _band_rgba,
    "mask": lambda: _img(c=1) > 0.5,
    "points": lambda: np.array([(2.0, 3.0), (10.0, 5.0), (16.0, 12.0), (20.0, 18.0)]),
    "polylines": lambda: [np.array([(2.0, 3.0), (10.0, 5.0), (16.0, 12.0)]), np.array([(4.0, 20.0), (20.0, 4.0)])],
    "structure": _structure,
    "cyclic_structure": _cyclic_structure,
    "example_image": _example_image,
    "dendrite": _dendrite,
    "plan_result": _plan_result,
    "lattice": lambda: importlib.import_module("branchnb.dendrite").make_lattice(1.0 - _img(24, 24, 1), rng=0),
    "library": _library,
    "variation": _variation,
    "cloud": _cloud,
    "strokes": _strokes,
    "target_strokes": _target_strokes,
    "pair": _pair,
    "source_index": _source_index,
    "fetched": _fetched,
    "edit_patches": _lazy("branchnb.strokes", "fetch_patches", ref("band_rgba"), [_band_skeleton()],
                          [_band_skeleton() + np.array([0, 3.0])]),
    "placed": _placed,
    "unaries": _unaries,
    "pairwise": _pairwise,
    "junctions": _junctions,
    "junction_strokes": _junction_strokes,
    "grown_tree": _grown_tree, "tree_layers": _tree_layers, "pareidolia_params": _pareidolia_params,
    "pareidolia": _pareidolia,
    "exemplar": _exemplar,
    "stylizer": _stylizer,
    "stylize_params": _stylize_params,
    "model": _model,
    "guidance": _guidance,
    "annotation_model": _annotation_model,
    "ex_params": _ex_params,
    "leaf_family": _leaf_family, "leaf_reg_params": _fast_reg_params, "leaf_layer_set": _leaf_layer_set,
    "leaf_registration": _leaf_registration, "leaf_analysis": _leaf_analysis, "leaf_generated": _leaf_generated,
    "leaf_tps": _leaf_tps,
}


def _v(value):
    return lambda: copy.deepcopy(value)


def _e(key):
    return lambda: copy.deepcopy(example(key))


def _call(fn):
    return fn


#: Example values by argument: ``"target.argument"`` first, then ``"argument"``.
ARGS = {
    # ---- generic names
    "image": _e("image"), "mask": _e("mask"), "points": _e("points"), "polylines": _e("polylines"),
    "shape": _v((24, 28)), "structure": _e("structure"), "example": _e("structure"),
    "density": lambda: _img(c=1) + 0.1, "importance": lambda: _img(24, 24, 1), "cost": lambda: 1 - _img(24, 24, 1),
    "rgba": _e("rgba"), "dendrite": _e("dendrite"),
    "plan_result": _e("plan_result"), "library": _e("library"), "cloud": _e("cloud"), "variation": _e("variation"),
    "path": lambda: str(Path(tempfile.mkdtemp(prefix="fuzz")) / "out"), "polygon": _v([(2.0, 2.0), (20.0, 3.0), (12.0, 18.0)]),
    "canvas": _e("image"),
    "unaries": _e("unaries"), "pairwise": _e("pairwise"), "patches": _e("placed"), "stylizer": _e("stylizer"),
    "source_strokes": _v([_band_skeleton()]), "target_strokes": _v([_band_skeleton() + np.array([0, 3.0])]),
    "strokes": _v([_band_skeleton()]), "pair": _e("pair"), "junctions": _e("junctions"),
    "junction": lambda: example("junctions")[0],
    "graph": _e("lattice"), "seeds": _v([(12, 2)]), "endpoints": _v([(3.0, 20.0), (20.0, 21.0)]),
    "n_points": _v(8), "n_endpoints": _v(12), "rho": _v(4.0),
    # ---- per function
    "core:extend_nearest.values": _e("image"), "core:extend_nearest.known": _e("mask"),
    "core:matte_from_background.image": lambda: np.where(_tree_rgba()[..., 3:] > 0, _tree_rgba()[..., :3], 1.0),
    "core:as_rng.rng": _v(0), "core:resample_chord.n": _v(5), "core:resample_uniform.h": _v(2.0),
    "core:polylines_to_svg.size": _v((28, 24)), "core:draw_polylines.widths": _v(2.0),
    "core:compare_samples.samples": _v(([0.1, 0.5, 0.9], [0.2, 0.3])),
    "core:histograms.samples": _v(([0.1, 0.5, 0.9], [0.2, 0.3])),
    "core:shared_bins.samples": _v(([0.1, 0.5, 0.9], [0.2, 0.3])),
    "core:histogram_distance.p": _v(np.array([0.2, 0.3, 0.5])), "core:histogram_distance.q": _v(np.array([0.1, 0.6, 0.3])),
    "core:histogram_distance.metric": _v("emd"),  # the metric that reads edges
    "core:compose_overlap.a": _e("image"), "core:compose_overlap.b": lambda: _img(seed=1),
    "core:compose_overlap.mask_a": lambda: np.pad(np.ones((24, 18), bool), ((0, 0), (0, 10))),
    "core:compose_overlap.mask_b": lambda: np.pad(np.ones((24, 18), bool), ((0, 0), (10, 0))),
    "core:seam_cut.a": _e("image"), "core:seam_cut.b": lambda: _img(seed=1), "core:seam_cut.region": _v(np.ones((24, 28), bool)),
    "core:seam_cut.pin_a": lambda: np.pad(np.ones((24, 1), bool), ((0, 0), (0, 27))),
    "core:seam_cut.pin_b": lambda: np.pad(np.ones((24, 1), bool), ((0, 0), (27, 0))),
    "core:seam_cost.a": _e("image"), "core:seam_cost.b": lambda: _img(seed=1), "core:seam_cost.take_b": _e("mask"),
    "core:psnr.a": _e("image"), "core:psnr.b": lambda: _img(seed=1),
    "core:iou.a": _e("mask"), "core:iou.b": lambda: _img(seed=2, c=1) > 0.5,
    "core:poisson_blend.target": _e("image"), "core:poisson_blend.source": lambda: _img(seed=1),
    "core:remap.map_x": lambda: np.tile(np.arange(28, dtype=np.float32), (24, 1)) * 0.9,
    "core:remap.map_y": lambda: np.tile(np.arange(24, dtype=np.float32)[:, None], (1, 28)) * 0.9,
    "core:rigid_align.source": _e("points"), "core:rigid_align.target": lambda: example("points")[:, ::-1].copy(),
    "core:segments_intersect.a0": _v([(0.0, 0.0), (1.0, 0.0)]), "core:segments_intersect.a1": _v([(4.0, 4.0), (1.0, 3.0)]),
    "core:segments_intersect.b0": _v([(0.0, 4.0), (3.0, 3.0)]), "core:segments_intersect.b1": _v([(4.0, 0.0), (4.0, 4.0)]),
    "core:transfer_patch.src_center": _v((12.0, 12.0)), "core:transfer_patch.src_angle": _v(0.3),
    "core:transfer_patch.dst_center": _v((14.0, 10.0)), "core:transfer_patch.dst_angle": _v(0.0),
    "core:transfer_patch.radius": _v(4.0),
    "core:Branch.thickness": _v([2.0, 1.5, 1.0, 1.0]), "core:Structure.branches": lambda: example("structure").branches,
    "core:Patch.pixels": lambda: _img(5, 5), "core:Patch.valid": _v(np.ones((5, 5), bool)), "core:Patch.origin": _v((2, 3)),
    "core:Patch.placed.shape": _v((24, 28)),
    "core:Structure.add_branch.points": _v([(20.0, 20.0), (10.0, 8.0)]), "core:Structure.add_branch.thickness": _v(1.0),
    "core:Structure.add_branch.parent": _v(0), "core:Structure.add_branch.parent_vertex": _v(2),
    "core:Structure.remove_subtree.index": _v(1), "core:Structure.with_thickness.index": _v(0),
    "core:Structure.with_thickness.vertex": _v(1), "core:Structure.with_thickness.r": _v(2.0),
    "core:Structure.children.index": _v(0), "core:Structure.generation.index": _v(1),
    "core:Structure.scaled.factor": _v(0.5), "core:Structure.resampled.h": _v(2.0),
    "core:Structure.with_polylines.polylines": lambda: [(b.points, b.thickness) for b in example("structure").branches],
    "core:Structure.from_json.text": lambda: example("structure").to_json(),
    "core:Structure.from_dict.d": lambda: json.loads(example("structure").to_json()),
    "core:Structure.check_inside.shape": _v((96, 64)), "core:Structure.render.shape": _v((96, 64)),
    "core:Structure.to_svg.shape": _v((96, 64)),
    # ---- branching
    "branching:branch_from_clicks.image": _e("example_image"), "branching:branch_from_clicks.points": _v([(6, 40), (20, 20), (26, 4)]),
    "branching:estimate_thickness.image": _e("example_image"),
    "branching:estimate_thickness.points": _v(np.array([(6.0, 40.0), (14.0, 30.0), (20.0, 20.0)])),
    "branching:structure_from_polylines.image": _e("example_image"),
    "branching:structure_from_polylines.polylines": _v([[(6, 40), (14, 30), (20, 20), (26, 4)], [(20, 20), (38, 12)]]),
    "branching:extract_structure.image": _e("example_image"),
    "branching:extend_branch.index": _v(1), "branching:extend_branch.n_steps": _v(3),
    "branching:guidance_map.shape": _v((32, 32)), "branching:guidance_map.path": _v([(2.0, 30.0), (30.0, 2.0)]),
    "branching:histogram_distances.example": _e("structure"), "branching:histogram_distances.structure": _e("structure"),
    "branching:synthesize_image.example_image": _e("example_image"),
    "branching:synthesize_image.example_structure": _e("structure"),
    "branching:synthesize_image.target_structure": lambda: example("structure").scaled(0.9),
    "branching:synthesize_structure.shape": _v((48, 48)),
    "branching:Guidance.map": lambda: np.linspace(0, 1, 48 * 48).reshape(48, 48),
    "branching:Guidance.from_path.shape": _v((48, 48)), "branching:Guidance.from_path.path": _v([(4, 40), (40, 8)]),
    "branching:Guidance.sample.points": _v(np.array([(4.0, 40.0), (20.0, 20.0)])),
    "branching:Guidance.along.points": _v(np.array([(4.0, 40.0), (20.0, 20.0)])),
    "branching:StructureModel.sample_length.rng": _v(0),
    # ---- dendrite
    **{f"dendrite:Dendrite.{f}": (lambda f=f: copy.deepcopy(getattr(example("dendrite"), f)))
       for f in ("nodes", "parent", "points", "radius", "branches", "branch_parent", "tips")},
    "dendrite:Lattice.weights": lambda: 1.0 + _img(24, 24, 1),
    "dendrite:importance_map.image": _e("image"),
    "dendrite:lightning.shape": _v((32, 24)), "dendrite:visiting_order_image.seeds": _v(True),
    "dendrite:place_endpoints.n_endpoints": _v(12),
    "dendrite:random_endpoints.mask": _e("mask"),
    "dendrite:stylize.image": lambda: example("stylizer").image, "dendrite:stylize.params": _e("stylize_params"),
    "dendrite:compare_metrics.params": _e("stylize_params"),
    "dendrite:Stylizer.image": lambda: example("stylizer").image, "dendrite:Stylizer.run.params": _e("stylize_params"),
    "dendrite:Stylizer.endpoints.params": _e("stylize_params"), "dendrite:Stylizer.dendrite.params": _e("stylize_params"),
    "dendrite:Stylizer.plan.params": _e("stylize_params"), "dendrite:Stylizer.lattice.params": _e("stylize_params"),
    "dendrite:Stylizer.importance.params": _e("stylize_params"),
    "dendrite:importance_thickness.importance": lambda: _img(24, 24, 1),
    "dendrite:rolling_importance.importance": lambda: _img(24, 24, 1),
    "dendrite:draw_points.points": _v([(3.0, 4.0), (10.0, 12.0)]),
    "dendrite:build_dendrite.endpoints": _v([(3, 20), (20, 21)]),
    "dendrite:PlanResult.path.node": _v(100),
    "dendrite:Lattice.node_index.points": _v([(3, 4), (5, 6)]), "dendrite:Lattice.node_points.nodes": _v([3, 30]),
    "dendrite:render_layers.trees": _e("tree_layers"), "dendrite:pareidolia_tree.params": _e("pareidolia_params"),
    "dendrite:Rendering.image": _e("image"), "dendrite:Rendering.svg": _v("<svg xmlns='http://www.w3.org/2000/svg'/>"),
    # ---- trees
    "trees:tree_contour.contour": lambda: example("exemplar").contour.contour,
    "trees:tree_contour.alpha": lambda: example("exemplar").image[..., 3],
    "trees:stem_trunk_mask.alpha": lambda: _tree_rgba()[..., 3],
    "trees:alpha_from_background.image": lambda: np.where(_tree_rgba()[..., 3:] > 0, _tree_rgba()[..., :3], 1.0),
    "trees:extract_contours.alpha": lambda: _tree_rgba()[..., 3],
    "trees:normalize_exemplar.image": _e("rgba"), "trees:normalize_exemplar.params": _e("ex_params"),
    "trees:tree_rgba.image": _e("rgba"),
    "trees:histogram_transfer.image": _e("rgba"), "trees:histogram_transfer.reference": lambda: _tree_rgba(60, 64),
    "trees:combine_shapes.shapes": lambda: [example("exemplar").contour.resampled] * 2,
    "trees:dirichlet_weights.n": _v(3),
    "trees:fill_contour.shape": _v((24, 24)),
    "trees:mean_value_coordinates.points": _v([(8.0, 8.0), (10.0, 6.0)]),
    "trees:transfer_colour.sources": lambda: [example("exemplar").normalized.image] * 2,
    "trees:process_exemplar.image": _e("rgba"), "trees:process_exemplar.exemplar_params": _e("ex_params"),
    "trees:morph_sequence.a": _v("a"), "trees:morph_sequence.b": _v("b"), "trees:morph_sequence.steps": _v(2),
    "trees:similar_variations.n": _v(2), "trees:tree_variations.n": _v(2), "trees:tree_variations.target": _v("a"),
    "trees:segment_tree.rgba": _e("rgba"), "trees:segment_tree.params": lambda: importlib.import_module(
        "branchnb.trees").SegmentParams(work_size=64, n_train=200, n_trees=5),
    "trees:segmentation_iou.pred": lambda: _tree_rgba()[..., 3] > 0.5, "trees:segmentation_iou.ref": lambda: _tree_rgba()[..., 3] > 0.5,
    "trees:billboard_cloud.rgba": _e("rgba"), "trees:billboard_cloud.params": lambda: importlib.import_module(
        "branchnb.trees").BillboardParams(n_segments=24, n_interior=8, max_size=96),
    "trees:export_gltf.path": lambda: str(Path(tempfile.mkdtemp(prefix="fuzz")) / "cloud.gltf"),
    "trees:export_obj.path": lambda: str(Path(tempfile.mkdtemp(prefix="fuzz")) / "cloud.obj"),
    "trees:export_lod_gltf.path": lambda: str(Path(tempfile.mkdtemp(prefix="fuzz")) / "lod.gltf"),
    "trees:crossfade_fraction.sources": lambda: [_tree_rgba()] * 2,
    "trees:render_views.height": _v(48), "trees:render_cloud.height": _v(48),
    "trees:evaluate_reference.names": _v(["tree_rpg_02"]), "trees:load_reference_masks.names": _v(["tree_rpg_02"]),
    "trees:load_reference_scribbles.name": _v("tree_rpg_02"), "trees:reference_from_scribbles.name": _v("tree_rpg_02"),
    "trees:TreeLibrary.exemplars": lambda: [example("exemplar")], "trees:TreeLibrary.size": _v(128),
    "trees:TreeLibrary.add.image": lambda: _tree_rgba(50, 40), "trees:TreeLibrary.add.name": _v("new"),
    "trees:TreeLibrary.index.name": _v("a"), "trees:TreeLibrary.set_trunk.name": _v("a"),
    "trees:TreeLibrary.add_exemplar.exemplar": lambda: dataclasses.replace(example("exemplar"), name="z"),
    "trees:TreeLibrary.variations_of.name": _v("a"), "trees:TreeLibrary.variations_of.n": _v(2),
    "trees:TreeLibrary.similar.n": _v(2), "trees:TreeLibrary.morph.a": _v("a"), "trees:TreeLibrary.morph.b": _v("b"),
    "trees:TreeLibrary.morph.steps": _v(2), "trees:TreeLibrary.from_data.names": _v(["tree_rpg_01"]),
    "trees:TreeLibrary.from_data.size": _v(128),
    # ---- strokes
    "strokes:Stroke.points": _v(_band_skeleton()),
    "strokes:Stroke.point_at.s": _v([0.0, 10.0]), "strokes:Stroke.angle_at.s": _v([0.0, 10.0]),
    "strokes:Stroke.normal_at.s": _v([0.0, 10.0]), "strokes:Stroke.project.points": _v([(20.0, 24.0)]),
    "strokes:Stroke.inside.shape": _v((48, 96)),
    "strokes:StrokePair.source": lambda: example("strokes")[0], "strokes:StrokePair.target": lambda: example("target_strokes")[0],
    "strokes:StrokePair.with_control.control": _v([(0.0, 0.0), (1.0, 1.0)]),
    "strokes:edit_structure.image": _e("band_rgba"), "strokes:fetch_patches.image": _e("band_rgba"),
    "strokes:compose_patches.patches": _e("edit_patches"),
    "strokes:source_index.image": _e("band_rgba"), "strokes:source_index.source_strokes": _e("strokes"),
    "strokes:object_colours.image": _e("band_rgba"), "strokes:object_colours.mask": lambda: _band_rgba()[..., 3] > 0.5,
    "strokes:compare_colours.image": _e("band_rgba"),
    "strokes:draw_strokes.image": _e("band_rgba"), "strokes:stroke_markers.canvas": _e("band_rgba"),
    "strokes:fetch.stroke_id": _v(0), "strokes:fetch.source_s": _v(30.0), "strokes:fetch.across": _v(0.0),
    "strokes:fetch.dst_point": _v((40.0, 24.0)), "strokes:fetch.dst_angle": _v(0.0), "strokes:fetch.radius": _v(8.0),
    "strokes:fetch.window": _v(8.0),
    "strokes:pair_energies.a": _e("fetched"), "strokes:pair_energies.b": lambda: example("fetched"),
    "strokes:sample_pair.spacing": _v(6.0), "strokes:sample_pair.window": _v(8.0),
    "strokes:find_junctions.strokes": _e("junction_strokes"), "strokes:find_junctions.tolerance": _v(3.0),
    "strokes:stroke_order.n": _v(2), "strokes:attach.target_strokes": _e("junction_strokes"),
    "strokes:attach.pair": lambda: importlib.import_module("branchnb.strokes").make_pairs(
        [[(10, 20), (80, 20)], [(40, 21), (50, 40)]], [[(10, 20), (80, 20)], [(40, 21), (50, 40)]])[1],
    "strokes:attach.depth": _v({}),
    "strokes:far_side.parent": lambda: example("junction_strokes")[0], "strokes:far_side.child_dir": _v(np.array([0.3, 1.0])),
    "strokes:far_side.origin": _v((30, 10)), "strokes:far_side.size": _v(17), "strokes:far_side.window": _v(6.0),
    "strokes:seam_mask.labels": lambda: (np.arange(24 * 28).reshape(24, 28) // 100).astype(np.int64),
    "strokes:labelling_cost.labels": lambda: np.where(np.arange(20 * 20).reshape(20, 20) % 20 < 10, 0, 1),
    "strokes:compose.shape": _v((20, 20)), "strokes:chain_energy.path": _v([0, 1, 1]),
    "strokes:candidate_offsets.window": _v(8.0), "strokes:candidate_offsets.step": _v(2.0),
    "strokes:pair_color.i": _v(2), "strokes:pair_color_hex.i": _v(2),
    "strokes:make_pairs.source_strokes": _v([_band_skeleton()]),
    "strokes:make_pairs.target_strokes": _v([_band_skeleton() + np.array([0, 3.0])]),
    "strokes:PlacedPatch.pixels": lambda: example("placed")[0].pixels, "strokes:PlacedPatch.valid": _v(np.ones((12, 12), bool)),
    "strokes:PlacedPatch.origin": _v((2, 2)), "strokes:PlacedPatch.placed.shape": _v((24, 28)),
    "strokes:PlacedPatch.window.shape": _v((24, 28)),
    "strokes:SourceIndex.half_width.stroke_id": _v(0), "strokes:SourceIndex.half_width.s": _v([1.0, 5.0]),
    "strokes:SourceIndex.radius.stroke_id": _v(0),
    "strokes:Fetched.take.mask": _v(np.ones((17, 17), bool)),
    # ---- widgets (pure models)
    "widgets:Shape.kind": _v("polyline"), "widgets:Shape.points": _v(np.array([(1.0, 2.0), (5.0, 6.0)])),
    "widgets:AnnotationModel.shapes": lambda: list(example("annotation_model").shapes),
    "widgets:AnnotationEvent.type": _v("added"),
    # ---- examples found by the first sweep
    "core:Branch.points": _v([(2.0, 3.0), (10.0, 5.0), (16.0, 12.0), (20.0, 18.0)]),
    "core:compare_samples.labels": _v(["x", "y"]), "core:histograms.weights": _v(None),
    "core:rigid_align.weights": _v(None),
    "core:Structure.render.alpha": _v(1.0),
    "branching:Guidance.path": _v(None), "branching:Guidance.along.tip": _v((20.0, 40.0)),
    "branching:Guidance.along.directions": _v(np.array([[0.0, -1.0], [1.0, 0.0]])), "branching:Guidance.along.length": _v(12.0),
    "branching:branch_from_clicks.parent": _v(None),
    "branching:extract_structure.mask": _v(None),
    "branching:SynthesisParams.from_feature_size.s": _v(12.0),
    "branching:StructureModel.matcher.rng": _v(0),
    "dendrite:Dendrite.with_radius.radius": lambda: example("dendrite").radius * 0.5,
    "dendrite:PlanResult.as_image.values": lambda: np.arange(24 * 24, dtype=float),
    "dendrite:Rendering.save_svg.path": lambda: str(Path(tempfile.mkdtemp(prefix="fuzz")) / "r.svg"),
    "dendrite:Stylizer.lattice.p": _e("stylize_params"), "dendrite:Stylizer.plan.p": _e("stylize_params"),
    "dendrite:Stylizer.endpoints.p": _e("stylize_params"), "dendrite:Stylizer.dendrite.p": _e("stylize_params"),
    "dendrite:Stylizer.lattice.rng_seed": _v(0), "dendrite:Stylizer.plan.rng_seed": _v(0),
    "dendrite:Stylizer.endpoints.rng_seed": _v(0), "dendrite:Stylizer.dendrite.rng_seed": _v(0),
    "dendrite:Stylizer.plan.seed": _v((16.0, 2.0)), "dendrite:Stylizer.dendrite.seed": _v((16.0, 2.0)),
    "dendrite:place_endpoints.mask": _v(None),
    "strokes:Fetched.take.k": _v(0), "strokes:Fetched.source_pixels.k": _v(0), "strokes:Fetched.source_pixels.shape": _v((48, 96)),
    "strokes:SourceIndex.half_width.k": _v(0), "strokes:SourceIndex.radius.k": _v(0), "strokes:SourceIndex.radius.s": _v([1.0, 5.0]),
    "strokes:SourceIndex.edge_width.k": _v(0), "strokes:SourceIndex.edge_width.s": _v([1.0, 5.0]),
    "strokes:PlacedPatch.placed.canvas_shape": _v((24, 28)),
    "strokes:StrokePair.source_arc_length.s_target": _v([0.0, 5.0]),
    "strokes:StrokePair.with_control.source_points": _v([(30.0, 24.0)]),
    "strokes:StrokePair.with_control.target_points": _v([(40.0, 27.0)]),
    "strokes:compare_colours.result": lambda: importlib.import_module("branchnb.strokes").edit_structure(
        _band_rgba(), [_band_skeleton()], [_band_skeleton() + np.array([0, 3.0])], rng=0),
    "strokes:seam_mask.alpha": _v(None),
    "strokes:fetch.index": _e("source_index"),
    "trees:transfer_colour.source_cages": lambda: [example("exemplar").cage(20)] * 2,
    "trees:transfer_colour.target_cage": lambda: example("exemplar").cage(20),
    "trees:transfer_colour.target_mask": lambda: example("exemplar").normalized.image[..., 3] > 0.5,
    "trees:combine_shapes.weights": _v(np.array([0.5, 0.5])),
    "trees:Exemplar.with_trunk.trunk": lambda: np.zeros((128, 128), bool),
    "trees:TreeLibrary.set_trunk.trunk": lambda: np.zeros((128, 128), bool),
    "trees:TreeLibrary.variations_of.target": _v("a"), "trees:TreeLibrary.variation.weights": _v(None),
    "trees:make_variation.weights": _v(None),
    "trees:reference_from_scribbles.image": _v(None),
    "widgets:AnnotationModel.of_kind.kind": _v("polyline"), "widgets:AnnotationModel.nearest_vertex.xy": _v((1.0, 2.0)),
    "widgets:AnnotationModel.add_shape.kind": _v("polyline"), "widgets:AnnotationModel.add_shape.points": _v([(1.0, 1.0), (4.0, 4.0)]),
    "widgets:AnnotationModel.append_point.index": _v(0), "widgets:AnnotationModel.append_point.xy": _v((7.0, 8.0)),
    "widgets:AnnotationModel.set_closed.index": _v(0), "widgets:AnnotationModel.set_radius.index": _v(0),
    "widgets:AnnotationModel.set_radius.vertex": _v(0), "widgets:AnnotationModel.set_radius.radius": _v(2.0),
    "widgets:AnnotationModel.move_vertex.index": _v(0), "widgets:AnnotationModel.move_vertex.vertex": _v(0),
    "widgets:AnnotationModel.move_vertex.xy": _v((3.0, 3.0)), "widgets:AnnotationModel.remove_shape.index": _v(0),
    "widgets:AnnotationModel.load_json.text": lambda: example("annotation_model").to_json(),
    "widgets:AnnotationModel.from_json.text": lambda: example("annotation_model").to_json(),
    # ---- batch
    "batch:BatchSpec.job": _v("branching"), "batch:BatchSpec.count": _v(2),
    "batch:BatchSpec.from_dict.d": lambda: {"job": "branching", "count": 2, "seed": 0},
    "batch:get_job.name": _v("branching"), "batch:params_to_dict.params": lambda: importlib.import_module("branchnb.branching").SynthesisParams(),
    "batch:spec_from_params.job": _v("branching"), "batch:spec_from_params.count": _v(2),
    "batch:save_spec.spec": lambda: importlib.import_module("branchnb.batch").BatchSpec(job="branching", count=2),
    "batch:save_spec.path": lambda: str(Path(tempfile.mkdtemp(prefix="fuzz")) / "spec.json"),
    "batch:load_spec.path": lambda: str(importlib.import_module("branchnb.batch").save_spec(
        importlib.import_module("branchnb.batch").BatchSpec(job="branching", count=2), Path(tempfile.mkdtemp(prefix="fuzz")) / "spec.json")),
    "batch:read_manifest.path": lambda: str(Path(tempfile.mkdtemp(prefix="fuzz")) / "manifest.jsonl"),
    # ---- leaves (a 64 px procedural family; see _leaf_family)
    "leaves:Layer.name": _v("veins"), "leaves:Layer.from_dict.d": lambda: example("leaf_layer_set").layers[0].to_dict(),
    "leaves:LayerSet.get.name": _v("veins"), "leaves:LayerSet.remove.name": _v("spots"),
    "leaves:LayerSet.move.name": _v("spots"), "leaves:LayerSet.move.new_index": _v(0),
    "leaves:LayerSet.add.name": _v("new"), "leaves:LayerSet.add_scribble.name": _v("veins"),
    "leaves:LayerSet.add_scribble.points": _v([(20.0, 30.0), (30.0, 32.0)]),
    "leaves:LayerSet.from_dict.d": lambda: example("leaf_layer_set").to_dict(),
    "leaves:LayerSet.from_json.text": lambda: example("leaf_layer_set").to_json(),
    "leaves:Scribble.points": _v([(20.0, 30.0), (30.0, 32.0)]),
    "leaves:Scribble.from_dict.d": lambda: example("leaf_layer_set").layers[0].scribbles[0].to_dict(),
    "leaves:grow_layers.image": lambda: example("leaf_family")[0].image,
    "leaves:grow_layers.blade": lambda: example("leaf_family")[0].blade,
    "leaves:grow_layers.layer_set": _e("leaf_layer_set"),
    "leaves:simulate_scribbles.mask": lambda: example("leaf_family")[0].layers["veins"], "leaves:simulate_scribbles.n": _v(3),
    "leaves:LayerInduction.spatial.e": _v(1), "leaves:LeafAnalysis.overlay.e": _v(1), "leaves:LeafAnalysis.layer.name": _v("veins"),
    "leaves:analyze.exemplars": _e("leaf_family"), "leaves:analyze.training_index": _v(0), "leaves:analyze.layers": _leaf_masks,
    "leaves:analyze.registrations": lambda: list(example("leaf_analysis").registrations),
    "leaves:analyze.registration_params": _e("leaf_reg_params"),
    "leaves:generate.analysis": _e("leaf_analysis"), "leaves:generate.n": _v(1),
    "leaves:save_leaves.leaves": lambda: [example("leaf_generated")],
    "leaves:save_leaves.outdir": lambda: str(Path(tempfile.mkdtemp(prefix="fuzz")) / "leaves"),
    "leaves:Registration.forward.points": _v(np.array([(20.0, 30.0), (32.0, 32.0)])),
    "leaves:Registration.forward_jacobian.points": _v(np.array([(20.0, 30.0), (32.0, 32.0)])),
    "leaves:Registration.inverse.points": _v(np.array([(20.0, 30.0), (32.0, 32.0)])),
    "leaves:Registration.to_training.image_or_mask": lambda: example("leaf_family")[1].image,
    "leaves:Registration.from_training.image_or_mask": lambda: example("leaf_family")[0].blade,
    "leaves:ThinPlateSpline.identity.centres": _v(np.array([(0.0, 0.0), (1.0, 0.0), (0.0, 1.0)])),
    "leaves:ThinPlateSpline.fit.source": _v(np.array([(0.0, 0.0), (1.0, 0.0), (0.0, 1.0), (1.0, 1.0), (0.5, 0.4)])),
    "leaves:ThinPlateSpline.fit.target": _v(np.array([(0.1, 0.0), (1.1, 0.1), (0.0, 1.1), (1.2, 1.0), (0.5, 0.5)])),
    "leaves:ThinPlateSpline.jacobian.points": _v(np.array([(0.2, 0.3), (0.7, 0.5)])),
    "leaves:blade_mask.image": lambda: example("leaf_family")[0].image,
    "leaves:normalise_exemplars.exemplars": lambda: [leaf.image for leaf in example("leaf_family")[:2]],
    "leaves:warp_mask.registration": _e("leaf_registration"),
    "leaves:warp_mask.mask": lambda: example("leaf_family")[0].blade, "leaves:warp_mask.to_training": _v(True),
    "leaves:reference_veins.name": _v("maple_leaf_01"),
    "leaves:is_structural.layer": lambda: example("leaf_analysis").layer("veins"),
    "leaves:layer_warnings.analysis": _e("leaf_analysis"), "leaves:warn_analysis.analysis": _e("leaf_analysis"),
    "leaves:layer_standout.image": lambda: example("leaf_family")[0].image,
    "leaves:layer_standout.blade": lambda: example("leaf_family")[0].blade,
    "leaves:layer_standout.mask": lambda: example("leaf_family")[0].layers["veins"],
    "leaves:shadow_share.image": lambda: example("leaf_family")[0].image,
    "leaves:shadow_share.blade": lambda: example("leaf_family")[0].blade,
    "leaves:scribble_mask.scribbles": lambda: example("leaf_layer_set").layers[0].scribbles,
    "leaves:scribble_mask.shape": _v((64, 64)),
    # lambda 0: a non-structural layer, whose reach is inf by definition (so inf may appear in results)
    "leaves:spatial_reach.lam": _v(0.0), "leaves:spatial_reach.delta": _v(1.0),
    "leaves:split_petiole.blade": lambda: example("leaf_family")[0].blade,
    "leaves:leaf_exemplar.image": lambda: example("leaf_family")[0].image,
    "leaves:prepare_exemplars.images": lambda: [leaf.image for leaf in example("leaf_family")[:2]],
    "leaves:correct_texture.warped": lambda: _img(32, 32), "leaves:correct_texture.warp_map": _leaf_warp_map,
    "leaves:correct_texture.source_image": lambda: _img(32, 32, seed=1),
    "leaves:distorted_pixels.warp_map": _leaf_warp_map, "leaves:jacobian_singular_values.warp_map": _leaf_warp_map,
    "leaves:draw_registration.registration": _e("leaf_registration"),
    "leaves:draw_registration.exemplar_image": lambda: example("leaf_family")[1].image,
    "leaves:draw_registration.training_image": lambda: example("leaf_family")[0].image,
    "leaves:edge_keypoints.image": lambda: example("leaf_family")[0].image,
    "leaves:edge_keypoints.blade": lambda: example("leaf_family")[0].blade, "leaves:edge_keypoints.n_points": _v(20),
    "leaves:edge_strength.image": lambda: example("leaf_family")[0].image,
    "leaves:procedural_leaf.variation": _v(1.0), "leaves:leaf_family.variation": _v(1.0),
    "leaves:correct_texture.mask": _v(np.ones((32, 32), bool)), "leaves:distorted_pixels.mask": _v(np.ones((32, 32), bool)),
    "leaves:edge_strength.mask": lambda: example("leaf_family")[0].blade,
    "leaves:leaf_family.n": _v(2), "leaves:leaf_family.size": _v(64), "leaves:procedural_leaf.size": _v(64),
    "leaves:register.exemplar": lambda: example("leaf_family")[1].image,
    "leaves:register.training": lambda: example("leaf_family")[0].image,
    "leaves:register.exemplar_blade": lambda: example("leaf_family")[1].blade,
    "leaves:register.training_blade": lambda: example("leaf_family")[0].blade,
    "leaves:register.params": _e("leaf_reg_params"),
    "leaves:start_alignment.exemplar_blade": lambda: example("leaf_family")[1].blade,
    "leaves:start_alignment.training_blade": lambda: example("leaf_family")[0].blade,
    "leaves:start_alignment.rotation_step": _v(45.0),
    "leaves:start_candidates.exemplar_blade": lambda: example("leaf_family")[1].blade,
    "leaves:start_candidates.training_blade": lambda: example("leaf_family")[0].blade,
    "leaves:start_candidates.rotation_step": _v(45.0),
    "leaves:tps_rpm.source": lambda: example("leaf_family")[1].keypoints[:16] / 64.0,
    "leaves:tps_rpm.target": lambda: example("leaf_family")[0].keypoints[:16] / 64.0,
    "leaves:tps_rpm.params": _e("leaf_reg_params"),
    "widgets:AnnotationModel.observe.callback": _v(print), "widgets:AnnotationModel.unobserve.callback": _v(print),
}

#: Instances whose methods are fuzzed: class name -> example key.
INSTANCES = {
    "Structure": "structure", "Branch": lambda: example("structure").branches[1], "Dendrite": "dendrite",
    "GrownTree": "grown_tree", "PareidoliaTree": "pareidolia",
    "Lattice": "lattice", "PlanResult": "plan_result", "Stylizer": "stylizer", "TreeLibrary": "library",
    "Exemplar": "exemplar", "BillboardCloud": "cloud", "Variation": "variation", "Stroke": lambda: example("strokes")[0],
    "StrokePair": "pair", "SourceIndex": "source_index", "Fetched": "fetched", "EditPatches": "edit_patches",
    "PlacedPatch": lambda: example("placed")[0],
    "Guidance": "guidance", "StructureModel": "model", "AnnotationModel": "annotation_model",
    "TreeContour": lambda: example("exemplar").contour,
    "Shape": lambda: example("annotation_model").shapes[0], "Rendering": lambda: importlib.import_module("branchnb.dendrite").render_plain(example("dendrite")),
    "Patch": lambda: importlib.import_module("branchnb.core").transfer_patch(_img(), (12, 12), 0.0, (14, 10), 0.0, 4),
    "SynthesisParams": lambda: importlib.import_module("branchnb.branching").SynthesisParams(),
    # a class name several packages use: "package:Class" first
    "leaves:Exemplar": lambda: importlib.import_module("branchnb.leaves").leaf_exemplar(example("leaf_family")[0].image),
    "leaves:SynthesisParams": lambda: importlib.import_module("branchnb.leaves").SynthesisParams(),
    "Layer": lambda: example("leaf_layer_set").layers[0], "LayerSet": "leaf_layer_set",
    "Scribble": lambda: example("leaf_layer_set").layers[0].scribbles[0],
    "LeafAnalysis": "leaf_analysis", "LayerInduction": lambda: example("leaf_analysis").layers[0],
    "GeneratedLeaf": "leaf_generated", "ProceduralLeaf": lambda: example("leaf_family")[0],
    "Registration": "leaf_registration", "ThinPlateSpline": "leaf_tps",
}

#: Arguments never fuzzed: internal hooks. (``progress`` callbacks are: a string there must give a TypeError.)
SKIP_ARGS = {"_scorer", "self", "cls", "name"}
#: Targets the harness leaves alone (network, big downloads, or pure re-exports of callables).
SKIP_TARGETS = {"trees:TreeLibrary.from_data", "trees:evaluate_reference",
                # whole batch runs (dask workers) and the global job registry: tested by their own suite
                "batch:run_batch", "batch:register_job", "batch:Job",
                "widgets:AnnotationModel.unobserve", "widgets:AnnotationModel.set_radius",
                "branching:StructureModel.sample_length", "branching:StructureModel.matcher"}


def _instance(cls_name, package=None):
    spec = INSTANCES.get(f"{package}:{cls_name}", INSTANCES.get(cls_name))
    if spec is None:
        return None
    return copy.deepcopy(spec() if callable(spec) else example(spec))


def _listed(target: Target, pname: str) -> bool:
    """Whether ``ARGS`` lists an example for this argument (rather than a guess from its name)."""
    return f"{target.id}.{pname}" in ARGS or f"{target.qualname}.{pname}" in _by_qualname() or pname in ARGS


@functools.cache
def _by_qualname():
    return {k.split(":", 1)[1]: v for k, v in ARGS.items() if ":" in k}


def _arg_example(target: Target, pname: str, guess: bool = False):
    if f"{target.id}.{pname}" in ARGS:
        return True, ARGS[f"{target.id}.{pname}"]()
    if f"{target.qualname}.{pname}" in _by_qualname():  # the same class re-exported by another package
        return True, _by_qualname()[f"{target.qualname}.{pname}"]()
    if pname in ARGS:
        return True, ARGS[pname]()
    return _guess(pname) if guess else (False, None)


#: Examples guessed from an argument's name, so that names added later get a valid call too.
GUESSES = [
    (r"(^|_)(image|img|rgb|photo|exemplar_image|canvas)$", "image"), (r"(^|_)rgba$", "rgba"),
    (r"(^|_)(mask|region|alpha)$", "mask"), (r"(^|_)(points|polyline|path|contour|cage|polygon)$", "points"),
    (r"(^|_)polylines$", "polylines"), (r"(^|_)structure$", "structure"), (r"(^|_)dendrite$", "dendrite"),
    (r"(^|_)strokes$", "strokes"), (r"(^|_)library$", "library"),
]
_GUESS_VALUES = {"shape": (24, 28), "size": 32, "n": 3, "count": 3, "steps": 3, "seed": 0, "name": "a"}
GUESSED: set = set()


def _guess(pname: str):
    if pname in _GUESS_VALUES:
        GUESSED.add(pname)
        return True, copy.deepcopy(_GUESS_VALUES[pname])
    for pattern, key in GUESSES:
        if re.search(pattern, pname):
            GUESSED.add(pname)
            return True, copy.deepcopy(example(key))
    return False, None


def signature_of(target: Target):
    obj, meth = resolve(target)
    if target.kind == "method":
        attr = inspect.getattr_static(obj, meth)
        func = attr.__func__ if isinstance(attr, (classmethod, staticmethod)) else attr
        sig = inspect.signature(func)
        params = list(sig.parameters.values())
        if not isinstance(attr, staticmethod) and params:
            params = params[1:]
        return params, attr
    return list(inspect.signature(obj).parameters.values()), obj


def baseline(target: Target):
    """``(callable, args, kwargs, varargs_name)`` of a valid call, or raise LookupError."""
    obj, meth = resolve(target)
    params, attr = signature_of(target)
    args, kwargs, var = [], {}, None
    for p in params:
        if p.name in ("progress", "_scorer"):
            continue
        if p.kind is p.VAR_KEYWORD:
            continue
        if p.kind is p.VAR_POSITIONAL:
            found, val = _arg_example(target, p.name)
            if found:
                args.extend(val)
                var = p.name
            continue
        found, val = _arg_example(target, p.name, guess=p.default is p.empty)
        if not found:
            if p.default is not p.empty:
                continue
            if p.name == "params" or (isinstance(p.annotation, str) and "Params" in p.annotation):
                val = _default_params(p.annotation, target.package)
                if val is None:
                    raise LookupError(f"no example for {p.name}")
            else:
                raise LookupError(f"no example for required argument {p.name!r}")
        if p.kind is p.POSITIONAL_ONLY:
            args.append(val)
        else:
            kwargs[p.name] = val
    if target.kind == "method":
        if isinstance(attr, (classmethod, staticmethod)):
            fn = getattr(obj, meth)
        else:
            inst = _instance(obj.__name__, target.package)
            if inst is None:
                raise LookupError(f"no example instance of {obj.__name__}")
            fn = getattr(inst, meth)
    else:
        fn = obj
    return fn, args, kwargs, var


def _default_params(annotation, package=None):
    """Default parameters named by ``annotation``, from the target's own package first
    (several packages have a ``SynthesisParams``)."""
    if not isinstance(annotation, str):
        return None
    m = re.search(r"(\w+Params)", annotation)
    if not m:
        return None
    for pkg in ([package] if package else []) + packages():
        mod = importlib.import_module(f"branchnb.{pkg}")
        if hasattr(mod, m.group(1)):
            return getattr(mod, m.group(1))()
    return None


# ============================================================================================ bad values
@dataclasses.dataclass(frozen=True)
class Case:
    target: str  # Target.id
    arg: str  # argument name, "params.field" for a dataclass field, "" for the valid call
    kind: str  # family of the bad value
    value: object = None

    def __repr__(self):
        v = self.value
        if isinstance(v, np.ndarray):
            text = f"array{np.shape(v)} {np.asarray(v).dtype}"
        elif isinstance(v, int) and v.bit_length() > 64:
            text = f"int of {v.bit_length()} bits"
        else:
            text = repr(v)[:60]
        return f"Case({self.target}, {self.arg or '<valid>'}, {self.kind}: {text})"


class _Cyclic:
    """Marker resolved to a structure whose parents form a cycle (built in the worker)."""

    def __repr__(self):
        return "<structure with a parent cycle>"


@dataclasses.dataclass(frozen=True)
class _Made:
    """Marker resolved in the worker to ``EXTRA_MAKERS[key]()``: a bad value that needs building."""

    key: str

    def __repr__(self):
        return f"<{self.key}>"


def _other_plan():
    from branchnb.dendrite import make_lattice, plan

    return plan(make_lattice(np.zeros((12, 12)), rng=0), (6, 6))


def _nan_lattice():
    from branchnb.dendrite import make_lattice

    lat = make_lattice(np.zeros((16, 16)), rng=0)
    lat.weights[3, 3] = NAN  # changed after the Lattice checked it, as a caller could
    return lat


def _layer_set_with(change: str):
    ls = copy.deepcopy(example("leaf_layer_set"))
    stroke = copy.deepcopy(ls.layers[0].scribbles[0])
    if change == "two layers":
        ls.layers[1].scribbles.append(stroke)
    elif change == "background":
        ls.background.append(stroke)
    else:
        ls.layers[0].scribbles[0].radius = 1e5  # changed after the Scribble checked it
    return ls


def _two_leaves():
    fam = example("leaf_family")
    return [np.concatenate([fam[0].image, fam[1].image], axis=1), fam[1].image, fam[2].image]


#: Builders of the bad values below (run in the worker, so they need not pickle).
EXTRA_MAKERS = {
    "another lattice's plan": _other_plan,
    "lattice with a NaN weight": _nan_lattice,
    "one stroke in two layers": lambda: _layer_set_with("two layers"),
    "one stroke in a layer and the background": lambda: _layer_set_with("background"),
    "scribble radius 1e5": lambda: _layer_set_with("radius"),
    "two leaves in one exemplar": _two_leaves,
    "layer named blade": lambda: {"blade": _leaf_masks()["veins"]},
    "layer with an empty name": lambda: {"": _leaf_masks()["veins"]},
}

#: Arguments with which an infinite result is the documented answer, not garbage.
NONFINITE_BY_CONTRACT = {
    "dendrite:plan.stop_at": "planning stops at these nodes: the nodes not reached cost inf",
}

#: Bad values one argument's family cannot make: valid objects that do not fit together (issue 27, items 4-5).
EXTRA_BAD = {
    "dendrite:path_statistics.plan_result": ["another lattice's plan"],
    "dendrite:plan.graph": ["lattice with a NaN weight"],
    "leaves:grow_layers.layer_set": ["one stroke in two layers", "one stroke in a layer and the background",
                                     "scribble radius 1e5"],
    "leaves:analyze.exemplars": ["two leaves in one exemplar"],
    "leaves:analyze.layers": ["layer named blade", "layer with an empty name"],
}


def array_variants(a: np.ndarray) -> list[tuple[str, object]]:
    a = np.asarray(a)
    out = []
    if a.dtype.kind in "fc":
        nan = a.astype(np.float64).copy()
        nan.flat[0] = NAN
        out.append(("nan", nan))
        inf = a.astype(np.float64).copy()
        inf.flat[-1] = INF
        out.append(("inf", inf))
        out.append(("huge", a.astype(np.float64) * 1e300 + 1e300))
        out.append(("negative", -np.abs(a.astype(np.float64)) - 1.0))
        out.append(("all inf", np.full(a.shape, INF)))
        if a.size >= 2:  # a span that overflows float64 (max - min = inf)
            out.append(("+-1e308", np.where(np.arange(a.size).reshape(a.shape) % 2 == 0, -1e308, 1e308)))
    out.append(("empty", a[:0]))
    if a.ndim >= 1 and len(a) >= 2:  # one row fewer than its siblings (a0/a1, p/q, points/values)
        out.append(("one shorter", a[:-1].copy()))
    if a.ndim >= 2:
        out.append(("1x1", a[:1, :1].copy()))
        out.append(("1-D", a.reshape(-1)[:5].copy()))
    if a.ndim >= 1:
        out.append(("scalar", np.asarray(a.reshape(-1)[0]).copy() if a.size else np.float64(0.5)))
        out.append(("extra axis", a[..., None, None].copy()))
    if a.ndim == 3:
        out.append(("5 channels", np.concatenate([a, a[..., :2]], axis=2)))
    out.append(("complex", a.astype(np.complex128) + 1j))
    out.append(("strings", a.astype(str)))
    out.append(("object", a.astype(object)))
    if a.dtype != bool:
        out.append(("int8", (a * 10).astype(np.int8)))
    return out


def bad_values(example_value, default) -> list[tuple[str, object]]:
    """Bad and edge-case values of the same family as ``example_value`` (or ``default``)."""
    v = example_value
    common = [("None", None), ("string", "bogus"), ("complex", 1 + 2j)]
    from branchnb.core import Structure

    if isinstance(v, Structure):
        return [("parent cycle", _Cyclic()), ("empty structure", Structure([])), ("string", "bogus"), ("None", None),
                ("far points", _far_structure())]
    if isinstance(v, (bool, np.bool_)):
        return [("string", "yes"), ("int 2", 2), ("None", None), ("nan", NAN)]
    if isinstance(v, (int, np.integer)):
        return [("negative", -1), ("zero", 0), ("huge", 10**9), ("int64 overflow", 2**63), ("fraction", 1.5),
                ("nan", NAN), ("inf", INF), ("bool", True), ("string", "3"), ("None", None),
                ("5000 digits", 10**5000)]
    if isinstance(v, (float, np.floating)):
        return [("nan", NAN), ("inf", INF), ("-inf", -INF), ("huge", 1e300), ("tiny", 1e-300), ("negative", -1.0),
                ("zero", 0.0), ("string", "1.0"), ("None", None), ("complex", 1j), ("bool", True)]
    if isinstance(v, str):
        return [("unknown string", "bogus-value"), ("empty string", ""), ("int", 3), ("None", None)]
    if isinstance(v, np.random.Generator):
        return [("negative seed", -1), ("string", "0"), ("float", 1.5), ("RandomState", np.random.RandomState(0)),
                ("5000-digit seed", 10**5000)]
    if isinstance(v, np.ndarray):
        return array_variants(v) + common[:2]
    if isinstance(v, (list, tuple)):
        out = [("empty", type(v)()), ("None", None), ("string", "bogus"), ("int", 5)]
        if v and all(dataclasses.is_dataclass(x) and not isinstance(x, type) for x in v):
            first = dataclasses.fields(v[0])[0].name      # a dict of the first field only (the rest missing)
            out.append(("incomplete dicts", [{first: copy.deepcopy(getattr(v[0], first))}]))
        try:
            a = np.asarray(v, dtype=float)
        except (TypeError, ValueError):
            a = None
        if a is not None and a.size:
            if a.ndim == 1 and len(v) in (2, 3, 4):  # a shape, a point or a colour
                out += [("nan entry", type(v)([NAN] + list(v[1:]))), ("inf entry", type(v)([INF] + list(v[1:]))),
                        ("huge entries", type(v)([1e9] * len(v))), ("negative entries", type(v)([-5] * len(v))),
                        ("zero entries", type(v)([0] * len(v))), ("too short", type(v)(v[:1])),
                        ("strings", type(v)(["a"] * len(v))), ("above one", type(v)([2.0] * len(v)))]
            else:
                out += [(k, val) for k, val in array_variants(a)
                        if k in ("nan", "inf", "huge", "1x1", "strings", "complex", "one shorter")]
                out.append(("far point", [np.array([(0.0, 5.0), (0.0, 1e20)])] + list(v[1:])))
        elif v and all(isinstance(x, (np.ndarray, list, tuple)) for x in v):
            first = np.asarray(v[0], dtype=float) if _numeric(v[0]) else None
            if first is not None and first.ndim == 2:
                out += [("nan point", [np.where(np.arange(first.size).reshape(first.shape) == 0, NAN, first)] + list(v[1:])),
                        ("far point", [np.array([(0.0, 5.0), (0.0, 1e20)])] + list(v[1:])),
                        ("3 columns", [np.zeros((3, 3))] + list(v[1:])), ("empty item", [np.zeros((0, 2))] + list(v[1:]))]
        return out
    if isinstance(v, dict):
        return [("None", None), ("string", "bogus"), ("list", [1, 2])]
    if v is None:
        return [("nan", NAN), ("inf", INF), ("negative", -1), ("string", "bogus"), ("huge", 10**12),
                ("complex array", np.ones((3, 2)) * 1j), ("nan array", np.full((4, 4), NAN)), ("int", 5),
                ("nan edges", np.array([0.0, NAN, 1.0]))]
    return [("None", None), ("string", "bogus"), ("int", 0)]


def _numeric(x) -> bool:
    try:
        np.asarray(x, dtype=float)
        return True
    except (TypeError, ValueError):
        return False


def _far_structure():
    from branchnb.core import Branch, Structure

    s = Structure([Branch([(0.0, 5.0), (0.0, 10.0)], 1.0)])
    s.branches[0].points[1, 1] = 1e20  # mutated after validation, as a caller could
    return s


def field_bad_values(field: dataclasses.Field) -> list[tuple[str, object]]:
    meta = field.metadata or {}
    default = field.default if field.default is not dataclasses.MISSING else None
    out = [("string", "bogus"), ("None", None), ("nan", NAN)]
    lo, hi = meta.get("min"), meta.get("max")
    if isinstance(default, bool):
        return [("string", "yes"), ("None", None), ("int 2", 2)]
    if isinstance(default, (int, float)) and not isinstance(default, bool):
        if lo is not None:
            out.append(("below min", lo - (1 if isinstance(default, int) else max(abs(lo) * 0.5, 1e-3))))
        if hi is not None:
            out.append(("above max", hi * 10 + 10))
        out.append(("inf", INF))
        if isinstance(default, int):
            out.append(("fraction", 1.5))
    if meta.get("options"):
        out.append(("not an option", "bogus-option"))
    return out


def cases_for(target: Target, *, valid: bool = True) -> list[Case]:
    """Every case of one target (the valid call first)."""
    if target.id in SKIP_TARGETS:
        return []
    out = [Case(target.id, "", "valid")] if valid else []
    obj, meth = resolve(target)
    if target.kind == "params":
        for f in dataclasses.fields(obj):
            for kind, val in field_bad_values(f):
                out.append(Case(target.id, f"params.{f.name}", kind, val))
        return out
    if target.kind == "class" and _is_container(obj):
        return []  # plain result data, built by the library; its methods are fuzzed on an example instance
    if target.kind == "method" and not isinstance(inspect.getattr_static(obj, meth), (classmethod, staticmethod)) \
            and obj.__name__ not in INSTANCES and f"{target.package}:{obj.__name__}" not in INSTANCES:
        return []
    try:
        fn, args, kwargs, var = baseline(target)
    except (LookupError, ValueError, TypeError) as exc:  # no example, or no inspectable signature
        if isinstance(exc, LookupError) or "signature" in str(exc):
            return [Case(target.id, "", "no example")]
        return [Case(target.id, "", f"example failed: {type(exc).__name__}: {exc}"[:200])]
    except Exception as exc:  # the example itself failed: report as such
        return [Case(target.id, "", f"example failed: {type(exc).__name__}: {exc}"[:200])]
    params, _ = signature_of(target)
    for p in params:
        if p.name in SKIP_ARGS:
            continue
        if p.kind is p.VAR_KEYWORD:  # a misspelt keyword must be named, not end in a dataclass TypeError
            out.append(Case(target.id, f"**{p.name}", "unknown keyword", {"bogus_keyword": 1}))
            continue
        if p.kind is p.VAR_POSITIONAL:
            if var:
                for kind, val in [("empty", ()), ("nan sample", ([NAN, 1.0],)), ("string sample", ("abc",)),
                                  ("complex sample", ([1j, 2],)), ("+-1e308 sample", ([-1e308, 1e308],))]:
                    out.append(Case(target.id, p.name, kind, val))
            continue
        if p.name in kwargs:
            ex = kwargs[p.name]
        elif p.default is not p.empty:
            ex = p.default
        else:
            continue
        for kind in EXTRA_BAD.get(f"{target.id}.{p.name}", ()):
            out.append(Case(target.id, p.name, kind, _Made(kind)))
        if dataclasses.is_dataclass(ex) and _is_params(type(ex)):
            for f in dataclasses.fields(ex):
                for kind, val in field_bad_values(f):
                    out.append(Case(target.id, f"{p.name}.{f.name}", kind, val))
            continue
        if ex is None and isinstance(p.annotation, str) and "Params" in p.annotation:
            dp = _default_params(p.annotation, target.package)
            if dp is not None:
                for f in dataclasses.fields(dp):
                    for kind, val in field_bad_values(f):
                        out.append(Case(target.id, f"{p.name}.{f.name}", kind, val))
                continue
        for kind, val in bad_values(ex, p.default):
            out.append(Case(target.id, p.name, kind, val))
    return out


# ================================================================================================ oracle
@dataclasses.dataclass
class Outcome:
    case: Case
    status: str  # "ok", "raised", "fail"
    detail: str = ""
    seconds: float = 0.0

    @property
    def failed(self) -> bool:
        return self.status == "fail"


def _walk_arrays(obj, depth=0, seen=None):
    """Float arrays and floats reachable from a result (dataclass fields, lists, dicts, attributes)."""
    if seen is None:
        seen = set()
    if depth > 4 or id(obj) in seen:
        return
    seen.add(id(obj))
    if isinstance(obj, np.ndarray):
        if obj.dtype.kind in "fc":
            yield obj
        elif obj.dtype == object and obj.size < 10_000:
            for x in obj.flat:
                yield from _walk_arrays(x, depth + 1, seen)
        return
    if isinstance(obj, (float, np.floating)):
        yield np.asarray(obj)
        return
    if isinstance(obj, (list, tuple)):
        for x in obj[:2000]:
            yield from _walk_arrays(x, depth + 1, seen)
        return
    if isinstance(obj, dict):
        for x in list(obj.values())[:2000]:
            yield from _walk_arrays(x, depth + 1, seen)
        return
    if dataclasses.is_dataclass(obj) and not isinstance(obj, type):
        for f in dataclasses.fields(obj):
            yield from _walk_arrays(getattr(obj, f.name, None), depth + 1, seen)
        return
    if type(obj).__module__.startswith("branchnb") and hasattr(obj, "__dict__"):
        for k, x in vars(obj).items():
            if not k.startswith("_"):
                yield from _walk_arrays(x, depth + 1, seen)


def nonfinite(result, *, nan_only: bool = False) -> bool:
    for a in _walk_arrays(result):
        if a.size and (np.isnan(a).any() if nan_only else not np.all(np.isfinite(a))):
            return True
    return False


def _has_inf(value) -> bool:
    """Whether a bad value carries inf (then inf, but not NaN, may pass through to the result)."""
    try:
        return any(a.size and np.isinf(a).any() for a in _walk_arrays(value))
    except TypeError:
        return False


_NUMBER = re.compile(r"(?<![\w#])[-+]?(?:\d+\.?\d*|\.\d+)(?:[eE][-+]?\d+)?|\b(?:nan|inf|NaN|Infinity)\b")


def check_text(text: str, what: str) -> str:
    """'' if ``text`` is a valid document of its kind (SVG/XML, strict JSON), else the problem."""
    s = text.lstrip()
    if s.startswith("<svg") or s.startswith("<?xml"):
        try:
            ET.fromstring(s)
        except ET.ParseError as exc:
            return f"{what} is not well-formed XML: {exc}"
        if re.search(r'="[^"]*\b(nan|inf|NaN|Infinity)\b', s):
            return f"{what} holds a non-finite number"
        return ""
    if s[:1] and s[:1] in "{[":
        try:
            json.loads(s, parse_constant=lambda t: (_ for _ in ()).throw(ValueError(t)))
        except ValueError as exc:
            return f"{what} is not strict JSON: {exc}"
    return ""


def check_file(path: Path) -> str:
    suffix = path.suffix.lower()
    try:
        if suffix in (".json", ".gltf", ".svg"):
            return check_text(path.read_text(), str(path.name))
        if suffix == ".obj":
            for line in path.read_text().splitlines():
                if line[:2] in ("v ", "vt", "vn") and re.search(r"\b(nan|inf)\b", line, re.I):
                    return f"{path.name} has a non-finite vertex: {line[:60]}"
        if suffix == ".png":
            import cv2

            if cv2.imread(str(path), cv2.IMREAD_UNCHANGED) is None:
                return f"{path.name} is not a readable PNG"
    except UnicodeDecodeError:
        return f"{path.name} is not text"
    return ""


def _result_problem(result, allow_nonfinite: bool, out_dir: Path | None, inf_given: bool = False) -> str:
    if not allow_nonfinite and nonfinite(result, nan_only=inf_given):
        return "result holds NaN" if inf_given else "result holds NaN/inf"
    if isinstance(result, str):
        return check_text(result, "returned text")
    for obj in (result, getattr(result, "svg", None)):
        if isinstance(obj, str):
            p = check_text(obj, "returned SVG")
            if p:
                return p
    if isinstance(result, (str, Path)) and Path(result).is_file():
        return check_file(Path(result))
    if out_dir is not None and out_dir.is_dir():
        for f in out_dir.rglob("*"):
            if f.is_file():
                p = check_file(f)
                if p:
                    return p
    return ""


def _names_argument(message: str, arg: str) -> bool:
    msg = message.lower()
    keys = {arg.lower(), arg.split(".")[-1].lower()}
    return any(k and k in msg for k in keys)


# ================================================================================================ worker
def _prepare(case: Case):
    target = next(t for t in _all_targets() if t.id == case.target)
    obj, _ = resolve(target)
    value = case.value
    if isinstance(value, _Cyclic):
        value = _cyclic_structure()
    if isinstance(value, _Made):
        value = EXTRA_MAKERS[value.key]()
    if target.kind == "params":
        field = case.arg.split(".", 1)[1] if case.arg else None
        if field is None:
            from branchnb.core.params import check_params
            return (lambda: check_params(obj())), None

        def run():
            from branchnb.core.params import check_params
            inst = obj()
            object.__setattr__(inst, field, value)
            return check_params(inst)
        return run, None
    fn, args, kwargs, var = baseline(target)
    out_dir = None
    for k, v in kwargs.items():
        if k == "path" or str(v).startswith(tempfile.gettempdir() + "/fuzz"):
            out_dir = Path(str(v)).parent
    if case.arg.startswith("**"):
        kwargs.update(value)
    elif case.arg:
        head, _, field = case.arg.partition(".")
        if field:
            params = kwargs.get(head)
            if params is None:
                p = dict((q.name, q) for q in signature_of(target)[0])[head]
                params = _default_params(p.annotation, target.package)
            params = copy.copy(params)
            object.__setattr__(params, field, value)
            kwargs[head] = params
        elif head == var:
            args = list(value)
        else:
            kwargs[head] = value
    return (lambda: fn(*args, **kwargs)), out_dir


@functools.cache
def _all_targets():
    return tuple(discover())


def run_case(case: Case, allow_nonfinite: bool = False) -> tuple[str, str]:
    """Run one case in this process; ``(status, detail)``."""
    try:
        import numpy.exceptions as npe

        complex_warning = npe.ComplexWarning
    except ImportError:  # pragma: no cover - numpy < 1.25
        complex_warning = np.ComplexWarning
    try:
        call, out_dir = _prepare(case)
    except Exception as exc:
        return "fail", f"harness could not build the call: {type(exc).__name__}: {exc}"
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")
        warnings.simplefilter("error", complex_warning)
        try:
            result = call()
        except (ValueError, TypeError) as exc:
            if case.kind == "valid":
                return "fail", f"valid call raised {type(exc).__name__}: {exc}"
            msg = str(exc)
            arg = case.arg.split(".")[-1] if "." in case.arg else case.arg
            if case.arg.startswith("**"):
                arg = "bogus_keyword"
            if not _names_argument(msg, arg):
                return "fail", f"{type(exc).__name__} does not name {arg!r}: {msg[:200]}"
            return "raised", f"{type(exc).__name__}: {msg[:200]}"
        except Exception as exc:
            tb = traceback.extract_tb(exc.__traceback__)[-1]
            return "fail", f"{type(exc).__name__}: {str(exc)[:200]} (at {Path(tb.filename).name}:{tb.lineno})"
    if case.kind == "valid":
        return "ok", "nonfinite" if nonfinite(result) else ""
    problem = _result_problem(result, allow_nonfinite, out_dir, _has_inf(case.value))
    if problem:
        return "fail", f"accepted and {problem}"
    return "ok", ""


def _worker(conn):
    os.environ.setdefault("OMP_NUM_THREADS", "1")
    # A bad path argument (a plain string) must not write into the checkout: work in a temp folder.
    os.chdir(tempfile.mkdtemp(prefix="fuzz-cwd"))
    while True:
        try:
            msg = conn.recv()
        except EOFError:
            return
        if msg is None:
            return
        case, allow = msg
        try:
            conn.send(run_case(case, allow))
        except Exception as exc:  # pragma: no cover - unpicklable detail
            conn.send(("fail", f"worker error {exc!r}"))


class Pool:
    """One forked worker that runs cases with a time limit and is replaced after a crash or hang."""

    def __init__(self, timeout: float = 20.0):
        self.timeout = timeout
        self.ctx = mp.get_context("fork")
        self.proc = None
        self.conn = None
        self.allow = {}

    def _start(self):
        parent, child = self.ctx.Pipe()
        self.proc = self.ctx.Process(target=_worker, args=(child,), daemon=True)
        self.proc.start()
        child.close()
        self.conn = parent

    def _stop(self):
        if self.proc is not None:
            if self.proc.is_alive():
                self.proc.kill()
            self.proc.join(5)
        self.proc = None

    def close(self):
        if self.proc is not None and self.proc.is_alive():
            try:
                self.conn.send(None)
            except OSError:
                pass
        self._stop()

    def run(self, case: Case) -> Outcome:
        if case.kind == "valid":
            allow = False
        else:
            if case.target not in self.allow:
                self.run(Case(case.target, "", "valid"))
            allow = self.allow.get(case.target, False) or f"{case.target}.{case.arg}" in NONFINITE_BY_CONTRACT
        if case.kind == "no example" or case.kind.startswith("example failed"):
            return Outcome(case, "fail", case.kind)
        if self.proc is None or not self.proc.is_alive():
            self._start()
        t0 = time.perf_counter()
        try:
            self.conn.send((case, allow))
            ready = self.conn.poll(self.timeout)
        except (BrokenPipeError, OSError):
            ready = False
        dt = time.perf_counter() - t0
        if not ready:
            alive = self.proc.is_alive()
            code = self.proc.exitcode
            self._stop()
            if alive:
                out = Outcome(case, "fail", f"no answer within {self.timeout:.0f} s (hang or runaway size)", dt)
            else:
                out = Outcome(case, "fail", f"process crashed (exit code {code})", dt)
        else:
            try:
                status, detail = self.conn.recv()
            except EOFError:
                code = self.proc.exitcode
                self._stop()
                status, detail = "fail", f"process crashed (exit code {code})"
            out = Outcome(case, status, detail, dt)
        if case.kind == "valid":
            self.allow[case.target] = out.detail == "nonfinite"
        return out


# ================================================================================================== sweep
def all_cases(pkgs=None) -> dict[str, list[Case]]:
    by_pkg: dict[str, list[Case]] = {}
    for t in discover(pkgs):
        by_pkg.setdefault(t.package, []).extend(cases_for(t))
    return by_pkg


def sweep(pkgs=None, *, timeout=20.0, limit=None, verbose=False, out=sys.stdout, valid_only=False):
    by_pkg = all_cases(pkgs)
    if valid_only:
        by_pkg = {k: [c for c in v if c.arg == ""] for k, v in by_pkg.items()}
    pool = Pool(timeout)
    table, failures = {}, []
    try:
        for pkg, cases in by_pkg.items():
            n = fails = 0
            classes: dict[str, int] = {}
            for case in cases[:limit]:
                o = pool.run(case)
                n += 1
                if o.failed:
                    fails += 1
                    failures.append(o)
                    cls = _failure_class(o.detail)
                    classes[cls] = classes.get(cls, 0) + 1
                    if verbose:
                        print(f"FAIL {case!r}: {o.detail}", file=out, flush=True)
            table[pkg] = (n, fails, classes)
            print(f"{pkg:10s} cases {n:5d} failures {fails:4d} {classes}", file=out, flush=True)
    finally:
        pool.close()
    return table, failures


def _failure_class(detail: str) -> str:
    if detail.startswith("process crashed"):
        return "crash"
    if detail.startswith("no answer"):
        return "hang"
    if detail.startswith("accepted"):
        return "accepted bad input"
    if "does not name" in detail:
        return "unnamed error"
    if detail.startswith("valid call") or detail.startswith("no example") or detail.startswith("example failed"):
        return "harness/example"
    return "deep error"


def main(argv=None):
    import argparse

    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("packages", nargs="*", help="subpackages (default: all)")
    ap.add_argument("--timeout", type=float, default=20.0)
    ap.add_argument("--limit", type=int, default=None, help="cases per package")
    ap.add_argument("-v", "--verbose", action="store_true")
    ap.add_argument("--json", help="write failures to this JSON file")
    ap.add_argument("--valid-only", action="store_true", help="only the valid example calls")
    a = ap.parse_args(argv)
    table, failures = sweep(a.packages or None, timeout=a.timeout, limit=a.limit, verbose=a.verbose,
                            valid_only=a.valid_only)
    total = sum(v[0] for v in table.values()), sum(v[1] for v in table.values())
    print(f"{'total':10s} cases {total[0]:5d} failures {total[1]:4d}")
    if a.json:
        Path(a.json).write_text(json.dumps([{"case": repr(o.case), "detail": o.detail} for o in failures], indent=1))


if __name__ == "__main__":
    main()

