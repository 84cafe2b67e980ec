"""The store layout: a Zarr v3 group written and read through xarray.

Dimensions ``("law", "nu_f", "nu")``; coordinates ``law`` (str: a law name or formula), ``nu_f`` and
``nu`` (float64, sorted); one chunk per tile (1 × tiles.nu_f × tiles.nu). Data variables:

=================  =======  ==========  ==============================================================
name               dtype    fill        meaning
=================  =======  ==========  ==============================================================
delta … max_vel.   float64  NaN         the six ``bifurcation.engine.result.FIELDS``
steps              int64    0           Taylor steps of the cycle
status             int8     0           ``bifurcation.Status`` code; 0 = not computed
done               bool     False       the point's values are written (the resume mask)
=================  =======  ==========  ==============================================================

A chunk that was never written reads as its fill value, so an unfinished store is a valid dataset.
Within a tile the data variables are written first and ``done`` last (zarr's local store replaces each
chunk file atomically), so ``done`` never claims data that is not there. Group attributes carry the
provenance: workflow text, its sha256 and fingerprint, package versions, command line, UTC time.
"""

from __future__ import annotations

import importlib.metadata
import shlex
import sys
import uuid
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from ..engine.result import FIELD_ATTRS, FIELDS, Status

__all__ = ["DIMS", "FILL", "STORE_FORMAT", "VARIABLES", "command_line", "coordinate_attrs", "provenance",
           "variable_attrs"]

DIMS = ("law", "nu_f", "nu")
#: Bumped when the layout changes; a store of another format is refused.
STORE_FORMAT = 1
#: Data variables in write order: the data first, ``done`` last.
VARIABLES = {**{name: np.dtype("float64") for name in FIELDS}, "steps": np.dtype("int64"),
             "status": np.dtype("int8"), "done": np.dtype("bool")}
FILL = {**{name: np.nan for name in FIELDS}, "steps": 0, "status": int(Status.NOT_COMPUTED), "done": False}
_PACKAGES = ("bifurcation", "heyoka", "numpy", "dask", "distributed", "zarr", "xarray")


def variable_attrs(name: str) -> dict:
    if name == "done":
        return {"long_name": "point computed and written (resume mask)", "units": "1"}
    long_name, units = FIELD_ATTRS[name]
    attrs = {"long_name": long_name, "units": units}
    if name == "status":
        attrs["flag_values"] = [int(s) for s in Status]
        attrs["flag_meanings"] = " ".join(str(s) for s in Status)
    return attrs


def coordinate_attrs() -> dict:
    return {
        "law": {"long_name": "friction law Φ (a name of bifurcation.law_names() or a formula in x)"},
        "nu_f": {"long_name": "friction velocity ν_f, Eq. (2) of Vasconcelos PRL 76, 4865 (1996)", "units": "1"},
        "nu": {"long_name": "pulling speed ν, Eq. (5) of Vasconcelos PRL 76, 4865 (1996)", "units": "1"},
    }


def _version(package: str) -> str:
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return "not installed"


def provenance(workflow, command: str | None = None) -> dict:
    """Group attributes of a new store for ``workflow``."""
    return {
        "bifurcation_store": STORE_FORMAT,
        "title": workflow.name,
        "description": workflow.description,
        "source": "Vasconcelos, First-order phase transition in a model for earthquakes, PRL 76, 4865 (1996)",
        "workflow_toml": workflow.text,
        "workflow_sha256": workflow.sha256,
        "workflow_fingerprint": workflow.fingerprint,
        "precision": workflow.precision,
        "t_max": workflow.t_max,
        "max_steps": workflow.max_steps,
        "tiles": list(workflow.tiles),
        **{f"version_{p}": _version(p) for p in _PACKAGES},
        "python": sys.version.split()[0],
        "command": command if command is not None else command_line(),
        "created_utc": utc_now(),
        "run_id": uuid.uuid4().hex,
        "submits": [],
    }


def command_line() -> str:
    """This process's command line as a shell would take it, the program by its name only."""
    return shlex.join([Path(sys.argv[0]).name, *sys.argv[1:]])


def utc_now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="seconds")
