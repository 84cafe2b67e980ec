"""`bifurcation study chain WORKFLOW` (the chain model's ``study`` hook) runs the chain study
(``models.chain.report.main``) on a workflow checked whole first. The study itself takes minutes; here its
entry point is replaced by a recorder, so only the command's own work is tested (bad input:
tests/test_bad_inputs.py, its study block)."""

from __future__ import annotations

import json
import shutil
import tomllib
from pathlib import Path

import pytest
from click.testing import CliRunner

from bifurcation.cli import cli
from bifurcation.models import get_model

REPO = Path(__file__).resolve().parents[1]


@pytest.fixture
def runs(monkeypatch, tmp_path):
    """The argument lists the study was started with (nothing runs), from an empty working directory."""
    from bifurcation.models.chain import report

    calls = []
    monkeypatch.setattr(report, "main", lambda argv: calls.append(argv))
    monkeypatch.chdir(tmp_path)
    shutil.copy(REPO / "workflows" / "chain-report.toml", tmp_path / "study.toml")
    return calls


def test_the_study_group_holds_each_models_study_hook_under_its_name():
    group = cli.commands["study"]
    assert group.commands["chain"] is get_model("chain").hook("study")
    # the generic group names no model: what it holds comes from the declarations
    assert "chain" not in (REPO / "bifurcation" / "cli" / "_study.py").read_text()


@pytest.mark.parametrize("name", ["chain-report.toml", "chain-report-large.toml"])
def test_the_shipped_workflows_pass_the_check_unchanged(name):
    from bifurcation.models.chain.report_workflow import load_report_workflow

    path = REPO / "workflows" / name
    assert load_report_workflow(path) == tomllib.loads(path.read_text())


def test_out_defaults_to_the_workflows_out_and_nothing_is_made_before_the_study(runs, tmp_path):
    r = CliRunner().invoke(cli, ["study", "chain", "study.toml"])
    assert r.exit_code == 0, r.output
    assert runs == [["study.toml", "--out", "results/local/chain"]]
    assert sorted(p.name for p in tmp_path.iterdir()) == ["study.toml"]   # the study makes its directory


def test_force_runs_again_into_a_study_and_from_data_re_renders(runs, tmp_path):
    done = tmp_path / "done"
    done.mkdir()
    (done / "REPORT.md").write_text("# a study\n")
    r = CliRunner().invoke(cli, ["study", "chain", "study.toml", "--out", str(done)])
    assert r.exit_code == 2 and "--force" in r.stderr and runs == []
    assert CliRunner().invoke(cli, ["study", "chain", "study.toml", "--out", str(done), "--force"]).exit_code == 0
    saved = {"workflow": (tmp_path / "study.toml").read_text(), "wall_seconds": 1.0, "cpu_seconds": 1.0,
             "sweeps": {"runs": []}, "catalogs": [], "threshold": []}
    (done / "data.json").write_text(json.dumps(saved))
    r = CliRunner().invoke(cli, ["study", "chain", "study.toml", "--out", str(done), "--from-data"])
    assert r.exit_code == 0, r.output
    assert runs == [["study.toml", "--out", str(done)], ["study.toml", "--out", str(done), "--from-data"]]
    assert r.stdout == f"wrote {done / 'REPORT.md'} and its figures from {done / 'data.json'}\n"
