"""Generate tests/data/fading_reference.json: Δ and Δ0 of fading laws from the mpmath Taylor reference.

Run once (about an hour on one core; the values do not depend on the machine):

    python tests/make_fading_reference.py [--only-missing]
    # or in two processes, then merged:
    python tests/make_fading_reference.py --part=0/2 & python tests/make_fading_reference.py --part=1/2
    python tests/make_fading_reference.py --merge
    python tests/make_fading_reference.py --table    # the engine's errors against the file

Each value comes from ``bifurcation.reference_taylor`` (an mpmath Taylor integrator that shares no
code with the engine or the law parser) at dps 30 with 10 guard digits, i.e. good to ≪ 1e-25
relative; it is stored as a 30-digit decimal string. ν and ν_f are the floats listed (their exact
binary values, the same the engine sees). The file is rewritten after every point, so an interrupted
run keeps what it has and ``--only-missing`` resumes it.
"""

from __future__ import annotations

import json
import math
import pathlib
import sys
import time

import mpmath

ROOT = pathlib.Path(__file__).resolve().parent
sys.path.insert(0, str(ROOT.parent))

from bifurcation.reference_taylor import taylor_cycle, taylor_limit  # noqa: E402

OUT = ROOT / "data" / "fading_reference.json"
DPS = 30

FADING = ("exp(-x)", "exp(-x - x^2)", "exp(-x - x^3)")
OTHERS = ("1/(1 + x)", "exp(-x/2)/(1 + x/2)", "piecewise(1 - x, 0.5, 0.5*exp(1 - 2*x))")
NUS = (1e-3, 1e-11, 1e-18)
NU_FS = (1e-4, 1e-3, 7.5e-3, 0.05, 0.3, 1.0)
OTHER_NU_FS = (1e-3, 0.05)
LIMIT_NU_FS = (1e-3, 0.05, 0.5)
#: laws added after the first file: a Gaussian fade, an algebraic square, three pieces (two breakpoints),
#: each on both sides of the transition (ν_f = 0.45 stick-slip, 0.7 creep at these ν)
LATER = ("exp(-x - x^2/2)", "1/(1 + x/2)^2", "piecewise(1 - x, 0.5, 0.75 - x/2, 1.5, 0)")
LATER_NU_FS = (1e-3, 0.05, 0.45, 0.7)


def _jobs():
    """The issue's failing cases first, then a coarse cover of every law, then the rest of the grid."""
    for law, nu, nu_f in (("exp(-x)", 1e-3, 1e-3), ("exp(-x)", 1e-18, 1e-3), ("exp(-x)", 1e-7, 5e-3),
                          ("exp(-x)", 1e-11, 7.5e-3), ("exp(-x - x^2)", 1e-3, 0.05),
                          ("exp(-x - x^2)", 1e-11, 0.05), ("exp(-x - x^2)", 1e-3, 0.08),
                          ("exp(-x - x^2)", 1e-11, 0.08)):
        yield "cycle", law, nu, nu_f
    yield "limit", "exp(-x)", None, 1e-3
    yield "limit", "exp(-x)", None, 5e-3
    for law in FADING:
        for nu_f in (1e-4, 1e-3, 0.05, 1.0):
            for nu in (1e-3, 1e-18):
                yield "cycle", law, nu, nu_f
    for law in FADING:
        for nu_f in LIMIT_NU_FS:
            yield "limit", law, None, nu_f
    for law in OTHERS:
        for nu_f in OTHER_NU_FS:
            yield "cycle", law, 1e-11, nu_f
        yield "limit", law, None, 0.05
    for law in FADING:
        for nu_f in NU_FS:
            for nu in NUS:
                yield "cycle", law, nu, nu_f
    for law in OTHERS:
        for nu_f in OTHER_NU_FS:
            yield "cycle", law, 1e-3, nu_f
        for nu_f in LIMIT_NU_FS:
            yield "limit", law, None, nu_f
    for law in LATER:
        for nu_f in LATER_NU_FS:
            for nu in (1e-3, 1e-12):
                yield "cycle", law, nu, nu_f
        for nu_f in (0.05, 0.45):
            yield "limit", law, None, nu_f


def _key(kind, law, nu, nu_f):
    return f"{kind}|{law}|{nu!r}|{nu_f!r}"


def _done(path) -> dict:
    try:
        return json.loads(path.read_text()).get("points", {})
    except (OSError, ValueError):
        return {}


def _merge() -> None:
    data = json.loads(OUT.read_text()) if OUT.exists() else {"points": {}}  # never lose stored points
    for part in sorted(OUT.parent.glob("fading_reference.part*.json")):
        loaded = json.loads(part.read_text())
        data["points"].update(loaded["points"])
        data["meta"] = loaded["meta"]
    OUT.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")
    print(f"{OUT}: {len(data['points'])} points")


def _table() -> None:
    """Print the engine's relative errors against the stored values as a Markdown table."""
    import bifurcation as bf

    names = {"exp(-x)": "exponential", "1/(1 + x)": "carlson-langer"}
    points = json.loads(OUT.read_text())["points"].values()
    print("| law | ν | ν_f | double | quad | batch 4 | status |\n|---|---|---|---|---|---|---|")
    for p in sorted(points, key=lambda p: (p["kind"], p["law"], p["nu_f"], -(p["nu"] or 0))):
        law = names.get(p["law"], p["law"])
        if p["kind"] == "cycle":
            ref = mpmath.mpf(p["delta"])
            runs = [bf.slip(law, nu=p["nu"], nu_f=p["nu_f"], precision=pr) for pr in ("double", "quad")]
            runs.append(bf.slip(law, nu=[p["nu"]] * 2, nu_f=[p["nu_f"]] * 2, batch=4))
            errors = [abs(float(r.delta.ravel()[0] / ref - 1)) for r in runs]
            status, nu = runs[0].status_names().item(), f"{p['nu']:g}"
        else:
            ref = mpmath.mpf(p["delta0"])
            runs = [bf.limit(law, nu_f=p["nu_f"], precision=pr) for pr in ("double", "quad")]
            errors = [abs(float(r.delta0.item() / ref - 1)) for r in runs] + [math.nan]
            status, nu = "limit Δ0", "→ 0"
        print(f"| {p['law']} | {nu} | {p['nu_f']:g} | " + " | ".join(
            "—" if e != e else f"{e:.1e}" for e in errors) + f" | {status} |", flush=True)


def main(argv) -> None:
    if "--merge" in argv:
        return _merge()
    if "--table" in argv:
        return _table()
    # --part k/m: every m-th job from the k-th, into its own file (run m processes, then --merge)
    k, m = next((tuple(map(int, a.split("=")[1].split("/"))) for a in argv if a.startswith("--part=")), (0, 1))
    out = OUT.with_name(f"fading_reference.part{k}.json") if m > 1 else OUT
    data = json.loads(out.read_text()) if out.exists() and "--only-missing" in argv else {}
    meta = {"generator": "tests/make_fading_reference.py", "reference": "bifurcation/reference_taylor.py",
            "dps": DPS}
    jobs = list(dict.fromkeys(_jobs()))  # each point once, in order
    for index, (kind, law, nu, nu_f) in enumerate(jobs):
        key = _key(kind, law, nu, nu_f)
        if index % m != k or any(key in _done(p) for p in OUT.parent.glob("fading_reference*.json")):
            continue
        start = time.time()
        if kind == "cycle":
            r = taylor_cycle(law, nu, nu_f, dps=DPS)
            value = {"delta": mpmath.nstr(r["delta"], DPS), "stop_time": mpmath.nstr(r["stop_time"], DPS)}
        else:
            r = taylor_limit(law, nu_f, dps=DPS)
            value = {"delta0": mpmath.nstr(r["delta0"], DPS)}
        value.update(kind=kind, law=law, nu=nu, nu_f=nu_f, steps=r["steps"])
        data.setdefault("points", {})[key] = value
        data["meta"] = meta
        out.write_text(json.dumps(data, indent=1, sort_keys=True) + "\n")
        print(f"{key}: {value.get('delta', value.get('delta0'))} ({r['steps']} steps, "
              f"{time.time() - start:.1f} s)", flush=True)


if __name__ == "__main__":
    main(sys.argv[1:])
