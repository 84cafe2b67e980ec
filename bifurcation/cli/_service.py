"""Service subcommands: ``submit`` (a workflow onto Dask, into a store) and ``query`` (a store by label)."""

from __future__ import annotations

import sys

import click

from . import _options as O
from ._common import Real, echo_json, examples, fail, number

__all__ = ["COMMANDS"]


def _numbers(name: str, words: tuple = (), example: str = "1e-9"):
    """``_common.number`` for a repeatable option: each value parsed, the same message for a bad one
    (its example the axis's own: ``--n`` suggested 1e-9 before); ``words`` (a choice axis's names, e.g.
    free/periodic) are taken as the index they name."""
    one = number(name, f"{words[0]} or 0" if words else example)

    def convert(ctx, param, values):
        return tuple(float(words.index(v)) if v in words else one(ctx, param, value)
                     for value in values for v in [str(value).strip()])

    return convert


@click.command("submit", epilog=examples(
    'bifurcation submit workflows/paper-fig3.toml --workers 2',
    'bifurcation submit workflows/critical-point.toml --workers 2',
    'bifurcation submit workflows/chain-study.toml --workers 2'))
@click.argument("workflow", metavar="WORKFLOW")
@click.option("--store", metavar="PATH", default=None,
              help="Zarr store (default: results/<study name>.zarr). Resumed if it holds this workflow.")
@O.SCHEDULER
@O.WORKERS
@click.option("--workers-timeout", type=Real(example="120"), default=None, metavar="SECONDS",
              help="With --scheduler and --workers N: how long to wait for N workers (default 120).")
@click.option("--new-store", is_flag=True, help="Replace an existing store that holds another workflow.")
@O.WRITE_FROM
@click.option("--dashboard", is_flag=True,
              help="Serve Dask's dashboard from the embedded cluster (port 8787 or the next free one).")
@click.option("--detach", is_flag=True,
              help="With --scheduler: hand the study to the cluster and return; the workers finish it "
                   "(follow with `bifurcation status`).")
@O.JSON
def submit_cmd(workflow: str, store, scheduler, workers, workers_timeout, new_store: bool, writer: str,
               dashboard: bool, detach: bool, as_json: bool) -> None:
    """Compute the missing points of WORKFLOW (a TOML file) on Dask into a Zarr store.

    A submit of a workflow already in the store resumes it; one that finds a detached run of it
    (--detach) joins it: waits for it, then computes what is left.
    """
    from ..run import submit
    from ._common import check_outside_stores

    if store is not None:   # a store inside another store would be lost or taken for damage with it
        check_outside_stores(store, "--store", itself=False)
    summary = submit(workflow, store=store, scheduler=scheduler, workers=workers, new_store=new_store,
                     writer=writer, workers_timeout=workers_timeout, dashboard=dashboard, detach=detach)
    if as_json:
        echo_json(summary.to_dict())
    else:
        click.echo(str(summary))
    if summary.failed:
        click.echo(f"bifurcation: {summary.failed} points failed; submit again to retry them", err=True)
        sys.exit(1)


def _axis_options(command):
    """One repeatable option per axis of every registered model (``--nu``, ``--nu-f``, ``--gamma``),
    from the models' declarations: a new model's axes appear here without a change to the CLI."""
    from ..models import get_model, model_names

    seen = {}
    for name in model_names():
        for axis in get_model(name).axes:
            seen.setdefault(axis.name, axis)
    for axis in reversed(list(seen.values())):
        words = f" or {'/'.join(axis.names)}" if axis.names else ""
        command = click.option(axis.option, axis.name, multiple=True, callback=_numbers(axis.option, axis.names, _example(axis)),
                               help=f"{axis.symbol}: a label of the store{words} (repeatable). Default: all.")(command)
    return command


def _example(axis) -> str:
    """An axis's example as a user types it: an integer for an integer axis (``--n 16``)."""
    if axis.dtype == "int64":
        return str(int(axis.example))
    return f"{axis.example:g}".replace("e-0", "e-").replace("e+0", "e+")    # 1e-9, not 1e-09


def _option_names() -> dict:
    from ..models import get_model, model_names

    names = {"store": "--store", "law": "--law"}
    for name in model_names():
        names.update({axis.name: axis.option for axis in get_model(name).axes})
    return names


@click.command("query", epilog=examples(
    'bifurcation query --store results/paper-fig3.zarr --nu 1e-9 --nu-f 0.4',
    'bifurcation query --store results/paper-fig3.zarr --nu-f 0.4 --json',
    'bifurcation query --store results/chain-study.zarr --n 16 --nu-f 0.2 --catalog'))
@O.STORE
@click.option("--law", multiple=True, help="Law label (repeatable; a formula matches by its expression). Default: all.")
@_axis_options
@O.NEAREST
@O.FORMAT
@click.option("--json", "as_json", is_flag=True, help="Print JSON (the same as --format json).")
@click.option("--done-only", is_flag=True, help="Only points already computed.")
@click.option("--catalog", is_flag=True,
              help="Print the per-event catalog of the one run selected (a chain store): one row per event.")
def query_cmd(store: str, law, nearest: bool, fmt: str, as_json: bool, done_only: bool, catalog: bool,
              **axes) -> None:
    """Print the points of a store selected by law and by the axes of its model (exact labels; streamed:
    memory independent of the store)."""
    from ..errors import InputError
    from ..store.query import iter_records, write_records

    if as_json:
        if fmt not in ("table", "json"):
            fail(f"--json and --format {fmt} ask for two formats; give one")
        fmt = "json"

    notes: list[str] = []
    if catalog:
        return _print_catalog(store, law, nearest, fmt, notes, axes)
    try:   # the selection and every selected chunk are checked here, before any output
        records = iter_records(store, law=law or None, computed_only=done_only, nearest=nearest, notes=notes,
                               **{k: v for k, v in axes.items() if v})
    except InputError as exc:
        _fail_as_option(exc)
    for note in notes:
        click.echo(f"bifurcation: note: {note}", err=True)
    write_records(records, fmt, sys.stdout, law_width=records.law_width)


def _fail_as_option(exc) -> None:
    """A selection error named by the option as the user typed it (``--nu-f``, not ``nu_f``)."""
    name = _option_names().get(exc.argument)
    if name is None:
        raise exc
    fail(exc.line(name))


def _print_catalog(store, law, nearest, fmt, notes, axes) -> None:
    """``query --catalog``: the run's record on stderr (table, CSV) or in the JSON, then one row per event."""
    from ..errors import InputError
    from ..store.catalog import read_catalog
    from ..store.query import write_records

    try:
        out = read_catalog(store, law=list(law) or None, nearest=nearest, notes=notes,
                           **{k: list(v) for k, v in axes.items() if v})
    except InputError as exc:
        _fail_as_option(exc)
    for note in notes:
        click.echo(f"bifurcation: note: {note}", err=True)
    run = out.pop("run")
    if fmt == "json":
        echo_json({"run": run, **{k: v.tolist() for k, v in out.items()}})
        return
    click.echo("run: " + ", ".join(f"{k} = {v}" for k, v in run.items()), err=True)
    if "hypocentre" in out:
        click.echo("events and hypocentres count from 0 (hypocentre 0 is block j = 1 of docs/chain.md)", err=True)
    keys = ("event", *out)
    count = len(next(iter(out.values())))
    rows = ({"event": i, **{k: v[i].item() for k, v in out.items()}} for i in range(count))
    write_records(rows, fmt, sys.stdout, law_width=5, keys=keys)


COMMANDS = [submit_cmd, query_cmd]
