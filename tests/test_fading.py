"""Friction that fades at high velocity (issue 7; docs/engine.md, "Friction that fades").

References: ``tests/data/fading_reference.json``, values of ``bifurcation.reference_taylor`` (an mpmath
Taylor integrator at 40 working digits that shares no code with the engine or the law parser), produced once
by ``tests/make_fading_reference.py`` because a point takes 15-90 s of mpmath. The reference itself is
checked here against the exact piecewise-linear cycle and the Carlson–Langer ``mpmath.odefun`` run.

Targets (issue 7): relative error of Δ ≤ 2e-14 in double and ≤ 1e-15 in quad (quad results are real128
rounded to float64, so ≤ 1 ulp ≈ 2.2e-16 of Δ ≈ 2 is expected), and Δ0 likewise.
"""

from __future__ import annotations

import json
import math
import pathlib

import mpmath
import numpy as np
import pytest

import bifurcation as bf
from bifurcation.engine import _integrator
from bifurcation.laws import _fading
from bifurcation.engine.result import Status
from bifurcation.laws import resolve_law
from bifurcation.theory.reference import piecewise_linear_exact
from bifurcation.reference_taylor import REFERENCE_LAWS, taylor_cycle

DATA = pathlib.Path(__file__).parent / "data" / "fading_reference.json"
POINTS = list(json.loads(DATA.read_text())["points"].values())
TOLERANCE = {"double": 2e-14, "quad": 1e-15}
#: The engine's names of two reference laws.
ENGINE_NAME = {"exp(-x)": "exponential", "1/(1 + x)": "carlson-langer"}


def _engine_law(law: str) -> str:
    return ENGINE_NAME.get(law, law)


def _groups(kind: str) -> dict:
    groups: dict = {}
    for p in POINTS:
        if p["kind"] == kind:
            groups.setdefault(p["law"], []).append(p)
    return groups


# -- the reference against independent yardsticks --------------------------------------------------------
def test_reference_reproduces_the_exact_piecewise_linear_cycle():
    # Eq. (12) has a closed-form cycle (bifurcation.theory.reference); the Taylor reference must agree to its
    # own precision (dps 30 asked: 1e-28 leaves two digits for the event roots).
    # (1e-3, 1e-3): V falls from ν_f through 0 within one scan interval of a friction-free step; the
    # reference once stepped over that switch (Δ off by 1.1e-7) and the three-piece law's file values with it
    for nu, nu_f in ((1e-9, 0.05), (1e-3, 1e-3)):
        ours = taylor_cycle("piecewise(1 - x, 1, 0)", nu, nu_f, dps=30)
        exact = piecewise_linear_exact(nu, nu_f, dps=40)
        assert abs(ours["delta"] / exact["delta"] - 1) < 1e-28
        assert abs(ours["stop_time"] / exact["stop_time"] - 1) < 1e-28


def test_reference_reproduces_carlson_langer_odefun(carlson_langer_reference):
    # mpmath.odefun at dps 30 (bifurcation.theory.reference.carlson_langer_mp) against our series integrator.
    ours = taylor_cycle("1/(1 + x)", 1e-3, 0.4, dps=30)
    ref = carlson_langer_reference(1e-3)
    assert abs(ours["delta"] / ref["delta"] - 1) < 1e-25


def test_reference_file_covers_the_issue():
    keys = {(p["kind"], p["law"], p["nu"], p["nu_f"]) for p in POINTS}
    for case in (("cycle", "exp(-x)", 1e-3, 1e-3), ("cycle", "exp(-x)", 1e-18, 1e-3),
                 ("cycle", "exp(-x)", 1e-7, 5e-3), ("cycle", "exp(-x)", 1e-11, 7.5e-3),
                 ("cycle", "exp(-x - x^2)", 1e-3, 0.05), ("cycle", "exp(-x - x^2)", 1e-11, 0.08),
                 ("limit", "exp(-x)", None, 1e-3)):
        assert case in keys, case
    assert all(p["law"] in REFERENCE_LAWS for p in POINTS)


# -- the engine against the reference ---------------------------------------------------------------------
#: Laws whose real128 run stays in the fast suite: a fading law of each kind (e^{−x}, its faster-fading
#: e^{−x−x²}, a piecewise law with a fading piece) and an algebraic one; the other quad runs (1.5–3.5 s
#: each for a cycle, 0.1-1 s for a limit) are marked slow; every law keeps its double runs fast.
_FAST_QUAD = {"exp(-x)", "exp(-x - x^2)", "piecewise(1 - x, 0.5, 0.5*exp(1 - 2*x))", "1/(1 + x)"}


@pytest.mark.parametrize("law, precision", [
    pytest.param(law, precision, marks=pytest.mark.slow) if precision == "quad" and law not in _FAST_QUAD
    else (law, precision)
    for law in sorted(_groups("cycle")) for precision in ("double", "quad")])
def test_slip_matches_reference(law, precision):
    points = _groups("cycle")[law]
    nu = np.array([p["nu"] for p in points])
    nu_f = np.array([p["nu_f"] for p in points])
    r = bf.slip(_engine_law(law), nu=nu, nu_f=nu_f, precision=precision)
    errors = [abs(r.delta[i] / float(mpmath.mpf(p["delta"])) - 1) for i, p in enumerate(points)]
    bad = [(p["nu"], p["nu_f"], f"{e:.1e}", str(Status(int(s))))
           for p, e, s in zip(points, errors, r.status) if not e <= TOLERANCE[precision]]
    assert not bad, bad
    assert np.isin(r.status, [int(Status.STICK_SLIP), int(Status.CREEP), int(Status.NO_STICK)]).all()


@pytest.mark.parametrize("law, precision", [   # the same split as above (these quad runs: 0.7-1 s each)
    pytest.param(law, precision, marks=pytest.mark.slow) if precision == "quad" and law not in _FAST_QUAD
    else (law, precision)
    for law in sorted(_groups("limit")) for precision in ("double", "quad")])
def test_limit_matches_reference(law, precision):
    points = _groups("limit")[law]
    r = bf.limit(_engine_law(law), nu_f=[p["nu_f"] for p in points], precision=precision)
    errors = [abs(r.delta0[i] / float(mpmath.mpf(p["delta0"])) - 1) for i, p in enumerate(points)]
    bad = [(p["nu_f"], f"{e:.1e}") for p, e in zip(points, errors) if not e <= TOLERANCE[precision]]
    assert not bad, bad


def test_batch_matches_reference():
    # The SIMD path: rungs are terminal there too (a non-terminal event cannot end a lane's step).
    points = _groups("cycle")["exp(-x)"]
    nu = np.array([p["nu"] for p in points])
    nu_f = np.array([p["nu_f"] for p in points])
    r = bf.slip("exponential", nu=nu, nu_f=nu_f, batch=4)
    errors = [abs(r.delta[i] / float(mpmath.mpf(p["delta"])) - 1) for i, p in enumerate(points)]
    assert max(errors) <= TOLERANCE["double"], errors
    # fewer points than lanes: the idle lanes must not poison the batch (they divided 0/0 before)
    few = bf.slip("exponential", nu=nu[:2], nu_f=nu_f[:2], batch=8)
    assert np.array_equal(few.delta, r.delta[:2])


def test_idle_lanes_start_clean_after_points_without_a_stop():
    # Regression (found when batching became slip's default): a lane that finished a point without a
    # stop kept a non-finite time when it went idle, and heyoka refused the next call on the same cached
    # integrator ("one of the current times is not finite"). Idle lanes rest at time 0 now.
    points = _groups("cycle")["exp(-x)"]
    nu = np.array([p["nu"] for p in points])
    nu_f = np.array([p["nu_f"] for p in points])
    first = bf.slip("exponential", nu=nu, nu_f=nu_f, batch=8)
    assert (first.status != int(Status.STICK_SLIP)).any()   # the points that left a lane non-finite
    few = bf.slip("exponential", nu=nu[:2], nu_f=nu_f[:2], batch=8)
    np.testing.assert_array_equal(few.delta, first.delta[:2])


# -- the issue's failing cases, before the fix ------------------------------------------------------------
def test_without_rungs_the_issue_comes_back(monkeypatch):
    # Fault injection: the same integrator without its ladder steps over the deceleration again
    # (issue 7: Δ too large by ≈ (π²/12)·ν_f², 4.1e-7 relative at ν_f = 1e-3). So the rungs are what
    # fixes it, and the reference sees the difference.
    ref = next(p for p in POINTS if p["kind"] == "cycle" and p["law"] == "exp(-x)"
               and p["nu"] == 1e-18 and p["nu_f"] == 1e-3)
    monkeypatch.setattr(_fading, "ladder", lambda law, precision: _fading.Ladder((), math.inf))
    blind = _integrator.build(resolve_law("exponential"))
    raw = bf.engine.cycle.run_cycle(blind, {"nu": 1e-18, "nu_f": 1e-3, "forcing": 1.0})
    error = 1e-18 * float(raw["W"]) / float(mpmath.mpf(ref["delta"])) - 1
    assert 3e-7 < error < 5e-7
    assert abs(error - (math.pi ** 2 / 12) * 1e-6 / 2) < 0.1 * error


# -- the ladder ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize("law", ["carlson-langer", "piecewise-linear", "1/sqrt(1 + 2*x)", "piecewise(1 - x, 1, 0)"])
def test_algebraic_and_constant_laws_get_no_rungs(law):
    # They cost nothing: no event is added to their integrator.
    for precision in ("double", "quad"):
        assert _fading.ladder(resolve_law(law), precision).rungs == ()
    c = _integrator.compiled(resolve_law(law))
    assert _integrator.EventKind.RUNG not in c.kinds


@pytest.mark.parametrize("law", ["exponential", "exp(-x - x^2)", "0.75 + 0.25*exp(-4*x)",
                                 "piecewise(1 - x, 0.5, 0.5*exp(1 - 2*x))"])
def test_fading_laws_get_a_ladder_with_the_promised_spacing(law):
    f = resolve_law(law)
    for precision, u in (("double", 2.0 ** -53), ("quad", 2.0 ** -113)):
        rungs = _fading.ladder(f, precision).rungs
        assert len(rungs) >= 5 and list(rungs) == sorted(rungs, reverse=True)
        with mpmath.workdps(50):
            slope = [abs(mpmath.diff(f.drop_mp, r)) for r in rungs]
            # above the top the friction varies by less than rounding over its scale
            top = rungs[0] * 1.5
            assert abs(mpmath.diff(f.drop_mp, top)) * max(1, top) <= u / 16
        # |g'| grows by at most e² from a rung to the next (1 % slack for the bisection)
        assert all(b <= 1.01 * _fading.GROWTH * a for a, b in zip(slope, slope[1:]))
        # the last rung is where the friction becomes visible to the step control
        assert slope[-1] * max(1, rungs[-1]) >= _fading.VISIBLE
    # quad's ladder is its own: it starts higher, where friction falls below quad's rounding
    assert _fading.ladder(f, "quad").rungs[0] > _fading.ladder(f, "double").rungs[0]


# -- points the engine cannot vouch for -------------------------------------------------------------------------
def test_beyond_the_checked_range_is_unresolved_not_stick_slip(monkeypatch):
    # The accepted ν_f ≥ 1e-4 keep U̇/ν_f ≤ 2e4 < 1e5, the end of the scan; so the range is injected:
    # checked only up to x = 50, a point reaching x ~ 1000 (ν_f = 1e-3) is unresolved (NaN fields, a
    # message), in scalar, batch and limit alike, and one staying below (ν_f = 0.3) is not.
    real = _fading.ladder
    monkeypatch.setattr(_integrator, "_CACHE", {})
    monkeypatch.setattr(_fading, "ladder", lambda law, precision: _fading.Ladder(real(law, precision).rungs, 50.0))
    r = bf.slip("exponential", nu=[1e-9, 1e-9], nu_f=[1e-3, 0.3])
    assert r.status_names().tolist() == ["unresolved", "stick-slip"]
    assert math.isnan(r.delta[0]) and "beyond x = 50" in r.messages[0] and math.isfinite(r.delta[1])
    rb = bf.slip("exponential", nu=[1e-9, 1e-9], nu_f=[1e-3, 0.3], batch=2)
    assert rb.status_names().tolist() == ["unresolved", "stick-slip"]
    lim = bf.limit("exponential", nu_f=[1e-3, 0.3])
    assert lim.status_names().tolist() == ["unresolved", "stick-slip"] and math.isnan(lim.delta0[0])
    assert Status(7) is Status.UNRESOLVED and str(Status.UNRESOLVED) == "unresolved"
    record = r.to_records()[0]
    assert record["status"] == "unresolved" and record["delta"] is None and "message" in record


def test_a_law_with_a_constant_last_piece_is_checked_to_infinity():
    # Nothing to resolve on a constant piece: no point of Eq. (12) can be unresolved.
    assert _fading.ladder(resolve_law("piecewise-linear"), "double").x_checked == math.inf
    assert _fading.ladder(resolve_law("carlson-langer"), "double").x_checked == _fading.X_CHECKED
