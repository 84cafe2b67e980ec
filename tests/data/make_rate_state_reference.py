"""Generate tests/data/rate_state_mpmath.json: the mpmath Taylor reference for rsfmodel's five cases.

    PYTHONPATH=. python tests/data/make_rate_state_reference.py      # ~1-2 minutes on one core

For each case of tests/_rsfmodel_data.py (same parameters, load-point velocity 1 then 10 from t = 10),
``bifurcation.models.rate_state.reference.reference_run`` (mpmath, no heyoka, rsfmodel's own variables
μ and θ) at 40 digits, order 36, local tolerance 1e-36; and again at order 30, tolerance 1e-32, whose
largest relative difference in μ is stored as ``self_consistency`` (an upper estimate of the
reference's own error). Values are stored as 30-digit decimal strings.
"""

from __future__ import annotations

import json
import pathlib
import sys

import mpmath as mp

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

from _rsfmodel_data import CASES  # noqa: E402

from bifurcation.models.rate_state import SliderSpec, load_history  # noqa: E402
from bifurcation.models.rate_state.reference import reference_run  # noqa: E402


def main() -> None:
    out = {"generator": "tests/data/make_rate_state_reference.py", "dps": 40, "order": 36, "times": list(range(41)),
           "cases": {}}
    history = load_history([1.0, 10.0], at=[10.0])
    for name, c in CASES.items():
        spec = SliderSpec(a=c["a"], b=[s[1] for s in c["states"]], dc=[s[2] for s in c["states"]],
                          state_law=[s[0] for s in c["states"]], k=c["k"])
        ref = reference_run(spec, history, range(41), dps=40, order=36, tol_digits=36)
        low = reference_run(spec, history, range(41), dps=40, order=30, tol_digits=32)
        with mp.workdps(40):
            diff = max(abs(x - y) / abs(x) for x, y in zip(ref["mu"], low["mu"]))
        out["cases"][name] = {
            "mu": [mp.nstr(x, 30) for x in ref["mu"]],
            "theta": [[mp.nstr(x, 30) for x in row] for row in ref["theta"]],
            "v": [mp.nstr(x, 30) for x in ref["v"]],
            "steps": ref["steps"],
            "self_consistency": mp.nstr(diff, 3),
        }
        print(name, ref["steps"], mp.nstr(diff, 3), flush=True)
    (HERE / "rate_state_mpmath.json").write_text(json.dumps(out, indent=1) + "\n")


if __name__ == "__main__":
    main()
