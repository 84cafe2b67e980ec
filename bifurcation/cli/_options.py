"""The options shared by several subcommands, each defined once; choices come from the package's
constants (precisions, output formats, tile writers), so a new value reaches every command."""

from __future__ import annotations

import click

from ..engine._validate import PRECISIONS
from ..run.submission import WRITERS
from ..store.query import FORMATS
from ._common import Whole, number

__all__ = ["FORMAT", "JSON", "LAW", "NEAREST", "NU", "NU_F", "PRECISION", "SCHEDULER", "STORE", "WORKERS",
           "WRITE_FROM"]

JSON = click.option("--json", "as_json", is_flag=True, help="Print JSON.")
STORE = click.option("--store", metavar="PATH", required=True, help="A store written by `bifurcation submit`.")
LAW = click.option("--law", required=True, help="Law name (see `bifurcation laws`) or formula in x.")
NU = click.option("--nu", required=True, callback=number("--nu", "1e-9"), help="Pulling speed ν > 0.")
NU_F = click.option("--nu-f", "nu_f", required=True, callback=number("--nu-f", "0.4"),
                    help="Friction velocity ν_f > 0.")
NEAREST = click.option("--nearest", is_flag=True,
                       help="Take the nearest label where a value is not one (said on stderr); default: refuse, "
                            "naming the nearest labels.")
PRECISION = click.option("--precision", type=click.Choice(PRECISIONS), default=PRECISIONS[0], show_default=True)
FORMAT = click.option("--format", "fmt", type=click.Choice(FORMATS), default=FORMATS[0], show_default=True)
SCHEDULER = click.option("--scheduler", metavar="ADDRESS|SCHEDULER_FILE", default=None,
                         help="Dask scheduler (tcp://host:8786) or scheduler file. Default: "
                              "$DASK_SCHEDULER_ADDRESS, else this process, joined by an embedded local cluster "
                              "when the work left is worth one.")
WORKERS = click.option("--workers", type=Whole(example="2"), default=None,
                       help="Embedded: processes that compute, this one included (default: cores; 1: no "
                            "cluster). With --scheduler: wait for N workers.")
WRITE_FROM = click.option("--write-from", "writer", type=click.Choice(WRITERS), default=WRITERS[0],
                          show_default=True,
                          help="Who writes finished tiles: the workers (store on a filesystem all workers share) "
                               "or this process (no shared filesystem needed).")
