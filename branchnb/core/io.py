"""Reading and writing images in the project convention."""

from __future__ import annotations

from pathlib import Path

import cv2
import numpy as np

from .image import as_float_image, to_uint8

__all__ = ["imread", "imsave", "encode_png"]


def _opencv_u8(image) -> np.ndarray:
    """uint8 in OpenCV's channel order (BGR / BGRA)."""
    u8 = to_uint8(image)
    if u8.ndim == 3:
        code = cv2.COLOR_RGBA2BGRA if u8.shape[2] == 4 else cv2.COLOR_RGB2BGR
        u8 = cv2.cvtColor(u8, code)
    return u8


def encode_png(image) -> bytes:
    """Encode an image (any layout accepted by ``as_float_image``) as PNG bytes (lossless)."""
    ok, buf = cv2.imencode(".png", _opencv_u8(image))
    if not ok:  # pragma: no cover - OpenCV failure
        raise RuntimeError("PNG encoding failed")
    return buf.tobytes()


def imsave(path, image) -> Path:
    """Save an image to ``path`` (format from the suffix; PNG keeps alpha)."""
    path = Path(path)
    if not cv2.imwrite(str(path), _opencv_u8(image)):
        raise ValueError(f"could not write image to {path}")
    return path


def imread(path) -> np.ndarray:
    """Read an image file as float32 in [0, 1], (H, W, C), RGB(A) order."""
    raw = cv2.imread(str(path), cv2.IMREAD_UNCHANGED)
    if raw is None:
        raise ValueError(f"could not read an image from {path}")
    if raw.ndim == 3:
        code = cv2.COLOR_BGRA2RGBA if raw.shape[2] == 4 else cv2.COLOR_BGR2RGB
        raw = cv2.cvtColor(raw, code)
    return as_float_image(raw, name=str(path))
