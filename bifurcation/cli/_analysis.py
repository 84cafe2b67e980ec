"""Analysis subcommands: ``extrapolate``, ``fit-period``, ``report`` and ``reproduce`` (the main job)."""

from __future__ import annotations

import contextlib
import sys
import time
from pathlib import Path

import click

from . import _options as O
from ._common import echo_json, examples, fail, number
from ..errors import shown_path

__all__ = ["COMMANDS", "PAPER_WORKFLOWS"]

#: The paper's workflows, run by ``bifurcation reproduce`` (files in the repository's workflows/).
PAPER_WORKFLOWS = ("paper-fig2.toml", "paper-fig3.toml", "critical-point.toml")
#: What marks a directory as holding a report already (`report`, `reproduce`): refused without --force.
REPORT_FILES = ("REPORT.md", "report.html")


@contextlib.contextmanager
def _with_options(message_names: dict):
    """Report an analysis InputError as one line, with the option names the user typed."""
    from ..errors import InputError

    try:
        yield
    except InputError as exc:
        fail(exc.line(message_names.get(exc.argument, exc.argument)))


_STORE = click.option("--store", "stores", metavar="PATH", multiple=True, required=True,
                      help="A store written by `bifurcation submit`, or a directory of stores (repeatable).")
_LAW = click.option("--law", required=True, help="Law label in the store, e.g. carlson-langer.")
_NU_F = click.option("--nu-f", "nu_f", required=True, callback=number("--nu-f"), help="Friction velocity ν_f.")
_JSON = O.JSON
_NEAREST = O.NEAREST
_NAMES = {"nu_f": "--nu-f", "law": "--law", "store": "--store", "nu": "--store (ν values)"}


def _stores(paths):
    import os

    from ..analysis import load_stores
    from ..errors import InputError

    seen = set()
    for path in paths:   # the same store twice made a report of it twice, section for section (found at review)
        real = os.path.realpath(path)
        if real in seen:
            raise InputError("--store", path, "is given twice", "give each store once")
        seen.add(real)
    with _with_options(_NAMES):
        return load_stores(list(paths))


def _analyse(fn, stores, law: str, nu_f: float, as_json: bool, nearest: bool):
    """``fn(stores, law, nu_f)`` with option-named errors; with ``--json`` print its summary and return
    None, else return the result for the command to print."""
    from ..errors import InputError

    sources = _stores(stores)
    with _with_options(_NAMES):
        try:
            result = fn(sources, law, nu_f, nearest=nearest)
        except InputError as exc:   # the analysis names the stores' model; the user typed their paths
            if exc.argument != "store" or not str(exc.value).startswith("model "):
                raise
            raise InputError("store", ", ".join(stores), f"is a {exc.value} store: it {exc.problem}",
                             exc.fix) from None
    if result.nu_f != nu_f:
        click.echo(f"bifurcation: note: --nu-f {nu_f!r} is not a label; took the nearest, {result.nu_f!r}",
                   err=True)
    if as_json:
        echo_json(result.summary())
        return None
    return result


@click.command("extrapolate", epilog=examples(
    'bifurcation extrapolate --store results/critical-point.zarr --law carlson-langer --nu-f 0.5'))
@_STORE
@_LAW
@_NU_F
@_JSON
@_NEAREST
def extrapolate(stores, law: str, nu_f: float, as_json: bool, nearest: bool) -> None:
    """Δ(ν → 0) at ν_f extrapolated from the store's finite-ν points, vs the direct limit and the paper."""
    from ..analysis import extrapolate_delta

    ex = _analyse(extrapolate_delta, stores, law, nu_f, as_json, nearest)
    if ex is None:
        return
    paper = "—" if ex.paper_value is None else f"{ex.paper_value:.10g}  ({ex.paper_source})"
    nu_f = ex.nu_f
    click.echo(f"{law} at ν_f = {nu_f:g} ({ex.regime}; variable {ex.variable}; {ex.nu.size} points)")
    click.echo(f"delta0_extrapolated  {ex.delta0_extrapolated:.12g} ± {ex.uncertainty:.2g}")
    click.echo(f"delta0_direct        {ex.delta0_direct:.16g} (± {ex.delta0_direct_error:.1g})")
    click.echo(f"paper_value          {paper}")
    agree = "consistent" if ex.consistent else "INCONSISTENT"
    click.echo(f"extrapolated − direct {ex.deviation:+.2g}  ({agree})")


@click.command("fit-period", epilog=examples(
    'bifurcation fit-period --store results/critical-point.zarr --law piecewise-linear --nu-f 0.3 --json'))
@_STORE
@_LAW
@_NU_F
@_JSON
@_NEAREST
def fit_period(stores, law: str, nu_f: float, as_json: bool, nearest: bool) -> None:
    """Fit T − Δ0/ν = (α−ω) ln(1/ν) + C0 + K ν^−r + … (ν_f < 1/2) and compare the log coefficient with α − ω."""
    from ..analysis import fit_period as fit

    f = _analyse(fit, stores, law, nu_f, as_json, nearest)
    if f is None:
        return
    nu_f = f.nu_f
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


@click.command("report", epilog=examples(
    'bifurcation report --store results/paper-fig3.zarr --out results/local/my-report'))
@_STORE
@click.option("--out", "out", metavar="DIR", required=True, help="Directory for REPORT.md, report.html, PNGs.")
@click.option("--force", is_flag=True, help="Replace an earlier report in --out (default: refuse).")
@O.JSON
def report(stores, out: str, force: bool, as_json: bool) -> None:
    """Report what one or more stores hold (model, laws, axes, transition, fits, figures) into DIR."""
    from ..report import write_store_report
    from ._common import check_replace, check_writable_dir

    check_writable_dir(out)   # before the analysis, not after it (and nothing made if a store is refused)
    check_replace(out, REPORT_FILES, given=True, force=force)
    sources = _stores(stores)
    with _with_options(_NAMES), _undone_on_error(out), _stages("report") as progress:
        files = write_store_report(sources, out, progress=progress)
    if as_json:
        echo_json(_written(files))
        return
    click.echo(f"wrote {shown_path(files['markdown'])}, {shown_path(files['html'])} and {len(files['figures'])} figure{'' if len(files['figures']) == 1 else 's'}")


#: Seconds without a new stage before a line says the current one is still running, and between them.
STILL_SECONDS = 30.0
#: Seconds a command runs before its stages are shown: a short report (or an error found at once, which
#: stays one line on stderr) prints none.
QUIET_SECONDS = 5.0


@contextlib.contextmanager
def _stages(label: str):
    """A ``progress(text)`` for a long command: after QUIET_SECONDS each stage is a line on stderr with the
    elapsed time, and while one stage lasts (a Clauset fit of 10^5 sizes: minutes) a line every STILL_SECONDS
    says it still runs. (``report`` of the rs-chain study's store printed nothing for ~150 s, issue 21 walk 4.)"""
    import threading

    started = time.perf_counter()
    state = {"stage": None, "since": started, "shown": False}
    lock = threading.Lock()

    def show(now: float, still: bool = False) -> None:
        state["shown"] = True
        # the repeat names the stage without its parenthesised detail (said once, on its first line)
        stage = state["stage"].split(" (", 1)[0] if still else state["stage"]
        click.echo(f"bifurcation: {label}: {'still running: ' if still else ''}{stage} "
                   f"[{now - started:.0f} s]", err=True)

    def progress(text: str) -> None:
        with lock:
            now = time.perf_counter()
            state.update(stage=text, since=now, shown=False)
            if now - started >= QUIET_SECONDS:
                show(now)

    stop = threading.Event()

    def watch() -> None:
        while not stop.wait(max(0.05, min(STILL_SECONDS, QUIET_SECONDS or STILL_SECONDS) / 3)):
            with lock:
                now = time.perf_counter()
                if state["stage"] is None or now - started < QUIET_SECONDS:
                    continue
                if not state["shown"]:
                    show(now)
                elif now - state["since"] >= STILL_SECONDS:
                    state["since"] = now
                    show(now, still=True)

    thread = threading.Thread(target=watch, name=f"{label}-stages", daemon=True)
    thread.start()
    try:
        yield progress
    finally:
        stop.set()
        thread.join()


@contextlib.contextmanager
def _undone_on_error(out) -> None:
    """A report that fails part way (a damaged chunk met while drawing) leaves --out as it found it: the
    directory removed if this run made it, else the files this run added (an empty --out was left behind
    by a store whose catalog metadata was cut, issue 21 walk 3)."""
    import shutil

    out = Path(out)
    existed = out.is_dir()
    before = set(out.iterdir()) if existed else set()
    try:
        yield
    except BaseException:
        if not existed:
            shutil.rmtree(out, ignore_errors=True)
        else:
            for path in set(out.iterdir()) - before:
                shutil.rmtree(path, ignore_errors=True) if path.is_dir() else path.unlink(missing_ok=True)
        raise


def _written(files: dict) -> dict:
    """The files a report wrote, as JSON-ready paths."""
    return {"markdown": str(files["markdown"]), "html": str(files["html"]),
            "figures": [str(f) for f in files["figures"]]}


def _workflow_dir() -> Path:
    here = Path(__file__).resolve().parents[2] / "workflows"
    if not all((here / w).is_file() for w in PAPER_WORKFLOWS):
        fail(f"the paper workflows ({', '.join(PAPER_WORKFLOWS)}) are not in {here}; run `bifurcation "
             "reproduce` from a clone of the repository (pip install -e .)")
    return here


@click.command("reproduce", epilog=examples(
    'bifurcation reproduce --out results/local/my-paper-report'))
@click.option("--out", default="results/local/paper", show_default=True, metavar="DIR",
              help="Where the report goes (the stores go to results/<study>.zarr). The committed "
                   "reference is results/paper: `--out results/paper --force` rewrites it.")
@O.SCHEDULER
@O.WORKERS
@click.option("--new-stores", is_flag=True,
              help="Replace a results/<study>.zarr that holds an older version of a paper workflow.")
@click.option("--force", is_flag=True,
              help="Replace an earlier report in an --out you give (the default --out is replaced on every run).")
@O.JSON
def reproduce(out: str, scheduler, workers, new_stores: bool, force: bool, as_json: bool) -> None:
    """Run the paper's workflows (resumable) and write the report to DIR: the main job."""
    from ..errors import InputError
    from ..report import write_report
    from ..run import submit
    from ..run.cluster import check_scheduler, check_workers, connect

    from ._common import check_replace, check_writable_dir

    started = time.perf_counter()
    target = check_scheduler(scheduler)
    workers = check_workers(workers, embedded=target is None)
    check_writable_dir(out)
    given = click.get_current_context().get_parameter_source("out") is not click.core.ParameterSource.DEFAULT
    check_replace(out, REPORT_FILES, given=given, force=force)
    workflows = _workflow_dir()
    stores, summaries = [], []
    # One cluster for the three workflows (starting an embedded one costs ~1 s and compiles per worker).
    with connect(target, workers) as client:
        for name in PAPER_WORKFLOWS:
            try:
                summary = submit(workflows / name, scheduler=client, new_store=new_stores)
            except InputError as exc:
                fail(f"{name}: {exc.line()} (or run "
                     "`bifurcation reproduce --new-stores` to recompute the paper's stores)")
            if not as_json:
                click.echo(str(summary))
            summaries.append(summary.to_dict())
            if summary.failed:
                click.echo(f"bifurcation: {summary.failed} points of {name} failed; run `bifurcation "
                           "reproduce` again to retry them", err=True)
                sys.exit(1)
            stores.append(summary.store)
    files = write_report(stores, out)
    if as_json:
        echo_json({"submits": summaries, "report": _written(files),
                   "wall_time": round(time.perf_counter() - started, 3)})
        return
    click.echo(f"wrote {shown_path(files['markdown'])} (and report.html, {len(files['figures'])} figure{'' if len(files['figures']) == 1 else 's'}) in "
               f"{time.perf_counter() - started:.1f} s")


COMMANDS = [extrapolate, fit_period, report, reproduce]
