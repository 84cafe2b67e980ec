"""The rate-and-state chain (N = 2, 3) and the slider with mass and radiation damping at random parameters
no test used, against helper indep4's own mpmath reference (tests/_indep4_rs.py on tests/_indep4_taylor.py:
own series recurrences at 40 digits, order 30; no code of the package).

Reference values: tests/data/indep4_rs.json (chains) and indep4_slider.json, made by tests/data/make_indep4_rs.py (deterministic seeds; the
parameter ranges are in its docstring).

Tolerances: hypocentres, sizes and extremum kinds identical; |Δ|/max(1, |x|) ≤ BOUND = 1e-12 for the
catalog's t_start, potency, duration, max_velocity and the extrema's times and ln V. The engines run
heyoka at tolerance ε (docs/rs-chain.md: "≤ 1.8e-14 from the mpmath references"; docs/rate-state.md); the
events are roots on Taylor polynomials, and t is absolute time (ulp(10) = 1.8e-15), so 1e-12 leaves ~50×
over what was measured here (chains ≤ 2.1e-14, sliders ≤ 6.3e-14: tests/data/indep4_report.md).
"""

from __future__ import annotations

import json
import pathlib

import numpy as np
import pytest
from mpmath import mp, mpf

_HERE = pathlib.Path(__file__).parent / "data"
DATA = {"chains": json.loads((_HERE / "indep4_rs.json").read_text())["chains"],
        "sliders": json.loads((_HERE / "indep4_slider.json").read_text())["sliders"]}
BOUND = 1e-12
FIELDS = ("t_start", "potency", "duration", "max_velocity")


def _rel(a, b):
    with mp.workdps(30):
        ref = mpf(b)
        return float(abs(mpf(float(a)) - ref) / max(1, abs(ref)))


def chain_errors(cs):
    from bifurcation.models.rs_chain import rs_chain
    r = rs_chain(n=cs["n"], state_law=cs["law"], a=cs["a"], b=cs["b"], dc=cs["dc"], k=cs["k"], ell=cs["ell"],
                 v_lp=cs["v_lp"], mass=cs["mass"], eta=cs["eta"], v_th=cs["v_th"], periodic=cs["periodic"],
                 amplitude=cs["amplitude"], seed=cs["seed"], events=len(cs["catalog"]))
    assert str(r.status) in ("complete", "RSChainStatus.COMPLETE") or len(r.potency) == len(cs["catalog"]), r.status
    same, worst = True, 0.0
    for j, e in enumerate(cs["catalog"]):
        same &= int(r.hypocentre[j]) == e["hypocentre"] and int(r.n_blocks[j]) == e["n_blocks"]
        worst = max(worst, *(_rel(getattr(r, f)[j], e[f]) for f in FIELDS))
    return same, worst


def slider_errors(cs):
    from bifurcation.models.rate_state import rate_state
    ref = cs["extrema"]
    t_end = float(mpf(ref[-1][0])) * (1 + 1e-9) if len(ref) == 8 else cs["t_end"]
    r = rate_state(a=cs["a"], b=cs["b"], dc=cs["dc"], state_law=cs["law"], k=cs["k"], v_lp=cs["v_lp"],
                   t=np.array([0.0, t_end]), mass=cs["mass"], damping=cs["eta"], v0=cs["v0"])
    got = np.asarray(r.extrema)
    same = len(got) >= len(ref) and all(int(got[i][2]) == ref[i][2] for i in range(len(ref)))
    worst = 0.0
    for i in range(min(len(ref), len(got))):
        worst = max(worst, _rel(got[i][0], ref[i][0]), _rel(got[i][1], ref[i][1]))
    if "v_end" in cs:
        worst = max(worst, _rel(np.asarray(r.v)[-1], cs["v_end"]))
    return same, worst, len(got)


CHAINS = {c["i"]: c for c in DATA["chains"]}
SLIDERS = {c["i"]: c for c in DATA["sliders"]}


@pytest.mark.parametrize("i", sorted(CHAINS)[:2])
def test_rs_chain_against_own_reference_fast(i):
    same, worst = chain_errors(CHAINS[i])
    assert same and worst <= BOUND, (i, same, worst)


@pytest.mark.parametrize("i", sorted(SLIDERS)[:2])
def test_damped_inertial_slider_against_own_reference_fast(i):
    same, worst, _ = slider_errors(SLIDERS[i])
    assert same and worst <= BOUND, (i, same, worst)


@pytest.mark.slow
@pytest.mark.parametrize("i", sorted(CHAINS)[2:])
def test_rs_chain_against_own_reference(i):
    same, worst = chain_errors(CHAINS[i])
    assert same and worst <= BOUND, (i, same, worst)


@pytest.mark.slow
@pytest.mark.parametrize("i", sorted(SLIDERS)[2:])
def test_damped_inertial_slider_against_own_reference(i):
    same, worst, _ = slider_errors(SLIDERS[i])
    assert same and worst <= BOUND, (i, same, worst)


if __name__ == "__main__":
    for i, cs in sorted(CHAINS.items()):
        same, worst = chain_errors(cs)
        print(f"chain {i} {cs['law']} N={cs['n']} M={cs['mass']:.2g} eta={cs['eta']:.2g} periodic={cs['periodic']} "
              f"same={same} max_err={worst:.2e}", flush=True)
    for i, cs in sorted(SLIDERS.items()):
        same, worst, ng = slider_errors(cs)
        print(f"slider {i} {cs['law']} k/k_c={cs['k'] * cs['dc'] / (cs['b'] - cs['a']):.2f} M={cs['mass']:.2g} "
              f"eta={cs['eta']:.2g} extrema={len(cs['extrema'])}/{ng} same={same} max_err={worst:.2e}", flush=True)
