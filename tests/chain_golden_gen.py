"""Generate tests/data/chain_golden.json: catalogs of small chains from the independent mpmath reference.

Run once (about 10–20 minutes on one core):

    PYTHONPATH=. python tests/chain_golden_gen.py

For each case: the initial displacements (the engine's seeded random start, written out as exact
float reprs), the reference catalog of ``bifurcation.models.chain.reference.reference_chain`` at
36 digits (Taylor order 36; it shares no code with the engine), and the sensitivity of each event to
a 1-ulp change of one initial displacement, measured with the engine in quad precision (how much any
double-precision code must be allowed to differ; the chains are chaotic).
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import mpmath
import numpy as np

from bifurcation.models.chain import chain
from bifurcation.models.chain.reference import reference_chain

EVENTS = 24
CASES = [
    # law, n, ends, ell, nu, nu_f, amplitude, seed
    ("carlson-langer", 4, "free", 1.0, 1e-2, 0.3, 0.1, 3),
    ("carlson-langer", 5, "periodic", 1.0, 1e-4, 0.3, 0.1, 3),
    ("carlson-langer", 8, "free", 1.0, 1e-6, 0.3, 0.1, 3),
    ("piecewise-linear", 4, "free", 1.0, 1e-6, 0.3, 0.1, 3),
    ("piecewise-linear", 5, "periodic", 1.0, 1e-2, 0.3, 0.1, 3),
    ("piecewise-linear", 8, "periodic", 1.0, 1e-4, 0.3, 0.1, 3),
]


def main() -> None:
    out = Path(__file__).parent / "data" / "chain_golden.json"
    cases = []
    for law, n, ends, ell, nu, nu_f, amp, seed in CASES:
        t0 = time.time()
        base = chain(law, n=n, ell=ell, nu=nu, nu_f=nu_f, ends=ends, amplitude=amp, seed=seed, events=1)
        u0 = base.u0
        ref = reference_chain(law, n=n, ell=ell, nu=nu, nu_f=nu_f, u0=u0, ends=ends, events=EVENTS)
        quad = chain(law, n=n, ell=ell, nu=nu, nu_f=nu_f, ends=ends, u0=u0, events=EVENTS, precision="quad")
        u1 = u0.copy()
        u1[1] = np.nextafter(u1[1], 1.0)
        pert = chain(law, n=n, ell=ell, nu=nu, nu_f=nu_f, ends=ends, u0=u1, events=EVENTS, precision="quad")
        sens = {k: [abs(float((b - a) / a)) for a, b in zip(quad[k], pert[k])] for k in ("t_start", "potency")}
        cases.append({
            "law": law, "n": n, "ends": ends, "ell": ell, "nu": nu, "nu_f": nu_f,
            "u0": [repr(float(x)) for x in u0],
            "t_start": [mpmath.nstr(x, 34) for x in ref["t_start"]],
            "hypocentre": ref["hypocentre"], "n_blocks": ref["n_blocks"],
            "potency": [mpmath.nstr(x, 34) for x in ref["potency"]],
            "duration": [mpmath.nstr(x, 34) for x in ref["duration"]],
            "max_velocity": [mpmath.nstr(x, 34) for x in ref["max_velocity"]],
            "ulp_sensitivity": sens,
        })
        print(f"{law} n={n} {ends} nu={nu}: {time.time() - t0:.0f} s, sizes {ref['n_blocks']}", flush=True)
    doc = {"generator": "tests/chain_golden_gen.py", "reference": "reference_chain(dps=36, order=36)",
           "events": EVENTS, "cases": cases}
    out.write_text(json.dumps(doc, indent=1) + "\n")
    print("wrote", out, file=sys.stderr)


if __name__ == "__main__":
    main()
