"""ParamPanel: controls built from a parameter dataclass."""

from __future__ import annotations

import asyncio
import dataclasses
import enum
from collections.abc import Callable

import ipywidgets as widgets

from ..core.params import check_params, param_info
from .feedback import ErrorArea

__all__ = ["ParamPanel"]


def _control(f: dataclasses.Field, meta: dict, value, continuous: bool) -> widgets.Widget:
    label = meta.get("label") or f.name
    common = {"description": label, "style": {"description_width": "initial"},
              "layout": widgets.Layout(width="auto", min_width="320px")}
    lo, hi, step = meta.get("min"), meta.get("max"), meta.get("step")
    options = meta.get("options")
    if isinstance(value, enum.Enum):
        options = options or tuple(type(value))
    if options is not None:
        w = widgets.Dropdown(options=list(options), value=value, **common)
    elif isinstance(value, bool):
        w = widgets.Checkbox(value=value, indent=False, **common)
    elif isinstance(value, int):
        if lo is not None and hi is not None:
            w = widgets.IntSlider(value=value, min=int(lo), max=int(hi), step=int(step or 1),
                                  continuous_update=continuous, **common)
        else:
            w = widgets.BoundedIntText(value=value, min=-10**9 if lo is None else int(lo),
                                       max=10**9 if hi is None else int(hi), **common)
    elif isinstance(value, float):
        if lo is not None and hi is not None and meta.get("log") and lo > 0:
            import math

            w = widgets.FloatLogSlider(value=value, base=10, min=math.log10(lo), max=math.log10(hi),
                                       step=step or 0.05, continuous_update=continuous, **common)
        elif lo is not None and hi is not None:
            w = widgets.FloatSlider(value=value, min=float(lo), max=float(hi),
                                    step=step or (float(hi) - float(lo)) / 100.0,
                                    continuous_update=continuous, readout_format=".3g", **common)
        else:
            w = widgets.BoundedFloatText(value=value, min=-1e12 if lo is None else float(lo),
                                         max=1e12 if hi is None else float(hi), **common)
    elif isinstance(value, str):
        w = widgets.Text(value=value, continuous_update=False, **common)
    else:
        return None
    if meta.get("help"):
        w.tooltip = meta["help"]
    return w


class ParamPanel(widgets.VBox):
    """Labelled controls for every field of a parameter dataclass.

    Sliders get their range, step and tooltip from the field metadata
    (:func:`branchnb.core.params.param`); bools become checkboxes, fields
    with ``options`` dropdowns. Changes are debounced: ``on_change``
    callbacks fire once the user pauses for ``debounce`` seconds, with the
    validated dataclass. Invalid combinations are shown in the panel's
    error area.

    Parameters
    ----------
    params : dataclass instance or type
        Initial values (a type means its defaults).
    on_change : callable, optional
        ``callback(values)``.
    debounce : float
        Seconds to wait after the last change (0: call immediately).
    continuous : bool
        Update while a slider is dragged (True) or on release.
    title : str, optional

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> from branchnb.core.params import param
    >>> @dataclass
    ... class P:
    ...     k: int = param(3, min=1, max=10, help="history length")
    >>> panel = ParamPanel(P, debounce=0)
    >>> panel.controls["k"].value = 5
    >>> panel.values
    P(k=5)
    """

    def __init__(self, params, *, on_change: Callable | None = None, debounce: float = 0.2,
                 continuous: bool = True, title: str | None = None):
        if isinstance(params, type):
            if not dataclasses.is_dataclass(params):
                raise TypeError(f"params must be a dataclass, got {params.__name__}")
            params = params()
        if not dataclasses.is_dataclass(params):
            raise TypeError(f"params must be a dataclass instance, got {type(params).__name__}")
        if debounce < 0:
            raise ValueError(f"debounce must be >= 0, got {debounce}")
        self._type = type(params)
        self._defaults = self._type()
        self._fixed = {}
        self.debounce = float(debounce)
        self._callbacks: list[Callable] = []
        self._pending = None
        self._silent = False
        self.errors = ErrorArea()
        self.controls: dict[str, widgets.Widget] = {}
        for f, meta in param_info(params):
            value = getattr(params, f.name)
            w = _control(f, meta, value, continuous) if meta.get("ui", True) else None
            if w is None:
                self._fixed[f.name] = value
                continue
            w.observe(self._changed, names="value")
            self.controls[f.name] = w
        self.reset_button = widgets.Button(description="reset to defaults", icon="undo",
                                           layout=widgets.Layout(width="auto"))
        self.reset_button.on_click(self.errors.guard(lambda _: self.reset()))
        children = []
        if title:
            children.append(widgets.HTML(f"<b>{title}</b>"))
        children += list(self.controls.values()) + [self.reset_button, self.errors]
        super().__init__(children)
        if on_change is not None:
            self.on_change(on_change)

    @property
    def values(self):
        """The current parameters as a (validated) dataclass instance."""
        kw = dict(self._fixed)
        kw.update({name: w.value for name, w in self.controls.items()})
        return check_params(self._type(**kw))

    def set_values(self, params) -> None:
        """Show ``params`` (one callback afterwards, not one per field)."""
        if not isinstance(params, self._type):
            raise TypeError(f"params must be a {self._type.__name__}, got {type(params).__name__}")
        self._silent = True
        try:
            for name, w in self.controls.items():
                w.value = getattr(params, name)
            self._fixed = {k: getattr(params, k) for k in self._fixed}
        finally:
            self._silent = False
        self._changed(None)

    def reset(self) -> None:
        """Back to the dataclass defaults (the paper's values)."""
        self.set_values(self._defaults)

    def on_change(self, callback: Callable, remove: bool = False) -> None:
        """Register ``callback(values)`` (or remove it)."""
        if remove:
            self._callbacks.remove(callback)
        else:
            if not callable(callback):
                raise TypeError("callback must be callable")
            self._callbacks.append(callback)

    def _changed(self, _change) -> None:
        if self._silent:
            return
        if self._pending is not None:
            self._pending.cancel()
            self._pending = None
        loop = None
        if self.debounce > 0:
            try:
                loop = asyncio.get_running_loop()
            except RuntimeError:
                loop = None
        if loop is None:
            self.flush()
        else:
            self._pending = loop.call_later(self.debounce, self.flush)

    def flush(self) -> None:
        """Fire the callbacks now with the current values."""
        self._pending = None
        with self.errors.catch():
            values = self.values
            for cb in list(self._callbacks):
                cb(values)
