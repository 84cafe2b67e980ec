"""The chain workflow runner's checkpoints hand over only the events since the last one (issue 21).

Before, every checkpoint joined the whole catalog so far and passed it to ``Checkpoints.save``: a copy growing
as events² (measured, one process, N = 2, 10^5 events, a checkpoint every 10: 11.9 s of CPU against 7.4 s
now, 3e9 elements handed over against 6e5). The catalogs must stay the same bit for bit: with checkpoints or
without, resumed or not, and what the checkpoints saved is the catalog's prefix."""

from __future__ import annotations

import numpy as np
import pytest

from bifurcation.models import get_model
from bifurcation.models.chain.model import run_chains

from _store_helpers import Recorder

EVENTS, EVERY = 50, 7
NAMES = ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity")


@pytest.fixture(scope="module")
def points():
    return {"n": np.array([2]), "ell": np.array([1.0]), "nu": np.array([1e-2]), "nu_f": np.array([0.3]),
            "amplitude": np.array([0.1]), "seed": np.array([1]), "events": np.array([EVENTS]),
            "periodic": np.array([0]), "sigma": np.array([0.0]), "v_threshold": np.array([0.0])}


def _bytes(out):
    return {k: (out[k][0].dtype, out[k][0].tobytes()) for k in NAMES}


def test_checkpoints_get_only_the_new_events_and_the_catalog_is_unchanged(points):
    model = get_model("chain")
    plain, _ = run_chains(model, "carlson-langer", points)
    rec = Recorder(EVERY)
    checked, _ = run_chains(model, "carlson-langer", points, checkpoints=rec)
    assert plain["events_done"][0] == checked["events_done"][0] == EVENTS
    assert _bytes(plain) == _bytes(checked)                      # bit for bit, with checkpoints or without
    assert len(rec.saves) == (EVENTS - 1) // EVERY               # at 7, 14, ..., 49
    for j, save in enumerate(rec.saves):                         # each save: only the events since the last
        assert save["first"] == j * EVERY
        assert all(len(v) == EVERY for v in save["catalog"].values()), j   # the whole catalog before
    for k in NAMES:                                              # the saves joined: the catalog's prefix
        joined = np.concatenate([s["catalog"][k] for s in rec.saves])
        assert joined.dtype == checked[k][0].dtype
        assert joined.tobytes() == checked[k][0][:len(joined)].tobytes(), k


def test_a_run_resumed_from_a_checkpoint_is_bit_identical(points):
    model = get_model("chain")
    rec = Recorder(EVERY)
    full, _ = run_chains(model, "carlson-langer", points, checkpoints=rec)
    third = rec.saves[2]                                         # at event 21
    upto = third["first"] + EVERY
    catalog = {k: np.concatenate([s["catalog"][k] for s in rec.saves[:3]]) for k in NAMES}
    resumed_rec = Recorder(EVERY, {"state": third["state"], "catalog": catalog, "steps": third["steps"]})
    resumed, _ = run_chains(model, "carlson-langer", points, checkpoints=resumed_rec)
    assert resumed["resumed"][0] == upto == 21
    assert _bytes(resumed) == _bytes(full)
    assert resumed["steps"][0] == full["steps"][0]
    assert [s["first"] for s in resumed_rec.saves] == list(range(upto, EVENTS - 1, EVERY))
