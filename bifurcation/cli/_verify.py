"""``verify``: check every chunk of a store, and ``--repair`` the damaged tiles."""

from __future__ import annotations

import sys

import click

from ._common import echo_json

__all__ = ["COMMANDS"]


@click.command("verify")
@click.option("--store", metavar="PATH", required=True, help="A store written by `bifurcation submit`.")
@click.option("--repair", is_flag=True, help="Recompute exactly the damaged tiles (and restore lost metadata).")
@click.option("--scheduler", metavar="ADDRESS|SCHEDULER_FILE", default=None,
              help="With --repair: the Dask scheduler (default as for submit).")
@click.option("--workers", type=int, default=None, help="With --repair: workers, as for submit.")
@click.option("--json", "as_json", is_flag=True, help="Print the report as JSON.")
def verify_cmd(store: str, repair: bool, scheduler, workers, as_json: bool) -> None:
    """Check every chunk's checksum and that `done` agrees with the data; exit 1 if damage is left."""
    from ..run.repair import verify

    report = verify(store, repair=repair, scheduler=scheduler, workers=workers)
    if as_json:
        echo_json(report.to_dict())
    else:
        click.echo(str(report))
    if not report.ok:
        sys.exit(1)


COMMANDS = [verify_cmd]
