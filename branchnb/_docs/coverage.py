"""How complete the numpydoc docstrings of the public API are, package by package.

``python -m branchnb._docs.coverage`` prints, for the classes and functions of
:func:`branchnb._docs.public_api`, how many lack a docstring, document not
all their parameters, have no Returns section (functions that return
something) or no Examples section (numpydoc's checks GL08, PR01, RT01,
EX01). ``-v`` lists the names.
"""

from __future__ import annotations

import inspect
import sys
import warnings
from collections import Counter, defaultdict

__all__ = ["CHECKS", "coverage", "format_coverage"]

#: numpydoc validation codes counted, with what they mean.
CHECKS = {"GL08": "no docstring", "PR01": "parameters not all documented", "RT01": "no Returns section",
          "EX01": "no Examples section"}


def coverage() -> tuple[Counter, dict]:
    """Count the public classes and functions per package and the ones failing each of :data:`CHECKS`.

    Returns
    -------
    totals : collections.Counter
        Package name -> number of public classes and functions.
    failing : dict
        ``(package, code)`` -> list of dotted names failing that check.

    Examples
    --------
    >>> totals, failing = coverage()          # doctest: +SKIP
    >>> totals["core"] > 0                    # doctest: +SKIP
    True
    """
    from numpydoc.validate import validate

    from . import public_api

    totals: Counter = Counter()
    failing: dict = defaultdict(list)
    for mod, entry in public_api().items():
        package = mod.split(".")[1] if "." in mod else "branchnb"
        for name, obj in entry.own:
            if not (inspect.isfunction(obj) or inspect.isclass(obj)):
                continue
            totals[package] += 1
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")  # numpydoc warns about sections it does not know
                codes = {code for code, _msg in validate(f"{mod}.{name}")["errors"]}
            for code in CHECKS:
                if code in codes:
                    failing[(package, code)].append(f"{mod}.{name}")
    return totals, dict(failing)


def format_coverage(totals: Counter, failing: dict, *, names: bool = False) -> str:
    """A plain-text table of :func:`coverage` (and the failing names with ``names``).

    Parameters
    ----------
    totals, failing :
        As returned by :func:`coverage`.
    names : bool
        List the failing names under the table.

    Returns
    -------
    str

    Examples
    --------
    >>> print(format_coverage(Counter(core=2), {("core", "EX01"): ["branchnb.core.f"]}))
    package    names  GL08  PR01  RT01  EX01
    core           2     0     0     0     1
    all            2     0     0     0     1
    """
    head = f"{'package':10} {'names':>5}" + "".join(f"  {c}" for c in CHECKS)
    rows = [head]
    for package in sorted(totals):
        rows.append(f"{package:10} {totals[package]:5}"
                    + "".join(f"  {len(failing.get((package, c), [])):4}" for c in CHECKS))
    rows.append(f"{'all':10} {sum(totals.values()):5}"
                + "".join(f"  {sum(len(v) for (p, c2), v in failing.items() if c2 == c):4}" for c in CHECKS))
    if names:
        for (package, code), listed in sorted(failing.items()):
            rows.append(f"\n{package} {code} ({CHECKS[code]}):")
            rows += [f"  {n}" for n in listed]
    return "\n".join(rows)


if __name__ == "__main__":  # pragma: no cover - a maintenance command
    print(format_coverage(*coverage(), names="-v" in sys.argv[1:]))
