"""Regenerate tests/data/indep3_rate_state.json: attracting cycles of the slider with both mass and
radiation damping just past the Hopf point (k/k_c = 0.99) and at a seeded random sample, by the
mpmath reference tests/_indep3_rate_state.py (own Taylor recurrences in V, θ, F at 45 digits, order
30; Newton shooting on F = 0, closure < 1e-40; started from a scipy LSODA transient).

    python tests/data/make_indep3_rate_state.py        # ~5 min on one core
    python tests/data/make_indep3_rate_state.py --check   # also at 55 digits (slow): digits that agree

Values stored as 25-digit strings.
"""

from __future__ import annotations

import argparse
import json
import pathlib
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

SEED = 20261126
# a = 0.01, b = 0.015, Dc = 0.01, V_lp = 1, M = 1e-4, η = 0.002: k_c = 0.55 (closed form of
# docs/rate-state.md, "With radiation damping"), every law supercritical there (l1 < 0, `bifurcation hopf`)
NEAR_HOPF = [(law, 0.01, 0.015, 0.01, 0.5445, 1.0, 1e-4, 0.002) for law in ("slip", "aging", "prz")]


def sample(n=3):
    """law, a, b, Dc, k, V_lp, M, η drawn from default_rng(SEED): a ∈ [0.005, 0.015], b/a ∈ [1.3, 2.5],
    Dc ∈ [1e-3, 1e-1] and V_lp ∈ [0.1, 10] log-uniform, M ∈ [1e-6, 1e-3] log-uniform, ηV_lp ∈
    [0.1, 0.4](b − a), k/k_c ∈ [0.9, 0.99] (slip law: supercritical with mass for every η, docs/rate-state.md)."""
    rng = np.random.default_rng(SEED)
    out = []
    for _ in range(n):
        a = round(float(rng.uniform(0.005, 0.015)), 4)
        b = round(a * float(rng.uniform(1.3, 2.5)), 4)
        dc = float(f"{10 ** rng.uniform(-3, -1):.3g}")
        v = float(f"{10 ** rng.uniform(-1, 1):.3g}")
        m = float(f"{10 ** rng.uniform(-6, -3):.3g}")
        eta = float(f"{(b - a) / v * rng.uniform(0.1, 0.4):.3g}")
        a2 = a + eta * v
        kc = (b - a2) / dc * (1 + m * v * v / (a2 * dc))
        k = float(f"{kc * rng.uniform(0.9, 0.99):.4g}")
        out.append(("slip", a, b, dc, k, v, m, eta))
    return out


def main():
    import _indep3_rate_state as ref
    from mpmath import mp, nstr
    ap = argparse.ArgumentParser()
    ap.add_argument("--check", action="store_true")
    a = ap.parse_args()
    cases = []
    for case in NEAR_HOPF + sample():
        law, aa, b, dc, k, v, m, eta = case
        t0 = time.process_time()
        r = ref.cycle(law, aa, b, dc, k, v, m, eta, dps=45)
        with mp.workdps(45):
            d = dict(law=law, a=aa, b=b, dc=dc, k=k, v_lp=v, mass=m, damping=eta,
                     **{key: nstr(r[key], 25) for key in ("period", "ln_v_max", "ln_v_min", "closure")})
        if a.check:
            r2 = ref.cycle(law, aa, b, dc, k, v, m, eta, dps=55)
            with mp.workdps(55):
                d["agreement_45_vs_55"] = float(max(abs(r[q] - r2[q]) / abs(r2[q]) for q in ("period", "ln_v_max", "ln_v_min")))
        d["cpu_seconds"] = round(time.process_time() - t0, 1)
        print(json.dumps(d), flush=True)
        cases.append(d)
    doc = {"provenance": "tests/data/make_indep3_rate_state.py (reference tests/_indep3_rate_state.py: own mpmath "
                         "Taylor integrator in V, theta, F at 45 digits, Newton shooting); sample default_rng(%d)" % SEED,
           "digits": 25, "cases": cases}
    (HERE / "indep3_rate_state.json").write_text(json.dumps(doc, indent=1) + "\n")


if __name__ == "__main__":
    main()
