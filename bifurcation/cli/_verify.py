"""``verify``: check every chunk of a store, and ``--repair`` the damaged tiles."""

from __future__ import annotations

import sys

import click

from . import _options as O
from ._common import echo_json, examples

__all__ = ["COMMANDS"]


@click.command("verify", epilog=examples(
    'bifurcation verify --store results/paper-fig3.zarr'))
@O.STORE
@click.option("--repair", is_flag=True, help="Recompute exactly the damaged tiles (and restore lost metadata).")
@O.SCHEDULER
@O.WORKERS
@O.JSON
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
