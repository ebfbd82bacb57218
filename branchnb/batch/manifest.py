"""``OUTDIR/manifest.jsonl``: one strict-JSON record per finished item.

A record::

    {"item": 17, "seed": 4056..., "status": "done", "params": {...}, "inputs": {...},
     "files": [{"name": "tree_00017.png", "bytes": 81234, "sha256": "..."}],
     "info": {...}, "time": 0.41, "error": null, "key": "..."}

Records are appended (and flushed) as items finish, so an interrupted run
leaves every finished item recorded; a later record of the same item
replaces an earlier one, a torn last line is ignored. An item is *complete*
when its latest record is ``done``, its seed, parameters, inputs and the
spec key match, and every listed file exists with the recorded size and
SHA-256. At the end of a run the file is rewritten with one line per item.
"""

from __future__ import annotations

import hashlib
import json
import os
from pathlib import Path

__all__ = ["Manifest", "read_manifest", "file_record", "MANIFEST_NAME"]

MANIFEST_NAME = "manifest.jsonl"


def file_record(name: str, content: bytes) -> dict:
    """``{"name", "bytes", "sha256"}`` of one output file."""
    return {"name": name, "bytes": len(content), "sha256": hashlib.sha256(content).hexdigest()}


def _file_matches(folder: Path, rec: dict) -> bool:
    p = folder / rec["name"]
    try:
        if p.stat().st_size != rec["bytes"]:
            return False
        return hashlib.sha256(p.read_bytes()).hexdigest() == rec["sha256"]
    except (OSError, KeyError, TypeError):
        return False


def read_manifest(path) -> dict[int, dict]:
    """The latest record of each item in a manifest file (``{}`` if there is none)."""
    path = Path(path)
    if path.is_dir():
        path = path / MANIFEST_NAME
    latest: dict[int, dict] = {}
    if not path.is_file():
        return latest
    with path.open(encoding="utf-8") as f:
        for line in f:
            try:
                rec = json.loads(line)
            except json.JSONDecodeError:
                continue  # a line torn by a crash while writing
            if isinstance(rec, dict) and isinstance(rec.get("item"), int):
                latest[rec["item"]] = rec
    return latest


class Manifest:
    """The manifest of one output folder: read, check, append, compact."""

    def __init__(self, outdir):
        self.outdir = Path(outdir)
        self.path = self.outdir / MANIFEST_NAME
        self.records = read_manifest(self.path)
        self._file = None

    def is_complete(self, item: int, expected: dict) -> bool:
        """Whether ``item`` is done with the ``expected`` seed/params/inputs/key and intact files."""
        rec = self.records.get(item)
        if rec is None or rec.get("status") != "done":
            return False
        if any(_canonical(rec.get(k)) != _canonical(v) for k, v in expected.items()):
            return False
        files = rec.get("files")
        return isinstance(files, list) and bool(files) and all(_file_matches(self.outdir, f) for f in files)

    def append(self, record: dict) -> None:
        """Write one record as one line and flush it to disk."""
        line = json.dumps(record, allow_nan=False, separators=(",", ":")) + "\n"
        if self._file is None:
            self._file = self.path.open("a", encoding="utf-8")
        self._file.write(line)
        self._file.flush()
        os.fsync(self._file.fileno())
        self.records[record["item"]] = record

    def compact(self) -> None:
        """Rewrite the file with the latest record per item, in item order (atomic replace)."""
        self.close()
        if not self.records:
            return
        tmp = self.path.with_name(self.path.name + ".tmp")
        with tmp.open("w", encoding="utf-8") as f:
            for i in sorted(self.records):
                f.write(json.dumps(self.records[i], allow_nan=False, separators=(",", ":")) + "\n")
            f.flush()
            os.fsync(f.fileno())
        os.replace(tmp, self.path)

    def close(self) -> None:
        if self._file is not None:
            self._file.close()
            self._file = None


def _canonical(value):
    return json.dumps(value, sort_keys=True, allow_nan=False)


def write_atomic(path: Path, content: bytes) -> None:
    """Write ``content`` to ``path`` through a temporary file, so no torn file is ever left."""
    tmp = path.with_name(f".{path.name}.part")
    with tmp.open("wb") as f:
        f.write(content)
    os.replace(tmp, path)
