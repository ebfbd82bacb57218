"""Parameter dataclasses: defaults are the papers' values, metadata drives the UI.

A technique declares its parameters once::

    @dataclass
    class BendingParams:
        k: int = param(9, min=1, max=40, help="history length k (paper: 3 m)")
        c: int = param(2, min=1, max=10, help="choose among the c best candidates")

``ParamPanel`` builds sliders from the metadata and :func:`check_params`
validates an instance with errors that name the field.
"""

from __future__ import annotations

import dataclasses
from typing import Any

__all__ = ["param", "check_params", "param_info"]


def param(default: Any, *, min: float | None = None, max: float | None = None,
          step: float | None = None, help: str = "", label: str | None = None,
          options: tuple | list | None = None, log: bool = False, ui: bool = True):
    """A dataclass field with range/help metadata.

    Parameters
    ----------
    default : object
        The paper's value.
    min, max : float, optional
        Inclusive valid range (also the slider range).
    step : float, optional
        Slider step.
    help : str
        One line shown as the slider's tooltip; name the paper's symbol.
    label : str, optional
        Slider label (the field name by default).
    options : sequence, optional
        Allowed values (a dropdown).
    log : bool
        Use a logarithmic slider.
    ui : bool
        False hides the field from ``ParamPanel``.

    Returns
    -------
    dataclasses.Field
        A field with this metadata (a list/dict/set default becomes a
        ``default_factory`` copying it).

    Examples
    --------
    >>> from dataclasses import dataclass, fields
    >>> @dataclass
    ... class P:
    ...     k: int = param(9, min=1, max=40, help="bending memory k")
    >>> P().k, fields(P)[0].metadata["max"]
    (9, 40)
    """
    meta = {"min": min, "max": max, "step": step, "help": help, "label": label,
            "options": tuple(options) if options is not None else None, "log": log, "ui": ui}
    if isinstance(default, (list, dict, set)):
        return dataclasses.field(default_factory=lambda: type(default)(default), metadata=meta)
    return dataclasses.field(default=default, metadata=meta)


def param_info(params) -> list[tuple[dataclasses.Field, dict]]:
    """``(field, metadata)`` of each field of a parameter dataclass (instance or type).

    Parameters
    ----------
    params : dataclass instance or type
        A parameter dataclass whose fields were made with :func:`param`
        (plain fields give an empty metadata dict).

    Returns
    -------
    list of (dataclasses.Field, dict)
        In field order; the dict has the keys of :func:`param` (``min``,
        ``max``, ``step``, ``help``, ``label``, ``options``, ``log``, ``ui``).

    Raises
    ------
    TypeError
        If ``params`` is not a dataclass.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass
    ... class P:
    ...     k: int = param(9, min=1, max=40)
    >>> [(f.name, meta["max"]) for f, meta in param_info(P)]
    [('k', 40)]
    """
    if not dataclasses.is_dataclass(params):
        raise TypeError(f"params must be a dataclass, got {type(params).__name__}")
    return [(f, dict(f.metadata)) for f in dataclasses.fields(params)]


def _field_kind(f: dataclasses.Field, default) -> tuple[str | None, bool]:
    """``(kind, allow_none)`` of a field from its annotation (or its default's type)."""
    ann = f.type if isinstance(f.type, str) else getattr(f.type, "__name__", str(f.type))
    parts = {p.strip() for p in ann.replace("Optional[", "").replace("]", "").split("|")}
    allow_none = "None" in parts or default is None
    parts.discard("None")
    kinds = parts & {"bool", "int", "float", "str"}
    if len(parts) == 1 and kinds:
        return kinds.pop(), allow_none
    for kind, t in (("bool", bool), ("int", int), ("float", float), ("str", str)):
        if isinstance(default, t):
            return kind, allow_none
    return None, allow_none


def check_params(params, *, name: str = "params"):
    """Validate a parameter dataclass instance against its types and metadata.

    Every field is checked for its annotated type (``bool``, ``int``,
    ``float``, ``str``; ``None`` only where the annotation or default
    allows it), for NaN/inf, for ``[min, max]`` (the bounds double as size
    guards) and for ``options``. Integral floats in int fields are
    normalised to int.

    Parameters
    ----------
    params : dataclass instance
        A parameter dataclass (fields made with :func:`param`); int fields
        holding integral floats are rewritten in place.
    name : str, optional
        How messages name the instance (``"params.k must be ..."``).

    Returns
    -------
    params
        The same instance, for chaining.

    Raises
    ------
    TypeError
        A field of the wrong type (e.g. a string for a float field).
    ValueError
        NaN/inf, a value outside ``[min, max]`` or not among ``options``;
        the message names the field.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> @dataclass
    ... class P:
    ...     k: int = param(9, min=1, max=40)
    >>> check_params(P(k="9"))
    Traceback (most recent call last):
    ...
    TypeError: params.k must be an int, got str '9'
    """
    from .validate import check_bool, check_int, check_real

    if not dataclasses.is_dataclass(params) or isinstance(params, type):
        raise TypeError(f"{name} must be a parameter dataclass instance, got {type(params).__name__}")
    for f, meta in param_info(params):
        v = getattr(params, f.name)
        fname = f"{name}.{f.name}"
        default = f.default if f.default is not dataclasses.MISSING else None
        kind, allow_none = _field_kind(f, default)
        if v is None:
            if allow_none:
                continue
            raise TypeError(f"{fname} must not be None")
        lo, hi = meta.get("min"), meta.get("max")
        if kind == "bool":
            check_bool(v, fname)
        elif kind == "int":
            iv = check_int(v, fname, lo, hi)
            if type(v) is not int:
                object.__setattr__(params, f.name, iv)
        elif kind == "float":
            check_real(v, fname, lo, hi)
        elif kind == "str" and not isinstance(v, str):
            raise TypeError(f"{fname} must be a str, got {type(v).__name__} {v!r:.60}")
        elif kind is None and isinstance(v, (int, float)) and not isinstance(v, bool):
            check_real(v, fname, lo, hi)
        if meta.get("options") is not None:
            try:
                ok = v in meta["options"]
            except Exception:
                ok = False
            if not ok:
                raise ValueError(f"{fname} must be one of {list(meta['options'])}, got {v!r:.60}")
    return params
