"""Levels of detail of a billboard cloud as glTF (issue 24: beyond the paper, what engines ask for)."""

import json
import shutil
import subprocess
from pathlib import Path

import numpy as np
import pytest

from branchnb import data
from branchnb.trees.billboard import BillboardParams, billboard_cloud
from branchnb.trees.lod import export_lod_gltf, lod_chain, reduce_cloud, validate_gltf
from branchnb.trees.preview import render_cloud


@pytest.fixture(scope="module")
def cloud():
    return billboard_cloud(data.load("tree_rpg_03"),
                           params=BillboardParams(max_size=128, n_segments=48, n_interior=8), rng=0)


def test_chain_levels_and_triangle_counts(cloud):
    chain = lod_chain(cloud)
    k = cloud.n_billboards
    assert [lv.name for lv in chain] == ["full", "reduced", "crossed", "single"]
    cards = [0 if lv.cards is None else lv.cards.n for lv in chain]
    assert chain[0].triangles == 2 * k + 2 * cards[0]
    assert chain[1].triangles <= 2 * int(np.ceil(0.3 * k)) + 2 + 2 * cards[1]
    assert [lv.triangles for lv in chain[2:]] == [4, 2]
    assert chain[0].triangles > chain[1].triangles > chain[2].triangles > chain[3].triangles


def test_reduced_level_looks_like_the_full_cloud_from_the_front(cloud):
    full = render_cloud(cloud, 0.0, crop="image")
    red = render_cloud(reduce_cloud(cloud), 0.0, crop="image")
    op = (full[..., 3] > 0.5) | (red[..., 3] > 0.5)
    err = np.abs(full[..., :3] * full[..., 3:] - red[..., :3] * red[..., 3:])[op].mean()
    assert err < 0.05, err


@pytest.mark.parametrize("mode", ["msft_lod", "files"])
def test_lod_gltf_files_are_valid(cloud, tmp_path, mode):
    files = export_lod_gltf(cloud, tmp_path / "tree.gltf", mode=mode)
    assert len(files) == (1 if mode == "msft_lod" else 4)
    for f in files:
        assert validate_gltf(f) == [], f
        doc = json.loads(f.read_text(), parse_constant=lambda c: pytest.fail(f"non-standard JSON {c}"))
        assert doc["asset"]["version"] == "2.0"
    if mode == "msft_lod":
        doc = json.loads(files[0].read_text())
        assert doc["nodes"][0]["extensions"]["MSFT_lod"]["ids"] == [1, 2, 3]
        assert "MSFT_lod" in doc["extensionsUsed"] and doc["scenes"][0]["nodes"] == [0]
        tris = [sum(doc["accessors"][p["indices"]]["count"] // 3 for p in m["primitives"]) for m in doc["meshes"]]
        assert tris == [lv.triangles for lv in lod_chain(cloud)]


def test_validate_gltf_finds_broken_files(cloud, tmp_path):
    f = export_lod_gltf(cloud, tmp_path / "tree.gltf")[0]
    doc = json.loads(f.read_text())
    doc["accessors"][3]["count"] += 10_000
    doc["nodes"][0]["extensions"]["MSFT_lod"]["ids"] = [0]
    f.write_text(json.dumps(doc))
    errs = validate_gltf(f)
    assert any("accessor 3" in e for e in errs) and any("MSFT_lod" in e for e in errs)


def test_lod_rejects_bad_arguments(cloud, tmp_path):
    with pytest.raises(ValueError, match="mode"):
        export_lod_gltf(cloud, tmp_path / "t.gltf", mode="zip")
    with pytest.raises(ValueError, match=r"\.gltf"):
        export_lod_gltf(cloud, tmp_path / "t.glb")
    with pytest.raises(TypeError, match="cloud"):
        lod_chain("tree")


def _validator() -> list[str] | None:
    """A node command running the Khronos validator, if its npm package is installed here."""
    node = shutil.which("node")
    if node is None:
        return None
    try:
        ok = subprocess.run([node, "-e", "require.resolve('gltf-validator')"], capture_output=True,
                            timeout=30).returncode == 0
    except (OSError, subprocess.TimeoutExpired):
        return None
    return [node] if ok else None


def test_khronos_validator_when_available(cloud, tmp_path):
    node = _validator()
    if node is None:
        pytest.skip("the gltf-validator npm package is not installed (validated by hand: see the report)")
    files = export_lod_gltf(cloud, tmp_path / "tree.gltf") + export_lod_gltf(cloud, tmp_path / "t.gltf",
                                                                              mode="files")
    script = ("const v=require('gltf-validator'),fs=require('fs');(async()=>{for(const f of process.argv.slice(1))"
              "{const r=await v.validateBytes(new Uint8Array(fs.readFileSync(f)));"
              "console.log(r.issues.numErrors+' '+r.issues.numWarnings)}})()")
    out = subprocess.run(node + ["-e", script, *map(str, files)], capture_output=True, text=True, timeout=120)
    assert out.stdout.split() == ["0", "0"] * len(files), out.stdout + out.stderr


def test_batch_billboard_job_writes_the_lod_chain(tmp_path):
    from branchnb.batch.jobs import get_job
    from branchnb.trees import VariationParams

    job = get_job("billboard_cloud")
    inputs = {**job.inputs, "from_variations": False, "image": 0, "lod": "msft_lod"}
    shared = {"images": [("rpg03", data.load("tree_rpg_03"))]}
    params = {"billboard": BillboardParams(max_size=96, n_segments=32, n_interior=8),
              "variation": VariationParams()}
    out = job.make(shared, params, inputs, np.random.default_rng(0), "cloud_00000")
    assert list(out.files) == ["cloud_00000.gltf"]
    assert set(out.info["lod_triangles"]) == {"full", "reduced", "crossed", "single"}
    p = Path(tmp_path) / "cloud_00000.gltf"
    p.write_bytes(out.files["cloud_00000.gltf"])
    assert validate_gltf(p) == []
    with pytest.raises(ValueError, match="lod"):
        job.make(shared, params, {**inputs, "lod": "yes"}, np.random.default_rng(0), "c")


def test_crossed_level_shows_the_side_view_with_its_outline():
    # Issue 24: the exported crossed quads repeated the front view on the turned quad; it now
    # carries the side view from 90 degrees as the in-memory side views draw it (inked rim).
    from branchnb.trees.drawn import drawn_tree
    from branchnb.trees.export import quad_vertices
    from branchnb.trees.lod import crossed_impostor
    from branchnb.trees.outline import rim_ink_share, silhouette_outline

    cloud = billboard_cloud(drawn_tree("fruit", rng=1, size=128), params=BillboardParams(max_size=128), rng=0)
    crossed, turn = crossed_impostor(cloud)
    assert crossed.n_billboards == 2 and turn.tolist() == [0.0, 90.0]
    side = render_cloud(cloud, 90.0)
    a = side[..., 3] >= 0.5
    ys, xs = np.nonzero(a)
    assert np.array_equal(crossed.textures[1], side[ys.min():ys.max() + 1, xs.min():xs.max() + 1])
    assert rim_ink_share(crossed.textures[1], silhouette_outline(cloud.image).ink) >= 0.95
    q = quad_vertices(crossed, turn=turn)
    assert np.allclose(q[1, :, 0], q[1, 0, 0]) and np.ptp(q[1, :, 2]) > 0     # the turned quad spans z
    assert np.allclose(q[0, :, 2], 0.0)
    chain = lod_chain(cloud)
    assert chain[2].name == "crossed" and chain[2].triangles == 4


def test_single_level_is_an_impostor_atlas_of_inked_views(tmp_path):
    from branchnb.trees.drawn import drawn_tree
    from branchnb.trees.outline import rim_ink_share, silhouette_outline

    cloud = billboard_cloud(drawn_tree("conifer", rng=2, size=128), params=BillboardParams(max_size=128), rng=0)
    single = lod_chain(cloud)[3]
    assert single.triangles == 2 and len(single.yaws) == 8 and len(single.cloud.textures) == 8
    shapes = {t.shape for t in single.cloud.textures}
    assert len(shapes) == 1                                       # the frames line up on one quad
    ink = silhouette_outline(cloud.image).ink
    for yaw, t in zip(single.yaws, single.cloud.textures):         # the front view as drawn
        assert rim_ink_share(t, ink) >= (0.9 if yaw else rim_ink_share(cloud.image, ink) - 0.02), yaw
    f = export_lod_gltf(cloud, tmp_path / "tree.gltf")[0]
    assert validate_gltf(f) == []
    frames = json.loads(f.read_text())["meshes"][3]["extras"]["impostor"]["frames"]
    assert [fr["yaw"] for fr in frames] == list(single.yaws)
    assert all(0 <= u <= 1 for fr in frames for u in fr["uv"])


@pytest.fixture(scope="module")
def drawn_cloud():
    from branchnb.trees.drawn import drawn_tree

    # The superpixel cloud (the fallback of drawn_cards): its side views need the baked outline and
    # the side cards. By default this tree's crown is whole cards now, which keep their rim ink
    # (test_default_cards_of_a_drawn_tree_keep_the_rim_ink).
    return billboard_cloud(drawn_tree("broadleaf", rng=3, size=128),
                           params=BillboardParams(max_size=128, drawn_cards=False), rng=0)


def test_default_cards_of_a_drawn_tree_keep_the_rim_ink():
    from branchnb.trees.drawn import drawn_tree
    from branchnb.trees.lod import engine_view
    from branchnb.trees.outline import rim_ink_share, silhouette_outline

    cloud = billboard_cloud(drawn_tree("broadleaf", rng=3, size=128), params=BillboardParams(max_size=128), rng=0)
    assert cloud.n_billboards < 20
    ink = silhouette_outline(cloud.image).ink
    full = lod_chain(cloud)[0]
    for yaw in (45.0, 90.0):
        assert rim_ink_share(engine_view(full.cloud, yaw, cards=full.cards), ink) >= 0.95


def test_exported_levels_keep_the_side_outline_of_drawn_trees(drawn_cloud):
    from branchnb.trees.lod import bake_side_outline, engine_view
    from branchnb.trees.outline import rim_ink_share, silhouette_outline

    ink = silhouette_outline(drawn_cloud.image).ink
    chain = lod_chain(drawn_cloud)
    for lv, bare in ((chain[0], drawn_cloud), (chain[1], reduce_cloud(drawn_cloud))):
        assert lv.cloud.n_billboards == bare.n_billboards
        # The front view is exactly as drawn; the side views gain ink on their rim.
        assert np.abs(engine_view(lv.cloud, 0.0) - engine_view(bare, 0.0)).max() < 1e-3
        for yaw in (45.0, 90.0):
            assert rim_ink_share(engine_view(lv.cloud, yaw), ink) >= rim_ink_share(engine_view(bare, yaw), ink)
    gain = rim_ink_share(engine_view(chain[0].cloud, 90.0), ink) - rim_ink_share(engine_view(drawn_cloud, 90.0), ink)
    assert gain > 0.1, gain
    # A cloud without an outlined silhouette is left as it is.
    from branchnb.trees.synthetic import synthetic_tree

    plain = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    same = bake_side_outline(plain)
    assert all(a is b or np.array_equal(a, b) for a, b in zip(same.textures, plain.textures))


def test_side_cards_ink_the_side_rim_and_leave_the_front_view(drawn_cloud, tmp_path):
    # Issue 24: baking alone reached 0.83 rim ink at 90 degrees on the full level (the front
    # billboards' edge texels show in the front view); fixed quads edge-on to the front view
    # carry the rest of the ink.
    from scipy import ndimage as ndi

    from branchnb.trees.lod import engine_view
    from branchnb.trees.lod_cards import side_outline_cards
    from branchnb.trees.outline import _depth, rim_ink_share, silhouette_outline

    o = silhouette_outline(drawn_cloud.image)
    full = lod_chain(drawn_cloud)[0]
    assert full.cards is not None and full.cards.n > 0
    assert {90.0, 270.0} <= set(full.cards.turn.tolist())
    assert len(set(full.cards.turn.tolist())) > 2                 # oblique sides' cards, turned
    front = engine_view(full.cloud, 0.0)
    assert np.abs(engine_view(full.cloud, 0.0, cards=full.cards) - front).max() == 0.0
    for yaw in (90.0, 270.0):
        baked = rim_ink_share(engine_view(full.cloud, yaw), o.ink)
        carded = rim_ink_share(engine_view(full.cloud, yaw, cards=full.cards), o.ink)
        assert carded >= 0.95 and carded > baked, (yaw, baked, carded)
    # Issue 24: at 45 and 135 degrees the full level's rim stayed where the bake put it (0.81
    # over 12 drawn trees); the oblique sides' cards carry it.
    for yaw in (45.0, 135.0):
        baked = rim_ink_share(engine_view(full.cloud, yaw), o.ink)
        carded = rim_ink_share(engine_view(full.cloud, yaw, cards=full.cards), o.ink)
        assert carded >= 0.9 and carded > baked + 0.05, (yaw, baked, carded)
    # Seen obliquely the cards add little ink inside the crown.
    for yaw in (45.0, 135.0):
        a, b = engine_view(full.cloud, yaw), engine_view(full.cloud, yaw, cards=full.cards)
        op = b[..., 3] >= 0.5
        deep = _depth(ndi.binary_fill_holes(op)) > 2 * o.width + 1
        new = (np.abs(a - b).max(axis=2) > 0) & deep
        assert new.sum() <= 0.01 * op.sum(), (yaw, new.sum(), op.sum())
    # Exported as a second primitive with a single-sided material.
    f = export_lod_gltf(drawn_cloud, tmp_path / "t.gltf")[0]
    assert validate_gltf(f) == []
    doc = json.loads(f.read_text())
    prims = doc["meshes"][0]["primitives"]
    assert len(prims) == 2 and doc["materials"][prims[1]["material"]]["doubleSided"] is False
    assert doc["meshes"][0]["extras"]["side_cards"]["quads"] == full.cards.n
    with pytest.raises(TypeError, match="cards"):
        engine_view(full.cloud, 90.0, cards="yes")
    with pytest.raises(ValueError, match="offset"):
        side_outline_cards(drawn_cloud, offset=0.0)


def test_side_cards_ink_a_broadleafs_oblique_rim():
    # Issue 24: the rear billboards on a broadleaf's 45 degree rim show deep inside the views
    # from 90 to 210 degrees; with turns every 30 degrees and ink allowed 2 w + 1 inside other
    # views its cards kept too few texels (0.87 at 96 px). Turns every 15 degrees and 3 w + 1.
    from scipy import ndimage as ndi

    from branchnb.trees.drawn import drawn_trees
    from branchnb.trees.lod import bake_side_outline, engine_view
    from branchnb.trees.lod_cards import side_outline_cards
    from branchnb.trees.outline import _depth, rim_ink_share, silhouette_outline

    img = dict(drawn_trees((False,), rng=11, size=96))["broadleaf_0"]
    cloud = billboard_cloud(img, params=BillboardParams(max_size=96), rng=0)
    o = silhouette_outline(cloud.image)
    baked = bake_side_outline(cloud)
    cards = side_outline_cards(cloud, baked=baked)
    assert all((t[..., 3] >= 0.5).any() for t in cards.textures)          # no empty card
    assert rim_ink_share(engine_view(baked, 45.0, cards=cards), o.ink) >= 0.9
    for yaw in (45.0, 90.0, 135.0):                                        # little ink inside
        a, b = engine_view(baked, yaw), engine_view(baked, yaw, cards=cards)
        op = b[..., 3] >= 0.5
        deep = _depth(ndi.binary_fill_holes(op)) > 2 * o.width + 1
        assert ((np.abs(a - b).max(axis=2) > 0) & deep).sum() <= 0.02 * op.sum(), yaw
