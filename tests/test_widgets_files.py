"""Open image, save and load annotations: the kit's FileBar and every app's hooks."""

from __future__ import annotations

import datetime
import json
import xml.etree.ElementTree as ET

import cv2
import numpy as np
import pytest

from branchnb.core.io import encode_png
from branchnb.widgets.feedback import StatusLine
from branchnb.widgets.files import FileBar, canvases_json, check_file, decode_image, load_canvases
from branchnb.widgets.model import AnnotationModel

NOW = datetime.datetime(2026, 1, 1, tzinfo=datetime.timezone.utc)


def _valid(path):
    """The file parses as what its name says (the check a user's viewer would make)."""
    data = path.read_bytes()
    ext = path.suffix
    if ext == ".png":
        assert cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED) is not None, path
    elif ext in (".json", ".gltf"):
        d = json.loads(data)
        if ext == ".gltf":
            assert d["asset"]["version"] == "2.0" and d["meshes"]
            assert all(b["uri"].startswith("data:") for b in d["buffers"])
    elif ext == ".svg":
        assert ET.fromstring(data).tag.endswith("svg")


def test_decode_image_keeps_alpha_and_names_a_bad_file():
    rgba = np.zeros((5, 7, 4), np.float32)
    rgba[1:4, 2:5] = (1.0, 0.5, 0.0, 1.0)
    out = decode_image(encode_png(rgba), "a.png")
    assert out.shape == (5, 7, 4) and out.dtype == np.float32
    assert np.allclose(out, rgba, atol=1 / 255)
    ok, jpg = cv2.imencode(".jpg", np.full((6, 6, 3), 200, np.uint8))
    assert decode_image(jpg.tobytes()).shape == (6, 6, 3)
    for bad in (b"", b"hello", b"\x89PNG\r\n\x1a\n broken"):
        with pytest.raises(ValueError, match="holiday.png: not an image"):
            decode_image(bad, "holiday.png")


@pytest.mark.parametrize("name, data, message", [
    ("a.png", b"not a png", "does not decode"),
    ("a.json", b'{"x": Infinity}', "not valid JSON"),
    ("a.json", b"{x}", "not valid JSON"),
    ("a.svg", b"<svg><g></svg>", "not well-formed"),
    ("a.svg", b"<html/>", "not <svg>"),
    ("a.gltf", b'{"asset": {"version": "1.0"}}', "not a glTF 2.0"),
    ("a.gltf", b'{"asset": {"version": "2.0"}, "buffers": [{"uri": "a.bin"}]}', "not written with it"),
])
def test_check_file_refuses_invalid_files(name, data, message):
    with pytest.raises(ValueError, match=message):
        check_file(name, data)


def test_save_writes_checked_files_and_download_links(tmp_path):
    status = StatusLine()
    img = np.random.default_rng(0).random((9, 11, 4)).astype(np.float32)
    bar = FileBar(errors=status, name="demo", outputs=lambda: {"img.png": img, "info.json": {"n": 3},
                                                               "pic.svg": "<svg xmlns='http://www.w3.org/2000/svg'/>"},
                  annotations=lambda: AnnotationModel().to_json())
    bar.folder.value = str(tmp_path / "out")
    bar.save_button.click()
    assert status.last_error is None and "saved 4 files" in status.text
    names = sorted(p.name for p in (tmp_path / "out").iterdir())
    assert names == ["demo_annotations.json", "demo_img.png", "demo_info.json", "demo_pic.svg"]
    for p in (tmp_path / "out").iterdir():
        _valid(p)
    back = decode_image((tmp_path / "out" / "demo_img.png").read_bytes())
    assert np.abs(back - img).max() <= 0.5 / 255 + 1e-6          # lossless (8 bit)
    assert bar.links.value.count("download=") == 4 and bar.links.layout.display is None
    # an invalid output is refused before anything is written
    bad = FileBar(errors=status, name="bad", outputs=lambda: {"x.json": float("nan")})
    bad.folder.value = str(tmp_path / "bad")
    bad.save_button.click()
    assert "ValueError" in status.last_error or "TypeError" in status.last_error
    assert not (tmp_path / "bad").exists() or not list((tmp_path / "bad").iterdir())
    with pytest.raises(ValueError, match="plain file name"):
        FileBar(errors=status, name="x", outputs=lambda: {"../up.png": img}).contents()
    with pytest.raises(ValueError, match="nothing to save"):
        FileBar(errors=status, outputs=lambda: {}).contents()


def test_annotations_round_trip_through_json_and_bad_files_change_nothing():
    a, b = AnnotationModel(), AnnotationModel()
    a.add_shape("stroke", [(1, 2), (3, 4)])
    b.add_shape("point", [(5, 6)])
    text = canvases_json({"source": a, "target": b}, app="strokes", extra={"k": 1})
    a2, b2 = AnnotationModel(), AnnotationModel()
    assert load_canvases(text, {"source": a2, "target": b2}, app="strokes") == {"k": 1}
    assert a2.to_json() == a.to_json() and b2.to_json() == b.to_json()
    with pytest.raises(ValueError, match="saved by the 'strokes' app"):
        load_canvases(text, {"source": a2, "target": b2}, app="leaves")
    with pytest.raises(ValueError, match="no canvas named"):
        load_canvases(text, {"source": a2}, app="strokes")
    broken = json.loads(text)
    broken["canvases"]["target"] = {"shapes": [{"kind": "nope", "points": [[0, 0]]}]}
    before = a2.to_json()
    with pytest.raises(ValueError):
        load_canvases(json.dumps(broken), {"source": a2, "target": b2}, app="strokes")
    assert a2.to_json() == before                                   # nothing half-loaded
    # a plain model's JSON goes to the first canvas
    assert load_canvases(a.to_json(), {"only": b2}) == {} and b2.to_json() == a.to_json()
    for bad in ("", "[]", "{}", '{"canvases": 3}'):
        with pytest.raises(ValueError):
            load_canvases(bad, {"source": a2})


def test_upload_widgets_hand_files_to_the_hooks():
    status = StatusLine()
    got = []
    bar = FileBar(errors=status, open=lambda imgs: got.extend(imgs) or "ok", load=got.append, multiple=True)
    png = encode_png(np.ones((3, 4, 3)))
    bar.upload.value = ({"name": "a.png", "type": "image/png", "size": len(png), "content": memoryview(png),
                         "last_modified": NOW},)
    assert [(n, im.shape) for n, im in got] == [("a", (3, 4, 3))] and status.last_error is None
    assert "opened a.png | ok" in status.text
    bar.upload.value = ({"name": "b.txt", "type": "text/plain", "size": 2, "content": memoryview(b"hi"),
                         "last_modified": NOW},)
    assert "b.txt: not an image" in status.last_error
    bar.annotation_upload.value = ({"name": "n.json", "type": "application/json", "size": 2,
                                    "content": memoryview(b"{}"), "last_modified": NOW},)
    assert got[-1] == "{}"
    assert "(" not in bar.style.value.split("content:")[1][:30]     # the label, not "(0)"


# -- the apps' hooks ------------------------------------------------------------------------
def _save(app, tmp_path):
    app.shell.files.folder.value = str(tmp_path)
    paths = app.shell.files.save()
    for p in paths:
        _valid(p)
    return {p.name: p for p in paths}


def test_branching_app_opens_saves_and_restores(tmp_path):
    from branchnb.branching import Branch, Structure
    from branchnb.widgets.branching import BranchingApp

    t = np.linspace(0, 1, 40)
    s = Structure([Branch(np.c_[10 + 100 * t, 50 + 8 * np.sin(7 * t)], 2.0)], image_shape=(100, 130))
    app = BranchingApp(np.ones((100, 130, 3)), structure=s)
    assert app.result_controls.layout.display == "none"            # nothing to extend yet
    app.shell.click("synthesize")
    assert app.result_controls.layout.display is None
    files = _save(app, tmp_path)
    assert set(files) == {"branching_structure.json", "branching_structure.svg", "branching_structure.png",
                          "branching_annotations.json"}
    assert Structure.from_json(files["branching_structure.json"].read_text()).n_vertices == \
        app.result.structure.n_vertices
    shapes = app.canvas.model.to_json()
    app.canvas.buttons["clear"].click()
    assert app.view.stale and app.view.title_texts[0].startswith("out of date")
    app.shell.files.load_text(files["branching_annotations.json"].read_text())
    assert app.canvas.model.to_json() == shapes
    app.shell.files.open_files([("mine.png", encode_png(np.zeros((60, 90, 3))))])
    assert app.image.shape == (60, 90, 3) and len(app.canvas.model) == 0 and app.result is None


def test_dendrite_app_saves_png_and_svg_and_opens_an_image(tmp_path):
    from branchnb.dendrite import StylizeParams
    from branchnb.widgets.dendrite import DendriteApp

    img = np.ones((48, 48))
    img[12:36, 12:36] = 0.0
    app = DendriteApp(img, params=StylizeParams(n_endpoints=40, stipple_iterations=3))
    app.set_seed((10, 10))
    files = _save(app, tmp_path)
    assert set(files) == {"dendrite_stylize.png", "dendrite_stylize.svg", "dendrite_annotations.json"}
    app.shell.files.open_files([("x.png", encode_png(np.random.default_rng(1).random((30, 40))))])
    assert app.image.shape == (30, 40, 3) and app.seed is None and app.rendering is not None
    app.shell.files.load_text(files["dendrite_annotations.json"].read_text())
    assert app.seed.tolist() == [10.0, 10.0]


def test_strokes_app_saves_the_result_and_restores_both_canvases(tmp_path):
    from branchnb.widgets.strokes import StrokeEditApp

    img = np.zeros((40, 80, 4), np.float32)
    img[15:25, 5:75] = (0.6, 0.4, 0.2, 1.0)
    app = StrokeEditApp(img, max_display=200)
    app.add_stroke("source", [(8, 20), (72, 20)])
    app.add_stroke("target", [(40, 5), (40, 35)])
    files = _save(app, tmp_path)
    assert set(files) == {"strokes_result.png", "strokes_annotations.json"}
    assert decode_image(files["strokes_result.png"].read_bytes()).shape[2] == 4
    app.shell.files.open_files([("y.png", encode_png(img[::-1]))])
    assert app.result is None and len(app.source_canvas.model) == 0
    app.shell.files.load_text(files["strokes_annotations.json"].read_text())
    assert app.result is not None and len(app.target_canvas.model) == 1


def test_trees_app_adds_trees_and_saves_the_mix(tmp_path):
    from branchnb import data
    from branchnb.trees.variations import TreeLibrary
    from branchnb.widgets.trees import TreeVariationsApp

    app = TreeVariationsApp(TreeLibrary.from_data(["tree_rpg_01", "tree_rpg_03"], size=96), display=96, thumb=32)
    app.set_weight("tree_rpg_01", 0.7)
    files = _save(app, tmp_path)
    assert set(files) == {"trees_variation.png", "trees_mix.json", "trees_annotations.json"}
    assert json.loads(files["trees_mix.json"].read_text())["weights"] == pytest.approx([0.7, 0.3])
    app.shell.files.open_files([("oak.png", encode_png(data.load("tree_rpg_06"))),
                                ("oak.png", encode_png(data.load("tree_rpg_08")))])
    assert app.library.names[2:] == ["oak", "oak_2"] and app.selected == ["oak", "oak_2"]
    assert "oak" in app.morph_a.options and "oak_2" in app.seg_tree.options
    app.shell.files.load_text(files["trees_annotations.json"].read_text())
    assert app.selected == ["tree_rpg_01", "tree_rpg_03"] and app.weights.tolist() == pytest.approx([0.7, 0.3])


def test_leaves_app_opens_exemplars_and_restores_layers(tmp_path):
    from branchnb.leaves import leaf_family
    from branchnb.widgets.leaves import LeafApp

    app = LeafApp(leaf_family(2, size=96, rng=0))
    app.add_layer("rim", "#00ff00")
    app.canvas.model.add_shape("scribble", [(40, 40), (50, 50)], label="rim")
    files = _save(app, tmp_path)
    assert set(files) == {"leaves_annotations.json"}                 # nothing generated yet
    with pytest.raises(ValueError, match="two or more"):
        app.shell.files.open_files([("one.png", encode_png(leaf_family(1, size=80, rng=1)[0].image))])
    fam = leaf_family(3, size=80, rng=1)
    app.shell.files.open_files([(f"l{i}.png", encode_png(f.image)) for i, f in enumerate(fam)])
    assert len(app.images) == 3 and len(app.canvas.model) == 0 and app.analysis is None
    app.remove_layer("rim")
    app.shell.files.load_text(files["leaves_annotations.json"].read_text())
    assert app.layer_names() == ["veins", "spots", "rim"] and app.canvas.model.shapes[0].label == "rim"


def test_page_mode_offers_downloads_only(tmp_path, monkeypatch):
    monkeypatch.chdir(tmp_path)
    status = StatusLine()
    bar = FileBar(errors=status, name="p", outputs=lambda: {"a.png": np.zeros((3, 3, 3))})
    bar.use_page_mode()
    bar.save_button.click()
    assert status.last_error is None and "ready" in status.text
    assert bar.folder.layout.display == "none" and "download='p_a.png'" in bar.links.value
    assert list(tmp_path.iterdir()) == []                  # nothing written on the server
