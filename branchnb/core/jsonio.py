"""Strict JSON: what the package writes is standard JSON, what it reads is checked.

Python's :mod:`json` writes ``NaN``/``Infinity`` tokens (not JSON), reads
``1e400`` as ``inf`` and recurses without limit. :func:`dumps_strict` and
:func:`loads_strict` close those holes; every reader/writer of the package
goes through them.
"""

from __future__ import annotations

import json
import math

import numpy as np

__all__ = ["dumps_strict", "loads_strict", "check_depth", "MAX_JSON_DEPTH"]

#: Deepest nesting :func:`loads_strict` accepts (structures nest 3 levels).
MAX_JSON_DEPTH = 64


def _plain(obj, path: str):
    """Convert numpy values to JSON types and reject non-finite numbers, naming the key path."""
    if isinstance(obj, dict):
        out = {}
        for k, v in obj.items():
            if not isinstance(k, str):
                raise TypeError(f"{path} has a non-string key {k!r}")
            out[k] = _plain(v, f"{path}[{k!r}]")
        return out
    if isinstance(obj, (list, tuple)):
        return [_plain(v, f"{path}[{i}]") for i, v in enumerate(obj)]
    if isinstance(obj, np.ndarray):
        return _plain(obj.tolist(), path)
    if isinstance(obj, (bool, np.bool_)):
        return bool(obj)
    if isinstance(obj, (int, np.integer)):
        return int(obj)
    if isinstance(obj, (float, np.floating)):
        if not math.isfinite(float(obj)):
            raise ValueError(f"{path} is {float(obj)}: JSON has no NaN or infinity")
        return float(obj)
    if obj is None or isinstance(obj, str):
        return obj
    raise TypeError(f"{path} has a value of type {type(obj).__name__} that JSON cannot hold")


def dumps_strict(obj, *, name: str = "data", **kwargs) -> str:
    """``json.dumps`` that refuses NaN/inf (naming where it is) and converts numpy values.

    Parameters
    ----------
    obj : object
        Dicts, lists, tuples, str, bool, None, numbers, numpy scalars and
        arrays (turned into lists).
    name : str, optional
        How the message names ``obj`` (the path inside is appended).
    **kwargs
        Passed to :func:`json.dumps` (``indent``, ``sort_keys``, ...).

    Returns
    -------
    str

    Raises
    ------
    ValueError
        If a number is NaN or infinite.

    Examples
    --------
    >>> dumps_strict({"a": np.float32(0.5)})
    '{"a": 0.5}'
    >>> dumps_strict({"a": [1.0, float("nan")]})
    Traceback (most recent call last):
    ...
    ValueError: data['a'][1] is nan: JSON has no NaN or infinity
    """
    return json.dumps(_plain(obj, name), allow_nan=False, **kwargs)


def check_depth(obj, *, name: str = "data", limit: int = MAX_JSON_DEPTH) -> None:
    """Refuse nested lists/dicts deeper than ``limit`` (without recursing, so any depth is safe).

    Parameters
    ----------
    obj : object
        A parsed JSON value (dicts, lists, tuples and scalars).
    name : str, optional
        How the message names ``obj``.
    limit : int, optional
        Deepest nesting allowed; a list or dict at top level is level 1.
        Default ``MAX_JSON_DEPTH`` (64).

    Raises
    ------
    ValueError
        If ``obj`` nests deeper than ``limit``.

    Examples
    --------
    >>> check_depth({"a": [[1]]}, limit=3)
    >>> check_depth([[[[]]]], limit=3)
    Traceback (most recent call last):
    ...
    ValueError: data nests deeper than 3 levels
    """
    stack = [(obj, 1)]
    while stack:
        value, level = stack.pop()
        if isinstance(value, (dict, list, tuple)):
            if level > limit:
                raise ValueError(f"{name} nests deeper than {limit} levels")
            children = value.values() if isinstance(value, dict) else value
            stack.extend((v, level + 1) for v in children if isinstance(v, (dict, list, tuple)))


def _reject_constant(token):
    raise ValueError(f"non-standard JSON number {token}")


def _finite_float(text):
    v = float(text)
    if not math.isfinite(v):
        raise ValueError(f"number {text[:40]} is out of the floating-point range")
    return v


def _unique_keys(pairs):
    out = {}
    for k, v in pairs:
        if k in out:
            raise ValueError(f"duplicate key {k!r} (a later value would silently replace {out[k]!r:.40})")
        out[k] = v
    return out


def loads_strict(text, *, name: str = "text"):
    """Parse standard JSON: no NaN/Infinity tokens, no overflowing numbers, no duplicate keys, bounded nesting.

    Parameters
    ----------
    text : str, bytes or bytearray
        The JSON text (bytes are decoded as UTF-8).
    name : str, optional
        How error messages name ``text``.

    Returns
    -------
    object
        The parsed value, as :func:`json.loads` gives it.

    Raises
    ------
    TypeError
        ``text`` is not a str/bytes.
    ValueError
        Invalid or non-standard JSON (the message names ``name``).

    Examples
    --------
    >>> loads_strict('{"x": [1, 2.5]}')
    {'x': [1, 2.5]}
    >>> loads_strict('[1e400]')
    Traceback (most recent call last):
    ...
    ValueError: text is not valid JSON: number 1e400 is out of the floating-point range
    >>> loads_strict('{"count": 2, "count": 9}')
    Traceback (most recent call last):
    ...
    ValueError: text is not valid JSON: duplicate key 'count' (a later value would silently replace 2)
    """
    if not isinstance(text, (str, bytes, bytearray)):
        raise TypeError(f"{name} must be a JSON string, got {type(text).__name__}")
    # Nesting deeper than the limit is rejected before parsing so the parser cannot recurse away.
    raw = text.decode("utf-8", "replace") if isinstance(text, (bytes, bytearray)) else text
    level = peak = 0
    in_str = esc = False
    for ch in raw:
        if in_str:
            if esc:
                esc = False
            elif ch == "\\":
                esc = True
            elif ch == '"':
                in_str = False
        elif ch == '"':
            in_str = True
        elif ch in "[{":
            level += 1
            if level > peak:
                peak = level
                if peak > MAX_JSON_DEPTH:
                    raise ValueError(f"{name} nests deeper than {MAX_JSON_DEPTH} levels")
        elif ch in "]}":
            level -= 1
    try:
        return json.loads(raw, parse_constant=_reject_constant, parse_float=_finite_float,
                          object_pairs_hook=_unique_keys)
    except (json.JSONDecodeError, ValueError, RecursionError) as exc:
        raise ValueError(f"{name} is not valid JSON: {exc}") from None
