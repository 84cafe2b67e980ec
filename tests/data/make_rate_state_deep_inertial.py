"""Generate tests/data/rate_state_deep_inertial.json: mpmath references for deep stick-slip cycles with mass.

    PYTHONPATH=. python tests/data/make_rate_state_deep_inertial.py            # all cases, one after another
    PYTHONPATH=. python tests/data/make_rate_state_deep_inertial.py 0 3 6     # some cases (parts merged)

Sliders with mass M > 0 (a = 0.01, Dc = 1, V_lp = 1; η ≥ 0), three or more per state law: aging and
PRZ cycles (b = 0.025) whose ln(V/V_lp) spans 45–58; slip-law cycles (b = 0.035–0.05, M = 1e-4–1e-2:
at b = 0.025 they span only 26–33, inertia capping the top) spanning 41–63, their minimum set by the
inertial plunge after each slip (slow_manifold.py, "Fast time"). For each case the engine (``slow_manifold.deep_cycle_point``: the
event-split integrator, Newton on its return map) gives only the *start*: its section point
(θ_i, dV/dt) on V = V_lp. From there ``reference_inertial.reference_inertial_cycle`` (mpmath, 40
digits, Taylor order 24, step tolerance 1e-28; variables τ, V, θ; no heyoka; the slow phase by
fixed-point iteration of its Taylor coefficients, switched at |ε| = 1e-5, ten times deeper than the
engine's 1e-4) runs one turn: the reference. One turn, not two: the start's 1e-16 (the engine's fixed
point) moves the period by about that, far below the 1e-10 that is checked; ``fixed_point_residual``
(|Δ ln θ| over the turn) shows how far the start is from the mpmath cycle. With ``--variants`` the cases
given are also run with the switch at 1e-4 and at order 30 / tolerance 1e-32 (``variants``); ``--echo``
prints the reference's progress.
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
# (state law, η, κ = k/k_c with mass and damping, M[, b]); b is BASE's where not given
CASES = [("aging", 1e-8, 0.1, 1e-6), ("aging", 0.0, 0.1, 1e-6), ("aging", 0.0, 0.03, 1e-6),
         ("prz", 1e-8, 0.1, 1e-6), ("prz", 0.0, 0.1, 1e-6), ("prz", 1e-8, 0.03, 1e-6),
         ("slip", 0.0, 0.03, 1e-4, 0.05), ("slip", 1e-8, 0.03, 1e-4, 0.05), ("slip", 0.0, 0.01, 1e-2, 0.05),
         ("slip", 0.0, 0.01, 1e-4, 0.035), ("slip", 1e-8, 0.01, 1e-4, 0.05)]
REF = {"dps": 40, "order": 24, "tol_digits": 28, "switch": 1e-5, "extra": 30}
# Per case: at M = 1e-2 the switch up at 1e-5 comes at ln V ≈ −8, 400 time units before the slip, and
# the inertial phase's steps are limited by the fast rate a/(M V) there (~400 steps per time unit): 1e-3
# (the engine's is 1e-4) keeps it to the slip.
REF_CASE = {8: {"switch": 1e-3}}
OUT = HERE / "rate_state_deep_inertial.json"


def spec_of(law, eta, kappa, mass, b=BASE["b"]):
    h = hopf_point(a=BASE["a"], b=b, dc=BASE["dc"], state_law=law, v_lp=BASE["v_lp"], mass=mass,
                   damping=eta, dps=30, lyapunov=False)
    spec = SliderSpec(a=BASE["a"], b=b, dc=BASE["dc"], state_law=law, k=kappa * h.k_c, damping=eta,
                      mass=mass)
    return spec, 2 * math.pi / h.omega_c


def run_case(index: int) -> dict:
    law, eta, kappa, mass, *rest = CASES[index]
    t0 = time.time()
    spec, period0 = spec_of(law, eta, kappa, mass, *rest)
    c, phase, w = deep_cycle_point(spec, BASE["v_lp"], period0)
    if c.status != "limit-cycle" or phase != "inertial":
        raise SystemExit(f"case {index}: the engine gave {c.status} ({c.message}), section phase {phase}")
    start = [mp.exp(mp.mpf(v)) for v in w[:-1]] + [mp.mpf(w[-1]) / mp.mpf(mass)]

    def reference(**kw):
        with mp.workdps(REF["dps"]):
            opts = dict(REF)
            opts.update(REF_CASE.get(index, {}))
            opts.update(kw)
            r = reference_inertial_cycle(spec, BASE["v_lp"], start, turns=1, echo=ECHO, **opts)["turns"][0]
            return r, mp.nstr(abs(mp.log(r["theta"][0] / start[0])), 3)

    r, residual = reference()
    entry = {"state_law": law, "damping": eta, "kappa": kappa, "mass": mass, **({"b": rest[0]} if rest else {}), "k": spec.k,
             "start_section": [repr(float(v)) for v in w],
             "period": mp.nstr(r["period"], 30), "ln_v_max": mp.nstr(r["ln_v_max"], 30),
             "ln_v_min": mp.nstr(r["ln_v_min"], 30), "steps_inertial_slow": list(r["steps"]),
             "iterations_max": r["iterations"], "fixed_point_residual": residual,
             "engine_period": repr(c.period), "engine_period_error": repr(c.period_error),
             **({"reference": REF_CASE[index]} if index in REF_CASE else {})}
    if VARIANTS:
        entry["variants"] = {}
        for name, kw in (("switch 1e-4", {"switch": 1e-4}), ("order 30, tol 1e-32", {"order": 30, "tol_digits": 32})):
            rv, _ = reference(**kw)
            entry["variants"][name] = mp.nstr(rv["period"], 30)
    print(index, law, eta, kappa, mass, entry["period"], entry["ln_v_min"], entry["ln_v_max"],
          f"{time.time() - t0:.0f} s", flush=True)
    return entry


VARIANTS = False
ECHO = None


def main() -> None:
    global VARIANTS
    args = sys.argv[1:]
    global ECHO
    VARIANTS = "--variants" in args
    ECHO = (lambda s: print(s, flush=True)) if "--echo" in args else None
    wanted = [int(a) for a in args if not a.startswith("--")] or list(range(len(CASES)))
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
