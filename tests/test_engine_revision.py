"""A model's engine revision (``Model.revision``) keeps a store begun by an older engine from being resumed
with runs of the newer one, whose numbers may differ (the rate-state chain's revision 1 of 2026-11-26 moved
its catalogs' last bits; revision 2 ends runs whose steady sliding is stable as "steady"), and says so in
one line instead of "holds another workflow"."""
from __future__ import annotations

import dataclasses
import json

import pytest

from bifurcation.errors import InputError
from bifurcation.models import get_model
from bifurcation.store import create_store
from bifurcation.store.zarr_store import check_store
from bifurcation.workflow import parse_workflow

from test_rs_chain_checkpoint import WORKFLOW


def test_the_revision_enters_the_fingerprint_and_the_store(tmp_path, monkeypatch):
    workflow = parse_workflow(WORKFLOW)
    assert workflow.spec.revision == 2
    now = workflow.fingerprint
    attrs = create_store(tmp_path / "s.zarr", workflow)
    assert attrs["engine_revision"] == 2 and attrs["workflow_fingerprint"] == now
    assert check_store(tmp_path / "s.zarr", workflow)["workflow_fingerprint"] == now

    older = dataclasses.replace(get_model("rs-chain"), revision=0)   # the engine before revisions
    monkeypatch.setattr(type(workflow), "spec", property(lambda self: older))
    assert workflow.fingerprint != now


def test_a_store_begun_by_an_older_engine_is_refused_with_what_to_do(tmp_path):
    workflow = parse_workflow(WORKFLOW)
    path = tmp_path / "old.zarr"
    create_store(path, workflow)
    meta = path / "zarr.json"           # make it look begun by revision 0: no revision, another fingerprint
    doc = json.loads(meta.read_text())
    doc["attributes"].pop("engine_revision")
    doc["attributes"]["workflow_fingerprint"] = "0" * 64
    meta.write_text(json.dumps(doc))
    with pytest.raises(InputError) as err:
        check_store(path, workflow)
    text = str(err.value)
    assert "revision 0 of the rs-chain engine" in text and "now revision 2" in text and "--new-store" in text


def test_models_without_a_revision_keep_their_fingerprints():
    """Revision 0 adds nothing to the fingerprint: stores made before revisions were counted still resume.
    (The rate-state slider is at revision 1 since its cycle's Newton polish of 2026-11-26, 2 since its
    slow-approach Newton resolves points next to a Hopf point that were not-resolved.)"""
    for name in ("single-block", "chain"):
        assert get_model(name).revision == 0
    assert get_model("rate-state").revision == 2
