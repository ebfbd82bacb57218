"""Issue-23 figures on line-art children (branching60): as many children per length as the example, leaving
at the example's angles.

``python -m branchnb.branching._child_check [SEEDS] [KINDS] [PNG_DIR]`` (e.g. ``0,1 L,frame,ring,L+,vine,vine+``)
runs interlaced bands (:func:`._band_examples.band_example`, ``+``: with leaf stubs) and border vines with
shallow side strands (:func:`._line_art_examples.vine_example`) at 256-768 px through the default workflow
(``extract_structure``, ``fit_model(ex, domain=example_domain(img, ex))``, ``synthesize_structure``) and
prints per case and per kind: branches per 1000 px of length of the example (as fitted: strands joined)
``bk_ex`` and of the output ``bk_out``, their ratio ``bk``, the L1 distance of the child-angle histograms
``ahd`` (0 = equal, 2 = disjoint; :func:`.child_angles._child_angles`), the median child angle of both ``med_ex`` /
``med_out`` (degrees) and the difference of their means ``dmean``, the share of the output roots' length
``rout`` and of all its length ``lout`` outside the ornament's known band (:func:`example_envelope`: where
the example's strands run, not the wider domain they may grow in), and :mod:`._band_check`'s ``out``, ``ml``, ``len`` and ``turn``. PNG_DIR: sheets
example | seed s | seed s + 1.

Also (branching70): ``aerr`` the earth mover's distance (degrees) between the output's and the example's
child angles; the bands ``S``, ``spiral``, ``knot`` and ``border`` (256-1024 px; ``border`` 0.04-0.2 of
the side wide); and ``paint``, an interlaced band (L, frame or ring by the seed) synthesized into a band the
user painted (``synthesize_structure(model, domain=mask)``: an S-curve brush stroke as wide as the
example's band domain), judged against the painted stroke's centre line with the example's swing.
"""
# ruff: noqa: E501, E702
from __future__ import annotations

import numpy as np
from scipy.stats import wasserstein_distance

from ._check_table import check_args, print_table, write_sheet
from .child_angles import ANGLE_EDGES
from .child_angles import _child_angles as child_angles

KINDS = ("L", "U", "frame", "ring", "L+", "frame+", "vine", "vine+", "S", "spiral", "knot", "border", "paint")
SIZES = (256, 384, 512, 640, 768)
#: sizes of the kinds after ``vine+`` (branching70)
NEW_SIZES = (256, 512, 768, 1024)
#: the example kinds of ``paint``, by the seed
PAINT_EXAMPLES = ("L", "frame", "ring")


def size_of(kind: str, seed: int) -> int:
    i = KINDS.index(kind)
    return SIZES[(seed + i) % len(SIZES)] if i < KINDS.index("S") else NEW_SIZES[(seed + i) % len(NEW_SIZES)]
def angle_histogram_l1(a: np.ndarray, b: np.ndarray) -> float:
    """L1 distance (0-2) between the normalised :data:`ANGLE_EDGES` histograms of two sets of angles."""
    if len(a) == 0 or len(b) == 0:
        return 0.0 if len(a) == len(b) else 2.0
    ha = np.histogram(a, ANGLE_EDGES)[0] / len(a)
    hb = np.histogram(b, ANGLE_EDGES)[0] / len(b)
    return float(np.abs(ha - hb).sum())


def per_1000(s) -> float:
    """Branches per 1000 px of length."""
    return 1000.0 * len(s.branches) / max(s.total_length, 1e-9)


def example_image(kind: str, size: int, seed: int) -> np.ndarray:
    from ._band_examples import band_example
    from ._line_art_examples import vine_example

    leaves = kind.endswith("+")
    if kind.rstrip("+") == "vine":
        return vine_example(size, rng=seed, leaves=leaves)[0]
    if kind == "paint":
        return band_example(PAINT_EXAMPLES[seed % len(PAINT_EXAMPLES)], size, seed)[0]
    return band_example(kind.rstrip("+"), size, seed, leaves=leaves)[0]


def painted_band(img: np.ndarray, domain: np.ndarray, size: int, seed: int) -> tuple[np.ndarray, np.ndarray]:
    """``(mask, known band)`` of the ``paint`` kind: an S-curve brush stroke across ``img``'s frame as wide
    as the example's band ``domain`` (twice its deepest pixel, the frame being no edge), and the pixels of it
    within the example's swing (:func:`._band_examples.band_envelope`'s reach) of the stroke's centre line."""
    import cv2
    from scipy import ndimage as ndi

    from ._band_examples import _band_params, _centre_path

    H, W = img.shape[:2]
    half = float(ndi.distance_transform_edt(np.pad(domain, 1)).max())
    centre, _ = _centre_path("S", H, W, half)
    line = np.zeros((H, W), np.uint8)
    cv2.polylines(line, [np.round(centre * 4).astype(np.int32)], False, 1, 1, cv2.LINE_8, 2)
    d = ndi.distance_transform_edt(line == 0)
    _r, _h, _w, amp, _p, lw = _band_params(PAINT_EXAMPLES[seed % len(PAINT_EXAMPLES)], size, seed, False)
    mask = d <= half
    return mask, mask & (d <= amp + lw)


def example_envelope(kind: str, size: int, seed: int) -> np.ndarray:
    """The known band of :func:`example_image`'s ornament ((H, W) bool): where its strands run."""
    from ._band_examples import band_envelope
    from ._line_art_examples import vine_envelope

    leaves = kind.endswith("+")
    if kind.rstrip("+") == "vine":
        return vine_envelope(size, rng=seed, leaves=leaves)
    if kind == "paint":
        return band_envelope(PAINT_EXAMPLES[seed % len(PAINT_EXAMPLES)], size, seed)
    return band_envelope(kind.rstrip("+"), size, seed, leaves=leaves)


def envelope_figures(out, envelope: np.ndarray) -> dict:
    """``rout`` the share of the roots' length and ``lout`` of all the length of ``out`` outside the
    ornament's known band ``envelope``."""
    from ..core.structure import Structure
    from ._check_table import length_share

    roots = Structure([b for b in out.branches if b.parent is None], image_shape=out.image_shape)
    r_in, r_tot = length_share(roots, envelope)
    a_in, a_tot = length_share(out, envelope)
    return {"rout": 1.0 - r_in / max(r_tot, 1e-9), "lout": 1.0 - a_in / max(a_tot, 1e-9)}


def figures(ex, out) -> dict:
    """The child figures of one case (example structure ``ex`` as fitted, synthesized structure ``out``):
    also ``dmean``, the output's mean child angle minus the example's (degrees)."""
    ae, ao = child_angles(ex), child_angles(out)
    return {"bk_ex": per_1000(ex), "bk_out": per_1000(out), "bk": per_1000(out) / max(per_1000(ex), 1e-9),
            "ahd": angle_histogram_l1(ae, ao), "med_ex": float(np.median(ae)) if len(ae) else 0.0,
            "med_out": float(np.median(ao)) if len(ao) else 0.0,
            "dmean": float(np.mean(ao) - np.mean(ae)) if len(ae) and len(ao) else 0.0,
            "aerr": float(wasserstein_distance(ao, ae)) if len(ae) and len(ao) else 0.0}


def case(kind: str, size: int, seed: int, png: str | None = None) -> dict:
    from . import example_domain, extract_structure, fit_model, synthesize_structure
    from ._band_check import figures as band_figures

    img = example_image(kind, size, seed)
    ex = extract_structure(img)
    model = fit_model(ex, domain=example_domain(img, ex))
    env = example_envelope(kind, size, seed)
    dom = None
    if kind == "paint":   # the same ornament in a band the user painted
        dom, env = painted_band(img, model.domain, size, seed)
    res = synthesize_structure(model, rng=seed, domain=dom)
    ink = img[..., :3].mean(-1) < 0.5
    from scipy import ndimage as ndi
    # the band check's strand spacing, read off the drawing: 2 x the 90th percentile distance of the
    # domain to the ink (the known spacing of band_example is not known for vines)
    spacing = 2.0 * float(np.quantile(ndi.distance_transform_edt(~ink)[model.domain], 0.9))
    f = band_figures(img, spacing, model.example, res.structure)
    f.update(figures(model.example, res.structure))
    f.update(envelope_figures(res.structure, env))
    f["nb_ex"], f["nb_out"] = len(model.example.branches), len(res.structure.branches)
    if png:
        write_sheet(png, img if dom is None else np.where(dom[..., None], img, 0.8).astype(np.float32),
                    res.structure, synthesize_structure(model, rng=seed + 1, domain=dom).structure)
    return f


def main(argv=None) -> None:
    seeds, kinds, pngdir = check_args(argv, KINDS, (0, 1, 2))
    keys = ("bk_ex", "bk_out", "bk", "ahd", "med_ex", "med_out", "dmean", "aerr", "rout", "lout", "out", "ml", "len", "turn")
    print_table(kinds, seeds, size_of, case, keys,
                lambda r: f"nb {r['nb_ex']:3d}->{r['nb_out']:3d}", pngdir, width=6)


if __name__ == "__main__":
    main()
