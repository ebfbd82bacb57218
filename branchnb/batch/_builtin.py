"""The technique jobs: tree variations, billboard clouds, dendrite trees, branching structures.

Each job's heavy input (a processed tree library, a fitted structure model)
is built once by ``prepare`` on the client and scattered to the workers;
``make`` computes one item from it. Technique modules are imported inside
the functions, so ``import branchnb.batch`` stays light.
"""

from __future__ import annotations

import json
import tempfile
from pathlib import Path

import numpy as np

from ..branching.image_synthesis import ImageSynthesisParams
from ..branching.params import SynthesisParams
from ..dendrite.trees import TreeParams
from ..trees.billboard import BillboardParams
from ..trees.variations import VariationParams
from .jobs import ItemOutput, Job, register_job, resolve_path

_IMAGE_SUFFIXES = (".png", ".jpg", ".jpeg", ".tif", ".tiff", ".webp")


def _round(values, digits: int = 6) -> list[float]:
    return [round(float(v), digits) for v in np.asarray(values, float).ravel()]


# ----------------------------------------------------------------------------- inputs


def _image_sources(value, base_dir, *, name: str, default) -> list[tuple[str, Path | str]]:
    """``(label, source)`` of every image: a folder, a file, a sample name, or a list of those."""
    from .. import data

    if value is None:
        value = list(default)
    entries = [value] if isinstance(value, str) else value
    if not isinstance(entries, list) or not entries:
        raise ValueError(f"inputs.{name} must be a folder, a file, a sample name or a non-empty list of them")
    out = []
    for e in entries:
        if not isinstance(e, str) or not e:
            raise ValueError(f"inputs.{name}: entries must be non-empty strings, got {e!r}")
        p = resolve_path(e, base_dir, name=name)
        if p.is_dir():
            files = sorted(f for f in p.iterdir() if f.suffix.lower() in _IMAGE_SUFFIXES)
            if not files:
                raise ValueError(f"inputs.{name}: folder {str(p)!r} holds no images ({', '.join(_IMAGE_SUFFIXES)})")
            out += [(f.stem, f) for f in files]
        elif p.is_file():
            out.append((p.stem, p))
        elif e in data.names():
            out.append((e, e))
        else:
            raise ValueError(f"inputs.{name}: {e!r} is neither a file or folder (from {base_dir or '.'}) "
                             "nor a sample name (branchnb.data.names())")
    labels = [lab for lab, _ in out]
    dup = sorted({lab for lab in labels if labels.count(lab) > 1})
    if dup:
        raise ValueError(f"inputs.{name}: several images are called {dup}; rename them")
    from ..core.io import check_image_file

    for _, src in out:  # every header before any pixel: a hostile file is refused before the others decode
        if not isinstance(src, str):
            try:
                check_image_file(src)
            except ValueError as exc:
                raise ValueError(f"inputs.{name}: {exc}") from None
    return out


def _load(source) -> np.ndarray:
    from .. import data
    from ..core.io import imread

    return data.load(source) if isinstance(source, str) else imread(source)


def _library(inputs, base_dir, params=None):
    from ..trees.variations import RPG_TREES, TreeLibrary

    size = inputs["size"]
    if isinstance(size, bool) or not isinstance(size, int):
        raise ValueError(f"inputs.size must be an int, got {size!r}")
    lib = TreeLibrary(size=size, trunk=inputs["trunk"])
    for label, src in _image_sources(inputs["library"], base_dir, name="library", default=RPG_TREES):
        try:
            lib.add(_load(src), label)
        except ValueError as exc:
            raise ValueError(f"inputs.library: tree {label!r}: {exc}") from None
    return lib


# ----------------------------------------------------------------------------- tree variations


def _variation(lib, p: VariationParams, inputs, rng):
    from ..trees.variations import make_variation, tree_variations

    if inputs["target"] is not None:
        return tree_variations(lib, inputs["target"], 1, p, use=inputs["use"], rng=rng,
                               reference=inputs["reference"])[0]
    return make_variation(lib, inputs["weights"], p, use=inputs["use"], rng=rng,
                          reference=inputs["reference"])


def _variation_info(v) -> dict:
    return {"names": list(v.names), "weights": _round(v.weights), "colour_weights": _round(v.colour_weights),
            "reference": v.reference}


def _make_tree(lib, params, inputs, rng, stem) -> ItemOutput:
    from ..core.io import encode_png

    v = _variation(lib, params["variation"], inputs, rng)
    return ItemOutput({f"{stem}.png": encode_png(v.image)}, _variation_info(v))


_TREE_INPUTS = {"library": None, "size": 512, "trunk": "auto", "target": None, "weights": None,
                "use": None, "reference": None}
_TREE_ITEM_INPUTS = ("target", "weights", "use", "reference")

def _unused_tree(given: dict, sections: set) -> dict:
    if given.get("target") is not None and given.get("weights") is not None:
        return {"weights": "a 'target' is given, and variations of a target draw their own weights"}
    return {}


register_job(Job(
    "tree_variations", sections={"variation": VariationParams}, inputs=_TREE_INPUTS,
    item_inputs=_TREE_ITEM_INPUTS, prepare=_library, make=_make_tree, stem="tree", unused=_unused_tree,
    description="new RGBA tree billboards from a library of RGBA exemplars (random mixes, fixed weights, "
                "or variations of one target tree keeping its share 'keep')"))


# ----------------------------------------------------------------------------- billboard clouds


def _prepare_clouds(inputs, base_dir, params):
    if inputs["from_variations"]:
        return {"library": _library(inputs, base_dir)}
    from ..trees.variations import RPG_TREES

    srcs = _image_sources(inputs["library"], base_dir, name="library", default=RPG_TREES)
    return {"images": [(label, _load(src)) for label, src in srcs]}


def _make_cloud(shared, params, inputs, rng, stem) -> ItemOutput:
    from ..core.io import encode_png
    from ..trees.billboard import billboard_cloud
    from ..trees.export import export_gltf
    from ..trees.preview import render_views

    info = {}
    if "library" in shared:
        v = _variation(shared["library"], params["variation"], inputs, rng)
        image, info = v.image, _variation_info(v)
    else:
        i = inputs["image"]
        images = shared["images"]
        if i is None:
            i = int(rng.integers(len(images)))
        if isinstance(i, bool) or not isinstance(i, int) or not -len(images) <= i < len(images):
            raise ValueError(f"inputs.image must be an index into the {len(images)} library images, got {i!r}")
        label, image = images[i]
        info = {"image": label}
    cloud = billboard_cloud(image, params=params["billboard"], rng=rng)
    info["billboards"] = cloud.counts()
    lod = inputs["lod"]
    if lod not in (None, "msft_lod", "files"):
        raise ValueError(f"inputs.lod must be null, 'msft_lod' or 'files', got {lod!r}")
    with tempfile.TemporaryDirectory() as tmp:
        if lod is None:
            gltf = export_gltf(cloud, Path(tmp) / f"{stem}.gltf", height=float(inputs["height"]),
                               yaw=float(inputs["yaw"]), embed_texture=bool(inputs["embed_texture"]))
        else:
            from ..trees.lod import export_lod_gltf, lod_chain

            gltf = export_lod_gltf(cloud, Path(tmp) / f"{stem}.gltf", mode=lod,
                                   height=float(inputs["height"]), yaw=float(inputs["yaw"]))[0]
            info["lod_triangles"] = {lv.name: lv.triangles for lv in lod_chain(cloud)}
        files = {f.name: f.read_bytes() for f in sorted(gltf.parent.iterdir())}
    if inputs["preview"]:
        files[f"{stem}_preview.png"] = encode_png(render_views(cloud, (0.0, 60.0, 120.0), height=256))
    return ItemOutput(files, info)


def _unused_cloud(given: dict, sections: set) -> dict:
    if given.get("from_variations", True):
        out = {} if given.get("image") is None else {
            "image": "it picks one of the library images, which happens only with from_variations = false"}
        return out or _unused_tree(given, sections)
    why = "billboard clouds are made of the library images themselves (from_variations = false)"
    out = {k: why for k in ("size", "trunk", *_TREE_ITEM_INPUTS) if given.get(k) is not None}
    if "variation" in sections:
        out["variation"] = why
    return out


register_job(Job(
    "billboard_cloud", sections={"billboard": BillboardParams, "variation": VariationParams},
    inputs={**_TREE_INPUTS, "from_variations": True, "image": None, "height": 10.0, "yaw": 0.0,
            "embed_texture": False, "preview": False, "lod": None},
    item_inputs=(*_TREE_ITEM_INPUTS, "image", "height", "yaw"), prepare=_prepare_clouds, make=_make_cloud,
    stem="cloud", unused=_unused_cloud,
    description="billboard clouds as glTF 2.0 (+ atlas PNG): of new tree variations (from_variations) "
                "or of the library images themselves; lod: 'msft_lod' (one self-contained file, "
                "MSFT_lod chain full/reduced/crossed/single) or 'files' (one file per level)"))


# ----------------------------------------------------------------------------- dendrite trees


def _shape(value, name: str = "shape") -> tuple[int, int]:
    if (not isinstance(value, list) or len(value) != 2
            or not all(isinstance(v, int) and not isinstance(v, bool) for v in value)):
        raise ValueError(f"inputs.{name} must be [height, width] (ints), got {value!r}")
    h, w = value
    if not (8 <= h <= 8192 and 8 <= w <= 8192):
        raise ValueError(f"inputs.{name} must lie within 8 .. 8192 pixels per side, got {value!r}")
    return h, w


def _prepare_dendrite(inputs, base_dir, params):
    return None


def _make_dendrite(_shared, params, inputs, rng, stem) -> ItemOutput:
    from ..core.io import encode_png
    from ..dendrite.trees import grow_layers, grow_tree, render_layers

    shape = _shape(inputs["shape"])
    layers = inputs["layers"]
    if isinstance(layers, bool) or not isinstance(layers, int) or not 1 <= layers <= 8:
        raise ValueError(f"inputs.layers must be an int in 1 .. 8, got {layers!r}")
    p = params["tree"]
    if layers == 1:
        tree = grow_tree(shape, p, rng=rng)
        rendering = tree.render()
        info = {"nodes": int(tree.dendrite.n_nodes)}
    else:
        trees = grow_layers(shape, p, layers=layers, rng=rng)
        rendering = render_layers(trees)
        info = {"nodes": [int(t.dendrite.n_nodes) for t in trees]}
    files = {f"{stem}.png": encode_png(rendering.image)}
    if inputs["svg"]:
        files[f"{stem}.svg"] = rendering.svg.encode("utf-8")
    return ItemOutput(files, info)


register_job(Job(
    "dendrite_tree", sections={"tree": TreeParams},
    inputs={"shape": [512, 448], "layers": 1, "svg": True},
    item_inputs=("shape", "layers", "svg"), prepare=_prepare_dendrite, make=_make_dendrite, stem="dendrite",
    description="trees grown by iterative path planning (PNG + SVG)"))


# ----------------------------------------------------------------------------- branching structures


def _read_example(path: Path, image_shape):
    """A Structure from a Structure JSON (``to_json``) or the branching app's annotation JSON."""
    from ..core.structure import Structure

    try:
        d = json.loads(path.read_text(encoding="utf-8"))
    except json.JSONDecodeError as exc:
        raise ValueError(f"inputs.example: {path.name} is not valid JSON: {exc}") from None
    if isinstance(d, dict) and "shapes" in d:
        # the branching app's canvas export (annotation JSON), read without importing widgets
        from ..core.annotations import structure_from_annotation_json

        try:
            structure = structure_from_annotation_json(d, image_shape=image_shape)
        except (TypeError, ValueError) as exc:
            raise ValueError(f"inputs.example: {path.name}: {exc}") from None
    elif isinstance(d, dict) and "branches" in d:
        structure = Structure.from_dict(d)
        if structure.image_shape is None and image_shape is not None:
            structure = Structure(structure.branches, image_shape=image_shape)
    else:
        raise ValueError(f"inputs.example: {path.name} holds neither a structure ('branches') nor "
                         "annotations ('shapes')")
    if not structure.branches:
        raise ValueError(f"inputs.example: {path.name} has no branch")
    return structure


def _prepare_branching(inputs, base_dir, params):
    from ..branching.synthesis import fit_model
    from ..core.image import as_float_image

    if inputs["example"] is None:
        raise ValueError("inputs.example is required: the annotated example's JSON file")
    image = None
    if inputs["image"] is not None:
        (_, src), = _image_sources(inputs["image"], base_dir, name="image", default=())
        image = as_float_image(_load(src), name="inputs.image")
    shape = image.shape[:2] if image is not None else None
    example = _read_example(resolve_path(inputs["example"], base_dir, name="example"), shape)
    # fitted once with the spec's parameters; items that change h, m, k, bins or svm_C refit
    return {"model": fit_model(example, params["synthesis"]), "example": example, "image": image}


def _make_branching(shared, params, inputs, rng, stem) -> ItemOutput:
    from ..branching.image_synthesis import synthesize_image
    from ..branching.synthesis import synthesize_structure
    from ..core.io import encode_png

    shape = None if inputs["shape"] is None else _shape(inputs["shape"])
    res = synthesize_structure(shared["model"], params["synthesis"], rng=rng, shape=shape)
    s = res.structure
    if not s.branches:
        raise ValueError(f"the synthesis grew no branch (stop reason: {res.diagnostics.get('stop_reason')})")
    doc = s.to_dict()
    files = {f"{stem}.json": json.dumps(doc, allow_nan=False).encode("utf-8"),
             f"{stem}.png": encode_png(s.render(shape)),
             f"{stem}.svg": s.to_svg(shape).encode("utf-8")}
    if shared["image"] is not None and inputs["render_image"]:
        out = synthesize_image(shared["image"], shared["example"], s, params["image"], rng=rng, shape=shape)
        files[f"{stem}_image.png"] = encode_png(out.image)
    d = res.diagnostics
    info = {"branches": int(d.get("n_branches", len(s.branches))), "vertices": int(s.n_vertices),
            "stop_reason": str(d.get("stop_reason"))}
    return ItemOutput(files, info)


def _unused_branching(given: dict, sections: set) -> dict:
    if given.get("image") is not None:
        return {}
    why = "no example 'image' is given, so no image is synthesised"
    out = {"render_image": why} if "render_image" in given else {}
    if "image" in sections:
        out["image"] = why
    return out


register_job(Job(
    "branching", sections={"synthesis": SynthesisParams, "image": ImageSynthesisParams},
    inputs={"example": None, "image": None, "shape": None, "render_image": True},
    item_inputs=("shape", "render_image"), prepare=_prepare_branching, make=_make_branching,
    stem="branching", unused=_unused_branching,
    description="branching structures (JSON, PNG, SVG) learnt from an annotated example's JSON, and "
                "their images synthesised from the example image when one is given"))


# ----------------------------------------------------------------------------- leaf variations


def _register_leaves() -> None:
    """Register ``leaf_variations`` when ``branchnb.leaves`` has its layered synthesis."""
    import importlib.util
    import warnings

    try:
        if (importlib.util.find_spec("branchnb.leaves") is None
                or importlib.util.find_spec("branchnb.leaves.synthesis") is None):
            return
        from . import _leaves

        _leaves.register()
    except ImportError as exc:  # the leaves API changed: the other jobs keep working
        warnings.warn(f"branchnb.batch: no leaf_variations job ({exc})", RuntimeWarning, stacklevel=2)


_register_leaves()
