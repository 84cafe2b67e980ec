"""A report of a store that is still being written (or has points missing) says so at the top of the store's
section, not as if the study were complete (issue 21 walk)."""

from __future__ import annotations

from click.testing import CliRunner

from bifurcation.cli import cli
from bifurcation.store.lock import StoreLock


def _store(path, skip_after=None):
    from bifurcation.run.tiles import compute_tile, iter_tiles
    from bifurcation.store import create_store, write_tile
    from bifurcation.workflow import Workflow

    workflow = Workflow(name="being-written", laws=("carlson-langer",), nu=(1e-6, 1e-9), nu_f=(0.3, 0.4),
                        tiles=(1, 2))
    run_id = create_store(path, workflow)["run_id"]
    for i, tile in enumerate(iter_tiles(workflow)):
        if skip_after is None or i < skip_after:
            write_tile(path, tile, compute_tile(tile), run_id)


def _report(store, out):
    result = CliRunner().invoke(cli, ["report", "--store", str(store), "--out", str(out)])
    assert result.exit_code == 0, result.output
    return (out / "REPORT.md").read_text()


def test_report_of_a_store_being_written_says_so(tmp_path):
    store = tmp_path / "s.zarr"
    _store(store, skip_after=1)
    with StoreLock(store).acquire():
        text = _report(store, tmp_path / "r1")
    assert "**Still being written** by run " in text and "2 of 4 points done" in text, text[:2000]
    text = _report(store, tmp_path / "r2")   # the writer has gone: points missing, said as such
    assert "Still being written" not in text and "**Incomplete**: 2 of 4 points done" in text


def test_report_of_a_complete_store_has_neither_note(tmp_path):
    store = tmp_path / "s.zarr"
    _store(store)
    text = _report(store, tmp_path / "r")
    assert "Still being written" not in text and "Incomplete" not in text
