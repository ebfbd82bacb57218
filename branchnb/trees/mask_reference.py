"""Crown/trunk reference masks made independently of the segmenter.

``data/trees_masks_independent/polygons.json`` holds, for a few real RGBA
exemplars, a *trunk* polygon (and optional *ignore* polygons for ground)
placed by eye on grid renders of the image, never on a segmentation (the
file's ``note`` says how). A reference label image is the alpha silhouette
split by those polygons: 0 background, 1 crown, 2 trunk, 255 ignored.
Unlike ``data/trees_masks`` (corrected from this segmenter's own output),
the mean IoU against these is an honest figure; the paper's DeepLabv3+
reached 0.672 on its photographs.
"""

from __future__ import annotations

import json

import cv2
import numpy as np

from .. import data as _data

__all__ = ["POLYGONS_FILE", "load_polygons", "independent_reference", "load_independent_masks",
           "evaluate_independent"]

#: The hand-placed polygons.
POLYGONS_FILE = _data.DATA_DIR / "trees_masks_independent" / "polygons.json"


def load_polygons() -> dict[str, dict]:
    """name -> {"trunk": (K, 2) float array, "ignore": list of (K, 2) arrays}.

    Examples
    --------
    >>> sorted(load_polygons()["plain_tree"])
    ['ignore', 'trunk']
    """
    table = json.loads(POLYGONS_FILE.read_text())["masks"]
    return {n: {"trunk": np.asarray(d["trunk"], float),
                "ignore": [np.asarray(p, float) for p in d.get("ignore", [])]}
            for n, d in table.items()}


def _fill(polygon: np.ndarray, shape: tuple[int, int]) -> np.ndarray:
    m = np.zeros(shape, np.uint8)
    cv2.fillPoly(m, [np.round(polygon).astype(np.int32)], 1)
    return m > 0


def independent_reference(alpha, polygons: dict) -> np.ndarray:
    """Label image (0 / 1 crown / 2 trunk / 255 ignore) from a silhouette and its polygons.

    Parameters
    ----------
    alpha : (H, W) array_like
        Opacity of the source image, in [0, 1]; pixels >= 0.5 are the tree.
    polygons : dict
        ``{"trunk": (K, 2) array, "ignore": list of (K, 2) arrays}`` in
        source pixels (x, y), as :func:`load_polygons` gives them. Opaque
        pixels inside ``trunk`` become 2 (trunk wins over ignore), inside an
        ``ignore`` polygon 255, other opaque pixels 1.

    Returns
    -------
    (H, W) uint8 ndarray
        0 background, 1 crown, 2 trunk, 255 ignored (left out of the IoU).

    Examples
    --------
    >>> import numpy as np
    >>> a = np.zeros((10, 6)); a[1:9, 1:5] = 1
    >>> lab = independent_reference(a, {"trunk": np.array([[0, 6], [5, 6], [5, 9], [0, 9]]), "ignore": []})
    >>> lab[3, 2], lab[7, 2], lab[0, 0]
    (np.uint8(1), np.uint8(2), np.uint8(0))
    """
    opaque = np.asarray(alpha) >= 0.5
    lab = np.where(opaque, 1, 0).astype(np.uint8)
    for poly in polygons.get("ignore", []):
        lab[_fill(poly, opaque.shape) & opaque] = 255
    lab[_fill(polygons["trunk"], opaque.shape) & opaque] = 2
    return lab


def load_independent_masks(names=None) -> dict[str, np.ndarray]:
    """name -> reference label image of :func:`independent_reference`.

    Parameters
    ----------
    names : iterable of str, optional
        Sample names (keys of :func:`load_polygons`, loaded with
        :func:`branchnb.data.load`); None takes every image in the file.

    Returns
    -------
    dict of str to (H, W) uint8 ndarray
        Label images at the samples' source resolution.

    Raises
    ------
    KeyError
        If a name has no polygons.

    Examples
    --------
    >>> lab = load_independent_masks(["tree_rpg_05"])["tree_rpg_05"]
    >>> lab.shape, sorted(set(lab.ravel().tolist()))
    ((511, 256), [0, 1, 2])
    """
    polys = load_polygons()
    names = list(polys) if names is None else list(names)
    return {n: independent_reference(_data.load(n)[..., 3], polys[n]) for n in names}


def evaluate_independent(names=None, *, rng=0, **segment_kwargs) -> dict[str, dict[str, float]]:
    """Per-image IoU of :func:`~branchnb.trees.segmentation.segment_tree` on these masks.

    Parameters
    ----------
    names : iterable of str, optional
        Sample names to evaluate (default: all images with polygons).
    rng : int or numpy.random.Generator
        Seed of the segmenter's random forest training samples (default 0,
        so the figures repeat).
    **segment_kwargs
        Passed to :func:`~branchnb.trees.segmentation.segment_tree`, e.g.
        ``params=SegmentParams(work_size=256)``.

    Returns
    -------
    dict
        ``name -> {"crown", "trunk", "mean"}`` IoU in [0, 1] per image,
        plus ``"mean"``: the mean over images of the per-image mean IoU.
        Ignored pixels (255) do not count.

    Examples
    --------
    >>> from branchnb.trees.segmentation import SegmentParams
    >>> r = evaluate_independent(["plain_tree"], params=SegmentParams(work_size=128))  # doctest: +SKIP
    >>> sorted(r["plain_tree"])  # doctest: +SKIP
    ['crown', 'mean', 'trunk']
    """
    from .segmentation import segment_tree, segmentation_iou

    refs = load_independent_masks(names)
    out: dict = {}
    for n, ref in refs.items():
        seg = segment_tree(_data.load(n), rng=rng, **segment_kwargs)
        out[n] = segmentation_iou(seg.labels, ref)
    out["mean"] = float(np.mean([v["mean"] for v in out.values()]))
    return out
