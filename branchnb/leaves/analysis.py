"""The analysis pipeline: training layers, registration, layer induction, residuals.

:func:`analyze` strings the paper's analysis steps together and keeps what
each step made, so a change of ``eps`` or ``kappa`` re-runs the induction
only (:meth:`LeafAnalysis.reinduce`): the training layers and the
registrations do not depend on them.
"""

from __future__ import annotations

import dataclasses
import io
from dataclasses import dataclass, field

import numpy as np

from ..core.image import as_rgb
from ..core.params import check_params
from ..core.random import as_rng
from ..core.threads import thread_map
from ..core.validate import check_int, check_shape
from .analysis_combine import colour_delta
from .analysis_induce import (  # noqa: F401  (importable from here as before)
    COLOUR_RELIABLE,
    INKED_OUTLINE,
    LAYER_COLOUR_PRESENT,
    OUTLINE_IN_LAYER,
    SAME_CONTRAST,
    UNDER_INDUCED,
    LayerInduction,
    Progress,
    _carried,
    _combine,
    _contrast,
    _has_layer_colour,
    _induced,
    _liberal_to_training,
    _long_network,
    _matched_lab,
    _other_colour,
    _outline_band,
    _outline_in_layer,
    _over_induced,
    _own_cdf,
    _own_delta,
    _pinholes,
    _progress,
    _ridge_extension,
    _snapped,
    _under_induced,
    _unmatched,
    _without_dots,
    induce,
    registration_tolerance,
    thin_width,
    warp_mask,
)
from .analysis_masks import _contrast_map, _exemplar_mask, _MaskSteps
from .analysis_normalise import (  # noqa: F401
    COMPOUND_GAP,
    _axis_angle,
    _check_one_leaf,
    _shift_layers,
    _shift_mask,
    _turned_extents,
    normalise_exemplars,
)
from .induction import (
    ColourSpace,
    InductionParams,
    blade_lab_stats,
    layer_width,
    scaled_lengths,
)
from .layers import LayerSet, SnapParams, TrainingLayers, grow_layers
from .margin_band import band_threshold
from .own_contrast import trim_by_contrast, without_blobs  # noqa: F401
from .stored_maps import CombinedMaps
from .structural import MIN_FOUND, layer_standout, warn_analysis

__all__ = ["IdentityRegistration", "LayerInduction", "LeafAnalysis", "analyze", "induce",
           "normalise_exemplars", "registration_tolerance", "warp_mask"]



class IdentityRegistration:
    """The training leaf's registration to itself (same interface as the others).

    Parameters
    ----------
    shape : (int, int)
        ``(H, W)`` of the common canvas.

    Examples
    --------
    >>> r = IdentityRegistration((4, 5))
    >>> r.forward([(1.0, 2.0)]).tolist(), r.map_to_training.shape
    ([[1.0, 2.0]], (4, 5, 2))
    """

    def __init__(self, shape):
        h, w = check_shape(shape, "shape")
        xx, yy = np.meshgrid(np.arange(w, dtype=np.float32), np.arange(h, dtype=np.float32))
        self.shape = (h, w)
        self.map_to_training = self.map_from_training = np.stack([xx, yy], -1)

    def forward(self, points) -> np.ndarray:
        """Points unchanged (``inverse`` is the same).

        Parameters
        ----------
        points : (N, 2) array_like
            ``(x, y)`` in pixels.

        Returns
        -------
        (N, 2) float ndarray
            A copy.
        """
        return np.asarray(points, float).reshape(-1, 2).copy()

    inverse = forward

    def to_training(self, image_or_mask):
        """The image or mask unchanged (``from_training`` is the same).

        Parameters
        ----------
        image_or_mask : (H, W[, C]) array_like
            On the common canvas.

        Returns
        -------
        ndarray
            A copy.
        """
        return np.array(image_or_mask, copy=True)

    from_training = to_training



@dataclass
class LeafAnalysis:
    """Everything the analysis made; input of :func:`branchnb.leaves.synthesis.generate`.

    Parameters
    ----------
    exemplars : list of (H, W, 4) float32 ndarray
        The normalised exemplars (common canvas).
    blades : list of (H, W) bool ndarray
        Each exemplar's blade on the canvas.
    training_index : int
        The exemplar the user scribbled on (the training leaf).
    training : TrainingLayers
        The user's layers grown on the training leaf.
    registrations : list
        ``registrations[i]`` maps exemplar ``i`` to the training leaf
        (identity-like for the training leaf itself).
    params : InductionParams
        The induction parameters used (``eps``, ``kappa``, ...).
    space : ColourSpace
        The colour quantisation shared by all exemplars.
    layers : list of LayerInduction
        Top layer first.
    residuals : list of list of (H, W, 3) float32 ndarray
        ``residuals[k][i]``: exemplar ``i`` after removing the first ``k``
        layers (``residuals[0]`` = the exemplars, ``residuals[-1]`` the
        background).
    layer_set : LayerSet or None
        The user's layers, scribbles in canvas pixels (None when finished
        masks were given).
    rng_seed : int
        Seed of the analysis's random steps; :meth:`reinduce` reuses it.
    offsets : list of (dx, dy)
        Where each input exemplar's pixel (0, 0) lies on the common canvas
        (before a mirrored exemplar was turned over).
    mirrored : list of bool
        Which exemplars were turned over (left-right) to face like the
        training leaf (``analyze(mirror=True)``).
    """

    exemplars: list
    blades: list
    training_index: int
    training: TrainingLayers
    registrations: list
    params: InductionParams
    space: ColourSpace
    layers: list
    residuals: list = field(repr=False)
    layer_set: LayerSet | None = None
    rng_seed: int = 0
    offsets: list = field(default_factory=list)
    mirrored: list = field(default_factory=list)

    @property
    def lambdas(self) -> dict:
        return {x.name: x.lam for x in self.layers}

    @property
    def deltas(self) -> dict:
        return {x.name: x.delta for x in self.layers}

    @property
    def background(self) -> list:
        """Each exemplar's residual after every layer was removed."""
        return self.residuals[-1]

    def layer(self, name: str) -> LayerInduction:
        """The induction of layer ``name`` (KeyError if there is none).

        Parameters
        ----------
        name : str
            A user layer's name.

        Returns
        -------
        LayerInduction
        """
        for x in self.layers:
            if x.name == name:
                return x
        raise KeyError(f"no layer {name!r}; layers are {[x.name for x in self.layers]}")

    def report(self) -> str:
        """One line per layer: lambda, delta and the training overlap."""
        return "\n".join(f"{x.name}: lambda = {x.lam:.3f} (liberal overlap {x.liberal_overlap:.3f}), "
                         f"delta = {x.delta:.3f}, training IoU = {x.training_overlap:.3f}"
                         for x in self.layers)

    def reinduce(self, progress: Progress | None = None, **changes) -> LeafAnalysis:
        """Re-run the induction only, with some induction parameters changed.

        Examples: ``analysis.reinduce(eps=30)``, ``analysis.reinduce(kappa=2.0)``.
        Registration and the training layers are reused.

        Parameters
        ----------
        progress : callable(fraction, text), optional
            Called between steps; raise from it to stop.
        **changes
            :class:`~branchnb.leaves.induction.InductionParams` fields to change.

        Returns
        -------
        LeafAnalysis
            A new analysis (this one is not modified).
        """
        params = dataclasses.replace(self.params, **changes)
        check_params(params, name="params")
        layers, residuals, space = induce(
            [e[..., :3] for e in self.exemplars], self.blades, self.training_index,
            {n: self.training.masks[n] for n in self.training.order}, self.registrations,
            params, space=self.space if params.bins == self.space.bins else None,
            progress=progress, rng=self.rng_seed, carried=_carried(self.training))
        out = _with_standout(dataclasses.replace(self, params=params, layers=layers, residuals=residuals,
                                                 space=space))
        warn_analysis(out, stacklevel=2)
        return out

    def retune(self, **changes) -> LeafAnalysis:
        """A quick re-induction (eqs. 2-4 only) for a changed ``eps``, ``kappa`` or liberal threshold.

        Each layer keeps its colour term ``S_e`` and neighbourhood; the
        residuals are not inpainted again. The masks are made by the same
        code as :meth:`reinduce`'s (:func:`~branchnb.leaves.analysis_masks._exemplar_mask`:
        snapped paths, the exemplar's own ``delta``, contrast, outline,
        ink-zone, hole-rim and speck trimming), so the top layer's masks
        equal :meth:`reinduce`'s whenever the neighbourhood ``n`` the
        induction chose stays the best one; a lower layer's too where the
        layers above it did not change (its ``S_e`` was measured on the
        residual they left). For a slider preview: generate from
        :meth:`reinduce`, whose residuals are new.

        Examples: ``analysis.retune(eps=30)``, ``analysis.retune(kappa=2.0)``.

        Parameters
        ----------
        **changes
            :class:`~branchnb.leaves.induction.InductionParams` fields to
            change (``eps``, ``kappa``, ``liberal_threshold``).

        Returns
        -------
        LeafAnalysis
            A new analysis (this one is not modified).
        """
        return _with_standout(_retuned(self, changes))

    def overlay(self, e: int, *, base: np.ndarray | None = None, step: int = 1) -> np.ndarray:
        """Exemplar ``e`` on white with its induced layers tinted in the layers' colours.

        Parameters
        ----------
        e : int
            Exemplar index.
        base : (H, W, 3) ndarray, optional
            That exemplar on white already (an app keeps it between slider
            moves; every ``step``-th pixel when ``step`` > 1, for a
            thumbnail); it is not modified.
        step : int, optional
            Take every ``step``-th pixel (1: full size).

        Returns
        -------
        (H, W, 3) float32 ndarray
        """
        e = check_int(e, "e", 0, len(self.exemplars) - 1)
        step = check_int(step, "step", 1, 10_000)
        if base is None:
            out = as_rgb(self.exemplars[e])[::step, ::step]
        else:
            out = as_rgb(base, name="base").copy()
            want = self.blades[e][::step, ::step].shape
            if out.shape[:2] != want:
                raise ValueError(f"base must be exemplar {e} on white at step {step}, of shape {want}, "
                                 f"got {out.shape[:2]}")
        colours = {}
        if self.layer_set is not None:
            colours = {x.name: x.colour for x in self.layer_set.layers}
        default = ["#d62728", "#1f77b4", "#2ca02c", "#9467bd", "#ff7f0e"]
        for k, x in enumerate(self.layers):
            hexc = colours.get(x.name, default[k % len(default)])
            c = np.array([int(hexc[i:i + 2], 16) for i in (1, 3, 5)], np.float32) / 255
            m = x.masks[e][::step, ::step]
            out[m] = 0.35 * out[m] + 0.65 * c
        return out

    def _repr_png_(self) -> bytes:
        from PIL import Image
        tiles = [self.overlay(e) for e in range(len(self.exemplars))]
        img = np.concatenate(tiles, axis=1)
        buf = io.BytesIO()
        Image.fromarray((np.clip(img, 0, 1) * 255).astype(np.uint8)).save(buf, format="PNG")
        return buf.getvalue()


def _retuned(analysis, changes):
    """:meth:`LeafAnalysis.retune`: ``_combine`` again on each layer's stored colour terms and distances."""
    allowed = {"eps", "kappa", "liberal_threshold", "reference_area"}
    extra = sorted(set(changes) - allowed)
    if extra:
        raise ValueError(f"retune changes only {sorted(allowed)}; {extra} change the colour terms: "
                         "use reinduce")
    a = analysis
    params = dataclasses.replace(a.params, **changes)
    check_params(params, name="changes")
    t = a.training_index
    lengths = [scaled_lengths(params, b) for b in a.blades]
    tolerance = registration_tolerance(a.registrations, t)
    taken = [np.zeros_like(b) for b in a.blades]
    layers = []
    stats = None
    for k, old in enumerate(a.layers):
        user = a.training.masks[old.name]
        user = user & (a.blades[t] | _pinholes(a.blades[t], user))
        best = None
        colours = old.steps.colours if old.steps is not None and old.steps.colours else {old.neighbourhood: old.colour}
        for n_px, colour in colours.items():
            # The window the induction would keep with these parameters (its rule: the best training IoU).
            liberal = old.steps.liberal.get(n_px) if old.steps is not None and old.steps.liberal else None
            got = _combine(colour, old.distance, lengths, tolerance, params, a.blades, a.registrations, t, user,
                           liberal=liberal)
            if best is None or got[4] > best[0][4] + 1e-9:
                best = (got, n_px, colour)
        (lam, overlap, combined, delta, tr_iou), n_px, colour = best
        steps = old.steps if old.steps is not None else _MaskSteps(
            user, a.blades, t, old.snapped, old.centred, [None] * len(a.blades), [None] * len(a.blades),
            [None] * len(a.blades), [None] * len(a.blades), [None] * len(a.blades), False, False)

        def contrast_of(e, k=k, old=old, steps=steps):
            # The induction's map where it made one; else (the trim newly applies) from the residual.
            nonlocal stats
            if old.contrast is not None and old.contrast[e] is not None:
                return old.contrast[e]
            if stats is None:
                stats = [blade_lab_stats(im[..., :3], b) for im, b in zip(a.exemplars, a.blades)]
            res = a.residuals[k]
            return _contrast_map(_matched_lab(res[t], stats, t, t, params), _matched_lab(res[e], stats, e, t, params),
                                 steps, e)

        masks = []
        reach = band_threshold(colour[t], user, a.blades[t]) if steps.band else None
        delta_s = colour_delta(colour[t], user, a.blades[t], lam, tr_iou, steps.snapped is not None)
        for e in range(len(a.blades)):
            m, _ = _exemplar_mask(steps, e, combined[e], delta, tr_iou, taken[e], contrast_of,
                                  colour_e=colour[e], band_delta=reach, delta_s=delta_s)
            moved = m & taken[e]
            if moved.any():  # marks given back by their shape leave the layers above (as in induce)
                for above in layers:
                    above.masks[e] = above.masks[e] & ~moved
            taken[e] |= m
            masks.append(m)
        layers.append(dataclasses.replace(old, lam=lam, liberal_overlap=overlap, delta=delta,
                                          training_overlap=tr_iou, masks=masks, colour=colour, neighbourhood=n_px,
                                          combined=CombinedMaps(lam, colour, old.distance,
                                                                [ln[0] for ln in lengths]),
                                          eps_px=[ln[0] for ln in lengths]))
    return dataclasses.replace(a, params=params, layers=layers)


#: Gap, as a fraction of the leaf's size (square root of its area), across which blade pieces are one leaf.
def analyze(exemplars, training_index: int, layers, params: InductionParams | None = None,
            progress: Progress | None = None, *, registrations=None,
            snap_params: SnapParams | None = None, registration_params=None,
            rng=0, mirror: bool = True) -> LeafAnalysis:
    """The whole analysis: training layers, registration, layer induction and residuals.

    Parameters
    ----------
    exemplars : list of (H, W, 4) images
        Leaves of one kind (at least two), RGBA with the leaf in the alpha.
    training_index : int
        The exemplar the user scribbled on.
    layers : LayerSet or dict of name -> (H, W) bool
        The user's scribbled layers (grown by lazy snapping), or finished
        layer masks on the training leaf, top layer first.
    params : InductionParams, optional
        The paper's defaults if omitted.
    progress : callable(fraction, text), optional
        Called between steps with the fraction done; raise from it to stop.
    registrations : list, optional
        Precomputed registrations (exemplar ``i`` -> training leaf, e.g. from
        :func:`~branchnb.leaves.registration.register` on the canvases of
        :func:`~branchnb.leaves.analysis_normalise.normalise_exemplars`); a
        None entry is computed (the training leaf's: the identity).
    snap_params : SnapParams, optional
        Lazy-snapping parameters.
    registration_params : optional
        Passed to :func:`branchnb.leaves.registration.register`.
    rng : int
        Seed of every random step (k-means, quilting); the analysis is reproducible.
    mirror : bool
        Turn over (left-right) every exemplar that is a mirror image of the
        training leaf (default True; beyond the paper): leaves of one kind
        face either way, and the paper's registration keeps orientation. An
        exemplar nominated by its outline
        (:func:`~branchnb.leaves.orientation.mirrored_exemplars`) is
        registered both ways and turned over only when its registered blade
        fits the training blade clearly better so
        (:func:`~branchnb.leaves.orientation.turned_over_fits`). Skipped when
        ``registrations`` are given. The turned exemplars are listed in
        ``LeafAnalysis.mirrored``.

    Returns
    -------
    LeafAnalysis

    Warns
    -----
    NonStructuralLayerWarning
        A layer scribbled as thin lines (a structure) came out
        non-structural: its masks do not stand out from their blades
        (:func:`~branchnb.leaves.structural.is_structural`); the message
        names the layer and its ``lambda``. Beyond the paper.
    ShadowAsLeafWarning
        An exemplar's blade holds a grey drop or cast shadow
        (:func:`~branchnb.leaves.structural.shadow_share`).

    Notes
    -----
    Beyond the paper: the exemplars are registered, snapped and induced in
    threads (:func:`branchnb.core.threads.thread_map`; NumPy, OpenCV and the
    compiled kernels release the GIL), one per core; the environment
    variable ``BRANCHNB_THREADS=1`` runs them in turn. The results do not
    depend on it (the residuals' patch quilting still draws from one
    generator, exemplar after exemplar).

    Examples
    --------
    The whole pipeline on three procedural leaves: scribbles on the
    training leaf (here simulated along its true veins; in a notebook,
    :class:`branchnb.widgets.leaves.LeafApp`), analysis, new leaves.

    >>> from branchnb.leaves import Layer, LayerSet, generate, is_structural, layer_warnings, leaf_family
    >>> from branchnb.leaves import simulate_scribbles
    >>> leaves = leaf_family(3, size=160, rng=0)
    >>> veins = simulate_scribbles(leaves[0].layers["veins"], 10, length=12, rng=0)
    >>> a = analyze(leaves, 0, LayerSet([Layer("veins", "#d62728", 0, veins)]))
    >>> [x.name for x in a.layers], len(a.layer("veins").masks)
    (['veins'], 3)
    >>> is_structural(a.layer("veins")), layer_warnings(a)   # else analyze warned (NonStructuralLayerWarning)
    (True, [])
    >>> new = generate(a, 2, rng=0)
    >>> new[0].image.shape == a.exemplars[0].shape
    True

    Registrations made beforehand (a None entry is computed):

    >>> from branchnb.leaves import normalise_exemplars, register
    >>> canvases, blades, offsets = normalise_exemplars(leaves)
    >>> regs = [None] + [register(canvases[i], canvases[0], blades[i], blades[0]) for i in (1, 2)]
    >>> b = analyze(leaves, 0, {"veins": leaves[0].layers["veins"]}, registrations=regs)
    >>> type(b.registrations[0]).__name__, b.registrations[1] is regs[1]
    ('IdentityRegistration', True)
    """
    params = check_params(params if params is not None else InductionParams(), name="params")
    if isinstance(rng, np.random.Generator) or rng is None:
        rng = int(as_rng(rng).integers(2**31 - 1))
    if isinstance(exemplars, (str, bytes, dict)) or not hasattr(exemplars, "__len__") or len(exemplars) < 2:
        raise ValueError(f"exemplars must be a list of at least 2 leaves (one kind), got {exemplars!r:.60}")
    images, blades, offsets = normalise_exemplars(exemplars)
    n = len(images)
    if n < 2:
        raise ValueError(f"exemplars must hold at least two leaves, got {n}")
    if isinstance(training_index, bool) or not isinstance(training_index, (int, np.integer)) \
            or not 0 <= training_index < n:
        shown = training_index if not isinstance(training_index, int) or abs(training_index) < 10**12 else "a huge int"
        raise ValueError(f"training_index must be an int in [0, {n - 1}], got {shown!r}")
    t = int(training_index)
    for i, b in enumerate(blades):
        if b.sum() < 64:
            raise ValueError(f"exemplars[{i}] has (almost) no leaf pixels (alpha > 0.5)")
    if not isinstance(mirror, (bool, np.bool_)):
        raise TypeError(f"mirror must be a bool, got {type(mirror).__name__}")
    mirrored = [False] * n
    # Nominated by the outline alone; registered both ways below and turned over only when that fits.
    nominated = [False] * n
    if mirror and registrations is None:
        from .orientation import mirrored_exemplars
        nominated = mirrored_exemplars(blades, t)
    report = _progress(progress, 0.0, 1.0)
    report(0.0, "training layers")
    layer_set = None
    if isinstance(layers, LayerSet):
        # Scribbles are in the training image's own pixels: move them with it.
        layer_set = _shift_layers(layers, offsets[t])
        training = grow_layers(images[t], blades[t], layer_set, snap_params, rng=rng)
    elif isinstance(layers, dict):
        if not layers:
            raise ValueError("layers is empty: give a LayerSet or at least one layer mask")
        masks = {}
        taken = np.zeros_like(blades[t])
        for name, m in layers.items():
            if not isinstance(name, str) or not name.strip() or name == "blade":
                raise ValueError(f"layers: {name!r} is not a layer name (a non-empty str; 'blade' is the "
                                 "background's)")
            m = _shift_mask(m, offsets[t], blades[t].shape, f"layers[{name!r}]")
            # A stroke across the matte's pinholes stays one stroke (see analysis_induce._pinholes).
            m = m & (blades[t] | _pinholes(blades[t], m)) & ~taken
            if not m.any():
                raise ValueError(f"layers[{name!r}] selects no pixel of the training leaf's blade")
            masks[name] = m
            taken |= m
        training = TrainingLayers(masks, blades[t], blades[t] & ~taken, list(masks),
                                  np.zeros(blades[t].shape, np.int32))
    else:
        raise TypeError(f"layers must be a LayerSet or a dict of masks, got {type(layers).__name__}")
    if registrations is None:
        registrations = [None] * n
    elif isinstance(registrations, (str, bytes, dict)) or not hasattr(registrations, "__len__"):
        raise TypeError(f"registrations must be a list (one per exemplar), got {type(registrations).__name__}")
    elif len(registrations) != n:
        raise ValueError(f"registrations must have one entry per exemplar ({n}), got {len(registrations)}")
    registrations = list(registrations)
    if registrations[t] is None:
        registrations[t] = IdentityRegistration(blades[t].shape)
    todo = [i for i in range(n) if registrations[i] is None]
    if todo:
        from .orientation import turned_over_fits
        from .registration import RegistrationParams, _as_leaf, _training_keypoints, register
        report(0.05, f"registering {len(todo)} exemplar(s)")
        prm = RegistrationParams() if registration_params is None else registration_params
        if len(todo) > 1 and isinstance(prm, RegistrationParams):
            # The training leaf's keypoints, found once here (remembered), not by every thread at once.
            tr = _as_leaf(images[t], blades[t], "training")
            _training_keypoints(tr.rgb, tr.blade, prm.n_keypoints, prm.outline_fraction)
        # The exemplars register independently (deterministic, no shared state): in threads, as
        # TPS-RPM's kernels, OpenCV and NumPy's loops release the GIL.
        # A nominated mirror image is registered turned over too (the canvas is centred on each blade:
        # turning it over keeps the blade centred).
        jobs = [(i, False) for i in todo] + [(i, True) for i in todo if nominated[i]]

        def job(ij):
            i, turn = ij
            im, b = (images[i][:, ::-1].copy(), blades[i][:, ::-1].copy()) if turn else (images[i], blades[i])
            return register(im, images[t], b, blades[t], params=registration_params, rng=rng)
        done = dict(zip(jobs, thread_map(job, jobs)))
        for i in todo:
            registrations[i] = done[(i, False)]
            if nominated[i]:
                if turned_over_fits(done[(i, False)], done[(i, True)], blades[i], blades[t]):
                    mirrored[i] = True
                    images[i], blades[i] = images[i][:, ::-1].copy(), blades[i][:, ::-1].copy()
                    registrations[i] = done[(i, True)]
        report(0.5, "registered")
    layers_out, residuals, space = induce(
        [im[..., :3] for im in images], blades, t, {k: training.masks[k] for k in training.order},
        registrations, params, progress=_progress(progress, 0.5, 1.0), rng=rng, carried=_carried(training))
    out = _with_standout(LeafAnalysis(images, blades, t, training, list(registrations), params, space, layers_out,
                                      residuals, layer_set, rng, offsets, mirrored))
    warn_analysis(out, stacklevel=2)
    return out


#: A stroke is a line when its polyline is at least this many brush diameters long.
LINE_STROKE = 4.0


def scribbled_as_lines(analysis: LeafAnalysis, name: str) -> bool:
    """Whether the user drew layer ``name`` as a structure: thin lines rather than dabs or blobs.

    From the scribbles when there are any (most of their length in strokes
    at least :data:`LINE_STROKE` brush diameters long: the sample maple's
    vein strokes are 8-17, its spot dabs 0-2, simulated vein strokes of
    radius 0.5 at 192 px 2-14), else from the layer's mask
    (:func:`~branchnb.leaves.snapping.is_thin_layer`). A layer snapped to
    the exemplars' ridges is always one; a band along the outline
    (:func:`~branchnb.leaves.margin_band.outline_region`, a variegated
    margin traced with long strokes) never is (beyond the paper).

    Parameters
    ----------
    analysis : LeafAnalysis
        The analysis (its ``layer_set``, training masks and layers).
    name : str
        A user layer's name.

    Returns
    -------
    bool

    Examples
    --------
    >>> from types import SimpleNamespace as NS
    >>> import numpy as np
    >>> from branchnb.leaves import Layer, LayerSet, Scribble
    >>> ls = LayerSet([Layer("veins", "#d62728", 0, [Scribble([(0, 0), (30, 0)], 1.0)]),
    ...                Layer("spots", "#1f77b4", 1, [Scribble([(5, 5)], 3.0)])])
    >>> a = NS(layer_set=ls, layers=[NS(name="veins", snapped=None), NS(name="spots", snapped=None)])
    >>> scribbled_as_lines(a, "veins"), scribbled_as_lines(a, "spots")
    (True, False)
    """
    from .margin_band import outline_region
    from .snapping import is_thin_layer
    for x in analysis.layers:
        if x.name == name and x.snapped is not None:
            return True
    t = analysis.training_index if hasattr(analysis, "training_index") else None
    if t is not None and hasattr(analysis, "training") and name in analysis.training.masks and \
            outline_region(analysis.blades[t], analysis.training.masks[name] & analysis.blades[t]):
        # A band along the outline (a variegated margin) is a region whatever its strokes: its
        # place is the paper's test (lambda, reach), not how much it stands out like a vein.
        return False
    if analysis.layer_set is not None:
        strokes = [s for layer in analysis.layer_set.layers if layer.name == name for s in layer.scribbles]
        if strokes:
            lengths = np.array([float(np.hypot(*np.diff(s.points, axis=0).T).sum()) if len(s.points) > 1 else 0.0
                                for s in strokes])
            lines = lengths >= LINE_STROKE * np.array([max(2.0 * s.radius, 1.0) for s in strokes])
            return float(lengths[lines].sum()) >= 0.5 * max(float(lengths.sum()), 1e-9)
    t = analysis.training_index
    user = analysis.training.masks[name] & analysis.blades[t]
    return bool(is_thin_layer(user, max_width=thin_width(analysis.blades[t], user)))


def _with_standout(analysis: LeafAnalysis) -> LeafAnalysis:
    """``analysis`` with each layer scribbled as lines given its ``standout`` on every exemplar."""
    layers = []
    for k, x in enumerate(analysis.layers):
        standout = None
        if scribbled_as_lines(analysis, x.name):
            residual, blades, t = analysis.residuals[k], analysis.blades, analysis.training_index
            share_t = float(x.masks[t].sum()) / max(float(blades[t].sum()), 1.0)
            # An exemplar on which the layer covers under MIN_FOUND of the training leaf's share was not
            # found there (its few pixels may sit on a spot: a vein layer on plain blade went 0.1 -> 1.0).
            # Measured off the outline band as wide as the layer (as induction leaves it out of thin
            # layers, :func:`~branchnb.leaves.analysis_outline._outline_band`): an edge is no vein.
            margin = max(2.0, float(np.ceil(layer_width(x.masks[t])))) if x.masks[t].any() else 2.0
            standout = [0.0 if e != t and float(m.sum()) < MIN_FOUND * share_t * float(blades[e].sum())
                        else layer_standout(residual[e], blades[e], m, margin=margin)
                        for e, m in enumerate(x.masks)]
        layers.append(dataclasses.replace(x, standout=standout))
    return dataclasses.replace(analysis, layers=layers)
