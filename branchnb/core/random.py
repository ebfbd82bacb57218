"""Random-number conventions: every random function takes ``rng``."""

from __future__ import annotations

import numpy as np

__all__ = ["as_rng", "as_seed", "RngLike"]

RngLike = "int | numpy.random.Generator | None"


def as_rng(rng: int | np.random.Generator | None = None, *, name: str = "rng") -> np.random.Generator:
    """Turn ``rng`` into a :class:`numpy.random.Generator`, as scikit-image does.

    Parameters
    ----------
    rng : {numpy.random.Generator, int, None}
        A generator is used as is (shared state); an int seeds a new one;
        None draws fresh OS entropy (not reproducible).
    name : str, optional
        How error messages name the argument.

    Returns
    -------
    numpy.random.Generator

    Raises
    ------
    TypeError
        If ``rng`` is neither None, an int nor a Generator (bool included).
    ValueError
        If the seed is negative or 2**128 or more.

    Examples
    --------
    >>> int(as_rng(0).integers(10)) == int(as_rng(0).integers(10))
    True
    """
    if isinstance(rng, np.random.Generator):
        return rng
    if rng is None:
        return np.random.default_rng()
    if isinstance(rng, (bool, np.bool_)) or not isinstance(rng, (int, np.integer)):
        raise TypeError(f"{name} must be an int seed or a numpy.random.Generator, got {type(rng).__name__}")
    if rng < 0:
        raise ValueError(f"{name} seed must be non-negative, got {rng if rng > -10**12 else 'a huge negative int'}")
    if int(rng).bit_length() > 128:
        # a 5,000-digit seed would reach Python's int-to-text limit in some message or file far from here
        raise ValueError(f"{name} seed must be below 2**128, got an int of {int(rng).bit_length()} bits")
    return np.random.default_rng(int(rng))


def as_seed(rng: int | np.random.Generator | None = None, *, name: str = "rng") -> int:
    """An int seed from ``rng``, for functions that cache their stages by seed.

    An int is returned as is; a Generator gives one draw from its stream (so
    passing the same generator twice gives two different, reproducible
    seeds, as for :func:`as_rng`); None draws fresh OS entropy.

    Parameters
    ----------
    rng : {numpy.random.Generator, int, None}
        As for :func:`as_rng`.
    name : str, optional
        How error messages name the argument.

    Returns
    -------
    int
        A seed in ``[0, 2**63 - 1)`` for a Generator or None, else ``rng``.

    Raises
    ------
    TypeError, ValueError
        As :func:`as_rng`.

    Examples
    --------
    >>> as_seed(7), as_seed(np.random.default_rng(0)) == as_seed(np.random.default_rng(0))
    (7, True)
    """
    if isinstance(rng, (int, np.integer)) and not isinstance(rng, (bool, np.bool_)):
        as_rng(rng, name=name)  # same checks and messages
        return int(rng)
    return int(as_rng(rng, name=name).integers(0, 2**63 - 1))
