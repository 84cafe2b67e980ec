"""Analysis subcommands: ``extrapolate``, ``fit-period``, ``report`` and ``reproduce`` (the main job)."""

from __future__ import annotations

import contextlib
import sys
import time
from pathlib import Path

import click

from ._common import echo_json, fail, number

__all__ = ["COMMANDS", "PAPER_WORKFLOWS"]

#: The paper's workflows, run by ``bifurcation reproduce`` (files in the repository's workflows/).
PAPER_WORKFLOWS = ("paper-fig2.toml", "paper-fig3.toml", "critical-point.toml")


@contextlib.contextmanager
def _with_options(message_names: dict):
    """Report an analysis InputError as one line, with the option names the user typed."""
    from ..errors import InputError

    try:
        yield
    except InputError as exc:
        fail(f"{message_names.get(exc.argument, exc.argument)}={exc.value!r}: {exc.problem}; {exc.fix}")


_STORE = click.option("--store", "stores", metavar="PATH", multiple=True, required=True,
                      help="A store written by `bifurcation submit`, or a directory of stores (repeatable).")
_LAW = click.option("--law", required=True, help="Law label in the store, e.g. carlson-langer.")
_NU_F = click.option("--nu-f", "nu_f", required=True, callback=number("--nu-f"), help="Friction velocity ν_f.")
_JSON = click.option("--json", "as_json", is_flag=True, help="Print one JSON object.")
_NAMES = {"nu_f": "--nu-f", "law": "--law", "store": "--store", "nu": "--store (ν values)"}


def _stores(paths):
    from ..analysis import load_stores

    with _with_options(_NAMES):
        return load_stores(list(paths))


def _analyse(fn, stores, law: str, nu_f: float, as_json: bool):
    """``fn(stores, law, nu_f)`` with option-named errors; with ``--json`` print its summary and return
    None, else return the result for the command to print."""
    sources = _stores(stores)
    with _with_options(_NAMES):
        result = fn(sources, law, nu_f)
    if as_json:
        echo_json(result.summary())
        return None
    return result


@click.command("extrapolate")
@_STORE
@_LAW
@_NU_F
@_JSON
def extrapolate(stores, law: str, nu_f: float, as_json: bool) -> None:
    """Δ(ν → 0) at ν_f extrapolated from the store's finite-ν points, vs the direct limit and the paper."""
    from ..analysis import extrapolate_delta

    ex = _analyse(extrapolate_delta, stores, law, nu_f, as_json)
    if ex is None:
        return
    paper = "—" if ex.paper_value is None else f"{ex.paper_value:.10g}  ({ex.paper_source})"
    click.echo(f"{law} at ν_f = {nu_f:g} ({ex.regime}; variable {ex.variable}; {ex.nu.size} points)")
    click.echo(f"delta0_extrapolated  {ex.delta0_extrapolated:.12g} ± {ex.uncertainty:.2g}")
    click.echo(f"delta0_direct        {ex.delta0_direct:.16g} (± {ex.delta0_direct_error:.1g})")
    click.echo(f"paper_value          {paper}")
    agree = "consistent" if ex.consistent else "INCONSISTENT"
    click.echo(f"extrapolated − direct {ex.deviation:+.2g}  ({agree})")


@click.command("fit-period")
@_STORE
@_LAW
@_NU_F
@_JSON
def fit_period(stores, law: str, nu_f: float, as_json: bool) -> None:
    """Fit T − Δ0/ν = (α−ω) ln(1/ν) + C0 + K ν^−r + … (ν_f < 1/2) and compare the log coefficient with α − ω."""
    from ..analysis import fit_period as fit

    f = _analyse(fit, stores, law, nu_f, as_json)
    if f is None:
        return
    click.echo(f"{law} at ν_f = {nu_f:g}: r = (α−ω)² = {f.exponent_r:.6f}, window ν ≤ {f.nu_max:g}, "
               f"{f.n_points} points, {len(f.model)} terms")
    click.echo(f"log_coefficient          {f.log_coefficient:.10f} ± {f.log_coefficient_uncertainty:.1g}")
    click.echo(f"log_coefficient_expected {f.log_coefficient_expected:.10f}  (α − ω; rel. deviation "
               f"{f.relative_deviation:+.1e})")
    for label, value in f.terms.items():
        if label != "ln(1/nu)":
            click.echo(f"  {label:22s} {value:+.8g} ± {f.term_errors[label]:.2g}")
    click.echo(f"residual_max             {f.residual_max:.3g}  (max residual/error {f.chi_max:.2f})")
    if f.resonance_note:
        click.echo(f"note: {f.resonance_note}")


@click.command("report")
@_STORE
@click.option("--out", "out", metavar="DIR", required=True, help="Directory for REPORT.md, report.html, PNGs.")
def report(stores, out: str) -> None:
    """Write the report (claims table, errata, fits, figures) from one or more stores into DIR."""
    from ..report import write_report
    from ._common import check_out_dir

    check_out_dir(out)   # before the analysis, not after it
    sources = _stores(stores)
    files = write_report(sources, out)
    click.echo(f"wrote {files['markdown']}, {files['html']} and {len(files['figures'])} figures")


def _workflow_dir() -> Path:
    here = Path(__file__).resolve().parents[2] / "workflows"
    if not all((here / w).is_file() for w in PAPER_WORKFLOWS):
        fail(f"the paper workflows ({', '.join(PAPER_WORKFLOWS)}) are not in {here}; run `bifurcation "
             "reproduce` from a clone of the repository (pip install -e .)")
    return here


@click.command("reproduce")
@click.option("--out", default="results/paper", show_default=True, metavar="DIR",
              help="Where the report goes (the stores go to results/<study>.zarr).")
@click.option("--scheduler", metavar="ADDRESS|SCHEDULER_FILE", default=None,
              help="Dask scheduler; default $DASK_SCHEDULER_ADDRESS, else an embedded local cluster.")
@click.option("--workers", type=int, default=None, help="Embedded cluster: worker processes (default: cores).")
@click.option("--new-stores", is_flag=True,
              help="Replace a results/<study>.zarr that holds an older version of a paper workflow.")
def reproduce(out: str, scheduler, workers, new_stores: bool) -> None:
    """Run the paper's workflows (resumable) and write the report to DIR: the main job."""
    from ..errors import InputError
    from ..report import write_report
    from ..run import submit
    from ..run.cluster import check_scheduler, check_workers, connect

    from ._common import check_out_dir

    started = time.perf_counter()
    check_out_dir(out)
    workflows = _workflow_dir()
    stores = []
    # One cluster for the three workflows (starting an embedded one costs ~1 s and compiles per worker).
    with connect(check_scheduler(scheduler), check_workers(workers)) as client:
        for name in PAPER_WORKFLOWS:
            try:
                summary = submit(workflows / name, scheduler=client, new_store=new_stores)
            except InputError as exc:
                fail(f"{name}: {exc.argument}={exc.value!r}: {exc.problem}; {exc.fix} (or run "
                     "`bifurcation reproduce --new-stores` to recompute the paper's stores)")
            click.echo(str(summary))
            if summary.failed:
                click.echo(f"bifurcation: {summary.failed} points of {name} failed; run `bifurcation "
                           "reproduce` again to retry them", err=True)
                sys.exit(1)
            stores.append(summary.store)
    files = write_report(stores, out)
    click.echo(f"wrote {files['markdown']} (and report.html, {len(files['figures'])} figures) in "
               f"{time.perf_counter() - started:.1f} s")


COMMANDS = [extrapolate, fit_period, report, reproduce]
