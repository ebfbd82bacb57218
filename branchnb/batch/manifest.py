"""``OUTDIR/manifest.jsonl``: one strict-JSON record per finished item.

A record::

    {"item": 17, "seed": 4056..., "status": "done", "params": {...}, "inputs": {...},
     "files": [{"name": "tree_00017.png", "bytes": 81234, "sha256": "..."}],
     "info": {...}, "time": 0.41, "error": null, "key": "..."}

Records are appended (and flushed) as items finish, so an interrupted run
leaves every finished item recorded; a later record of the same item
replaces an earlier one. An item is *complete* when its latest record is
``done``, its seed, parameters, inputs and the spec key match, and every
listed file exists with the recorded size and SHA-256. At the end of a run
the file is rewritten with one line per item, in item order.

A line that cannot be read (torn by a crash, not UTF-8, not a JSON record)
is reported in ``Manifest.problems`` by file and line; the item it
names (when it can be told) is recomputed.

A run that could not start any item (its shared inputs failed, e.g. a
library image above the pixel limit) appends one *run* record instead of
failing every item one by one::

    {"run": "failed", "error": "ValueError: inputs.library: ...", "key": "...", "items_not_run": 200}

It is not an item (:func:`read_manifest` skips it; ``Manifest.run_failure``
holds the latest one) and the next run that gets going drops it.

The client keeps no record in memory: it indexes the file (item, offset and
length of each line, 20 bytes an item) and reads a record when it is asked
for, so resuming or running a batch of millions of items needs little
memory.
"""

from __future__ import annotations

import hashlib
import json
import os
import re
from array import array
from pathlib import Path

import numpy as np

__all__ = ["Manifest", "read_manifest", "file_record", "MANIFEST_NAME", "ManifestError"]

MANIFEST_NAME = "manifest.jsonl"
_ITEM = re.compile(rb'"item"\s*:\s*(\d{1,12})')
_MAX_PROBLEMS = 20


class ManifestError(ValueError):
    """The manifest cannot be used at all (e.g. ``manifest.jsonl`` is a folder)."""


def file_record(name: str, content: bytes) -> dict:
    """``{"name", "bytes", "sha256"}`` of one output file.

    Parameters
    ----------
    name : str
        File name inside the output folder.
    content : bytes
        The file's content.

    Returns
    -------
    dict

    Examples
    --------
    >>> rec = file_record("tree_00000.png", b"abc")
    >>> rec["bytes"], rec["sha256"][:8]
    (3, 'ba7816bf')
    """
    return {"name": name, "bytes": len(content), "sha256": hashlib.sha256(content).hexdigest()}


def _file_matches(folder: Path, rec: dict) -> bool:
    try:
        p = folder / rec["name"]
        if p.stat().st_size != rec["bytes"]:
            return False
        h = hashlib.sha256()
        with p.open("rb") as f:
            for block in iter(lambda: f.read(1 << 20), b""):
                h.update(block)
        return h.hexdigest() == rec["sha256"]
    except (OSError, KeyError, TypeError, ValueError):
        return False


def _reject_constant(name):
    raise ValueError(f"non-standard JSON constant {name}")


def _parse_line(raw: bytes):
    """``(record, None)`` or ``(None, reason)`` for one manifest line."""
    try:
        text = raw.decode("utf-8")
    except UnicodeDecodeError as exc:
        return None, f"not UTF-8 text (byte {exc.start})"
    try:
        rec = json.loads(text, parse_constant=_reject_constant)
    except (ValueError, RecursionError) as exc:
        return None, f"not a JSON record ({exc})"[:200]
    if isinstance(rec, dict) and "item" not in rec and rec.get("run") == "failed":
        return rec, None
    if not isinstance(rec, dict) or isinstance(rec.get("item"), bool) or not isinstance(rec.get("item"), int):
        return None, "a JSON value without an integer 'item'"
    if rec["item"] < 0:
        return None, f"item {rec['item']} is negative"
    return rec, None


def _manifest_path(path) -> Path:
    """The manifest file of ``path`` (an output folder, or the file itself); a folder in its place is an error."""
    path = Path(path)
    if path.is_dir() and path.name != MANIFEST_NAME:
        path = path / MANIFEST_NAME
    if path.is_dir():
        raise ManifestError(f"{path} is a folder, not a manifest file: move it away or use another output folder")
    return path


class Manifest:
    """The manifest of one output folder: index, check, append, compact.

    Parameters
    ----------
    outdir : str or Path
        The output folder; its ``manifest.jsonl`` is indexed at once (a
        missing file is an empty manifest).

    Raises
    ------
    ManifestError
        ``manifest.jsonl`` is a folder or cannot be read.

    Attributes
    ----------
    path : Path
        ``outdir / "manifest.jsonl"``.
    problems : list of str
        Lines that could not be read, as ``"<file> line <n>: <reason>"``
        (at most 20, then a count).
    run_failure : dict or None
        The latest run record (a run that could not start any item), if any.
    """

    def __init__(self, outdir):
        self.outdir = Path(outdir)
        self.path = _manifest_path(self.outdir / MANIFEST_NAME)
        self.problems: list[str] = []
        self.run_failure: dict | None = None
        self._n_problems = 0
        self._file = None
        self._dirty = False
        self._items, self._offsets, self._lengths = self._index()

    # -- reading ---------------------------------------------------------------
    def _problem(self, lineno: int, reason: str) -> None:
        self._n_problems += 1
        self._dirty = True
        if len(self.problems) < _MAX_PROBLEMS:
            self.problems.append(f"{self.path} line {lineno}: {reason}")
        elif len(self.problems) == _MAX_PROBLEMS:
            self.problems.append(f"{self.path}: more unreadable lines follow")

    def _scan(self):
        """``(item, offset, length)`` of every readable line; records problems (and damaged items)."""
        if not self.path.exists():
            return
        try:
            f = self.path.open("rb")
        except OSError as exc:
            raise ManifestError(f"cannot read {self.path}: {exc.strerror or exc}") from None
        with f:
            offset = 0
            for lineno, raw in enumerate(f, 1):
                n = len(raw)
                body = raw.rstrip(b"\r\n")
                if body.strip():
                    rec, why = _parse_line(body)
                    if rec is None:
                        m = _ITEM.search(body)
                        if m:  # a tombstone: this item's earlier records no longer count
                            why += f"; item {int(m.group(1))} is recomputed"
                            yield int(m.group(1)), -1, 0
                        self._problem(lineno, why)
                    elif "item" not in rec:      # a run record: not an item; dropped by the next compaction
                        self.run_failure = rec
                        self._dirty = True
                    else:
                        yield rec["item"], offset, len(body)
                offset += n

    def _index(self):
        items, offsets, lengths = array("q"), array("q"), array("q")
        for i, off, n in self._scan():
            items.append(i)
            offsets.append(off)
            lengths.append(n)
        items = np.frombuffer(items, np.int64) if items else np.zeros(0, np.int64)
        offsets = np.frombuffer(offsets, np.int64) if offsets else np.zeros(0, np.int64)
        lengths = np.frombuffer(lengths, np.int64) if lengths else np.zeros(0, np.int64)
        if len(items) and (len(np.unique(items)) != len(items) or np.any(np.diff(items) < 0)):
            self._dirty = True
        # keep the last line of each item: reverse, then the first occurrence of each unique item
        rev = items[::-1]
        uniq, first = np.unique(rev, return_index=True)
        keep = len(items) - 1 - first
        keep = keep[offsets[keep] >= 0]                   # an item whose last line is damaged has no record
        return items[keep], offsets[keep], lengths[keep]

    def __len__(self) -> int:
        return len(self._items)

    def items(self) -> np.ndarray:
        """Item indices with a readable record (sorted)."""
        return self._items.copy()

    def get(self, item: int) -> dict | None:
        """The latest readable record of ``item`` (None if there is none).

        Parameters
        ----------
        item : int
            Item index.

        Returns
        -------
        dict or None
        """
        k = int(np.searchsorted(self._items, item))
        if k >= len(self._items) or self._items[k] != item:
            return None
        with self.path.open("rb") as f:
            f.seek(int(self._offsets[k]))
            rec, _ = _parse_line(f.read(int(self._lengths[k])))
        return rec

    def is_complete(self, item: int, expected: dict) -> bool:
        """Whether ``item`` is done with the ``expected`` seed/params/inputs/key and intact files.

        Parameters
        ----------
        item : int
            Item index.
        expected : dict
            ``{record key: value}`` the latest record must hold (compared as
            canonical JSON), e.g. ``seed``, ``params``, ``inputs``, ``key``.

        Returns
        -------
        bool
            True when the record is ``done``, matches ``expected`` and lists
            at least one file, each present with its size and SHA-256.
        """
        rec = self.get(item)
        if rec is None or rec.get("status") != "done":
            return False
        if any(_canonical(rec.get(k)) != _canonical(v) for k, v in expected.items()):
            return False
        files = rec.get("files")
        return (isinstance(files, list) and bool(files) and all(isinstance(f, dict) for f in files)
                and all(_file_matches(self.outdir, f) for f in files))

    # -- writing ---------------------------------------------------------------
    def append(self, record: dict, *, sync: bool = True) -> None:
        """Write one record as one line and flush it (the record is not kept in memory).

        The line reaches the operating system at once (it survives the
        process being killed); ``sync=True`` also waits until it is on the
        disk (``fsync``, ~10 ms), else :meth:`sync` does it for several lines.

        Parameters
        ----------
        record : dict
            Strict JSON data (no NaN/inf), an item record or a run record.
        sync : bool
            Wait for the disk (default True).

        Raises
        ------
        ManifestError
            The file cannot be opened for writing.
        """
        line = json.dumps(record, allow_nan=False, separators=(",", ":")) + "\n"
        if self._file is None:
            try:
                self._file = self.path.open("a", encoding="utf-8")
            except OSError as exc:
                raise ManifestError(f"cannot write {self.path}: {exc.strerror or exc}") from None
        self._file.write(line)
        self._file.flush()
        if sync:
            os.fsync(self._file.fileno())
        self._dirty = True

    def sync(self) -> None:
        """Wait until every appended line is on the disk."""
        if self._file is not None:
            os.fsync(self._file.fileno())

    def record_run_failure(self, error: str, key: str, items_not_run: int) -> None:
        """Append a run record: this run could not start any item, because of ``error``.

        Parameters
        ----------
        error : str
            ``"Type: message"`` of what stopped the run.
        key : str
            The spec key (:func:`~branchnb.batch.runner.spec_key`) of the run.
        items_not_run : int
            Items that were left to compute.
        """
        self.append({"run": "failed", "error": error, "key": key, "items_not_run": int(items_not_run)})
        self.close()

    def compact(self) -> None:
        """Rewrite the file with the latest readable record per item, in item order (atomic replace).

        Streams the file twice (index, then copy), so memory stays at the
        index's 20 bytes per item whatever the manifest's size.
        """
        self.close()
        if not self._dirty or not self.path.is_file():
            return
        self.problems, self._n_problems = [], 0
        items, offsets, lengths = self._index()
        tmp = self.path.with_name(self.path.name + ".tmp")
        with self.path.open("rb") as src, tmp.open("wb") as dst:
            for off, n in zip(offsets.tolist(), lengths.tolist()):
                src.seek(off)
                dst.write(src.read(n) + b"\n")
            dst.flush()
            os.fsync(dst.fileno())
        os.replace(tmp, self.path)
        self._items, self._offsets, self._lengths = self._index()
        self._dirty = False

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None


def read_manifest(path) -> dict[int, dict]:
    """The latest record of each item in a manifest file or output folder (``{}`` if there is none).

    Unreadable lines and run records are skipped (see :class:`Manifest` for how a run reports them).

    Parameters
    ----------
    path : str or Path
        An output folder or its ``manifest.jsonl``.

    Returns
    -------
    dict
        ``{item: record}``.

    Raises
    ------
    ManifestError
        ``manifest.jsonl`` is a folder or cannot be read.
    """
    path = _manifest_path(path)
    m = Manifest.__new__(Manifest)
    m.outdir, m.path, m.problems, m._n_problems, m.run_failure = path.parent, path, [], 0, None
    m._file, m._dirty = None, False
    m._items, m._offsets, m._lengths = m._index()
    return {int(i): m.get(int(i)) for i in m._items}


def _canonical(value):
    return json.dumps(value, sort_keys=True, allow_nan=False)


def write_atomic(path: Path, content: bytes) -> None:
    """Write ``content`` to ``path`` through a temporary file, so no torn file is ever left.

    Parameters
    ----------
    path : Path
        Destination (replaced if it exists); the temporary file
        ``.<name>.part`` lies in the same folder.
    content : bytes
        What to write.
    """
    tmp = path.with_name(f".{path.name}.part")
    with tmp.open("wb") as f:
        f.write(content)
    os.replace(tmp, path)
