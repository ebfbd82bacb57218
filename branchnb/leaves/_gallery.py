"""Gallery pictures of leaf variations: procedural family, registration, generated leaves."""

from __future__ import annotations

from pathlib import Path

import numpy as np

from ..gallery import GalleryItem, SectionWriter

SECTION = "Leaf variations by structural layering"


def _row(images, pad: int = 4) -> np.ndarray:
    h = max(i.shape[0] for i in images)
    cells = [np.pad(i[..., :3], ((0, h - i.shape[0]), (0, pad), (0, 0)), constant_values=1.0) for i in images]
    return np.hstack(cells)


def render(outdir: Path) -> list[GalleryItem]:
    from .. import data
    from .exemplar import leaf_exemplar
    from .procedural import leaf_family
    from .registration import draw_registration, register

    outdir = Path(outdir)
    writer = SectionWriter(SECTION, outdir)
    save, items = writer.save, writer.items

    fam = leaf_family(4, size=256, rng=1)
    save("leaves_family.png", _row([f.on_white() for f in fam]), "A procedural leaf family",
         "leaf_family(4, size=256, rng=1): lobed leaves with outline variation, open-venation veins "
         "(Runions et al. 2005), spots and noise texture; each carries its true layers and keypoints")
    reg = register(fam[1], fam[0])
    save("leaves_registration_procedural.png", draw_registration(reg, fam[1].on_white(), fam[0].on_white(),
                                                                 blade=fam[0].blade),
         "TPS-RPM registration (procedural)",
         "left: exemplar with the training grid mapped onto it; right: training leaf, its keypoints "
         "(hollow) and the exemplar's keypoints after the warp (filled)")
    maple = [leaf_exemplar(data.load(f"maple_leaf_0{i}")) for i in (1, 5)]
    reg = register(maple[1], maple[0])
    save("leaves_registration_maple.png", _row([draw_registration(reg, maple[1].on_white(), maple[0].on_white(),
                                                                  blade=maple[0].blade),
                                                reg.to_training(maple[1].on_white())]),
         "TPS-RPM registration (photographed maple leaves)",
         "maple_leaf_05 registered to maple_leaf_01, and resampled into its frame")
    return items
