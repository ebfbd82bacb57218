"""One door for every public function: numbers, arrays, colours, sizes and polylines.

Every check raises :class:`TypeError` (wrong kind of value) or
:class:`ValueError` (right kind, bad value) with a message that starts with
the argument's name, so a user can tell which argument to fix. The
algorithms behind the door can then assume clean data: finite numbers, real
arrays, colours in [0, 1], coordinates small enough to index pixels with.

:func:`checked` applies the number checks to a whole signature at once::

    @checked(n=Int(1, MAX_COUNT), sigma=Real(0, 100, low_open=True))
    def blur_many(image, n: int, sigma: float = 1.0): ...

Parameters annotated ``float``, ``int`` or ``bool`` (optionally ``| None``
when the default is None) are type-checked without being listed; ``rng``
is checked with :func:`check_rng`; parameter dataclasses passed in go
through :func:`~branchnb.core.params.check_params` and structures through
``Structure.validate`` (which catches parent cycles made after construction).
"""
from __future__ import annotations

import functools
import inspect
import re

import numpy as np

from .validate_arrays import (  # noqa: F401
    as_colour,
    as_colours,
    as_point,
    as_polylines,
    check_finite,
    check_output_path,
    check_range_pair,
    check_shape,
    real_array,
)
from .validate_scalars import (  # noqa: F401
    COORD_LIMIT,
    MAX_COUNT,
    MAX_ITERATIONS,
    MAX_PIXELS,
    _check_range,
    _fmt,
    _is_real_scalar,
    brief,
    check_bool,
    check_callback,
    check_choice,
    check_int,
    check_real,
    check_rng,
)

__all__ = [
    "COORD_LIMIT",
    "MAX_PIXELS",
    "MAX_COUNT",
    "MAX_ITERATIONS",
    "Real",
    "Int",
    "Array",
    "Choice",
    "Point",
    "Points",
    "Shape",
    "Colour",
    "Instance",
    "ListOf",
    "Seq",
    "Image",
    "Colormap",
    "checked",
    "check_real",
    "check_int",
    "check_bool",
    "check_choice",
    "check_rng",
    "check_callback",
    "brief",
    "real_array",
    "as_colour",
    "as_colours",
    "check_shape",
    "as_polylines",
    "as_point",
    "check_range_pair",
    "check_finite",
    "check_output_path",
]


class Real:
    """Spec for :func:`checked`: a real number in a range (``arrays=True``: or an array of them).

    Parameters
    ----------
    min, max : float, optional
        Bounds, as for :func:`check_real`.
    low_open, high_open : bool
        Exclude the bound itself, as for :func:`check_real`.
    allow_inf : bool
        Let +-inf through.
    arrays : bool
        Also accept a numpy array (of at least one dimension) whose values
        all satisfy the bounds; it is passed on as a float64 array.

    Examples
    --------
    >>> Real(0, 1)(0.5, "alpha", False)
    0.5
    """

    def __init__(self, min=None, max=None, *, low_open=False, high_open=False, allow_inf=False, arrays=False):
        self.kw = dict(min=min, max=max, low_open=low_open, high_open=high_open, allow_inf=allow_inf)
        self.arrays = arrays

    def __call__(self, value, name, allow_none):
        if self.arrays and isinstance(value, np.ndarray) and value.ndim > 0:
            arr = real_array(value, name, allow_inf=self.kw["allow_inf"])
            for v in (arr.min(), arr.max()):
                check_real(v, name, **self.kw)
            return arr
        return check_real(value, name, allow_none=allow_none, **self.kw)


class Int:
    """Spec for :func:`checked`: an int in a range.

    Parameters
    ----------
    min, max : int, optional
        Inclusive bounds (see :func:`check_int`).

    Examples
    --------
    >>> Int(1)(2.0, "n", False)
    2
    """

    def __init__(self, min=None, max=None):
        self.min, self.max = min, max

    def __call__(self, value, name, allow_none):
        return check_int(value, name, self.min, self.max, allow_none=allow_none)


class Array:
    """Spec for :func:`checked`: a real array (see :func:`real_array` for the options).

    Parameters
    ----------
    **kwargs
        Keyword arguments of :func:`real_array` (``ndim``, ``dtype``,
        ``finite``, ``allow_empty``, ``min``, ``max``, ``allow_inf``); the
        converted array is passed on.

    Examples
    --------
    >>> Array(ndim=1, min=0)([1, 2], "weights", False).tolist()
    [1.0, 2.0]
    """

    def __init__(self, **kwargs):
        self.kw = kwargs

    def __call__(self, value, name, allow_none):
        if value is None and allow_none:
            return None
        return real_array(value, name, **self.kw)


class Points:
    """Spec for :func:`checked`: finite ``(x, y)`` points, one ``(2,)`` or ``(N, 2)``.

    Examples
    --------
    >>> Points()([(0, 0), (1, 2)], "points", False).shape
    (2, 2)
    """

    def __call__(self, value, name, allow_none):
        if value is None and allow_none:
            return None
        arr = real_array(value, name, ndim=(1, 2), allow_empty=True)
        if arr.shape[-1] != 2:
            raise ValueError(f"{name} must be (x, y) points of shape (2,) or (N, 2), got {arr.shape}")
        return arr


class Image:
    """Spec for :func:`checked`: an image :func:`~branchnb.core.image.as_float_image` accepts.

    The image is checked and passed on unchanged.

    Examples
    --------
    >>> Image()(np.zeros((2, 2)), "image", False).shape
    (2, 2)
    """

    def __call__(self, value, name, allow_none):
        if value is None and allow_none:
            return None
        from .image import as_float_image

        as_float_image(value, name=name)
        return value


class Seq:
    """Spec for :func:`checked`: a list or tuple (e.g. one entry per stroke), not a string or a number.

    Examples
    --------
    >>> Seq()("abc", "strokes", False)
    Traceback (most recent call last):
    ...
    TypeError: strokes must be a sequence (list or tuple), got str
    """

    def __call__(self, value, name, allow_none):
        if value is None and allow_none:
            return None
        if isinstance(value, (str, bytes, dict)) or not hasattr(value, "__len__") or (
                isinstance(value, np.ndarray) and value.ndim == 0):
            raise TypeError(f"{name} must be a sequence (list or tuple), got {type(value).__name__}")
        return value


class Colormap:
    """Spec for :func:`checked`: the name of a matplotlib colormap.

    Examples
    --------
    >>> Colormap()("magma", "cmap", False)
    'magma'
    """

    def __call__(self, value, name, allow_none):
        import matplotlib

        if not isinstance(value, str) or value not in matplotlib.colormaps:
            raise ValueError(f"{name} must be a matplotlib colormap name (e.g. 'magma'), got {value!r:.60}")
        return value


class Choice:
    """Spec for :func:`checked`: one of a few values (strings are matched exactly).

    Parameters
    ----------
    *options : object
        The allowed values (see :func:`check_choice`).

    Examples
    --------
    >>> Choice("l1", "emd")("l1", "metric", False)
    'l1'
    """

    def __init__(self, *options):
        self.options = options

    def __call__(self, value, name, allow_none):
        if value is None and allow_none:
            return None
        return check_choice(value, name, self.options)


class Point:
    """Spec for :func:`checked`: one finite (x, y) point.

    Examples
    --------
    >>> Point()((3, 4), "seed", False).tolist()
    [3.0, 4.0]
    """

    def __call__(self, value, name, allow_none):
        if value is None and allow_none:
            return None
        return as_point(value, name)


class Shape:
    """Spec for :func:`checked`: a positive (H, W) within :data:`MAX_PIXELS`.

    Examples
    --------
    >>> Shape()((48, 64, 3), "shape", False)
    (48, 64)
    """

    def __call__(self, value, name, allow_none):
        if value is None and allow_none:
            return None
        return check_shape(value, name)


class Colour:
    """Spec for :func:`checked`: one colour in [0, 1].

    Parameters
    ----------
    channels : tuple of int
        Allowed numbers of components (RGB or RGBA by default); the colour
        is passed on as a float32 array (see :func:`as_colour`).

    Examples
    --------
    >>> Colour()((1, 0, 0), "color", False).tolist()
    [1.0, 0.0, 0.0]
    """

    def __init__(self, channels=(3, 4)):
        self.channels = channels

    def __call__(self, value, name, allow_none):
        if value is None and allow_none:
            return None
        return as_colour(value, name, channels=self.channels)


class Instance:
    """Spec for :func:`checked`: an instance of a class named here (by name, so no import is needed).

    Parameters
    ----------
    *class_names : str
        Names of accepted classes; an instance of a subclass of any of them
        passes (matched by ``__name__`` along the MRO).

    Examples
    --------
    >>> Instance("Structure")(None, "structure", True) is None
    True
    """

    def __init__(self, *class_names):
        self.names = set(class_names)

    def __call__(self, value, name, allow_none):
        if value is None and allow_none:
            return None
        if not self.names & {k.__name__ for k in type(value).__mro__}:
            raise TypeError(f"{name} must be {' or '.join(sorted(self.names))}, got {type(value).__name__}")
        return value


class ListOf:
    """Spec for :func:`checked`: a list or tuple whose items are instances of the named classes.

    Parameters
    ----------
    *class_names : str
        Names of accepted item classes (see :class:`Instance`).

    Examples
    --------
    >>> ListOf("int")([1, 2], "counts", False)
    [1, 2]
    """

    def __init__(self, *class_names):
        self.item = Instance(*class_names)

    def __call__(self, value, name, allow_none):
        if value is None and allow_none:
            return None
        if isinstance(value, (str, bytes, dict)) or not isinstance(value, (list, tuple)):
            raise TypeError(f"{name} must be a list of {' or '.join(sorted(self.item.names))}, "
                            f"got {type(value).__name__}")
        for i, v in enumerate(value):
            self.item(v, f"{name}[{i}]", False)
        return value


def _annotation_text(annotation) -> str:
    """An annotation as source text (``from __future__ import annotations`` gives it so already)."""
    if isinstance(annotation, str):
        return annotation
    if isinstance(annotation, type):
        return annotation.__name__
    return re.sub(r"\b[\w.]+\.(\w+)", r"\1", str(annotation)).replace("NoneType", "None")


def _class_spec(annotation):
    """An :class:`Instance` spec for annotations like ``"Dendrite"``, ``"PlanResult | None"``
    or ``"list[Stroke]"``."""
    annotation = _annotation_text(annotation)
    m = re.fullmatch(r"list\[([A-Z][A-Za-z0-9_]*)\]", annotation.strip())
    if m:
        return ListOf(m.group(1)), False
    parts = [p.strip() for p in annotation.split("|")]
    names = [p for p in parts if p != "None"]
    if not names or not all(re.fullmatch(r"[A-Z][A-Za-z0-9_]*", p) for p in names):
        return None
    return Instance(*names), "None" in parts


def _check_objects(value, name):
    """Parameter dataclasses go through ``check_params``; structures through ``validate``."""
    import dataclasses

    if dataclasses.is_dataclass(value) and not isinstance(value, type):
        fields = dataclasses.fields(value)
        if fields and all("help" in f.metadata for f in fields):
            from .params import check_params

            check_params(value, name=name)
            return
    validate = getattr(type(value), "validate", None)
    if validate is not None and type(value).__name__ == "Structure":
        try:
            value.validate()
        except ValueError as exc:
            raise ValueError(f"{name}: {exc}") from None


_AUTO = {"float": Real(), "int": Int(), "bool": None}


def _auto_spec(annotation, default):
    """The check an annotation asks for: ('float'|'int'|'bool', allow_none) or None."""
    annotation = _annotation_text(annotation)
    parts = {p.strip() for p in annotation.split("|")}
    allow_none = "None" in parts or default is None
    parts.discard("None")
    if len(parts) == 1 and (kind := parts.pop()) in _AUTO:
        return kind, allow_none
    return None


def checked(**specs):
    """Decorate a public function so its scalar arguments are validated at the door.

    Parameters
    ----------
    **specs : Real, Int or callable
        Per-argument checks: a :class:`Real`/:class:`Int` spec, or any
        callable ``f(value, name, allow_none) -> value``. Arguments not
        listed but annotated ``float``/``int``/``bool`` get a type check;
        ``rng`` gets :func:`check_rng`. The checked (normalised) values are
        what the function receives.

    Returns
    -------
    callable
        The decorator; the decorated function keeps its name, docstring
        and signature.

    Examples
    --------
    >>> @checked(n=Int(1, 10))
    ... def repeat(word: str, n: int = 2, scale: float = 1.0):
    ...     return word * n
    >>> repeat("ab", 3.0)
    'ababab'
    >>> repeat("ab", scale=float("inf"))
    Traceback (most recent call last):
    ...
    ValueError: scale must be a finite number, got inf
    """

    def decorate(func):
        sig = inspect.signature(func)
        plan = []
        for pname, p in sig.parameters.items():
            if p.kind in (p.VAR_POSITIONAL, p.VAR_KEYWORD):
                continue
            optional_none = p.default is None or "None" in _annotation_text(p.annotation)
            default = p.empty if p.default is p.empty else p.default
            if pname in specs:
                plan.append((pname, specs[pname], optional_none))
            elif pname == "rng":
                plan.append((pname, lambda v, n, _a: check_rng(v, n), True))
            elif (cls_spec := _class_spec(p.annotation)) is not None:
                plan.append((pname, cls_spec[0], cls_spec[1] or p.default is None))
            elif p.annotation is not p.empty and (auto := _auto_spec(p.annotation, default)):
                kind, allow_none = auto
                if kind == "bool":
                    plan.append((pname, lambda v, n, a: v if (a and v is None) else check_bool(v, n), allow_none))
                else:
                    plan.append((pname, _AUTO[kind], allow_none))
        unknown = set(specs) - set(sig.parameters)
        if unknown:
            raise TypeError(f"checked(): {func.__name__} has no parameter {sorted(unknown)}")

        @functools.wraps(func)
        def wrapper(*args, **kwargs):
            try:
                bound = sig.bind(*args, **kwargs)
            except TypeError as exc:
                raise TypeError(f"{func.__name__}(): {exc}") from None
            arguments = bound.arguments
            for pname, spec, allow_none in plan:
                if pname in arguments:
                    arguments[pname] = spec(arguments[pname], pname, allow_none)
            for pname, value in arguments.items():
                if pname not in specs and not isinstance(value, (int, float, str, np.ndarray, type(None))):
                    _check_objects(value, pname)
            return func(*bound.args, **bound.kwargs)

        return wrapper

    return decorate


