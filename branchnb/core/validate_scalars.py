"""Scalar checks behind :mod:`branchnb.core.validate`: numbers, choices, callbacks and seeds.

Split out of :mod:`branchnb.core.validate` by kind of value; import these names from there.
"""

from __future__ import annotations

import numbers
import operator

import numpy as np

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

