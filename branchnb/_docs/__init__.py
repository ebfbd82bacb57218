"""The documentation site: Sphinx + numpydoc + MyST-NB, built from the repository.

:func:`build` gathers one source folder and runs Sphinx on it:

* the hand-written pages of ``branchnb/_docs/pages`` (install, quick start, one
  page per technique with its paper, the batch guide, the notebook style);
* the notebooks of ``notebooks/``, rendered from their stored outputs (never
  executed here);
* an API reference generated from the docstrings: every name of every public
  module's ``__all__``, each documented once, where it is re-exported from its
  package (:func:`public_api`);
* a gallery of the notebooks' figures, plus ``branchnb gallery``'s pictures
  when asked for;
* the bench table when asked for (``branchnb bench`` takes minutes).

No step reaches the network. ``branchnb docs`` calls :func:`build` and opens the
result in a browser.
"""

from __future__ import annotations

import base64
import html
import importlib
import inspect
import json
import pkgutil
import re
import shutil
import time
from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path

__all__ = ["build", "public_api", "ApiModule", "NOTEBOOKS_DIR", "DEFAULT_OUTDIR"]

HERE = Path(__file__).resolve().parent
ROOT = HERE.parent.parent
#: The checkout's notebooks (absent in an installed wheel: the site is then built without them).
NOTEBOOKS_DIR = ROOT / "notebooks"
#: Where ``branchnb docs`` builds by default: ``build/docs`` of the checkout (git-ignored).
DEFAULT_OUTDIR = ROOT / "build" / "docs"

# API pages in reading order: (page file stem, title, leading package).
API_GROUPS = (
    ("core", "Core: what the techniques share", "branchnb.core"),
    ("branching", "Branching-structure synthesis", "branchnb.branching"),
    ("dendrite", "Dendritic structures by path planning", "branchnb.dendrite"),
    ("trees", "Image-based tree variations", "branchnb.trees"),
    ("leaves", "Leaf variations by structural layering", "branchnb.leaves"),
    ("strokes", "Structure editing with user strokes", "branchnb.strokes"),
    ("widgets", "Widgets: the kit and the apps", "branchnb.widgets"),
    ("batch", "Batch generation on Dask", "branchnb.batch"),
    ("misc", "Sample data, plotting, gallery, bench and command line", "branchnb"),
)


@dataclass
class ApiModule:
    """The public names of one module, as the API reference shows them.

    Attributes
    ----------
    name : str
        Dotted module name, e.g. ``"branchnb.core"``.
    own : list of (str, object)
        Names documented on this module's section (their canonical place).
    elsewhere : list of (str, str)
        Names this module re-exports from a module documented elsewhere, as
        ``(name, canonical dotted path)``.
    """

    name: str
    own: list = field(default_factory=list)
    elsewhere: list = field(default_factory=list)


def _public_modules() -> list[str]:
    import branchnb

    names = ["branchnb"]
    for info in pkgutil.walk_packages(branchnb.__path__, "branchnb."):
        parts = info.name.split(".")[1:]
        if any(p.startswith("_") for p in parts):
            continue
        names.append(info.name)
    return names


def _exports(mod) -> list[str]:
    if hasattr(mod, "__all__"):
        return [str(n) for n in mod.__all__]
    return [k for k, v in vars(mod).items()
            if not k.startswith("_") and getattr(v, "__module__", None) == mod.__name__
            and (inspect.isclass(v) or inspect.isfunction(v))]


def _key(name: str, obj) -> tuple:
    # Functions and classes are the same object wherever re-exported; plain values
    # (small ints, strings) may share an id by accident, so their name joins the key.
    if inspect.isclass(obj) or inspect.isroutine(obj) or callable(obj):
        return ("obj", id(obj))
    return ("value", name, id(obj))


def public_api() -> dict[str, ApiModule]:
    """Every public name of the package, each assigned one canonical module.

    A module is public when no part of its dotted name starts with ``_``; its
    public names are its ``__all__`` (or, without one, the classes and functions
    it defines). A name exported by several modules is documented where it is
    highest in the package tree among the modules that export it *and* contain
    its definition (so :class:`branchnb.core.Structure`, defined in
    ``branchnb.core.structure``, belongs to ``branchnb.core``; ``branchnb.branching``
    links to it).

    Returns
    -------
    dict of str -> ApiModule
        By module name, in package order.

    Examples
    --------
    >>> api = public_api()
    >>> any(n == "resample_uniform" for n, _ in api["branchnb.core"].own)
    True
    """
    modules = {}
    for name in _public_modules():
        modules[name] = importlib.import_module(name)
    exports = {name: [(n, getattr(mod, n)) for n in _exports(mod) if hasattr(mod, n)]
               for name, mod in modules.items()}
    holders: dict[tuple, list[str]] = {}
    for mod_name, items in exports.items():
        for n, obj in items:
            holders.setdefault(_key(n, obj), []).append(mod_name)

    def canonical(n, obj) -> str:
        cands = holders[_key(n, obj)]
        defined = getattr(obj, "__module__", None) if (inspect.isclass(obj) or inspect.isroutine(obj)) else None
        if defined:
            ancestors = [m for m in cands if defined == m or defined.startswith(m + ".")]
            if ancestors:
                return min(ancestors, key=lambda m: (m.count("."), m))
        return min(cands, key=lambda m: (m.count("."), m))

    api = {}
    for mod_name, items in exports.items():
        entry = ApiModule(mod_name)
        for n, obj in items:
            home = canonical(n, obj)
            if home == mod_name:
                entry.own.append((n, obj))
            else:
                entry.elsewhere.append((n, f"{home}.{n}"))
        api[mod_name] = entry
    return api


def _directive(mod: str, name: str, obj) -> list[str]:
    target = f"{mod}.{name}"
    if inspect.isclass(obj):
        if issubclass(obj, BaseException):
            return [f".. autoexception:: {target}"]
        return [f".. autoclass:: {target}", "   :members:"]
    if inspect.ismodule(obj):
        return [f"* :mod:`{obj.__name__}`"]
    if callable(obj):  # functions, and numba dispatchers or partials that act as functions
        return [f".. autofunction:: {target}"]
    return [f".. autodata:: {target}", "   :no-value:"]


def _shadowed(mod_name: str) -> bool:
    """True when the parent package has an attribute of this module's name that is not the module.

    ``branchnb.strokes.fetch`` is both a module and the function the package
    exports; the function keeps the dotted name, the module section is not indexed.
    """
    if "." not in mod_name:
        return False
    parent, leaf = mod_name.rsplit(".", 1)
    value = getattr(importlib.import_module(parent), leaf, None)
    return value is not None and not inspect.ismodule(value)


def _underline(text: str, char: str) -> str:
    return f"{text}\n{char * len(text)}"


def _group_of(mod_name: str) -> str:
    for stem, _title, lead in API_GROUPS[:-1]:
        if mod_name == lead or mod_name.startswith(lead + "."):
            return stem
    return "misc"


def write_api(src: Path, api: dict[str, ApiModule] | None = None) -> list[str]:
    """Write ``api/*.rst`` (one page per technique, the core, widgets, batch, misc) into ``src``.

    Returns the page names for the toctree.
    """
    api = public_api() if api is None else api
    out = src / "api"
    out.mkdir(parents=True, exist_ok=True)
    pages = []
    for stem, title, _lead in API_GROUPS:
        mods = [m for m in api.values() if _group_of(m.name) == stem and (m.own or m.elsewhere)]
        if not mods:
            continue
        lines = [_underline(title, "="), ""]
        for m in mods:
            lines += [_underline(m.name, "-"), "", f".. automodule:: {m.name}", "   :no-members:"]
            lines += (["   :no-index:"] if _shadowed(m.name) else []) + ["", f".. currentmodule:: {m.name}", ""]
            if m.own:
                lines += [".. list-table::", "   :widths: 35 65", ""]
                for n, obj in m.own:
                    summary = _summary(obj)
                    role = _role(obj)
                    lines += [f"   * - :{role}:`~{m.name}.{n}`", f"     - {summary}"]
                lines.append("")
            if m.elsewhere:
                refs = ", ".join(f":{_role_for_path(p)}:`~{p}`" for _n, p in m.elsewhere)
                lines += [".. rst-class:: bnb-api-also", "", f"Also exported here: {refs}.", ""]
            for n, obj in m.own:
                lines += _directive(m.name, n, obj) + [""]
        (out / f"{stem}.rst").write_text("\n".join(lines), encoding="utf-8")
        pages.append(f"api/{stem}")
    index = [_underline("API reference", "="), "",
             "Every public name of every public module, generated from the docstrings. A name that a package",
             "re-exports is documented once, where it is exported highest in the tree; the other modules link to it.",
             "", ".. toctree::", "   :maxdepth: 1", ""] + [f"   {p.split('/')[1]}" for p in pages]
    (out / "index.rst").write_text("\n".join(index) + "\n", encoding="utf-8")
    return pages


def _role(obj) -> str:
    if inspect.isclass(obj):
        return "exc" if issubclass(obj, BaseException) else "class"
    if inspect.ismodule(obj):
        return "mod"
    if callable(obj):
        return "func"
    return "data"


def _role_for_path(path: str) -> str:
    mod, name = path.rsplit(".", 1)
    return _role(getattr(importlib.import_module(mod), name))


def _summary(obj) -> str:
    if not (inspect.isclass(obj) or callable(obj) or inspect.ismodule(obj)):
        return f"``{_short_repr(obj)}``"
    doc = inspect.getdoc(obj) or ""
    first = doc.strip().split("\n\n")[0].replace("\n", " ").strip()
    # The overview table sits outside the docstring's module, where its relative
    # references would not resolve: they become code text (the entry below links).
    first = _ROLE.sub(lambda m: f"``{m.group(2).lstrip('.').split('.')[-1] if m.group(1) else m.group(2)}``",
                      first)
    return first or "(no description)"


_ROLE = re.compile(r":(?:[a-z]+:)?[a-z]+:`(~?)([^`<]+?)`")


def _short_repr(value) -> str:
    text = " ".join(repr(value).split()).replace("`", "'")
    return text if len(text) <= 60 else text[:57] + "..."


# --- notebooks and gallery -------------------------------------------------------------------

_HEADING = re.compile(r"^(#{1,3})\s+(.*)$", re.M)


def copy_notebooks(src: Path, notebooks: Path | None) -> list[str]:
    """Copy ``notebooks/*.ipynb`` (and ``notebooks/figures``) into ``src/notebooks``; their page names."""
    if notebooks is None or not Path(notebooks).is_dir():
        return []
    dst = src / "notebooks"
    dst.mkdir(parents=True, exist_ok=True)
    pages = []
    for nb in sorted(Path(notebooks).glob("*.ipynb")):
        shutil.copy2(nb, dst / nb.name)
        pages.append(f"notebooks/{nb.stem}")
    figures = Path(notebooks) / "figures"
    if figures.is_dir():
        shutil.copytree(figures, dst / "figures", dirs_exist_ok=True)
    return pages


def _title_of(cells) -> str:
    for cell in cells:
        if cell.get("cell_type") == "markdown":
            m = _HEADING.search(_text(cell.get("source", "")))
            if m:
                return _plain(m.group(2))
    return "notebook"


def _text(source) -> str:
    return "".join(source) if isinstance(source, list) else str(source)


def _plain(md: str) -> str:
    return re.sub(r"[*_`]", "", md).strip()


def notebook_figures(path: Path, *, min_width: int = 240):
    """The PNG and JPEG figures stored in a notebook, with the heading they sit under.

    Yields ``(heading, image_bytes, width, height)``; figures narrower than
    ``min_width`` pixels (icons, tiny plots) are left out. Notebooks with many
    photographs store JPEG figures to stay within their size budget.
    """
    cells = json.loads(Path(path).read_text(encoding="utf-8")).get("cells", [])
    heading = _title_of(cells)
    for cell in cells:
        if cell.get("cell_type") == "markdown":
            for m in _HEADING.finditer(_text(cell.get("source", ""))):
                heading = _plain(m.group(2))
            continue
        for out in cell.get("outputs", []):
            data = out.get("data", {})
            encoded = data.get("image/png") or data.get("image/jpeg")
            if not encoded:
                continue
            raw = base64.b64decode(_text(encoded))
            w, h = _image_size(raw)
            if w >= min_width:
                yield heading, raw, w, h


def _image_size(raw: bytes) -> tuple[int, int]:
    """``(width, height)`` of PNG or JPEG bytes; ``(0, 0)`` for anything else."""
    import io

    from PIL import Image, UnidentifiedImageError

    try:
        with Image.open(io.BytesIO(raw)) as im:
            return im.size if im.format in ("PNG", "JPEG") else (0, 0)
    except (UnidentifiedImageError, OSError):
        return 0, 0


def _extension(raw: bytes) -> str:
    return "jpg" if raw[:3] == b"\xff\xd8\xff" else "png"


def _anchor(heading: str) -> str:
    from docutils.nodes import make_id

    return make_id(heading)


def write_gallery(src: Path, notebooks: Path | None, gallery_dir: Path | None = None) -> None:
    """Write ``gallery.rst``: the notebooks' figures (linking to their section) and ``branchnb gallery``'s.

    The notebook part costs nothing (the figures are stored in the notebooks);
    ``gallery_dir`` is a folder written by ``branchnb gallery`` (its
    ``index.html`` gives titles and captions).
    """
    # raw HTML images are not collected by Sphinx: they go with the static files
    img_dir = src / "_static" / "gallery"
    img_dir.mkdir(parents=True, exist_ok=True)
    lines = [_underline("Gallery", "="), "",
             "Every figure of the notebooks, as they are committed, under the heading of the section that made it;",
             "click one to read the code and the explanation around it.", ""]
    nbs = sorted(Path(notebooks).glob("*.ipynb")) if notebooks and Path(notebooks).is_dir() else []
    for nb in nbs:
        cells = json.loads(nb.read_text(encoding="utf-8")).get("cells", [])
        cards = []
        for k, (heading, raw, _w, _h) in enumerate(notebook_figures(nb)):
            fname = f"{nb.stem}_{k:02d}.{_extension(raw)}"
            (img_dir / fname).write_bytes(raw)
            link = f"notebooks/{nb.stem}.html#{_anchor(heading)}"
            cards.append(f"<figure><a href='{html.escape(link)}'><img src='_static/gallery/{fname}' loading='lazy' "
                         f"alt='{html.escape(heading)}'></a><figcaption>{html.escape(heading)}</figcaption></figure>")
        if not cards:
            continue
        title = _title_of(cells)
        lines += [_underline(title, "-"), "", f"From :doc:`notebooks/{nb.stem}`.", "", ".. raw:: html", "",
                  "   <div class='bnb-gallery'>"] + [f"   {c}" for c in cards] + ["   </div>", ""]
    if gallery_dir is not None:
        lines += _command_gallery(Path(gallery_dir), img_dir)
    elif not nbs:
        lines += ["No notebooks were found (an installed wheel has none); ``branchnb docs --gallery`` adds the",
                  "pictures of ``branchnb gallery``.", ""]
    (src / "gallery.rst").write_text("\n".join(lines), encoding="utf-8")


_FIGURE = re.compile(r"<h2>(?P<section>.*?)</h2>|<figure><a href='(?P<file>[^']+)'>.*?<b>(?P<title>.*?)</b><br>"
                     r"(?P<caption>.*?)</figcaption></figure>", re.S)


def _command_gallery(folder: Path, img_dir: Path) -> list[str]:
    index = folder / "index.html"
    if not index.is_file():
        raise FileNotFoundError(f"gallery folder {str(folder)!r} has no index.html (run `branchnb gallery` first)")
    lines = [_underline("branchnb gallery", "-"), "",
             "One example per technique, written by ``branchnb gallery OUTDIR`` (no Jupyter needed).", ""]
    section, cards = None, []

    def flush():
        if section is not None and cards:
            lines.extend([_underline(section, "~"), "", ".. raw:: html", "", "   <div class='bnb-gallery'>"]
                         + [f"   {c}" for c in cards] + ["   </div>", ""])

    for m in _FIGURE.finditer(index.read_text(encoding="utf-8")):
        if m.group("section") is not None:
            flush()
            section, cards = html.unescape(m.group("section")), []
            continue
        name = html.unescape(m.group("file"))
        if not (folder / name).is_file():
            continue
        dst = f"cmd_{Path(name).name}"
        shutil.copy2(folder / name, img_dir / dst)
        src_attr = f"_static/gallery/{html.escape(dst)}"
        cards.append(f"<figure><a href='{src_attr}'><img src='{src_attr}' "
                     f"loading='lazy'></a><figcaption><b>{m.group('title')}</b><br>{m.group('caption')}"
                     f"</figcaption></figure>")
    flush()
    return lines


# --- bench -----------------------------------------------------------------------------------

def write_bench(src: Path, rows=None) -> None:
    """Write ``bench.rst``: what the figures mean, and the table of ``rows`` when given."""
    text = (HERE / "pages" / "bench.rst").read_text(encoding="utf-8")
    if rows:
        import platform

        table = [".. list-table::", "   :header-rows: 1", "   :widths: 34 10 30 10 8 30", "",
                 "   * - benchmark", "     - ours [s]", "     - anchor", "     - anchor [s]", "     - ratio",
                 "     - note"]
        for r in rows:
            cells = [r.name, f"{r.seconds:.4f}", r.anchor, f"{r.anchor_seconds:.4f}", f"{r.ratio:.3f}", r.note]
            table.append("   * - " + _cell(cells[0]))
            table += ["     - " + _cell(c) for c in cells[1:]]
        when = time.strftime("%Y-%m-%d %H:%M UTC", time.gmtime())
        text += (f"\nMeasured while building this site ({when}, {platform.machine()}, Python "
                 f"{platform.python_version()}):\n\n" + "\n".join(table) + "\n")
    else:
        text += ("\nThis copy of the site was built without running the benchmarks (they take minutes). "
                 "``branchnb docs --bench`` measures them and puts the table here; ``branchnb bench`` prints "
                 "the same table in a terminal.\n")
    (src / "bench.rst").write_text(text, encoding="utf-8")


def _cell(text: str) -> str:
    text = str(text).replace("\n", " ").replace("`", "'").replace("*", "\\*").replace("|", "\\|")
    return text or " "


# --- the build -------------------------------------------------------------------------------

def build(outdir=None, *, notebooks=NOTEBOOKS_DIR, gallery_dir=None, run_gallery: bool = False,
          bench: bool = False, quick_bench: bool = False, bench_rows=None, strict: bool = True,
          log: Callable[[str], None] | None = print) -> Path:
    """Build the HTML site into ``outdir/html`` and return the path of its ``index.html``.

    Parameters
    ----------
    outdir : path-like, optional
        Build folder (``build/docs`` of the checkout by default); ``outdir/src`` is
        the gathered source, ``outdir/html`` the site. Rebuilds are incremental.
    notebooks : path-like or None
        Folder of ``*.ipynb`` to render (from their stored outputs); None for none.
    gallery_dir : path-like, optional
        A folder written by ``branchnb gallery`` whose pictures join the gallery page.
    run_gallery : bool
        Run ``branchnb gallery`` into ``outdir/gallery`` first (about two minutes).
    bench : bool
        Run ``branchnb bench`` and put its table on the bench page (several minutes).
    quick_bench : bool
        With ``bench``: the smaller inputs of ``branchnb bench --quick``.
    bench_rows : list of branchnb.bench.BenchRow, optional
        Rows measured earlier (``branchnb.bench.run()``), shown instead of running the benchmarks.
    strict : bool
        Treat every Sphinx warning as an error (the test suite builds this way).
    log : callable or None
        Receives one line per step (``print`` by default; None for silence).

    Returns
    -------
    pathlib.Path
        ``outdir/html/index.html``.

    Raises
    ------
    RuntimeError
        When Sphinx reports warnings (with ``strict``) or errors; the message
        holds them.

    Examples
    --------
    >>> from branchnb._docs import build
    >>> index = build("/tmp/branchnb-docs", notebooks=None, log=None)  # doctest: +SKIP
    """
    say = log or (lambda _msg: None)
    outdir = Path(DEFAULT_OUTDIR if outdir is None else outdir)
    src, html_dir = outdir / "src", outdir / "html"
    t0 = time.perf_counter()
    if src.exists():
        shutil.rmtree(src)
    shutil.copytree(HERE / "pages", src)
    shutil.copytree(HERE / "static", src / "_static")
    shutil.copy2(HERE / "conf.py", src / "conf.py")
    say("docs: API pages from the docstrings")
    write_api(src)
    nb_pages = copy_notebooks(src, notebooks)
    _write_notebook_index(src, nb_pages)
    _missing_notebooks(src, nb_pages)
    banner = Path(notebooks or NOTEBOOKS_DIR) / "figures" / "readme_banner.jpg"
    if banner.is_file():
        shutil.copy2(banner, src / "_static" / "banner.jpg")
    say(f"docs: {len(nb_pages)} notebooks (stored outputs, not executed)")
    if run_gallery:
        from .. import gallery

        gallery_dir = outdir / "gallery"
        say(f"docs: running branchnb gallery into {gallery_dir} (about two minutes)")
        gallery.build(gallery_dir)
    write_gallery(src, notebooks, gallery_dir)
    rows = list(bench_rows) if bench_rows is not None else None
    if bench and rows is None:
        from .. import bench as bench_mod

        say("docs: running the benchmarks (several minutes)")
        rows = bench_mod.run(quick=quick_bench)
    write_bench(src, rows)
    say("docs: sphinx")
    _sphinx(src, html_dir, strict=strict, doctrees=outdir / "doctrees")
    say(f"docs: built in {time.perf_counter() - t0:.0f} s: {html_dir / 'index.html'}")
    return html_dir / "index.html"


def _write_notebook_index(src: Path, pages: list[str]) -> None:
    lines = [_underline("Notebooks", "="), "",
             "The notebooks as committed, with their outputs (they are not re-run to build this site). Open them",
             "in JupyterLab (``branchnb lab``) to run them and to use the apps.", ""]
    if pages:
        lines += [".. toctree::", "   :maxdepth: 1", ""] + [f"   {p.split('/', 1)[1]}" for p in pages]
    else:
        lines += ["This copy of the package has no ``notebooks/`` folder (an installed wheel); the notebooks are",
                  "in the source repository."]
    (src / "notebooks").mkdir(exist_ok=True)
    (src / "notebooks" / "index.rst").write_text("\n".join(lines) + "\n", encoding="utf-8")


#: The notebooks the pages link to; a copy without them (an installed wheel) gets a short note in their place.
LINKED_NOTEBOOKS = ("00_tour", "01_branching", "02_tree_variations", "03_dendrites", "04_leaves",
                    "05_stroke_editing")


def _missing_notebooks(src: Path, pages: list[str]) -> None:
    for stem in LINKED_NOTEBOOKS:
        if f"notebooks/{stem}" in pages:
            continue
        (src / "notebooks" / f"{stem}.md").write_text(
            f"---\norphan: true\n---\n\n# {stem}\n\nThis copy of branchnb has no `notebooks/` folder (an "
            f"installed wheel): `{stem}.ipynb` is in the source repository's `notebooks/` folder.\n",
            encoding="utf-8")


def _sphinx(src: Path, html_dir: Path, *, strict: bool, doctrees: Path) -> None:
    import io

    from sphinx.application import Sphinx
    from sphinx.util.docutils import docutils_namespace, patch_docutils

    warnings = io.StringIO()
    with patch_docutils(src), docutils_namespace():
        app = Sphinx(str(src), str(src), str(html_dir), str(doctrees), "html", status=None,
                     warning=warnings, freshenv=False, keep_going=True, parallel=1)
        app.build()
    text = warnings.getvalue().strip()
    if app.statuscode or (strict and text):
        raise RuntimeError("the documentation build reported problems:\n" + (text or "(see above)"))
