"""Command line: ``branchnb lab``, ``branchnb gallery OUTDIR``, ``branchnb batch SPEC OUTDIR``, ``branchnb bench``."""

from __future__ import annotations

import argparse
import os
import signal
import subprocess
import sys
import tempfile
from pathlib import Path

TOUR = Path(__file__).resolve().parent.parent / "notebooks" / "00_tour.ipynb"


class CommandError(Exception):
    """A user error on the command line: printed as one line, exit status 1 (no traceback)."""


def lab_command(notebook=None, extra=()) -> list[str]:
    """The ``jupyter lab`` command line that opens ``notebook`` (the tour by default).

    JupyterLab refuses to start as root without ``--allow-root``; containers
    often run as root, so the flag is added exactly then. An installed wheel
    has no ``notebooks/`` folder: then JupyterLab opens on its launcher.
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


def run_lab(cmd: list[str]) -> int:
    """Run JupyterLab so that signals reach it.

    On POSIX the process *becomes* the server (``exec``): SIGTERM, SIGINT and
    a terminal's Ctrl-C go to Jupyter itself, which shuts down its kernels;
    nothing is left running behind a dead parent. Elsewhere the server runs
    as a child and SIGTERM/SIGINT are forwarded to it.
    """
    sys.stdout.flush()
    sys.stderr.flush()
    if os.name == "posix":
        os.execv(cmd[0], cmd)  # does not return
    child = subprocess.Popen(cmd)  # pragma: no cover - not POSIX

    def forward(signum, _frame):  # pragma: no cover
        child.send_signal(signum)

    for sig in (signal.SIGINT, signal.SIGTERM):  # pragma: no cover
        signal.signal(sig, forward)
    return child.wait()  # pragma: no cover


def writable_dir(outdir, *, name: str = "OUTDIR") -> Path:
    """``outdir`` as a folder that exists (created if needed) and can be written to.

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


def _parser() -> argparse.ArgumentParser:
    parser = argparse.ArgumentParser(prog="branchnb", description=__doc__)
    sub = parser.add_subparsers(dest="cmd", required=True)
    p_lab = sub.add_parser("lab", help="open JupyterLab on the tour notebook (or NOTEBOOK)",
                           description="Other options are passed on to jupyter lab.")
    p_lab.add_argument("lab_args", nargs=argparse.REMAINDER,
                       help="[NOTEBOOK] [jupyter lab options]; NOTEBOOK defaults to notebooks/00_tour.ipynb")
    p_gal = sub.add_parser("gallery", help="render one example per technique to PNGs + index.html")
    p_gal.add_argument("outdir")
    p_batch = sub.add_parser(
        "batch", help="generate many variations from a JSON/TOML spec on Dask",
        description="Run the job of SPEC (JSON or TOML) for its count of items on a Dask cluster "
                    "(a LocalCluster with one process per core unless --scheduler is given). Files "
                    "and OUTDIR/manifest.jsonl are written as items finish; running the same "
                    "command again resumes.")
    p_batch.add_argument("spec", help="spec file (.json or .toml)")
    p_batch.add_argument("outdir", help="output folder (created if needed)")
    p_batch.add_argument("--scheduler", metavar="ADDRESS",
                         help="address of a running Dask scheduler, e.g. tcp://10.0.0.5:8786")
    p_batch.add_argument("--workers", type=int, metavar="N",
                         help="LocalCluster worker processes (default: one per core)")
    p_batch.add_argument("--chunk", type=int, metavar="K",
                         help="items per Dask task (default: chosen from the count and the workers)")
    p_batch.add_argument("--count", type=int, metavar="N", help="override the spec's count")
    p_batch.add_argument("--no-progress", action="store_true", help="no progress bar")
    p_bench = sub.add_parser("bench", help="print benchmark figures, each against its anchor")
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
    from .batch import load_spec, run_batch

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
                            chunk=args.chunk, progress=None if args.no_progress else "tqdm")
    except (ValueError, TypeError) as exc:  # a bad shared input, e.g. a library folder without trees
        raise CommandError(str(exc)) from None
    print(summary)
    print(f"manifest: {summary.outdir / 'manifest.jsonl'}")
    return 130 if summary.interrupted else (1 if summary.failed else 0)


def main(argv=None) -> int:
    parser = _parser()
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["lab"] and not {"-h", "--help"} & set(argv[1:2]):
        # Everything after "lab" goes to jupyter lab untouched (argparse would reorder it).
        rest = argv[1:]
        notebook = rest.pop(0) if rest and not rest[0].startswith("-") else None
        return run_lab(lab_command(notebook, rest))
    args, extra = parser.parse_known_args(argv)
    if extra:
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    try:
        if args.cmd == "gallery":
            from .gallery import build

            outdir = writable_dir(args.outdir)
            try:
                items = build(outdir)
            except OSError as exc:
                raise CommandError(f"cannot write the gallery to {str(outdir)!r}: {exc}") from None
            print(f"wrote {len(items)} pictures and index.html to {outdir}")
            return 0
        if args.cmd == "batch":
            return _batch(args)
        if args.cmd == "bench":
            from .bench import format_table, run

            print(format_table(run(quick=args.quick)))
            return 0
        if args.cmd == "docs":
            return _docs(args)
    except CommandError as exc:
        print(f"branchnb {args.cmd}: error: {exc}", file=sys.stderr)
        return 1
    return 2  # pragma: no cover


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
