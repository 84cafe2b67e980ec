"""The package's import graph: folders in layers, each importing only from layers below it (STYLE.md §13).

The graph is read from the source with ``ast`` (every ``import`` and ``from ... import``, also those
inside functions, which are how heavy modules are deferred), not by importing anything. A *unit* is a
folder of the package (``bifurcation/store``, ``bifurcation/models/chain``) or a top-level module
(``bifurcation/errors.py``). ``LAYERS`` below is the one declaration of their order (docs/models.md,
"Layers", and README's "Layout" cite it). A model's hooks (``Model.hooks``) are ``"module:attr"``
strings imported on use: they are how a lower layer reaches a model's report section or CLI commands
without an import edge, so they are not edges here.
"""

from __future__ import annotations

import ast
from collections import defaultdict
from pathlib import Path

import pytest

PACKAGE = Path(__file__).resolve().parents[1] / "bifurcation"

#: Bottom to top. A unit may import only units of lower layers (not its own layer's peers).
LAYERS = (
    # the ground floor: errors, the outcome vocabulary every model and the store share, lazy names
    ("bifurcation.errors", "bifurcation.outcome", "bifurcation._lazy", "bifurcation.reference_taylor"),
    # the package's root (its version; its public names are lazy strings), physical bounds, friction
    # laws (with their fading ladders), closed-form theory
    ("bifurcation", "bifurcation.bounds", "bifurcation.laws", "bifurcation.theory"),
    # declarations: the Model contract, the registry, the single and damped block
    ("bifurcation.models",),
    # the engine: handed a Model, never looks one up
    ("bifurcation.engine",),
    # what reads declarations to lay out and validate work
    ("bifurcation.store", "bifurcation.workflow"),
    ("bifurcation.run",),
    ("bifurcation.analysis",),
    ("bifurcation.report", "bifurcation.bench"),
    # model packages (every folder under bifurcation/models/): built on all of the above; the shipped
    # ones first, so a new model package may build on their public modules (the rate-state chain
    # imports the slider's state laws, rate_state.laws) but never the other way round
    ("bifurcation.models.chain", "bifurcation.models.rate_state"),
    ("bifurcation.models.*",),
    ("bifurcation.cli",),
    ("bifurcation.__main__",),
)


def _module_name(path: Path, root: Path) -> str:
    parts = list(path.relative_to(root.parent).with_suffix("").parts)
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


def _modules(root: Path = PACKAGE) -> dict[str, Path]:
    return {_module_name(p, root): p for p in sorted(root.rglob("*.py"))}


def _unit(module: str, modules: dict[str, Path]) -> str:
    path, top = modules[module], modules["bifurcation"].parent
    if path.parent == top and path.name != "__init__.py":
        return module                                         # a top-level module
    return _module_name(path.parent / "__init__.py", top)     # its folder


def _layer(unit: str) -> int:
    for k, layer in enumerate(LAYERS):
        if unit in layer:
            return k
    if unit.startswith("bifurcation.models."):
        return next(k for k, layer in enumerate(LAYERS) if "bifurcation.models.*" in layer)
    raise KeyError(unit)


def module_edges(modules: dict[str, Path]) -> set[tuple[str, str]]:
    """(importer, imported) for every import of the package's own modules, at any depth of the code."""
    edges = set()
    for module, path in modules.items():
        package = module.split(".") if path.name == "__init__.py" else module.split(".")[:-1]
        for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"), str(path))):
            if isinstance(node, ast.Import):
                targets = [a.name for a in node.names]
            elif isinstance(node, ast.ImportFrom):
                base = ".".join(package[:len(package) - node.level + 1] + ([node.module] if node.module else [])) \
                    if node.level else node.module
                # `from X import y` imports X, and X.y too when y is a submodule
                targets = [base] + [f"{base}.{a.name}" for a in node.names]
            else:
                continue
            for target in targets:
                if not target or target.split(".")[0] != "bifurcation":
                    continue
                while target not in modules:            # `from X import name`: the module X
                    target = target.rpartition(".")[0]
                if target != module:
                    edges.add((module, target))
    return edges


def unit_graph(modules: dict[str, Path]) -> dict[tuple[str, str], list[tuple[str, str]]]:
    """(unit, unit) → the module edges behind it, between different units."""
    graph = defaultdict(list)
    for a, b in module_edges(modules):
        ua, ub = _unit(a, modules), _unit(b, modules)
        if ua != ub:
            graph[(ua, ub)].append((a, b))
    return graph


def cycles(graph) -> list[list[str]]:
    """The strongly connected components of more than one unit (Tarjan)."""
    succ = defaultdict(set)
    for a, b in graph:
        succ[a].add(b)
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in sorted(succ[v]):
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))

    for v in sorted(set(succ) | {b for _, b in graph}):
        if v not in index:
            visit(v)
    return out


@pytest.fixture(scope="module")
def graph():
    modules = _modules()
    return modules, unit_graph(modules)


def test_the_reader_sees_imports_at_every_depth(tmp_path):
    # The reader itself, on a package written here: a relative import inside a function, an absolute
    # one, a `from . import` of a submodule and a name imported from a package all count; a
    # third-party import does not; a cycle between two folders is found.
    root = tmp_path / "bifurcation"
    (root / "a").mkdir(parents=True)
    (root / "b").mkdir()
    (root / "__init__.py").write_text("")
    (root / "a" / "__init__.py").write_text("from . import low\n")
    (root / "a" / "low.py").write_text("import numpy\n\ndef f():\n    from ..b.high import g\n")
    (root / "b" / "__init__.py").write_text("X = 1\n")
    (root / "b" / "high.py").write_text("import bifurcation.a\nfrom bifurcation.b import X\n")
    modules = _modules(root)
    assert module_edges(modules) == {("bifurcation.a", "bifurcation.a.low"),
                                     ("bifurcation.a.low", "bifurcation.b.high"),
                                     ("bifurcation.b.high", "bifurcation.a"),
                                     ("bifurcation.b.high", "bifurcation.b")}
    assert cycles(unit_graph(modules)) == [["bifurcation.a", "bifurcation.b"]]


def test_every_unit_has_a_layer(graph):
    modules, _ = graph
    units = {_unit(m, modules) for m in modules}
    unplaced = []
    for unit in sorted(units):
        try:
            _layer(unit)
        except KeyError:
            unplaced.append(unit)
    assert not unplaced, f"place these folders/modules in LAYERS: {unplaced}"


def test_no_cycles_between_folders(graph):
    _, edges = graph
    found = cycles(edges)
    detail = [f"{a} -> {b}: {sorted(edges[(a, b)])[:3]}" for c in found for a in c for b in c if (a, b) in edges]
    assert found == [], f"import cycles between folders {found}:\n" + "\n".join(detail)


def test_every_import_goes_down_the_layers(graph):
    _, edges = graph
    upward = sorted(f"{a} (layer {_layer(a)}) imports {b} (layer {_layer(b)}): {sorted(w)[:3]}"
                    for (a, b), w in edges.items() if _layer(b) >= _layer(a))
    assert upward == [], "imports that do not go down the layers (LAYERS in this file):\n" + "\n".join(upward)
