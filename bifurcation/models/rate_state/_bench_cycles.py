"""Deep stick-slip cycles in ``bifurcation bench --suite rate-state``: time per cycle, engine vs LSODA.

Kept apart from ``_bench.py`` (rsfmodel's cases) on purpose. With mass (``_inertial_rows``): the
event-split integrator (``slow_manifold.run_hybrid``) against LSODA+numba on the full inertial
equations (x, ln θ, z = M V̇), same start on the cycle's section, same end time. Three massless damped sliders whose
cycles span 42–45 in ln(V/V_lp) (a = 0.01, b = 0.025, Dc = 1, V_lp = 1; one per state law), each
started on its cycle at the section V = V_lp (the engine's fixed point of the return map) and run
for ``cycles`` periods T_ref of the mpmath reference (tests/data/make_rate_state_deep_cycles.py:
40 digits, no heyoka; the 30-digit periods are copied below). Both integrators get the same start and
the same end time; the error is the phase drift per cycle |Δt|/(N T_ref) read from ln V at the end
(Δt = ln(V_end/V_lp)/ẋ at the section). Baseline: LSODA (numbalsoda, Fortran-grade LSODA called from
numba, with a numba ``cfunc`` right-hand side in the same variables ln V, ln θ — a compiled integrator
with a compiled right-hand side, what a user would write) at rtol = atol = 1e-8 … 1e-12. Best of
``repeat`` CPU times of this process (QDYN: wall time of its process); ratios, never asserted.

QDYN, if the environment variable ``BIFURCATION_QDYN`` names a built QDYN source directory (its
``qdyn`` executable beside ``pyqdyn.py``; github.com/ydluo/qdyn, not part of this package): its
spring-block (MESHDIM = 0, RK45 at its default ACC = 1e-7 and its tightest 1e-11) on the same slider in its units
(σ = 1e6 Pa, shear modulus 3e10 Pa, L = μ/(kσ), c_s = μ/(2ησ)) from the same section point, for the
same time; time per cycle from a run that writes its time series every 10⁶ steps (so the wall time is
the solver's, plus process start), drift from a second run that writes every step (upward V = V_lp
crossings interpolated linearly in ln V: the mean period against the reference).
"""

from __future__ import annotations

import math
import os
import time

import numpy as np

__all__ = ["run_deep_cycle_bench"]

# (law, η, κ) and the mpmath period (tests/data/rate_state_deep_cycles.json, second turn, 30 digits)
_CASES = (
    ("aging", 1e-8, 0.1),
    ("slip", 1e-15, 0.03),
    ("prz", 1e-8, 0.03),
)
_REFERENCE = {
    ("aging", 1e-8, 0.1): "208.264939766827703017002248985",
    ("slip", 1e-15, 0.03): "1132.97607722850778193883509519",
    ("prz", 1e-8, 0.03): "675.213037010269605571231616814",
}
_BASE = {"a": 0.01, "b": 0.025, "dc": 1.0, "v_lp": 1.0}
# With mass (slow_manifold.py): (law, η, κ, M[, b]) and the mpmath period (tests/data/rate_state_deep_inertial.json)
_INERTIAL_CASES = (
    ("aging", 1e-8, 0.1, 1e-6),
    ("prz", 1e-8, 0.1, 1e-6),
    ("slip", 0.0, 0.03, 1e-4, 0.05),
)
_INERTIAL_REFERENCE = {
    ("aging", 1e-8, 0.1, 1e-6): "313.588142034062321455320093443",
    ("prz", 1e-8, 0.1, 1e-6): "284.758080733042039355930602426",
    ("slip", 0.0, 0.03, 1e-4): "669.901580388787572858918657242",
}
_RTOLS = (1e-8, 1e-10, 1e-12)


def _lsoda_rhs(law: str):
    import numba as nb

    aging, slip = law == "aging", law == "slip"
    sig = nb.types.void(nb.types.float64, nb.types.CPointer(nb.types.float64), nb.types.CPointer(nb.types.float64),
                        nb.types.CPointer(nb.types.float64))

    @nb.cfunc(sig, nopython=True, cache=False)
    def rhs(t, u, du, p):   # p: a, k, V_lp, η, b, Dc
        x, y = u[0], u[1]
        v = math.exp(x)
        if aging:
            ydot = math.exp(-y) - v / p[5]
        elif slip:
            ydot = -(v / p[5]) * (x + y - math.log(p[5]))
        else:
            ydot = math.exp(-y) - math.exp(2 * x + y) / (4 * p[5] * p[5])
        du[0] = (p[1] * (p[2] - v) - p[4] * ydot) / (p[0] + p[3] * v)
        du[1] = ydot
    return rhs


def _lsoda_inertial_rhs(law: str):
    """The inertial slider in x = ln V, y = ln θ, z = M V̇ (``_system``), for LSODA."""
    import numba as nb

    aging, slip = law == "aging", law == "slip"
    sig = nb.types.void(nb.types.float64, nb.types.CPointer(nb.types.float64), nb.types.CPointer(nb.types.float64),
                        nb.types.CPointer(nb.types.float64))

    @nb.cfunc(sig, nopython=True, cache=False)
    def rhs(t, u, du, p):   # p: a, k, V_lp, η, b, Dc, M
        x, y, z = u[0], u[1], u[2]
        v = math.exp(x)
        if aging:
            ydot = math.exp(-y) - v / p[5]
        elif slip:
            ydot = -(v / p[5]) * (x + y - math.log(p[5]))
        else:
            ydot = math.exp(-y) - math.exp(2 * x + y) / (4 * p[5] * p[5])
        xdot = z * math.exp(-x) / p[6]
        du[0] = xdot
        du[1] = ydot
        du[2] = p[1] * (p[2] - v) - (p[0] + p[3] * v) * xdot - p[4] * ydot
    return rhs


class _Quiet:
    """Silence file descriptors 1 and 2 (LSODA's Fortran warnings: "t + h = t", i.e. its steps fall
    below the resolution of the absolute time at the slip spikes; the drift column shows the cost)."""

    def __enter__(self):
        import os
        import sys

        sys.stdout.flush()
        sys.stderr.flush()
        self.saved = [os.dup(1), os.dup(2)]
        self.null = os.open(os.devnull, os.O_WRONLY)
        os.dup2(self.null, 1)
        os.dup2(self.null, 2)

    def __exit__(self, *exc):
        import os

        os.dup2(self.saved[0], 1)
        os.dup2(self.saved[1], 2)
        for fd in (*self.saved, self.null):
            os.close(fd)


def _best(fn, repeat):
    # CPU seconds of this process (the engine and LSODA are single-threaded): on a shared machine other
    # processes' load disturbs them less than wall time (QDYN, a separate process, is timed by the wall)
    best, out = math.inf, None
    for _ in range(repeat):
        t0 = time.process_time()
        out = fn()
        best = min(best, time.process_time() - t0)
    return best, out


def _qdyn_case(src: str, law: str, eta: float, k: float, theta0: float, t_end: float, every: int, acc: float):
    """(wall seconds, t, ln(V/V_lp)) of one QDYN spring-block run (module docstring)."""
    import os
    import shutil
    import subprocess
    import sys
    import tempfile

    sys.path.insert(0, src)
    from pyqdyn import qdyn   # QDYN's own input writer

    sigma, mu = 1e6, 3e10
    work = tempfile.mkdtemp(prefix="bifurcation_qdyn_")
    cwd = os.getcwd()
    try:
        os.chdir(work)
        p = qdyn()
        s = p.set_dict
        s.update({"MESHDIM": 0, "TMAX": t_end, "NTOUT": 10 ** 9, "NTOUT_OT": every, "V_PL": _BASE["v_lp"],
                  "MU": mu, "VS": mu / (2 * eta * sigma), "SIGMA": sigma, "L": mu / (k * sigma), "ACC": acc,
                  "SOLVER": 2, "FRICTION_MODEL": "RSF", "V_TH": 1e300})
        s["SET_DICT_RSF"].update({"RNS_LAW": 0, "THETA_LAW": {"aging": 1, "slip": 2}[law], "A": _BASE["a"],
                                  "B": _BASE["b"], "DC": _BASE["dc"], "V_SS": _BASE["v_lp"], "MU_SS": 0.6,
                                  "V_0": _BASE["v_lp"], "TH_0": theta0})
        p.settings(s)
        p.render_mesh()
        p.write_input()
        t0 = time.perf_counter()
        run = subprocess.run([os.path.join(src, "qdyn")], capture_output=True, text=True)
        wall = time.perf_counter() - t0
        ot = np.loadtxt("output_ot_0", comments="#", ndmin=2)
    finally:
        os.chdir(cwd)
        shutil.rmtree(work, ignore_errors=True)
    last = [ln.strip() for ln in (run.stdout + run.stderr).splitlines() if "error" in ln.lower()]
    return wall, ot[:, 0], np.log(ot[:, 3] / _BASE["v_lp"]), (last[-1] if last else "")


def _qdyn_row(src, law, eta, spec, theta0, t_ref, cycles, acc) -> dict:
    wall, _, _, _ = _qdyn_case(src, law, eta, spec.k, theta0, cycles * t_ref, 10 ** 6, acc)
    _, t, x, error = _qdyn_case(src, law, eta, spec.k, theta0, cycles * t_ref, 1, acc)
    if t[-1] < 0.99 * cycles * t_ref:   # QDYN stopped early: no time per cycle to report
        return {"acc": acc, "ms_per_cycle": math.nan, "period_error": math.nan, "steps": int(t.size),
                "stopped": f"QDYN stopped at t = {t[-1]:.4g} (ln V/V_lp = {x[-1]:.3g}): {error or 'no message'}"}
    up = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    t_up = t[up] - x[up] * (t[up + 1] - t[up]) / (x[up + 1] - x[up])
    period = float(np.mean(np.diff(t_up))) if t_up.size > 1 else math.nan
    return {"acc": acc, "ms_per_cycle": 1e3 * wall / cycles, "period_error": abs(period / t_ref - 1),
            "steps": int(t.size)}


def run_deep_cycle_bench(cycles: int = 20, repeat: int = 3, echo=print) -> dict:
    """Time per cycle and phase error per cycle for the engine and LSODA+numba (module docstring)."""
    from ._system import parameters, rhs_expressions
    from .attractor import fate
    from .cycle import limit_cycle
    from .simulate import run_spec
    from .spec import SliderSpec, load_history

    try:
        import numbalsoda
    except ImportError:
        numbalsoda = None
    rows = []
    for law, eta, kappa in _CASES:
        a, b, dc, v_lp = _BASE["a"], _BASE["b"], _BASE["dc"], _BASE["v_lp"]
        spec = SliderSpec(a=a, b=b, dc=dc, state_law=law, k=kappa * (b - a - eta * v_lp) / dc, damping=eta)
        c = limit_cycle(spec, v_lp)
        f = fate(spec, v_lp, c.period, max_steps=2_000_000, t_max=math.inf)
        t_ref = float(_REFERENCE[(law, eta, kappa)])
        t_end = cycles * t_ref
        x0 = math.log(v_lp)
        u0 = np.array([x0, f.w[0]])
        xdot0 = float(rhs_expressions(spec.state_law, False, u0, parameters(spec, spec.k, v_lp), np.exp, np.log,
                                      damped=True)[0])

        def drift(x_end):
            return abs((x_end - x0) / xdot0) / t_end

        def engine():
            return run_spec(spec, load_history(v_lp), [0.0, t_end], ln_v0=x0, ln_theta0=[f.w[0]])

        engine()   # compile outside the timing
        t_eng, r = _best(engine, repeat)
        row = {"case": f"{law} η={eta:g} κ={kappa:g}", "span_ln_v": c.ln_v_max - c.ln_v_min, "cycles": cycles,
               "engine_ms_per_cycle": 1e3 * t_eng / cycles, "engine_drift_per_cycle": drift(float(r.ln_v[-1])),
               "engine_steps_per_cycle": r.steps / cycles, "lsoda": []}
        if numbalsoda is not None:
            ptr = _lsoda_rhs(law).address
            data = np.array([a, spec.k, v_lp, eta, b, dc])
            for rtol in _RTOLS:
                def lsoda(rtol=rtol):
                    return numbalsoda.lsoda(ptr, u0.copy(), np.array([0.0, t_end]), data=data, rtol=rtol,
                                            atol=rtol, mxstep=10 ** 8)
                with _Quiet():
                    lsoda()
                    t_l, (usol, ok) = _best(lsoda, repeat)
                row["lsoda"].append({"rtol": rtol, "ms_per_cycle": 1e3 * t_l / cycles, "ok": bool(ok),
                                     "drift_per_cycle": drift(float(usol[-1, 0])) if ok else math.nan,
                                     "ratio": t_l / t_eng})
        qdyn_src = os.environ.get("BIFURCATION_QDYN")
        if qdyn_src and law in ("aging", "slip"):   # QDYN has no PRZ law
            row["qdyn"] = [_qdyn_row(qdyn_src, law, eta, spec, math.exp(f.w[0]), t_ref, cycles, acc)
                           for acc in (1e-7, 1e-11)]   # QDYN's default accuracy and its tightest
            for q in row["qdyn"]:
                q["ratio"] = q["ms_per_cycle"] / row["engine_ms_per_cycle"]
        rows.append(row)
        if echo:
            base = " | ".join(f"LSODA {x['rtol']:g}: {x['ms_per_cycle']:.2f} ms ({x['ratio']:.1f}x), drift "
                              f"{x['drift_per_cycle']:.1e}" for x in row["lsoda"]) or "LSODA: numbalsoda not installed"
            for q in row.get("qdyn", []):
                base += (f" | QDYN ACC {q['acc']:g}: {q['stopped']}" if "stopped" in q else
                         f" | QDYN ACC {q['acc']:g}: {q['ms_per_cycle']:.2f} ms ({q['ratio']:.1f}x), period error "
                         f"{q['period_error']:.1e}")
            echo(f"{row['case']:24s} span {row['span_ln_v']:.1f}: engine {row['engine_ms_per_cycle']:.2f} ms/cycle "
                 f"({row['engine_steps_per_cycle']:.0f} steps), drift {row['engine_drift_per_cycle']:.1e} | {base}")
    inertial = _inertial_rows(cycles, repeat, echo, numbalsoda)
    return {"suite": "rate-state deep cycles", "cycles": cycles, "repeat": repeat, "cases": rows,
            "inertial_cases": inertial,
            "reference": "mpmath periods, tests/data/make_rate_state_deep_cycles.py and make_rate_state_deep_inertial.py"}


def _inertial_rows(cycles, repeat, echo, numbalsoda) -> list:
    """Deep cycles with mass: the event-split integrator (slow_manifold.run_hybrid) against LSODA on the full
    inertial equations (its BDF mode handles the stiff stick phase), both from the engine's section point."""
    from .hopf import hopf_point
    from .slow_manifold import deep_cycle_point, run_hybrid
    from .spec import SliderSpec

    rows = []
    for law, eta, kappa, mass, *rest in _INERTIAL_CASES:
        key = (law, eta, kappa, mass)
        if key not in _INERTIAL_REFERENCE:
            continue
        a, b, dc, v_lp = _BASE["a"], (rest or [_BASE["b"]])[0], _BASE["dc"], _BASE["v_lp"]
        h = hopf_point(a=a, b=b, dc=dc, state_law=law, v_lp=v_lp, mass=mass, damping=eta, dps=30, lyapunov=False)
        spec = SliderSpec(a=a, b=b, dc=dc, state_law=law, k=kappa * h.k_c, damping=eta, mass=mass)
        c, phase, w = deep_cycle_point(spec, v_lp, 2 * math.pi / h.omega_c)
        if c.status != "limit-cycle" or phase != "inertial":
            rows.append({"case": f"{law} b={b:g} η={eta:g} κ={kappa:g} M={mass:g}", "status": c.status})
            continue
        t_ref = float(_INERTIAL_REFERENCE[key])
        t_end = cycles * t_ref
        x0 = math.log(v_lp)
        u0 = np.array([x0, *w])
        xdot0 = w[-1] / (mass * v_lp)

        def drift(x_end):
            return abs((x_end - x0) / xdot0) / t_end

        def engine():
            return run_hybrid(spec, v_lp, "inertial", u0, t_end)

        t_eng, r = _best(engine, repeat)
        row = {"case": f"{law} b={b:g} η={eta:g} κ={kappa:g} M={mass:g}", "span_ln_v": c.ln_v_max - c.ln_v_min,
               "cycles": cycles, "engine_ms_per_cycle": 1e3 * t_eng / cycles,
               "engine_drift_per_cycle": drift(float(r.state[0])) if r.status == "ok" else math.nan,
               "engine_steps_per_cycle": r.steps / cycles, "lsoda": []}
        if numbalsoda is not None:
            ptr = _lsoda_inertial_rhs(law).address
            data = np.array([a, spec.k, v_lp, eta, b, dc, mass])
            for rtol in _RTOLS:
                def lsoda(rtol=rtol):
                    return numbalsoda.lsoda(ptr, u0.copy(), np.array([0.0, t_end]), data=data, rtol=rtol,
                                            atol=rtol, mxstep=10 ** 8)
                with _Quiet():
                    lsoda()
                    t_l, (usol, ok) = _best(lsoda, repeat)
                # LSODA may report success with a non-finite state (measured: NaN on the way out of the
                # deep stick phase): that is a failure, not a drift
                ok = bool(ok) and bool(np.all(np.isfinite(usol[-1])))
                row["lsoda"].append({"rtol": rtol, "ms_per_cycle": 1e3 * t_l / cycles, "ok": ok,
                                     "drift_per_cycle": drift(float(usol[-1, 0])) if ok else math.nan,
                                     "ratio": t_l / t_eng})
        rows.append(row)
        if echo:
            base = " | ".join(f"LSODA {x['rtol']:g}: " + (f"{x['ms_per_cycle']:.2f} ms ({x['ratio']:.1f}x), drift "
                              f"{x['drift_per_cycle']:.1e}" if x["ok"] else "failed (non-finite state)")
                              for x in row["lsoda"]) or "LSODA: numbalsoda not installed"
            echo(f"{row['case']:30s} span {row['span_ln_v']:.1f}: engine {row['engine_ms_per_cycle']:.2f} ms/cycle "
                 f"({row['engine_steps_per_cycle']:.0f} steps), drift {row['engine_drift_per_cycle']:.1e} | {base}")
    return rows

