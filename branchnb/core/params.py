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
    """
    meta = {"min": min, "max": max, "step": step, "help": help, "label": label,
            "options": tuple(options) if options is not None else None, "log": log, "ui": ui}
    if isinstance(default, (list, dict, set)):
        return dataclasses.field(default_factory=lambda: type(default)(default), metadata=meta)
    return dataclasses.field(default=default, metadata=meta)


def param_info(params) -> list[tuple[dataclasses.Field, dict]]:
    """``(field, metadata)`` of each field of a parameter dataclass (instance or type)."""
    if not dataclasses.is_dataclass(params):
        raise TypeError(f"params must be a dataclass, got {type(params).__name__}")
    return [(f, dict(f.metadata)) for f in dataclasses.fields(params)]


def check_params(params, *, name: str = "params"):
    """Validate a parameter dataclass instance against its metadata.

    Raises
    ------
    TypeError
        A field of the wrong type (e.g. a float for an int field).
    ValueError
        A value outside ``[min, max]`` or not among ``options``; the
        message names the field.

    Returns
    -------
    params
        The same instance, for chaining.
    """
    if not dataclasses.is_dataclass(params) or isinstance(params, type):
        raise TypeError(f"{name} must be a parameter dataclass instance, got {type(params).__name__}")
    for f, meta in param_info(params):
        v = getattr(params, f.name)
        default = f.default if f.default is not dataclasses.MISSING else None
        if isinstance(default, bool):
            if not isinstance(v, bool):
                raise TypeError(f"{name}.{f.name} must be a bool, got {v!r}")
            continue
        if isinstance(default, int) and not isinstance(default, bool):
            if isinstance(v, bool) or not isinstance(v, int) and not (
                isinstance(v, float) and v.is_integer()
            ):
                if v is not None:
                    raise TypeError(f"{name}.{f.name} must be an int, got {v!r}")
        if meta.get("options") is not None and v not in meta["options"]:
            raise ValueError(f"{name}.{f.name} must be one of {list(meta['options'])}, got {v!r}")
        if isinstance(v, (int, float)) and not isinstance(v, bool):
            if v != v:  # NaN
                raise ValueError(f"{name}.{f.name} is NaN")
            lo, hi = meta.get("min"), meta.get("max")
            if lo is not None and v < lo:
                raise ValueError(f"{name}.{f.name} must be >= {lo}, got {v}")
            if hi is not None and v > hi:
                raise ValueError(f"{name}.{f.name} must be <= {hi}, got {v}")
    return params
