"""Batch generation: thousands of variations from one spec, reproducibly, on Dask.

A spec (JSON or TOML, or :func:`spec_from_params` from an app's current
parameters) names a job, a count, a seed, the job's parameter dataclasses
and its inputs; :func:`run_batch` (or ``branchnb batch SPEC OUTDIR``) runs
the items on a Dask ``LocalCluster`` (or an existing cluster), writes their
files and ``OUTDIR/manifest.jsonl`` as they finish, and resumes where a
previous run stopped.

Jobs (:data:`JOBS`): ``tree_variations``, ``billboard_cloud``,
``dendrite_tree``, ``branching``; :func:`register_job` adds more.

>>> from branchnb.batch import spec_from_params, JOBS
>>> from branchnb.dendrite.trees import TreeParams
>>> spec = spec_from_params("dendrite_tree", TreeParams(iterations=3), count=500, seed=1)
>>> spec.job, spec.count, "dendrite_tree" in JOBS
('dendrite_tree', 500, True)
"""

from . import _builtin  # noqa: F401  (registers the technique jobs)
from .jobs import JOBS, ItemOutput, Job, get_job, register_job
from .manifest import read_manifest
from .runner import BatchSummary, run_batch
from .spec import BatchSpec, load_spec, params_to_dict, save_spec, spec_from_params

__all__ = [
    "BatchSpec", "BatchSummary", "ItemOutput", "JOBS", "Job", "get_job", "load_spec", "params_to_dict",
    "read_manifest", "register_job", "run_batch", "save_spec", "spec_from_params",
]
