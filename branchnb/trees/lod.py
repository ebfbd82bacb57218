"""Levels of detail of one billboard cloud, exported as glTF (beyond the paper).

Game engines (SpeedTree, ez-tree) draw a tree with a chain of ever cheaper
representations as it moves away from the camera. From one
:class:`~branchnb.trees.billboard.BillboardCloud` this module derives

0. ``full``: the whole cloud (two triangles per billboard);
1. ``reduced``: the front view as one billboard at the back, before it
   the billboards that carry most of the picture (front and trunk first,
   by opaque area), ``reduced_share`` of them;

   on drawn trees both carry the side views' outline baked into their
   textures (:func:`bake_side_outline`) where the front view hides the
   texels, and the rest of it from 45, 90, 135, 225, 270 and 315 degrees
   on side cards, fixed quads hidden in the front view
   (:func:`~branchnb.trees.lod_cards.side_outline_cards`): an engine draws
   no silhouette ink of its own;
2. ``crossed``: two perpendicular quads (four triangles), the front view
   on one and the side view from 90 degrees on the other
   (:func:`crossed_impostor`), rendered as the in-memory side views are:
   a drawn tree's side view keeps its inked silhouette outline;
3. ``single``: one quad (two triangles), an impostor whose texture holds
   the views from 8 yaws (:func:`impostor_frames`, every 45 degrees,
   rendered as the in-memory side views are, with a drawn tree's inked
   silhouette outline); the quad shows the front view, and
   ``extras.impostor`` lists each frame's yaw and texture rectangle, so
   that an engine's impostor shader can show the frame nearest to the
   camera's direction.

:func:`export_lod_gltf` writes them as one self-contained glTF 2.0 file
with the ``MSFT_lod`` extension (the first node holds the full cloud and
lists the coarser nodes; ``extras.MSFT_screencoverage`` gives the screen
coverage below which each level hands over to the next), or one file per
level (``mode="files"``). Every level uses the same units, axes and origin
as :func:`~branchnb.trees.export.export_gltf`.

Examples
--------
>>> import tempfile, pathlib, json
>>> from branchnb import data
>>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
>>> cloud = billboard_cloud(data.load("tree_rpg_03"), params=BillboardParams(max_size=128), rng=0)
>>> chain = lod_chain(cloud)
>>> [lv.name for lv in chain], [lv.triangles for lv in chain][2:]
(['full', 'reduced', 'crossed', 'single'], [4, 2])
>>> out = export_lod_gltf(cloud, pathlib.Path(tempfile.mkdtemp()) / "tree.gltf")
>>> json.loads(out[0].read_text())["nodes"][0]["extensions"]["MSFT_lod"]["ids"]
[1, 2, 3]
"""

from __future__ import annotations

from dataclasses import dataclass

from ..core.validate import Real, checked
from .export import _check_cloud
from .lod_gltf import SCREEN_COVERAGE, export_full_gltf, export_lod_gltf, validate_gltf
from .lod_levels import (  # noqa: F401  (the private helpers stay importable from here)
    _drop_floating_billboards,
    _subset_keep_sources,
    crossed_impostor,
    impostor_cloud,
    impostor_frames,
    reduce_cloud,
)
from .lod_view import (  # noqa: F401
    _opaque_texels,
    _pinholes_filled,
    _subset,
    _texel_offsets,
    _view_ids,
    bake_side_outline,
    engine_view,
)

__all__ = ["LOD_LEVELS", "LodLevel", "reduce_cloud", "impostor_cloud", "crossed_impostor",
           "impostor_frames", "engine_view", "bake_side_outline", "lod_chain", "export_lod_gltf",
           "export_full_gltf", "validate_gltf", "SCREEN_COVERAGE"]

#: The levels of :func:`lod_chain`, finest first.
LOD_LEVELS = ("full", "reduced", "crossed", "single")


@dataclass(eq=False)
class LodLevel:
    """One level of detail.

    Parameters
    ----------
    name : str
        ``"full"``, ``"reduced"``, ``"crossed"`` or ``"single"``.
    cloud : BillboardCloud
        The billboards of this level.
    crossed : bool
        Two perpendicular quads per billboard.
    turn : (K,) float array or None
        Per billboard, degrees its quad is turned by (the crossed impostor's
        side view: 90).
    yaws : tuple of float or None
        Impostor frames: the yaw of each texture of ``cloud`` (the quad shows
        the first).
    cards : SideCards or None
        Fixed, single-sided quads drawn with the level
        (:func:`~branchnb.trees.lod_cards.side_outline_cards`: the side
        views' rim ink of a drawn tree), or None.

    Examples
    --------
    >>> from branchnb.trees.billboard import billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> cloud = billboard_cloud(synthetic_tree("clean", rng=0, size=64).image, rng=0)
    >>> LodLevel("full", cloud).triangles == 2 * cloud.n_billboards
    True
    """

    name: str
    cloud: object
    crossed: bool = False
    turn: object = None
    yaws: object = None
    cards: object = None

    @property
    def quads(self) -> int:
        n = 0 if self.cards is None else self.cards.n
        return self.cloud.n_billboards * (2 if self.crossed else 1) + n

    @property
    def triangles(self) -> int:
        """Triangles drawn (two per quad)."""
        return 2 * self.quads



@checked(reduced_share=Real(0, 1, low_open=True))
def lod_chain(cloud, *, reduced_share: float = 0.3) -> list[LodLevel]:
    """The four levels of detail of one cloud (:data:`LOD_LEVELS`), finest first.

    Parameters
    ----------
    cloud : BillboardCloud
        The full cloud (the ``full`` level: its billboards, with the side
        outline of a drawn tree baked in by :func:`bake_side_outline` and
        the rest of it on side cards,
        :func:`~branchnb.trees.lod_cards.side_outline_cards`).
    reduced_share : float
        Share of the billboards the ``reduced`` level keeps (:func:`reduce_cloud`).

    Returns
    -------
    list of LodLevel
        ``full`` (the cloud), ``reduced`` (both baked with
        :func:`bake_side_outline`, and with side cards for drawn trees,
        :attr:`LodLevel.cards`), ``crossed``
        (:func:`crossed_impostor`) and ``single`` (:func:`impostor_frames`,
        8 frames).

    Examples
    --------
    >>> from branchnb.trees.billboard import BillboardParams, billboard_cloud
    >>> from branchnb.trees.synthetic import synthetic_tree
    >>> img = synthetic_tree("clean", rng=0, size=64).image   # the paper's cloud, not drawn cards
    >>> cloud = billboard_cloud(img, params=BillboardParams(drawn_cards=False), rng=0)
    >>> [(lv.name, lv.triangles) for lv in lod_chain(cloud)]
    [('full', 1284), ('reduced', 388), ('crossed', 4), ('single', 2)]
    """
    from .lod_cards import side_outline_cards

    _check_cloud(cloud)
    single, yaws = impostor_frames(cloud)
    crossed, turn = crossed_impostor(cloud)
    out = []
    for name, c in (("full", cloud), ("reduced", reduce_cloud(cloud, reduced_share))):
        baked = bake_side_outline(c)
        out.append(LodLevel(name, baked, cards=side_outline_cards(c, baked=baked)))
    return out + [LodLevel("crossed", crossed, turn=turn), LodLevel("single", single, yaws=yaws)]

