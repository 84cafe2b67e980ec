"""``bifurcation bench --suite chain``: the event-exact chain against a fixed-step RK4 chain code.

The baseline is the kind of code the public Burridge–Knopoff studies use: the whole chain as one
vectorised numpy state, classical RK4 at a fixed step dt, a stuck block held by
V̇ = max(σ − 1, 0), negative velocities clipped to 0 after every step, events found from the
clipped velocities. It is given every advantage the exact engine has that costs nothing: the same
initial state and quiescent phases jumped exactly (t + (1 − max σ)/ν). Its step is chosen as the
largest dt whose event-size distribution (n_blocks) is within the two-sample KS distance ``ks`` of
the exact catalog's, or within the sampling noise of a KS distance between two samples of n events
(1.36·sqrt(2/n), 95 %) when the run is too short to resolve ``ks``. The potency distribution is
compared too, as magnitudes log10 P rounded to 0.01: raw potencies are atoms (every isolated 1-block
event slips the same amount), and an atom moved by RK4's error (2e-3 relative at dt = 0.05) makes the
raw KS distance the atom's whole weight. Timings are wall-clock on one core, reported, never
asserted.
"""

from __future__ import annotations

import math
import time

import numpy as np

__all__ = ["ks_distance", "rk4_chain", "run_chain_bench"]


def _phi(law: str):
    if law == "carlson-langer":
        return lambda x: 1.0 / (1.0 + x)
    if law == "piecewise-linear":
        return lambda x: np.where(x < 1.0, 1.0 - x, 0.0)
    if law == "exponential":
        return lambda x: np.exp(-x)
    raise ValueError(f"the RK4 baseline has no numpy Φ for {law!r}")


def rk4_chain(law: str, *, n: int, ell: float, nu: float, nu_f: float, u0, events: int, dt: float,
              ends: str = "free", max_steps: int = 10_000_000) -> dict:
    """Fixed-step RK4 catalog (potency, n_blocks, duration, max_velocity) of the first ``events`` events."""
    phi = _phi(law)
    l2 = ell * ell
    u = np.array(u0, dtype=float)
    v = np.zeros(n)
    t = 0.0
    if ends == "periodic":
        def lap(a):
            return np.roll(a, 1) - 2 * a + np.roll(a, -1)
    else:
        def lap(a):
            out = np.empty_like(a)
            out[1:-1] = a[2:] - 2 * a[1:-1] + a[:-2]
            if n > 1:
                out[0], out[-1] = a[1] - a[0], a[-2] - a[-1]
            else:
                out[0] = 0.0
            return out

    def acc(uu, vv, tt):
        sigma = l2 * lap(uu) - uu + nu * tt
        return np.where(vv > 0, sigma - phi(np.maximum(vv, 0) / nu_f), np.maximum(sigma - 1, 0))

    cat = {k: [] for k in ("potency", "n_blocks", "duration", "max_velocity")}
    steps = 0
    for _ in range(events):
        sigma = l2 * lap(u) - u + nu * t
        t += (1 - sigma.max()) / nu
        u_start, t_start = u.copy(), t
        moved = np.zeros(n, dtype=bool)
        vmax = 0.0
        while True:
            k1u, k1v = v, acc(u, v, t)
            k2u, k2v = v + dt / 2 * k1v, acc(u + dt / 2 * k1u, v + dt / 2 * k1v, t + dt / 2)
            k3u, k3v = v + dt / 2 * k2v, acc(u + dt / 2 * k2u, v + dt / 2 * k2v, t + dt / 2)
            k4u, k4v = v + dt * k3v, acc(u + dt * k3u, v + dt * k3v, t + dt)
            u = u + dt / 6 * (k1u + 2 * k2u + 2 * k3u + k4u)
            v = np.maximum(v + dt / 6 * (k1v + 2 * k2v + 2 * k3v + k4v), 0.0)   # no back-slip, by hand
            t += dt
            steps += 1
            live = v > 0
            moved |= live
            vmax = max(vmax, v.max())
            if not live.any() or steps > max_steps:
                break
        cat["potency"].append(float(np.sum(u - u_start)))
        cat["n_blocks"].append(int(moved.sum()))
        cat["duration"].append(t - t_start)
        cat["max_velocity"].append(vmax)
    out = {k: np.array(v_) for k, v_ in cat.items()}
    out["steps"] = steps
    return out


def ks_distance(a, b) -> float:
    """Two-sample Kolmogorov–Smirnov distance sup |F_a − F_b| (numpy only)."""
    a, b = np.sort(np.asarray(a)), np.sort(np.asarray(b))
    grid = np.concatenate((a, b))
    fa = np.searchsorted(a, grid, side="right") / a.size
    fb = np.searchsorted(b, grid, side="right") / b.size
    return float(np.max(np.abs(fa - fb)))


def run_chain_bench(*, law: str = "carlson-langer", ell: float = 1.0, nu: float = 1e-3, nu_f: float = 0.2,
                    sizes=(64, 256, 1024), events=(600, 200, 60), dts=(0.2, 0.1, 0.05),
                    ks: float = 0.01, amplitude: float = 0.1, seed: int = 1, echo=print) -> dict:
    """Events per second of the exact engine and of RK4 at the step that matches its event sizes."""
    from ...laws import resolve_law
    from ._loop import ChainLoop
    from ._validate import check_initial

    say = echo or (lambda *_: None)
    law_obj = resolve_law(law)
    rows = []
    say(f"chain bench: {law}, ℓ = {ell}, ν = {nu}, ν_f = {nu_f}, free ends, random start A = {amplitude}, "
        f"seed {seed}; RK4 steps {list(dts)}; KS target {ks}")
    for n, k in zip(sizes, events):
        u0 = check_initial(n, ell, "free", None, amplitude, seed)
        warm = ChainLoop(law_obj, n, ell, nu, nu_f, "free", u0)
        warm.run(min(k, 50))      # compile the window sizes this run needs, outside the timing
        loop = ChainLoop(law_obj, n, ell, nu, nu_f, "free", u0)
        t0 = time.perf_counter()
        cat = loop.run(k)["catalog"]
        exact_s = time.perf_counter() - t0
        potency = np.array([float(x) for x in cat["potency"]])
        sizes_ = np.array(cat["n_blocks"])
        wall = np.array(loop.wall)
        row = {"n": n, "events": k, "exact_s": exact_s, "exact_events_per_s": k / exact_s,
               "mean_n_blocks": float(sizes_.mean()), "noise_ks": 1.36 * math.sqrt(2 / k), "rk4": []}
        chosen = None
        for dt in dts:
            t0 = time.perf_counter()
            base = rk4_chain(law, n=n, ell=ell, nu=nu, nu_f=nu_f, u0=u0, events=k, dt=dt)
            s = time.perf_counter() - t0
            d = ks_distance(sizes_, base["n_blocks"])
            dm = ks_distance(np.round(np.log10(potency), 2), np.round(np.log10(np.maximum(base["potency"], 1e-300)), 2))
            row["rk4"].append({"dt": dt, "seconds": s, "events_per_s": k / s, "ks": d, "ks_magnitude": dm})
            say(f"  N = {n:5d}: RK4 dt = {dt:<5g} {k / s:9.1f} events/s, KS(n_blocks) = {d:.3f}, "
                f"KS(magnitude, 0.01) = {dm:.3f}")
            if chosen is None and d <= max(ks, row["noise_ks"]):
                chosen = row["rk4"][-1]
        row["matched"] = chosen
        row["ratio"] = row["exact_events_per_s"] / chosen["events_per_s"] if chosen else math.nan
        # cost against event size: mean wall time per event, by n_blocks
        bins = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048]
        row["cost_by_size"] = [{"n_blocks": f"{lo}-{hi - 1}", "events": int(np.sum((sizes_ >= lo) & (sizes_ < hi))),
                                "ms_per_event": float(1e3 * wall[(sizes_ >= lo) & (sizes_ < hi)].mean())}
                               for lo, hi in zip(bins, bins[1:]) if np.any((sizes_ >= lo) & (sizes_ < hi))]
        say(f"  N = {n:5d}: exact {row['exact_events_per_s']:9.1f} events/s (mean size "
            f"{row['mean_n_blocks']:.1f}); KS noise at {k} events {row['noise_ks']:.3f}; "
            + (f"matched RK4 dt = {chosen['dt']:g}: ratio {row['ratio']:.1f}x" if chosen else "no RK4 step matched"))
        say("           cost by size: " + ", ".join(f"{c['n_blocks']}: {c['ms_per_event']:.2f} ms ({c['events']})"
                                               for c in row["cost_by_size"]))
        rows.append(row)
    return {"suite": "chain", "law": law, "ell": ell, "nu": nu, "nu_f": nu_f, "rows": rows}
