"""The one workflow validator (bifurcation.workflow.validate): what every command's workflow reader shares."""

import textwrap
from pathlib import Path

import pytest

from bifurcation.errors import InputError
from bifurcation.models import get_model
from bifurcation.workflow.validate import SUBMIT, Table, WorkflowKind, read_toml

#: A shipped continuation workflow (one quasi-static PRZ branch), changed one key at a time below.
RS = (Path(__file__).resolve().parents[1] / "workflows" / "rate-state-quick.toml").read_text()


def _load(tmp_path, text):
    from bifurcation.models.rate_state.study import load_study

    path = tmp_path / "w.toml"
    path.write_text(text)
    return load_study(path), path


def test_an_unknown_key_is_named_with_its_table_and_file(tmp_path):
    _, path = _load(tmp_path, RS)
    for old, new, key, table in (("v_lp = 1.0", "v_lp = 1.0\nmass = 3", "slider.mass", "[slider]"),
                                 ('state_law = "prz"', 'state_law = "prz"\npoint = 4', "branch[0].point", "[branch[0]]")):
        with pytest.raises(InputError) as info:
            _load(tmp_path, RS.replace(old, new))
        assert info.value.argument == key
        assert info.value.problem == f"is not a known key of {table} in {path}"
    with pytest.raises(InputError, match=rf"output={{'dir': 'x'}}: is not a known table or key of the workflow in "
                                         rf"{path}; use only the tables study, slider, branch, hopf"):
        _load(tmp_path, RS + "[output]\ndir = 'x'\n")
    # submit's schema reads through the same Table: the same words
    from bifurcation.workflow import parse_workflow

    with pytest.raises(InputError, match=r"engine.threads=4: is not a known key of \[engine\] in f.toml"):
        parse_workflow(textwrap.dedent("""\
            [study]
            name = "s"
            [engine]
            laws = ["carlson-langer"]
            threads = 4
            [grid.nu]
            values = [1e-9]
            [grid.nu_f]
            values = [0.4]
            """), source="f.toml")


@pytest.mark.parametrize("change, key, problem", [
    ("a = 0.01", "slider.a", "is not finite"),                       # a = nan
    ("b = 0.015", "slider.b", "must be > 0.01"),                     # b = 0.005: not above a
    ("dc = 0.01", "slider.dc", "is a string, not a number"),
])
def test_types_ranges_and_finite_numbers(tmp_path, change, key, problem):
    bad = {"a = 0.01": "a = nan", "b = 0.015": "b = 0.005", "dc = 0.01": 'dc = "0.01"'}[change]
    with pytest.raises(InputError) as info:
        _load(tmp_path, RS.replace(change, bad))
    assert info.value.argument == key and problem in info.value.problem


def test_table_bounds_are_open_or_closed_as_asked():
    t = Table({"x": 0.0, "n": 3, "xs": [1.0, 2.0], "flag": 1}, "t", ("x", "n", "xs", "flag"))
    assert t.number("x", low=0) == 0.0
    with pytest.raises(InputError, match=r"t.x=0.0: must be > 0; give a value > 0"):
        t.number("x", above=0)
    with pytest.raises(InputError, match=r"t.n=3: is out of range: must be <= 2"):
        t.integer("n", low=None, high=2)
    with pytest.raises(InputError, match=r"t.xs='2 values': has more than 1 values"):
        t.numbers("xs", most=1)
    with pytest.raises(InputError, match=r"t.flag=1: is an integer, not true or false"):
        t.boolean("flag")
    assert t.numbers("missing", [5]) == (5.0,) and t.boolean("other", True) is True


def test_a_branch_label_is_given_once(tmp_path):
    twice = RS.replace("[hopf]", '[[branch]]\nstate_law = "aging"\nlabel = "prz, quasi-static"\n[hopf]')
    with pytest.raises(InputError, match=r"branch\[1\].label='prz, quasi-static': repeats branch\[0\].label"):
        _load(tmp_path, twice)


def test_another_commands_workflow_is_named_by_the_kind_its_model_declares(tmp_path):
    # the kinds are declarations on the models (their workflow hook), not a list in the generic layer
    continuation = get_model("rate-state").hook("workflow")
    assert isinstance(continuation, WorkflowKind) and continuation.command == "continue"
    assert get_model("chain").hook("workflow").command == "study chain"
    path = tmp_path / "w.toml"
    path.write_text(RS)
    with pytest.raises(InputError, match=r"is a rate-state continuation workflow of `bifurcation continue`.*"
                                         r"not one for `bifurcation submit`; run it with `bifurcation continue FILE`"):
        read_toml(path, SUBMIT, argument="WORKFLOW", example="x")
    text, data = read_toml(path, continuation, argument="WORKFLOW", example="x")
    assert text == RS and data["slider"]["a"] == 0.01


CHAIN_REPORT = (Path(__file__).resolve().parents[1] / "workflows" / "chain-report.toml").read_text()


def test_the_chain_reports_workflow_is_read_through_the_same_validator(tmp_path):
    import tomllib

    from bifurcation.models.chain.study_workflow import load_report_workflow

    for name in ("chain-report.toml", "chain-report-large.toml"):   # the shipped ones, as the report reads them
        path = Path(__file__).resolve().parents[1] / "workflows" / name
        assert load_report_workflow(path) == tomllib.loads(path.read_text())
    path = tmp_path / "c.toml"
    for old, new, match in [
        ("transient_cycles = 3", "transient_cycles = 3\nsteps = 4", rf"sweep.steps=4: is not a known key of \[sweep\] in "
                                                                   rf"{path}"),
        ("seeds = [1, 6, 6, 4, 2]", "seeds = [1, 6, 6, 4]", r"sweep.seeds='4 values': has not the 5 values of sizes"),
        ('ends = "free"', 'ends = "fixed"', r"chain.ends='fixed': is not a kind of ends; use one of free, periodic"),
        ("skip = 300", "skip = 5000", r"catalog.skip=5000: leaves no event of the shortest catalog \(2000\)"),
        ("cycles = [[60, 24, 10], [15, 5, 2]]", "cycles = [[60, 24], [15, 5, 2]]", r"near_half.cycles\[0\]"),
        ("ell = 1.0", 'ell = "1"', r"chain.ell='1': is a string, not a number"),
        ('law = "carlson-langer"', 'law = "coulomb"', r"chain.law='coulomb': is not a known law"),
    ]:
        assert old in CHAIN_REPORT, old
        path.write_text(CHAIN_REPORT.replace(old, new, 1))
        with pytest.raises(InputError, match=match):
            load_report_workflow(path)


def test_a_bad_chain_report_workflow_is_one_line_exit_2_and_writes_nothing(tmp_path, capsys):
    from bifurcation.models.chain.study import main

    path = tmp_path / "c.toml"
    path.write_text(CHAIN_REPORT.replace('out = "results/local/chain"', f'out = "{tmp_path / "out"}"')
                    .replace("nu = 1e-3", "nu = nan", 1))
    with pytest.raises(SystemExit) as info:
        main([str(path)])
    assert info.value.code == 2
    err = capsys.readouterr().err.strip().splitlines()
    assert err == ["bifurcation: error: chain.nu=nan: is not finite; give a finite number"]
    assert not (tmp_path / "out").exists()
