"""``bifurcation bench --suite rs-chain``: the engine against compiled baselines, side by side in one run.

Baselines (``_baseline.py``; the same equations in the same variables, ln V_j, ln θ_j, P; quasi-dynamic
with radiation damping, free ends; docs/rs-chain.md), each with the event definition as one scalar
function g = max_j ln V_j − ln v_th (an event starts at an upward root, ends at the next downward one):

- compiled (the ratio quoted): DOP853 in one ``numba.njit`` loop (scipy's coefficients, step control and
  dense output; g checked at each step's end, a sign change located on the dense output to the rounding
  of t), rtol = atol from 1e-8 to 1e-14;
- second column: ``scipy.integrate.solve_ivp(method="LSODA")`` with a ``numba.njit`` right-hand side,
  Jacobian and event functions (scipy's Python loop drives LSODA and its root finding), rtol = atol.

Both codes start from the same state and run to the end of the engine's K-th event. The baselines'
accuracy is read on the first ``FIRST`` events against the engine's catalog (which agrees with the
mpmath reference to ≤ 2.5e-14 where one exists, tests/test_rs_chain.py): later events of a chaotic chain
part ways for any two codes, so "agree" counts the leading events within 1e-6. The engine runs with its
velocity-maximum events (the default catalog) and without them (``maxima=False``: the baselines compute no
maxima). Times are the best of ``repeat`` runs, CPU seconds of this process, timed alternately; reported
as ratios (baseline time / engine time), never asserted; the load average is printed with them.

Equal accuracy: the engine also runs at looser heyoka tolerances (``ENGINE_TOLS``, ``run(tol=...)``), its
error read the same way against its exact catalog; the ratio "at equal accuracy" sets the compiled DOP853
at its most accurate against the engine at the loosest tolerance whose error is no larger (and whose
agreeing events are no fewer). On the mpmath reference both codes run (tests/data, N = 2, aging, free,
η = 1e-3) the two errors are independent of the engine: DOP853 at rtol 1e-14 4.4e-13, the engine at tol
1e-12 2.7e-13 (tests/test_rs_chain.py).

Grid: a study runs many chains; ``GRID_SEEDS`` of them per case (seeds 1, 2, …) are timed by the scalar
engine, by the batch engine (``batch.run_batch``: heyoka's batch integrator, ``LANES`` chains in the SIMD
lanes, each with the scalar engine's events and catalog assembly) and by the compiled DOP853 at its most
accurate tolerance of the case, alternately; the batch's error is read against the scalar catalogs.
"""

from __future__ import annotations

import math
import time

import numpy as np

__all__ = ["lsoda_catalog", "run_rs_chain_bench"]

#: rtol = atol of the compiled DOP853 and of scipy's LSODA (its 1e-8 is left out: seconds a run, and the
#: compiled baseline shows the loose end)
DOP853_RTOLS = (1e-8, 1e-10, 1e-12, 1e-13, 1e-14)
LSODA_RTOLS = (1e-10, 1e-12)

#: heyoka tolerances of the engine's looser runs (``run(tol=...)``); the exact default (double epsilon) is
#: the reference. Against the mpmath references of tests/data (N ≤ 4) the catalog's error is ≈ 0.4 × tol
#: (measured 3.7e-13 at 1e-12, 1.7e-11 at 1e-10; tests/test_rs_chain.py).
ENGINE_TOLS = (1e-13, 1e-12, 1e-10)

CASES = ((4, 1.0, 100), (16, 3.0, 60), (64, 3.0, 20))   # (N, ℓ, events)

#: A grid of this many chains per case (seeds 1, 2, …; the case's N, ℓ, K): the batch engine
#: (``batch.run_batch``, heyoka's SIMD lanes) against the scalar engine and the compiled DOP853 on the same runs.
GRID_SEEDS = 8
#: The baseline's accuracy is read on the first FIRST events: later ones part ways in a chaotic chain
#: (a 1e-12 difference grows event by event), for both codes alike.
FIRST = 10
_COMMON = dict(state_law="aging", a=0.01, b=0.015, dc=0.01, k=0.1, v_lp=1.0, eta=1e-3, v_th=10.0)


def lsoda_catalog(kernels, spec, state0, t_end: float, rtol: float, atol: float) -> dict:
    """scipy LSODA's events up to ``t_end`` (numba right-hand side, Jacobian and event function)."""
    from scipy.integrate import solve_ivp

    n, ln_th = spec.n, math.log(spec.v_th)
    args = (n, spec.a, spec.b, spec.dc, spec.k, spec.ell ** 2, spec.v_lp, spec.eta)
    gmax = kernels["gmax"]

    def up(t, u, *_):
        return gmax(u, n, ln_th)
    up.direction = 1

    def down(t, u, *_):
        return gmax(u, n, ln_th)
    down.direction = -1

    sol = solve_ivp(kernels["rhs"], (0.0, t_end), state0, method="LSODA", rtol=rtol, atol=atol,
                    events=(up, down), args=args, jac=kernels["jac"])
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


def _row(base: dict, ref, seconds: float, engine_s: float, events: int, rtol: float) -> dict:
    err, agree = _summary(_errors(base, ref))
    return {"rtol": rtol, "atol": rtol, "seconds": seconds, "events_found": int(len(base["t_start"])),
            f"max_rel_error_first_{FIRST}": err, "events_agreeing_to_1e-6": agree, "ratio": seconds / engine_s,
            "steps": base.get("steps")}


def _equal_accuracy(engine_rows: list, target: dict) -> dict | None:
    """The engine at its loosest tolerance whose error is no larger than ``target``'s (a baseline row)."""
    key = f"max_rel_error_first_{FIRST}"
    fits = [r for r in engine_rows if r[key] <= target[key] and r["events_agreeing_to_1e-6"] >= target[
        "events_agreeing_to_1e-6"]]
    return max(fits, key=lambda r: r["tol"]) if fits else None


def _engine_row(timed: list, ref, exact_s: float, tol: float) -> dict:
    t_max, t_none, mine = timed
    err, agree = _summary(_errors(mine.catalog(), ref))
    return {"tol": tol, "seconds": t_max, "no_maxima_s": t_none, f"max_rel_error_first_{FIRST}": err,
            "events_agreeing_to_1e-6": agree, "steps": mine.steps, "speedup": exact_s / t_max}


def _best_row(rows: list) -> dict:
    """The baseline at its most accurate (the loosest tolerance among equals)."""
    key = f"max_rel_error_first_{FIRST}"
    return min(rows, key=lambda r: (r[key], -r["events_agreeing_to_1e-6"], -r["rtol"]))


def _grid(spec, events: int, seeds: int, repeat: int, rtol: float, say, tol=None) -> dict:
    """The same ``seeds`` chains by the scalar engine, the batch engine (exact, and at ``tol`` if given: the
    tolerance of equal accuracy) and the compiled DOP853 (``rtol``)."""
    from ._baseline import dop853_catalog
    from .batch import LANES, run_batch
    from .simulate import initial_state, run

    starts = [initial_state(spec, 1.0, seed) for seed in range(1, seeds + 1)]
    run_batch([spec] * min(seeds, LANES), starts[:LANES], 2)      # compile outside the timing
    if tol is not None:
        run_batch([spec] * min(seeds, LANES), starts[:LANES], 2, tol=tol)
    refs = [run(spec, s0, events) for s0 in starts]
    ends = [r.t_end + 0.5 * (r.t_end - r.t_start[-1] if r.events > 1 else 1.0) for r in refs]
    t_scalar = t_batch = t_dop = t_loose = math.inf
    batch = dop = loose = None
    for _ in range(repeat):                     # alternately: a change of load hits all three
        t_scalar = min(t_scalar, _cpu(lambda: [run(spec, s0, events) for s0 in starts], 1)[0])
        t_b, batch = _cpu(lambda: run_batch([spec] * seeds, starts, events), 1)
        t_batch = min(t_batch, t_b)
        t_d, dop = _cpu(lambda: [dop853_catalog(spec, s0, t, events, rtol, rtol) for s0, t in zip(starts, ends)], 1)
        t_dop = min(t_dop, t_d)
        if tol is not None:
            t_l, loose = _cpu(lambda: run_batch([spec] * seeds, starts, events, tol=tol), 1)
            t_loose = min(t_loose, t_l)
    key = f"max_rel_error_first_{FIRST}"
    batch_err = max(_summary(_errors(b.catalog(), r))[0] for b, r in zip(batch, refs))
    dop_err = max(_summary(_errors(d, r))[0] for d, r in zip(dop, refs))
    row = {"seeds": seeds, "lanes": LANES, "scalar_s": t_scalar, "batch_s": t_batch, "dop853_s": t_dop,
           "dop853_rtol": rtol, "batch_steps_equal": all(b.steps == r.steps for b, r in zip(batch, refs)),
           f"batch_{key}": batch_err, f"dop853_{key}": dop_err,
           "batch_speedup": t_scalar / t_batch, "ratio": t_dop / t_batch, "tol": tol}
    if tol is not None:
        row[f"tol_{key}"] = max(_summary(_errors(b.catalog(), r))[0] for b, r in zip(loose, refs))
        row["tol_batch_s"] = t_loose
        row["tol_ratio"] = t_dop / t_loose
    say(f"    grid of {seeds} chains (seeds 1-{seeds}), {LANES} SIMD lanes: scalar engine {seeds * events / t_scalar:8.1f} "
        f"ev/s, batch engine {seeds * events / t_batch:8.1f} ev/s ({row['batch_speedup']:.2f}x the scalar; err from "
        f"the scalar {batch_err:.1e}, steps {'equal' if row['batch_steps_equal'] else 'differ'}), compiled DOP853 "
        f"rtol {rtol:g} {seeds * events / t_dop:8.1f} ev/s (err {dop_err:.1e}): it takes {row['ratio']:.2f}x the "
        f"batch engine's time")
    if tol is not None:
        say(f"      batch engine at tol {tol:g} (equal accuracy): {seeds * events / t_loose:8.1f} ev/s (err from the "
            f"exact scalar {row[f'tol_{key}']:.1e}): the compiled DOP853 takes {row['tol_ratio']:.2f}x its time")
    return row


def run_rs_chain_bench(repeat: int = 3, cases=CASES, rtols=DOP853_RTOLS, lsoda_rtols=LSODA_RTOLS,
                       engine_tols=ENGINE_TOLS, grid_seeds=GRID_SEEDS, echo=print, progress=None) -> dict:
    """Events per CPU second of the engine, the compiled DOP853 and scipy's LSODA, per (N, ℓ, K).
    ``progress(text)`` (the CLI: a line on stderr) is told which case and which stage runs."""
    import os
    import time

    from ._baseline import build, dop853_catalog
    from .simulate import RSChainSpec, initial_state, run

    say = echo or (lambda *_: None)
    started = time.perf_counter()

    def note(text: str) -> None:   # minutes pass between two result lines (over 120 s before the first)
        if progress is not None:
            progress(f"{text} [{time.perf_counter() - started:.0f} s]")
    # measured: build() 0.5 s and the first dop853_catalog 4.0 s of CPU (N = 4, 2026-11-26); cache=False closures
    note("compiling the numba baselines (compiled DOP853, LSODA's right-hand side and Jacobian; ~5 s of CPU, "
         "every run: they are not cached)")
    kernels = build()
    load = os.getloadavg()
    rows = []
    say("rs-chain bench: aging law, a = 0.01, b = 0.015, Dc = 0.01, k = 0.1, V_lp = 1, η = 1e-3, v_th = 10, "
        "free ends, A = 1, seed 1; CPU seconds, best of "
        f"{repeat}; load average {load[0]:.1f} {load[1]:.1f} {load[2]:.1f}")
    say("  engine: heyoka, every block's crossings (and velocity maxima) located on each Taylor step; "
        "compiled: DOP853 in one numba loop, events on max_j ln V_j located on its dense output (the ratio); "
        "LSODA: scipy solve_ivp with numba rhs, Jacobian and events (second column); rtol = atol; "
        "engine tol: heyoka's tolerance of a looser engine run (the exact default: double epsilon); "
        "grid: the same chains by the scalar engine, the batch engine (SIMD lanes) and the compiled DOP853; "
        f"err: largest relative difference from the engine's catalog over the first {FIRST} events; "
        "ratio = baseline time / engine time (> 1: the engine is faster)")
    for case, (n, ell, events) in enumerate(cases, 1):
        step = (lambda what, case=case, n=n, ell=ell: note(f"case {case} of {len(cases)} (N = {n}, ℓ = {ell:g}): {what}"))
        step(f"{events} events by the engine (exact, and at tol {', '.join(f'{t:g}' for t in engine_tols)}, with and "
             f"without maxima) and the compiled DOP853 at {len(rtols)} rtols, best of {repeat}")
        spec = RSChainSpec(n=n, ell=ell, **_COMMON)
        s0 = initial_state(spec, 1.0, 1)
        run(spec, s0, 2)                                      # compile outside the timing
        run(spec, s0, 2, maxima=False)
        for tol in engine_tols:
            run(spec, s0, 2, tol=tol)
            run(spec, s0, 2, tol=tol, maxima=False)
        ref = run(spec, s0, events)
        t_end = ref.t_end + 0.5 * (ref.t_end - ref.t_start[-1] if ref.events > 1 else 1.0)
        dop853_catalog(spec, s0, t_end, events, 1e-6, 1e-6)   # numba compile
        kernels["rhs"](0.0, s0, n, spec.a, spec.b, spec.dc, spec.k, ell * ell, spec.v_lp, spec.eta)
        kernels["jac"](0.0, s0, n, spec.a, spec.b, spec.dc, spec.k, ell * ell, spec.v_lp, spec.eta)
        # alternate the engine's and the baseline's repeats: a change of load hits both
        t_ours = t_nomax = math.inf
        dop = {rtol: (math.inf, None) for rtol in rtols}
        loose = {tol: [math.inf, math.inf, None] for tol in engine_tols}   # with maxima, without, catalog
        for _ in range(repeat):
            t_ours = min(t_ours, _cpu(lambda: run(spec, s0, events), 1)[0])
            t_nomax = min(t_nomax, _cpu(lambda: run(spec, s0, events, maxima=False), 1)[0])
            for tol in engine_tols:
                t_e, mine = _cpu(lambda tol=tol: run(spec, s0, events, tol=tol), 1)
                t_n = _cpu(lambda tol=tol: run(spec, s0, events, tol=tol, maxima=False), 1)[0]
                loose[tol] = [min(loose[tol][0], t_e), min(loose[tol][1], t_n), mine]
            for rtol in rtols:
                t_b, base = _cpu(lambda rtol=rtol: dop853_catalog(spec, s0, t_end, events, rtol, rtol), 1)
                if t_b < dop[rtol][0]:
                    dop[rtol] = (t_b, base)
        row = {"n": n, "ell": ell, "events": events, "engine_s": t_ours, "engine_events_per_s": events / t_ours,
               "engine_steps": ref.steps, "engine_no_maxima_s": t_nomax,
               "engine_balance_max": float(np.max(ref.balance)),
               "dop853": [_row(dop[r][1], ref, dop[r][0], t_ours, events, r) for r in rtols], "lsoda": [],
               "engine_tol": [_engine_row(loose[tol], ref, t_ours, tol) for tol in engine_tols]}
        step(f"scipy LSODA at rtol {', '.join(f'{r:g}' for r in lsoda_rtols)}, best of {repeat}")
        for rtol in lsoda_rtols:
            t_base, base = _cpu(lambda rtol=rtol: lsoda_catalog(kernels, spec, s0, t_end, rtol, rtol), repeat)
            row["lsoda"].append(_row(base, ref, t_base, t_ours, events, rtol))
        best = _best_row(row["dop853"])
        row["dop853_best"] = best
        exact = {"tol": 0.0, "seconds": t_ours, "no_maxima_s": t_nomax, f"max_rel_error_first_{FIRST}": 0.0,
                 "events_agreeing_to_1e-6": events}
        match = _equal_accuracy([exact, *row["engine_tol"]], best)
        row["equal_accuracy"] = None if match is None else {
            "engine_tol": match["tol"] or None, "dop853_rtol": best["rtol"],
            "ratio": best["seconds"] / match["seconds"], "ratio_no_maxima": best["seconds"] / match["no_maxima_s"]}
        rows.append(row)
        say(f"N = {n:4d} ℓ = {ell:g}, {events} events: engine {events / t_ours:8.1f} ev/s ({ref.steps} steps), "
            f"without maxima {events / t_nomax:8.1f} ev/s")
        for r in row["engine_tol"]:
            say(f"    engine tol {r['tol']:g}: {events / r['seconds']:8.1f} ev/s, without maxima "
                f"{events / r['no_maxima_s']:8.1f} ev/s ({r['steps']} steps), err "
                f"{r[f'max_rel_error_first_{FIRST}']:.1e}, {r['events_agreeing_to_1e-6']} agree")
        for r in row["dop853"]:
            say(f"    compiled DOP853 rtol {r['rtol']:g}: {events / r['seconds']:8.1f} ev/s ({r['steps']} steps), "
                f"err {r[f'max_rel_error_first_{FIRST}']:.1e}, {r['events_agreeing_to_1e-6']} agree, "
                f"{r['events_found']} found: {r['ratio']:.2f}x the engine's time, "
                f"{r['seconds'] / t_nomax:.2f}x without maxima")
        for r in row["lsoda"]:
            say(f"    scipy LSODA (numba rhs, jac) rtol {r['rtol']:g}: {events / r['seconds']:7.1f} ev/s, "
                f"err {r[f'max_rel_error_first_{FIRST}']:.1e}, {r['events_agreeing_to_1e-6']} agree: "
                f"{r['ratio']:.1f}x")
        say(f"    at its most accurate (rtol {best['rtol']:g}, err {best[f'max_rel_error_first_{FIRST}']:.1e}) the "
            f"compiled DOP853 takes {best['ratio']:.2f}x the engine's time")
        eq = row["equal_accuracy"]
        if eq is None:
            say("    no engine tolerance measured is as accurate as the baseline at its best")
        else:
            say(f"    at equal accuracy (engine tol {eq['engine_tol'] or 'exact'}, err no larger than the "
                f"baseline's): the compiled DOP853 takes {eq['ratio']:.2f}x the engine's time, "
                f"{eq['ratio_no_maxima']:.2f}x without maxima")
        if grid_seeds:
            step(f"a grid of {grid_seeds} chains by the scalar engine, the batch engine and the compiled DOP853, "
                 f"best of {repeat}")
        row["grid"] = _grid(spec, events, grid_seeds, repeat, best["rtol"], say,
                            tol=(eq or {}).get("engine_tol")) if grid_seeds else None
    return {"suite": "rs-chain", "repeat": repeat, "load_average": list(load), "cases": rows,
            "baselines": {"dop853": "compiled: scipy's DOP853 transcribed to one numba.njit loop, events located "
                                    "on its dense output (bifurcation/models/rs_chain/_baseline.py)",
                          "lsoda": "scipy.integrate.solve_ivp(method='LSODA') with numba rhs, Jacobian and "
                                   "event functions"},
            "reference": "the engine's own catalog (it agrees with the mpmath reference to <= 2.5e-14 where one "
                         "exists)"}


if __name__ == "__main__":   # python -m bifurcation.models.rs_chain._bench
    run_rs_chain_bench()
