"""Burridge–Knopoff chains against an independent mpmath reference at untested parameters.

Reference: tests/_indep_chain.py — the model of docs/chain.md integrated in physical variables
(U_j, V_j, absolute t) at 40 digits by tests/_indep_taylor.py, no code of the package; every stop,
start, kink crossing and velocity maximum a root of its Taylor polynomial. The start u0 is drawn here
(0.3 · default_rng(seed).random(N)) and passed to both as `u0`.

Cases: N = 3–6, free and periodic, σ_f = 0.008–0.25, ℓ = 0.8–2.4, ν = 2e-4 … 7e-3, three laws; the
piecewise-linear law crosses its kink (max velocity > (1 − σ_f)ν_f in its events).

Checks and tolerances. These chains amplify rounding strongly: in case 2 a 1-ulp change of u0[0]
moves event 8 by 1.6e-11 and event 18 by 5.3e-7 (relative), so no double-precision code can be
held to a fixed bound over 20 events (docs/chain.md, "Precision", says the same of its own cases).
* precision="quad" (the exact engine in real128): hypocentres and sizes identical, every field of all
  20 events within 1e-15 relative of the reference (a returned double: 1–2 roundings; the real128
  error amplified by the chain stays < 1e-20). Measured: 0 (bit-equal to the rounded reference) in
  case 2.
* the exact engine in double: hypocentres and sizes identical; event j within
  max(1e-12, 50 S_j), S_j the largest change any event i ≤ j shows when u0[0], or every u0[k], moves
  by 1 ulp (the same engine: the chain's own sensitivity). docs/chain.md states "within 2–50× that
  1-ulp sensitivity"; measured ≤ 22× S_j here.
* the compiled engine (DOP853, tol 1e-11): its stated accuracy is per event from the same pre-event
  state (`verify`; ≤ 1.2e-11 measured, tests/test_chain_compiled.py holds 1e-10), asserted with
  verify = 1 at 1e-10. Its catalog carries a ~1e-11 error per event through the chain's
  amplification, which the 1-ulp probes above can underestimate (case 0: the exact engine is 8.4e-14
  off by event 17, the probes say ≤ 2e-15). Measured against the exact engine, the drift follows tol
  (case 0, event 17: 7.0e-9 at tol 1e-11, 4.3e-11 at tol 1e-13) and is ~1e5 times the exact engine's
  own error (7e-9 / 8.4e-14); bound max(1e-9, 5e5 S_j, 1e6 E_j), E_j the exact engine's largest error
  against the reference up to event j (itself held to its bound above).
Hypocentres and sizes must be identical for all 20 events in every engine (no coincident events in
these cases).
"""

from __future__ import annotations

import numpy as np
import pytest

import bifurcation as bf

import _indep_chain as ref
from _indep_sample import sample

CASES = [
    dict(law="piecewise-linear", n=5, ends="free", ell=1.7, nu=3e-3, nu_f=0.23, sigma=0.008, seed=11),
    dict(law="carlson-langer", n=6, ends="periodic", ell=0.8, nu=2e-4, nu_f=0.17, sigma=0.15, seed=12),
    dict(law="exponential", n=3, ends="free", ell=2.4, nu=7e-3, nu_f=0.27, sigma=0.25, seed=13),
    dict(law="piecewise-linear", n=4, ends="periodic", ell=1.2, nu=1.5e-3, nu_f=0.19, sigma=0.21, seed=14),
]
# case 3 (σ_f = 0.21 on the piecewise-linear law) ran only on the exact engines when written: the compiled
# engine then refused σ_f > 0.01 on a law with switches (lifted since; tests/test_chain_compiled.py)
COMPILED = [0, 1, 2]
FIELDS = ("t_start", "potency", "duration", "max_velocity")
_REF = {}


def _reference(i):
    if i not in _REF:
        cs = CASES[i]
        u0 = [float(x) for x in 0.3 * np.random.default_rng(cs["seed"]).random(cs["n"])]
        _REF[i] = u0, ref.chain_catalog(cs["law"], cs["n"], cs["ell"], cs["nu"], cs["nu_f"], u0, 20,
                                        ends=cs["ends"], sigma=cs["sigma"])
    return _REF[i]


def _run(i, u0, **kw):
    cs = CASES[i]
    return bf.chain(cs["law"], n=cs["n"], ell=cs["ell"], nu=cs["nu"], nu_f=cs["nu_f"], ends=cs["ends"], u0=u0,
                    events=20, sigma=cs["sigma"], **kw)


def _rel(r, j, e, f):
    return float(abs(getattr(r, f)[j] - e[f]) / max(1, abs(e[f])))


@pytest.mark.slow
@pytest.mark.parametrize("engine,i", sample([("quad", i) for i in range(len(CASES))] + [("exact", i) for i in range(len(CASES))]
                                            + [("compiled", i) for i in COMPILED], 4))
def test_chain_against_mpmath(engine, i):
    cs = CASES[i]
    u0, cat = _reference(i)
    kw = {"quad": {"precision": "quad"}, "exact": {}, "compiled": {"engine": "compiled", "verify": 1.0}}[engine]
    r = _run(i, u0, **kw)
    assert str(r.status) == "complete"
    assert list(r.hypocentre) == [e["hypocentre"] for e in cat]
    assert list(r.n_blocks) == [e["n_blocks"] for e in cat]
    if engine == "quad":
        bound = [1e-15] * 20
    else:
        e0 = _run(i, u0)
        sens = []
        for u1 in ([float(np.nextafter(u0[0], 1.0))] + list(u0[1:]), [float(np.nextafter(u, 1.0)) for u in u0]):
            e1 = _run(i, u1)
            sens.append([max(_rel(e1, j, {f: getattr(e0, f)[j] for f in FIELDS}, f) for f in FIELDS)
                         for j in range(20)])
        s = np.maximum.accumulate(np.max(sens, axis=0))
        if engine == "exact":
            bound = np.maximum(1e-12, 50 * s)
        else:
            # the exact engine's own error against the reference measures (rounding per event) ×
            # (the chain's amplification); the compiled engine's tol 1e-11 is ~1e5 roundings
            err_exact = np.maximum.accumulate([max(_rel(e0, j, e, f) for f in FIELDS) for j, e in enumerate(cat)])
            bound = np.maximum.reduce([np.full(20, 1e-9), 5e5 * s, 1e6 * err_exact])
    if engine == "compiled":
        assert r.verification["largest_any"] <= 1e-10
    for j, e in enumerate(cat):
        for f in FIELDS:
            assert _rel(r, j, e, f) <= bound[j], (engine, i, j, f, _rel(r, j, e, f), bound[j])
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
