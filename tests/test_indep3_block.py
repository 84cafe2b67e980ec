"""The single block at the corners of its documented domain, against a third independent reference.

Reference values: tests/data/indep3_block.json, made by tests/data/make_indep3_block.py with
tests/_indep3_block.py (own mpmath Taylor recurrences in U, U̇, 45 digits, order 32, events bisected
to working precision; no code of the package nor of the two earlier references). A rerun at 55
digits and order 40 agrees to the json's "agreement_45_vs_55_digits".

Points: the domain bifurcation/bounds.py accepts, ν ∈ [1e-20, 1] and ν_f ∈ [1e-4, 10], which the
earlier references cover only for ν ∈ [1e-15, 0.3], ν_f ∈ [0.02, 0.95]: 23 corners (ν = 1, 0.7, 0.5,
1e-18, 1e-20; ν_f = 1e-4, 3e-4, 1e-3, 0.98, 2, 10) and 16 points drawn log-uniformly over the whole
domain (numpy default_rng(20261126)); four laws, one of them a formula. Both precisions.

Tolerances: docs/engine.md "Precision" (double: 3e-15 away from ν_f ≈ 1/2, max(1e-14, κε) just above it;
quad: a real128 result returned as a double, one ulp either way, 2.3e-16). None of these points is
within 0.08 of 1/2, so 5e-15 in double (3e-15 with room for the times and max U̇, which share the
step errors, as tests/test_indep_single.py). Statuses: as tests/test_indep_single.py — no-stick where
the spring beats static friction after the stop (|νT − Δ + 1| > 1), creep where ν_f > 1/2 and U̇
never reached ν_f, else stick-slip.

Measured when written (AVX2, shared machine): double Δ ≤ 2.0e-15, stop time ≤ 2e-16, max U̇ ≤ 2.1e-15,
t1 ≤ 4.7e-14 relative (Carlson–Langer, ν = 3.14e-11, ν_f = 1.17e-4: 1.9e-16 absolute at t1 = 4.0e-3;
at ν_f = 1e-4 and ν = 1e-9 a direct double/quad comparison gives 6.9e-14); quad ≤ 1.4e-16 in every field.
"""

from __future__ import annotations

import json
import math
import pathlib

import pytest
from mpmath import mp, mpf

import bifurcation as bf

DATA = json.loads((pathlib.Path(__file__).parent / "data" / "indep3_block.json").read_text())
POINTS = DATA["points"]
FIELDS = ("delta", "stop_time", "creep_time", "max_velocity")
TOL = {"double": 5e-15, "quad": 2.3e-16}


def _expected_status(p):
    with mp.workdps(30):
        if abs(mpf(p["nu"]) * mpf(p["stop_time"]) - mpf(p["delta"]) + 1) > 1:
            return "no-stick"
    return "creep" if (p["nu_f"] > 0.5 and p["creep_time"] is None) else "stick-slip"


def test_reference_file_is_whole():
    """Every point has a reference (none ran out of steps) and the two precisions agreed."""
    assert len(POINTS) == 39
    assert all("error" not in p for p in POINTS)
    assert DATA["agreement_45_vs_55_digits"] < 1e-30


@pytest.mark.parametrize("precision", ["double", "quad"])
def test_domain_corners_and_sample(precision):
    """All 39 points in one call each (~0.1 s each in double, ~1 s in quad)."""
    worst = {}
    for p in POINTS:
        r = bf.slip(p["law"], nu=p["nu"], nu_f=p["nu_f"], precision=precision)
        where = (p["law"], p["nu"], p["nu_f"], precision)
        assert r.status_names()[()] == _expected_status(p), where
        for k in FIELDS:
            got = float(getattr(r, k))
            if p[k] is None:                  # U̇ never reached ν_f: t1 is NaN by definition
                assert math.isnan(got), (where, k)
                continue
            with mp.workdps(30):
                rel = float(abs(mpf(got) - mpf(p[k])) / abs(mpf(p[k])))
            worst[k] = max(worst.get(k, 0.0), rel)
            tol = TOL[precision]
            if k == "creep_time" and precision == "double":
                # t1 is located inside a step of O(1) length: an absolute error of ~ε (measured 1.9e-16
                # at ν_f = 1.17e-4, where t1 = 4.0e-3: 4.7e-14 relative; docs/engine.md, "Precision", states it)
                tol = max(tol, 4.4e-16 / float(p[k]))
            assert rel <= tol, (where, k, got, p[k], rel)
