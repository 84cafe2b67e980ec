"""`rate-state --cycle` with mass far below k_c: bounded, and the cycle it reaches is the direct run's.

The case (issue 21, a review's hang): slip law, a = 0.01, b = 0.015, Dc = 0.01, k = 0.1, V_lp = 1, M = 1.
k_c = 5000.5 there (2π/ω_c = 0.089), but at k = 0.1 steady sliding loses stability as the block's inertial
oscillation (2π/|λ| = 19.87, Re λ = 0.0025): the perturbation needs ~1800 time units to reach the cycle,
which the transient run's old budget (4000 Hopf periods, 355) cut short, and the event-split fall-back then
stalled for > 5 min. Now the transient budget is in linear periods at k (``attractor.time_scale``) and every
event-split run is bounded (``slow_manifold.PIECE``, ``TURN_FACTOR``).
"""

from __future__ import annotations

import json
import math
import subprocess
import sys
import time

import numpy as np
import pytest

from bifurcation.models.rate_state import SliderSpec, rate_state

CASE = dict(a=0.01, b=0.015, dc=0.01, state_law="slip", k=0.1, mass=1.0)
#: The period of the direct run's settled cycle (the last two maxima of V in a run to 2600, below).
DIRECT_PERIOD = 19.935505097406804
ARGS = ["rate-state", "--state-law", "slip", "--a", "0.01", "--b", "0.015", "--dc", "0.01", "--k", "0.1",
        "--v-lp", "1", "--mass", "1", "--cycle", "--json"]


def test_time_scale_far_below_k_c_is_the_inertial_period():
    # Far below k_c the leading eigenvalue of steady sliding is the spring-mass one, ±i√(k/M), shifted by
    # the friction: 2π√(M/k) = 19.869 against 19.8707 measured (7.5e-5 apart), hence 1e-3; the Hopf
    # period 2π/ω_c = 0.0889 (ω_c = 70.71, `bifurcation hopf`) would be 224× too short a unit.
    from bifurcation.models.rate_state.attractor import time_scale

    spec = SliderSpec(**CASE)
    unit = time_scale(spec, 1.0, 2 * math.pi / 70.71067811865474)
    assert unit == pytest.approx(2 * math.pi * math.sqrt(CASE["mass"] / CASE["k"]), rel=1e-3)
    # near k_c the unit is the Hopf period (to 5e-5 at k = 0.9999 k_c, measured), never shorter
    near = SliderSpec(**{**CASE, "k": 5000.0})
    assert 0.0888577 <= time_scale(near, 1.0, 0.0888577) < 0.0888577 * (1 + 1e-3)


@pytest.mark.slow   # ~5 s the command (measured 4.2–6.3 s under load), ~3 s the direct run
def test_cli_cycle_far_below_k_c_with_mass_ends_with_the_direct_runs_cycle():
    start = time.monotonic()
    # 120 s: the bound is 2e6 transient steps (~35 s at ~17 µs) plus the event-split budget; measured 5 s
    out = subprocess.run([sys.executable, "-m", "bifurcation", *ARGS], capture_output=True, text=True,
                         timeout=120)
    took = time.monotonic() - start
    record = json.loads(out.stdout)
    assert out.returncode == 0 and record["status"] == "limit-cycle", (out.returncode, out.stderr[-500:])
    assert took < 120
    # Reference: a direct run through the transient (no shooting, no Newton): the time between successive
    # maxima of V on the settled cycle, at their exact event times (dense output). Measured: the last two
    # maxima of a run to 2600 give 19.935505097406804, 4e-15 from the shooting period, ln V extrema 6e-16
    # and 1.4e-13 apart; 1e-11 / 1e-11 leave room for another CPU's rounding over ~130 direct cycles.
    r = rate_state(**{k: v for k, v in CASE.items()}, v_lp=1.0, t=np.array([0.0, 2600.0]), v0=1.01)
    maxima = r.extrema[r.extrema[:, 2] > 0]
    assert r.status == "ok" and len(maxima) > 10
    assert record["period"] == pytest.approx(maxima[-1, 0] - maxima[-2, 0], rel=1e-11)
    assert record["ln_v_max"] == pytest.approx(maxima[-1, 1], abs=1e-11)
    minima = r.extrema[r.extrema[:, 2] < 0]
    assert record["ln_v_min"] == pytest.approx(minima[-1, 1], abs=1e-11)


@pytest.mark.slow   # ~2–4 s: compiles the slip law's order-5 integrators
def test_event_split_turn_that_stalled_is_cut_off_and_recovered(monkeypatch):
    # The error-estimate turn (switch 1e-5, order 5) from the event-split Newton's section point of CASE
    # (measured w below) stalled in the approach phase (steps of 3.7e-14 at s = 8e5, below its ulp) for 5e6
    # steps. Now a stalled piece (PIECE steps that do not move the time) ends the approach, and the turn goes
    # on in the plain inertial phase (the same equations): a section after 2270 steps (measured), the period
    # the direct run's (4e-15 measured; 1e-11 as above).
    from bifurcation.models.rate_state import slow_manifold as sm

    spec = SliderSpec(**CASE)
    w = np.array([-4.601894334812911, 0.32545892813371924])
    kw = dict(stop_at_sections=2, switch=sm.SWITCH / 10, order=sm.ORDER + 1, max_steps=5_000_000)
    r = sm.run_hybrid(spec, 1.0, "inertial", np.r_[0.0, w], 1000.0, **kw)
    assert r.status == "section" and r.steps < 10 * sm.PIECE, r.message
    assert r.t == pytest.approx(DIRECT_PERIOD, rel=1e-11)
    # without the recovery the stall itself is cut off within a piece or two (a section, should heyoka
    # one day not stall there)
    monkeypatch.setattr(sm, "RESCUES", 0)
    r = sm.run_hybrid(spec, 1.0, "inertial", np.r_[0.0, w], 1000.0, **kw)
    assert r.status in ("stalled", "section") and r.steps < 10 * sm.PIECE, r.message
    if r.status == "stalled":
        assert "stalled" in r.message


@pytest.mark.slow   # ~2–8 s: the event-split search, Newton and its error turns
def test_deep_cycle_far_below_k_c_is_bounded_and_is_the_direct_runs_cycle():
    # The event-split search alone (what the command fell back on before the transient's budget was in
    # periods at k): before, its 10×-deeper error turn stalled for > 5 min; now it ends with the cycle
    # (measured 1.9 s, period 19.93550509740689, 4e-15 from the direct run; 1e-11 as above), saying what it
    # does on the way.
    from bifurcation.models.rate_state import slow_manifold as sm

    spec = SliderSpec(**CASE)
    lines = []
    c = sm.deep_cycle(spec, 1.0, 2 * math.pi / 70.71067811865474, max_steps=2_000_000, progress=lines.append)
    assert lines and all(isinstance(s, str) for s in lines)
    assert c.status == "limit-cycle", c.message
    assert c.period == pytest.approx(DIRECT_PERIOD, rel=1e-11)
    assert c.ln_v_min == pytest.approx(-15.891938074166369, abs=1e-11)   # the direct run's (1.4e-13 apart)
