"""Batched drawing that cannot leave the canvas manager stuck."""

from __future__ import annotations

from contextlib import contextmanager

from ipycanvas import canvas as _ipycanvas


@contextmanager
def batched():
    """Like ``ipycanvas.hold_canvas()`` but restores the manager on errors.

    ``hold_canvas`` switches the global canvas manager into caching mode and
    only switches it back if the block finishes; an exception inside the
    block would leave every canvas of the kernel silently buffering. This
    version always flushes and restores.
    """
    manager = _ipycanvas._CANVAS_MANAGER
    was_caching = manager._caching
    manager._caching = True
    try:
        yield
    finally:
        manager.flush()
        manager._caching = was_caching
