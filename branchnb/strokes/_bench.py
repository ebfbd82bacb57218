"""Benchmarks of stroke-based structure editing.

One edit with a 512 x 512 output (the rope bent along an arc): the full
method (dynamic-programming sampling + graph-cut composition) against
the baseline timed in the same run (greedy sampling + plain overlay,
same patches and search window). The notes give the energies of both,
so the rows also show what the extra time buys.

The multi-part row (issue 25: "a 5-part edit at ~1000 px < 2 s"): a
1000 x 600 procedural twig bent, its two leaves and two fruits carried
along with their own strokes, against the same twig bent with its stroke
alone (the parts follow it), timed in the same run; and a 1000 x 1000
procedural figure whose four limbs are turned about their roots (wide
joints closed, stale outline cleared), against its body alone.
"""

from __future__ import annotations

import dataclasses

from ..bench import BenchRow, timeit
from ._examples import figure_limbs_turned, lizard_straighten, rope_bend, tree_add_branch, twig_five_parts
from .edit import StrokeEditParams, edit_structure

__all__ = ["rows"]


def _row(name: str, example, quick: bool) -> BenchRow:
    img, src, tgt, kw = example()
    full = StrokeEditParams()
    base = dataclasses.replace(full, sampling="greedy", composition="overlay")
    res = {}

    def run(p, key):
        res[key] = edit_structure(img, src, tgt, p, **kw)

    repeat = 1 if quick else 3
    ours = timeit(lambda: run(full, "full"), repeat=repeat, warmup=not quick)
    anchor = timeit(lambda: run(base, "base"), repeat=repeat, warmup=not quick)
    ef, eb = res["full"].energies, res["base"].energies
    h, w = res["full"].image.shape[:2]
    return BenchRow(
        f"edit_structure {name}, {w} x {h} output (DP sampling + graph cut)", ours,
        "same edit, greedy sampling + plain overlay", anchor,
        f"sampling energy {ef['sampling']:.2f} vs {eb['sampling']:.2f}; "
        f"seam cost {ef['seam']:.1f} vs {eb['seam']:.1f}")


def _multi_part_row(quick: bool, example=twig_five_parts,
                    title: str = "5-part twig, {w} x {h} (bent; 2 leaves + 2 fruits carried by strokes)",
                    anchor_title: str = "same twig bent with its stroke alone (the parts follow)") -> BenchRow:
    img, src, tgt, _ = example(1000)
    res = {}

    def five():
        res["five"] = edit_structure(img, src, tgt)

    def one():
        edit_structure(img, src[:1], tgt[:1])

    repeat = 1 if quick else 3
    ours = timeit(five, repeat=repeat, warmup=not quick)
    anchor = timeit(one, repeat=repeat, warmup=not quick)
    h, w = img.shape[:2]
    return BenchRow("edit_structure " + title.format(w=w, h=h), ours, anchor_title, anchor,
                    f"target < 2 s; {len(res['five'].junctions)} junctions")


def rows(quick: bool = False) -> list[BenchRow]:
    out = [_row("rope bent along an arc", rope_bend, quick)]
    if not quick:
        out.append(_multi_part_row(quick))
        out.append(_multi_part_row(quick, figure_limbs_turned, "5-part figure, {w} x {h} (arms and legs turned)",
                                   "same figure, its body alone (the limbs follow)"))
    if not quick:
        out.append(_row("lizard tail straightened", lizard_straighten, quick))
        out.append(_row("tree_rpg_12 + new branch", tree_add_branch, quick))
    return out
