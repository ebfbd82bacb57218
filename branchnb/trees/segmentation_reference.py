"""Crown/trunk segmentation: scores, the hand-labelled reference masks, overlays.

Split out of :mod:`branchnb.trees.segmentation` (which re-exports every name):
:func:`segmentation_iou`, :func:`mean_iou`, the project's reference masks and
scribbles (:func:`load_reference_masks`, :func:`load_reference_scribbles`,
:func:`reference_from_scribbles`), :func:`evaluate_reference` and
:func:`overlay_labels`.

Examples
--------
>>> import numpy as np
>>> lab = np.array([[0, 1], [2, 2]])
>>> segmentation_iou(lab, lab)["trunk"]
1.0
"""

from __future__ import annotations

import json
from pathlib import Path
from typing import TYPE_CHECKING

import cv2
import numpy as np

from .. import data as _data
from ..core.image import as_float_image, composite_over
from ..core.validate import Array, Image, checked
from .segmentation_cues import BACKGROUND, CROWN, IGNORE, LABEL_NAMES, TRUNK  # noqa: F401

if TYPE_CHECKING:
    from .segmentation import SegmentParams

__all__ = [
    "segmentation_iou",
    "mean_iou",
    "load_reference_masks",
    "load_reference_scribbles",
    "reference_from_scribbles",
    "evaluate_reference",
    "overlay_labels",
    "MASKS_DIR",
]

#: Folder of the hand-labelled masks (``data/trees_masks``).
MASKS_DIR = _data.DATA_DIR / "trees_masks"


# ---------------------------------------------------------------------------
# Scores, reference masks, pictures
# ---------------------------------------------------------------------------


@checked(pred=Array(ndim=2), ref=Array(ndim=2))
def segmentation_iou(pred, ref) -> dict[str, float]:
    """Per-class IoU of a predicted label image against a reference.

    Parameters
    ----------
    pred, ref : (H, W) int array_like
        Labels 0 background, 1 crown, 2 trunk; pixels where ``ref`` is 255
        are ignored. A class absent from both gets NaN.

    Returns
    -------
    dict
        ``{"crown": IoU, "trunk": IoU, "mean": mean of the non-NaN ones}``.
        Background is not scored: it is given by the alpha channel.

    Examples
    --------
    >>> import numpy as np
    >>> segmentation_iou(np.array([[1, 2]]), np.array([[1, 1]]))["crown"]
    0.5
    """
    pred = np.asarray(pred)
    ref = np.asarray(ref)
    if pred.shape != ref.shape:
        raise ValueError(f"pred and ref must have the same shape, got {pred.shape} and {ref.shape}")
    valid = ref != IGNORE
    out = {}
    for name, v in LABEL_NAMES.items():
        a = (pred == v) & valid
        b = (ref == v) & valid
        union = (a | b).sum()
        out[name] = float((a & b).sum() / union) if union else float("nan")
    vals = [x for x in out.values() if x == x]
    out["mean"] = float(np.mean(vals)) if vals else float("nan")
    return out


def mean_iou(preds, refs) -> float:
    """Mean over images of the per-image mean class IoU (:func:`segmentation_iou`).

    Parameters
    ----------
    preds : iterable of (H, W) int array_like
        Predicted label images (0 background, 1 crown, 2 trunk).
    refs : iterable of (H, W) int array_like
        The references, paired with ``preds`` in order (255 ignored).

    Returns
    -------
    float
        Mean of the per-image means; images where neither class occurs
        (NaN) are left out.

    Raises
    ------
    ValueError
        If no image has a scored class, or a pair's shapes differ.

    Examples
    --------
    >>> import numpy as np
    >>> ref = np.array([[1, 2]])
    >>> mean_iou([ref, np.array([[1, 1]])], [ref, ref])  # (1 + (0.5 + 0) / 2) / 2
    0.625
    """
    scores = [segmentation_iou(p, r)["mean"] for p, r in zip(preds, refs)]
    scores = [x for x in scores if x == x]
    if not scores:
        raise ValueError("no image with a scored class")
    return float(np.mean(scores))


MASK_SUFFIX = "_mask"


def _mask_path(name: str) -> Path:
    return MASKS_DIR / f"{name}{MASK_SUFFIX}.png"


def _reference_names() -> tuple[str, ...]:
    if not MASKS_DIR.is_dir():
        return ()
    return tuple(sorted(p.stem[: -len(MASK_SUFFIX)] for p in MASKS_DIR.glob(f"*{MASK_SUFFIX}.png")))


def load_reference_masks(names=None) -> dict[str, np.ndarray]:
    """The project's hand-labelled crown/trunk masks of the sample trees.

    They live in ``data/trees_masks/<name>_mask.png`` (8-bit label images).
    Each was made like an app user would make it: run :func:`segment_tree`,
    look at the result, correct it with scribbles, repeat; the scribbles
    are stored in ``data/trees_masks/scribbles.json`` and
    :func:`reference_from_scribbles` rebuilds a mask from them.

    Parameters
    ----------
    names : str or sequence of str, optional
        Sample names (``branchnb.data.names("trees")``); all labelled ones
        if None.

    Returns
    -------
    dict
        name -> (H, W) uint8 label image of the same size as
        ``branchnb.data.load(name)``: 0 background, 1 crown, 2 trunk,
        255 opaque but not part of the tree (ground, grass; ignored).

    Examples
    --------
    >>> masks = load_reference_masks(["tree_rpg_01"])
    >>> sorted(set(masks["tree_rpg_01"].ravel().tolist()))
    [0, 1, 2]
    """
    available = _reference_names()
    if names is None:
        names = available
    elif isinstance(names, str):
        names = [names]
    elif not isinstance(names, (list, tuple)):
        raise TypeError(f"names must be a sample name or a list of them, got {type(names).__name__}")
    out = {}
    for n in names:
        if n not in available:
            raise ValueError(f"names: no reference mask for {n!r}; labelled: {list(available)}")
        raw = cv2.imread(str(_mask_path(n)), cv2.IMREAD_UNCHANGED)
        if raw is None or raw.ndim != 2:  # pragma: no cover - corrupt file
            raise ValueError(f"could not read a label image from {_mask_path(n)}")
        out[n] = raw.astype(np.uint8)
    return out


def _scribble_table() -> dict:
    path = MASKS_DIR / "scribbles.json"
    return json.loads(path.read_text()) if path.is_file() else {}


def load_reference_scribbles(name: str, *, ignore: bool = False) -> list[dict]:
    """The scribbles that corrected the automatic segmentation of ``name``.

    Parameters
    ----------
    name : str
        A sample tree.
    ignore : bool
        Also return the ``"ignore"`` polygons (closed; filled with 255 in
        the reference: ground patches, grass), which are not scribbles.

    Returns
    -------
    list of dict
        ``{"label": "crown" | "trunk", "points": (N, 2) array, "radii":
        (N,) array or None}``, accepted by ``segment_tree(..., scribbles=)``.
        Empty when the automatic result needed no correction.

    Examples
    --------
    >>> load_reference_scribbles("tree_rpg_01")   # its automatic result needed no correction
    []
    """
    table = _scribble_table()
    if name not in table:
        raise ValueError(f"no stored scribbles for {name!r}")
    out = []
    for d in table[name]:
        if d["label"] == "ignore" and not ignore:
            continue
        out.append({"label": d["label"], "points": np.asarray(d["points"], float),
                    "radii": None if d.get("radii") is None else np.asarray(d["radii"], float)})
    return out


@checked(image=Image())
def reference_from_scribbles(name: str, image=None) -> np.ndarray:
    """Rebuild the reference label image of ``name`` from its stored scribbles.

    ``segment_tree(image, scribbles)`` with default parameters (but no
    ground cut, which came later) and ``rng=0``, then the ``"ignore"`` polygons set to 255 on opaque pixels.
    This is how ``data/trees_masks/*_mask.png`` were written; a later change
    of the segmenter can move a few pixels, the stored PNGs are the labels.

    Parameters
    ----------
    name : str
        A sample tree with stored scribbles (``data/trees_masks/scribbles.json``).
    image : (H, W, 4) array_like, optional
        The image to segment; None loads the sample ``name``.

    Returns
    -------
    (H, W) uint8 ndarray
        0 background, 1 crown, 2 trunk, 255 ignored.

    Raises
    ------
    ValueError
        If ``name`` has no stored scribbles.

    Examples
    --------
    >>> labels = reference_from_scribbles("tree_rpg_01")
    >>> labels.shape
    (503, 411)
    """
    from .. import data

    img = data.load(name) if image is None else image
    items = load_reference_scribbles(name, ignore=True)
    scribbles = [d for d in items if d["label"] != "ignore"]
    # The stored masks were made before the ground cut existed.
    from .segmentation import SegmentParams, segment_tree

    seg = segment_tree(img, scribbles=scribbles or None, params=SegmentParams(ground=False), rng=0)
    labels = seg.labels
    opaque = labels > 0
    for d in items:
        if d["label"] == "ignore":
            poly = np.zeros(labels.shape, np.uint8)
            cv2.fillPoly(poly, [np.round(d["points"]).astype(np.int32)], 1)
            labels[(poly > 0) & opaque] = IGNORE
    return labels


def evaluate_reference(names=None, params: SegmentParams | None = None, *,
                       rng=0) -> dict[str, dict[str, float]]:
    """Per-image IoU of the automatic segmenter (no scribbles) on the reference masks.

    The references were made by correcting this segmenter's output, so the
    figure is optimistic; :func:`branchnb.trees.mask_reference.evaluate_independent`
    gives the honest one.

    Parameters
    ----------
    names : str or sequence of str, optional
        Sample names with a reference mask (:func:`load_reference_masks`);
        None evaluates all of them (slow: about a second per image).
    params : SegmentParams, optional
        Segmenter parameters; None uses the defaults.
    rng : int or numpy.random.Generator
        Seed of the training subsample and the forest (default 0).

    Returns
    -------
    dict
        name -> :func:`segmentation_iou` result, plus ``"mIoU"`` -> the mean
        over images under the key ``"mean"``.

    Examples
    --------
    >>> from branchnb.trees.segmentation import SegmentParams
    >>> r = evaluate_reference(["tree_rpg_01"], SegmentParams(work_size=128, n_trees=5))
    >>> r["mIoU"]["mean"] > 0.9
    True
    """
    from .. import data
    from .segmentation import segment_tree

    refs = load_reference_masks(names)
    out: dict[str, dict[str, float]] = {}
    for n, ref in refs.items():
        seg = segment_tree(data.load(n), params=params, rng=rng)
        out[n] = segmentation_iou(seg.labels, ref)
    vals = [v["mean"] for v in out.values() if v["mean"] == v["mean"]]
    out["mIoU"] = {"mean": float(np.mean(vals)) if vals else float("nan")}
    return out


def overlay_labels(image, labels, *, seeds=None, strength: float = 0.55) -> np.ndarray:
    """Tint an RGBA image by labels: crown green, trunk red, ignored blue.

    Parameters
    ----------
    image : (H, W, 4) array_like
        The tree image (RGBA, composited over white; RGB is taken as opaque).
    labels : (H, W) int array_like
        0 background (left as it is), 1 crown, 2 trunk, 255 ignored.
    seeds : (H, W) int array_like, optional
        Drawn as saturated dots (every third pixel) on top.
    strength : float
        Tint opacity.

    Returns
    -------
    (H, W, 3) float32 ndarray
        Labelled pixels: their grey value blended with the label colour.

    Raises
    ------
    ValueError
        If ``labels`` does not match the image's (H, W).

    Examples
    --------
    >>> import numpy as np
    >>> img = np.ones((2, 2, 4), np.float32)
    >>> overlay_labels(img, np.array([[0, 1], [2, 255]]), strength=1.0)[0, 1].tolist()
    [0.10000000149011612, 0.75, 0.10000000149011612]
    """
    img = as_float_image(image, name="image")
    labels = np.asarray(labels)
    if labels.shape != img.shape[:2]:
        raise ValueError(f"labels has shape {labels.shape}, expected {img.shape[:2]}")
    rgb = composite_over(img if img.shape[2] == 4 else np.dstack([img[..., :3], np.ones(img.shape[:2])]),
                         (1.0, 1.0, 1.0))
    grey = rgb.mean(axis=2, keepdims=True)
    out = rgb.copy()
    colours = {CROWN: (0.1, 0.75, 0.1), TRUNK: (0.85, 0.1, 0.1), IGNORE: (0.2, 0.3, 0.9)}
    for v, c in colours.items():
        m = labels == v
        out[m] = (1 - strength) * grey[m] + strength * np.asarray(c, np.float32)
    if seeds is not None:
        seeds = np.asarray(seeds)
        dots = np.zeros(labels.shape, bool)
        dots[::3, ::3] = True
        for v, c in ((CROWN, (0.0, 1.0, 0.0)), (TRUNK, (1.0, 0.0, 0.0))):
            out[(seeds == v) & dots] = c
    return out.astype(np.float32)
