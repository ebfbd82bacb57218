"""Sample images: the real example images in ``data/`` plus scikit-image's bundled ones.

>>> from branchnb import data
>>> img = data.load("tree_rpg_01")     # RGBA float32 in [0, 1]
>>> "retina_fundus" in data.names()
True

Licences and credit lines are in ``data/README.md``.
"""

from __future__ import annotations

from functools import lru_cache
from importlib import resources
from pathlib import Path

import numpy as np

from .core.image import as_float_image
from .core.io import imread

__all__ = ["names", "load", "path", "DATA_DIR"]


def _data_dir() -> Path:
    """The sample folder: ``branchnb/_data`` inside an installed wheel, else the checkout's ``data/``.

    The build maps the project's top-level ``data/`` folder into the package
    as ``branchnb/_data`` (see ``pyproject.toml``), so an installed wheel
    carries its samples; an editable install or a plain checkout on
    ``sys.path`` reads ``data/`` beside the package.
    """
    packaged = resources.files(__package__).joinpath("_data")
    if packaged.is_dir():
        # a wheel is always installed unpacked, so the Traversable is a real folder
        return Path(str(packaged))
    return Path(__file__).resolve().parent.parent / "data"


#: Folder holding the sample files (``data/`` of the project, packaged as ``branchnb/_data``).
DATA_DIR = _data_dir()

_SKIMAGE = ("astronaut", "camera", "chelsea", "coffee", "retina", "horse")
_SUFFIXES = (".png", ".jpg", ".jpeg")


@lru_cache(maxsize=1)
def _files() -> dict[str, Path]:
    if not DATA_DIR.is_dir():
        return {}
    return {
        p.stem: p
        for p in sorted(DATA_DIR.rglob("*"))
        if p.suffix.lower() in _SUFFIXES
    }


def names(category: str | None = None) -> list[str]:
    """Names accepted by :func:`load`, sorted.

    Parameters
    ----------
    category : str, optional
        A folder of ``data/`` (``branching``, ``trees``, ``skeleton_objects``,
        ``leaves``) or ``skimage``; all names if None.

    Returns
    -------
    list of str

    Raises
    ------
    ValueError
        If ``category`` is not a folder of ``data/`` nor ``"skimage"``.

    Examples
    --------
    >>> names("skimage")[:2]
    ['astronaut', 'camera']
    """
    files = _files()
    if category is None:
        return sorted(set(files) | set(_SKIMAGE))
    if category == "skimage":
        return list(_SKIMAGE)
    found = sorted(n for n, p in files.items() if p.parent.name == category)
    if not found:
        cats = sorted({p.parent.name for p in files.values()} | {"skimage"})
        raise ValueError(f"unknown category {category!r}; choose one of {cats}")
    return found


def path(name: str) -> Path:
    """File path of a sample stored in ``data/``.

    Parameters
    ----------
    name : str
        A sample name from :func:`names` (the file's stem, e.g.
        ``"tree_rpg_01"``); scikit-image's bundled images have no file here.

    Returns
    -------
    pathlib.Path

    Raises
    ------
    ValueError
        If no file of that name is in ``data/``.

    Examples
    --------
    >>> path("tree_rpg_01").suffix
    '.png'
    """
    files = _files()
    if name not in files:
        raise ValueError(f"unknown sample name {name!r}; see branchnb.data.names()")
    return files[name]


def load(name: str) -> np.ndarray:
    """Load a sample image as float32 in [0, 1], (H, W, C).

    RGBA files keep their alpha (C = 4), photos are RGB (C = 3), grey
    files and masks have C = 1.

    Parameters
    ----------
    name : str
        A name from :func:`names`: a file of ``data/`` or one of
        scikit-image's samples (``"camera"``, ``"retina"``, ...).

    Returns
    -------
    (H, W, C) float32 ndarray
        A new array in [0, 1].

    Raises
    ------
    TypeError
        If ``name`` is not a str.
    ValueError
        Unknown name (the message lists where to look).

    Examples
    --------
    >>> load("camera").shape
    (512, 512, 1)
    """
    if not isinstance(name, str):
        raise TypeError(f"name must be a str, got {type(name).__name__}")
    if name in _SKIMAGE and name not in _files():
        import skimage.data

        return as_float_image(getattr(skimage.data, name)(), name=name)
    return imread(path(name))
