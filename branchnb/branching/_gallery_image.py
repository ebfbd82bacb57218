"""Gallery pictures of fragment-based image synthesis (issue 3, items 9-10).

``gallery_items(outdir)`` is meant to be called from :mod:`branchnb.branching._gallery`.
Each picture shows, left to right: the example with its structure, the
synthesized structure, and the synthesized image.
"""

from __future__ import annotations

import importlib.util
from pathlib import Path

import numpy as np

from ..core.io import imsave
from ..core.structure import Structure
from ..gallery import GalleryItem
from ._image_examples import random_tree, river_example
from .image_synthesis import ImageSynthesisParams, synthesize_image

__all__ = ["gallery_items"]

SECTION = "Branching structures"

#: Real examples: (data name, extraction options, structure seed, image params, where the structure is
#: learnt and synthesized: "full" resolution then scaled to half, or at "half" resolution).
REAL = (
    ("retina_fundus", {"scale": 0.5}, 3, ImageSynthesisParams(flatten_shading=0.05), "full"),
    ("lightning_trace", {"root": "top"}, 2, ImageSynthesisParams(), "half"),
)


def _panel(example: np.ndarray, ex_structure: Structure, target: Structure,
           image: np.ndarray, gap: int = 8) -> np.ndarray:
    ex = example[..., :3]
    left = ex_structure.render(background=ex * 0.6 + 0.4 * ex.mean(), color=(0.95, 0.15, 0.1))
    h, w = image.shape[:2]
    mid = target.render((h, w), color=(0.0, 0.0, 0.0))
    parts = [left, mid, image[..., :3]]
    H = max(p.shape[0] for p in parts)
    out = []
    for k, p in enumerate(parts):
        pad = np.ones((H, p.shape[1], 3), np.float32)
        pad[: p.shape[0]] = p
        out.append(pad)
        if k < len(parts) - 1:
            out.append(np.full((H, gap, 3), 0.6, np.float32))
    return np.hstack(out)


def _have_structure_part() -> bool:
    return (importlib.util.find_spec("branchnb.branching.extraction") is not None
            and importlib.util.find_spec("branchnb.branching.synthesis") is not None)


def gallery_items(outdir) -> list[GalleryItem]:
    """Write the image-synthesis pictures into ``outdir`` and describe them."""
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    items: list[GalleryItem] = []
    if _have_structure_part():
        from skimage.transform import resize

        from .. import data
        from .extraction import extract_structure
        from .synthesis import synthesize_structure

        for name, ex_kw, seed, params, where in REAL:
            full = data.load(name)
            h, w = full.shape[:2]
            img = resize(full, (h // 2, w // 2), anti_aliasing=True).astype(np.float32).clip(0, 1)
            if where == "full":
                example = extract_structure(full, **ex_kw)
                target = synthesize_structure(example, rng=seed).structure.scaled(0.5)
                example = example.scaled(0.5)
            else:
                example = extract_structure(img, **ex_kw)
                target = synthesize_structure(example, rng=seed).structure
            res = synthesize_image(img, example, target, params, rng=0)
            fn = f"branching_image_{name}.png"
            imsave(outdir / fn, _panel(img, example, target, res.image))
            items.append(GalleryItem(
                SECTION, f"synthesized image: {name}", fn,
                f"left: example with its extracted structure (red); middle: synthesized structure; "
                f"right: image from {len(res.fragments)} fragments of the example along it, the gaps "
                f"completed from branch-free example pixels ({res.timings['total']:.1f} s)"))
    img, example = river_example((256, 256), 0, n_children=4)
    target = random_tree((256, 256), 7, n_children=5, grandchildren=1)
    res = synthesize_image(img, example, target, rng=0)
    fn = "branching_image_river.png"
    imsave(outdir / fn, _panel(img, example, target, res.image))
    items.append(GalleryItem(
        SECTION, "synthesized image: procedural river", fn,
        "left: procedural example with its exact structure; middle: new structure; right: "
        f"synthesized image ({len(res.fragments)} fragments + gap completion, "
        f"{res.timings['total']:.1f} s)"))
    return items
