"""Generate tests/data/chain_sigma_golden.json: catalogs of small chains with a friction drop σ > 0 from the
independent mpmath reference (issue 17).

Run once (a few minutes on one core):

    PYTHONPATH=. python tests/chain_sigma_golden_gen.py

For each case: the initial displacements (the engine's seeded random start, as exact float reprs) and the
reference catalog of ``bifurcation.models.chain.reference.reference_chain(..., sigma=σ)`` at 40 digits
(Taylor order 40; it shares no code with the engine: physical variables, the whole chain in one system,
g_σ = σ + (1 − σ) g(V/((1 − σ) ν_f)) by series arithmetic). ``tests/test_chain_sigma.py`` compares the
engine with it.
"""

from __future__ import annotations

import json
import sys
import time
from pathlib import Path

import mpmath

from bifurcation.models.chain import chain
from bifurcation.models.chain.reference import reference_chain

EVENTS = 20
DPS = 40
CASES = [
    # law, n, ends, ell, nu, nu_f, amplitude, seed, sigma
    ("carlson-langer", 4, "free", 1.0, 1e-2, 0.3, 0.5, 3, 0.01),
    ("carlson-langer", 5, "periodic", 1.0, 1e-4, 0.3, 0.5, 3, 0.05),
    ("carlson-langer", 8, "free", 1.0, 1e-6, 0.2, 0.5, 3, 0.01),
    ("piecewise-linear", 4, "free", 1.0, 1e-4, 0.3, 0.5, 3, 0.05),
    ("piecewise-linear", 5, "periodic", 1.0, 1e-2, 0.3, 0.5, 3, 0.01),
    ("piecewise-linear", 8, "periodic", 1.0, 1e-4, 0.3, 0.5, 3, 0.05),
    ("exponential", 3, "free", 1.0, 1e-3, 0.3, 0.5, 3, 0.01),
]


def main() -> None:
    out = Path(__file__).parent / "data" / "chain_sigma_golden.json"
    cases = []
    for law, n, ends, ell, nu, nu_f, amp, seed, sigma in CASES:
        t0 = time.time()
        base = chain(law, n=n, ell=ell, nu=nu, nu_f=nu_f, ends=ends, amplitude=amp, seed=seed, events=1)
        u0 = base.u0
        ref = reference_chain(law, n=n, ell=ell, nu=nu, nu_f=nu_f, u0=u0, ends=ends, events=EVENTS,
                              dps=DPS, order=DPS, sigma=sigma)
        cases.append({
            "law": law, "n": n, "ends": ends, "ell": ell, "nu": nu, "nu_f": nu_f, "sigma": sigma,
            "u0": [repr(float(x)) for x in u0],
            "t_start": [mpmath.nstr(x, 36) for x in ref["t_start"]],
            "hypocentre": ref["hypocentre"], "n_blocks": ref["n_blocks"],
            "potency": [mpmath.nstr(x, 36) for x in ref["potency"]],
            "duration": [mpmath.nstr(x, 36) for x in ref["duration"]],
            "max_velocity": [mpmath.nstr(x, 36) for x in ref["max_velocity"]],
        })
        print(f"{law} n={n} {ends} nu={nu} sigma={sigma}: {time.time() - t0:.0f} s, sizes {ref['n_blocks']}",
              flush=True)
    doc = {"generator": "tests/chain_sigma_golden_gen.py", "reference": f"reference_chain(dps={DPS}, order={DPS})",
           "events": EVENTS, "cases": cases}
    out.write_text(json.dumps(doc, indent=1) + "\n")
    print("wrote", out, file=sys.stderr)


if __name__ == "__main__":
    main()
