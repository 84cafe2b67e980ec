"""The event actions (``engine._actions``) shared by the scalar loop and the batch lanes, on a
hand-made three-piece system (no compile): a lane's run writes through to the batch's arrays exactly
as the scalar run writes its own, and an impossible switch is refused in both."""

import math

import numpy as np

from bifurcation.engine._actions import LaneRecords, Run, act
from bifurcation.engine._integrator import Compiled, EventKind
from bifurcation.engine.result import Status
from bifurcation.models._base import Slots

# events: 0 end, 1 and 2 switches at breakpoints 0 and 1 (breakpoint 0 carries the "first" record
# t1), 3 a rung, 4 a set of slot "c" to 5
SLOTS = Slots(("a", "c"), n_pieces=3)
C = Compiled(law=None, precision="double", integrator=None, n_pieces=3, batch_size=1, slots=SLOTS,
             kinds=(EventKind.STOP, EventKind.SWITCH, EventKind.SWITCH, EventKind.RUNG, EventKind.SET),
             breakpoint_of=(-1, 0, 1, -1, -1), records=("", "", "", "", ""), state_of=(-1,) * 5,
             first_records=("t1",), first_alias=("t1", 0), sets_of=((), (), (), (), ((SLOTS.index("c"), 5.0),)))


def _scalar():
    pars = np.zeros(SLOTS.size)
    clock = iter([1.0, 2.0, 3.0])
    run = Run(pars, None, {"t1": math.nan}, {}, lambda: next(clock))
    run.start(C)
    return run, pars


def _lane(lane=2, lanes=4):
    pars = np.zeros((SLOTS.size, lanes))
    recorded = {"t1": np.full(lanes, np.nan)}
    clock = iter([1.0, 2.0, 3.0])
    records = LaneRecords(recorded, lane)
    run = Run(pars[:, lane], None, records, records, lambda: next(clock))
    run.start(C)
    return run, pars, recorded


def _sequence(run):
    """Up through both breakpoints, down through the second and the first, a rung, a set, the end."""
    return [act(C, index, run) for index in (1, 2, 2, 1, 3, 4)] + [act(C, 0, run)]


def test_a_lane_takes_the_same_actions_as_a_scalar_run():
    scalar, pars = _scalar()
    lane, batch, recorded = _lane()
    assert _sequence(scalar) == _sequence(lane) == [None] * 6 + [Status.STICK_SLIP]
    assert scalar.piece == lane.piece == 0
    np.testing.assert_array_equal(batch[:, 2], pars)
    assert not batch[:, [0, 1, 3]].any()                        # other lanes untouched
    assert list(pars[SLOTS.piece0:]) == [1, 0, 0] and pars[SLOTS.index("c")] == 5.0
    # the first up-crossing of breakpoint 0 is t1; its later (down) crossing is kept in order
    assert scalar.found["t1"] == recorded["t1"][2] == 1.0
    assert scalar.crossings == lane.crossings == [2.0]


def test_a_switch_that_does_not_border_the_piece_is_refused():
    for run in (_scalar()[0], _lane()[0]):
        assert act(C, 2, run) is Status.NONFINITE                  # breakpoint 1 seen in piece 0
        assert run.message == "switch event 1 seen in piece 0"
