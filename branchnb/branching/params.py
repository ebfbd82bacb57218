"""Parameters of branching-structure extraction and synthesis, with the paper's defaults.

Lengths are in pixels of the example image. The paper ties its Markov
parameters to a *feature size* ``s`` and the resampling step ``h``:
``m = s / h`` elements are appended per step and the history holds
``k + 1`` elements with ``k = 3 m``. The defaults below are these rules
for ``s = 16`` and ``h = 4`` (``m = 4``, ``k = 12``);
:meth:`SynthesisParams.from_feature_size` applies them to any ``s``, ``h``.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

from ..core.params import check_params, param
from ..core.validate import Real, checked

__all__ = ["ClickParams", "ExtractionParams", "SynthesisParams"]


@dataclass
class SynthesisParams:
    """Structure synthesis (paper sections: bending model, global histogram
    matching, furcation model, space colonization, guided synthesis, stopping).

    Parameters
    ----------
    h : float, default 4.0
        Resampling step h (pixels) between successive vertices.
    m : int, default 4
        Elements appended per step, m = s / h (feature size s).
    k : int, default 12
        History length: the last k + 1 (turning angle, thickness) elements are
        matched (paper: k = 3 m).
    c : int, default 2
        Choose among the c best candidates, probability ~ Q.
    thickness_blend : bool, default True
        Scale copied radii so they continue from the tip (the input's relative
        change, within its range); False = the paper's exact copy (goes beyond the
        paper).
    wG : float, default 50.0
        Global histogram weight wG in Q* = Q exp(wG (dA + dR) n_t / m);
        0 switches histogram matching off.
    bins : int, default 16
        Histogram bins B over the input's min..max.
    d : int, default -1
        Furcations per branch d; -1 draws d from the input's children-per-branch.
    min_spacing : int, default 4
        Minimum distance between furcations on a branch, in vertices (h pixels
        each).
    mirror_children : bool, default True
        Also offer each input furcation mirrored (angles negated) when choosing a
        child's first segment.
    svm_C : float, default 1.0
        Regularisation C of the linear SVM of the furcation model.
    colonization : bool, default True
        Space colonization: Q** = Q* / (D + eps), no crossings.
    rho : float, default 0.0
        Density radius rho in D(p) = exp(-d(p, B)^2 / rho^2) (pixels); 0 = auto: the
        example's median half-gap between branches.
    inv_eps : float, default 1000.0
        1 / eps in Q* / (D + eps).
    guidance_width : float, default 40.0
        Width of the guidance valley along the user path (pixels).
    roots : {'learned', 'example'}, default 'learned'
        Where roots start: drawn from the learnt root model (on the same boundary as
        the example's roots, heading into the domain, spaced like them), or exactly
        at the example's root starts.
    n_roots : int, default -1
        Roots (separate trees) to grow; -1 = as many as the example has.
    max_generations : int, default 4
        Stop: maximum branch generation (0 = roots only).
    max_total_length : float, default 0.0
        Stop: maximum total length of all branches (pixels); 0 = auto: the example's
        total length per domain area times the output domain's area, times
        :data:`~branchnb.branching.growth.LENGTH_FACTOR` = 1.15 (beyond the paper, whose
        examples were all small: a fixed 20000 px stopped a 1000 px retina or cracked
        mud short of the example's density; up to
        :data:`~branchnb.branching.growth.FILL_LENGTH_FACTOR` = 1.3 while holes the
        example does not have are filled), at most
        :data:`~branchnb.branching.growth.LENGTH_BOUND` px per domain pixel.
    max_coverage : float, default 0.0
        Stop: fraction of the domain within rho of a branch; 0 = auto: the example's
        own fraction (fills to the example's density), in [0, 1].
    fill_rounds : int, default 10
        Stop: when every branch has stopped before the coverage target is reached,
        fill the free space: tips with room ahead grow on and branches with room
        beside them furcate once more, up to this many rounds (ends earlier when a
        round adds nothing).
    stop_density : float, default 0.9
        Stop a branch when every candidate sees density D >= this (D in [0, 1]).
    branch_end : {'length', 'markov'}, default 'length'
        A branch ends at a length drawn from input branches of its generation and
        similar thickness ('length'), or where the chain reaches the end of an input
        branch ('markov').
    max_branch_factor : float, default 1.5
        A branch grows at most this times the longest input branch.

    Examples
    --------
    >>> p = SynthesisParams.from_feature_size(24, h=4)
    >>> (p.m, p.k)
    (6, 18)
    """

    # -- resampling / bending model (Markov) ---------------------------------
    h: float = param(4.0, min=1.0, max=32.0, step=0.5,
                     help="resampling step h (pixels) between successive vertices")
    m: int = param(4, min=1, max=32, help="elements appended per step, m = s / h (feature size s)")
    k: int = param(12, min=0, max=64,
                   help="history: the last k + 1 (angle, thickness) pairs are matched; paper k = 3 m")
    c: int = param(2, min=1, max=20, help="choose among the c best candidates, probability ~ Q")
    thickness_blend: bool = param(True, help="scale copied radii so they continue from the tip (the input's "
                                  "relative change, within its range; off = the paper's exact copy)")
    # -- global histogram matching ---------------------------------------------
    wG: float = param(50.0, min=0.0, max=500.0, step=1.0,
                      help="global histogram weight wG in Q* = Q exp(wG (dA + dR) n_t / m)")
    bins: int = param(16, min=2, max=64, help="histogram bins B over the input's min..max")
    # -- furcation model ---------------------------------------------------------
    d: int = param(-1, min=-1, max=50,
                   help="furcations per branch d; -1 draws d from the input's children-per-branch")
    min_spacing: int = param(4, min=0, max=50,
                             help="minimum index distance between furcations on a branch")
    mirror_children: bool = param(True, help="also offer each input furcation mirrored (angles negated) "
                                  "when choosing a child's first segment")
    svm_C: float = param(1.0, min=1e-3, max=1e3, log=True,
                         help="regularisation C of the linear SVM of the furcation model")
    # -- space colonization -------------------------------------------------------
    colonization: bool = param(True, help="space colonization: Q** = Q* / (D + eps), no crossings")
    rho: float = param(0.0, min=0.0, max=200.0, step=0.5,
                       help="density radius rho in D(p) = exp(-d(p, B)^2 / rho^2) (pixels); "
                            "0 = auto: the example's median half-gap between branches")
    inv_eps: float = param(1000.0, min=1.0, max=1e6, log=True, help="1 / eps in Q* / (D + eps)")
    # -- guided synthesis ---------------------------------------------------------
    guidance_width: float = param(40.0, min=1.0, max=500.0, step=1.0,
                                  help="width of the guidance valley along the user path (pixels)")
    # -- roots ----------------------------------------------------------------------
    roots: str = param("learned", options=("learned", "example"),
                       help="where roots start: drawn from the learnt root model (on the same boundary "
                            "as the example's roots, heading into the domain, spaced like them), or "
                            "exactly at the example's root starts")
    n_roots: int = param(-1, min=-1, max=500,
                         help="roots (separate trees) to grow; -1 = as many as the example has")
    # -- stopping -----------------------------------------------------------------
    max_generations: int = param(4, min=0, max=20,
                                 help="stop: maximum branch generation (0 = roots only)")
    max_total_length: float = param(0.0, min=0.0, max=1e6, step=100.0,
                                    help="stop: maximum total length of all branches (pixels); 0 = auto: "
                                         "the example's length per domain area x the domain's area "
                                         "x 1.3 (x 2 while filling holes)")
    max_coverage: float = param(0.0, min=0.0, max=1.0, step=0.01,
                                help="stop: fraction of the domain within rho of a branch; 0 = auto: "
                                     "the example's own fraction (fills to the example's density)")
    fill_rounds: int = param(10, min=0, max=50,
                             help="stop: when every branch has stopped before the coverage target is "
                                  "reached, fill the free space: tips with room ahead grow on and branches "
                                  "with room beside them furcate once more, up to this many rounds (ends "
                                  "earlier when a round adds nothing)")
    stop_density: float = param(0.9, min=0.0, max=1.0, step=0.01,
                                help="stop a branch when every candidate sees density >= this")
    branch_end: str = param("length", options=("length", "markov"),
                            help="a branch ends at a length drawn from input branches of its generation "
                                 "and similar thickness ('length'), or where the chain reaches the end of "
                                 "an input branch ('markov')")
    max_branch_factor: float = param(1.5, min=0.1, max=10.0, step=0.1,
                                     help="a branch grows at most this times the longest input branch")

    @classmethod
    @checked(s=Real(0, 1e5, low_open=True), h=Real(0, 1e3, low_open=True))
    def from_feature_size(cls, s: float, h: float = 4.0, **overrides) -> SynthesisParams:
        """The paper's rules ``m = s / h`` (rounded, >= 1) and ``k = 3 m``.

        Parameters
        ----------
        s : float
            Feature size s of the example (pixels), > 0.
        h : float, default 4.0
            Resampling step h (pixels), > 0.
        **overrides
            Any other field of :class:`SynthesisParams` (also ``m`` or ``k`` to
            overrule the rules).

        Returns
        -------
        SynthesisParams
            The paper's defaults with ``h``, ``m = max(1, round(s / h))``,
            ``k = 3 m`` and the overrides, checked against the fields' ranges.

        Raises
        ------
        ValueError
            If ``s`` or ``h`` is not > 0, or an override is out of its range.

        Examples
        --------
        >>> p = SynthesisParams.from_feature_size(16, h=4, c=3)
        >>> (p.m, p.k, p.c)
        (4, 12, 3)
        """
        if not s > 0 or not h > 0:
            raise ValueError(f"feature size s and step h must be > 0, got s={s}, h={h}")
        m = max(1, round(s / h))
        p = cls(h=float(h), m=m, k=3 * m)
        p = dataclasses.replace(p, **overrides)
        return check_params(p)

    @property
    def eps(self) -> float:
        return 1.0 / self.inv_eps


@dataclass
class ExtractionParams:
    """Automatic extraction of a source structure (``extract_structure``).

    Parameters
    ----------
    filter : {'sato', 'frangi', 'meijering'}, default 'sato'
        Ridge / vesselness filter (scikit-image).
    polarity : {'auto', 'dark', 'bright'}, default 'auto'
        Branches darker or brighter than the background.
    sigma_min : float, default 1.0
        Smallest filter scale (pixels).
    sigma_max : float, default 4.0
        Largest filter scale (pixels).
    threshold : float, default 0.0
        Ridge threshold on the normalised response; 0 = Otsu.
    hysteresis : float, default 0.5
        Low threshold = hysteresis x high threshold.
    min_branch_length : float, default 12.0
        Drop skeleton end branches (spurs) shorter than this (pixels).
    min_component_length : float, default 60.0
        Drop connected pieces shorter than this in total (pixels).
    h : float, default 4.0
        Resampling step h of the result (pixels).
    radius : {'fwhm', 'ridge'}, default 'fwhm'
        Thickness: distance transform of the half-contrast (FWHM) mask, or of the
        thresholded ridge mask.
    smooth_path : float, default 4.0
        Smooth each skeleton path over this arc length (pixels; removes the pixel
        staircase); 0 = off.
    smooth_radius : float, default 8.0
        Smooth the radius along each branch over this arc length (pixels); 0 = off.
    scale : float, default 1.0
        Process a downscaled copy (faster); results are in full-size pixels.
    root : {'auto', 'thickest', 'top', 'bottom', 'left', 'right', 'border', 'nearest_region'}, default 'auto'
        Which end point of each connected piece becomes the root: auto = the
        thickest end where widths vary (vessels, a delta's inland trunk), the outlet
        where the network meets a large branch-free flat region (a map's sea; else
        the border) where every line has one width, unless it meets it at several
        mouths and its forks fan out from an end inland (a delta: rooted there); or
        the thickest, the top-most ..., the one nearest to the image border, or the
        one nearest to a large flat region (else the border; a delta reaching it at
        several mouths roots at the end its channels fan out from).
    binary : {'auto', 'on', 'off'}, default 'auto'
        Binary (or near-binary) input such as a water mask: centre lines by the
        medial axis with the distance-transform radius instead of the ridge filter;
        auto = detect it.
    join_gaps : float, default 3.0
        Beyond the paper: drawn strokes broken at junctions (a side branch
        stopping short of its stem) and at the over-and-under crossings of an
        interlace are joined across paper gaps up to this many pixels beyond
        half the line's width, where their directions continue (see
        :func:`~branchnb.branching.stroke_joins.find_stroke_joins`); 0 = never.
    close_cycles : float, default 40.0
        Beyond the paper: the tree of branches cuts every cycle of the traced
        lines once (where the fronts of its shortest paths meet) and the spur
        pruning then drops the two half-edges, so a network (cracks, mud,
        braided channels, roads) came out as a tree of open ends. Every cut
        cycle at least this long (pixels of loop; shorter ones are pixel
        clusters where lines meet) is closed again by a join branch that
        follows the traced line across the cut and ends on the branch on the
        other side. 0 = off. Binary masks (a delta's braided channels, traced
        by their medial axis) keep the tree: closing their braids misplaces the
        sea the region layout puts off their mouths.
    centre_reach : float, default 1.0
        Beyond the paper: every traced vertex moves up to this many pixels
        across its branch onto the crest of the line it traces (sub-pixel
        centre lines, :func:`~branchnb.branching.centring.centre_on_lines`);
        a skeleton on pixel centres ran a fraction of a pixel beside thin
        lines (1-2 px rivers, capillaries), which then read as paler than
        they are. 0 = off. Binary masks (traced by their medial axis) are
        not moved.
    false_ridges : bool, default True
        Beyond the paper: in a photograph the ridge filter also answers along the
        edge of a lit region (a bright cloud layer under a dark one) and along a row
        of separate lights (a city under a storm); such skeleton stretches (an edge:
        the line stands out from one side only; a row of dots: Frangi's blobness
        along it) are dropped (see
        :func:`~branchnb.branching.line_profiles.false_ridge_pixels`). Only bright
        lines are tested (a dark crack with a lit rim is one-sided by nature and its
        darkness intermittent: 5.7 % of the cracked-mud sample's cracks were lost);
        lines traced by colour and binary masks are not.
    """

    filter: str = param("sato", options=("sato", "frangi", "meijering"),
                        help="ridge / vesselness filter (scikit-image)")
    polarity: str = param("auto", options=("auto", "dark", "bright"),
                          help="branches darker or brighter than the background")
    sigma_min: float = param(1.0, min=0.5, max=20.0, step=0.5, help="smallest filter scale (pixels)")
    sigma_max: float = param(4.0, min=0.5, max=40.0, step=0.5, help="largest filter scale (pixels)")
    threshold: float = param(0.0, min=0.0, max=1.0, step=0.01,
                             help="ridge threshold on the normalised response; 0 = Otsu")
    hysteresis: float = param(0.5, min=0.05, max=1.0, step=0.05,
                              help="low threshold = hysteresis x high threshold")
    min_branch_length: float = param(12.0, min=0.0, max=500.0, step=1.0,
                                     help="drop skeleton end branches (spurs) shorter than this")
    min_component_length: float = param(60.0, min=0.0, max=5000.0, step=5.0,
                                        help="drop connected pieces shorter than this in total")
    h: float = param(4.0, min=1.0, max=32.0, step=0.5, help="resampling step h of the result")
    radius: str = param("fwhm", options=("fwhm", "ridge"),
                        help="thickness: distance transform of the half-contrast (FWHM) mask, or of "
                             "the thresholded ridge mask")
    smooth_path: float = param(4.0, min=0.0, max=50.0, step=0.5,
                               help="smooth each skeleton path over this arc length (pixel staircase)")
    smooth_radius: float = param(8.0, min=0.0, max=100.0, step=1.0,
                                 help="smooth the radius along each branch over this arc length")
    scale: float = param(1.0, min=0.1, max=1.0, step=0.05,
                         help="process a downscaled copy (faster); results are in full-size pixels")
    root: str = param("auto", options=("auto", "thickest", "top", "bottom", "left", "right", "border",
                                       "nearest_region"),
                      help="which end point of each connected piece becomes the root: auto = the thickest "
                           "end where widths vary (vessels, a delta's inland trunk), the outlet where the "
                           "network meets a large branch-free flat region (a map's sea; else the border) "
                           "where every line has one width (a delta fanning out to it at several mouths: the end "
                           "inland it fans out from); or the thickest, "
                           "the top-most ..., the one nearest to the image border, or the one nearest "
                           "to a large flat region (else the border)")
    binary: str = param("auto", options=("auto", "on", "off"),
                        help="binary (or near-binary) input such as a water mask: centre lines by the "
                             "medial axis with the distance-transform radius instead of the ridge "
                             "filter; auto = detect it")
    join_gaps: float = param(3.0, min=0.0, max=50.0, step=0.5,
                             help="drawn strokes broken at junctions and crossings: join them across "
                                  "paper gaps up to this (pixels, beyond half the line width) where "
                                  "their directions continue (through an interlace crossing, tip to "
                                  "tip, into a stroke at a T-junction); 0 = never")
    close_cycles: float = param(40.0, min=0.0, max=2000.0, step=5.0,
                                help="close the cycles of a network (cells) at least this long (pixels "
                                     "of loop) by join branches; 0 = cycles stay cut (a tree)")
    centre_reach: float = param(1.0, min=0.0, max=4.0, step=0.25,
                                help="move traced vertices up to this far across their branch onto the "
                                     "line's crest (sub-pixel centre lines); 0 = off")
    false_ridges: bool = param(True, help="drop traced stretches that are the edge of a lit region or a row "
                                          "of separate dots (photographs), not a line")


@dataclass
class ClickParams:
    """Input extraction from user clicks: resampling + perpendicular thickness search.

    Parameters
    ----------
    h : float, default 4.0
        Resampling step h (pixels).
    max_radius : float, default 15.0
        Thickness search range perpendicular to the branch (pixels).
    min_radius : float, default 0.75
        Smallest thickness r (pixels).
    smooth : int, default 2
        Median-smooth the thickness over 2 smooth + 1 vertices (0 = off).
    sigma : float, default 1.0
        Gaussian scale of the gradient (pixels).
    snap : float, default 12.0
        A polyline starting this close (pixels) to a branch becomes its child; 0 =
        never.
    """

    h: float = param(4.0, min=1.0, max=32.0, step=0.5, help="resampling step h (pixels)")
    max_radius: float = param(15.0, min=1.0, max=200.0, step=1.0,
                              help="thickness search range perpendicular to the branch (pixels)")
    min_radius: float = param(0.75, min=0.1, max=20.0, step=0.05, help="smallest thickness r")
    smooth: int = param(2, min=0, max=20,
                        help="median-smooth the thickness over 2 smooth + 1 vertices (0 = off)")
    sigma: float = param(1.0, min=0.0, max=10.0, step=0.25,
                         help="Gaussian scale of the gradient (pixels)")
    snap: float = param(12.0, min=0.0, max=200.0, step=1.0,
                        help="a polyline starting this close to a branch becomes its child")
