"""Open any technique's app by name, on a sample or on the user's own images.

This is what ``branchnb app NAME [IMAGE ...]`` runs inside its Voilà
page, and what a notebook can call to get an app with sensible inputs in
one line.

Examples
--------
>>> import numpy as np
>>> app = open_app("dendrite", [np.ones((40, 50, 3), np.float32)])
>>> type(app).__name__
'DendriteApp'
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path

import cv2
import numpy as np

from ..core.image import as_float_image

__all__ = ["APPS", "open_app", "read_images"]

#: The apps ``open_app`` knows (``branchnb app --help`` says what IMAGE means for each).
APPS = ("branching", "dendrite", "trees", "strokes", "leaves")

#: User images larger than this (long side, pixels) are shrunk for the branching app: its
#: synthesis is interactive at this size.
BRANCHING_MAX = 512


def read_images(paths: Sequence) -> list[tuple[str, np.ndarray]]:
    """Read image files as ``(name, float32 image)``; a clear ``ValueError`` names a bad path.

    Parameters
    ----------
    paths : sequence of str or os.PathLike
        Image files (PNG, JPEG, TIFF, ...).

    Returns
    -------
    list of (str, ndarray)
        Each file's stem and its image, float32 in [0, 1], ``(H, W, C)``.

    Raises
    ------
    ValueError
        If a path is not a file or cannot be decoded.

    Examples
    --------
    >>> from branchnb import data
    >>> [(name, image.shape) for name, image in read_images([data.path("tree_rpg_01")])]
    [('tree_rpg_01', (503, 411, 4))]
    """
    from ..core.io import imread

    out = []
    for p in paths:
        path = Path(p)
        if not path.is_file():
            raise ValueError(f"IMAGE {str(path)!r} is not a file")
        out.append((path.stem, imread(path)))
    return out


def _shrink(img: np.ndarray, long_side: int) -> np.ndarray:
    h, w = img.shape[:2]
    s = long_side / max(h, w)
    if s >= 1:
        return img
    return cv2.resize(img, (max(1, round(w * s)), max(1, round(h * s))), interpolation=cv2.INTER_AREA)


def _named(images) -> list[tuple[str, np.ndarray]]:
    out = []
    for i, item in enumerate(images):
        if isinstance(item, (str, Path)):
            out.extend(read_images([item]))
        elif isinstance(item, tuple) and len(item) == 2 and isinstance(item[0], str):
            out.append((item[0], as_float_image(item[1], name=f"images[{i}]")))
        else:
            out.append((f"image_{i}", as_float_image(item, name=f"images[{i}]")))
    return out


def open_app(name: str, images=None, *, page: bool = False, **kwargs):
    """The app ``name`` (one of :data:`APPS`) on ``images``, or on a sample when None.

    Parameters
    ----------
    name : str
        ``branching``, ``dendrite``, ``trees``, ``strokes`` or ``leaves``.
    images : sequence, optional
        Paths, arrays, or ``(name, array)`` pairs: the example image
        (branching), the picture (dendrite), the source object (strokes),
        or the exemplars (trees, leaves: two or more).
    page : bool
        The app is a web page (``branchnb app``): "save" offers downloads
        only (see :meth:`~branchnb.widgets.files.FileBar.use_page_mode`).
    **kwargs
        Passed on to the app's constructor.

    Returns
    -------
    BranchingApp, DendriteApp, TreeVariationsApp, StrokeEditApp or LeafApp
        The app; display it as the last expression of a notebook cell.

    Raises
    ------
    ValueError
        An unknown ``name``, an unreadable image, or too few exemplars.

    Examples
    --------
    >>> app = open_app("dendrite")                         # doctest: +SKIP
    >>> app = open_app("leaves", ["leaf1.png", "leaf2.png"])  # doctest: +SKIP
    """
    if name not in APPS:
        raise ValueError(f"name must be one of {list(APPS)}, got {name!r}")
    app = _build(name, images, kwargs)
    if page and app.shell.files is not None:
        app.shell.files.use_page_mode()
    return app


def _build(name: str, images, kwargs):
    if images is not None and (isinstance(images, (str, Path, np.ndarray)) or not hasattr(images, "__iter__")):
        images = [images]
    named = _named(images) if images is not None else []
    if images is not None and not named:
        raise ValueError("images is empty: give at least one image, or None for the sample")
    from .. import data

    if name == "branching":
        from ..branching import extract_structure
        from .branching import BranchingApp

        img = _shrink(named[0][1], BRANCHING_MAX) if named else \
            cv2.resize(data.load("retina_fundus"), (360, 360), interpolation=cv2.INTER_AREA)
        try:
            structure = extract_structure(img)
        except ValueError:
            structure = None  # nothing branch-like found: the user draws the branches
        if structure is not None and not structure.branches:
            structure = None
        return BranchingApp(img, structure=structure, **kwargs)
    if name == "dendrite":
        from .dendrite import DendriteApp

        return DendriteApp(named[0][1] if named else data.load("camera"), **kwargs)
    if name == "strokes":
        from .strokes import StrokeEditApp

        img = named[0][1] if named else _shrink(data.load("lizard"), 400)
        h, w = img.shape[:2]
        kwargs.setdefault("target_shape", (h, w))
        kwargs.setdefault("max_display", 400)
        return StrokeEditApp(img, **kwargs)
    if name == "trees":
        from ..trees.variations import TreeLibrary
        from .trees import TreeVariationsApp

        if named:
            if len(named) < 2:
                raise ValueError("trees: give two or more tree images (RGBA cut-outs) to mix")
            lib = TreeLibrary(size=512)
            for n, img in named:
                lib.add(img, n)
        else:
            lib = TreeLibrary.from_data(["tree_rpg_01", "tree_rpg_03", "tree_rpg_06", "tree_rpg_08"], size=256)
        return TreeVariationsApp(lib, **kwargs)
    from ..leaves import Layer, LayerSet, leaf_family, simulate_scribbles
    from .leaves import LeafApp

    if named:
        if len(named) < 2:
            raise ValueError("leaves: give two or more leaf images of one kind")
        return LeafApp([img for _, img in named], **kwargs)
    fam = leaf_family(3, size=224, rng=4)
    layers = LayerSet([Layer("veins", "#d62728", 0), Layer("spots", "#1f77b4", 1)])
    for layer, n, length in (("veins", 10, 20), ("spots", 8, 8)):
        for s in simulate_scribbles(fam[0].layers[layer], n, length=length, rng=2):
            layers.add_scribble(layer, s.points)
    kwargs.setdefault("layers", layers)
    return LeafApp(fam, **kwargs)
