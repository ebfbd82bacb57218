"""Open, save and load annotations: the same three buttons in every app.

:class:`FileBar` gives an app

- **open image**: a file upload; the chosen image(s) are decoded to the
  project's float32 RGB(A) arrays and handed to the app's ``open`` hook;
- **save**: what the app makes (its ``outputs`` hook: file name -> PNG,
  SVG, glTF or JSON content) plus its annotations (the ``annotations``
  hook) are checked (a PNG must decode, JSON and glTF must parse, an SVG
  must be well-formed XML) and written into a folder; each file also gets
  a download link, which is how a page served by ``branchnb app`` (Voilà)
  hands files to its user;
- **load annotations**: a JSON file written by "save" (or by
  :func:`canvases_json`) goes to the app's ``load`` hook.

The hooks are plain callables, so each app adds only a few lines; scripts
call :meth:`FileBar.save`, :meth:`FileBar.open_files` and
:meth:`FileBar.load_text` directly.

Examples
--------
>>> import numpy as np, tempfile
>>> from branchnb.widgets.feedback import ErrorArea
>>> bar = FileBar(errors=ErrorArea(), name="demo", outputs=lambda: {"grey.png": np.full((4, 4, 3), 0.5)},
...               annotations=lambda: '{"shapes": []}')
>>> bar.folder.value = tempfile.mkdtemp()
>>> sorted(p.name for p in bar.save())
['demo_annotations.json', 'demo_grey.png']
"""

from __future__ import annotations

import base64
import html
import json
import os
import xml.etree.ElementTree as ET
from collections.abc import Callable, Mapping
from pathlib import Path

import cv2
import ipywidgets as widgets
import numpy as np

from ..core.image import as_float_image
from ..core.io import encode_png

__all__ = ["FileBar", "decode_image", "check_file", "canvases_json", "load_canvases"]

#: Files larger than this get no download link (a data URL of that size would stall the page).
LINK_LIMIT = 40 * 2**20

_MIME = {".png": "image/png", ".svg": "image/svg+xml", ".json": "application/json",
         ".gltf": "model/gltf+json", ".bin": "application/octet-stream", ".txt": "text/plain"}


def decode_image(data, name: str = "image") -> np.ndarray:
    """Decode image file bytes (PNG, JPEG, TIFF, BMP, WebP ...) to float32 RGB(A) in [0, 1].

    Parameters
    ----------
    data : bytes-like
        The file's content (as an upload widget gives it).
    name : str
        The file name, for error messages.

    Returns
    -------
    (H, W, C) float32 ndarray
        C = 1 for gray files, 3 for colour, 4 with alpha; 8- and 16-bit
        files are scaled to [0, 1].

    Raises
    ------
    ValueError
        The bytes are no image OpenCV can read; the message names the file.

    Examples
    --------
    >>> decode_image(encode_png(np.ones((2, 3, 3)))).shape
    (2, 3, 3)
    """
    buf = np.frombuffer(bytes(data), np.uint8)
    raw = cv2.imdecode(buf, cv2.IMREAD_UNCHANGED) if buf.size else None
    if raw is None:
        raise ValueError(f"{name}: not an image file that can be read (PNG, JPEG, TIFF, BMP or WebP)")
    if raw.ndim == 3:
        raw = cv2.cvtColor(raw, cv2.COLOR_BGRA2RGBA if raw.shape[2] == 4 else cv2.COLOR_BGR2RGB)
    return as_float_image(raw, name=name)


def _strict_json(text: str, name: str):
    def reject(token):
        raise ValueError(f"{name}: {token} is not valid JSON")

    try:
        return json.loads(text, parse_constant=reject)
    except json.JSONDecodeError as exc:
        raise ValueError(f"{name}: not valid JSON ({exc})") from None


def check_file(name: str, data: bytes, siblings: Mapping[str, bytes] | None = None) -> None:
    """Raise ``ValueError`` unless ``data`` is a valid file of the kind its name says.

    PNG: decodes. JSON: parses (no NaN or Infinity). SVG: well-formed XML
    with an ``<svg>`` root. glTF: JSON with ``asset.version == "2.0"``,
    whose external ``uri`` s are among ``siblings`` (the other files
    written with it). Other suffixes are not checked.

    Parameters
    ----------
    name : str
        File name; its suffix (case-insensitive) says what ``data`` must be.
    data : bytes
        The content about to be written.
    siblings : mapping of str to bytes, optional
        Files written together with it, by name (for a glTF's buffers and
        images).

    Raises
    ------
    ValueError
        Naming the file and what is wrong with it.

    Examples
    --------
    >>> check_file("a.json", b'{"x": 1}')
    >>> check_file("a.json", b'{"x": NaN}')
    Traceback (most recent call last):
    ...
    ValueError: a.json: NaN is not valid JSON
    """
    ext = Path(name).suffix.lower()
    if ext == ".png":
        if cv2.imdecode(np.frombuffer(data, np.uint8), cv2.IMREAD_UNCHANGED) is None:
            raise ValueError(f"{name}: the PNG does not decode")
    elif ext in (".json", ".gltf"):
        d = _strict_json(data.decode("utf-8"), name)
        if ext == ".gltf":
            if not isinstance(d, dict) or str(d.get("asset", {}).get("version")) != "2.0":
                raise ValueError(f"{name}: not a glTF 2.0 file (asset.version is not '2.0')")
            for key in ("buffers", "images"):
                for item in d.get(key, []):
                    uri = item.get("uri", "")
                    if uri and not uri.startswith("data:") and uri not in (siblings or {}):
                        raise ValueError(f"{name}: {key} refers to {uri!r}, which is not written with it")
    elif ext == ".svg":
        try:
            root = ET.fromstring(data)
        except ET.ParseError as exc:
            raise ValueError(f"{name}: not well-formed SVG ({exc})") from None
        if not root.tag.endswith("svg"):
            raise ValueError(f"{name}: the root element is <{root.tag}>, not <svg>")


def _as_bytes(name: str, content) -> bytes:
    if isinstance(content, (bytes, bytearray, memoryview)):
        return bytes(content)
    if isinstance(content, str):
        return content.encode("utf-8")
    if isinstance(content, np.ndarray) and Path(name).suffix.lower() == ".png":
        return encode_png(content)
    if isinstance(content, (dict, list)):
        return json.dumps(content, allow_nan=False, indent=1).encode("utf-8")
    raise TypeError(f"output {name!r}: give bytes, str, a dict, or an image array for a .png, "
                    f"got {type(content).__name__}")


def _safe_name(name: str) -> str:
    if not isinstance(name, str) or not name or "/" in name or "\\" in name or name.startswith("."):
        raise ValueError(f"output file name must be a plain file name, got {name!r}")
    return name


def canvases_json(canvases: Mapping, *, app: str = "", extra: Mapping | None = None) -> str:
    """The annotations of several canvases (name -> AnnotationCanvas or AnnotationModel) as one JSON text.

    ``extra`` holds what else the app needs to restore its work (layer
    names and colours, weights, ...); it must be plain JSON.

    Parameters
    ----------
    canvases : mapping
        Canvas name -> :class:`~branchnb.widgets.canvas.AnnotationCanvas`
        or :class:`~branchnb.widgets.model.AnnotationModel`.
    app : str
        Name of the app that writes it; :func:`load_canvases` refuses files
        of another app.
    extra : mapping, optional
        Other state, plain JSON with finite numbers.

    Returns
    -------
    str
        ``{"format": "branchnb-annotations", "version": 1, "app", "canvases", "extra"}``.

    Raises
    ------
    ValueError, TypeError
        If ``extra`` holds NaN/inf or objects JSON cannot hold.

    Examples
    --------
    >>> from branchnb.widgets.model import AnnotationModel
    >>> src, dst = AnnotationModel(), AnnotationModel()
    >>> src.add_shape("point", [(3, 4)])  # returns its index
    0
    >>> text = canvases_json({"image": src}, app="demo", extra={"seed": 7})
    >>> load_canvases(text, {"image": dst}, app="demo")
    {'seed': 7}
    >>> dst.shapes[0].points.tolist()
    [[3.0, 4.0]]
    """
    d = {"format": "branchnb-annotations", "version": 1, "app": app,
         "canvases": {k: getattr(c, "model", c).to_dict() for k, c in canvases.items()},
         "extra": dict(extra or {})}
    return json.dumps(d, allow_nan=False)


def load_canvases(text, canvases: Mapping, *, app: str = "") -> dict:
    """Restore what :func:`canvases_json` wrote; returns its ``extra``.

    A plain :meth:`AnnotationModel.to_json` text is accepted too (it goes to
    the first canvas). Every canvas is checked before any is changed.

    Parameters
    ----------
    text : str or bytes
        The JSON text (bytes are decoded as UTF-8).
    canvases : mapping
        Canvas name -> canvas or model, as given to :func:`canvases_json`;
        each named in ``text`` is replaced (undoably), the others are kept.
    app : str
        This app's name; a file saved by another app is refused (a file
        without an app name is accepted).

    Returns
    -------
    dict
        The ``extra`` saved with the annotations (empty if none).

    Raises
    ------
    TypeError
        If ``text`` is not text.
    ValueError
        Not annotation JSON, written by another app, or naming a canvas this app does not have.

    Examples
    --------
    >>> from branchnb.widgets.model import AnnotationModel
    >>> m = AnnotationModel()
    >>> load_canvases('{"canvases": {"image": {"shapes": []}}, "app": "trees"}', {"image": m}, app="leaves")
    Traceback (most recent call last):
    ...
    ValueError: annotations: these were saved by the 'trees' app, not 'leaves'
    """
    if isinstance(text, (bytes, bytearray)):
        text = bytes(text).decode("utf-8")
    if not isinstance(text, str):
        raise TypeError(f"text must be the JSON text, got {type(text).__name__}")
    d = _strict_json(text, "annotations")
    if not isinstance(d, dict):
        raise ValueError("annotations: expected a JSON object")
    if "canvases" not in d:
        if "shapes" not in d:
            raise ValueError("annotations: neither 'canvases' (a file saved by an app) nor 'shapes'")
        d = {"canvases": {next(iter(canvases)): d}, "app": app}
    if app and d.get("app") and d["app"] != app:
        raise ValueError(f"annotations: these were saved by the {d['app']!r} app, not {app!r}")
    parts = d["canvases"]
    if not isinstance(parts, dict):
        raise ValueError("annotations: 'canvases' must be an object")
    unknown = set(parts) - set(canvases)
    if unknown:
        raise ValueError(f"annotations: no canvas named {sorted(unknown)}; this app has {list(canvases)}")
    from .model import AnnotationModel

    for v in parts.values():
        AnnotationModel.from_json(v)  # raises before anything changes
    for k, v in parts.items():
        getattr(canvases[k], "model", canvases[k]).load_json(v)
    extra = d.get("extra", {})
    return extra if isinstance(extra, dict) else {}


class FileBar:
    """The open / save / load-annotations controls of one app.

    Parameters
    ----------
    errors : ErrorArea or StatusLine
        Where errors and "wrote ..." messages go.
    name : str
        Prefix of the saved files (``<name>_<output>``).
    open : callable, optional
        ``open(images)`` with a list of ``(file stem, float32 image)``;
        may return a message. No "open image" button without it.
    open_label : str
        Label of the open button (plain text).
    multiple : bool
        Whether several images can be chosen at once (exemplars).
    outputs : callable, optional
        ``outputs() -> {file name: content}`` (bytes, str, dict, or an
        image array for ``.png``) of what the technique made.
    annotations : callable, optional
        ``annotations() -> str`` (JSON), saved as ``<name>_annotations.json``.
    load : callable, optional
        ``load(text)``: restore annotations. No "load annotations" button without it.
    folder : str
        Where "save" writes (relative to the kernel's working folder).

    Examples
    --------
    >>> from branchnb.widgets.feedback import ErrorArea
    >>> bar = FileBar(errors=ErrorArea(), name="demo", outputs=lambda: {"notes.json": {"k": 9}})
    >>> list(bar.contents())
    ['demo_notes.json']
    """

    def __init__(self, *, errors, name: str = "branchnb", open: Callable | None = None,
                 open_label: str = "open image", multiple: bool = False,
                 outputs: Callable | None = None, annotations: Callable | None = None,
                 load: Callable | None = None, folder: str = "branchnb-out"):
        for arg, fn in (("open", open), ("outputs", outputs), ("annotations", annotations), ("load", load)):
            if fn is not None and not callable(fn):
                raise TypeError(f"{arg} must be callable, got {type(fn).__name__}")
        self.errors = errors
        self.name = _safe_name(str(name))
        self._open, self._outputs, self._annotations, self._load = open, outputs, annotations, load
        self.widgets: list[widgets.Widget] = []
        # ipywidgets' upload button always says "<description> (<number of files>)"; the count
        # means nothing here (the files are handed on at once), so the label comes from CSS.
        tag = f"bnb-up-{id(self):x}"
        self._labels: dict[str, str] = {}
        self.upload = None
        if open is not None:
            self.upload = self._upload(f"{tag}-open", open_label, "image/*", "folder-open", multiple)
            self.upload.tooltip = ("load your own image" + ("s (choose several)" if multiple else "")
                                   + "; PNG keeps transparency")
            self.upload.observe(errors.guard(lambda ch: self._uploaded(ch["new"])), names="value")
            self.widgets.append(self.upload)
        self.save_button = None
        self.folder = widgets.Text(value=str(folder), placeholder="folder", tooltip="folder that 'save' "
                                   "writes into (relative to the notebook)",
                                   layout=widgets.Layout(width="150px"))
        if outputs is not None or annotations is not None:
            self.save_button = widgets.Button(description="save", icon="download", layout=widgets.Layout(
                width="auto"), tooltip="write the result and the annotations (PNG/SVG/JSON ...) into the "
                "folder on the right; download links appear below")
            self.save_button.on_click(errors.guard(lambda _b: self._saved()))
            self.widgets += [self.save_button, self.folder]
        self.annotation_upload = None
        if load is not None:
            self.annotation_upload = self._upload(f"{tag}-ann", "load annotations", ".json,application/json",
                                                  "upload", False)
            self.annotation_upload.tooltip = "restore annotations saved earlier (a *_annotations.json)"
            self.annotation_upload.observe(errors.guard(lambda ch: self._annotations_uploaded(ch["new"])),
                                           names="value")
            self.widgets.append(self.annotation_upload)
        css = "".join(f".{c}{{font-size:0 !important}}.{c} i{{font-size:13px;margin-right:4px}}"
                      f".{c}::after{{content:'{label}';font-size:13px}}" for c, label in self._labels.items())
        self.style = widgets.HTML(f"<style>{css}</style>", layout=widgets.Layout(width="0px", height="0px",
                                                                                  margin="0", overflow="hidden"))
        self.style.add_class("bnb-probe")
        self.widgets.append(self.style)
        self.links = widgets.HTML(layout=widgets.Layout(display="none"))
        self.links.add_class("bnb-links")
        self.written: list[Path] = []
        #: In a web page (``branchnb app``) "save" offers downloads only: the server's folder is
        #: of no use to the person in front of the page. See :meth:`use_page_mode`.
        self.page = False

    def use_page_mode(self, page: bool = True) -> None:
        """Downloads only (no folder box, nothing written on the server); for ``branchnb app`` pages.

        Parameters
        ----------
        page : bool
            True switches to downloads only; False brings the folder box back.
        """
        self.page = bool(page)
        self.folder.layout.display = "none" if self.page else None
        if self.save_button is not None:
            self.save_button.tooltip = ("prepare the result and the annotations as downloads (links appear "
                                        "below)" if self.page else self.save_button.tooltip)

    def _upload(self, cls: str, label: str, accept: str, icon: str, multiple: bool) -> widgets.FileUpload:
        if not isinstance(label, str) or not label.strip() or "'" in label or "\\" in label:
            raise ValueError(f"label must be plain text, got {label!r}")
        up = widgets.FileUpload(accept=accept, multiple=bool(multiple), description=label, icon=icon,
                                layout=widgets.Layout(width="auto"))
        up.add_class(cls)
        self._labels[cls] = label
        return up

    # -- opening ----------------------------------------------------------------------
    def open_files(self, files) -> object:
        """Decode ``files`` (a list of ``(name, bytes)``) and hand them to the app's ``open`` hook.

        Parameters
        ----------
        files : sequence of (str, bytes)
            File names and contents; the hook gets ``(file stem, image)``
            pairs (see :func:`decode_image`).

        Returns
        -------
        object
            What the hook returns (a message, or None).

        Raises
        ------
        ValueError
            If the app opens no images, ``files`` is empty or a file is no image.
        """
        if self._open is None:
            raise ValueError("this app opens no images")
        images = [(Path(str(n)).stem or str(n), decode_image(b, str(n))) for n, b in files]
        if not images:
            raise ValueError("no file chosen")
        return self._open(images)

    def _uploaded(self, value) -> None:
        if not value:
            return
        try:
            out = self.open_files([(f["name"], f["content"]) for f in value])
        finally:
            self._reset(self.upload)
        names = ", ".join(f["name"] for f in value)
        self.errors.info(f"opened {names}" + (f" | {out}" if isinstance(out, str) else ""))

    def load_text(self, text) -> object:
        """Restore annotations from JSON text (what "load annotations" does with the file).

        Parameters
        ----------
        text : str
            Annotation JSON, as written by "save" (``<name>_annotations.json``).

        Returns
        -------
        object
            What the app's ``load`` hook returns.

        Raises
        ------
        ValueError
            If the app loads no annotations, or as the hook raises.
        """
        if self._load is None:
            raise ValueError("this app loads no annotations")
        return self._load(text)

    def _annotations_uploaded(self, value) -> None:
        if not value:
            return
        try:
            f = value[0]
            self.load_text(bytes(f["content"]).decode("utf-8"))
        finally:
            self._reset(self.annotation_upload)
        self.errors.info(f"loaded annotations from {f['name']}")

    @staticmethod
    def _reset(upload) -> None:
        # the same file chosen again must fire again
        try:
            upload.value = ()
        except Exception:  # noqa: BLE001 - older ipywidgets keep it; harmless
            pass

    # -- saving ----------------------------------------------------------------------------
    def contents(self) -> dict[str, bytes]:
        """What "save" writes: ``{file name: bytes}``, every file checked (see :func:`check_file`)."""
        files: dict[str, bytes] = {}
        outs = self._outputs() if self._outputs is not None else {}
        if not isinstance(outs, Mapping):
            raise TypeError(f"the app's outputs hook must return a dict, got {type(outs).__name__}")
        for n, content in outs.items():
            files[f"{self.name}_{_safe_name(n)}"] = _as_bytes(n, content)
        if self._annotations is not None:
            files[f"{self.name}_annotations.json"] = _as_bytes("annotations.json", self._annotations())
        if not files:
            raise ValueError("nothing to save yet")
        # a glTF names its buffers and atlas without the prefix: those files are written beside it
        siblings = {n[len(self.name) + 1:]: b for n, b in files.items()} | files
        for n, b in files.items():
            check_file(n, b, siblings)
        return files

    def save(self, folder=None) -> list[Path]:
        """Write :meth:`contents` into ``folder`` (default: the folder box); returns the paths.

        Each file is written under a temporary name and renamed, so no
        half-written file ever has the real name. Download links are shown.

        Parameters
        ----------
        folder : str or os.PathLike, optional
            Output folder (``~`` expanded, created if needed); the folder
            box's value by default.

        Returns
        -------
        list of pathlib.Path
            The files written, ``<name>_<output>`` and ``<name>_annotations.json``.

        Raises
        ------
        ValueError
            Nothing to save, a file that fails :func:`check_file`, or a folder
            that is empty or an existing file.
        """
        files = self.contents()
        out = Path(self.folder.value if folder is None else folder).expanduser()
        if not str(out).strip():
            raise ValueError("folder is empty: type a folder name ('.' for the notebook's folder)")
        if out.exists() and not out.is_dir():
            raise ValueError(f"folder {str(out)!r} is an existing file")
        out.mkdir(parents=True, exist_ok=True)
        paths = []
        for n, b in files.items():
            p = out / n
            tmp = out / f".{n}.part"
            tmp.write_bytes(b)
            os.replace(tmp, p)  # never a half-written file under the real name
            paths.append(p)
        self.written = paths
        self._show_links(out, files)
        return paths

    def _saved(self) -> None:
        if self.page:
            files = self.contents()
            self._show_links(None, files)
            self.errors.info(f"{len(files)} file{'s' * (len(files) != 1)} ready: click to download")
            return
        paths = self.save()
        self.errors.info(f"saved {len(paths)} file{'s' * (len(paths) != 1)} to {paths[0].parent.resolve()}")

    def _show_links(self, folder: Path | None, files: Mapping[str, bytes]) -> None:
        links = []
        for n, b in files.items():
            if len(b) > LINK_LIMIT:
                links.append(html.escape(n))
                continue
            mime = _MIME.get(Path(n).suffix.lower(), "application/octet-stream")
            href = f"data:{mime};base64,{base64.b64encode(b).decode('ascii')}"
            links.append(f"<a download='{html.escape(n, quote=True)}' href='{href}'>{html.escape(n)}</a>")
        where = "" if folder is None else f"saved to <code>{html.escape(str(folder.resolve()))}</code>; "
        self.links.value = (f"<div style='font-size:12px;line-height:18px'>{where}download: "
                            + " ".join(links) + "</div>")
        self.links.layout.display = None
