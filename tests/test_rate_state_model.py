"""The rate-state model of the registry (issue 11): workflow → submit → store → query / status / report.

References: the closed forms k_c = (b − a)/Dc·[1 + M V²/(a Dc)], ω_c = (V/Dc)√((b − a)/a) (Ruina 1983;
Rice & Ruina 1983; derived in docs/rate-state.md) and the period of a cycle from a direct run of the
engine (``rate_state``) that starts from the same perturbed steady slide and is read between its own
threshold events, independently of the shooting Newton that gave the stored value.
"""

from __future__ import annotations

import math
import textwrap

import numpy as np
import pytest
from click.testing import CliRunner

from bifurcation.cli import cli
from bifurcation.errors import InputError
from bifurcation.models import get_model
from bifurcation.models.rate_state.model import RateStateStatus, label_identity, resolve_label
from bifurcation.run.tiles import compute_serial
from bifurcation.store import open_store
from bifurcation.workflow import parse_workflow

WORKFLOW = textwrap.dedent("""
    [study]
    name = "rs"
    [model]
    name = "rate-state"
    [engine]
    laws = ["aging", "ruina"]
    [grid.kappa]
    values = [0.5, 0.9, 1.5]
    [grid.mass]
    values = [0.0, 1e-5]
    [tiles]
    kappa = 2
    """)


def test_labels_canonicalise_aliases_and_refuse_unknown_laws():
    assert resolve_label("dieterich + ruina") == ("aging", "slip")
    with pytest.raises(InputError, match=r"state_law='RUINA': is not a known state law \(names are lower case\)"):
        resolve_label("dieterich+RUINA")   # spelled exactly, as every choice of the CLI (walk 7)
    assert label_identity("perrin") == "prz" and label_identity("slip+aging") == "slip+aging"
    with pytest.raises(InputError, match="state_law='frob': is not a known state law"):
        resolve_label("frob")
    with pytest.raises(InputError, match="names 3 state variables"):
        resolve_label("aging+slip+prz")
    w = parse_workflow(WORKFLOW)
    assert w.laws == ("aging", "ruina") and w.shape == (2, 3, 1, 1, 1, 1, 2, 1, 1, 1)
    # the defaults stand in for the axes left out
    assert (w.v_lp, w.a, w.b, w.dc, w.b2, w.dc2, w.damping) == ((1.0,), (0.01,), (0.015,), (0.01,), (0.0,), (0.1,), (0.0,))


def test_workflow_round_trips_with_its_defaults_written_out():
    w = parse_workflow(WORKFLOW)
    again = parse_workflow(w.to_toml())
    assert again == w and again.fingerprint == w.fingerprint and "[grid.dc2]" in w.to_toml()


@pytest.fixture(scope="module")
def submitted(tmp_path_factory):
    root = tmp_path_factory.mktemp("rs")
    wf = root / "rs.toml"
    wf.write_text(WORKFLOW)
    store = root / "rs.zarr"
    r = CliRunner().invoke(cli, ["submit", str(wf), "--store", str(store), "--workers", "1"])
    assert r.exit_code == 0, r.output
    return wf, store, r.output


def test_submit_reports_the_models_statuses(submitted):
    _, _, output = submitted
    assert "12 computed" in output and "steady-sliding 4" in output and "limit-cycle 4" in output
    assert "unbounded-growth 4" in output and "stick-slip" not in output


def test_store_equals_the_serial_engine_bit_for_bit(submitted):
    wf, store, _ = submitted
    reference = compute_serial(parse_workflow(wf.read_text()))
    ds = open_store(store)
    assert ds.attrs["model"] == "rate-state"
    for name, values in reference.items():
        stored = np.asarray(ds[name].values)
        if stored.dtype.kind == "f":
            stored, values = stored.view(np.int64), values.view(np.int64)
        np.testing.assert_array_equal(stored, values, err_msg=name)


def test_stored_hopf_points_equal_the_closed_forms(submitted):
    _, store, _ = submitted
    ds = open_store(store)
    a, b, dc, v = 0.01, 0.015, 0.01, 1.0
    for m, mass in enumerate((0.0, 1e-5)):
        k_c = (b - a) / dc * (1 + mass * v * v / (a * dc))
        omega = v / dc * math.sqrt((b - a) / a)
        got = ds["k_c"].values[:, :, 0, 0, 0, 0, m, 0, 0, 0]
        # found by mpmath at 30 digits, rounded to double: a few ulps of the closed form
        np.testing.assert_allclose(got, k_c, rtol=1e-14)
        np.testing.assert_allclose(ds["omega_c"].values[:, :, 0, 0, 0, 0, m, 0, 0, 0], omega, rtol=1e-14)
        np.testing.assert_allclose(ds["k"].values[:, :, 0, 0, 0, 0, m, 0, 0, 0], k_c * np.array([[0.5, 0.9, 1.5]] * 2),
                                   rtol=1e-14)
    crit = ds["criticality"].values[:, 0, 0, 0, 0, 0, :, 0, 0, 0]
    # quasi-static aging and slip: degenerate (3); with η = M V²/(a Dc) = 0.1 aging is subcritical (1)
    # below its Bautin point η ≈ 0.138 and slip supercritical (2) (docs/rate-state.md)
    assert crit.tolist() == [[3, 1], [3, 2]]


def test_fates_along_kappa(submitted):
    _, store, _ = submitted
    ds = open_store(store)
    status = ds["status"].values[:, :, 0, 0, 0, 0, :, 0, 0, 0]
    S = RateStateStatus
    # quasi-static: below k_c V blows up (no bounded cycle), above it sliding is restored;
    # with inertia, stable cycles below k_c
    for law in range(2):
        assert status[law, :, 0].tolist() == [S.UNBOUNDED_GROWTH, S.UNBOUNDED_GROWTH, S.STEADY_SLIDING]
        assert status[law, :, 1].tolist() == [S.LIMIT_CYCLE, S.LIMIT_CYCLE, S.STEADY_SLIDING]
    cyc = status == S.LIMIT_CYCLE
    assert np.all(np.isfinite(ds["period"].values[:, :, 0, 0, 0, 0, :, 0, 0, 0][cyc]))
    assert np.all(np.isnan(ds["period"].values[:, :, 0, 0, 0, 0, :, 0, 0, 0][~cyc]))
    assert np.all(ds["multiplier_max"].values[:, :, 0, 0, 0, 0, :, 0, 0, 0][cyc] < 1)


@pytest.mark.parametrize("law", ["aging", "slip"])
def test_cycle_period_and_extrema_against_a_direct_run(submitted, law):
    # The direct run: the same start, 80 linear periods without any Newton; the cycle's multiplier
    # (< 0.62 here) shrinks the transient below rounding long before; the period is read between the
    # last two upward crossings of V_lp (exact events), the extrema from the last cycle's ẋ = 0 events.
    from bifurcation.models.rate_state import rate_state

    _, store, _ = submitted
    ds = open_store(store)
    i = 0 if law == "aging" else 1
    for j, kappa in ((0, 0.5), (1, 0.9)):
        k = float(ds["k"].values[i, j, 0, 0, 0, 0, 1, 0, 0, 0])
        period = float(ds["period"].values[i, j, 0, 0, 0, 0, 1, 0, 0, 0])
        r = rate_state(a=0.01, b=0.015, dc=0.01, state_law=law, k=k, mass=1e-5, v_lp=1.0,
                       t=[0.0, 80 * period], v0=math.exp(1e-2), theta0=[0.01], thresholds=[1.0])
        ups = r.crossings[r.crossings[:, 2] > 0, 0]
        # double arithmetic over 80 periods, two event times of O(10) each rounded to ~1e-15 relative
        assert ups[-1] - ups[-2] == pytest.approx(period, rel=1e-10), (law, kappa)
        last = r.extrema[r.extrema[:, 0] > ups[-2]]
        assert last[:, 1].max() == pytest.approx(float(ds["ln_v_max"].values[i, j, 0, 0, 0, 0, 1, 0, 0, 0]),
                                                 abs=1e-9)
        assert last[:, 1].min() == pytest.approx(float(ds["ln_v_min"].values[i, j, 0, 0, 0, 0, 1, 0, 0, 0]),
                                                 abs=1e-9)


def test_query_status_and_report_serve_the_store(submitted, tmp_path):
    _, store, _ = submitted
    r = CliRunner().invoke(cli, ["query", "--store", str(store), "--law", "dieterich", "--mass", "1e-5",
                                 "--kappa", "0.5", "--json"])
    assert r.exit_code == 0, r.output
    import json

    (rec,) = json.loads(r.stdout)
    assert rec["state_law"] == "aging" and rec["status"] == "limit-cycle" and rec["period"] > 0
    r = CliRunner().invoke(cli, ["status", "--store", str(store)])
    assert r.exit_code == 0 and "12/12 points done" in r.output and "0 failed" in r.output, r.output
    r = CliRunner().invoke(cli, ["report", "--store", str(store), "--out", str(tmp_path / "rep")])
    assert r.exit_code == 0, r.output
    md = (tmp_path / "rep" / "REPORT.md").read_text()
    assert "Model rate-state" in md and "| dθ/dt = 1 − Vθ/Dc |" in md and "subcritical" in md
    assert "0.9 (unbounded-growth) → 1.5 (steady-sliding)" in md


def test_points_the_engine_cannot_vouch_for_get_a_status():
    from bifurcation.engine.solve import solve

    S = RateStateStatus
    base = {"kappa": [0.9], "v_lp": 1.0, "a": 0.01, "b": 0.015, "dc": 0.01, "mass": 0.0, "b2": 0.0, "dc2": 0.1, "damping": 0.0}
    out = solve(get_model("rate-state"), "aging", {**base, "b": [0.005]})       # b < a: velocity strengthening
    assert out["status"][0] == S.NO_HOPF_POINT and math.isnan(out["k_c"][0])
    out = solve(get_model("rate-state"), "aging", {**base, "b2": [0.01]})       # b2 for a one-variable label
    assert out["status"][0] == S.NOT_APPLICABLE and "one" in out["messages"][0]
    # a step budget too small for the run: not resolved, with no number
    model = get_model("rate-state")
    fields, messages = model.runner(model, "aging", {k: np.atleast_1d(np.asarray(v, dtype=float))
                                                     for k, v in {**base, "mass": 1e-5}.items()},
                                    precision="double", t_max=1e5, max_steps=50, batch=1)
    assert fields["status"][0] == S.NOT_RESOLVED and math.isnan(fields["period"][0])
    assert "step budget spent" in messages[0]


def test_two_state_variables_take_b2_and_dc2():
    from bifurcation.engine.solve import solve
    from bifurcation.models.rate_state.hopf import hopf_point

    pts = {"kappa": [0.9], "v_lp": 1.0, "a": 0.01, "b": 0.012, "dc": 0.01, "mass": 0.0, "b2": 0.006, "dc2": 0.1, "damping": 0.0}
    out = solve(get_model("rate-state"), "aging+slip", pts)
    h = hopf_point(a=0.01, b=[0.012, 0.006], dc=[0.01, 0.1], state_law=["aging", "slip"], v_lp=1.0, dps=30)
    assert out["k_c"][0] == h.k_c and out["status"][0] == RateStateStatus.LIMIT_CYCLE
    assert out["criticality"][0] == 2   # supercritical: a small stable cycle below k_c


@pytest.mark.parametrize("edit,message", [
    (("[grid.mass]", "[grid.a]\nvalues = [0.0]\n[grid.mass]"), "grid.a.values[0]=0.0"),
    (("[grid.mass]", "[grid.b]\nvalues = [-0.1]\n[grid.mass]"), "grid.b.values[0]=-0.1"),
    (("[grid.mass]", "[grid.dc]\nvalues = [0]\n[grid.mass]"), "grid.dc.values[0]=0"),
    (("values = [0.5, 0.9, 1.5]", "values = [0.0, 0.9]"), "grid.kappa.values[0]=0.0"),
    (('"ruina"', '"frob"'), "engine.laws[1]='frob': is not a known state law"),
    (('"ruina"', '"aging+slip+prz"'), "names 3 state variables"),
    (("[grid.kappa]\nvalues = [0.5, 0.9, 1.5]\n", ""), "grid.kappa"),      # the one axis without a default
    (("[grid.mass]\nvalues = [0.0, 1e-5]", "[grid.mass]\nvalues = [-1e-5]"), "grid.mass.values[0]=-1e-05"),
])
def test_bad_input_is_one_line_exit_2_and_writes_nothing(tmp_path, edit, message):
    wf = tmp_path / "bad.toml"
    wf.write_text(WORKFLOW.replace(*edit))
    store = tmp_path / "bad.zarr"
    r = CliRunner().invoke(cli, ["submit", str(wf), "--store", str(store)])
    assert r.exit_code == 2, r.output
    assert len(r.output.strip().splitlines()) == 1 and message in r.output, r.output
    assert not store.exists()


def test_a_deep_inertial_slip_cycle_against_a_direct_run():
    # Stick-slip-like: slip law, b/a = 5, η = M V_lp²/(a Dc) = 100, κ = 0.1: V drops 8 decades below V_lp
    # (docs/rate-state.md, "Where cycles become stick-slip-like"). The direct run starts from the same
    # perturbed slide and runs 60 periods (measured: the oscillation grows from the slide for ~40 turns,
    # then the multiplier 0.07 per turn settles it; from turn 45 on successive intervals agree to 1e-12);
    # its period between exact V = V_lp events and its ln V minimum must match the Newton cycle.
    from bifurcation.engine.solve import solve
    from bifurcation.models.rate_state import rate_state

    pts = {"kappa": [0.1], "v_lp": 1.0, "a": 0.01, "b": 0.05, "dc": 0.01, "mass": 1e-2, "b2": 0.0, "dc2": 0.1, "damping": 0.0}
    out = solve(get_model("rate-state"), "slip", pts, max_steps=1_000_000)
    assert out["status"][0] == RateStateStatus.LIMIT_CYCLE
    period, k = float(out["period"][0]), float(out["k"][0])
    assert out["ln_v_min"][0] < -18.6 and out["multiplier_max"][0] < 0.1
    r = rate_state(a=0.01, b=0.05, dc=0.01, state_law="slip", k=k, mass=1e-2, v_lp=1.0, t=[0.0, 60 * period],
                   v0=math.exp(1e-2), theta0=[0.01], thresholds=[1.0], max_steps=3_000_000)
    assert r.status == "ok"
    ups = r.crossings[r.crossings[:, 2] > 0, 0]
    assert ups[-1] - ups[-2] == pytest.approx(period, rel=1e-10)
    last = r.extrema[r.extrema[:, 0] > ups[-2]]
    assert last[:, 1].min() == pytest.approx(float(out["ln_v_min"][0]), abs=1e-9)


@pytest.mark.slow   # 3 s; V_lp as a continuation parameter stays fast in test_rate_state_cycles.py
def test_v_lp_only_rescales_a_point_at_fixed_eta():
    # In τ = t V_lp/Dc and ln(V/V_lp) the equations contain V_lp only through η = M V_lp²/(a Dc)
    # (docs/rate-state.md): over 12 decades of V_lp at η = 0.1 the stored cycle has the same V_lp·T and
    # ln(V_min/V_lp), up to the shooting tolerance; quasi-static k_c = (b − a)/Dc does not move.
    from bifurcation.engine.solve import solve

    rows = []
    for v in (1e-9, 1.0, 1e3):
        out = solve(get_model("rate-state"), "slip", {"kappa": [0.5, 1.5], "v_lp": v, "a": 0.01, "b": 0.015, "dc": 0.01,
                                           "mass": 1e-5 / v ** 2, "b2": 0.0, "dc2": 0.1, "damping": 0.0})
        assert out["status"].tolist() == [RateStateStatus.LIMIT_CYCLE, RateStateStatus.STEADY_SLIDING]
        assert out["k_c"][0] == pytest.approx(0.55, rel=1e-14)   # (b − a)/Dc · (1 + η), η = 0.1
        rows.append((v * out["period"][0], out["ln_v_min"][0] - math.log(v), out["ln_v_max"][0] - math.log(v)))
    for row in rows[1:]:
        np.testing.assert_allclose(row, rows[0], rtol=1e-9, atol=1e-9)


def test_damping_axis_gives_the_damped_hopf_point_and_cycle():
    # One tile with η = 1 (the QDYN cases' units: a = 0.01, b = 0.015, Dc = 1e-4, V_lp = 1e-3):
    # k_c = (b − a − ηV)/Dc = 40 (docs/rate-state.md), a cycle at κ = 0.8 that is the `--cycle` result
    # (same engine and Newton: equal to 1e-12), steady sliding at κ = 1.2, and ηV_lp ≥ b − a
    # (η = 6) gives no Hopf point.
    from bifurcation.models.rate_state import SliderSpec
    from bifurcation.models.rate_state.cycle import limit_cycle

    w = parse_workflow(textwrap.dedent("""
        [study]
        name = "rs-damped"
        [model]
        name = "rate-state"
        [engine]
        laws = ["slip"]
        [grid.kappa]
        values = [0.8, 1.2]
        [grid.v_lp]
        values = [1e-3]
        [grid.dc]
        values = [1e-4]
        [grid.damping]
        values = [1.0, 6.0]
        """))
    fields = compute_serial(w)
    status = fields["status"].reshape(2, 2)   # kappa × damping
    k_c = fields["k_c"].reshape(2, 2)
    assert list(status[:, 0]) == [RateStateStatus.LIMIT_CYCLE, RateStateStatus.STEADY_SLIDING]
    assert list(status[:, 1]) == [RateStateStatus.NO_HOPF_POINT] * 2
    assert k_c[0, 0] == pytest.approx(40.0, rel=1e-14)
    c = limit_cycle(SliderSpec(a=0.01, b=0.015, dc=1e-4, state_law="slip", k=0.8 * k_c[0, 0], damping=1.0), 1e-3)
    assert fields["period"].reshape(2, 2)[0, 0] == pytest.approx(c.period, rel=1e-12)
