"""Gallery pictures of the crown/trunk segmentation and the billboard cloud.

``branchnb.trees._gallery`` (the technique's gallery module) calls
:func:`gallery_items` and appends its items.
"""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from ..gallery import GalleryItem, SectionWriter

SECTION = "Image-based tree variations"


def _fit(img: np.ndarray, height: int) -> np.ndarray:
    h, w = img.shape[:2]
    return cv2.resize(img, (max(1, round(w * height / h)), height), interpolation=cv2.INTER_AREA)


def _row(images, height: int = 256, gap: int = 4) -> np.ndarray:
    tiles = []
    for im in images:
        if tiles:
            tiles.append(np.ones((height, gap, 3), np.float32))
        tiles.append(_fit(im, height))
    return np.concatenate(tiles, axis=1)


def gallery_items(outdir: Path) -> list[GalleryItem]:
    from .. import data
    from .billboard import _front_overlay, billboard_cloud
    from .preview import render_views
    from .segmentation import load_reference_masks, overlay_labels, segment_tree, segmentation_iou

    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    writer = SectionWriter(SECTION, outdir)
    save, items = writer.save, writer.items

    names = ("tree_rpg_02", "tree_rpg_13", "arbre_modern", "tree_cutout_broadleaf", "palm_silhouette")
    refs = load_reference_masks(names)
    autos, hands, scores = [], [], []
    for n in names:
        img = data.load(n)
        seg = segment_tree(img, rng=0)
        autos.append(seg.overlay())
        hands.append(overlay_labels(img, refs[n]))
        scores.append(f"{n} {100 * segmentation_iou(seg.labels, refs[n])['mean']:.0f}%")
    top, bottom = _row(autos), _row(hands)
    save("trees_segmentation.png",
         np.concatenate([top, np.ones((4, top.shape[1], 3), np.float32), bottom], 0),
         "Crown/trunk segmentation",
         "top: automatic segmenter (crown green, trunk red); bottom: the project's hand-corrected "
         "reference labels (blue: ignored ground/grass). Mean IoU: " + ", ".join(scores))

    for n in ("tree_rpg_02", "tree_cutout_broadleaf"):
        cloud = billboard_cloud(data.load(n), rng=0)
        c = cloud.counts()
        save(f"trees_cloud_{n}.png", render_views(cloud, (0.0, 50.0, 100.0, 180.0), height=320),
             f"Billboard cloud: {n}",
             f"yaw 0 (= input), 50, 100 and 180 degrees; {c['front']} front, {c['rear']} rear, "
             f"{c['interior']} interior billboards and the trunk")
        if n == "tree_rpg_02":
            depth = cloud.depth / max(float(cloud.depth.max()), 1e-6)
            depth_rgb = np.repeat(depth[..., None], 3, axis=2).astype(np.float32)
            save("trees_cloud_construction.png", _row([_front_overlay(cloud), depth_rgb], 320),
                 "Billboard cloud construction",
                 f"left: SLIC superpixels with {len(cloud.replaced)} near-straight edges replaced by "
                 "silhouette pieces (red); right: biharmonic inflation of the crown (white = deepest)")
    return items
