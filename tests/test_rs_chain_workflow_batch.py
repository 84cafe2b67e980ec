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

# N = 5 quasi-dynamic (aging law, η = 1e-3, k = 0.1); 3 seeds x 2 couplings = 6 points in one tile: 6 chains
# of one structure in 4 lanes (two refills).
WORKFLOW = textwrap.dedent("""
    [study]
    name = "rs-batch"
    [model]
    name = "rs-chain"
    [engine]
    laws = ["aging"]
    batch = {batch}
    [grid.n]
    values = [5]
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

    workflow = parse_workflow(WORKFLOW.format(batch=batch, catalog=8))
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
            direct = run(spec := RSChainSpec(n=5, ell=ell, **QD), initial_state(spec, 1.0, seed), 8, crossings=True)
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


def test_the_runner_batches_only_runs_it_would_not_checkpoint():
    # a run of more events than the checkpoint chunk keeps its checkpoints (scalar, bit for bit); one
    # within it goes to the lanes
    from bifurcation.models import get_model
    from bifurcation.models.rs_chain.model import run_rs_chains

    class Saves:
        every = 4

        def __init__(self):
            self.saved = []

        def load(self, i):
            return None

        def save(self, i, state, catalog, *, steps, first=0):
            self.saved.append(i)

    n = 4
    points = {"n": np.full(n, 4), "k": np.full(n, 0.1), "ell": np.full(n, 2.0), "v_lp": np.ones(n),
              "a": np.full(n, 0.01), "b": np.full(n, 0.015), "dc": np.full(n, 0.01), "mass": np.zeros(n),
              "eta": np.full(n, 1e-3), "v_th": np.full(n, 10.0), "amplitude": np.ones(n),
              "seed": np.array([1, 2, 3, 4]), "events": np.array([9, 9, 4, 4]), "periodic": np.zeros(n, dtype=int)}
    model = get_model("rs-chain")
    cp1, cp4 = Saves(), Saves()
    f1, _ = run_rs_chains(model, "aging", points, checkpoints=cp1)
    f4, _ = run_rs_chains(model, "aging", points, batch=4, checkpoints=cp4)
    assert cp1.saved == cp4.saved == [0, 0, 1, 1]      # 9 events, every 4: saves after 4 and 8
    for name in CATALOG:
        for i in (0, 1):     # the checkpointed runs: the scalar engine's bits
            assert np.array_equal(f1[name][i], f4[name][i])
        for i in (2, 3):     # the lanes: rounding only
            assert np.max(np.abs(f4[name][i] / f1[name][i] - 1)) <= 1e-11
    assert any(not np.array_equal(f1[name][i], f4[name][i]) for name in CATALOG for i in (2, 3))


@pytest.mark.parametrize("text, message", [
    (WORKFLOW.format(batch=4, catalog=5), "engine.batch=4: runs without checkpoints, and grid.events reaches 8 > "
     "[tiles] catalog = 5"),
    (WORKFLOW.format(batch=4, catalog=8).replace("ell = 2\nseed = 3\n", ""), "engine.batch=4: has no lanes"),
    (WORKFLOW.format(batch=0, catalog=8), "engine.batch=0: is not a lane count"),
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
