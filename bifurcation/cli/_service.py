"""Service subcommands: ``submit`` (a workflow onto Dask, into a store) and ``query`` (a store by label)."""

from __future__ import annotations

import sys

import click

from ._common import echo_json, fail, number

__all__ = ["COMMANDS"]


def _numbers(name: str):
    """``_common.number`` for a repeatable option: each value parsed, the same message for a bad one."""
    one = number(name, "1e-9")

    def convert(ctx, param, values):
        return tuple(one(ctx, param, value) for value in values)

    return convert


@click.command("submit")
@click.argument("workflow", metavar="WORKFLOW")
@click.option("--store", metavar="PATH", default=None,
              help="Zarr store (default: results/<study name>.zarr). Resumed if it holds this workflow.")
@click.option("--scheduler", metavar="ADDRESS|SCHEDULER_FILE", default=None,
              help="Dask scheduler (tcp://host:8786) or scheduler file. Default: $DASK_SCHEDULER_ADDRESS, "
                   "else an embedded local cluster.")
@click.option("--workers", type=int, default=None,
              help="Embedded cluster: worker processes (default: cores). With --scheduler: wait for N workers.")
@click.option("--workers-timeout", type=float, default=None, metavar="SECONDS",
              help="With --scheduler and --workers N: how long to wait for N workers (default 120).")
@click.option("--new-store", is_flag=True, help="Replace an existing store that holds another workflow.")
@click.option("--write-from", "writer", type=click.Choice(["workers", "client"]), default="workers",
              show_default=True,
              help="Who writes finished tiles: the workers (store on a filesystem all workers share) "
                   "or this process (no shared filesystem needed).")
@click.option("--dashboard", is_flag=True,
              help="Serve Dask's dashboard from the embedded cluster (port 8787 or the next free one).")
@click.option("--detach", is_flag=True,
              help="With --scheduler: hand the study to the cluster and return; the workers finish it "
                   "(follow with `bifurcation status`).")
@click.option("--json", "as_json", is_flag=True, help="Print the summary as JSON.")
def submit_cmd(workflow: str, store, scheduler, workers, workers_timeout, new_store: bool, writer: str,
               dashboard: bool, detach: bool, as_json: bool) -> None:
    """Compute the missing points of WORKFLOW (a TOML file) on Dask into a Zarr store.

    A submit of a workflow already in the store resumes it; one that finds a detached run of it
    (--detach) joins it: waits for it, then computes what is left.
    """
    from ..run import submit

    summary = submit(workflow, store=store, scheduler=scheduler, workers=workers, new_store=new_store,
                     writer=writer, workers_timeout=workers_timeout, dashboard=dashboard, detach=detach)
    if as_json:
        echo_json(summary.to_dict())
    else:
        click.echo(str(summary))
    if summary.failed:
        click.echo(f"bifurcation: {summary.failed} points failed; submit again to retry them", err=True)
        sys.exit(1)


@click.command("query")
@click.option("--store", metavar="PATH", required=True, help="A store written by `bifurcation submit`.")
@click.option("--law", multiple=True, help="Law label (repeatable). Default: all.")
@click.option("--nu", multiple=True, callback=_numbers("--nu"),
              help="ν: exact label or nearest (repeatable). Default: all.")
@click.option("--nu-f", "nu_f", multiple=True, callback=_numbers("--nu-f"),
              help="ν_f: exact label or nearest (repeatable). Default: all.")
@click.option("--format", "fmt", type=click.Choice(["table", "csv", "json"]), default="table", show_default=True)
@click.option("--done-only", is_flag=True, help="Only points already computed.")
def query_cmd(store: str, law, nu, nu_f, fmt: str, done_only: bool) -> None:
    """Print the points of a store selected by law, ν and ν_f (streamed: memory independent of the store)."""
    from ..errors import InputError
    from ..query import iter_records, write_records

    try:   # the selection and every selected chunk are checked here, before any output
        records = iter_records(store, law=law or None, nu=nu or None, nu_f=nu_f or None, computed_only=done_only)
    except InputError as exc:   # name the options as the user typed them
        name = {"store": "--store", "law": "--law", "nu": "--nu", "nu_f": "--nu-f"}.get(exc.argument)
        if name is None:
            raise
        fail(f"{name}={exc.value!r}: {exc.problem}; {exc.fix}")
    write_records(records, fmt, sys.stdout, law_width=records.law_width)


COMMANDS = [submit_cmd, query_cmd]
