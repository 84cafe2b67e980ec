"""Regenerate tests/data/indep3_chain.json: stiff small chains (ℓ = 10, σ_f = 0.05, N = 2 and 3,
periodic and free) by the earlier helper's mpmath reference tests/_indep_chain.py (its own Taylor
integrator in U_j, V_j at 30 digits, order 24; no code of the package), at parameters no test used.

    python tests/data/make_indep3_chain.py     # ~3 min on one core

The start is u0 = 0.004 · default_rng(seed).random(N): at ℓ = 10 a block starts stuck only if its
neighbours' displacements differ by less than ~1/(2ℓ²) = 0.005. Values as 25-digit strings.
"""

from __future__ import annotations

import json
import pathlib
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

CASES = [
    dict(law="carlson-langer", n=2, ends="periodic", ell=10.0, nu=1e-3, nu_f=0.3, sigma=0.05, seed=21),
    dict(law="piecewise-linear", n=3, ends="periodic", ell=10.0, nu=1e-3, nu_f=0.2, sigma=0.05, seed=22),
    dict(law="exponential", n=2, ends="free", ell=10.0, nu=1e-2, nu_f=0.25, sigma=0.05, seed=23),
]
EVENTS = 5


def u0(case):
    return [float(x) for x in 0.004 * np.random.default_rng(case["seed"]).random(case["n"])]


def main():
    import _indep_chain as ref
    from mpmath import mp, nstr
    out = []
    for cs in CASES:
        t0 = time.process_time()
        cat = ref.chain_catalog(cs["law"], cs["n"], cs["ell"], cs["nu"], cs["nu_f"], u0(cs), EVENTS, ends=cs["ends"],
                                sigma=cs["sigma"], dps=30, order=24)
        with mp.workdps(30):
            events = [{k: (nstr(v, 25) if k not in ("hypocentre", "n_blocks") else int(v)) for k, v in e.items()
                       if k in ("t_start", "potency", "duration", "max_velocity", "hypocentre", "n_blocks")}
                      for e in cat]
        out.append(dict(cs, u0=u0(cs), events=events, cpu_seconds=round(time.process_time() - t0, 1)))
        print(json.dumps(out[-1]), flush=True)
    doc = {"provenance": "tests/data/make_indep3_chain.py (reference tests/_indep_chain.py at 30 digits, order 24)",
           "digits": 25, "cases": out}
    (HERE / "indep3_chain.json").write_text(json.dumps(doc, indent=1) + "\n")


if __name__ == "__main__":
    main()
