"""Fixtures shared between test modules."""

import functools
import os

import pytest

from bifurcation.theory.reference import carlson_langer_mp


@pytest.fixture(scope="session")
def carlson_langer_reference():
    """``carlson_langer_mp(nu, 0.4, dps=30)`` memoised per ν: ~2 s a point, wanted by two modules."""
    return functools.cache(lambda nu: carlson_langer_mp(nu, 0.4, dps=30))


# -- numba's first compile, off the critical path ---------------------------------------------------------
# With an empty numba disk cache (a fresh clone) the compiled chain engine and the RK4 baselines are compiled on
# first use: numba compiles the event loop once per law kind, and the fast suite runs the Carlson-Langer kind only
# (the tape's, every other law, runs in slow tests). Measured 2026-11-26 on a fresh clone with this warm-up off,
# load ~10: the Carlson-Langer loop 50.6 s of CPU (60.4 s again on the other xdist worker), the tape's 38.0 s,
# the RK4 baselines 4.6 s. When many other tests are selected, a subprocess (_numba_warmup.py) compiles them
# into the cache once while those tests run (the tape's loop too when slow tests of the compiled engine are
# selected); the modules that use them run last and wait for it, then load from the cache. The same tests run,
# on the same compiled code; with a warm cache, a subset, or no writable cache nothing changes.
_NUMBA_TESTS = {"test_chain_compiled.py", "test_chain_compiled_lone.py", "test_chain_compiled_taylor.py",
                "test_chain_bench.py", "test_cli_bounded.py", "test_indep4_chain.py"}
_warmup = []   # the running subprocess, if any (in the process that started it)


def _numba_cache_cold(laws) -> bool:
    from bifurcation.laws import resolve_law
    from bifurcation.models.chain._compiled import _CACHE, CompiledChain
    from bifurcation.models.chain._validate import check_initial

    if not _CACHE:
        return False
    u0 = check_initial(6, 1.0, "free", None, 0.1, 3)
    try:
        return not all(CompiledChain(resolve_law(law), 6, 1.0, 1e-3, 0.3, "free", u0).compiled() for law in laws)
    except Exception:   # noqa: BLE001 (the engine's API changed: no warm-up, the tests compile for themselves)
        return False


def _warmup_lock(config):
    """Under pytest-xdist (``-n 2``) only worker gw0 starts the warm-up; it holds an exclusive flock on this
    file for its lifetime, so a numba test on any worker waits on the lock (the warm-up is not its child).
    Every worker collects before any test is handed out, so the file exists by then if it ever will."""
    import tempfile
    from pathlib import Path

    run = getattr(config, "workerinput", {}).get("testrunuid")
    return Path(tempfile.gettempdir()) / f"bifurcation-numba-warmup-{run}.lock" if run else None


@pytest.hookimpl(trylast=True)   # after -m/-k deselection: count only the tests that will run
def pytest_collection_modifyitems(session, config, items):
    import subprocess
    import sys
    from pathlib import Path

    later = [item for item in items if item.path.name in _NUMBA_TESTS]
    if config.option.collectonly or not later or len(items) - len(later) < 300:
        return
    # every xdist worker orders the same way (xdist requires equal collections); --dist loadfile hands the
    # numba modules out last only with --no-loadscope-reorder (by default it sorts modules by test count)
    items[:] = [item for item in items if item.path.name not in _NUMBA_TESTS] + later
    # the tape's loop (every law but Carlson–Langer) only when slow tests of the compiled engine run
    laws = ["carlson-langer"] + (["exp(-x)"] if any(item.get_closest_marker("slow") and "compiled" in item.path.name
                                                    for item in later) else [])
    if os.environ.get("PYTEST_XDIST_WORKER", "gw0") != "gw0" or not _numba_cache_cold(laws):
        return
    lock = _warmup_lock(config)
    fd = None
    if lock is not None:
        import fcntl

        fd = os.open(lock, os.O_RDWR | os.O_CREAT, 0o600)
        fcntl.flock(fd, fcntl.LOCK_EX)   # the child inherits the open file and with it the lock
    try:
        _warmup.append(subprocess.Popen([sys.executable, str(Path(__file__).with_name("_numba_warmup.py")), *laws],
                                        stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                        pass_fds=() if fd is None else (fd,)))
    finally:
        if fd is not None:
            os.close(fd)


def _wait_for_lock(lock, timeout):
    import fcntl
    import time

    try:
        fd = os.open(lock, os.O_RDONLY)
    except FileNotFoundError:    # no warm-up in this run
        return
    try:
        end = time.monotonic() + timeout
        while time.monotonic() < end:
            try:
                fcntl.flock(fd, fcntl.LOCK_SH | fcntl.LOCK_NB)
                return
            except BlockingIOError:
                time.sleep(0.2)
    finally:
        os.close(fd)


def pytest_runtest_setup(item):
    if item.path.name not in _NUMBA_TESTS:
        return
    if _warmup:
        import subprocess

        try:
            _warmup[0].wait(timeout=900)   # a failed warm-up only means these tests compile for themselves
        except subprocess.TimeoutExpired:
            _warmup[0].kill()
            _warmup[0].wait()
        _warmup.clear()
    elif (lock := _warmup_lock(item.config)) is not None:
        _wait_for_lock(lock, 900)


def pytest_unconfigure(config):
    while _warmup:                     # a session that stopped early (-x, Ctrl-C): leave no process behind
        proc = _warmup.pop()
        proc.kill()
        proc.wait()
    if os.environ.get("PYTEST_XDIST_WORKER") == "gw0" and (lock := _warmup_lock(config)) is not None:
        lock.unlink(missing_ok=True)
