"""``bifurcation status`` (how far a study is, from its store alone) and ``bifurcation export``."""

from __future__ import annotations

import click

from . import _options as O
from ._common import echo_json, examples
from ..errors import shown_path

__all__ = ["COMMANDS"]


@click.command("status", epilog=examples("bifurcation status --store results/paper-fig3.zarr"))
@O.STORE
@O.JSON
def status(store: str, as_json: bool) -> None:
    """Progress of the study in a store: points done per law, outcomes, failures, who writes it, rate, ETA."""
    from ..store.status import study_status

    found = study_status(store)
    if as_json:
        echo_json(found.to_dict())
    else:
        click.echo(str(found))


@click.command("export", epilog=examples("bifurcation export --store results/paper-fig3.zarr --out results/fig3.nc",
                                          "bifurcation export --store results/paper-fig3.zarr --out results/fig3.csv"))
@click.option("--store", metavar="PATH", required=True, help="A store written by `bifurcation submit`.")
@click.option("--out", metavar="FILE", required=True, help="The file to write: .nc (netCDF, CF) or .csv.")
@click.option("--format", "fmt", type=click.Choice(["netcdf", "csv"]), default=None,
              help="The file type (default: from the suffix of --out).")
@click.option("--force", is_flag=True, help="Replace --out if it exists (default: refuse).")
@click.option("--partial", is_flag=True,
              help="Export a store that a submit is still writing: the points done so far (default: refuse).")
@click.option("--json", "as_json", is_flag=True, help="Print what was written as JSON.")
def export_cmd(store: str, out: str, fmt, force: bool, partial: bool, as_json: bool) -> None:
    """Write a store to a netCDF (CF conventions) or CSV file that reads back to the same numbers."""
    from ..store.export import export
    from ._common import check_outside_stores

    check_outside_stores(out, itself=False)
    written = export(store, out, fmt, force=force, partial=partial)
    if as_json:
        echo_json(written)
        return
    missing = written["points"] - written["computed"]
    click.echo(f"wrote {written['points']} points to {shown_path(written['out'])} ({written['format']})"
               + (f"; {missing} of them not computed yet (empty, status not-computed): `bifurcation submit` "
                  "the store's workflow to finish it" if missing else "")
               + ("; the per-event catalogs are not in a CSV (one row per run): export to .nc for them, or "
                  "`bifurcation query --catalog`" if "catalogs" in written else ""))


COMMANDS = [status, export_cmd]
