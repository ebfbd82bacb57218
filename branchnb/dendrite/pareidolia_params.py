"""Parameters of the image-guided tree (:class:`PareidoliaParams`), the paper's values as defaults.

Split from :mod:`branchnb.dendrite.pareidolia`, which re-exports it; how each
parameter came to its default is told there and in the field docs below.
"""

from __future__ import annotations

from dataclasses import dataclass

from ..core.params import param


@dataclass
class PareidoliaParams:
    """Image-guided tree. Lengths are in lattice pixels (a 512 x 512 image).

    Parameters
    ----------
    side : {"full", "left", "right"}
        Where the picture shows: the whole crown ("full", default) or one
        side, the other dissolving into random twigs.
    crown : {"content", "ellipse"}
        Crown shape: the picture's content (:func:`~branchnb.dendrite.pareidolia_crown.content_crown`, default)
        or a fixed ellipse (:func:`~branchnb.dendrite.trees.crown_mask`).
    crown_blur : float
        Gaussian blur (lattice px) smoothing the content crown; 10.
    n_endpoints : int
        Stippled endpoints on the picture; 3600 (the top of the paper's 2,000 -
        3,800: tone r at 4 px blur on 600-px pictures 0.59-0.83 -> 0.65-0.84).
        Multiplied by the square of image px per lattice px on images larger
        than the lattice (the pipe gain divided by its square root), and by the
        lattice's area over ``lattice_size`` squared on a grown lattice (at
        most 60,000).
    random_ratio : float
        Uniform random endpoints per stippled one (twigs in the light parts);
        0.15.
    noise_image : float
        Random weight amplitude (the lattice's ``noise``) on the picture side;
        0.25, low so branches follow the picture.
    noise_random : float
        Random weight amplitude on the far side when ``side`` is not
        ``"full"`` (a linear ramp across the crown); 1.5.
    cost_weight : float
        ``c`` in ``w = c (1 - I) + epsilon + noise U``; 2.
    epsilon : float
        Constant node weight ``epsilon``; 0.3.
    intensity_weight : float
        ``w_I`` of the importance map (:class:`~branchnb.dendrite.importance.ImportanceParams`); 1.
    gradient_weight : float
        ``w_G`` of the importance map; 3 (paper: 3 ``w_I``).
    endpoint_gamma : float
        Stippling density ``I ** gamma``; 1.
    iterations : int
        Growth iterations including the trunk (2-8); 4. Endpoints are added
        in batches that double from one iteration to the next.
    trunk_endpoints : int
        Main limbs grown in iteration 1 toward the upper crown; 9.
    blend_weight : float
        ``a`` of the blend metric of the last iteration (paper: 1000).
    thickness : {"importance", "branch"}
        "importance" (default): pipe model + importance emphasis, tone-matched
        inside the crown; "branch": pipe model only.
    window : int
        Rolling importance window (nodes) of the emphasis; 15.
    emphasis : float
        Width (px) added at full importance; 2.
    tone : float
        Inside the crown, 0 keeps the tree widths, 1 makes the ink match the
        picture's darkness (:func:`~branchnb.dendrite.thickness.tone_thickness`); 0.8.
    tip_width : float
        Width (px) of new twigs; 0.5.
    increment : float
        Width (px) added to a branch per later iteration (older branches are
        thicker); 0.2.
    max_width : float
        Widest stroke in the crown away from the trunk (px); 8. Beyond the
        paper (5 before): a dark region's twigs, 5-6 px apart, could not
        cover it, so the darkest tones read as mid-grey and the branches'
        texture drowned a picture with a narrow range of tones (a night
        photo). Tone r at 4 px blur on a night photo of a rocket, a
        portrait, a cup photo, a camera man, a cat photo, a grey ramp and
        flat coloured objects went from 0.73 0.91 0.95 0.93 0.92 0.94 0.87 /
        0.62 0.87 0.90 0.88 0.88 / 0.59 0.87 0.87 0.88 0.84 0.89 0.79 to
        0.81 0.96 0.97 0.96 0.94 0.96 0.88 / 0.71 0.92 0.93 0.91 0.90 /
        0.67 0.92 0.90 0.91 0.87 0.92 0.80 at 250 / 500 / 1000 px.
    limb_length : float
        Path length (px) from the fork over which the cap on the limbs' width
        falls from the trunk's width to ``max_width`` (the twigs near the fork);
        100.
    limb_width : float
        Beyond the paper: the trunk and the main limbs (iteration 1) are at
        least as wide as a pipe model over the limbs' ends, each end's pipe
        narrowing along its path from its share of the trunk to
        ``limb_width`` (px) at 80 % of its length, then to ``tip_width``; 4.
        The pipe model over all twigs made the limbs thin out soon after the
        fork (twigs hang mostly from their lower parts), and the trunk's top
        ended in a round cap as wide as the trunk (a knob). See the module
        docstring for the measurements.
    pipe : float
        Pipe model gain: width ``= tip_width + pipe * sqrt(tips carried - 1)``; 0.4.
    taper : float
        Twigs taper to about a third of their width over this path length (px)
        at their ends (0: no taper); 6.
    trunk_height : float
        Height of the blank strip below the picture for the trunk, as a share
        of the picture's height; 0.4.
    lattice_size : int
        Plan on a lattice with the diagonal of this square (0: the picture's
        own size); 512. The tree is drawn back at the picture's size. A
        larger picture gets a larger lattice (``max_upscale``).
    max_upscale : float
        Largest number of image px per lattice px; 1. A picture larger than
        ``lattice_size x max_upscale`` is planned on a larger lattice (its
        diagonal the picture's divided by ``max_upscale``, at most
        ``max_lattice``), so the twigs stay fine in image px (beyond the
        paper, see the module docstring).
    max_lattice : int
        Side of the largest grown lattice; 1024 (the time grows with its
        area: about 3 s at 512, 7-18 s at 1024 on a 2-core machine).
    tone_sigma : float
        Blur (lattice px) over which the ink is matched to the picture's
        tone; 5 (a few times the twigs' spacing, so the strokes' widths fill
        the gaps between them).
    contrast : float
        Beyond the paper: the picture's darkness inside the crown is
        stretched so its 1st-99th percentiles span black to white (gain at
        most 5) before the tone match; 1 (0 keeps the picture's own tone).
        The branches' texture adds the same noise to every picture, so a
        low-contrast one (mid-grey fur) drowned in it: tone r at 4 px blur
        on 1000-px pictures 0.61-0.84 -> 0.76-0.84.
    refine : int
        Beyond the paper: passes of a tone match on the drawing itself at
        the output's resolution (the strokes' real coverage, blurred over 3
        output px), within the lattice pass's limits; 2 (0: none).
    slim : bool
        Beyond the paper: along every terminal twig the widths become the
        closest non-increasing profile (weighted by length, so the twig keeps
        its ink); True. The tone match left twigs thin at their base (next to
        their parent's ink) and wide at their ends in dark regions: stalks
        ending in round blobs that read as dots, not twigs (see the module
        docstring).
    rise : float
        Beyond the paper: twigs grow toward the light. In the later iterations
        a lattice step up costs ``1 - rise`` times its length and a step down
        ``1 + rise`` (:func:`~branchnb.dendrite.lattice.direction_factors`);
        0.04 (0 = the paper's isotropic lattice). On the flat cost of a dark
        region the lattice noise alone shaped the twigs: short squiggles,
        widened by the tone match into bean-shaped blobs; a slight rise makes
        them grow up from their branches in sprays (see the module docstring).
        0.1 or more turns the twigs into vertical hatching.
    bottleneck : {"density", "edge"}
        Beyond the paper: the bottleneck term ``M`` of the later iterations' blend
        metric is the largest edge cost per unit of step length ("density",
        default; :class:`~branchnb.dendrite.lattice.Lattice`) instead of the
        largest edge cost ("edge", the paper's). With "edge" and ``a = 1000`` a
        diagonal step (sqrt(2) times dearer) was never taken on a flat region,
        so a flat dark region was drawn in 4-connected staircases: horizontal
        rails with vertical spikes (a 0 / 90 deg grain). See the module
        docstring for the measurements.
    min_twig : float
        Beyond the paper: endpoints closer than this (lattice px) to the tree
        grown so far are dropped; 2 (0 keeps them all). Next to a branch they
        added stubs of 1-3 px (a third of the terminal twigs of a dark figure,
        2 % of their ink) that read as bumps, not twigs. 3 made the twigs
        longer still but coarser: tone r at 4 px blur on a dark disc at 2000 px
        0.72 -> 0.64.
    cover : float
        Beyond the paper: the largest share of a region's area the ink aims to
        cover, blurred over a few px (the darkest tones bend smoothly toward it
        from ``0.6 cover`` on, so darker stays darker); 0.6 (1: solid ink, the
        paper's tone match). Matched to full darkness, a black region (a coat, a
        silhouette) was 75-80 % ink at the output size, twigs as wide as long
        with specks of paper between them: a dense mass, not branches. See the
        module docstring for the measurements.

    features : bool
        Beyond the paper: small dark features (eyes, a mouth, nostrils: darker than
        all round them and narrower than 2 twig spacings or a tenth of the crown's
        size: ``pareidolia_widths._features``) may be drawn up to
        solid ink at their own darkness, by twigs as short as 1.5x their width; True.
        With ``cover``'s gaps and the dark twigs' 6x aspect they were drawn as
        outlines or a twig across them. See the module docstring for the measurements.

    Examples
    --------
    >>> p = PareidoliaParams(side="left")
    >>> p.noise_image < p.noise_random
    True
    """

    side: str = param("full", options=("full", "left", "right"),
                      help="where the image shows: the whole crown or one side")
    crown: str = param("content", options=("content", "ellipse"),
                       help="crown shape: the image's content, or a fixed ellipse")
    crown_blur: float = param(10.0, min=1.0, max=60.0, step=1.0,
                              help="smoothing of the content crown (lattice px)")
    n_endpoints: int = param(3600, min=10, max=20000, step=50,
                             help="stippled endpoints on the image (x image px per lattice px "
                                  "on images larger than the lattice)")
    random_ratio: float = param(0.15, min=0.0, max=2.0, step=0.05,
                                help="uniform random endpoints per stippled one")
    noise_image: float = param(0.25, min=0.0, max=5.0, step=0.05,
                               help="random weight amplitude on the image")
    noise_random: float = param(1.5, min=0.0, max=5.0, step=0.05,
                                help="random weight amplitude on the far side (side != full)")
    cost_weight: float = param(2.0, min=0.0, max=10.0, step=0.1,
                               help="c: weight of (1 - importance) in the lattice")
    epsilon: float = param(0.3, min=0.0, max=5.0, step=0.05, help="constant node weight")
    intensity_weight: float = param(1.0, min=0.0, max=10.0, step=0.1, help="w_I")
    gradient_weight: float = param(3.0, min=0.0, max=10.0, step=0.1, help="w_G (paper: 3 w_I)")
    endpoint_gamma: float = param(1.0, min=0.25, max=4.0, step=0.05,
                                  help="image endpoints density = importance ** gamma")
    iterations: int = param(4, min=2, max=8, help="growth iterations (1 = trunk)")
    trunk_endpoints: int = param(9, min=1, max=100, help="main limbs of iteration 1")
    blend_weight: float = param(1000.0, min=0.0, max=10000.0, log=True,
                                help="a of the last iteration's blend metric (paper: 1000)")
    thickness: str = param("importance", options=("importance", "branch"),
                           help="importance emphasis and tone, or tree thickness only")
    window: int = param(15, min=1, max=101, step=2, help="rolling importance window (nodes)")
    emphasis: float = param(2.0, min=0.0, max=20.0, step=0.1,
                            help="extra width at full importance (px)")
    tone: float = param(0.8, min=0.0, max=1.0, step=0.05,
                        help="inside the crown: 0 = tree widths, 1 = ink matches the picture")
    tip_width: float = param(0.5, min=0.1, max=10.0, step=0.1, help="width of new twigs (px)")
    increment: float = param(0.2, min=0.0, max=20.0, step=0.1,
                             help="width added per later iteration: older branches are thicker (px)")
    max_width: float = param(8.0, min=0.5, max=30.0, step=0.5,
                             help="widest stroke in the crown, away from the trunk (px)")
    limb_length: float = param(100.0, min=1.0, max=500.0, step=5.0,
                               help="path length over which the limbs thin to max_width (px)")
    limb_width: float = param(4.0, min=0.0, max=30.0, step=0.5,
                              help="width the trunk's main limbs keep up to their ends (px)")
    pipe: float = param(0.4, min=0.0, max=5.0, step=0.05,
                        help="pipe model: width = tip_width + pipe * sqrt(tips carried)")
    taper: float = param(6.0, min=0.0, max=50.0, step=0.5,
                         help="twigs taper to a point over this path length at their ends (px)")
    trunk_height: float = param(0.4, min=0.1, max=2.0, step=0.05,
                                help="blank strip below the image for the trunk (x image height)")
    lattice_size: int = param(512, min=0, max=4096, step=64,
                              help="plan on a lattice with the diagonal of this square (0 = image)")
    max_upscale: float = param(1.0, min=1.0, max=16.0, step=0.5,
                               help="largest image px per lattice px: larger images get a finer lattice")
    max_lattice: int = param(1024, min=64, max=4096, step=64,
                             help="largest grown lattice (the time grows with its area)")
    tone_sigma: float = param(5.0, min=0.5, max=20.0, step=0.5,
                              help="blur (lattice px) over which the ink is matched to the picture")
    contrast: float = param(1.0, min=0.0, max=1.0, step=0.05,
                            help="stretch the picture's tone in the crown to the full range (1) "
                                 "or keep it (0)")
    refine: int = param(2, min=0, max=5,
                        help="tone-match passes on the drawing at the output's size (0 = none)")
    slim: bool = param(True, help="twigs never wider toward their ends (no club-shaped twigs)")
    rise: float = param(0.04, min=0.0, max=0.5, step=0.01,
                        help="twigs grow up: a step up costs 1 - rise, a step down 1 + rise")
    bottleneck: str = param("density", options=("density", "edge"),
                            help="the blend metric's bottleneck: cost per unit length (no "
                                 "lattice grain) or per edge (paper)")
    min_twig: float = param(2.0, min=0.0, max=20.0, step=0.5,
                            help="endpoints closer than this to the tree grown so far are "
                                 "dropped: no stubs (lattice px)")
    cover: float = param(0.6, min=0.2, max=1.0, step=0.05,
                         help="most ink a dark region gets: gaps keep its twigs readable "
                              "(1 = solid ink)")
    features: bool = param(True, help="small dark features (eyes, a mouth) may be drawn up to "
                                      "solid ink, so they read")
