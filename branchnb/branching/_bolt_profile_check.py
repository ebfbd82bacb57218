"""Cross-profile of synthesized lightning bolts against the example's (issue 23).

``python -m branchnb.branching._bolt_profile_check [key=value ...]`` synthesizes the NOAA storm photo
and three procedural storms (2 seeds each) and prints, for example and output, the luminance profile
across the bolts (core half-width, glow width where the excess falls to 10 %, core brightness), the
correlation of the normalised profiles and the share of bolt pixels saturated white. Extra
``key=value`` arguments go to :class:`~branchnb.branching.image_synthesis.ImageSynthesisParams`.
"""

from __future__ import annotations

import os
import pickle
import sys

import numpy as np

D_MAX = 14


def bolt_profile(image: np.ndarray, pm) -> dict:
    """Median luminance at integer distances 0..D_MAX from the centre lines of ``pm``, and its measures."""
    lum = np.asarray(image, np.float64)[..., :3].mean(axis=2)
    d = np.round(pm.dist).astype(int)
    prof = np.array([np.median(lum[d == k]) if (d == k).any() else np.nan for k in range(D_MAX + 1)])
    exc = prof - prof[-3:].mean()
    e0 = max(exc[0], 1e-6)
    n = exc / e0

    def width(level):
        below = np.nonzero(n < level)[0]
        if len(below) == 0:
            return float(D_MAX)
        k = below[0]
        if k == 0:
            return 0.0
        return float(k - 1 + (n[k - 1] - level) / max(n[k - 1] - n[k], 1e-9))

    body = pm.dist <= np.maximum(pm.radius, 1.5)
    sat = float(np.mean(np.asarray(image)[..., :3][body].min(axis=1) > 0.97)) if body.any() else 0.0
    core, glow = width(0.5), width(0.1)
    return {"profile": n, "core": core, "glow": glow, "ratio": core / max(glow, 1e-6),
            "peak": float(prof[0]), "sat": sat}


def cases():
    """(name, image) pairs: NOAA photo at 512 px and procedural storms."""
    import cv2

    from ._storm_examples import storm_example

    out = []
    path = "/work/shared/data/photos/branching/lightning_noaa.jpg"
    if os.path.exists(path):
        bgr = cv2.imread(path, cv2.IMREAD_COLOR)
        s = 512 / max(bgr.shape[:2])
        if s < 1:
            bgr = cv2.resize(bgr, None, fx=s, fy=s, interpolation=cv2.INTER_AREA)
        out.append(("noaa", cv2.cvtColor(bgr, cv2.COLOR_BGR2RGB).astype(np.float32) / 255))
    for kind, kw in (("full", {}), ("nocloud", {"cloud": False}), ("two", {"n_bolts": 2})):
        for seed in (0, 1):
            out.append((f"{kind}{seed}", storm_example(seed=seed, **kw)[0]))
    return out


def main(args: list[str]) -> None:
    import cv2

    from . import example_domain
    from .extraction import extract_structure
    from .image_synthesis import ImageSynthesisParams, synthesize_image
    from .model import fit_model
    from .skeleton_map import SkeletonMap
    from .synthesis import synthesize_structure

    kw = {}
    tag = "run"
    for a in args:
        k, v = a.split("=")
        if k == "tag":
            tag = v
            continue
        kw[k] = {"True": True, "False": False}.get(v, None)
        if kw[k] is None:
            kw[k] = float(v) if "." in v else int(v)
    p = ImageSynthesisParams(**kw)
    rows = []
    only = os.environ.get("BOLT_CASES")
    for name, img in cases():
        if only and name not in only.split(","):
            continue
        cache = f"/tmp/bolt_profile_{name}.pkl"
        if os.path.exists(cache):
            with open(cache, "rb") as f:
                ex, res = pickle.load(f)
        else:
            ex = extract_structure(img)
            res = synthesize_structure(fit_model(ex, domain=example_domain(img, ex)), rng=0)
            with open(cache, "wb") as f:
                pickle.dump((ex, res), f)
        out = synthesize_image(img, ex, res, params=p, rng=0).image
        pe = bolt_profile(img, SkeletonMap(ex, 1.0).pixel_map(img.shape[:2]))
        po = bolt_profile(out, SkeletonMap(res.structure, 1.0).pixel_map(out.shape[:2]))
        corr = float(np.corrcoef(pe["profile"], po["profile"])[0, 1])
        rows.append((pe["ratio"], po["ratio"], pe["peak"], po["peak"], corr, pe["sat"], po["sat"]))
        print(f"{name:9s} core/glow ex {pe['core']:.1f}/{pe['glow']:.1f}={pe['ratio']:.2f} "
              f"out {po['core']:.1f}/{po['glow']:.1f}={po['ratio']:.2f}  peak ex {pe['peak']:.2f} "
              f"out {po['peak']:.2f}  corr {corr:.3f}  sat ex {pe['sat']:.2f} out {po['sat']:.2f}", flush=True)
        os.makedirs("/tmp/branching36", exist_ok=True)
        o = (np.clip(out, 0, 1) * 255).astype(np.uint8)
        e = (np.clip(img, 0, 1) * 255).astype(np.uint8)
        if o.shape != e.shape:
            o = cv2.resize(o, (e.shape[1], e.shape[0]))
        cv2.imwrite(f"/tmp/branching36/{tag}_{name}.png", np.hstack([e, o])[..., ::-1])
    a = np.array(rows)
    rr = a[:, 1] / a[:, 0]
    print(f"mean: ratio out/ex {rr.mean():.2f} (min {rr.min():.2f}, max {rr.max():.2f})  peak ex {a[:, 2].mean():.2f}"
          f" out {a[:, 3].mean():.2f}  corr {a[:, 4].mean():.3f} (min {a[:, 4].min():.3f})  "
          f"sat ex {a[:, 5].mean():.3f} out {a[:, 6].mean():.3f}")


if __name__ == "__main__":
    main(sys.argv[1:])
