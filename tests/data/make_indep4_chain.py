"""Regenerate tests/data/indep4_chain.json: random chains against helper indep4's own mpmath reference
tests/_indep4_chain.py (own Taylor recurrences and event location at 40 digits, order 40; no code of the
package).

    python tests/data/make_indep4_chain.py [CASES [K ...]]     # ~0.05-5 s of CPU per event

Case k draws from numpy.random.default_rng([4, k]) (deterministic): the law in turn over the five of
``_indep4_chain.LAWS``; N uniform on 1..8; free or periodic ends; ℓ log-uniform on [0.2, 20]; σ_f from
{0, 0.01, 0.05, 0.3}; ν log-uniform on [1e-6, 1e-2]; ν_f = ν_f* · 10^U(−0.4, 0.4), ν_f* the lone-block
threshold 1/(2√k) of docs/chain.md "Threshold of a lone block" (k = 1 for N = 1, 1 + ℓ² at a free end,
1 + 2ℓ² in the interior, which of the two drawn for free chains of N ≥ 3), so both sides of it are run;
u0_j = −A r_j with A = U(0.2, 0.9)/(1 + 4ℓ²) (every σ_j(0) < 1). Each event is integrated from the
previous one's end state rounded to doubles, which the json records (the engine is restored to it).
Cases 1-3 are also run at 50 digits, order 50: their largest difference is recorded as ``self_check``.
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

EVENTS = 20
FIELDS = ("t_start", "potency", "duration", "max_velocity")


def case(k: int) -> dict:
    import _indep4_chain as ref
    r = np.random.default_rng([4, k])
    law = ref.LAWS[k % len(ref.LAWS)]
    n = int(r.integers(1, 9))
    ends = "periodic" if r.random() < 0.5 else "free"
    ell = float(10 ** r.uniform(math.log10(0.2), math.log10(20)))
    sigma = float(r.choice([0.0, 0.01, 0.05, 0.3]))
    nu = float(10 ** r.uniform(-6, -2))
    if n == 1:
        kk = 1.0
    elif ends == "periodic" or (n >= 3 and r.random() < 0.5):
        kk = 1 + 2 * ell ** 2
    else:
        kk = 1 + ell ** 2
    nu_f = float(10 ** r.uniform(-0.4, 0.4) / (2 * math.sqrt(kk)))
    amp = float(r.uniform(0.2, 0.9) / (1 + 4 * ell ** 2))
    u0 = [float(-amp * x) for x in r.random(n)]
    return dict(k=k, law=law, n=n, ends=ends, ell=ell, sigma=sigma, nu=nu, nu_f=nu_f, threshold_k=kk, u0=u0)


def run_case(cs: dict, events: int, dps: int = 40, order: int = 40) -> list:
    import _indep4_chain as ref
    from mpmath import mp, nstr
    cat = ref.catalog(cs["law"], cs["n"], cs["ell"], cs["nu"], cs["nu_f"], cs["ends"], cs["sigma"], cs["u0"],
                      events, dps=dps, order=order)
    out = []
    with mp.workdps(dps):
        for state, e in cat:
            out.append({"state": {"sigma": state[0], "u": state[1], "t": state[2]},
                        "hypocentre": e["hypocentre"], "n_blocks": e["n_blocks"], "steps": e["steps"],
                        **{f: nstr(e[f], 25) for f in FIELDS}})
    return out


def main():
    from mpmath import mpf
    ncases = int(sys.argv[1]) if len(sys.argv) > 1 else 30
    path = HERE / "indep4_chain.json"
    doc = json.loads(path.read_text()) if path.exists() else {}
    done = {c["k"]: c for c in doc.get("cases", [])}
    # cheap cases first (cost grows with ℓ·N: the steps follow the fastest mode)
    only = [int(a) for a in sys.argv[2:]]      # optional: just these cases
    for k in sorted(only or range(ncases), key=lambda q: case(q)["ell"] * case(q)["n"]):
        if k in done:
            continue
        cs = case(k)
        t0 = time.process_time()
        cs["events"] = run_case(cs, EVENTS)
        cs["cpu_seconds"] = round(time.process_time() - t0, 1)
        if k in (1, 2, 3):
            hi = run_case(cs, EVENTS, dps=50, order=50)
            cs["self_check"] = max(float(abs(mpf(a[f]) - mpf(b[f])) / max(1, abs(mpf(b[f]))))
                                   for a, b in zip(cs["events"], hi) for f in FIELDS)
            assert all(a["hypocentre"] == b["hypocentre"] and a["n_blocks"] == b["n_blocks"]
                       for a, b in zip(cs["events"], hi))
        if path.exists():                      # merge with what another run wrote meanwhile
            done.update({c["k"]: c for c in json.loads(path.read_text())["cases"] if c["k"] not in done})
        done[k] = cs
        print(k, cs["law"], cs["n"], cs["ends"], "cpu", cs["cpu_seconds"], cs.get("self_check"), flush=True)
        doc = {"provenance": "tests/data/make_indep4_chain.py (helper indep4's tests/_indep4_chain.py: "
                             "mpmath 40 digits, Taylor order 40; each event from the previous end state rounded "
                             "to doubles)", "digits": 25, "events_per_case": EVENTS,
               "cases": [done[i] for i in sorted(done)]}
        path.write_text(json.dumps(doc, indent=1) + "\n")


if __name__ == "__main__":
    main()
