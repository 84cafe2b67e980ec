"""The compiled baselines of ``bifurcation bench`` integrate the same models as the engine.

A baseline that computed something else would make its ratio meaningless; each is checked against
an independent reference here (never timed: timings live in ``bifurcation bench``).
"""

import importlib.util

import numpy as np
import pytest

import bifurcation as bf
from bifurcation.theory.reference import piecewise_linear_exact

# skipped test by test, not the module: the suite collects the same tests with or without the bench
# extra (a module-level importorskip collected 3 fewer, so README's count differed from CI's by one)
pytestmark = pytest.mark.skipif(
    any(importlib.util.find_spec(m) is None for m in ("numba", "numbalsoda")),
    reason="needs numba and numbalsoda (the bench extra: pip install -e '.[bench]')")


def dop853_cycles(*args, **kwargs):
    from bifurcation.bench.compiled import dop853_cycles

    return dop853_cycles(*args, **kwargs)


@pytest.mark.slow   # numba compiles the baseline's driver: ~3-6 s
def test_compiled_dop853_piecewise_linear_matches_the_exact_solution():
    # Reference: the closed-form piecewise solution in mpmath (theory.reference, 30 digits), switches
    # included. Tolerance 1e-12: DOP853 at rtol = atol = 1e-14 accumulates ~1e-13 over its ~50 steps
    # (bifurcation bench: max 1.5e-13 on the 2 000-point grid against the engine).
    nus = np.array([1e-3, 1e-9, 1e-15, 1e-6])
    nu_fs = np.array([0.1, 0.45, 0.6, 0.9])
    got = dop853_cycles("piecewise-linear", nus, nu_fs, rtol=1e-14)
    ref = np.array([float(piecewise_linear_exact(nu, nf, dps=30)["delta"]) for nu, nf in zip(nus, nu_fs)])
    assert np.max(np.abs(got - ref) / ref) < 1e-12


@pytest.mark.slow   # numba compiles the baseline's driver (once per process)
def test_compiled_dop853_carlson_langer_matches_quad():
    # Reference: the engine in real128 (agrees with mpmath references to ~1e-30, tests/test_precision.py).
    nus = np.array([1e-3, 1e-9, 1e-15])
    nu_fs = np.array([0.2, 0.5, 0.8])
    got = dop853_cycles("carlson-langer", nus, nu_fs, rtol=1e-14)
    ref = bf.slip("carlson-langer", nu=nus, nu_f=nu_fs, precision="quad").delta
    assert np.max(np.abs(got - ref) / ref) < 1e-12
    # broadcasting as slip does
    assert dop853_cycles("carlson-langer", nus[:, None], nu_fs[None, :]).shape == (3, 3)


def test_compiled_lsoda_reproduces_rsfmodel():
    # rsfmodel's stored friction (tests/_rsfmodel_data.py: their odeint at rtol 1e-12, printed to 8
    # decimals): the numba/LSODA baseline at the same tolerance must reproduce it to those decimals.
    from _rsfmodel_data import CASES

    from bifurcation.models.rate_state._bench import _CASES, _lsoda_case

    for name in _CASES:
        a, k, states = _CASES[name]
        mu = _lsoda_case(a, k, states, 1e-12)
        assert np.max(np.abs(mu - CASES[name]["friction"])) < 1e-8, name
