"""Every command's --help shows examples, and every example runs (exit status 0) as written.

The examples run in a scratch directory holding a copy of the repository's workflows/, in an order in
which each finds what an earlier one made (the stores of `submit`). `reproduce` runs its literal command
line on tiny stand-ins of the paper workflows (the full reproduction is the quick start's job).
"""

from __future__ import annotations

import re
import shlex
import shutil
import textwrap
from pathlib import Path

import pytest
from click.testing import CliRunner

from bifurcation.cli import cli

REPO = Path(__file__).resolve().parents[1]
_EXAMPLE = re.compile(r"^\s*\$ (bifurcation .+)$", re.M)
#: Commands whose examples make what others read, first.
_FIRST = ("submit",)
_LAST = ("reproduce",)


def _examples(name: str) -> list[str]:
    command = cli.commands[name]
    with cli.make_context("bifurcation", [name, "--help"], resilient_parsing=True) as ctx:
        text = command.get_help(click_context(ctx, command, name))
    return _EXAMPLE.findall(text)


def click_context(parent, command, name):
    import click

    return click.Context(command, info_name=name, parent=parent)


def test_every_command_has_an_example():
    missing = [name for name in cli.commands if not _examples(name)]
    assert missing == []


@pytest.fixture(scope="module")
def scratch(tmp_path_factory):
    root = tmp_path_factory.mktemp("examples")
    shutil.copytree(REPO / "workflows", root / "workflows")
    return root


def _order() -> list[str]:
    names = sorted(cli.commands)
    middle = [n for n in names if n not in _FIRST and n not in _LAST]
    return [*_FIRST, *middle, *_LAST]


_TINY = {
    "tiny-fig2.toml": '[study]\nname = "tiny-fig2"\n[engine]\nlaws = ["piecewise-linear"]\n'
                      '[grid.nu]\nvalues = [1e-6, 1e-9]\n[grid.nu_f]\nranges = [{ start = 0.02, stop = 0.98, num = 25 }]\n',
    "tiny-fig3.toml": '[study]\nname = "tiny-fig3"\n[engine]\nlaws = ["carlson-langer"]\n[grid.nu]\nvalues = [1e-9]\n'
                      '[grid.nu_f]\nvalues = [0.4]\nranges = [{ start = 0.02, stop = 0.98, num = 25 }]\n',
    "tiny-critical.toml": '[study]\nname = "tiny-critical"\n[engine]\nlaws = ["piecewise-linear", "carlson-langer"]\n'
                          '[grid.nu]\nlog = { start = 1e-3, stop = 1e-15, per_decade = 4 }\n'
                          '[grid.nu_f]\nvalues = [0.2, 0.3, 0.4, 0.5]\n',
}


#: Examples longer than a few seconds (each command keeps fast coverage in its own test file).
_SLOW = {"continue": "6 s: a continuation; tests/test_rate_state_cycles.py runs continue fast",
         "study": "3-13 s: re-renders the chain study's figures; tests/test_bad_inputs.py and test_chain_study.py "
                  "check the command fast"}


@pytest.mark.parametrize("name", [pytest.param(n, marks=pytest.mark.slow) if n in _SLOW else n for n in _order()])
def test_examples_run(name, scratch, monkeypatch):
    monkeypatch.chdir(scratch)
    if name == "bench":   # its compiled baselines come with the bench extra (numbalsoda builds from source)
        pytest.importorskip("numbalsoda")
    if name == "reproduce":
        from bifurcation.cli import _analysis

        tiny = scratch / "tiny-workflows"
        tiny.mkdir(exist_ok=True)
        for file, text in _TINY.items():
            (tiny / file).write_text(textwrap.dedent(text))
        monkeypatch.setattr(_analysis, "PAPER_WORKFLOWS", tuple(_TINY))
        monkeypatch.setattr(_analysis, "_workflow_dir", lambda: tiny)
    if name == "study":   # its example re-renders the committed chain study from its data
        shutil.copytree(REPO / "results" / "chain", scratch / "results" / "chain", dirs_exist_ok=True)
    if name not in _FIRST:   # pytest-xdist may hand this test to a process whose scratch `submit` never filled
        for first in _FIRST:
            if not (scratch / f".ran-{first}").exists():
                _run(first, scratch)
    outputs = _run(name, scratch, check_output=True)
    if name == "reproduce":   # its own embedded cluster has no dashboard: no link to it (issue 21)
        assert all("dashboard" not in out for out in outputs), outputs


def _run(name: str, scratch: Path, check_output: bool = False) -> list[str]:
    """Run ``name``'s examples in ``scratch`` (each must exit 0); their outputs."""
    outputs = []
    for line in _examples(name):
        args = shlex.split(line)[1:]
        result = CliRunner().invoke(cli, args)
        assert result.exit_code == 0, f"{line}\n{result.output}"
        outputs.append(result.output)
        if check_output:
            assert result.output.strip(), line   # every example prints something
    (scratch / f".ran-{name}").touch()
    return outputs
