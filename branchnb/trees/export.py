"""Export a billboard cloud to glTF 2.0 or OBJ + MTL, with one texture atlas.

Both formats get one quad per billboard, textured from a shared atlas PNG
(shelf packing; colours bled into the transparent texels so that texture
filtering does not darken the cut-outs). The quads face the camera of
``yaw`` degrees (0 = the input view). Billboard clouds are meant to be
drawn as axial billboards (each quad turned about its vertical axis to
face the camera); the glTF file lists each quad's centre and layer in
``meshes[0].extras`` for engines that do that, and a generic viewer shows
the fixed quads (what :func:`~branchnb.trees.preview.render_cloud` draws
with ``facing="fixed"``).

Units and axes: metres, ``y`` up, ``z`` towards the front view's camera,
the origin at the foot of the tree's vertical axis; ``height`` sets the
tree height.

* glTF: one ``.gltf`` JSON file with the geometry buffer embedded as a
  base64 data URI and the atlas as ``<stem>_atlas.png`` next to it (or
  embedded too, ``embed_texture=True``). Interior billboards are darkened
  through the ``COLOR_0`` vertex colour (multiplied with the texture by
  glTF's base colour rule); the material is unlit
  (``KHR_materials_unlit``), double sided, ``alphaMode: MASK``.
* OBJ: ``.obj`` + ``.mtl`` + atlas; darkening is quantised into a few
  materials whose ``Kd`` multiplies ``map_Kd``.

Examples
--------
>>> import tempfile, pathlib, json
>>> from branchnb import data
>>> from branchnb.trees.billboard import billboard_cloud
>>> cloud = billboard_cloud(data.load("tree_rpg_03"), rng=0)
>>> out = export_gltf(cloud, pathlib.Path(tempfile.mkdtemp()) / "tree.gltf")
>>> json.loads(out.read_text())["asset"]["version"]
'2.0'
"""

from __future__ import annotations

import base64
from pathlib import Path

import numpy as np

from ..core.image import extend_nearest
from ..core.io import encode_png, imsave
from ..core.jsonio import dumps_strict
from ..core.validate import Int, Real, check_finite, checked

__all__ = ["texture_atlas", "quad_vertices", "export_gltf", "export_obj"]


def texture_atlas(textures, *, padding: int = 2, bleed: bool = True) -> tuple[np.ndarray, np.ndarray]:
    """Pack RGBA textures into one atlas (shelf packing, tallest first).

    Parameters
    ----------
    textures : sequence of (h, w, 4) float arrays
        RGBA textures (straight alpha, in [0, 1]); at least one.
    padding : int
        Transparent texels between neighbours.
    bleed : bool
        Copy the nearest opaque colour into transparent texels (alpha stays 0).

    Returns
    -------
    atlas : (Ha, Wa, 4) float32
        Width a power of two.
    rects : (N, 4) int64
        ``(x, y, w, h)`` of each texture in the atlas.

    Raises
    ------
    ValueError
        If ``textures`` is empty or one is not ``(h, w, 4)``.

    Examples
    --------
    >>> import numpy as np
    >>> atlas, rects = texture_atlas([np.ones((4, 6, 4)), np.ones((3, 3, 4))])
    >>> rects[0].tolist()
    [2, 2, 6, 4]
    """
    texs = [np.asarray(t, np.float32) for t in textures]
    if not texs:
        raise ValueError("textures is empty")
    for i, t in enumerate(texs):
        if t.ndim != 3 or t.shape[2] != 4 or t.shape[0] < 1 or t.shape[1] < 1:
            raise ValueError(f"textures[{i}] must be (h, w, 4), got {t.shape}")
    area = sum((t.shape[0] + padding) * (t.shape[1] + padding) for t in texs)
    widest = max(t.shape[1] for t in texs) + 2 * padding
    Wa = 1 << int(np.ceil(np.log2(max(widest, np.sqrt(area * 1.15), 16))))
    order = sorted(range(len(texs)), key=lambda i: (-texs[i].shape[0], -texs[i].shape[1], i))
    rects = np.zeros((len(texs), 4), np.int64)
    x = y = padding
    shelf = 0
    for i in order:
        h, w = texs[i].shape[:2]
        if x + w + padding > Wa:
            x = padding
            y += shelf + padding
            shelf = 0
        rects[i] = (x, y, w, h)
        x += w + padding
        shelf = max(shelf, h)
    Ha = int(y + shelf + padding)
    atlas = np.zeros((Ha, Wa, 4), np.float32)
    for (x, y, w, h), t in zip(rects, texs):
        atlas[y:y + h, x:x + w] = t
    if bleed and (atlas[:, :, 3] > 0).any():
        empty = atlas[:, :, 3] <= 0
        atlas[empty, :3] = extend_nearest(atlas[:, :, :3], ~empty)[empty]
    return atlas, rects


def _frame(cloud, height: float):
    """Metres per pixel and the origin (axis x, bottom y) in pixels."""
    if not (np.isfinite(height) and height > 0):
        raise ValueError(f"height must be a positive number, got {height}")
    a = cloud.image[:, :, 3] > 0
    ys = np.nonzero(a.any(axis=1))[0]
    top, bottom = float(ys[0]), float(ys[-1] + 1)
    k = height / max(bottom - top, 1.0)
    return k, float(cloud.axis), bottom


def quad_vertices(cloud, *, yaw: float = 0.0, height: float = 10.0, crossed: bool = False,
                  turn=None) -> np.ndarray:
    """Corners of every billboard quad in metres, facing the camera at ``yaw`` degrees.

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud; its ``centers``/``sizes`` are in working pixels.
    yaw : float
        Camera angle in degrees the quads face (0 = the input view).
    height : float
        Tree height in metres: the opaque rows of ``cloud.image`` span
        ``[0, height]`` in ``y``, the tree's foot at ``y = 0`` and its axis at
        ``x = 0``.
    crossed : bool
        Append a second quad per billboard turned by 90 degrees about its
        vertical axis (a "cross" billboard: generic viewers then show some
        volume from the side too; edge-on, it is invisible in the ``yaw``
        view).
    turn : (K,) array_like, optional
        Per billboard, degrees its quad is turned by beyond ``yaw`` (a
        crossed impostor: the front view on one quad, a side view on a
        quad turned by 90 degrees).

    Returns
    -------
    (K, 4, 3) or (2K, 4, 3) float64
        Top-left, top-right, bottom-right, bottom-left (as seen from the
        camera), ``y`` up; with ``crossed`` the K turned quads follow.

    Raises
    ------
    ValueError
        If ``height`` is not a positive number.

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> q = quad_vertices(cloud, height=10.0)
    >>> q.shape == (cloud.n_billboards, 4, 3), round(float(q[..., 1].min()), 3)
    (True, 0.0)
    """
    k, ax, bottom = _frame(cloud, height)
    c = cloud.centers
    centre = np.stack([(c[:, 0] - ax) * k, (bottom - c[:, 1]) * k, c[:, 2] * k], axis=1)
    t = np.deg2rad(float(yaw) + (np.zeros(len(c)) if turn is None else np.asarray(turn, float)))[:, None]
    right = np.concatenate([np.cos(t), np.zeros_like(t), np.sin(t)], axis=1)
    up = np.array([0.0, 1.0, 0.0])
    hw = 0.5 * cloud.sizes[:, 0:1] * k
    hh = 0.5 * cloud.sizes[:, 1:2] * k
    tl = centre - hw * right + hh * up
    tr = centre + hw * right + hh * up
    br = centre + hw * right - hh * up
    bl = centre - hw * right - hh * up
    quads = np.stack([tl, tr, br, bl], axis=1)
    if crossed:
        return np.concatenate([quads, quad_vertices(cloud, yaw=float(yaw) + 90.0, height=height, turn=turn)])
    return quads


def _uvs(cloud, rects, atlas_shape):
    Ha, Wa = atlas_shape[:2]
    r = rects[cloud.texture].astype(np.float64)
    u0, v0 = r[:, 0] / Wa, r[:, 1] / Ha
    u1, v1 = (r[:, 0] + r[:, 2]) / Wa, (r[:, 1] + r[:, 3]) / Ha
    # tl, tr, br, bl with v measured from the top (glTF convention).
    return np.stack([np.stack([u0, v0], 1), np.stack([u1, v0], 1),
                     np.stack([u1, v1], 1), np.stack([u0, v1], 1)], axis=1)


#: Export frame: the camera yaw (degrees) and the tree height (metres).
_YAW = Real(-1e6, 1e6)
_HEIGHT = Real(0, 1e6, low_open=True)


def _out_path(path, suffix: str) -> Path:
    if not isinstance(path, (str, Path)) or not str(path).strip():
        raise TypeError(f"path must be a non-empty file path, got {path!r:.60}")
    path = Path(path)
    if path.suffix.lower() != suffix:
        raise ValueError(f"path must end in {suffix}, got {path.name!r}")
    if path.is_dir():
        raise ValueError(f"path {str(path)!r} is a directory")
    return path


def _check_cloud(cloud):
    from .billboard import BillboardCloud

    if not isinstance(cloud, BillboardCloud):
        raise TypeError(f"cloud must be a BillboardCloud, got {type(cloud).__name__}")
    if cloud.n_billboards == 0:
        raise ValueError("cloud has no billboards")


def _level_arrays(cloud, *, yaw: float, height: float, crossed: bool, turn=None):
    """Atlas and float32/uint32 vertex arrays (positions, uvs, colours, indices) of one cloud."""
    atlas, rects = texture_atlas(cloud.textures)
    # Power-of-two sides: mipmapped sampling (the sampler's minFilter) needs them in WebGL 1
    # and the Khronos validator notes other sizes.
    h, w = atlas.shape[:2]
    pot = np.zeros((1 << int(np.ceil(np.log2(h))), 1 << int(np.ceil(np.log2(w))), 4), np.float32)
    pot[:h, :w] = atlas
    pot[h:, :w, :3] = atlas[-1:, :, :3]
    pot[:, w:, :3] = pot[:, w - 1:w, :3]
    atlas = pot
    quads = check_finite(quad_vertices(cloud, yaw=yaw, height=height, crossed=crossed, turn=turn),
                         "vertex positions")
    K = len(quads)
    owner = np.arange(K) % cloud.n_billboards
    pos = quads.reshape(-1, 3).astype(np.float32)
    uv = _uvs(cloud, rects, atlas.shape)[owner].reshape(-1, 2).astype(np.float32)
    col = np.repeat(np.clip(cloud.tint[owner], 0, 1)[:, None], 3, axis=1)
    col = np.repeat(col, 4, axis=0).astype(np.float32)
    base = (np.arange(K, dtype=np.uint32) * 4)[:, None]
    idx = (base + np.array([0, 3, 2, 0, 2, 1], np.uint32)[None, :]).reshape(-1).astype(np.uint32)
    return atlas, pos, uv, col, idx


def _pack(blobs, targets, data: bytearray | None = None, buffer: int = 0):
    """Buffer views of ``blobs`` appended to ``data`` (4-byte aligned) and the data."""
    data = bytearray() if data is None else data
    views = []
    for b, tgt in zip(blobs, targets):
        data.extend(b"\0" * ((-len(data)) % 4))
        view = {"buffer": buffer, "byteOffset": len(data), "byteLength": len(b)}
        if tgt is not None:
            view["target"] = tgt
        views.append(view)
        data.extend(b)
    return views, data


def _accessors(first_view: int, pos, uv, col, idx) -> list:
    """Accessors of one level's positions, uvs, colours and indices (views ``first_view`` ...)."""
    v = first_view
    return [
        {"bufferView": v, "componentType": 5126, "count": int(len(pos)), "type": "VEC3",
         "min": pos.min(axis=0).tolist(), "max": pos.max(axis=0).tolist()},
        {"bufferView": v + 1, "componentType": 5126, "count": int(len(uv)), "type": "VEC2"},
        {"bufferView": v + 2, "componentType": 5126, "count": int(len(col)), "type": "VEC3"},
        {"bufferView": v + 3, "componentType": 5125, "count": int(len(idx)), "type": "SCALAR",
         "min": [int(idx.min())], "max": [int(idx.max())]},
    ]


@checked(yaw=_YAW, height=_HEIGHT)
def export_gltf(cloud, path, *, yaw: float = 0.0, height: float = 10.0,
                embed_texture: bool = False, crossed: bool = False) -> Path:
    """Write the cloud as a glTF 2.0 file (``.gltf`` JSON, embedded buffer).

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud to write: one textured quad per billboard, tinted by
        vertex colour, with the layer names and centres in ``extras``.
    path : str or Path
        Output ``.gltf`` file; the atlas goes to ``<stem>_atlas.png`` beside it
        unless ``embed_texture``.
    yaw : float
        The quads face the camera at this yaw (degrees).
    height : float
        Tree height in metres.
    embed_texture : bool
        Put the atlas PNG inside the buffer instead of a separate file.
    crossed : bool
        Two perpendicular quads per billboard (see :func:`quad_vertices`).

    Returns
    -------
    Path
        The ``.gltf`` file written (parent folders are created).

    Raises
    ------
    ValueError
        If ``height`` is not positive or the cloud has non-finite values.

    Examples
    --------
    >>> import os, tempfile
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> out = tempfile.mkdtemp()
    >>> export_gltf(cloud, os.path.join(out, "tree.gltf")).name, sorted(os.listdir(out))
    ('tree.gltf', ['tree.gltf', 'tree_atlas.png'])
    """
    path = _out_path(path, ".gltf")
    _check_cloud(cloud)
    atlas, pos, uv, col, idx = _level_arrays(cloud, yaw=yaw, height=height, crossed=crossed)
    blobs = [pos.tobytes(), uv.tobytes(), col.tobytes(), idx.tobytes()]
    png = encode_png(atlas) if embed_texture else None
    if png is not None:
        blobs.append(png)
    views, data = _pack(blobs, [34962, 34962, 34962, 34963, None])
    accessors = _accessors(0, pos, uv, col, idx)
    k, ax, bottom = _frame(cloud, height)
    centres = np.stack([(cloud.centers[:, 0] - ax) * k, (bottom - cloud.centers[:, 1]) * k,
                        cloud.centers[:, 2] * k], axis=1)
    from .billboard import LAYER_NAMES

    path.parent.mkdir(parents=True, exist_ok=True)
    if png is not None:
        image = {"bufferView": 4, "mimeType": "image/png"}
    else:
        atlas_path = path.with_name(path.stem + "_atlas.png")
        imsave(atlas_path, atlas)
        image = {"uri": atlas_path.name}
    doc = {
        "asset": {"version": "2.0", "generator": "branchnb.trees billboard cloud"},
        "extensionsUsed": ["KHR_materials_unlit"],
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": "tree"}],
        "meshes": [{
            "name": "billboards",
            "primitives": [{"attributes": {"POSITION": 0, "TEXCOORD_0": 1, "COLOR_0": 2},
                            "indices": 3, "material": 0, "mode": 4}],
            "extras": {
                "billboards": "axial: turn each quad about the vertical axis through its centre "
                              "to face the camera",
                "yaw": float(yaw),
                "crossed": bool(crossed),
                "quads_per_billboard": 2 if crossed else 1,
                "centers": np.round(centres, 5).tolist(),
                "layers": [LAYER_NAMES[int(v)] for v in cloud.layer],
            },
        }],
        "materials": [{
            "name": "billboard_atlas",
            "pbrMetallicRoughness": {"baseColorTexture": {"index": 0}, "metallicFactor": 0.0,
                                     "roughnessFactor": 1.0},
            "alphaMode": "MASK", "alphaCutoff": 0.5, "doubleSided": True,
            "extensions": {"KHR_materials_unlit": {}},
        }],
        "textures": [{"source": 0, "sampler": 0}],
        "samplers": [{"magFilter": 9729, "minFilter": 9987, "wrapS": 33071, "wrapT": 33071}],
        "images": [image],
        "buffers": [{"byteLength": len(data),
                     "uri": "data:application/octet-stream;base64," + base64.b64encode(bytes(data)).decode()}],
        "bufferViews": views,
        "accessors": accessors,
    }
    path.write_text(dumps_strict(doc, name="glTF document"))
    return path


@checked(yaw=_YAW, height=_HEIGHT, tint_levels=Int(1, 256))
def export_obj(cloud, path, *, yaw: float = 0.0, height: float = 10.0, tint_levels: int = 16,
               crossed: bool = False) -> Path:
    """Write the cloud as Wavefront OBJ + MTL + atlas PNG.

    Parameters
    ----------
    cloud : BillboardCloud
        The cloud to write.
    path : str or Path
        Output ``.obj``; ``<stem>.mtl`` and ``<stem>_atlas.png`` go beside it.
    yaw : float
        The quads face the camera at this yaw (degrees).
    height : float
        Tree height in metres.
    tint_levels : int
        Darkening is quantised into this many materials (``Kd`` multiplies
        the texture); 1 writes a single untinted material.
    crossed : bool
        Two perpendicular quads per billboard (see :func:`quad_vertices`).

    Returns
    -------
    Path
        The ``.obj`` file written (parent folders are created).

    Raises
    ------
    ValueError
        If ``height`` is not positive or the cloud has non-finite values.

    Examples
    --------
    >>> import os, tempfile
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> out = tempfile.mkdtemp()
    >>> export_obj(cloud, os.path.join(out, "tree.obj")).name, sorted(os.listdir(out))
    ('tree.obj', ['tree.mtl', 'tree.obj', 'tree_atlas.png'])
    """
    path = _out_path(path, ".obj")
    _check_cloud(cloud)
    atlas, rects = texture_atlas(cloud.textures)
    quads = check_finite(quad_vertices(cloud, yaw=yaw, height=height, crossed=crossed), "vertex positions")
    owner = np.arange(len(quads)) % cloud.n_billboards
    uv = check_finite(_uvs(cloud, rects, atlas.shape)[owner], "texture coordinates")
    path.parent.mkdir(parents=True, exist_ok=True)
    atlas_path = path.with_name(path.stem + "_atlas.png")
    mtl_path = path.with_suffix(".mtl")
    imsave(atlas_path, atlas)
    tint = np.clip(cloud.tint[owner], 0, 1)
    level = np.clip(np.round(tint * (tint_levels - 1)), 0, tint_levels - 1).astype(int) \
        if tint_levels > 1 else np.zeros(len(tint), int)
    used = sorted(set(level.tolist()))
    mtl = ["# branchnb.trees billboard cloud"]
    for lv in used:
        t = lv / (tint_levels - 1) if tint_levels > 1 else 1.0
        mtl += [f"newmtl tint_{lv:02d}", "Ka 0 0 0", f"Kd {t:.4f} {t:.4f} {t:.4f}", "Ks 0 0 0",
                "d 1.0", "illum 1", f"map_Kd {atlas_path.name}", f"map_d {atlas_path.name}", ""]
    mtl_path.write_text("\n".join(mtl))
    lines = ["# branchnb.trees billboard cloud: one quad per billboard (axial billboards),",
             f"# {len(quads)} quads, y up, metres, facing yaw {float(yaw):g} degrees"
             + (" (crossed: second half turned by 90 degrees)" if crossed else ""),
             f"mtllib {mtl_path.name}"]
    lines += [f"v {x:.6f} {y:.6f} {z:.6f}" for x, y, z in quads.reshape(-1, 3)]
    lines += [f"vt {u:.6f} {1.0 - v:.6f}" for u, v in uv.reshape(-1, 2)]
    from .billboard import LAYER_NAMES

    for lv in used:
        lines.append(f"usemtl tint_{lv:02d}")
        for i in np.flatnonzero(level == lv):
            a = 4 * i + 1
            j = int(owner[i])
            lines.append(f"g billboard_{j:04d}_{LAYER_NAMES[int(cloud.layer[j])]}" + ("_x" if i != j else ""))
            # tl, bl, br, tr: counter-clockwise seen from the camera.
            lines.append(f"f {a}/{a} {a + 3}/{a + 3} {a + 2}/{a + 2} {a + 1}/{a + 1}")
    path.write_text("\n".join(lines) + "\n")
    return path
