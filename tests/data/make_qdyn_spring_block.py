"""Run QDYN's spring-block (MESHDIM = 0, radiation damping on) on the cases of tests/data/qdyn_spring_block.json.

    python tests/data/make_qdyn_spring_block.py /path/to/qdyn/src [--acc 1e-11] [--tmax-periods 400]

QDYN (github.com/ydluo/qdyn; its code is not part of this repository) must be built in that directory
(``make`` with gfortran and OpenMPI's mpif90: the executable ``qdyn`` beside ``pyqdyn.py``). QDYN
integrates (its docs, "model assumptions"; derivs_all.f90):

    dV/dt = [k(V_pl − V) − σ (b/θ) dθ/dt] / (σ a/V + η),   k = MU/L,   η = MU/(2 VS),

which is this package's quasi-static damped slider with k/σ and η/σ (docs/rate-state.md). Each case
starts off steady sliding (V0 = 1.5 V_pl, θ0 = Dc/V_pl), runs ``tmax-periods`` linear periods with
output at every solver step, and reads off the attracting cycle from the last 20 % of the run:

- period: mean spacing of the upward crossings of V = V_pl (times by linear interpolation of ln V
  between output steps), with the spread of the individual periods;
- ln(V_max/V_pl), ln(V_min/V_pl): per cycle, the largest/smallest output point refined by the
  parabola through it and its two neighbours; the median over the cycles.

QDYN writes V with 8 significant digits (format e15.7) and t with 15: that, and its solver tolerance
ACC, bound what these numbers can show. Output: JSON on stdout (the case parameters, QDYN's git
commit when given with --commit, the numbers above).
"""

from __future__ import annotations

import argparse
import json
import math
import os
import shutil
import sys
import tempfile

import numpy as np

# The cases: a = 0.01, b = 0.015, Dc = 1e-4 m, σ = 1e7 Pa, V_pl = 1e-3 m/s, shear modulus 3e10 Pa,
# VS = 1500 m/s (η = MU/(2 VS) = 1e7 Pa s/m, η/σ = 1 s/m: ηV_pl = 1e-3 = 20 % of b − a), so
# k_c = σ(b − a − ηV_pl/σ)/Dc = 4e8 Pa/m; k = κ k_c through L = MU/k.
BASE = {"a": 0.01, "b": 0.015, "dc": 1e-4, "sigma": 1e7, "v_pl": 1e-3, "mu": 3e10, "vs": 1500.0, "mu0": 0.6}
KAPPAS = (0.5, 0.8, 0.9, 0.98)
LAWS = {"aging": 1, "slip": 2}


def slider_parameters(case: dict) -> dict:
    """The case in this package's units (k and η per unit normal stress)."""
    eta = case["mu"] / (2 * case["vs"]) / case["sigma"]
    k_c = (case["b"] - case["a"] - eta * case["v_pl"]) / case["dc"]
    return {"k": case["kappa"] * k_c, "damping": eta, "k_c": k_c}


#: QDYN's own test case test/stickslip.py ("RSF" mode) with pyqdyn's defaults for what it leaves out:
#: V_PL = 1e-6, MU = 2e10, L = 10 (k = MU/L), SIGMA = 5e7, VS = 3000, A = 0.01, B = 0.025, DC = 1e-5,
#: V_SS = 1e-6 (pyqdyn default), MU_SS = 0.6, aging law (THETA_LAW = 1), V0 = 0.9 V_PL, θ0 = DC/V_PL.
#: k/k_c = 0.0267: a deep stick-slip cycle (ln V/V_PL from −25 to +15). Its TMAX = 1e4 s is ~1.3 cycles;
#: here the run is long enough to settle on the cycle.
STICKSLIP = {"v_pl": 1e-6, "mu": 2e10, "l": 10.0, "sigma": 5e7, "vs": 3000.0, "a": 0.01, "b": 0.025, "dc": 1e-5,
             "mu0": 0.6}


def run_stickslip(src: str, acc: float, tmax: float) -> dict:
    """QDYN's stickslip test case run to ``tmax``; its cycle read off the last third of the run."""
    sys.path.insert(0, src)
    from pyqdyn import qdyn   # noqa: PLC0415

    c = STICKSLIP
    work = tempfile.mkdtemp(prefix="qdyn_")
    cwd = os.getcwd()
    os.chdir(work)
    try:
        p = qdyn()
        s = p.set_dict
        s.update({"MESHDIM": 0, "TMAX": tmax, "NTOUT": 10 ** 9, "NTOUT_OT": 1, "V_PL": c["v_pl"], "MU": c["mu"],
                  "VS": c["vs"], "SIGMA": c["sigma"], "L": c["l"], "ACC": acc, "SOLVER": 2,
                  "FRICTION_MODEL": "RSF", "V_TH": 1e300})
        s["SET_DICT_RSF"].update({"RNS_LAW": 0, "THETA_LAW": 1, "A": c["a"], "B": c["b"], "DC": c["dc"],
                                  "V_SS": c["v_pl"], "MU_SS": c["mu0"], "V_0": 0.9 * c["v_pl"],
                                  "TH_0": c["dc"] / c["v_pl"]})
        p.settings(s)
        p.render_mesh()
        p.write_input()
        p.run(test=True)
        ot = np.loadtxt("output_ot_0", comments="#")
    finally:
        os.chdir(cwd)
        shutil.rmtree(work, ignore_errors=True)
    t, x = ot[:, 0], np.log(ot[:, 3] / c["v_pl"])
    keep = t >= t[-1] * 2 / 3
    t, x = t[keep], x[keep]
    up = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    t_up = t[up] - x[up] * (t[up + 1] - t[up]) / (x[up + 1] - x[up])
    peaks, troughs = [], []
    for lo, hi in zip(up[:-1], up[1:]):
        for pick, out in ((np.argmax, peaks), (np.argmin, troughs)):
            i = lo + 1 + int(pick(x[lo + 1:hi + 1]))
            cf = np.polyfit(t[i - 1:i + 2] - t[i], x[i - 1:i + 2], 2)
            out.append(cf[2] - cf[1] ** 2 / (4 * cf[0]) if cf[0] != 0 else x[i])
    return {"acc": acc, "tmax": tmax, "periods": np.diff(t_up).tolist(), "ln_v_max": peaks, "ln_v_min": troughs,
            "k": c["mu"] / c["l"] / c["sigma"], "damping": c["mu"] / (2 * c["vs"]) / c["sigma"]}


def run_case(src: str, law: str, kappa: float, acc: float, tmax_periods: float) -> dict:
    sys.path.insert(0, src)
    from pyqdyn import qdyn   # noqa: PLC0415 (QDYN's own wrapper, from its source tree)

    case = dict(BASE, kappa=kappa, law=law)
    sp = slider_parameters(case)
    a_eff = case["a"] + sp["damping"] * case["v_pl"]
    omega = case["v_pl"] / case["dc"] * math.sqrt((case["b"] - a_eff) / a_eff)
    tmax = tmax_periods * 2 * math.pi / omega
    work = tempfile.mkdtemp(prefix="qdyn_")
    cwd = os.getcwd()
    os.chdir(work)
    try:
        p = qdyn()
        s = p.set_dict
        s.update({"MESHDIM": 0, "TMAX": tmax, "NTOUT": 10 ** 9, "NTOUT_OT": 1, "V_PL": case["v_pl"],
                  "MU": case["mu"], "VS": case["vs"], "SIGMA": case["sigma"], "L": case["mu"] / (sp["k"] * case["sigma"]),
                  "ACC": acc, "SOLVER": 2, "FRICTION_MODEL": "RSF", "V_TH": 1e300})
        s["SET_DICT_RSF"].update({"RNS_LAW": 0, "THETA_LAW": LAWS[law], "A": case["a"], "B": case["b"],
                                  "DC": case["dc"], "V_SS": case["v_pl"], "MU_SS": case["mu0"],
                                  "V_0": 1.5 * case["v_pl"], "TH_0": case["dc"] / case["v_pl"]})
        p.settings(s)
        p.render_mesh()
        p.write_input()
        p.run(test=True)
        # QDYN's time series (columns t, pot, pot_rate, V, θ, τ, dτ/dt, slip, σ), read directly
        # (pyqdyn's reader uses a pandas option that pandas 2 removed)
        ot = np.loadtxt("output_ot_0", comments="#")
        t = ot[:, 0]
        x = np.log(ot[:, 3] / case["v_pl"])
    finally:
        os.chdir(cwd)
        shutil.rmtree(work, ignore_errors=True)
    keep = t >= 0.8 * t[-1]
    t, x = t[keep], x[keep]
    up = np.flatnonzero((x[:-1] < 0) & (x[1:] >= 0))
    t_up = t[up] - x[up] * (t[up + 1] - t[up]) / (x[up + 1] - x[up])
    periods = np.diff(t_up)
    peaks, troughs = [], []
    for lo, hi in zip(up[:-1], up[1:]):
        # the largest and smallest output point of each cycle, refined by the parabola through it
        # and its two neighbours (the vertex value)
        for pick, out in ((np.argmax, peaks), (np.argmin, troughs)):
            i = lo + 1 + int(pick(x[lo + 1:hi + 1]))
            c = np.polyfit(t[i - 1:i + 2] - t[i], x[i - 1:i + 2], 2)
            out.append(c[2] - c[1] ** 2 / (4 * c[0]) if c[0] != 0 else x[i])
    return {"law": law, "kappa": kappa, **sp, "period": float(periods.mean()),
            "period_spread": float(periods.max() - periods.min()), "cycles": int(periods.size),
            "ln_v_max": float(np.median(peaks)), "ln_v_min": float(np.median(troughs)),
            "ln_v_max_spread": float(np.ptp(peaks)), "ln_v_min_spread": float(np.ptp(troughs)),
            "output_steps": int(keep.sum())}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("src", help="QDYN's src directory, built (qdyn executable beside pyqdyn.py)")
    ap.add_argument("--acc", type=float, default=1e-11)
    ap.add_argument("--tmax-periods", type=float, default=400.0)
    ap.add_argument("--commit", default="", help="QDYN's git commit, recorded in the output")
    ap.add_argument("--laws", default="aging,slip")
    ap.add_argument("--kappas", default=",".join(map(str, KAPPAS)))
    ap.add_argument("--stickslip-tmax", type=float, default=0.0,
                    help="also run QDYN's stickslip test case to this time (s), at ACC 1e-7 and --acc")
    args = ap.parse_args()
    cases = [run_case(os.path.abspath(args.src), law, float(k), args.acc, args.tmax_periods)
             for law in args.laws.split(",") for k in args.kappas.split(",")]
    doc = {"generator": "tests/data/make_qdyn_spring_block.py", "qdyn_commit": args.commit,
           "acc": args.acc, "solver": "RK45 (SOLVER = 2)", "tmax_periods": args.tmax_periods,
           "base": BASE, "cases": cases}
    if args.stickslip_tmax > 0:
        doc["stickslip"] = {"case": STICKSLIP, "runs": [run_stickslip(os.path.abspath(args.src), acc, args.stickslip_tmax)
                                                        for acc in (1e-7, args.acc)]}
    print(json.dumps(doc, indent=1))


if __name__ == "__main__":
    main()
