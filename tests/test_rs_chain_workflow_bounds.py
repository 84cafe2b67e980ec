"""rs-chain workflows obey their own bounds (issue 21): N × events ≤ bounds.RS_CHAIN_MAX_N_EVENTS, refused up
front through the model's ``check_grid`` hook, and bounds.RS_CHAIN_EVENT_WORK block-steps an event at run time.

Before: N = 65536 × 10^9 events was accepted by ``submit`` (6.6e13 block-events; at the measured 0.14–2.5 ms a
block-event, bifurcation/bounds.py, thousands of years of CPU)."""

from __future__ import annotations

import numpy as np
import pytest

from bifurcation import bounds
from bifurcation.errors import InputError
from bifurcation.workflow.spec import parse_workflow

RSC = """\
[study]
name = "big-rs"
[model]
name = "rs-chain"
[engine]
laws = ["aging"]
[grid.n]
values = [{n}]
[grid.k]
values = [0.1]
[grid.events]
values = [{events}]
"""


def test_rs_chain_n_times_events_beyond_the_bound_is_refused():
    with pytest.raises(InputError) as exc:
        parse_workflow(RSC.format(n=65536, events=10**9))
    e = exc.value
    assert e.argument == "grid.events" and e.value == 10**9
    assert "N × events" in e.problem and "about a day" in e.problem, str(e)
    assert "grid.events <= 457" in e.fix, str(e)              # 3e7 // 65536 = 457
    parse_workflow(RSC.format(n=65536, events=457))           # at the bound: accepted
    with pytest.raises(InputError, match="grid.events=458"):
        parse_workflow(RSC.format(n=65536, events=458))
    with pytest.raises(InputError, match="grid.events=30000001"):   # N = 1: the cap, not the axis bound 1e9
        parse_workflow(RSC.format(n=1, events=30_000_001))


def test_the_shipped_rs_chain_workflows_stay_within_the_bound():
    from pathlib import Path

    root = Path(__file__).resolve().parents[1] / "workflows"
    for name in ("rs-chain-large.toml", "rs-chain-study.toml"):   # 256 × 10^5 = 2.56e7 ≤ 3e7
        parse_workflow((root / name).read_text())


def test_the_rs_chain_bound_is_its_own_and_read_from_bounds(monkeypatch):
    """Lowering bounds.RS_CHAIN_MAX_N_EVENTS moves the refusal; the velocity-weakening chain's bound is another."""
    assert bounds.RS_CHAIN_MAX_N_EVENTS < bounds.CHAIN_MAX_N_EVENTS
    parse_workflow(RSC.format(n=16, events=100))
    monkeypatch.setattr(bounds, "RS_CHAIN_MAX_N_EVENTS", 1000)
    with pytest.raises(InputError, match="grid.events=100: with grid.n 16"):
        parse_workflow(RSC.format(n=16, events=100))


def test_rs_chain_runner_stops_an_event_at_the_work_bound(monkeypatch):
    """With the per-event work lowered to 40 block-steps (10 Taylor steps at N = 4, an event takes ~200) the
    runner stops the run with no-stop and says why; with the bound as shipped the same run completes."""
    from bifurcation.models import get_model
    from bifurcation.models.rs_chain import RSChainStatus
    from bifurcation.models.rs_chain.model import run_rs_chains

    model = get_model("rs-chain")
    points = {a.name: np.array([a.default if a.default is not None else a.example], dtype=a.dtype)
              for a in model.axes}
    points["n"][:], points["events"][:], points["k"][:] = 4, 3, 0.1
    out, messages = run_rs_chains(model, "aging", points)
    assert out["status"][0] == RSChainStatus.COMPLETE and out["events_done"][0] == 3, messages
    monkeypatch.setattr(bounds, "RS_CHAIN_EVENT_WORK", 40)
    out, messages = run_rs_chains(model, "aging", points)
    assert out["status"][0] == RSChainStatus.NO_STOP and out["events_done"][0] < 3, messages
    assert "lowered to 10 at N = 4: bounds.RS_CHAIN_EVENT_WORK" in messages[0], messages
