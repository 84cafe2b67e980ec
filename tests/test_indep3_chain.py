"""Stiff small chains (ℓ = 10, σ_f = 0.05; N = 2 and 3; periodic and free) against an mpmath reference.

Reference values: tests/data/indep3_chain.json, made by tests/data/make_indep3_chain.py with the
earlier helper's tests/_indep_chain.py (own Taylor integrator at 30 digits, order 24; no code of the
package) — the parameters are new (no test had ℓ > 2.4, nor N = 2, nor σ_f = 0.05 periodic), the
reference is not (this helper's own references are for the single block and the slider).

Tolerances, those of tests/test_indep_chain.py: hypocentres and sizes identical; precision="quad" within
1e-15 of the reference (a real128 result returned as a double); the exact engine in double within
max(1e-12, 50 S_j), S_j the largest change of events ≤ j when u0 moves by 1 ulp (docs/chain.md,
"Precision": "within 2–50× that 1-ulp sensitivity"); the compiled engine (tol 1e-11, `verify` ≤ 1e-10
per event) within max(1e-9, 5e5 S_j, 1e6 E_j), E_j the exact engine's error. Measured when written:
exact ≤ 1.4 S_j (3.3e-12 at event 5 of case 2, where S_5 = 5.0e-12: ℓ = 10 amplifies rounding), quad
≤ 9.8e-17, compiled ≤ 1.9e-8 (case 2, event 5; its per-event `verify` 5.5e-12).
"""

from __future__ import annotations

import json
import pathlib

import numpy as np
import pytest
from mpmath import mpf

import bifurcation as bf

DATA = json.loads((pathlib.Path(__file__).parent / "data" / "indep3_chain.json").read_text())
FIELDS = ("t_start", "potency", "duration", "max_velocity")
ENGINES = {"exact": {}, "quad": {"precision": "quad"}, "compiled": {"engine": "compiled", "verify": 1.0}}


def _run(cs, u0, **kw):
    return bf.chain(cs["law"], n=cs["n"], ell=cs["ell"], nu=cs["nu"], nu_f=cs["nu_f"], ends=cs["ends"], u0=u0,
                    events=len(cs["events"]), sigma=cs["sigma"], **kw)


def _rel(r, j, value, f):
    ref = mpf(value)
    return float(abs(mpf(float(getattr(r, f)[j])) - ref) / max(1, abs(ref)))


def _bounds(cs, engine):
    n = len(cs["events"])
    if engine == "quad":
        return np.full(n, 1e-15)
    e0 = _run(cs, cs["u0"])
    sens = []
    for u1 in ([float(np.nextafter(cs["u0"][0], 1.0))] + cs["u0"][1:], [float(np.nextafter(u, 1.0)) for u in cs["u0"]]):
        e1 = _run(cs, u1)
        sens.append([max(_rel(e1, j, getattr(e0, f)[j], f) for f in FIELDS) for j in range(n)])
    s = np.maximum.accumulate(np.max(sens, axis=0))
    if engine == "exact":
        return np.maximum(1e-12, 50 * s)
    err = np.maximum.accumulate([max(_rel(e0, j, e[f], f) for f in FIELDS) for j, e in enumerate(cs["events"])])
    return np.maximum.reduce([np.full(n, 1e-9), 5e5 * s, 1e6 * err])


def _check(i, engine):
    cs = DATA["cases"][i]
    kw = ENGINES[engine]
    bound = _bounds(cs, engine)
    r = _run(cs, cs["u0"], **kw)
    assert str(r.status) == "complete"
    assert list(r.hypocentre) == [e["hypocentre"] for e in cs["events"]]
    assert list(r.n_blocks) == [e["n_blocks"] for e in cs["events"]]
    if engine == "compiled":
        assert r.verification["largest_any"] <= 1e-10
    for j, e in enumerate(cs["events"]):
        for f in FIELDS:
            assert _rel(r, j, e[f], f) <= bound[j], (i, engine, j, f, _rel(r, j, e[f], f), bound[j])


def test_stiff_two_block_periodic_fast():
    _check(0, "exact")


@pytest.mark.slow     # 8 runs with their 1-ulp probes: 23 s in all under load (heyoka compiles quad once)
@pytest.mark.parametrize("i,engine", [(i, e) for i in range(3) for e in ENGINES if (i, e) != (0, "exact")])
def test_stiff_small_chains(i, engine):
    _check(i, engine)
