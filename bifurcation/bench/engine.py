"""``bifurcation bench``: the engine against its baselines, side by side in one run, as ratios.

Baselines, on the same scaled equations and the same events (stop at U̇ = 0, switches of the
piecewise-linear law at U̇ = ν_f):
- scipy ``solve_ivp`` DOP853 at rtol = atol = 1e-13, with a Python right-hand side;
- naive heyoka: a new integrator compiled for every point.
Each method's error is measured against independent references: the exact piecewise mpmath solution
(``bifurcation.theory.reference``) for the piecewise-linear law, heyoka real128 runs for Carlson–Langer.
Timings are wall-clock on one core after a warm-up; they are reported, never asserted.
"""

from __future__ import annotations

import math
import platform
import time

import numpy as np

__all__ = ["run_bench"]

_NUS = np.array([1e-3, 1e-6, 1e-9, 1e-12, 1e-15])


def _grid(points: int):
    nus = 10.0 ** -np.arange(3, 16)
    n_f = max(points // nus.size, 1)
    nu_f = np.linspace(0.02, 0.98, n_f)
    return nus[:, None], nu_f[None, :]


def _subset(n: int):
    nu_f = np.array([0.1, 0.3, 0.45, 0.5, 0.6, 0.9])
    pts = [(nu, nf) for nu in _NUS for nf in nu_f]
    idx = np.linspace(0, len(pts) - 1, min(n, len(pts))).round().astype(int)
    return [pts[i] for i in sorted(set(idx))]


# -- DOP853 on the same scaled equations ---------------------------------------------------------
def _drops(law: str):
    if law == "piecewise-linear":
        return [lambda x: x, lambda x: 1.0], [1.0]
    if law == "carlson-langer":
        return [lambda x: x / (1.0 + x)], []
    raise ValueError(law)


def dop853_cycle(law: str, nu: float, nu_f: float, rtol: float = 1e-13) -> float:
    """Δ by scipy's DOP853 on Ẅ = t − W + g(νẆ/ν_f)/ν, pieces switched at terminal events."""
    from scipy.integrate import solve_ivp

    drops, breaks = _drops(law)
    piece, t0, y0 = 0, 0.0, np.zeros(2)
    for _ in range(8):
        g = drops[piece]

        def rhs(t, y, g=g):
            return (y[1], t - y[0] + g(nu * y[1] / nu_f) / nu)

        def stop(t, y):
            return nu * y[1] / nu_f if t > t0 else 1.0

        stop.terminal, stop.direction = True, -1
        events = [stop]
        for b in breaks:
            def switch(t, y, b=b):
                return nu * y[1] / nu_f / b - 1.0

            switch.terminal, switch.direction = True, (1 if piece == 0 else -1)
            events.append(switch)
        sol = solve_ivp(rhs, (t0, 1e4), y0, method="DOP853", rtol=rtol, atol=rtol, events=events)
        if sol.t_events[0].size:
            return nu * sol.y_events[0][0][0]
        t0, y0 = sol.t_events[1][0], sol.y_events[1][0]
        piece = 1 - piece
    return math.nan


def _naive_heyoka(law: str, nu: float, nu_f: float) -> float:
    from ..engine._integrator import build
    from ..engine.cycle import run_cycle
    from ..laws import resolve_law

    c = build(resolve_law(law))
    return nu * float(run_cycle(c, {"nu": nu, "nu_f": nu_f, "forcing": 1.0})["W"])


def _reference(law: str, nu: float, nu_f: float) -> float:
    if law == "piecewise-linear":
        from ..theory.reference import piecewise_linear_exact

        return float(piecewise_linear_exact(nu, nu_f, dps=30)["delta"])
    from ..engine import slip

    return float(slip(law, nu=nu, nu_f=nu_f, precision="quad").delta)


def _timed(fn, *args):
    t = time.perf_counter()
    value = fn(*args)
    return value, time.perf_counter() - t


def _engine_grid(law: str, points: int, batch: int = 1) -> dict:
    from ..engine import slip

    nu, nu_f = _grid(points)
    slip(law, nu=[1e-9] * batch, nu_f=0.3, batch=batch)  # warm-up: compile once, as a worker does
    r, dt = _timed(lambda: slip(law, nu=nu, nu_f=nu_f, batch=batch))
    n = r.delta.size
    return {"points": n, "batch": batch, "us_per_point": 1e6 * dt / n,
            "mean_steps": float(r.steps.mean())}


def _compare(law: str, subset: int) -> dict:
    from ..engine import slip

    pts = _subset(subset)
    out = {}
    refs = [_reference(law, nu, nf) for nu, nf in pts]
    nus, nu_fs = (np.array(v) for v in zip(*pts))
    slip(law, nu=1e-9, nu_f=0.3)
    # The engine as users run it: one call over the points (per-point cost, no per-call overhead).
    r, dt = _timed(lambda: slip(law, nu=nus, nu_f=nu_fs))
    errs = np.abs(r.delta - refs) / np.abs(refs)
    out["engine"] = {"us_per_point": 1e6 * dt / len(pts), "max_rel_error": float(errs.max()),
                     "median_rel_error": float(np.median(errs))}
    methods = {
        "naive_heyoka": lambda nu, nf: _naive_heyoka(law, nu, nf),
        "dop853": lambda nu, nf: dop853_cycle(law, nu, nf),
        # scipy refuses rtol < 100 eps; this is DOP853 as close to our error as it can get.
        "dop853_tightest": lambda nu, nf: dop853_cycle(law, nu, nf, rtol=2.3e-14),
    }
    for name, fn in methods.items():
        total, errs = 0.0, []
        for (nu, nf), ref in zip(pts, refs):
            value, dt = _timed(fn, nu, nf)
            total += dt
            errs.append(abs(value - ref) / abs(ref))
        out[name] = {"us_per_point": 1e6 * total / len(pts), "max_rel_error": float(np.nanmax(errs)),
                     "median_rel_error": float(np.nanmedian(errs))}
    for name in methods:
        out[name]["time_ratio_vs_engine"] = out[name]["us_per_point"] / out["engine"]["us_per_point"]
    out["points"] = len(pts)
    return out


def run_bench(points: int = 2000, subset: int = 12, pipeline_points: int = 0, echo=print) -> dict:
    """Run the benchmarks; return a JSON-able report (and print a table through ``echo``)."""
    import heyoka

    say = echo or (lambda *_: None)
    report = {"machine": {"python": platform.python_version(), "heyoka": heyoka.__version__,
                          "processor": platform.machine()}, "laws": {}}
    for law in ("carlson-langer", "piecewise-linear"):
        say(f"\n== {law}")
        grid = _engine_grid(law, points)
        batched = _engine_grid(law, points, batch=8)
        say(f"engine grid: {grid['points']} points (ν 1e-3…1e-15 × ν_f 0.02…0.98), one core: "
            f"{grid['us_per_point']:.1f} µs/trajectory scalar, {batched['us_per_point']:.1f} batch of 8 "
            f"(SIMD; scalar/batch = {grid['us_per_point'] / batched['us_per_point']:.2f}), "
            f"{grid['mean_steps']:.1f} steps on average")
        best = min(grid["us_per_point"], batched["us_per_point"])
        cmp_ = _compare(law, subset)
        for name in ("naive_heyoka", "dop853", "dop853_tightest"):
            cmp_[name]["time_ratio_vs_engine_grid"] = cmp_[name]["us_per_point"] / best
        say(f"subset of {cmp_['points']} points (ν 1e-3…1e-15, ν_f 0.1…0.9) vs references "
            f"(× grid: against the engine's best per-trajectory cost on the grid, {best:.1f} µs):")
        say(f"  {'method':16s} {'µs/point':>10s} {'× engine':>9s} {'× grid':>8s} {'max rel err':>12s} "
            f"{'median':>9s}")
        for name in ("engine", "naive_heyoka", "dop853", "dop853_tightest"):
            m = cmp_[name]
            ratio = m.get("time_ratio_vs_engine", 1.0)
            grid_ratio = m.get("time_ratio_vs_engine_grid", float("nan"))
            say(f"  {name:16s} {m['us_per_point']:10.1f} {ratio:9.1f} {grid_ratio:8.1f} "
                f"{m['max_rel_error']:12.2e} {m['median_rel_error']:9.2e}")
        report["laws"][law] = {"grid": grid, "grid_batch8": batched, "subset": cmp_}
    if pipeline_points:
        from .pipeline import bench_pipeline

        say(f"\n== pipeline: {pipeline_points} points, 2 workers, store writes included")
        # Above 1e5 points the one-core engine run would take minutes: time the pipeline alone there.
        pipe = bench_pipeline(points=pipeline_points, workers=2, serial=pipeline_points <= 200_000)
        report["pipeline"] = pipe
        for key, value in pipe.items():
            if isinstance(value, (int, float, str)):
                say(f"  {key:28s} {value:.4g}" if isinstance(value, float) else f"  {key:28s} {value}")
    return report
