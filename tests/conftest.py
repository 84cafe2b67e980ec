"""Fixtures shared between test modules."""

import functools

import pytest

from bifurcation.theory.reference import carlson_langer_mp


@pytest.fixture(scope="session")
def carlson_langer_reference():
    """``carlson_langer_mp(nu, 0.4, dps=30)`` memoised per ν: ~2 s a point, wanted by two modules."""
    return functools.cache(lambda nu: carlson_langer_mp(nu, 0.4, dps=30))


# -- numba's first compile, off the critical path ---------------------------------------------------------
# With an empty numba disk cache (a fresh clone) the compiled chain engine (two law kinds) and the RK4
# baselines cost ~28 s of CPU to compile on first use. When many other tests are selected, a subprocess
# (_numba_warmup.py) compiles them into the cache on the second core while those tests run; the modules
# that use them run last and wait for it, then load from the cache. The same tests run, on the same
# compiled code; with a warm cache, a subset, or no writable cache nothing changes.
_NUMBA_TESTS = {"test_chain_compiled.py", "test_chain_compiled_lone.py", "test_chain_bench.py"}
_warmup = []   # the running subprocess, if any


def _numba_cache_cold() -> bool:
    from bifurcation.laws import resolve_law
    from bifurcation.models.chain._compiled import _CACHE, CompiledChain
    from bifurcation.models.chain._validate import check_initial

    if not _CACHE:
        return False
    u0 = check_initial(6, 1.0, "free", None, 0.1, 3)
    try:
        return not all(CompiledChain(resolve_law(law), 6, 1.0, 1e-3, 0.3, "free", u0, lone=False).compiled()
                       for law in ("carlson-langer", "exp(-x)"))
    except Exception:   # noqa: BLE001 (the engine's API changed: no warm-up, the tests compile for themselves)
        return False


@pytest.hookimpl(trylast=True)   # after -m/-k deselection: count only the tests that will run
def pytest_collection_modifyitems(session, config, items):
    import subprocess
    import sys
    from pathlib import Path

    later = [item for item in items if item.path.name in _NUMBA_TESTS]
    if config.option.collectonly or not later or len(items) - len(later) < 300 or not _numba_cache_cold():
        return
    _warmup.append(subprocess.Popen([sys.executable, str(Path(__file__).with_name("_numba_warmup.py"))],
                                    stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL))
    items[:] = [item for item in items if item.path.name not in _NUMBA_TESTS] + later


def pytest_runtest_setup(item):
    if _warmup and item.path.name in _NUMBA_TESTS:
        import subprocess

        try:
            _warmup[0].wait(timeout=900)   # a failed warm-up only means these tests compile for themselves
        except subprocess.TimeoutExpired:
            _warmup[0].kill()
            _warmup[0].wait()
        _warmup.clear()


def pytest_unconfigure(config):
    while _warmup:                     # a session that stopped early (-x, Ctrl-C): leave no process behind
        proc = _warmup.pop()
        proc.kill()
        proc.wait()
