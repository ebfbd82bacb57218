"""The job registry: what one batch item computes, and from which shared inputs.

A :class:`Job` has parameter *sections* (the technique's parameter
dataclasses, the same ones the apps' sliders edit), *inputs* with their
defaults (some of which may change per item), a ``prepare`` step that runs
once on the client (load and process the library, fit a model; the result
is scattered to every worker once) and a ``make`` function that turns the
prepared data, one item's parameters, inputs and ``rng`` into files.

Adding a job is a few lines::

    from branchnb.batch import Job, ItemOutput, register_job
    from branchnb.core.io import encode_png

    def make(shared, params, inputs, rng, stem):
        img = my_technique.generate(shared, params["main"], rng=rng)
        return ItemOutput({f"{stem}.png": encode_png(img)})

    register_job(Job("my_job", sections={"main": MyParams}, inputs={"size": 256},
                     prepare=lambda inputs, base_dir, params: None, make=make, stem="thing"))
"""

from __future__ import annotations

from collections.abc import Callable
from dataclasses import dataclass, field
from pathlib import Path
from typing import Any

__all__ = ["Job", "ItemOutput", "JOBS", "register_job", "get_job", "resolve_path"]


@dataclass
class ItemOutput:
    """What one item produced.

    Parameters
    ----------
    files : dict
        ``{file name: bytes}``; names start with the item's ``stem``.
    info : dict
        JSON-able facts for the manifest (e.g. the exemplars and weights mixed).
    """

    files: dict[str, bytes]
    info: dict = field(default_factory=dict)


@dataclass(frozen=True)
class Job:
    """A batch job.

    Parameters
    ----------
    name : str
        What specs call it.
    sections : dict
        ``{section: parameter dataclass}``; a spec's ``params`` has one table per section.
    inputs : dict
        ``{input: default}``, every input the job understands.
    prepare : callable(inputs, base_dir, params) -> object
        Runs once on the client with the shared inputs (all but ``item_inputs``),
        the spec's folder and its (base) parameters; the result goes to every
        worker once (``Client.scatter``).
    make : callable(shared, params, inputs, rng, stem) -> ItemOutput
        One item: ``params`` maps sections to validated dataclass instances,
        ``inputs`` holds all inputs (shared and the item's), ``rng`` is the item's
        ``numpy.random.Generator``, ``stem`` the file-name stem.
    stem : str
        File names are ``<stem>_<index>...``.
    item_inputs : tuple of str
        Inputs a spec may change per item (``vary``/``items``); ``()`` (the
        default): every input is shared by all items.
    description : str
        A one-line human description of what an item makes (informational).
    unused : callable(given, sections) -> dict, optional
        Which of the inputs a spec gives (``given``: name -> value, from
        ``inputs``, ``vary`` and ``items``) and parameter sections it sets
        (``sections``) this job would ignore, as ``{key: why}``; the spec is
        refused naming them, so nothing is recorded as used that was not.
    """

    name: str
    sections: dict[str, type]
    inputs: dict[str, Any]
    prepare: Callable[[dict, Path | None, dict], Any]
    make: Callable[..., ItemOutput]
    stem: str
    item_inputs: tuple[str, ...] = ()
    description: str = ""
    unused: Callable[[dict, set], dict] | None = None

    def __post_init__(self):
        if not self.name or not isinstance(self.name, str):
            raise ValueError("Job.name must be a non-empty str")
        missing = sorted(set(self.item_inputs) - set(self.inputs))
        if missing:
            raise ValueError(f"Job {self.name!r}: item_inputs {missing} are not among its inputs")
        if not callable(self.prepare) or not callable(self.make):
            raise TypeError(f"Job {self.name!r}: prepare and make must be callable")
        if self.unused is not None and not callable(self.unused):
            raise TypeError(f"Job {self.name!r}: unused must be callable or None")


#: Registered jobs by name (:func:`register_job` adds to it).
JOBS: dict[str, Job] = {}


def register_job(job: Job, *, replace: bool = False) -> Job:
    """Add ``job`` to :data:`JOBS` (``replace=True`` to redefine a name).

    Parameters
    ----------
    job : Job
        The job to register under ``job.name``.
    replace : bool
        Redefine an already registered name instead of raising ValueError
        (default False).

    Returns
    -------
    Job
        ``job`` itself, so ``register_job`` can wrap a definition.

    Raises
    ------
    TypeError
        ``job`` is not a :class:`Job`.
    ValueError
        A job of that name is registered and ``replace`` is False.
    """
    if not isinstance(job, Job):
        raise TypeError(f"job must be a Job, got {type(job).__name__}")
    if job.name in JOBS and not replace:
        raise ValueError(f"a job named {job.name!r} is already registered (replace=True to redefine it)")
    JOBS[job.name] = job
    return job


def get_job(name: str) -> Job:
    """The registered job called ``name``.

    Importing this module registers nothing; the first call imports the
    built-in technique jobs.

    Parameters
    ----------
    name : str
        The job's name, as a spec's ``job`` gives it.

    Returns
    -------
    Job

    Raises
    ------
    TypeError
        ``name`` is not a str.
    ValueError
        No job of that name is registered (the message lists the ones that are).
    """
    from . import _builtin  # noqa: F401  (registers the technique jobs)

    if not isinstance(name, str):
        raise TypeError(f"job must be a job name (str), got {type(name).__name__}")
    if name not in JOBS:
        raise ValueError(f"unknown job {name!r}; registered jobs: {sorted(JOBS)}")
    return JOBS[name]


def resolve_path(value, base_dir: Path | None, *, name: str) -> Path:
    """``value`` as a path; a relative one starts at ``base_dir`` (the spec file's folder).

    Parameters
    ----------
    value : str or Path
        A path from a spec's inputs; ``~`` is expanded.
    base_dir : Path or None
        The folder a relative ``value`` is relative to (the spec file's);
        None leaves a relative path relative to the working directory.
    name : str
        The input's name, used in the error message (``inputs.<name>``).

    Returns
    -------
    Path
        Not checked for existence.

    Raises
    ------
    ValueError
        ``value`` is not a str or Path, or is empty.
    """
    if not isinstance(value, (str, Path)) or str(value) == "":
        raise ValueError(f"inputs.{name} must be a path, got {value!r}")
    p = Path(value).expanduser()
    if not p.is_absolute() and base_dir is not None:
        p = Path(base_dir) / p
    return p
