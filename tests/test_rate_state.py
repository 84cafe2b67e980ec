"""The rate-and-state slider: rsfmodel's five cases as a peer, our mpmath reference, events, bad input."""

import json
import math
import pathlib

import mpmath as mp
import numpy as np
import pytest
from click.testing import CliRunner

from _rsfmodel_data import CASES
from bifurcation.cli import cli
from bifurcation.errors import InputError
from bifurcation.models.rate_state import load_history, rate_state

GOLDEN = json.loads((pathlib.Path(__file__).parent / "data" / "rate_state_mpmath.json").read_text())
HISTORY = load_history([1.0, 10.0], at=[10.0])
T = np.arange(41.0)


def _run(name, **kw):
    c = CASES[name]
    return rate_state(a=c["a"], b=[s[1] for s in c["states"]], dc=[s[2] for s in c["states"]],
                      state_law=[s[0] for s in c["states"]], k=c["k"], v_lp=HISTORY, t=T, **kw)


def _golden(name):
    g = GOLDEN["cases"][name]
    return (np.array([float(x) for x in g["mu"]]), np.array([float(x) for x in g["v"]]),
            [np.array([float(x) for x in row]) for row in g["theta"]])


@pytest.mark.parametrize("name", sorted(CASES))
def test_rsfmodel_cases_agree_with_their_stored_arrays(name):
    # Their arrays: odeint at rtol = atol = 1e-12, printed to 8 decimals (rounding up to 5e-9). The
    # exact solution (our mpmath golden) is itself up to 1.06e-8 from them (dieterich_1, V = 29: odeint's
    # own error); ours must be as close to theirs as the exact solution is, to 1e-12.
    c, r = CASES[name], _run(name)
    mu, v, theta = _golden(name)
    assert r.status == "ok"
    pairs = [(r.mu, c["friction"], mu), (r.v, c["velocity"], v)]
    pairs += [(r.theta[i], row, theta[i]) for i, row in enumerate(c["state"])]
    for ours, theirs, exact in pairs:
        theirs = np.array(theirs)
        assert np.all(np.abs(ours - theirs) <= np.abs(exact - theirs) + 1e-12)
        assert np.max(np.abs(ours - theirs)) < 1.1e-8


@pytest.mark.parametrize("name", sorted(CASES))
def test_rsfmodel_cases_against_our_mpmath_reference(name):
    # Golden: tests/data/make_rate_state_reference.py (mpmath Taylor series, 40 digits, no heyoka; its
    # self-consistency between orders 30 and 36 is ~1e-40). Goal 1e-12 relative in μ; measured ~2e-16,
    # so 1e-14 leaves room for another CPU's rounding and still fails on any real error.
    assert float(GOLDEN["cases"][name]["self_consistency"]) < 1e-30
    r = _run(name)
    mu, v, theta = _golden(name)
    assert np.max(np.abs(r.mu - mu) / mu) < 1e-14
    assert np.max(np.abs(r.v - v) / v) < 1e-13   # V = e^x: a relative error of x times |x| ≤ 4
    for i, th in enumerate(theta):
        assert np.max(np.abs(r.theta[i] - th) / th) < 1e-13


@pytest.mark.parametrize("name", ["ruina_1", "dieterich_2"])
def test_quad_precision_matches_the_mpmath_reference_to_its_30_digits(name):
    # real128 (tolerance 1.9e-34) against the 30-digit golden strings: agreement to 1e-28 shows both
    # the engine's equations and the reference integrate the same model (double cannot test this).
    g = GOLDEN["cases"][name]
    r = _run(name, precision="quad")
    with mp.workdps(40):
        err = max(abs(mp.mpf(str(x)) - mp.mpf(y)) / mp.mpf(y) for x, y in zip(r.mu, g["mu"]))
    assert err < 1e-28


def test_velocity_extrema_and_slip_events_are_exact():
    # An event's time, checked by running again to exactly that time: V there equals the threshold,
    # and V at a recorded maximum is above its neighbours. rsfmodel's arrays show V: 1 → 29 → 6.3 → …,
    # so V = 5 is crossed once upwards and V = 20 once up and once down.
    r = _run("dieterich_1", thresholds=[5.0, 20.0])
    assert sorted(map(tuple, r.crossings[:, 1:].tolist())) == [(0.0, 1.0), (1.0, -1.0), (1.0, 1.0)]
    for t, j, _ in r.crossings:
        s = rate_state(a=0.005, b=0.01, dc=10.0, state_law="aging", k=1e-3, v_lp=HISTORY, t=[0.0, t])
        assert abs(s.v[-1] / r.thresholds[int(j)] - 1) < 1e-13
    maxima = r.extrema[r.extrema[:, 2] > 0]
    t_max, lnv_max = maxima[1, 0], maxima[1, 1]
    s = rate_state(a=0.005, b=0.01, dc=10.0, state_law="aging", k=1e-3, v_lp=HISTORY,
                   t=[0.0, t_max - 1e-4, t_max, t_max + 1e-4])
    assert abs(s.ln_v[2] - lnv_max) < 1e-13
    assert s.ln_v[1] < s.ln_v[2] > s.ln_v[3]


def test_extrema_alternate_and_a_steady_state_records_no_noise():
    # After the reload of a 1e12 hold the slider settles onto steady sliding: ẋ is rounding noise there
    # and changed sign ~70 times per time unit; only the real maximum and minimum may be recorded.
    hold = load_history([1.0, 0.0, 1.0], at=[10.0, 1e12 + 10])
    r = rate_state(a=0.01, b=0.012, dc=1e-2, state_law="slip", k=10.0, v_lp=hold, t=[0.0, 1e12 + 10, 1e12 + 110])
    assert r.extrema[:, 2].tolist() == [1.0, -1.0] and r.extrema[0, 1] > 5
    e = _run("dieterich_1").extrema
    assert np.all(e[1:, 2] == -e[:-1, 2]) and e[0, 0] > 10   # nothing during the steady first segment


def test_slide_hold_slide_spans_many_decades_of_velocity():
    # A 1e6 hold: V falls by 11 decades (aging law, θ grows like t); the log variables keep ln V to
    # ~1e-15 relative against a real128 run at the end of the hold and after the reload.
    hold = load_history([1.0, 0.0, 1.0], at=[10.0, 1e6 + 10])
    kw = dict(a=0.01, b=0.012, dc=1e-2, state_law="aging", k=10.0, v_lp=hold)
    for t in ([0.0, 1e6 + 10], [0.0, 1e6 + 20]):
        r, q = rate_state(t=t, **kw), rate_state(t=t, precision="quad", **kw)
        assert r.status == "ok"
        assert abs(r.ln_v[1] - float(q.ln_v[1])) < 1e-15 * max(abs(float(q.ln_v[1])), 1) * 4
    assert r.v[1] == pytest.approx(1.0, rel=1e-6) and r.slip[-1] > 0


@pytest.mark.slow   # 8 s; holds stay in the fast suite through test_slide_hold_slide_spans_many_decades_of_velocity
def test_reload_after_a_1e12_hold_is_as_precise_as_its_first_second():
    # Slip law, hold of 1e12: V falls 15.5 decades (ln V = −35.7). Each load segment runs in its own
    # local time, so the reload is resolved to its own scale and not to ulp(1e12) = 1.2e-4 (which
    # cost 1.5e-3 in ln V before). Measured against real128: ≤ 4e-14 absolute in ln V.
    hold = load_history([1.0, 0.0, 1.0], at=[10.0, 1e12 + 10])
    kw = dict(a=0.01, b=0.012, dc=1e-2, state_law="slip", k=10.0, v_lp=hold,
              t=[0.0, 1e3, 1e12 + 10, 1e12 + 10.001, 1e12 + 1e3])
    r, q = rate_state(**kw), rate_state(precision="quad", **kw)
    assert r.status == q.status == "ok" and r.ln_v[2] < -35
    assert np.max(np.abs(r.ln_v - q.ln_v.astype(float))) < 1e-13


def test_inertial_slider_relaxes_to_steady_state_and_matches_quad():
    kw = dict(a=0.01, b=0.005, dc=1e-2, state_law="slip", k=1.0, mass=1e-4, v_lp=1.0, v0=2.0,
              t=np.linspace(0, 5, 6))
    r, q = rate_state(**kw), rate_state(precision="quad", **kw)
    assert abs(r.v[-1] - 1) < 1e-6     # velocity strengthening (b < a): steady sliding is stable
    assert np.max(np.abs(r.mu - q.mu.astype(float))) < 1e-14


def test_max_steps_gives_a_status_not_a_number():
    r = rate_state(a=0.01, b=0.015, dc=1e-2, state_law="aging", k=1e-3, v_lp=1.0, v0=1.5, t=[0, 1e4],
                   max_steps=20)
    assert r.status == "max-steps" and math.isnan(r.mu[-1]) and "max-steps" in r.message


BAD = [
    (["--a", "0"], "a=0.0: must be > 0"),
    (["--a", "-0.01"], "a=-0.01: must be > 0"),
    (["--a", "nan"], "a=nan: is not finite"),
    (["--b", "-0.1"], "b=-0.1: must be >= 0"),
    (["--dc", "0"], "dc=0.0: must be > 0"),
    (["--k", "0"], "k=0.0: must be > 0"),
    (["--k", "-1"], "k=-1.0: must be > 0"),
    (["--state-law", "frobnicate"], "--state-law='frobnicate': is not a known state law"),
    (["--v-lp", "1,10,3", "--at", "10,10"], "are not strictly increasing"),
    (["--v-lp", "1,10,3", "--at", "10,5"], "are not strictly increasing"),
    (["--v-lp", "1,10"], "needs 1 step times for 2 velocities"),
    (["--v-lp", ""], "--v-lp='': is empty"),   # refused before parsing (issue 21: empty values named as '')
    (["--v-lp", "-1"], "--v-lp=-1.0: must be >= 0"),
    (["--mass", "0"], "mass=0.0: must be > 0"),
]


@pytest.mark.parametrize("change,message", BAD)
def test_bad_input_is_one_line_with_exit_status_2(change, message):
    args = {"--state-law": "aging", "--a": "0.01", "--b": "0.015", "--dc": "0.01", "--k": "1",
            "--v-lp": "1", "--t-end": "10"}
    extra = []
    for key, value in zip(change[::2], change[1::2]):
        if key in args:
            args[key] = value
        else:
            extra += [key, value]
    argv = ["rate-state", *[x for kv in args.items() for x in kv], *extra]
    result = CliRunner().invoke(cli, argv)
    assert result.exit_code == 2, result.output
    lines = result.output.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("bifurcation: error:") and message in lines[0]
    assert "Traceback" not in result.output


def test_bad_input_through_the_api_names_the_argument():
    with pytest.raises(InputError, match="v_lp=\\[\\]: is empty"):
        rate_state(a=0.01, b=0.015, dc=0.01, state_law="aging", k=1, v_lp=[], t=[0, 1])
    with pytest.raises(InputError, match="t=.*is not sorted"):
        rate_state(a=0.01, b=0.015, dc=0.01, state_law="aging", k=1, v_lp=1, t=[2, 1])
    with pytest.raises(InputError, match="dc/state_law"):
        rate_state(a=0.01, b=[0.015, 0.01], dc=[0.01], state_law="aging", k=1, v_lp=1, t=[0, 1])


def test_the_bench_baseline_integrates_the_same_model():
    # bifurcation bench --suite rate-state times scipy odeint on rsfmodel's own variables (μ, θ); at
    # rsfmodel's rtol = 1e-12 it must reproduce their stored friction to their 8 printed decimals.
    pytest.importorskip("scipy")
    from bifurcation.models.rate_state._bench import _CASES, _odeint_case

    for name in ("ruina_1", "prz_1"):
        a, k, states = _CASES[name]
        mu = _odeint_case(a, k, states, 1e-12)
        assert np.max(np.abs(mu - CASES[name]["friction"])) < 1e-8
