"""The attracting cycle of a slider under constant loading, as a result with error estimates.

``limit_cycle`` perturbs steady sliding (ln V raised by ``attractor.PERTURBATION``), lets the
transient die out and solves for the cycle by Newton on the Poincaré return map (section V = V_lp
crossed upwards; ``attractor.fate``, ``continuation.ReturnMap``). The cycle's numbers come from the
converged shooting map: period T (the map's time), ln(V_max/V_lp), ln(V_min/V_lp) (velocity extrema at
their exact event times on the dense output) and slip V_lp·T.

Error estimates: the same cycle is run again without stopping (``simulate.run_spec`` from the fixed
point, non-terminal events at V = V_lp), and its second turn — a step grid that no longer starts on
the section, so independent rounding and truncation — gives a second period and extrema. The estimate
of each number is the larger of |shooting − second turn| and 4 ulps of the value (for the ln V extrema,
of the largest of |ln V| and |ln θ_i|: the map's own variables), divided by 1 − ρ
(ρ the largest Floquet multiplier: the fixed point of a map known to δ is known to δ/(1 − ρ)); the
two ln V extrema share twice the larger of theirs. Where
no attracting cycle exists the status says what happened instead (``steady-sliding``, ``unbounded-growth``,
``not-resolved``, ``no-hopf-point``) and every number is NaN.

With mass, where the transient run stalls (a deep stick phase: the fast mode a'/(M V) limits the
explicit steps), the cycle is sought again by the event-split integrator (``slow_manifold.deep_cycle``:
inertial / slow-manifold phases); its error estimates also include a turn with the switch 10× deeper
and one more order of the series.
"""

from __future__ import annotations

import math
from dataclasses import asdict, dataclass

import numpy as np

__all__ = ["CycleResult", "limit_cycle"]

_ULPS = 4 * 2.220446049250313e-16


@dataclass(frozen=True)
class CycleResult:
    """The attracting cycle reached from perturbed steady sliding (module docstring)."""

    status: str                 # "limit-cycle", "steady-sliding", "unbounded-growth", "not-resolved", "no-hopf-point"
    message: str
    period: float = math.nan
    period_error: float = math.nan
    ln_v_max: float = math.nan          # ln(V_max / V_lp)
    ln_v_max_error: float = math.nan
    ln_v_min: float = math.nan          # ln(V_min / V_lp)
    ln_v_min_error: float = math.nan
    slip: float = math.nan              # slip per cycle, V_lp·T
    slip_error: float = math.nan
    multiplier_max: float = math.nan    # largest |Floquet multiplier|
    steps: int = 0                      # Taylor steps of the transient run

    def to_record(self) -> dict:
        return asdict(self)


_STATUS = {"steady": "steady-sliding", "unbounded": "unbounded-growth", "unresolved": "not-resolved"}


def limit_cycle(spec, v_lp: float, *, max_steps: int = 2_000_000, progress=None) -> CycleResult:
    """The attracting cycle of ``spec`` (a ``SliderSpec``) at constant load-point velocity ``v_lp``.

    Bounded: the transient run by ``max_steps`` Taylor steps and ``attractor.MAX_PERIODS`` linear periods
    (``attractor.time_scale``), the event-split search by ``max_steps`` more (``slow_manifold.deep_cycle``).
    ``progress(text)``, if given, is called along the way (the CLI throttles it onto stderr)."""
    from ...errors import InputError
    from .attractor import fate
    from .hopf import hopf_point

    try:
        h = hopf_point(a=spec.a, b=spec.b, dc=spec.dc, state_law=spec.state_law, v_lp=v_lp, mass=spec.mass,
                       damping=spec.damping, dps=30, lyapunov=False)
    except InputError as exc:
        # stable at every k: a perturbation decays, there is no cycle born at a Hopf point
        return CycleResult("no-hopf-point", f"no limit cycle: {exc.problem}")
    period0 = 2 * math.pi / h.omega_c
    f = fate(spec, v_lp, period0, max_steps=max_steps, t_max=math.inf, progress=progress)
    if f.kind == "unresolved" and spec.inertial:
        # with mass the explicit integrator stalls in a deep stick phase (fast mode a'/(M V)): the
        # event-split integrator (slow_manifold.py) takes over; where it cannot vouch either, say both
        from .slow_manifold import deep_cycle

        deep = deep_cycle(spec, v_lp, period0, max_steps=max_steps, progress=progress)
        if deep.status == "limit-cycle":
            return deep
        return CycleResult("not-resolved", f"no limit cycle at k/k_c = {spec.k / h.k_c:.6g}: no cycle could be "
                           f"vouched for ({f.message}; event-split integrator: {deep.message})",
                           steps=f.steps + deep.steps)
    if f.kind != "cycle":
        what = {"steady": "the perturbation decays to steady sliding", "unbounded": "V grows without bound",
                "unresolved": "no cycle could be vouched for"}[f.kind]
        detail = f.message if f.message.startswith(what) else f"{what}" + (f" ({f.message})" if f.message else "")
        return CycleResult(_STATUS[f.kind], f"no limit cycle at k/k_c = {spec.k / h.k_c:.6g}: {detail}",
                           steps=f.steps)
    x_lp = math.log(v_lp)
    second = _second_turn(spec, v_lp, f.w, f.period, max_steps)
    if second is None:
        return CycleResult("not-resolved", "the cycle found by Newton could not be re-run for its error estimate",
                           steps=f.steps)
    period2, top2, bottom2 = second

    # A fixed point of a map known to δ lies within δ/(1 − ρ) of the true one (ρ the largest multiplier):
    # the second turn measures δ, not the fixed point's error. Without the factor, at multiplier 0.984 the
    # estimates said 3e-16 where an mpmath shooting found the extrema 1.2e-13 off (tests/test_indep3_rate_state.py).
    # The two extrema share the fixed point's error, and one turn's difference is one sample of δ (it
    # came out 3.6x smaller for ln V_min than for ln V_max in a PRZ case): they get the larger of the two, twice.
    amplify = 1.0 / max(1.0 - f.multiplier_max, 1e-6)

    def err(a, b, floor=0.0):
        return max(abs(a - b), _ULPS * abs(a), floor) * amplify

    top, bottom = f.ln_v_max - x_lp, f.ln_v_min - x_lp
    # the map works in ln V and ln θ_i, not ln(V/V_lp): its rounding is ulps of those, which a small cycle's
    # ln(V/V_lp) (0.04 next to a Hopf point) does not show, and a second turn may agree by chance. Slip law,
    # M 0, η 0.00173, ρ = 0.9993: extrema 7.4e-13 off an mpmath shooting, estimate 3.2e-13 from the
    # second turn (tests/test_rscycle.py); ulps of ln θ = −5.2 give 1.3e-11.
    floor = _ULPS * max([abs(f.ln_v_max), abs(f.ln_v_min)] + [abs(v) for v in f.w[:spec.n_states]])
    ln_v_error = 2 * max(err(top, top2 - x_lp, floor), err(bottom, bottom2 - x_lp, floor))
    return CycleResult("limit-cycle", f.message, f.period, err(f.period, period2), top, ln_v_error,
                       bottom, ln_v_error, v_lp * f.period, v_lp * err(f.period, period2),
                       f.multiplier_max, f.steps)


def _second_turn(spec, v_lp, w, period, max_steps):
    """(period, max ln V, min ln V) of the second turn of a direct run from the cycle's section point."""
    from .simulate import run_spec
    from .spec import load_history

    n = spec.n_states
    r = run_spec(spec, load_history(v_lp), [0.0, 2.5 * period], ln_v0=math.log(v_lp), ln_theta0=list(w[:n]),
                 z0=w[n] if spec.inertial else 0.0, thresholds=[v_lp], max_steps=max_steps)
    ups = [c[0] for c in r.crossings if c[2] > 0]
    if r.status != "ok" or len(ups) < 2:
        return None
    t0, t1 = ups[0], ups[1]
    ext = r.extrema
    inside = ext[(ext[:, 0] > t0) & (ext[:, 0] < t1)] if ext.size else ext
    values = [math.log(v_lp)] + ([] if inside.size == 0 else list(inside[:, 1]))
    return t1 - t0, float(np.max(values)), float(np.min(values))
