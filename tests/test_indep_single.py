"""The single block against independent references at parameters no other test uses.

References (no code of the package): tests/_indep_single.py — an mpmath Taylor integration of
Ü = νt − U + 1 − Φ(U̇/ν_f) in the physical variables U, U̇ (the engine integrates W = U/ν) at 50
digits, events located on the step polynomials; and, for the piecewise-linear law, the exact solution
of each linear piece (a second method; the two agree to ≤ 5e-41 at (ν, ν_f) = (1e-2, 0.3),
(1e-4, 0.49), (0.03, 0.7), see test_the_two_references_agree).

Points: drawn once from numpy's default_rng(20261125) (ν log-uniform in [1e-4, 1e-1], ν_f uniform
in [0.05, 0.95]) plus ν_f = 0.4999, 0.5, 0.5001, 0.52 around the transition; four laws, a formula
among them. Measured when written (AVX-512 machine): largest relative difference 4.3e-16 in double
precision, 1.1e-16 for precision="quad" (whose result is returned as a double).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from mpmath import mpf

import bifurcation as bf

import _indep_single as ref
from _indep_sample import sample

# docs/engine.md, "Precision": double-precision Δ is within 3e-15 of the exact solution everywhere except
# on the creep side right at ν_f ≈ 0.51 (1.1e-14); none of these points is there, 5e-15 is that
# bound with room for the other outputs (stop time, t1, max velocity), which share the same step
# errors. Quad runs at tolerance 1.9e-34 and is returned as a double, Δ and max U̇ as ν times the
# rounded W(stop) and Ẇ_max (bifurcation/models/single_block.py): two roundings, within one ulp
# (2.3e-16 relative at worst); measured 1.6e-16 (max U̇ at ν_f = 0.5001 and 0.4999: 0.9 ulp).
TOL = {"double": 5e-15, "quad": 2.3e-16}
FIELDS = ("delta", "stop_time", "creep_time", "max_velocity")
LAWS = {"carlson-langer": "carlson-langer", "piecewise-linear": "piecewise-linear",
        "exponential": "exponential", "1/(1+x/2)^2": "quadratic-cl"}


def _points():
    rng = np.random.default_rng(20261125)
    laws = list(LAWS)
    pts = []
    for i in range(24):
        law = laws[i % 4]
        nu = float(10 ** rng.uniform(-4, -1))
        nuf = float(rng.uniform(0.05, 0.95)) if i < 16 else [0.4999, 0.5, 0.5001, 0.52][i % 4]
        pts.append((law, nu, nuf))
    return pts


POINTS = _points()
# the corners: small ν_f (velocities ~50 ν_f), the largest ν (ν = 0.1, where the piecewise-linear
# block stops with spring force −1.015: status no-stick), ν_f = 0.95; measured ≤ 4.0e-16 (double)
EDGES = [("exponential", 1e-4, 0.02), ("piecewise-linear", 0.1, 0.03), ("carlson-langer", 3e-4, 0.02),
         ("exponential", 0.1, 0.95)]


def _check(law, nu, nuf, precision, r=None):
    r = ref.single_cycle(LAWS[law], nu, nuf) if r is None else r
    p = bf.slip(law, nu=nu, nu_f=nuf, precision=precision)
    expected = "creep" if (nuf > 0.5 and r["creep_time"] is None) else "stick-slip"
    if abs(nu * r["stop_time"] - r["delta"] + 1) > 1:   # the spring beats static friction after the stop
        expected = "no-stick"
    assert p.status_names()[()] == expected
    for k in FIELDS:
        got = float(getattr(p, k))
        if r[k] is None:                      # U̇ never reached ν_f: t1 is NaN by definition
            assert math.isnan(got), k
            continue
        rel = abs(mpf(got) - r[k]) / abs(r[k])
        assert rel <= TOL[precision], (law, nu, nuf, precision, k, got, float(r[k]), float(rel))


def test_piecewise_linear_closed_form_fast():
    """One point, piecewise-linear with the kink crossed twice, against the exact pieces (~1 s)."""
    nu, nuf = 0.0023, 0.37
    r = ref.piecewise_linear_closed_form(nu, nuf)
    p = bf.slip("piecewise-linear", nu=nu, nu_f=nuf)
    for k in FIELDS:
        assert abs(mpf(float(getattr(p, k))) - r[k]) / abs(r[k]) <= TOL["double"], k


@pytest.mark.slow
def test_the_two_references_agree():
    for nu, nuf in [(1e-2, 0.3), (1e-4, 0.49), (0.03, 0.7)]:
        a = ref.single_cycle("piecewise-linear", nu, nuf)
        b = ref.piecewise_linear_closed_form(nu, nuf)
        for k in FIELDS:
            if a[k] is None:
                assert b[k] is None
            else:
                assert abs(a[k] - b[k]) <= mpf(10) ** -38 * abs(b[k]), k


@pytest.mark.slow
@pytest.mark.parametrize("law,nu,nuf", sample(POINTS[::3] + POINTS[16:20] + EDGES, 4))
@pytest.mark.parametrize("precision", ["double", "quad"])
def test_slip_against_mpmath(law, nu, nuf, precision):
    _check(law, nu, nuf, precision)


@pytest.mark.slow
@pytest.mark.parametrize("law,nuf", sample([("piecewise-linear", 0.3), ("carlson-langer", 0.27), ("exponential", 0.41)], 2))
def test_limit_against_mpmath(law, nuf):
    """bf.limit's Δ0 (ν → 0, computed directly) against the ν = 0 orbit of _indep_single.limit_delta0.

    Reference: started ε = 1e-22 along the fast eigenvector at 50 digits; ε = 1e-26 changes Δ0 by
    ≤ 3e-38 relative (measured at these points). The package's Δ0 is a double from a 12th-order
    manifold series and its compiled integrator (docs/engine.md, "Precision": Eq. 18 to ≤ 3e-16), so 4e-16 relative;
    measured ≤ 1.1e-16.
    """
    r = ref.limit_delta0(law, nuf)
    lim = bf.limit(law, nu_f=nuf)
    assert abs(mpf(float(lim.delta0)) - r["delta0"]) / r["delta0"] <= 4e-16
    assert abs(mpf(float(lim.max_velocity0)) - r["max_velocity0"]) / r["max_velocity0"] <= 4e-16


@pytest.mark.slow
def test_fading_exponential_at_small_nu_f():
    """e^{−x} at ν = 1e-6, ν_f = 1e-4: the friction comes back near the stop after x ~ 1e4 (~10 s).

    Before its step cap (_indep_single._fade_cap) this reference stepped over that return and gave
    Δ = 2.0000031280449; with it, Δ = 2.00000312152581189379263492433…, which tests/_indep3_block.py
    (tests/data/indep3_block.json, 45 digits, order 32) also gives: measured agreement ≤ 2.6e-30 relative
    in all four fields, checked here to 1e-28 (the json keeps 30 digits). The engine is held to TOL as above,
    in both precisions.
    """
    import json
    import pathlib

    from mpmath import mp

    r = ref.single_cycle("exponential", 1e-6, 1e-4)
    pts = json.loads((pathlib.Path(__file__).parent / "data" / "indep3_block.json").read_text())["points"]
    other = next(p for p in pts if p["law"] == "exponential" and p["nu"] == 1e-6 and p["nu_f"] == 1e-4)
    with mp.workdps(50):
        for k in FIELDS:
            assert abs(r[k] - mpf(other[k])) <= mpf(10) ** -28 * abs(r[k]), k
    for precision in ("double", "quad"):
        _check("exponential", 1e-6, 1e-4, precision, r)
