"""The store layout: a Zarr v3 group written and read through xarray, read from the model.

Dimensions ``model.dims``: the labels, then the model's axes (for the single block
``("law", "nu_f", "nu")``); coordinates: the labels (str: a law name or formula) and each axis
(float64, sorted), with the CF attributes the model declares; one chunk per tile (1 × tiles). One
data variable per output of the model, then ``done``. The single block's:

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
provenance: the model's name, workflow text, its sha256 and fingerprint, package versions, command
line, UTC time. A store without a ``model`` attribute (written before models) holds the single block.
"""

from __future__ import annotations

import importlib.metadata
import shlex
import sys
import uuid
from datetime import datetime, timezone
from pathlib import Path

import numpy as np

from ..engine.result import FIELDS
from ..outcome import Status

__all__ = ["DIMS", "FILL", "STORE_FORMAT", "VARIABLES", "command_line", "coordinate_attrs", "fills",
           "provenance", "store_attrs", "store_model", "variable_attrs", "variables"]

DIMS = ("law", "nu_f", "nu")
#: Bumped when the layout changes; a store of another format is refused.
STORE_FORMAT = 1
#: Data variables in write order: the data first, ``done`` last.
VARIABLES = {**{name: np.dtype("float64") for name in FIELDS}, "steps": np.dtype("int64"),
             "status": np.dtype("int8"), "done": np.dtype("bool")}
FILL = {**{name: np.nan for name in FIELDS}, "steps": 0, "status": int(Status.NOT_COMPUTED), "done": False}
_PACKAGES = ("bifurcation", "heyoka", "numpy", "dask", "distributed", "zarr", "xarray")


def _model(model):
    from ..models import get_model

    return get_model(model)


def variables(model=None) -> dict:
    """The (grid) data variables of ``model``'s store (name → dtype) in write order: the per-run
    outputs, then ``done``. Per-event outputs are catalogs (``bifurcation.store.catalog``)."""
    spec = _model(model)
    # per-event outputs are not grid variables: they live in the store's catalog group (store.catalog)
    out = {o.name: np.dtype(o.dtype) for o in spec.outputs if not o.per_event}
    out["done"] = np.dtype("bool")
    return out


def fills(model=None) -> dict:
    """Fill value per data variable of ``model``'s store (what a point never computed reads as)."""
    return {**{o.name: o.fill for o in _model(model).outputs}, "done": False}


def store_model(attrs: dict) -> str:
    """The model name a store's attributes record (stores written before models: the single block)."""
    from ..models import DEFAULT_MODEL

    return str(attrs.get("model", DEFAULT_MODEL))


def variable_attrs(name: str, model=None) -> dict:
    if name == "done":
        return {"long_name": "point computed and written (resume mask)", "units": "1"}
    spec = _model(model)
    output = spec.output(name)
    attrs = {"long_name": output.long_name, "units": output.units}
    if name == "status":
        flags = (Status.NOT_COMPUTED, *spec.statuses)
        attrs["flag_values"] = [int(s) for s in flags]
        attrs["flag_meanings"] = " ".join(str(s) for s in flags)
    return attrs


def coordinate_attrs(model=None) -> dict:
    spec = _model(model)
    return {spec.labels.name: {"long_name": spec.labels.long_name},
            **{axis.name: axis.attrs() for axis in spec.axes}}


def _version(package: str) -> str:
    try:
        return importlib.metadata.version(package)
    except importlib.metadata.PackageNotFoundError:
        return "not installed"


def provenance(workflow, command: str | None = None) -> dict:
    """Group attributes of a new store for ``workflow``."""
    return {
        **store_attrs(workflow.spec, title=workflow.name, description=workflow.description, text=workflow.text,
                      fingerprint=workflow.fingerprint, command=command),
        "precision": workflow.precision,
        "t_max": workflow.t_max,
        "max_steps": workflow.max_steps,
        "tiles": list(workflow.tiles),
        "submits": [],
    }


def store_attrs(model, *, title: str, description: str, text: str, fingerprint: str,
                command: str | None = None) -> dict:
    """The group attributes every store has: format, model, study, its workflow (text, sha256 and the
    fingerprint of what determines its numbers), package versions, command line, time and run id."""
    import hashlib

    return {
        "bifurcation_store": STORE_FORMAT,
        "model": model.name,
        "title": title,
        "description": description,
        "source": model.source,
        "references": model.source,   # CF: the published description of the model
        "workflow_toml": text,
        "workflow_sha256": hashlib.sha256(text.encode()).hexdigest(),
        "workflow_fingerprint": fingerprint,
        **({"engine_revision": model.revision} if model.revision else {}),   # Model.revision
        **{f"version_{p}": _version(p) for p in _PACKAGES},
        "python": sys.version.split()[0],
        "command": command if command is not None else command_line(),
        "created_utc": utc_now(),
        "run_id": uuid.uuid4().hex,
    }


def command_line() -> str:
    """This process's command line as a shell would take it, the program by its name only."""
    return shlex.join([Path(sys.argv[0]).name, *sys.argv[1:]])


def utc_now() -> str:
    return datetime.now(timezone.utc).isoformat(timespec="seconds")
