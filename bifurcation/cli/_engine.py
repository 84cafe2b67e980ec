"""Engine subcommands: ``laws``, ``slip``, ``limit``, ``bench``."""

from __future__ import annotations

import click

from . import _options as O
from ._common import echo_json, examples, format_value

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

    record = limit(law, nu_f=nu_f, precision=precision).to_records()[0]
    _print_point(record, ("law", "nu_f", *LIMIT_FIELDS, "status", "message"), as_json)


@click.command("bench", epilog=examples(
    'bifurcation bench --points 200 --subset 2'))
@click.option("--points", default=2000, show_default=True, type=click.IntRange(1, 20_000),
              help="Grid points for the engine timing (1 to 20000: a benchmark is seconds, not a study).")
@click.option("--subset", default=12, show_default=True, type=click.IntRange(1, 1000),
              help="Points for the slow baselines (DOP853), 1 to 1000.")
@click.option("--pipeline", "pipeline_points", default=0, show_default=True, type=click.IntRange(0, 20_000),
              help="Also time the Dask pipeline on this many points (0: skip; at most 20000).")
@click.option("--suite", type=click.Choice(["engine", "rate-state", "chain"]), default="engine", show_default=True,
              help="engine: the single block vs DOP853; rate-state: rsfmodel's cases vs odeint; "
                   "chain: the exact chain vs fixed-step RK4.")
@O.JSON
def bench(points: int, subset: int, pipeline_points: int, suite: str, as_json: bool) -> None:
    """Benchmarks, side by side in one run, reported as ratios (never a test)."""
    import importlib.util

    if suite == "chain":
        from ..models.chain._bench import run_chain_bench

        report = run_chain_bench(echo=None if as_json else click.echo)
        if as_json:
            echo_json(report)
        return

    if importlib.util.find_spec("scipy") is None:
        raise click.UsageError("the benchmark's DOP853 baseline needs scipy; install it with "
                               "python -m pip install -e \".[bench]\"")
    if suite == "rate-state":
        from ..models.rate_state._bench import run_rate_state_bench

        report = run_rate_state_bench(echo=None if as_json else click.echo)
        if as_json:
            echo_json(report)
        return
    from ..bench import run_bench

    report = run_bench(points=points, subset=subset, pipeline_points=pipeline_points,
                       echo=None if as_json else click.echo)
    if as_json:
        echo_json(report)


COMMANDS = [laws, slip_cmd, limit_cmd, bench]
