"""Frozen, validated specifications of a rate-and-state spring-slider and its load-point history.

Every check names the argument, shows the value and says what to do (``InputError``), so the CLI can
print it as one line with exit status 2.
"""

from __future__ import annotations

import math
from dataclasses import dataclass

from ...errors import InputError
from .laws import StateLaw, resolve_state_law

__all__ = ["LoadHistory", "SliderSpec", "load_history"]


def _finite(argument: str, value, *, positive=False, nonnegative=False, fix="give a finite number") -> float:
    try:
        v = float(value)
    except (TypeError, ValueError):
        raise InputError(argument, value, "is not a number", fix) from None
    if not math.isfinite(v):
        raise InputError(argument, value, "is not finite", fix)
    if positive and not v > 0:
        raise InputError(argument, value, "must be > 0", fix)
    if nonnegative and not v >= 0:
        raise InputError(argument, value, "must be >= 0", fix)
    from ...engine._exact import Text, decimal_text

    text = decimal_text(value)   # a decimal given as text keeps it: a "quad" run reads it in real128
    return value if isinstance(value, Text) else (Text(text) if text is not None else v)


@dataclass(frozen=True)
class LoadHistory:
    """A piecewise-constant load-point velocity: ``velocities[j]`` on [times[j], times[j+1]).

    ``times[0]`` is the start of the run; the last velocity holds to the end. A velocity step is a
    boundary of the integration (``propagate_until`` lands on it exactly), never smoothed.
    Velocity 0 is a hold (slide-hold-slide).
    """

    times: tuple[float, ...]
    velocities: tuple[float, ...]

    def __post_init__(self) -> None:
        if len(self.times) == 0 or len(self.times) != len(self.velocities):
            raise InputError("v_lp", self.velocities, "needs one start time per velocity (and at least one)",
                             "give e.g. load_history([1, 10], at=[10]) for velocity 1, then 10 from t = 10")
        times = tuple(_finite("v_lp times", t, fix="give finite step times") for t in self.times)
        vels = tuple(_finite("v_lp", v, nonnegative=True, fix="give load-point velocities >= 0 (0 is a hold)")
                     for v in self.velocities)
        if any(b <= a for a, b in zip(times, times[1:])):
            raise InputError("v_lp times", self.times, "are not strictly increasing",
                             "sort the step times and remove duplicates")
        object.__setattr__(self, "times", times)
        object.__setattr__(self, "velocities", vels)

    def velocity_at(self, t: float) -> float:
        """The load-point velocity in force at time ``t`` (the later one at a step)."""
        v = self.velocities[0]
        for tj, vj in zip(self.times, self.velocities):
            if t >= tj:
                v = vj
        return v

    def displacement(self, t, dtype=None) -> float:
        """Load-point displacement δ_lp(t) − δ_lp(times[0]); in ``dtype`` (e.g. real128) when given, the
        velocities read from their decimal text at that precision (engine._exact)."""
        if dtype is not None:
            from ...engine._exact import at_precision

            d = dtype(0)
            for j, (tj, vj) in enumerate(zip(self.times, self.velocities)):
                end = self.times[j + 1] if j + 1 < len(self.times) else math.inf
                if t <= tj:
                    break
                d += at_precision(vj, dtype) * (at_precision(min(t, end), dtype) - at_precision(tj, dtype))
            return d
        d = 0.0
        for j, (tj, vj) in enumerate(zip(self.times, self.velocities)):
            end = self.times[j + 1] if j + 1 < len(self.times) else math.inf
            if t <= tj:
                break
            d += vj * (min(t, end) - tj)
        return d


def load_history(velocities, at=(), start: float = 0.0) -> LoadHistory:
    """A load history from velocities and the times of the steps between them.

    ``load_history([1, 10], at=[10])``: velocity 1 from ``start`` = 0, 10 from t = 10 (rsfmodel's tests).
    ``load_history(3.0)``: constant velocity 3.
    """
    if isinstance(velocities, LoadHistory):
        return velocities
    if isinstance(velocities, (int, float)) or (hasattr(velocities, "ndim") and velocities.ndim == 0):
        velocities = [velocities]
    velocities = list(velocities)
    at = list(at)
    if len(velocities) == 0:
        raise InputError("v_lp", velocities, "is empty", "give at least one load-point velocity")
    if len(at) != len(velocities) - 1:
        raise InputError("v_lp at", at, f"needs {len(velocities) - 1} step times for {len(velocities)} velocities",
                         "give one step time between consecutive velocities")
    if at and not float(at[0]) > start:
        raise InputError("v_lp at", at, f"must start after the run's start t = {start:g}",
                         "give step times later than the start")
    return LoadHistory((start, *at), tuple(velocities))


@dataclass(frozen=True)
class SliderSpec:
    """A spring-slider with rate-and-state friction (docs/rate-state.md).

    μ = μ0 + a ln(V/V*) + Σ b_i ln(V* θ_i/(c_i Dc_i)); quasi-static k(δ_lp − δ) − ηV = μ when ``mass``
    is None, else M δ̈ = k(δ_lp − δ) − ηV − μ. ``damping`` η ≥ 0 is radiation damping in the slider's
    units (friction per unit slip rate: η_phys/σ_n, beside k = stiffness/σ_n).
    """

    a: float
    b: tuple[float, ...]
    dc: tuple[float, ...]
    state_law: tuple[str, ...]
    k: float
    mass: float | None = None
    mu0: float = 0.6
    v_ref: float = 1.0
    damping: float = 0.0

    def __post_init__(self) -> None:
        set_ = object.__setattr__
        set_(self, "a", _finite("a", self.a, positive=True, fix="the direct-effect parameter a must be > 0"))
        b = _tuple(self.b)
        dc = _tuple(self.dc)
        laws = (self.state_law,) * len(b) if isinstance(self.state_law, str) else tuple(self.state_law)
        if len(b) == 0:
            raise InputError("b", self.b, "is empty", "give one b per state variable, e.g. b=[0.015]")
        if len(b) > 2:
            raise InputError("b", self.b, f"has {len(b)} state variables", "give one or two state variables")
        if len(dc) != len(b) or len(laws) != len(b):
            raise InputError("dc/state_law", (self.dc, self.state_law),
                             f"do not match the {len(b)} state variable(s) of b",
                             "give one b, one dc and one state law per state variable")
        set_(self, "b", tuple(_finite("b", v, nonnegative=True, fix="b must be >= 0 (b < a: velocity strengthening)")
                              for v in b))
        set_(self, "dc", tuple(_finite("dc", v, positive=True, fix="the critical slip distance Dc must be > 0")
                               for v in dc))
        set_(self, "state_law", tuple(resolve_state_law(n).name for n in laws))
        set_(self, "k", _finite("k", self.k, positive=True, fix="the spring stiffness k must be > 0"))
        if self.mass is not None:
            set_(self, "mass", _finite("mass", self.mass, positive=True,
                                       fix="give a mass > 0, or none for the quasi-static slider"))
        set_(self, "damping", _finite("damping", self.damping, nonnegative=True,
                                      fix="give a radiation damping η >= 0 (0: none), in friction per unit slip rate"))
        set_(self, "mu0", _finite("mu0", self.mu0))
        set_(self, "v_ref", _finite("v_ref", self.v_ref, positive=True, fix="the reference velocity V* must be > 0"))

    @property
    def n_states(self) -> int:
        return len(self.b)

    @property
    def inertial(self) -> bool:
        return self.mass is not None

    @property
    def damped(self) -> bool:
        return self.damping > 0

    @property
    def laws(self) -> tuple[StateLaw, ...]:
        return tuple(resolve_state_law(n) for n in self.state_law)

    def mu(self, ln_v, ln_theta, log=math.log, num=float):
        """Friction μ from ln V and ln θ_i (numpy arrays, real128 arrays with ``num``, or mpmath numbers)."""
        if num is not float:   # a decimal input read at the precision of ``num`` (engine._exact)
            from ...engine._exact import decimal_text

            convert = num
            num = lambda x: convert(decimal_text(x)) if decimal_text(x) is not None else convert(x)  # noqa: E731
        mu = num(self.mu0) + num(self.a) * (ln_v - log(num(self.v_ref)))
        for law, b, dc, y in zip(self.laws, self.b, self.dc, ln_theta):
            mu = mu + num(b) * (y + log(num(self.v_ref)) - log(num(law.steady_factor) * num(dc)))
        return mu

def _tuple(value) -> tuple:
    if isinstance(value, str):
        return (value,)
    try:
        return tuple(value)
    except TypeError:
        return (value,)
