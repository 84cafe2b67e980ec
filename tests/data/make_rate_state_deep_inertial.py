"""Generate tests/data/rate_state_deep_inertial.json: mpmath references for deep stick-slip cycles with mass.

    PYTHONPATH=. python tests/data/make_rate_state_deep_inertial.py            # all cases, one after another
    PYTHONPATH=. python tests/data/make_rate_state_deep_inertial.py 0 3 6     # some cases (parts merged)

Sliders with mass M > 0 (a = 0.01, b = 0.025, Dc = 1, V_lp = 1; η ≥ 0), three per state law: aging and
PRZ cycles whose ln(V/V_lp) spans 45–58; slip-law cycles with mass span only 26–33 here (inertia caps
the top, and the slip law's lows stay shallow). For each case the engine (``slow_manifold.deep_cycle_point``: the
event-split integrator, Newton on its return map) gives only the *start*: its section point
(θ_i, dV/dt) on V = V_lp. From there ``reference_inertial.reference_inertial_cycle`` (mpmath, 40
digits, Taylor order 24, step tolerance 1e-28; variables τ, V, θ; no heyoka; the slow phase by
fixed-point iteration of its Taylor coefficients, switched at |ε| = 1e-5, ten times deeper than the
engine's 1e-4) runs one turn: the reference. One turn, not two: the start's 1e-16 (the engine's fixed
point) moves the period by about that, far below the 1e-10 that is checked; ``fixed_point_residual``
(|Δ ln θ| over the turn) shows how far the start is from the mpmath cycle. With ``--variants`` case 0 is also
run with the switch at 1e-4 and at order 30 / tolerance 1e-32 (``variants``).
Values are 30-digit strings. Minutes per case on one core.

The start is the engine's double-precision fixed point, whose last bits can differ on another CPU
(AVX2 vs AVX-512): that moves the reference's digits beyond ~1e-15 relative, far below what the tests
compare (1e-10), but a regenerated file may differ there.
"""

from __future__ import annotations

import json
import math
import pathlib
import sys
import time

import mpmath as mp

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from bifurcation.models.rate_state import SliderSpec  # noqa: E402
from bifurcation.models.rate_state.hopf import hopf_point  # noqa: E402
from bifurcation.models.rate_state.reference_inertial import reference_inertial_cycle  # noqa: E402
from bifurcation.models.rate_state.slow_manifold import deep_cycle_point  # noqa: E402

BASE = {"a": 0.01, "b": 0.025, "dc": 1.0, "v_lp": 1.0}
# (state law, η, κ = k/k_c with mass and damping, M)
CASES = [("aging", 1e-8, 0.1, 1e-6), ("aging", 0.0, 0.1, 1e-6), ("aging", 0.0, 0.03, 1e-6),
         ("prz", 1e-8, 0.1, 1e-6), ("prz", 0.0, 0.1, 1e-6), ("prz", 1e-8, 0.03, 1e-6),
         ("slip", 0.0, 0.01, 1e-6), ("slip", 0.0, 0.005, 1e-6), ("slip", 1e-15, 0.03, 1e-6)]
REF = {"dps": 40, "order": 24, "tol_digits": 28, "switch": 1e-5, "extra": 30}
OUT = HERE / "rate_state_deep_inertial.json"


def spec_of(law, eta, kappa, mass):
    h = hopf_point(a=BASE["a"], b=BASE["b"], dc=BASE["dc"], state_law=law, v_lp=BASE["v_lp"], mass=mass,
                   damping=eta, dps=30, lyapunov=False)
    spec = SliderSpec(a=BASE["a"], b=BASE["b"], dc=BASE["dc"], state_law=law, k=kappa * h.k_c, damping=eta,
                      mass=mass)
    return spec, 2 * math.pi / h.omega_c


def run_case(index: int) -> dict:
    law, eta, kappa, mass = CASES[index]
    t0 = time.time()
    spec, period0 = spec_of(law, eta, kappa, mass)
    c, phase, w = deep_cycle_point(spec, BASE["v_lp"], period0)
    if c.status != "limit-cycle" or phase != "inertial":
        raise SystemExit(f"case {index}: the engine gave {c.status} ({c.message}), section phase {phase}")
    start = [mp.exp(mp.mpf(v)) for v in w[:-1]] + [mp.mpf(w[-1]) / mp.mpf(mass)]

    def reference(**kw):
        with mp.workdps(REF["dps"]):
            opts = dict(REF)
            opts.update(kw)
            r = reference_inertial_cycle(spec, BASE["v_lp"], start, turns=1, **opts)["turns"][0]
            return r, mp.nstr(abs(mp.log(r["theta"][0] / start[0])), 3)

    r, residual = reference()
    entry = {"state_law": law, "damping": eta, "kappa": kappa, "mass": mass, "k": spec.k,
             "start_section": [repr(float(v)) for v in w],
             "period": mp.nstr(r["period"], 30), "ln_v_max": mp.nstr(r["ln_v_max"], 30),
             "ln_v_min": mp.nstr(r["ln_v_min"], 30), "steps_inertial_slow": list(r["steps"]),
             "iterations_max": r["iterations"], "fixed_point_residual": residual,
             "engine_period": repr(c.period), "engine_period_error": repr(c.period_error)}
    if index == 0 and VARIANTS:
        entry["variants"] = {}
        for name, kw in (("switch 1e-4", {"switch": 1e-4}), ("order 30, tol 1e-32", {"order": 30, "tol_digits": 32})):
            rv, _ = reference(**kw)
            entry["variants"][name] = mp.nstr(rv["period"], 30)
    print(index, law, eta, kappa, mass, entry["period"], entry["ln_v_min"], entry["ln_v_max"],
          f"{time.time() - t0:.0f} s", flush=True)
    return entry


VARIANTS = False


def main() -> None:
    global VARIANTS
    args = sys.argv[1:]
    VARIANTS = "--variants" in args
    wanted = [int(a) for a in args if a != "--variants"] or list(range(len(CASES)))
    old = json.loads(OUT.read_text()) if OUT.exists() else {}
    cases = {int(k): v for k, v in old.get("cases", {}).items()}
    for i in wanted:
        cases[i] = run_case(i)
        # merge with what is on disk now (another process may have written other cases meanwhile)
        now = json.loads(OUT.read_text()) if OUT.exists() else {}
        merged = {int(k): v for k, v in now.get("cases", {}).items()}
        merged[i] = cases[i]
        OUT.write_text(json.dumps({"generator": "tests/data/make_rate_state_deep_inertial.py", "base": BASE,
                                   "reference": REF, "cases": {str(k): merged[k] for k in sorted(merged)}},
                                  indent=1) + "\n")


if __name__ == "__main__":
    main()
