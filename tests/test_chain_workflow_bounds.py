"""Chain workflows obey the bounds of `bifurcation chain` (issue 21): one definition (bifurcation.bounds),
checked up front by the workflow's validation (submit, status, study, ...), and the per-event work at run time.

Before: a workflow of 10^9 events at N = 2^20 was accepted and ran for hours, its layout cache growing to
5.4 GB (8192 windows of thousands of blocks, 212 bytes a block)."""

from __future__ import annotations

import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from bifurcation import bounds
from bifurcation.errors import InputError
from bifurcation.workflow.spec import parse_workflow

CHAIN = """\
[study]
name = "big"
[model]
name = "chain"
[engine]
laws = ["carlson-langer"]
[grid.n]
values = [{n}]
[grid.ell]
values = [1.0]
[grid.nu]
values = [1e-9]
[grid.nu_f]
values = [0.3]
[grid.amplitude]
values = [0.1]
[grid.seed]
values = [1]
[grid.events]
values = [{events}]
[grid.periodic]
values = [0]
"""


def test_workflow_n_times_events_beyond_the_bound_is_refused():
    with pytest.raises(InputError) as exc:
        parse_workflow(CHAIN.format(n=1 << 20, events=10**9))
    e = exc.value
    assert e.argument == "grid.events" and e.value == 10**9
    assert "N × events" in e.problem and "grid.events <= 9536" in e.fix, str(e)   # 1e10 // 2^20 = 9536
    parse_workflow(CHAIN.format(n=1 << 20, events=9536))      # at the bound: accepted
    parse_workflow(CHAIN.format(n=1, events=10**9))           # N = 1: 1e9 ≤ 1e10


def test_workflow_and_cli_share_one_definition(monkeypatch):
    """Lowering bounds.CHAIN_MAX_N_EVENTS moves both refusals: no second constant anywhere."""
    from click.testing import CliRunner

    from bifurcation.cli import cli

    monkeypatch.setattr(bounds, "CHAIN_MAX_N_EVENTS", 1000)
    with pytest.raises(InputError, match="grid.events"):
        parse_workflow(CHAIN.format(n=16, events=100))
    result = CliRunner().invoke(cli, ["chain", "--law", "carlson-langer", "--n", "16", "--ell", "1", "--nu", "1e-3",
                                      "--nu-f", "0.3", "--amplitude", "0.1", "--seed", "1", "--events", "100"])
    assert result.exit_code == 2 and "--events=100: with --n 16 is N × events" in result.stderr, result.output


def test_submit_of_a_too_large_chain_workflow_is_one_line_and_writes_nothing(tmp_path):
    wf = tmp_path / "big.toml"
    wf.write_text(CHAIN.format(n=1 << 20, events=10**9))
    store = tmp_path / "big.zarr"
    p = subprocess.run([sys.executable, "-m", "bifurcation", "submit", str(wf), "--store", str(store)],
                       capture_output=True, text=True, timeout=60)
    assert p.returncode == 2, p.stderr
    lines = p.stderr.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("bifurcation: error: grid.events=1000000000"), p.stderr
    assert not store.exists()


def test_workflow_runner_stops_an_event_at_the_shared_work_bound(monkeypatch):
    """N·ν = 3.2 (N = 64, ν = 0.05): blocks fail faster than events end. With the per-event bound lowered
    to 20000 block-steps the workflow's runner stops at it (no-stop, the events before kept), as the CLI
    does; before, only the workflow's max_steps bounded the event (hours at N = 2^20)."""
    from bifurcation.models import get_model
    from bifurcation.models.chain import ChainStatus
    from bifurcation.models.chain.model import run_chains

    monkeypatch.setattr(bounds, "CHAIN_EVENT_WORK", {k: 20_000 for k in bounds.CHAIN_EVENT_WORK})
    points = {"n": np.array([64]), "ell": np.array([1.0]), "nu": np.array([0.05]), "nu_f": np.array([0.3]),
              "amplitude": np.array([0.1]), "seed": np.array([1]), "events": np.array([50]),
              "periodic": np.array([0])}
    out, messages = run_chains(get_model("chain"), "carlson-langer", points, max_steps=50_000)
    assert out["status"][0] == int(ChainStatus.NO_STOP), messages
    assert "did not end within 2e+04 block-steps" in messages[0], messages


def test_layout_cache_is_bounded_in_blocks():
    """Windows of 2000 blocks at 600 places: the cache held them all (1.2e6 blocks, 241 MB traced) and
    would have held 8192 (3.5 GB); it now holds at most 2^18 blocks (~56 MB)."""
    from bifurcation.laws import resolve_law
    from bifurcation.models.chain._loop import ChainLoop
    from bifurcation.models.chain._validate import check_initial

    n = 1 << 16
    loop = ChainLoop(resolve_law("carlson-langer"), n, 1.0, 1e-6, 0.2, "free",
                     check_initial(n, 1.0, "free", None, 0.1, 1))
    rng = np.random.default_rng(0)
    for _ in range(300):
        start = int(rng.integers(0, n - 3000))
        loop._slip = set(range(start, start + 2000))
        idx = loop._layout()[0]
        assert idx[0] == max(start - 1, 0) and len(idx) == 2002   # the layout itself is right
    held = sum(len(v[0]) for v in loop._layouts.values())
    assert 0 < held <= 1 << 18, held


def test_study_chain_workflow_n_times_events_is_bounded(tmp_path):
    from bifurcation.models.chain.study_workflow import load_report_workflow

    text = (Path(__file__).parents[1] / "workflows" / "chain-report.toml").read_text()
    bad = text.replace("events = [3000, 2000]", "events = [3000, 200000000]")
    assert bad != text
    (tmp_path / "w.toml").write_text(bad)
    with pytest.raises(InputError) as exc:
        load_report_workflow(tmp_path / "w.toml")
    assert exc.value.argument == "catalog.events[1]" and "N × events" in exc.value.problem, str(exc.value)
    bad = text.replace('preset = "vasconcelos-1996"\nevents = 1000000', 'preset = "vasconcelos-1996"\n'
                       'events = 1000000\nn = 100000')
    assert bad != text
    (tmp_path / "w.toml").write_text(bad)
    with pytest.raises(InputError, match=r"presets\.run\[0\]\.events"):
        load_report_workflow(tmp_path / "w.toml")


def test_workflow_runner_holds_its_catalog_as_arrays(monkeypatch):
    """A workflow run's catalog grows as arrays per piece of <= 1000 events (48 bytes an event), not as Python
    lists of the whole run: traced peak per added event 319 bytes before, 83 after (measured in a process of
    its own, N = 4, 5000 and 80000 events; not here, where the numba warm-up thread allocates beside it). A run
    of 10^9 events at N <= 10 is within the workflow's bounds. Checked here by what the loop is asked to run
    and keeps: pieces of at most 1000 events, no per-event timings piling up, the same catalog."""
    import bifurcation as bf
    from bifurcation.models import get_model
    from bifurcation.models.chain._loop import ChainLoop
    from bifurcation.models.chain.model import run_chains

    asked, kept = [], []
    run = ChainLoop.run

    def spy(self, k):
        asked.append(k)
        kept.append(len(self.wall))
        return run(self, k)

    monkeypatch.setattr(ChainLoop, "run", spy)
    pts = {"n": np.array([4]), "ell": np.array([1.0]), "nu": np.array([1e-3]), "nu_f": np.array([0.3]),
           "amplitude": np.array([0.1]), "seed": np.array([1]), "events": np.array([2500]), "periodic": np.array([0])}
    out, _ = run_chains(get_model("chain"), "carlson-langer", pts)
    assert asked == [1000, 1000, 500] and max(kept) == 0, (asked, kept)
    monkeypatch.setattr(ChainLoop, "run", run)
    whole = bf.chain("carlson-langer", n=4, ell=1.0, nu=1e-3, nu_f=0.3, amplitude=0.1, seed=1, events=2500)
    for name in ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity"):
        assert np.array_equal(out[name][0], getattr(whole, name)), name   # pieces change nothing
