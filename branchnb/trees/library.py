"""The library of processed exemplars (:class:`TreeLibrary`).

Split out of :mod:`branchnb.trees.variations`, which re-exports it.

Examples
--------
>>> from branchnb.trees import TreeLibrary
>>> len(TreeLibrary(size=64))
0
"""

from __future__ import annotations

from collections.abc import Sequence

import cv2
import numpy as np

from .. import data as _data
from ..core.image import composite_over
from ..core.io import encode_png
from ..core.params import check_params
from ..core.validate import Array, Int, Seq, checked
from .contour import ContourParams
from .exemplar import (
    SPRITE_SIZE,
    ExemplarParams,
)
from .histogram_transfer import _remember_parts
from .translucent import translucent_level
from .variations import (
    GROUND_METHODS,
    MAX_VARIATIONS,
    RPG_TREES,
    TRUNK_METHODS,
    Exemplar,
    Variation,
    VariationParams,
    _check_compatible,
    _select,
    exemplar_parts,
    make_variation,
    process_exemplar,
    tile_images,
)
from .variety import morph_sequence, similar_variations, tree_variations

__all__ = ["TreeLibrary"]

#: The paper's working size ``S`` (and the most an automatic size takes).
PAPER_SIZE = 1024
#: Least automatic working size (``ExemplarParams.size``'s minimum).
MIN_AUTO_SIZE = 32


def _extent(image) -> int:
    """Largest side of the opaque (alpha >= 0.5, or a translucent source's own level) bounding box of
    an RGBA image (0: none or not RGBA)."""
    a = np.asarray(image)
    if a.ndim != 3 or a.shape[2] != 4:
        return 0
    al = a[..., 3].astype(np.float32)
    if np.issubdtype(a.dtype, np.integer):
        al = al / float(np.iinfo(a.dtype).max)
    # a translucent source's silhouette lies lower (translucent.py): a glass tree has no alpha >= 0.5
    ys, xs = np.nonzero(al >= translucent_level(al))
    return int(max(np.ptp(ys), np.ptp(xs)) + 1) if len(ys) else 0


def _auto_size(extents) -> int:
    """Automatic working size: the paper's 1024, but the largest extent when that is at most
    :data:`~branchnb.trees.exemplar.SPRITE_SIZE` (sprites), at least
    :data:`MIN_AUTO_SIZE` (an integer multiple of the extent below that, so that pixel art is
    enlarged by whole pixels)."""
    e = max([int(x) for x in extents] + [1])
    if e > SPRITE_SIZE:
        return PAPER_SIZE
    if e < MIN_AUTO_SIZE:
        return e * -(-MIN_AUTO_SIZE // e)
    return e




class TreeLibrary:
    """Processed exemplars that variations are made from.

    Parameters
    ----------
    exemplars : sequence of Exemplar, optional
        Processed exemplars to start with (:func:`process_exemplar`); they
        must share the working size and contour layout.
    size : int or None
        Working size ``S`` of trees added later (paper: 1024). None (the
        default) picks it from the trees added: the paper's 1024, but when
        no tree's extent (its opaque bounding box) exceeds 256 px, the
        largest extent (at least 32: an integer multiple of the extent
        below that). Beyond the paper: 32-256 px sprites are worked on, and their variations
        come out, at their own size, in a fraction of a second, instead of
        16x enlarged blocks at 1024; pixel art stays on its own pixel grid
        (:mod:`~branchnb.trees.pixel_art`). When a larger tree is added, the
        trees added before are processed again at the new size.
    contour_params : ContourParams, optional
        For trees added later.
    trunk : {"auto", "segmentation", "stem"}
        How trees added later find their trunk (:func:`~branchnb.trees.processing.exemplar_trunk`).
    ground : {"cut", "keep"}
        Whether trees added later have ground clutter at the trunk foot
        cut off (:func:`process_exemplar`).

    Notes
    -----
    Cast shadows (beyond the paper; issue 24): a soft, semi-transparent
    shadow under a tree (a game sprite's ellipse at the foot, alpha below
    the 0.5 alpha threshold) is no part of an exemplar. It is dropped from
    every exemplar, so from every variation too: a tree added with its
    shadow gives the same exemplar as without it, and no mix carries a
    half shadow. The shadow is not redrawn under a mix (the variations stand
    on the bottom edge of their square image, with no room below the foot);
    composite one under the variation when the scene needs it. Nor do its
    soft pixels make a hard-edged sprite count as anti-aliased
    (:func:`~branchnb.trees.exemplar.normalize_exemplar`): it stays pixel art,
    outline and all.

    Examples
    --------
    >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
    >>> len(lib), lib.names
    (2, ['tree_rpg_05', 'tree_rpg_06'])

    A 64 px sprite is worked on at its own size:

    >>> from branchnb.trees._sprite_check import sprite
    >>> sprites = TreeLibrary()
    >>> sprites.add(sprite("fir", 64)).size, sprites.size
    (62, 62)
    """

    @checked(exemplars=Seq(), size=Int(16, 8192))
    def __init__(self, exemplars: Sequence[Exemplar] = (), *, size: int | None = None,
                 contour_params: ContourParams | None = None, trunk: str = "auto",
                 ground: str = "cut"):
        if trunk not in TRUNK_METHODS:
            raise ValueError(f"trunk must be one of {list(TRUNK_METHODS)}, got {trunk!r}")
        if ground not in GROUND_METHODS:
            raise ValueError(f"ground must be one of {list(GROUND_METHODS)}, got {ground!r}")
        self.exemplars: list[Exemplar] = []
        self.trunk = trunk
        self.ground = ground
        self._auto = size is None
        self.size = PAPER_SIZE if size is None else int(size)
        # source images of trees added by add() (for a new automatic working size)
        self._sources: dict[str, tuple] = {}
        self.contour_params = contour_params if contour_params is not None else ContourParams()
        check_params(ExemplarParams(size=self.size), name="size")
        for i, e in enumerate(exemplars):
            if not isinstance(e, Exemplar):
                raise TypeError(f"exemplars[{i}] must be an Exemplar (see process_exemplar), got {type(e).__name__}")
            self.add_exemplar(e)

    @classmethod
    def from_data(cls, names: Sequence[str] | None = None, *, size: int = 1024,
                  contour_params: ContourParams | None = None, trunk: str = "auto",
                  ground: str = "cut") -> TreeLibrary:
        """A library of sample trees from ``branchnb.data`` (default: :data:`RPG_TREES`).

        Parameters
        ----------
        names : sequence of str, optional
            Sample names (``branchnb.data.names("trees")``); None takes
            :data:`RPG_TREES`.
        size : int
            Working size ``S`` (paper: 1024; 128-256 is enough to try things
            quickly).
        contour_params : ContourParams, optional
            ``N``, crown share, ``M``, dilation.
        trunk : {"auto", "segmentation", "stem"}
            How each tree finds its trunk (:func:`~branchnb.trees.processing.exemplar_trunk`).
        ground : {"cut", "keep"}
            Whether ground clutter at the trunk foot is cut off.

        Returns
        -------
        TreeLibrary
            The processed samples, in the order of ``names``.

        Examples
        --------
        >>> lib = TreeLibrary.from_data(["tree_rpg_05"], size=128)
        >>> lib.names, lib.size
        (['tree_rpg_05'], 128)
        """
        lib = cls(size=size, contour_params=contour_params, trunk=trunk, ground=ground)
        for n in (RPG_TREES if names is None else names):
            lib.add(_data.load(n), n)
        return lib

    # -- contents
    @property
    def names(self) -> list[str]:
        return [e.name for e in self.exemplars]

    def __len__(self) -> int:
        return len(self.exemplars)

    def __iter__(self):
        return iter(self.exemplars)

    def __contains__(self, name) -> bool:
        return name in self.names

    def __getitem__(self, key) -> Exemplar:
        return _select(self.exemplars, [key])[0]

    @checked()
    def index(self, name: str) -> int:
        """Position of the exemplar called ``name``.

        Parameters
        ----------
        name : str
            An exemplar's name.

        Returns
        -------
        int
            Its index in the library's ``exemplars`` list (and in weight vectors).

        Raises
        ------
        ValueError
            If no exemplar has that name.
        """
        if name not in self.names:
            raise ValueError(f"no exemplar named {name!r}; the library has {self.names}")
        return self.names.index(name)

    @checked(trunk_mask=Array(ndim=2))
    def add(self, image, name: str | None = None, *, trunk_mask=None) -> Exemplar:
        """Process an RGBA tree image and add it (see :func:`process_exemplar`).

        Parameters
        ----------
        image : (H, W, 4) array_like
            RGBA tree on a transparent background, any size; normalised to
            the library's working size.
        name : str, optional
            Its name; None gives ``"tree_<i>"``. An exemplar of the same name
            is replaced.
        trunk_mask : (H, W) array_like, optional
            Trunk pixels of ``image``; None finds the trunk with the
            library's ``trunk`` method.

        Returns
        -------
        Exemplar
            The processed exemplar, now in the library.

        Examples
        --------
        >>> from branchnb.trees.synthetic import synthetic_tree
        >>> lib = TreeLibrary(size=64)
        >>> lib.add(synthetic_tree("clean", rng=0, size=64).image).name, len(lib)
        ('tree_0', 1)
        """
        name = f"tree_{len(self)}" if name is None else str(name)
        if self._auto and all(n in self._sources for n in self.names):
            sources = {**self._sources, name: (image, trunk_mask)}
            size = _auto_size([_extent(im) for im, _ in sources.values()])
            if size != self.size:       # re-process the trees added before at the new size
                self.size = size
                old = [e.name for e in self.exemplars]
                self.exemplars = []
                for n in old:
                    self._add_source(*sources[n], n)
                if name in old:
                    return self[name]
        return self._add_source(image, trunk_mask, name)

    def _add_source(self, image, trunk_mask, name: str) -> Exemplar:
        ex = process_exemplar(image, name, trunk_mask=trunk_mask, trunk=self.trunk, ground=self.ground,
                              exemplar_params=ExemplarParams(size=self.size, sprite_pixels=self._auto),
                              contour_params=self.contour_params)
        out = self.add_exemplar(ex)
        self._sources[name] = (image, trunk_mask)
        return out

    @checked()
    def set_trunk(self, name: str, trunk, source: str = "mask") -> Exemplar:
        """Replace the trunk mask (working-image pixels) of exemplar ``name``,
        e.g. with a segmentation corrected by scribbles; pins and contours follow.

        Parameters
        ----------
        name : str
            The exemplar to change.
        trunk : (S, S) array_like
            New trunk pixels in its working image.
        source : str
            Recorded as the exemplar's ``trunk_source``.

        Returns
        -------
        Exemplar
            The new exemplar (replacing the old one in the library).
        """
        return self.add_exemplar(self[name].with_trunk(trunk, source))

    def add_exemplar(self, exemplar: Exemplar) -> Exemplar:
        """Add (or replace, by name) an already processed exemplar.

        Parameters
        ----------
        exemplar : Exemplar
            From :func:`process_exemplar`; it must share the working size
            and contour layout of the exemplars already in the library (the
            first one sets the library's ``size``).

        Returns
        -------
        Exemplar
            ``exemplar``.

        Raises
        ------
        TypeError
            If ``exemplar`` is not an Exemplar.
        ValueError
            If its size or contour layout differs from the library's.
        """
        if not isinstance(exemplar, Exemplar):
            raise TypeError(f"exemplar must be an Exemplar, got {type(exemplar).__name__}")
        if self.exemplars:
            _check_compatible([self.exemplars[0], exemplar])
        elif exemplar.size != self.size:
            self.size = exemplar.size
        self._sources.pop(exemplar.name, None)
        if exemplar.name in self.names:
            self.exemplars[self.index(exemplar.name)] = exemplar
        else:
            self.exemplars.append(exemplar)
        # Recolouring against (or of) this tree reuses its stored parts instead of segmenting it.
        _remember_parts(exemplar.image, exemplar_parts(exemplar))
        return exemplar

    # -- operations
    @checked()
    def variation(self, weights=None, params: VariationParams | None = None, **kwargs) -> Variation:
        """:func:`make_variation` on this library.

        Parameters
        ----------
        weights : (k,) array_like or dict, optional
            Convex shape weights, one per exemplar or ``{name: weight}``;
            None draws random ones.
        params : VariationParams, optional
            Synthesis parameters; None uses the defaults.
        **kwargs
            Further arguments of :func:`make_variation` (``use``,
            ``colour_weights``, ``reference``, ``rng``, parameter overrides).

        Returns
        -------
        Variation

        Examples
        --------
        >>> from branchnb.trees import TreeLibrary
        >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
        >>> lib.variation([0.5, 0.5], rng=0).label(1)
        '0.5 tree_rpg_05 + 0.5 tree_rpg_06'
        """
        return make_variation(self, weights, params, **kwargs)

    @checked(n=Int(1, MAX_VARIATIONS))
    def variations_of(self, target, n: int = 6, params: VariationParams | None = None,
                      **kwargs) -> list[Variation]:
        """:func:`tree_variations` on this library.

        Parameters
        ----------
        target : str or int
            ``T``, the tree to vary.
        n : int
            Number of variations.
        params : VariationParams, optional
            ``keep`` is ``T``'s shape weight; None uses the defaults.
        **kwargs
            Further arguments of :func:`tree_variations` (``use``, ``rng``,
            ``reference``, parameter overrides).

        Returns
        -------
        list of Variation
        """
        return tree_variations(self, target, n, params, **kwargs)

    @checked(n=Int(1, MAX_VARIATIONS))
    def similar(self, variation: Variation, n: int = 6, params: VariationParams | None = None,
                **kwargs) -> list[Variation]:
        """:func:`similar_variations` on this library.

        Parameters
        ----------
        variation : Variation
            The centre ("more like this").
        n : int
            Number of variations.
        params : VariationParams, optional
            Synthesis parameters; None uses the defaults.
        **kwargs
            Further arguments of :func:`similar_variations` (``keep``,
            ``rng``, parameter overrides).

        Returns
        -------
        list of Variation
        """
        return similar_variations(self, variation, n, params, **kwargs)

    @checked(steps=Int(2, MAX_VARIATIONS))
    def morph(self, a, b, steps: int = 5, params: VariationParams | None = None,
              **kwargs) -> list[Variation]:
        """:func:`morph_sequence` on this library.

        Parameters
        ----------
        a, b : str or int
            The two trees.
        steps : int
            Number of frames (>= 2).
        params : VariationParams, optional
            Synthesis parameters; None uses the defaults.
        **kwargs
            Further arguments of :func:`morph_sequence` (``colour``, ``rng``,
            parameter overrides).

        Returns
        -------
        list of Variation
        """
        return morph_sequence(self, a, b, steps, params, **kwargs)

    @checked(size=Int(8, 4096))
    def thumbnails(self, size: int = 96) -> list[np.ndarray]:
        """Each exemplar over white, ``(size, size, 3)``.

        Parameters
        ----------
        size : int
            Side of each thumbnail in pixels (area-averaged from ``S``).

        Returns
        -------
        list of (size, size, 3) float32 ndarray
            In library order.
        """
        return [cv2.resize(composite_over(e.image, (1.0, 1.0, 1.0)), (size, size),
                           interpolation=cv2.INTER_AREA) for e in self.exemplars]

    @checked(size=Int(8, 4096), cols=Int(1, 1000))
    def contact_sheet(self, size: int = 96, cols: int = 7) -> np.ndarray:
        """All thumbnails in a grid.

        Parameters
        ----------
        size : int
            Side of each thumbnail in pixels.
        cols : int
            Thumbnails per row (fewer when the library is smaller).

        Returns
        -------
        (H, W, 3) float32 ndarray
            :func:`tile_images` of :meth:`thumbnails`, 2 px white gaps.

        Examples
        --------
        >>> from branchnb.trees import TreeLibrary
        >>> lib = TreeLibrary.from_data(["tree_rpg_05", "tree_rpg_06"], size=128)
        >>> lib.contact_sheet(32, cols=2).shape
        (32, 66, 3)
        """
        return tile_images(self.thumbnails(size), cols=cols)

    def __repr__(self) -> str:
        return f"TreeLibrary({len(self)} exemplars, size={self.size}: {', '.join(self.names)})"

    def _repr_png_(self) -> bytes | None:
        return encode_png(self.contact_sheet()) if self.exemplars else None
