"""Burridge–Knopoff chains against an independent mpmath reference at untested parameters.

Reference: tests/_indep_chain.py — the model of docs/chain.md integrated in physical variables
(U_j, V_j, absolute t) at 40 digits by tests/_indep_taylor.py, no code of the package; every stop,
start, kink crossing and velocity maximum a root of its Taylor polynomial. The start u0 is drawn here
(0.3 · default_rng(seed).random(N)) and passed to both as `u0`.

Cases: N = 3–6, free and periodic, σ_f = 0.008–0.25, ℓ = 0.8–2.4, ν = 2e-4 … 7e-3, three laws; the
piecewise-linear law crosses its kink (max velocity > (1 − σ_f)ν_f in its events).

Tolerances (docs/chain.md, "Precision" and "Engines"): the exact engine agreed with the package's
own mpmath reference to ≤ 2.3e-13 over the first 10 events and ≤ 1.3e-10 over 20 (the chain's chaos
amplifies rounding: a 1-ulp change of the start moves late events by up to 2e-7), so first 10
events: 1e-12, all 20: 1e-9 relative (to max(1, |x|)). The compiled engine runs DOP853 at tol 1e-11:
its stated accuracy is per event, re-run exactly from the same pre-event state (`verify`; ≤ 1.2e-11
measured, tests/test_chain_compiled.py holds 1e-10), asserted here with verify=1 at 1e-10. Over a
catalog these per-event errors are carried and amplified by later events: measured on case 0
against the exact engine, 2.2e-10 by event 9 and 7.0e-9 by event 17 at tol 1e-11 (and 1.5e-12,
4.3e-11 at tol 1e-13: they follow tol), so the catalog bounds are 1e-9 (first 10) and 3e-8 (all 20).
Hypocentres and sizes must be
identical for all 20 events (no coincident events in these cases: the reference's roots of
different blocks are ≥ 1e-6 apart).
"""

from __future__ import annotations

import numpy as np
import pytest

import bifurcation as bf

import _indep_chain as ref

CASES = [
    dict(law="piecewise-linear", n=5, ends="free", ell=1.7, nu=3e-3, nu_f=0.23, sigma=0.008, seed=11),
    dict(law="carlson-langer", n=6, ends="periodic", ell=0.8, nu=2e-4, nu_f=0.17, sigma=0.15, seed=12),
    dict(law="exponential", n=3, ends="free", ell=2.4, nu=7e-3, nu_f=0.27, sigma=0.25, seed=13),
    dict(law="piecewise-linear", n=4, ends="periodic", ell=1.2, nu=1.5e-3, nu_f=0.19, sigma=0.21, seed=14),
]
# the compiled engine refuses σ_f > 0.01 on a law with switches (docs/chain.md, "Engines")
COMPILED = [0, 1, 2]
TOL = {"exact": (1e-12, 1e-9), "compiled": (1e-9, 3e-8)}
FIELDS = ("t_start", "potency", "duration", "max_velocity")
_REF = {}


def _reference(i):
    if i not in _REF:
        cs = CASES[i]
        u0 = [float(x) for x in 0.3 * np.random.default_rng(cs["seed"]).random(cs["n"])]
        _REF[i] = u0, ref.chain_catalog(cs["law"], cs["n"], cs["ell"], cs["nu"], cs["nu_f"], u0, 20,
                                        ends=cs["ends"], sigma=cs["sigma"])
    return _REF[i]


@pytest.mark.slow
@pytest.mark.parametrize("engine,i", [("exact", i) for i in range(len(CASES))]
                         + [("compiled", i) for i in COMPILED])
def test_chain_against_mpmath(engine, i):
    cs = CASES[i]
    u0, cat = _reference(i)
    r = bf.chain(cs["law"], n=cs["n"], ell=cs["ell"], nu=cs["nu"], nu_f=cs["nu_f"], ends=cs["ends"], u0=u0,
                 events=20, sigma=cs["sigma"], engine=engine, **({"verify": 1.0} if engine == "compiled" else {}))
    assert r.status == "complete"
    if engine == "compiled":
        assert r.verification["largest_any"] <= 1e-10
    assert list(r.hypocentre) == [e["hypocentre"] for e in cat]
    assert list(r.n_blocks) == [e["n_blocks"] for e in cat]
    first, all_ = TOL[engine]
    for j, e in enumerate(cat):
        for f in FIELDS:
            rel = float(abs(getattr(r, f)[j] - e[f]) / max(1, abs(e[f])))
            assert rel <= (first if j < 10 else all_), (engine, i, j, f, rel)
    if cs["law"] == "piecewise-linear":       # the kink was crossed in at least one event
        assert max(e["max_velocity"] for e in cat) > (1 - cs["sigma"]) * cs["nu_f"]


def test_small_chain_fast():
    """Three events of a 3-block periodic Carlson–Langer chain with σ_f = 0.05 (~2 s)."""
    u0 = [0.05, 0.21, 0.13]
    cat = ref.chain_catalog("carlson-langer", 3, 1.4, 0.01, 0.31, u0, 3, ends="periodic", sigma=0.05,
                            dps=30, order=24)
    r = bf.chain("carlson-langer", n=3, ell=1.4, nu=0.01, nu_f=0.31, ends="periodic", u0=u0, events=3,
                 sigma=0.05)
    assert list(r.hypocentre) == [e["hypocentre"] for e in cat]
    assert list(r.n_blocks) == [e["n_blocks"] for e in cat]
    for j, e in enumerate(cat):
        for f in FIELDS:
            assert float(abs(getattr(r, f)[j] - e[f]) / max(1, abs(e[f]))) <= 1e-12, (j, f)
