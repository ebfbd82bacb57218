"""Every public callable documents exactly its parameters in a numpydoc "Parameters" section.

Pure introspection, no Sphinx: for each public module of the packages in
:data:`PACKAGES` (no dotted part starting with ``_``), each public function,
class and public method *defined there* that takes parameters besides
``self``/``cls`` must have a "Parameters" section whose names are the
signature's names, in order (``*args``/``**kwargs`` written with or without
stars; arguments starting with ``_`` are internal and left out).
Every entry says what the parameter means (a description under it). A
class documents its constructor (a dataclass: its init fields).
To cover another package, add its dotted name to :data:`PACKAGES`;
``python tests/test_docstrings.py branchnb.trees ...`` lists what it still lacks.
"""

from __future__ import annotations

import importlib
import inspect
import pkgutil
import warnings

import pytest

docscrape = pytest.importorskip("numpydoc.docscrape")

#: Packages (or single modules) whose public callables must document their parameters.
PACKAGES = ("branchnb.core", "branchnb.widgets", "branchnb.plot", "branchnb.gallery", "branchnb.data",
            "branchnb.bench", "branchnb.dendrite", "branchnb.strokes", "branchnb.trees",
            "branchnb.branching", "branchnb.batch", "branchnb.cli", "branchnb.leaves")


def public_modules(package: str) -> list[str]:
    mod = importlib.import_module(package)
    names = [package]
    for info in pkgutil.walk_packages(getattr(mod, "__path__", []), package + "."):
        if not any(part.startswith("_") for part in info.name.split(".")[1:]):
            names.append(info.name)
    return names


def _methods(cls, prefix: str):
    """(dotted name, callable, docstring) of the public methods defined in ``cls`` itself."""
    for meth_name, raw in vars(cls).items():
        func = raw.__func__ if isinstance(raw, (staticmethod, classmethod)) else raw
        handler = not inspect.isfunction(func) and inspect.isfunction(getattr(func, "func", None))
        func = func.func if handler else func  # a public traitlets observer wraps its function
        if meth_name.startswith("_") or not inspect.isfunction(func):
            continue
        yield f"{prefix}.{meth_name}", func if handler else getattr(cls, meth_name), func.__doc__


def _own_callables(mod_name: str):
    """(dotted name, callable, docstring) of the public functions, classes and methods defined in the module."""
    mod = importlib.import_module(mod_name)
    for name, obj in vars(mod).items():
        if name.startswith("_") or not (inspect.isfunction(obj) or inspect.isclass(obj)):
            continue
        if getattr(obj, "__module__", None) != mod_name:
            continue
        yield f"{mod_name}.{name}", obj, obj.__doc__
        if inspect.isclass(obj):
            yield from _methods(obj, f"{mod_name}.{name}")


def signature_names(obj) -> list[str]:
    try:
        params = inspect.signature(obj).parameters
    except (TypeError, ValueError):  # builtins without a signature
        return []
    # a leading underscore marks an internal argument (a test hook): not part of the documented API
    return [n for n in params if n not in ("self", "cls") and not n.startswith("_")]


def _parameters(doc: str | None) -> list | None:
    if not doc:
        return None
    with warnings.catch_warnings():
        warnings.simplefilter("ignore")  # numpydoc warns about sections it does not know
        parsed = docscrape.NumpyDocString(inspect.cleandoc(doc))
    return parsed["Parameters"] or None


def documented_names(doc: str | None) -> list[str] | None:
    """Names listed in the docstring's Parameters section (None when it has none)."""
    params = _parameters(doc)
    if params is None:
        return None
    names = []
    for param in params:
        names += [n.strip().lstrip("*") for n in param.name.split(",") if n.strip()]
    return names


def undescribed_names(doc: str | None) -> list[str]:
    """Entries of the Parameters section with no description under them."""
    return [p.name for p in _parameters(doc) or () if not "".join(p.desc).strip()]


def parameter_problems(packages=PACKAGES) -> tuple[int, list[str]]:
    """(number of callables checked, one line per callable whose Parameters section is missing or wrong)."""
    checked, problems = 0, []
    for package in packages:
        for mod_name in public_modules(package):
            for dotted, obj, doc in _own_callables(mod_name):
                wanted = signature_names(obj)
                if not wanted:
                    continue
                checked += 1
                got = documented_names(doc)
                if got is None:
                    problems.append(f"{dotted}: no Parameters section (signature: {', '.join(wanted)})")
                elif got != wanted:
                    problems.append(f"{dotted}: documents {got}, signature has {wanted}")
                elif undescribed_names(doc):
                    problems.append(f"{dotted}: no description for {undescribed_names(doc)}")
    return checked, problems


@pytest.mark.parametrize("package", PACKAGES)
def test_every_public_callable_documents_exactly_its_parameters(package):
    checked, problems = parameter_problems((package,))
    assert checked > 0, f"nothing public with parameters found in {package}"
    assert not problems, f"{len(problems)} of {checked}:\n" + "\n".join(problems)


def test_the_checker_sees_public_trait_observers():
    traitlets = pytest.importorskip("traitlets")

    class Probe(traitlets.HasTraits):
        value = traitlets.Int(0)

        @traitlets.observe("value")
        def value_changed(self, change):
            """React to a new value (no Parameters section)."""

    found = {d: obj for d, obj, _doc in _methods(Probe, "Probe")}
    assert signature_names(found["Probe.value_changed"]) == ["change"]


def test_the_checker_catches_a_missing_an_extra_a_misordered_and_an_undescribed_name():
    assert documented_names("Summary.") is None
    assert documented_names("S.\n\nParameters\n----------\na, b : int\n    Two.\n**kw\n    More.\n") == ["a", "b", "kw"]

    def f(a, *args, b=1, **kw):
        """S.

        Parameters
        ----------
        a : int
            A.
        *args
            More.
        b : int
            B.
        """
    assert signature_names(f) == ["a", "args", "b", "kw"]
    assert documented_names(f.__doc__) == ["a", "args", "b"] != signature_names(f)
    assert documented_names("S.\n\nParameters\n----------\nb\n    B.\na\n    A.\n") == ["b", "a"] != ["a", "b"]
    assert undescribed_names("S.\n\nParameters\n----------\na : int\nb : int\n    B.\n") == ["a"]
    assert undescribed_names(f.__doc__) == []


if __name__ == "__main__":  # pragma: no cover - a maintenance command
    import sys

    for pkg in sys.argv[1:] or PACKAGES:
        n, found = parameter_problems((pkg,))
        print(f"{pkg}: {len(found)} of {n} callables lack a correct Parameters section")
        print("".join(f"  {p}\n" for p in found), end="")
