"""Event membership by a slip-velocity threshold (issue 17, item 2; docs/chain.md, "Event membership").

The dynamics is the same with or without a threshold (the catalog's times and durations are identical);
only which blocks count in ``n_blocks`` and ``potency`` changes. Per-block velocity maxima come from the
same exact nt-events as the catalog's ``max_velocity``, per-block slips from the segments' increments.
"""

from __future__ import annotations

import json

import numpy as np
import pytest
from click.testing import CliRunner

import bifurcation as bf
from bifurcation.cli import cli
from bifurcation.models.chain import chain
from bifurcation.models.chain._validate import DEFAULT_V_THRESHOLD

ARGS = dict(n=24, ell=1.0, nu=1e-3, nu_f=0.45, amplitude=0.5, seed=1, events=150)


@pytest.fixture(scope="module")
def runs():
    base = chain("carlson-langer", **ARGS)
    return base, {v: chain("carlson-langer", v_threshold=v, **ARGS) for v in (1e-300, 1e-2, 0.1)}


def test_the_dynamics_does_not_change(runs):
    base, by = runs
    for r in by.values():
        for f in ("t_start", "hypocentre", "duration", "max_velocity", "steps"):
            assert np.array_equal(r[f], base[f]), f
        assert np.array_equal(r.n_blocks_all, base.n_blocks) and np.array_equal(r.potency_all, base.potency)
    assert base.membership == "all-stuck" and base.v_threshold is None


def test_a_vanishing_threshold_is_the_all_stuck_definition(runs):
    # every block that moved had V > 0: the same members; the potency is summed per block instead of
    # per segment (both exactly rounded sums of the same increments): measured 2.2e-16 relative
    base, by = runs
    r = by[1e-300]
    assert np.array_equal(r.n_blocks, base.n_blocks)
    assert np.max(np.abs(r.potency / base.potency - 1)) <= 1e-14


def test_members_are_the_blocks_faster_than_the_threshold(runs):
    base, by = runs
    for v, r in by.items():
        assert np.all(r.n_blocks <= r.n_blocks_all) and np.all(r.potency <= r.potency_all * (1 + 1e-15))
        # the fastest block of an event is a member exactly when the event's maximal velocity (recorded
        # independently, for the whole window) exceeds V_th
        assert np.array_equal(r.n_blocks > 0, r.max_velocity > v)
        assert np.all(r.potency[r.n_blocks == 0] == 0) and np.all(r.potency[r.n_blocks > 0] > 0)
    # this case has both: events of creep only (no member at 0.01) and members dropped from larger ones
    r = by[1e-2]
    assert np.sum(r.n_blocks == 0) > 10 and np.any((r.n_blocks > 0) & (r.n_blocks < r.n_blocks_all))


def test_a_lone_block_event_counts_iff_its_velocity_exceeds_the_threshold():
    u0 = np.zeros(9)
    u0[4] = -0.3
    one = chain("piecewise-linear", n=9, ell=1.0, nu=1e-3, nu_f=0.2, u0=u0, events=1)
    assert one.n_blocks[0] == 1
    vmax = float(one.max_velocity[0])
    below = chain("piecewise-linear", n=9, ell=1.0, nu=1e-3, nu_f=0.2, u0=u0, events=1, v_threshold=vmax * 0.999)
    above = chain("piecewise-linear", n=9, ell=1.0, nu=1e-3, nu_f=0.2, u0=u0, events=1, v_threshold=vmax * 1.001)
    assert below.n_blocks[0] == 1 and below.potency[0] == pytest.approx(one.potency[0], rel=1e-15)
    assert above.n_blocks[0] == 0 and above.potency[0] == 0


def test_the_default_is_ten_times_the_pulling_speed():
    r = chain("carlson-langer", n=4, ell=1.0, nu=1e-3, nu_f=0.3, amplitude=0.5, seed=2, events=3, v_threshold="default")
    assert DEFAULT_V_THRESHOLD == 10 and r.v_threshold == pytest.approx(1e-2) and r.membership == "v-threshold=0.01"


@pytest.mark.parametrize("bad", [0, 0.0, -1e-3, float("nan"), float("inf"), "fast", True])
def test_api_refuses_a_bad_threshold(bad):
    with pytest.raises(bf.InputError, match="v_threshold"):
        chain("carlson-langer", n=2, ell=1.0, nu=1e-3, nu_f=0.3, amplitude=0.1, seed=1, events=1, v_threshold=bad)


@pytest.mark.parametrize("bad", ["--v-threshold=0", "--v-threshold=-1", "--v-threshold=nan", "--v-threshold=inf",
                                 "--v-threshold=abc"])
def test_cli_refuses_a_bad_threshold_in_one_line_exit_2(bad):
    args = ["chain", "--law", "carlson-langer", "--n", "3", "--ell", "1", "--nu", "1e-3", "--nu-f", "0.3",
            "--amplitude", "0.1", "--events", "2", bad]
    res = CliRunner().invoke(cli, args)
    assert res.exit_code == 2, res.output
    lines = [line for line in res.output.splitlines() if line.strip()]
    assert len(lines) == 1 and "--v-threshold" in lines[0] and "Traceback" not in res.output


def test_cli_threshold_default_and_the_catalog_says_which():
    args = ["chain", "--law", "carlson-langer", "--n", "6", "--ell", "1", "--nu", "1e-3", "--nu-f", "0.45",
            "--amplitude", "0.5", "--seed", "1", "--events", "20", "--v-threshold", "default", "--json"]
    res = CliRunner().invoke(cli, args, catch_exceptions=False)
    assert res.exit_code == 0, res.output
    doc = json.loads(res.output)
    api = chain("carlson-langer", n=6, ell=1.0, nu=1e-3, nu_f=0.45, amplitude=0.5, seed=1, events=20, v_threshold=1e-2)
    assert doc["membership"] == "v-threshold=0.01" and doc["n_blocks"] == api.n_blocks.tolist()
    assert doc["potency"] == api.potency.tolist() and doc["n_blocks_all"] == api.n_blocks_all.tolist()
    plain = json.loads(CliRunner().invoke(cli, args[:-3] + ["--json"]).output)
    assert plain["membership"] == "all-stuck" and "n_blocks_all" not in plain


def test_a_workflow_axis_v_threshold_is_the_api():
    from bifurcation.run.tiles import compute_serial
    from bifurcation.workflow import parse_workflow

    wf = parse_workflow("""
[study]
name = "chain-vth-test"
[model]
name = "chain"
[engine]
laws = ["carlson-langer"]
[grid.n]
values = [6]
[grid.ell]
values = [1.0]
[grid.nu]
values = [1e-3]
[grid.nu_f]
values = [0.45]
[grid.amplitude]
values = [0.5]
[grid.seed]
values = [1]
[grid.events]
values = [20]
[grid.periodic]
values = [0]
[grid.v_threshold]
values = [0.0, 0.01]
""")
    out = compute_serial(wf)
    for i, v in enumerate((None, 0.01)):
        api = chain("carlson-langer", n=6, ell=1.0, nu=1e-3, nu_f=0.45, amplitude=0.5, seed=1, events=20,
                    v_threshold=v, t_max=wf.t_max, max_steps=wf.max_steps)
        at = (0,) * 10 + (i,)
        assert np.array_equal(out["n_blocks"][at], api.n_blocks)
        assert np.array_equal(out["potency"][at].view(np.int64), api.potency.view(np.int64))
