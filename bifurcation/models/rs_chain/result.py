"""Outcome codes of a rate-and-state chain run (light: no heyoka, the declaration imports it)."""

from __future__ import annotations

from enum import IntEnum

__all__ = ["RSChainStatus"]


class RSChainStatus(IntEnum):
    """Outcome of a run; codes agree with ``bifurcation.Status`` where the meaning is shared (0: not computed)."""

    COMPLETE = 1    #: all requested events catalogued
    NO_STOP = 3     #: an event (or the wait for the next) exceeded t_max or max_steps; earlier events kept
    NOT_APPLICABLE = 6  #: the point is not a chain the model runs (v_th <= V_lp, a block starting above v_th)
    NONFINITE = 5   #: the integrator produced a non-finite state (e.g. M = 0, η = 0 below critical stiffness)
    NOT_RESOLVED = 7  #: the run was not made in a precision the engine vouches for (only double)
    #: steady sliding: no block above v_th and the deviations from steady sliding observed to decay (with
    #: the linearisation stable) over several Dc/V_lp, so no further event comes; earlier events kept
    #: (simulate.STEADY_BAND; docs/rs-chain.md, "Steady sliding")
    STEADY = 8

    def __str__(self) -> str:
        return self.name.lower().replace("_", "-")
