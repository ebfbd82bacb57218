"""Batch specs: which job, how many items, the seed, the job's parameter dataclasses and inputs.

A spec is a small JSON or TOML document::

    {
      "job": "tree_variations",
      "count": 1000,
      "seed": 7,
      "inputs": {"library": "my_trees/", "size": 512, "target": "oak"},
      "params": {"variation": {"keep": 0.6, "n_mix": 3}},
      "vary": {"variation.keep": [0.4, 0.6, 0.8]},
      "items": {"12": {"variation.m_points": 30}}
    }

``params`` holds one table per parameter section of the job (the same
dataclasses the apps' sliders edit, e.g. ``variation`` =
:class:`~branchnb.trees.VariationParams`); missing fields keep the paper's
defaults. ``vary`` gives lists of values, item ``i`` taking entry
``i % len``; ``items`` overrides single items. Keys are
``"section.field"`` for parameters and plain names for item inputs
(e.g. ``target``). Relative paths in ``inputs`` are relative to the spec
file's folder.

Each item's seed comes from the spec's seed and the item's index through
:meth:`numpy.random.SeedSequence.spawn`, so an item gives the same files
whatever the number of workers and the order in which items run.
"""

from __future__ import annotations

import dataclasses
import json
import math
import re
import sys
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

import numpy as np

from ..core.jsonio import MAX_JSON_DEPTH, check_depth, loads_strict
from ..core.params import check_params
from ..core.validate import brief
from .jobs import Job, get_job

if sys.version_info >= (3, 11):
    import tomllib
else:  # pragma: no cover - Python 3.10 (the tomli dependency)
    import tomli as tomllib

__all__ = ["BatchSpec", "load_spec", "save_spec", "spec_from_params", "params_to_dict", "MAX_COUNT"]

#: Upper bound of ``count`` (a guard against a typo launching a runaway batch).
MAX_COUNT = 10_000_000

_KEYS = ("job", "count", "seed", "inputs", "params", "vary", "items")


def _plain(value, where: str):
    """``value`` as strict-JSON data (lists, dicts, str, int, finite float, bool, None)."""
    if isinstance(value, (bool, str)) or value is None:
        return value
    if isinstance(value, (int, np.integer)):
        return int(value)
    if isinstance(value, (float, np.floating)):
        if not math.isfinite(value):
            raise ValueError(f"{where} must be finite, got {value}")
        return float(value)
    if isinstance(value, Path):
        return str(value)
    if isinstance(value, np.ndarray):
        return _plain(value.tolist(), where)
    if isinstance(value, dict):
        return {str(k): _plain(v, f"{where}.{k}") for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v, f"{where}[{i}]") for i, v in enumerate(value)]
    raise TypeError(f"{where} must be JSON data (numbers, strings, lists, tables), got {type(value).__name__}")


def params_to_dict(params) -> dict:
    """The fields of a parameter dataclass instance as plain (JSON) values.

    Parameters
    ----------
    params : dataclass instance
        E.g. a :class:`~branchnb.trees.VariationParams`; arrays become lists,
        paths strings.

    Returns
    -------
    dict
        ``{field: value}``, strict JSON data.

    Raises
    ------
    TypeError
        ``params`` is not a dataclass instance, or a field holds no JSON data.
    ValueError
        A float field is not finite.

    Examples
    --------
    >>> from branchnb.trees import VariationParams
    >>> params_to_dict(VariationParams(keep=0.7))["keep"]
    0.7
    """
    if not dataclasses.is_dataclass(params) or isinstance(params, type):
        raise TypeError(f"params must be a parameter dataclass instance, got {type(params).__name__}")
    return _plain(dataclasses.asdict(params), type(params).__name__)


def _build_params(job: Job, values: dict[str, dict], where: str) -> dict[str, Any]:
    """One validated dataclass instance per section of ``job``."""
    out = {}
    for section, cls in job.sections.items():
        fields = values.get(section, {})
        names = {f.name for f in dataclasses.fields(cls)}
        unknown = sorted(set(fields) - names)
        if unknown:
            raise TypeError(f"{where}.{section}: unknown field(s) {unknown} of {cls.__name__}; "
                            f"known: {sorted(names)}")
        out[section] = check_params(cls(**fields), name=f"{where}.{section}")
    return out


@dataclass(frozen=True)
class BatchSpec:
    """A validated batch spec (see the module docstring for the format).

    Parameters
    ----------
    job : str
        Name of a registered job (:data:`branchnb.batch.JOBS`).
    count : int
        Number of items, 1 to :data:`MAX_COUNT`.
    seed : int
        Root of the item seeds, ``>= 0`` (default 0); see :meth:`item_seeds`.
    inputs : dict
        The job's inputs (library folder, example file, output size, ...).
    params : dict
        ``{section: {field: value}}``, the non-default parameter fields.
    vary : dict
        ``{key: [values]}``, item ``i`` takes ``values[i % len(values)]``.
    items : dict
        ``{index: {key: value}}`` overrides of single items.
    base_dir : Path or None
        Folder that relative paths in ``inputs`` start from; None (default):
        the working directory.

    Raises
    ------
    ValueError, TypeError
        An unknown job, input, section, field or key, a count or seed out of
        range, or invalid base parameters (naming the offending key).
    """

    job: str
    count: int
    seed: int = 0
    inputs: dict = field(default_factory=dict)
    params: dict = field(default_factory=dict)
    vary: dict = field(default_factory=dict)
    items: dict = field(default_factory=dict)
    base_dir: Path | None = None

    def __post_init__(self):
        job = get_job(self.job)
        if self.base_dir is not None:
            if not isinstance(self.base_dir, (str, Path)) or str(self.base_dir) == "":
                raise TypeError(f"base_dir must be a folder path or None, got {self.base_dir!r}")
            object.__setattr__(self, "base_dir", Path(self.base_dir))
        if isinstance(self.count, bool) or not isinstance(self.count, (int, np.integer)):
            raise TypeError(f"count must be an int, got {self.count!r}")
        if not 1 <= self.count <= MAX_COUNT:
            raise ValueError(f"count must lie in [1, {MAX_COUNT}], got {brief(self.count)}")
        if isinstance(self.seed, bool) or not isinstance(self.seed, (int, np.integer)) or self.seed < 0:
            raise ValueError(f"seed must be an int >= 0, got {self.seed!r:.40}")
        if int(self.seed).bit_length() > 128:
            raise ValueError(f"seed must be below 2**128, got an int of {int(self.seed).bit_length()} bits")
        for name in ("inputs", "params", "vary", "items"):
            if not isinstance(getattr(self, name), dict):
                raise TypeError(f"{name} must be a table (dict), got {type(getattr(self, name)).__name__}")
            check_depth(getattr(self, name), name=name, limit=MAX_JSON_DEPTH - 1)
        object.__setattr__(self, "count", int(self.count))
        object.__setattr__(self, "seed", int(self.seed))
        object.__setattr__(self, "inputs", _plain(self.inputs, "inputs"))
        object.__setattr__(self, "params", _plain(self.params, "params"))
        object.__setattr__(self, "vary", _plain(self.vary, "vary"))
        items = {}
        for k, v in self.items.items():
            try:
                i = int(k)
            except (TypeError, ValueError):
                raise ValueError(f"items: keys must be item indices, got {k!r}") from None
            if not 0 <= i < self.count:
                raise ValueError(f"items: index {i} outside 0 .. {self.count - 1}")
            if not isinstance(v, dict):
                raise TypeError(f"items[{i}] must be a table of overrides, got {type(v).__name__}")
            items[i] = _plain(v, f"items[{i}]")
        object.__setattr__(self, "items", items)
        unknown = sorted(set(self.inputs) - set(job.inputs))
        if unknown:
            raise ValueError(f"inputs: unknown input(s) {unknown} of job {job.name!r}; "
                             f"known: {sorted(job.inputs)}")
        unknown = sorted(set(self.params) - set(job.sections))
        if unknown:
            raise ValueError(f"params: unknown section(s) {unknown} of job {job.name!r}; "
                             f"known: {sorted(job.sections)}")
        for sec, fields in self.params.items():
            if not isinstance(fields, dict):
                raise TypeError(f"params.{sec} must be a table of fields, got {type(fields).__name__}")
        _build_params(job, self.params, "params")  # the base parameters must be valid
        for key, values in self.vary.items():
            self._check_key(job, key, "vary")
            if not isinstance(values, list) or not values:
                raise ValueError(f"vary.{key} must be a non-empty list of values")
        for i, over in self.items.items():
            for key in over:
                self._check_key(job, key, f"items[{i}]")
        if job.unused is not None:
            given = dict(self.inputs)
            for key, values in self.vary.items():
                if "." not in key:
                    given.setdefault(key, values[0])
            for over in self.items.values():
                for key, v in over.items():
                    if "." not in key:
                        given.setdefault(key, v)
            sections = set(self.params) | {k.split(".", 1)[0] for k in self.vary if "." in k}
            sections |= {k.split(".", 1)[0] for over in self.items.values() for k in over if "." in k}
            unused = job.unused(given, sections)
            if unused:
                key, why = sorted(unused.items())[0]
                where = f"params.{key}" if key in job.sections else f"inputs.{key}"
                raise ValueError(f"{where} is not used by job {job.name!r}: {why}")

    @staticmethod
    def _check_key(job: Job, key: str, where: str) -> None:
        if "." in key:
            section, name = key.split(".", 1)
            if section not in job.sections:
                raise ValueError(f"{where}: {key!r} names no parameter section of job {job.name!r} "
                                 f"({sorted(job.sections)})")
            names = {f.name for f in dataclasses.fields(job.sections[section])}
            if name not in names:
                raise ValueError(f"{where}: {key!r}: {job.sections[section].__name__} has no field "
                                 f"{name!r}")
        elif key not in job.item_inputs:
            raise ValueError(f"{where}: {key!r} is not an item input of job {job.name!r} "
                             f"(item inputs: {sorted(job.item_inputs)}; parameters: 'section.field')")

    # -- derived --------------------------------------------------------------
    @property
    def job_info(self) -> Job:
        return get_job(self.job)

    def with_count(self, count: int) -> BatchSpec:
        """The same spec with another ``count`` (item seeds do not change).

        Parameters
        ----------
        count : int
            The new number of items; ``items`` overrides past it are dropped.

        Returns
        -------
        BatchSpec
        """
        return dataclasses.replace(self, count=count,
                                   items={i: v for i, v in self.items.items() if i < count})

    def item_seeds(self, indices=None) -> list[int]:
        """Seeds of items ``indices`` (all by default): ``SeedSequence(seed).spawn(count)``,
        each child reduced to one 63-bit int (the ``rng`` the job gets, and the manifest's ``seed``).

        Parameters
        ----------
        indices : iterable of int, optional
            Item indices; None (default): ``range(count)``.

        Returns
        -------
        list of int
            One seed per index; item ``i``'s seed depends only on ``seed``
            and ``i`` (not on ``count``).
        """
        idx = range(self.count) if indices is None else indices
        # child i of SeedSequence(seed).spawn(count) is SeedSequence(seed, spawn_key=(i,)): built
        # directly, so a million-item spec does not hold a million children
        return [int(np.random.SeedSequence(self.seed, spawn_key=(int(i),)).generate_state(1, np.uint64)[0]
                    >> np.uint64(1)) for i in idx]

    def _item_values(self, index: int) -> dict[str, Any]:
        values = {k: v[index % len(v)] for k, v in self.vary.items()}
        values.update(self.items.get(index, {}))
        return values

    def item_raw(self, index: int) -> tuple[dict, dict]:
        """Parameters ``{section: {field: value}}`` and item inputs of item ``index``, unvalidated.

        Parameters
        ----------
        index : int
            The item (0-based): ``vary`` entry ``index % len`` and any
            ``items[index]`` override apply.

        Returns
        -------
        params : dict
            ``{section: {field: value}}``, the base ``params`` with the
            item's changes (defaults not filled in).
        inputs : dict
            The job's item inputs with the item's values.
        """
        job = self.job_info
        params = {s: dict(self.params.get(s, {})) for s in job.sections}
        inputs = {k: self.inputs.get(k, job.inputs[k]) for k in job.item_inputs}
        for key, v in self._item_values(index).items():
            if "." in key:
                s, name = key.split(".", 1)
                params[s][name] = v
            else:
                inputs[key] = v
        return params, inputs

    def item_params(self, index: int) -> dict[str, Any]:
        """The validated parameter dataclasses of item ``index`` (raises ValueError/TypeError).

        Parameters
        ----------
        index : int
            The item (0-based).

        Returns
        -------
        dict
            ``{section: dataclass instance}``, missing fields at their defaults.
        """
        params, _ = self.item_raw(index)
        return _build_params(self.job_info, params, f"item {index} params")

    def shared_inputs(self) -> dict:
        """Inputs of the job's one-off preparation (the library, the example, ...) with defaults."""
        job = self.job_info
        return {k: self.inputs.get(k, v) for k, v in job.inputs.items() if k not in job.item_inputs}

    def to_dict(self) -> dict:
        """The spec as plain data (what :func:`save_spec` writes)."""
        d = {"job": self.job, "count": self.count, "seed": self.seed, "inputs": self.inputs,
             "params": self.params}
        if self.vary:
            d["vary"] = self.vary
        if self.items:
            d["items"] = {str(k): v for k, v in sorted(self.items.items())}
        return d

    @classmethod
    def from_dict(cls, d: dict, base_dir=None) -> BatchSpec:
        """A spec from plain data (a parsed JSON or TOML document).

        Parameters
        ----------
        d : dict
            The document: ``job`` and ``count`` are required, ``seed``,
            ``inputs``, ``params``, ``vary`` and ``items`` optional.
        base_dir : str or Path, optional
            Folder relative input paths start from (the spec file's); None:
            the working directory.

        Returns
        -------
        BatchSpec

        Raises
        ------
        ValueError, TypeError
            An unknown or missing key, or an invalid spec.
        """
        if not isinstance(d, dict):
            raise TypeError(f"a spec must be a table (dict), got {type(d).__name__}")
        check_depth(d, name="the spec", limit=MAX_JSON_DEPTH)
        unknown = sorted(set(d) - set(_KEYS))
        if unknown:
            raise ValueError(f"unknown spec key(s) {unknown}; a spec has {list(_KEYS)}")
        for key in ("job", "count"):
            if key not in d:
                raise ValueError(f"the spec needs a {key!r}")
        return cls(job=d["job"], count=d["count"], seed=d.get("seed", 0), inputs=d.get("inputs", {}),
                   params=d.get("params", {}), vary=d.get("vary", {}), items=d.get("items", {}),
                   base_dir=base_dir)


def load_spec(path) -> BatchSpec:
    """Read a spec from a ``.json`` or ``.toml`` file (relative input paths start at its folder).

    Parameters
    ----------
    path : str or Path
        The spec file; its suffix (``.json`` or ``.toml``) picks the parser.

    Returns
    -------
    BatchSpec
        With ``base_dir`` the file's folder.

    Raises
    ------
    ValueError
        Unknown suffix, a syntax error (with its position), or an invalid spec.
    """
    if not isinstance(path, (str, Path)) or str(path) == "":
        raise TypeError(f"path must be a spec file path, got {path!r}")
    path = Path(path)
    suffix = path.suffix.lower()
    if suffix not in (".json", ".toml"):
        raise ValueError(f"path: a spec file must end in .json or .toml, got {path.name!r}")
    try:
        text = path.read_text(encoding="utf-8")
    except (OSError, UnicodeDecodeError) as exc:
        raise ValueError(f"path: cannot read the spec {str(path)!r}: {getattr(exc, 'strerror', None) or exc}") from None
    try:
        if suffix == ".json":
            data = loads_strict(text, name=path.name)   # duplicate keys, NaN, depth refused
        else:
            data = tomllib.loads(text)                  # TOML refuses duplicate keys itself
    except tomllib.TOMLDecodeError as exc:
        raise ValueError(f"{path.name} is not valid TOML: {exc}") from None
    except RecursionError:
        raise ValueError(f"{path.name} is not valid TOML: it nests deeper than {MAX_JSON_DEPTH} levels") from None
    return BatchSpec.from_dict(data, base_dir=path.resolve().parent)


def _toml_value(v, where: str) -> str:
    if isinstance(v, bool):
        return "true" if v else "false"
    if isinstance(v, (int, float)):
        return repr(v)
    if isinstance(v, str):
        return json.dumps(v)
    if isinstance(v, list):
        if any(x is None for x in v):
            raise ValueError(f"{where}: TOML has no null; save this spec as JSON")
        return "[" + ", ".join(_toml_value(x, where) for x in v) + "]"
    if isinstance(v, dict):
        return "{" + ", ".join(f"{_toml_key(k)} = {_toml_value(x, where)}" for k, x in v.items()
                               if x is not None) + "}"
    raise TypeError(f"{where}: cannot write {type(v).__name__} to TOML")


def _toml_key(k: str) -> str:
    return k if re.fullmatch(r"[A-Za-z0-9_-]+", k) else json.dumps(k)


def _toml(d: dict) -> str:
    lines = [f"{k} = {_toml_value(d[k], k)}" for k in ("job", "count", "seed")]
    tables = [("inputs", d["inputs"])]
    tables += [(f"params.{s}", f) for s, f in d["params"].items()]
    if "vary" in d:
        tables.append(("vary", d["vary"]))
    tables += [(f'items."{i}"', over) for i, over in d.get("items", {}).items()]
    for name, table in tables:
        lines += ["", f"[{name}]"]
        lines += [f"{_toml_key(k)} = {_toml_value(v, f'{name}.{k}')}" for k, v in table.items()
                  if v is not None]  # TOML has no null: a missing key means the default
    return "\n".join(lines) + "\n"


def save_spec(spec: BatchSpec, path) -> Path:
    """Write ``spec`` as JSON (strict) or TOML, chosen by the suffix of ``path``.

    Parameters
    ----------
    spec : BatchSpec
        The spec to write (``base_dir`` is not written: relative paths stay
        relative to the file's folder when it is read back).
    path : str or Path
        Destination ending in ``.json`` or ``.toml`` (overwritten).

    Returns
    -------
    Path
        ``path``.

    Raises
    ------
    TypeError
        ``spec`` is not a BatchSpec.
    ValueError
        Another suffix, or a None value inside a list (TOML has no null).
    """
    if not isinstance(spec, BatchSpec):
        raise TypeError(f"spec must be a BatchSpec, got {type(spec).__name__}")
    path = Path(path)
    suffix = path.suffix.lower()
    d = spec.to_dict()
    if suffix == ".json":
        text = json.dumps(d, indent=2, allow_nan=False) + "\n"
    elif suffix == ".toml":
        text = _toml(d)
    else:
        raise ValueError(f"path must end in .json or .toml, got {path.name!r}")
    path.write_text(text, encoding="utf-8")
    return path


def spec_from_params(job: str, *params, count: int, seed: int = 0, only_changed: bool = False,
                     vary: dict | None = None, **inputs) -> BatchSpec:
    """A spec for ``job`` from parameter dataclass instances, e.g. an app's current parameters.

    Parameters
    ----------
    job : str
        A registered job name (``"tree_variations"``, ``"billboard_cloud"``, ...).
    *params : dataclass instances
        Each goes to the job's section of its type (e.g. a ``VariationParams``
        to ``variation``).
    count, seed : int
        Number of items, and the root of their seeds (default 0); see
        :class:`BatchSpec`.
    only_changed : bool
        Store only the fields that differ from the defaults (a shorter spec
        that follows future default changes); all fields by default.
    vary : dict, optional
        See :class:`BatchSpec`.
    **inputs
        The job's inputs (``library=...``, ``weights=...``, ...).

    Examples
    --------
    >>> from branchnb.trees import VariationParams
    >>> spec = spec_from_params("tree_variations", VariationParams(keep=0.7), count=100,
    ...                         library=["tree_rpg_01", "tree_rpg_02"], size=256)
    >>> spec.params["variation"]["keep"], spec.count
    (0.7, 100)
    """
    j = get_job(job)
    if not isinstance(only_changed, bool):
        raise TypeError(f"only_changed must be a bool, got {only_changed!r}")
    by_type = {cls: s for s, cls in j.sections.items()}
    sections = {}
    for p in params:
        section = by_type.get(type(p))
        if section is None:
            raise TypeError(f"job {job!r} takes no {type(p).__name__}; its sections are "
                            + ", ".join(f"{s} ({c.__name__})" for s, c in j.sections.items()))
        d = params_to_dict(p)
        if only_changed:
            default = params_to_dict(type(p)())
            d = {k: v for k, v in d.items() if default.get(k) != v}
        sections[section] = d
    return BatchSpec(job=job, count=count, seed=seed, inputs=inputs, params=sections,
                     vary={} if vary is None else vary)
