"""Which test compiles which heyoka integrator, at what CPU cost: a pytest plugin, off unless asked for.

    BIFURCATION_HEYOKA_PROFILE=/tmp/hy XDG_CACHE_HOME=$(mktemp -d) python -m pytest -p tests._heyoka_profile ...

wraps ``heyoka.taylor_adaptive`` / ``taylor_adaptive_batch`` (looked up at call time by the package) and writes one
tab-separated file per pytest process (``gw0.tsv``, ...): node id, constructor, CPU seconds of the process during
the construction (user + sys), wall seconds, a hash of the system and its options (equal hashes: the same
integrator), number of equations, fp_type, compact mode. With an empty heyoka cache (XDG_CACHE_HOME) the first
construction of a hash is its compile; later ones load it from heyoka's on-disk cache, also across xdist workers.
Measured 2026-11-26 (load ~12) on the nine costliest chain/rate-state files: 144 distinct integrators, 58 s of CPU,
107 of them (42.5 s) serving one test only; compiles repeated across the two workers: 1.6 s."""

import hashlib
import os
import resource
import time

import heyoka as hy
import pytest

_current = ["<collection>"]
_rows = []


def _cpu() -> float:
    own = resource.getrusage(resource.RUSAGE_SELF)
    return own.ru_utime + own.ru_stime


def _wrap(name):
    original = getattr(hy, name)

    def constructor(sys, *args, **kwargs):
        cpu, wall = _cpu(), time.monotonic()
        ta = original(sys, *args, **kwargs)
        cpu, wall = _cpu() - cpu, time.monotonic() - wall
        sys = list(sys)
        options = {k: v for k, v in kwargs.items() if k not in ("t_events", "nt_events", "pars")}
        key = repr((name, sys, sorted((k, repr(v)) for k, v in options.items()), len(kwargs.get("t_events") or ()),
                    len(kwargs.get("nt_events") or ())))
        _rows.append((_current[0], name, cpu, wall, hashlib.sha1(key.encode()).hexdigest()[:12], len(sys),
                      kwargs.get("fp_type"), bool(kwargs.get("compact_mode"))))
        return ta

    constructor.__wrapped__ = original
    setattr(hy, name, constructor)


if os.environ.get("BIFURCATION_HEYOKA_PROFILE"):
    _wrap("taylor_adaptive")
    _wrap("taylor_adaptive_batch")


@pytest.hookimpl(hookwrapper=True)
def pytest_runtest_protocol(item, nextitem):
    _current[0] = item.nodeid
    yield
    _current[0] = "<between tests>"


def pytest_sessionfinish(session):
    folder = os.environ.get("BIFURCATION_HEYOKA_PROFILE")
    if not folder:
        return
    os.makedirs(folder, exist_ok=True)
    with open(os.path.join(folder, os.environ.get("PYTEST_XDIST_WORKER", "main") + ".tsv"), "w", encoding="utf-8") as f:
        for node, name, cpu, wall, key, n, fp_type, compact in _rows:
            f.write(f"{node}\t{name}\t{cpu:.3f}\t{wall:.3f}\t{key}\t{n}\t{fp_type}\t{compact}\n")
