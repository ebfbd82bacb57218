"""Writing new leaves out: RGBA PNGs and a strict-JSON record (:func:`save_leaves`).

Split from :mod:`branchnb.leaves.synthesis`, which re-exports it.
"""

from __future__ import annotations

import os

from ..core.io import encode_png
from ..core.jsonio import dumps_strict


def save_leaves(leaves, outdir, *, prefix: str = "leaf") -> list[str]:
    """Write each leaf as an RGBA PNG plus ``leaves.json``, a strict-JSON record of what made each.

    Returns the paths written (PNGs, then the JSON).

    Parameters
    ----------
    leaves : list of GeneratedLeaf
        The leaves, e.g. from :func:`~branchnb.leaves.synthesis.generate`.
    outdir : str or path-like
        Output folder (created if needed; existing files are overwritten).
    prefix : str
        File names are ``<prefix>_0000.png``, ... and ``<prefix>s.json``
        (default ``"leaf"``: ``leaves.json``).

    Returns
    -------
    list of str
    """
    if isinstance(leaves, (str, bytes, dict)) or not isinstance(leaves, (list, tuple)):
        raise TypeError(f"leaves must be a list of GeneratedLeaf, got {type(leaves).__name__}")
    leaves = list(leaves)
    if not isinstance(outdir, (str, os.PathLike)) or not str(outdir).strip():
        raise TypeError(f"outdir must be a non-empty folder path, got {outdir!r:.60}")
    if os.path.exists(outdir) and not os.path.isdir(outdir):
        raise ValueError(f"outdir {str(outdir)!r} is a file, not a folder")
    from .synthesis import GeneratedLeaf  # here: .synthesis imports this module

    for i, leaf in enumerate(leaves):
        if not isinstance(leaf, GeneratedLeaf):
            raise TypeError(f"leaves[{i}] must be a GeneratedLeaf, got {type(leaf).__name__}")
    if not isinstance(prefix, str) or not prefix or os.sep in prefix:
        raise ValueError(f"prefix must be a plain file-name prefix, got {prefix!r}")
    os.makedirs(outdir, exist_ok=True)
    paths, records = [], []
    for i, leaf in enumerate(leaves):
        name = f"{prefix}_{i:04d}.png"
        path = os.path.join(outdir, name)
        with open(path, "wb") as f:
            f.write(encode_png(leaf.image))
        rec = leaf.record()
        rec["file"] = name
        records.append(rec)
        paths.append(path)
    jpath = os.path.join(outdir, f"{prefix}s.json")
    text = dumps_strict({"version": 1, "leaves": records}, name="leaves", indent=1)
    with open(jpath, "w") as f:
        f.write(text)
    paths.append(jpath)
    return paths
