"""Measuring the structural judgement (:mod:`branchnb.leaves.structural`): true veins against veins on plain blade.

``python -m branchnb.leaves._measure_structural [procedural] [gradients] [maples]`` prints, per case, ``lambda``,
the paper's verdict (:data:`~branchnb.leaves.structural.MIN_STRUCTURAL_LAMBDA` and the reach), each
exemplar's standout, their median and whether :func:`~branchnb.leaves.analysis.analyze` warned
(:class:`~branchnb.leaves.structural.NonStructuralLayerWarning`). Cases: the four procedural kinds at
160 and 192 px (3 leaves, rng 3) with their true vein mask, the same mask on the same leaves with their
veins painted out (:func:`plain_blade`), and at 192 px simulated scribbles on those plain leaves; the
sample maples with their stored scribbles and with hand-traced veins on maple_leaf_02 / _04 / _06;
``gradients``: the true vein layer given on gradient-filled drawings without veins (1 and 2 px ink
outlines, :func:`gradient_drawing`) and main veins scribbled on a painted-out lobed leaf.
"""

from __future__ import annotations

import sys
import time
import warnings

import cv2
import numpy as np
from scipy import ndimage as ndi

from .. import data
from .analysis import analyze
from .exemplar import leaf_exemplar
from .layers import Layer, LayerSet, simulate_scribbles
from .procedural import leaf_family
from .reference import reference_veins
from .structural import MAX_STRUCTURAL_REACH, MIN_STRUCTURAL_LAMBDA, NonStructuralLayerWarning, spatial_reach


def plain_blade(leaf) -> np.ndarray:
    """A procedural leaf's RGBA with its veins (and petiole) painted out (OpenCV inpainting)."""
    img = leaf.image.copy()
    veins = ndi.binary_dilation(leaf.layers["veins"], iterations=1) & leaf.blade
    fill = np.median(img[..., :3][leaf.blade & ~leaf.layers["veins"]], axis=0)
    base = np.where(leaf.blade[..., None], img[..., :3], fill)
    rgb = (np.clip(base, 0, 1) * 255).astype(np.uint8)
    out = cv2.inpaint(rgb, veins.astype(np.uint8), 5, cv2.INPAINT_TELEA).astype(np.float32) / 255
    img[..., :3] = np.where(veins[..., None], out, img[..., :3])
    return img


def _row(tag, exemplars, t, layers):
    t0 = time.time()
    with warnings.catch_warnings(record=True) as caught:
        warnings.simplefilter("always")
        a = analyze(exemplars, t, layers)
    x = a.layer("veins")
    paper = x.lam > MIN_STRUCTURAL_LAMBDA and spatial_reach(x.lam, x.delta) <= MAX_STRUCTURAL_REACH
    so = "-" if x.standout is None else " ".join(f"{v:.2f}" for v in x.standout)
    med = "-" if x.standout is None else f"{np.median(x.standout):.2f}"
    warned = any(w.category is NonStructuralLayerWarning for w in caught)
    print(f"{tag:30s} lambda {x.lam:.3f} paper {'struct' if paper else 'NON   '} standout [{so}] median {med} "
          f"warned {warned} ({time.time() - t0:.0f} s)", flush=True)


def procedural() -> None:
    for size in (160, 192):
        for kind, palette in [("lobed", "green"), ("trilobed", "autumn"), ("elliptic", "green"),
                              ("fan", "autumn")]:
            fam = leaf_family(3, size=size, kind=kind, palette=palette, rng=3)
            veins = fam[0].layers["veins"]
            plain = [plain_blade(leaf) for leaf in fam]
            _row(f"{size} {kind} true veins", fam, 0, {"veins": veins})
            _row(f"{size} {kind} on plain blade", plain, 0, {"veins": veins})
            if size == 192:
                strokes = simulate_scribbles(veins, 10, length=12, rng=0)
                _row(f"{size} {kind} scribbled on plain", plain, 0,
                     LayerSet([Layer("veins", "#d62728", 0, strokes)]))


def gradient_drawing(leaf, width: int = 2) -> np.ndarray:
    """A procedural leaf drawn as clip art with a gradient fill (not flat art), a dark ink outline and no veins."""
    b = leaf.blade
    yy, xx = np.mgrid[:b.shape[0], :b.shape[1]] / max(b.shape)
    img = np.ones(b.shape + (3,), np.float32)
    fill = np.stack([0.3 + 0.7 * xx, 0.95 - 0.6 * yy, 0.1 + 0.4 * xx * yy], -1).astype(np.float32)
    img[b] = fill[b]
    img[b & ~ndi.binary_erosion(b, iterations=width)] = 0.05
    return img


def gradients() -> None:
    """A vein layer given on gradient drawings without veins (their ink outline is no vein)."""
    for kind, size, seed in [("trilobed", 128, 2), ("lobed", 160, 1), ("elliptic", 192, 4), ("fan", 160, 3),
                             ("trilobed", 256, 5)]:
        fam = leaf_family(3, size=size, kind=kind, rng=seed)
        for width in (1, 2):
            _row(f"{size} {kind} gradient {width} px", [leaf_exemplar(gradient_drawing(leaf, width)) for leaf in fam],
                 0, {"veins": fam[0].layers["veins"]})
    # The main veins scribbled on a lobed leaf with its veins painted out (the app's test).
    from .layers import Scribble
    fam = leaf_family(3, size=160, kind="lobed", rng=3)
    _row("160 lobed main veins on plain", [plain_blade(leaf) for leaf in fam], 0,
         LayerSet([Layer("veins", "#d62728", 0, [Scribble(v, 1.0) for v in fam[0].veins[1:7]])]))


def maples() -> None:
    leaves = [leaf_exemplar(data.load(f"maple_leaf_0{i}")) for i in range(1, 8)]
    stored = LayerSet.from_json((data.DATA_DIR / "leaves" / "maple_leaf_01_layers.json").read_text())
    _row("maples (7) stored scribbles", leaves, 0, stored)
    _row("maples 01/03/05 stored", [leaves[i] for i in (0, 2, 4)], 0, stored)
    traced = [reference_veins(f"maple_leaf_0{i}") for i in range(1, 8)]
    for t in (1, 3, 5):
        _row(f"maples traced, training {t + 1:02d}", leaves, t, {"veins": traced[t]})


if __name__ == "__main__":
    todo = sys.argv[1:] or ["procedural", "gradients", "maples"]
    if "procedural" in todo:
        procedural()
    if "gradients" in todo:
        gradients()
    if "maples" in todo:
        maples()
