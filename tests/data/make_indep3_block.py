"""Regenerate tests/data/indep3_block.json: the single block at the corners of its documented domain
and at a seeded random sample of it, by the mpmath reference tests/_indep3_block.py (45 digits,
order-32 Taylor steps, events bisected to working precision).

    python tests/data/make_indep3_block.py [--jobs 2]      # ~10 min on one core

Domain (bifurcation/bounds.py, what slip/limit/workflows accept): ν ∈ [1e-20, 1], ν_f ∈ [1e-4, 10].
Each value is stored as a 30-digit string; a second run at 55 digits and order 40 (``--check``) agrees
with the first to the digits given in the json's "agreement" field.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys
import time
from concurrent.futures import ProcessPoolExecutor

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

LAWS = ["carlson-langer", "piecewise-linear", "exponential", "1/(1+x+x^2)"]
# corners a referee tries first: the bounds of ν and ν_f, the ends of the paper's (0, 1) for ν_f
CORNERS = [
    ("carlson-langer", 1.0, 0.3), ("piecewise-linear", 1.0, 0.3), ("exponential", 1.0, 0.02),
    ("carlson-langer", 0.7, 0.98), ("piecewise-linear", 0.5, 0.98), ("exponential", 1e-3, 0.98),
    ("carlson-langer", 1e-12, 0.02), ("piecewise-linear", 1e-9, 0.02), ("1/(1+x+x^2)", 1e-6, 0.02),
    ("carlson-langer", 1e-20, 0.3), ("piecewise-linear", 1e-20, 0.49), ("exponential", 1e-18, 0.25),
    ("carlson-langer", 1e-4, 10.0), ("piecewise-linear", 1e-2, 2.0), ("exponential", 0.3, 10.0),
    ("carlson-langer", 1e-3, 1e-4), ("piecewise-linear", 1e-6, 1e-4), ("1/(1+x+x^2)", 1e-2, 1e-3),
    ("piecewise-linear", 1.0, 0.6), ("piecewise-linear", 0.9, 0.9),
    ("exponential", 1e-6, 1e-4), ("exponential", 1e-3, 3e-4), ("exponential", 1e-12, 1e-3),
]
SEED = 20261126


def sample(n=16):
    """ν log-uniform in [1e-20, 1], ν_f log-uniform in [1e-4, 10], laws in turn (default_rng(SEED))."""
    rng = np.random.default_rng(SEED)
    out = []
    for i in range(n):
        nu = float(f"{10 ** rng.uniform(-20, 0):.3g}")
        nuf = float(f"{10 ** rng.uniform(-4, 1):.3g}")
        out.append((LAWS[i % 4], nu, nuf))
    return out


def _one(args):
    import _indep3_block as ref
    from mpmath import mp, nstr
    law, nu, nuf, dps, order = args
    t0 = time.process_time()
    try:
        r = ref.cycle(law, nu, nuf, dps=dps, order=order)
    except RuntimeError as e:
        return {"law": law, "nu": nu, "nu_f": nuf, "error": str(e)}
    with mp.workdps(dps):
        out = {k: (None if r[k] is None else nstr(r[k], 30, min_fixed=1, max_fixed=0))
               for k in ("delta", "stop_time", "creep_time", "max_velocity")}
    out.update(law=law, nu=nu, nu_f=nuf, steps=r["steps"], crossings=r["crossings"],
               cpu_seconds=round(time.process_time() - t0, 1))
    return out


def main():
    ap = argparse.ArgumentParser()
    ap.add_argument("--jobs", type=int, default=1)
    ap.add_argument("--check", action="store_true", help="also run at 55 digits, order 40, and compare")
    ap.add_argument("--only", type=int, nargs="*", help="indices of points to run (debug)")
    a = ap.parse_args()
    pts = CORNERS + sample()
    if a.only:
        pts = [pts[i] for i in a.only]
    with ProcessPoolExecutor(a.jobs) as ex:
        res = list(ex.map(_one, [(l, n, f, 45, 32) for l, n, f in pts]))
        agreement = None
        if a.check:
            from mpmath import mpf
            chk = list(ex.map(_one, [(l, n, f, 55, 40) for l, n, f in pts]))
            agreement = 0.0
            for r, c in zip(res, chk):
                for k in ("delta", "stop_time", "creep_time", "max_velocity"):
                    if r.get(k) is not None and c.get(k) is not None:
                        agreement = max(agreement, float(abs(mpf(r[k]) - mpf(c[k])) / abs(mpf(c[k]))))
    doc = {"provenance": "tests/data/make_indep3_block.py (reference tests/_indep3_block.py: own mpmath Taylor "
                         "integrator, 45 digits, order 32); sample numpy default_rng(%d)" % SEED,
           "digits": 30, "agreement_45_vs_55_digits": agreement, "points": res}
    if not a.only:
        (HERE / "indep3_block.json").write_text(json.dumps(doc, indent=1) + "\n")
    print(json.dumps(doc, indent=1))


if __name__ == "__main__":
    main()
