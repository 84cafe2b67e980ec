"""The one set of bounds on the model's parameters and on the work of one cycle.

Every entry point reads these: ``slip`` and ``limit`` (``engine._validate``), workflows
(``workflow.spec``), and ``query`` (which checks the labels a user asks for). A value outside them is
refused with the same message everywhere, never computed into a plausible-looking status.

* ν ∈ [1e-20, 1]: the engine is checked against real128 down to ν = 1e-20 (tests/test_precision.py);
  above ν = 1 the block is not slowly driven (Vasconcelos, PRL 76, 4865 (1996), Eq. 5).
* ν_f ∈ [1e-4, 10]: the paper's range is (0, 1); ν_f > 1/2 is creep as ν → 0. Below 1e-4 the
  shortest time between events (~ln 2 / (2α)) nears the event cooldown (``engine._integrator``).
* ``max_steps`` ≤ 10^7 Taylor steps and ``t_max`` ≤ 10^9 time units per cycle: a cycle of the
  default grid takes ≤ 10^4 steps (``Status.NO_STOP`` beyond the defaults 2·10^5, 10^5); 10^7 steps are
  about a minute of one core, so one point can never hold a worker for hours (``max_steps = 1e18`` was
  accepted and never ended).
* Chains (``bifurcation chain`` and chain workflows alike, read by ``models.chain._validate``): N × events
  ≤ ``CHAIN_MAX_N_EVENTS`` per run, refused up front, and ``CHAIN_EVENT_WORK`` block-steps per event at
  run time (the run stops with no-stop, keeping the events before); ``CHAIN_RUN_WORK`` bounds the
  block-steps of one CLI run (a workflow's run is checkpointed and resumable, and its whole run is
  bounded by N × events and the per-event work instead).
* Rate-and-state chains (``[model] name = "rs-chain"`` workflows, ``models.rs_chain.model.check_grid``):
  N × events ≤ ``RS_CHAIN_MAX_N_EVENTS`` per run, refused up front, and ``RS_CHAIN_EVENT_WORK``
  block-steps per event at run time (a Taylor step costs ~1 µs a block; the run stops with no-stop).
"""

from __future__ import annotations

__all__ = ["CHAIN_EVENT_WORK", "CHAIN_MAX_N_EVENTS", "CHAIN_RUN_WORK", "MAX_STEPS_MAX", "NU_BOUNDS", "NU_F_BOUNDS",
           "RS_CHAIN_EVENT_WORK", "RS_CHAIN_MAX_N_EVENTS", "T_MAX_MAX", "check_max_steps", "check_t_max",
           "in_bounds_fix"]

NU_BOUNDS = (1e-20, 1.0)
NU_F_BOUNDS = (1e-4, 10.0)
MAX_STEPS_MAX = 10**7
T_MAX_MAX = 1e9

#: The most work one chain event may take, in block-steps (Taylor steps × the width of the window
#: integrated; the compiled engine: DOP853 steps × N), per engine and precision: about 4 min of CPU each on
#: the development machine (measured: 2.5 µs a block-step exact in double, 110 µs in quad, at N = 2000 and
#: 25000; compiled 1.4 ms a step at N = 25000). An event ends only when every block is stuck; at N·ν ≥ 1
#: blocks fail faster than events end and one may never end (N = 25000, ν = 1e-3 slid for hours before
#: this bound). A legitimate event spanning N = 1024 blocks took 1.7e7 (compiled).
CHAIN_EVENT_WORK = {("exact", "double"): 10**8, ("exact", "quad"): 2 * 10**6, ("compiled", "double"): 10**9}
#: The same for all the events of one ``bifurcation chain`` run together (exact engine; ~20 min of CPU
#: here): many events that end, each near CHAIN_EVENT_WORK (N = 2^20 at a published ν = 0.01), would
#: otherwise add up to hours.
CHAIN_RUN_WORK = {("exact", "double"): 5 * 10**8, ("exact", "quad"): 10**7}
#: The most N × events of one chain run: each event also costs O(N) outside its window (the next
#: hypocentre, the quiescent load): measured 66 events/s at N = 2^20 (ν = 1e-9), so 1e10 is about 2.5 min.
CHAIN_MAX_N_EVENTS = 10**10

#: The most N × events of one rate-and-state chain run (an event there is a stiff rate-and-state slip
#: integrated by Taylor steps over all N blocks, ~10^3 times the cost of the chain's): measured (aging,
#: ℓ = 3, η = 1e-3, k = 0.1, A = 1, seed 1, one core, process time) 0.21 ms a block-event at N = 16,
#: 0.34 ms at N = 64, 0.14 ms at N = 256 and 2.5 ms at N = 1024 (its first 30 events, which grow out of the
#: start: 2197 steps an event); the store's run of 10^5 events at N = 256 took ~2.4 h (0.34 ms). At the
#: worst, 2.5 ms, 3·10^7 block-events are ~21 h of one core: the largest accepted run is about a day
#: (10^5 events at N = 256, workflows/rs-chain-large.toml, is 2.56·10^7). Before: N = 65536 × 10^9 events
#: was accepted.
RS_CHAIN_MAX_N_EVENTS = 3 * 10**7
#: The most block-steps (Taylor steps × N) of one rate-and-state chain event, or of the wait for it: a
#: step costs 0.96–1.15 µs a block (measured at N = 16 to 1024), so 10^10 is ~3 h of one core; the
#: workflow's ``max_steps`` alone allowed 10^7 steps × 65536 blocks (~8 days) for one event.
RS_CHAIN_EVENT_WORK = 10**10


def in_bounds_fix(name: str) -> str:
    """The fix of an out-of-bounds ``nu`` / ``nu_f``: the bounds and an example."""
    low, high = NU_BOUNDS if name == "nu" else NU_F_BOUNDS
    example = "1e-9" if name == "nu" else "0.4"
    return f"give a value in [{low:g}, {high:g}] such as {example} (bifurcation.bounds)"


def check_max_steps(key: str, value) -> int:
    """``max_steps``: an integer in [1, ``MAX_STEPS_MAX``]."""
    from .errors import InputError

    if isinstance(value, bool) or not isinstance(value, int) or value < 1:
        raise InputError(key, value, "is not a positive integer", "give a whole number of steps such as 200000")
    if value > MAX_STEPS_MAX:
        raise InputError(key, value, f"is more than {MAX_STEPS_MAX:.0e} steps per cycle (bifurcation.bounds)",
                         "give at most 10000000; a cycle that needs more ends as no-stop")
    return value


def check_t_max(key: str, value: float) -> float:
    """``t_max``: a time in (0, ``T_MAX_MAX``]."""
    from .errors import InputError

    if not value > 0:
        raise InputError(key, value, "must be > 0", "give a positive time such as 1e5")
    if value > T_MAX_MAX:
        raise InputError(key, value, f"is more than {T_MAX_MAX:.0e} time units per cycle (bifurcation.bounds)",
                         "give at most 1e9; a cycle that needs more ends as no-stop")
    return value
