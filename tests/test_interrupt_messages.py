"""Ctrl-C says what the interrupted command kept (found at review: every command printed the submit's
"A submit keeps every finished tile in its store: submit the same workflow again to resume", also
`continue` and `study chain`, which keep nothing and are not resumed by a submit)."""

from __future__ import annotations

from pathlib import Path

import pytest

from bifurcation.cli import cli

ROOT = Path(__file__).resolve().parents[1]


def _interrupted(argv, capsys) -> str:
    with pytest.raises(SystemExit) as exc:
        cli.main(argv)
    assert exc.value.code == 130
    lines = capsys.readouterr().err.strip().splitlines()
    assert len(lines) == 1 and lines[0].startswith("bifurcation: interrupted. "), lines
    return lines[0]


def _raise(*args, **kwargs):
    raise KeyboardInterrupt


def test_continue_interrupted_does_not_talk_of_a_submit(tmp_path, monkeypatch, capsys):
    import bifurcation.models.rate_state.study as study

    monkeypatch.setattr(study, "run_study", _raise)
    line = _interrupted(["continue", str(ROOT / "workflows/rate-state-quick.toml"), "--out", str(tmp_path / "o")],
                        capsys)
    assert "submit" not in line and "continue writes its store and report only at the end" in line


def test_study_interrupted_does_not_talk_of_a_submit(tmp_path, monkeypatch, capsys):
    import bifurcation.models.chain.study as study

    monkeypatch.setattr(study, "main", _raise)
    line = _interrupted(["study", "chain", str(ROOT / "workflows/chain-report.toml"), "--out", str(tmp_path / "o")],
                        capsys)
    assert "submit" not in line and "writes its directory only at the end" in line


def test_submit_interrupted_still_says_it_resumes(tmp_path, monkeypatch, capsys):
    monkeypatch.setattr("bifurcation.run.submit", _raise)
    line = _interrupted(["submit", str(ROOT / "workflows/paper-fig3.toml"), "--store", str(tmp_path / "s.zarr"),
                         "--workers", "1"], capsys)
    assert "submit the same workflow again to resume" in line
