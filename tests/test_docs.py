"""The documentation site builds from the repository with warnings as errors and no network."""

from __future__ import annotations

import re
import time
from pathlib import Path

import pytest

pytest.importorskip("sphinx")
pytest.importorskip("myst_nb")
pytest.importorskip("numpydoc")

from branchnb import cli, gallery  # noqa: E402
from branchnb._docs import NOTEBOOKS_DIR, build, public_api  # noqa: E402
from branchnb.bench import BenchRow  # noqa: E402

ROWS = [BenchRow("plan 256 x 256 | nonscalar", 0.0123, "skimage.graph.MCP_Geometric", 0.0246, "same run"),
        BenchRow("a *starred* name", 2.0, "paper figure `x`", 1.0, "")]


@pytest.fixture(scope="module")
def site(tmp_path_factory):
    out = tmp_path_factory.mktemp("docs")
    pictures = out / "gallery"
    gallery.build(pictures, sections=())        # the sample pictures only: seconds, not minutes
    t0 = time.perf_counter()
    index = build(out, strict=True, log=None, gallery_dir=pictures, bench_rows=ROWS)
    return index.parent, time.perf_counter() - t0


def test_site_builds_strictly_with_every_section(site):
    html, seconds = site
    print(f"docs build: {seconds:.1f} s")
    for page in ("index.html", "install.html", "conventions.html", "batch.html", "cli.html", "bench.html",
                 "gallery.html", "notebook_style.html", "api/index.html", "notebooks/index.html",
                 *(f"techniques/{t}.html" for t in ("branching", "trees", "dendrite", "leaves", "strokes"))):
        assert (html / page).is_file(), page
    for nb in sorted(NOTEBOOKS_DIR.glob("*.ipynb")):
        assert (html / "notebooks" / f"{nb.stem}.html").is_file(), nb.name


def test_every_public_name_has_an_entry_in_the_api_reference(site):
    html, _ = site
    ids = set()
    for page in (html / "api").glob("*.html"):
        ids |= set(re.findall(r'<dt class="sig sig-object py" id="([^"]+)"', page.read_text(encoding="utf-8")))
    api = public_api()
    missing = [f"{m}.{n}" for m, entry in api.items() for n, _ in entry.own if f"{m}.{n}" not in ids]
    assert not missing, missing[:20]
    assert len(ids) > 300


def test_references_between_docstrings_are_links(site):
    html, _ = site
    text = (html / "api" / "branching.html").read_text(encoding="utf-8")
    # Structure is documented once, in the core, and the branching page links there
    assert 'href="core.html#branchnb.core.Structure"' in text
    assert 'id="branchnb.branching.Structure"' not in text


def test_notebooks_are_rendered_from_their_stored_outputs(site):
    html, _ = site
    tour = html / "notebooks" / "00_tour.html"
    if not tour.is_file():
        pytest.skip("no notebooks in this copy")
    text = tour.read_text(encoding="utf-8")
    assert "<img" in text                       # the stored figures
    gallery = (html / "gallery.html").read_text(encoding="utf-8")
    assert gallery.count("<figure>") >= 10 and "notebooks/00_tour.html#" in gallery


def test_gallery_and_bench_pages_show_what_was_measured(site):
    html, _ = site
    gallery_page = (html / "gallery.html").read_text(encoding="utf-8")
    assert "branchnb gallery" in gallery_page and "samples_lizard.png" in gallery_page
    assert (html / "_static" / "gallery" / "cmd_samples_lizard.png").is_file()
    bench = (html / "bench.html").read_text(encoding="utf-8")
    assert "skimage.graph.MCP_Geometric" in bench and "0.500" in bench and "2.000" in bench   # the ratios
    assert "a *starred* name" in bench                                                    # escaped, verbatim


def test_build_reports_a_broken_reference(tmp_path, monkeypatch):
    from branchnb import _docs

    pages = tmp_path / "pages"
    (pages).mkdir()
    (pages / "index.md").write_text("# x\n\nSee {func}`branchnb.core.no_such_function`.\n")
    (pages / "bench.rst").write_text("Bench\n=====\n")
    monkeypatch.setattr(_docs, "HERE", _docs.HERE)  # the real conf.py and static files
    monkeypatch.setattr(_docs, "write_api", lambda src: [])
    real_copytree = _docs.shutil.copytree

    def copytree(src, dst, **kw):  # the pages come from the temporary folder
        return real_copytree(pages if Path(src).name == "pages" else src, dst, **kw)

    monkeypatch.setattr(_docs.shutil, "copytree", copytree)
    with pytest.raises(RuntimeError, match="no_such_function"):
        build(tmp_path / "out", notebooks=None, log=None)


def test_cli_docs_rejects_a_gallery_dir_without_index(tmp_path, capsys):
    code = cli.main(["docs", "--no-open", "--out", str(tmp_path / "o"), "--gallery-dir", str(tmp_path)])
    assert code == 1 and "holds no index.html" in capsys.readouterr().err
