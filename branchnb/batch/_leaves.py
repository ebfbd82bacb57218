"""The ``leaf_variations`` job: new leaves by structural layering (``branchnb.leaves``).

The analysis (training layers, registration, layer induction, residuals)
runs once in ``prepare`` and is scattered; each item is one
:func:`~branchnb.leaves.synthesis.generate_leaf` with a seed drawn from the
item's ``rng``. :func:`register` adds the job (``branchnb.batch`` calls it
when ``branchnb.leaves`` is there); this module imports without it.
"""

from __future__ import annotations

import json

import numpy as np

from ._builtin import _image_sources, _load
from .jobs import ItemOutput, Job, register_job, resolve_path


def _layers(value, base_dir):
    """A LayerSet JSON file (the leaf app's scribbles), or ``{layer: mask image}`` on the training leaf."""
    from ..leaves.layers import LayerSet

    if isinstance(value, str):
        path = resolve_path(value, base_dir, name="layers")
        try:
            return LayerSet.from_json(path.read_text(encoding="utf-8"))
        except (OSError, json.JSONDecodeError) as exc:
            raise ValueError(f"inputs.layers: cannot read a layer set from {str(path)!r}: {exc}") from None
    if isinstance(value, dict) and value:
        masks = {}
        for name, src in value.items():
            (_, s), = _image_sources(src, base_dir, name=f"layers.{name}", default=())
            img = _load(s)
            masks[name] = img[..., -1] > 0.5 if img.shape[-1] in (2, 4) else img[..., 0] > 0.5
        return masks
    raise ValueError("inputs.layers is required: a LayerSet JSON file, or {layer name: mask image} "
                     "(top layer first) on the training leaf")


def _prepare(inputs, base_dir, params):
    from ..leaves.analysis import analyze

    srcs = _image_sources(inputs["exemplars"], base_dir, name="exemplars", default=())
    images = [_load(s) for _, s in srcs]
    rng = inputs["rng"]
    if isinstance(rng, bool) or not isinstance(rng, int) or rng < 0:
        raise ValueError(f"inputs.rng must be an int >= 0, got {rng!r}")
    return analyze(images, inputs["training_index"], _layers(inputs["layers"], base_dir),
                   params["induction"], rng=rng)


def _make(analysis, params, inputs, rng, stem) -> ItemOutput:
    from ..core.io import encode_png
    from ..leaves.synthesis import generate_leaf

    leaf = generate_leaf(analysis, int(rng.integers(2**31 - 1)), params["synthesis"])
    return ItemOutput({f"{stem}.png": encode_png(np.clip(leaf.image, 0.0, 1.0))}, leaf.record())


def register() -> Job:
    """Register the ``leaf_variations`` job (needs ``branchnb.leaves``)."""
    from ..leaves.induction import InductionParams
    from ..leaves.synthesis import SynthesisParams

    return register_job(Job(
        "leaf_variations", sections={"synthesis": SynthesisParams, "induction": InductionParams},
        inputs={"exemplars": None, "training_index": 0, "layers": None, "rng": 0},
        prepare=_prepare, make=_make, stem="leaf",
        description="new RGBA leaves by structural layering from a few exemplars of one kind and the layers "
                    "scribbled on one of them (a LayerSet JSON or layer masks)"), replace=True)
