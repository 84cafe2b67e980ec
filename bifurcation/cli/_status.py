"""``bifurcation status``: how far a study is, from its store alone (no cluster, no submitting process)."""

from __future__ import annotations

import click

from ._common import echo_json

__all__ = ["COMMANDS"]


@click.command("status", epilog="Example:\n\n\b\n  $ bifurcation status --store results/paper-fig3.zarr")
@click.option("--store", metavar="PATH", required=True, help="A store written by `bifurcation submit`.")
@click.option("--json", "as_json", is_flag=True, help="Print JSON.")
def status(store: str, as_json: bool) -> None:
    """Progress of the study in a store: points done per law, outcomes, failures, who writes it, rate, ETA."""
    from ..store.status import study_status

    found = study_status(store)
    if as_json:
        echo_json(found.to_dict())
    else:
        click.echo(str(found))


COMMANDS = [status]
