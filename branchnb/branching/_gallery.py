"""Gallery pictures of branching-structure extraction and synthesis."""

from __future__ import annotations

import dataclasses
from pathlib import Path

import numpy as np

from .. import data
from ..core.io import imsave
from ..gallery import GalleryItem
from .extraction import extract_structure
from .guidance import Guidance
from .params import SynthesisParams
from .synthesis import fit_model, synthesize_structure

SECTION = "Branching structures"

EXAMPLES = {
    "retina_fundus": dict(scale=0.5),
    "lightning_trace": dict(scale=0.5, root="top"),
    "cracked_mud": dict(scale=0.5, min_branch_length=40),
}


def _side_by_side(*images, gap: int = 8) -> np.ndarray:
    h = max(im.shape[0] for im in images)
    parts = []
    for k, im in enumerate(images):
        pad = np.ones((h, im.shape[1], 3), np.float32)
        pad[: im.shape[0]] = im[..., :3]
        parts.append(pad)
        if k < len(images) - 1:
            parts.append(np.full((h, gap, 3), 0.6, np.float32))
    return np.hstack(parts)


def render(outdir: Path) -> list[GalleryItem]:
    outdir = Path(outdir)
    items: list[GalleryItem] = []
    structures = {}
    for name, kw in EXAMPLES.items():
        img = data.load(name)
        s = extract_structure(img, **kw)
        structures[name] = s
        fn = f"branching_extract_{name}.png"
        imsave(outdir / fn, s.render(background=img[..., :3] * 0.55, by_generation=True, alpha=0.9,
                                     min_width=1.5))
        items.append(GalleryItem(SECTION, f"extract_structure: {name}", fn,
                                 f"{len(s.branches)} branches, {s.n_vertices} vertices; colour = generation "
                                 "(green root, blue 1st, orange 2nd, ...)"))

    # Synthesis from the retina example.
    ex = structures["retina_fundus"]
    model = fit_model(ex)
    res = synthesize_structure(model, rng=3)
    fn = "branching_synth_retina.png"
    imsave(outdir / fn, _side_by_side(ex.render(by_generation=True), res.structure.render(by_generation=True)))
    d = res.diagnostics
    items.append(GalleryItem(SECTION, "synthesize_structure: retina", fn,
                             f"left: extracted example; right: synthesized ({d['n_vertices']} vertices, "
                             f"{d['time_s']:.2f} s), paper defaults k = 12, m = 4, c = 2, wG = 50"))

    # Histogram matching on/off and colonization on/off (lightning).
    lex = structures["lightning_trace"]
    lmodel = fit_model(lex)
    start = [(512.0, 10.0, np.pi / 2)]
    pics, cap = [], []
    for wG in (0.0, 50.0):
        p = dataclasses.replace(SynthesisParams(), wG=wG, max_total_length=3000.0)
        r = synthesize_structure(lmodel, p, rng=1, starts=start)
        pics.append(r.structure.render(by_generation=True))
        cap.append(f"wG = {wG:g}: distance {r.diagnostics['hist_distance']['sum']:.2e}")
    fn = "branching_histogram_matching.png"
    imsave(outdir / fn, _side_by_side(*pics))
    items.append(GalleryItem(SECTION, "global histogram matching off / on", fn, "; ".join(cap)))

    pics, cap = [], []
    from ..core.polyline import segments_intersect

    for col in (False, True):
        p = dataclasses.replace(SynthesisParams(), colonization=col, max_total_length=4000.0)
        r = synthesize_structure(lmodel, p, rng=2, starts=start)
        p0, p1, _ = r.structure.segments()
        n_x = int(np.triu(segments_intersect(p0, p1, p0, p1), 1).sum())
        pics.append(r.structure.render(by_generation=True))
        cap.append(f"colonization {'on' if col else 'off'}: {n_x} crossings")
    fn = "branching_colonization.png"
    imsave(outdir / fn, _side_by_side(*pics))
    items.append(GalleryItem(SECTION, "space colonization off / on", fn, "; ".join(cap)))

    # Guided synthesis along an S-shaped path.
    shape = lex.image_shape
    t = np.linspace(0, 1, 50)
    path = np.c_[150 + 700 * t, 330 + 220 * np.sin(2 * np.pi * t)]
    gd = Guidance.from_path(shape, path, width=40)
    r = synthesize_structure(lmodel, dataclasses.replace(SynthesisParams(), max_total_length=4000.0), rng=0,
                             guidance=gd)
    img = r.structure.render(background=np.dstack([gd.map] * 3) * 0.25 + 0.75, by_generation=True)
    from ..core.render import draw_polylines

    img = draw_polylines(img, [path], widths=1.0, colors=(0.9, 0.1, 0.1))
    fn = "branching_guided.png"
    imsave(outdir / fn, img)
    items.append(GalleryItem(SECTION, "guided synthesis", fn,
                             "guidance valley (grey) along a user path (red); lightning example"))

    items.extend(_image_synthesis(outdir))
    return items


def _image_synthesis(outdir: Path) -> list[GalleryItem]:
    """The final images of fragment-based synthesis (items 9-10): retina, lightning, a river."""
    from ._gallery_image import gallery_items

    return gallery_items(outdir)
