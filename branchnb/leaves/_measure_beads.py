"""Beaded donor veins and spiky outlines of new leaves, measured (issue 22; a check script, not API).

``python -m branchnb.leaves._measure_beads [procedural] [maples] [--n 8]`` (new leaves, ``generate(a, n,
rng=0)``), ``... pasted [procedural] [maples] [--old]`` (each donor's pasted vein layer in its own frame;
``--old``: without the side-knob rule of :func:`branchnb.leaves.prepared._completed`).

Cause found (maples, the notebook's analysis): the pasted layers are not
broken along their length (the footprint covers 92-97 % of each traced
vein's skeleton within its reach) and the synthesis keeps each donor vein's
contrast along its core (new leaf within 1 px against donor, point by
point). The beads are the donors' own: at 250 px a maple's midrib between
its vein nodes stands 0.02-0.05 out of the blade and its nodes 0.13-0.17
(maple_leaf_05), and speckled donors (maple_leaf_04) carry the flecks
touching their veins; pasted onto a smoother or more textured background
the faint line between nodes sinks and the flecks stand alone. Part of
the flecks came through the mask's completion (side knobs), now left out.

**Beads.** A donor's vein, pasted into a new leaf, should come out as
continuous as it is in the donor. Each donor vein with a known answer (the
true vein layer of a procedural leaf, the hand tracing of a sample maple) is
skeletonised in the donor's frame and carried into the new leaf through the
coordinates the synthesis sampled the layer at. Along it, the vein's
contrast (darkness or lightness against the blade's median over 9 px, of the
donor layer's polarity) is read in the donor and in the new leaf (the
largest within 1 px, so a 1 px offset does not count as a gap). Over the
skeleton points where the donor's vein is visible (contrast at least a third
of its median) and the pasted layer covers the carried point:

* ``gap``: share whose contrast in the new leaf is below half the donor's;
* ``pieces``: the visible points kept, as pieces along the skeleton, per
  100 px of kept skeleton, minus the donor's own pieces per 100 px (0: as
  continuous as the donor; a dashed vein adds a piece per dash).

**Pasted off the vein** (``pasted``). The synthesis changes the background
by ``cover * (ratio - 1)`` under a layer; ``off`` is the share of that
change more than 1 px from the true vein, ``core`` the change on the vein
itself. Before -> after the side-knob rule: maples 0.201 -> 0.188 (per
exemplar 0.31/0.06/0.08/0.29/0.13/0.18/0.37 -> 0.30/0.04/0.06/0.27/0.11/0.17/0.36;
the rest is mostly veins the tracing leaves out), procedural lobed,
trilobed, elliptic 256 px 0.010/0.007/0.010 unchanged, core unchanged.
New leaves (maples, rng 0, the same donors): ``gap`` mean 0.038 -> 0.037,
``pieces`` +1.86 -> +1.78 per 100 px. A footprint ring pasted at half
weight took off-vein down to 0.171 but cut faint veins (``gap`` 0.044,
``pieces`` +2.14): not kept.

**Spikes.** The new blade's outline (without the petiole) is smoothed a
little and its turning angle over +-3 px arcs read (0 straight, 180 a
needle); ``turn``: the largest per new leaf, against the exemplars' largest.
Found: it does not tell a spike on maples, whose own lobe tips already turn
156-180 degrees (the notebook's spiky lobe, new leaf 3 of ``generate(a, 8,
rng=0)``, reads 180 against the exemplars' 163-180); a spike is a drawn-out
lobe, long rather than sharp.
"""

from __future__ import annotations

import sys

import numpy as np
from scipy import ndimage as ndi

from .analysis_normalise import _on_canvas

__all__: list[str] = []


def _lum(rgb: np.ndarray) -> np.ndarray:
    return np.asarray(rgb, np.float32)[..., :3].mean(-1)


def line_contrast(rgb: np.ndarray, blade: np.ndarray, sign: float) -> np.ndarray:
    """Signed contrast ``sign * (L - median_9(L)) / median_9(L)`` of a line's pixels against the blade near them.

    Outside the blade the luminance is the nearest blade pixel's, so the
    paper does not count as blade.
    """
    lum = _lum(rgb)
    blade = np.asarray(blade, bool)
    idx = ndi.distance_transform_edt(~blade, return_distances=False, return_indices=True)
    filled = lum[idx[0], idx[1]]
    med = ndi.median_filter(filled, size=9)
    return (sign * (filled - med) / np.maximum(med, 0.02)).astype(np.float32)


def _skeleton(mask: np.ndarray) -> np.ndarray:
    from skimage.morphology import skeletonize
    return skeletonize(np.asarray(mask, bool))


def carried_contrast(donor_rgb, donor_blade, donor_veins, new_rgb, new_blade, coords, cover, sign):
    """Per donor skeleton point: ``(donor contrast, new contrast, covered)``; new contrast NaN where not carried.

    ``coords`` (H, W, 2): the donor pixel (x, y) each new pixel sampled the
    layer at; ``cover`` (H, W): the pasted layer's coverage in the new leaf.
    """
    sk = _skeleton(donor_veins & donor_blade)
    ys, xs = np.nonzero(sk)
    if len(ys) == 0:
        return np.zeros(0), np.zeros(0), np.zeros(0, bool), (ys, xs)
    c_d = ndi.maximum_filter(line_contrast(donor_rgb, donor_blade, sign), size=3)[ys, xs]
    ids = np.full(sk.shape, -1, np.int64)
    ids[ys, xs] = np.arange(len(ys))
    dist, near = ndi.distance_transform_edt(~sk, return_indices=True)
    cx = np.clip(np.rint(coords[..., 0]).astype(int), 0, sk.shape[1] - 1)
    cy = np.clip(np.rint(coords[..., 1]).astype(int), 0, sk.shape[0] - 1)
    # Donor-frame distance of each new pixel's source to the skeleton (to its whole-pixel rounding).
    d_new = dist[cy, cx]
    owner = ids[near[0][cy, cx], near[1][cy, cx]]
    on = (d_new <= 1.0) & new_blade
    c_new_map = ndi.maximum_filter(line_contrast(new_rgb, new_blade, sign), size=3)
    c_n = np.full(len(ys), np.nan)
    cov = np.zeros(len(ys), bool)
    sel = np.flatnonzero(on.ravel())
    o = owner.ravel()[sel]
    vals = c_new_map.ravel()[sel]
    cv = cover.ravel()[sel] > 0.5
    order = np.argsort(o, kind="stable")
    o, vals, cv = o[order], vals[order], cv[order]
    if len(o):
        starts = np.r_[0, np.flatnonzero(np.diff(o)) + 1]
        mx = np.maximum.reduceat(vals, starts)
        anyc = np.logical_or.reduceat(cv, starts)
        c_n[o[starts]] = mx
        cov[o[starts]] = anyc
    return c_d, c_n, cov, (ys, xs)


def bead_scores(c_d, c_n, cov, pts, shape):
    """``(gap, pieces)`` of one pasted vein layer (see the module docstring)."""
    ok = np.isfinite(c_n) & cov
    if ok.sum() < 10:
        return float("nan"), float("nan")
    vis = c_d >= max(1.0 / 3.0 * float(np.median(c_d[c_d > 0])) if (c_d > 0).any() else 0.0, 0.01)
    use = ok & vis
    if use.sum() < 10:
        return float("nan"), float("nan")
    kept = use & (c_n >= 0.5 * c_d)
    gap = float(1.0 - kept.sum() / use.sum())
    ys, xs = pts

    def pieces(sel):
        m = np.zeros(shape, bool)
        m[ys[sel], xs[sel]] = True
        n = ndi.label(m, structure=np.ones((3, 3)))[1]
        return 100.0 * n / max(sel.sum(), 1)

    return gap, float(pieces(kept) - pieces(use))


def outline_turning(blade: np.ndarray, arc: int = 3) -> np.ndarray:
    """Turning angle (degrees, positive = convex) at each point of the largest outer contour, over +-``arc`` px."""
    import cv2
    m = np.asarray(blade, np.uint8)
    cs, _ = cv2.findContours(m, cv2.RETR_EXTERNAL, cv2.CHAIN_APPROX_NONE)
    if not cs:
        return np.zeros(0)
    c = max(cs, key=len)[:, 0, :].astype(np.float64)
    if len(c) < 4 * arc:
        return np.zeros(0)
    c = ndi.gaussian_filter1d(c, 1.0, axis=0, mode="wrap")
    a = np.roll(c, arc, 0) - c
    b = np.roll(c, -arc, 0) - c
    ang = np.degrees(np.arctan2(a[:, 0] * b[:, 1] - a[:, 1] * b[:, 0], (a * b).sum(1)))
    # 180 - |angle between the two arms|: 0 on a straight outline, near 180 at a needle tip.
    turn = 180.0 - np.abs(ang)
    return turn


def _trace_leaf(a, seed):
    """``generate_leaf(a, seed)`` with its vein layer's sample coordinates and coverage.

    Read from the locals of :func:`branchnb.leaves.synthesis_layers._paste_layers` as it returns: the
    layers are pasted bottom first, so its last ``c`` (the donor's source coordinates) and ``a_k`` (the
    sampled layer coverage) are layer 0's whenever layer 0 had a donor. (``generate_leaf``'s own locals
    held them before the paste moved there; the hook then saw neither and measure() failed on them.) Both are
    returned on the whole canvas (0 outside the work box the synthesis computed the leaf on).
    """
    from . import synthesis
    from .synthesis_layers import _paste_layers
    code = _paste_layers.__code__
    cap = {}

    def prof(frame, event, arg):
        if event == "return" and frame.f_code is code:
            cap.update(frame.f_locals)

    old = sys.getprofile()
    sys.setprofile(prof)
    try:
        leaf = synthesis.generate_leaf(a, seed)
    finally:
        sys.setprofile(old)
    if "chosen" not in cap:
        raise RuntimeError("_measure_beads: generate_leaf no longer pastes its layers through "
                           "synthesis_layers._paste_layers; update _trace_leaf")
    if "a_k" in cap:
        # The paste works on the new leaf's work box (``p.last_box``); the measure reads the whole canvas.
        box = cap["p"].last_box
        shape = leaf.blade.shape
        c = np.zeros(shape + (2,), np.float32)
        a_k = np.zeros(shape, np.float32)
        c[box] = cap["c"][..., :2]
        a_k[box] = cap["a_k"]
        cap["c"], cap["a_k"] = c, a_k
    return leaf, cap


def _lamina(blade):
    """The blade without its petiole (lobe tips kept: ``split_petiole``'s lamina drops every thin part)."""
    from .starts import split_petiole
    return blade & ~split_petiole(blade)[1]


def measure(a, truths, n_new=8, rng=0, k=None):
    """Per new leaf ``(gap, pieces, spikes)`` and the spike limit, for analysis ``a`` whose exemplars' true
    veins (on the analysis canvas) are ``truths``. The vein layer must be the last one pasted (index 0) unless
    ``k`` says which."""
    from ..core.random import as_rng
    from .prepared import _prepared
    from .synthesis import _stratified_seeds
    p = _prepared(a)
    if k is None:
        k = int(np.argmax([L.lam for L in a.layers]))
    sign = p.leftover[1] if p.leftover is not None else -1.0
    limit = max(float(outline_turning(_lamina(b)).max(initial=0.0)) for b in a.blades)
    seeds = _stratified_seeds(as_rng(rng), n_new, len(a.exemplars))
    rows = []
    for s in seeds:
        leaf, cap = _trace_leaf(a, int(s))
        e = leaf.layers.get(a.layers[k].name, -1)
        spikes = float(outline_turning(_lamina(leaf.blade)).max(initial=0.0))
        if e < 0 or k != 0 or cap.get("k") != 0 or "a_k" not in cap:
            rows.append((float("nan"), float("nan"), spikes, e))
            continue
        donor = np.asarray(p.stage[k][e], np.float32)
        c_d, c_n, cov, pts = carried_contrast(donor, a.blades[e], truths[e], leaf.on_white(), leaf.blade,
                                              cap["c"], cap["a_k"], sign)
        g, pc = bead_scores(c_d, c_n, cov, pts, a.blades[e].shape)
        rows.append((g, pc, spikes, e))
    return rows, limit


def maple_case():
    """The notebook's maples: stored scribbles on maple_leaf_01, the traced veins as truth."""
    from ..data import DATA_DIR, load
    from .analysis import analyze
    from .exemplar import leaf_exemplar
    from .layers import LayerSet
    from .reference import reference_veins
    maple = [leaf_exemplar(load(f"maple_leaf_0{i}")) for i in range(1, 8)]
    layer_set = LayerSet.from_json((DATA_DIR / "leaves" / "maple_leaf_01_layers.json").read_text())
    a = analyze(maple, 0, layer_set)
    shape = a.blades[0].shape
    truths = [_on_canvas(reference_veins(f"maple_leaf_0{i + 1}"), a.offsets[i], shape) for i in range(7)]
    return a, truths


def procedural_case(kind, size, seed, n=4):
    """A procedural family, leaf 0's true veins as the user's layer, the true veins as truth."""
    from .analysis import analyze
    from .procedural import leaf_family
    fam = leaf_family(n, size=size, kind=kind, rng=seed)
    a = analyze(fam, 0, {"veins": fam[0].layers["veins"]})
    shape = a.blades[0].shape
    truths = [_on_canvas(f.layers["veins"], a.offsets[i], shape) for i, f in enumerate(fam)]
    return a, truths


def _main(argv):
    import time
    if "--old" in argv:
        from . import prepared
        prepared._LINE_KNOBS = False
    pasted = "pasted" in argv
    argv = [x for x in argv if x != "pasted"]
    which = [x for x in argv if not x.startswith("--")] or ["procedural", "maples"]
    n_new = 8
    if "--n" in argv:
        n_new = int(argv[argv.index("--n") + 1])
        which = [x for x in which if x != str(n_new)]
    cases = []
    if "procedural" in which:
        for kind in ("lobed", "trilobed", "elliptic"):
            for size, seed in ((256, 0),):
                cases.append((f"{kind} {size} s{seed}", lambda k=kind, s=size, r=seed: procedural_case(k, s, r)))
    if "maples" in which:
        cases.append(("maples", maple_case))
    for name, make in cases:
        t = time.time()
        a, truths = make()
        if pasted:
            po = pasted_off_vein(a, truths)
            print(f"{name:18s} off-vein share {' '.join(f'{x[0]:.2f}' for x in po)} (mean "
                  f"{np.nanmean([x[0] for x in po]):.3f})  core {' '.join(f'{x[1]:+.3f}' for x in po)}  "
                  f"[{time.time() - t:.0f} s]", flush=True)
            continue
        rows, limit = measure(a, truths, n_new)
        g = np.array([r[0] for r in rows])
        pc = np.array([r[1] for r in rows])
        sp = [round(r[2]) for r in rows]
        print(f"{name:18s} gap mean {np.nanmean(g):.3f} max {np.nanmax(g):.3f}  pieces/100px mean "
              f"{np.nanmean(pc):+.2f} max {np.nanmax(pc):+.2f}  turn {sp} (exemplars <= {limit:.0f} deg)  "
              f"donors {[r[3] for r in rows]}  gaps {np.round(g, 2).tolist()}  [{time.time() - t:.0f} s]",
              flush=True)


def pasted_off_vein(a, truths):
    """Per exemplar ``(off, core)``: how a donor's vein layer changes a new leaf, in the donor's own frame.

    The synthesis pastes ``cover * (ratio - 1)`` of the background, ``ratio``
    the layer's stage image over the leaf under it and ``cover`` the
    layer's footprint (``prepared._Prepared.layer_masks``). ``off``: the share
    of that change (absolute, summed) more than 1 px from the true vein:
    specks, flecks and a halo cut off at the footprint's ragged edge, the
    beads and lumps of pasted veins. ``core``: the median change of the
    vein's polarity on the true vein's skeleton (the vein itself; it should
    not fall).
    """
    from .prepared import _prepared
    p = _prepared(a)
    if p.leftover is None:
        return []
    k, sign = p.leftover[0], p.leftover[1]
    out = []
    for e in range(len(a.exemplars)):
        cover = np.asarray(p.layer_masks[k][e], np.float32)
        tr = np.asarray(truths[e], bool) & a.blades[e]
        if not (cover > 0).any() or not tr.any():
            out.append((float("nan"), float("nan")))
            continue
        ratio = _lum(p.stage[k][e]) / np.maximum(_lum(p.layer_under[k][e]), 0.02)
        change = cover * (ratio - 1.0)
        near = ndi.binary_dilation(tr, iterations=1)
        tot = float(np.abs(change).sum())
        sk = _skeleton(tr) & (cover > 0.5)
        core = float(np.median(sign * change[sk])) if sk.any() else float("nan")
        out.append((float(np.abs(change[~near]).sum()) / max(tot, 1e-9), core))
    return out


if __name__ == "__main__":
    _main(sys.argv[1:])
