"""Regenerate tests/data/indep4_rs.json: the rate-and-state chain (N = 2, 3) and the slider with mass and
radiation damping at random parameters, by helper indep4's own mpmath reference tests/_indep4_rs.py (own
Taylor recurrences, tests/_indep4_taylor.py, 40 digits, order 30; no code of the package).

    python tests/data/make_indep4_rs.py chains      # -> tests/data/indep4_rs.json
    python tests/data/make_indep4_rs.py sliders     # -> tests/data/indep4_slider.json

Chains (default_rng([44, i])): aging or slip; a ∈ [0.005, 0.02], b = a·U(1.2, 2), Dc log-uniform on
[0.005, 0.05], k = k_c·U(0.1, 0.8) with k_c = (b − a)/Dc; ℓ log-uniform on [0.3, 3]; V_lp log-uniform on
[0.1, 10], v_th = V_lp·U(2, 20); quasi-dynamic (M = 0, η = 10^U(−4, −2)) or inertial (M = 10^U(−5, −3),
η = 0 or 10^U(−4, −2)); free or periodic; amplitude U(0.5, 1.5), seed 0..999; 2 events. A case whose reference needs more than 4000
steps (deep inertial cycles: the fast mode a/(MV) at small V) is skipped and listed in ``skipped``.
Sliders (default_rng([45, i])): aging or slip; a, b, Dc as above; k = k_c·U(0.3, 2) (both sides of the
quasi-static critical stiffness: stick-slip cycles, and decay to steady sliding); V_lp log-uniform on
[0.1, 10], v0 = V_lp·10^U(−0.5, 0.5); M = 10^U(−5, −3); η = 10^U(−4, −2); the first 8 ln V extrema
within t_end = 20(b − a)/(k V_lp) + 20 Dc/V_lp (five times that from slider 8 on: some of the first eight
saw one extremum only), and the state there.
"""

from __future__ import annotations

import json
import math
import pathlib
import sys
import time

import numpy as np

HERE = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(HERE.parent))

CHAINS, SLIDERS = 14, 16


def chain_case(i):
    r = np.random.default_rng([44, i])
    law = ["aging", "slip"][i % 2]
    a = float(r.uniform(0.005, 0.02))
    b = float(a * r.uniform(1.2, 2.0))
    dc = float(10 ** r.uniform(math.log10(0.005), math.log10(0.05)))
    k = float((b - a) / dc * r.uniform(0.1, 0.8))
    ell = float(10 ** r.uniform(math.log10(0.3), math.log10(3)))
    v_lp = float(10 ** r.uniform(-1, 1))
    v_th = float(v_lp * r.uniform(2, 20))
    inertial = r.random() < 0.4
    mass = float(10 ** r.uniform(-5, -3)) if inertial else 0.0
    eta = float(10 ** r.uniform(-4, -2)) if (not inertial or r.random() < 0.5) else 0.0
    return dict(i=i, n=2 + int(r.integers(0, 2)), law=law, a=a, b=b, dc=dc, k=k, ell=ell, v_lp=v_lp, v_th=v_th,
                mass=mass, eta=eta, periodic=bool(r.random() < 0.5), amplitude=float(r.uniform(0.5, 1.5)),
                seed=int(r.integers(0, 1000)), events=2)


def slider_case(i):
    r = np.random.default_rng([45, i])
    law = ["aging", "slip"][i % 2]
    a = float(r.uniform(0.005, 0.02))
    b = float(a * r.uniform(1.2, 2.0))
    dc = float(10 ** r.uniform(math.log10(0.005), math.log10(0.05)))
    k = float((b - a) / dc * r.uniform(0.3, 2.0))
    v_lp = float(10 ** r.uniform(-1, 1))
    v0 = float(v_lp * 10 ** r.uniform(-0.5, 0.5))
    mass = float(10 ** r.uniform(-5, -3))
    eta = float(10 ** r.uniform(-4, -2))
    t_end = (20 * (b - a) / (k * v_lp) + 20 * dc / v_lp) * (1 if i < 8 else 5)
    return dict(i=i, law=law, a=a, b=b, dc=dc, k=k, v_lp=v_lp, v0=v0, mass=mass, eta=eta, t_end=t_end)


def main(which):
    import _indep4_rs as ref
    from mpmath import mp, nstr
    doc = {"provenance": "tests/data/make_indep4_rs.py (helper indep4's tests/_indep4_rs.py: mpmath 40 digits, "
                         "Taylor order 30)", "digits": 25, "chains": [], "sliders": []}
    path = HERE / ("indep4_rs.json" if which == "chains" else "indep4_slider.json")
    if which == "chains" and path.exists():          # resume: keep the chains done and skipped
        old = json.loads(path.read_text())
        doc["chains"], doc["skipped"] = old.get("chains", []), old.get("skipped", [])
    seen = {c["i"] for c in doc["chains"]} | {q.get("chain") for q in doc.get("skipped", [])}
    for i in range(CHAINS if which == "chains" else 0):
        if i in seen:
            continue
        cs = chain_case(i)
        t0 = time.process_time()
        try:
            cat = ref.rs_chain_events(max_steps=4000, **{q: v for q, v in cs.items() if q != "i"})
        except RuntimeError as err:
            print("chain", i, "skipped:", err, flush=True)
            doc.setdefault("skipped", []).append({"chain": i, "reason": str(err)})
            continue
        with mp.workdps(40):
            cs["catalog"] = [{f: (int(e[f]) if f in ("hypocentre", "n_blocks") else nstr(e[f], 25)) for f in e}
                             for e in cat]
        cs["cpu_seconds"] = round(time.process_time() - t0, 1)
        doc["chains"].append(cs)
        print("chain", i, cs["law"], cs["n"], cs["mass"], cs["eta"], cs["cpu_seconds"], flush=True)
        path.write_text(json.dumps(doc, indent=1) + "\n")
    for i in range(SLIDERS if which == "sliders" else 0):
        cs = slider_case(i)
        t0 = time.process_time()
        try:
            ext, x = ref.slider_extrema(max_extrema=8, max_steps=4000, **{q: v for q, v in cs.items() if q != "i"})
        except RuntimeError as err:
            print("slider", i, "skipped:", err, flush=True)
            doc.setdefault("skipped", []).append({"slider": i, "reason": str(err)})
            continue
        with mp.workdps(40):
            cs["extrema"] = [[nstr(t, 25), nstr(lv, 25), s] for t, lv, s in ext]
            if len(ext) < 8:
                cs["v_end"], cs["theta_end"] = nstr(x[0], 25), nstr(x[1], 25)
        cs["cpu_seconds"] = round(time.process_time() - t0, 1)
        doc["sliders"].append(cs)
        print("slider", i, cs["law"], len(ext), cs["cpu_seconds"], flush=True)
        path.write_text(json.dumps(doc, indent=1) + "\n")


if __name__ == "__main__":
    main(sys.argv[1])
