"""Validation of chain arguments: one-line errors naming the argument, the value and the fix."""

from __future__ import annotations

import math

import numpy as np

from ...errors import InputError

__all__ = ["DEFAULT_V_THRESHOLD", "ENDS", "ENGINES", "check_engine", "check_events", "check_initial",
           "check_n_events", "check_sigma", "check_size", "check_v_threshold", "check_verify"]

ENDS = ("free", "periodic")
ENGINES = ("exact", "compiled")


def _is_int(x) -> bool:
    return not isinstance(x, bool) and isinstance(x, (int, np.integer))


def _nonnegative(name: str, value, fix: str) -> float:
    """``value`` as a finite float ≥ 0, else a one-line error naming ``name``."""
    try:
        out = float(value)
    except (TypeError, ValueError):
        raise InputError(name, value, "is not a number", fix) from None
    if not math.isfinite(out) or out < 0:
        raise InputError(name, value, "must be finite and ≥ 0", fix)
    return out


def check_n_events(n: int, events: int, *, n_key: str, events_key: str, what: str, more: str, cap: int | None = None,
                   why: str = "each event costs O(N)") -> None:
    """N × events of one run within ``cap`` (default ``bounds.CHAIN_MAX_N_EVENTS``: each event costs O(N)
    outside its window): the same one-line error for ``bifurcation chain`` (``--events``) and a chain workflow
    (``grid.events``); ``what`` names the run, ``why`` the cost, ``more`` (after the fix) where longer runs go."""
    from ... import bounds

    cap = bounds.CHAIN_MAX_N_EVENTS if cap is None else cap
    if n * events > cap:
        raise InputError(events_key, events, f"with {n_key} {n} is N × events = {n * events:.3g} > "
                         f"{cap:.0e}, the most {what} computes ({why}; bifurcation.bounds)",
                         f"give {events_key} <= {cap // n} at this N{more}")


def check_size(n, ell, ends) -> tuple[int, float, str]:
    if not _is_int(n) or n < 1:
        raise InputError("n", n, "is not a number of blocks", "give an integer N ≥ 1, e.g. 64")
    ell_f = _nonnegative("ell", ell, "give a coupling ℓ ≥ 0, e.g. 1")
    if ends not in ENDS:
        raise InputError("ends", ends, "is not a boundary condition", "use 'free' or 'periodic'")
    return int(n), ell_f, ends


def check_sigma(sigma) -> float:
    """The friction drop σ: finite, 0 ≤ σ < 1 (Φ_σ(x) = (1 − σ)Φ(x/(1 − σ)); σ = 1 leaves no friction)."""
    fix = "give a friction drop 0 ≤ σ < 1, e.g. 0.01 (0: the seed's model)"
    if isinstance(sigma, bool):
        raise InputError("sigma", sigma, "is not a number", fix)
    try:
        out = float(sigma)
    except (TypeError, ValueError):
        raise InputError("sigma", sigma, "is not a number", fix) from None
    if not math.isfinite(out) or out < 0 or out >= 1:
        raise InputError("sigma", sigma, "must be finite with 0 ≤ σ < 1", fix)
    return out


#: the documented default of event membership by velocity: V_th = DEFAULT_V_THRESHOLD · ν (docs/chain.md,
#: "Event membership"): a block that creeps at the loading speed, O(ν), stays out; seismic slip is faster
DEFAULT_V_THRESHOLD = 10.0


def check_v_threshold(v_threshold, nu: float):
    """None (every block that moved belongs to the event), "default" (10 ν) or a finite V_th > 0."""
    if v_threshold is None:
        return None
    if isinstance(v_threshold, str) and v_threshold == "default":
        return DEFAULT_V_THRESHOLD * float(nu)
    fix = f"give a slip velocity V_th > 0 (in V0), e.g. {DEFAULT_V_THRESHOLD:g}·ν, or 'default', or None for 'until all stuck'"
    if isinstance(v_threshold, bool):
        raise InputError("v_threshold", v_threshold, "is not a number", fix)
    try:
        out = float(v_threshold)
    except (TypeError, ValueError):
        raise InputError("v_threshold", v_threshold, "is not a number", fix) from None
    if not math.isfinite(out) or out <= 0:
        raise InputError("v_threshold", v_threshold, "must be finite and > 0", fix)
    return out


def check_events(events) -> int:
    if not _is_int(events) or events < 1:
        raise InputError("events", events, "is not a number of events", "give an integer ≥ 1, e.g. 1000")
    return int(events)


def stress(u: np.ndarray, ell: float, ends: str) -> np.ndarray:
    """σ_j at t = 0: ℓ²(u_{j+1} − 2u_j + u_{j−1}) − u_j with the ghosts of ``ends``."""
    if ends == "periodic":
        lap = np.roll(u, 1) - 2 * u + np.roll(u, -1)
    else:
        lap = np.concatenate((u[:1], u[:-1])) - 2 * u + np.concatenate((u[1:], u[-1:]))
    return ell * ell * lap - u


def check_initial(n: int, ell: float, ends: str, u0, amplitude, seed) -> np.ndarray:
    """The initial displacements: ``u0`` as given, or a random start from ``amplitude`` and ``seed``.

    Random start: u_j = A r_j + c with r_j uniform in [0, 1) from ``numpy.random.default_rng(seed)``
    and the constant c chosen so that max_j σ_j(0) = 0 (a uniform shift of u moves every σ_j by the
    same amount, so it only sets the time of the first failure, t = 1/ν).
    """
    if u0 is not None and (amplitude is not None or seed is not None):
        raise InputError("u0", "given", "cannot be combined with amplitude/seed",
                         "give either u0 or amplitude and seed")
    if u0 is None:
        if amplitude is None:
            raise InputError("amplitude", None, "is missing", "give u0=array or amplitude=A (and seed=S)")
        amp = _nonnegative("amplitude", amplitude, "give an amplitude A ≥ 0, e.g. 0.5")
        if seed is None:   # a random start names its seed (issue 21: no silent seed 0)
            raise InputError("seed", None, "is missing (a random start from amplitude needs it)",
                             "give seed=S, e.g. seed=1 (the start is numpy.random.default_rng(S); seed=0 is the "
                             "start earlier versions took when none was given)")
        if not _is_int(seed) or seed < 0:
            raise InputError("seed", seed, "is not an integer ≥ 0", "give an integer seed ≥ 0, e.g. 1")
        rng = np.random.default_rng(int(seed))
        with np.errstate(over="ignore", invalid="ignore"):
            u = amp * rng.random(n)
            u = u + np.max(stress(u, ell, ends))
    else:
        try:
            u = np.array(u0, dtype=float)
        except (TypeError, ValueError):
            raise InputError("u0", u0, "is not an array of numbers", f"give {n} numbers") from None
        if u.ndim > 1:
            raise InputError("u0", f"an array of shape {u.shape}", "is not one list of displacements",
                             f"give {n} numbers in one flat list")
        u = u.ravel()
        if u.size != n:
            raise InputError("u0", f"{u.size} values", f"does not have n = {n} values", f"give exactly {n} numbers")
        if not np.all(np.isfinite(u)):
            bad = int(np.flatnonzero(~np.isfinite(u))[0])
            raise InputError("u0", f"u0[{bad}] = {u[bad]}", "is not finite", "give finite numbers")
    with np.errstate(over="ignore", invalid="ignore"):
        s = stress(u, ell, ends)
    if not np.all(np.isfinite(s)):   # u finite, its stresses not: the amplitude or u0 overflows
        name, value = ("u0", f"max |u0| = {np.max(np.abs(u)):.3g}") if u0 is not None else ("amplitude", amplitude)
        raise InputError(name, value, "gives stresses beyond the floating-point range",
                         "give displacements of a sensible size (|σ_j| ≪ 1e300), e.g. amplitude 0.5")
    if np.any(s >= 1):
        j = int(np.argmax(s))
        raise InputError("u0" if u0 is not None else "amplitude", f"σ[{j}] = {s[j]:.6g}" if u0 is not None
                         else amplitude, f"puts block {j} at stress σ = {s[j]:.6g} ≥ 1 at t = 0",
                         "all blocks must start stuck (σ_j < 1): lower the displacements or the amplitude")
    return u


def check_engine(engine, sigma, tol, precision, energy) -> tuple[str, float, float]:
    """(engine, σ_f, tol) checked: the compiled engine is double precision without energy budget; σ_f
    in [0, 1) (both engines); tol in [1e-15, 1e-3]."""
    if engine not in ENGINES:
        raise InputError("engine", engine, "is not a chain engine", "use 'exact' or 'compiled'")
    try:
        sig = float(sigma)
    except (TypeError, ValueError):
        raise InputError("sigma", sigma, "is not a number", "give a friction drop 0 ≤ σ < 1, e.g. 0.01") from None
    if not (math.isfinite(sig) and 0 <= sig < 1):
        raise InputError("sigma", sigma, "must be in [0, 1)", "give a friction drop 0 ≤ σ < 1, e.g. 0.01")
    if tol is None:
        from ._compiled import TOL
        tol_f = TOL
    else:
        try:
            tol_f = float(tol)
        except (TypeError, ValueError):
            raise InputError("tol", tol, "is not a number", "give a tolerance in [1e-15, 1e-3], e.g. 1e-12") from None
        if not (math.isfinite(tol_f) and 1e-15 <= tol_f <= 1e-3):
            raise InputError("tol", tol, "is outside [1e-15, 1e-3]", "give a tolerance in [1e-15, 1e-3], e.g. 1e-12")
    if engine == "compiled":
        if precision != "double":
            raise InputError("precision", precision, "is not available in the compiled engine",
                             "use precision='double' or engine='exact'")
        if energy:
            raise InputError("energy", energy, "is not available in the compiled engine",
                             "use energy=False or engine='exact'")
    else:
        if tol is not None:
            raise InputError("tol", tol, "applies to the compiled engine only", "use engine='compiled' or drop tol")
    return engine, sig, tol_f


def check_verify(verify, engine, sigma) -> float:
    """The fraction of events to re-run exactly: 0 (none) or in (0, 1], compiled engine (any σ_f)."""
    try:
        f = float(verify)
    except (TypeError, ValueError):
        raise InputError("verify", verify, "is not a number", "give a fraction in (0, 1], e.g. 0.01") from None
    if not (math.isfinite(f) and 0 <= f <= 1):
        raise InputError("verify", verify, "must be in [0, 1]", "give a fraction in (0, 1], e.g. 0.01")
    if f > 0 and engine != "compiled":
        raise InputError("verify", verify, "checks the compiled engine", "use engine='compiled' with verify")
    return f
