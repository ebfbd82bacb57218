"""Random-number conventions: every random function takes ``rng``."""

from __future__ import annotations

import numpy as np

__all__ = ["as_rng", "RngLike"]

RngLike = "int | numpy.random.Generator | None"


def as_rng(rng: int | np.random.Generator | None = None, *, name: str = "rng") -> np.random.Generator:
    """Turn ``rng`` into a :class:`numpy.random.Generator`, as scikit-image does.

    Parameters
    ----------
    rng : {numpy.random.Generator, int, None}
        A generator is used as is (shared state); an int seeds a new one;
        None draws fresh OS entropy (not reproducible).

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
        raise ValueError(f"{name} seed must be non-negative, got {rng}")
    return np.random.default_rng(int(rng))
