"""Rate-and-state subcommands: ``hopf`` (the Hopf point of steady sliding) and ``rate-state`` (one run)."""

from __future__ import annotations

import math

import click

from ._common import Whole, _not_a_number, echo_json, examples, format_value, number

__all__ = ["COMMANDS", "MAX_OUTPUTS"]

#: The most output times of one ``bifurcation rate-state`` run (each a printed line; the arrays are held in
#: memory). Denser output is the Python API's ``rate_state(t=...)`` over windows of the run.
MAX_OUTPUTS = 10**6


def _check_times(t_end, outputs) -> None:
    """--t-end and --outputs, before anything is computed."""
    import math

    from ..errors import InputError

    if not math.isfinite(t_end) or t_end <= 0:
        raise InputError("--t-end", t_end, "must be a finite time > 0 (the run starts at t = 0)",
                         "give an end time such as 40")
    if outputs < 2 or outputs > MAX_OUTPUTS:
        raise InputError("--outputs", outputs, f"must be in [2, {MAX_OUTPUTS}] (the start and the end at least)",
                         f"give a number of output times such as 41; denser output: the Python API "
                         f"bifurcation.rate_state(t=...) over windows of the run")


def _check_steps(t_end, at) -> None:
    """Every --at step before --t-end (a later one would never be applied)."""
    from ..errors import InputError

    for step in at or []:
        if step >= t_end:
            raise InputError("--at", step, f"is not before --t-end {t_end:g}: that velocity step would never "
                             "be applied", "give step times before the end time, or a later --t-end")


#: The longest ``bifurcation rate-state`` run, in units of the slider's shortest time scale (``_time_scale``):
#: measured 0.2 Taylor steps per Dc/V_lp on the README's aging example (20 759 steps to t = 1e5, 23 s here)
#: and ~0.1 per inertial relaxation time; 1e5 of them stay well inside DEFAULT_MAX_STEPS (2e6) and a minute.
MAX_TIME_SCALES = 1e5
#: Shortest inertial relaxation time M/(a/V + η) the double Taylor steps take: their top-order (20)
#: coefficients grow like τ^-20 and pass the blow-up guard's 1e300 at τ ~ 1e-15 (measured: M = 1e-18,
#: τ = 2e-16 ran; M = 1e-20, τ = 2e-18 ended "unbounded" at step 0; M = 1e-300: "nonfinite" at t = nan).
MIN_INERTIAL_TIME = 1e-14
#: Seconds between progress lines on stderr of a long run.
PROGRESS_SECONDS = 5.0
#: The Taylor steps of one run in quad (the API's default, 2e6, bounds double: 15 s measured on an inertial
#: stick-slip run that reaches it; real128 steps are ~40× slower, 1600 steps/s at load 9: 2e6 was ~20 min).
#: Beyond it the run ends with status max-steps, as in double.
QUAD_MAX_STEPS = 100_000


def _time_scale(spec, velocities) -> tuple[float, str]:
    """The slider's shortest time scale over the loading (steps scale with it) and the option that sets it:
    Dc_i/V_lp (state evolution), and with --mass the inertial relaxation time M/(a/V_lp + η)."""
    moving = [float(v) for v in velocities if float(v) > 0]
    tau, option = min(float(d) for d in spec.dc) / max(moving), "--dc"
    if spec.mass is not None:
        inertial = float(spec.mass) / (float(spec.a) / min(moving) + float(spec.damping))
        if inertial < tau:
            tau, option = inertial, "--mass"
    return tau, option


def _check_mass(spec, velocities) -> None:
    """--mass (or --dc) so small that its time scale overflows the Taylor steps: refused, not run to a NaN."""
    from ..errors import InputError

    if not any(float(v) > 0 for v in velocities):
        return
    tau, option = _time_scale(spec, velocities)
    # Dc/V_lp alike (measured at --t-end 1000 Dc: Dc = 1e-15 ended unbounded after 45 steps, 1e-17 nonfinite
    # at step 0, 1e-20 at t = nan): named as --dc, not as the --t-end that no value could fix (issue 21)
    if option == "--dc" and tau < MIN_INERTIAL_TIME:
        dc = min(float(d) for d in spec.dc)
        fastest = max(float(v) for v in velocities)
        raise InputError("--dc", dc, f"with --v-lp {fastest:g} gives a state-evolution time Dc/V_lp = {tau:.3g}, "
                         f"below {MIN_INERTIAL_TIME:g}, where the Taylor steps stall or overflow",
                         f"give --dc >= {MIN_INERTIAL_TIME * dc / tau:.3g} (e.g. 0.01), or a smaller --v-lp")
    # the state variables' own time a Dc_i/(b_i V_lp) alike (the linearised rates scale with b/a V/Dc; measured
    # at a = 0.005, Dc = 10, V_lp = 1: b = 1e13 stalled after 51 steps, 1e16 nonfinite at step 0, 1e300 at t = nan)
    fastest = max(float(v) for v in velocities)
    for b, dc in zip(spec.b, spec.dc):
        state = float(spec.a) * float(dc) / (float(b) * fastest) if float(b) > 0 else math.inf
        if state < MIN_INERTIAL_TIME:
            raise InputError("--b", f"{float(b):g}", f"with --a {float(spec.a):g}, --dc {float(dc):g} and --v-lp {fastest:g} "
                             f"gives a state time a Dc/(b V_lp) = {state:.3g}, below {MIN_INERTIAL_TIME:g}, where "
                             "the Taylor steps stall or overflow",
                             f"give --b <= {float(b) * state / MIN_INERTIAL_TIME:.3g} (e.g. 0.015)")
    # the spring's time a/(k V_lp) alike (measured at a = 0.005, V_lp = 10: k = 1e12 crawled, 3 % of t = 2e-6 in
    # 1.7e6 steps; 1e15 stalled at step 0;
    # k = 1e300 ended nonfinite with NaN rows)
    fastest = max(float(v) for v in velocities)
    elastic = float(spec.a) / (float(spec.k) * fastest) if float(spec.k) > 0 else math.inf
    if elastic < MIN_INERTIAL_TIME:
        raise InputError("--k", spec.k, f"with --v-lp {fastest:g} gives an elastic time a/(k V_lp) = {elastic:.3g}, "
                         f"below {MIN_INERTIAL_TIME:g}, where the Taylor steps stall or overflow",
                         f"give --k <= {float(spec.k) * elastic / MIN_INERTIAL_TIME:.3g} (e.g. 1e-3)")
    if spec.mass is None:
        return
    if option == "--mass" and tau < MIN_INERTIAL_TIME:
        raise InputError("--mass", spec.mass, f"gives an inertial relaxation time M/(a/V_lp + η) = {tau:.3g}, "
                         f"below {MIN_INERTIAL_TIME:g}, where the Taylor steps overflow",
                         "give a larger --mass, or omit --mass for the quasi-static slider")


def _check_length(spec, velocities, t_end) -> None:
    """--t-end within MAX_TIME_SCALES of the shortest time scale: a run that ends within its bounds."""
    from ..errors import InputError

    tau, option = _time_scale(spec, velocities)
    if t_end / tau > MAX_TIME_SCALES:
        what = "Dc/V_lp" if option == "--dc" else "M/(a/V_lp + η)"
        raise InputError("--t-end", t_end, f"spans {t_end / tau:.3g} times the slider's shortest time scale "
                         f"{what} = {tau:.3g} (set by {option}); at most {MAX_TIME_SCALES:g} run within the step "
                         f"bound", f"give --t-end <= {MAX_TIME_SCALES * tau:.3g}, or a larger {option}, or --cycle "
                         "for the attracting cycle"
                         + "; longer runs: the Python API bifurcation.rate_state (max_steps bounds it)")


def _floats(name: str, example: str):
    def convert(ctx, param, value):
        if value is None:
            return None
        from ..engine._exact import Text

        out = []
        for part in str(value).split(","):
            try:   # keeps its decimal text: --precision quad reads it in real128
                out.append(Text(part))
            except ValueError:
                raise click.BadParameter(_not_a_number(part, example), param_hint=name) from None
        return out
    return convert


@click.command("hopf", epilog=examples(
    'bifurcation hopf --state-law slip --a 0.01 --b 0.015 --dc 0.01 --v-lp 1 --json'))
@click.option("--state-law", required=True, help="aging (dieterich), slip (ruina) or prz; comma-separated for two.")
@click.option("--a", "a", required=True, callback=number("--a", "0.01"), help="Direct effect a > 0.")
@click.option("--b", "b", required=True, callback=_floats("--b", "0.015 or 0.015,0.005"), help="b_i >= 0.")
@click.option("--dc", required=True, callback=_floats("--dc", "0.01 or 0.01,0.1"), help="Dc_i > 0.")
@click.option("--v-lp", "v_lp", required=True, callback=number("--v-lp", "1"), help="Load-point velocity > 0.")
@click.option("--mass", default=None, callback=number("--mass", "1e-3"), help="Mass M > 0 (inertial).")
@click.option("--damping", default=None, callback=number("--damping", "0.002"),
              help="Radiation damping ETA >= 0, friction per unit slip rate (k(V_lp t - δ) - ETA V = μ - μ0); "
                   "default 0.")
@click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
def hopf_cmd(state_law, a, b, dc, v_lp, mass, damping, as_json) -> None:
    """The Hopf point of steady sliding: k_c, ω_c, the first Lyapunov coefficient, criticality."""
    from ..models.rate_state.hopf import hopf_point

    laws = [s.strip() for s in state_law.split(",")]
    if len(laws) == 1 and len(b) > 1:
        laws = laws * len(b)
    damping = 0.0 if damping is None else damping
    record = hopf_point(a=a, b=b, dc=dc, state_law=laws, v_lp=v_lp, mass=mass, damping=damping).to_record()
    record = {"state_law": laws, "a": a, "b": b, "dc": dc, "v_lp": v_lp, "mass": mass, "damping": damping, **record}
    if as_json:
        echo_json(record)
        return
    for key, value in record.items():   # lists and None as words, not Python's ['aging'] and None
        shown = (f"{value:.17g}" if isinstance(value, float) else
                 ", ".join(format_value(v) for v in value) if isinstance(value, (list, tuple)) else format_value(value))
        click.echo(f"{key:22s} {shown}")


@click.command("rate-state", epilog=examples(
    'bifurcation rate-state --state-law aging --a 0.005 --b 0.01 --dc 10 --k 1e-3 --v-lp 1,10 --at 10 --t-end 40 --outputs 5',
    'bifurcation rate-state --state-law slip --a 0.01 --b 0.015 --dc 1e-4 --k 32 --v-lp 1e-3 --damping 1 --cycle --json'))
@click.option("--state-law", required=True, help="aging (dieterich), slip (ruina) or prz; comma-separated for two.")
@click.option("--a", "a", required=True, callback=number("--a", "0.01"), help="Direct effect a > 0.")
@click.option("--b", "b", required=True, callback=_floats("--b", "0.015 or 0.015,0.005"), help="b_i >= 0.")
@click.option("--dc", required=True, callback=_floats("--dc", "0.01 or 0.01,0.1"), help="Dc_i > 0.")
@click.option("--k", "k", required=True, callback=number("--k", "1e-3"), help="Spring stiffness k > 0.")
@click.option("--v-lp", "v_lp", required=True, callback=_floats("--v-lp", "1,10"),
              help="Load-point velocities, comma-separated (0 is a hold).")
@click.option("--at", "at", default=None, callback=_floats("--at", "10"),
              help="Times of the velocity steps, comma-separated, increasing (one fewer than --v-lp).")
@click.option("--t-end", "t_end", default=None, callback=number("--t-end", "40"),
              help="End time (required, except with --cycle, which takes none).")
@click.option("--outputs", default=41, show_default=True, type=Whole(example="41"), help="Number of evenly spaced output times.")
@click.option("--mass", default=None, callback=number("--mass", "1e-3"), help="Mass M > 0 (inertial).")
@click.option("--damping", default=None, callback=number("--damping", "0.002"),
              help="Radiation damping ETA >= 0, friction per unit slip rate (k(V_lp t - δ) - ETA V = μ - μ0); "
                   "default 0.")
@click.option("--precision", type=click.Choice(["double", "quad"]), default="double", show_default=True)
@click.option("--cycle", is_flag=True,
              help="Print the attracting cycle reached from perturbed steady sliding (period, ln(V/V_lp) "
                   "extrema, slip, each with an error estimate) instead of a time series; one --v-lp.")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
def rate_state_cmd(state_law, a, b, dc, k, v_lp, at, t_end, outputs, mass, damping, precision, cycle,
                   as_json) -> None:
    """One run of the rate-and-state spring-slider: μ, V, θ at evenly spaced times, and the extrema of V."""
    import math

    import numpy as np

    from ..errors import InputError
    from ..models.rate_state import SliderSpec, load_history, rate_state

    if cycle and t_end is not None:   # the cycle search sets its own run length: a given one would be ignored
        raise InputError("--t-end", t_end, "does not apply with --cycle (the search runs until the cycle is "
                         "found or refused)", "drop --t-end, or drop --cycle for a time series up to it")
    if cycle and click.get_current_context().get_parameter_source("outputs") is not click.core.ParameterSource.DEFAULT:
        raise InputError("--outputs", outputs, "does not apply with --cycle (it prints the cycle, not a time "
                         "series)", "drop --outputs, or drop --cycle for a time series")
    if t_end is not None:
        _check_times(t_end, outputs)
    for step in at or []:
        if not math.isfinite(step):
            raise InputError("--at", step, "is not a finite time", "give step times such as 10 or 10,20")
    laws = [s.strip() for s in state_law.split(",")]
    if len(laws) == 1 and len(b) > 1:
        laws = laws * len(b)
    damping = 0.0 if damping is None else damping
    for name, given in (("--dc", [getattr(x, "text", str(x)) for x in dc]), ("--state-law", laws)):   # (was named dc/state_law)
        if len(given) != len(b):
            raise InputError(name, ",".join(given), f"has {len(given)} value(s) for the {len(b)} state variable(s) "
                             "of --b", "give one --dc and one --state-law per value of --b, e.g. --b 0.015,0.005 "
                             "--dc 0.01,0.1 --state-law aging (one law: the same for both)")
    spec = SliderSpec(a=a, b=b, dc=dc, state_law=laws, k=k, mass=mass, damping=damping)   # checks before work
    if cycle and len(v_lp) != 1:   # before the step times: --at was named ("needs 1 step times", walk 6)
        raise InputError("--v-lp", ",".join(f"{float(v):g}" for v in v_lp), "must be one load-point velocity > 0 "
                         "with --cycle", "give a constant loading, e.g. --v-lp 1, without --at")
    try:
        history = load_history(v_lp, at=at or [])
    except InputError as exc:   # the step times are --at here (their check names them v_lp at / v_lp times)
        if exc.argument in ("v_lp at", "v_lp times"):
            raise InputError("--at", ",".join(f"{float(x):g}" for x in at or []), exc.problem, exc.fix) from None
        raise
    _check_mass(spec, history.velocities)
    if cycle:
        _cycle(spec, history, precision, as_json)
        return
    if t_end is None:
        raise InputError("--t-end", None, "is missing", "give the end time of the run, e.g. --t-end 40 (or --cycle)")
    _check_steps(t_end, at)
    if not history.velocities[0] > 0:   # the start V is the first velocity; the API's v0 is no CLI option
        raise InputError("--v-lp", ",".join(f"{v:g}" for v in history.velocities),
                         "starts with a hold (0): the slider starts sliding steadily at the first velocity",
                         "begin with a velocity > 0 and hold after it, e.g. --v-lp 1,0,1 --at 5,10")
    _check_length(spec, history.velocities, t_end)
    t = np.linspace(history.times[0], t_end, outputs)
    bound = {"max_steps": QUAD_MAX_STEPS} if precision == "quad" else {}
    r = rate_state(a=a, b=b, dc=dc, state_law=laws, k=k, v_lp=history, t=t, mass=mass, damping=damping,
                   precision=precision, progress=_progress(t_end), **bound)
    record = {"status": r.status, "message": r.message, "steps": r.steps, "t": r.t.tolist(),
              "mu": [float(x) for x in r.mu], "v": r.v.tolist(), "theta": r.theta.tolist(),
              "slip": [float(x) for x in r.slip], "extrema": r.extrema.tolist()}
    if as_json:
        echo_json(record)
        return
    click.echo(f"status {r.status} ({r.steps} steps) {r.message}")
    click.echo(f"{'t':>12s} {'mu':>20s} {'V':>24s}")
    for ti, mi, vi in zip(record["t"], record["mu"], record["v"]):
        click.echo(f"{ti:12.6g} {mi:20.16f} {vi:24.17g}")


def _progress(t_end):
    """``progress(t, steps)`` printing a line on stderr every PROGRESS_SECONDS of a long run."""
    import time

    last = [time.monotonic()]

    def say(t: float, steps: int) -> None:
        now = time.monotonic()
        if now - last[0] >= PROGRESS_SECONDS:
            last[0] = now
            click.echo(f"bifurcation: rate-state: t = {t:.6g} of {t_end:g} ({100 * t / t_end:.0f} %), "
                       f"{steps} Taylor steps", err=True)
    return say


def _cycle(spec, history, precision, as_json) -> None:
    """``rate-state --cycle``: the attracting cycle, or its absence as a status (one line, exit 2)."""
    import math

    from ..errors import InputError
    from ..models.rate_state.cycle import limit_cycle
    from ._common import fail

    if len(history.velocities) != 1 or not history.velocities[0] > 0:
        raise InputError("--v-lp", list(history.velocities), "must be one load-point velocity > 0 with --cycle",
                         "give a constant loading, e.g. --v-lp 1, without --at")
    if precision != "double":
        raise InputError("--precision", precision, "is not available with --cycle",
                         "leave --precision at double (real128 is for verification runs)")
    from ..models.rate_state.hopf import hopf_point

    try:   # no Hopf point, no cycle: refused before any run, naming the option (was JSON on stdout and "--cycle:
        # no-hopf-point: no limit cycle: sums to <= a", naming none; walk 6). The same call limit_cycle makes first.
        hopf_point(a=spec.a, b=spec.b, dc=spec.dc, state_law=spec.state_law, v_lp=history.velocities[0],
                   mass=spec.mass, damping=spec.damping, dps=30, lyapunov=False)
    except InputError as exc:
        option = {"b": "--b", "damping": "--damping", "mass": "--mass", "v_lp": "--v-lp"}.get(exc.argument, exc.argument)
        value = ",".join(f"{x:g}" for x in exc.value) if isinstance(exc.value, tuple) else exc.value
        raise InputError(option, value, exc.problem + " (so no limit cycle)", exc.fix) from None
    import heyoka

    # a run that blows up (a status here) makes heyoka log a warning about the non-finite step
    heyoka.set_logger_level_error()
    c = limit_cycle(spec, history.velocities[0], progress=_Progress("--cycle"))
    record = c.to_record()
    if as_json:
        echo_json(record)
    if c.status != "limit-cycle":
        fail(f"--cycle: {c.status}: {c.message}")
    if not as_json:
        for key, value in record.items():
            if isinstance(value, float) and math.isfinite(value):
                click.echo(f"{key:16s} {value:.17g}")
            else:
                click.echo(f"{key:16s} {value}")


class _Progress:
    """One line on stderr at most every ``PERIOD`` seconds, none in a run's first ``PERIOD`` (quick runs, and
    a status reached quickly, stay one line; a long transient or event-split search — up to ~1 min, e.g. slip
    law, M = 10, k = 0.1 — says what it is doing)."""

    PERIOD = 10.0

    def __init__(self, what: str) -> None:
        import time

        self.what, self.clock = what, time.monotonic
        self.next = self.clock() + self.PERIOD

    def __call__(self, text: str) -> None:
        now = self.clock()
        if now >= self.next:
            self.next = now + self.PERIOD
            click.echo(f"bifurcation: {self.what}: {text}", err=True)


@click.command("continue", epilog=examples(
    'bifurcation continue workflows/rate-state-quick.toml --out results/local/rate-state-quick'))
@click.argument("workflow")
@click.option("--out", default=None,
              help="Output directory (default results/local/<study name>/; the committed reference of "
                   "workflows/rate-state.toml is results/rate-state: `--out results/rate-state --force` rewrites it).")
@click.option("--damping", default=None, callback=number("--damping", "0.002"),
              help="Radiation damping ETA >= 0 for every branch (replaces the workflow's damping keys).")
@click.option("--force", is_flag=True,
              help="Replace an earlier run in an --out you give (the default --out is replaced on every run).")
def continue_cmd(workflow: str, out, damping, force: bool) -> None:
    """Continue cycles of the rate-state slider from its Hopf points: store, report, figure."""
    from ..models.rate_state.spec import _finite
    from ..models.rate_state.study import check_damping, load_study, run_study

    from ._common import check_replace, check_writable_dir

    study = load_study(workflow)  # validate before anything is computed or written
    if damping is not None:
        damping = _finite("--damping", damping, nonnegative=True, fix="give a radiation damping >= 0 (0: none)")
        for branch in study.branches:
            check_damping(branch, damping, "--damping")
    # and where it goes (run_study's default)
    check_writable_dir(out if out is not None else f"results/local/{study.name}")
    check_replace(out, ("REPORT.md", "branches.zarr", "bifurcation-diagram.png"), given=out is not None, force=force)
    run_study(workflow, out, echo=click.echo, damping=damping)


COMMANDS = [continue_cmd, hopf_cmd, rate_state_cmd]
