"""Example edits on the sample objects (shared by the gallery, the benchmarks and the tests).

Each example returns ``(image, source_strokes, target_strokes, kwargs)``
for :func:`~branchnb.strokes.edit_structure`. The strokes were drawn by
hand along the objects' skeletons.
"""

from __future__ import annotations

import numpy as np

from .. import data

__all__ = ["LIZARD_TAIL", "rope_bend", "lizard_straighten", "tree_add_branch", "twig_five_parts",
           "twig_parts_edit", "rigid_fit",
           "figure_limbs_turned", "EXAMPLES"]

#: The lizard's tail, from the hips to the tip (``lizard`` image pixels).
LIZARD_TAIL = np.array([
    [472, 465], [496, 489], [516, 514], [532, 539], [546, 564], [556, 589], [566, 614],
    [577, 639], [588, 664], [596, 689], [604, 714], [615, 739], [628, 764], [645, 789],
    [665, 814], [688, 838], [713, 859], [738, 874], [763, 886], [788, 895], [813, 901],
    [838, 905], [863, 905], [888, 903], [913, 899], [938, 894], [963, 887], [988, 877],
    [1008, 860]], float)

#: ``tree_rpg_12``: the trunk up to the right fork, the left branch, the middle branch.
TREE_TRUNK = np.array([(205, 435), (208, 310), (245, 250), (300, 195), (330, 160),
                       (370, 110), (398, 45)], float)
TREE_LEFT = np.array([(208, 310), (185, 255), (150, 205), (112, 165), (100, 130), (60, 100),
                      (15, 95)], float)
TREE_MIDDLE = np.array([(325, 160), (300, 140), (265, 115), (245, 80), (215, 15)], float)


def rope_bend():
    """Bend the straight part of the rope along a quarter circle (512 x 512 output).

    The rest of the loop touches the piece at both ends, so it cannot follow
    a bend rigidly: the piece comes alone (as in the paper).
    """
    img = data.load("rope_loop")
    src = np.array([(215, 515), (215, 815)], float)
    a = np.linspace(0, np.pi / 2, 40)
    tgt = np.c_[110 + 200 * np.sin(a), 80 + 200 * (1 - np.cos(a))]
    return img, [src], [tgt], {"target_shape": (512, 512)}


def lizard_straighten():
    """Straighten the lizard's curled tail (1000 x 130 output)."""
    img = data.load("lizard")
    length = float(np.hypot(*np.diff(LIZARD_TAIL, axis=0).T).sum())
    tgt = np.array([(150, 60), (150 + length, 60)])
    return img, [LIZARD_TAIL], [tgt], {"target_shape": (130, 1000)}


def tree_add_branch():
    """Keep the trunk and two branches, grow a new branch from the trunk (same size output)."""
    img = data.load("tree_rpg_12")
    new = np.array([(245, 250), (300, 262), (360, 255), (430, 225), (480, 215)], float)
    src = [TREE_TRUNK, TREE_LEFT, TREE_MIDDLE, TREE_MIDDLE]
    tgt = [TREE_TRUNK, TREE_LEFT, TREE_MIDDLE, new]
    return img, src, tgt, {}


def bent_spine(spine: np.ndarray, height: int, sag: float = 0.12) -> np.ndarray:
    """The twig's stroke bent into an arc sagging by ``sag`` of the image height."""
    x0, x1 = spine[0, 0], spine[-1, 0]
    return np.c_[spine[:, 0], 0.45 * height + sag * height * np.sin((spine[:, 0] - x0) / (x1 - x0) * np.pi)]


def rigid_fit(a: np.ndarray, b: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """The rotation ``R`` and shift ``t`` taking the points ``a`` onto ``b`` (least squares:
    ``b ~ a @ R.T + t``)."""
    ma, mb = a.mean(axis=0), b.mean(axis=0)
    u, _, vt = np.linalg.svd((a - ma).T @ (b - mb))
    rot = (u @ vt).T
    return rot, mb - rot @ ma


def twig_parts_edit(size: int = 1000, add_leaf: bool = False):
    """A procedural twig bent with its two leaves and two fruits carried along by strokes.

    Parameters
    ----------
    size : int
        The twig's image size (px).
    add_leaf : bool
        Also add a copy of leaf 1 at 85 % of the bent twig (a sixth pair).

    Returns
    -------
    obj : PartObject
        The twig (:func:`~branchnb.strokes.procedural.twig`, seed 0) with its part labels.
    src, tgt : list of (N, 2) ndarray
        Source and target strokes for :func:`~branchnb.strokes.edit_structure`.
    moves : dict
        Part label -> ``(R, t)``, the rigid map ``x -> R x + t`` of every carried part
        (its source stroke fitted onto its target stroke; strokes of two points left out).
    """
    from .parts import carry_stroke
    from .procedural import twig
    from .strokes import Stroke

    obj = twig(size, rng=0)
    spine = obj.strokes[0]
    bent = bent_spine(spine, obj.image.shape[0])
    src = [spine] + [obj.strokes[k] for k in range(1, 5)]
    tgt = [bent] + [carry_stroke(obj.strokes[k], spine, bent) for k in range(1, 5)]
    moves = {k: rigid_fit(src[k], tgt[k]) for k in range(1, 5) if len(src[k]) > 2}
    if add_leaf:
        st = Stroke(bent)
        src.append(obj.strokes[1])
        tgt.append(st.point_at(0.85 * st.length) + (tgt[1] - tgt[1][0]))
    return obj, src, tgt, moves


def twig_five_parts(size: int = 1000):
    """Bend a procedural twig and carry its two leaves and two fruits along with strokes (5 pairs)."""
    obj, src, tgt, _ = twig_parts_edit(size)
    return obj.image, src, tgt, {}


def figure_limbs_turned(size: int = 1000):
    """Turn a procedural figure's arms and legs about their roots, the body kept (5 pairs).

    The arms are raised by ~50-57 degrees, the legs spread by 17 degrees; the
    head (not stroked) follows the body.
    """
    from .procedural import figure

    obj = figure(size, rng=0)
    body = obj.strokes[0]
    src, tgt = [body], [body]
    for k, ang in ((2, 0.9), (3, -1.0), (4, 0.3), (5, -0.3)):
        st = obj.strokes[k]
        c, s = np.cos(ang), np.sin(ang)
        src.append(st)
        tgt.append((st - st[0]) @ np.array([[c, -s], [s, c]]).T + st[0])
    return obj.image, src, tgt, {}


EXAMPLES = {
    "rope_bend": rope_bend,
    "lizard_straighten": lizard_straighten,
    "tree_add_branch": tree_add_branch,
    "twig_five_parts": twig_five_parts,
    "figure_limbs_turned": figure_limbs_turned,
}
