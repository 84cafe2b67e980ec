"""The batch loop's bookkeeping (engine._batch): a point's outcome, steps included, is its own whatever
its lane, its neighbours and the lane count, also where the loop takes its slow path (no stop within
max_steps or t_max), and switches acted on in heyoka's callbacks give the scalar loop's piece
sequence (equal to rounding, as test_engine's batch test)."""

import numpy as np
import pytest

import bifurcation as bf

FIELDS = ("delta", "creep_time", "slip_duration", "stop_time", "max_velocity", "steps", "status")


def _same(a, b, where=slice(None)):
    for field in FIELDS:
        np.testing.assert_array_equal(getattr(a, field)[where], getattr(b, field)[where], err_msg=field)


@pytest.mark.parametrize("law", ["carlson-langer", "piecewise-linear"])
def test_points_without_a_stop_do_not_depend_on_neighbours(law):
    rng = np.random.default_rng(3)
    nu = 10.0 ** -rng.uniform(3, 14, 21)
    nu_f = rng.uniform(0.05, 0.95, 21)
    free = bf.slip(law, nu=nu, nu_f=nu_f, batch=8)
    # steps on this sample run from 5 to ~40: a budget of 12 stops some points and not others
    capped = bf.slip(law, nu=nu, nu_f=nu_f, batch=8, max_steps=12)
    perm = rng.permutation(nu.size)
    other = bf.slip(law, nu=nu[perm], nu_f=nu_f[perm], batch=3, max_steps=12)
    for field in FIELDS:
        np.testing.assert_array_equal(getattr(capped, field)[perm], getattr(other, field), err_msg=field)
    stopped = free.steps <= 12
    assert 0 < stopped.sum() < nu.size
    _same(capped, free, stopped)   # a point that stops within the budget: its own bits
    assert np.all(capped.steps[~stopped] == 12)   # exactly the budget, whichever return noticed it
    assert np.all(capped.status[~stopped] == int(bf.Status.NO_STOP))
    # a time limit: the points that stop before it are unchanged, the others end exactly at it
    t_cap = float(np.mean(np.sort(free.stop_time)[10:12]))   # between two stop times
    timed = bf.slip(law, nu=nu, nu_f=nu_f, batch=8, t_max=t_cap)
    timed3 = bf.slip(law, nu=nu[perm], nu_f=nu_f[perm], batch=3, t_max=t_cap)
    for field in FIELDS:
        np.testing.assert_array_equal(getattr(timed, field)[perm], getattr(timed3, field), err_msg=field)
    early = free.stop_time < t_cap
    _same(timed, free, early)
    assert np.all(np.isnan(timed.delta[~early]))


def test_batch_order_is_a_permutation_by_decade_of_nu_then_nu_f():
    from bifurcation.engine.cycle import batch_order
    from bifurcation.models.single_block import SINGLE_BLOCK

    nu = np.array([1e-9, 3e-4, 2e-9, 5e-4, 1e-12])
    nu_f = np.array([0.5, 0.2, 0.1, 0.1, 0.9])
    order = batch_order(SINGLE_BLOCK, {"nu_f": nu_f, "nu": nu})
    # decades -12, -9 (ν_f 0.1 then 0.5), -4 (ν_f 0.1 then 0.2)
    assert order.tolist() == [4, 2, 0, 3, 1]


def test_default_path_returns_points_in_input_order_whatever_the_order():
    # the batch run reorders the points (batch_order) and must put results and messages back
    rng = np.random.default_rng(7)
    nu = 10.0 ** -rng.uniform(3, 14, 40)
    nu_f = rng.uniform(0.05, 0.95, 40)
    base = bf.slip("piecewise-linear", nu=nu, nu_f=nu_f, max_steps=12)
    perm = rng.permutation(40)
    other = bf.slip("piecewise-linear", nu=nu[perm], nu_f=nu_f[perm], max_steps=12)
    for field in FIELDS:
        np.testing.assert_array_equal(getattr(base, field)[perm], getattr(other, field), err_msg=field)
    assert base.messages and {int(perm[i]): m for i, m in other.messages.items()} == base.messages
    assert sorted(base.messages) == np.flatnonzero(base.status == int(bf.Status.NO_STOP)).tolist()


def test_parked_lanes_give_the_same_bits(monkeypatch):
    # ended lanes parked at rest until a share of the lanes has ended (engine._batch.PARK_SHARE) give
    # the bits of a loop that reloads every lane at once (PARK_SHARE = 0), steps and no-stops included
    from bifurcation.engine import _batch

    rng = np.random.default_rng(11)
    nu = 10.0 ** -rng.uniform(3, 14, 50)
    nu_f = rng.uniform(0.05, 0.95, 50)
    for law in ("carlson-langer", "piecewise-linear"):
        parked = bf.slip(law, nu=nu, nu_f=nu_f, batch=8, max_steps=30)
        monkeypatch.setattr(_batch, "PARK_SHARE", 0)
        plain = bf.slip(law, nu=nu, nu_f=nu_f, batch=8, max_steps=30)
        monkeypatch.undo()
        _same(parked, plain)
        assert parked.messages == plain.messages


@pytest.mark.parametrize("law", ["carlson-langer", "piecewise-linear", "exponential"])
def test_batch_takes_the_scalar_loops_steps(law):
    # velocity maxima and t1 are terminal events in batch mode too (acted on in heyoka's callback), so a
    # batch point takes the scalar loop's Taylor steps, maxima and t1 at the step's end, not from dense
    # output; values equal to rounding (the bound is test_engine's batch test's: ν_f = 0.51 is ill-conditioned)
    rng = np.random.default_rng(5)
    nu = 10.0 ** -rng.uniform(3, 15, 120)
    nu_f = rng.uniform(0.01, 0.99, 120)
    scalar = bf.slip(law, nu=nu, nu_f=nu_f, batch=1)
    batch = bf.slip(law, nu=nu, nu_f=nu_f, batch=16)
    np.testing.assert_array_equal(batch.steps, scalar.steps)
    np.testing.assert_array_equal(batch.status, scalar.status)
    for field in ("delta", "max_velocity", "creep_time", "stop_time"):
        a, b = getattr(batch, field), getattr(scalar, field)
        np.testing.assert_array_equal(np.isnan(a), np.isnan(b), err_msg=field)
        assert np.nanmax(np.abs(a - b) / np.abs(b)) <= 3e-14, field


@pytest.mark.parametrize("law", ["carlson-langer", "piecewise-linear"])
def test_blocks_of_lanes_give_the_per_lane_bits(monkeypatch, law):
    # while every lane of a block of consecutive points parks, the block is finished and reloaded by
    # whole rows (engine._batch, load_block); a lane without a stop (max_steps, t_max) sends the loop
    # lane by lane until every lane has ended, then back to blocks. Against the loop that reloads each
    # lane on its own (PARK_SHARE = 0): the same bits, steps and messages, over 5 blocks of 16 and a
    # partial one
    from bifurcation.engine import _batch

    rng = np.random.default_rng(23)
    nu = 10.0 ** -rng.uniform(3, 14, 87)
    nu_f = rng.uniform(0.05, 0.95, 87)
    free = bf.slip(law, nu=nu, nu_f=nu_f, batch=1)
    # bounds that end about a fifth of the points early: between two of the points' step counts and stop times
    steps, stops = np.sort(free.steps), np.sort(free.stop_time)
    for bounds in ({}, {"max_steps": int(steps[70])}, {"t_max": float(stops[69] + stops[70]) / 2}):
        blocks = bf.slip(law, nu=nu, nu_f=nu_f, batch=16, **bounds)
        monkeypatch.setattr(_batch, "PARK_SHARE", 0)
        lanes = bf.slip(law, nu=nu, nu_f=nu_f, batch=16, **bounds)
        monkeypatch.undo()
        _same(blocks, lanes)
        assert blocks.messages == lanes.messages
        if bounds:   # the bound ends some points early and not others
            assert 5 < len(blocks.messages) < nu.size / 2
