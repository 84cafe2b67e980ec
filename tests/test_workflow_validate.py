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
    assert get_model("chain").hook("workflow").command == "chain-report"
    path = tmp_path / "w.toml"
    path.write_text(RS)
    with pytest.raises(InputError, match=r"is a rate-state continuation workflow of `bifurcation continue`.*"
                                         r"not one for `bifurcation submit`; run it with `bifurcation continue FILE`"):
        read_toml(path, SUBMIT, argument="WORKFLOW", example="x")
    text, data = read_toml(path, continuation, argument="WORKFLOW", example="x")
    assert text == RS and data["slider"]["a"] == 0.01
