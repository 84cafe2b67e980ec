"""The ``rate-state`` model of the registry: per point, the Hopf point and the fate of perturbed sliding.

A label is the state law of each state variable: ``aging``, ``slip``, ``prz`` (aliases dieterich,
ruina, perrin; lower case, as every choice of the CLI) or two joined by ``+`` (``aging+slip``: the
first variable takes the axes b, dc, the second b2, dc2). Axes: κ = k/k_c, V_lp, a, b, Dc, M (0:
quasi-static), b2, Dc2; all but κ have a default, so a workflow names only what it sweeps. Per point
the runner (``_run``):

1. the Hopf point of steady sliding at V_lp (``hopf.hopf_point`` at 30 digits, shared by the points
   that differ only in κ): k_c, ω_c, the first Lyapunov coefficient l1 and its sign (``criticality``);
2. at k = κ k_c, the fate of steady sliding perturbed by 1e-2 in ln V (``attractor.fate``; with mass,
   where it is not resolved, the event-split integrator ``slow_manifold.deep_cycle``):
   ``RateStateStatus`` and, for a limit cycle, its period, max and min ln V, slip per cycle and
   largest Floquet multiplier. Whatever the engine cannot vouch for is NaN with a status that says so.

docs/rate-state.md ("The model in the registry") has the workflow and what each status means.
"""

from __future__ import annotations

import math
from enum import IntEnum

import numpy as np

from ...errors import InputError
from .._base import Axis, Hooks, Labels, Model, Output
from .laws import resolve_state_law

__all__ = ["CRITICALITY", "RATE_STATE", "RateStateStatus", "label_identity", "resolve_label"]


class RateStateStatus(IntEnum):
    """Outcome of a rate-state point (stored codes; 0 is the store's "not computed")."""

    NOT_COMPUTED = 0
    STEADY_SLIDING = 1      #: the perturbation decayed below 1e-9: steady sliding attracts it
    LIMIT_CYCLE = 2         #: it went to an attracting cycle (found by Newton, multipliers inside 1)
    UNBOUNDED_GROWTH = 3    #: V grew beyond e^80 V_lp, or blew up in finite time (quasi-static, k < k_c)
    NOT_RESOLVED = 4        #: step or time budget spent, stiffness at small V, or no converged cycle
    NO_HOPF_POINT = 5       #: Σb ≤ a (or ηV_lp ≥ b − a): steady sliding is stable at every k (κ undefined)
    NOT_APPLICABLE = 6      #: b2 > 0 for a label with one state variable

    def __str__(self) -> str:
        return self.name.lower().replace("_", "-")


#: ``criticality`` output codes (0: not computed).
CRITICALITY = {"subcritical": 1, "supercritical": 2, "degenerate": 3}
_FATE = {"steady": RateStateStatus.STEADY_SLIDING, "cycle": RateStateStatus.LIMIT_CYCLE,
         "unbounded": RateStateStatus.UNBOUNDED_GROWTH, "unresolved": RateStateStatus.NOT_RESOLVED}


def resolve_label(text) -> tuple[str, ...]:
    """The state law of each state variable named by ``text`` ("aging", "ruina", "aging+slip")."""
    if not isinstance(text, str) or not text.strip():
        raise InputError("state_law", text, "is not a state law name",
                         "give aging, slip or prz, or two joined by '+' such as aging+slip")
    parts = [p.strip() for p in text.split("+")]
    if len(parts) > 2:
        raise InputError("state_law", text, f"names {len(parts)} state variables",
                         "give one or two state laws, such as aging or aging+slip")
    return tuple(resolve_state_law(p).name for p in parts)


def label_identity(text) -> str:
    """The canonical label: aliases resolved, spaces dropped ("dieterich + ruina" → "aging+slip")."""
    return "+".join(resolve_label(text))


LABELS = Labels(name="state_law", long_name="state evolution law of each state variable (aging, slip, prz; "
                "two joined by '+')", workflow_key="laws", resolve=resolve_label, identity=label_identity,
                example="aging")

AXES = (
    Axis("kappa", "κ", "spring stiffness over its critical value, k/k_c", bounds=(1e-3, 1e3), scale="log",
         example=0.9, default_tile=8),
    Axis("v_lp", "V_lp", "load-point velocity V_lp", bounds=(1e-12, 1e6), units="length/time", scale="log",
         example=1.0, default_tile=1, default=1.0),
    Axis("a", "a", "direct-effect parameter a (> 0)", bounds=(1e-6, 1.0), scale="log", example=0.01,
         default_tile=1, default=0.01),
    Axis("b", "b", "evolution-effect parameter b of the first state variable (>= 0)", bounds=(0.0, 1.0),
         example=0.015, default_tile=1, default=0.015),
    Axis("dc", "D_c", "critical slip distance Dc of the first state variable (> 0)", bounds=(1e-9, 1e6),
         units="length", scale="log", example=0.01, default_tile=1, default=0.01),
    Axis("mass", "M", "block mass M per unit normal force (0: quasi-static)", bounds=(0.0, 1e30),
         units="time^2/length", example=1e-5, default_tile=1, default=0.0),
    Axis("b2", "b₂", "evolution-effect parameter of the second state variable (0 for one variable)",
         bounds=(0.0, 1.0), example=0.006, default_tile=1, default=0.0),
    Axis("dc2", "D_c2", "critical slip distance of the second state variable", bounds=(1e-9, 1e6),
         units="length", scale="log", example=0.1, default_tile=1, default=0.1),
    Axis("damping", "η", "radiation damping η, friction per unit slip rate (0: none; k(V_lp t − δ) − ηV = μ − μ0)",
         bounds=(0.0, 1e30), units="time/length", example=0.002, default_tile=1, default=0.0),
)

OUTPUTS = (
    Output("k_c", "critical stiffness k_c of steady sliding (Hopf point, found numerically)", "1/length"),
    Output("omega_c", "angular frequency ω_c at the Hopf point", "1/time"),
    Output("lyapunov_coefficient", "first Lyapunov coefficient l1 at the Hopf point"),
    Output("criticality", "Hopf point: 1 subcritical, 2 supercritical, 3 degenerate (|l1| at rounding)",
           dtype="int8", fill=0, names=("", *sorted(CRITICALITY, key=CRITICALITY.get))),
    Output("k", "spring stiffness k = κ k_c", "1/length"),
    Output("period", "period of the attracting cycle", "time"),
    Output("ln_v_max", "max ln V over the cycle (V in the units of V_lp, not scaled)"),
    Output("ln_v_min", "min ln V over the cycle"),
    Output("slip", "slip per cycle, V_lp T", "length"),
    Output("multiplier_max", "largest |Floquet multiplier| of the cycle"),
    Output("steps", "Taylor steps of the run from perturbed steady sliding", dtype="int64", fill=0),
    Output("status", "outcome code (see RateStateStatus)", dtype="int8", fill=0),
)


def _run(model, label, points, *, precision, t_max, max_steps, batch):
    """The model's runner (``Model.runner``): Hopf point and fate of every point, in order."""
    from .attractor import fate
    from .hopf import hopf_point
    from .spec import SliderSpec

    laws = resolve_label(label)
    size = np.size(points["kappa"])
    fields = {o.name: np.full(size, o.fill, dtype=o.dtype) for o in model.outputs}
    messages: dict = {}
    hopf_cache: dict = {}
    for i in range(size):
        p = {name: float(points[name][i]) for name in points}
        if len(laws) == 1 and p["b2"] != 0:
            fields["status"][i] = RateStateStatus.NOT_APPLICABLE
            messages[i] = f"b2 = {p['b2']:g} names a second state variable; label {label!r} has one"
            continue
        if precision != "double":
            fields["status"][i] = RateStateStatus.NOT_RESOLVED
            messages[i] = (f"precision {precision!r}: rate-state points are computed in double (real128 is for "
                           "verification runs: rate_state(precision='quad'))")
            continue
        b = [p["b"], p["b2"]][:len(laws)]
        dc = [p["dc"], p["dc2"]][:len(laws)]
        mass = p["mass"] or None
        key = (p["v_lp"], p["a"], *b, *dc, p["mass"], p["damping"])
        if key not in hopf_cache:
            try:
                hopf_cache[key] = hopf_point(a=p["a"], b=b, dc=dc, state_law=laws, v_lp=p["v_lp"], mass=mass,
                                             damping=p["damping"], dps=30)
            except InputError as exc:
                hopf_cache[key] = exc
            except (ValueError, ZeroDivisionError) as exc:   # mpmath's root finder did not converge
                hopf_cache[key] = RuntimeError(f"Hopf point not found: {exc}")
        h = hopf_cache[key]
        if isinstance(h, Exception):
            fields["status"][i] = (RateStateStatus.NO_HOPF_POINT if isinstance(h, InputError)
                                   else RateStateStatus.NOT_RESOLVED)
            messages[i] = str(h)
            continue
        fields["k_c"][i], fields["omega_c"][i] = h.k_c, h.omega_c
        fields["lyapunov_coefficient"][i] = h.lyapunov_coefficient
        fields["criticality"][i] = CRITICALITY.get(h.criticality, 0)
        k = p["kappa"] * h.k_c
        fields["k"][i] = k
        spec = SliderSpec(a=p["a"], b=b, dc=dc, state_law=laws, k=k, mass=mass, damping=p["damping"])
        # [engine] t_max is in the single block's time unit; here time scales like Dc/V_lp, so the run's
        # bound is MAX_PERIODS linear periods (and max_steps), whatever V_lp is
        f = fate(spec, p["v_lp"], 2 * math.pi / h.omega_c, max_steps=max_steps, t_max=math.inf)
        if f.kind == "unresolved" and spec.inertial:
            f = _deep(spec, p["v_lp"], 2 * math.pi / h.omega_c, max_steps, f)
        fields["status"][i] = _FATE[f.kind]
        fields["steps"][i] = f.steps
        for name in ("period", "ln_v_max", "ln_v_min", "slip", "multiplier_max"):
            fields[name][i] = getattr(f, name)
        if f.message:
            messages[i] = f.message
    return fields, messages


def _deep(spec, v_lp, period0, max_steps, f):
    """With mass, where the explicit run stalls or overflows (a deep stick phase or the slip law's inertial
    plunge), the event-split integrator's cycle (``slow_manifold.deep_cycle``, as ``--cycle`` does); ``f``
    (with both reasons) where it cannot vouch for one either."""
    from dataclasses import replace

    from .attractor import Fate
    from .slow_manifold import deep_cycle

    d = deep_cycle(spec, v_lp, period0, max_steps=max_steps)
    if d.status != "limit-cycle":
        return replace(f, message=f"{f.message}; event-split integrator: {d.message}", steps=f.steps + d.steps)
    x_lp = math.log(v_lp)   # Fate's extrema are ln V, CycleResult's ln(V/V_lp)
    return Fate("cycle", d.message, d.period, d.ln_v_max + x_lp, d.ln_v_min + x_lp, d.slip, d.multiplier_max,
                f.steps + d.steps)


RATE_STATE = Model(
    name="rate-state",
    title="spring-slider with rate-and-state friction",
    description=("μ = μ0 + a ln(V/V*) + Σ b_i ln(V* θ_i/(c_i Dc_i)), quasi-static k(V_lp − V) = dμ/dt (M = 0) or "
                 "M δ̈ = k(δ_lp − δ) − μ; per point the Hopf point of steady sliding (k_c, ω_c, l1) and, at "
                 "k = κ k_c, where steady sliding perturbed by 1e-2 in ln V goes (docs/rate-state.md)"),
    source=("Ruina, JGR 88, 10359 (1983); Rice & Ruina, J. Appl. Mech. 50, 343 (1983); "
            "Gu, Rice, Ruina & Tse, JMPS 32, 167 (1984)"),
    labels=LABELS,
    axes=AXES,
    parameters=(),
    state=(),
    events=(),
    outputs=OUTPUTS,
    statuses=tuple(s for s in RateStateStatus if s != RateStateStatus.NOT_COMPUTED),
    equations=None,
    classify=None,
    runner=_run,
    hooks=Hooks(describe_label="bifurcation.models.rate_state.store_report:describe_label",
                report="bifurcation.models.rate_state.store_report:blocks",
                bench="bifurcation.models.rate_state._bench:run_suite", bench_needs=("scipy", "numba", "numbalsoda"),
                commands="bifurcation.cli._rate_state:COMMANDS",
                workflow="bifurcation.models.rate_state.study:WORKFLOW"),
    units_note="those of the workflow's own V_lp, Dc and M (docs/rate-state.md)",
    # 1: the limit cycle's Newton shooting is polished with the Jacobian at the solution (2026-11-26),
    # which moves the last bits of a cycle's numbers. A store begun before must not be resumed with it.
    # 2: next to a Hopf point a run whose approach is too slow for its budget is solved by Newton on the return
    # map (attractor.SLOW_RHO, 2026-11-26): points that were not-resolved may now be cycles (what resolved
    # before is unchanged to the bit), so a store begun before would mix the two answers.
    revision=2,
)
