"""Sphinx extension: a reference to any path of a documented object resolves to its one entry.

The API reference documents each object once, where its package re-exports it
(``branchnb.core.seam_cut``), but docstrings name it in several ways: by the
module that defines it (``branchnb.core.graphcut.seam_cut``), relative to the
module or class they are written in (``seam_cut``, ``to_dict``), or through
another package that re-exports it. When Sphinx's own lookup fails, this
extension imports the named object and, if that object is documented, links
to its entry. A name of real code that is not public (a helper, a constant
outside ``__all__``) is shown as code without a link; a name that exists
nowhere stays unresolved, and the nitpicky build reports it.
"""

from __future__ import annotations

import importlib
import inspect
from functools import cache

_CANON: dict | None = None
_FIELD = object()  # stands for a dataclass field without a class-level default


def _canonical_names() -> dict:
    global _CANON
    if _CANON is None:
        from . import _key, public_api

        canon = {}
        for mod_name, entry in public_api().items():
            for name, obj in entry.own:
                canon.setdefault(_key(name, obj), f"{mod_name}.{name}")
        _CANON = canon
    return _CANON


@cache  # the same names come up thousands of times; a failed import is slow
def _lookup(path: str):
    """``(object, owner)`` for a dotted path (``owner`` is the class holding an attribute), or None."""
    parts = path.split(".")
    for cut in range(len(parts), 0, -1):
        try:
            obj = importlib.import_module(".".join(parts[:cut]))
        except Exception:  # noqa: BLE001 - any import failure means "not this prefix"
            continue
        owner = None
        for attr in parts[cut:]:
            owner = obj
            try:
                obj = inspect.getattr_static(obj, attr) if inspect.isclass(obj) else getattr(obj, attr)
            except AttributeError:
                if attr in getattr(owner, "__dataclass_fields__", {}):
                    obj = _FIELD
                    continue
                return None
        return obj, owner
    return None


def _target_for(path: str) -> tuple[str, bool] | None:
    """The documented name of the object at ``path`` and whether it is a module, or None."""
    found = _lookup(path)
    if found is None:
        return None
    from . import _key

    obj, owner = found
    canon = _canonical_names()
    if inspect.ismodule(obj):
        return obj.__name__, True
    name = path.rsplit(".", 1)[-1]
    raw = obj.__func__ if isinstance(obj, (staticmethod, classmethod)) else obj
    if obj is not _FIELD and _key(name, raw) in canon:
        return canon[_key(name, raw)], False
    if inspect.isclass(owner) and _key(owner.__name__, owner) in canon:
        return f"{canon[_key(owner.__name__, owner)]}.{name}", False
    return None


def _missing_reference(app, env, node, contnode):
    if node.get("refdomain") != "py":
        return None
    target = node.get("reftarget", "")
    if not target or target.startswith("."):
        target = target.lstrip(".")
    mod, cls = node.get("py:module"), node.get("py:class")
    candidates = []
    # autodoc marks where a docstring came from ("...: docstring of branchnb.leaves.synthesis.GeneratedLeaf"):
    # names in it are relative to the *defining* module, not to where the page documents it
    source = _source_of(node)
    if "docstring of " in source:
        owner = source.rsplit("docstring of ", 1)[1].strip()
        parts = owner.split(".")
        candidates += [".".join(parts[:k] + [target]) for k in range(len(parts), 1, -1)]
    if mod and cls:
        candidates.append(f"{mod}.{cls}.{target}")
    if mod:
        candidates.append(f"{mod}.{target}")
        # a package's docstring may name its submodules' objects relatively too
        candidates += [f"{mod.rsplit('.', k)[0]}.{target}" for k in range(1, mod.count("."))]
    candidates.append(target)
    domain = env.get_domain("py")
    exists = False
    for path in candidates:
        exists = exists or _lookup(path) is not None
        hit = _target_for(path)
        if hit is None:
            continue
        canon, is_module = hit
        found = domain.resolve_any_xref(env, node.get("refdoc", ""), app.builder, canon, node, contnode)
        # a module and a function may share a dotted name (branchnb.strokes.fetch): pick the kind named
        exact = [res for role, res in found if (role == "py:mod") == is_module]
        if exact:
            return exact[0]
    # The name is real code that the API reference does not show (a private helper or
    # constant): keep it as code text. A name that exists nowhere stays an error.
    return contnode if exists else None


def _source_of(node) -> str:
    while node is not None:
        if getattr(node, "source", None):
            return str(node.source)
        node = node.parent
    return ""


def setup(app):
    """Register the resolver (Sphinx calls this)."""
    app.connect("missing-reference", _missing_reference)
    return {"parallel_read_safe": True, "parallel_write_safe": True}
