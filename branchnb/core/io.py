"""Reading and writing images in the project convention.

Every image the package reads from a file or from bytes goes through
:func:`imread` / :func:`imdecode`: the size the file *declares* is read from
its header (PNG's IHDR, or Pillow's lazy open for JPEG, TIFF, WebP, BMP, ...)
and checked against :data:`MAX_IMAGE_PIXELS` before a single pixel is
decoded, so a small hostile file declaring 30000 x 30000 pixels is refused
at once instead of growing into gigabytes.
"""

from __future__ import annotations

import io
import os
import re
import struct
import warnings
from pathlib import Path

import cv2
import numpy as np

from .image import as_float_image, to_uint8

__all__ = ["imread", "imdecode", "imsave", "encode_png", "image_size", "check_image_file", "MAX_IMAGE_PIXELS"]


def _env_limit() -> int:
    text = os.environ.get("BRANCHNB_MAX_IMAGE_PIXELS", "")
    try:
        value = int(text) if text.strip() else 0
    except ValueError:
        value = 0
    return value if value > 0 else 2**26


#: Largest image (width x height) the readers decode: 2**26 = 8192 x 8192 by
#: default (about 1 GB as float32 RGBA). Set the environment variable
#: ``BRANCHNB_MAX_IMAGE_PIXELS`` (it reaches Dask workers too), assign this
#: attribute, or pass ``max_pixels=`` to a reader to change it.
MAX_IMAGE_PIXELS: int = _env_limit()

_PNG_SIGNATURE = b"\x89PNG\r\n\x1a\n"
_PIL_PIXELS = re.compile(r"\((\d+) pixels\)")


def _opencv_u8(image) -> np.ndarray:
    """uint8 in OpenCV's channel order (BGR / BGRA)."""
    u8 = to_uint8(image)
    if u8.ndim == 3:
        code = cv2.COLOR_RGBA2BGRA if u8.shape[2] == 4 else cv2.COLOR_RGB2BGR
        u8 = cv2.cvtColor(u8, code)
    return u8


def encode_png(image, *, palette: bool = False) -> bytes:
    """Encode an image (any layout accepted by ``as_float_image``) as PNG bytes (lossless).

    Parameters
    ----------
    image : array_like
        Gray, RGB or RGBA; uint8/uint16/bool or float in [0, 1]. Written as
        8 bits per channel (alpha kept).
    palette : bool
        Write an RGB image of at most 256 colours as an indexed (palette) PNG, one byte a
        pixel: the same pixels, a third to a tenth of the bytes on a banded map (a plan's
        visiting order stored in a notebook). Other images are written as usual.

    Returns
    -------
    bytes
        The PNG file's content.

    Examples
    --------
    >>> import numpy as np
    >>> encode_png(np.zeros((2, 2, 3)))[:4]
    b'\\x89PNG'
    """
    if palette:
        packed = _palette_png(to_uint8(image))
        if packed is not None:
            return packed
    ok, buf = cv2.imencode(".png", _opencv_u8(image))
    if not ok:  # pragma: no cover - OpenCV failure
        raise RuntimeError("PNG encoding failed")
    return buf.tobytes()


def _palette_png(u8: np.ndarray) -> bytes | None:
    """An indexed PNG of the uint8 RGB image ``u8``, or None (not RGB, or over 256 colours)."""
    if u8.ndim != 3 or u8.shape[2] != 3:
        return None
    packed = (u8[..., 0].astype(np.uint32) << 16) | (u8[..., 1].astype(np.uint32) << 8) | u8[..., 2]
    # a sparse sample first: a photo or a shaded rendering is refused without sorting it all
    if np.unique(packed[::7, ::7]).size > 256:
        return None
    colours, index = np.unique(packed, return_inverse=True)
    if colours.size > 256:
        return None
    from PIL import Image

    im = Image.fromarray(index.reshape(u8.shape[:2]).astype(np.uint8), mode="P")
    rgb = np.stack([(colours >> 16) & 255, (colours >> 8) & 255, colours & 255], 1).astype(np.uint8)
    im.putpalette(rgb.ravel().tolist())
    buf = io.BytesIO()
    im.save(buf, format="PNG", optimize=True)
    return buf.getvalue()


def imsave(path, image) -> Path:
    """Save an image to ``path`` (format from the suffix; PNG keeps alpha).

    Parameters
    ----------
    path : str or os.PathLike
        Destination file; its suffix (``.png``, ``.jpg``, ``.tif``, ...)
        chooses the format. An existing file is overwritten.
    image : array_like
        Gray, RGB or RGBA; uint8/uint16/bool or float in [0, 1]. Saved as
        8 bits per channel.

    Returns
    -------
    pathlib.Path
        ``path``.

    Raises
    ------
    ValueError
        If OpenCV cannot write the file (unknown suffix, missing folder).

    Examples
    --------
    >>> import numpy as np, tempfile, os
    >>> imsave(os.path.join(tempfile.mkdtemp(), "a.png"), np.zeros((2, 2))).name
    'a.png'
    """
    path = Path(path)
    if not cv2.imwrite(str(path), _opencv_u8(image)):
        raise ValueError(f"could not write image to {path}")
    return path


def _limit(max_pixels) -> int:
    if max_pixels is None:
        return int(MAX_IMAGE_PIXELS)
    if isinstance(max_pixels, bool) or not isinstance(max_pixels, (int, np.integer)) or max_pixels < 1:
        raise ValueError(f"max_pixels must be an int >= 1, got {max_pixels!r}")
    return int(max_pixels)


def _header_size(f, name: str) -> tuple[int, int, str]:
    """``(width, height, format)`` declared by the header of the open binary file ``f`` (no decoding)."""
    head = f.read(32)
    if not head:
        raise ValueError(f"could not read an image from {name}: the file is empty")
    if head.startswith(_PNG_SIGNATURE):
        if len(head) < 24 or head[12:16] != b"IHDR":
            raise ValueError(f"could not read an image from {name}: a PNG without its IHDR header (truncated?)")
        w, h = struct.unpack(">II", head[16:24])
        return int(w), int(h), "PNG"
    if head.startswith(b"\xff\xd8"):
        f.seek(0)
        size = _jpeg_size(f)
        if size is not None:
            return size[0], size[1], "JPEG"
    f.seek(0)
    from PIL import Image, UnidentifiedImageError

    try:
        with warnings.catch_warnings():
            warnings.simplefilter("ignore", Image.DecompressionBombWarning)
            with Image.open(f) as im:  # lazy: reads the header only
                return int(im.size[0]), int(im.size[1]), str(im.format)
    except Image.DecompressionBombError as exc:
        m = _PIL_PIXELS.search(str(exc))
        pixels = int(m.group(1)) if m else -1
        return pixels, 1, "?"  # only the product is known; the caller reports it
    except UnidentifiedImageError:
        raise ValueError(f"could not read an image from {name}: not an image format Pillow or OpenCV "
                         f"recognise (the file starts with {head[:12]!r})") from None
    except (OSError, SyntaxError, struct.error, ValueError) as exc:
        raise ValueError(f"could not read an image from {name}: its header is damaged ({exc})") from None


def _jpeg_size(f) -> tuple[int, int] | None:
    """Width and height from a JPEG's first SOF marker (None if not found: Pillow then decides)."""
    f.seek(2)
    for _ in range(10_000):  # markers before the frame header; a bound against a looping file
        b = f.read(1)
        while b == b"\xff":
            b = f.read(1)
        if not b:
            return None
        marker = b[0]
        if marker in (0x01, *range(0xD0, 0xD8)):  # stand-alone markers carry no length
            continue
        seg = f.read(2)
        if len(seg) < 2:
            return None
        length = struct.unpack(">H", seg)[0]
        if marker in (0xC0, 0xC1, 0xC2, 0xC3, 0xC5, 0xC6, 0xC7, 0xC9, 0xCA, 0xCB, 0xCD, 0xCE, 0xCF):
            frame = f.read(5)
            if len(frame) < 5:
                return None
            h, w = struct.unpack(">HH", frame[1:5])
            return int(w), int(h)
        if length < 2:
            return None
        f.seek(length - 2, 1)
    return None


def _check_size(w: int, h: int, fmt: str, name: str, limit: int) -> None:
    if w < 1 or h < 1:
        raise ValueError(f"could not read an image from {name}: its header declares {w} x {h} pixels")
    if w * h > limit:
        size = f"{w} x {h} = {w * h:,} pixels" if fmt != "?" else f"{w:,} pixels"
        raise ValueError(f"refusing to decode {name}: it declares {size}, above the limit of {limit:,} "
                         "(branchnb.core.io.MAX_IMAGE_PIXELS, env BRANCHNB_MAX_IMAGE_PIXELS, or max_pixels=)")


def image_size(source, *, name: str | None = None) -> tuple[int, int]:
    """``(width, height)`` an image file or bytes declares in its header, without decoding it.

    Parameters
    ----------
    source : str, Path, bytes
        A file path, or the file's content.
    name : str, optional
        What error messages call the image (default: the path, or ``"image"``).

    Returns
    -------
    (int, int)
        ``(width, height)`` in pixels.

    Raises
    ------
    ValueError
        Missing, empty or unreadable file, or not an image.

    Examples
    --------
    >>> image_size(encode_png(np.zeros((3, 5), np.float32)))
    (5, 3)
    """
    if isinstance(source, (bytes, bytearray, memoryview)):
        w, h, fmt = _header_size(io.BytesIO(bytes(source)), name or "image")
    else:
        path = _check_path(source)
        with path.open("rb") as f:
            w, h, fmt = _header_size(f, name or str(path))
    if fmt == "?":
        raise ValueError(f"{name or source}: declares {w:,} pixels, too many to report a size")
    return w, h


def check_image_file(path, *, max_pixels: int | None = None) -> tuple[int, int]:
    """Make every check :func:`imread` makes before decoding, without decoding: ``(width, height)``.

    Lets a caller that will read many files (a library folder) refuse a bad
    one before it has decoded any of the others.

    Parameters
    ----------
    path : str or Path
        The image file to check; only its header is read.
    max_pixels : int, optional
        As in :func:`imread`.

    Returns
    -------
    (int, int)
        ``(width, height)`` the header declares.

    Raises
    ------
    ValueError
        As :func:`imread` for a missing, empty, unrecognised or damaged
        header, or a file declaring more than ``max_pixels`` pixels.

    Examples
    --------
    >>> import tempfile, os
    >>> p = os.path.join(tempfile.mkdtemp(), "a.png")
    >>> _ = imsave(p, np.ones((4, 6, 3), np.float32))
    >>> check_image_file(p)
    (6, 4)
    >>> check_image_file(p, max_pixels=10)
    Traceback (most recent call last):
    ...
    ValueError: refusing to decode ...a.png: it declares 6 x 4 = 24 pixels, above the limit of 10 ...
    """
    limit = _limit(max_pixels)
    path = _check_path(path)
    name = str(path)
    with path.open("rb") as f:
        w, h, fmt = _header_size(f, name)
    _check_size(w, h, fmt, name, limit)
    return w, h


def _check_path(path) -> Path:
    if not isinstance(path, (str, os.PathLike)) or str(path) == "":
        raise TypeError(f"path must be a file path (str or Path), got {type(path).__name__}")
    path = Path(path)
    try:
        if path.is_dir():
            raise ValueError(f"could not read an image from {path}: it is a folder")
        with path.open("rb"):
            pass
    except OSError as exc:
        raise ValueError(f"could not read an image from {path}: {exc.strerror or exc}") from None
    return path


def _decode(read, name: str) -> np.ndarray:
    """Run OpenCV's decoder ``read()`` (the size is already checked) and convert its result."""
    try:
        raw = read()
    except cv2.error as exc:
        raise ValueError(f"could not read an image from {name}: OpenCV refused it ({exc.err})") from None
    if raw is None:
        raise ValueError(f"could not read an image from {name}: the image data is damaged, truncated or in "
                         "a variant OpenCV cannot decode")
    return _to_float(raw, name)


def _to_float(raw, name: str) -> np.ndarray:
    if raw.ndim == 3:
        if raw.shape[2] == 4:
            raw = cv2.cvtColor(raw, cv2.COLOR_BGRA2RGBA)
        elif raw.shape[2] == 3:
            raw = cv2.cvtColor(raw, cv2.COLOR_BGR2RGB)
    return as_float_image(raw, name=name)


def imread(path, *, max_pixels: int | None = None) -> np.ndarray:
    """Read an image file as float32 in [0, 1], (H, W, C), RGB(A) order.

    Parameters
    ----------
    path : str or Path
        Image file (PNG, JPEG, TIFF, BMP, WebP, ...).
    max_pixels : int, optional
        Refuse files declaring more pixels than this (default
        :data:`MAX_IMAGE_PIXELS`); checked on the header, before decoding.

    Returns
    -------
    (H, W, C) float32 ndarray, C in {1, 3, 4}.

    Raises
    ------
    ValueError
        The file is missing, a folder, empty, not an image, damaged, or
        declares more than ``max_pixels`` pixels; the message names the file
        and says which.

    Examples
    --------
    >>> import tempfile, os
    >>> p = os.path.join(tempfile.mkdtemp(), "a.png")
    >>> _ = imsave(p, np.ones((4, 6, 3), np.float32))
    >>> imread(p).shape
    (4, 6, 3)
    """
    limit = _limit(max_pixels)
    path = _check_path(path)
    name = str(path)
    with path.open("rb") as f:
        _check_size(*_header_size(f, name), name, limit)
    return _decode(lambda: cv2.imread(name, cv2.IMREAD_UNCHANGED), name)


def imdecode(data, *, name: str = "image", max_pixels: int | None = None) -> np.ndarray:
    """Decode an image file's bytes (e.g. an upload) like :func:`imread`.

    Parameters
    ----------
    data : bytes
        The content of a PNG, JPEG, TIFF, WebP, BMP, ... file.
    name : str, optional
        What error messages call it (e.g. the uploaded file's name).
    max_pixels : int, optional
        As in :func:`imread`.

    Returns
    -------
    (H, W, C) float32 ndarray
        In [0, 1], RGB(A) order, C in {1, 3, 4}.

    Raises
    ------
    TypeError
        If ``data`` is not bytes.
    ValueError
        Not an image, or more pixels than ``max_pixels``.

    Examples
    --------
    >>> imdecode(encode_png(np.zeros((2, 3, 4), np.float32))).shape
    (2, 3, 4)
    """
    if not isinstance(data, (bytes, bytearray, memoryview)):
        raise TypeError(f"data must be bytes, got {type(data).__name__}")
    limit = _limit(max_pixels)
    data = bytes(data)
    _check_size(*_header_size(io.BytesIO(data), name), name, limit)
    return _decode(lambda: cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED), name)
