"""``bifurcation bench --suite rate-state``: the engine against scipy ``odeint`` on rsfmodel's five cases.

Same cases, parameters and load history as rsfmodel's tests (tests/_rsfmodel_data.py: velocity 1, then 10
from t = 10; output at t = 0..40). The baseline is odeint (LSODA, rsfmodel's integrator) on rsfmodel's own
variables (μ, θ_i), given its best chance: each constant-velocity segment integrated separately, so
the step at t = 10 is a boundary as in our engine. odeint is run at rtol = atol = 1e-12 (rsfmodel's
setting) and at the tightest tolerance that keeps it accurate; the reference for both is our real128
run (which matches the mpmath reference to 1e-28, tests/test_rate_state.py). Times are the best of
``repeat`` runs, wall-clock, one core; reported as ratios, never asserted.
"""

from __future__ import annotations

import math
import time

import numpy as np

__all__ = ["run_rate_state_bench"]

_CASES = {  # name: (a, k, [(law, b, Dc)]) — rsfmodel's tests/rsf_tests.py at 8b1c9dd, numbers only
    "dieterich_1": (0.005, 1e-3, [("aging", 0.01, 10.0)]),
    "ruina_1": (0.01, 1e-3, [("slip", 0.005, 10.0)]),
    "prz_1": (0.011, 3e-3, [("prz", 0.01, 5.0)]),
    "dieterich_2": (0.012, 3e-3, [("aging", 0.0185, 5.0), ("aging", 0.0088, 50.0)]),
    "ruina_2": (0.012, 8e-3, [("slip", 0.0185, 5.0), ("slip", 0.0088, 50.0)]),
}
_TOLS = (1e-12, 1e-13, 1e-14, 3e-15)


def _odeint_case(a, k, states, rtol):
    from scipy.integrate import odeint

    mu0, vref = 0.6, 1.0
    laws = [s[0] for s in states]
    b = np.array([s[1] for s in states])
    dc = np.array([s[2] for s in states])
    c = np.array([2.0 if law == "prz" else 1.0 for law in laws])

    def rhs(y, t, v_lp):
        mu, th = y[0], y[1:]
        v = vref * math.exp((mu - mu0 - float(np.sum(b * np.log(vref * th / (c * dc))))) / a)
        out = [k * (v_lp - v)]
        for i, law in enumerate(laws):
            p = v * th[i] / dc[i]
            out.append(1 - p if law == "aging" else (-p * math.log(p) if law == "slip" else 1 - (p / 2) ** 2))
        return out

    y0 = np.array([mu0, *(c * dc / 1.0)])
    first = odeint(rhs, y0, np.arange(0.0, 11.0), args=(1.0,), rtol=rtol, atol=rtol)
    second = odeint(rhs, first[-1], np.arange(10.0, 41.0), args=(10.0,), rtol=rtol, atol=rtol)
    return np.concatenate([first[:, 0], second[1:, 0]])


def _best(fn, repeat):
    best = math.inf
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = fn()
        best = min(best, time.perf_counter() - t0)
    return best, out


def run_rate_state_bench(repeat: int = 5, echo=print) -> dict:
    """Time and error per case for the engine and odeint; returns a JSON-ready report."""
    import warnings

    from .simulate import rate_state
    from .spec import load_history

    history = load_history([1.0, 10.0], at=[10.0])
    t = np.arange(41.0)
    rows = []
    for name, (a, k, states) in _CASES.items():
        kw = dict(a=a, b=[s[1] for s in states], dc=[s[2] for s in states], state_law=[s[0] for s in states],
                  k=k, v_lp=history, t=t)
        ref = rate_state(precision="quad", **kw).mu.astype(float)
        rate_state(**kw)  # compile outside the timing
        t_ours, r = _best(lambda: rate_state(**kw), repeat)
        err_ours = float(np.max(np.abs(r.mu - ref) / ref))
        base = {}
        for tol in _TOLS:
            with warnings.catch_warnings():
                warnings.simplefilter("ignore")
                t_ode, mu = _best(lambda tol=tol: _odeint_case(a, k, states, tol), repeat)
            base[tol] = (t_ode, float(np.max(np.abs(mu - ref) / ref)))
        tightest = min(base, key=lambda tol: (base[tol][1], -tol))
        reach = [tol for tol in _TOLS if base[tol][1] <= err_ours]
        chosen = max(reach) if reach else tightest
        row = {"case": name, "engine_s": t_ours, "engine_error": err_ours,
               "odeint_1e-12_s": base[1e-12][0], "odeint_1e-12_error": base[1e-12][1],
               "odeint_chosen_rtol": chosen, "odeint_chosen_s": base[chosen][0],
               "odeint_chosen_error": base[chosen][1], "ratio_at_1e-12": base[1e-12][0] / t_ours,
               "ratio_at_chosen": base[chosen][0] / t_ours, "odeint_reaches_engine": bool(reach)}
        rows.append(row)
        if echo:
            echo(f"{name:12s} engine {t_ours * 1e3:7.2f} ms err {err_ours:.1e} | odeint 1e-12 "
                 f"{base[1e-12][0] * 1e3:7.2f} ms err {base[1e-12][1]:.1e} ({row['ratio_at_1e-12']:.1f}x) | "
                 f"odeint {chosen:g} {base[chosen][0] * 1e3:7.2f} ms err {base[chosen][1]:.1e} "
                 f"({row['ratio_at_chosen']:.1f}x{'' if reach else ', its best: never reaches ours'})")
    return {"suite": "rate-state", "repeat": repeat, "cases": rows,
            "reference": "heyoka real128 run of the same model (agrees with the mpmath reference to 1e-28)"}
