"""Ctrl-C (SIGINT) in the middle of a tile's write waits for the write's end, like SIGTERM
(tests/test_terminate.py): found at review, a KeyboardInterrupt raised between the tile's data chunks and
its ``done`` chunk left data without ``done``, which ``verify`` reports as damage ("unfinished")."""

from __future__ import annotations

import os
import random
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

from _proc import bifurcation, running, wait_until
from _store_helpers import assert_store_equals

# 2 laws × 8 ν_f × 32 ν in 8 tiles of 4 × 16: small, so the in-process submit takes about a second
TOML = """
[study]
name = "interrupted-write"

[engine]
laws = ["piecewise-linear", "carlson-langer"]

[grid.nu]
log = { start = 1e-3, stop = 1e-15, num = 32 }

[grid.nu_f]
ranges = [{ start = 0.02, stop = 0.96, num = 8 }]

[tiles]
nu_f = 4
nu = 16
"""


def test_ctrl_c_inside_a_tile_write_waits_for_its_end(tmp_path, monkeypatch, capsys):
    """A real SIGINT, sent to this process right after the second tile's first data chunk is written:
    the command still ends with 130 and the interrupted line, but only once that tile is whole (its
    ``done`` written), so ``verify`` finds no damage and the lock is gone."""
    import zarr

    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler   # Python's own: Ctrl-C raises
    store = tmp_path / "s.zarr"
    writes = []   # (array name) of every chunk write, in order
    setitem = zarr.Array.__setitem__

    def write(self, key, value):
        setitem(self, key, value)
        name = self.basename
        writes.append(name)
        if name != "done" and writes.count("done") == 1 and writes[-2] == "done":   # the 2nd tile's first chunk
            os.kill(os.getpid(), signal.SIGINT)   # the handler runs here, at the next bytecode

    monkeypatch.setattr(zarr.Array, "__setitem__", write)
    (tmp_path / "w.toml").write_text(TOML)
    with pytest.raises(SystemExit) as exc:
        cli.main(["submit", str(tmp_path / "w.toml"), "--store", str(store), "--workers", "1"])
    assert exc.value.code == 130
    err = capsys.readouterr().err.strip().splitlines()
    assert err[-1].startswith("bifurcation: interrupted. A submit keeps every finished tile"), err
    assert writes.count("done") == 2, writes   # the second tile was finished, no third one started
    assert writes[-1] == "done"
    monkeypatch.undo()
    assert not (store / LOCK_NAME).exists()
    report = verify(store)
    assert report.damage == () and report.ok, str(report)
    done = read_done(store)
    assert np.count_nonzero(done) == 2 * 4 * 16   # two whole tiles
    assert signal.getsignal(signal.SIGINT) is signal.default_int_handler   # restored


def test_a_deferred_ctrl_c_is_a_keyboard_interrupt():
    """``errors.stop`` with SIGINT: KeyboardInterrupt (the CLI's status 130 and line), at once outside a
    write and at the end of the outermost ``uninterrupted`` block inside one."""
    from bifurcation.errors import stop, uninterrupted

    written = []
    with pytest.raises(KeyboardInterrupt):
        with uninterrupted():
            with uninterrupted():
                stop(signal.SIGINT)
                written.append("data")
            written.append("done")
    assert written == ["data", "done"]
    with pytest.raises(KeyboardInterrupt):
        stop(signal.SIGINT)
    with uninterrupted():   # nothing pending is left over from above
        pass


#: 4608 points in 72 tiles of 64 (a few tens of ms each; ~1.4 s in all at 3300 points/s, measured at load
#: ~4): a Ctrl-C at a random time within 0.4 s of the first tile lands in a tile's computation or its write,
#: never after the end (with 24 tiles the run had once finished 0.26 s after its first tile)
RUN = (TOML.replace("num = 8", "num = 24").replace("num = 32", "num = 96")
       .replace('"interrupted-write"', '"ctrl-c"'))
N_RUNS = 6


@pytest.mark.slow   # ~4-8 s a run at load ~5: real submits, each interrupted at a random time
def test_ctrl_c_at_random_times_leaves_a_store_verify_accepts(tmp_path):
    """A real `bifurcation submit` given Ctrl-C (SIGINT to its process group, as a terminal sends it) at a
    random time after its first tile, ``N_RUNS`` times: each ends with 130 and the interrupted line, no
    traceback, no lock, and a store that ``verify`` finds sound (no tile half written)."""
    rng = random.Random(20261126)   # fixed: a failure is reproduced by running the test again
    (tmp_path / "w.toml").write_text(RUN)
    for k in range(N_RUNS):
        store = tmp_path / f"s{k}.zarr"
        delay = rng.uniform(0.0, 0.4)
        with running(bifurcation("submit", "w.toml", "--store", store, "--workers", "1"), tmp_path,
                     stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True) as run:
            wait_until(lambda: any((store / "done").rglob("c/*")), 60, "a first tile", proc=run)
            time.sleep(delay)
            os.killpg(run.pid, signal.SIGINT)
            out, err = run.communicate(timeout=60)
        where = f"run {k}, Ctrl-C {delay:.3f} s after the first tile"
        assert run.returncode == 130, (where, err)
        assert err.strip().splitlines()[-1].startswith("bifurcation: interrupted. A submit keeps every finished "
                                                       "tile"), (where, err)
        assert "Traceback" not in err, (where, err)
        assert not (store / LOCK_NAME).exists(), where
        assert 0 < np.count_nonzero(read_done(store)) < 4608, where   # stopped mid-run
        report = verify(store)
        assert report.damage == () and report.ok, (where, str(report))
    # the last one resumed: only its missing points, and the store equals an uninterrupted run bit for bit
    done = read_done(store)
    assert 0 < np.count_nonzero(done) < done.size
    workflow = load_workflow(tmp_path / "w.toml")
    summary = submit(workflow, store, workers=1, progress=False)
    assert summary.failed == 0 and summary.skipped == np.count_nonzero(done)
    assert_store_equals(store, compute_serial(workflow))


@pytest.mark.parametrize("suffix", [".nc", ".csv"])
def test_ctrl_c_inside_an_export_leaves_no_file_under_its_name(tmp_path, monkeypatch, capsys, suffix):
    """A real SIGINT while `export` is half way through writing its file (the writer patched to write part
    of it, then be interrupted): status 130, nothing under the final name, an earlier file replaced with
    --force kept as it was, no partial file left beside it (export writes ``.NAME.part-PID`` and renames)."""
    import xarray as xr

    from bifurcation.store import query as query_module

    def half_then_ctrl_c(target):
        with open(target, "wb") as fh:
            fh.write(b"half a file")
        os.kill(os.getpid(), signal.SIGINT)   # Python's handler raises KeyboardInterrupt at the next bytecode

    if suffix == ".nc":
        monkeypatch.setattr(xr.Dataset, "to_netcdf", lambda self, target, **kw: half_then_ctrl_c(target))
    else:
        monkeypatch.setattr(query_module, "write_records",
                            lambda records, fmt, fh: (fh.write("law,nu\n"), fh.flush(), half_then_ctrl_c(fh.name)))
    store = _export_store(tmp_path)
    out, earlier = tmp_path / f"e{suffix}", tmp_path / f"earlier{suffix}"
    earlier.write_bytes(b"an earlier export")
    for target, extra in ((out, []), (earlier, ["--force"])):
        with pytest.raises(SystemExit) as exc:
            cli.main(["export", "--store", str(store), "--out", str(target), *extra])
        assert exc.value.code == 130
        assert capsys.readouterr().err.strip().splitlines()[-1].startswith("bifurcation: interrupted.")
    assert not out.exists()
    assert earlier.read_bytes() == b"an earlier export"
    assert sorted(p.name for p in tmp_path.iterdir()) == ["earlier" + suffix, "s.zarr", "w.toml"]


def _export_store(tmp_path):
    """A small finished store (2 tiles of TOML's grid, in process)."""
    (tmp_path / "w.toml").write_text(TOML.replace("num = 32", "num = 16").replace("num = 8", "num = 4"))
    store = tmp_path / "s.zarr"
    summary = submit(load_workflow(tmp_path / "w.toml"), store, workers=1, progress=False)
    assert summary.complete
    return store


def test_a_study_stopped_while_writing_data_json_keeps_the_earlier_one(tmp_path, monkeypatch):
    """`study chain` writes data.json at its end (and `--presets-only`, `--catalogs-only`,
    `--published-nu-only` rewrite an existing one, the record of hours of runs). A stop inside that write
    (here: half the text written, then KeyboardInterrupt) leaves the earlier data.json whole and no partial
    file; the control shows what the in-place ``write_text`` it replaces left: a truncated file."""
    import json
    from pathlib import Path

    from bifurcation.models.chain.study import _write_data

    write_text = Path.write_text

    def half_then_stop(self, text, *args, **kwargs):
        write_text(self, text[: len(text) // 2], *args, **kwargs)
        raise KeyboardInterrupt

    earlier = {"workflow": "earlier", "runs": list(range(100))}
    (tmp_path / "data.json").write_text(json.dumps(earlier))
    monkeypatch.setattr(Path, "write_text", half_then_stop)
    with pytest.raises(KeyboardInterrupt):
        _write_data(tmp_path, {"workflow": "new", "runs": list(range(1000))})
    with pytest.raises(KeyboardInterrupt):   # control: the in-place write of before
        (tmp_path / "control.json").write_text(json.dumps(earlier))
    monkeypatch.undo()
    assert json.loads((tmp_path / "data.json").read_text()) == earlier
    with pytest.raises(json.JSONDecodeError):
        json.loads((tmp_path / "control.json").read_text())
    assert sorted(p.name for p in tmp_path.iterdir()) == ["control.json", "data.json"]
    _write_data(tmp_path, {"workflow": "new"})   # and unpatched it replaces the file
    assert json.loads((tmp_path / "data.json").read_text()) == {"workflow": "new"}
