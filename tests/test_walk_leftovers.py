"""Found on the issue-21 walk: a --scheduler that answers but is no dask scheduler, --nearest far outside the
model's bounds, and a store of an older layout; each was a traceback or a wrong answer, now one line."""

from __future__ import annotations

import shutil
import socket
import threading
import time

from click.testing import CliRunner

from bifurcation.cli import cli

FIG = """\
[study]
name = "walk"
[engine]
laws = ["carlson-langer"]
[grid.nu]
values = [1e-6, 1e-9]
[grid.nu_f]
values = [0.3, 0.4]
"""


def _one_line(result, needle: str) -> str:
    assert result.exception is None or isinstance(result.exception, SystemExit), repr(result.exception)
    assert result.exit_code == 2, result.output
    errors = [l for l in result.stderr.splitlines() if l.startswith("bifurcation: error: ")]
    assert len(errors) == 1 and needle in errors[0], result.stderr
    assert "Traceback" not in result.output and "Exception ignored" not in result.stderr
    return errors[0]


def test_scheduler_that_answers_as_http_is_one_line(tmp_path):
    """An HTTP server (the dashboard's port 8787 given for the scheduler's 8786): distributed read its reply
    as a 3 EiB frame (MemoryError traceback), then waited 20 s in the half-built Client's __del__."""
    server = socket.socket()
    server.bind(("127.0.0.1", 0))
    server.listen(4)
    port = server.getsockname()[1]

    def serve():
        while True:
            try:
                conn, _ = server.accept()
            except OSError:
                return
            try:
                conn.sendall(b"HTTP/1.1 400 Bad Request\r\nContent-Length: 0\r\n\r\n" * 4)
                conn.recv(65536)
            except OSError:
                pass
            conn.close()

    threading.Thread(target=serve, daemon=True).start()
    wf = tmp_path / "w.toml"
    wf.write_text(FIG)
    try:
        started = time.perf_counter()
        result = CliRunner().invoke(cli, ["submit", str(wf), "--store", str(tmp_path / "s.zarr"),
                                          "--scheduler", f"tcp://127.0.0.1:{port}"])
        elapsed = time.perf_counter() - started
    finally:
        server.close()
    _one_line(result, "answered, but not as a dask scheduler")
    assert elapsed < 15, elapsed   # (was 20 s more in __del__; a bound, not a timing claim)
    assert not (tmp_path / "s.zarr").exists()


def _store(path):
    from bifurcation.run.tiles import compute_tile, iter_tiles
    from bifurcation.store import create_store, write_tile
    from bifurcation.workflow import parse_workflow

    workflow = parse_workflow(FIG)
    run_id = create_store(path, workflow)["run_id"]
    for tile in iter_tiles(workflow):
        write_tile(path, tile, compute_tile(tile), run_id)


def test_nearest_outside_the_model_bounds_is_refused(tmp_path):
    _store(tmp_path / "s.zarr")
    for value in ("-1", "1e300"):   # took the nearest label (1e-9, 1e-6) and printed its rows, exit 0
        result = CliRunner().invoke(cli, ["query", "--store", str(tmp_path / "s.zarr"), "--law", "carlson-langer",
                                          "--nearest", "--nu", value])
        _one_line(result, "the model's bounds of ν")
    ok = CliRunner().invoke(cli, ["query", "--store", str(tmp_path / "s.zarr"), "--law", "carlson-langer",
                                  "--nearest", "--nu", "2e-9"])
    assert ok.exit_code == 0 and "took the nearest, 1e-09" in ok.stderr, ok.output


def test_store_of_an_older_layout_is_one_line(tmp_path):
    """A store written before an axis was added (results/chain-study.zarr of 2026-11-25 has no sigma): query
    and report failed with KeyError 'sigma'. Made here by removing an axis's coordinate array."""
    store = tmp_path / "s.zarr"
    _store(store)
    shutil.rmtree(store / "nu_f")
    for argv in (["query", "--store", str(store), "--law", "carlson-langer"],
                 ["report", "--store", str(store), "--out", str(tmp_path / "r")],
                 ["status", "--store", str(store)]):
        _one_line(CliRunner().invoke(cli, argv), "was written by an older version of bifurcation")
    assert not (tmp_path / "r").exists()
