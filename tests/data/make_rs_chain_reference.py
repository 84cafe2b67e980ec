"""Writes tests/data/rs_chain_reference.json: the mpmath reference catalogs of the rate-and-state chain.

    python tests/data/make_rs_chain_reference.py        (a few minutes; 40 digits, order 30, tolerance 1e-34)

Each case starts from ``initial_state`` of the engine (its double values of ln V_j, ln θ_j, taken exactly
into mpmath) and records the first events of ``bifurcation.models.rs_chain.reference.reference_catalog``,
written as 30-digit decimal strings. The engine's catalogs are compared with them in tests/test_rs_chain.py.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import mpmath as mp

from bifurcation.models.rs_chain.reference import reference_catalog
from bifurcation.models.rs_chain.simulate import RSChainSpec, initial_state

CASES = {
    "n2-aging-free": dict(n=2, state_law="aging", ell=1.0, periodic=False, mass=0.0, events=8),
    "n3-slip-periodic": dict(n=3, state_law="slip", ell=2.0, periodic=True, mass=0.0, events=6),
    "n4-prz-free": dict(n=4, state_law="prz", ell=1.0, periodic=False, mass=0.0, events=6),
    "n2-aging-inertial": dict(n=2, state_law="aging", ell=1.0, periodic=False, mass=1e-5, events=5),
}
COMMON = dict(a=0.01, b=0.015, dc=0.01, k=0.1, v_lp=1.0, eta=1e-3, v_th=10.0)
AMPLITUDE, SEED = 1.0, 1


def main(names) -> None:
    out_path = Path(__file__).with_name("rs_chain_reference.json")
    for name in names:
        case = CASES[name]
        events = case["events"]
        spec = RSChainSpec(**{k: v for k, v in case.items() if k != "events"}, **COMMON)
        s0 = initial_state(spec, AMPLITUDE, SEED)
        t0 = time.time()
        ref = reference_catalog(n=spec.n, law=spec.state_law, a=spec.a, b=spec.b, dc=spec.dc, k=spec.k, ell=spec.ell,
                                v_lp=spec.v_lp, mass=spec.mass, eta=spec.eta, v_th=spec.v_th, periodic=spec.periodic,
                                x0=[float(v) for v in s0[:spec.n]], y0=[float(v) for v in s0[spec.n:2 * spec.n]],
                                events=events, dps=40, order=30, tol_digits=34)
        out = json.loads(out_path.read_text()) if out_path.exists() else {}   # other cases may run in parallel
        out[name] = {"case": {**case, **COMMON, "amplitude": AMPLITUDE, "seed": SEED},
                     "steps": ref["steps"], "seconds": round(time.time() - t0, 1),
                     **{f: [int(v) if isinstance(v, int) else mp.nstr(v, 30) for v in ref[f]]
                        for f in ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity")}}
        print(name, out[name]["steps"], "steps", out[name]["seconds"], "s", flush=True)
        out_path.write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main(sys.argv[1:] or list(CASES))
