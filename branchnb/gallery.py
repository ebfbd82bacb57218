"""Headless gallery: one example per implemented technique, as PNGs plus index.html.

Every technique may provide ``branchnb.<technique>._gallery`` with a function
``render(outdir: Path) -> list[GalleryItem]`` that writes its PNGs into
``outdir``. The sample images with an annotation overlay always come first.
"""

from __future__ import annotations

import html
import importlib
import importlib.util
from dataclasses import dataclass, field
from pathlib import Path

import numpy as np
from skimage.morphology import skeletonize

from . import data
from .core.image import as_gray, as_rgb, split_alpha
from .core.io import imsave
from .core.render import draw_polylines
from .core.sampling import stipple

__all__ = ["GalleryItem", "SectionWriter", "build", "SECTIONS"]

SECTIONS = (
    "branchnb.branching._gallery",
    "branchnb.dendrite._gallery",
    "branchnb.trees._gallery",
    "branchnb.leaves._gallery",
    "branchnb.strokes._gallery",
)


@dataclass
class GalleryItem:
    """One picture of the gallery: ``filename`` inside the output folder.

    Parameters
    ----------
    section : str
        Heading the picture is listed under (the technique, or
        ``"Sample data"``); consecutive items of one section share it.
    title : str
        Bold caption line.
    filename : str
        The PNG's name, relative to the gallery folder.
    caption : str
        What to look at in the picture (plain text, escaped in the HTML).

    Examples
    --------
    >>> GalleryItem("Sample data", "camera", "samples_camera.png").caption
    ''
    """

    section: str
    title: str
    filename: str
    caption: str = ""



@dataclass
class SectionWriter:
    """Saves one section's pictures into ``outdir`` and collects their :class:`GalleryItem` s.

    Parameters
    ----------
    section : str
        The section heading given to every item saved.
    outdir : pathlib.Path
        Existing folder the PNGs are written to.
    items : list of GalleryItem
        Items collected so far (empty by default); :meth:`save` appends.

    Examples
    --------
    >>> import tempfile
    >>> w = SectionWriter("Demo", Path(tempfile.mkdtemp()))
    >>> w.save("grey.png", np.full((4, 4, 3), 0.5, np.float32), "grey", "a flat picture")
    >>> [(i.section, i.filename) for i in w.items]
    [('Demo', 'grey.png')]
    """

    section: str
    outdir: Path
    items: list[GalleryItem] = field(default_factory=list)

    def save(self, filename: str, image: np.ndarray, title: str, caption: str = "") -> None:
        """Write ``image`` as ``outdir / filename`` and append its :class:`GalleryItem`.

        Parameters
        ----------
        filename : str
            File name inside ``outdir`` (its suffix picks the format; use
            ``.png``). An existing file is overwritten.
        image : ndarray
            Gray, RGB or RGBA; uint8/uint16/bool or float in [0, 1].
        title : str
            Bold caption line.
        caption : str
            What to look at in the picture.
        """
        imsave(Path(self.outdir) / filename, image)
        self.items.append(GalleryItem(self.section, title, filename, caption))

def _skeleton_overlay(name: str) -> np.ndarray:
    rgb, alpha = split_alpha(data.load(name))
    skel = skeletonize(alpha > 0.5)
    ys, xs = np.nonzero(skel)
    img = as_rgb(np.dstack([rgb, alpha]), background=(1, 1, 1))
    dots = [np.array([[x, y]], float) for x, y in zip(xs, ys)]
    return draw_polylines(img, dots, widths=3.0, colors=(0.85, 0.1, 0.1))


def _stipple_overlay(name: str, n: int = 1500) -> np.ndarray:
    img = as_rgb(data.load(name))
    density = (1.0 - as_gray(img)) ** 2 + 1e-3
    pts = stipple(density, n, iterations=10, rng=0)
    return draw_polylines(img * 0.5 + 0.5, [p[None] for p in pts], widths=3.0,
                          colors=(0.1, 0.2, 0.8))


def _samples(outdir: Path) -> list[GalleryItem]:
    items = []
    for name in ("lizard", "tree_rpg_11"):
        fn = f"samples_{name}.png"
        imsave(outdir / fn, _skeleton_overlay(name))
        items.append(GalleryItem("Sample data", name, fn, "alpha mask skeleton (red) over the image"))
    for name in ("camera", "retina_fundus"):
        fn = f"samples_{name}.png"
        imsave(outdir / fn, _stipple_overlay(name))
        items.append(GalleryItem("Sample data", name, fn, "weighted Voronoi stipples on darkness (blue)"))
    return items


def build(outdir, sections=None, progress=None) -> list[GalleryItem]:
    """Render the gallery into ``outdir`` (created if needed) and write ``index.html``.

    The sample pictures (skeletons of alpha masks, stipples) always come
    first; then each section's ``render(outdir)`` adds its own.

    Parameters
    ----------
    outdir : str or os.PathLike
        Output folder, created with its parents if needed; existing files of
        the same names are overwritten.
    sections : sequence of str, optional
        Dotted names of the technique modules with a ``render(outdir)``
        function to include (:data:`SECTIONS` by default; ``()`` gives only
        the sample pictures, in seconds). Modules not installed are skipped.
    progress : callable, optional
        Called with a short name (``"sample data"``, ``"branching"``, ...)
        as each part starts.

    Returns
    -------
    list of GalleryItem
        Every picture written, in page order.

    Examples
    --------
    >>> items = build("build/gallery", sections=())       # doctest: +SKIP
    >>> [i.filename for i in items][:2]                   # doctest: +SKIP
    ['samples_lizard.png', 'samples_tree_rpg_11.png']
    """
    sections = SECTIONS if sections is None else sections
    outdir = Path(outdir)
    outdir.mkdir(parents=True, exist_ok=True)
    if progress is not None:
        progress("sample data")
    items = _samples(outdir)
    for mod_name in sections:
        pkg = mod_name.rsplit(".", 1)[0]
        if importlib.util.find_spec(pkg) is None or importlib.util.find_spec(mod_name) is None:
            continue
        if progress is not None:
            progress(pkg.rsplit(".", 1)[-1])
        items.extend(importlib.import_module(mod_name).render(outdir))
    parts = ["<!doctype html><meta charset='utf-8'><title>branchnb gallery</title>",
             "<style>body{font-family:sans-serif;max-width:1100px;margin:auto}"
             "figure{display:inline-block;margin:8px;vertical-align:top;max-width:340px}"
             "img{max-width:340px;border:1px solid #ccc}</style><h1>branchnb gallery</h1>"]
    section = None
    for it in items:
        if it.section != section:
            section = it.section
            parts.append(f"<h2>{html.escape(section)}</h2>")
        parts.append(
            f"<figure><a href='{html.escape(it.filename)}'><img src='{html.escape(it.filename)}'></a>"
            f"<figcaption><b>{html.escape(it.title)}</b><br>{html.escape(it.caption)}</figcaption></figure>"
        )
    (outdir / "index.html").write_text("\n".join(parts), encoding="utf-8")
    return items
