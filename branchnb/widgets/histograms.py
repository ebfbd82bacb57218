"""HistogramCompare: several distributions on shared bins, with distances."""

from __future__ import annotations

import ipywidgets as widgets
import numpy as np
from ipycanvas import Canvas

from ..core.histogram import METRICS, HistogramComparison, compare_samples
from ._assets import PixelRatioProbe, backing_ratio
from ._draw import batched
from .feedback import ErrorArea

__all__ = ["HistogramCompare", "PALETTE", "channel_range"]

#: Narrowest column (CSS px) a histogram shrinks to fit; a narrower report is taken for a transient layout.
MIN_FIT = 120

#: Height (CSS px) of a histogram with no data yet.
EMPTY_HEIGHT = 24

PALETTE = ("#1f77b4", "#ff7f0e", "#2ca02c", "#d62728", "#9467bd", "#8c564b")


class HistogramCompare(widgets.VBox):
    """Side-by-side and overlaid histograms of two or more samples on shared bins.

    The first sample is the reference; the caption (``title`` and the
    distance of every other sample to it) sits above the plots, so in a
    stack of histograms each caption reads with the plot below it. Updates redraw the canvas in one
    batched message, so the plot changes in place without flicker.

    Parameters
    ----------
    bins : int
        Number of shared bins.
    metric : str
        ``l1``, ``l2sq``, ``chi2`` or ``emd`` (see :mod:`branchnb.core.histogram`).
    title : str
        Heading of the caption above the plots (none if empty).
    width, height : int
        Canvas size in CSS pixels (narrower where the browser shows it in a
        narrower column: it is redrawn at the width it gets); the backing store has ``pixel_ratio``
        device pixels per CSS pixel (the browser's ``devicePixelRatio``,
        reported by a hidden probe; 2 until it is known), so the plot is
        sharp on HiDPI screens.

    Examples
    --------
    >>> h = HistogramCompare(bins=8)
    >>> h.update([0, 1, 1, 2], [0, 2, 2, 2], labels=["input", "synthesized"])
    >>> round(float(h.comparison.distances[1]), 3)
    1.0
    """

    def __init__(self, *, bins: int = 16, metric: str = "l1", title: str = "",
                 width: int = 640, height: int = 170):
        if metric not in METRICS:
            raise ValueError(f"metric must be one of {sorted(METRICS)}, got {metric!r}")
        if not isinstance(bins, (int, np.integer)) or bins < 1:
            raise ValueError(f"bins must be a positive int, got {bins!r}")
        for arg, v in (("width", width), ("height", height)):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 32 <= v <= 4096:
                raise ValueError(f"{arg} must be an int in [32, 4096] (pixels), got {v!r}")
        self.bins = int(bins)
        self.metric = metric
        self.title = title
        self.comparison: HistogramComparison | None = None
        self.css_width, self.css_height = int(width), int(height)
        self._wanted_width = int(width)
        self.pixel_ratio = 2.0
        self.canvas = Canvas(width=1, height=1)
        self.canvas.layout.max_width = "100%"
        self.caption = widgets.HTML()
        self.errors = ErrorArea()
        self._probe = PixelRatioProbe()
        # Caption first: below its plot it read as the heading of the next plot in a stack.
        super().__init__([self.caption, self.canvas, self.errors, self._probe])
        self.add_class("bnb-hist")
        self.add_class("bnb-fit")
        self.layout.max_width = "100%"
        self.layout.margin = "6px 0 0 0"  # a gap between stacked histograms
        self._probe.observe(self.errors.guard(self._on_probe, action=False), names="ratio")
        self._probe.observe(self.errors.guard(self._on_width, action=False), names="width")
        self._size()

    def _on_probe(self, change) -> None:
        r = backing_ratio(change["new"])
        if r != self.pixel_ratio:
            self.pixel_ratio = r
            self._size()

    def _on_width(self, change) -> None:
        # Narrower than asked for where it is shown: draw at that width (a squeezed canvas blurs).
        avail = int(change["new"])
        if 0 < avail < MIN_FIT:
            return  # a column caught in the middle of a layout pass: keep the size
        w = self._wanted_width if avail <= 0 else min(self._wanted_width, avail)
        if w != self.css_width:
            self.css_width = w
            self._size()

    def resize(self, width: int, height: int | None = None) -> None:
        """Change the plot's size in CSS pixels (e.g. to fit a column) and redraw.

        Parameters
        ----------
        width : int
            New width in CSS pixels, 32 .. 4096.
        height : int, optional
            New height in CSS pixels, 32 .. 4096; unchanged if None.

        Raises
        ------
        ValueError
            If a size is not an int in range.
        """
        for arg, v in (("width", width), ("height", height if height is not None else self.css_height)):
            if isinstance(v, bool) or not isinstance(v, (int, np.integer)) or not 32 <= v <= 4096:
                raise ValueError(f"{arg} must be an int in [32, 4096] (pixels), got {v!r}")
        self.css_width = self._wanted_width = int(width)
        if height is not None:
            self.css_height = int(height)
        self._size()

    def _size(self) -> None:
        r = self.pixel_ratio
        # Without data only the one-line "no data yet" shows: no tall empty box.
        h = self.css_height if self.comparison is not None else EMPTY_HEIGHT
        self.canvas.width = int(round(self.css_width * r))
        self.canvas.height = int(round(h * r))
        self.canvas.layout.width = f"{self.css_width}px"
        self.canvas.layout.height = f"{h}px"
        if self.comparison is None:
            self._draw_empty()
        else:
            self._draw()

    def update(self, *samples, labels=None, range=None) -> None:
        """Bin ``samples`` together (the first is the reference) and redraw.

        Errors (an empty sample, NaN, ...) are shown in the widget's error
        area instead of being raised.

        Parameters
        ----------
        *samples : array_like
            One or more 1-D samples (e.g. turning angles of the input and of
            the result).
        labels : list of str, optional
            One legend name per sample.
        range : (float, float), optional
            Histogram range; the joint min..max by default.
        """
        with self.errors.catch():
            if len(samples) < 1:
                raise ValueError("update needs at least one sample")
            self.show(compare_samples(*samples, labels=labels, bins=self.bins,
                                      range=range, metric=self.metric))

    def show(self, comparison: HistogramComparison) -> None:
        """Draw a precomputed :class:`~branchnb.core.histogram.HistogramComparison`.

        Parameters
        ----------
        comparison : HistogramComparison
            E.g. from :func:`branchnb.core.histogram.compare_samples`; its
            bins and metric are shown as they are.

        Raises
        ------
        TypeError
            If ``comparison`` is not a HistogramComparison.
        """
        if not isinstance(comparison, HistogramComparison):
            raise TypeError("comparison must be a HistogramComparison")
        was_empty = self.comparison is None
        self.comparison = comparison
        if was_empty:
            self._size()  # back to full height (draws)
        else:
            self._draw()

    def clear(self) -> None:
        """Back to "no data yet" (e.g. after the data was removed)."""
        self.comparison = None
        self.caption.value = ""
        self._size()

    def _draw_empty(self) -> None:
        c = self.canvas
        with batched():
            c.clear()
            c.save()
            c.scale(self.pixel_ratio)
            c.fill_style = "#888"
            c.font = "12px sans-serif"
            c.fill_text(f"{self.title}: no data yet" if self.title else "no data yet", 10, 16)
            c.restore()

    def _draw(self) -> None:
        cmp = self.comparison
        k, nb = cmp.hists.shape
        c = self.canvas
        w, h = self.css_width, self.css_height
        panels = k + 1  # one per sample, plus the overlay
        pad, top, bottom = 8, 20, 18
        pw = (w - pad * (panels + 1)) / panels
        ph = h - top - bottom
        ymax = float(cmp.hists.max()) or 1.0
        bw = pw / nb
        with batched():
            c.clear()
            c.save()
            c.scale(self.pixel_ratio)  # draw in CSS pixels; the backing store has pixel_ratio per CSS pixel
            c.font = "12px sans-serif"
            for i in range(panels):
                x0 = pad + i * (pw + pad)
                c.stroke_style = "#bbb"
                c.line_width = 1
                c.stroke_rect(x0, top, pw, ph)
                c.fill_style = "#333"
                name = cmp.labels[i] if i < k else "overlay"
                c.fill_text(name[:28], x0 + 2, top - 6)
                if i < k:
                    heights = cmp.hists[i] / ymax * (ph - 2)
                    xs = x0 + np.arange(nb) * bw
                    c.fill_style = PALETTE[i % len(PALETTE)]
                    c.fill_rects(xs + 0.5, top + ph - heights, max(bw - 1, 1), heights)
                else:
                    for j in range(k):
                        heights = cmp.hists[j] / ymax * (ph - 2)
                        xs = x0 + np.arange(nb + 1) * bw
                        ys = top + ph - np.concatenate([heights, heights[-1:]])
                        step = np.column_stack([np.repeat(xs, 2)[1:-1], np.repeat(ys[:-1], 2)])
                        c.stroke_style = PALETTE[j % len(PALETTE)]
                        c.line_width = 2
                        c.stroke_lines(step)
                c.fill_style = "#666"
                c.fill_text(f"{cmp.edges[0]:.3g}", x0, top + ph + 13)
                c.text_align = "right"
                c.fill_text(f"{cmp.edges[-1]:.3g}", x0 + pw, top + ph + 13)
                c.text_align = "left"
            c.restore()
        rows = " &nbsp; ".join(
            f"<span style='color:{PALETTE[j % len(PALETTE)]}'>&#9632;</span> {cmp.labels[j]} vs "
            f"{cmp.labels[0]}: <b>{self.metric} = {cmp.distances[j]:.3g}</b>"
            for j in range(1, k)
        )
        head = f"<b>{self.title}</b> &nbsp; " if self.title else ""
        self.caption.value = f"<span style='font-size:12px'>{head}{rows}</span>"


def channel_range(samples, channel: int, *, min_width: float = 0.1) -> tuple[float, float]:
    """Histogram range of one colour channel over several ``(P, 3)`` samples.

    The data's own span rather than [0, 1], and centred on the data when
    the span is narrower than ``min_width``: the blue of drawn green trees
    is often exactly 0, so on [0, 1] its one bar sat on the left border and
    the histogram looked empty.

    Parameters
    ----------
    samples : sequence of (P, 3) array_like
        RGB pixel samples in [0, 1] (e.g. of the input trees and the
        variation); empty ones are skipped.
    channel : int
        0, 1 or 2 for red, green, blue.
    min_width : float
        Narrowest range returned.

    Returns
    -------
    (float, float)
        The 0.1 % .. 99.9 % quantiles padded by 2 % and clipped to [0, 1],
        or a ``min_width`` range centred on the data (which may reach below
        0 or above 1); ``(0, 1)`` without data.

    Examples
    --------
    >>> import numpy as np
    >>> channel_range([np.array([[0.1, 0.5, 0.0], [0.2, 0.6, 0.0]])], 2)
    (-0.05, 0.05)
    """
    vals = [np.asarray(p)[:, channel] for p in samples if len(p)]
    if not vals:
        return 0.0, 1.0
    v = np.concatenate(vals)
    lo, hi = float(np.quantile(v, 0.001)), float(np.quantile(v, 0.999))
    if hi - lo < min_width:
        mid = 0.5 * (lo + hi)
        return round(mid - 0.5 * min_width, 6), round(mid + 0.5 * min_width, 6)
    pad = 0.02 * (hi - lo)
    return max(0.0, lo - pad), min(1.0, hi + pad)
