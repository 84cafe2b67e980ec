"""Engine subcommands: ``laws``, ``slip``, ``limit``, ``bench``."""

from __future__ import annotations

import click

from . import _options as O
from ._common import Whole, echo_json, examples, format_value, quiet_heyoka

__all__ = ["COMMANDS"]



@click.command("laws", epilog=examples(
    'bifurcation laws'))
@O.JSON
def laws(as_json: bool) -> None:
    """List the named friction laws with their equations and sources."""
    from ..laws import law_names, resolve_law

    rows = [resolve_law(n) for n in law_names()]
    if as_json:
        echo_json([{"name": l.name, "formula": l.formula, "equation": l.equation, "source": l.source}
                   for l in rows])
        return
    for l in rows:
        click.echo(f"{l.name:18s} {l.equation}\n{'':18s} {l.source}")
    click.echo("\nOr give --law a formula in x, e.g. 'exp(-x)', '1/sqrt(1+2*x)', 'piecewise(1 - x, 1, 0)'.")


def _print_point(record: dict, keys, as_json: bool) -> None:
    if as_json:
        echo_json(record)
        return
    for k in keys:
        if k in record:
            click.echo(f"{k:18s} {format_value(record[k])}")


@click.command("slip", epilog=examples(
    'bifurcation slip --law carlson-langer --nu 1e-9 --nu-f 0.4',
    "bifurcation slip --law 'exp(-x)' --nu 1e-12 --nu-f 0.3 --json"))
@O.LAW
@O.NU
@O.NU_F
@O.PRECISION
@O.JSON
def slip_cmd(law: str, nu: float, nu_f: float, precision: str, as_json: bool) -> None:
    """One slip cycle at (ν, ν_f): Δ, T, t1, slip duration, max velocity, status."""
    from ..engine import FIELDS, slip

    quiet_heyoka()
    record = slip(law, nu=nu, nu_f=nu_f, precision=precision).to_records()[0]
    record["precision"] = precision
    _print_point(record, ("law", "nu", "nu_f", *FIELDS, "steps", "status", "message"), as_json)


@click.command("limit", epilog=examples(
    'bifurcation limit --law piecewise-linear --nu-f 0.5 --json'))
@O.LAW
@O.NU_F
@O.PRECISION
@O.JSON
def limit_cmd(law: str, nu_f: float, precision: str, as_json: bool) -> None:
    """The ν → 0 limit at ν_f, computed directly on the ν = 0 flow: Δ0 and more."""
    from ..engine import LIMIT_FIELDS, limit

    quiet_heyoka()
    record = limit(law, nu_f=nu_f, precision=precision).to_records()[0]
    _print_point(record, ("law", "nu_f", *LIMIT_FIELDS, "status", "message"), as_json)


def _suites() -> list[str]:
    """The bench suites: the models that declare a ``bench`` hook (``engine``: the single block's old name)."""
    from ..models import get_model, model_names

    return [name for name in model_names() if get_model(name).hooks.bench]


@click.command("bench", epilog=examples(
    'bifurcation bench --points 200 --subset 2'))
@click.option("--points", default=2000, show_default=True, type=Whole(1, 20_000, "2000"),
              help="Grid points for the engine timing (1 to 20000: a benchmark is seconds, not a study).")
@click.option("--subset", default=12, show_default=True, type=Whole(1, 1000, "12"),
              help="Points for the slow baselines (DOP853), 1 to 1000.")
@click.option("--pipeline", "pipeline_points", default=0, show_default=True, type=Whole(0, 1_000_000, "0"),
              help="Also time the Dask pipeline on this many points (0: skip; at most 10^6).")
@click.option("--suite", type=click.Choice(["engine", *_suites()]), default="engine", show_default=True,
              help="A model whose declaration has a bench hook; engine (the single block): the engine vs "
                   "compiled DOP853; rate-state: rsfmodel's cases vs compiled LSODA, deep cycles vs LSODA; chain: the chain vs RK4; "
                   "rs-chain: vs a compiled (numba) DOP853 and scipy LSODA.")
@O.JSON
def bench(points: int, subset: int, pipeline_points: int, suite: str, as_json: bool) -> None:
    """Benchmarks, side by side in one run, reported as ratios (never a test)."""
    import importlib.util
    import inspect

    from ..errors import InputError
    from ..models import DEFAULT_MODEL, get_model

    model = get_model(DEFAULT_MODEL if suite == "engine" else suite)
    run = model.hook("bench")
    options = {"points": points, "subset": subset, "pipeline_points": pipeline_points}
    accepted = inspect.signature(run).parameters
    ctx = click.get_current_context()
    for name, flag in (("points", "--points"), ("subset", "--subset"), ("pipeline_points", "--pipeline")):
        # an option given on the command line that this suite does not take would be silently ignored
        if name not in accepted and ctx.get_parameter_source(name) is not click.core.ParameterSource.DEFAULT:
            raise InputError(flag, options[name], f"does not apply to --suite {suite} (its cases are fixed)",
                             f"drop {flag}, or use --suite engine")
    # after the arguments (an option that does not apply is the first thing to say)
    missing = [m for m in model.hooks.bench_needs if importlib.util.find_spec(m) is None]
    if missing:
        raise click.UsageError(f"the {suite} benchmark's baselines need {', '.join(missing)}; install them with "
                               "python -m pip install -e \".[bench]\"")
    # a suite that says what it is doing (minutes between its result lines; numba's first compile) says it on stderr
    options["progress"] = lambda text: click.echo(f"bifurcation: bench: {text}", err=True)
    report = run(echo=None if as_json else click.echo, **{k: v for k, v in options.items() if k in accepted})
    if as_json:
        echo_json(report)


COMMANDS = [laws, slip_cmd, limit_cmd, bench]
