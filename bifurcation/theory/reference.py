"""Independent high-precision references for one slip cycle, in mpmath.

Nothing here uses heyoka or the engine: these are the yardsticks the engine is tested against.

``piecewise_linear_exact``
    The piecewise-linear law, Eq. (12) of Vasconcelos, PRL 76, 4865 (1996), solved *exactly*. On each
    piece the equation of motion is linear with constant coefficients, so the motion is a closed form
    (homogeneous + particular solution) from the state where the piece starts; only the switch and
    stop times are roots of closed forms, found by bracketing and refined at ``dps`` digits.
``carlson_langer_mp``
    The Carlson–Langer law, Eq. (19), by mpmath's Taylor-series ODE solver ``mpmath.odefun``. It is
    slow (seconds to a minute per point); use it for a couple of points only (we use ν = 1e-3 and
    1e-6 at ν_f = 0.4).
``limit_orbit_exact``
    The ν → 0 slip, independently of Eq. (18): the exact piecewise motion along the limit orbit
    (Eq. 14 continued through the frictionless piece). Eq. (18) itself is in ``bifurcation.theory``,
    which is tested against this module and so is not imported here.

Frame (docs/physics.md): U is measured from the start position, Ü = νt − U + 1 − Φ(U̇/ν_f),
U(0) = U̇(0) = 0, and the cycle ends when U̇ first returns to 0. α = 1/(2ν_f).

Inputs ν, ν_f may be floats (taken as the exact binary numbers, the same the engine sees), decimal
strings or mpmath numbers.
"""

from __future__ import annotations

from dataclasses import dataclass

import mpmath

from ..errors import InputError

__all__ = ["carlson_langer_mp", "limit_orbit_exact", "piecewise_linear_exact"]

#: Extra digits carried internally, so the returned values are good to the ``dps`` asked for.
_GUARD = 20
#: Extra digits for ``mpmath.odefun``, whose tolerance is 10^−(dps+5). 10 are enough: at ν = 1e-3,
#: ν_f = 0.4, dps 30 the results agree with 20 guard digits to 2e-40, and 20 take 30% longer (2.7 s).
_CL_GUARD = 10
#: Scan steps per unit of the fastest rate of a piece; roots closer than this are caught through the
#: extremum check in between, so the step only needs to be small against the oscillation period.
_STEPS_PER_RATE = 8


@dataclass(frozen=True)
class _Piece:
    """A linear piece Ü − 2aU̇ + U = νt + c − 2aν, whose particular solution is U_p = νt + c.

    Linear friction (x ≤ 1): a = α, c = 2αν (Eq. 6). Frictionless (x ≥ 1): a = 0, c = 1.
    """

    name: str
    damping: object   # a
    offset: object    # c


class _Motion:
    """Closed-form motion on one piece from the state (u0, v0) at time t_start.

    With y = U − U_p and κ = a² − 1, y(s) = e^{as}[y0 C(s) + (ẏ0 − a y0) S(s)], where C, S solve
    f'' = κ f with C(0) = 1, C'(0) = 0, S(0) = 0, S'(0) = 1 (cos/sin, 1/s, cosh/sinh), and
    ẏ(s) = e^{as}[ẏ0 C + (a ẏ0 − y0) S], ÿ = 2a ẏ − y. This covers α < 1, α = 1 and α > 1 alike.
    """

    def __init__(self, piece: _Piece, nu, t_start, u0, v0):
        self.piece, self.nu, self.t_start = piece, nu, t_start
        a = piece.damping
        self.a = a
        self.kappa = a * a - 1
        self.y0 = u0 - (nu * t_start + piece.offset)
        self.dy0 = v0 - nu
        self.rate = mpmath.sqrt(abs(self.kappa))

    def _cs(self, s):
        w = self.rate
        if self.kappa < 0:
            return mpmath.cos(w * s), mpmath.sin(w * s) / w
        if self.kappa > 0:
            return mpmath.cosh(w * s), mpmath.sinh(w * s) / w
        return mpmath.mpf(1), s

    def state(self, s):
        """(U, U̇, Ü) at time t_start + s."""
        a, y0, dy0 = self.a, self.y0, self.dy0
        c, sn = self._cs(s)
        e = mpmath.exp(a * s)
        y = e * (y0 * c + (dy0 - a * y0) * sn)
        dy = e * (dy0 * c + (a * dy0 - y0) * sn)
        t = self.t_start + s
        return self.nu * t + self.piece.offset + y, self.nu + dy, 2 * a * dy - y

    def velocity(self, s):
        return self.state(s)[1]

    def acceleration(self, s):
        return self.state(s)[2]

    def step(self):
        """Scan step: small against every time scale of the piece (growth a ± ω, period 2π/ω)."""
        fastest = abs(self.a) + (self.rate if self.kappa > 0 else 0)
        return mpmath.mpf(1) / (_STEPS_PER_RATE * max(1, fastest))


def _refine(f, df, lo, hi, dps):
    """Root of f in the bracket [lo, hi] (f(lo), f(hi) of opposite signs), verified at ``dps`` digits."""
    try:
        root = mpmath.findroot(f, (lo, hi), solver="anderson", verify=False)
        if not lo <= root <= hi:
            raise ValueError("left the bracket")
    except (ValueError, ZeroDivisionError):
        root = mpmath.findroot(f, (lo, hi), solver="bisect", verify=False)
    for _ in range(3):  # Newton polish, staying inside the bracket
        d = df(root)
        if d == 0:
            break
        new = root - f(root) / d
        if not lo <= new <= hi:
            break
        root = new
    d = df(root)
    correction = abs(f(root) / d) if d != 0 else mpmath.inf
    if not correction <= mpmath.mpf(10) ** (-dps + 5) * max(1, abs(root)):
        raise ArithmeticError(f"root in [{mpmath.nstr(lo, 8)}, {mpmath.nstr(hi, 8)}] not converged: "
                              f"Newton correction {mpmath.nstr(correction, 3)}")
    return root


def _first_event(motion: _Motion, targets, s_max, dps):
    """First s > 0 where U̇ crosses one of ``targets``, and the largest U̇ on [0, s].

    Scans U̇ and Ü on a grid. A sign change of U̇ − target brackets a root; a sign change of Ü
    brackets an extremum of U̇, which is located and checked too (a root pair inside one step, or
    a grazing touch, is caught there). The start point is excluded: a piece may start exactly on a
    target (U̇(0) = 0 is a double root at t = 0; the second linear piece starts at U̇ = ν_f).
    """
    h = motion.step()
    s_prev = h
    _, v_prev, acc_prev = motion.state(s_prev)
    vmax = max(motion.state(0)[1], v_prev)
    while s_prev < s_max:
        s_next = s_prev + h
        _, v_next, acc_next = motion.state(s_next)
        points = [(s_prev, v_prev)]
        if acc_prev > 0 > acc_next or acc_prev < 0 < acc_next:
            s_ext = _refine(motion.acceleration, lambda s: _jerk(motion, s), s_prev, s_next, dps)
            v_ext = motion.velocity(s_ext)
            points.append((s_ext, v_ext))
            vmax = max(vmax, v_ext)
        points.append((s_next, v_next))
        for (sa, va), (sb, vb) in zip(points, points[1:]):
            hits = [(tg, sa, sb) for tg in targets if (va - tg) * (vb - tg) <= 0 and va != tg]
            if hits:
                found = [(_refine(lambda s, tg=tg: motion.velocity(s) - tg, motion.acceleration, a_, b_, dps),
                          tg) for tg, a_, b_ in hits]
                s_event, target = min(found, key=lambda x: x[0])
                return s_event, target, max(vmax, max(v for s, v in points if s <= s_event))
        vmax = max(vmax, v_next)
        s_prev, v_prev, acc_prev = s_next, v_next, acc_next
    return None, None, vmax


def _jerk(motion: _Motion, s):
    """d³U/dt³ = 2a Ü − U̇ + ν on any piece (derivative of Ü = 2a U̇ − U + νt + const)."""
    _, v, acc = motion.state(s)
    return 2 * motion.a * acc - v + motion.nu


def _run(nu, nu_f, t_start, u0, v0, piece_name, dps, t_max):
    """Follow the piecewise motion from a state until U̇ returns to 0; returns the cycle summary."""
    alpha = 1 / (2 * nu_f)
    linear = _Piece("linear", alpha, 2 * alpha * nu)
    free = _Piece("frictionless", mpmath.mpf(0), mpmath.mpf(1))
    piece = linear if piece_name == "linear" else free
    t, u, v = t_start, u0, v0
    switch_times, vmax = [], v0
    while True:
        motion = _Motion(piece, nu, t, u, v)
        targets = [mpmath.mpf(0), nu_f] if piece is linear else [nu_f]
        s, target, vpiece = _first_event(motion, targets, t_max - t, dps)
        vmax = max(vmax, vpiece)
        if s is None:
            raise ArithmeticError(f"no stop before t = {mpmath.nstr(t_max, 6)} (nu={mpmath.nstr(nu, 6)}, "
                                  f"nu_f={mpmath.nstr(nu_f, 6)}); raise t_max if the cycle is really longer")
        u, _, _ = motion.state(s)
        t = t + s
        if piece is linear and target == 0:
            return t, u, switch_times, vmax
        v = target  # exactly on the switching value
        switch_times.append(t)
        piece = free if piece is linear else linear


def _mp(x, name):
    try:
        value = mpmath.mpf(x)
    except (TypeError, ValueError):
        raise InputError(name, x, "is not a real number", f"give {name} as a float, string or mpmath number") from None
    if not (mpmath.isfinite(value) and value > 0):
        raise InputError(name, x, "must be positive and finite", f"give {name} > 0")
    return value


def piecewise_linear_exact(nu, nu_f, dps: int = 40, t_max=10_000) -> dict:
    """Exact slip cycle for the piecewise-linear law, Eq. (12), in mpmath.

    The motion is the closed-form solution of each linear piece (Eq. 6 on x ≤ 1, with particular
    solution ν(t + 2α); Ü + U = νt + 1 on x ≥ 1, particular νt + 1), continued through every switch
    at U̇ = ν_f until U̇ returns to 0. Switch and stop times are bracketed by scanning and refined to
    ``dps`` digits (verified by a Newton correction ≤ 10^(−dps+5)).

    Parameters
    ----------
    nu, nu_f : float, str or mpmath number
        Pulling speed ν and friction velocity ν_f (floats are used as their exact binary values).
    dps : int
        Decimal digits of the results.
    t_max : number
        Give up (``ArithmeticError``) if the block has not stopped by this time.

    Returns
    -------
    dict
        ``delta`` (U at the stop), ``stop_time``, ``creep_time`` (first time U̇ = ν_f, None in creep),
        ``slip_duration`` (stop_time − creep_time, None in creep), ``max_velocity``, ``switch_times``
        (all times U̇ crosses ν_f) and ``status`` ("stick-slip" or "creep"), all mpmath numbers.
    """
    with mpmath.workdps(dps + _GUARD):
        nu, nu_f = _mp(nu, "nu"), _mp(nu_f, "nu_f")
        zero = mpmath.mpf(0)
        stop, delta, switches, vmax = _run(nu, nu_f, zero, zero, zero, "linear", dps, mpmath.mpf(t_max))
        creep_time = switches[0] if switches else None
        return {
            "delta": delta,
            "stop_time": stop,
            "creep_time": creep_time,
            "slip_duration": stop - creep_time if switches else None,
            "max_velocity": vmax,
            "switch_times": switches,
            "status": "stick-slip" if switches else "creep",
        }


def limit_orbit_exact(nu_f, dps: int = 40) -> dict:
    """The ν → 0 cycle for Eq. (12) computed by the exact piecewise motion, without Eq. (18).

    For ν = 0 the fast eigen-solution U = c e^{λ+ t}, λ+ = α + ω, of Eq. (6) is exact, so the limit
    orbit (Eq. 14) reaches U̇ = ν_f at U = ν_f/λ+ = ν_f(α − ω). From there the exact piecewise motion
    with ν = 0 gives τ1, τ2 (Eqs. 16, 17) and Δ0 (Eq. 18). Only for ν_f ≤ 1/2.

    Returns
    -------
    dict
        ``delta0``, ``tau1`` (end of the frictionless swing), ``tau2`` (the stop), time from τ = 0.
    """
    with mpmath.workdps(dps + _GUARD):
        nu_f = _mp(nu_f, "nu_f")
        if nu_f > mpmath.mpf(1) / 2:
            raise InputError("nu_f", nu_f, "has no stick-slip limit orbit (alpha < 1)", "use nu_f <= 1/2")
        alpha = 1 / (2 * nu_f)
        lam = alpha + mpmath.sqrt(alpha * alpha - 1)
        zero = mpmath.mpf(0)
        stop, delta, switches, _ = _run(zero, nu_f, zero, nu_f / lam, nu_f, "frictionless", dps,
                                        mpmath.mpf(1000))
        return {"delta0": delta, "tau1": switches[0], "tau2": stop}


def carlson_langer_mp(nu, nu_f, dps: int = 30, t_max=200) -> dict:
    """Slip cycle for the Carlson–Langer law, Eq. (19), by ``mpmath.odefun`` (Taylor series).

    Solved in the scaled variables U = νW of docs/physics.md, so W is O(1) early in the cycle:
    Ẅ = t − W + g(νẆ/ν_f)/ν with g(x) = x/(1 + x), i.e. Ẅ = t − W + Ẇ/(ν_f + νẆ), W(0) = Ẇ(0) = 0.
    The stop (Ẇ back to 0), the creep time (νẆ = ν_f) and the maximum velocity (Ẅ = 0) are found by
    bracketing on a grid and ``findroot`` on the dense Taylor solution.

    Slow: seconds to a minute per point at dps 30. Meant for a couple of check points only (ν = 1e-3
    and 1e-6 at ν_f = 0.4), not for grids.

    Returns
    -------
    dict
        ``delta``, ``stop_time``, ``creep_time`` (None if U̇ never reaches ν_f), ``slip_duration``,
        ``max_velocity``. No status: for a smooth law, stick-slip (Δ finite as ν → 0, ν_f ≤ 1/2) is
        not decided by whether U̇ reaches ν_f (at ν_f = 0.4 it peaks at 0.355).
    """
    with mpmath.workdps(dps + _CL_GUARD):
        nu, nu_f = _mp(nu, "nu"), _mp(nu_f, "nu_f")
        solution = mpmath.odefun(lambda t, y: [y[1], _cl_rhs(t, y[0], y[1], nu, nu_f)], 0, [0, 0],
                                 tol=mpmath.mpf(10) ** (-dps - 5))

        def wdot(t):
            return solution(t)[1]

        def wddot(t):
            return _cl_rhs(t, *solution(t), nu, nu_f)

        h = mpmath.mpf(1) / 16
        t_prev, v_prev, acc_prev = h, wdot(h), wddot(h)
        creep_time, vmax = None, v_prev
        target = nu_f / nu
        while t_prev < t_max:
            t_next = t_prev + h
            v_next, acc_next = wdot(t_next), wddot(t_next)
            if creep_time is None and v_prev < target <= v_next:
                creep_time = _refine(lambda t: wdot(t) - target, wddot, t_prev, t_next, dps)
            if acc_prev > 0 >= acc_next:
                t_ext = _refine(wddot, lambda t: _cl_jerk(solution, nu, nu_f, t), t_prev, t_next, dps)
                vmax = max(vmax, wdot(t_ext))
            if v_next <= 0:
                stop = _refine(wdot, wddot, t_prev, t_next, dps)
                delta = nu * solution(stop)[0]
                return {
                    "delta": delta,
                    "stop_time": stop,
                    "creep_time": creep_time,
                    "slip_duration": stop - creep_time if creep_time is not None else None,
                    "max_velocity": nu * vmax,
                }
            t_prev, v_prev, acc_prev = t_next, v_next, acc_next
        raise ArithmeticError(f"no stop before t = {t_max} (nu={mpmath.nstr(nu, 6)}, nu_f={mpmath.nstr(nu_f, 6)})")


def _cl_rhs(t, w, v, nu, nu_f):
    """Ẅ = t − W + Ẇ/(ν_f + νẆ): the Carlson–Langer law in the scaled variables (g(x) = x/(1 + x))."""
    return t - w + v / (nu_f + nu * v)


def _cl_jerk(solution, nu, nu_f, t):
    """d/dt of Ẅ = t − W + Ẇ/(ν_f + νẆ)."""
    w, v = solution(t)
    return 1 - v + _cl_rhs(t, w, v, nu, nu_f) * nu_f / (nu_f + nu * v) ** 2
