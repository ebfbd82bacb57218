"""ImageView: one or several numpy images side by side, lossless by default."""

from __future__ import annotations

import html

import cv2
import ipywidgets as widgets
import numpy as np

from ..core.image import as_float_image, to_uint8
from ..core.io import encode_png

__all__ = ["ImageView"]

#: Narrowest useful width (CSS px) of an image cell before the cells wrap onto another row.
MIN_CELL = 180


def _encode(image, fast: bool) -> tuple[bytes, str]:
    if not fast:  # a banded map or a line drawing of few colours goes as a palette PNG
        return encode_png(image, palette=True), "png"
    u8 = to_uint8(image)
    if u8.ndim == 3 and u8.shape[2] == 4:
        return encode_png(image), "png"  # JPEG has no alpha
    if u8.ndim == 3:
        u8 = cv2.cvtColor(u8, cv2.COLOR_RGB2BGR)
    ok, buf = cv2.imencode(".jpg", u8, [cv2.IMWRITE_JPEG_QUALITY, 90])
    return buf.tobytes(), "jpeg"


class ImageView(widgets.HBox):
    """Show numpy images side by side with titles; update in place.

    Images are sent as PNG (lossless) so that what you see is what the
    array holds; ``fast=True`` sends JPEG (quality 90) for big previews
    where speed matters more (ipycanvas' own ``put_image_data`` would send
    RGB as JPEG quality 75).

    Parameters
    ----------
    images : sequence of (H, W, C) array_like
        The images, any layout :func:`branchnb.core.image.as_float_image`
        accepts (a single array is one image).
    titles : sequence of str
        One title per image (missing ones are empty).
    fast : bool
        Send JPEG (quality 90) instead of lossless PNG.
    width : int
        Display width of each image in CSS pixels; a narrower image is shown
        at its own size, never enlarged (click an image in the browser to
        see it at its own resolution, or twice its size when it is small).
    max_size : int, optional
        Shrink images whose long side exceeds this before sending them
        (e.g. twice ``width`` for sharp HiDPI display without sending a
        full-size image on every slider move); None sends them as they are.

    Examples
    --------
    >>> import numpy as np
    >>> v = ImageView([np.zeros((4, 4, 3)), np.ones((4, 4, 3))], titles=["a", "b"])
    >>> v.title_texts
    ['a', 'b']
    """

    def __init__(self, images=(), titles=(), *, fast: bool = False, width: int = 320,
                 max_size: int | None = None):
        super().__init__(layout=widgets.Layout(flex_flow="row wrap", max_width="100%", width="100%",
                                               align_items="flex-start"))
        self.add_class("bnb-view")
        if isinstance(width, bool) or not isinstance(width, int) or width < 16:
            raise ValueError(f"width must be an int >= 16 (pixels), got {width!r}")
        if max_size is not None and (isinstance(max_size, bool) or not isinstance(max_size, int)
                                     or max_size < 16):
            raise ValueError(f"max_size must be None or an int >= 16, got {max_size!r}")
        self.fast = bool(fast)
        self.width = int(width)
        self.max_size = max_size
        self.images: list[widgets.Image] = []
        self.titles: list[widgets.HTML] = []
        self._title_text: list[str] = []
        #: Whether :meth:`mark_stale` greyed the images (until the next :meth:`update`).
        self.stale = False
        if len(images):
            self.update(images, titles)

    def mark_stale(self, note: str = "out of date") -> None:
        """Mark the shown images as no longer matching the input (greyed, titles prefixed with ``note``).

        The next :meth:`update` clears the mark.

        Parameters
        ----------
        note : str
            Prefix of every title (``"out of date: result"``); titles that
            already start with it are left as they are.
        """
        self.stale = True
        self.add_class("bnb-stale")
        for i, t in enumerate(self.title_texts):
            if not t.startswith(note):
                self.set_title(i, f"{note}: {t}" if t else note)

    def update(self, images, titles=None) -> None:
        """Replace the images (widgets are reused when the count is unchanged).

        Clears a :meth:`mark_stale` mark.

        Parameters
        ----------
        images : sequence of (H, W, C) array_like or array
            The new images (a single array is one image).
        titles : sequence of str, optional
            New titles; the current ones are kept if None (empty for new
            images).
        """
        if self.stale:
            self.stale = False
            self.remove_class("bnb-stale")
        images = list(images) if not hasattr(images, "ndim") else [images]
        if titles is None:
            titles = self.title_texts[: len(images)]
        titles = list(titles) + [""] * (len(images) - len(titles))
        if len(self.images) != len(images):
            self.images = [widgets.Image(layout=widgets.Layout(width="100%", max_width=f"{self.width}px",
                                                               object_fit="contain",
                                                               border="1px solid #ddd"))
                           for _ in images]
            self.titles = [widgets.HTML(layout=widgets.Layout(width="100%")) for _ in images]
            self._title_text = [""] * len(images)
            # Cells share the row: as many side by side as fit at a useful size (at least
            # MIN_CELL px), each at most ``width`` px; they wrap, and shrink in a narrow column.
            basis = min(self.width, MIN_CELL)
            self.children = [widgets.VBox([t, im], layout=widgets.Layout(
                flex=f"1 1 {basis}px", max_width=f"{self.width}px", min_width="0", margin="0 6px 4px 0"))
                for t, im in zip(self.titles, self.images)]
        for i, (img, title) in enumerate(zip(images, titles)):
            self._put(i, img)
            self.set_title(i, title)

    def update_one(self, index: int, image, title: str | None = None) -> None:
        """Replace one image (and its title) in place.

        Parameters
        ----------
        index : int
            Position of the image, ``0 <= index < len(images)``.
        image : (H, W, C) array_like
            The new image.
        title : str, optional
            New title; unchanged if None.

        Raises
        ------
        ValueError
            If ``index`` is out of range.
        """
        if not 0 <= index < len(self.images):
            raise ValueError(f"index {index} out of range for {len(self.images)} images")
        self._put(index, image)
        if title is not None:
            self.set_title(index, title)

    def _put(self, i: int, image) -> None:
        small = self._shrink(image)
        data, fmt = _encode(small, self.fast)
        w = np.asarray(small).shape[1] if np.ndim(small) >= 2 else self.width
        # Never enlarged: an image narrower than the view width is shown at its own size
        # (a click on it enlarges it, see the kit's stylesheet).
        width = f"{min(self.width, int(w))}px"
        if self.images[i].layout.max_width != width:
            self.images[i].layout.max_width = width
        self.images[i].format = fmt
        self.images[i].value = data

    def set_title(self, index: int, title: str) -> None:
        """Change one image's title (e.g. to mark it out of date).

        Parameters
        ----------
        index : int
            Position of the image; an index out of range is ignored.
        title : str
            The new title (plain text, escaped).
        """
        if not 0 <= index < len(self.titles):
            return
        self.titles[index].value = (f"<div class='bnb-view-title' style='font-size:12px;font-weight:600;"
                                    f"line-height:15px'>{html.escape(str(title))}</div>")
        self._title_text += [""] * (len(self.titles) - len(self._title_text))
        self._title_text[index] = str(title)

    @property
    def title_texts(self) -> list[str]:
        return list(self._title_text[: len(self.titles)])

    def _shrink(self, image):
        if self.max_size is None:
            return image
        a = np.asarray(image)
        if a.ndim < 2 or max(a.shape[:2]) <= self.max_size:
            return image
        h, w = a.shape[:2]
        s = self.max_size / max(h, w)
        a = as_float_image(a, name="image")
        return cv2.resize(a, (max(1, round(w * s)), max(1, round(h * s))), interpolation=cv2.INTER_AREA)
