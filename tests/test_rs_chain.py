"""The rate-and-state Burridge–Knopoff chain (issue 20 item 5; docs/rs-chain.md): one package plus one
registry line, checked against the slider, against itself uncoupled, against an mpmath reference, by a
stress balance per event, and through the store, query, report and the CLI's bad-input path."""

from __future__ import annotations

import json
import math
import textwrap
from pathlib import Path

import numpy as np
import pytest
from click.testing import CliRunner

from bifurcation.cli import cli
from bifurcation.errors import InputError
from bifurcation.models import get_model
from bifurcation.models.rs_chain.result import RSChainStatus
from bifurcation.models.rs_chain.simulate import RSChainSpec, initial_state, run

DATA = Path(__file__).parent / "data"
CATALOG = ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity")
QD = dict(state_law="aging", a=0.01, b=0.015, dc=0.01, k=0.1, v_lp=1.0, eta=1e-3, v_th=10.0)


def test_the_model_is_declared_with_the_chains_catalog_schema():
    model = get_model("rs-chain")
    chain = get_model("chain")
    assert [o.name for o in model.catalog_outputs] == [o.name for o in chain.catalog_outputs] == list(CATALOG)
    assert [o.dtype for o in model.catalog_outputs] == [o.dtype for o in chain.catalog_outputs]
    assert model.catalog_size == "events" and model.catalog_count == "events_done"
    assert model.axis("n").structural and model.runner is not None


def test_one_block_is_the_slider_bit_for_bit():
    # The inertial slip-law slider of docs/rate-state.md's table (b/a = 5, M V²/(a Dc) = 100, κ = 0.15,
    # a limit cycle of period 0.0815579 there): N = 1 compiles the slider's own right-hand side (plus P),
    # so every crossing of V = 1.5 comes at the slider's time; the target is <= 1e-13 relative.
    from bifurcation.models.rate_state.simulate import run_spec
    from bifurcation.models.rate_state.spec import SliderSpec, load_history

    a, b, dc, mass = 0.01, 0.05, 0.01, 0.01
    k = 0.15 * (b - a) / dc * (1 + mass / (a * dc))
    spec = RSChainSpec(n=1, state_law="slip", a=a, b=b, dc=dc, k=k, ell=0.0, v_lp=1.0, mass=mass, eta=0.0, v_th=1.5)
    s0 = initial_state(spec, 0.5, 3)
    r = run(spec, s0, 24, crossings=True)     # past the transient: the last periods are the cycle's
    assert r.status == RSChainStatus.COMPLETE and r.events == 24
    slider = run_spec(SliderSpec(a=a, b=b, dc=dc, state_law="slip", k=k, mass=mass), load_history(1.0),
                      [0.0, r.t_end], thresholds=[1.5], ln_v0=s0[0], ln_theta0=[s0[1]], z0=0.0)
    theirs = slider.crossings[:len(r.crossings)]
    assert np.array_equal(theirs[:, 2], r.crossings[:, 2])
    assert np.max(np.abs(theirs[:, 0] - r.crossings[:, 0]) / r.crossings[:, 0]) <= 1e-13
    assert abs(r.t_start[-1] - r.t_start[-2] - 0.0815579) < 1e-7    # docs/rate-state.md's period, 6 digits


@pytest.mark.parametrize("periodic", [False, True])
def test_uncoupled_blocks_are_independent_sliders(periodic):
    # ℓ = 0: the crossings of block j in a 3-block chain are those of a 1-block run from block j's start
    # (the coupling term is ℓ²k·ΔV = 0 exactly; only the shared step sizes differ: <= 1e-13 relative)
    spec = RSChainSpec(n=3, ell=0.0, periodic=periodic, **QD)
    s0 = initial_state(spec, 1.0, 7)
    r = run(spec, s0, 12, crossings=True)
    assert r.status == RSChainStatus.COMPLETE
    one = RSChainSpec(n=1, ell=0.0, **QD)
    for j in range(3):
        mine = r.crossings[r.crossings[:, 1] == j]
        alone = run(one, np.array([s0[j], s0[3 + j], 0.0]), len(mine) // 2 + 1, crossings=True).crossings
        assert np.array_equal(alone[:len(mine), 2], mine[:, 2])
        assert np.max(np.abs(alone[:len(mine), 0] - mine[:, 0]) / mine[:, 0]) <= 1e-13


def _reference_cases():
    path = DATA / "rs_chain_reference.json"
    return json.loads(path.read_text()) if path.exists() else {}


@pytest.mark.parametrize("name", sorted(_reference_cases()))
def test_catalog_agrees_with_the_mpmath_reference(name):
    # tests/data/rs_chain_reference.json: bifurcation.models.rs_chain.reference at 40 digits, order 30,
    # step tolerance 1e-34 (tests/data/make_rs_chain_reference.py), from the engine's own double start.
    # Target: <= 1e-10 relative on every field of every event (>= 5 events per case).
    ref = _reference_cases()[name]
    case = dict(ref["case"])
    events, amplitude, seed = case.pop("events"), case.pop("amplitude"), case.pop("seed")
    spec = RSChainSpec(**case)
    r = run(spec, initial_state(spec, amplitude, seed), events, crossings=True)
    assert r.events == events >= 5
    assert list(r.n_blocks) == ref["n_blocks"]
    # The hypocentre is compared where the event's first two up-crossings are apart by more than 1e-9 of
    # t: a periodic chain of equal blocks synchronises, and its blocks then cross within rounding of
    # each other (a tie: no first block to compare; n3-slip-periodic from its third event on).
    up = r.crossings[r.crossings[:, 2] == 1]
    for i, t0 in enumerate(r.t_start):
        later = up[(up[:, 0] >= t0) & (up[:, 0] <= t0 + r.duration[i])][:, 0]
        if later.size < 2 or later[1] - later[0] > 1e-9 * t0:
            assert r.hypocentre[i] == ref["hypocentre"][i], i
    for field in ("t_start", "potency", "duration", "max_velocity"):
        want = np.array([float(v) for v in ref[field]])
        err = np.abs(getattr(r, field) - want) / np.abs(want)
        assert np.max(err) <= 1e-10, (field, err)


@pytest.mark.parametrize("name", sorted(_reference_cases()))
def test_a_looser_tolerance_costs_accuracy_in_proportion(name):
    # run(tol=...) (docs/rs-chain.md, "Speed"), against the same mpmath references as above. Measured when
    # written, over the 4 cases and t_start, potency, duration, max_velocity: ≤ 5.7e-14 at tol 1e-13,
    # ≤ 3.7e-13 at 1e-12, ≤ 1.7e-11 at 1e-10 (≈ 0.4 tol). The bound 4 tol leaves a factor ~10 for other
    # CPUs and libm; a catalog at the exact default must stay ≤ 1e-13 (measured ≤ 1.8e-14), and each
    # looser tolerance must be measurably less accurate than the exact default (the knob does something).
    ref = _reference_cases()[name]
    case = dict(ref["case"])
    events, amplitude, seed = case.pop("events"), case.pop("amplitude"), case.pop("seed")
    spec = RSChainSpec(**case)
    worst = {}
    for tol in (None, 1e-12, 1e-10):
        r = run(spec, initial_state(spec, amplitude, seed), events, **({} if tol is None else {"tol": tol}))
        assert r.events == events and list(r.n_blocks) == ref["n_blocks"]
        worst[tol] = max(float(np.max(np.abs(getattr(r, f) / np.array([float(v) for v in ref[f]]) - 1)))
                         for f in ("t_start", "potency", "duration", "max_velocity"))
    assert worst[None] <= 1e-13, worst
    assert worst[1e-12] <= 4e-12 and worst[1e-10] <= 4e-10, worst
    assert worst[1e-10] > worst[1e-12] > worst[None], worst


def test_a_bad_tolerance_is_a_one_line_error():
    spec = RSChainSpec(n=2, ell=1.0, **QD)
    s0 = initial_state(spec, 1.0, 1)
    with pytest.raises(InputError, match=r"tol=1e-05: is outside \[2.22e-16, 1e-08\]; give a tolerance"):
        run(spec, s0, 3, tol=1e-5)
    with pytest.raises(InputError, match=r"tol=0.0: must be > 0"):
        run(spec, s0, 3, tol=0.0)
    with pytest.raises(InputError, match=r"tol='x': is not a number"):
        run(spec, s0, 3, tol="x")


# N = 6 (explicit code, the integrator of tests/test_rs_chain_checkpoint.py) and N = 20 (heyoka's compact mode,
# N > COMPACT_ABOVE = 16, as that file's compact-mode test): the two code paths, on integrators other fast tests
# compile anyway; N = 16 was an explicit integrator no other fast test used (3.6 s of CPU to compile cold)
@pytest.mark.parametrize("n", [6, 20])
def test_stress_balance_per_event_and_that_it_can_fail(n):
    # ΔΣ(μ_j + ηV_j) over an event = k(N V_lp Δt − ΔP): the two sides come from different variables
    # (x, y against the integrated P). Rounding of a sum of N O(1) terms over the stress change of a
    # one-block event (~1e-3): ~1e-12, so 1e-10 is the bound.
    from bifurcation.models.rs_chain._system import COMPACT_ABOVE

    assert (n > COMPACT_ABOVE) == (n == 20)
    spec = RSChainSpec(n=n, ell=1.0, **QD)
    r = run(spec, initial_state(spec, 1.0, 1), 60)
    # (a short event can load more than it slips: its "drop" is negative; the balance holds either way)
    assert r.status == RSChainStatus.COMPLETE and np.all(r.stress_drop != 0)
    assert np.max(r.balance) <= 1e-10
    # the same check with the loading stiffness off by 1e-6 fails on every event
    load = spec.k * (1 + 1e-6) * (spec.n * spec.v_lp * r.duration - r.potency)
    assert np.min(np.abs(-r.stress_drop - load) / np.abs(r.stress_drop)) > 1e-8


def test_bad_inputs_are_one_line_errors_naming_the_argument():
    with pytest.raises(InputError, match=r"v_th=0.5: is not above the plate velocity v_lp = 1; give"):
        RSChainSpec(n=2, k=0.1, ell=1.0, v_lp=1.0, v_th=0.5, state_law="aging", a=0.01, b=0.015, dc=0.01)
    with pytest.raises(InputError, match=r"eta=-1.0: must be >= 0"):
        RSChainSpec(n=2, k=0.1, ell=1.0, v_lp=1.0, eta=-1.0, state_law="aging", a=0.01, b=0.015, dc=0.01)
    with pytest.raises(InputError, match=r"state_law='glue': is not a known state law"):
        RSChainSpec(n=2, k=0.1, ell=1.0, v_lp=1.0, state_law="glue", a=0.01, b=0.015, dc=0.01)
    with pytest.raises(InputError, match=r"n=0: must be a whole number"):
        RSChainSpec(n=0, k=0.1, ell=1.0, v_lp=1.0, state_law="aging", a=0.01, b=0.015, dc=0.01)
    spec = RSChainSpec(n=2, ell=1.0, **QD)
    with pytest.raises(InputError, match=r"amplitude=5.0: starts a block at V >= v_th"):
        initial_state(spec, 5.0, 1)


WORKFLOW = textwrap.dedent("""
    [study]
    name = "rs-chain-test"
    [model]
    name = "rs-chain"
    [engine]
    laws = ["aging", "slip"]
    [grid.n]
    values = [1, 3]
    [grid.k]
    values = [0.1]
    [grid.ell]
    values = [2.0]
    [grid.mass]
    values = [0.0]
    [grid.v_th]
    values = [0.5, 10.0]
    [grid.events]
    values = [15]
    [tiles]
    catalog = 4
    """)


def test_the_store_holds_the_direct_runs_bit_for_bit(tmp_path):
    # in-process: the tiles of the workflow computed and written, one run's catalog read back
    from bifurcation.run.tiles import compute_tile, iter_tiles
    from bifurcation.store import create_store, write_tile
    from bifurcation.store.catalog import read_catalog
    from bifurcation.workflow import parse_workflow

    workflow = parse_workflow(WORKFLOW.replace('"aging", "slip"', '"aging"'))   # one law: fewer compilations
    path = tmp_path / "rs.zarr"
    run_id = create_store(path, workflow)["run_id"]
    for tile in iter_tiles(workflow):
        write_tile(path, tile, compute_tile(tile), run_id)
    cat = read_catalog(path, law="aging", n=3, v_th=10.0)
    spec = RSChainSpec(n=3, ell=2.0, **QD)
    direct = run(spec, initial_state(spec, 1.0, 1), 15)
    for name in CATALOG:
        assert np.array_equal(np.asarray(cat[name]), getattr(direct, name)), name


@pytest.mark.slow
def test_submit_status_query_report_through_the_declaration(tmp_path):
    wf = tmp_path / "rs.toml"
    wf.write_text(WORKFLOW)
    store = tmp_path / "rs.zarr"
    runner = CliRunner()
    res = runner.invoke(cli, ["submit", str(wf), "--store", str(store), "--workers", "1"])
    assert res.exit_code == 0, res.output
    res = runner.invoke(cli, ["status", "--store", str(store)])
    assert res.exit_code == 0 and "8/8 points done" in res.output, res.output
    res = runner.invoke(cli, ["query", "--store", str(store), "--json"])
    rows = json.loads(res.output)
    statuses = {(r["state_law"], r["n"], r["v_th"]): r["status"] for r in rows}
    # v_th = 0.5 is below V_lp = 1: no valid chain, said per point; v_th = 10: 15 events
    assert {s for (_, _, v), s in statuses.items() if v == 0.5} == {"not-applicable"}
    assert {s for (_, _, v), s in statuses.items() if v == 10.0} == {"complete"}
    res = runner.invoke(cli, ["query", "--store", str(store), "--law", "slip", "--n", "3", "--v-th", "10",
                              "--catalog", "--json"])
    assert res.exit_code == 0, res.output
    cat = json.loads(res.output)
    spec = RSChainSpec(n=3, ell=2.0, **{**QD, "state_law": "slip"})
    direct = run(spec, initial_state(spec, 1.0, 1), 15)
    events = cat["events"] if isinstance(cat, dict) and "events" in cat else cat
    got = np.array([e["potency"] for e in events]) if isinstance(events, list) else np.asarray(cat["potency"])
    assert np.array_equal(got, direct.potency)      # the store holds the direct run bit for bit
    out = tmp_path / "report"
    res = runner.invoke(cli, ["report", "--store", str(store), "--out", str(out)])
    assert res.exit_code == 0, res.output
    text = (out / "REPORT.md").read_text()
    assert "Rate-and-state chain runs and their catalogs" in text and "not-applicable" in text


def test_a_bad_workflow_is_one_line_exit_2_before_any_work(tmp_path):
    runner = CliRunner()
    for bad, needle in [(WORKFLOW.replace('"aging", "slip"', '"glue"'), "glue"),
                        (WORKFLOW.replace("values = [0.1]", "values = [-0.1]"), "k")]:
        wf = tmp_path / "bad.toml"
        wf.write_text(bad)
        res = runner.invoke(cli, ["submit", str(wf), "--store", str(tmp_path / "bad.zarr"), "--workers", "1"])
        assert res.exit_code == 2, res.output
        lines = [line for line in res.output.splitlines() if line.strip()]
        assert len(lines) == 1 and needle in lines[0], res.output
        assert not (tmp_path / "bad.zarr").exists()


@pytest.mark.slow
def test_bench_hook_runs_and_reports_ratios():
    from bifurcation.models.rs_chain._bench import run_rs_chain_bench

    out = run_rs_chain_bench(repeat=1, cases=((2, 1.0, 12),), rtols=(1e-8,), lsoda_rtols=(1e-8,),
                             engine_tols=(1e-10,), grid_seeds=2, echo=None)
    row = out["cases"][0]
    assert row["engine_events_per_s"] > 0 and row["lsoda"][0]["events_found"] >= 10
    assert row["dop853"][0]["events_found"] >= 10 and row["dop853"][0]["ratio"] > 0
    assert math.isfinite(row["lsoda"][0]["max_rel_error_first_10"])
    # the looser engine: less accurate than the exact one (err 0 by definition), still within 1e-8
    assert 0 < row["engine_tol"][0]["max_rel_error_first_10"] < 1e-8
    # the grid: the batch engine's catalogs are the scalar ones to rounding (tests/test_rs_chain_batch.py)
    grid = row["grid"]
    assert grid["seeds"] == 2 and grid["batch_max_rel_error_first_10"] < 1e-10 and grid["ratio"] > 0


@pytest.mark.slow   # ~10-25 s: numba compiles the DOP853 loop
def test_compiled_baselines_integrate_the_engines_equations():
    # The bench's baselines (models/rs_chain/_baseline.py) write the chain out by hand in numba. Their
    # right-hand side must be the engine's (_system.rhs_expressions evaluated on floats: 1e-13 relative, a
    # few roundings), their Jacobian its derivative (central differences, step 1e-6: error ~1e-9 relative
    # to the largest entry), and the compiled DOP853's catalog the engine's: at rtol = atol = 1e-12 its first
    # 10 events agree to 1e-9 (measured 2.4e-11 at N = 4; the engine agrees with mpmath to 1.8e-14).
    pytest.importorskip("numba")
    pytest.importorskip("scipy")
    from bifurcation.models.rs_chain._baseline import build, dop853_catalog
    from bifurcation.models.rs_chain._system import Layout, rhs_expressions

    k = build()
    spec = RSChainSpec(n=4, ell=1.0, **QD)
    layout = Layout(4, False)
    u = initial_state(spec, 1.0, 1)
    u[4:8] += np.array([0.3, -0.2, 0.1, -0.4])       # off steady state: every term of ẏ counts
    args = (4, spec.a, spec.b, spec.dc, spec.k, spec.ell ** 2, spec.v_lp, spec.eta)
    ours = np.array(rhs_expressions(spec.law, layout, list(u), spec.parameters(), math.exp, math.log,
                                    periodic=False, damped=True), dtype=float)
    theirs = k["rhs"](0.0, u, *args)
    assert np.allclose(theirs, ours, rtol=1e-13, atol=1e-13 * np.max(np.abs(ours)))
    jac = k["jac"](0.0, u, *args)
    eps = 1e-6
    fd = np.empty_like(jac)
    for i in range(u.size):
        up, dn = u.copy(), u.copy()
        up[i] += eps
        dn[i] -= eps
        fd[:, i] = (k["rhs"](0.0, up, *args) - k["rhs"](0.0, dn, *args)) / (2 * eps)
    assert np.max(np.abs(jac - fd)) < 1e-7 * np.max(np.abs(jac))
    ref = run(spec, initial_state(spec, 1.0, 1), 12)
    base = dop853_catalog(spec, initial_state(spec, 1.0, 1), 1.5 * ref.t_end, 12, 1e-12, 1e-12)
    for name in ("t_start", "potency", "duration"):
        assert np.max(np.abs(base[name][:10] / getattr(ref, name)[:10] - 1)) < 1e-9, name


def test_massless_undamped_blow_up_is_a_status_not_a_number():
    # M = 0, η = 0 is the slider's quasi-static system: below k_c = (b − a)/Dc = 0.5 V blows up in finite
    # time (the slider's "stalled"); the run keeps the events before and says what to change
    spec = RSChainSpec(n=1, ell=0.0, **{**QD, "eta": 0.0, "k": 0.3})
    r = run(spec, initial_state(spec, 0.1, 1), 5)
    assert r.status == RSChainStatus.NONFINITE and r.events < 5
    assert "give η > 0 or M > 0" in r.message
    assert np.all(np.isfinite(r.potency))


@pytest.mark.slow   # numba compiles the DOP853 loop (~4 s of CPU), then a one-case suite
def test_bench_suite_rs_chain_says_on_stderr_which_case_runs(monkeypatch):
    """`bifurcation bench --suite rs-chain` printed its header, then nothing for over 120 s (issue 21, walk 4):
    the compile and each case's stages are lines on stderr; the results stay on stdout."""
    from bifurcation.models.rs_chain._bench import run_rs_chain_bench

    # its defaults (repeat, cases, rtols, lsoda_rtols, engine_tols, grid_seeds, echo, progress) made small
    assert len(run_rs_chain_bench.__defaults__) == 8
    monkeypatch.setattr(run_rs_chain_bench, "__defaults__", (1, ((2, 1.0, 12),), (1e-8,), (1e-8,), (1e-10,), 2,
                                                             print, None))
    result = CliRunner().invoke(cli, ["bench", "--suite", "rs-chain"])
    assert result.exit_code == 0, result.output
    lines = result.stderr.splitlines()
    assert lines and all(l.startswith("bifurcation: bench: ") and l.endswith(" s]") for l in lines), lines
    assert lines[0].startswith("bifurcation: bench: compiling the numba baselines"), lines
    assert "case 1 of 1 (N = 2, ℓ = 1): 12 events by the engine" in lines[1]
    assert any("scipy LSODA" in l for l in lines) and any("a grid of 2 chains" in l for l in lines), lines
    assert "bifurcation: bench" not in result.stdout and "N =    2 ℓ = 1, 12 events: engine" in result.stdout
