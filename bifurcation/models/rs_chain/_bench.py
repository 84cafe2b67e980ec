"""``bifurcation bench --suite rs-chain``: the engine against scipy's LSODA with a numba right-hand side.

The baseline is what a user would write in an afternoon: the same equations in the same variables
(ln V_j, ln θ_j, P; quasi-dynamic with radiation damping, free ends; docs/rs-chain.md) as one
``numba.njit`` function, integrated by ``scipy.integrate.solve_ivp(method="LSODA")`` (stiff/non-stiff
switching), with the event definition as two scalar event functions on max_j ln V_j − ln v_th
(upward: an event starts; downward: it ends), located by solve_ivp's root finding on the dense output.
Both codes start from the same state and run to the end of the engine's K-th event; the baseline's
catalog (t_start, potency, duration) is compared event by event with the engine's (which agrees with
the mpmath reference to ≤ 1e-10, tests/test_rs_chain.py). Timings are the best of ``repeat`` runs,
CPU seconds of this process; reported as ratios, never asserted.
"""

from __future__ import annotations

import math
import time

import numpy as np

__all__ = ["lsoda_catalog", "run_rs_chain_bench"]

CASES = ((4, 1.0, 100), (16, 3.0, 60), (64, 3.0, 20))   # (N, ℓ, events)
#: The baseline's accuracy is read on the first FIRST events: later ones part ways in a chaotic chain
#: (a 1e-12 difference grows event by event), for both codes alike.
FIRST = 10
_COMMON = dict(state_law="aging", a=0.01, b=0.015, dc=0.01, k=0.1, v_lp=1.0, eta=1e-3, v_th=10.0)


def _numba_rhs():
    import numba

    @numba.njit(cache=False)
    def rhs(t, u, n, a, b, dc, k, ell2, v_lp, eta):
        out = np.empty_like(u)
        v = np.exp(u[:n])
        total = 0.0
        for j in range(n):
            y = u[n + j]
            ydot = math.exp(-y) - v[j] / dc                  # aging: θ̇/θ = 1/θ − V/Dc
            lap = 0.0
            if n > 1:
                if j > 0:
                    lap += v[j - 1] - v[j]
                if j < n - 1:
                    lap += v[j + 1] - v[j]
            drive = k * (v_lp - v[j]) + ell2 * k * lap
            out[j] = (drive - b * ydot) / (a + eta * v[j])
            out[n + j] = ydot
            total += v[j]
        out[2 * n] = total
        return out

    return rhs


def lsoda_catalog(rhs, spec, state0, t_end: float, rtol: float, atol: float) -> dict:
    """The baseline's events up to ``t_end``: t_start, potency, duration (arrays)."""
    from scipy.integrate import solve_ivp

    n, ln_th = spec.n, math.log(spec.v_th)
    args = (n, spec.a, spec.b, spec.dc, spec.k, spec.ell ** 2, spec.v_lp, spec.eta)

    def up(t, u, *_):
        return np.max(u[:n]) - ln_th
    up.direction = 1

    def down(t, u, *_):
        return np.max(u[:n]) - ln_th
    down.direction = -1

    sol = solve_ivp(rhs, (0.0, t_end), state0, method="LSODA", rtol=rtol, atol=atol, events=(up, down),
                    args=args)
    t_up, t_dn = sol.t_events
    p_up, p_dn = sol.y_events[0][:, 2 * n] if len(t_up) else [], sol.y_events[1][:, 2 * n] if len(t_dn) else []
    m = min(len(t_up), len(t_dn))
    return {"t_start": np.asarray(t_up[:m]), "duration": np.asarray(t_dn[:m]) - np.asarray(t_up[:m]),
            "potency": np.asarray(p_dn[:m]) - np.asarray(p_up[:m]), "status": sol.status, "nfev": sol.nfev}


def _cpu(fn, repeat):
    best, out = math.inf, None
    for _ in range(repeat):
        t0 = time.process_time()
        out = fn()
        best = min(best, time.process_time() - t0)
    return best, out


def _errors(base: dict, ref) -> np.ndarray:
    """Per event in sequence, the largest relative difference of t_start, potency and duration."""
    count = min(len(base["t_start"]), ref.events)
    worst = np.zeros(count)
    for name in ("t_start", "potency", "duration"):
        a, b = np.asarray(base[name][:count]), np.asarray(getattr(ref, name)[:count])
        worst = np.maximum(worst, np.abs(a - b) / np.abs(b))
    return worst


def _summary(errors: np.ndarray, first: int = FIRST) -> tuple[float, int]:
    """(largest error over the first ``first`` events, how many leading events agree to 1e-6)."""
    head = float(np.max(errors[:first])) if errors.size >= first else math.inf
    bad = np.flatnonzero(errors > 1e-6)
    return head, int(bad[0]) if bad.size else int(errors.size)


def run_rs_chain_bench(repeat: int = 3, cases=CASES, rtols=(1e-8, 1e-10, 1e-12), echo=print) -> dict:
    """Events per CPU second of the engine and of LSODA (numba rhs) at several rtol, per (N, ℓ, K)."""
    from .simulate import RSChainSpec, initial_state, run

    say = echo or (lambda *_: None)
    rhs = _numba_rhs()
    rows = []
    say("rs-chain bench: aging law, a = 0.01, b = 0.015, Dc = 0.01, k = 0.1, V_lp = 1, η = 1e-3, v_th = 10, "
        "free ends, A = 1, seed 1; engine (heyoka, exact crossings) vs scipy LSODA + numba rhs; CPU seconds, "
        f"best of {repeat}")
    for n, ell, events in cases:
        spec = RSChainSpec(n=n, ell=ell, **_COMMON)
        s0 = initial_state(spec, 1.0, 1)
        run(spec, s0, 2)                                      # compile outside the timing
        t_ours, ref = _cpu(lambda: run(spec, s0, events), repeat)
        t_end = ref.t_end + 0.5 * (ref.t_end - ref.t_start[-1] if ref.events > 1 else 1.0)
        rhs(0.0, s0, n, spec.a, spec.b, spec.dc, spec.k, ell * ell, spec.v_lp, spec.eta)   # numba compile
        row = {"n": n, "ell": ell, "events": events, "engine_s": t_ours, "engine_events_per_s": events / t_ours,
               "engine_balance_max": float(np.max(ref.balance)), "lsoda": []}
        line = f"N = {n:4d} ℓ = {ell:g}: engine {events / t_ours:8.1f} ev/s"
        for rtol in rtols:
            t_base, base = _cpu(lambda rtol=rtol: lsoda_catalog(rhs, spec, s0, t_end, rtol, rtol * 1e-3), repeat)
            err, agree = _summary(_errors(base, ref))
            row["lsoda"].append({"rtol": rtol, "seconds": t_base, "events_found": int(len(base["t_start"])),
                                 f"max_rel_error_first_{FIRST}": err, "events_agreeing_to_1e-6": agree,
                                 "ratio": t_base / t_ours})
            line += (f" | LSODA rtol {rtol:g}: {events / t_base:7.1f} ev/s, err {err:.1e} over {FIRST}, "
                     f"{agree} agree ({t_base / t_ours:.1f}x)")
        say(line)
        rows.append(row)
    return {"suite": "rs-chain", "repeat": repeat, "cases": rows,
            "reference": "the engine's own catalog (it agrees with the mpmath reference to <= 1e-10)"}


if __name__ == "__main__":   # python -m bifurcation.models.rs_chain._bench
    run_rs_chain_bench()
