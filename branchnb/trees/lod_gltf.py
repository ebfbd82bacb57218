"""Levels of detail written as glTF 2.0 (``MSFT_lod`` or one file per level), and a structural
check of the files written (beyond the paper, issue 24).

Part of :mod:`branchnb.trees.lod` (split from it; every name is importable from there too).
"""

from __future__ import annotations

import base64
from pathlib import Path
from typing import TYPE_CHECKING

import numpy as np

from ..core.io import encode_png
from ..core.jsonio import dumps_strict
from ..core.validate import Choice, Real, checked
from .export import _HEIGHT, _YAW, _accessors, _check_cloud, _level_arrays, _out_path, _pack, texture_atlas

if TYPE_CHECKING:
    from .lod import LodLevel

__all__ = ["SCREEN_COVERAGE", "export_lod_gltf", "export_full_gltf", "validate_gltf"]

#: Default screen coverage (share of the screen height) below which a level hands over to the next.
SCREEN_COVERAGE = (0.5, 0.2, 0.05, 0.0)



def _add_mesh(pos, uv, col, idx, data: bytearray, views: list, accessors: list) -> tuple[int, bytearray]:
    """Pack one quad mesh into the buffer; returns its first accessor's index and the buffer."""
    first = len(views)
    v, data = _pack([pos.tobytes(), uv.tobytes(), col.tobytes(), idx.tobytes()],
                    [34962, 34962, 34962, 34963], data)
    views += v
    acc = len(accessors)
    accessors += _accessors(first, pos, uv, col, idx)
    return acc, data


def _add_texture(atlas, data: bytearray, views: list, images: list, textures: list) -> bytearray:
    """Pack an atlas as a PNG image and add its texture (the last of ``textures``)."""
    v, data = _pack([encode_png(atlas)], [None], data)
    images.append({"bufferView": len(views), "mimeType": "image/png"})
    views += v
    textures.append({"source": len(images) - 1, "sampler": 0})
    return data

def _material(name: str, texture: int, double_sided: bool = True) -> dict:
    return {"name": name,
            "pbrMetallicRoughness": {"baseColorTexture": {"index": texture}, "metallicFactor": 0.0,
                                     "roughnessFactor": 1.0},
            "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": bool(double_sided),
            "extensions": {"KHR_materials_unlit": {}}}


def _cards_cloud(cards, cloud):
    """Side cards as a BillboardCloud (for the exported arrays)."""
    from .billboard import FRONT, BillboardCloud

    n = cards.n
    return BillboardCloud(np.asarray(cards.centers, float), np.asarray(cards.sizes, float), np.arange(n),
                          np.ones(n), np.full(n, FRONT), np.full(n, -1), list(cards.textures), cloud.axis,
                          cloud.image, cloud.superpixels, cloud.depth, [], cloud.scale, cloud.lines, [])


def _document(levels: list[LodLevel], *, yaw: float, height: float, lod: bool,
              coverage=SCREEN_COVERAGE) -> dict:
    """A self-contained glTF document (embedded buffer and textures) of some levels."""
    data = bytearray()
    views, accessors, meshes, materials, textures, images, nodes = [], [], [], [], [], [], []
    atlases: dict[int, int] = {}                     # id(cloud) -> image index
    for i, lv in enumerate(levels):
        atlas, pos, uv, col, idx = _level_arrays(lv.cloud, yaw=yaw, height=height, crossed=lv.crossed,
                                                 turn=lv.turn)
        acc0, data = _add_mesh(pos, uv, col, idx, data, views, accessors)
        key = id(lv.cloud)
        if key not in atlases:
            data = _add_texture(atlas, data, views, images, textures)
            materials.append(_material(f"{lv.name}_atlas", len(textures) - 1))
            atlases[key] = len(materials) - 1
        extras = {"triangles": lv.triangles, "crossed": lv.crossed}
        if lv.turn is not None:
            extras["turn_degrees"] = [float(t) for t in lv.turn]
        if lv.yaws is not None:
            _, rects = texture_atlas(lv.cloud.textures)
            Ha, Wa = atlas.shape[:2]
            extras["impostor"] = {
                "frames": [{"yaw": float(y), "uv": [float(x / Wa), float(yy / Ha), float((x + w) / Wa),
                                                    float((yy + h) / Ha)]}
                           for y, (x, yy, w, h) in zip(lv.yaws, rects.tolist())],
                "note": "the quad shows frame 0; show the frame whose yaw is nearest to the camera's"}
        prims = [{"attributes": {"POSITION": acc0, "TEXCOORD_0": acc0 + 1, "COLOR_0": acc0 + 2},
                  "indices": acc0 + 3, "material": atlases[key], "mode": 4}]
        if lv.cards is not None and lv.cards.n:
            # Side cards: fixed quads facing their side's camera, single sided (culled from behind).
            cc = _cards_cloud(lv.cards, lv.cloud)
            atlas, pos, uv, col, idx = _level_arrays(cc, yaw=yaw, height=height, crossed=False,
                                                     turn=np.asarray(lv.cards.turn) - yaw)
            acc1, data = _add_mesh(pos, uv, col, idx, data, views, accessors)
            data = _add_texture(atlas, data, views, images, textures)
            materials.append(_material(f"{lv.name}_side_cards", len(textures) - 1, double_sided=False))
            prims.append({"attributes": {"POSITION": acc1, "TEXCOORD_0": acc1 + 1, "COLOR_0": acc1 + 2},
                          "indices": acc1 + 3, "material": len(materials) - 1, "mode": 4})
            extras["side_cards"] = {
                "primitive": 1, "quads": lv.cards.n, "turn_degrees": [float(t) for t in lv.cards.turn],
                "note": "fixed quads (not turned to the camera), single sided: the side views' outline, "
                        "hidden from the front (edge-on, or the texels it would show left out)"}
        meshes.append({"name": lv.name, "primitives": prims, "extras": extras})
        nodes.append({"mesh": i, "name": f"tree_lod{i}_{lv.name}"})
    ext = ["KHR_materials_unlit"]
    if lod and len(levels) > 1:
        nodes[0]["extensions"] = {"MSFT_lod": {"ids": list(range(1, len(levels)))}}
        nodes[0]["extras"] = {"MSFT_screencoverage": [float(c) for c in coverage[:len(levels)]]}
        ext = ["KHR_materials_unlit", "MSFT_lod"]
    doc = {
        "asset": {"version": "2.0", "generator": "branchnb.trees level-of-detail chain"},
        "extensionsUsed": ext,
        "scene": 0,
        "scenes": [{"nodes": [0] if lod else list(range(len(levels)))}],
        "nodes": nodes, "meshes": meshes, "materials": materials, "textures": textures,
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071}],
        "images": images,
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(data)).decode()}],
        "bufferViews": views, "accessors": accessors,
    }
    return doc


@checked(yaw=_YAW, height=_HEIGHT, mode=Choice("msft_lod", "files"),
         reduced_share=Real(0, 1, low_open=True))
def export_lod_gltf(cloud, path, *, mode: str = "msft_lod", yaw: float = 0.0, height: float = 10.0,
                    reduced_share: float = 0.3) -> list[Path]:
    """Write the level-of-detail chain of a cloud as glTF 2.0 (self-contained ``.gltf`` files).

    Parameters
    ----------
    cloud : BillboardCloud
        The full cloud; the chain is :func:`~branchnb.trees.lod.lod_chain` of it.
    path : str or Path
        Output ``.gltf`` file. ``mode="files"`` writes ``<stem>_lod0.gltf``
        ... ``<stem>_lod3.gltf`` beside it instead.
    mode : {"msft_lod", "files"}
        One file whose first node carries the ``MSFT_lod`` extension (its
        ``ids`` are the coarser levels' nodes; ``extras.MSFT_screencoverage``
        the hand-over coverages 0.5, 0.2, 0.05), or one file per level.
    yaw, height
        As in :func:`~branchnb.trees.export.export_gltf`.
    reduced_share : float
        Share of the billboards the ``reduced`` level keeps.

    Returns
    -------
    list of Path
        The file(s) written.

    Notes
    -----
    Triangles per level: ``2 K`` (full, ``K`` billboards),
    ``2 ceil(0.3 K) + 2`` (reduced), 4 (crossed), 2 (single); a drawn
    tree's full and reduced levels add 2 per side card (a second
    primitive with a single-sided material; on 12 drawn trees 0 to about
    180 cards, 94 % more triangles on the full level, ``extras.side_cards``),
    which ``extras.triangles`` counts. At 96 px (4 drawn kinds, 2 RPG
    sprites, 6 clip-art samples, 2 trees on a base) the full level has
    10-1580 triangles (cards included; 256 superpixels make a 29 x 96 px
    tree's full level 1272), the reduced 6-510, and no billboard or card
    is empty. Every file passes the Khronos glTF
    validator with no error or warning (checked with ``npx gltf-validator``;
    :func:`validate_gltf` checks the structure without it).

    Examples
    --------
    >>> import os, tempfile
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> out = tempfile.mkdtemp()
    >>> [p.name for p in export_lod_gltf(cloud, os.path.join(out, "t.gltf"), mode="files")]
    ['t_lod0.gltf', 't_lod1.gltf', 't_lod2.gltf', 't_lod3.gltf']
    """
    path = _out_path(path, ".gltf")
    from .lod import lod_chain

    _check_cloud(cloud)
    levels = lod_chain(cloud, reduced_share=reduced_share)
    path.parent.mkdir(parents=True, exist_ok=True)
    if mode == "msft_lod":
        path.write_text(dumps_strict(_document(levels, yaw=yaw, height=height, lod=True),
                                     name="glTF document"))
        return [path]
    out = []
    for i, lv in enumerate(levels):
        p = path.with_name(f"{path.stem}_lod{i}.gltf")
        p.write_text(dumps_strict(_document([lv], yaw=yaw, height=height, lod=False),
                                  name="glTF document"))
        out.append(p)
    return out


def export_full_gltf(cloud, path, *, yaw: float = 0.0, height: float = 10.0) -> Path:
    """Write a cloud as one glTF 2.0 file with a drawn tree's side outline (the ``full`` level alone).

    The billboards carry the side outline baked into their textures
    (:func:`~branchnb.trees.lod.bake_side_outline`) and the rest of it on single-sided side
    cards (:func:`~branchnb.trees.lod_cards.side_outline_cards`, a second
    primitive), as the ``full`` level of :func:`export_lod_gltf`, without
    building the coarser levels. A photographed tree gets neither.

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud to write.
    path : str or Path
        Output ``.gltf`` file (self-contained: embedded buffer and PNG textures).
    yaw : float
        Turn of the tree about its axis in the file (degrees).
    height : float
        Height of the tree in metres (> 0).

    Returns
    -------
    Path
        The written file.

    Examples
    --------
    >>> import os, tempfile
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> p = export_full_gltf(cloud, os.path.join(tempfile.mkdtemp(), "t.gltf"))
    >>> validate_gltf(p)
    []
    """
    from .lod import LodLevel
    from .lod_cards import side_outline_cards
    from .lod_view import bake_side_outline

    if isinstance(yaw, bool) or not isinstance(yaw, (int, float, np.integer, np.floating)):
        raise TypeError(f"yaw must be a number (degrees), got {type(yaw).__name__}")
    if not np.isfinite(yaw):
        raise ValueError(f"yaw must be finite, got {yaw}")
    if isinstance(height, bool) or not isinstance(height, (int, float, np.integer, np.floating)):
        raise TypeError(f"height must be a number (metres), got {type(height).__name__}")
    if not (np.isfinite(height) and height > 0):
        raise ValueError(f"height must be a positive number, got {height}")
    path = _out_path(path, ".gltf")
    _check_cloud(cloud)
    baked = bake_side_outline(cloud)
    level = LodLevel("full", baked, cards=side_outline_cards(cloud, baked=baked))
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_text(dumps_strict(_document([level], yaw=float(yaw), height=float(height), lod=False),
                                 name="glTF document"))
    return path


_COMPONENTS = {"SCALAR": 1, "VEC2": 2, "VEC3": 3, "VEC4": 4}
_SIZES = {5126: 4, 5125: 4, 5123: 2, 5121: 1}


def validate_gltf(path) -> list[str]:
    """Structural checks of a self-contained ``.gltf`` file (the validator's main rules).

    Checks the asset version, that every index (scene, node, mesh,
    material, texture, image, accessor, buffer view) points at an existing
    object, that buffer views lie inside the decoded buffer and accessors
    inside their views, that 4-byte components are 4-byte aligned, that
    ``POSITION`` has its ``min``/``max`` equal to the data's, that indices
    address existing vertices, that ``MSFT_lod`` ids are nodes outside the
    scene and that the extension is declared, and that embedded images are
    PNG.

    Parameters
    ----------
    path : str or Path
        A ``.gltf`` JSON file with its buffers embedded as ``data:`` URIs
        (as :func:`export_lod_gltf` writes them).

    Returns
    -------
    list of str
        The problems found (empty: valid).

    Examples
    --------
    >>> import os, tempfile
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> (path,) = export_lod_gltf(cloud, os.path.join(tempfile.mkdtemp(), "t.gltf"))
    >>> validate_gltf(path)
    []
    """
    import json

    doc = json.loads(Path(path).read_text())
    errs = []
    if doc.get("asset", {}).get("version") != "2.0":
        errs.append("asset.version is not 2.0")
    bufs = []
    for b in doc.get("buffers", []):
        uri = b.get("uri", "")
        if not uri.startswith("data:"):
            errs.append("buffer is not embedded")
            bufs.append(b"")
            continue
        raw = base64.b64decode(uri.split(",", 1)[1])
        if len(raw) != b["byteLength"]:
            errs.append(f"buffer byteLength {b['byteLength']} != data {len(raw)}")
        bufs.append(raw)
    views = doc.get("bufferViews", [])
    for i, v in enumerate(views):
        if not 0 <= v["buffer"] < len(bufs) or v["byteOffset"] + v["byteLength"] > len(bufs[v["buffer"]]):
            errs.append(f"bufferView {i} out of its buffer")
    n = {k: len(doc.get(k, [])) for k in ("nodes", "meshes", "materials", "textures", "images",
                                          "accessors", "samplers")}
    data = {}
    for i, a in enumerate(doc.get("accessors", [])):
        if not 0 <= a["bufferView"] < len(views):
            errs.append(f"accessor {i}: no bufferView {a['bufferView']}")
            continue
        v = views[a["bufferView"]]
        size = _SIZES[a["componentType"]]
        length = a["count"] * _COMPONENTS[a["type"]] * size
        if length > v["byteLength"]:
            errs.append(f"accessor {i} longer than its bufferView")
            continue
        if (v["byteOffset"] + a.get("byteOffset", 0)) % size:
            errs.append(f"accessor {i} misaligned")
        dt = {5126: "<f4", 5125: "<u4", 5123: "<u2", 5121: "u1"}[a["componentType"]]
        raw = bufs[v["buffer"]][v["byteOffset"]:v["byteOffset"] + length]
        data[i] = np.frombuffer(raw, dtype=dt).reshape(a["count"], _COMPONENTS[a["type"]])
        if not np.all(np.isfinite(data[i])):
            errs.append(f"accessor {i} has non-finite values")
    for mi, m in enumerate(doc.get("meshes", [])):
        for prim in m["primitives"]:
            att = prim["attributes"]
            for k, ai in list(att.items()) + [("indices", prim.get("indices", 0))]:
                if not 0 <= ai < n["accessors"]:
                    errs.append(f"mesh {mi}: {k} accessor {ai} missing")
            pos = data.get(att.get("POSITION"))
            acc = doc["accessors"][att["POSITION"]] if att.get("POSITION", -1) < n["accessors"] else {}
            if pos is not None and (not np.allclose(acc.get("min"), pos.min(0))
                                    or not np.allclose(acc.get("max"), pos.max(0))):
                errs.append(f"mesh {mi}: POSITION min/max do not match the data")
            idx = data.get(prim.get("indices"))
            if idx is not None and pos is not None and idx.size and idx.max() >= len(pos):
                errs.append(f"mesh {mi}: index beyond the vertices")
            if idx is not None and idx.size % 3:
                errs.append(f"mesh {mi}: indices not a whole number of triangles")
            if not 0 <= prim.get("material", 0) < n["materials"]:
                errs.append(f"mesh {mi}: material missing")
    for ti, t in enumerate(doc.get("textures", [])):
        if not 0 <= t["source"] < n["images"] or not 0 <= t.get("sampler", 0) < n["samplers"]:
            errs.append(f"texture {ti}: image or sampler missing")
    for ii, im in enumerate(doc.get("images", [])):
        if "uri" in im:
            if not (Path(path).parent / im["uri"]).is_file():
                errs.append(f"image {ii}: file {im['uri']} missing")
            continue
        v = views[im["bufferView"]] if im.get("bufferView", -1) < len(views) else None
        if v is None or bufs[v["buffer"]][v["byteOffset"]:v["byteOffset"] + 8] != b"\x89PNG\r\n\x1a\n":
            errs.append(f"image {ii} is not an embedded PNG")
    in_scene = set()
    for s in doc.get("scenes", []):
        for ni in s["nodes"]:
            if not 0 <= ni < n["nodes"]:
                errs.append(f"scene node {ni} missing")
            in_scene.add(ni)
    for ni, node in enumerate(doc.get("nodes", [])):
        if not 0 <= node.get("mesh", 0) < n["meshes"]:
            errs.append(f"node {ni}: mesh missing")
        lod = node.get("extensions", {}).get("MSFT_lod")
        if lod is not None:
            if "MSFT_lod" not in doc.get("extensionsUsed", []):
                errs.append("MSFT_lod used but not declared")
            for j in lod["ids"]:
                if not 0 <= j < n["nodes"] or j in in_scene:
                    errs.append(f"MSFT_lod id {j} is not a node outside the scene")
    return errs

