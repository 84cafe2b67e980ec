"""Generate tests/data/rate_state_damped_mpmath.json: the mpmath reference for the damped slider.

    PYTHONPATH=. python tests/data/make_rate_state_damped_reference.py      # ~1 minute on one core

``bifurcation.models.rate_state.reference.reference_run`` (mpmath Taylor series, no heyoka; variables
τ = μ + ηV and θ, V from a ln(V/V*) + ηV = R by Lambert W) at 40 digits, order 36, local tolerance
1e-36, and again at order 30, tolerance 1e-32; the largest relative difference in μ between the two is
stored as ``self_consistency``. Cases (quasi-static, radiation damping η):

- ``aging_step``: rsfmodel-like velocity step 1 → 10 at t = 10 (a = 0.011, b = 0.01, Dc = 10, k = 1e-3)
  with η = 0.002 (ηV = 0.02 after the step: twice a);
- ``slip_cycle``, ``prz_cycle``: a = 0.01, b = 0.015, Dc = 0.01, η = 0.002 (k_c = 0.3), k = 0.24,
  started at V = 1.02 with θ at steady state for V = 1: the growing oscillation towards the cycle;
- ``aging_slip_two_states``: aging + slip (b = 0.012, 0.006; Dc = 0.01, 0.1), k = 0.2, η = 0.003, same start.
"""

from __future__ import annotations

import json
import pathlib
import sys

import mpmath as mp

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from bifurcation.models.rate_state import SliderSpec, load_history  # noqa: E402
from bifurcation.models.rate_state.reference import reference_run  # noqa: E402

CASES = {
    "aging_step": {"a": 0.011, "b": [0.01], "dc": [10.0], "laws": ["aging"], "k": 1e-3, "damping": 0.002,
                   "v_lp": [1.0, 10.0], "at": [10.0], "t_end": 40.0, "v0": None, "theta0": None},
    "slip_cycle": {"a": 0.01, "b": [0.015], "dc": [0.01], "laws": ["slip"], "k": 0.24, "damping": 0.002,
                   "v_lp": [1.0], "at": [], "t_end": 2.0, "v0": 1.02, "theta0": [0.01]},
    "prz_cycle": {"a": 0.01, "b": [0.015], "dc": [0.01], "laws": ["prz"], "k": 0.24, "damping": 0.002,
                  "v_lp": [1.0], "at": [], "t_end": 2.0, "v0": 1.02, "theta0": [0.02]},
    "aging_slip_two_states": {"a": 0.01, "b": [0.012, 0.006], "dc": [0.01, 0.1], "laws": ["aging", "slip"],
                              "k": 0.2, "damping": 0.003, "v_lp": [1.0], "at": [], "t_end": 2.0, "v0": 1.02,
                              "theta0": [0.01, 0.1]},
}
OUTPUTS = 21


def main() -> None:
    out = {"generator": "tests/data/make_rate_state_damped_reference.py", "dps": 40, "order": 36, "cases": {}}
    for name, c in CASES.items():
        spec = SliderSpec(a=c["a"], b=c["b"], dc=c["dc"], state_law=c["laws"], k=c["k"], damping=c["damping"])
        history = load_history(c["v_lp"], at=c["at"])
        times = [c["t_end"] * i / (OUTPUTS - 1) for i in range(OUTPUTS)]
        kw = {"v0": c["v0"], "theta0": c["theta0"]}
        ref = reference_run(spec, history, times, dps=40, order=36, tol_digits=36, **kw)
        low = reference_run(spec, history, times, dps=40, order=30, tol_digits=32, **kw)
        with mp.workdps(40):
            diff = max(abs(x - y) / abs(x) for x, y in zip(ref["mu"], low["mu"]))
        out["cases"][name] = {
            **c, "times": times,
            "mu": [mp.nstr(x, 30) for x in ref["mu"]],
            "theta": [[mp.nstr(x, 30) for x in row] for row in ref["theta"]],
            "v": [mp.nstr(x, 30) for x in ref["v"]],
            "steps": ref["steps"], "self_consistency": mp.nstr(diff, 3),
        }
        print(name, ref["steps"], mp.nstr(diff, 3), flush=True)
    (HERE / "rate_state_damped_mpmath.json").write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
