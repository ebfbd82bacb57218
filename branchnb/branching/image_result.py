"""What :func:`~branchnb.branching.image_synthesis.synthesize_image` returns.

:class:`ImageSynthesisResult` (the image, where every pixel came from, the
seams) and :class:`FragmentMatch` (the source fragment chosen for each
target fragment, with its costs).
"""

from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np

from ..core.image import as_rgb
from ..core.io import encode_png
from ..core.render import draw_polylines
from ..core.structure import Structure
from .fragments import Fragment
from .image_params import ImageSynthesisParams
from .regions import ExampleRegions

__all__ = ["FragmentMatch", "ImageSynthesisResult"]


@dataclass
class FragmentMatch:
    """One synthesised target fragment and the source fragment chosen for it.

    Parameters
    ----------
    target, source : Fragment
        The target fragment (on the synthesised skeleton) and the source
        fragment (on the example's) copied into it.
    shape_cost : float
        ``S`` of the chosen candidate.
    colour_cost : float
        ``C`` of the chosen candidate.
    angle : float
        Rotation of the rigid alignment (radians).
    max_displacement : float
        Largest skeleton correction the displacement field applied (pixels).
    pixels : int
        Output pixels the fragment ended up providing.
    """

    target: Fragment
    source: Fragment
    shape_cost: float
    colour_cost: float
    angle: float
    max_displacement: float
    pixels: int


@dataclass
class ImageSynthesisResult:
    """Result of :func:`synthesize_image`.

    Parameters
    ----------
    image : (H, W, C) float32 ndarray
        The synthesised image (same channels as the example).
    fragment_mask : (H, W) bool ndarray
        Pixels provided by skeleton fragments.
    fill_mask : (H, W) bool ndarray
        Pixels provided by gap completion.
    source : (H, W, 2) float ndarray
        Example pixel (x, y) each output pixel was copied from (before the
        photometric correction); NaN where none.
    fragment_index : (H, W) int ndarray
        Index into ``fragments`` of the fragment that provided each pixel
        (-1 for gap completion).
    seams : (H, W) bool ndarray
        Seam pixels of all compositions (fragments and patches).
    fragments : list of FragmentMatch
        The source chosen for every target fragment, in synthesis order.
    seam_cost : float
        Sum of the seam costs of every composition.
    target : Structure
        The target structure (as given).
    example_regions : ExampleRegions
        Branch body, branch-like and unusable masks of the example.
    n_inpainted : int
        Output pixels no patch could fill (diffusion-inpainted; normally 0).
    timings : dict
        Seconds spent per stage.
    params : ImageSynthesisParams
        The parameters used.
    example_labels, labels : (H, W) int ndarray or None
        Flat-colour regions of the example and of the output
        (``params.keep_regions``).
    """

    image: np.ndarray
    fragment_mask: np.ndarray
    fill_mask: np.ndarray
    source: np.ndarray
    fragment_index: np.ndarray
    seams: np.ndarray
    fragments: list
    seam_cost: float
    target: Structure
    example_regions: ExampleRegions | None = None
    n_inpainted: int = 0
    timings: dict = field(default_factory=dict)
    params: ImageSynthesisParams | None = None
    #: Flat-colour regions of the example ((h, w) int; all 0 when it is not flat-coloured).
    example_labels: np.ndarray | None = None
    #: Region of every output pixel (None when regions were not kept).
    labels: np.ndarray | None = None

    def overlay(self, *, skeleton: bool = True, seams: bool = True) -> np.ndarray:
        """The image with the target skeleton (red) and the seams (yellow) drawn over it.

        Parameters
        ----------
        skeleton : bool, default True
            Draw the target skeleton in red.
        seams : bool, default True
            Draw the seams in yellow.

        Returns
        -------
        (H, W, 3) ndarray
            An RGB copy of the image with the overlays.
        """
        img = as_rgb(self.image) if self.image.shape[2] != 3 else self.image
        img = img.copy()
        if seams:
            img[self.seams] = 0.6 * img[self.seams] + 0.4 * np.array([1.0, 0.9, 0.0], np.float32)
        if skeleton:
            img = draw_polylines(img, [b.points for b in self.target.branches], widths=1.0,
                                 colors=(0.9, 0.1, 0.1))
        return img

    def _repr_png_(self) -> bytes:
        return encode_png(self.image)
