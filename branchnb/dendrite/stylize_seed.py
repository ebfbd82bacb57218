"""Dendritic stylization, step 0: the working image and the seed (split from
:mod:`~branchnb.dendrite.stylization`, whose :class:`~branchnb.dendrite.stylization.Stylizer`
has these methods).

The image resampled to the planning lattice, the scale between image and lattice, the
seed the structure grows from (the darkest point, or for lightning the top of the picture
or the strike's origin on a lightning photo).
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from ..core.image import as_gray
from ..core.params import check_params
from ..core.validate import Points, checked
from .lattice import direction_factors
from .main_channel import (
    silhouette,
    wide_top,
)
from .photo_strike import strike_origin
from .scale import planning_size, resample_to_lattice
from .stylize_params import (
    LIGHTNING_SEED_BLUR,
    LIGHTNING_SEED_DENSITY,
    STRIKE_MAX_COVER,
    STRIKE_PHOTO_UP,
    StylizeParams,
)

__all__: list[str] = []

def _subset(p, names):
    return tuple(getattr(p, n) for n in names)


#: Rounds of :func:`~branchnb.dendrite.thickness.twigs_within_ink` on a small image.
_PRUNE_ROUNDS = 3

_IMPORTANCE = ("lattice_size", "intensity_weight", "gradient_weight", "sigma")
_LATTICE = ("cost_weight", "epsilon", "noise")
_PLAN = ("metric", "blend_weight", "break_ties")
_ENDPOINTS = ("n_endpoints", "endpoint_gamma", "endpoint_threshold", "endpoint_floor",
              "stipple_iterations")


#: Direction factors of a bolt's side branches on a photo without a strike (``STRIKE_PHOTO_UP``).
_SIDE_FACTORS = direction_factors(up=STRIKE_PHOTO_UP) / direction_factors()



class _SeedSteps:
    """:class:`~branchnb.dendrite.stylization.Stylizer`'s lattice-scale and seed methods
    (they use its ``image`` and ``_get`` cache)."""

    @checked()
    def working_image(self, p: StylizeParams) -> np.ndarray:
        """The image resampled to the planning lattice (``p.lattice_size``; on a small picture
        at most ``SMALL_LATTICE_RATIO`` times its size, :func:`~branchnb.dendrite.scale.planning_size`).

        Parameters
        ----------
        p : StylizeParams
            Only ``lattice_size`` is used.

        Returns
        -------
        (h, w, 3) float32 ndarray
            Cached; the input itself when the sizes agree.
        """
        size = planning_size(self.shape, p.lattice_size)
        return self._get(("work", size), lambda: resample_to_lattice(self.image, size))

    def lattice_factor(self, p: StylizeParams) -> float:
        """Pixels of the planning lattice per pixel of a ``p.lattice_size`` lattice: 1, or below 1
        on a picture planned on a smaller lattice (:func:`~branchnb.dendrite.scale.planning_size`).

        Parameters
        ----------
        p : StylizeParams
            Only ``lattice_size`` is used.

        Returns
        -------
        float

        Examples
        --------
        >>> from branchnb.dendrite import Stylizer, StylizeParams
        >>> p = StylizeParams()
        >>> Stylizer(np.ones((600, 800))).lattice_factor(p), Stylizer(np.ones((48, 64))).lattice_factor(p)
        (1.0, 0.265625)
        """
        size = planning_size(self.shape, p.lattice_size)  # validates lattice_size
        if p.lattice_size <= 0:
            return 1.0
        return size / float(p.lattice_size)

    def size_scale(self, p: StylizeParams) -> float:
        """Image pixels per pixel of a ``p.lattice_size`` lattice (geometric mean of x and y): the
        scale the size adaptation (:func:`~branchnb.dendrite.stylize_params.effective_params`)
        is stated for, also where the picture is planned on a smaller lattice.

        Parameters
        ----------
        p : StylizeParams
            Only ``lattice_size`` is used.

        Returns
        -------
        float
        """
        return float(np.sqrt(np.prod(self.scale(p)))) * self.lattice_factor(p)

    @checked()
    def scale(self, p: StylizeParams) -> np.ndarray:
        """Image pixels per lattice pixel, ``(sx, sy)``.

        Parameters
        ----------
        p : StylizeParams
            Only ``lattice_size`` is used.

        Returns
        -------
        (2,) float64 ndarray
            1 on a lattice of the image's own size, 2 for a 1024-px image on the
            512 lattice.

        Examples
        --------
        >>> from branchnb.dendrite import Stylizer, StylizeParams
        >>> Stylizer(np.ones((64, 64))).scale(StylizeParams(lattice_size=32)).tolist()
        [2.0, 2.0]
        """
        h, w = self.shape
        hw, ww = self.working_image(p).shape[:2]
        return np.array([w / ww, h / hw])

    @checked(points=Points())
    def to_lattice(self, p: StylizeParams, points) -> np.ndarray:
        """Image ``(x, y)`` points in lattice coordinates (pixel centres map to centres).

        Parameters
        ----------
        p : StylizeParams
            Only ``lattice_size`` is used.
        points : (N, 2) array_like
            ``(x, y)`` in image pixels.

        Returns
        -------
        (N, 2) float64 ndarray
            Lattice ``(x, y)``, clipped to the lattice.
        """
        hw, ww = self.working_image(p).shape[:2]
        q = (np.asarray(points, float) + 0.5) / self.scale(p) - 0.5
        return np.clip(q, 0, [ww - 1, hw - 1])

    @checked(points=Points())
    def to_image(self, p: StylizeParams, points) -> np.ndarray:
        """Lattice ``(x, y)`` points in image coordinates.

        Parameters
        ----------
        p : StylizeParams
            Only ``lattice_size`` is used.
        points : (N, 2) array_like
            ``(x, y)`` in lattice pixels.

        Returns
        -------
        (N, 2) float64 ndarray
            Image ``(x, y)`` (not clipped).
        """
        return (np.asarray(points, float) + 0.5) * self.scale(p) - 0.5

    @checked()
    def default_seed(self, params: StylizeParams | None = None,
                     metaphor: str | None = "plain") -> np.ndarray:
        """Where the dendrite starts by default.

        Without ``params``, the image centre. With them, the centre of the most
        important region: the maximum of the importance blurred over 8 % of the
        lattice diagonal. The non-scalar metric floods from the seed in order of
        the path's largest edge, so everything behind a costly barrier (a bright
        region around the seed) ties at that barrier's cost and is reached by
        nearly straight cumulative paths, a radial burst; starting in the
        darkest, most detailed region keeps the branches wandering where the
        ink is.

        Parameters
        ----------
        params : StylizeParams, optional
            Parameters of the importance map and the endpoint threshold; None
            gives the image centre.
        metaphor : {"plain", "vines", "lightning", None}
            The rendering the seed is for. For ``"plain"`` and None, on a picture whose
            ground is its paper (a neon drawing on black, chalk on a board, ink on pink
            card: :func:`~branchnb.dendrite.foreground._paper_ground`) the seed is found
            on the picture levelled to that ground, as :meth:`run` finds it; the other
            metaphors read the picture as it is.

        Returns
        -------
        (2,) float64 ndarray
            ``(x, y)`` in image pixels.

        Notes
        -----
        Beyond the paper (dendrite42): :meth:`run` with the plain metaphor seeds on the
        levelled picture, but the app's preview asked for the seed on the picture as it is,
        so on a dark or coloured paper its trunk started elsewhere than the full update's
        (on a dark ground the ground itself is the darkest region).

        Examples
        --------
        >>> from branchnb.dendrite import Stylizer, StylizeParams
        >>> img = np.ones((40, 60)); img[5:15, 40:55] = 0.0
        >>> st = Stylizer(img)
        >>> st.default_seed().tolist(), bool(st.default_seed(StylizeParams(lattice_size=0))[0] > 30)
        ([29.5, 19.5], True)
        """
        if metaphor not in ("plain", "vines", "lightning", None):
            raise ValueError(f"metaphor must be 'plain', 'vines', 'lightning' or None, got {metaphor!r}")
        h, w = self.shape
        if params is None:
            return np.array([(w - 1) / 2.0, (h - 1) / 2.0])
        if metaphor in ("plain", None):
            ground = self._get(("paper_ground",), self._find_paper_ground)
            if ground is not None:
                return self._levelled(ground)._importance_seed(params)
        return self._importance_seed(params)

    def start_seed(self, params: StylizeParams | None = None, metaphor: str | None = "plain") -> np.ndarray:
        """Where :meth:`run` starts the dendrite when no seed is given.

        The plain metaphor's :meth:`default_seed`, a lightning bolt's :meth:`top_seed` and the
        vines' most important inner point of their object, each with the parameters :meth:`run`
        adapts to the image size and the metaphor (an app's reduced-size preview asks for this
        seed on the full picture, so its trunk starts where the full update's does).

        Parameters
        ----------
        params : StylizeParams, optional
            Paper defaults if None.
        metaphor : {"plain", "vines", "lightning", None}
            The rendering the seed is for.

        Returns
        -------
        (2,) float64 ndarray
            ``(x, y)`` in image pixels.

        Examples
        --------
        >>> from branchnb.dendrite import Stylizer, StylizeParams
        >>> img = np.ones((40, 60)); img[10:30, 40:55] = 0.0
        >>> st = Stylizer(img)
        >>> p = StylizeParams(lattice_size=0)
        >>> bool(np.allclose(st.start_seed(p, "lightning"), st.run(p, metaphor="lightning").seed))
        True
        """
        if metaphor not in ("plain", "vines", "lightning", None):
            raise ValueError(f"metaphor must be 'plain', 'vines', 'lightning' or None, got {metaphor!r}")
        p = check_params(params if params is not None else StylizeParams())
        if metaphor in ("plain", None):
            return self.default_seed(p, metaphor=metaphor)
        _given, p, _k, obj, _opts = self._metaphor_setup(p, metaphor, {}, with_options=False)
        if metaphor == "lightning":
            return self.top_seed(p)
        return self._vine_seed(p, obj) if obj is not None else self.default_seed(p, metaphor=metaphor)

    def _importance_seed(self, params: StylizeParams) -> np.ndarray:
        """:meth:`default_seed` on the picture as it is (image pixels)."""
        h, w = self.shape
        imp = self.importance(params).astype(np.float64)
        if np.ptp(imp) == 0:
            return np.array([(w - 1) / 2.0, (h - 1) / 2.0])
        sigma = 0.08 * float(np.hypot(*imp.shape))
        smooth = ndimage.gaussian_filter(imp, sigma, mode="constant")
        row, col = np.unravel_index(int(np.argmax(smooth)), smooth.shape)
        if imp[row, col] < params.endpoint_threshold:  # e.g. inside a ring: the nearest ink
            ys, xs = np.nonzero(imp >= params.endpoint_threshold)
            if xs.size:
                k = int(np.argmin((xs - col) ** 2 + (ys - row) ** 2))
                row, col = ys[k], xs[k]
        return self.to_image(params, [float(col), float(row)])

    def top_seed(self, params: StylizeParams) -> np.ndarray:
        """Where a lightning bolt starts: the top of the picture's content.

        The median column of the pixels whose importance reaches
        ``params.endpoint_threshold`` within 5 % of the lattice's height below
        the topmost such pixel (beyond the paper: from the default seed, in the
        middle of the picture, the bolt burst out in every direction; from the
        top it runs down and forks like a strike). On a photo (content all over)
        with a strike of its own, the top of its brightest strike
        (:func:`~branchnb.dendrite.photo_strike.strike_origin`). Only content pixels in a
        wide part count (:func:`~branchnb.dendrite.main_channel.wide_top`):
        their share of content within a blur of ``LIGHTNING_SEED_BLUR`` of the
        lattice's diagonal reaches ``LIGHTNING_SEED_DENSITY`` of its maximum (a
        thin tip on top, a fern's leaflets or a horse's ear, started the widest
        channel with a knot).

        Parameters
        ----------
        params : StylizeParams
            Parameters of the importance map and the endpoint threshold.

        Returns
        -------
        (2,) float64 ndarray
            ``(x, y)`` in image pixels; the top centre of the image when nothing
            reaches the threshold.

        Examples
        --------
        >>> from branchnb.dendrite import Stylizer, StylizeParams
        >>> img = np.ones((40, 60)); img[10:30, 40:55] = 0.0
        >>> [round(v) for v in Stylizer(img).top_seed(StylizeParams(lattice_size=0))]
        [47, 7]
        """
        content = self._lightning_content(params)[0]  # an object on its ground, if found
        if silhouette(content).mean() > STRIKE_MAX_COVER:
            # a photo: its own brightest strike's top, if it has one (beyond the paper:
            # from the top of the picture a bolt on a lightning photo started in the cloud)
            at = self.strike(params)
            if at is not None:
                return self.to_image(params, [float(at[0]), float(at[1])])
        at = wide_top(content, LIGHTNING_SEED_BLUR, LIGHTNING_SEED_DENSITY)
        if at is None:
            return np.array([(self.shape[1] - 1) / 2.0, 0.0])
        xb, yb = at
        return self.to_image(params, [float(xb), float(yb)])

    def strike(self, p: StylizeParams) -> tuple[int, int] | None:
        """The top of the photo's own strike on the lattice, or None (cached).

        :func:`~branchnb.dendrite.photo_strike.strike_origin` of the working image's
        luminance, computed once per lattice size (the seed and the side branches both
        ask for it).

        Parameters
        ----------
        p : StylizeParams
            Uses ``lattice_size``.

        Returns
        -------
        (x, y) or None
            In lattice pixels.
        """
        return self._get(("strike_origin", p.lattice_size),
                         lambda: strike_origin(as_gray(self.working_image(p))))
