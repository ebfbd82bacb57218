"""Bit-identity gate of structure synthesis for speed work (issue 23, branching40).

``python -m branchnb.branching._speed_gate_check OUT.pkl [KINDS] [SIZES] [N_SEEDS] [CACHE]`` synthesizes, with
the defaults, every kind (default: mud, river, retina, lightning, lineart = drawn cracks, czech = a map,
delta) at every size (default 250, 512, 1000) for seeds 0 .. N_SEEDS - 1 (default 3): 63 structures. It
prints each one's SHA-1 (points, radii, parents of every branch) and CPU seconds and pickles them to
OUT.pkl. ``python -m branchnb.branching._speed_gate_check --compare A.pkl B.pkl`` says whether two runs
(e.g. main and a branch, with ``PYTHONPATH`` pointing at each) are equal and lists the CPU times side by
side. The fitted examples are read from CACHE (see :func:`._seed_check.fitted_example`), so both runs
synthesize from the very same models.
"""

from __future__ import annotations

import hashlib
import pickle
import sys
import time

import numpy as np

KINDS = ("mud", "river", "retina", "lightning", "lineart", "czech", "delta")


def structure_hash(s) -> str:
    """SHA-1 of a structure's branches: points and radii (float64 bytes), parent and parent vertex."""
    h = hashlib.sha1()
    for b in s.branches:
        h.update(np.ascontiguousarray(b.points, np.float64).tobytes())
        h.update(np.ascontiguousarray(b.thickness, np.float64).tobytes())
        h.update(repr((b.parent, b.parent_vertex)).encode())
    return h.hexdigest()


def run(out: str, kinds=KINDS, sizes=(250, 512, 1000), n_seeds: int = 3, cache: str | None = None) -> dict:
    from branchnb.branching import synthesize_structure
    from branchnb.branching._seed_check import fitted_example

    res = {}
    for kind in kinds:
        for size in sizes:
            _img, _dom, model = fitted_example(kind, size, cache)
            synthesize_structure(model, None, rng=99)   # compile (numba) and fill the model's caches
            for seed in range(n_seeds):
                t0 = time.process_time()
                r = synthesize_structure(model, None, rng=seed)
                t = time.process_time() - t0
                hx = structure_hash(r.structure)
                res[(kind, size, seed)] = (hx, t, len(r.structure.branches))
                print(f"{kind:9s} {size:4d} {seed}  cpu {t:6.2f}  branches {len(r.structure.branches):5d}  {hx[:12]}",
                      flush=True)
    with open(out, "wb") as f:
        pickle.dump(res, f)
    return res


def compare(a: str, b: str) -> bool:
    with open(a, "rb") as f:
        A = pickle.load(f)
    with open(b, "rb") as f:
        B = pickle.load(f)
    keys = [k for k in A if k in B]
    same = [A[k][0] == B[k][0] for k in keys]
    by_kind: dict = {}
    for k in keys:
        by_kind.setdefault(k[:2], []).append((A[k][1], B[k][1], A[k][0] == B[k][0]))
    for (kind, size), v in by_kind.items():
        ta, tb, eq = np.array(v, dtype=object).T
        print(f"{kind:9s} {size:4d}  cpu {' '.join(f'{t:.2f}' for t in ta)} -> {' '.join(f'{t:.2f}' for t in tb)}"
              f"  {'equal' if all(eq) else 'DIFFERENT'}")
    print(f"{sum(same)}/{len(keys)} structures equal" + ("" if all(same) and keys else "  -- NOT EQUAL"))
    return bool(keys) and all(same)


if __name__ == "__main__":
    argv = sys.argv[1:]
    if argv and argv[0] == "--compare":
        sys.exit(0 if compare(argv[1], argv[2]) else 1)
    kinds = argv[1].split(",") if len(argv) > 1 and argv[1] != "all" else KINDS
    sizes = [int(v) for v in argv[2].split(",")] if len(argv) > 2 else (250, 512, 1000)
    n = int(argv[3]) if len(argv) > 3 else 3
    cache = argv[4] if len(argv) > 4 else None
    run(argv[0], kinds, sizes, n, cache)
