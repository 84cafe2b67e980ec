"""The rs-chain runner's checkpoints hand over only the events since the last one (issue 21), as the chain's
(tests/test_chain_checkpoint_append.py). Before, every checkpoint rebuilt the whole catalog so far from the
event rows and passed it to ``Checkpoints.save``: a copy growing as events² (measured in the commit that
made this change). Catalogs and checkpoint contents must stay the same bit for bit: with checkpoints or
without, resumed or not; the saves joined are the catalog's prefix; each save's state bytes are those the
whole-catalog runner saved: compared with the snapshots of a straight ``simulate.run`` and, for the
stress drop and balance (the largest balance of the events in full chunks, both of those past them), with
that run's own result arrays (built apart from ``Snapshot.arrays``)."""

from __future__ import annotations

import numpy as np
import pytest

from bifurcation.models import get_model
from bifurcation.models.rs_chain.model import run_rs_chains
from bifurcation.models.rs_chain.simulate import RSChainSpec, initial_state, run

from _store_helpers import Recorder

EVENTS, EVERY = 45, 7
NAMES = ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity")
QD = dict(a=0.01, b=0.015, dc=0.01, k=0.1, v_lp=1.0, eta=1e-3, v_th=10.0)


@pytest.fixture(scope="module")
def points():
    p = {"n": 4, "ell": 3.0, "mass": 0.0, "periodic": 0, "amplitude": 1.0, "seed": 1, "events": EVENTS, **QD}
    return {k: np.array([v]) for k, v in p.items()}


def _bytes(out):
    return {k: (out[k][0].dtype, out[k][0].tobytes()) for k in NAMES}


def test_checkpoints_get_only_the_new_events_and_nothing_else_changes(points):
    model = get_model("rs-chain")
    plain, _ = run_rs_chains(model, "aging", points)
    rec = Recorder(EVERY)
    checked, _ = run_rs_chains(model, "aging", points, checkpoints=rec)
    assert plain["events_done"][0] == checked["events_done"][0] == EVENTS
    assert _bytes(plain) == _bytes(checked)                      # bit for bit, with checkpoints or without
    assert plain["steps"][0] == checked["steps"][0]
    assert len(rec.saves) == (EVENTS - 1) // EVERY               # at 7, 14, ..., 42
    for j, save in enumerate(rec.saves):                         # each save: only the events since the last
        assert save["first"] == j * EVERY
        assert all(len(v) == EVERY for v in save["catalog"].values()), j   # the whole catalog before
    for k in NAMES:                                              # the saves joined: the catalog's prefix
        joined = np.concatenate([s["catalog"][k] for s in rec.saves])
        assert joined.dtype == checked[k][0].dtype
        assert joined.tobytes() == checked[k][0][:len(joined)].tobytes(), k
    # the state bytes: those of the snapshots a straight run hands to save (the whole-catalog runner's)
    spec = RSChainSpec(n=4, ell=3.0, state_law="aging", **QD)
    snaps = []
    straight = run(spec, initial_state(spec, 1.0, 1), EVENTS, every=EVERY, save=snaps.append)
    assert len(snaps) == len(rec.saves)
    for snap, save in zip(snaps, rec.saves):
        assert {k: v.tobytes() for k, v in snap.arrays(EVERY).items()} == save["state"]
        assert save["steps"] == snap.steps[0]
        # the per-event values the catalog does not keep, against the straight run's own arrays (built
        # apart from Snapshot.arrays): of the events in full chunks only the largest balance, of those past
        # them the whole rows (stress drop and balance the last two columns)
        done, cut = len(snap.rows), snap.boundary(EVERY)
        assert save["state"]["balance_max"] == np.array([np.max(straight.balance[:cut])]).tobytes()
        assert save["state"]["events"] == np.array([done], dtype=np.int64).tobytes()
        tail = np.frombuffer(save["state"]["tail"], dtype=np.float64).reshape(-1, 8)
        assert tail[:, 6].tobytes() == straight.stress_drop[cut:done].tobytes()
        assert tail[:, 7].tobytes() == straight.balance[cut:done].tobytes()


def test_a_run_resumed_from_a_checkpoint_is_bit_identical(points):
    model = get_model("rs-chain")
    rec = Recorder(EVERY)
    full, _ = run_rs_chains(model, "aging", points, checkpoints=rec)
    third = rec.saves[2]                                         # at event 21
    upto = third["first"] + EVERY
    catalog = {k: np.concatenate([s["catalog"][k] for s in rec.saves[:3]]) for k in NAMES}
    resumed_rec = Recorder(EVERY, {"state": third["state"], "catalog": catalog, "steps": third["steps"]})
    resumed, _ = run_rs_chains(model, "aging", points, checkpoints=resumed_rec)
    assert resumed["resumed"][0] == upto == 21
    assert _bytes(resumed) == _bytes(full)
    assert resumed["steps"][0] == full["steps"][0]
    # the resumed run's saves go on from the stored events, and are those of the uninterrupted run
    assert [s["first"] for s in resumed_rec.saves] == [s["first"] for s in rec.saves[3:]] == [21, 28, 35]
    for got, ref in zip(resumed_rec.saves, rec.saves[3:]):
        assert got["state"] == ref["state"] and got["first"] == ref["first"]
        assert all(got["catalog"][k].tobytes() == ref["catalog"][k].tobytes() for k in NAMES)
