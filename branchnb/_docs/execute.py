"""Execute a notebook in place, keeping the widget state of the widgets it shows.

``python -m branchnb._docs.execute notebooks/00_tour.ipynb [...]`` runs each
notebook top to bottom in a fresh kernel (like the test suite) and writes it
back with its outputs and the state of every widget a cell displays, so a
reader of the committed file (and the documentation site) sees the apps.

nbclient's ``store_widget_state`` keeps every widget model the kernel still
holds, including ones that no cell shows (a closed dialog, the models behind
a recomputed view); :func:`prune_widget_state` keeps only the models
reachable from a displayed view, which is what a renderer can use. That is
often half of the state; keys that only repeat what the browser knows are
dropped too (:func:`_compact`). That keeps notebooks with apps under their
size budget.
"""

from __future__ import annotations

import json
import re
import sys
import time
from pathlib import Path

__all__ = ["execute", "prune_widget_state"]

_STATE = "application/vnd.jupyter.widget-state+json"
_VIEW = "application/vnd.jupyter.widget-view+json"
_REF = re.compile(r"IPY_MODEL_([0-9a-f]{32})")


def prune_widget_state(nb) -> tuple[int, int]:
    """Drop the widget models no displayed view reaches, and layouts' null keys; returns ``(kept, dropped)``.

    Parameters
    ----------
    nb : nbformat.NotebookNode
        A notebook with ``metadata.widgets`` as nbclient stores it (changed in place).

    Returns
    -------
    tuple of int
        Models kept and dropped.

    Examples
    --------
    >>> import nbformat
    >>> nb = nbformat.v4.new_notebook()
    >>> nb.metadata["widgets"] = {_STATE: {"state": {"a" * 32: {"state": {"children": ["IPY_MODEL_" + "b" * 32]}},
    ...                                               "b" * 32: {"state": {}}, "c" * 32: {"state": {}}}}}
    >>> nb.cells.append(nbformat.v4.new_code_cell(outputs=[nbformat.v4.new_output(
    ...     "display_data", data={_VIEW: {"model_id": "a" * 32}})]))
    >>> prune_widget_state(nb)
    (2, 1)
    """
    state = nb.get("metadata", {}).get("widgets", {}).get(_STATE, {}).get("state")
    if not state:
        return 0, 0
    roots = [out["data"][_VIEW]["model_id"] for cell in nb.cells if cell.get("cell_type") == "code"
             for out in cell.get("outputs", []) if _VIEW in out.get("data", {})]
    keep, stack = set(), list(roots)
    while stack:
        mid = stack.pop()
        if mid in keep or mid not in state:
            continue
        keep.add(mid)
        stack += _REF.findall(json.dumps(state[mid]))
    dropped = [mid for mid in state if mid not in keep]
    for mid in dropped:
        del state[mid]
    for model in state.values():
        model["state"] = _compact(model)
    return len(keep), len(dropped)


def _compact(model: dict) -> dict:
    """A model's state without what the browser knows anyway.

    Layout and style models default every attribute to null in the browser,
    so their null keys say nothing; the module names and versions repeat the
    record's own ``model_module``/``model_module_version``. Most of an app's
    saved state is such keys.
    """
    state = model.get("state")
    if not isinstance(state, dict):
        return state
    name = str(model.get("model_name", ""))
    module, version = model.get("model_module"), model.get("model_module_version")
    out = {}
    for k, v in state.items():
        if v is None and (name == "LayoutModel" or name.endswith("StyleModel")) and not k.startswith("_"):
            continue
        if (k in ("_model_module", "_view_module") and v == module) or \
                (k in ("_model_module_version", "_view_module_version") and v == version):
            continue
        out[k] = v
    return out


def execute(path, *, timeout: int = 900) -> Path:
    """Run the notebook at ``path`` in a fresh kernel and write it back with its outputs and widget state.

    Parameters
    ----------
    path : path-like
        The ``.ipynb`` file; it runs in its own folder (as in the test suite).
    timeout : int
        Seconds allowed for one cell.

    Returns
    -------
    pathlib.Path
        ``path``.
    """
    import nbformat
    from nbclient import NotebookClient

    path = Path(path)
    nb = nbformat.read(path, as_version=4)
    t0 = time.perf_counter()
    NotebookClient(nb, kernel_name="python3", timeout=timeout, store_widget_state=True,
                   resources={"metadata": {"path": str(path.parent)}}).execute()
    kept, dropped = prune_widget_state(nb)
    nbformat.write(nb, path)
    print(f"{path.name}: {time.perf_counter() - t0:.0f} s, widget models kept {kept}, dropped {dropped}, "
          f"{path.stat().st_size / 1e6:.2f} MB")
    return path


if __name__ == "__main__":  # pragma: no cover - a maintenance command
    for arg in sys.argv[1:]:
        execute(arg)
