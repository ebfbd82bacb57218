"""Dendritic stylization, the lightning metaphor's main channel and strike (split from
:mod:`~branchnb.dendrite.stylization`, whose :class:`~branchnb.dendrite.stylization.Stylizer`
has these methods).

A bolt's main channel straightened (hairpins cut), a lightning photo's strike traced as
the channel with short side branches, and the dendrite pruned to the tips kept.
"""

from __future__ import annotations

import numpy as np
from scipy import ndimage

from ..core.image import as_gray, as_rgb
from .dendrite import Dendrite, build_dendrite
from .endpoints import place_endpoints
from .foreground import _object_mask
from .lattice import Lattice
from .main_channel import (
    _channel_end,
    channel_plan,
    silhouette,
    straighten,
    strike_weights,
    with_channel,
)
from .photo_side import _short_sides, side_branches, strike_region
from .photo_strike import jag_channel, photo_channel
from .planner import PlanResult
from .strike_outline import outline_endpoints, outline_parts, outline_weights
from .strike_part import _seed_part
from .stylize_params import (
    LIGHTNING_LOOP_REACH,
    STRIKE_MAX_COVER,
    StylizeParams,
)
from .stylize_seed import _ENDPOINTS, _IMPORTANCE, _LATTICE, _PLAN, _SIDE_FACTORS, _subset

__all__: list[str] = []

#: Share of the content off the object (a ground passing the importance threshold) beyond
#: which a lightning bolt draws the object found on its ground instead.
CONTENT_MAX_SPILL = 0.25
#: How far off the object content counts as spilled, as a share of the lattice's diagonal.
CONTENT_SPILL_REACH = 0.02



class _StrikeSteps:
    """:class:`~branchnb.dendrite.stylization.Stylizer`'s lightning methods (they use its
    cached stages: ``plan``, ``dendrite``, ``importance`` ...)."""

    def _working_object(self, p: StylizeParams) -> np.ndarray | None:
        """:func:`~branchnb.dendrite.foreground._object_mask` of the working image (cached: the
        bolt's content and its outline parts both ask for it)."""
        return self._get(("working_object", p.lattice_size), lambda: _object_mask(self.working_image(p)))

    def _lightning_content(self, p: StylizeParams) -> tuple[np.ndarray, bool]:
        """Where a lightning bolt finds something to draw, and whether that is an object
        found on its ground (cached).

        The importance at least ``p.endpoint_threshold``, as the paper's stippling has it.
        Beyond the paper: where that covers the picture (more than ``STRIKE_MAX_COVER`` of
        it: a sky gradient, a dark or textured ground pass the threshold) and the picture
        has no strike of its own, or where more than ``CONTENT_MAX_SPILL`` of it lies farther
        than ``CONTENT_SPILL_REACH`` of the diagonal from the object, the object that differs in colour from its frame
        (:func:`~branchnb.dendrite.foreground._object_mask`), if there is one: a tree
        cut-out over a sky and a grass strip got one generic bolt down a dark frame.
        """
        def make():
            content = self.importance(p) >= p.endpoint_threshold
            photo = silhouette(content).mean() > STRIKE_MAX_COVER
            if photo and self.strike(p) is not None:
                return content, False
            obj = self._working_object(p)
            if obj is None:
                return content, False
            if photo:
                return obj, True
            # a ground that passes the threshold in part (a sky gradient's darker top) drew
            # half the bolt on the sky: where much of the content lies off the object, the
            # object is what to draw (a drawing on white keeps its own content, lines and all)
            # (at least 3 px: the importance's edges blur past a small object's outline)
            r = max(3, int(round(CONTENT_SPILL_REACH * float(np.hypot(*content.shape)))))
            near = ndimage.distance_transform_edt(~obj) <= r
            spill = float((content & ~near).sum()) / max(int(content.sum()), 1)
            return (obj, True) if spill > CONTENT_MAX_SPILL else (content, False)
        return self._get(("lightning_content", _subset(p, _IMPORTANCE), p.endpoint_threshold), make)

    def _outline_parts(self, p: StylizeParams, content) -> tuple[np.ndarray, np.ndarray]:
        """The objects whose outlines a lightning bolt traces, and their parts (cached;
        :func:`~branchnb.dendrite.strike_outline.outline_parts`).

        The object that differs in colour from the frame
        (:func:`~branchnb.dendrite.foreground._object_mask`) where there is one, else the
        content's silhouette: the importance's blurred edges and a drop shadow join a word's
        letters into one blob. Parts of two colours meeting along a sharp border are split
        (:func:`~branchnb.dendrite.strike_outline.split_by_colour`).
        """
        def make():
            obj = self._working_object(p)
            objs = obj & content if obj is not None else silhouette(content)
            # and split by colour: touching fruits, overlapping letters of two colours
            return objs, outline_parts(objs, image=as_rgb(self.working_image(p)))
        return self._get(("outline_parts", _subset(p, _IMPORTANCE), p.endpoint_threshold), make)

    def _traced_outlines(self, p: StylizeParams) -> np.ndarray | None:
        """The objects whose outlines a lightning bolt traces (two parts or more of
        :meth:`_outline_parts` on a picture that is not a photo), or None."""
        content, _ = self._lightning_content(p)
        if silhouette(content).mean() > STRIKE_MAX_COVER:
            return None
        objs, parts = self._outline_parts(p, content)
        return objs if parts.max() >= 2 else None

    def _object_endpoints(self, p: StylizeParams, rng_seed: int, obj) -> np.ndarray:
        # stippled on the object only: stippled on the whole picture, the tips on a sky
        # drew branches across it
        return self._get(("object_endpoints", _subset(p, _IMPORTANCE + _ENDPOINTS), rng_seed),
                         lambda: place_endpoints(
                             np.where(obj, self.importance(p), 0.0), p.n_endpoints,
                             gamma=p.endpoint_gamma, floor=0.0, threshold=0.0,
                             iterations=p.stipple_iterations, rng=rng_seed + 1))

    def _main_channel_straight(self, p: StylizeParams, seed, rng_seed: int) -> Dendrite:
        """:meth:`dendrite` with the hairpins of its main channel cut (cached).

        Beyond the paper: a lightning bolt's widest channel follows the picture's
        edges, and through a thin, ragged part (a fern's tip leaflets) it doubled
        back in hairpins a few pixels apart, a bright knot;
        :func:`~branchnb.dendrite.main_channel.shortcut_loops` joins each
        hairpin's legs within ``LIGHTNING_LOOP_REACH`` of the lattice's diagonal.
        """
        seed_key = tuple(np.round(np.asarray(seed, float), 3))
        key = ("straight", _subset(p, _IMPORTANCE + _LATTICE + _PLAN + _ENDPOINTS),
               seed_key, rng_seed)

        def make():
            res = self.plan(p, seed, rng_seed)
            return straighten(res, self.dendrite(p, seed, rng_seed), self.endpoints(p, rng_seed),
                              reach=LIGHTNING_LOOP_REACH * float(np.hypot(*res.shape)))
        return self._get(key, make)

    def _strike(self, p: StylizeParams, seed, rng_seed: int) -> tuple[PlanResult, Dendrite, bool, bool]:
        """The plan and the dendrite of a lightning bolt, its main channel planned first (cached).

        Beyond the paper: on an object on a background the planner runs on
        :func:`~branchnb.dendrite.main_channel.strike_weights` (the main channel
        down through the object a highway, a filled object's outline costly)
        and the channel's end joins the endpoints, so the bolt's other branches
        fork off the channel; then its hairpins are cut. On a photo the channel is
        :func:`~branchnb.dendrite.photo_strike.photo_channel` and the side branches
        follow :func:`~branchnb.dendrite.photo_strike.side_branches`; with nothing to
        draw, the plain plan (:meth:`_main_channel_straight`). Beyond the paper (dendrite40):
        on a word or several separate objects (:meth:`_traced_outlines`) the tips lie along
        every object's outline and the band inside the outlines is cheap
        (:mod:`~branchnb.dendrite.strike_outline`), so the bolt traces the letters instead of
        running along their bottom. The flags say whether
        the channel was planned, and whether it runs down a stem to the object's foot
        (:func:`~branchnb.dendrite.main_channel._channel_end`; it is then the dendrite's
        ``main``).
        """
        key = ("strike", _subset(p, _IMPORTANCE + _LATTICE + _PLAN + _ENDPOINTS),
               tuple(np.round(np.asarray(seed, float), 3)), rng_seed)

        def make():
            lat = self.lattice(p, rng_seed)
            content, found = self._lightning_content(p)
            got = strike_weights(lat.weights, content, seed, rng=rng_seed)
            if got is None:  # a photo: no object to go through
                path = (photo_channel(lat.weights, content, seed)
                        if silhouette(content).mean() > STRIKE_MAX_COVER else None)
                if path is None or len(path) < 2:  # nothing to draw, or nothing below the seed
                    return (self.plan(p, seed, rng_seed),
                            self._main_channel_straight(p, seed, rng_seed), False, False)
                region = None
                if self.strike(p) is None:  # no bolt to follow: its straight stretches zigzag
                    path = jag_channel(path, content.shape, rng=rng_seed)
                    # and its side branches stay in the bolt's cone (they crossed the sky)
                    region = strike_region(path, content.shape)
                mask = np.zeros(lat.weights.shape, bool)
                mask[path[:, 1], path[:, 0]] = True
                # the side branches follow the edges that stand out of the picture's noise
                # (beyond the paper: on the importance they wandered through a night sky)
                w, ends = side_branches(as_gray(self.working_image(p)), self.edge_map(p),
                                        lat.weights, content, p,
                                        struck=self.strike(p) is not None, rng=rng_seed,
                                        region=region)
                if ends is None:
                    ends = self.endpoints(p, rng_seed)
                    if region is not None:
                        inside = region[np.clip(np.rint(ends[:, 1]).astype(int), 0, region.shape[0] - 1),
                                        np.clip(np.rint(ends[:, 0]).astype(int), 0, region.shape[1] - 1)]
                        ends = ends[inside] if inside.any() else ends
                # and they grow downward as the lightning metaphor's do (edges stepping up
                # or sideways cost more): from the channel's foot they ran along the ground
                factors = lat.factors if region is None else lat.factors * _SIDE_FACTORS
                res = self._plan_on(Lattice(w, factors), p, mask)
                if region is not None:
                    # and they are short beside the channel, as a real bolt's are (beyond
                    # the paper: forking at the channel's top they ran down beside it)
                    short = _short_sides(res, ends, path)
                    ends = short if len(short) else ends
                res = channel_plan(res, path)
                ends = np.concatenate([ends, path[-1:].astype(float)])
                return res, with_channel(build_dendrite(res, ends), path), True, False
            objs, parts = self._outline_parts(p, content)
            if self._traced_outlines(p) is not None:  # several objects, letters: the bolt
                # traces their outlines
                res = self._plan_on(Lattice(outline_weights(got[0], lat.weights, objs, parts),
                                            lat.factors), p, seed)
                ends = outline_endpoints(objs, parts, rng=rng_seed)
            else:
                res = self._plan_on(Lattice(got[0], lat.factors), p, seed)
                ends = (self._object_endpoints(p, rng_seed, content) if found
                        else self.endpoints(p, rng_seed))
            ends = np.concatenate([ends, got[1][-1:].astype(float)])
            whole = build_dendrite(res, ends)
            d = straighten(res, whole, ends,
                           reach=LIGHTNING_LOOP_REACH * float(np.hypot(*res.shape)))
            # down a stem (a tree's trunk) the channel is the bolt's main path to its foot:
            # by its tips the main path left it for the crown's largest limb
            # on a picture of several separate objects too: the bolt strikes the one its seed
            # lies over (beyond the paper: by its tips the main path jumped from object to
            # object across the ground)
            sil = silhouette(content)
            part = _seed_part(sil, tuple(np.round(np.asarray(seed, float))))
            grounded = _channel_end(part)[1] or int(part.sum()) < int(sil.sum())
            if grounded:
                try:
                    d = with_channel(d, got[1])
                except ValueError:  # the straightening (of the walk by tips) cut through the
                    # channel, which is jagged (strike_channel), not looped: keep it whole
                    try:
                        d = with_channel(whole, got[1])
                    except ValueError:  # another path ties with it somewhere
                        grounded = False
            return res, d, True, grounded
        return self._get(key, make)

    def _dendrite_pruned(self, p: StylizeParams, seed, rng_seed: int, keep) -> Dendrite:
        """:meth:`dendrite` traced to the tips ``keep`` selects only (cached).

        Parameters
        ----------
        p : StylizeParams
            Parameters of every stage up to the endpoints.
        seed : (x, y)
            Start point in lattice pixels.
        rng_seed : int
            Seed (>= 0) of the lattice noise and the stippling.
        keep : (E,) array_like of bool
            One per tip of :meth:`dendrite` (its ``tips``, in order).

        Returns
        -------
        Dendrite
            On the lattice, every radius 1.
        """
        keep = np.asarray(keep, bool)
        full = self.dendrite(p, seed, rng_seed)
        seed_key = tuple(np.round(np.asarray(seed, float), 3))
        key = ("pruned", _subset(p, _IMPORTANCE + _LATTICE + _PLAN + _ENDPOINTS), seed_key,
               rng_seed, keep.tobytes())
        return self._get(key, lambda: build_dendrite(self.plan(p, seed, rng_seed),
                                                     full.points[full.tips[keep]]))

