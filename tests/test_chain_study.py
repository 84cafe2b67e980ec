"""`bifurcation study chain WORKFLOW` (the chain model's ``study`` hook) runs the chain study
(``models.chain.study.main``) on a workflow checked whole first. The study itself takes minutes; here its
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
    from bifurcation.models.chain import study

    calls = []
    monkeypatch.setattr(study, "main", lambda argv: calls.append(argv))
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
    from bifurcation.models.chain.study_workflow import load_report_workflow

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
    saved = {"workflow": (tmp_path / "study.toml").read_text(), "wall_seconds": 1.0, "cpu_seconds": 1.0,
             "sweeps": {"runs": []}, "catalogs": [], "threshold": []}
    (done / "data.json").write_text(json.dumps(saved))   # a chain study: its report and its data
    r = CliRunner().invoke(cli, ["study", "chain", "study.toml", "--out", str(done)])
    assert r.exit_code == 2 and "--force" in r.stderr and runs == []
    assert CliRunner().invoke(cli, ["study", "chain", "study.toml", "--out", str(done), "--force"]).exit_code == 0
    r = CliRunner().invoke(cli, ["study", "chain", "study.toml", "--out", str(done), "--from-data"])
    assert r.exit_code == 0, r.output
    assert runs == [["study.toml", "--out", str(done)], ["study.toml", "--out", str(done), "--from-data"]]
    assert r.stdout == f"wrote {done / 'REPORT.md'} and its figures from {done / 'data.json'}\n"


def test_the_committed_chain_report_is_one_typed_document_in_both_formats():
    """The chain study's report is built of report.document's blocks (issue 20, item 3): rendered from the
    committed data (what `--from-data` reads, ~5 s with the transition's bootstrap; nothing written), Markdown and HTML read back to the
    outline of those blocks, every table row has its header's cell count, and the Markdown is the committed
    results/chain/REPORT.md (regenerate it with `bifurcation study chain workflows/chain-report.toml
    --from-data --out results/chain --force` after changing the report's text)."""
    from _report_outline import from_blocks, from_html, from_markdown

    from bifurcation.models.chain.study import saved_data, study_blocks
    from bifurcation.models.chain.study_workflow import load_report_workflow
    from bifurcation.report.document import to_html, to_markdown

    out, workflow = REPO / "results" / "chain", "workflows/chain-report.toml"
    cfg = load_report_workflow(REPO / workflow)
    blocks = study_blocks(out, cfg, workflow, saved_data(out, cfg))
    expected = from_blocks(blocks, out)
    # the title, 8 sections (the Speed one carried over from REPORT.md), 6 subsections (the ℓ scan's the 4th), the
    # 8 figures and 24 tables (3 of them the Speed section's, read back from REPORT.md; 2 the ℓ scan's)
    assert [k for k in expected if k[0] == "h"] == [("h", 1)] + [("h", 2)] * 2 + [("h", 3)] * 4 + [("h", 2)] * 2 \
        + [("h", 3)] + [("h", 2)] + [("h", 3)] + [("h", 2)] * 3
    # (the Speed section: the compiled baselines' table, then the heyoka engine's two against interpreted RK4)
    assert sum(k[0] == "figure" for k in expected) == 8 and sum(k[0] == "table" for k in expected) == 24
    md = to_markdown(blocks)
    assert from_markdown(md, out) == expected
    assert from_html(to_html(blocks, out)) == expected
    assert md == (out / "REPORT.md").read_text(encoding="utf-8")
