"""Array checks behind :mod:`branchnb.core.validate`: real arrays, colours, shapes, polylines, points, paths.

Split out of :mod:`branchnb.core.validate` by kind of value; import these names from there.
"""

from __future__ import annotations

import numpy as np

from .validate_scalars import COORD_LIMIT, MAX_PIXELS, check_int, check_real


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
