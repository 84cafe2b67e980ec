"""Generate tests/data/chain_sigma0_golden.json: catalogs of the chain engine *before* the friction drop σ
was added (issue 17), to prove that σ = 0 stays bit-identical.

Run on the unmodified engine (it was: main at 7d25016, before any σ code existed), once:

    PYTHONPATH=. python tests/chain_sigma0_golden_gen.py

Every float is stored as ``float.hex`` (every bit). ``tests/test_chain_sigma.py`` recomputes the same
catalogs with today's engine (σ left at its default and σ = 0 given explicitly) and requires equality
bit for bit. Do not regenerate it with a changed engine: that would make the test vacuous.
"""

from __future__ import annotations

import json
import subprocess
import sys
from pathlib import Path

from bifurcation.models.chain import chain

FIELDS = ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity", "steps")
CASES = [
    # law, n, ends, ell, nu, nu_f, amplitude, seed, events, precision
    ("carlson-langer", 1, "free", 1.0, 1e-3, 0.3, 0.0, 1, 5, "double"),
    ("carlson-langer", 8, "free", 1.0, 1e-2, 0.3, 0.5, 3, 60, "double"),
    ("carlson-langer", 16, "periodic", 3.0, 1e-4, 0.05, 0.5, 5, 300, "double"),
    ("piecewise-linear", 8, "periodic", 1.0, 1e-4, 0.3, 0.5, 7, 60, "double"),
    ("piecewise-linear", 12, "free", 2.0, 1e-6, 0.15, 0.5, 2, 200, "double"),
    ("exponential", 6, "free", 1.0, 1e-3, 0.3, 0.5, 4, 40, "double"),
    ("1/(1 + x/2)^2", 6, "periodic", 1.0, 1e-3, 0.3, 0.5, 9, 40, "double"),
    ("carlson-langer", 4, "free", 1.0, 1e-4, 0.3, 0.5, 3, 10, "quad"),
]


def run(case) -> dict:
    law, n, ends, ell, nu, nu_f, amp, seed, events, precision = case
    r = chain(law, n=n, ell=ell, nu=nu, nu_f=nu_f, ends=ends, amplitude=amp, seed=seed, events=events,
              precision=precision)
    out = {"case": list(case), "status": str(r.status)}
    for f in FIELDS:
        arr = getattr(r, f)
        out[f] = [int(x) for x in arr] if arr.dtype.kind == "i" else [float(x).hex() for x in arr]
    out["t"] = float(r.t).hex()
    out["u"] = [float(x).hex() for x in r.u]
    out["stress"] = [float(x).hex() for x in r.stress]
    return out


def cpu() -> dict:
    """The CPU features heyoka's code generation depends on (bit-identity is a same-features property)."""
    import platform

    flags = set()
    try:
        for line in open("/proc/cpuinfo"):
            if line.startswith("flags"):
                flags = set(line.split(":", 1)[1].split())
                break
    except OSError:
        pass
    return {"machine": platform.machine(), "features": sorted(f for f in ("avx2", "avx512f", "fma") if f in flags)}


def main() -> None:
    head = subprocess.run(["git", "rev-parse", "HEAD"], capture_output=True, text=True).stdout.strip()
    doc = {"generator": "tests/chain_sigma0_golden_gen.py", "engine_commit": head, "fields": FIELDS,
           "cases": [run(c) for c in CASES], "cpu": cpu()}
    out = Path(__file__).parent / "data" / "chain_sigma0_golden.json"
    out.write_text(json.dumps(doc, indent=1) + "\n")
    print("wrote", out, file=sys.stderr)


if __name__ == "__main__":
    main()
