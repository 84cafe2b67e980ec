"""SIGTERM (a batch job's walltime: Slurm sends SIGTERM, then SIGKILL after KillWait) and SIGHUP stop a real
`bifurcation submit` like Ctrl-C: status 128 + signal, one line saying how to resume, the store's lock
released (before, the process died at once and left the lock, which a resubmit from another node may not
break), no damaged chunk, and the resume equals an uninterrupted run bit for bit."""

from __future__ import annotations

import os
import signal
import subprocess
import time

import numpy as np
import pytest

from bifurcation.cli import cli
from bifurcation.run import submit
from bifurcation.run.repair import verify
from bifurcation.run.tiles import compute_serial
from bifurcation.store import read_done
from bifurcation.store.lock import LOCK_NAME
from bifurcation.workflow import load_workflow

from _proc import bifurcation, group_alive, running, wait_until
from _store_helpers import assert_store_equals

# 1536 points in 24 tiles of 64: each tile takes a few tens of ms, so the signal lands between the first
# finished tile and the last one
TOML = """
[study]
name = "terminated"

[engine]
laws = ["piecewise-linear", "carlson-langer"]

[grid.nu]
log = { start = 1e-3, stop = 1e-15, num = 32 }

[grid.nu_f]
ranges = [{ start = 0.02, stop = 0.96, num = 24 }]

[tiles]
nu_f = 4
nu = 16
"""


@pytest.mark.slow   # 9-12 s each at load ~9 on 2 cores: a real submit, killed, verified and resumed
@pytest.mark.parametrize("signum", [signal.SIGTERM, signal.SIGHUP], ids=["SIGTERM", "SIGHUP"])
def test_a_terminated_submit_releases_its_lock_and_resumes_bit_for_bit(tmp_path, signum):
    (tmp_path / "w.toml").write_text(TOML)
    store = tmp_path / "s.zarr"
    with running(bifurcation("submit", "w.toml", "--store", store, "--workers", "1"), tmp_path,
                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as run:
        # mid-run: the lock is held and the first tile's done chunk is written
        wait_until(lambda: any((store / "done").rglob("c/*")), 60, "a tile (the submit ended first?)", proc=run)
        assert (store / LOCK_NAME).exists()
        run.send_signal(signum)
        out, err = run.communicate(timeout=60)
    # 128 + signal (a run that had finished would exit 0: the check cannot pass by a late signal)
    assert run.returncode == 128 + signum, err
    assert err.strip().splitlines()[-1] == (
        f"bifurcation: terminated by {signal.Signals(signum).name}. A submit keeps every finished tile in its "
        "store: submit the same workflow again to resume.")
    assert "Traceback" not in err
    assert not (store / LOCK_NAME).exists(), "the lock was left behind"
    done = read_done(store)
    assert 0 < np.count_nonzero(done) < done.size, "not stopped mid-run"
    report = verify(store)
    assert report.damage == () and report.ok, str(report)
    workflow = load_workflow(tmp_path / "w.toml")
    summary = submit(workflow, store, workers=1)   # the resume: only the missing points
    assert summary.failed == 0 and summary.skipped == np.count_nonzero(done)
    assert_store_equals(store, compute_serial(workflow))


def test_sigterm_in_process_exits_143_and_restores_the_handlers(tmp_path, monkeypatch, capsys):
    """The fast check of the same path: a SIGTERM delivered while `submit` runs ends the command with
    128 + 15 and the one line; the handlers of the caller are restored afterwards (pytest's own)."""
    def terminated(*args, **kwargs):
        os.kill(os.getpid(), signal.SIGTERM)
        time.sleep(5)   # the handler raises at the next bytecode; reaching the end would fail below
        raise AssertionError("SIGTERM did not stop the command")

    before = {s: signal.getsignal(s) for s in (signal.SIGTERM, signal.SIGHUP)}
    monkeypatch.setattr("bifurcation.run.submit", terminated)
    (tmp_path / "w.toml").write_text(TOML)
    with pytest.raises(SystemExit) as exc:
        cli.main(["submit", str(tmp_path / "w.toml"), "--store", str(tmp_path / "s.zarr"), "--workers", "1"])
    assert exc.value.code == 143
    (line,) = capsys.readouterr().err.strip().splitlines()
    assert line.startswith("bifurcation: terminated by SIGTERM. A submit keeps every finished tile")
    assert {s: signal.getsignal(s) for s in before} == before


def test_a_stop_inside_a_tile_write_waits_for_its_end():
    """A SIGTERM during a tile's write (data first, done last) is acted on once the tile is whole: cut
    there it left data without done, reported by verify as damage (found with helpers, below)."""
    from bifurcation.errors import Terminated, stop, uninterrupted

    written = []
    with pytest.raises(Terminated) as exc:
        with uninterrupted():
            with uninterrupted():   # nested: the outermost block's end acts
                stop(signal.SIGTERM)
                written.append("data")
            written.append("done")
    assert written == ["data", "done"] and exc.value.signum == signal.SIGTERM
    with pytest.raises(Terminated):   # outside a block: at once
        stop(signal.SIGHUP)
    with uninterrupted():   # nothing pending is left over from above
        pass


@pytest.mark.slow   # ~15-40 s at load ~9: a study large enough that a helper process starts
@pytest.mark.skipif((os.cpu_count() or 1) < 2, reason="helpers start only with 2 cores")
def test_a_batch_jobs_sigterm_to_every_process_leaves_no_damage(tmp_path):
    """Slurm's SIGTERM reaches every process of the job, helpers included: they leave the stop to the
    submitting process, which finishes the tiles being written; status 143, no lock, no damaged chunk,
    no process left."""
    # 2 × 1024 × 512 points: helpers start once the work left exceeds HANDOVER_CPU_SECONDS (10 s); at one
    # process's ~41 µs a point (docs/benchmarks.md, 10^6 points in 41.3 s) that is ~43 s, so a machine 3× faster still
    # starts one. The former 196 608 points (~8 s) started none on the idle machine (CI, 2026-11-26).
    text = (TOML.replace("num = 32", "num = 1024").replace("num = 24", "num = 512")
            .replace("nu = 16", "nu = 64").replace("nu_f = 4", "nu_f = 8"))
    (tmp_path / "w.toml").write_text(text)
    store = tmp_path / "s.zarr"
    with running(bifurcation("submit", "w.toml", "--store", store, "--workers", "2"), tmp_path,
                 stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as run:
        deadline = time.monotonic() + 120
        err = ""
        while "helper process(es)" not in err:   # the note is printed as the helper starts
            assert run.poll() is None, "the submit ended before a helper started"
            assert time.monotonic() < deadline, "no helper within 120 s"
            err += os.read(run.stderr.fileno(), 4096).decode()
        time.sleep(3.0)   # the helper is importing or in its first tiles
        os.killpg(run.pid, signal.SIGTERM)
        out, rest = run.communicate(timeout=120)
        time.sleep(1.0)
        left = group_alive(run.pid)   # checked before `running` ends the group
    assert run.returncode == 143, err + rest
    assert "Traceback" not in rest and "terminated by SIGTERM" in rest
    assert not (store / LOCK_NAME).exists()
    report = verify(store)
    assert report.damage == () and report.ok, str(report)
    assert not left, "a process of the submit's group lived on"   # no helper lives on
