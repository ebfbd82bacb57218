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
import numbers
import operator
import re

import numpy as np

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

#: Largest absolute coordinate (pixels) a point may have. Far beyond any image, small
#: enough that rasterisers can turn coordinates into int indices safely.
COORD_LIMIT = 1e7
#: Largest image (H * W) a function may allocate: 16k x 16k.
MAX_PIXELS = 16384 * 16384
#: Largest number of items (points, variations, branches, ...) one call may make.
MAX_COUNT = 1_000_000
#: Largest number of iterations of an iterative method.
MAX_ITERATIONS = 100_000


def _is_real_scalar(value) -> bool:
    if isinstance(value, (bool, np.bool_)):
        return False
    if isinstance(value, np.ndarray):
        return value.ndim == 0 and (np.issubdtype(value.dtype, np.integer)
                                    or np.issubdtype(value.dtype, np.floating))
    return isinstance(value, numbers.Real)


def _fmt(v) -> str:
    """A number for a message; an int too big for float (or for Python's int-to-text limit) by its size."""
    if isinstance(v, int) and v.bit_length() > 64:
        return f"an int of {v.bit_length()} bits"
    return f"{v:g}"


def _check_range(v, name, lo, hi, low_open=False, high_open=False):
    if lo is not None and (v < lo or (low_open and v == lo)):
        raise ValueError(f"{name} must be {'>' if low_open else '>='} {lo}, got {_fmt(v)}")
    if hi is not None and (v > hi or (high_open and v == hi)):
        raise ValueError(f"{name} must be {'<' if high_open else '<='} {hi}, got {_fmt(v)}")


def check_real(value, name: str, min: float | None = None, max: float | None = None, *,
               low_open: bool = False, high_open: bool = False, allow_none: bool = False,
               allow_inf: bool = False) -> float | None:
    """A finite real number within ``[min, max]``, as a Python float.

    Parameters
    ----------
    value : object
        Any real scalar (Python or numpy int/float; not bool-like strings).
    name : str
        Argument name used in error messages.
    min, max : float, optional
        Bounds (inclusive unless ``low_open`` / ``high_open``); None: unbounded.
    low_open : bool
        Exclude ``min`` itself (``value > min``).
    high_open : bool
        Exclude ``max`` itself (``value < max``).
    allow_none : bool
        Let None through (returned as None).
    allow_inf : bool
        Let +-inf through (bounds still apply).

    Returns
    -------
    float or None

    Raises
    ------
    TypeError
        If ``value`` is not a real number.
    ValueError
        If it is NaN, infinite (unless allowed) or out of bounds.

    Examples
    --------
    >>> check_real(2, "sigma", 0, 10)
    2.0
    >>> check_real(float("nan"), "sigma")
    Traceback (most recent call last):
    ...
    ValueError: sigma must be a finite number, got nan
    """
    if value is None and allow_none:
        return None
    if not _is_real_scalar(value):
        raise TypeError(f"{name} must be a real number, got {type(value).__name__} {value!r:.60}")
    try:
        v = float(value)
    except OverflowError:  # an int beyond float's range
        raise ValueError(f"{name} must be a finite number, got {_fmt(int(value))}") from None
    if v != v or (not allow_inf and not np.isfinite(v)):
        raise ValueError(f"{name} must be a finite number, got {v}")
    _check_range(v, name, min, max, low_open, high_open)
    return v


def brief(value, limit: int = 60) -> str:
    """``repr(value)`` cut to ``limit`` characters, safe for any value (a 5,000-digit int cannot be printed).

    Parameters
    ----------
    value : object
        What to show in an error message.
    limit : int
        Most characters returned.

    Returns
    -------
    str
        The cut repr; ``"an int of N bits"`` for ints beyond 64 bits, and
        ``"a <type>"`` when ``repr`` itself fails.

    Examples
    --------
    >>> brief(10**5000), brief("abc")
    ('an int of 16610 bits', "'abc'")
    """
    if isinstance(value, (int, np.integer)) and not isinstance(value, bool) and int(value).bit_length() > 64:
        return f"an int of {int(value).bit_length()} bits"
    try:
        return repr(value)[:limit]
    except Exception:  # noqa: BLE001 - a repr that fails: the type says enough
        return f"a {type(value).__name__}"


def check_callback(value, name: str = "progress"):
    """``value`` if it is callable or None; otherwise a TypeError naming ``name``.

    Parameters
    ----------
    value : callable or None
        A progress or event callback.
    name : str
        Argument name used in the error message.

    Returns
    -------
    callable or None
        ``value`` unchanged.

    Raises
    ------
    TypeError
        If ``value`` is neither callable nor None.

    Examples
    --------
    >>> check_callback(print) is print, check_callback(None)
    (True, None)
    """
    if value is not None and not callable(value):
        raise TypeError(f"{name} must be a callable or None, got {type(value).__name__}")
    return value


def check_int(value, name: str, min: int | None = None, max: int | None = None, *,
              allow_none: bool = False) -> int | None:
    """An integer (an integral float is accepted) within ``[min, max]``, as a Python int.

    Parameters
    ----------
    value : object
        A Python or numpy int, or a float with an integral value; bools are
        refused.
    name : str
        Argument name used in error messages.
    min, max : int, optional
        Inclusive bounds; None: unbounded.
    allow_none : bool
        Let None through (returned as None).

    Returns
    -------
    int or None

    Raises
    ------
    TypeError
        If ``value`` is not an integer (or integral float).
    ValueError
        If it is out of bounds or does not fit in 64 bits.

    Examples
    --------
    >>> check_int(3.0, "n", 1)
    3
    >>> check_int("3", "n")
    Traceback (most recent call last):
    ...
    TypeError: n must be an int, got str '3'
    """
    if value is None and allow_none:
        return None
    if isinstance(value, (bool, np.bool_)) or not _is_real_scalar(value):
        raise TypeError(f"{name} must be an int, got {type(value).__name__} {value!r:.60}")
    try:
        v = operator.index(value)
    except TypeError:
        f = float(value)
        if not np.isfinite(f) or not f.is_integer():
            raise TypeError(f"{name} must be an int, got {f}") from None
        v = int(f)
    if int(v).bit_length() > 64:  # no count, index or size is this big; and such ints break messages and C code
        raise ValueError(f"{name} must fit in 64 bits, got {_fmt(int(v))}")
    _check_range(v, name, min, max)
    return int(v)


def check_bool(value, name: str) -> bool:
    """A bool (numpy bools accepted).

    Parameters
    ----------
    value : object
        ``True``/``False`` or a numpy bool; 0/1 and strings are refused.
    name : str
        Argument name used in the error message.

    Returns
    -------
    bool

    Raises
    ------
    TypeError
        If ``value`` is not a bool.

    Examples
    --------
    >>> check_bool(np.True_, "closed")
    True
    """
    if not isinstance(value, (bool, np.bool_)):
        raise TypeError(f"{name} must be a bool, got {type(value).__name__} {value!r:.60}")
    return bool(value)


def check_choice(value, name: str, options) -> object:
    """One of ``options`` (compared with ``==``; strings stay case-sensitive).

    Parameters
    ----------
    value : object
        The value given.
    name : str
        Argument name used in the error message.
    options : iterable
        The allowed values; the type must match too (``1`` is not ``1.0``
        or ``True``).

    Returns
    -------
    object
        ``value`` unchanged.

    Raises
    ------
    ValueError
        If ``value`` is not among ``options``.

    Examples
    --------
    >>> check_choice("emd", "metric", ("l1", "emd"))
    'emd'
    """
    options = tuple(options)
    try:
        ok = any(value == o and type(value) is type(o) for o in options)
    except Exception:  # an array compared with a string, ...
        ok = False
    if not ok:
        raise ValueError(f"{name} must be one of {list(options)}, got {value!r:.60}")
    return value


def check_rng(rng, name: str = "rng"):
    """Check that ``rng`` is None, a non-negative int seed or a Generator; return it unchanged.

    Use :func:`branchnb.core.random.as_rng` to turn it into a Generator.

    Parameters
    ----------
    rng : {numpy.random.Generator, int, None}
        The ``rng`` argument of a random function.
    name : str
        Argument name used in error messages.

    Returns
    -------
    numpy.random.Generator, int or None
        ``rng`` unchanged.

    Raises
    ------
    TypeError
        If ``rng`` is of another type (bools included).
    ValueError
        If the seed is negative or 2**128 or more.

    Examples
    --------
    >>> check_rng(3)
    3
    """
    if rng is None or isinstance(rng, np.random.Generator):
        return rng
    if isinstance(rng, (bool, np.bool_)) or not isinstance(rng, (numbers.Integral, np.integer)):
        raise TypeError(f"{name} must be an int seed or a numpy.random.Generator, got {type(rng).__name__}")
    if rng < 0:
        raise ValueError(f"{name} seed must be non-negative, got {_fmt(int(rng))}")
    if int(rng).bit_length() > 128:
        raise ValueError(f"{name} seed must be below 2**128, got {_fmt(int(rng))}")
    return rng


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


def real_array(values, name: str, *, ndim: int | tuple[int, ...] | None = None, dtype=np.float64,
               finite: bool = True, allow_empty: bool = False, min: float | None = None,
               max: float | None = None, allow_inf: bool = False) -> np.ndarray:
    """A real (non-complex, numeric) array as ``dtype``.

    Parameters
    ----------
    values : array_like
        Numbers of any shape (bool allowed; strings, objects and complex
        numbers are refused).
    name : str
        Argument name used in error messages.
    ndim : int or tuple of int, optional
        Allowed numbers of dimensions (any by default).
    dtype : numpy dtype
        Result dtype (float64 by default). An integer dtype requires
        integral, finite values within its range.
    finite : bool
        Reject NaN and inf.
    allow_empty : bool
        Accept zero-size arrays.
    min, max : float, optional
        Inclusive value bounds (NaN ignored).
    allow_inf : bool
        With ``finite``, reject only NaN (inf may mean "wall" or "unreached").

    Returns
    -------
    ndarray
        A new array of ``dtype`` (the input is never modified).

    Raises
    ------
    TypeError
        Not numbers, complex, or non-integral values for an integer dtype.
    ValueError
        Wrong dimensions, empty, NaN/inf, or out of bounds.

    Examples
    --------
    >>> real_array([1, 2], "weights").dtype
    dtype('float64')
    >>> real_array([1j], "weights")
    Traceback (most recent call last):
    ...
    TypeError: weights must be real-valued, got dtype complex128
    """
    if isinstance(values, (str, bytes)):
        raise TypeError(f"{name} must be an array of numbers, got {type(values).__name__}")
    try:
        arr = np.asarray(values)
    except (TypeError, ValueError) as exc:
        raise TypeError(f"{name} must be an array of numbers ({exc})") from None
    if np.iscomplexobj(arr):
        raise TypeError(f"{name} must be real-valued, got dtype {arr.dtype}")
    if arr.dtype == object or not (np.issubdtype(arr.dtype, np.number) or arr.dtype == bool):
        raise TypeError(f"{name} must be an array of numbers, got dtype {arr.dtype}")
    if ndim is not None:
        allowed = (ndim,) if isinstance(ndim, int) else tuple(ndim)
        if arr.ndim not in allowed:
            raise ValueError(f"{name} must have {' or '.join(map(str, allowed))} dimension(s), got shape {arr.shape}")
    if arr.size == 0 and not allow_empty:
        raise ValueError(f"{name} is empty (shape {arr.shape})")
    if np.issubdtype(np.dtype(dtype), np.integer) and arr.dtype.kind == "f":
        if not np.all(np.isfinite(arr)) or not np.all(arr == np.round(arr)):
            raise TypeError(f"{name} must hold integers, got non-integral or non-finite values")
        if arr.size and np.abs(arr).max() > np.iinfo(dtype).max:
            raise ValueError(f"{name} has values beyond the {np.dtype(dtype)} range")
    arr = arr.astype(dtype, copy=True)
    if finite and allow_inf and arr.dtype.kind == "f" and np.isnan(arr).any():
        raise ValueError(f"{name} contains NaN values")
    if finite and not allow_inf and not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or infinite values")
    if arr.size and min is not None and float(np.nanmin(arr)) < min:
        raise ValueError(f"{name} must be >= {min}, got a minimum of {float(np.nanmin(arr)):g}")
    if arr.size and max is not None and float(np.nanmax(arr)) > max:
        raise ValueError(f"{name} must be <= {max}, got a maximum of {float(np.nanmax(arr)):g}")
    return arr


def as_colour(colour, name: str = "color", *, channels=(3, 4)) -> np.ndarray:
    """One colour: a float32 vector of 1, 3 or 4 components in [0, 1].

    Parameters
    ----------
    colour : array_like
        The components, in [0, 1].
    name : str
        Argument name used in error messages.
    channels : tuple of int
        Allowed numbers of components (RGB or RGBA by default).

    Returns
    -------
    (C,) float32 ndarray

    Raises
    ------
    TypeError
        If ``colour`` is not numbers.
    ValueError
        Wrong number of components, NaN/inf, or a component outside [0, 1].

    Examples
    --------
    >>> as_colour((1, 0.5, 0)).tolist()
    [1.0, 0.5, 0.0]
    >>> as_colour((2, 0, 0))
    Traceback (most recent call last):
    ...
    ValueError: color components must lie in [0, 1], got [2.0, 0.0, 0.0]
    """
    c = real_array(colour, name, ndim=1, dtype=np.float32, finite=False)
    if c.shape[0] not in channels:
        raise ValueError(f"{name} must have {' or '.join(map(str, channels))} components, got {c.shape[0]}")
    if not np.all(np.isfinite(c)):
        raise ValueError(f"{name} contains NaN or infinite values")
    if c.min() < 0 or c.max() > 1:
        raise ValueError(f"{name} components must lie in [0, 1], got {np.round(c, 4).tolist()}")
    return c


def as_colours(colours, n: int, name: str = "colors", *, channels=(1, 3, 4)) -> np.ndarray:
    """One colour for all, or one per item: an ``(n, C)`` float32 array in [0, 1].

    Parameters
    ----------
    colours : array_like
        One colour ``(C,)`` (repeated ``n`` times) or ``(n, C)``, in [0, 1].
    n : int
        Number of items (0 is treated as 1).
    name : str
        Argument name used in error messages.
    channels : tuple of int
        Allowed numbers of components ``C`` (gray, RGB or RGBA by default).

    Returns
    -------
    (max(n, 1), C) float32 ndarray

    Raises
    ------
    ValueError
        Wrong shape, NaN/inf, or a component outside [0, 1].

    Examples
    --------
    >>> as_colours((1, 0, 0), 2).tolist()
    [[1.0, 0.0, 0.0], [1.0, 0.0, 0.0]]
    """
    c = real_array(colours, name, ndim=(1, 2), dtype=np.float32, finite=False)
    if c.ndim == 1:
        c = np.broadcast_to(c, (max(n, 1), c.shape[0]))
    if c.shape[1] not in channels or c.shape[0] != max(n, 1):
        raise ValueError(f"{name} must be one colour or one colour per item ({n}), got shape {c.shape}")
    if not np.all(np.isfinite(c)):
        raise ValueError(f"{name} contains NaN or infinite values")
    if c.min() < 0 or c.max() > 1:
        raise ValueError(f"{name} components must lie in [0, 1]")
    return np.ascontiguousarray(c)


def check_shape(shape, name: str = "shape", *, max_pixels: int = MAX_PIXELS) -> tuple[int, int]:
    """A positive ``(H, W)`` (extra trailing entries ignored) no larger than ``max_pixels``.

    Parameters
    ----------
    shape : sequence of int
        ``(H, W)`` or an array shape ``(H, W, C)``; integral floats accepted.
    name : str
        Argument name used in error messages.
    max_pixels : int
        Largest ``H * W`` allowed (:data:`MAX_PIXELS` by default).

    Returns
    -------
    (int, int)

    Raises
    ------
    TypeError
        If ``shape`` is not a sequence of at least two integers.
    ValueError
        If a side is < 1 or the area exceeds ``max_pixels``.

    Examples
    --------
    >>> check_shape((4.0, 5, 3))
    (4, 5)
    """
    if isinstance(shape, (str, bytes)) or not hasattr(shape, "__len__") or len(shape) < 2:
        raise TypeError(f"{name} must be an (H, W) pair, got {shape!r:.60}")
    h = check_int(shape[0], f"{name}[0]", 1)
    w = check_int(shape[1], f"{name}[1]", 1)
    if h * w > max_pixels:
        raise ValueError(f"{name} {h} x {w} is larger than the limit of {max_pixels} pixels")
    return h, w


def as_polylines(polylines, name: str = "polylines", *, min_points: int = 0) -> list[np.ndarray]:
    """A list of ``(N_i, 2)`` float64 arrays with finite coordinates within :data:`COORD_LIMIT`.

    A single ``(N, 2)`` array counts as one polyline.

    Parameters
    ----------
    polylines : sequence of (N_i, 2) array_like
        Vertices (x, y) in pixels; an empty entry becomes a ``(0, 2)`` array.
    name : str
        Argument name used in error messages (``polylines[3]``).
    min_points : int
        Fewest vertices each polyline must have.

    Returns
    -------
    list of (N_i, 2) float64 ndarray
        New arrays.

    Raises
    ------
    TypeError
        If ``polylines`` is not a sequence or a polyline is not numbers.
    ValueError
        Wrong shape, too few points, or coordinates that are NaN/inf or
        beyond :data:`COORD_LIMIT`.

    Examples
    --------
    >>> [p.shape for p in as_polylines([[(0, 0), (1, 1)], []])]
    [(2, 2), (0, 2)]
    """
    if isinstance(polylines, (str, bytes)) or not hasattr(polylines, "__len__"):
        raise TypeError(f"{name} must be a sequence of (N, 2) point arrays, got {type(polylines).__name__}")
    if isinstance(polylines, np.ndarray) and polylines.ndim == 2:
        polylines = [polylines]
    out = []
    for i, pl in enumerate(polylines):
        p = real_array(pl, f"{name}[{i}]", ndim=(1, 2), allow_empty=True, finite=False)
        if p.ndim == 1 and p.size == 0:
            p = p.reshape(0, 2)
        if p.ndim != 2 or p.shape[1] != 2:
            raise ValueError(f"{name}[{i}] must have shape (N, 2), got {p.shape}")
        if len(p) < min_points:
            raise ValueError(f"{name}[{i}] needs at least {min_points} point(s), got {len(p)}")
        check_finite(p, f"{name}[{i}]", limit=COORD_LIMIT)
        out.append(p)
    return out


def check_finite(values, name: str, *, limit: float | None = None) -> np.ndarray:
    """Raise unless every value is finite (and ``|value| <= limit``); return the array.

    Writers call this on what they are about to write so no file holds NaN.

    Parameters
    ----------
    values : array_like
        Numbers of any shape.
    name : str
        Argument name used in error messages.
    limit : float, optional
        Largest magnitude allowed; None: any finite value.

    Returns
    -------
    ndarray
        ``np.asarray(values)`` (not copied).

    Raises
    ------
    TypeError
        If ``values`` is complex.
    ValueError
        If a value is NaN/inf or beyond ``limit``.

    Examples
    --------
    >>> check_finite([1.0, 2.0], "x", limit=10).tolist()
    [1.0, 2.0]
    """
    arr = np.asarray(values)
    if np.iscomplexobj(arr):
        raise TypeError(f"{name} must be real-valued, got dtype {arr.dtype}")
    if arr.size and not np.all(np.isfinite(arr)):
        raise ValueError(f"{name} contains NaN or infinite values")
    if limit is not None and arr.size and float(np.abs(arr).max()) > limit:
        raise ValueError(f"{name} has a value of magnitude {float(np.abs(arr).max()):g}, beyond the limit {limit:g}")
    return arr


def as_point(point, name: str = "point") -> np.ndarray:
    """One finite ``(x, y)`` point within :data:`COORD_LIMIT`, as a float64 array of 2.

    Parameters
    ----------
    point : array_like
        ``(x, y)`` in pixels.
    name : str
        Argument name used in error messages.

    Returns
    -------
    (2,) float64 ndarray

    Raises
    ------
    TypeError, ValueError
        If ``point`` is not two finite real numbers within the limit.

    Examples
    --------
    >>> as_point((3, 4)).tolist()
    [3.0, 4.0]
    """
    p = real_array(point, name, ndim=1)
    if p.shape != (2,):
        raise ValueError(f"{name} must be an (x, y) pair, got {p.shape[0]} value(s)")
    return check_finite(p, name, limit=COORD_LIMIT)


def check_range_pair(value, name: str = "range", *, allow_none: bool = True, allow_equal: bool = True):
    """A finite ``(lo, hi)`` with ``lo <= hi`` (or ``lo < hi``) as two floats, or None.

    Parameters
    ----------
    value : (float, float) or None
        The pair given.
    name : str
        Argument name used in error messages.
    allow_none : bool
        Let None through (returned as None).
    allow_equal : bool
        Accept ``lo == hi``; False requires ``lo < hi``.

    Returns
    -------
    (float, float) or None

    Raises
    ------
    TypeError
        If ``value`` is not a pair of real numbers.
    ValueError
        If a bound is NaN/inf or ``hi < lo`` (or equal, when not allowed).

    Examples
    --------
    >>> check_range_pair((0, 1))
    (0.0, 1.0)
    """
    if value is None and allow_none:
        return None
    if isinstance(value, (str, bytes)) or not hasattr(value, "__len__") or len(value) != 2:
        raise TypeError(f"{name} must be a (lo, hi) pair, got {value!r:.60}")
    lo = check_real(value[0], f"{name}[0]")
    hi = check_real(value[1], f"{name}[1]")
    if hi < lo or (hi == lo and not allow_equal):
        raise ValueError(f"{name} must have lo {'<=' if allow_equal else '<'} hi, got ({lo:g}, {hi:g})")
    return lo, hi


def check_output_path(path, name: str = "path", *, suffixes: tuple[str, ...] | None = None):
    """A path a file can be written to: not empty, not a directory, in an existing folder.

    Parameters
    ----------
    path : str or pathlib.Path
        The file to write (it may exist; it is not touched here).
    name : str
        Argument name used in error messages.
    suffixes : tuple of str, optional
        Allowed lower-case suffixes with the dot (``(".png", ".jpg")``);
        the file name's suffix is compared case-insensitively. Any by default.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    TypeError
        If ``path`` is not a non-empty str or Path.
    ValueError
        If it is a directory, its folder does not exist, or the suffix is
        not allowed.

    Examples
    --------
    >>> import tempfile, os
    >>> check_output_path(os.path.join(tempfile.mkdtemp(), "a.PNG"), suffixes=(".png",)).name
    'a.PNG'
    """
    from pathlib import Path

    if not isinstance(path, (str, Path)) or (isinstance(path, str) and not path.strip()):
        raise TypeError(f"{name} must be a non-empty file path, got {path!r:.60}")
    p = Path(path)
    if p.is_dir():
        raise ValueError(f"{name} {str(p)!r} is a directory, not a file")
    if not p.parent.is_dir():
        raise ValueError(f"{name}: folder {str(p.parent)!r} does not exist")
    if suffixes and p.suffix.lower() not in suffixes:
        raise ValueError(f"{name} must end with {' or '.join(suffixes)}, got {p.name!r}")
    return p
