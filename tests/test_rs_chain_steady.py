"""Steady sliding (status ``steady``; docs/rs-chain.md, "Steady sliding"): a run whose deviations from
steady sliding are observed to decay ends early, says so, and keeps every event before bit for bit."""

from __future__ import annotations

import math

import numpy as np
import pytest

from bifurcation.models.rs_chain import simulate
from bifurcation.models.rs_chain._system import PARAMETERS, Layout, rhs_expressions, steady_state
from bifurcation.models.rs_chain.batch import run_batch
from bifurcation.models.rs_chain.result import RSChainStatus
from bifurcation.models.rs_chain.simulate import RSChainSpec, initial_state, linear_growth, run

CATALOG = ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity")
#: the reported case: 384 s of CPU and 10^7 steps to `no-stop` before this status
STABLE = dict(n=3, state_law="aging", a=0.008, b=0.0135, dc=0.02, k=0.12, ell=1.0, v_lp=1.0, eta=5e-3)


def test_the_reported_stable_chain_ends_steady_in_a_few_steps():
    spec = RSChainSpec(**STABLE)
    r = run(spec, initial_state(spec, 0.5, 1), 100)
    # 72 steps measured (t = 2.9); the old run took 10^7 steps (max_steps) to say no-stop
    assert r.status == RSChainStatus.STEADY and r.events == 0 and r.steps < 1000
    assert r.message.startswith("steady: steady sliding after 0 events") and "max Re λ = -3.65" in r.message
    assert str(RSChainStatus.STEADY) == "steady"
    # without the test the same start runs to the step bound (here lowered to 20 000)
    old = run(spec, initial_state(spec, 0.5, 1), 100, max_steps=20_000, steady=False)
    assert old.status == RSChainStatus.NO_STOP and old.steps == 20_001


def test_linear_growth_is_the_closed_form_of_the_slider():
    # quasi-dynamic slider at V = V_lp, A = a + ηV: linearising (A + ...)ẋ = k(V_lp − V) − b ẏ with
    # ẏ = −(V/Dc)(x̃ + ỹ) (aging and slip law alike to first order) gives
    #     A s² + (A V/Dc + k V − b V/Dc) s + k V²/Dc = 0,
    # so Re s = −(A/Dc + k − b/Dc) V/(2A) while complex, and k_c = (b − a − ηV)/Dc = 0.025 here.
    # Finite differences of h = 1e-6 are ~1e-10 relative: 1e-7 is the bound.
    for law in ("aging", "slip"):
        for k in (0.02, 0.03, 0.12):
            spec = RSChainSpec(n=1, state_law=law, a=0.008, b=0.0135, dc=0.02, k=k, ell=0.0, v_lp=1.0, eta=5e-3)
            A = 0.008 + 5e-3
            c1, c0 = A / 0.02 + k - 0.0135 / 0.02, k / 0.02
            disc = c1 * c1 - 4 * A * c0
            assert disc < 0                     # complex pair at these k
            growth, _, omega = linear_growth(spec)
            assert growth == pytest.approx(-c1 / (2 * A), rel=1e-7, abs=1e-9), (law, k)
            assert omega == pytest.approx(math.sqrt(-disc) / (2 * A), rel=1e-7), (law, k)
            assert (growth < 0) == (k > 0.025)


def _dense_growth(spec: RSChainSpec) -> float:
    """max Re λ of the whole chain's Jacobian (x, y[, z] of every block, P left out), by central
    differences of ``rhs_expressions``: no mode decomposition."""
    layout = Layout(spec.n, spec.inertial)
    values = spec.parameters()
    par = {name: values[name] for name in PARAMETERS}
    x0, y0 = steady_state(spec.law, spec.v_lp, spec.dc)
    base = np.array([x0] * spec.n + [y0] * spec.n + ([0.0] * spec.n if spec.inertial else []) + [0.0])
    dim = layout.size - 1
    jac = np.empty((dim, dim))
    for i in range(dim):
        h = 1e-6 * max(1.0, abs(base[i]))
        up, dn = base.copy(), base.copy()
        up[i] += h
        dn[i] -= h
        f = [np.array(rhs_expressions(spec.law, layout, list(v), par, np.exp, np.log, periodic=spec.periodic,
                                      damped=spec.eta > 0)[:dim], dtype=float) for v in (up, dn)]
        jac[:, i] = (f[0] - f[1]) / (2 * h)
    return float(np.max(np.linalg.eigvals(jac).real))


@pytest.mark.parametrize("extra", [dict(n=3), dict(n=4, periodic=True), dict(n=5, ell=3.0, k=0.02),
                                   dict(n=3, mass=1e-4, eta=0.0, k=0.3), dict(n=2, periodic=True, k=0.024)])
def test_the_modes_are_the_whole_chains_spectrum(extra):
    # the per-mode reduction (one slider of stiffness k(1 + 4ℓ² sin²)) against the dense Jacobian of the
    # whole chain, both by finite differences (~1e-9 absolute on eigenvalues of size ~10-100)
    spec = RSChainSpec(**{**STABLE, **extra})
    assert linear_growth(spec)[0] == pytest.approx(_dense_growth(spec), rel=1e-6, abs=1e-6)


def _feed(w, spec, d0, factor, windows=8) -> list:
    """Samples at every τ of d(t) = d0 · factor^(t / window length) for ``windows`` windows; the answers."""
    n = spec.n
    out = []
    while w.next <= windows * w.length:
        t = w.next
        v = d0 * factor ** (t / w.length)
        out.append(w.sample(t, np.concatenate([np.full(n, w.x_ss + v), np.full(n, w.y_ss)]), 0))
    return out


def test_the_test_is_on_the_observed_decay_not_the_stiffness():
    # one stable linearisation (k = 0.12 > k_c) and deviations within the band: only a decay by more than
    # STEADY_RATIO a window is steady; a constant or a growing deviation never is
    spec = RSChainSpec(**STABLE)
    w = simulate._Steady(spec, 0.0)
    assert w.stable and simulate.STEADY_RATIO == 0.5

    def answers(d0, factor, windows=8):
        w.reset()
        w.next = w.after(0.0)
        return _feed(w, spec, d0, factor, windows)

    assert not any(answers(5e-4, 1.0))
    assert not any(answers(1e-5, 1.5))
    assert not any(answers(5e-4, 0.6))          # 0.6 > STEADY_RATIO
    assert any(answers(5e-4, 0.3))
    assert not any(answers(5e-4, 0.3, windows=4))   # 4 windows, 3 of them complete: not yet
    assert not any(answers(3e-3, 0.3, windows=2))   # outside the band
    # a block above v_th restarts the windows
    answers(5e-4, 0.3, windows=3)
    assert not w.sample(w.next, np.zeros(2 * spec.n), 1) and w.maxima == [] and w.start is None


def test_an_unstable_linearisation_is_never_steady():
    # k = 0.015 < k_c = 0.025: the run goes to its bound however it looks (no event: a cycle below v_th)
    spec = RSChainSpec(**{**STABLE, "k": 0.015})
    assert linear_growth(spec)[0] > 0
    r = run(spec, initial_state(spec, 0.5, 1), 5, max_steps=20_000)
    assert r.status == RSChainStatus.NO_STOP


def test_events_then_steady_keeps_the_events_bit_for_bit():
    # the slider (N = 1) just above k_c = 0.025, kicked: 2 events, then the deviations decay at the
    # linear rate (Re λ = −0.115) and the run ends steady; without the test it runs to max_steps with
    # the same 2 events, bit for bit (the test only reads the state)
    spec = RSChainSpec(n=1, state_law="aging", a=0.008, b=0.0135, dc=0.02, k=0.028, ell=0.0, v_lp=1.0,
                       eta=5e-3, v_th=1.5)
    start = initial_state(spec, 0.0, 1) + np.array([0.3, 0.0, 0.0])
    r = run(spec, start, 20)
    old = run(spec, start, 20, max_steps=5000, steady=False)
    assert r.status == RSChainStatus.STEADY and r.events == 2 and "after 2 events" in r.message
    assert old.status == RSChainStatus.NO_STOP and old.events == 2
    for name in CATALOG:
        assert getattr(r, name).tobytes() == getattr(old, name).tobytes(), name


@pytest.mark.parametrize("case", [
    dict(n=20, state_law="aging", a=0.01, b=0.015, dc=0.01, k=0.1, ell=1.0, v_lp=1.0, eta=1e-3, events=30),
    dict(n=4, state_law="slip", a=0.01, b=0.015, dc=0.01, k=0.1, ell=3.0, v_lp=1.0, eta=1e-3, events=40),
    dict(n=3, state_law="aging", a=0.01, b=0.015, dc=0.01, k=0.05, ell=1.0, v_lp=1.0, mass=1e-4, eta=1e-3,
         periodic=True, events=8),
])
def test_runs_with_events_are_unchanged(case):
    # catalogs and steps equal, bit for bit, with and without the test (also checked against main's
    # engine before this change: the same bytes for 60, 100 and 40 events of these cases)
    case = dict(case)
    events = case.pop("events")
    spec = RSChainSpec(**case)
    new, old = (run(spec, initial_state(spec, 1.0, 1), events, steady=s) for s in (True, False))
    assert new.status == old.status == RSChainStatus.COMPLETE and new.steps == old.steps
    for name in CATALOG:
        assert getattr(new, name).tobytes() == getattr(old, name).tobytes(), name


def test_batch_lanes_end_steady_as_the_scalar_runs():
    # lanes with a stable chain (k = 0.12, 0.05, 0.2) end steady at the scalar run's step; the unstable
    # one (k = 0.015) runs to its bound in both
    specs = [RSChainSpec(**{**STABLE, "k": k}) for k in (0.12, 0.015, 0.05, 0.2)]
    starts = [initial_state(s, 0.5, 1) for s in specs]
    lanes = run_batch(specs, starts, 5, max_steps=20_000)
    for spec, start, b in zip(specs, starts, lanes):
        r = run(spec, start, 5, max_steps=20_000)
        assert (b.status, b.events, b.steps) == (r.status, r.events, r.steps), spec.k
        assert b.status == (RSChainStatus.NO_STOP if spec.k == 0.015 else RSChainStatus.STEADY)


@pytest.mark.parametrize("batch", [1, 4])
def test_the_workflow_runner_stores_steady_with_and_without_batch(batch):
    # the store's runner (one run per point; batch = 4 puts both points in run_batch's lanes): the
    # stable point's status is steady (8) with its message, the unstable one's no-stop at the bound
    from bifurcation.models import get_model
    from bifurcation.models.rs_chain.model import run_rs_chains

    points = {name: np.array(values) for name, values in dict(
        n=[3, 3], k=[0.12, 0.015], ell=[1.0, 1.0], v_lp=[1.0, 1.0], a=[0.008, 0.008], b=[0.0135, 0.0135],
        dc=[0.02, 0.02], mass=[0.0, 0.0], eta=[5e-3, 5e-3], v_th=[10.0, 10.0], amplitude=[0.5, 0.5],
        seed=[1, 1], events=[5, 5], periodic=[0, 0]).items()}
    out, messages = run_rs_chains(get_model("rs-chain"), "aging", points, max_steps=20_000, batch=batch)
    assert list(out["status"]) == [int(RSChainStatus.STEADY), int(RSChainStatus.NO_STOP)]
    assert list(out["events_done"]) == [0, 0] and messages[0].startswith("steady: steady sliding")
    assert "steady" in [str(s) for s in get_model("rs-chain").statuses]


def test_a_submit_with_a_steady_point_tallies_it(tmp_path):
    # a status code beyond bifurcation.Status (steady = 8) broke the submit's tally (a bincount of 9
    # against 8 counters); the workflow is the reported case
    from click.testing import CliRunner

    from bifurcation.cli import cli

    toml = tmp_path / "steady.toml"
    toml.write_text('[study]\nname = "rs-steady"\n[model]\nname = "rs-chain"\n[engine]\nlaws = ["aging"]\n'
                    + "".join(f"[grid.{k}]\nvalues = [{v}]\n" for k, v in dict(
                        n=3, k=0.12, a=0.008, b=0.0135, dc=0.02, eta=5e-3, amplitude=0.5, events=50).items())
                    + "[tiles]\ncatalog = 100\n")
    out = CliRunner().invoke(cli, ["submit", str(toml), "--store", str(tmp_path / "s.zarr"), "--workers", "1"])
    assert out.exit_code == 0, out.output
    assert "statuses of computed points: steady 1" in out.output
