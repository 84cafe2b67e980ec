"""The two-parameter diagram's pieces: the PRZ fold-of-cycles curve, the doubling cascade, the basins."""

import math

import numpy as np
import pytest

from bifurcation.models.rate_state import SliderSpec, load_history
from bifurcation.models.rate_state.basin import critical_in_slip, in_slip
from bifurcation.models.rate_state.continuation import continue_cycles
from bifurcation.models.rate_state.simulate import run_spec
from bifurcation.models.rate_state.two_parameter import fold_curve

#: The Bautin point of the inertial PRZ law (a = 0.01, b = 0.015, Dc = 0.01, V_lp = 1) in η = M V²/(a Dc):
#: secant root of l1 (two_parameter.bautin_point; tests/test_rate_state_two_parameter.py checks it against
#: the study's bracketing scan to 1e-10).
ETA_BAUTIN_PRZ = 0.0815295856361991


@pytest.mark.slow
def test_prz_fold_curve_ends_at_its_bautin_point():
    # ~15–30 s. From the fold flagged on the branch at η = 0.01 (κ ≈ 1.0575), 52 folds in η up to 0.998 η_B,
    # as for the aging law (test_rate_state_fold_curve.py): each a cycle to 1e-12 with a multiplier 1 to
    # 1e-9, κ_f falling monotonically onto 1, and √(κ_f − 1) extrapolated to 0 from the last two folds
    # landing on η_B (measured 4.5e-6 relative; 1e-4 allows for the next term of κ_f − 1 ∝ (η_B − η)²).
    br = continue_cycles(state_law="prz", a=0.01, b=0.015, dc=0.01, v_lp=1.0, mass=0.01e-4, points=10,
                         max_step=0.1, kappa_range=(0.6, 20))
    start = br.points[br.folds[0]]
    fc = fold_curve(list(np.linspace(0.01, 0.998 * ETA_BAUTIN_PRZ, 52)), start.w, start.kappa, state_law="prz")
    assert len(fc) == 52 and all(f.status == "ok" for f in fc)
    assert max(f.residual for f in fc) < 1e-12 and max(f.fold_residual for f in fc) < 1e-9
    kappas = np.array([f.kappa for f in fc])
    assert np.all(kappas > 1) and np.all(np.diff(kappas) < 0)
    (e1, k1), (e2, k2) = [(f.eta, math.sqrt(f.kappa - 1)) for f in fc[-2:]]
    assert abs((e2 - k2 * (e2 - e1) / (k2 - k1)) / ETA_BAUTIN_PRZ - 1) < 1e-4
    for f in fc[::5]:   # periods against direct runs (second turn, an independent step grid): <= 1e-10
        spec = SliderSpec(a=0.01, b=0.015, dc=0.01, state_law="prz", k=f.k, mass=f.eta * 1e-4)
        r = run_spec(spec, load_history(1.0), [0.0, 2.5 * f.period], ln_v0=0.0, ln_theta0=[f.w[0]], z0=f.w[1],
                     thresholds=[1.0])
        ups = [c[0] for c in r.crossings if c[2] > 0]
        assert abs((ups[1] - ups[0]) / f.period - 1) < 1e-10


def test_slip_law_runs_away_in_finite_slip():
    # Quasi-static slip law at κ = 1.1, ln θ raised by 1.0 (above the bracket 0.7606 … 0.7612 of the study):
    # with slip as the clock ln V passes 600 within ~14 Dc of slip — the double-exponential blow-up
    # (dΩ/dδ = [(b − a)Ω/Dc − k]/a for Ω = ln(Vθ/Dc) > κ, report "Basins above k_c").
    outcome, peak, at = in_slip("slip", 1.1, 1.0)
    assert outcome == "runs away" and peak > 599.9 and at < 30


@pytest.mark.slow
def test_aging_spike_ends_where_the_slip_law_runs_away():
    # ~20–60 s (loaded machine). Aging law, same raise at κ = 1.1, 1.5: the spike ends (ln V back below −0.5). Its peak for
    # Δ = 5 at κ = 1.1 (52.6 measured) lies below the fast-slip bound ln V ≤ (b/Dc − k)/a · Δ a Dc/
    # ((κ − 1)(b − a)) = 95 (report "Basins above k_c"). The slip law's threshold is bracketed at κ = 1.1
    # by bisection to 1e-3 relative: 0.7606 … 0.7612 in the study's run; within 2e-3 of it here.
    for kappa, delta in ((1.1, 2.0), (1.1, 5.0), (1.5, 5.0)):
        outcome, peak, _ = in_slip("aging", kappa, delta, slip_max=500.0)
        k = kappa * 0.5
        assert outcome == "returns" and peak < (1.5 - k) / 0.01 * delta * 1e-4 / ((kappa - 1) * 0.005)
    lo, hi = critical_in_slip("slip", 1.1, 0.05, 5.0)
    assert hi - lo < 1e-3 * hi and abs(lo / 0.7606 - 1) < 2e-3


def test_quasi_static_stall_below_k_c_is_read_as_a_blow_up_by_where_it_stopped():
    # the study's quasi-static fate row (study._quasi_static_fates): PRZ at κ = 0.9 stalls after ~630 steps.
    # Its largest *completed* maximum of ln V is ~2.3 (the report's old 'max ln V reached'), but the run
    # stops on the next spike at ln V ≈ 22 (measured 22.26), where the step falls below the resolution of
    # t: a blow-up by attractor.fate's rule (ln V > 10), which the report's verdict now requires
    from bifurcation.models.rate_state.report import BLOWUP_LN_V, blew_up
    from bifurcation.models.rate_state.simulate import rate_state

    period = 2 * math.pi / (math.sqrt(0.5) * 100)
    r = rate_state(a=0.01, b=0.015, dc=0.01, state_law="prz", k=0.9 * 0.5, v_lp=1.0, t=[0.0, 400 * period],
                   v0=1.0, theta0=[2.0 * 0.01 * math.exp(0.01)])
    assert r.status == "stalled"
    assert max(r.extrema[:, 1]) < 3 < BLOWUP_LN_V < r.meta["ln_v_stop"]
    assert f"at ln V = {r.meta['ln_v_stop']:.4g}" in r.message
    row = {"status": r.status, "ln_v_stop": r.meta["ln_v_stop"]}
    assert blew_up(row)
    assert not blew_up({"status": "stalled", "ln_v_stop": -5.0})      # a stall at small V is not a blow-up
    assert not blew_up({"status": "ok", "ln_v_stop": math.nan})
    assert blew_up({"status": "unbounded", "ln_v_stop": 30.3})


def test_horner_is_np_polyval_bit_for_bit():
    # _system._peak evaluates the step's Taylor polynomial (order 20) and its derivatives with _horner in
    # place of np.polyval (40 µs a call in numpy scalars): the same operations in the same order, so the
    # same doubles — also where they overflow to inf or go NaN
    from bifurcation.models.rate_state._system import _horner

    rng = np.random.default_rng(5)
    for scale in (1.0, 1e20, 1e150):
        for _ in range(200):
            c = rng.standard_normal(21) * scale ** rng.uniform(0, 1, 21)
            x = float(rng.uniform(-2, 2)) * 10.0 ** int(rng.integers(-20, 8))
            with np.errstate(all="ignore"):
                want = np.polyval(c, x)
            got = _horner(c.tolist(), x)
            assert np.float64(got).tobytes() == np.float64(want).tobytes(), (scale, x)
