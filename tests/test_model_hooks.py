"""A model's capabilities are hooks on its declaration (STYLE.md §13); the generic layers never ask its name."""

import ast
import inspect
from pathlib import Path

import click
import pytest

from bifurcation.models import Hooks, Model, get_model, model_names

PACKAGE = Path(__file__).resolve().parents[1] / "bifurcation"


@pytest.mark.parametrize("name", model_names())
def test_every_declared_hook_resolves_to_what_its_contract_says(name):
    model = get_model(name)
    hooks = model.hooks
    for hook in ("describe_label", "report", "bench"):
        target = model.hook(hook)
        assert (target is None) == (getattr(hooks, hook) == ""), hook
        assert target is None or callable(target), hook
    report = model.hook("report")
    if report is not None:
        assert list(inspect.signature(report).parameters)[:5] == ["ds", "model", "out", "figures", "stem"]
    bench = model.hook("bench")
    if bench is not None:
        assert "echo" in inspect.signature(bench).parameters
    commands = model.hook("commands")
    assert commands is None or all(isinstance(c, click.Command) for c in commands)
    describe = model.hook("describe_label")
    if describe is not None:
        row = describe(model.labels.example)
        assert isinstance(row.equation, str) and row.equation and isinstance(row.source, str) and row.source


def test_the_shipped_models_declare_their_capabilities():
    # what the report, `bench --suite` and the command list read from them (docs/models.md, "Hooks")
    assert get_model("single-block").hook("report").__name__ == "single_block_section"
    assert get_model("damped-block").hook("report").__name__ == "block_section"
    assert {c.name for c in get_model("rate-state").hook("commands")} == {"continue", "hopf", "rate-state"}
    assert {c.name for c in get_model("chain").hook("commands")} == {"chain"}
    benched = [n for n in model_names() if get_model(n).hooks.bench]
    assert benched[:3] == ["single-block", "chain", "rate-state"]   # a model added later may bench too


def test_a_hook_that_is_not_module_colon_attribute_is_refused():
    with pytest.raises(ValueError, match="hook report='bifurcation.report.study': give 'package.module:attribute'"):
        Hooks(report="bifurcation.report.study")
    with pytest.raises(ValueError, match="hook bench='bench:run bench'"):
        Hooks(bench="bench:run bench")


def test_the_engine_is_handed_a_model_not_a_name():
    from bifurcation.engine.solve import solve

    with pytest.raises(TypeError, match="not 'damped-block' .*get_model"):
        solve("damped-block", "carlson-langer", {"gamma": [0.1], "nu_f": [0.4], "nu": [1e-3]})
    out = solve(get_model("damped-block"), "carlson-langer", {"gamma": [0.1], "nu_f": [0.4], "nu": [1e-3]})
    assert out["status"].shape == (1,) and int(out["status"][0]) in (1, 2)


def _name_comparisons(path: Path) -> list[str]:
    """``<x>.name ==/!= "<model name>"`` and ``store_model(...) ==/!= "<model name>"`` in a source file."""
    names = set(model_names())
    found = []
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if not isinstance(node, ast.Compare):
            continue
        sides = [node.left, *node.comparators]
        if any(isinstance(s, ast.Constant) and s.value in names for s in sides):
            found.append(f"{path}:{node.lineno}: {ast.unparse(node)}")
    return found


def test_no_generic_layer_branches_on_a_model_name():
    # (both came back once: the batch engine's parking and the store's old-layout check named a model)
    folders = ("engine", "store", "run", "workflow", "analysis", "report", "bench", "cli")
    found = [hit for folder in folders for path in sorted((PACKAGE / folder).rglob("*.py"))
             for hit in _name_comparisons(path)]
    assert found == [], "call a hook of the model instead (docs/models.md, Hooks):\n" + "\n".join(found)


def test_the_name_comparison_finder_finds_one(tmp_path):
    path = tmp_path / "probe.py"
    path.write_text('def f(model, ds):\n    if model.name == "rate-state":\n        return 1\n'
                    '    return store_model(ds.attrs) != "chain"\n', encoding="utf-8")
    assert len(_name_comparisons(path)) == 2


def test_the_engine_parks_lanes_by_the_models_declared_rest_slot_not_by_its_name():
    # parking is a declaration (Model.rest_slot), so the engine names no model; a slot it does not have is refused
    import dataclasses

    from bifurcation.models import get_model

    block = get_model("single-block")
    assert block.rest_slot == "forcing" and block.rest_slot in block.parameters
    assert "single-block" not in (Path(__file__).resolve().parents[1] / "bifurcation" / "engine" / "_batch.py").read_text()
    with pytest.raises(ValueError, match="rest_slot 'nope' is not one of its parameters"):
        dataclasses.replace(block, rest_slot="nope")
