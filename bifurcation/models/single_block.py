r"""The single block (the default model): one block, friction Φ(U̇/ν_f), axes law × ν_f × ν.

Equation of motion (Eq. 5 of Vasconcelos, PRL 76, 4865 (1996); docs/physics.md), measured from the
start of a slip:

.. math:: \ddot U = \nu t - U + 1 - \Phi(\dot U/\nu_f), \qquad U(0) = \dot U(0) = 0.

Integrated in the scaled variable U = νW (docs/physics.md, "Scaling"):

.. math:: \ddot W = c\,t - W + \sum_k s_k\, g_k(x)/\nu, \qquad x = \nu \dot W/\nu_f,

with g_k = 1 − Φ on piece k of the law, s_k the one-hot selector of that piece (flipped by the
``switch`` events, so a kink is crossed exactly and never smoothed), c = ``forcing`` (1 for a
finite-ν cycle; 0 with ν = 1 turns the same integrator into the ν = 0 flow of the direct limit).

ν_f enters by division, never through a precomputed 1/ν_f or ν/ν_f: just above ν_f = 1/2 the creep
cycle is ill-conditioned in ν_f (d ln Δ/d ln ν_f ≈ 700 at ν_f = 0.51) and the one systematic rounding of
such a constant cost 4e-14 in Δ; roundings made per evaluation do not add up that way. Every event
function is O(1) in the scaled variables while the block slips (a switching function of size 1e12
spoils the location of the other events).
"""

from __future__ import annotations

import math

import numpy as np

from ..bounds import NU_BOUNDS, NU_F_BOUNDS
from ..laws import law_names, resolve_law
from ..outcome import DEFAULT_MAX_STEPS, DEFAULT_T_MAX, Status
from ._base import Axis, Event, Hooks, Labels, Model, Output, StateVar, System

__all__ = ["BLOCK_UNITS", "DEFAULT_MAX_STEPS", "DEFAULT_T_MAX", "FIELDS", "FIELD_ATTRS", "LAW", "NU", "NU_F",
           "OUTPUTS", "SINGLE_BLOCK", "STOP_EVENTS", "block_equations", "classify_cycles", "law_identity"]

#: The units of the block models' numbers (the scaling of Eq. 4; a line of their reports).
BLOCK_UNITS = "Δ in F0/k, velocities in V0 = F0/√(mk), times in √(m/k) (docs/physics.md)"

#: Float fields of a slip result, in order.
FIELDS = ("delta", "period", "creep_time", "slip_duration", "stop_time", "max_velocity")

#: Long names and units, used by the CLI, the store and ``SlipResult``.
FIELD_ATTRS = {
    # Dimensionless, as in the paper (Eq. 4): CF units "1", the scale named in the long name. Short names
    # (they are xarray's plot labels); where a field is undefined it is NaN (see ``SlipResult``).
    "delta": ("slip Δ per cycle (in F0/k)", "1"),
    "period": ("recurrence time T = Δ/ν (in √(m/k))", "1"),
    "creep_time": ("creep time t1, until U̇ = ν_f (in √(m/k))", "1"),
    "slip_duration": ("slip duration, t1 to the stop (in √(m/k))", "1"),
    "stop_time": ("time to the stop, t0 in creep (in √(m/k))", "1"),
    "max_velocity": ("maximum block velocity U̇ (in V0)", "1"),
    "steps": ("Taylor steps taken", "1"),
    "status": ("outcome of the cycle", "1"),
}


def law_identity(text: str):
    """What makes two law labels the same law: its parsed expression (``1/(1+x/2)**2`` is
    ``1/(1+x/2)^2``, spaces do not matter), a named law by its formula: ``carlson-langer`` is
    ``1/(1+x)``, the same Φ (the engine evaluates the named law without cancellation, the formula
    through its own series: equal to rounding), so a query by either finds it."""
    text = str(text).strip()
    from ..laws.formula import formula_key

    if text in law_names():
        from ..laws.builtin import BUILTIN

        return ("formula", formula_key(BUILTIN[text]().formula))
    return ("formula", formula_key(text))


LAW = Labels(
    name="law", long_name="friction law Φ",
    workflow_key="laws", resolve=resolve_law, identity=law_identity, example="carlson-langer")

NU_F = Axis("nu_f", "ν_f", "friction velocity ν_f (in V0)",
            bounds=NU_F_BOUNDS, example=0.4)
NU = Axis("nu", "ν", "pulling speed ν (in V0)",
          bounds=NU_BOUNDS, scale="log", example=1e-9)

#: The outputs of a cycle, in store order (the engine's ``FIELDS``, then ``steps`` and ``status``).
OUTPUTS = (*(Output(name, *FIELD_ATTRS[name]) for name in FIELDS),
           Output("steps", *FIELD_ATTRS["steps"], dtype="int64", fill=0),
           Output("status", *FIELD_ATTRS["status"], dtype="int8", fill=int(Status.NOT_COMPUTED)))

#: The events of a cycle, in the order the engine registers them.
STOP_EVENTS = (
    Event("stop", "end", "U̇ returns to 0 from above (x = 0, direction negative): the cycle ends"),
    Event("max_velocity", "maximum", "dU̇/dt = 0 from above: a velocity maximum", records="vmax", of="V"),
    Event("reach_nu_f", "first", "U̇ = ν_f from below (t1), declared only where x = 1 is not a breakpoint",
          records="creep_time"),
    Event("switch", "switch", "x crosses breakpoint b of the law (x/b − 1 = 0, either way): the piece "
          "selector moves one piece up or down; at b = 1 the first up-crossing is also t1",
          per_piece=True),
    Event("rung", "step", "x falls through a rung r of the law's ladder (x/r − 1 = 0 from above): the step "
          "ends there, so no Taylor step steps over friction that fades (laws._fading, docs/engine.md)",
          per_piece=True),
)


def block_equations(law, slots, num, *, damping=None, precision="double") -> System:
    """The scaled single-block system for ``law`` (module docstring), with an optional extra force
    ``−damping·Ẇ`` (``damping`` a heyoka expression; None: none, the single block itself), and the
    ladder of rungs the law needs in ``precision`` (``laws._fading``)."""
    import heyoka as hy

    from ..laws import _fading

    W, V = hy.make_vars("W", "V")
    nu, nu_f, c = slots.par("nu"), slots.par("nu_f"), slots.par("forcing")
    x = (nu * V) / nu_f
    pieces = law.pieces
    if len(pieces) == 1:
        drop = pieces[0].drop(x, num)
    else:
        # select on the one-hot parameter, not a product with it: a piece may be NaN outside its own
        # interval (log(x) at x = 0, say) and 0·NaN is NaN. The condition is constant over every step,
        # so this is no state-dependent switch and weakens no event guarantee.
        last = len(pieces) - 1
        drop = hy.select(slots.piece_par(last), pieces[last].drop(x, num), num(0))
        for k in range(last - 1, -1, -1):
            drop = hy.select(slots.piece_par(k), pieces[k].drop(x, num), drop)
    load = c * hy.time - W if damping is None else c * hy.time - W - damping * V
    rhs = load + drop / nu
    # dx/dt = νẄ/ν_f, written without the 1/ν so that it stays O(1) during the slip.
    dxdt = (nu * load + drop) / nu_f
    ladder = _fading.ladder(law, precision)
    events = {"stop": (x, "negative"), "max_velocity": (dxdt, "negative"),
              "switch": [(x / b - 1.0, "any") for b in law.breakpoints],
              "rung": [(x / r - 1.0, "negative") for r in ladder.rungs]}
    info = {"x_checked": ladder.x_checked}
    if 1.0 not in law.breakpoints:
        events["reach_nu_f"] = (x - 1.0, "positive")
        return System(state=(W, V), rhs=(V, rhs), events=events, info=info)
    return System(state=(W, V), rhs=(V, rhs), events=events, info=info,
                  first_on_switch=("creep_time", law.breakpoints.index(1.0)))


def _equations(law, slots, num, *, precision="double") -> System:
    return block_equations(law, slots, num, precision=precision)


def _unresolved(status: np.ndarray, messages: dict, x_max: np.ndarray, x_checked: float) -> None:
    """Mark stopped points whose U̇/ν_f went past the ladder's checked range (docs/engine.md)."""
    beyond = (status == int(Status.STICK_SLIP)) & (x_max > x_checked)
    for i in np.flatnonzero(beyond):
        status[i] = int(Status.UNRESOLVED)
        messages[int(i)] = (f"U̇/ν_f reached {x_max[i]:.3g}, beyond x = {x_checked:.3g} up to which the engine "
                            "checked that no Taylor step can step over this law's friction; use a larger ν_f")


def classify_cycles(raw: dict, points: dict, *, critical_nu_f) -> tuple[dict, dict]:
    """Result fields from raw outcomes: creep vs stick-slip, the stick check, NaN where undefined.

    ``critical_nu_f`` (per point) is where the ν = 0 fixed point turns from an unstable node into an
    unstable focus: above it, a stop with U̇ < ν_f throughout is the creep cycle (docs/physics.md).
    """
    nu = points["nu"]
    status = raw["status"].copy()
    messages = dict(raw["messages"])
    _unresolved(status, messages, nu * raw["vmax"] / points["nu_f"], raw.get("info", {}).get("x_checked", math.inf))
    stopped = status == int(Status.STICK_SLIP)
    creep = stopped & (points["nu_f"] > critical_nu_f) & np.isnan(raw["creep_time"])
    status[creep] = int(Status.CREEP)
    # Static friction holds |spring force| = |1 + ν(t − W)| ≤ 1 after the stop; else it back-slips.
    back = stopped & (nu * (raw["W"] - raw["time"]) > 2)
    for i in np.flatnonzero(back):
        status[i] = int(Status.NO_STICK)
        messages[int(i)] = (f"spring force {1 + nu[i] * (raw['time'][i] - raw['W'][i]):.6g} exceeds "
                            "static friction after the stop: the block would slide back")
    # stick-slip, creep and no-stick all stopped: the cycle itself is well defined
    W = np.where(stopped, raw["W"], math.nan)
    fields = {
        "delta": nu * W,
        "period": W,
        "creep_time": np.where(stopped, raw["creep_time"], math.nan),
        "slip_duration": np.where(stopped, raw["time_after_creep_time"], math.nan),
        "stop_time": np.where(stopped, raw["time"], math.nan),
        "max_velocity": np.where(stopped, nu * raw["vmax"], math.nan),
        "steps": raw["steps"],
        "status": status,
    }
    return fields, messages


def _classify(raw: dict, points: dict) -> tuple[dict, dict]:
    return classify_cycles(raw, points, critical_nu_f=0.5)


SINGLE_BLOCK = Model(
    name="single-block",
    title="one block, velocity-weakening friction Φ(U̇/ν_f)",
    description="Ü = νt − U + 1 − Φ(U̇/ν_f); one slip cycle per point: slip Δ, recurrence time T = Δ/ν, "
                "creep time t1, status (stick-slip, creep, ...)",
    source="Vasconcelos, First-order phase transition in a model for earthquakes, PRL 76, 4865 (1996)",
    labels=LAW,
    axes=(NU_F, NU),
    parameters=("nu", "nu_f", "forcing"),
    fixed={"forcing": 1.0},
    rest_slot="forcing",
    state=(StateVar("W", "scaled displacement U/ν"), StateVar("V", "scaled velocity U̇/ν")),
    events=STOP_EVENTS,
    outputs=OUTPUTS,
    statuses=tuple(s for s in Status if s is not Status.NOT_COMPUTED),
    equations=_equations,
    classify=_classify,
    hooks=Hooks(describe_label="bifurcation.laws:resolve_law",
                report="bifurcation.report.study:single_block_section",
                bench="bifurcation.bench:run_bench", bench_needs=("scipy", "numba", "numbalsoda")),
    units_note=BLOCK_UNITS,
)
