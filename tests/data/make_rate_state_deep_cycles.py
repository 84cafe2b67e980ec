"""Generate tests/data/rate_state_deep_cycles.json: mpmath references for deep stick-slip cycles.

    PYTHONPATH=. python tests/data/make_rate_state_deep_cycles.py      # ~10 minutes on one core

Massless sliders with radiation damping (a = 0.01, b = 0.025, Dc = 1, V_lp = 1), cycles whose
ln(V/V_lp) spans 40–45 (three per state law). For each case the engine's attracting cycle
(``cycle.limit_cycle`` / ``attractor.fate``: Newton on the return map) gives only the *start*: its
section point θ on V = V_lp. From there ``reference.reference_cycle`` (mpmath, 40 digits, Taylor
order 30, relative tolerance 1e-32; variables τ = μ + ηV and θ, no heyoka) runs two turns; the second
is the reference (the first turn moves the start onto the mpmath cycle: the multipliers are ≤ 0.1, so
a 1e-16 start error leaves ≤ 1e-17 after a turn). ``self_consistency``: the second turn again at order
24, tolerance 1e-26, relative difference of the periods. Values are 30-digit strings.

The start is the engine's double-precision fixed point, whose last bits can differ on another CPU
(AVX2 vs AVX-512): after the first, contracting turn that moves the reference's digits beyond ~1e-17
relative, far below what the tests compare (1e-13), but a regenerated file may differ there.
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
from bifurcation.models.rate_state.attractor import fate  # noqa: E402
from bifurcation.models.rate_state.cycle import limit_cycle  # noqa: E402
from bifurcation.models.rate_state.reference import reference_cycle  # noqa: E402

BASE = {"a": 0.01, "b": 0.025, "dc": 1.0, "v_lp": 1.0}
CASES = [("aging", 1e-8, 0.3), ("aging", 1e-8, 0.1), ("aging", 1e-8, 0.03),
         ("slip", 1e-15, 0.05), ("slip", 1e-15, 0.03), ("slip", 1e-15, 0.02),
         ("prz", 1e-9, 0.3), ("prz", 1e-8, 0.1), ("prz", 1e-8, 0.03)]


def spec_of(law, eta, kappa) -> SliderSpec:
    k_c = (BASE["b"] - BASE["a"] - eta * BASE["v_lp"]) / BASE["dc"]   # docs/rate-state.md
    return SliderSpec(a=BASE["a"], b=BASE["b"], dc=BASE["dc"], state_law=law, k=kappa * k_c, damping=eta)


def main() -> None:
    out = {"generator": "tests/data/make_rate_state_deep_cycles.py", "dps": 40, "order": 30, "base": BASE,
           "cases": []}
    for law, eta, kappa in CASES:
        t0 = time.time()
        spec = spec_of(law, eta, kappa)
        c = limit_cycle(spec, BASE["v_lp"])
        f = fate(spec, BASE["v_lp"], c.period, max_steps=2_000_000, t_max=math.inf)
        with mp.workdps(40):
            theta0 = [mp.exp(mp.mpf(w)) for w in f.w[:1]]
            ref = reference_cycle(spec, BASE["v_lp"], theta0, turns=2)
            low = reference_cycle(spec, BASE["v_lp"], ref["turns"][0]["theta"], turns=1, order=24, tol_digits=26)
            second, first = ref["turns"][1], ref["turns"][0]
            consistency = abs(low["turns"][0]["period"] / second["period"] - 1)
            out["cases"].append({
                "state_law": law, "damping": eta, "kappa": kappa, "k": spec.k,
                "start_ln_theta": repr(f.w[0]),
                "period": mp.nstr(second["period"], 30), "ln_v_max": mp.nstr(second["ln_v_max"], 30),
                "ln_v_min": mp.nstr(second["ln_v_min"], 30), "steps": second["steps"],
                "first_turn_period": mp.nstr(first["period"], 30),
                "fixed_point_residual": mp.nstr(abs(mp.log(second["theta"][0] / first["theta"][0])), 3),
                "self_consistency": mp.nstr(consistency, 3),
            })
        print(law, eta, kappa, second["steps"], mp.nstr(second["period"], 20), mp.nstr(consistency, 3),
              f"{time.time() - t0:.0f} s", flush=True)
    (HERE / "rate_state_deep_cycles.json").write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
