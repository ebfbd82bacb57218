"""The branchnb command line: lab, app, gallery, batch and bench."""

from __future__ import annotations

import argparse
import os
import secrets
import signal
import socket
import subprocess
import sys
import tempfile
import textwrap
import time
import urllib.parse
from pathlib import Path

TOUR = Path(__file__).resolve().parent.parent / "notebooks" / "00_tour.ipynb"

DESCRIPTION = """\
branchnb: five computer-graphics techniques for branching and natural
structures, as a numpy library and Jupyter apps.

commands:
  lab [NOTEBOOK]         JupyterLab on the tour notebook (prints its URL)
  app NAME [IMAGE ...]   one technique's app as a web page (Voila)
  gallery OUTDIR         one example per technique as PNGs + index.html
  batch SPEC OUTDIR      many variations from a JSON/TOML spec on Dask
  bench                  speed figures, each against its anchor

Run "branchnb COMMAND --help" for a command's options.
"""


#: ``branchnb app`` NAME -> what it is and what IMAGE means (the names of branchnb.widgets.apps.APPS).
APP_HELP = {
    "branching": "branching structures from an annotated example (IMAGE: the example)",
    "dendrite": "dendritic stylization, trees and pareidolia by path planning (IMAGE: the picture)",
    "trees": "tree variations from a library (IMAGE ...: two or more RGBA tree cut-outs)",
    "strokes": "stroke-based editing of an object (IMAGE: the object, cut out or on plain ground)",
    "leaves": "leaf variations by structural layering (IMAGE ...: two or more leaves of one kind)",
}


class CommandError(Exception):
    """A user error on the command line: printed as one line, exit status 1 (no traceback)."""


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _option(args, *names):
    """The value of the last ``--name=value`` / ``--name value`` among ``args`` (None if absent)."""
    value = None
    for i, a in enumerate(args):
        for n in names:
            if a.startswith(n + "="):
                value = a.split("=", 1)[1]
            elif a == n and i + 1 < len(args) and not args[i + 1].startswith("-"):
                value = args[i + 1]
    return value


def _has_browser() -> bool:
    import webbrowser

    try:
        webbrowser.get()
    except webbrowser.Error:
        return False
    return True


def lab_command(notebook=None, extra=()) -> list[str]:
    """The ``jupyter lab`` command line that opens ``notebook`` (the tour by default).

    JupyterLab refuses to start as root without ``--allow-root``; containers
    often run as root, so the flag is added exactly then. An installed wheel
    has no ``notebooks/`` folder: then JupyterLab opens on its launcher.

    Parameters
    ----------
    notebook : str or Path, optional
        The notebook to open; None: the tour (``notebooks/00_tour.ipynb``)
        when it exists, else the launcher.
    extra : sequence of str
        Further ``jupyter lab`` options, appended as given.

    Returns
    -------
    list of str
        The argument vector, starting with the current Python.
    """
    if notebook:
        cmd = [sys.executable, "-m", "jupyterlab", str(Path(notebook))]
    elif TOUR.is_file():
        cmd = [sys.executable, "-m", "jupyterlab", str(TOUR)]
    else:
        cmd = [sys.executable, "-m", "jupyterlab"]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        cmd.append("--allow-root")
    return cmd + list(extra)


def lab_setup(notebook=None, extra=(), *, env=None) -> tuple[list[str], dict, str]:
    """Command, environment and the one URL ``branchnb lab`` prints.

    The server listens on 127.0.0.1 (unless ``--ip`` is given) on a free
    port with a fresh token (or the ones given), its root folder is the
    notebook's, and the URL opens the notebook itself, not the launcher,
    in any browser (a remote or headless machine included). JupyterLab's own
    start-up messages are turned down to warnings so that this URL is not
    buried; a local browser, when there is one, opens it.

    Parameters
    ----------
    notebook : str or Path, optional
        The notebook to open; None: the tour when it exists, else the launcher.
    extra : sequence of str
        ``jupyter lab`` options; a given ``--ip``, ``--port``, token,
        root folder, log level or ``--no-browser`` replaces the default.
    env : dict, optional
        Base environment (default: ``os.environ``); copied, not modified.

    Returns
    -------
    cmd : list of str
        The command line (:func:`lab_command`).
    env : dict
        The environment to run it in (``JUPYTER_TOKEN`` set).
    url : str
        The notebook's URL with its token.

    Raises
    ------
    CommandError
        ``notebook`` is not a file, or not inside the root folder given.
    """
    extra = list(extra)
    env = dict(os.environ if env is None else env)
    nb = Path(notebook) if notebook else (TOUR if TOUR.is_file() else None)
    if nb is not None and not nb.is_file():
        raise CommandError(f"NOTEBOOK {str(nb)!r} is not a file")
    opts = []
    root = _option(extra, "--ServerApp.root_dir", "--notebook-dir", "--ServerApp.notebook_dir")
    if nb is not None and root is None:
        root = str(nb.resolve().parent)
        opts.append(f"--ServerApp.root_dir={root}")
    ip = _option(extra, "--ip", "--ServerApp.ip")
    if ip is None:
        ip = "127.0.0.1"
        opts.append(f"--ServerApp.ip={ip}")
    port = _option(extra, "--port", "--ServerApp.port")
    if port is None:
        port = str(_free_port())
        opts += [f"--ServerApp.port={port}", "--ServerApp.port_retries=0"]
    token = _option(extra, "--IdentityProvider.token", "--ServerApp.token", "--NotebookApp.token", "--token")
    if token is None:
        token = env.get("JUPYTER_TOKEN") or secrets.token_hex(24)
        # Through the environment, not an option that ``ps`` would show; given, not generated,
        # JupyterLab prints no URL of its own, so the one printed here is the only one.
        env["JUPYTER_TOKEN"] = token
    if not any(a.startswith(("--log-level", "--ServerApp.log_level")) for a in extra):
        opts += ["--ServerApp.log_level=WARN", "--LabApp.log_level=WARN"]
    if "--no-browser" not in extra and not _has_browser():
        opts.append("--no-browser")
    path = "/lab"
    if nb is not None:
        try:
            rel = nb.resolve().relative_to(Path(root).resolve())
        except ValueError:
            raise CommandError(f"NOTEBOOK {str(nb)!r} is not inside the root folder {root!r}") from None
        path = "/lab/tree/" + urllib.parse.quote(rel.as_posix())
    host = "127.0.0.1" if ip in ("", "0.0.0.0", "::", "*") else ip
    url = f"http://{host}:{port}{path}" + (f"?token={token}" if token else "")
    return lab_command(nb, opts + extra), env, url


def run_lab(cmd: list[str], env: dict | None = None) -> int:
    """Run JupyterLab so that signals reach it.

    On POSIX the process *becomes* the server (``exec``): SIGTERM, SIGINT and
    a terminal's Ctrl-C go to Jupyter itself, which shuts down its kernels;
    nothing is left running behind a dead parent. Elsewhere the server runs
    as a child and SIGTERM/SIGINT are forwarded to it.

    Parameters
    ----------
    cmd : list of str
        The command line, e.g. from :func:`lab_setup` or :func:`app_setup`.
    env : dict, optional
        Its environment; None: ``os.environ``.

    Returns
    -------
    int
        The server's exit status (on POSIX this call does not return).
    """
    sys.stdout.flush()
    sys.stderr.flush()
    env = dict(os.environ) if env is None else env
    if os.name == "posix":
        os.execve(cmd[0], cmd, env)  # does not return
    child = subprocess.Popen(cmd, env=env)  # pragma: no cover - not POSIX

    def forward(signum, _frame):  # pragma: no cover
        child.send_signal(signum)

    for sig in (signal.SIGINT, signal.SIGTERM):  # pragma: no cover
        signal.signal(sig, forward)
    return child.wait()  # pragma: no cover


def writable_dir(outdir, *, name: str = "OUTDIR") -> Path:
    """``outdir`` as a folder that exists (created if needed) and can be written to.

    Parameters
    ----------
    outdir : str or Path
        The folder (parents created as needed).
    name : str
        What the command line calls it, for the messages (default ``"OUTDIR"``).

    Returns
    -------
    Path

    Raises
    ------
    CommandError
        An empty name (it would mean the current folder), an existing file,
        or a folder that cannot be created or written to; the message says which.
    """
    if outdir is None or str(outdir).strip() == "":
        raise CommandError(f"{name} is empty; give a folder name (use '.' for the current folder)")
    path = Path(outdir)
    if path.exists() and not path.is_dir():
        raise CommandError(f"{name} {str(path)!r} is an existing file, not a folder")
    try:
        path.mkdir(parents=True, exist_ok=True)
        with tempfile.TemporaryFile(dir=path):
            pass
    except OSError as exc:
        raise CommandError(f"cannot write to {name} {str(path)!r}: {exc.strerror or exc}") from None
    return path


def _open_browser_later(url: str, probe: str, timeout: float = 120.0) -> None:
    """Open ``url`` in the local browser once ``probe`` answers (a detached helper process).

    The server replaces this process (``exec``), so the wait cannot run here.
    """
    code = ("import sys, time, urllib.request, webbrowser\n"
            "t = time.time() + float(sys.argv[3])\n"
            "while time.time() < t:\n"
            "    try:\n"
            "        urllib.request.urlopen(sys.argv[2], timeout=2); break\n"
            "    except Exception:\n"
            "        time.sleep(0.5)\n"
            "else:\n"
            "    sys.exit(0)\n"
            "webbrowser.open(sys.argv[1])\n")
    subprocess.Popen([sys.executable, "-c", code, url, probe, str(timeout)], stdin=subprocess.DEVNULL,
                     stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL, start_new_session=True)


def app_setup(name: str, images=(), extra=(), *, folder=None, env=None) -> tuple[list[str], dict, str]:
    """Command, environment and URL of ``branchnb app NAME [IMAGE ...]`` (a Voila page of one app).

    The page's notebook (one cell: :func:`branchnb.widgets.apps.open_app`)
    is written into ``folder`` (a new temporary folder by default); Voila
    runs it and shows the app alone, without code cells. The server listens
    on 127.0.0.1 on a free port and asks for a fresh token, like ``branchnb lab``.

    Parameters
    ----------
    name : str
        The app: one of :data:`APP_HELP` (``"branching"``, ``"dendrite"``,
        ``"trees"``, ``"strokes"``, ``"leaves"``).
    images : sequence of str or Path
        Images the app opens with (read here, so a bad one fails at once);
        empty: the app's own sample.
    extra : sequence of str
        Further ``voila`` options; a given ``--port`` or ``--token`` replaces
        the default.
    folder : str or Path, optional
        Where the page's notebook is written; None: a new temporary folder.
    env : dict, optional
        Base environment (default: ``os.environ``); copied, not modified.

    Returns
    -------
    cmd : list of str
        The ``voila`` command line.
    env : dict
        The environment to run it in.
    url : str
        The page's URL with its token.

    Raises
    ------
    CommandError
        An unknown ``name`` or an unreadable image (naming it).
    """
    if name not in APP_HELP:
        raise CommandError(f"NAME must be one of {', '.join(APP_HELP)}; got {name!r}")
    from .widgets.apps import read_images

    paths = [str(Path(p).resolve()) for p in images]
    try:
        read_images(paths)  # a bad IMAGE fails here, with its name, not in the page
    except ValueError as exc:
        raise CommandError(str(exc)) from None
    import nbformat

    folder = Path(tempfile.mkdtemp(prefix=f"branchnb-app-{name}-") if folder is None else folder)
    nb = nbformat.v4.new_notebook()
    nb.cells = [nbformat.v4.new_code_cell(
        f"from branchnb.widgets.apps import open_app\nopen_app({name!r}, {paths!r} or None, page=True)")]
    nb.metadata["kernelspec"] = {"name": "python3", "display_name": "Python 3", "language": "python"}
    path = folder / f"{name}.ipynb"
    nbformat.write(nb, str(path))
    extra = list(extra)
    env = dict(os.environ if env is None else env)
    opts = []
    port = _option(extra, "--port", "--Voila.port")
    if port is None:
        port = str(_free_port())
        opts += [f"--Voila.port={port}", "--Voila.port_retries=0"]
    token = _option(extra, "--token", "--Voila.token")
    if token is None:
        token = secrets.token_hex(24)
        opts.append(f"--token={token}")
    opts += ["--Voila.ip=127.0.0.1", "--no-browser", "--Voila.log_level=WARN",
             "--VoilaConfiguration.show_tracebacks=True"]
    cmd = [sys.executable, "-m", "voila", str(path)] + opts + extra
    url = f"http://127.0.0.1:{port}/" + (f"?token={token}" if token else "")
    return cmd, env, url


def _help_text(text: str) -> str:
    return textwrap.dedent(text).strip()


def _parser() -> argparse.ArgumentParser:
    raw = argparse.RawDescriptionHelpFormatter
    parser = argparse.ArgumentParser(prog="branchnb", description=DESCRIPTION, formatter_class=raw)
    sub = parser.add_subparsers(dest="cmd", required=True, metavar="COMMAND")
    p_lab = sub.add_parser(
        "lab", help="JupyterLab on the tour notebook (or NOTEBOOK)", formatter_class=raw,
        usage="branchnb lab [NOTEBOOK] [jupyter lab options]",
        description=_help_text("""
            Start JupyterLab on the tour notebook (notebooks/00_tour.ipynb) or on NOTEBOOK, and print
            one line with the URL that opens it (on 127.0.0.1, with a fresh token). A local browser,
            when there is one, opens it. Other options go to jupyter lab unchanged (e.g. --port 8899,
            --ip 0.0.0.0 to serve other machines). Ctrl-C stops the server.
        """))
    p_lab.add_argument("lab_args", nargs=argparse.REMAINDER, metavar="...",
                       help="[NOTEBOOK] [jupyter lab options]")
    p_app = sub.add_parser(
        "app", help="one technique's app as a standalone web page (Voila)", formatter_class=raw,
        description=_help_text("""
            Serve one technique's app as a web page without code cells (Voila): the app alone, on
            your own image(s) when given, on a sample otherwise. It listens on 127.0.0.1 with a
            fresh token; the printed URL opens it. In the page, "save" offers the results as
            downloads. A teacher can hand students the page instead of a notebook.

            apps:
        """) + "\n" + "\n".join(f"  {k:10s} {v}" for k, v in APP_HELP.items()))
    p_app.add_argument("name", metavar="NAME", help="one of: " + ", ".join(APP_HELP))
    p_app.add_argument("images", nargs="*", metavar="IMAGE", help="image file(s) to start with")
    p_app.add_argument("--port", type=int, help="port (default: a free one)")
    p_gal = sub.add_parser("gallery", help="one example per technique as PNGs + index.html",
                           description="Render one example per technique into OUTDIR as PNGs plus "
                                       "OUTDIR/index.html. Each picture is listed as it is written.")
    p_gal.add_argument("outdir", metavar="OUTDIR")
    p_batch = sub.add_parser(
        "batch", help="many variations from a JSON/TOML spec on Dask",
        description="Run the job of SPEC (JSON or TOML) for its count of items on a Dask cluster "
                    "(a LocalCluster with one process per core unless --scheduler is given). Files "
                    "and OUTDIR/manifest.jsonl are written as items finish; running the same "
                    "command again resumes.")
    p_batch.add_argument("spec", metavar="SPEC", help="spec file (.json or .toml)")
    p_batch.add_argument("outdir", metavar="OUTDIR", help="output folder (created if needed)")
    p_batch.add_argument("--scheduler", metavar="ADDRESS",
                         help="address of a running Dask scheduler, e.g. tcp://10.0.0.5:8786")
    p_batch.add_argument("--workers", type=int, metavar="N",
                         help="LocalCluster worker processes (default: one per core)")
    p_batch.add_argument("--chunk", type=int, metavar="K",
                         help="items per Dask task (default: adapted to the measured item time, 1 near the end)")
    p_batch.add_argument("--count", type=int, metavar="N", help="override the spec's count")
    p_batch.add_argument("--no-progress", action="store_true", help="no progress bar or status lines")
    p_batch.add_argument("--dashboard", action="store_true",
                         help="start the Dask dashboard of the local cluster (on 127.0.0.1 only)")
    p_bench = sub.add_parser("bench", help="speed figures, each against its anchor",
                             description="Print benchmark figures; each row names its anchor and the "
                                         "ratio measured in the same run.")
    p_bench.add_argument("--quick", action="store_true", help="smaller inputs, for a smoke run")
    p_docs = sub.add_parser(
        "docs", help="build the documentation site and open it",
        description="Build the HTML documentation (install, techniques, notebooks from their stored outputs, "
                    "API reference, gallery, batch guide) with Sphinx and open it in a browser.")
    p_docs.add_argument("--out", metavar="DIR", help="build folder (default: build/docs of the checkout)")
    p_docs.add_argument("--no-open", action="store_true", help="only print the path of the site")
    p_docs.add_argument("--gallery", action="store_true", help="run `branchnb gallery` too (about two minutes)")
    p_docs.add_argument("--gallery-dir", metavar="DIR", help="add the pictures of an earlier `branchnb gallery DIR`")
    p_docs.add_argument("--bench", action="store_true", help="run the benchmarks for the bench page (minutes)")
    p_docs.add_argument("--quick", action="store_true", help="with --bench: the smaller inputs")
    p_docs.add_argument("--no-strict", action="store_true", help="build even when Sphinx warns")
    return parser


#: ``branchnb gallery`` says it is still working after this many seconds without a new picture.
HEARTBEAT = 15.0


def _gallery(outdir_arg) -> int:
    """``branchnb gallery``: a line at once, then one line per picture as it is written."""
    import threading

    outdir = writable_dir(outdir_arg)
    t0 = time.perf_counter()
    print(f"branchnb gallery: rendering one example per technique into {outdir} "
          "(a few minutes; each picture is listed as it is written)", flush=True)
    before = {p: p.stat().st_mtime_ns for p in outdir.glob("*.png")}
    seen: set = set()
    stop = threading.Event()
    state = {"section": "", "said": t0}

    def say(text: str) -> None:
        now = time.perf_counter()
        state["said"] = now
        print(f"  {now - t0:6.1f} s  {text}", flush=True)

    def report_new() -> None:
        for p in sorted(outdir.glob("*.png"), key=lambda q: q.stat().st_mtime_ns):
            try:
                m = p.stat().st_mtime_ns
            except OSError:
                continue
            if p not in seen and before.get(p) != m:
                seen.add(p)
                say(p.name)

    def watch() -> None:
        while not stop.wait(0.5):
            report_new()
            if state["section"] and time.perf_counter() - state["said"] >= HEARTBEAT:
                say(f"{state['section']}: still working on its next picture ...")

    def section(name: str) -> None:
        report_new()
        state["section"] = name
        say(f"{name} ...")

    from .gallery import build

    watcher = threading.Thread(target=watch, daemon=True)
    watcher.start()
    try:
        items = build(outdir, progress=section)
    except OSError as exc:
        raise CommandError(f"cannot write the gallery to {str(outdir)!r}: {exc}") from None
    finally:
        stop.set()
        watcher.join()
    report_new()
    print(f"wrote {len(items)} pictures and index.html to {outdir} in {time.perf_counter() - t0:.0f} s")
    return 0


def _docs(args) -> int:
    try:
        from ._docs import DEFAULT_OUTDIR, build
    except ImportError as exc:  # sphinx & co. come with the `dev` extra
        raise CommandError(f"{exc.name or exc} is missing; install the docs tools with "
                           "`python -m pip install -e \".[dev]\"`") from None
    outdir = writable_dir(args.out if args.out is not None else DEFAULT_OUTDIR, name="--out")
    gallery_dir = None
    if args.gallery_dir is not None:
        gallery_dir = Path(args.gallery_dir)
        if not (gallery_dir / "index.html").is_file():
            raise CommandError(f"--gallery-dir {str(gallery_dir)!r} holds no index.html of `branchnb gallery`")
    try:
        index = build(outdir, gallery_dir=gallery_dir, run_gallery=args.gallery, bench=args.bench,
                      quick_bench=args.quick, strict=not args.no_strict)
    except RuntimeError as exc:
        raise CommandError(str(exc)) from None
    print(f"site: {index}")
    if not args.no_open:
        import webbrowser

        if not webbrowser.open(index.as_uri()):
            print("no web browser found: open the file above in one")
    return 0


def _batch(args) -> int:
    if not args.no_progress:  # the first second: before the imports of Dask and the techniques
        print(f"branchnb batch: reading {args.spec} ...", file=sys.stderr, flush=True)
    from .batch import load_spec, run_batch
    from .batch.runner import ClusterLostError

    outdir = writable_dir(args.outdir)
    try:
        spec = load_spec(args.spec)
        if args.count is not None:
            spec = spec.with_count(args.count)
    except (OSError, ValueError, TypeError) as exc:
        raise CommandError(f"spec {args.spec!r}: {exc}") from None
    if args.workers is not None and args.scheduler is not None:
        raise CommandError("--workers sets up a local cluster; with --scheduler the cluster has its own workers")
    if args.workers is not None and args.workers < 1:
        raise CommandError(f"--workers must be >= 1, got {args.workers}")
    if args.chunk is not None and args.chunk < 1:
        raise CommandError(f"--chunk must be >= 1, got {args.chunk}")
    try:
        summary = run_batch(spec, outdir, scheduler=args.scheduler, n_workers=args.workers,
                            chunk=args.chunk, progress=None if args.no_progress else "tqdm",
                            dashboard=args.dashboard)
    except (ValueError, TypeError, ClusterLostError) as exc:  # a bad shared input, e.g. a library folder without trees
        raise CommandError(str(exc)) from None
    print(summary)
    print(f"manifest: {summary.outdir / 'manifest.jsonl'}")
    return 130 if summary.interrupted else (1 if summary.failed else 0)


def main(argv=None) -> int:
    """Run one ``branchnb`` command (the console script's entry point).

    Parameters
    ----------
    argv : list of str, optional
        The arguments after the program name; None: ``sys.argv[1:]`` (and
        the process is about to exit).

    Returns
    -------
    int
        Exit status: 0 on success, 1 for a user error (printed as one line)
        or a batch with failed items, 130 for an interrupted batch; ``lab``
        and ``app`` do not return on POSIX (the server replaces the process).
    """
    parser = _parser()
    as_program = argv is None
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["lab"] and not {"-h", "--help"} & set(argv[1:2]):
        # Everything after "lab" goes to jupyter lab untouched (argparse would reorder it).
        rest = argv[1:]
        notebook = rest.pop(0) if rest and not rest[0].startswith("-") else None
        try:
            cmd, env, url = lab_setup(notebook, rest)
        except CommandError as exc:
            print(f"branchnb lab: error: {exc}", file=sys.stderr)
            return 1
        print(f"branchnb lab: {url}", flush=True)
        return run_lab(cmd, env)
    args, extra = parser.parse_known_args(argv)
    if extra and args.cmd != "app":
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    try:
        if args.cmd == "app":
            if args.port is not None:
                extra = [f"--Voila.port={args.port}"] + extra
            cmd, env, url = app_setup(args.name, args.images, extra)
            print(f"branchnb app: {url}", flush=True)
            if _has_browser():
                # probed without the token: the login page answers once the server listens, and
                # no kernel is started for the probe
                _open_browser_later(url, url.split("?")[0])
            return run_lab(cmd, env)
        if args.cmd == "gallery":
            return _gallery(args.outdir)
        if args.cmd == "batch":
            try:
                return _batch(args)
            except KeyboardInterrupt:  # before the run took over Ctrl-C (imports, reading the spec)
                print("branchnb batch: interrupted", file=sys.stderr)
                return 130
            finally:
                if as_program:  # only exiting is left: a late Ctrl-C must not tear Dask's atexit clean-up
                    signal.signal(signal.SIGINT, signal.SIG_IGN)
        if args.cmd == "bench":
            from .bench import format_table, run

            t0 = time.perf_counter()
            print("branchnb bench: measuring each suite against its anchor (progress on stderr, the "
                  "table at the end)", file=sys.stderr, flush=True)
            rows = run(quick=args.quick, progress=lambda name: print(
                f"  {time.perf_counter() - t0:6.1f} s  {name} ...", file=sys.stderr, flush=True))
            print(format_table(rows))
            return 0
        if args.cmd == "docs":
            return _docs(args)
    except CommandError as exc:
        print(f"branchnb {args.cmd}: error: {exc}", file=sys.stderr)
        return 1
    return 2  # pragma: no cover


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
