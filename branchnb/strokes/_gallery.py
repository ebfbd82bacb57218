"""Gallery pictures of stroke-based structure editing."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import cv2
import numpy as np

from ..core.io import imsave
from ..gallery import GalleryItem
from ._examples import bent_spine, lizard_straighten, rope_bend, tree_add_branch
from .display import draw_strokes
from .edit import StrokeEditParams, edit_structure

SECTION = "Stroke-based structure editing"


def _fit(img: np.ndarray, height: int) -> np.ndarray:
    s = height / img.shape[0]
    return cv2.resize(img, (max(1, round(img.shape[1] * s)), height), interpolation=cv2.INTER_AREA)


def _row(*images, height: int = 360, gap: int = 8) -> np.ndarray:
    parts = []
    for k, im in enumerate(images):
        parts.append(_fit(np.ascontiguousarray(im[..., :3], np.float32), height))
        if k < len(images) - 1:
            parts.append(np.full((height, gap, 3), 0.6, np.float32))
    return np.clip(np.hstack(parts), 0, 1)


def _source(img, src, crop=None) -> np.ndarray:
    pic = draw_strokes(img, src, width=3.0)
    if crop is not None:
        pic = pic[crop]
    return pic


def render(outdir: Path) -> list[GalleryItem]:
    outdir = Path(outdir)
    items: list[GalleryItem] = []

    # Bend a straight object: the rope.
    img, src, tgt, kw = rope_bend()
    res = edit_structure(img, src, tgt, **kw)
    fn = "strokes_rope_bend.png"
    imsave(outdir / fn, _row(_source(img, src, (slice(380, 900), slice(0, 446))),
                             res.show(strokes=True), res.show(seams=True)))
    items.append(GalleryItem(SECTION, "bend a straight object (rope)", fn,
                             "source stroke (left), the rope re-synthesized along an arc (middle), "
                             f"graph-cut seams in red (right); patch radius {res.radius:.0f} px"))

    # Straighten a bent object: the lizard's tail; DP vs greedy, graph cut vs overlay.
    img, src, tgt, kw = lizard_straighten()
    pics, caps = [], []
    tail = StrokeEditParams(unstroked="drop")  # the tail alone, not the body hanging from its root
    for label, p in (("DP + graph cut", tail),
                     ("greedy + graph cut", dataclasses.replace(tail, sampling="greedy")),
                     ("DP + overlay", dataclasses.replace(tail, composition="overlay"))):
        r = edit_structure(img, src, tgt, p, **kw)
        pics.append(r.show(seams=False))
        caps.append(f"{label}: sampling energy {r.energies['sampling']:.2f}, "
                    f"seam cost {r.energies['seam']:.0f}")
    fn = "strokes_lizard_straighten.png"
    src_pic = _fit(_source(img, src), 300)
    width = max(src_pic.shape[1], pics[0].shape[1])
    stack = [np.pad(src_pic, ((0, 8), (0, width - src_pic.shape[1]), (0, 0)), constant_values=1.0)]
    stack += [np.pad(pic, ((0, 8), (0, width - pic.shape[1]), (0, 0)), constant_values=1.0)
              for pic in pics]
    imsave(outdir / fn, np.vstack(stack))
    items.append(GalleryItem(SECTION, "straighten a bent object (lizard tail)", fn,
                             "top: source stroke; then " + "; ".join(caps)))

    # Add a branch: the same source branch used twice.
    img, src, tgt, kw = tree_add_branch()
    res = edit_structure(img, src, tgt, **kw)
    fn = "strokes_tree_branch.png"
    imsave(outdir / fn, _row(_source(img, src[:3]), res.show(strokes=True), res.show(seams=True),
                             height=320))
    items.append(GalleryItem(SECTION, "add a branch (tree_rpg_12)", fn,
                             "source strokes (left; the middle branch is the source of two target "
                             f"strokes), result with target strokes (the branches nobody stroked follow "
                             f"the trunk), seams; {len(res.junctions)} junctions"))

    # Many parts: a procedural twig bent with one stroke, its leaves and fruits follow.
    from .procedural import twig

    obj = twig(700, rng=0)
    spine = obj.strokes[0]
    bent = bent_spine(spine, obj.image.shape[0])
    drop = edit_structure(obj.image, [spine], [bent], StrokeEditParams(unstroked="drop", close_cuts=False))
    follow = edit_structure(obj.image, [spine], [bent])
    fn = "strokes_twig_parts.png"
    imsave(outdir / fn, _row(_source(obj.image, [spine]), drop.show(strokes=True), follow.show(strokes=True),
                             height=300))
    items.append(GalleryItem(SECTION, "bend a twig: the parts nobody stroked follow", fn,
                             "source stroke (left), the paper's output (the stroked twig alone, middle), "
                             "leaves and fruits carried rigidly by the twig (right, the default)"))

    # Seam exponent.
    img, src, tgt, kw = rope_bend()
    pics, caps = [], []
    for power in (0.5, 1.0, 2.0):
        r = edit_structure(img, src, tgt, dataclasses.replace(StrokeEditParams(), seam_power=power),
                           **kw)
        pics.append(r.show(seams=True)[40:320, 80:360])
        caps.append(f"power {power:g}")
    fn = "strokes_seam_power.png"
    imsave(outdir / fn, _row(*pics, height=280))
    items.append(GalleryItem(SECTION, "seam exponent", fn,
                             "seams (red) for d ** power / G with " + ", ".join(caps)))
    return items
