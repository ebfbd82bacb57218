"""ParamPanel: honest controls built from a parameter dataclass.

Every control is one row of the same geometry: a readable label with the
paper's symbol (the tooltip is the field's help text), the slider (or
checkbox, dropdown), and an editable readout. The panel keeps the *exact*
value of every field: the browser snaps a slider to its step grid when it
draws it (20 would become 19.88), and that snap is not taken for a user
change, so an untouched field keeps the dataclass default and "reset"
restores the exact defaults. A typed value outside the field's range is
refused with a message naming the range (nothing is clamped silently).
"""

from __future__ import annotations

import asyncio
import dataclasses
import enum
import html
import math
from collections.abc import Callable, Mapping, Sequence

import ipywidgets as widgets

from ..core.params import check_params, param_info
from .feedback import ErrorArea

__all__ = ["ParamPanel", "LABEL_WIDTH", "SLIDER_WIDTH", "READOUT_WIDTH"]

#: Geometry shared by every control row (pixels), so that sliders line up.
LABEL_WIDTH, SLIDER_WIDTH, READOUT_WIDTH = 158, 96, 54


def _nice_step(span: float) -> float:
    raw = span / 200.0
    if raw <= 0 or not math.isfinite(raw):
        return 0.01
    e = 10 ** math.floor(math.log10(raw))
    return min((m * e for m in (1, 2, 5, 10) if m * e >= raw), default=raw)


def _grid_min(value: float, lo: float, step: float) -> float:
    """The slider minimum (>= ``lo``) whose step grid passes through ``value``.

    The browser rounds a slider's value onto ``min + k * step``; with this
    minimum the thumb sits exactly on the default.
    """
    if not lo <= value or step <= 0:
        return lo
    k = math.floor((value - lo) / step + 1e-9)
    return value - k * step


def _fmt(v) -> str:
    if isinstance(v, bool) or isinstance(v, int):
        return str(v)
    if isinstance(v, float):
        return f"{v:.6g}"
    return str(v)


class _Row:
    """One field: label, input widget, readout, message; knows the exact value."""

    def __init__(self, name: str, meta: dict, value, *, label: str, symbol: str, log: bool | None,
                 continuous: bool):
        self.name, self.meta, self.exact = name, meta, value
        self.kind = "other"
        self.tol = 0.0
        lo, hi = meta.get("min"), meta.get("max")
        self.lo, self.hi = lo, hi
        help_text = meta.get("help") or ""
        geometry = widgets.Layout(width=f"{SLIDER_WIDTH}px")
        options = meta.get("options")
        if isinstance(value, enum.Enum):
            options = options or tuple(type(value))
        w: widgets.Widget
        if options is not None:
            w = widgets.Dropdown(options=list(options), value=value,
                                 layout=widgets.Layout(width=f"{SLIDER_WIDTH + READOUT_WIDTH + 4}px"))
            self.kind = "choice"
        elif isinstance(value, bool):
            w = widgets.Checkbox(value=value, indent=False, layout=geometry)
            self.kind = "bool"
        elif isinstance(value, int) and lo is not None and hi is not None:
            step = int(meta.get("step") or 1)
            w = widgets.IntSlider(value=value, min=int(_grid_min(value, int(lo), step)), max=int(hi),
                                  step=step, readout=False,
                                  continuous_update=continuous, layout=geometry)
            self.kind, self.tol = "int", step / 2.0
        elif isinstance(value, float) and lo is not None and hi is not None:
            use_log = meta.get("log") if log is None else log
            if use_log and hi > 0:
                top = math.log10(hi)
                bottom = math.log10(lo) if lo > 0 else top - 4.0
                step = 0.02  # in decades: about 2.3 % per step
                shown = min(max(value, 10 ** bottom), 10 ** top)
                bottom = _grid_min(math.log10(shown), bottom, step)
                w = widgets.FloatLogSlider(value=shown, base=10, min=bottom, max=top, step=step,
                                           readout=False, continuous_update=continuous, layout=geometry)
                self.kind, self.tol = "log", step / 2.0
            else:
                step = float(meta.get("step") or _nice_step(float(hi) - float(lo)))
                w = widgets.FloatSlider(value=value, min=_grid_min(value, float(lo), step),
                                        max=float(hi), step=step,
                                        readout=False, continuous_update=continuous, layout=geometry)
                self.kind, self.tol = "float", step / 2.0
        elif isinstance(value, (int, float)):
            w = widgets.Text(value=_fmt(value), continuous_update=False,
                             layout=widgets.Layout(width=f"{SLIDER_WIDTH + READOUT_WIDTH + 4}px"))
            self.kind = "number"
        elif isinstance(value, str):
            w = widgets.Text(value=value, continuous_update=False,
                             layout=widgets.Layout(width=f"{SLIDER_WIDTH + READOUT_WIDTH + 4}px"))
            self.kind = "text"
        else:
            raise TypeError(f"no control for {name} = {value!r}")
        w.tooltip = help_text
        self.widget = w
        sym = f" <i style='color:#555'>{html.escape(symbol)}</i>" if symbol else ""
        self.text, self.symbol, self.help = label, symbol, help_text
        tip = f"{label}{f' ({symbol})' if symbol else ''}: {help_text}" if help_text else label
        # One line whatever the label's length: a long one ends in "..." (the full text is the
        # tooltip and the section's help list).
        self.label = widgets.HTML(
            f"<div class='bnb-param-label' title='{html.escape(tip, quote=True)}' style='white-space:nowrap;"
            f"overflow:hidden;text-overflow:ellipsis;font-size:12px;line-height:28px;"
            f"max-width:{LABEL_WIDTH}px'>"
            f"{html.escape(label)}{sym}</div>",
            layout=widgets.Layout(width=f"{LABEL_WIDTH}px", margin="0 4px 0 0", overflow="hidden"))
        self.label.tooltip = help_text
        parts = [self.label, w]
        self.readout = None
        if self.kind in ("int", "float", "log"):
            self.readout = widgets.Text(value=_fmt(value), continuous_update=False,
                                        layout=widgets.Layout(width=f"{READOUT_WIDTH}px"))
            self.readout.tooltip = f"type a value in [{_fmt(lo)}, {_fmt(hi)}]"
            parts.append(self.readout)
        self.message = widgets.HTML(layout=widgets.Layout(display="none"))
        self.box = widgets.VBox([widgets.HBox(parts, layout=widgets.Layout(align_items="center")),
                                 self.message], layout=widgets.Layout(margin="0 0 1px 0"))
        self.box.add_class(f"bnb-param-{name}")  # for tests in a real browser

    # -- values -----------------------------------------------------------------
    def is_snap(self, shown) -> bool:
        """Whether the widget's value is only the browser's grid-snapped view of the exact value."""
        if self.kind in ("int", "float"):
            return abs(float(shown) - float(self.exact)) <= self.tol + 1e-9 * max(1.0, abs(self.exact))
        if self.kind == "log":
            e = float(self.exact)
            if e <= 0:
                return float(shown) <= 10 ** self.widget.min * 1.0001
            return abs(math.log10(float(shown)) - math.log10(e)) <= self.tol + 1e-9
        return shown == self.exact

    def from_widget(self, shown):
        if self.kind == "int":
            return int(round(shown))
        if self.kind in ("float", "log"):
            return float(shown)
        if self.kind == "number":
            return self.parse(shown)
        return shown

    def parse(self, text):
        """A typed value, checked against the field's type and range (ValueError with the reason)."""
        t = str(text).strip()
        is_int = isinstance(self.exact, int) and not isinstance(self.exact, bool)
        try:
            v = float(t)
        except ValueError:
            raise ValueError(f"{self.name}: {t!r} is not a number") from None
        if not math.isfinite(v):
            raise ValueError(f"{self.name}: {t!r} is not a finite number")
        if is_int:
            if not v.is_integer():
                raise ValueError(f"{self.name} takes whole numbers, got {t}")
            v = int(v)
        if (self.lo is not None and v < self.lo) or (self.hi is not None and v > self.hi):
            raise ValueError(f"{self.name} must be in [{_fmt(self.lo)}, {_fmt(self.hi)}], got {t}; "
                             f"kept {_fmt(self.exact)}")
        return v

    def show_exact(self) -> None:
        """Put the exact value into the widget (the browser may snap it) and the readout."""
        v = self.exact
        if self.kind == "log":
            self.widget.value = min(max(float(v), 10 ** self.widget.min), 10 ** self.widget.max)
        elif self.kind in ("number",):
            self.widget.value = _fmt(v)
        else:
            self.widget.value = v
        if self.readout is not None:
            self.readout.value = _fmt(v)

    def say(self, text: str | None) -> None:
        if text:
            self.message.value = (f"<span style='color:#c62828;font-size:11px'>"
                                  f"{html.escape(text)}</span>")
            self.message.layout.display = None
        else:
            self.message.value = ""
            self.message.layout.display = "none"


class ParamPanel(widgets.VBox):
    """Labelled controls for every field of a parameter dataclass, grouped in sections.

    Ranges, steps and tooltips come from the field metadata
    (:func:`branchnb.core.params.param`); bools become checkboxes, fields
    with ``options`` dropdowns, ``log=True`` fields logarithmic sliders.
    The panel returns exactly the dataclass defaults until the user
    changes a control (see the module docstring). ``on_change`` callbacks
    get the validated dataclass once the user pauses for ``debounce``
    seconds (sliders report on release unless ``continuous``).

    Parameters
    ----------
    params : dataclass instance or type
        Initial values (a type means its defaults).
    on_change : callable, optional
        ``callback(values)``, called with the validated dataclass after each
        (debounced) change; more can be added with :meth:`on_change`.
    debounce : float
        Seconds to wait after the last change (0: call at once).
    continuous : bool
        Update while a slider is dragged (True) or on release.
    title : str, optional
        Heading above the controls.
    sections : sequence of (title, field names), optional
        Groups, e.g. the paper's sections; fields not listed go into a
        last group "other". Each group is a collapsible box.
    closed : sequence of str
        Section titles shown collapsed.
    labels : mapping, optional
        ``name -> (readable label, paper symbol)`` (or just a label);
        default: the field's ``label`` metadata, else its name.
    log : sequence of str
        Extra fields shown with a logarithmic slider (they span decades).
    hide : sequence of str
        Fields without a control (they keep the given value; the app may
        offer them elsewhere).
    errors : ErrorArea or StatusLine, optional
        Where errors go (the app's status line); a new area by default.

    Examples
    --------
    >>> from dataclasses import dataclass
    >>> from branchnb.core.params import param
    >>> @dataclass
    ... class P:
    ...     k: int = param(3, min=1, max=10, help="history length k")
    ...     s: float = param(20.0, min=0.5, max=40.0, help="step")
    >>> panel = ParamPanel(P, labels={"k": ("history length", "k")})
    >>> panel.controls["s"].value = 19.9     # the browser snapped 20 to its grid
    >>> panel.controls["k"].value = 5        # the user moved k
    >>> panel.values
    P(k=5, s=20.0)
    >>> panel.type_value("s", "99")
    False
    >>> panel.reset(); panel.values == P()
    True
    """

    def __init__(self, params, *, on_change: Callable | None = None, debounce: float = 0.0,
                 continuous: bool = False, title: str | None = None,
                 sections: Sequence[tuple[str, Sequence[str]]] | None = None,
                 closed: Sequence[str] = (), labels: Mapping | None = None,
                 log: Sequence[str] = (), hide: Sequence[str] = (), errors: ErrorArea | None = None):
        if isinstance(params, type):
            if not dataclasses.is_dataclass(params):
                raise TypeError(f"params must be a dataclass, got {params.__name__}")
            params = params()
        if not dataclasses.is_dataclass(params):
            raise TypeError(f"params must be a dataclass instance, got {type(params).__name__}")
        if not isinstance(debounce, (int, float)) or not debounce >= 0:
            raise ValueError(f"debounce must be >= 0, got {debounce!r}")
        self._type = type(params)
        self._defaults = self._type()
        self.debounce = float(debounce)
        self._callbacks: list[Callable] = []
        self._pending = None
        self._silent = False
        self.errors = errors if errors is not None else ErrorArea()
        self._own_errors = errors is None
        labels = dict(labels or {})
        self._fixed: dict = {}
        self.rows: dict[str, _Row] = {}
        self.controls: dict[str, widgets.Widget] = {}
        names = [f.name for f, _ in param_info(params)]
        for name in list(labels) + list(log) + list(hide):
            if name not in names:
                raise ValueError(f"labels/log/hide: {self._type.__name__} has no field {name!r}")
        for f, meta in param_info(params):
            value = getattr(params, f.name)
            if not meta.get("ui", True) or f.name in hide or not isinstance(
                    value, (bool, int, float, str, enum.Enum)):
                self._fixed[f.name] = value
                continue
            lab = labels.get(f.name, meta.get("label") or f.name.replace("_", " "))
            text, symbol = (lab, "") if isinstance(lab, str) else (lab[0], lab[1] if len(lab) > 1 else "")
            row = _Row(f.name, meta, value, label=text, symbol=symbol,
                       log=True if f.name in log else None, continuous=continuous)
            row.widget.observe(lambda ch, r=row: self._on_widget(r, ch), names="value")
            if row.readout is not None:
                row.readout.observe(lambda ch, r=row: self._on_typed(r, ch["new"]), names="value")
            self.rows[f.name] = row
            self.controls[f.name] = row.widget
        self.reset_button = widgets.Button(description="reset to defaults", icon="undo",
                                           tooltip="every field back to the paper's value",
                                           layout=widgets.Layout(width="auto", height="28px",
                                                                 min_height="28px"))
        self.reset_button.on_click(self.errors.guard(lambda _: self.reset()))
        self.sections = self._group(sections, closed)
        children = []
        if title:
            children.append(widgets.HTML(f"<b>{html.escape(title)}</b>"))
        children += self.sections + [self.reset_button]
        if self._own_errors:
            children.append(self.errors)
        super().__init__(children)
        if on_change is not None:
            self.on_change(on_change)

    def _group(self, sections, closed) -> list[widgets.Widget]:
        if not sections:
            rows = list(self.rows.values())
            return [widgets.VBox([self._help(rows)] + [r.box for r in rows])]
        out, used = [], set()
        groups = []
        for title, names in sections:
            rows = []
            for n in names:
                if n not in self.rows and n not in self._fixed:
                    raise ValueError(f"sections: {self._type.__name__} has no field {n!r}")
                if n in self.rows:
                    rows.append(self.rows[n])
                    used.add(n)
            groups.append((title, rows))
        rest = [r for n, r in self.rows.items() if n not in used]
        if rest:
            groups.append(("other", rest))
        for title, rows in groups:
            acc = widgets.Accordion(children=[widgets.VBox([self._help(rows)] + [r.box for r in rows])],
                                    titles=(title,),
                                    selected_index=None if title in closed else 0)
            acc.layout.margin = "0 0 2px 0"
            out.append(acc)
        return out

    @staticmethod
    def _help(rows) -> widgets.HTML:
        """A visible "? what these do" line per section: each field's label, symbol and help."""
        items = "".join(
            f"<li><b>{html.escape(r.text)}</b>{f' <i>{html.escape(r.symbol)}</i>' if r.symbol else ''}"
            f"{': ' + html.escape(r.help) if r.help else ''}</li>" for r in rows)
        box = widgets.HTML(
            "<details class='bnb-help' style='font-size:12px;color:#444;line-height:16px;margin:0 0 4px 2px'>"
            "<summary style='cursor:pointer;color:#1565c0'>? what these do</summary>"
            f"<ul style='margin:2px 0 2px 14px;padding:0'>{items}</ul></details>",
            layout=widgets.Layout(width="100%"))
        box.add_class("bnb-help-box")
        return box

    # -- values -------------------------------------------------------------------
    @property
    def values(self):
        """The current parameters as a (validated) dataclass instance."""
        kw = dict(self._fixed)
        kw.update({name: r.exact for name, r in self.rows.items()})
        return check_params(self._type(**kw))

    def set_values(self, params) -> None:
        """Show ``params`` exactly (one callback afterwards, not one per field).

        Parameters
        ----------
        params : dataclass instance
            Of the panel's dataclass type; checked with
            :func:`branchnb.core.params.check_params`. Hidden fields take
            its values too.

        Raises
        ------
        TypeError, ValueError
            If ``params`` is of another type or a field is invalid.
        """
        if not isinstance(params, self._type):
            raise TypeError(f"params must be a {self._type.__name__}, got {type(params).__name__}")
        check_params(params)
        self._silent = True
        try:
            for name, r in self.rows.items():
                r.exact = getattr(params, name)
                r.say(None)
                r.show_exact()
            self._fixed = {k: getattr(params, k) for k in self._fixed}
        finally:
            self._silent = False
        self._changed()

    def reset(self) -> None:
        """Back to the exact dataclass defaults (the paper's values)."""
        self.set_values(self._defaults)

    def type_value(self, name: str, text: str) -> bool:
        """Type ``text`` into a field's readout; False (and a message) if it is refused.

        What a user does in the browser, for scripts and tests: values
        beyond the slider's range but within the field's bounds are kept
        exactly.

        Parameters
        ----------
        name : str
            Field name.
        text : str
            What is typed (e.g. ``"0.25"``).

        Returns
        -------
        bool
            True if the value was accepted.

        Raises
        ------
        ValueError
            If there is no such field or it has no readout (checkbox, dropdown).
        """
        if name not in self.rows:
            raise ValueError(f"no control named {name!r}")
        r = self.rows[name]
        if r.readout is None:
            raise ValueError(f"{name} has no readout to type into")
        r.readout.value = str(text)
        return r.message.layout.display == "none"

    def on_change(self, callback: Callable, remove: bool = False) -> None:
        """Register ``callback(values)`` (or remove it).

        Parameters
        ----------
        callback : callable
            Called with the validated dataclass after each (debounced) change.
        remove : bool
            Unregister ``callback`` instead.

        Raises
        ------
        TypeError
            If ``callback`` is not callable.
        ValueError
            If removing a callback that was not registered.
        """
        if remove:
            self._callbacks.remove(callback)
        else:
            if not callable(callback):
                raise TypeError("callback must be callable")
            self._callbacks.append(callback)

    # -- events ---------------------------------------------------------------------
    def _on_widget(self, row: _Row, change) -> None:
        if self._silent:
            return
        shown = change["new"]
        if row.is_snap(shown):
            return  # the browser's view of the exact value, not a user change
        try:
            row.exact = row.from_widget(shown)
        except ValueError as exc:
            row.say(str(exc))
            return
        row.say(None)
        if row.readout is not None:
            self._silent = True
            try:
                row.readout.value = _fmt(row.exact)
            finally:
                self._silent = False
        self._changed()

    def _on_typed(self, row: _Row, text) -> None:
        if self._silent:
            return
        try:
            v = row.parse(text)
        except ValueError as exc:
            row.say(str(exc))
            self._silent = True
            try:
                row.readout.value = _fmt(row.exact)
            finally:
                self._silent = False
            return
        row.say(None)
        if v == row.exact:
            return
        row.exact = v
        self._silent = True
        try:
            row.show_exact()
        finally:
            self._silent = False
        self._changed()

    def _changed(self, _change=None) -> None:
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
