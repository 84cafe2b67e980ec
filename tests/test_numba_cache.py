"""numba's disk cache of the compiled chain engine goes stale when a file its code depends on changes
(bifurcation/models/chain/_numba_cache.py): numba itself checks only the file that defines a function."""

from __future__ import annotations

import ast
import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from bifurcation.models.chain import _compiled
from bifurcation.models.chain._numba_cache import CACHE, source_key

_ENGINE = """
import json, sys
import numba as nb
from bifurcation.models.chain._numba_cache import jit
import dep

@jit(depends=[dep.__file__])
def keyed():
    return dep.C            # a module global: numba freezes it into the compiled code

@nb.njit(cache=True)
def plain():
    return dep.C

print(json.dumps([keyed(), plain(), sum(keyed.stats.cache_hits.values())]))
"""


def _run(folder: Path) -> list:
    env = {**os.environ, "NUMBA_CACHE_DIR": str(folder / "cache"), "PYTHONPATH": str(folder)}
    res = subprocess.run([sys.executable, str(folder / "engine.py")], capture_output=True, text=True, timeout=120,
                         env=env, cwd=folder)
    assert res.returncode == 0, res.stderr
    return json.loads(res.stdout.strip().splitlines()[-1])


@pytest.mark.skipif(not CACHE, reason="numba has no writable disk cache here")
def test_a_change_in_a_file_the_code_depends_on_makes_the_cache_stale(tmp_path):
    """A function with ``depends=[dep.py]`` that freezes dep.C: after dep.py changes, a new process
    computes the new value; the plain ``cache=True`` twin still loads the old code from disk (numba's
    own check misses it: the case this guards against)."""
    (tmp_path / "engine.py").write_text(_ENGINE)
    (tmp_path / "dep.py").write_text("C = 1.0\n")
    assert _run(tmp_path) == [1.0, 1.0, 0]                 # compiled and stored
    (tmp_path / "dep.py").write_text("C = 2.0\n")
    keyed, plain, hits = _run(tmp_path)
    assert (keyed, hits) == (2.0, 0)                       # compiled again, not loaded
    assert plain == 1.0                                    # stale: what the engine did before the key


def _relative_imports(path: Path) -> set[str]:
    """Modules of the same package imported at module level (``from . import x``, ``from .x import y``)."""
    names = set()
    for node in ast.parse(path.read_text()).body:
        if isinstance(node, ast.ImportFrom) and node.level == 1:
            names |= {a.name for a in node.names} if node.module is None else {node.module}
    return names


@pytest.mark.skipif(not CACHE, reason="numba has no writable disk cache here")
def test_the_engines_cache_stamp_covers_its_dependencies(tmp_path):
    """Every numba function of the compiled engine is checked against a key of _dop853, _lawtape and
    _lone (numba's private stamp: this fails if a numba release moves it, instead of the key silently
    doing nothing); the engine imports no other module of its package at module level but the cache
    probe; and the key follows the files' contents."""
    depends = [Path(p) for p in _compiled._DEPENDS]
    assert {p.stem for p in depends} == {"_dop853", "_lawtape", "_lone"}
    assert _relative_imports(Path(_compiled.__file__)) - {p.stem for p in depends} == {"_numba_cache"}
    key = source_key(depends)
    funcs = [f for f in vars(_compiled).values() if hasattr(f, "_cache") and hasattr(f, "py_func")]
    assert len(funcs) > 20 and _compiled.run_events in funcs
    for f in funcs:
        assert f._cache._cache_file._source_stamp[1] == key, f
    copies = []
    for p in depends:
        copies.append(tmp_path / p.name)
        copies[-1].write_bytes(p.read_bytes())
    assert source_key(copies) == key
    copies[0].write_bytes(copies[0].read_bytes() + b"# an edit\n")
    assert source_key(copies) != key
