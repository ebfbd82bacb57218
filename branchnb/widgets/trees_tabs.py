"""The trees app's segmentation and billboard-cloud tabs (moved from :mod:`branchnb.widgets.trees` unchanged).

:class:`~branchnb.widgets.trees.TreeVariationsApp` gets these methods from
``_SegmentCloudTabs``: scribble segmentation of a library tree (its trunk,
and so its pins) and the billboard cloud of the current variation or a
library tree seen from any yaw.
"""

from __future__ import annotations

import importlib.util

import numpy as np

from ..trees.segmentation import segment_tree
from ..trees.variations import exemplar_trunk

#: Whether the billboard cloud (and its tab) is available.
HAS_BILLBOARD = importlib.util.find_spec("branchnb.trees.billboard") is not None


class _SegmentCloudTabs:
    """Methods of :class:`~branchnb.widgets.trees.TreeVariationsApp` for its segmentation and cloud tabs."""

    def segment(self, name: str | None = None, scribbles=None) -> None:
        """Segment library tree ``name`` with optional scribbles and give the library the new trunk (pins follow).

        Without scribbles the library's automatic trunk is restored.

        Parameters
        ----------
        name : str, optional
            Library tree; the one shown on the segmentation canvas if None.
        scribbles : sequence of Shape, optional
            Labelled scribbles (``"trunk"``/``"crown"``/...); the canvas'
            scribbles if None (none for another tree than the one shown).
        """
        name = self.seg_tree.value if name is None else name
        ex = self.library[name]
        shapes = self.seg_canvas.model.of_kind("scribble") if scribbles is None else scribbles
        if name != self.seg_tree.value and scribbles is None:
            shapes = []
        if shapes:
            seg = segment_tree(ex.image, scribbles=shapes)
            self.segmentation = seg
            self.library.set_trunk(name, seg.trunk, "scribbles")
        else:  # back to the library's automatic trunk
            trunk, source = exemplar_trunk(ex.image, self.library.trunk)
            self.segmentation = None
            self.library.set_trunk(name, trunk, source)
        self._show_segmentation()
        if name in self.selected or name in (self.morph_a.value, self.morph_b.value):
            self.update()
            self.set_morph()

    def build_cloud(self, source: str | None = None, yaw: float | None = None):
        """Build the billboard cloud of the current variation or a library tree.

        Parameters
        ----------
        source : str, optional
            ``"current variation"`` or a library tree name; the dropdown's
            value if None.
        yaw : float, optional
            View angle in degrees for the second view (see :meth:`set_yaw`).

        Returns
        -------
        BillboardCloud or None
            Also kept as ``cloud``.

        Raises
        ------
        RuntimeError
            If :mod:`branchnb.trees.billboard` is not available.
        """
        if not HAS_BILLBOARD:
            raise RuntimeError("branchnb.trees.billboard is not available")
        from ..trees.billboard import billboard_cloud

        with self.errors.catch():
            if source is not None:
                self.cloud_source.value = source
            src = self.cloud_source.value
            if src == "current variation":
                if self.variation is None:
                    raise ValueError("no current variation")
                self.cloud = billboard_cloud(self.variation.image, rng=int(self.rng.value))
            else:
                ex = self.library[src]
                self.cloud = billboard_cloud(ex.image, ex.trunk, rng=int(self.rng.value))
            counts = ", ".join(f"{k} {v}" for k, v in self.cloud.counts().items())
            self.cloud_status.value = f"{self.cloud.n_billboards} billboards ({counts})"
            self.set_yaw(yaw)
        return self.cloud

    def set_yaw(self, yaw: float | None = None) -> None:
        """Render the billboard cloud from ``yaw`` degrees (0: the input view).

        Parameters
        ----------
        yaw : float, optional
            Rotation about the vertical axis in degrees; the slider's value
            if None. Nothing is drawn before a cloud was built.
        """
        if yaw is not None:
            self._syncing = True
            try:
                self.yaw.value = float(yaw)
            finally:
                self._syncing = False
        if self.cloud is None:
            return
        y = float(self.yaw.value)
        self.cloud_view.update([self.cloud.render(0.0), self.cloud.render(y)],
                               ["front view (yaw 0)", f"yaw {y:.0f} deg"])

    def _seg_overlay(self, ex) -> np.ndarray:
        over = np.zeros(ex.image.shape[:2] + (4,), np.float32)
        crown = ex.alpha & ~ex.trunk
        over[crown] = (0.1, 0.8, 0.1, 0.35)
        over[ex.trunk] = (0.9, 0.1, 0.1, 0.45)
        return over

    def _show_segmentation(self) -> None:
        ex = self.library[self.seg_tree.value]
        self.seg_canvas.set_overlay(self._seg_overlay(ex))
        self.seg_view.update([ex.render()], ["pins B (red), R (blue), L (magenta); C_r, C_s"])
        p = ex.contour.pins
        self.seg_status.value = (
            f"trunk from <b>{ex.trunk_source}</b>: {ex.trunk.sum() / max(ex.alpha.sum(), 1):.1%} of "
            f"the tree &nbsp;|&nbsp; B ({p.b[0]:.0f}, {p.b[1]:.0f}), R ({p.r[0]:.0f}, {p.r[1]:.0f}), "
            f"L ({p.l[0]:.0f}, {p.l[1]:.0f})" + ("" if p.has_trunk else " (no trunk: L = R = B)"))

    def _on_seg_tree(self) -> None:
        self._loading_scribbles = True
        try:
            name = self.seg_tree.value
            self.seg_canvas.set_image(self.library[name].image)
            self.seg_canvas.model.load_json(self._scribbles.get(name, '{"shapes": []}'))
        finally:
            self._loading_scribbles = False
        self._show_segmentation()

    def _on_scribble(self, _event) -> None:
        if self._loading_scribbles:
            return
        name = self.seg_tree.value
        self._scribbles[name] = self.seg_canvas.model.to_json()
        self.segment(name)
