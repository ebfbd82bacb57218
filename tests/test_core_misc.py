from dataclasses import dataclass

import numpy as np
import pytest

from branchnb import data
from branchnb.bench import BenchRow, format_table
from branchnb.cli import lab_command, main
from branchnb.core.params import check_params, param
from branchnb.core.random import as_rng


def test_as_rng():
    assert as_rng(3).random() == as_rng(3).random()
    g = np.random.default_rng(1)
    assert as_rng(g) is g
    with pytest.raises(TypeError, match="rng"):
        as_rng(1.5)
    with pytest.raises(ValueError, match="non-negative"):
        as_rng(-1)


def test_data_load_and_names():
    names = data.names()
    assert {"retina_fundus", "lizard", "tree_rpg_01", "astronaut"} <= set(names)
    img = data.load("tree_rpg_01")
    assert img.dtype == np.float32 and img.shape[2] == 4 and 0 <= img.min() and img.max() <= 1
    assert data.load("camera").shape == (512, 512, 1)
    assert set(data.names("trees")) >= {"tree_rpg_01", "tree_rpg_14"}
    with pytest.raises(ValueError, match="unknown sample name 'nope'"):
        data.load("nope")
    with pytest.raises(ValueError, match="unknown category"):
        data.names("nope")
    with pytest.raises(TypeError, match="name must be a str"):
        data.load(3)


def test_every_data_file_has_a_licence_line():
    readme = (data.DATA_DIR / "README.md").read_text()
    for name in data.names():
        if name not in data.names("skimage"):
            assert data.path(name).name in readme, f"{name} has no attribution line in data/README.md"


@dataclass
class _P:
    k: int = param(3, min=1, max=10)
    w: float = param(0.5, min=0.0, max=1.0)
    mode: str = param("a", options=("a", "b"))
    on: bool = param(True)


def test_check_params():
    assert check_params(_P()) == _P()
    with pytest.raises(ValueError, match=r"params\.k must be >= 1"):
        check_params(_P(k=0))
    with pytest.raises(ValueError, match=r"params\.w must be <= 1"):
        check_params(_P(w=2.0))
    with pytest.raises(ValueError, match="mode must be one of"):
        check_params(_P(mode="c"))
    with pytest.raises(TypeError, match="k must be an int"):
        check_params(_P(k="3"))
    with pytest.raises(TypeError, match="on must be a bool"):
        check_params(_P(on=1))


def test_lab_command_adds_allow_root_only_for_root(monkeypatch):
    import os

    monkeypatch.setattr(os, "geteuid", lambda: 0)
    cmd = lab_command()
    assert "--allow-root" in cmd and cmd[-2].endswith("00_tour.ipynb")
    monkeypatch.setattr(os, "geteuid", lambda: 1000)
    assert "--allow-root" not in lab_command("x.ipynb")


def test_bench_table_and_ratio():
    row = BenchRow("op", 0.5, "anchor", 2.0)
    assert row.ratio == 0.25
    assert "0.250" in format_table([row])


def test_gallery_writes_pngs(tmp_path):
    from branchnb.gallery import build

    items = build(tmp_path, sections=())
    assert len(items) >= 4 and (tmp_path / "index.html").exists()
    for it in items:
        assert (tmp_path / it.filename).stat().st_size > 1000


def test_cli_gallery(tmp_path, capsys, monkeypatch):
    import branchnb.gallery

    monkeypatch.setattr(branchnb.gallery, "SECTIONS", ())
    assert main(["gallery", str(tmp_path / "g")]) == 0
    assert "index.html" in capsys.readouterr().out


def test_metrics():
    from branchnb.core.metrics import iou, psnr

    a = np.zeros((4, 4, 3))
    b = a.copy()
    b[0, 0] = 0.5
    m = np.zeros((4, 4), bool)
    m[1:, 1:] = True
    assert psnr(a, a) == np.inf and psnr(a, b, m) == np.inf
    assert psnr(a, b) == pytest.approx(10 * np.log10(1 / (0.25 * 3 / 48)))
    assert iou(m, m) == 1.0 and iou(m, ~m) == 0.0
    with pytest.raises(ValueError, match="same shape"):
        psnr(a, a[:2])
    with pytest.raises(ValueError, match="no pixel"):
        psnr(a, b, np.zeros((4, 4), bool))
