"""Command line: ``branchnb lab``, ``branchnb gallery OUTDIR``, ``branchnb bench``."""

from __future__ import annotations

import argparse
import os
import subprocess
import sys
from pathlib import Path

TOUR = Path(__file__).resolve().parent.parent / "notebooks" / "00_tour.ipynb"


def lab_command(notebook=None, extra=()) -> list[str]:
    """The ``jupyter lab`` command line that opens ``notebook`` (the tour by default).

    JupyterLab refuses to start as root without ``--allow-root``; containers
    often run as root, so the flag is added exactly then.
    """
    nb = Path(notebook) if notebook else TOUR
    cmd = [sys.executable, "-m", "jupyterlab", str(nb)]
    if hasattr(os, "geteuid") and os.geteuid() == 0:
        cmd.append("--allow-root")
    return cmd + list(extra)


def main(argv=None) -> int:
    parser = argparse.ArgumentParser(prog="branchnb", description=__doc__)
    sub = parser.add_subparsers(dest="cmd", required=True)
    p_lab = sub.add_parser("lab", help="open JupyterLab on the tour notebook (or NOTEBOOK)",
                           description="Other options are passed on to jupyter lab.")
    p_lab.add_argument("lab_args", nargs=argparse.REMAINDER,
                       help="[NOTEBOOK] [jupyter lab options]; NOTEBOOK defaults to notebooks/00_tour.ipynb")
    p_gal = sub.add_parser("gallery", help="render one example per technique to PNGs + index.html")
    p_gal.add_argument("outdir")
    p_bench = sub.add_parser("bench", help="print benchmark figures, each against its anchor")
    p_bench.add_argument("--quick", action="store_true", help="smaller inputs, for a smoke run")
    argv = list(sys.argv[1:] if argv is None else argv)
    if argv[:1] == ["lab"] and not {"-h", "--help"} & set(argv[1:2]):
        # Everything after "lab" goes to jupyter lab untouched (argparse would reorder it).
        rest = argv[1:]
        notebook = rest.pop(0) if rest and not rest[0].startswith("-") else None
        return subprocess.call(lab_command(notebook, rest))
    args, extra = parser.parse_known_args(argv)
    if extra:
        parser.error(f"unrecognized arguments: {' '.join(extra)}")
    if args.cmd == "gallery":
        from .gallery import build

        items = build(args.outdir)
        print(f"wrote {len(items)} pictures and index.html to {args.outdir}")
        return 0
    if args.cmd == "bench":
        from .bench import format_table, run

        print(format_table(run(quick=args.quick)))
        return 0
    return 2  # pragma: no cover


if __name__ == "__main__":  # pragma: no cover
    sys.exit(main())
