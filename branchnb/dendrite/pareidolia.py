"""Pareidolia trees: an image hidden in the branches of a tree (paper, section 9).

The tree grows as in :mod:`branchnb.dendrite.trees`, but its crown is the picture:

* **Canvas and crown.** The canvas is the image with a blank strip of
  ``trunk_height`` below it. The crown is the image's content: where the
  blurred importance says there is something to draw (a leaf's silhouette,
  a portrait's figure), filled and smoothed, inside a rounded box of the
  image (``crown="content"``); ``crown="ellipse"`` is the fixed ellipse.
* **Iteration 1, trunk and main limbs** (cumulative metric): the trunk rises
  from the bottom centre of the strip to the crown's base on a calm random
  lattice; the main limbs leave its upper part toward well-spaced points
  of the crown on the image-weighted lattice, so even the limbs run along
  dark regions and edges instead of crossing the picture at random.
* **Later iterations** use ``w = c (1 - I) + epsilon + noise(x) * U`` with
  the image's importance ``I``; the whole structure so far is the seed
  set. Endpoints are stippled on the importance in the crown, plus
  ``random_ratio`` as many uniform random ones (for twigs in the light
  parts), added in growing batches. With ``side="left"`` or ``"right"``
  the picture shows on that side only: the random contribution rises
  linearly from ``noise_image`` to ``noise_random`` across the crown, the
  stippled endpoints stay on the image side and the random ones go to the
  other side, so the picture dissolves into ordinary twigs.
* **Thickness.** The pipe model (Leonardo's rule, width ``tip_width *
  n_tips ** (1 / 2)``) makes a trunk that tapers at every fork; each later
  iteration adds ``increment`` to the older branches; plus the importance
  emphasis (rolling importance along the branches). Inside the
  crown the widths are then matched to the picture's tone
  (:func:`~branchnb.dendrite.thickness.tone_thickness`), capped by a limit
  that is the pipe width at the fork and falls to ``max_width`` over
  ``limb_length`` of path: thick limbs near the trunk, a readable picture
  in the crown. ``thickness="branch"`` keeps the tree thickness only.

Everything is computed on a lattice of ``lattice_size`` (like the
stylization) and drawn back at the image's own size. Beyond the paper, the
texture of the twigs stays fine in image pixels at every size: on an image
larger than the lattice the endpoint count grows with the scale
(``n_endpoints x image px per lattice px``), and past ``max_upscale`` image
px per lattice px the lattice itself grows (to the image's size, at most
``max_lattice``), with the endpoints per its area and the crown's and limbs'
lengths scaled alike (the stippling runs on the nominal lattice, whose cost
does not grow). Planned at 512 and drawn back at 2000 px, the branches were 4
image px per lattice px apart and tone r inside the crown at 4 px blur fell
with the size. Measured on a portrait, a cat photo, a coffee cup, a drawn
face, a grey ramp and flat coloured objects at 1000 / 2000 px (with
``n_endpoints`` 3600 instead of 2400, too), r went from
0.72 0.49 0.71 0.71 0.55 0.56 / 0.60 0.34 0.55 0.57 0.41 0.42 to
0.83 0.61 0.83 0.84 0.74 0.73 / 0.76 0.50 0.78 0.76 0.58 0.61, at about twice
the time (5-11 s at 1000 px, 10-17 s at 2000 px on a shared 2-core machine).
Past ``max_lattice`` x ``max_upscale`` px the lattice stops growing (for
the time), so two steps beyond the paper keep the tone at any size:
``contrast`` stretches the picture's tone in the crown (the branches' texture
drowned a low-contrast picture, the cat's mid-grey fur), and ``refine``
matches the tone again on the drawing itself at the output's resolution (the
strokes' real coverage, blurred over 3 output px, within the lattice pass's
limits, limbs untouched). On the same six pictures r at 4 px blur went to
0.84 0.76 0.84 0.87 0.87 0.84 (1000 px) and 0.79 0.70 0.79 0.81 0.81 0.75
(2000 px), with the tone match's blurs on a coarser grid and the refine pass
drawn without per-branch checks: 2-4 s of CPU at 1000 px, 4.5-7 s at 2000 px.
The cat at 2000 px (upscaled 4.4x from 451 px) is just at 0.7.

Twig ends taper everywhere: after the tone match, the last ``taper`` px of a
branch are never wider than the branch ``taper`` px back times a profile that
falls to 0.3 at the end (the tone match alone widened a dark region's twig
ends more than their bodies and the round caps drew dots). Those dots carried
ink: in dark, flat regions the picture is lighter than with dots (tone r at 4
px blur on 1000-px pictures 0.5-0.73, below the issue's 0.7 on a cat photo, a
gradient and flat coloured objects). Nor is an end twig wider than the branch at its
fork (the pipe model's rule; ``_slim_twigs``' fork cap): in the crown's light parts the
tone match thinned a twig to a pale line and left the twigs at its end twice as wide,
dark flecks along pale twigs. ``python -m branchnb.dendrite._twig_ends`` (600 px, cap off
-> on): end twigs more than 0.5 px wider than their fork on a portrait, a cat, a cup, the
camera man, the rocket, a maple leaf 0.156 0.164 0.173 0.140 0.154 0.091 -> 0.026 0.028
0.030 0.021 0.028 0.013 (in the light parts 0.206 0.039 0.121 0.192 0.000 0.092 -> 0.002
0.000 0.005 0.017 0.000 0.013); tone r at 4 px blur 0.858 0.908 0.844 0.859 0.613 0.835
-> 0.855 0.894 0.831 0.856 0.601 0.818 (the ink the cap drops).

Limbs that reach into the crown (beyond the paper). With the pipe model over all
twigs the limbs thinned soon after the fork: the twigs hang mostly from their
lower parts, and the cap falling over ``limb_length`` did the rest, so the
picture sat on a bare pole; the trunk's top ended in a round cap as wide as the
trunk (a knob on flat objects). Now the trunk and the main limbs (iteration 1)
are at least as wide as a pipe model over the limbs' ends (each end's pipe
narrowing from its share of the trunk to ``limb_width`` at 80 % of its length,
then to a twig; Leonardo's rule holds at every junction), narrower in the
crown's light parts (down to ``limb_width``, not below), and the limbs end in
the picture's dark parts. Measured with the defaults on a portrait, a cup photo,
flat coloured objects, a drawn face, a grey ramp and a landscape at 500 / 1000
px, the height reached by branches wider than twice a twig went from 0.00-0.27
/ 0.03-0.57 of the crown's height to 0.35-0.87 / 0.38-0.90; tone r at 4 px blur
from 0.84-0.97 / 0.84-0.96 to 0.83-0.95 / 0.81-0.94 (a cat photo at 2000 px:
0.70 -> 0.69, flat objects 0.82 -> 0.80), at the same CPU time.

Pictures larger than the largest lattice (beyond the paper). There the endpoint
count grew with image px per lattice px, but the twigs share an area: their
spacing in image px still grew with the square root of it, and the pipe model
over the extra twigs made the trunk and limbs 2.5x wider at 2000 px than at
1000 px (the picture only 2x larger); 47 % of the error of a 2000-px cat photo's
tone lay within 12 px of the limbs (8 % of the crown). Now the count grows with
the square of image px per lattice px and the pipe gain falls with the square
root of that density, so a picture larger than ``max_lattice`` gets the 1000-px
drawing's twig spacing and trunk in image px. Tone r at 4 px blur at 2000 px on
a portrait, a grey portrait, a cat photo, a cup photo, a maple-leaf photo, a
night photo of a rocket, flat objects, a drawn face, a grey ramp, a landscape
and line art went from 0.80 0.85 0.69 0.77 0.84 0.41 0.80 0.89 0.84 0.92 0.89
to 0.87 0.90 0.75 0.84 0.89 0.53 0.88 0.93 0.89 0.94 0.92 (limb reach 0.36-0.92
of the crown, blunt ends 0-3 % instead of 0-10 %; 4-7 s of CPU on a loaded machine, a median 13 %
more); inputs up to ``max_lattice`` px are unchanged. The night photo stays
low at every size (0.42 at 500 px): a dark sky that needs solid ink everywhere
and fine lit towers no twig can draw.

Limbs keep to the dark parts (beyond the paper). Planned on the importance's cost,
the limbs followed the strongest edges, up the middle of a lit object: on the night
photo of the rocket a thick limb ran up the white rocket (tone r at 4 px blur 0.42 at
500 px), and a synthetic night sky with a lit tower had half its limb ink within 4 px
of the tower. The limbs are now planned on the picture's darkness blurred over
``crown_blur / 2`` (their ends already were stippled on it): 7 % of the limb ink near
the tower. Tone r at 4 px blur at 500 px on the rocket, a portrait, a cup photo, a dark
camera photo, a dimmed cat photo and a dark drawn portrait went from 0.42 0.83 0.85 0.82
0.78 0.84 to 0.50 0.87 0.89 0.83 0.85 0.87; the limbs' reach
(branches wider than twice a twig, share of the crown's height) from 0.62 0.57 0.54 0.64
to 0.65 0.45 0.53 0.66 on the portrait, cup, camera and cat.

The trunk enters the crown on its dark side (beyond the paper). Below the middle of a
picture there is often something light (a lit rocket on its pad, a white space suit),
and the trunk and the limbs' bases, the widest strokes, were drawn over it: on a
1000-px night photo of a rocket 43 % of the tone error lay within 8 px of the trunk and
limbs (9 % of the crown). The trunk now enters at the darkest point within the middle
``_FORK_SPAN`` (0.3) of the crown's width, standing straight under it. With
``max_width`` 8, tone r at 4 px blur at 500 px on the rocket, a portrait, a cup photo,
a camera man and a cat photo went from 0.71 0.92 0.93 0.91 0.90 to 0.80 0.94 0.93 0.92
0.93 (the rocket at 1000 px 0.67 -> 0.77).

Twigs never wider toward their ends (``slim``, beyond the paper). The tone match widens
a node by the ink missing around it: a twig's base, next to its parent's ink, stayed
thin while its end in a dark region grew wide, a stalk ending in a round blob that
reads as a dot or a leaf. Along every terminal twig the widths are now the closest
non-increasing profile (pool adjacent violators, weighted by length, so the twig keeps
its ink) and at most half the twig's length, in the lattice tone rounds and in the
output-size passes. On a portrait (250 px), a camera man (500), a cat photo (750), a
face of 25 px upscaled (500), a drawn face (750), a cup photo (500), the night photo of
a rocket (750), a maple-leaf photo (500), a drawn lizard (750), a tree photo (250) and a
horse silhouette (500) the share of twigs whose last third is 1.25x wider than their
first went from 0.14 0.15 0.11 0.12 0.11 0.15 0.15 0.07 0.05 0.08 0.08 to 0 everywhere,
tone r at 4 px blur from 0.97 0.92 0.90 0.89 0.91 0.93 0.76 0.88 0.91 0.96 0.96 to 0.97
0.90 0.90 0.87 0.90 0.92 0.74 0.88 0.91 0.95 0.95 (the rocket at 2000 px 0.73 -> 0.73).

Twigs that grow toward the light (``rise``, beyond the paper). On the flat cost of a
dark region (a bean, a black coat, a silhouette) the lattice noise alone shaped the
twigs: squiggles about one endpoint spacing long, which the tone match widened into
bean-shaped blobs, a texture of spots rather than twigs. The later iterations now plan
on a lattice whose steps up cost ``1 - rise`` (0.96) and down ``1 + rise``, so twigs
leave their branches upward in sprays; terminal twigs are also at least 3x (was 2x) as
long as wide. Measured with the defaults on dark beans
on paper (300 / 900 px), a horse silhouette (400), a black tree on a hill (600), a cup
photo (500), a portrait (250), a camera man (512), the night photo of a rocket (750), a
drawn lizard (300) and a cat photo (1000): the share of the twigs' ink in compact twigs
(chord from base to tip < 3x the twig's width) went from 0.74 0.77 0.92 0.87 0.76 0.72
0.75 0.78 0.62 0.58 to 0.45 0.45 0.67 0.55 0.49 0.52 0.50 0.52 0.35 0.41, the twigs'
mean length (ink-weighted) grew 7-17 %, tone r at 4 px blur in the crown from 0.86 0.84
0.97 0.84 0.92 0.97 0.90 0.74 0.95 0.89 to 0.86 0.85 0.98 0.85 0.92 0.97 0.91 0.75 0.95
0.89. A rise of 0.1 or more draws vertical hatching, and much less noise (0.08) lays
the twigs along the lattice's axes (r 0.68 on the rocket).

Dark regions with gaps (``cover``, beyond the paper). Matched to full darkness, a
black region (a coat, a silhouette, beans) was 75-80 % ink at the output size, its twigs
about as wide as long (median length / width 3.7) with specks of paper between them: a
dense mass, not branches. The tone match now aims at an ink coverage that bends smoothly
toward ``cover`` (0.6) from ``0.6 cover`` on, in the lattice pass and in the output-size
passes, so darker stays darker but a black region keeps gaps. With the defaults on a dark
disc (250 / 300 / 800 / 2000 px), dark beans (300 / 800), a dark figure with a light face
(300 / 800 / 2000), a horse silhouette (500), a portrait (320), a camera man (512), a
tree on a hill (600), a palm silhouette (600), a cat photo (1000), a cup photo (500) and
a drawn evergreen (700), the paper share of the dark region (darkness >= 0.6, eroded 3
px) went from 0.20-0.48 to 0.44-0.59, the share of its ink in line-like branches (chord
>= 4x mean width) from 0.49-0.75 to 0.71-0.90, the terminal twigs' median length / width
from 3.6-4.9 to 5.0-6.2, and tone r at 4 px blur in the crown from 0.83-0.99 to 0.80-0.96
(lowest: the disc at 2000 px 0.92 -> 0.81, the evergreen 0.83 -> 0.80).

Small pictures (beyond the paper). A picture smaller than the lattice is planned on the
512-px lattice, and stippling 3,600 endpoints on it took ~45 % of the time on a 250-px
portrait; the endpoints are now stippled on a grid of about the picture's own size
(``floor(lattice px / image px)`` times coarser) and spread over its cells, the 9 limb
ends on one twice as coarse: CPU time on the portrait 1.43 -> 0.91 s (with the rise
above), tone r 0.965 -> 0.969; pictures of 256 px or more are planned as before.

No lattice grain, longer twigs (beyond the paper). The later iterations' blend metric
``a M + S`` took ``M`` as the largest edge cost, and a diagonal step costs sqrt(2) times
an axis step over the same weights: with ``a = 1000`` and weights that vary by less than
that (a flat region, mild noise) no path stepped diagonally, and flat dark regions were
drawn as horizontal rails with vertical spikes. ``M`` is now taken per unit of step
length (``bottleneck="density"``). Endpoints within ``min_twig`` lattice px of the tree
grown so far are dropped (they only added 1-3 px stubs), and in the picture's dark parts
a twig is at least 6x as long as wide (3x in the light and mid tones, where twig ends
draw small features), the rest of its ink going into the branch it hangs from. With the
defaults on a dark disc (250 / 800 / 2000 px), a dark figure with a light face (300 /
2000), the astronaut, the camera man, a cat photo, a cup photo, a horse silhouette, a tree
on a hill, a palm and an evergreen, the orientation histogram of the ink in the dark
regions (structure tensor, 12 bins of 15 deg, 1 = uniform) went from a largest bin of
2.3-3.6 to 1.4-2.0 and an axis share (0 / 45 / 90 / 135 deg) of 1.15-1.71 to 1.01-1.19;
the terminal twigs' median length / width from 5.0-6.2 to 6.7-7.6 and their median
length 1.15-1.7x; tone r at 4 px blur in the crown from 0.76-0.96 to 0.72-0.96 (the
astronaut 0.87 -> 0.85, the disc at 2000 px 0.76 -> 0.72, the rest within 0.03); the
paper share of the dark regions 0.44-0.59 -> 0.48-0.61; no blunt twig ends before or
after.

Small dark features read (``features``, beyond the paper). A portrait's eyes and mouth are
darker than all round them and only a few twig spacings across: ``cover`` kept gaps in
them, the dark twigs' 6x aspect left no twig there long enough to be wide, and the tone
match's gain (the crown's mean ink, ~0.6 of the picture's darkness) compressed them with
the rest, so they came out as outlines or a twig across them. Features are now the top-hat
by reconstruction of the darkness (``pareidolia_widths._features``: parts that vanish
under an opening of 2 twig spacings or a tenth of the crown's size and are not joined to a
larger dark region, so the hair round a light face on a dark coat is no feature), and in
them the ink may rise to solid, at the feature's own darkness, by twigs as short as 1.5x
their width. Measured as the slope of the drawing's darkness on the picture's in and
around each feature's box at 4 px blur (1 = the picture's contrast), the weakest feature
of a procedural face with eyes, mouth and nostrils at 250 / 750 / 2000 px went from 0.45 /
0.52 / 0.45 to 0.58 / 0.71 / 0.70 (eyes and mouth 0.59-0.63 / 0.53-0.56 / 0.49-0.53 to
0.77-0.92 / 0.86-0.92 / 0.95-0.98; the nostrils, 6 x 5 px at 250 px, stayed at 0.58-0.61,
and since the features aim at their own darkness read 0.88-1.57 at 250 px over three
nostril sizes and darknesses and three seeds, eyes 0.81-0.91 and mouth 1.02-1.08 on the
same faces, 0.95 / 1.05 at 750 px), a grey face with small eyes at 250 / 750 px from 0.51
/ 0.39 to 0.87 / 0.78, the astronaut's eyes at 512 / 1000 px from 0.82 / 0.64 to 1.05 /
0.87 and a cat's pupils from 0.72 to 1.27. Tone r at 4 px blur on those faces 0.972 0.923
0.885 0.721 0.603 -> 0.969 0.920 0.880 0.790 0.717, the astronaut 0.851 / 0.861 -> 0.854 /
0.861, the cat 0.892 -> 0.941, the camera man 0.834 -> 0.853, a cup 0.839 -> 0.844, a
horse 0.976 -> 0.976, a maple-leaf photo 0.891 -> 0.895, a tree photo 0.888 -> 0.951, a
dark figure with a light face at 300 / 2000 px 0.968 / 0.860 -> 0.968 / 0.860, a dark disc
at 2000 px 0.717 -> 0.717.

Pictures dark all over, and limbs within the tone (beyond the paper). On the night photo of
a rocket (darkness 0.6-0.88 over most of the crown) tone r at 4 px blur was 0.61 at 600 px:
the 4 px round the limbs (9 % of the crown) held 34 % of the tone error, and away from them
the twigs that carry a dark picture's ink were so wide that their gaps made a coarse texture
(r 0.72 there). On such a picture (the crown's mean darkness from 0.6, fully from 0.7; on a
portrait the limbs then narrowed to twigs in the light face) the limbs' ink is budgeted
against the tone: past a quarter of ``limb_length`` from the fork the output-size pass may
narrow a limb where the drawing is darker than the picture, its pipe width beyond
``limb_width`` fully and ``limb_width`` itself to half (``pareidolia_widths._LIMB_BUDGET``,
``_LIMB_MIN``); and a picture whose crown is darker than 0.6 on average gets ``1 + 3 (mean -
0.6)`` times the endpoints, the pipe gain divided by its square root so the trunk keeps its
width (``_DARK_TWIGS``). ``python -m branchnb.dendrite._pareidolia_sweep 300,600 0``: tone r
at 2 / 4 / 8 px blur, the rocket at 300 px 0.69 / 0.81 / 0.83 -> 0.80 / 0.88 / 0.88, at 600
px 0.42 / 0.61 / 0.72 -> 0.54 / 0.76 / 0.84, at 1000 px (seeds 0 / 1) 0.46 / 0.65 / 0.75 ->
0.56 / 0.78 / 0.85 and 0.46 / 0.64 / 0.74 -> 0.55 / 0.76 / 0.83; a cup photo (its crown just
darker than 0.6) at 300 px 0.931 -> 0.940 at 4 px. Pictures lighter than that are unchanged
(the astronaut, a procedural face at 300 / 600 px: identical figures); CPU time the same
within the load's noise.

A tree crown round an object on a blank ground (beyond the paper; see
:func:`~branchnb.dendrite.pareidolia_crown.content_crown`). The crown was the object's own
silhouette, blurred: an apple-, leaf- or logo-shaped tree. It is now a lobed tree crown of
1.3 times the object's box joined with the object, whose blank ground gets light but solid
twigs (their tone target at least ``_GROUND_TONE`` 0.15 there, and ``_GROUND_TWIGS`` 0.3
random endpoints per stippled one and share of the crown), and the trunk keeps its pipe
width across that ground up to the object (it stepped from 13 to 6 px, or 21 to 4, as it
entered the crown). Share of the crown outside the object's silhouette / the crown's
solidity (area over convex hull) at 300 / 600 px (``_pareidolia_sweep 300,600 0
apple,maple_leaf_01,logo``): a procedural clip-art apple 0.09 / 0.10 -> 0.45 / 0.45 (solidity
0.98 -> 0.97-0.98), a maple-leaf photo 0.22 / 0.23 -> 0.64 / 0.65 (solidity 0.61 -> 0.91 /
0.92), a procedural logo 0.14 / 0.15 -> 0.47 / 0.48 (0.84 -> 0.96); tone r at 4 px blur on the
object's part of the crown apple 0.66 / 0.62 -> 0.74 / 0.67, maple 0.80 / 0.58 -> 0.87 /
0.60, logo 0.96 / 0.92 -> 0.99 / 0.97 (over the whole crown maple 0.90 / 0.82 -> 0.87 /
0.81, the others up). Measured with the limbs' budget then on for every picture; the
figures may differ by a little now that it is not on these light pictures.
Tone r over the whole crown rises more (the blank ground's white is easy to match) and is
no fair measure there.

Wide and dark photos (beyond the paper, issue 25). A crown filling a wide frame was the
frame's ellipse, its top cut flat by the frame and its scallops stretched with the frame: a
rounded rectangle. :func:`~branchnb.dendrite.pareidolia_crown.tree_crown` now keeps the
outline inside the frame, its widest line lower on a wide frame (a dome on a flatter base,
``pareidolia_crown._DOME``) and its scallops evenly spaced along the outline. On a photo dark
all over the stretched tones still sat where ``cover`` bends the ink toward its cap, so dark
towers against a dark sky got the sky's ink and the picture read as a lighter column; the
stretched darkness is now raised to the power that brings its mean in the crown to
``_TONE_MEAN`` (0.5, what photos of ordinary exposure stretch to;
``pareidolia_widths._tone_map``), keeping the darkest dark. Measured with ``python -m
branchnb.dendrite._dome_check`` (rules off -> on); with the defaults (seed 0, long side 300 / 700 px)
the share of the crown's width whose top lies within 1 % of its height of its top went from
0.28-0.30 to 0.08-0.13 on coffee, chelsea, the astronaut cropped to 3:2, the rocket, the
camera man, a procedural portrait (4:5), the Hubble deep field, coins and a darkened
astronaut; tone r at 4 px blur in the crown 0.936 / 0.835 -> 0.944 / 0.857 (coffee), 0.953 /
0.902 -> 0.956 / 0.906 (chelsea), 0.922 / 0.867 -> 0.918 / 0.864 (astronaut 3:2), 0.880 /
0.772 -> 0.857 / 0.761 (rocket), 0.927 / 0.851 -> 0.932 / 0.858 (camera), 0.961 / 0.901 ->
0.965 / 0.907 (portrait), 0.706 / 0.655 -> 0.731 / 0.653 (Hubble, a star field: below 0.7
before too), 0.934 / 0.848 -> 0.926 / 0.860 (coins), 0.921 -> 0.929 (dark astronaut, 300
px). On a procedural wide night picture (dark sky, two darker towers, a lit column) the
towers' ink over the sky's next to them at 4 px blur went from 0.27 to 0.37, tone r from
0.80 to 0.73 (the power bends the tone scale; a mean of 0.55: 0.33 / 0.76, 0.45: 0.40 /
0.70; a linear scale to the same mean instead of a power: 0.22 / 0.78).

A crown that keeps a margin from the frame (beyond the paper, issue 25). Filling the
frame, the crown's side scallops touched its left and right edges, and twigs ran along
strong edges outside the crown (a tower by the frame) into them. The crown's outline now
keeps ``pareidolia_crown._MARGIN`` (4 % of the frame's shorter side) from the frame's
sides and top (a crown round an object on a blank ground: from its sides), and the picture outside
the crown costs ``_OFF_CROWN`` (3) times ``cost_weight`` more to the limbs' and twigs'
paths. Measured with the defaults (seed 0; ``python -m
branchnb.dendrite._margin_check``, which switches both off and on) on coffee, chelsea,
the astronaut, the rocket, the camera man, coins, immunohistochemistry, the horse, the
Hubble deep field and procedural pictures (a face-like blob layout, a tall narrow
subject, a wide landscape, a portrait, a wide picture with a tall tower over dark
shrubs) at 300 / 700 / 1000 px, and 7 photos cropped to 1:1, 3:2 and 2:3 at 700 px: the
share of the left or right edge's rows whose 1 % band holds ink 0-0.16 -> 0 everywhere
(the top's 0-0.03 -> 0-0.001), the ink's closest side margin 0-1 % -> 2-5 % of the width; tone r
at 4 px blur in the crown up on 33 of 50 (mean +0.005; coffee 0.944 / 0.857 / 0.857 ->
0.940 / 0.870 / 0.866, the rocket 0.857 / 0.761 / 0.759 -> 0.856 / 0.765 / 0.771, the
Hubble field 0.731 / 0.653 / 0.662 -> 0.766 / 0.673 / 0.677, a portrait 0.965 / 0.907 /
0.898 -> 0.968 / 0.915 / 0.916), the largest drops within a seed's noise (the camera man
at 700 px 0.858 -> 0.846 with seed 0, 0.855 -> 0.851 with seed 1; the astronaut cropped to
3:2 0.861 -> 0.845 / 0.853 -> 0.852; the horse 0.973 / 0.942 / 0.944 -> 0.974 / 0.940 /
0.940). The crown covers 0.62-0.66 of the picture instead of 0.70-0.72 (round the horse 0.73
instead of 0.77), and the share of its high-contrast quarter (local contrast over 1 % of the long
side) inside the crown fell by 0.00-0.12 (the rocket 0.60 -> 0.54: its towers stand at the
frame's sides).

The steps live in their own modules: :mod:`.pareidolia_crown` (the crown's silhouette),
:mod:`.pareidolia_widths` (limb widths and tone fitting), :mod:`.pareidolia_params`
(:class:`PareidoliaParams`); this module grows the tree and re-exports their names.
"""

from __future__ import annotations

import dataclasses
from dataclasses import dataclass

import numpy as np
from scipy import ndimage
from skimage.transform import resize

from ..core.image import as_float_image, as_rgb
from ..core.io import encode_png
from ..core.params import check_params
from ..core.random import as_rng
from ..core.sampling import stipple
from .dendrite import Dendrite, build_dendrite
from .endpoints import _snap_into, place_endpoints, random_endpoints
from .importance import ImportanceParams, darkness, importance_map
from .lattice import Lattice, direction_factors, node_weights
from .pareidolia_crown import _FORK_SPAN, _content, _fork_point, content_crown, side_ramp, tree_crown  # noqa: F401
from .pareidolia_params import PareidoliaParams
from .pareidolia_widths import _feature_cover, _features, _refine_tone, _shrink, _stretch, _thickness, _tone_map
from .planner import plan
from .render import Rendering
from .scale import resample_to_lattice
from .trees import TreeParams, crown_mask, iteration_metric, render_tree

__all__ = ["PareidoliaParams", "PareidoliaTree", "content_crown", "pareidolia_tree",
           "side_ramp", "tree_crown"]


@dataclass
class PareidoliaTree:
    """The result: ``dendrite`` (with thickness) on the canvas (image + trunk strip),
    the canvas image, the importance and crown on the planning lattice, and the
    endpoints used (canvas pixels).

    Parameters
    ----------
    image : (H, W, 3) float32 ndarray
        The canvas: the picture with the blank trunk strip below it, at the
        picture's own resolution.
    importance : (h, w) float32 ndarray
        Importance on the planning lattice (0 in the trunk strip).
    dendrite : Dendrite
        The tree with its widths, in canvas pixels.
    endpoints_image : (E, 2) float64 ndarray
        Stippled endpoints ``(x, y)`` in canvas pixels.
    endpoints_random : (R, 2) float64 ndarray
        Uniform random endpoints in canvas pixels.
    params : PareidoliaParams
        A copy of the parameters used.
    crown : (h, w) bool ndarray, optional
        The crown mask on the planning lattice (:meth:`crown_on_canvas` for
        the canvas size).

    Examples
    --------
    >>> img = np.ones((64, 64)); img[16:40, 16:40] = 0.0
    >>> t = pareidolia_tree(img, PareidoliaParams(n_endpoints=40, iterations=2, lattice_size=0), rng=0)
    >>> t.image.shape[:2] == t.dendrite.shape, t.crown_on_canvas().shape == t.image.shape[:2]
    (True, True)
    """

    image: np.ndarray
    importance: np.ndarray
    dendrite: Dendrite
    endpoints_image: np.ndarray
    endpoints_random: np.ndarray
    params: PareidoliaParams
    crown: np.ndarray | None = None

    def render(self, **options) -> Rendering:
        """:func:`~branchnb.dendrite.trees.render_tree` of the tree.

        Parameters
        ----------
        **options
            Keyword arguments of :func:`~branchnb.dendrite.trees.render_tree`
            (``background``, ``color``); ``smooth`` defaults to 3.

        Returns
        -------
        Rendering
        """
        options.setdefault("smooth", 3)
        return render_tree(self.dendrite, **options)

    def crown_on_canvas(self) -> np.ndarray:
        """The crown as an (H, W) bool mask on the canvas."""
        from skimage.transform import resize

        h, w = self.image.shape[:2]
        if self.crown.shape == (h, w):
            return self.crown.copy()
        return resize(self.crown.astype(float), (h, w), order=0) > 0.5

    def _repr_png_(self) -> bytes:
        return encode_png(self.render().image)


_MAX_ENDPOINTS = 60000
_DARK_TWIGS = 3.0
_DARK_FROM = 0.6
#: Most mean darkness of the crown after the stretch (``pareidolia_widths._tone_map``; 0:
#: none); photos of ordinary exposure (portraits, a cat, a camera man) stretch to 0.45-0.51.
_TONE_MEAN = 0.5
#: Darkness the twigs aim at on the blank ground inside a tree crown round an object.
_GROUND_TONE = 0.15
#: Extra random endpoints on that ground, per stippled endpoint and share of the crown.
_GROUND_TWIGS = 0.3
#: Extra node cost (x ``cost_weight``) of the picture outside the crown. 0 (none): twigs
#: left the crown along strong edges next to it (``_margin_check``).
_OFF_CROWN = 3.0



def _coarse_points(place, mask: np.ndarray, f: int, rng) -> np.ndarray:
    """``place(f)`` gives points on the ``f``-times coarser grid; spread them over their
    ``f x f`` cells and snap those that miss ``mask`` to its nearest pixel."""
    pts = np.asarray(place(f), np.float64)
    if f == 1 or len(pts) == 0:
        return pts
    h, w = mask.shape
    pts = (pts + 0.5) * f - 0.5 + rng.uniform(-0.5 * f, 0.5 * f, pts.shape)
    return _snap_into(np.rint(np.clip(pts, 0, [w - 1, h - 1])), mask)


def pareidolia_tree(image, params: PareidoliaParams | None = None, *, rng=None) -> PareidoliaTree:
    """Grow a tree whose crown shows ``image``.

    Parameters
    ----------
    image : array_like
        The picture to hide (grey or colour); the canvas has its width.
    params : PareidoliaParams, optional
        Defaults (``PareidoliaParams()``) if None.
    rng : {numpy.random.Generator, int}, optional
        Random generator or seed of every random step (lattice noise,
        crown outline, limb and twig endpoints); the same seed gives the
        same tree.

    Returns
    -------
    PareidoliaTree

    Raises
    ------
    ValueError
        If ``image`` is smaller than 16 x 16 pixels or a parameter is out of
        its range.

    Examples
    --------
    >>> img = np.ones((96, 96)); img[20:50, 10:40] = 0.0
    >>> t = pareidolia_tree(img, PareidoliaParams(n_endpoints=60, iterations=2,
    ...                                           lattice_size=0), rng=0)
    >>> t.dendrite.is_tree()
    True
    """
    p = check_params(params if params is not None else PareidoliaParams())
    full = as_rgb(as_float_image(image, name="image"), name="image")
    if full.shape[0] < 16 or full.shape[1] < 16:
        raise ValueError(f"image must be at least 16 x 16 pixels, got {full.shape[1]} x "
                         f"{full.shape[0]}")
    rng = as_rng(rng)
    side_px = float(np.hypot(*full.shape[:2]) / np.sqrt(2.0))  # side of the square of that diagonal
    lattice = p.lattice_size
    if lattice > 0 and side_px > lattice * p.max_upscale:
        # a finer lattice for a large picture, up to max_lattice
        lattice = max(lattice, min(int(round(side_px / p.max_upscale)), p.max_lattice))
    img0 = resample_to_lattice(full, lattice)
    hi, w = img0.shape[:2]
    # larger images: more endpoints, so the branches stay as far apart in image px (x the
    # square of image px per lattice px: the twigs share an area), and as dense per
    # lattice px on a grown lattice
    up = float(np.hypot(*full.shape[:2]) / np.hypot(hi, w))
    grow = (lattice / p.lattice_size) ** 2 if p.lattice_size > 0 else 1.0
    n_img = int(min(round(p.n_endpoints * max(up, 1.0) ** 2 * grow), _MAX_ENDPOINTS))
    coarse = max(1, round(lattice / p.lattice_size)) if p.lattice_size > 0 else 1
    # a picture smaller than the lattice has no detail finer than its own pixels: its
    # endpoints are stippled on a grid of about its size (beyond the paper; stippling
    # 3600 points on the 512-px lattice was ~45 % of the time on a 250-px portrait)
    fine = max(coarse, int(np.floor(1.0 / up + 1e-6))) if up < 1.0 else coarse
    user = p
    dense = n_img / max(p.n_endpoints * grow, 1.0)
    if dense > 1.0 + 1e-3:
        # ... and the pipe model's gain falls as the square root of that density, so the
        # trunk and limbs stay as wide in image px as the picture is large (with the gain
        # as given they carried the extra twigs: 2.5x wider at 2000 px than at 1000 px)
        p = dataclasses.replace(p, pipe=p.pipe / float(np.sqrt(dense)))
    if lattice != p.lattice_size:  # lengths of the crown and limbs follow the grown lattice
        g = lattice / p.lattice_size
        p = dataclasses.replace(p, crown_blur=p.crown_blur * g, limb_length=p.limb_length * g)
    h = hi + round(p.trunk_height * hi)
    img = np.ones((h, w, 3), np.float32)
    img[:hi] = img0
    imp = np.zeros((h, w), np.float32)
    imp[:hi] = importance_map(img0, ImportanceParams(p.intensity_weight, p.gradient_weight))
    dark = np.zeros((h, w), np.float32)
    dark[:hi] = darkness(img0)

    # crown
    tp = TreeParams(iterations=p.iterations, trunk_endpoints=p.trunk_endpoints,
                    epsilon=p.epsilon, noise=1.0, tip_width=p.tip_width, increment=0.0,
                    pipe=0.0, crown_top=0.0, crown_bottom=(hi + 0.5) / h, crown_width=1.0,
                    blend_weight=p.blend_weight)
    crown = np.zeros((h, w), bool)
    if p.crown == "content":
        crown[:hi] = content_crown(imp[:hi], blur=p.crown_blur, outline=tree_crown((hi, w), rng=rng))
    else:
        crown = crown_mask((h, w), tp)
    # a picture dark all over needs more twigs (beyond the paper): wide twigs carrying
    # its ink left gaps as large as themselves, a coarse texture that hid its tones
    mean_dark = float(dark[crown].mean()) if crown.any() else 0.0
    more = 1.0 + _DARK_TWIGS * max(mean_dark - _DARK_FROM, 0.0)
    if more > 1.0 + 1e-3:  # ... and the trunk and limbs stay as wide (the pipe gain)
        n_img = int(min(round(n_img * more), _MAX_ENDPOINTS))
        p = dataclasses.replace(p, pipe=p.pipe / float(np.sqrt(more)))
    # the limbs follow the linear stretch; the twigs' tone the half-equalised one
    dark_limbs = _stretch(dark, crown, p.contrast, equalize=0.0)
    dark = _tone_map(_stretch(dark, crown, p.contrast), crown, _TONE_MEAN * (p.contrast > 0))
    # the blank ground a tree crown round an object holds gets light but solid twigs, so
    # the crown reads as a crown (matched to white they were sub-pixel grey wisps)
    ground = np.zeros((h, w), bool)
    blank = ground
    if p.crown == "content" and _GROUND_TONE > 0:
        ground[:hi] = crown[:hi] & ~_content(imp[:hi], p.crown_blur)
        dark = np.where(ground, np.maximum(dark, _GROUND_TONE), dark).astype(np.float32)
        # the trunk and limbs keep their widths up to the object itself (a tighter margin)
        blank = np.zeros((h, w), bool)
        blank[:hi] = crown[:hi] & ~_content(imp[:hi], 0.2 * p.crown_blur)
    if p.side == "full":
        noise = np.full((h, w), p.noise_image)
        img_side = np.ones((h, w), bool)
    else:
        ramp = side_ramp((h, w), p.side)
        noise = p.noise_image + (p.noise_random - p.noise_image) * ramp
        img_side = ramp < 0.5
    cost = p.cost_weight * (1.0 - imp.astype(np.float64))
    # the picture outside the crown is dear (beyond the paper): paths to endpoints near the
    # crown's edge ran along strong edges outside it (a tower by the frame) into the margin
    off = np.zeros((h, w), bool)
    if _OFF_CROWN > 0:
        off[:hi] = ~crown[:hi]
        cost[off] += _OFF_CROWN * p.cost_weight

    # iteration 1: the trunk on a calm random lattice, the limbs on the image lattice
    fork = _fork_point(crown, dark_limbs, p.crown_blur)
    root = np.array([fork[0], h - 1.0])  # a trunk that stands straight under its fork
    calm = Lattice(node_weights(np.zeros((h, w)), epsilon=1.0, noise=0.3, rng=rng))
    trunk = build_dendrite(plan(calm, root, metric="cumulative"), fork[None],
                           radius=p.tip_width / 2, iteration=1)
    k = max(1, round(trunk.n_nodes * 0.75))
    seeds = np.zeros(h * w, bool)
    seeds[trunk.nodes[k - 1:]] = True
    top = np.flatnonzero(crown.any(axis=1))
    upper = crown & (np.arange(h)[:, None] < top.min() + 0.8 * (top.max() - top.min() + 1))
    # the limbs end in the picture's dark parts (stippled on its blurred darkness), where
    # their ink is part of the picture: placed uniformly, a limb that followed a dark
    # outline cut across a light region to its end as a thick spoke (a drawn face)
    def shade(f):  # on the coarse grid the stippling runs on
        u = _shrink(upper.astype(float), f)
        g = ndimage.gaussian_filter(_shrink(dark_limbs.astype(np.float64), f), p.crown_blur / f)
        return u * (0.1 + g / max(float(g[u > 0].max(initial=0.0)), 1e-6))

    limb_ends = _coarse_points(lambda f: stipple(shade(f), p.trunk_endpoints, iterations=15, rng=rng),
                               upper, 2 * fine, rng)  # 9 points: a coarse grid will do
    # the limbs run through the picture's dark parts: on the importance's cost they
    # followed strong edges, up the middle of a bright object (a lit rocket at night)
    limb_cost = p.cost_weight * (1.0 - np.clip(ndimage.gaussian_filter(
        dark_limbs.astype(np.float64), 0.5 * p.crown_blur), 0.0, 1.0))
    limb_cost[off] += _OFF_CROWN * p.cost_weight
    lat = Lattice(node_weights(limb_cost, epsilon=p.epsilon, noise=noise, rng=rng))
    d = build_dendrite(plan(lat, seeds.reshape(h, w), metric="cumulative"), limb_ends,
                       base=trunk, radius=p.tip_width / 2, iteration=1)

    # endpoints: stippled on the importance in the crown, a few random ones
    region = img_side & crown
    if (imp[region] >= 0.05).any():
        # on a grown lattice the stippling runs on the nominal one (its cost grows with
        # the pixels), and the points are spread over the finer cells
        e_img = _coarse_points(lambda f: place_endpoints(
            _shrink(imp, f), n_img, gamma=p.endpoint_gamma, floor=0.0, threshold=0.05,
            mask=_shrink(region.astype(float), f) > 0.5, rng=rng), region, fine, rng)
    else:
        e_img = random_endpoints(region, n_img, rng=rng)
    n_rand = round(p.random_ratio * n_img)
    rand_region = crown & ~img_side if p.side != "full" else crown
    e_rand = (random_endpoints(rand_region, n_rand, rng=rng) if n_rand > 0 and rand_region.any()
              else np.zeros((0, 2)))
    if ground.any() and _GROUND_TWIGS > 0:
        # ... and twigs of their own there (the stippling leaves blank ground empty)
        n_gr = round(_GROUND_TWIGS * n_img * ground.sum() / max(crown.sum(), 1))
        e_rand = np.vstack([e_rand, random_endpoints(ground, n_gr, rng=rng)]) if n_gr > 0 else e_rand
    ends = np.vstack([e_img, e_rand])
    ends = ends[rng.permutation(len(ends))]
    # growing batches over iterations 2..n (each twice the previous)
    n_it = p.iterations - 1
    # twigs grow toward the light (beyond the paper): up a little cheaper, down dearer
    rise = direction_factors(up=1.0 - p.rise, down=1.0 + p.rise) if p.rise > 0 else None
    sizes = 2.0 ** np.arange(n_it)
    cuts = np.round(np.cumsum(sizes) / sizes.sum() * len(ends)).astype(int)
    start = 0
    for j, i in enumerate(range(2, p.iterations + 1)):
        batch = ends[start:cuts[j]]
        start = cuts[j]
        if len(batch) == 0:
            continue
        metric, a = iteration_metric(i, tp)
        lat = Lattice(node_weights(cost, epsilon=p.epsilon, noise=noise, rng=rng), rise,
                      bottleneck=p.bottleneck)
        seeds = np.zeros(h * w, bool)
        seeds[d.nodes] = True
        if p.min_twig > 0:
            # an endpoint next to the tree grown so far adds a stub, not a twig (beyond the
            # paper): a bump on its branch that the tone match cannot make read as a twig
            gap = ndimage.distance_transform_edt(~seeds.reshape(h, w))
            at = np.clip(np.rint(batch).astype(np.int64), 0, [w - 1, h - 1])
            batch = batch[gap[at[:, 1], at[:, 0]] >= p.min_twig]
            if len(batch) == 0:
                continue
        res = plan(lat, seeds.reshape(h, w), metric=metric, blend_weight=a)
        d = build_dendrite(res, batch, base=d, radius=p.tip_width / 2, iteration=i)

    bounds = {}
    # small dark features (eyes, a mouth) may be solid ink (beyond the paper)
    spacing = float(np.sqrt(crown.sum() / max((1.0 + p.random_ratio) * n_img, 1.0)))
    feat = _features(dark, spacing, float(np.sqrt(crown.sum()))) * crown if p.features else np.zeros_like(dark)
    d = _thickness(d, p, imp, dark, crown, trunk.n_nodes, bounds, cover=_feature_cover(feat, p.cover),
                   ground=blank)
    if "ramp" in bounds:
        # the limbs' ink is budgeted against the tone on a picture dark all over only (from
        # _DARK_FROM, fully 0.1 darker): on lighter ones they narrowed to twigs' width in a
        # portrait's light face and no longer reached into the crown
        bounds["ramp"] = bounds["ramp"] * float(np.clip((mean_dark - _DARK_FROM) / 0.1, 0.0, 1.0))
    shape_full = (full.shape[0] + round(p.trunk_height * full.shape[0]), full.shape[1])
    canvas = np.ones((*shape_full, 3), np.float32)
    canvas[:full.shape[0]] = full
    scale = np.array([shape_full[1] / w, shape_full[0] / h])

    def to_canvas(pts):
        return (np.asarray(pts, float) + 0.5) * scale - 0.5

    if shape_full != (h, w):
        d = d.rescaled(shape_full)
    if p.refine > 0 and bounds:
        big = resize(crown.astype(np.float32), shape_full, order=0) > 0.5 \
            if shape_full != (h, w) else crown
        dark_out = _tone_map(_stretch(darkness(canvas), big, p.contrast), big,
                             _TONE_MEAN * (p.contrast > 0))
        if ground.any():
            g = resize(ground.astype(np.float32), shape_full, order=0) > 0.5 \
                if shape_full != (h, w) else ground
            dark_out = np.where(g, np.maximum(dark_out, _GROUND_TONE), dark_out)
        if shape_full != (h, w):
            feat = resize(feat, shape_full, order=1)
        d = _refine_tone(d, dark_out, bounds,
                         float(np.sqrt(scale.prod())) if shape_full != (h, w) else 1.0, p,
                         _feature_cover(feat, p.cover))
    return PareidoliaTree(canvas, imp, d, to_canvas(e_img), to_canvas(e_rand).reshape(-1, 2),
                          dataclasses.replace(user), crown)
