"""The rs-chain batch engine (bifurcation/models/rs_chain/batch.py): chains of one structure in the SIMD
lanes of one heyoka batch integrator, each lane with the scalar engine's events and catalog assembly.

References: the scalar engine (``simulate.run``, itself ≤ 1.8e-14 from the mpmath references) and the
mpmath references of tests/data/rs_chain_reference.json directly (40 digits, order 30; see
tests/test_rs_chain.py). Only the arithmetic is vectorised (SIMD exp and division), so a lane agrees
with the scalar run to rounding, amplified from event to event in a chaotic chain: measured when written
≤ 6.4e-13 relative over the first 10 events of 4-8 chains at N = 4, 16, 64 (and the same step counts).
Bounds: 1e-10, the scalar engine's own bound against mpmath, on every field.
"""

from __future__ import annotations

import json
from pathlib import Path

import numpy as np
import pytest

from bifurcation.errors import InputError
from bifurcation.models.rs_chain.batch import LANES, run_batch
from bifurcation.models.rs_chain.result import RSChainStatus
from bifurcation.models.rs_chain.simulate import RSChainSpec, initial_state, run

DATA = Path(__file__).parent / "data"
QD = dict(state_law="aging", a=0.01, b=0.015, dc=0.01, k=0.1, v_lp=1.0, eta=1e-3, v_th=10.0)
FIELDS = ("t_start", "potency", "duration", "max_velocity")


def _close(got, want, bound=1e-10) -> None:
    assert got.status == want.status and got.events == want.events
    assert list(got.n_blocks) == list(want.n_blocks)
    # hypocentres where the event's first two up-crossings are apart by more than 1e-9 of t (a closer pair
    # is a tie that rounding decides: the rule of tests/test_rs_chain.py's mpmath comparison)
    if want.crossings is not None:
        up = want.crossings[want.crossings[:, 2] == 1]
        for i, t0 in enumerate(want.t_start):
            later = up[(up[:, 0] >= t0) & (up[:, 0] <= t0 + want.duration[i])][:, 0]
            if later.size < 2 or later[1] - later[0] > 1e-9 * t0:
                assert got.hypocentre[i] == want.hypocentre[i], i
    for name in FIELDS:
        err = np.max(np.abs(getattr(got, name) / getattr(want, name) - 1))
        assert err <= bound, (name, err)
    assert abs(got.steps - want.steps) <= 0.01 * want.steps      # measured: equal


def test_lanes_are_the_scalar_runs_in_order_with_refills():
    # LANES + 2 chains with different ℓ and seeds: the two last ones take the lanes of the first to end
    specs = [RSChainSpec(n=6, ell=ell, **QD) for ell in (1.0, 2.0, 3.0, 1.5, 2.5, 1.0)][:LANES + 2]
    starts = [initial_state(spec, 1.0, seed) for seed, spec in enumerate(specs, start=1)]
    got = run_batch(specs, starts, 12)
    assert len(got) == len(specs)
    for g, spec, s0 in zip(got, specs, starts):
        assert g.spec == spec and g.meta["lanes"] == LANES
        _close(g, run(spec, s0, 12, crossings=True))


def _reference_cases():
    path = DATA / "rs_chain_reference.json"
    return json.loads(path.read_text()) if path.exists() else {}


@pytest.mark.parametrize("name", sorted(_reference_cases()))
def test_one_chain_in_a_batch_agrees_with_the_mpmath_reference(name):
    ref = _reference_cases()[name]
    case = dict(ref["case"])
    events, amplitude, seed = case.pop("events"), case.pop("amplitude"), case.pop("seed")
    spec = RSChainSpec(**case)
    (got,) = run_batch([spec], [initial_state(spec, amplitude, seed)], events)   # spare lanes idle
    assert got.status == RSChainStatus.COMPLETE and got.events == events
    assert list(got.n_blocks) == ref["n_blocks"]
    for name_ in FIELDS:
        want = np.array([float(v) for v in ref[name_]])
        assert np.max(np.abs(getattr(got, name_) / want - 1)) <= 1e-10, name_


def test_a_lane_that_cannot_finish_is_no_stop_and_the_others_complete():
    # max_steps bounds the steps from one event's end to the next one's, per lane (as simulate.run)
    specs = [RSChainSpec(n=3, ell=1.0, **QD), RSChainSpec(n=3, ell=1.0, **{**QD, "v_th": 1e6})]
    starts = [initial_state(s, 1.0, 2) for s in specs]
    done, stuck = run_batch(specs, starts, 5, max_steps=2000)
    assert done.status == RSChainStatus.COMPLETE and done.events == 5
    assert stuck.status == RSChainStatus.NO_STOP and stuck.events == 0 and "max_steps = 2000" in stuck.message
    _close(done, run(specs[0], starts[0], 5, max_steps=2000, crossings=True))


def test_bad_batches_are_one_line_errors():
    a = RSChainSpec(n=3, ell=1.0, **QD)
    with pytest.raises(InputError, match="differs in structure from the first"):
        run_batch([a, RSChainSpec(n=4, ell=1.0, **QD)], [initial_state(a), np.zeros(9)], 3)
    undamped = RSChainSpec(n=3, ell=1.0, **{**QD, "eta": 0.0})
    with pytest.raises(InputError, match=r"massless and undamped .*run it with simulate.run"):
        run_batch([undamped], [initial_state(undamped)], 3)
    with pytest.raises(InputError, match="is empty"):
        run_batch([], [], 3)
    with pytest.raises(InputError, match="are not 1 states of 7 values"):
        run_batch([a], [np.zeros(5)], 3)
    with pytest.raises(InputError, match=r"tol=1e-05: is outside \[2.22e-16, 1e-08\]; give a tolerance"):
        run_batch([a], [initial_state(a)], 3, tol=1e-5)
