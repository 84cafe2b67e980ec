"""Slowly attracting cycles next to a Hopf point (largest Floquet multiplier 0.95–0.9999): `rate-state
--cycle` solves the fixed point of the return map directly once the transient's approach is too slow to
finish in its budget (attractor.SLOW_RHO: docs/rate-state.md, "The attracting cycle as a result"), against
the mpmath shooting tests/_rscycle_rate_state.py (own Taylor recurrences at 45 digits; with mass the
integrator of tests/_indep3_rate_state.py) stored in tests/data/rscycle_sweep.json
(tests/data/make_rscycle_sweep.py; closure < 1e-35).

Tolerances: the engine's own error estimates (the second-turn difference, at least 4 ulps of the map's
variables, divided by 1 − ρ: a fixed point of a map known to δ is known to δ/(1 − ρ)), and in absolute
terms 1e-13 relative on the period times max(1, 1e-3/(1 − ρ)) and max(1e-12, 1e-14/(1 − ρ)) on the ln V
extrema: a double return map rounds ln θ ~ 5 over ~10³ steps a turn, δ measured 5e-16 … 2.5e-15 over the
sweep (|Δ ln V|·(1 − ρ)), so 1e-14 leaves a factor 4; measured at most 1.7e-11 at ρ = 0.999855. The multiplier is compared to 1e-6: the engine's comes from a central-difference
Jacobian (h = 1e-7 relative, rounding 1e-16/1e-7 = 1e-9 in each entry, amplified where J = DP − I is
near-singular).
"""

from __future__ import annotations

import json
import math
import pathlib

import pytest
from click.testing import CliRunner
from mpmath import mpf

from bifurcation.cli import cli

DATA = json.loads((pathlib.Path(__file__).parent / "data" / "rscycle_sweep.json").read_text())
CASES = DATA["cases"]


def _run(c):
    args = ["rate-state", "--state-law", c["law"], "--a", repr(c["a"]), "--b", repr(c["b"]), "--dc", repr(c["dc"]),
            "--v-lp", repr(c["v_lp"]), "--damping", repr(c["damping"]), "--k", repr(c["k"]), "--cycle", "--json"]
    if c["mass"]:
        args += ["--mass", repr(c["mass"])]
    res = CliRunner().invoke(cli, args)
    assert res.exit_code in (0, 2), res.output
    return json.loads(res.stdout if hasattr(res, "stdout") else res.output)


def _check(c, out):
    assert c["reference"] == "ok" and float(mpf(c["closure"])) < 1e-35
    rho = float(mpf(c["multiplier_max"]))
    assert out["status"] == "limit-cycle", out
    assert abs(out["multiplier_max"] - rho) < 1e-6, (out["multiplier_max"], rho)
    scale = max(1.0, 1e-3 / (1 - rho))
    for key in ("period", "ln_v_max", "ln_v_min"):
        diff = float(abs(mpf(out[key]) - mpf(c[key])))
        assert diff <= out[f"{key}_error"], (key, out[key], c[key], diff, out[f"{key}_error"])
    assert float(abs(mpf(out["period"]) - mpf(c["period"])) / mpf(c["period"])) <= 1e-13 * scale
    for key in ("ln_v_max", "ln_v_min"):
        assert float(abs(mpf(out[key]) - mpf(c[key]))) <= max(1e-12, 1e-14 / (1 - rho)), key


def test_slow_approach_resolved_fast():
    """The miss (tests/data/indep3_rate_state.json case 4; slip law, k = 0.96 k_c, M 1.31e-4, η 4.77e-4,
    multiplier 0.9977): not-resolved before (no cycle within 4000 linear periods nor 2000 event-split turns),
    now the cycle by Newton on the return map, vouched for by the run's approach to it (~2 s)."""
    c = CASES[0]
    assert (c["law"], c["k"], c["mass"]) == ("slip", 33.0, 0.000131)
    out = _run(c)
    assert "Newton on the return map" in out["message"], out
    _check(c, out)


def test_still_growing_at_the_end_of_the_budget_fast():
    """Case 11 (slip law, M 2.89e-6, k = 0.99995 k_c, multiplier 0.99969): after its 4000 linear periods the
    run is still spiralling out (section amplitude 0.011 of the cycle's 0.022); the normal-form
    fit of its growth predicts 0.0217, Newton converges there and the return map takes the segment between
    to the cycle (~2 s)."""
    c = CASES[11]
    assert (c["law"], c["mass"], c["damping"]) == ("slip", 2.89e-06, 0.0)
    out = _run(c)
    assert "still growing away from steady sliding" in out["message"], out
    _check(c, out)


#: Measured (tests/data/rscycle_sweep.json): every case whose reference converged is resolved; the two
#: that are not (26, 28: aging law with mass, subcritical Hopf points) are held below as what they are.
NOT_RESOLVED: dict = {}


@pytest.mark.slow
@pytest.mark.parametrize("i", range(1, len(CASES)))
def test_sweep_near_hopf(i):
    c = CASES[i]
    out = _run(c)
    if c["reference"] != "ok":
        # the reference's Newton found no cycle from ln V raised by 0.3 (it fell onto steady sliding's trace):
        # a subcritical Hopf point (`bifurcation hopf`: l1 > 0), no small attracting cycle to find. The engine
        # must not report one; a large stick-slip cycle beyond the fold would be another matter.
        assert out["status"] != "limit-cycle" or out["ln_v_max"] - out["ln_v_min"] > 1.0, out
        return
    if i in NOT_RESOLVED:
        assert out["status"] == "not-resolved" and out["period"] is None, out
        assert NOT_RESOLVED[i] in out["message"], out["message"]
        return
    _check(c, out)
