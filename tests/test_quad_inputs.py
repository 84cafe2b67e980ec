"""A verification mode reads its inputs at its own precision (issue 21): with ``precision="quad"`` a
decimal given as text (``"-0.03"``, the CLI's arguments, a Decimal) is parsed into real128, not through
the nearest double, whose 1e-17 rounding the dynamics amplify. Checked against the independent mpmath
references (``models.chain.reference``, ``models.rate_state.reference``) at 45–50 digits."""

from __future__ import annotations

from decimal import Decimal

import mpmath as mp
import numpy as np
import pytest
from click.testing import CliRunner

from bifurcation.engine._exact import Text, at_precision, decimal_text

U0 = ["-0.03", "0", "-0.01"]


def test_decimal_text_and_at_precision():
    import heyoka as hy

    assert decimal_text("0.03") == decimal_text(Text("0.03")) == decimal_text(Decimal("0.03")) == "0.03"
    assert decimal_text(0.03) is None and float(Text(" 0.03")) == 0.03
    assert at_precision("0.03", hy.real128) == hy.real128("0.03") != hy.real128(0.03)
    assert at_precision(0.03, hy.real128) == hy.real128(0.03)       # a float is its binary value
    assert at_precision("0.03", np.float64) == 0.03


@pytest.fixture(scope="module")
def chain_reference():
    from bifurcation.models.chain.reference import reference_chain

    # < 1 s: 3 blocks, 5 events of the exactly solvable law, 50 digits from the decimal inputs
    return reference_chain("piecewise-linear", n=3, ell="1", nu="0.001", nu_f="0.3", u0=U0, events=5, dps=50)


def _chain_error(catalog, reference) -> float:
    with mp.workdps(50):
        return max(float(abs(mp.mpf(str(a)) - b) / abs(b))
                   for key in ("potency", "t_start") for a, b in zip(catalog[key], reference[key]))


def test_chain_quad_reads_decimals_in_real128(chain_reference):
    from bifurcation.laws import resolve_law
    from bifurcation.models.chain._loop import ChainLoop

    law, u = resolve_law("piecewise-linear"), np.array([-0.03, 0.0, -0.01])
    exact = ChainLoop(law, 3, 1.0, 1e-3, 0.3, "free", u, precision="quad",
                      exact={"nu": "0.001", "nu_f": "0.3", "ell": "1", "u0": U0}).run(5)
    binary = ChainLoop(law, 3, 1.0, 1e-3, 0.3, "free", u, precision="quad").run(5)
    # measured 6.5e-34 from the decimals (real128's 1.9e-34 tolerance, a few events); 4.1e-17 from
    # their doubles: the inputs' rounding, which a verification mode must not add
    assert _chain_error(exact["catalog"], chain_reference) < 1e-31
    assert _chain_error(binary["catalog"], chain_reference) > 1e-18


def test_chain_and_its_cli_hand_the_decimals_to_the_quad_run(monkeypatch):
    from bifurcation.cli import cli
    from bifurcation.models.chain import _loop, chain

    seen = []
    original = _loop.ChainLoop.__init__

    def spy(self, *args, exact=None, **kw):
        seen.append(exact)
        original(self, *args, exact=exact, **kw)

    monkeypatch.setattr(_loop.ChainLoop, "__init__", spy)
    chain("piecewise-linear", n=3, ell="1", nu="0.001", nu_f="0.3", u0=U0, events=1, precision="quad")
    r = CliRunner().invoke(cli, ["chain", "--law", "piecewise-linear", "--n", "3", "--ell", "1", "--nu", "0.001",
                                 "--nu-f", "0.3", "--u0", ",".join(U0), "--events", "1", "--precision", "quad"])
    assert r.exit_code == 0, r.output
    for exact in seen:
        assert [decimal_text(exact[k]) for k in ("nu", "nu_f", "ell")] == ["0.001", "0.3", "1"]
        assert [decimal_text(x) for x in exact["u0"]] == U0


def test_slip_quad_reads_decimals_in_real128(monkeypatch):
    import heyoka as hy

    import bifurcation as bf
    from bifurcation.engine import _exact

    calls = []
    original = _exact.at_precision
    monkeypatch.setattr(_exact, "at_precision", lambda x, dtype: calls.append((decimal_text(x), dtype)) or
                        original(x, dtype))
    r = bf.slip("piecewise-linear", nu="1e-3", nu_f="0.51", precision="quad")
    assert {("1e-3", hy.real128), ("0.51", hy.real128)} <= set(calls)
    # and the result is the exact cycle's (mpmath, 40 digits, from the same decimals) to double rounding
    from bifurcation.theory.reference import piecewise_linear_exact

    ref = piecewise_linear_exact("1e-3", "0.51", dps=40)["delta"]
    assert abs(float(r.delta) - float(ref)) <= 2.2e-16 * float(ref)


def test_rate_state_quad_reads_decimals_in_real128():
    from bifurcation.models.rate_state import load_history, rate_state
    from bifurcation.models.rate_state.reference import reference_run
    from bifurcation.models.rate_state.spec import SliderSpec

    t = [0.0, 0.25]
    spec = SliderSpec(a="0.011", b="0.015", dc="0.01", state_law="aging", k="0.6", mu0="0.6")
    ref = reference_run(spec, load_history(["1", "3"], at=[0.2]), t, dps=45)   # k > k_c = 0.4: stable

    def error(**kw):
        r = rate_state(state_law="aging", t=t, precision="quad", **kw)
        assert r.status == "ok", r.message
        with mp.workdps(45):
            return max(float(abs(mp.mpf(str(m)) - rm) / abs(rm)) for m, rm in zip(r.mu, ref["mu"]))

    # measured 8e-26 from the decimals (the rest: real128 tolerance over ~2000 steps, the reference's
    # own 36-digit steps) against 3.7e-17 from their doubles
    assert error(a="0.011", b="0.015", dc="0.01", k="0.6", mu0="0.6", v_lp=load_history(["1", "3"], at=[0.2])) < 1e-23
    assert error(a=0.011, b=0.015, dc=0.01, k=0.6, mu0=0.6, v_lp=load_history([1.0, 3.0], at=[0.2])) > 1e-18


def test_limit_quad_reads_decimals_in_real128(monkeypatch):
    """``limit(..., precision="quad")`` hands ν_f's decimal text to the real128 orbit (and, as an mpf of
    that text, to the 60-digit manifold start), not the nearest double; Δ0 is then Eq. (18) of the
    paper at the decimal ν_f to double rounding (the result is returned in double)."""
    import heyoka as hy
    import mpmath

    import bifurcation as bf
    from bifurcation.engine import _exact
    from bifurcation.theory.linear import delta0_piecewise_linear

    calls = []
    original = _exact.at_precision
    monkeypatch.setattr(_exact, "at_precision", lambda x, dtype: calls.append((decimal_text(x), dtype)) or
                        original(x, dtype))
    r = bf.limit("piecewise-linear", nu_f="0.3", precision="quad")
    assert ("0.3", hy.real128) in calls
    with mpmath.workdps(40):
        ref = delta0_piecewise_linear(mpmath.mpf("0.3"))
    assert abs(float(r.delta0) - float(ref)) <= 2.2e-16 * float(ref)


def test_rate_state_quad_slip_is_at_quad_precision():
    # slip = δ_lp − (μ + ηV − μ0 − ηV0)/k: with k, η and the load point's displacement taken through
    # doubles, quad's slip was 6.7e-20 off (measured; μ itself 9e-35) — now 4.7e-35. Reference: the mpmath
    # run's μ and V at 45 digits from the same decimals, the history's step time as the binary 0.2 it is.
    from bifurcation.models.rate_state import load_history, rate_state
    from bifurcation.models.rate_state.reference import reference_run
    from bifurcation.models.rate_state.spec import SliderSpec

    t = [0.0, 0.1, 0.25]
    inputs = dict(a="0.011", b="0.015", dc="0.01", state_law="aging", k="0.6", mu0="0.6", damping="0.3")
    history = load_history(["1", "3"], at=[0.2])
    ref = reference_run(SliderSpec(**inputs), history, t, dps=45)
    r = rate_state(**inputs, v_lp=history, t=t, precision="quad")
    assert r.status == "ok", r.message
    with mp.workdps(45):
        eta, k, step = mp.mpf("0.3"), mp.mpf("0.6"), mp.mpf(0.2)
        tau = [m + eta * v for m, v in zip(ref["mu"], ref["v"])]
        dlp = [min(mp.mpf(s), step) + 3 * max(mp.mpf(s) - step, 0) for s in t]
        slip = [dlp[i] - (tau[i] - tau[0]) / k for i in range(len(t))]
        error = max(float(abs(mp.mpf(str(a)) - b) / abs(b)) for a, b in zip(r.slip[1:], slip[1:]))
    assert error < 1e-31   # measured 4.7e-35 (real128's tolerance 1.9e-34): 3 digits of margin for another CPU
