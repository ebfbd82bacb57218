"""One plotting style for every notebook and doc page: labelled panels side by side.

The notebooks teach by pictures, so they share one look: the same dpi, images
large enough to see a dendrite or a vein (4 inches at 100 dpi = 400 px per
panel by default), inputs and outputs side by side in one figure, histograms
with labelled axes and a legend, and scalar maps with a labelled colour bar.

The conventions every notebook follows (the docs' "Notebook style" page says
the same):

* call :func:`use_style` once at the top; never set a dpi or define a
  notebook's own ``show()``;
* one figure per step, input and output side by side (:func:`show`, or
  :func:`panels` + :func:`image_panel` for a custom layout);
* scalar maps keep their own range and get a labelled colour bar
  (``colorbar="cost"``), never clipped to [0, 1] black;
* histograms on shared bins with labelled axes and a legend
  (:func:`hist_panel`, :func:`show_histograms`);
* colours that code a category (generation, layer, stroke pair) get a legend
  (:func:`legend_patches`).

This module needs matplotlib (a dependency of the package) and is never
imported by the technique modules, which stay plain numpy.

Examples
--------
>>> import numpy as np
>>> from branchnb import plot
>>> plot.use_style()
>>> fig, axes = plot.panels(2)
>>> _ = plot.image_panel(axes[0], np.zeros((8, 8, 3), np.float32), "input")
>>> _ = plot.image_panel(axes[1], np.eye(8, dtype=np.float32), "output", colorbar="value")
>>> plot.close(fig)
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence

import matplotlib.pyplot as plt
import numpy as np

from .core.image import as_float_image, composite_over

__all__ = [
    "DPI",
    "PANEL_INCHES",
    "use_style",
    "panels",
    "image_panel",
    "hist_panel",
    "show",
    "show_histograms",
    "legend_patches",
    "close",
]

#: Figure resolution used by every notebook (dots per inch).
DPI = 100
#: Default side of one panel in inches; at ``DPI`` this is 400 px.
PANEL_INCHES = 4.0

_STYLE = {
    "figure.dpi": DPI,
    "savefig.dpi": DPI,
    "axes.titlesize": 10,
    "axes.labelsize": 9,
    "xtick.labelsize": 8,
    "ytick.labelsize": 8,
    "legend.fontsize": 8,
    "figure.titlesize": 11,
    "image.interpolation": "antialiased",
}


def use_style() -> None:
    """Set the shared notebook style (dpi, font sizes) in ``matplotlib.rcParams``.

    Call once at the top of a notebook. Only the style's own keys (dpi, font
    sizes, image interpolation) are changed, so a user's other settings stay.

    Examples
    --------
    >>> import matplotlib.pyplot as plt
    >>> from branchnb import plot
    >>> plot.use_style()
    >>> plt.rcParams["figure.dpi"] == plot.DPI
    True
    """
    plt.rcParams.update(_STYLE)


def panels(n: int, *, cols: int | None = None, size: float = PANEL_INCHES, widths: Sequence[float] | None = None,
           height: float | None = None, suptitle: str | None = None):
    """A figure with ``n`` panels in a grid, as ``(figure, flat array of axes)``.

    Parameters
    ----------
    n : int
        Number of panels (>= 1).
    cols : int, optional
        Panels per row; all in one row by default.
    size : float
        Width of one panel in inches (its height too unless ``height`` is given).
    widths : sequence of float, optional
        Relative panel widths for a single row (e.g. a wide result beside a narrow input).
    height : float, optional
        Row height in inches.
    suptitle : str, optional
        A title over the whole figure.

    Returns
    -------
    figure : matplotlib.figure.Figure
    axes : numpy.ndarray of matplotlib.axes.Axes
        The ``n`` axes in reading order (spare grid cells are hidden).

    Raises
    ------
    ValueError
        ``n`` is not a positive integer, or ``widths`` does not fit one row of ``n`` panels.

    Examples
    --------
    >>> from branchnb import plot
    >>> fig, axes = plot.panels(3, cols=2)
    >>> len(axes), [round(v) for v in fig.get_size_inches()]
    (3, [8, 8])
    >>> plot.close(fig)
    """
    if isinstance(n, bool) or not isinstance(n, (int, np.integer)) or n < 1:
        raise ValueError(f"n must be a positive integer, got {n!r}")
    cols = int(n if cols is None else max(1, min(int(cols), n)))
    rows = -(-int(n) // cols)
    height = size if height is None else float(height)
    if widths is not None:
        widths = [float(w) for w in widths]
        if rows != 1 or len(widths) != cols:
            raise ValueError("widths needs one value per panel in a single row")
        if min(widths) <= 0:
            raise ValueError("widths must be positive")
        fig_w = size * sum(widths) / max(widths)  # the widest panel is `size` wide
        fig, axes = plt.subplots(1, cols, figsize=(fig_w, height), squeeze=False,
                                 gridspec_kw={"width_ratios": widths})
    else:
        fig, axes = plt.subplots(rows, cols, figsize=(size * cols, height * rows), squeeze=False)
    flat = axes.ravel()
    for ax in flat[n:]:
        ax.set_visible(False)
    if suptitle:
        fig.suptitle(suptitle)
    return fig, flat[:n]


def _displayable(image, background):
    img = np.asarray(image)
    if img.ndim == 3 and img.shape[-1] == 1:
        img = img[..., 0]
    if img.ndim == 2:
        return np.asarray(img, dtype=np.float32), True
    img = as_float_image(img)
    if img.shape[-1] == 4:
        if background == "checker":
            h, w = img.shape[:2]
            tile = max(4, min(h, w) // 32)
            yy, xx = np.mgrid[0:h, 0:w]
            checks = (((yy // tile) + (xx // tile)) % 2).astype(np.float32)
            bg = (0.82 + 0.12 * checks)[..., None].repeat(3, axis=2)
            return composite_over(img, bg), False
        return composite_over(img, background), False
    return np.clip(img[..., :3], 0.0, 1.0), False


def image_panel(ax, image, title: str | None = None, *, cmap: str = "gray", vmin: float | None = None,
                vmax: float | None = None, colorbar: str | bool | None = None, background="checker",
                scale_bar: bool = False):
    """Draw one image (RGB, RGBA or a scalar map) on ``ax`` without axes.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The panel to draw on (e.g. one of :func:`panels`); its axes are hidden.
    image : array_like
        ``(H, W)`` scalar map, or ``(H, W, 3 | 4)`` colour image in [0, 1] (uint8 is scaled).
    title : str, optional
        Panel title.
    cmap : str
        Matplotlib colormap name, for scalar maps only.
    vmin, vmax : float, optional
        Colour range of a scalar map; default the map's finite range, so a
        map in any units is visible (never clipped to [0, 1] black).
    colorbar : str or bool, optional
        For scalar maps: add a colour bar, labelled with the string when one is given.
    background : 'checker' or RGB triple
        What shows through transparent pixels of an RGBA image.
    scale_bar : bool
        Write the image's size in pixels under the title (useful when panels of
        different sizes sit side by side).

    Returns
    -------
    matplotlib.image.AxesImage

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb import plot
    >>> fig, axes = plot.panels(1)
    >>> cost = np.linspace(0, 50, 64).reshape(8, 8)
    >>> artist = plot.image_panel(axes[0], cost, "lattice cost", colorbar="cost")
    >>> artist.get_clim()            # the map's own range, not [0, 1]
    (0.0, 50.0)
    >>> plot.close(fig)
    """
    data, scalar = _displayable(image, background)
    if scalar:
        finite = data[np.isfinite(data)]
        lo = float(finite.min()) if vmin is None and finite.size else vmin
        hi = float(finite.max()) if vmax is None and finite.size else vmax
        if lo is not None and hi is not None and hi <= lo:
            hi = lo + 1.0
        artist = ax.imshow(data, cmap=cmap, vmin=lo, vmax=hi, interpolation="nearest")
        if colorbar:
            cb = ax.figure.colorbar(artist, ax=ax, fraction=0.046, pad=0.02)
            if isinstance(colorbar, str):
                cb.set_label(colorbar)
    else:
        artist = ax.imshow(data, interpolation="antialiased")
    label = title or ""
    if scale_bar:
        label = f"{label}\n{data.shape[1]} x {data.shape[0]} px" if label else f"{data.shape[1]} x {data.shape[0]} px"
    if label:
        ax.set_title(label)
    ax.set_xticks([])
    ax.set_yticks([])
    for spine in ax.spines.values():
        spine.set_visible(False)
    return artist


def hist_panel(ax, samples: Mapping[str, Sequence[float]], *, bins=30, xlabel: str = "value",
               ylabel: str = "share", title: str | None = None, range: tuple[float, float] | None = None):
    """Overlay the histograms of several named samples on one axis, with a legend.

    The bins are shared (one ``range`` over all samples), and each histogram is
    normalised to shares summing to 1 so that samples of different sizes compare.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The panel to draw on.
    samples : mapping of label -> 1-D values
        E.g. ``{"example": angles_in, "synthesized": angles_out}``.
    bins : int or sequence of edges
        Number of shared bins over ``range``, or the edges themselves.
    xlabel, ylabel, title : str
        Axis labels and panel title.
    range : (float, float), optional
        Shared range; the finite range of all samples by default.

    Returns
    -------
    matplotlib.axes.Axes
        ``ax``.

    Raises
    ------
    TypeError
        ``samples`` is not a non-empty mapping.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb import plot
    >>> fig, axes = plot.panels(1)
    >>> ax = plot.hist_panel(axes[0], {"example": np.zeros(10), "result": np.ones(30)}, bins=4, xlabel="angle (rad)")
    >>> ax.get_xlabel(), [t.get_text() for t in ax.get_legend().get_texts()]
    ('angle (rad)', ['example (n=10)', 'result (n=30)'])
    >>> plot.close(fig)
    """
    if not isinstance(samples, Mapping) or not samples:
        raise TypeError("samples must be a non-empty mapping of label -> values")
    arrays = {str(k): np.asarray(v, dtype=np.float64).ravel() for k, v in samples.items()}
    arrays = {k: v[np.isfinite(v)] for k, v in arrays.items()}
    if range is None:
        every = np.concatenate([v for v in arrays.values()] + [np.zeros(0)])
        range = (float(every.min()), float(every.max())) if every.size else (0.0, 1.0)
        if range[1] <= range[0]:
            range = (range[0] - 0.5, range[0] + 0.5)
    edges = np.histogram_bin_edges(np.zeros(0), bins=bins, range=range) if np.ndim(bins) == 0 else np.asarray(bins)
    for label, values in arrays.items():
        counts, _ = np.histogram(values, bins=edges)
        share = counts / max(counts.sum(), 1)
        ax.stairs(share, edges, label=f"{label} (n={values.size})", linewidth=1.5)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    if title:
        ax.set_title(title)
    ax.legend(frameon=False)
    return ax


def show(images: Sequence, titles: Sequence[str] = (), *, cols: int | None = None, size: float = PANEL_INCHES,
         widths: Sequence[float] | None = None, suptitle: str | None = None, cmap: str = "gray",
         colorbar: str | bool | None = None, background="checker", scale_bar: bool = False) -> None:
    """Show images side by side in one figure (the notebooks' one-liner).

    Parameters
    ----------
    images : sequence of array_like
        Images or scalar maps (see :func:`image_panel`).
    titles : sequence of str
        One per image (missing ones are blank).
    cols : int, optional
        Panels per row (see :func:`panels`).
    size : float
        Width of one panel in inches (see :func:`panels`).
    widths : sequence of float, optional
        Relative panel widths for a single row (see :func:`panels`).
    suptitle : str, optional
        Figure title.
    cmap : str
        Colormap of scalar maps (see :func:`image_panel`).
    colorbar : str or bool, optional
        Colour bars on scalar maps (see :func:`image_panel`).
    background : 'checker' or RGB triple
        What shows through transparent pixels (see :func:`image_panel`).
    scale_bar : bool
        Write each image's size under its title (see :func:`image_panel`).

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb import plot
    >>> plot.show([np.zeros((8, 8, 3)), np.eye(8)], ["input", "output"], colorbar="value")
    >>> plot.close("all")
    """
    images = list(images)
    titles = list(titles) + [""] * max(0, len(images) - len(titles))
    fig, axes = panels(len(images), cols=cols, size=size, widths=widths, suptitle=suptitle)
    for ax, img, title in zip(axes, images, titles):
        image_panel(ax, img, title, cmap=cmap, colorbar=colorbar, background=background, scale_bar=scale_bar)
    fig.tight_layout()
    plt.show()


def show_histograms(groups: Mapping[str, Mapping[str, Sequence[float]]], *, xlabels: Mapping[str, str] | None = None,
                    bins=30, size: float = PANEL_INCHES, suptitle: str | None = None) -> None:
    """One histogram panel per quantity, each overlaying several samples.

    Parameters
    ----------
    groups : mapping of panel title -> (mapping of label -> values)
        E.g. ``{"turning angle": {"example": a0, "synthesized": a1}, "radius": {...}}``.
    xlabels : mapping of panel title -> x-axis label, optional
        The quantity's name is the label by default.
    bins : int or sequence of edges
        Shared by the samples of one panel (see :func:`hist_panel`).
    size : float
        Width of one panel in inches.
    suptitle : str, optional
        A title over the whole figure.

    Raises
    ------
    TypeError
        ``groups`` is not a non-empty mapping.

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb import plot
    >>> rng = np.random.default_rng(0)
    >>> plot.show_histograms({"turning angle": {"example": rng.normal(0, 0.1, 200), "result": rng.normal(0, 0.2, 200)}},
    ...                      xlabels={"turning angle": "angle (rad)"})
    >>> plot.close("all")
    """
    if not isinstance(groups, Mapping) or not groups:
        raise TypeError("groups must be a non-empty mapping of title -> samples")
    xlabels = dict(xlabels or {})
    fig, axes = panels(len(groups), size=size, height=size * 0.7, suptitle=suptitle)
    for ax, (title, samples) in zip(axes, groups.items()):
        hist_panel(ax, samples, bins=bins, xlabel=xlabels.get(title, title), title=title)
    fig.tight_layout()
    plt.show()


def legend_patches(ax, colors: Mapping[str, Sequence[float] | str], *, title: str | None = None,
                   loc: str = "upper right", outside: bool = False):
    """A legend of coloured squares for colours that code a category.

    For pictures whose colours mean something (branch generation, leaf layer,
    stroke pair) but carry no plotted artist to label.

    Parameters
    ----------
    ax : matplotlib.axes.Axes
        The panel the legend goes on.
    colors : mapping of label -> colour
        A colour is an RGB(A) triple in [0, 1] or any matplotlib colour string.
    title : str, optional
        Legend title, e.g. ``"generation"``.
    loc : str
        Legend position (matplotlib's ``loc``).
    outside : bool
        Put the legend to the right of the axes, so it hides no pixel of the image.

    Returns
    -------
    matplotlib.legend.Legend

    Examples
    --------
    >>> import numpy as np
    >>> from branchnb import plot
    >>> fig, axes = plot.panels(1)
    >>> _ = plot.image_panel(axes[0], np.zeros((8, 8, 3), np.float32), "structure")
    >>> leg = plot.legend_patches(axes[0], {"root": (0.1, 0.6, 0.2), "children": "tab:blue"}, title="generation")
    >>> [t.get_text() for t in leg.get_texts()]
    ['root', 'children']
    >>> plot.close(fig)
    """
    from matplotlib.colors import to_rgba
    from matplotlib.patches import Patch

    if not isinstance(colors, Mapping) or not colors:
        raise TypeError("colors must be a non-empty mapping of label -> colour")
    handles = []
    for label, colour in colors.items():
        try:
            rgba = to_rgba(tuple(np.asarray(colour, float).tolist()) if not isinstance(colour, str) else colour)
        except (TypeError, ValueError):
            raise ValueError(f"colors[{label!r}] is not a colour: {colour!r}") from None
        handles.append(Patch(facecolor=rgba, edgecolor="none", label=str(label)))
    kwargs = {"bbox_to_anchor": (1.02, 1.0), "loc": "upper left", "borderaxespad": 0.0} if outside else {"loc": loc}
    return ax.legend(handles=handles, title=title, frameon=not outside, **kwargs)


def close(fig) -> None:
    """Close a figure made with :func:`panels` (scripts and tests that draw many).

    Parameters
    ----------
    fig : matplotlib.figure.Figure or "all"
        The figure, or ``"all"`` for every open figure.

    Examples
    --------
    >>> from branchnb import plot
    >>> fig, _ = plot.panels(1)
    >>> plot.close(fig)
    """
    plt.close(fig)
