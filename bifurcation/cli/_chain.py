"""``bifurcation chain``: the event catalog of a Burridge–Knopoff chain (docs/chain.md)."""

from __future__ import annotations

import contextlib

import click

from ..bounds import CHAIN_EVENT_WORK, CHAIN_MAX_N_EVENTS, CHAIN_RUN_WORK
from ..errors import InputError
from ._common import Whole, echo_json, examples, number

__all__ = ["COMMANDS", "MAX_EVENTS"]

#: The most events one ``bifurcation chain`` run computes: its catalog is held in memory and printed, and
#: at ~7000 events/s (N = 2, measured at load 4: 250000 events in 37 s; far fewer for long chains) 10^6
#: events are minutes, with a progress line every 10 s. Longer catalogs are
#: studies: a workflow through ``bifurcation submit`` checkpoints every run and resumes.
MAX_EVENTS = 10**6
_STUDY = ("for more, run a study: a workflow with [grid.n] and [grid.events] through `bifurcation submit` "
          "(checkpointed and resumable; workflows/chain-study.toml, docs/chain.md)")


def _check_bounds(n, ell, amplitude, seed, events, sigma=None, v_threshold=None) -> None:
    """The chain's values against the bounds its workflows obey (the model's axes), and the CLI's cap on
    events, before anything is computed."""
    from ..models import get_model
    from ..models.chain._validate import check_n_events

    axes = {axis.name: axis for axis in get_model("chain").axes}
    if events is not None and events > MAX_EVENTS:
        raise InputError("--events", events, f"is more than {MAX_EVENTS}, the most one `bifurcation chain` run "
                         "computes", f"give at most {MAX_EVENTS}; {_STUDY}")
    if events is not None and n is not None and 1 <= n <= (1 << 20):
        check_n_events(n, events, n_key="--n", events_key="--events", what="one `bifurcation chain` run",
                       more="; for more, run a study of several runs (seeds) through `bifurcation submit`, each "
                            "within the same bound (workflows/chain-study.toml, docs/chain.md)")
    given = {"n": n, "ell": ell, "amplitude": amplitude, "seed": seed, "events": events, "sigma": sigma,
             "v_threshold": v_threshold}
    for name, value in given.items():
        if value is None or value != value:   # missing, or NaN (refused with its own message later)
            continue
        low, high = (int(b) if float(b).is_integer() else b for b in axes[name].bounds)
        if not low <= value <= high:
            option = "--" + name.replace("_", "-")
            raise InputError(option, value, f"is outside [{low}, {high}], the bounds of the chain model (its "
                             "workflows' too: bifurcation.models.chain)", f"give a value in [{low}, {high}]")


#: The chain's work bounds (one definition, bifurcation.bounds; chain workflows obey them too): per event
#: and per run in block-steps, and N × events.
MAX_WORK, MAX_RUN_WORK, MAX_N_EVENTS = CHAIN_EVENT_WORK, CHAIN_RUN_WORK, CHAIN_MAX_N_EVENTS

#: Seconds within one event (no event finished) before a line says it is still running, and between them.
STILL_RUNNING_SECONDS = 30.0


def _progress(started: float):
    """A line on stderr about every 10 s of a long run: events done, the chain's time, the elapsed time
    (``run.progress.event_lines``, as the runs of ``study chain``)."""
    import time

    from ..run.progress import event_lines

    line = event_lines("chain", started)

    def report(done: int, events: int, t: float) -> None:
        report.done, report.last_event, report.compiling = done, time.perf_counter(), None
        line(done, events, t)

    # compiling: set by the compiled engine before numba compiles its loop (what the cache allows), None after
    report.done, report.last_event, report.compiling = 0, started, None
    return report


@contextlib.contextmanager
def _still_running(report, events: int, n: int, nu: float, work: float = MAX_WORK["exact", "double"],
                   counted: bool = True):
    """While the run is inside one event (the progress above is said between events), a line every
    STILL_RUNNING_SECONDS: an event ends only when every block is stuck, and when failures come faster than
    events end (N·ν of order 1 and more: measured, carlson-langer ν_f = 0.3 from amplitude 0.1: N·ν = 1
    ended 5 events, N·ν = 5 and 20 had an event still sliding after 3000 steps and 10-40 s, the chain
    reloaded meanwhile) it may run to the engine's max_steps, which at thousands of blocks is hours."""
    import threading
    import time

    stop = threading.Event()

    def watch() -> None:
        while not stop.wait(STILL_RUNNING_SECONDS / 3):
            now = time.perf_counter()
            if now - report.last_event >= STILL_RUNNING_SECONDS:
                report.last_event = now
                hint = (f"; at N·ν = {n * nu:.3g} blocks fail faster than events end and this one may not "
                        f"end (it stops at {work:.3g} block-steps, minutes at this N): interrupt and give a "
                        "smaller --nu or --n (N·ν < 1)") if n * nu >= 1 else ""
                compiling = getattr(report, "compiling", None)
                if compiling is not None:   # numba compiling the engine: no event has started (was "still sliding")
                    from ..models.chain._compiled import COMPILE_SECONDS

                    then = "; with --verify no progress is reported until the end" if not counted else ""
                    click.echo(f"bifurcation: chain: {'still compiling' if counted else 'compiling or running'} "
                               f"the chain engine (numba) after {now - report.started:.0f} s (~{COMPILE_SECONDS} s "
                               f"of CPU; {compiling}{then})", err=True)
                elif not counted:   # the compiled engine with --verify reports nothing until the end
                    click.echo(f"bifurcation: chain: still running after {now - report.started:.0f} s (with "
                               f"--verify no progress is reported until the end){hint}", err=True)
                else:
                    click.echo(f"bifurcation: chain: event {report.done + 1} of {events} still sliding after "
                               f"{now - report.started:.0f} s{hint}", err=True)

    report.started = time.perf_counter()
    thread = threading.Thread(target=watch, name="chain-still-running", daemon=True)
    thread.start()
    try:
        yield
    finally:
        stop.set()
        thread.join()


def _over_bound(r, work: float, n: int, nu: float, engine: str) -> str:
    """What a run stopped by the CLI's work bound (MAX_WORK) means and what to do."""
    from ..models.chain import ChainStatus

    by_work = "block-steps" in r.message or (engine == "compiled" and "max_steps" in r.message and work // n < 10**6)
    if r.status != ChainStatus.NO_STOP or not by_work:
        return ""
    why = (f"at N·ν = {n * nu:.3g} ≥ 1 blocks fail faster than events end: give a smaller --nu or --n (N·ν < 1); "
           if n * nu >= 1 else "")
    what = (f"one run: {MAX_RUN_WORK[engine, r.precision]:.3g}"
            if "the run's bound" in r.message else f"one event: {work:.3g}")
    return f" (the bound of {what} block-steps of a `bifurcation chain` run, minutes of CPU; {why}{_STUDY})"


def _u0(ctx, param, value):
    if value is None:
        return None
    from ..engine._exact import Text

    try:   # each keeps its decimal text: --precision quad reads it in real128
        return [Text(x) for x in value.split(",")]
    except ValueError:
        raise click.BadParameter(f"{value!r} is not a comma-separated list of numbers (ASCII digits, no '_'); "
                                 "give e.g. 0,-0.1,0.05", param_hint="--u0") from None


@click.command("chain", epilog=examples(
    'bifurcation chain --law carlson-langer --n 8 --ell 1 --nu 1e-3 --nu-f 0.3 --amplitude 0.1 --seed 1 --events 10',
    'bifurcation chain --preset carlson-langer-1991 --n 16 --amplitude 0.5 --seed 1 --events 20'))
@click.option("--preset", help="A published parameter set (carlson-langer-1991, mori-kawamura-2006, vasconcelos-1996; "
                               "docs/chain.md): fills --law, --n, --ell, --nu, --nu-f, --sigma, --ends where not given.")
@click.option("--law", help="Law name (see `bifurcation laws`) or formula in x.")
@click.option("--n", "n", type=Whole(example="16"), help="Number of blocks N ≥ 1.")
@click.option("--ell", callback=number("--ell", "1"), help="Coupling ℓ ≥ 0.")
@click.option("--nu", callback=number("--nu", "1e-6"), help="Pulling speed ν > 0.")
@click.option("--nu-f", "nu_f", callback=number("--nu-f", "0.3"), help="Friction velocity ν_f > 0.")
@click.option("--ends", help="Boundary condition: free (default) or periodic.")
@click.option("--u0", callback=_u0, help="Initial displacements u_1,...,u_N (comma-separated).")
@click.option("--amplitude", callback=number("--amplitude", "0.1"), help="Random start: amplitude A ≥ 0.")
@click.option("--seed", type=Whole(example="1"), help="Random start: seed of numpy's default_rng.")
@click.option("--events", required=True, type=Whole(example="100"), help="Number of events K ≥ 1.")
@click.option("--precision", type=click.Choice(["double", "quad"]), default="double", show_default=True)
@click.option("--sigma", callback=number("--sigma", "0.01"),
              help="Friction drop 0 ≤ σ ≤ 0.99 (the model's bounds): Φ_σ(x) = (1 − σ)Φ(x/(1 − σ)); 0 (default) is the seed's model (docs/chain.md).")
@click.option("--v-threshold", "v_threshold", default=None,
              help="Event membership by slip velocity: count only blocks faster than V_th (in V0), or 'default' "
                   "for 10·ν (docs/chain.md). Without it: every block that moved, until all are stuck.")
@click.option("--engine", type=click.Choice(["exact", "compiled"]), default="exact", show_default=True,
              help="exact: heyoka Taylor (the reference); compiled: numba (Taylor steps for Carlson-Langer, DOP853 "
                   "otherwise), events located the same way.")
@click.option("--verify", callback=number("--verify", "0.01"), default="0",
              help="Compiled engine: re-run this fraction of events exactly and print the largest difference.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object (keys = the field names).")
def chain_cmd(preset, law, n, ell, nu, nu_f, ends, u0, amplitude, seed, events, precision, sigma, v_threshold,
              engine, verify, as_json) -> None:
    """The first K events of a chain of N blocks: t_start, hypocentre, n_blocks, potency, duration,
    max_velocity per event, and the final state."""
    from ..models.chain import CATALOG_FIELDS, chain
    from ..engine._exact import Text
    from ..models.chain._validate import check_sigma, check_size, check_v_threshold

    import time

    if preset is not None:
        from ..models.chain.presets import get_preset

        try:
            p = get_preset(preset).parameters()
        except InputError as exc:
            raise InputError("--preset", preset, exc.problem, exc.fix) from None
        law, n, ell, nu, nu_f = (x if x is not None else p[k] for x, k in
                                 ((law, "law"), (n, "n"), (ell, "ell"), (nu, "nu"), (nu_f, "nu_f")))
        sigma = sigma if sigma is not None else p["sigma"]
        ends = ends if ends is not None else p["ends"]
    for name, value, example in (("--law", law, "carlson-langer"), ("--n", n, "16"), ("--ell", ell, "10"),
                                 ("--nu", nu, "0.01"), ("--nu-f", nu_f, "0.2")):
        if value is None:
            raise InputError(name, None, "is missing", f"give it, e.g. {name} {example}, or --preset NAME, which sets "
                             "--law, --n, --ell, --nu and --nu-f (e.g. --preset carlson-langer-1991)")
    sigma = 0.0 if sigma is None else sigma
    ends = "free" if ends is None else ends
    _check_bounds(n, ell, amplitude, seed, events)
    check_size(n, ell, ends)   # the chain first (N, ℓ, ends), then its start
    try:
        check_sigma(sigma)
    except InputError as exc:     # name the option as the user typed it
        raise InputError("--sigma", sigma, exc.problem, exc.fix) from None
    if v_threshold is not None and v_threshold != "default":
        try:
            v_threshold = float(Text(v_threshold))   # (float() alone reads '1_0')
        except ValueError:
            raise InputError("--v-threshold", v_threshold, "is not a number",
                             "give a slip velocity > 0 such as 0.01, or 'default' for 10·ν") from None
        try:
            check_v_threshold(v_threshold, 1.0)
        except InputError as exc:
            raise InputError("--v-threshold", v_threshold, exc.problem,
                             "give a slip velocity > 0 such as 0.01, or 'default' for 10·ν") from None
    # the engines' limits in the CLI's words (the library's errors name its keyword arguments)
    if engine == "compiled" and precision != "double":
        raise InputError("--precision", precision, "is not available with --engine compiled (double only)",
                         "give --precision double, or --engine exact for quad")
    if engine == "compiled" and v_threshold is not None:
        raise InputError("--v-threshold", v_threshold, "is not available with --engine compiled",
                         "drop --v-threshold, or give --engine exact for membership by a slip-velocity threshold")
    if verify and 0 < verify <= 1 and engine != "compiled":   # (out of range: the library's message)
        raise InputError("--verify", verify, "checks the compiled engine against the exact one",
                         "give --engine compiled with --verify")
    # σ and V_th within the bounds of the model's axes too (after their own checks: a value, in range)
    _check_bounds(None, None, None, None, None, sigma, v_threshold if v_threshold != "default" else None)
    for name, value in (("--amplitude", amplitude), ("--seed", seed)):   # named as typed (was --u0='given')
        if u0 is not None and value is not None:
            raise InputError(name, value, "is given with --u0, which sets the start itself",
                             f"drop {name} (a start from --u0), or drop --u0 (a random start from --amplitude and --seed)")
    if u0 is None and amplitude is None:
        raise InputError("--amplitude", None, "is missing", "give --u0 a,b,c or --amplitude A --seed S")
    if u0 is None and seed is None:   # a random start names its seed: no silent seed 0
        raise InputError("--seed", None, "is missing (a random start from --amplitude needs it)",
                         "give --seed S, e.g. --seed 1 (the start is numpy.random.default_rng(S))")

    report = _progress(time.perf_counter())
    work = MAX_WORK[engine, precision]
    with _still_running(report, events, n, float(nu), work, counted=not (engine == "compiled" and verify > 0)):
        r = chain(law, n=n, ell=ell, nu=nu, nu_f=nu_f, ends=ends, u0=u0, amplitude=amplitude, seed=seed,
                  events=events, precision=precision, sigma=sigma, v_threshold=v_threshold, engine=engine,
                  verify=verify, progress=report, max_work=work, max_run_work=MAX_RUN_WORK.get((engine, precision)))
    if as_json:
        echo_json(r.to_json())
    else:
        # numbers as `query` prints them: the shortest text that reads back to the same double (repr), at
        # most 24 characters (-1.7976931348623157e+308); was %.15g, which rounded away the last digits
        click.echo(f"{'event':>6s} " + " ".join(f"{k:>24s}" for k in CATALOG_FIELDS))
        for i in range(r.events):
            cells = [f"{r[k][i]:24d}" if k in ("hypocentre", "n_blocks") else f"{float(r[k][i])!r:>24s}"
                     for k in CATALOG_FIELDS]
            click.echo(f"{i:6d} " + " ".join(cells))
        click.echo(f"status {r.status}; t = {float(r.t)!r}" + (f"; membership {r.membership}" if r.v_threshold else "")
                   + (f"; {r.message}" if r.message else "") + _over_bound(r, work, n, float(nu), engine))
        click.echo("(events and hypocentres count from 0: hypocentre 0 is block j = 1 of docs/chain.md)")
        below = sum(1 for i in range(r.events) if r["n_blocks"][i] == 0) if r.v_threshold else 0
        if below:   # a table of zeros said nothing about why (docs/chain.md's --v-threshold example: 50 of 50)
            click.echo(f"({below} of {r.events} events had no block faster than V_th = {r.v_threshold:g}: n_blocks "
                       "and potency count only those, so they are 0 there)")
        if r.verification is not None:
            v = r.verification
            every = f"one in {v['every']}" if v["every"] < r.events else "the first only"   # not a 300-digit 1/1e-300
            click.echo(f"verify: {v['checked']} events re-run exactly ({every}); largest relative "
                       f"difference {v['largest_any']:.2e} (" + ", ".join(f"{k} {x:.1e}" for k, x in v['largest'].items())
                       + f"); hypocentre or size differ in {len(v['mismatched'])}")
    if r.status != 1:
        raise SystemExit(1)


COMMANDS = [chain_cmd]
