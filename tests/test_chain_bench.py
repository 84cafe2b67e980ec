"""The chain benchmark's machinery (never its timings: speed is measured by ``bifurcation bench``)."""

from __future__ import annotations

import numpy as np
import pytest

from bifurcation.laws import resolve_law
from bifurcation.models.chain._bench import _steady_start, rk4_chain, run_chain_bench
from bifurcation.models.chain._loop import ChainLoop
from bifurcation.models.chain._validate import check_initial, stress


def test_the_steady_start_is_the_state_after_the_transient():
    """σ_j = ℓ²(ΔU)_j − U_j + νt depends on U and t only through U − νt: the handed-over start
    U − νt at t = 0 has the stresses the exact engine holds after the transient, to the rounding of
    U − νt (|U|, νt ~ 10 here, so a few 1e-15), and the next five events of both loops are the same
    (potencies to 1e-9: the rounding difference grows in a chaotic chain, but not by 1e5 in 5 events)."""
    law, n, ell, nu, nu_f = resolve_law("carlson-langer"), 16, 1.0, 1e-3, 0.2
    u0 = check_initial(n, ell, "free", None, 0.1, 3)
    start = _steady_start(law, n, ell, nu, nu_f, u0, 40, 8)
    loop = ChainLoop(law, n, ell, nu, nu_f, "free", u0)
    loop.run(40)
    assert np.max(np.abs(stress(start, ell, "free") - loop.sigma)) <= 1e-13
    again = ChainLoop(law, n, ell, nu, nu_f, "free", start).run(5)["catalog"]
    after = loop.run(5)["catalog"]
    assert again["hypocentre"] == after["hypocentre"] and again["n_blocks"] == after["n_blocks"]
    np.testing.assert_allclose(again["potency"], after["potency"], rtol=1e-9)


@pytest.mark.slow   # 8 s; the baselines' catalogs stay in the fast suite (test_numba_rk4_baselines_are_the_interpreted_rk4)
def test_the_suite_reports_rates_and_ratios_at_every_step():
    """One tiny case: the report carries the compiled engine's rate and its verification, and per
    baseline (numba RK4 active set and whole chain, numpy RK4) and dt the rate, KS distances in [0, 1]
    and the ratio compiled/baseline computed from the two rates."""
    out = run_chain_bench(cases=((1e-3, 8, 20, 5),), dts=(0.2, 0.1), verify=0.25, echo=None)
    (row,) = out["rows"]
    assert (row["nu"], row["n"], row["events"], row["transient"]) == (1e-3, 8, 20, 5)
    assert [(r["kind"], r["dt"]) for r in row["numba"]] == [("active", 0.2), ("active", 0.1), ("plain", 0.2),
                                                             ("plain", 0.1)]
    assert [r["dt"] for r in row["rk4"]] == [0.2, 0.1]
    for r in row["numba"] + row["rk4"]:
        assert 0 <= r["ks"] <= 1 and 0 <= r["ks_magnitude"] <= 1
        assert r["ratio"] == row["compiled_events_per_s"] / r["events_per_s"]
    assert row["verify"]["checked"] == 5 and row["verify"]["mismatched"] == []
    assert row["verify"]["largest_any"] <= 1e-10
    assert row["exact_events_per_s"] > 0
    u0 = check_initial(8, 1.0, "free", None, 0.1, 1)
    assert len(rk4_chain("carlson-langer", n=8, ell=1.0, nu=1e-3, nu_f=0.2, u0=u0, events=7, dt=0.2)["potency"]) == 7


def test_numba_rk4_baselines_are_the_interpreted_rk4():
    """The compiled baselines step the same equations as ``rk4_chain`` (stuck blocks held by
    max(σ − 1, 0), clipped velocities): the whole-chain version gives its catalog to rounding over a
    few events (1e-9: operations ordered differently, a chaotic chain); the active-set version the
    same sizes (it steps a block only once a neighbour moved, a difference at the step's rounding)."""
    from bifurcation.models.chain._bench_rk4 import run_rk4

    u0 = check_initial(16, 1.0, "free", None, 0.1, 4)
    kw = dict(n=16, ell=1.0, nu=1e-4, nu_f=0.2, u0=u0, events=6, dt=0.1)
    ref = rk4_chain("carlson-langer", **kw)
    plain = run_rk4("plain", "carlson-langer", **kw)
    active = run_rk4("active", "carlson-langer", **kw)
    np.testing.assert_allclose(plain["potency"], ref["potency"], rtol=1e-9)
    np.testing.assert_array_equal(plain["n_blocks"], ref["n_blocks"])
    np.testing.assert_array_equal(active["n_blocks"], ref["n_blocks"])
    np.testing.assert_allclose(active["potency"], ref["potency"], rtol=1e-6)


def test_the_stop_phase_model_stops_where_the_lone_trajectory_stops():
    """``run_stop_phase`` (docs/chain.md, "Why N = 64 and 256 stay below 1.0×") counts Taylor steps to a lone
    block's stop with τ, s (dτ = (1 + x) ds) and v as the independent variable. Its three series are checked by
    where they put the stop: the lone interior block's stop time from heyoka's stored trajectory (``_lone``,
    tolerance 2.2e-16, an independent integrator), to 1e-11 (the model's steps are at tol 1e-11 relative to
    O(1–10^3) scaled values, ≤ 9 of them; measured 6e-13). The pole of Φ past the stop comes after it, and
    removing it (s) never takes more steps than τ from the same point (the docs' claim)."""
    from bifurcation.models.chain._bench import run_stop_phase
    from bifurcation.models.chain._lone import trajectory

    law, nu, nu_f, ell = resolve_law("carlson-langer"), 1e-4, 0.2, 1.0
    t_ref = trajectory(law, nu, nu_f, ell, 0.0, 0)["T"]
    out = run_stop_phase(nu=nu, nu_f=nu_f, ell=ell, echo=None)
    assert abs(out["t_stop"] - t_ref) <= 1e-11
    assert out["t_pole"] > out["t_stop"] + 0.05
    for row in out["rows"]:
        for var in ("tau", "s", "v"):
            assert abs(row[f"stop_{var}"] - t_ref) <= 1e-11, (row, var)
        assert 1 <= row["s"] <= row["tau"]


def test_event_shares_partition_the_catalog_and_one_block_events_take_no_step():
    """``run_event_shares`` (docs/chain.md, "Issue 18's ideas for N = 64 and 256") splits a compiled catalog by event
    size: its rows partition the events and the steps (each share sums to 1 to rounding), and no one-block event took
    a Taylor step (on a free chain the stored lone trajectory, ``_lone``, ends every one: interior or end block).
    (Not every two-block event takes steps: two lone blocks far apart in one event do not, 0.9 % of events at N = 64.)"""
    from bifurcation.models.chain._bench import run_event_shares

    rows = run_event_shares(sizes=(32,), events=400, transient=200, echo=None)["rows"]
    assert abs(sum(r["events"] for r in rows) - 1.0) < 1e-12
    assert abs(sum(r["steps"] for r in rows) - 1.0) < 1e-12
    assert rows[0]["events"] > 0.5 and rows[1]["events"] > 0.0      # both kinds occur at this N and ν
    assert rows[0]["stepped"] == 0.0 and rows[0]["steps"] == 0.0
    assert rows[1]["stepped"] > 0.0 and rows[1]["steps_per_event"] > 5.0    # a pair event is integrated


def test_bench_suite_chain_says_on_stderr_which_case_runs(monkeypatch):
    """`bifurcation bench --suite chain` printed its header, then nothing for over 120 s (issue 21, walk 4):
    now each case and stage is a line on stderr (the numba compile too, or that it loads from the cache),
    the results stay on stdout. A one-case suite (the CLI's own hook, smaller defaults)."""
    from click.testing import CliRunner

    from bifurcation.cli import cli

    monkeypatch.setitem(run_chain_bench.__kwdefaults__, "cases", ((1e-3, 8, 20, 5),))
    monkeypatch.setitem(run_chain_bench.__kwdefaults__, "dts", (0.2,))
    monkeypatch.setitem(run_chain_bench.__kwdefaults__, "verify", 0.25)
    result = CliRunner().invoke(cli, ["bench", "--suite", "chain"])
    assert result.exit_code == 0, result.output
    lines = result.stderr.splitlines()
    assert lines and all(l.startswith("bifurcation: bench: ") and l.endswith(" s]") for l in lines), lines
    assert ("compiling the chain engine for carlson-langer" in lines[0]
            or "loading them from numba's disk cache" in lines[0]), lines[0]
    stages = [l.split(": ", 3)[-1] for l in lines[1:]]
    assert stages[0].startswith("5 transient events, then 20 timed events") and "case 1 of 1 (ν = 0.001, N = 8)" in lines[1]
    for what in ("DOP853", "verify", "exact (heyoka)", "numba RK4", "interpreted numpy RK4"):
        assert any(what in s for s in stages), (what, stages)
    assert "bifurcation: bench" not in result.stdout and "ν = 0.001, N =     8: compiled" in result.stdout
