"""Cycles of the rate-state slider: continuation from the Hopf point, Floquet multipliers, folds, store."""

import math

import numpy as np
import pytest
import xarray as xr
from click.testing import CliRunner

from bifurcation.cli import cli
from bifurcation.models.rate_state.continuation import continue_cycles, period_by_simulation

SLIDER = dict(a=0.01, b=0.015, dc=0.01, v_lp=1.0)


def test_subcritical_quasi_static_prz_branch_is_unstable_and_bends_to_k_above_k_c():
    # l1 > 0 (test_rate_state_hopf): the cycles born at k_c exist for k > k_c and are unstable
    # (a multiplier > 1, growing with the amplitude); their period starts at 2π/ω_c.
    br = continue_cycles(state_law="prz", points=8, max_step=0.5, **SLIDER)
    assert br.hopf.criticality == "subcritical" and len(br.points) == 8 and not br.folds
    kappas = [p.kappa for p in br.points]
    assert all(k > 1 for k in kappas[2:]) and kappas == sorted(kappas)
    mult = [max(abs(z) for z in p.multipliers) for p in br.points]
    assert all(m > 1 for m in mult[2:]) and mult[2:] == sorted(mult[2:])
    assert br.points[0].period == pytest.approx(2 * math.pi / br.hopf.omega_c, rel=1e-5)  # amplitude 1e-3
    for i in (0, 4, 7):
        # An independent turn of the cycle (double: a step grid not aligned with the section; real128).
        assert period_by_simulation(br, i) == pytest.approx(br.points[i].period, rel=1e-10)
        assert period_by_simulation(br, i, "quad") == pytest.approx(br.points[i].period, rel=1e-10)


def test_inertial_aging_branch_turns_at_a_fold_and_becomes_stable():
    # η = M V²/(a Dc) = 0.1 is below the aging law's Bautin point (η ≈ 0.138): subcritical, so the branch
    # leaves k_c upwards, unstable, folds (measured κ_f ≈ 1.00124) and comes back stable below k_c.
    br = continue_cycles(state_law="aging", mass=0.1 * 0.01 * 0.01, points=10, max_step=0.5, **SLIDER)
    assert br.hopf.criticality == "subcritical"
    assert len(br.folds) == 1
    i = br.folds[0]
    assert 1.0005 < br.points[i].kappa < 1.002
    assert max(abs(z) for z in br.points[1].multipliers) > 1
    last = br.points[-1]
    assert last.kappa < 1 and max(abs(z) for z in last.multipliers) < 1
    assert all(p.residual < 1e-10 for p in br.points) and all(p.status == "ok" for p in br.points)


def test_degenerate_quasi_static_aging_family_stays_at_k_c():
    # Ranjith & Rice (1999): at k_c the quasi-static aging law has a family of cycles; the continuation
    # must walk up it at κ = 1 (to rounding), with the trivial multiplier 1 along the family.
    br = continue_cycles(state_law="aging", points=6, max_step=0.5, **SLIDER)
    amps = [p.ln_v_max - p.ln_v_min for p in br.points]
    assert amps[-1] > 50 * amps[0]
    assert all(abs(p.kappa - 1) < 1e-8 for p in br.points)
    assert all(abs(abs(p.multipliers[0]) - 1) < 1e-5 for p in br.points)
    assert not br.folds


WORKFLOW = """
[study]
name = "tiny"
[slider]
a = 0.01
b = 0.015
dc = 0.01
v_lp = 1.0
[[branch]]
label = "prz"
state_law = "prz"
points = 4
max_step = 0.5
[hopf]
b_over_a = [2.0]
v_lp = [1.0]
eta = [0.0]
bautin = false
"""


def test_continue_writes_a_store_and_a_report(tmp_path):
    wf = tmp_path / "tiny.toml"
    wf.write_text(WORKFLOW)
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, ["continue", str(wf), "--out", str(out)])
    assert r.exit_code == 0, r.output
    assert (out / "REPORT.md").exists() and (out / "bifurcation-diagram.png").exists()
    ds = xr.open_zarr(out / "branches.zarr", consolidated=False)
    assert ds.branch.values.tolist() == ["prz"] and ds.sizes["point"] == 4
    assert (ds.status.values == 1).all() and np.all(ds.period_check.values < 1e-10)
    assert ds.k_c.values[0] == pytest.approx([0.5] * 4, rel=1e-12)   # a branch's k_c, at each of its points
    assert "subcritical" in (out / "REPORT.md").read_text()
    from _report_outline import from_html, from_markdown   # REPORT.md and report.html: one document

    outline = from_markdown((out / "REPORT.md").read_text(), out)   # (every table row as wide as its header)
    assert outline == from_html((out / "report.html").read_text()) and any(k[0] == "figure" for k in outline)


@pytest.mark.parametrize("edit,message", [
    (("points = 4", "pointz = 4"), "branch[0].pointz"),
    (('state_law = "prz"', 'state_law = "frob"'), "branch[0].state_law='frob'"),
    (("b = 0.015", "b = 0.005"), "slider.b=0.005: must be > 0.01"),
    (("dc = 0.01", "dc = -1"), "slider.dc=-1"),
    (("bautin = false", "bautin = 3"), "hopf.bautin=3"),
    (("points = 4", 'points = 4\nparameter = "k"'), "branch[0].parameter='k'"),
    (("points = 4", "points = 4\nstart_point = 2"), "branch[0].start_point=2: is only for a branch in V_lp"),
    (("points = 4", 'points = 4\nparameter = "v_lp"\nv_lp_max = 0.5'), "branch[0].v_lp=1.0: is not inside"),
])
def test_bad_workflow_is_one_line_and_writes_nothing(tmp_path, edit, message):
    wf = tmp_path / "bad.toml"
    wf.write_text(WORKFLOW.replace(*edit))
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, ["continue", str(wf), "--out", str(out)])
    assert r.exit_code == 2 and len(r.output.strip().splitlines()) == 1 and message in r.output, r.output
    assert not out.exists()


def test_continue_on_a_missing_workflow_is_one_line(tmp_path):
    r = CliRunner().invoke(cli, ["continue", str(tmp_path / "nope.toml")])
    assert r.exit_code == 2 and len(r.output.strip().splitlines()) == 1 and "cannot be read" in r.output


def test_branch_in_v_lp_quasi_static_is_the_cycle_rescaled():
    # Quasi-static, with τ = t V_lp/Dc and ln(V/V_lp) the equations do not contain V_lp and k_c = (b − a)/Dc
    # does not depend on it (docs/rate-state.md): along V_lp at fixed k the cycle keeps V_lp·T and
    # ln(V/V_lp) (the unstable PRZ cycle at κ ≈ 1.05, over 2+ decades of V_lp).
    from bifurcation.models.rate_state.continuation import continue_in_v_lp

    br = continue_cycles(state_law="prz", points=6, max_step=0.5, **SLIDER)
    vb = continue_in_v_lp(br, 5, points=12, max_step=2.0, v_lp_range=(1e-3, 1e3))
    assert vb.meta["parameter"] == "v_lp" and len(vb.points) == 12 and not vb.folds
    v = np.array([p.v_lp for p in vb.points])
    assert v.max() / v.min() > 100
    ref = vb.points[1]
    for p in vb.points[1:]:
        assert p.k == br.points[5].k and p.kappa == pytest.approx(br.points[5].kappa, rel=1e-15)
        # the shooting Newton's own tolerance (1e-12 on the unknowns) bounds the agreement
        assert p.v_lp * p.period == pytest.approx(ref.v_lp * ref.period, rel=1e-11)
        assert p.ln_v_max - math.log(p.v_lp) == pytest.approx(ref.ln_v_max - math.log(ref.v_lp), abs=1e-10)
        assert p.ln_v_min - math.log(p.v_lp) == pytest.approx(ref.ln_v_min - math.log(ref.v_lp), abs=1e-10)
    for i in (0, 5, 11):
        assert period_by_simulation(vb, i) == pytest.approx(vb.points[i].period, rel=1e-10)
    assert period_by_simulation(vb, 11, "quad") == pytest.approx(vb.points[11].period, rel=1e-10)


def test_branch_in_v_lp_with_inertia_moves_kappa_as_k_c_grows_with_v_lp():
    # With inertia k_c = (b − a)/Dc·[1 + M V_lp²/(a Dc)]: at fixed k a faster load point is a softer spring
    # (κ falls), and the stable cycle (multipliers inside 1) changes period and depth.
    from bifurcation.models.rate_state.continuation import continue_in_v_lp

    mass = 0.1 * 0.01 * 0.01
    br = continue_cycles(state_law="aging", mass=mass, points=10, max_step=0.5, **SLIDER)
    vb = continue_in_v_lp(br, 9, points=10, max_step=0.5, v_lp_range=(1e-3, 1e3))
    assert len(vb.points) == 10 and all(p.status == "ok" for p in vb.points)
    for i, p in enumerate(vb.points):
        k_c = 0.5 * (1 + mass * p.v_lp ** 2 / (0.01 * 0.01))
        assert p.kappa == pytest.approx(p.k / k_c, rel=1e-14)
        assert max(abs(z) for z in p.multipliers) < 1
        assert period_by_simulation(vb, i) == pytest.approx(p.period, rel=1e-10)
    v = [p.v_lp for p in vb.points]
    kap = [p.kappa for p in vb.points]
    assert v == sorted(v) and kap == sorted(kap, reverse=True) and v[-1] > 3 and kap[-1] < 0.25


@pytest.mark.slow   # 5 s; continue's store and report are tested fast above
def test_continue_writes_a_branch_in_v_lp(tmp_path):
    wf = tmp_path / "v.toml"
    wf.write_text(WORKFLOW.replace('points = 4\nmax_step = 0.5',
                                   'points = 4\nmax_step = 2.0\nparameter = "v_lp"\nstart_point = 3\n'
                                   'v_lp_min = 0.01\nv_lp_max = 100'))
    out = tmp_path / "out"
    r = CliRunner().invoke(cli, ["continue", str(wf), "--out", str(out)])
    assert r.exit_code == 0, r.output
    ds = xr.open_zarr(out / "branches.zarr", consolidated=False)
    assert ds.attrs["parameter"] == ["v_lp"] and ds.sizes["point"] == 4
    v = ds.v_lp.values[0]
    assert v[0] == 1.0 and np.all(np.diff(v) > 0)
    # quasi-static: V_lp·T is the same cycle's at every V_lp (the shooting tolerance bounds the agreement)
    np.testing.assert_allclose(v * ds.period.values[0], v[0] * ds.period.values[0, 0], rtol=1e-10)
    assert np.all(ds.period_check.values < 1e-10)
    assert "a branch in V_lp at fixed k" in (out / "REPORT.md").read_text()
