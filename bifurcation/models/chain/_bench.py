"""``bifurcation bench --suite chain``: the event-exact chain against a fixed-step RK4 chain code.

The baseline is the kind of code the public Burridge–Knopoff studies use: the whole chain as one
vectorised numpy state, classical RK4 at a fixed step dt, a stuck block held by
V̇ = max(σ − 1, 0), negative velocities clipped to 0 after every step, events found from the
clipped velocities. It is given every advantage the exact engine has that costs nothing: the same
initial state and quiescent phases jumped exactly (t + (1 − max σ)/ν). Equal accuracy is the
largest dt whose event-size distribution is within the two-sample KS distance 0.01 of the exact
catalog's; a KS distance that small needs ~40 000 events per catalog (95 % sampling noise
1.36·sqrt(2/n)), so ``run_ks_study`` resolves the step and the suite (short catalogs, KS shown with
its noise) measures the rates at several dt. The event magnitude distribution is compared too, as magnitudes log10 P rounded to 0.01: raw potencies are atoms (every isolated 1-block
event slips the same amount), and an atom moved by RK4's error (2e-3 relative at dt = 0.05) makes the
raw KS distance the atom's whole weight. Timings are CPU seconds of this single-threaded process
(wall-clock shown too: on a shared machine it measures the other jobs), reported, never asserted.
``python -m bifurcation.models.chain._bench suite|ks|long|atom|tolerance|stop|shares`` runs the suite, the longer KS study,
the tolerance grid, stop-phase model and steps by event size (docs/chain.md, "Speed") and the 10^5-event timing of results/chain/REPORT.md ("Speed").
"""

from __future__ import annotations

import math
import time

import numpy as np

__all__ = ["ks_distance", "rk4_chain", "run_chain_bench", "run_ks_study", "run_lone_block_check", "run_long"]


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


def _timed(fn):
    """(result, wall seconds, CPU seconds of this process): on a shared machine the CPU time is the
    figure that other jobs do not inflate; both codes are single-threaded."""
    w0, c0 = time.perf_counter(), time.process_time()
    out = fn()
    return out, time.perf_counter() - w0, time.process_time() - c0


def _cost_by_size(sizes, wall) -> list:
    bins = [1, 2, 4, 8, 16, 32, 64, 128, 256, 512, 1024, 2048]
    return [{"n_blocks": f"{lo}-{hi - 1}", "events": int(np.sum((sizes >= lo) & (sizes < hi))),
             "ms_per_event": float(1e3 * wall[(sizes >= lo) & (sizes < hi)].mean())}
            for lo, hi in zip(bins, bins[1:]) if np.any((sizes >= lo) & (sizes < hi))]


def _exact(law_obj, n, ell, nu, nu_f, u0, k, compact_above):
    from ._integrator import window_integrator
    from ._loop import ChainLoop

    def warm_up():
        # every window size the run can meet (powers of two up to N, and N), compiled before the
        # timing: a size first met inside it (a rare wide event) put up to 20 s of compile into it
        sizes = {1 << i for i in range(n.bit_length()) if 1 << i <= n} | {n}
        for m in sorted(sizes):
            window_integrator(law_obj, m, "double", False, compact_above)
        ChainLoop(law_obj, n, ell, nu, nu_f, "free", u0, compact_above=compact_above).run(min(k, 50))

    _, compile_s, _ = _timed(warm_up)
    loop = ChainLoop(law_obj, n, ell, nu, nu_f, "free", u0, compact_above=compact_above)
    out, wall_s, cpu_s = _timed(lambda: loop.run(k))
    return loop, out["catalog"], wall_s, cpu_s, compile_s


def _steady_start(law_obj, n, ell, nu, nu_f, u0, events, compact_above) -> np.ndarray:
    """The displacements after ``events`` exact events from ``u0``, as a start at t = 0.

    σ_j = ℓ²(ΔU)_j − U_j + νt depends on U and t only through U − νt, so U − νt at t = 0 is the same
    state (every block stuck between two events); both codes start from it."""
    from ._loop import ChainLoop
    from ._validate import check_initial

    if events <= 0:
        return u0
    loop = ChainLoop(law_obj, n, ell, nu, nu_f, "free", u0, compact_above=compact_above)
    out = loop.run(events)
    if out["status"] != 1:
        raise RuntimeError(f"the transient of {events} events stopped: {out['message']}")
    return check_initial(n, ell, "free", np.asarray(loop.u, dtype=float) - float(nu * loop.t), None, None)


def _magnitudes(p):
    return np.round(np.log10(np.maximum(np.asarray(p, dtype=float), 1e-300)), 2)


#: (ν, N, timed events, transient events) of the default suite: ν = 1e-4, the regime of the study
#: (events of a few blocks, the chain all stuck between them) and of issue 18's targets.
CASES = ((1e-4, 64, 2000, 1000), (1e-4, 256, 2000, 1000), (1e-4, 1024, 1000, 2000), (1e-4, 4096, 300, 4000))
#: the exact (heyoka) engine is timed up to this N (its warm-up compiles every window size up to N)
EXACT_UP_TO = 1024


def _steady_start_compiled(law_obj, n, ell, nu, nu_f, u0, events) -> np.ndarray:
    """As ``_steady_start``, the transient run by the compiled engine (``--verify`` checks it)."""
    from ._compiled import CompiledChain
    from ._validate import check_initial

    if events <= 0:
        return u0
    run = CompiledChain(law_obj, n, ell, nu, nu_f, "free", u0)
    out = run.run(events)
    if out["status"] != 1:
        raise RuntimeError(f"the transient of {events} events stopped: {out['message']}")
    return check_initial(n, ell, "free", np.asarray(run.u, dtype=float) - nu * run.t, None, None)


def run_chain_bench(*, law: str = "carlson-langer", ell: float = 1.0, nu_f: float = 0.2, cases=CASES,
                    dts=(0.2, 0.1), amplitude: float = 0.1, seed: int = 1, compact_above: int = 32,
                    verify: float = 0.01, echo=print, progress=None) -> dict:
    """Events per CPU second, side by side in one process, from the same steady start, of: the compiled
    engine (``_compiled``, tolerance 1e-12, its ``verify`` sample re-run by the exact engine, untimed),
    the exact heyoka engine (N ≤ ``EXACT_UP_TO``), numba RK4 with an active set and of the whole
    chain at each dt (``_bench_rk4``, the baselines of issue 18), and the interpreted numpy RK4
    (``rk4_chain``, a second column). Ratios are compiled engine / baseline on CPU time.

    The start: the random start of amplitude ``amplitude`` run through the case's transient by the
    compiled engine, so the timed events are the chain's steady state. Every numba function is
    compiled before the timings (a tiny run of each). KS distances of catalogs this short are within
    their sampling noise (shown): equal statistics are resolved by ``run_ks_study``. ``progress(text)``
    (the CLI: a line on stderr) is told which case and which code runs, and when numba compiles.
    """
    from ...laws import resolve_law
    from ._bench_rk4 import run_rk4
    from ._compiled import CompiledChain, run_verified
    from ._validate import check_initial
    from .simulate import compile_notice, compile_when

    say = echo or (lambda *_: None)
    started = time.perf_counter()

    def note(text: str) -> None:   # minutes pass between two result lines (the first case alone > 120 s)
        if progress is not None:
            progress(f"{text} [{time.perf_counter() - started:.0f} s]")
    law_obj = resolve_law(law)
    rows = []
    say(f"chain bench: {law}, ℓ = {ell}, ν_f = {nu_f}, free ends, random start A = {amplitude}, seed {seed}, "
        f"run through a transient by the compiled engine; RK4 steps {list(dts)}; rates per CPU second of this "
        f"process (wall in brackets); ratio = compiled engine / baseline")
    tiny = check_initial(8, ell, "free", None, amplitude, seed)          # compile every numba path first
    first = CompiledChain(law_obj, 8, ell, 1e-3, nu_f, "free", tiny)
    note(compile_notice(law) + ", then the numba RK4 baselines" if not first.compiled() else
         "the compiled engine and the numba RK4 baselines: loading them from numba's disk cache")
    first.run(3)
    for kind in ("active", "plain"):
        run_rk4(kind, law, n=8, ell=ell, nu=1e-3, nu_f=nu_f, u0=tiny, events=3, dt=0.1)
    for case, (nu, n, k, skip) in enumerate(cases, 1):
        step = (lambda what, case=case, nu=nu, n=n: note(f"case {case} of {len(cases)} (ν = {nu:g}, N = {n}): {what}"))
        step(f"{skip} transient events, then {k} timed events of the compiled engine")
        u0 = _steady_start_compiled(law_obj, n, ell, nu, nu_f, check_initial(n, ell, "free", None, amplitude, seed),
                                    skip)
        run = CompiledChain(law_obj, n, ell, nu, nu_f, "free", u0)
        out, wall_s, cpu_s = _timed(lambda: run.run(k))
        cat = out["catalog"]
        rate = k / cpu_s
        row = {"nu": nu, "n": n, "events": k, "transient": skip, "compiled_events_per_s": rate,
               "compiled_events_per_wall_s": k / wall_s, "mean_n_blocks": float(cat["n_blocks"].mean()),
               "steps_per_event": float(cat["steps"].mean()), "noise_ks": 1.36 * math.sqrt(2 / k),
               "numba": [], "rk4": []}
        sizes_, mags = cat["n_blocks"], _magnitudes(cat["potency"])
        if CompiledChain(law_obj, 1, ell, nu, nu_f, "free", np.zeros(1)).taylor:
            # the same engine with DOP853 steps (its integrator before the Taylor method), side by side
            dop = CompiledChain(law_obj, n, ell, nu, nu_f, "free", u0, taylor=False)
            step("the same engine with DOP853 steps" + ("" if dop.compiled() else
                                                         f" (numba compiles this variant first: {compile_when()})"))
            dout, _, dcpu = _timed(lambda: dop.run(k))
            row["dop853_events_per_s"] = k / dcpu
            row["dop853_steps_per_event"] = float(dout["catalog"]["steps"].mean())
        if verify:
            step(f"verify: {verify:g} of the events re-run by the exact (heyoka) engine")
            _, rep = run_verified(CompiledChain(law_obj, n, ell, nu, nu_f, "free", u0), k, verify)
            row["verify"] = rep
        if n <= EXACT_UP_TO:
            step(f"the exact (heyoka) engine, {k} events (it first compiles an integrator per window size up to N)")
            _, ecat, ewall, ecpu, compile_s = _exact(law_obj, n, ell, nu, nu_f, u0, k, compact_above)
            row["exact_events_per_s"] = k / ecpu
            row["exact_compile_s"] = compile_s
        step(f"numba RK4 (active set and whole chain) at dt = {', '.join(map(str, dts))}, {k} events each")
        for kind in ("active", "plain"):
            for dt in dts:
                base, s, c = _timed(lambda: run_rk4(kind, law, n=n, ell=ell, nu=nu, nu_f=nu_f, u0=u0, events=k, dt=dt))
                row["numba"].append({"kind": kind, "dt": dt, "events_per_s": k / c, "events_per_wall_s": k / s,
                                     "ks": ks_distance(sizes_, base["n_blocks"]),
                                     "ks_magnitude": ks_distance(mags, _magnitudes(base["potency"])),
                                     "ratio": rate / (k / c)})
        step(f"interpreted numpy RK4 at dt = {', '.join(map(str, dts))}, {min(k, 300)} events each")
        for dt in dts:
            kk = min(k, 300)
            base, s, c = _timed(lambda: rk4_chain(law, n=n, ell=ell, nu=nu, nu_f=nu_f, u0=u0, events=kk, dt=dt))
            row["rk4"].append({"dt": dt, "events": kk, "events_per_s": kk / c, "ratio": rate / (kk / c),
                               "ks": ks_distance(sizes_[:kk], base["n_blocks"]),
                               "ks_magnitude": ks_distance(mags[:kk], _magnitudes(base["potency"]))})
        exact = (f"exact {row['exact_events_per_s']:.0f}/s (compiled/exact {rate / row['exact_events_per_s']:.2f}x)"
                 if "exact_events_per_s" in row else "exact not timed (N > 1024)")
        say(f"  ν = {nu:g}, N = {n:5d}: compiled {rate:9.0f} events/s ({k / wall_s:.0f}), {row['steps_per_event']:.0f} "
            f"steps/event, mean size {row['mean_n_blocks']:.2f}; {exact}")
        if "dop853_events_per_s" in row:
            d = row["dop853_events_per_s"]
            rk = next(r["events_per_s"] for r in row["numba"] if r["kind"] == "active" and r["dt"] == dts[-1])
            say(f"           the same engine with DOP853 steps (taylor=False): {d:9.0f} events/s, "
                f"{row['dop853_steps_per_event']:.0f} steps/event; Taylor/DOP853 = {rate / d:.2f}x; DOP853/numba RK4 "
                f"active dt = {dts[-1]:g}: {d / rk:.3f}x")
        if "verify" in row:
            v = row["verify"]
            say(f"           verify: {v['checked']} events re-run exactly, largest relative difference "
                f"{v['largest_any']:.1e}, hypocentre/size differ in {len(v['mismatched'])}")
        for r in row["numba"]:
            say(f"           numba RK4 {r['kind']:6s} dt = {r['dt']:<4g} {r['events_per_s']:9.0f} events/s, "
                f"compiled/RK4 = {r['ratio']:.3f}x, KS(n_blocks) {r['ks']:.3f}, KS(magnitude) {r['ks_magnitude']:.3f} "
                f"(noise {row['noise_ks']:.3f})")
        say("           interpreted numpy RK4 (second column): " + ", ".join(
            f"dt = {r['dt']:g}: {r['events_per_s']:.0f} events/s, compiled/RK4 = {r['ratio']:.1f}x" for r in row["rk4"]))
        rows.append(row)
    return {"suite": "chain", "law": law, "ell": ell, "nu_f": nu_f, "compact_above": compact_above, "rows": rows}


def run_ks_study(*, n: int = 256, events: int = 40_000, dts=(0.2, 0.1, 0.05), law: str = "carlson-langer",
                 ell: float = 1.0, nu: float = 1e-4, nu_f: float = 0.2, amplitude: float = 0.1, seed: int = 1,
                 transient: int = 2000, verify: float = 0.001, echo=print) -> dict:
    """KS distance of RK4's event sizes and magnitudes from the exact catalog's, against its noise.

    The exact catalogs come from the compiled engine (a ``verify`` sample re-run by the heyoka engine,
    reported), after ``transient`` events. The noise floor is measured, not only quoted: the KS distance
    between two exact catalogs of the same chain from different random starts (seeds ``seed`` and
    ``seed + 1``), next to the 95 % two-sample bound 1.36·sqrt(2/k). A KS distance of RK4 below that
    floor is not resolved. RK4: numba, active set and whole chain, from the first catalog's start.
    """
    from ...laws import resolve_law
    from ._bench_rk4 import run_rk4
    from ._compiled import CompiledChain, run_verified
    from ._validate import check_initial

    say = echo or (lambda *_: None)
    law_obj = resolve_law(law)
    cats, report = [], None
    for s_ in (seed, seed + 1):
        u0_ = _steady_start_compiled(law_obj, n, ell, nu, nu_f, check_initial(n, ell, "free", None, amplitude, s_),
                                     transient)
        run = CompiledChain(law_obj, n, ell, nu, nu_f, "free", u0_)
        if report is None and verify:
            (out, report), _, cpu_s = _timed(lambda: run_verified(run, events, verify))
        else:
            out, _, cpu_s = _timed(lambda: run.run(events))
        cats.append((u0_, out["catalog"], cpu_s))
    (u0, cat, cpu_s), (_, other, _) = cats
    sizes_, mags = cat["n_blocks"], _magnitudes(cat["potency"])
    floor = {"ks": ks_distance(sizes_, other["n_blocks"]),
             "ks_magnitude": ks_distance(mags, _magnitudes(other["potency"]))}
    out = {"n": n, "nu": nu, "events": events, "noise_ks": 1.36 * math.sqrt(2 / events),
           "exact_vs_exact": floor, "verify": report, "rk4": []}
    say(f"KS study: N = {n}, {events} events per catalog, {law}, ℓ = {ell}, ν = {nu}, ν_f = {nu_f}; 95 % noise bound "
        f"{out['noise_ks']:.4f}; exact seed {seed} vs seed {seed + 1}: KS(n_blocks) = {floor['ks']:.4f}, "
        f"KS(magnitude) = {floor['ks_magnitude']:.4f}"
        + (f"; verify: {report['checked']} events re-run by heyoka, largest difference {report['largest_any']:.1e}, "
           f"{len(report['mismatched'])} differ in hypocentre/size" if report else ""))
    for kind in ("active", "plain"):
        for dt in dts:
            base = run_rk4(kind, law, n=n, ell=ell, nu=nu, nu_f=nu_f, u0=u0, events=events, dt=dt)
            row = {"kind": kind, "dt": dt, "ks": ks_distance(sizes_, base["n_blocks"]),
                   "ks_magnitude": ks_distance(mags, _magnitudes(base["potency"]))}
            out["rk4"].append(row)
            say(f"  numba RK4 {kind:6s} dt = {dt:<5g} KS(n_blocks) = {row['ks']:.4f}, KS(magnitude, 0.01) = "
                f"{row['ks_magnitude']:.4f}")
    return out


def run_long(*, n: int = 256, events: int = 100_000, chunk: int = 10_000, law: str = "carlson-langer",
             ell: float = 1.0, nu: float = 1e-3, nu_f: float = 0.2, amplitude: float = 0.1, seed: int = 1,
             compact_above: int = 32, echo=print) -> dict:
    """Wall and CPU time of one long exact run, reported every ``chunk`` events (so that a run cut
    short still gives a measured rate; an extrapolation from it is labelled as one)."""
    from ...laws import resolve_law
    from ._loop import ChainLoop
    from ._validate import check_initial

    say = echo or (lambda *_: None)
    u0 = check_initial(n, ell, "free", None, amplitude, seed)
    loop = ChainLoop(resolve_law(law), n, ell, nu, nu_f, "free", u0, compact_above=compact_above)
    w0, c0 = time.perf_counter(), time.process_time()
    done, sizes_, marks = 0, [], []
    while done < events:
        k = min(chunk, events - done)
        out = loop.run(k)
        sizes_ += out["catalog"]["n_blocks"]
        done += len(out["catalog"]["n_blocks"])
        marks.append({"events": done, "wall_s": time.perf_counter() - w0, "cpu_s": time.process_time() - c0})
        say(f"  {done} events: wall {marks[-1]['wall_s']:.1f} s, CPU {marks[-1]['cpu_s']:.1f} s "
            f"({done / marks[-1]['cpu_s']:.1f} events per CPU s), status {out['status']}")
        if out["status"] != 1:
            break
    sizes_ = np.array(sizes_)
    return {"n": n, "events": done, "marks": marks, "mean_n_blocks": float(sizes_.mean()),
            "largest": int(sizes_.max()), "spanning": int(np.sum(sizes_ == n))}


def run_scaling(*, sizes=(64, 1024, 16384, 100_000), nu: float = 1e-8, nu_f: float = 0.2, sigma: float = 0.0,
                events: int = 3000, transient: int = 300, law: str = "carlson-langer", ell: float = 1.0,
                amplitude: float = 0.1, seed: int = 1, tile: int = 1024, tile_events: int = 30_000,
                echo=print) -> dict:
    """The compiled engine's CPU time per event and memory against N (issue 18: cost independent of N,
    compared at equal event sizes).

    The start of every N: the steady state of a ``tile``-block chain (``tile_events`` events from the
    random start) repeated along the chain, each copy's stresses lowered by its own uniform offset in
    [0, 0.05) so the copies do not fail in step (identical copies fail together and make one event
    of every copy); the first copy keeps its own. So every N meets the events of one steady state,
    and at ν small enough that the chain is all stuck between events (N ν ≤ 1e-3 here) their sizes
    are equal; a larger ν lets far blocks start during an event at large N and the events grow with N
    (at ν = 1e-6 and N = 10⁵, 3.0 blocks against 2.0 at N = 64). Reported beside the µs: mean size, DOP853
    steps per event (0 for an event that stays on the stored lone trajectory), µs per step, the
    widest window. Memory: the bytes of the engine's arrays (all allocated once per run, O(N))."""
    from ...laws import resolve_law
    from ._compiled import CompiledChain
    from ._validate import check_initial

    say = echo or (lambda *_: None)
    law_obj = resolve_law(law)
    base = CompiledChain(law_obj, tile, ell, nu, nu_f, "free", check_initial(tile, ell, "free", None, amplitude, seed),
                         sigma=sigma)
    base.run(tile_events)
    s_tile = base.stress.copy()
    rng = np.random.default_rng(seed)
    rows = []
    for n in sizes:
        copies = -(-n // tile)
        offsets = np.concatenate(([0.0], -rng.uniform(0.0, 0.05, copies - 1)))
        s0 = (np.tile(s_tile, copies) + np.repeat(offsets, tile))[:n]
        run = CompiledChain(law_obj, n, ell, nu, nu_f, "free", np.zeros(n), sigma=sigma)
        run.restore(s0, np.zeros(n), 0.0)
        run.run(transient)
        w0 = len(run.widest)
        out, wall_s, cpu_s = _timed(lambda: run.run(events))
        nbytes = sum(a.nbytes for t in (run._win, run._g) for a in t if isinstance(a, np.ndarray))
        cat = out["catalog"]
        steps = float(cat["steps"].mean())
        row = {"n": n, "us_per_event": 1e6 * cpu_s / events, "mean_n_blocks": float(cat["n_blocks"].mean()),
               "steps_per_event": steps, "us_per_step": 1e6 * cpu_s / max(1.0, float(cat["steps"].sum())),
               "widest": float(np.mean(run.widest[w0:])), "bytes": nbytes, "status": int(out["status"])}
        rows.append(row)
        say(f"  N = {n:6d}: {row['us_per_event']:7.1f} µs per event (CPU), mean size {row['mean_n_blocks']:.2f}, "
            f"{steps:.0f} steps/event ({row['us_per_step']:.2f} µs per step, widest window {row['widest']:.1f}), "
            f"engine arrays {nbytes / 1e6:.2f} MB ({nbytes / n:.0f} B per block)")
    return {"nu": nu, "sigma": sigma, "rows": rows}


def run_million(*, n: int = 1024, events: int = 1_000_000, nu: float = 1e-4, nu_f: float = 0.2,
                law: str = "carlson-langer", ell: float = 1.0, amplitude: float = 0.1, seed: int = 1,
                echo=print) -> dict:
    """10^6 events of one chain on the compiled engine, CPU and wall time (issue 18's target: ≤ 2 min)."""
    from ...laws import resolve_law
    from ._compiled import CompiledChain
    from ._validate import check_initial

    run = CompiledChain(resolve_law(law), n, ell, nu, nu_f, "free", check_initial(n, ell, "free", None, amplitude, seed))
    run.run(10)                                    # compile outside the timing
    out, wall_s, cpu_s = _timed(lambda: run.run(events))
    res = {"n": n, "events": int(out["catalog"]["potency"].size), "cpu_s": cpu_s, "wall_s": wall_s,
           "status": int(out["status"]), "mean_n_blocks": float(out["catalog"]["n_blocks"].mean())}
    (echo or (lambda *_: None))(f"{res['events']} events of N = {n}: CPU {cpu_s:.1f} s, wall {wall_s:.1f} s, "
                                f"mean size {res['mean_n_blocks']:.2f}, status {res['status']}")
    return res


def run_event_shares(*, sizes=(64, 256), events: int = 20_000, transient: int = 1000, law: str = "carlson-langer",
                     ell: float = 1.0, nu: float = 1e-4, nu_f: float = 0.2, amplitude: float = 0.1, seed: int = 1,
                     echo=print) -> dict:
    """Where the compiled engine's Taylor steps go, by event size (the bench's start and law): per size 1, 2, 3, 4
    and ≥ 5 blocks, its share of the events, of the events that took steps (the others ended on the stored lone
    trajectory, ``_lone``) and of all steps, and the steps per such event. What a stored family of two-block
    events could save at most (docs/chain.md, "Issue 18's ideas for N = 64 and 256"). Reported, never asserted."""
    from ...laws import resolve_law
    from ._compiled import CompiledChain
    from ._validate import check_initial

    say = echo or (lambda *_: None)
    law_obj = resolve_law(law)
    rows = []
    for n in sizes:
        u0 = _steady_start_compiled(law_obj, n, ell, nu, nu_f, check_initial(n, ell, "free", None, amplitude, seed),
                                    transient)
        cat = CompiledChain(law_obj, n, ell, nu, nu_f, "free", u0).run(events)["catalog"]
        nb, st = cat["n_blocks"], cat["steps"]
        total = max(int(st.sum()), 1)
        for lo, hi in ((1, 1), (2, 2), (3, 3), (4, 4), (5, n)):
            sel = (nb >= lo) & (nb <= hi)
            stepped = sel & (st > 0)
            r = {"n": n, "size": lo if lo == hi else f"{lo}+", "events": float(sel.mean()),
                 "stepped": float(stepped.mean()), "steps": float(st[sel].sum() / total),
                 "steps_per_event": float(st[stepped].mean()) if stepped.any() else 0.0}
            rows.append(r)
            say(f"  N = {n:4d}, size {r['size']!s:>2}: {r['events']:.3f} of events, {r['stepped']:.3f} with steps "
                f"({r['steps_per_event']:.1f} each), {r['steps']:.3f} of all steps")
    return {"rows": rows}


def run_lone_block_check(*, n: int = 64, events: int = 300, dts=(0.2, 0.1, 0.05, 0.02), nu: float = 1e-3,
                         nu_f: float = 0.2, seed: int = 1, echo=print) -> dict:
    """Relative error of the lone interior block's slip, exact engine and RK4, against the closed form
    P = Δ(ν/√k, √k ν_f)/k, k = 1 + 2ℓ² = 3 (docs/chain.md, "Threshold"; Δ from the single-block
    engine): an accuracy measure that, unlike a KS distance, needs no long catalog."""
    import bifurcation as bf

    from ._validate import check_initial

    say = echo or (lambda *_: None)
    k = 3.0
    single = float(bf.slip("carlson-langer", nu=nu / math.sqrt(k), nu_f=nu_f * math.sqrt(k)).delta) / k
    u0 = check_initial(n, 1.0, "free", None, 0.1, seed)
    r = bf.chain("carlson-langer", n=n, ell=1.0, nu=nu, nu_f=nu_f, u0=u0, events=events)
    lone = (r.n_blocks == 1) & (r.hypocentre > 0) & (r.hypocentre < n - 1)
    out = {"closed_form": single, "exact_events": int(lone.sum()),
           "exact_max_error": float(np.max(np.abs(r.potency[lone] / single - 1))), "rk4": []}
    say(f"lone interior block, N = {n}, {events} events: exact {out['exact_events']} events, max |P/P_closed − 1| = "
        f"{out['exact_max_error']:.1e}")
    for dt in dts:
        c = rk4_chain("carlson-langer", n=n, ell=1.0, nu=nu, nu_f=nu_f, u0=u0, events=events, dt=dt)
        p = c["potency"][c["n_blocks"] == 1]
        near = p[np.abs(p / single - 1) < 0.2]     # interior lone blocks (free-end ones have k = 2)
        err = float(np.median(near / single - 1))
        out["rk4"].append({"dt": dt, "events": int(near.size), "median_error": err})
        say(f"  RK4 dt = {dt:<5g} {near.size} events, median P/P_closed − 1 = {err:+.2e}")
    return out


def run_tolerance_grid(*, sizes=(64, 256), tols=(1e-11, 1e-10, 1e-9), events: int = 10_000, reps: int = 3,
                       law: str = "carlson-langer", ell: float = 1.0, nu: float = 1e-4, nu_f: float = 0.2,
                       amplitude: float = 0.1, seed: int = 1, transient: int = 1000, verify: float = 0.01,
                       echo=print) -> dict:
    """The compiled engine's events per CPU second at several tolerances against the numba active-set RK4 at
    dt = 0.1, timed in turn ``reps`` times from the same steady start (median ratio and range), with the
    Taylor steps per event and a ``verify`` sample re-run by the heyoka engine at each tolerance: what a
    looser tolerance buys (docs/chain.md, "Speed"). Reported, never asserted."""
    from ...laws import resolve_law
    from ._bench_rk4 import run_rk4
    from ._compiled import CompiledChain, run_verified
    from ._validate import check_initial

    say = echo or (lambda *_: None)
    law_obj = resolve_law(law)
    tiny = check_initial(8, ell, "free", None, amplitude, seed)          # compile both first
    CompiledChain(law_obj, 8, ell, 1e-3, nu_f, "free", tiny).run(3)
    run_rk4("active", law, n=8, ell=ell, nu=1e-3, nu_f=nu_f, u0=tiny, events=3, dt=0.1)
    rows = []
    for n in sizes:
        u0 = _steady_start_compiled(law_obj, n, ell, nu, nu_f, check_initial(n, ell, "free", None, amplitude, seed),
                                    transient)
        for tol in tols:
            ratios, steps = [], 0.0
            for _ in range(reps):
                run = CompiledChain(law_obj, n, ell, nu, nu_f, "free", u0, tol=tol)
                out, _, c = _timed(lambda: run.run(events))
                _, _, b = _timed(lambda: run_rk4("active", law, n=n, ell=ell, nu=nu, nu_f=nu_f, u0=u0, events=events,
                                                 dt=0.1))
                ratios.append(b / c)
                steps = float(out["catalog"]["steps"].mean())
            _, rep = run_verified(CompiledChain(law_obj, n, ell, nu, nu_f, "free", u0, tol=tol), events, verify)
            row = {"n": n, "tol": tol, "ratio": float(np.median(ratios)), "ratio_range": (min(ratios), max(ratios)),
                   "steps_per_event": steps, "verify": rep["largest_any"], "verify_checked": rep["checked"],
                   "mismatched": len(rep["mismatched"])}
            rows.append(row)
            say(f"  N = {n:4d}, tol {tol:g}: compiled/numba RK4 active dt = 0.1 {row['ratio']:.3f}x "
                f"({min(ratios):.3f}-{max(ratios):.3f}, {reps} runs of {events} events), {steps:.2f} Taylor steps/event, "
                f"verify {rep['largest_any']:.1e} over {rep['checked']} events, {row['mismatched']} differ in hypocentre/size")
    return {"rows": rows}


def _lone_series(w0, v0, t0, k, c3, c4, order, variable):
    """Taylor coefficients (orders 0 … order) of a lone block's slip ẇ = v, v̇ = −k w + τ + c4 x/(1 + x),
    x = c3 v (Carlson–Langer, σ_f = 0, scaled as ``_integrator``) about (w0, v0, τ0), with the independent variable
    τ ("tau": rows w, v), s with dτ = (1 + x) ds ("s": rows w, v, τ; the pole of Φ removed) or v itself ("v": rows
    w, τ; a decelerating block's stop is the end of the series' interval)."""
    p = order
    W, V, T = np.zeros(p + 1), np.zeros(p + 1), np.zeros(p + 1)
    W[0], V[0], T[0] = w0, v0, t0
    if variable == "tau":
        R = np.zeros(p + 1)
        R[0] = 1.0 / (1.0 + c3 * v0)
        for n in range(p):
            if n:
                R[n] = -c3 * R[0] * np.dot(V[1:n + 1], R[n - 1::-1][:n])
            load = -k * W[n] + (t0 if n == 0 else 1.0 if n == 1 else 0.0)
            V[n + 1] = (load + (c4 * (1.0 - R[0]) if n == 0 else -c4 * R[n])) / (n + 1)
            W[n + 1] = V[n] / (n + 1)
        return W, V
    if variable == "s":
        E, L = np.zeros(p + 1), np.zeros(p + 1)
        for n in range(p):
            E[n] = (1.0 if n == 0 else 0.0) + c3 * V[n]
            L[n] = -k * W[n] + T[n]
            V[n + 1] = (np.dot(E[:n + 1], L[n::-1]) + c4 * (E[n] - (1.0 if n == 0 else 0.0))) / (n + 1)
            W[n + 1] = np.dot(E[:n + 1], V[n::-1]) / (n + 1)
            T[n + 1] = E[n] / (n + 1)
        return W, V, T
    A, Q = np.zeros(p + 1), np.zeros(p + 1)
    x0 = c3 * v0
    for n in range(p):
        g = c4 * x0 / (1.0 + x0) if n == 0 else -c4 / (1.0 + x0) * (-c3 / (1.0 + x0)) ** n
        A[n] = -k * W[n] + T[n] + g
        Q[n] = 1.0 / A[0] if n == 0 else -Q[0] * np.dot(A[1:n + 1], Q[n - 1::-1][:n])
        W[n + 1] = (v0 * Q[n] + (Q[n - 1] if n else 0.0)) / (n + 1)
        T[n + 1] = Q[n] / (n + 1)
    return W, T


def run_stop_phase(*, nu: float = 1e-4, nu_f: float = 0.2, ell: float = 1.0, order: int = 20, tol: float = 1e-11,
                   before=(0.5, 0.3, 0.2, 0.1), echo=print) -> dict:
    """Why the last steps before a stop are short (docs/chain.md, "Speed"): a lone interior block's slip
    (k = 1 + 2ℓ², from rest, scipy's DOP853 at rtol 1e-13 as the reference trajectory) continued past its stop
    meets the pole of Φ (x = −1) a little later, a branch point of v(τ) that bounds the Taylor series' radius, so
    steps shrink geometrically towards the stop. Counts the Taylor steps (order ``order``, the engine's step rule
    from the last two coefficients at the mixed tolerance ``tol``) from points ``before`` the stop to past it, with
    τ, s (dτ = (1 + x) ds) and v as the independent variable, and the stop's τ each finds (``stop_<variable>``).
    A model of the engine's step rule in numpy, not the engine."""
    from scipy.integrate import solve_ivp

    say = echo or (lambda *_: None)
    c3, c4, k = nu / nu_f, 1.0 / nu, 1.0 + 2.0 * ell * ell

    def rhs(t, y):
        x = c3 * y[1]
        return [y[1], -k * y[0] + t + c4 * x / (1.0 + x)]

    stop = lambda t, y: y[1] if t > 0.5 else 1.0          # noqa: E731 (v = 0 after the start's v = 0)
    pole = lambda t, y: y[1] + (1.0 - 1e-6) / c3          # noqa: E731
    pole.terminal = True
    sol = solve_ivp(rhs, [0.0, 100.0], [0.0, 0.0], method="DOP853", rtol=1e-13, atol=1e-14, events=[stop, pole],
                    dense_output=True)
    t_stop, t_pole = float(sol.t_events[0][0]), float(sol.t_events[1][0])

    def rule(cols, eps):
        a1 = max(abs(c[order - 1]) / e for c, e in zip(cols, eps))
        a0 = max(abs(c[order]) / e for c, e in zip(cols, eps))
        return 0.9 * min(a1 ** (-1.0 / (order - 1)), a0 ** (-1.0 / order))

    def poly(c, h):
        return float(np.polyval(c[::-1], h))

    def cross(V, h):
        """The root of the step's v polynomial in (0, h] (v > 0 at 0, ≤ 0 at h), by bisection."""
        a, b = 0.0, h
        for _ in range(200):
            c = 0.5 * (a + b)
            if not a < c < b:
                break
            a, b = (c, b) if poly(V, c) > 0.0 else (a, c)
        return b

    def steps(t0, variable):
        """(steps to the stop from τ = t0, the stop's τ from the last step's polynomial)."""
        w, v = sol.sol(t0)
        t, n = t0, 0
        while n < 1000:
            n += 1
            ev = tol + tol * abs(v)
            ew = max(ev, tol + tol * abs(w))
            et = tol + tol * max(1.0, abs(t))
            if variable == "tau":
                W, V = _lone_series(w, v, t, k, c3, c4, order, "tau")
                h = rule([W, V], [ew, ev])
                v1 = poly(V, h)
                if v1 <= 0.0:
                    return n, t + cross(V, h)
                w, v, t = poly(W, h), v1, t + h
            elif variable == "s":
                W, V, T = _lone_series(w, v, t, k, c3, c4, order, "s")
                h = rule([W, V, T], [ew, ev, et])
                v1 = poly(V, h)
                if v1 <= 0.0:
                    return n, poly(T, cross(V, h))
                w, v, t = poly(W, h), v1, poly(T, h)
            else:
                W, T = _lone_series(w, v, t, k, c3, c4, order, "v")
                h = rule([W, T], [ew, et])
                if v - h <= 0.0:
                    return n, poly(T, -v)
                w, t, v = poly(W, -h), poly(T, -h), v - h
        return n, np.nan

    rows = []
    say(f"lone interior block (k = {k:g}), ν = {nu:g}, ν_f = {nu_f:g}: stop at τ = {t_stop:.4f}, x = −1 on the "
        f"continuation past it at τ = {t_pole:.4f} ({t_pole - t_stop:.3f} later); Taylor order {order}, tol {tol:g}")
    for b in before:
        r = {"before": b, "v_start": float(sol.sol(t_stop - b)[1])}
        for var in ("tau", "s", "v"):
            r[var], r[f"stop_{var}"] = steps(t_stop - b, var)
        rows.append(r)
        say(f"  from {b:g} before the stop (v = {r['v_start']:.0f}): steps to the stop with τ {r['tau']}, "
            f"s {r['s']}, v as the variable {r['v']}")
    return {"t_stop": t_stop, "t_pole": t_pole, "rows": rows}


#: the presets at their own loading rate (issue 17's ``[published_nu]``): (preset, ν_f); MK at α = 1, 2, 3
PUBLISHED_NU_CASES = (("carlson-langer-1991", 0.2), ("mori-kawamura-2006", 0.5), ("mori-kawamura-2006", 0.25),
                      ("mori-kawamura-2006", 1.0 / 6.0))


def _rk4_vth_from(p, nu_f, u, v, t, cycles, vth, dt, prune=20):
    from ._bench_rk4 import LAW_CODES, rk4_vth

    out, tot = np.zeros((5, 10**6)), np.zeros(3)
    uu, vv = u.copy(), v.copy()
    ne, _ = rk4_vth(LAW_CODES[p.law], p.ell ** 2, p.nu, nu_f, p.sigma, p.ends == "periodic", uu, vv, t,
                    t + cycles / p.nu, vth, dt, prune, out, tot)
    return ne, out[:, :ne], tot


def run_published_nu(*, cases=PUBLISHED_NU_CASES, transient_cycles: float = 50.0, cycles: float = 10.0,
                     reps: int = 3, dts=(0.1, 0.05), v_threshold: float = 0.1, seed: int = 1, amplitude: float = 0.1,
                     say=print) -> list:
    """The compiled engine's V_th-split catalogs (``_subevents``) at the presets' own ν = 0.01 against a numba
    active-set RK4 with the same friction drop and the same V_th split read at step ends (``_bench_rk4.rk4_vth``),
    side by side in this process from the same state: after ``transient_cycles`` of the engine, each repetition
    runs the engine ``cycles`` loading cycles on and RK4 (each dt) the same span from the engine's state at its
    start (U and V of every block). Rates in events per CPU second and CPU seconds per loading cycle (the event
    counts of the two codes differ: RK4 reads V at step ends); ratio = engine events/s ÷ RK4 events/s."""
    from ...laws import resolve_law
    from ._subevents import SubeventRun
    from ._validate import check_initial
    from .presets import get_preset

    rows = []
    for name, nu_f in cases:
        p = get_preset(name)
        u0 = check_initial(p.n, p.ell, p.ends, None, amplitude, seed)
        run = SubeventRun(resolve_law(p.law), p.n, p.ell, p.nu, nu_f, p.ends, u0, v_threshold=v_threshold,
                          sigma=p.sigma)
        _, _, c_tr = _timed(lambda: run.run(10**6, t_stop=transient_cycles / p.nu))
        _rk4_vth_from(p, nu_f, np.asarray(run.chain.u, dtype=float), np.zeros(p.n), run.t, 0.01, v_threshold, 0.1)  # compile
        for rep in range(reps):
            c = run.chain
            m = int(run._ctx[5]) if run._ctx[0] else 0
            u = np.array(c._g.u, dtype=float)
            v = np.zeros(p.n)
            for i in range(m):
                if c._win.slip[i]:
                    v[c._win.blk[i]] = p.nu * c._win.v[i]
            t0 = run.t
            steps0 = run.totals[3]
            out, _, cpu = _timed(lambda: run.run(10**6, t_stop=t0 + cycles / p.nu))
            ne = out["catalog"]["potency"].size
            row = {"preset": name, "nu_f": nu_f, "rep": rep, "t0": t0, "cycles": cycles, "engine_events": ne,
                   "engine_cpu": cpu, "engine_steps": float(run.totals[3] - steps0), "widest": int(run.totals[4]),
                   "engine_nb_mean": float(out["catalog"]["n_blocks"].mean()) if ne else 0.0}
            for dt in dts:
                (nr, cat, tot), _, cpu_r = _timed(lambda: _rk4_vth_from(p, nu_f, u, v, t0, cycles, v_threshold, dt))
                row[f"rk4_{dt:g}_events"], row[f"rk4_{dt:g}_cpu"] = nr, cpu_r
                row[f"rk4_{dt:g}_set"] = float(tot[2])
                row[f"rk4_{dt:g}_nb_mean"] = float(cat[4].mean()) if nr else 0.0
                row[f"ratio_{dt:g}"] = (ne / cpu) / (nr / cpu_r) if nr and ne else float("nan")
                row[f"ratio_cycle_{dt:g}"] = cpu_r / cpu
            rows.append(row)
            say(f"{name} ν_f = {nu_f:.4g} rep {rep}: engine {ne} events {cpu:.2f} CPU s "
                f"({1e3 * cpu / max(ne, 1):.1f} ms/event, {row['engine_steps'] / max(ne, 1):.0f} steps/event, "
                f"mean n_blocks {row['engine_nb_mean']:.1f}); " + "; ".join(
                    f"RK4 dt {dt:g}: {row[f'rk4_{dt:g}_events']} events {row[f'rk4_{dt:g}_cpu']:.2f} CPU s "
                    f"(set ≤ {row[f'rk4_{dt:g}_set']:.0f}, mean n_blocks {row[f'rk4_{dt:g}_nb_mean']:.1f}), "
                    f"ratio {row[f'ratio_{dt:g}']:.3f} per event, {row[f'ratio_cycle_{dt:g}']:.3f} per cycle"
                    for dt in dts), flush=True)
    import os
    say(f"load average {os.getloadavg()}")
    return rows


if __name__ == "__main__":   # the long measurements of results/chain/REPORT.md ("Speed")
    import sys

    what = sys.argv[1] if len(sys.argv) > 1 else "suite"
    if what == "published-nu":    # the presets at ν = 0.01 against a compiled RK4 (docs/chain.md, "Split in time")
        run_published_nu(**({"cycles": float(sys.argv[2])} if len(sys.argv) > 2 else {}))
    elif what == "suite":
        run_chain_bench()
    elif what == "ks":
        run_ks_study(events=int(sys.argv[2]) if len(sys.argv) > 2 else 40_000,
                     n=int(sys.argv[3]) if len(sys.argv) > 3 else 256)
    elif what == "long":
        run_long(events=int(sys.argv[2]) if len(sys.argv) > 2 else 100_000)
    elif what == "scaling":
        run_scaling(**({"nu": float(sys.argv[2])} if len(sys.argv) > 2 else {}))
    elif what == "million":
        run_million()
    elif what == "atom":
        run_lone_block_check()
    elif what == "tolerance":
        run_tolerance_grid()
    elif what == "stop":
        run_stop_phase()
    elif what == "shares":
        run_event_shares()
