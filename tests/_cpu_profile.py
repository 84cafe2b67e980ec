"""Per-test CPU time, robust to the machine's load (wall times are not): a pytest plugin, off unless asked for.

    BIFURCATION_CPU_PROFILE=/tmp/prof python -m pytest -p tests._cpu_profile -m "not slow" -n 2 --dist load

writes one tab-separated file per pytest process (``gw0.tsv``, ``gw1.tsv``; ``main.tsv`` the controlling one) with
a row per test phase: node id, phase (setup/call/teardown), CPU seconds of the process (user + sys, every thread)
and CPU seconds of the child processes reaped during the phase (a module-scoped cluster's workers show up in the
teardown of the module's last test; tests/conftest.py's numba warm-up in the setup of the first numba test), then
wall seconds. The first line holds the process's totals (what collection and start-up add to the rows' sum).
Profile an empty-cache run by pointing NUMBA_CACHE_DIR, XDG_CACHE_HOME (heyoka) and MPLCONFIGDIR at new
directories; a second run on those caches gives each test's cold-only cost as the difference."""

import os
import resource
import time

import pytest

_rows = []


def _cpu() -> tuple[float, float]:
    own, kids = resource.getrusage(resource.RUSAGE_SELF), resource.getrusage(resource.RUSAGE_CHILDREN)
    return own.ru_utime + own.ru_stime, kids.ru_utime + kids.ru_stime


def _timed(phase):
    @pytest.hookimpl(hookwrapper=True)
    def hook(item):
        cpu, wall = _cpu(), time.monotonic()
        yield
        after = _cpu()
        _rows.append((item.nodeid, phase, after[0] - cpu[0], after[1] - cpu[1], time.monotonic() - wall))
    return hook


pytest_runtest_setup = _timed("setup")
pytest_runtest_call = _timed("call")
pytest_runtest_teardown = _timed("teardown")


def pytest_sessionfinish(session):
    folder = os.environ.get("BIFURCATION_CPU_PROFILE")
    if not folder:
        return
    os.makedirs(folder, exist_ok=True)
    own, kids = _cpu()
    with open(os.path.join(folder, os.environ.get("PYTEST_XDIST_WORKER", "main") + ".tsv"), "w", encoding="utf-8") as f:
        f.write(f"#total\t{own:.3f}\t{kids:.3f}\n")
        for node, phase, own, kids, wall in _rows:
            f.write(f"{node}\t{phase}\t{own:.3f}\t{kids:.3f}\t{wall:.3f}\n")
