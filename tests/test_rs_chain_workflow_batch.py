"""``[engine] batch`` for rs-chain workflows: a tile's chains of one structure in the SIMD lanes of
``rs_chain.batch.run_batch`` (docs/rs-chain.md, "Batch mode in workflows").

Reference: the same workflow with batch = 1 (the scalar engine, itself ≤ 1.8e-14 from the mpmath references
of tests/test_rs_chain.py), through the same store path. Bound 1e-11 relative per event: run_batch agrees
with the scalar runs to rounding, measured ≤ 1.1e-12 over 10-12 events of 4-8 chains at N = 4-64
(tests/test_rs_chain_batch.py); a 9x margin for rounding amplified from event to event.
"""

from __future__ import annotations

import textwrap

import numpy as np
import pytest

from bifurcation.errors import InputError
from bifurcation.models.rs_chain.simulate import RSChainSpec, initial_state, run
from bifurcation.workflow import parse_workflow

CATALOG = ("t_start", "potency", "duration", "max_velocity")
QD = dict(state_law="aging", a=0.01, b=0.015, dc=0.01, k=0.1, v_lp=1.0, eta=1e-3, v_th=10.0)

# N = 6 quasi-dynamic (aging law, η = 1e-3, k = 0.1); 3 seeds x 2 couplings = 6 points in one tile: 6 chains
# of one structure in 4 lanes (two refills). N = 6: the scalar and 4-lane integrators tests/test_rs_chain_checkpoint.py
# and tests/test_rs_chain_batch.py compile anyway (N = 5 compiled two of its own: ~2 s of CPU on an empty heyoka cache).
WORKFLOW = textwrap.dedent("""
    [study]
    name = "rs-batch"
    [model]
    name = "rs-chain"
    [engine]
    laws = ["aging"]
    batch = {batch}
    [grid.n]
    values = [6]
    [grid.k]
    values = [0.1]
    [grid.ell]
    values = [1.0, 3.0]
    [grid.eta]
    values = [1e-3]
    [grid.seed]
    values = [1, 2, 3]
    [grid.events]
    values = [8]
    [tiles]
    ell = 2
    seed = 3
    catalog = {catalog}
    """)


def _store(tmp_path, batch: int):
    from bifurcation.run.tiles import iter_tiles, compute_tile
    from bifurcation.store import create_store, open_store, write_tile
    from bifurcation.store.catalog import tile_checkpoints

    workflow = parse_workflow(WORKFLOW.format(batch=batch, catalog=3))   # saves after 3 and 6 of 8 events
    path = tmp_path / f"b{batch}.zarr"
    run_id = create_store(path, workflow)["run_id"]
    for tile in iter_tiles(workflow):     # as submit does: the store's checkpoints handed to the runner
        write_tile(path, tile, compute_tile(tile, checkpoints=tile_checkpoints(path, run_id, tile)), run_id)
    return workflow, path, open_store(path)


def test_batch_4_equals_batch_1_per_event_through_the_store(tmp_path):
    from bifurcation.store.catalog import read_catalog

    w1, p1, d1 = _store(tmp_path, 1)
    w4, p4, d4 = _store(tmp_path, 4)
    assert w4.fingerprint != w1.fingerprint
    assert np.array_equal(d1["status"].values, d4["status"].values)
    assert (d1["status"].values == 1).all()          # every run complete (status 1: RSChainStatus.COMPLETE)
    assert np.array_equal(d1["events_done"].values, d4["events_done"].values)
    assert (d4["events_done"].values == 8).all()
    # steps: each lane takes its own steps, so equal counts (measured equal: tests/test_rs_chain_batch.py)
    assert np.array_equal(d1["steps"].values, d4["steps"].values)
    worst, ties = 0.0, 0
    for ell in (1.0, 3.0):
        for seed in (1, 2, 3):
            a = read_catalog(p1, law="aging", ell=ell, seed=seed)
            b = read_catalog(p4, law="aging", ell=ell, seed=seed)
            assert len(a["t_start"]) == len(b["t_start"]) == 8
            assert np.array_equal(a["n_blocks"], b["n_blocks"]), (ell, seed)
            # hypocentres: equal, except where the scalar run's first two up-crossings of the event are
            # within 1e-9 of t (a tie that rounding decides; tests/test_rs_chain_batch.py's rule): at ℓ = 3
            # the free ends synchronise (gaps 2e-16 .. 0 from the 6th event), and there either tied block
            direct = run(spec := RSChainSpec(n=6, ell=ell, **QD), initial_state(spec, 1.0, seed), 8, crossings=True)
            assert np.array_equal(direct.t_start, a["t_start"])       # the batch = 1 store is the scalar run
            up = direct.crossings[direct.crossings[:, 2] == 1]
            for i, (t0, d) in enumerate(zip(direct.t_start, direct.duration)):
                first = up[(up[:, 0] >= t0) & (up[:, 0] <= t0 + d)]
                if len(first) < 2 or first[1, 0] - first[0, 0] > 1e-9 * t0:
                    assert a["hypocentre"][i] == b["hypocentre"][i], (ell, seed, i)
                else:
                    ties += 1
                    tied = first[first[:, 0] - first[0, 0] <= 1e-9 * t0, 1]     # every block of the tie
                    assert b["hypocentre"][i] in tied, (ell, seed, i, tied)
            for name in CATALOG:
                err = np.max(np.abs(np.asarray(b[name]) / np.asarray(a[name]) - 1))
                worst = max(worst, err)
                assert err <= 1e-11, (ell, seed, name, err)
    # the batched runs really are not the scalar ones bit for bit (else the lanes were not used)
    assert worst > 0.0
    assert 0 < ties < 48          # measured: the ℓ = 3 runs' last events (gaps 0 .. 2.4e-9 relative)
    print(f"worst relative difference {worst:.2e}, {ties} tied hypocentres")


class _Saves:
    """A store's ``Checkpoints`` in memory: what the runner saves, by point."""

    def __init__(self, every: int, saved=None):
        self.every, self.saved, self.calls = every, dict(saved or {}), []

    def load(self, i):
        return self.saved.get(i)

    def save(self, i, state, catalog, *, steps, first=0):
        self.calls.append(i)
        old = self.saved.get(i)
        if old is not None and first:        # the store appends the events since the last save
            catalog = {k: np.concatenate([old["catalog"][k][:first], v]) for k, v in catalog.items()}
        self.saved[i] = {"state": {k: np.array(v, copy=True) for k, v in state.items()}, "catalog": catalog}


def _points(events):
    n = len(events)
    return {"n": np.full(n, 4), "k": np.full(n, 0.1), "ell": np.full(n, 2.0), "v_lp": np.ones(n),
            "a": np.full(n, 0.01), "b": np.full(n, 0.015), "dc": np.full(n, 0.01), "mass": np.zeros(n),
            "eta": np.full(n, 1e-3), "v_th": np.full(n, 10.0), "amplitude": np.ones(n),
            "seed": np.arange(1, n + 1), "events": np.array(events), "periodic": np.zeros(n, dtype=int)}


def test_lanes_save_checkpoints_where_the_scalar_runs_do():
    from bifurcation.models import get_model
    from bifurcation.models.rs_chain.model import run_rs_chains

    model, points = get_model("rs-chain"), _points([9, 9, 9, 9, 9, 4])
    cp1, cp4 = _Saves(4), _Saves(4)
    f1, _ = run_rs_chains(model, "aging", points, checkpoints=cp1)
    f4, _ = run_rs_chains(model, "aging", points, batch=4, checkpoints=cp4)
    # 9 events, every 4: saves after 4 and 8 (none after 9: no events remain); 4 events: none
    assert sorted(cp1.calls) == sorted(cp4.calls) == [0, 0, 1, 1, 2, 2, 3, 3, 4, 4]
    for i in range(5):
        assert cp4.saved[i]["catalog"]["t_start"].size == 8
        assert np.max(np.abs(cp4.saved[i]["catalog"]["t_start"] / cp1.saved[i]["catalog"]["t_start"] - 1)) <= 1e-11
    for name in CATALOG:
        for i in range(6):
            assert np.max(np.abs(f4[name][i] / f1[name][i] - 1)) <= 1e-11, (name, i)
    assert np.array_equal(f1["steps"], f4["steps"]) and (f4["resumed"] == 0).all()


def test_a_batch_resumed_from_its_lanes_checkpoints_is_the_straight_batch_bit_for_bit():
    # the batch killed after each save in turn (its checkpoints so far kept), then the same call again:
    # every run resumes from its last checkpoint and ends with the straight batch's bits (a lane's steps
    # depend on its own column only; tests/test_rs_chain_checkpoint.py's claim for the scalar engine)
    from bifurcation.models import get_model
    from bifurcation.models.rs_chain.model import run_rs_chains

    class Killed(Exception):
        pass

    model, points = get_model("rs-chain"), _points([9, 9, 9, 9, 9])
    straight_cp = _Saves(4)
    straight, _ = run_rs_chains(model, "aging", points, batch=4, checkpoints=straight_cp)
    n_saves = len(straight_cp.calls)
    for kill_after in (1, 4, n_saves - 1):
        cp = _Saves(4)
        real = cp.save

        def dying(i, *args, real=real, cp=cp, kill_after=kill_after, **kwargs):
            real(i, *args, **kwargs)
            if len(cp.calls) == kill_after:
                raise Killed

        cp.save = dying
        with pytest.raises(Killed):
            run_rs_chains(model, "aging", points, batch=4, checkpoints=cp)
        cp.save = real
        again, _ = run_rs_chains(model, "aging", points, batch=4, checkpoints=cp)
        assert (again["resumed"] > 0).any() and set(again["resumed"]) <= {0, 4, 8}
        for name in CATALOG + ("hypocentre", "n_blocks"):
            for i in range(5):
                assert np.array_equal(again[name][i], straight[name][i]), (kill_after, name, i)
        assert np.array_equal(again["steps"], straight["steps"])
        assert np.array_equal(again["events_done"], straight["events_done"])


def test_a_batch_tile_killed_after_three_checkpoints_resumes_from_the_store_bit_identical(tmp_path, monkeypatch):
    """As tests/test_rs_chain_checkpoint.py's for the scalar engine: the task dies right after its 3rd
    checkpoint; the recomputed tile restores those runs from the store and equals the uninterrupted batch
    tile (compute_serial: no checkpoints) bit for bit; the checkpoints are dropped once the tile is written."""
    from bifurcation.run.tiles import compute_serial, compute_tile, iter_tiles
    from bifurcation.store import create_store, write_tile
    from bifurcation.store.catalog import Checkpoints, tile_checkpoints

    workflow = parse_workflow(WORKFLOW.format(batch=4, catalog=3))
    serial = compute_serial(workflow)
    path = tmp_path / "ck.zarr"
    run_id = create_store(path, workflow)["run_id"]
    (tile,) = list(iter_tiles(workflow))
    calls = []
    original = Checkpoints.save

    def dying(self, i, *args, **kwargs):
        original(self, i, *args, **kwargs)
        calls.append(i)
        if len(calls) == 3:
            raise KeyboardInterrupt("killed")

    monkeypatch.setattr(Checkpoints, "save", dying)
    with pytest.raises(KeyboardInterrupt):
        compute_tile(tile, tile_checkpoints(path, run_id, tile))
    monkeypatch.undo()
    assert len(list((path / "checkpoints").glob("*.npz"))) == 3
    values = compute_tile(tile, tile_checkpoints(path, run_id, tile))
    assert sorted(values["resumed"].ravel()) == [0, 0, 0, 3, 3, 3]
    for name in (*CATALOG, "hypocentre", "n_blocks", "events_done", "t_end", "steps", "balance_max", "status"):
        got, want = values[name].ravel(), serial[name].ravel()
        for k in range(got.size):
            assert np.array_equal(got[k], want[k], equal_nan=np.asarray(want[k]).dtype.kind == "f"), (name, k)
    write_tile(path, tile, values, run_id)
    assert not list((path / "checkpoints").glob("*.npz"))


@pytest.mark.parametrize("text, message", [
    (WORKFLOW.format(batch=4, catalog=8).replace("ell = 2\nseed = 3\n", ""), "engine.batch=4: has no lanes"),
    (WORKFLOW.format(batch=0, catalog=8), "engine.batch=0: is not a lane count"),
    # tiles of several points, but no two of one structure: N differs, then η = 0 with M = 0 (never batched),
    # then the events: each ran one by one, silently, before this check
    (WORKFLOW.format(batch=4, catalog=8).replace("values = [6]", "values = [4, 6]").replace("ell = 2\nseed = 3\n",
                                                                                         "n = 2\n"),
     "engine.batch=4: has no lanes to fill: no tile holds two chains of one structure"),
    (WORKFLOW.format(batch=4, catalog=8).replace("values = [1e-3]", "values = [0.0]"),
     "engine.batch=4: has no lanes to fill: no tile holds two chains of one structure"),
    (WORKFLOW.format(batch=4, catalog=8).replace("values = [8]", "values = [8, 9]").replace(
        "ell = 2\nseed = 3\n", "events = 2\n"), "engine.batch=4: has no lanes to fill: no tile holds two"),
    (WORKFLOW.format(batch=65, catalog=8), "engine.batch=65: is more than 64 lanes"),
])
def test_a_batch_it_cannot_honour_is_refused_in_one_line(text, message):
    with pytest.raises(InputError) as exc:
        parse_workflow(text)
    assert message in str(exc.value) and "\n" not in str(exc.value)
    assert "fix" in repr(exc.value) or exc.value.fix


def test_the_fingerprint_of_a_batch_differs_from_the_scalar_and_from_other_lanes():
    prints = {b: parse_workflow(WORKFLOW.format(batch=b, catalog=8)).fingerprint for b in (1, 2, 4, 8)}
    assert len(set(prints.values())) == 4
    # the scalar fingerprint does not depend on rs-chain's batch revision (stores begun before keep theirs)
    from bifurcation.models import get_model

    assert get_model("rs-chain").batch_revision == 1
