"""Long CLI runs say what they are doing, and a closed output pipe ends them quietly (review, issue 21)."""

from __future__ import annotations

import subprocess
import sys
import time

import numpy as np

from click.testing import CliRunner

from bifurcation.cli import cli

RATE = ["rate-state", "--state-law", "aging", "--a", "0.005", "--b", "0.01", "--dc", "10", "--k", "1e-3",
        "--v-lp", "1,10", "--at", "10"]


def test_rate_state_long_run_prints_progress_on_stderr(monkeypatch):
    from bifurcation.cli import _rate_state

    monkeypatch.setattr(_rate_state, "PROGRESS_SECONDS", 0.0)   # every 100 steps, not every 5 s
    result = CliRunner().invoke(cli, RATE + ["--t-end", "4000", "--outputs", "2"])   # ~900 steps, ~1 s
    assert result.exit_code == 0, result.output
    lines = result.stderr.splitlines()
    assert len(lines) >= 5 and all(l.startswith("bifurcation: rate-state: t = ") for l in lines), lines
    assert result.stdout.startswith("status ok")


def test_rate_state_beyond_the_bound_is_refused_before_work():
    started = time.perf_counter()
    result = CliRunner().invoke(cli, RATE + ["--t-end", "1e6"])   # ran > 120 s with no output before
    assert time.perf_counter() - started < 10
    assert result.exit_code == 2 and "--t-end=1000000.0" in result.stderr and "--cycle" in result.stderr


def test_chain_event_that_runs_long_says_so(monkeypatch):
    """A stand-in engine that takes 0.6 s inside its first event: the still-running line appears, naming
    N·ν (2 here) and the fix (the real case, N = 25000 at ν = 1e-3, slides for hours)."""
    import bifurcation.models.chain as chain_module
    from bifurcation.cli import _chain

    real = chain_module.chain

    def slow(*args, **kwargs):
        time.sleep(0.6)
        return real(*args, **kwargs)

    monkeypatch.setattr(_chain, "STILL_RUNNING_SECONDS", 0.2)
    monkeypatch.setattr(chain_module, "chain", slow)
    result = CliRunner().invoke(cli, ["chain", "--law", "carlson-langer", "--n", "4", "--ell", "1", "--nu", "0.5",
                                      "--nu-f", "0.3", "--amplitude", "0.1", "--seed", "1", "--events", "1"])
    assert result.exit_code in (0, 1), result.output
    lines = result.stderr.splitlines()
    assert lines and lines[0].startswith("bifurcation: chain: event 1 of 1 still sliding after"), lines
    assert "N·ν = 2" in lines[0] and "--nu" in lines[0]


def test_closed_pipe_ends_quietly():
    """`bifurcation query ... | head -3`: the reader closes the pipe; status 141 (SIGPIPE's, as a Unix tool),
    no error on stderr (it was click's silent exit 1 before). The committed store's query prints more than a
    pipe's buffer (64 KiB), so the close is seen: the committed 10^5-event rs-chain catalog, ~9 MB of CSV."""
    from pathlib import Path

    store = Path(__file__).resolve().parents[1] / "results" / "rs-chain" / "rs-chain-large.zarr"
    proc = subprocess.Popen([sys.executable, "-m", "bifurcation", "query", "--store", str(store), "--catalog",
                             "--format", "csv"],
                            stdout=subprocess.PIPE, stderr=subprocess.PIPE)
    for _ in range(3):
        proc.stdout.readline()
    proc.stdout.close()
    _, err = proc.communicate(timeout=60)
    assert proc.returncode == 141, (proc.returncode, err)
    # a catalog query writes its run's description to stderr first; the closed pipe must add nothing
    assert b"Traceback" not in err and b"error" not in err.lower() and b"Broken pipe" not in err, err


def test_chain_event_that_never_ends_stops_at_the_work_bound(monkeypatch):
    """N·ν ≥ 1: blocks fail faster than events end (N = 25000, ν = 1e-3 slid for hours before the bound).
    With the bound made small the same kind of run (N = 64, ν = 0.05: N·ν = 3.2) stops at it with status
    no-stop, a line that names the bound and the fix, and exit 1; the engine counts the work it did."""
    from bifurcation.cli import _chain

    monkeypatch.setattr(_chain, "MAX_WORK", {k: 20_000 for k in _chain.MAX_WORK})
    args = ["chain", "--law", "carlson-langer", "--n", "64", "--ell", "1", "--nu", "0.05", "--nu-f", "0.3",
            "--amplitude", "0.1", "--seed", "1", "--events", "50"]
    for engine in ("exact", "compiled"):   # bounded by the work count, not a clock (no timed test)
        result = CliRunner().invoke(cli, args + ["--engine", engine])
        assert result.exit_code == 1, result.output
        status = [l for l in result.stdout.splitlines() if l.startswith("status ")]
        assert status and status[0].startswith("status no-stop"), result.stdout
        assert "block-steps" in status[0] and "N·ν = 3.2" in status[0] and "--nu" in status[0], status[0]


def test_chain_work_bound_is_kept_by_the_exact_engine():
    """An event's block-steps (Taylor steps × window width) never pass max_work: the catalog stops at the
    first event that would (before, max_steps overran by blocks starting every step: 5396 steps for 2000)."""
    import bifurcation as bf
    from bifurcation.models.chain import ChainStatus

    r = bf.chain("carlson-langer", n=64, ell=1.0, nu=0.05, nu_f=0.3, amplitude=0.1, seed=1, events=50,
                 max_work=20_000)
    assert r.status == ChainStatus.NO_STOP and "did not end within 2e+04 block-steps" in r.message, r.message
    free = bf.chain("carlson-langer", n=64, ell=1.0, nu=0.05, nu_f=0.3, amplitude=0.1, seed=1, events=r.events)
    assert np.array_equal(free.potency, r.potency)   # the events before the bound are the same
    # the run's bound: events that each end, summed (N = 64 at ν = 1e-4: ~10^3 block-steps an event)
    whole = bf.chain("carlson-langer", n=64, ell=1.0, nu=1e-4, nu_f=0.3, amplitude=0.1, seed=1, events=200)
    run = bf.chain("carlson-langer", n=64, ell=1.0, nu=1e-4, nu_f=0.3, amplitude=0.1, seed=1, events=200,
                   max_run_work=20_000)
    assert whole.status == ChainStatus.COMPLETE and run.status == ChainStatus.NO_STOP, run.message
    assert "the run's bound of 2e+04 block-steps ran out" in run.message and 0 < run.events < 200
    assert np.array_equal(whole.potency[:run.events], run.potency)


def test_chain_still_running_line_with_verify_does_not_claim_an_event(monkeypatch, capsys):
    """With --engine compiled --verify nothing reports progress until the end (compiling, then the verified
    run): the line said 'event 1 of 1000 still sliding after 244 s' on a fresh clone's README example."""
    from bifurcation.cli import _chain

    monkeypatch.setattr(_chain, "STILL_RUNNING_SECONDS", 0.15)
    report = _chain._progress(time.perf_counter())
    with _chain._still_running(report, 1000, 256, 1e-4, counted=False):
        time.sleep(0.5)
    lines = capsys.readouterr().err.splitlines()
    assert lines and all(l.startswith("bifurcation: chain: still running after ") and "--verify" in l
                         and "event" not in l for l in lines), lines


def test_chain_compiling_says_compiling_not_still_sliding(monkeypatch):
    """While numba compiles the compiled engine (~33 s of CPU on a cold cache) no event has started: the
    still-running line said 'event 1 of 3 still sliding after 30 s' (issue 21, walk 4). A stand-in compile
    (0.6 s inside the first call of the engine) with no writable cache: both lines say compiling, and that
    every run compiles again; none claims an event."""
    from bifurcation.cli import _chain
    from bifurcation.models.chain import _compiled

    real = _compiled.CompiledChain.run
    calls = []

    def first_compiles(self, k):
        if not calls:
            time.sleep(0.6)
        calls.append(k)
        return real(self, k)

    monkeypatch.setattr(_chain, "STILL_RUNNING_SECONDS", 0.2)
    monkeypatch.setattr(_compiled, "_CACHE", False)
    monkeypatch.setattr(_compiled.CompiledChain, "compiled", lambda self: False)
    monkeypatch.setattr(_compiled.CompiledChain, "run", first_compiles)
    result = CliRunner().invoke(cli, ["chain", "--law", "carlson-langer", "--n", "4", "--ell", "1", "--nu", "1e-3",
                                      "--nu-f", "0.3", "--amplitude", "0.1", "--seed", "1", "--events", "3",
                                      "--engine", "compiled"])
    assert result.exit_code == 0, result.output
    lines = result.stderr.splitlines()
    notice = [i for i, l in enumerate(lines) if l.startswith(
        "bifurcation: chain: compiling the chain engine for carlson-langer (every run: numba cannot write its disk cache")]
    assert len(notice) == 1, lines
    # (lines before the notice: the setup outlasting the stand-in's 0.2 s; the real bound is 30 s)
    during = [l for l in lines[notice[0] + 1:] if "after" in l][:2]   # the 0.6 s stand-in: 2-3 lines
    assert during and all(l.startswith("bifurcation: chain: still compiling the chain engine (numba) after ")
                          and "every run" in l for l in during), lines
    assert "Warning" not in result.stderr


def test_chain_still_running_line_after_the_compile_counts_events_again(monkeypatch, capsys):
    """The first progress call ends the compile: a line after it names the event again."""
    from bifurcation.cli import _chain

    monkeypatch.setattr(_chain, "STILL_RUNNING_SECONDS", 0.15)
    report = _chain._progress(time.perf_counter())
    report.compiling = "first run only"
    report(0, 5, 0.0)   # (the engine's first progress call)
    with _chain._still_running(report, 5, 4, 1e-3):
        time.sleep(0.5)
    lines = [l for l in capsys.readouterr().err.splitlines() if "after" in l]
    assert lines and all(l.startswith("bifurcation: chain: event 1 of 5 still sliding after") for l in lines), lines
