"""Regenerate tests/data/rscycle_sweep.json: slowly attracting cycles next to Hopf points (largest Floquet
multiplier 0.95–0.9999), aging and slip laws, with and without mass and radiation damping, by the mpmath
reference tests/_rscycle_rate_state.py (own Taylor recurrences, 45 digits, Newton shooting on V_max).

    python tests/data/make_rscycle_sweep.py            # 9 min of CPU (541 s summed over the 37 cases)
    python tests/data/make_rscycle_sweep.py --first 23 --last 24   # some cases only: json lines on stdout

(the committed json was assembled from such parts, run side by side, in case order: the same code, so
the same numbers but the cpu_seconds.) The targets are those of the linearisation: two aging cases with
mass came out subcritical (no small cycle; the reference's Newton falls onto steady sliding, stored as
"not converged") and four reach a cycle beyond a fold whose multiplier is 0.81–0.94.

Parameters from default_rng(SEED), 6 per law (slip, aging) and loading (massless damped, mass undamped,
mass damped; the massless undamped slider has no small cycle below k_c: its Hopf point is degenerate and V
grows without bound, docs/rate-state.md): a ∈ [0.005, 0.015], b/a ∈ [1.3, 2.5],
Dc ∈ [1e-3, 1e-1] and V_lp ∈ [0.1, 10] log-uniform; with mass, M V_lp²/(a Dc) ∈ [1e-2, 0.1] (aging:
below its Bautin point 0.138 at a 0.01, b 0.015 of docs/rate-state.md, hoped supercritical) or [1e-2, 10] (slip: supercritical with mass)
log-uniform;
with damping ηV_lp ∈ [0.1, 0.4](b − a); a target multiplier ρ with 1 − ρ ∈ [1e-4, 5e-2] log-uniform, and k
where the reference's own linearisation at steady sliding (eigenvalue σ ± iω) gives exp(−4πσ/ω) = ρ (the
multiplier of the amplitude of a small cycle: twice the growth rate over a period; bisection in k/k_c).

The reference's Newton needs a start near the cycle: the engine's section point (`attractor.fate`,
ln θ and M V̇ at V = V_lp) where it has one, else steady sliding with ln V raised by 0.3; whatever the
start, what it converges to is the reference's own fixed point (closure < 1e-35 required; stored).
Case 0 is the miss of tests/data/indep3_rate_state.json (case 4). Values stored as 25-digit strings.
"""

from __future__ import annotations

import argparse
import json
import math
import pathlib
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

SEED = 20261127
PER_GROUP = 6


def draw(n_per=PER_GROUP):
    import _rscycle_rate_state as ref
    from mpmath import mp, mpf

    rng = np.random.default_rng(SEED)
    out = []
    for law in ("slip", "aging"):
        for inertial, damped in ((False, True), (True, False), (True, True)):
                for _ in range(n_per):
                    a = round(float(rng.uniform(0.005, 0.015)), 4)
                    b = round(a * float(rng.uniform(1.3, 2.5)), 4)
                    dc = float(f"{10 ** rng.uniform(-3, -1):.3g}")
                    v = float(f"{10 ** rng.uniform(-1, 1):.3g}")
                    top = 0.1 if law == "aging" else 10.0
                    m = float(f"{10 ** rng.uniform(-2, math.log10(top)) * a * dc / v ** 2:.3g}") if inertial else 0.0
                    eta = float(f"{(b - a) / v * rng.uniform(0.1, 0.4):.3g}") if damped else 0.0
                    one_minus = 10 ** rng.uniform(-4, math.log10(5e-2))
                    with mp.workdps(25):
                        def mult(kappa, kc):
                            lam = ref.eigs(law, a, b, dc, kappa * kc, v, m, eta)[0]
                            return mp.exp(-4 * mp.pi * mp.re(lam) / abs(mp.im(lam)))
                        a2 = a + eta * v
                        kc = (b - a2) / dc * (1 + m * v * v / (a2 * dc))     # docs/rate-state.md (closed form)
                        lo, hi = mpf("0.3"), mpf(1) - mpf(10) ** -9
                        target = 1 - one_minus
                        for _ in range(60):
                            mid = (lo + hi) / 2
                            if mult(mid, kc) < target:
                                lo = mid
                            else:
                                hi = mid
                        k = float(f"{float(lo) * kc:.6g}")
                    out.append(dict(law=law, a=a, b=b, dc=dc, k=k, v_lp=v, mass=m, damping=eta,
                                    linear_multiplier=float(target), kappa=float(lo)))
    return out


def engine_start(c):
    """(V, θ[, F]) on the engine's section at its cycle, or None."""
    from bifurcation.models.rate_state.attractor import fate
    from bifurcation.models.rate_state.hopf import hopf_point
    from bifurcation.models.rate_state.spec import SliderSpec

    spec = SliderSpec(a=c["a"], b=(c["b"],), dc=(c["dc"],), state_law=(c["law"],), k=c["k"],
                      mass=c["mass"] or None, damping=c["damping"])
    h = hopf_point(a=spec.a, b=spec.b, dc=spec.dc, state_law=spec.state_law, v_lp=c["v_lp"], mass=spec.mass,
                   damping=spec.damping, dps=30, lyapunov=False)
    f = fate(spec, c["v_lp"], 2 * math.pi / h.omega_c, max_steps=2_000_000, t_max=math.inf)
    if f.kind != "cycle":
        return None
    return [c["v_lp"], math.exp(f.w[0])] + ([f.w[1]] if c["mass"] else [])


#: The miss that started this (tests/data/indep3_rate_state.json, case 4): slip law, k = 0.96 k_c, mass and
#: damping, multiplier 0.9977; `rate-state --cycle` answered not-resolved before the slow-approach path.
MISS = dict(law="slip", a=0.0094, b=0.0218, dc=0.0136, k=33.0, v_lp=8.96, mass=0.000131, damping=0.000477,
            linear_multiplier=None, kappa=None)


def main():
    import _rscycle_rate_state as ref
    from mpmath import mp, nstr

    ap = argparse.ArgumentParser()
    ap.add_argument("--first", type=int, default=0, help="only cases from this index on (json lines on stdout)")
    ap.add_argument("--last", type=int, default=None, help="only cases up to this index")
    args = ap.parse_args()
    every = [dict(MISS)] + draw()
    part = args.first != 0 or args.last is not None
    cases = []
    for c in every[args.first:None if args.last is None else args.last + 1]:
        t0 = time.process_time()
        start = engine_start(c)
        c["start"] = "engine" if start is not None else "steady+0.3"
        if start is None:
            th = c["dc"] / c["v_lp"]
            start = [c["v_lp"] * math.exp(0.3), th] + ([0.0] if c["mass"] else [])
        try:
            r = ref.cycle(c["law"], c["a"], c["b"], c["dc"], c["k"], c["v_lp"], c["mass"], c["damping"], start)
            with mp.workdps(45):
                ok = r["converged"] and r["closure"] < mp.mpf(10) ** -35 and r["multiplier_max"] < 1
                c.update({key: nstr(r[key], 25) for key in ("period", "ln_v_max", "ln_v_min", "closure",
                                                             "multiplier_max")})
            c["reference"] = "ok" if ok else "not converged"
        except (RuntimeError, ZeroDivisionError) as exc:
            c["reference"] = f"failed: {exc}"
        c["cpu_seconds"] = round(time.process_time() - t0, 1)
        print(json.dumps(c), flush=True)
        cases.append(c)
    if part:
        return
    write(cases)


def write(cases):
    doc = {"provenance": "tests/data/make_rscycle_sweep.py (reference tests/_rscycle_rate_state.py: own mpmath "
                         "Taylor integrators at 45 digits, Newton shooting); sample default_rng(%d)" % SEED,
           "digits": 25, "cases": cases}
    (HERE / "rscycle_sweep.json").write_text(json.dumps(doc, indent=1) + "\n")


if __name__ == "__main__":
    main()
