"""ImageView: one or several numpy images side by side, lossless by default."""

from __future__ import annotations

import cv2
import ipywidgets as widgets

from ..core.image import to_uint8
from ..core.io import encode_png

__all__ = ["ImageView"]


def _encode(image, fast: bool) -> tuple[bytes, str]:
    if not fast:
        return encode_png(image), "png"
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
    titles : sequence of str
    fast : bool
    width : int
        Display width of each image in pixels.

    Examples
    --------
    >>> import numpy as np
    >>> v = ImageView([np.zeros((4, 4, 3)), np.ones((4, 4, 3))], titles=["a", "b"])
    >>> [t.value for t in v.titles]
    ['a', 'b']
    """

    def __init__(self, images=(), titles=(), *, fast: bool = False, width: int = 320):
        super().__init__(layout=widgets.Layout(flex_flow="row wrap"))
        self.fast = bool(fast)
        self.width = int(width)
        self.images: list[widgets.Image] = []
        self.titles: list[widgets.Label] = []
        if len(images):
            self.update(images, titles)

    def update(self, images, titles=None) -> None:
        """Replace the images (widgets are reused when the count is unchanged)."""
        images = list(images) if not hasattr(images, "ndim") else [images]
        if titles is None:
            titles = [t.value for t in self.titles][: len(images)]
        titles = list(titles) + [""] * (len(images) - len(titles))
        if len(self.images) != len(images):
            self.images = [widgets.Image(layout=widgets.Layout(width=f"{self.width}px",
                                                               object_fit="contain"))
                           for _ in images]
            self.titles = [widgets.Label(style={"font_weight": "bold"}) for _ in images]
            self.children = [widgets.VBox([t, im]) for t, im in zip(self.titles, self.images)]
        for i, (img, title) in enumerate(zip(images, titles)):
            data, fmt = _encode(img, self.fast)
            self.images[i].format = fmt
            self.images[i].value = data
            self.titles[i].value = str(title)
