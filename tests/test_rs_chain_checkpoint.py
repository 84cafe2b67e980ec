"""Checkpoints of the rate-and-state chain (docs/rs-chain.md, "Large catalogs"): a run resumed from a
saved state gives the catalog of the straight run bit for bit — from the snapshot directly, through the
store's ``Checkpoints`` after a task that died, and (slow) after a real ``bifurcation submit`` killed -9."""

from __future__ import annotations

import dataclasses
import os
import signal
import textwrap

import numpy as np
import pytest
from click.testing import CliRunner

from bifurcation.cli import cli
from bifurcation.models import get_model
from bifurcation.models.rs_chain.checkpoint import Snapshot
from bifurcation.models.rs_chain.simulate import RSChainSpec, initial_state, run
from bifurcation.run.tiles import compute_serial, compute_tile, iter_tiles
from bifurcation.store import create_store, open_store, write_tile
from bifurcation.store.catalog import read_catalog, tile_checkpoints
from bifurcation.workflow import parse_workflow

CATALOG = ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity")
PER_EVENT = (*CATALOG, "stress_drop", "balance")
QD = dict(state_law="aging", a=0.01, b=0.015, dc=0.01, k=0.1, v_lp=1.0, eta=1e-3, v_th=10.0)


def _bits(a) -> np.ndarray:
    a = np.asarray(a)
    return a.view(np.int64) if a.dtype.kind == "f" else a


def assert_same(a, b, what="") -> None:
    """Bit for bit, NaN payloads included."""
    assert np.asarray(a).dtype == np.asarray(b).dtype, what
    np.testing.assert_array_equal(_bits(a), _bits(b), err_msg=what)


def _through_bytes(snap: Snapshot, every: int) -> Snapshot:
    """What a checkpoint file and the store give back: the state's bytes, the catalog's full chunks."""
    blobs = {name: value.tobytes() for name, value in snap.arrays(every).items()}
    return Snapshot.from_saved(blobs, snap.catalog(CATALOG, snap.boundary(every)))


def _same_run(got, ref) -> None:
    """Bit for bit; a run resumed through a checkpoint's bytes has NaN stress drop and balance for the
    events restored from the store's chunks (a checkpoint keeps only their largest balance)."""
    restored = int(np.count_nonzero(np.isnan(got.balance)))
    for name in CATALOG:
        assert_same(getattr(got, name), getattr(ref, name), name)
    for name in ("stress_drop", "balance"):
        assert_same(getattr(got, name)[restored:], getattr(ref, name)[restored:], name)
        assert np.all(np.isnan(getattr(got, name)[:restored])), name
    assert restored == 0 or got.restored_balance_max == np.max(ref.balance[:restored])
    assert got.balance_max == ref.balance_max == np.max(ref.balance)
    assert (got.steps, got.t_end, got.status) == (ref.steps, ref.t_end, ref.status)


@pytest.mark.parametrize("every", [10, 7])
def test_a_run_resumed_from_each_checkpoint_is_the_straight_run_bit_for_bit(every):
    # N = 6, 40 events, a checkpoint after events 10, 20, 30. Stored with chunk 7 the store holds 7, 14,
    # 28 of them and the checkpoint the rest (3, 6, 2 rows): both paths of Snapshot.from_saved
    spec = RSChainSpec(n=6, ell=3.0, **QD)
    s0 = initial_state(spec, 1.0, 1)
    ref = run(spec, s0, 40)
    snaps = []
    straight = run(spec, s0, 40, every=10, save=snaps.append)
    _same_run(straight, ref)                                   # saving changes nothing
    assert [len(s.rows) for s in snaps] == [10, 20, 30]
    for snap in snaps:
        resumed = run(spec, s0, 40, resume=_through_bytes(snap, every))
        _same_run(resumed, ref)
    # the double-length time is needed: resumed at the rounded time t_hi + t_lo (lo != 0 here) the later
    # events move (measured: durations by ~1e-15, potencies by ~5e-14; t_start happened to stay equal
    # from this snapshot) — so the equality above is no accident of a loose comparison
    snap = snaps[0]
    assert snap.dtime[1] != 0.0
    rounded = run(spec, s0, 40, resume=dataclasses.replace(snap, dtime=(snap.dtime[0] + snap.dtime[1], 0.0)))
    assert any(not np.array_equal(getattr(rounded, name)[10:], getattr(ref, name)[10:])
               for name in ("t_start", "potency", "duration"))


def test_an_inertial_periodic_run_resumes_bit_for_bit():
    # the z_j (net force) variables and periodic ends: N = 4, M = 1e-5, 20 events, checkpoints every 5
    spec = RSChainSpec(n=4, ell=3.0, mass=1e-5, periodic=True, **QD)
    s0 = initial_state(spec, 1.0, 2)
    snaps = []
    ref = run(spec, s0, 20, max_steps=200_000, every=5, save=snaps.append)
    assert ref.events == 20 and [len(s.rows) for s in snaps] == [5, 10, 15]
    _same_run(run(spec, s0, 20, max_steps=200_000, resume=_through_bytes(snaps[1], 5)), ref)


def test_a_compact_mode_chain_resumes_bit_for_bit():
    # N > _system.COMPACT_ABOVE = 16 compiles heyoka's compact mode (as N = 256 of
    # workflows/rs-chain-large.toml): N = 20, 30 events
    from bifurcation.models.rs_chain._system import COMPACT_ABOVE

    assert COMPACT_ABOVE < 20
    spec = RSChainSpec(n=20, ell=3.0, **QD)
    s0 = initial_state(spec, 1.0, 1)
    snaps = []
    ref = run(spec, s0, 30, every=10, save=snaps.append)
    assert [len(s.rows) for s in snaps] == [10, 20]
    _same_run(run(spec, s0, 30, resume=_through_bytes(snaps[1], 10)), ref)


def test_a_snapshot_inside_an_event_survives_the_bytes():
    # the saves of a run come after an event closed, usually with none open; a step may close one and
    # open the next, so the open event's bookkeeping must round-trip too (values here are arbitrary)
    rows = [(0.5 * e, e % 3, 1 + e % 2, 0.25 + e, 0.125, 11.0 + e, 1e-3 * e, 1e-14 * e) for e in range(5)]
    snap = Snapshot(state=np.linspace(-1.0, 1.0, 7), dtime=(3.0, -1.25e-16), steps=(1234, 56),
                    above=np.array([False, True, False]), current={"t_start": 2.5, "hypocentre": 1,
                                                                    "blocks": {1, 2}, "vmax": 12.5,
                                                                    "p0": 0.1, "s0": -0.3},
                    t_last=2.25, rows=rows)
    back = _through_bytes(snap, 2)
    assert_same(back.state, snap.state)
    assert (back.dtime, back.steps, back.t_last, back.current) == (snap.dtime, snap.steps, snap.t_last, snap.current)
    # the 4 rows of the full chunks come back from the catalog, with only their largest balance; the 5th whole
    assert [r[:6] for r in back.rows] == [r[:6] for r in snap.rows] and back.rows[4] == snap.rows[4]
    assert all(np.isnan(r[6]) and np.isnan(r[7]) for r in back.rows[:4]) and back.balance_max == rows[3][7]
    # and a checkpoint's size does not grow with the events before its last full chunk
    many = dataclasses.replace(snap, rows=rows * 200 + rows[:1])        # 1001 events, 1 past the last chunk
    assert sum(a.nbytes for a in many.arrays(2).values()) == sum(a.nbytes for a in snap.arrays(2).values())
    assert_same(back.above, snap.above)
    assert _through_bytes(dataclasses.replace(snap, current=None), 2).current is None


def test_a_checkpoint_of_the_former_layout_still_resumes():
    # before 2026-11-26 a checkpoint held the stress drop and balance of every event (16 bytes per event
    # so far) instead of "events" and "balance_max": such a file, left by an interrupted study, must resume
    spec = RSChainSpec(n=6, ell=3.0, **QD)
    s0 = initial_state(spec, 1.0, 1)
    snaps = []
    ref = run(spec, s0, 25, every=10, save=snaps.append)
    snap = snaps[1]                                                     # 20 events, chunk 7: 14 stored, 6 in tail
    blobs = {k: v.tobytes() for k, v in snap.arrays(7).items() if k not in ("events", "balance_max")}
    blobs["stress_drop"] = np.array([r[6] for r in snap.rows]).tobytes()
    blobs["balance"] = np.array([r[7] for r in snap.rows]).tobytes()
    back = Snapshot.from_saved(blobs, snap.catalog(CATALOG, snap.boundary(7)))
    assert back.rows == snap.rows                                       # every value, as the file held them
    resumed = run(spec, s0, 25, resume=back)
    for name in PER_EVENT:
        assert_same(getattr(resumed, name), getattr(ref, name), name)
    blobs["balance"] = blobs["balance"][:-8]                            # one event short: not this run's
    with pytest.raises(ValueError, match="checkpoint holds -1 events"):
        Snapshot.from_saved(blobs, snap.catalog(CATALOG, snap.boundary(7)))


WORKFLOW = textwrap.dedent("""
    [study]
    name = "rs-chain-checkpoint-test"
    [model]
    name = "rs-chain"
    [engine]
    laws = ["aging"]
    [grid.n]
    values = [6]
    [grid.k]
    values = [0.1]
    [grid.ell]
    values = [3.0]
    [grid.events]
    values = [40]
    [tiles]
    catalog = 10
    """)


def test_a_task_killed_after_two_checkpoints_resumes_from_the_store_bit_identical(tmp_path, monkeypatch):
    """In process, as the chain's: the task dies (an exception) right after its 2nd checkpoint of a
    40-event run (C = 10); the recomputed tile restores 20 events from the store and its catalog and
    per-run outputs equal the uninterrupted run's; the checkpoint is dropped once the tile is written."""
    from bifurcation.store.catalog import Checkpoints

    model = get_model("rs-chain")
    assert model.checkpoint
    workflow = parse_workflow(WORKFLOW)
    serial = compute_serial(workflow)        # no checkpoints
    path = tmp_path / "ck.zarr"
    run_id = create_store(path, workflow)["run_id"]
    (tile,) = list(iter_tiles(workflow))
    calls = []
    original = Checkpoints.save

    def dying(self, i, *args, **kwargs):
        original(self, i, *args, **kwargs)
        calls.append(i)
        if len(calls) == 2:
            raise KeyboardInterrupt("killed")   # not an Exception: nothing catches it on the way out

    monkeypatch.setattr(Checkpoints, "save", dying)
    with pytest.raises(KeyboardInterrupt):
        compute_tile(tile, tile_checkpoints(path, run_id, tile))
    monkeypatch.undo()
    assert [f.name for f in (path / "checkpoints").glob("*.npz")] == ["0.npz"]
    values = compute_tile(tile, tile_checkpoints(path, run_id, tile))
    assert values["resumed"].ravel()[0] == 20
    for name in (*CATALOG, "events_done", "t_end", "steps", "balance_max", "status"):
        got, want = values[name].ravel(), serial[name].ravel()
        for k in range(got.size):
            assert_same(got[k], want[k], name)
    write_tile(path, tile, values, run_id)
    assert not list((path / "checkpoints").glob("*.npz"))
    cat = read_catalog(path, law="aging")
    for name in CATALOG:
        assert_same(cat[name], serial[name].ravel()[0], name)


KILL = WORKFLOW.replace("values = [40]", "values = [6000]").replace("catalog = 10", "catalog = 500") \
    .replace("values = [6]", "values = [4]")


@pytest.mark.slow   # ~15 s: kills and resumes a real submit; the resume itself is tested fast above
@pytest.mark.distributed
def test_a_killed_submit_is_resumed_by_the_next_from_the_checkpoint(tmp_path):
    """`bifurcation submit` (embedded cluster) killed -9 with its process group after the run's first
    checkpoint (a 6000-event N = 4 run, C = 500); the next submit resumes from the checkpoint and the
    stored catalog equals the uninterrupted in-process run bit for bit."""
    from _proc import bifurcation, start, stop, wait_until

    wf = tmp_path / "kill.toml"
    wf.write_text(KILL)
    store = tmp_path / "killed.zarr"
    proc = start(bifurcation("submit", wf, "--store", store, "--workers", "1"), tmp_path, "submit")
    try:
        wait_until(lambda: (store / "checkpoints" / "0.npz").exists(), 120, "the first checkpoint", proc=proc,
                   detail=lambda: (tmp_path / "submit.log").read_text())
        os.killpg(proc.pid, signal.SIGKILL)
        proc.wait(10)
    finally:
        stop(proc)
    assert not open_store(store)["done"].values.any()
    result = CliRunner().invoke(cli, ["submit", str(wf), "--store", str(store), "--workers", "1", "--json"])
    assert result.exit_code == 0, result.output
    cat = read_catalog(store, law="aging")
    assert 0 < cat["run"]["resumed"] < 6000 and cat["run"]["resumed"] % 500 == 0
    reference = compute_serial(parse_workflow(KILL))
    for name in CATALOG:
        assert_same(cat[name], reference[name].reshape(-1)[0], name)
    assert not list((store / "checkpoints").glob("*.npz"))


class _MemoryCheckpoints:
    """The runner's side of ``store.catalog.Checkpoints`` in memory: what ``save`` got, ``load`` gives."""

    def __init__(self, every: int, saved=None) -> None:
        self.every, self.saved, self.calls = every, saved, []

    def load(self, i):
        return self.saved

    def save(self, i, state, catalog, *, steps, first=0):
        # ``catalog`` holds the events from ``first`` on, those before were saved earlier (as the store's)
        before = self.saved["catalog"] if first else {k: np.array(v[:0]) for k, v in catalog.items()}
        assert len(before["t_start"]) >= first, "events before first never saved"
        catalog = {k: np.concatenate([before[k][:first], v]) for k, v in catalog.items()}
        self.calls.append((i, len(catalog["t_start"]), steps))
        self.saved = {"state": {k: np.ascontiguousarray(v).tobytes() for k, v in state.items()},
                      "catalog": catalog, "steps": steps, "events": len(catalog["t_start"])}


def test_the_runner_saves_at_each_chunk_and_ignores_a_checkpoint_that_does_not_fit():
    model = get_model("rs-chain")
    given = {"n": 6, "k": 0.1, "ell": 3.0, "events": 40}          # the rest: the axes' defaults
    points = {a.name: np.asarray([given.get(a.name, a.default)], dtype=a.dtype) for a in model.axes}
    straight, _ = model.runner(model, "aging", points)
    memory = _MemoryCheckpoints(10)
    saving, _ = model.runner(model, "aging", points, checkpoints=memory)
    assert [c[1] for c in memory.calls] == [10, 20, 30]          # full chunks only, as the store needs
    good = memory.saved
    resumed, _ = model.runner(model, "aging", points, checkpoints=_MemoryCheckpoints(10, good))
    assert resumed["resumed"][0] == 30
    # a checkpoint of a chain of another size (a state of 5 values), or with its bytes cut: start over
    wrong = {**good, "state": {**good["state"], "state": good["state"]["state"][:40]}}
    cut = {**good, "state": {**good["state"], "tail": b"\0" * 12}}
    over1, _ = model.runner(model, "aging", points, checkpoints=_MemoryCheckpoints(10, wrong))
    over2, _ = model.runner(model, "aging", points, checkpoints=_MemoryCheckpoints(10, cut))
    assert over1["resumed"][0] == over2["resumed"][0] == 0
    for values in (saving, resumed, over1, over2):
        for name in (*CATALOG, "steps", "t_end", "balance_max", "events_done"):
            got, want = values[name], straight[name]
            if got.dtype == object:
                got, want = got[0], want[0]
            assert_same(got, want, name)
