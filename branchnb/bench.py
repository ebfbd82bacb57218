"""Benchmark rows: each measures one operation against a named anchor in the same run.

Every technique may provide a module ``branchnb.<technique>._bench`` with a
function ``rows(quick: bool) -> list[BenchRow]``; :func:`run` collects
them. The anchor is either another implementation timed in the same
process (e.g. ``skimage.graph.MCP``), or a figure the paper reports; the
ratio is ours / anchor, so < 1 means faster than the anchor.
"""

from __future__ import annotations

import importlib
import importlib.util
import time
from collections.abc import Callable
from dataclasses import dataclass

__all__ = ["BenchRow", "timeit", "run", "format_table", "SUITES"]

#: Modules searched for a ``rows(quick)`` function, in display order.
SUITES = (
    "branchnb.core._bench",
    "branchnb.branching._bench",
    "branchnb.dendrite._bench",
    "branchnb.trees._bench",
    "branchnb.leaves._bench",
    "branchnb.strokes._bench",
    "branchnb.batch._bench",
    "branchnb.widgets._bench",
)


@dataclass
class BenchRow:
    """One benchmark figure.

    Parameters
    ----------
    name : str
        What was measured (with the input size).
    seconds : float
        Our time (best of the repeats).
    anchor : str
        What it is compared with.
    anchor_seconds : float
        The anchor's time, measured in the same run or quoted from the paper.
    note : str
        Anything the reader needs (e.g. "paper figure, other machine").

    Examples
    --------
    >>> BenchRow("plan 256 x 256", 0.5, "skimage.graph.MCP", 1.0).ratio
    0.5
    """

    name: str
    seconds: float
    anchor: str
    anchor_seconds: float
    note: str = ""

    @property
    def ratio(self) -> float:
        """ours / anchor."""
        return self.seconds / self.anchor_seconds if self.anchor_seconds > 0 else float("inf")


def timeit(fn: Callable[[], object], *, repeat: int = 3, warmup: bool = True) -> float:
    """Best wall time of ``repeat`` calls of ``fn`` (after one warm-up call, e.g. for JIT).

    Parameters
    ----------
    fn : callable
        Called without arguments; its result is ignored.
    repeat : int
        Number of timed calls (at least 1 is made).
    warmup : bool
        Make one untimed call first (JIT compilation, caches).

    Returns
    -------
    float
        The fastest call, in seconds (``time.perf_counter``).

    Examples
    --------
    >>> timeit(lambda: sum(range(10)), repeat=2) >= 0
    True
    """
    if warmup:
        fn()
    best = float("inf")
    for _ in range(max(1, repeat)):
        t0 = time.perf_counter()
        fn()
        best = min(best, time.perf_counter() - t0)
    return best


def run(quick: bool = False, suites=SUITES, progress: Callable[[str], None] | None = None) -> list[BenchRow]:
    """Collect the rows of every available suite; ``progress(name)`` is called as each suite starts.

    Parameters
    ----------
    quick : bool
        Passed to each suite's ``rows(quick)``: smaller inputs and fewer
        repeats (seconds instead of minutes).
    suites : sequence of str
        Dotted names of modules with a ``rows(quick)`` function; those not
        installed are skipped. Default :data:`SUITES`.
    progress : callable, optional
        Called with the technique name (``"core"``, ``"branching"``, ...)
        before each suite runs.

    Returns
    -------
    list of BenchRow
        All suites' rows, in suite order.

    Examples
    --------
    >>> run(suites=("branchnb.nothing._bench",))
    []
    """
    rows: list[BenchRow] = []
    for mod_name in suites:
        if importlib.util.find_spec(mod_name.rsplit(".", 1)[0]) is None:
            continue
        if importlib.util.find_spec(mod_name) is None:
            continue
        if progress is not None:
            progress(mod_name.split(".")[1])
        mod = importlib.import_module(mod_name)
        rows.extend(mod.rows(quick))
    return rows


def format_table(rows: list[BenchRow]) -> str:
    """Plain-text table of rows.

    Parameters
    ----------
    rows : list of BenchRow
        The rows, shown in this order.

    Returns
    -------
    str
        A header, a rule and one left-aligned line per row: name, our
        seconds, anchor, anchor seconds, ratio (ours / anchor) and note.

    Examples
    --------
    >>> for line in format_table([BenchRow("f", 1.0, "g", 2.0)]).splitlines():
    ...     print(line.rstrip())
    benchmark  ours [s]  anchor  anchor [s]  ratio  note
    ---------  --------  ------  ----------  -----  ----
    f          1.0000    g       2.0000      0.500
    """
    header = ("benchmark", "ours [s]", "anchor", "anchor [s]", "ratio", "note")
    body = [
        (r.name, f"{r.seconds:.4f}", r.anchor, f"{r.anchor_seconds:.4f}", f"{r.ratio:.3f}", r.note)
        for r in rows
    ]
    widths = [max(len(str(x)) for x in col) for col in zip(header, *body)]
    line = "  ".join(f"{{:<{w}}}" for w in widths)
    out = [line.format(*header), line.format(*("-" * w for w in widths))]
    out += [line.format(*r) for r in body]
    return "\n".join(out)
