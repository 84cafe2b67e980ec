"""Compile what the fast suite's numba tests use into numba's disk cache: the compiled chain engine's
Carlson–Langer loop (its Taylor method and DOP853 are one specialization; the tape's loop, every other law,
runs in slow tests only: compiled here when they are selected, argv) and the RK4 baselines (tests/conftest.py runs this in a subprocess on a cold cache;
~35-50 s of CPU, see conftest.py). Prints what it compiled."""

import sys

from bifurcation.laws import resolve_law
from bifurcation.models.chain._bench_rk4 import run_rk4
from bifurcation.models.chain._compiled import CompiledChain
from bifurcation.models.chain._validate import check_initial

u0 = check_initial(6, 1.0, "free", None, 0.1, 3)
for law in sys.argv[1:] or ["carlson-langer"]:   # one law of each kind to compile: carlson-langer, exp(-x)
    run = CompiledChain(resolve_law(law), 6, 1.0, 1e-3, 0.3, "free", u0)
    if not run.compiled():
        run.run(2)
        print("compiled the engine for", law, flush=True)
for kind in ("plain", "active"):   # the types of test_chain_bench's calls (cache hits when warm)
    run_rk4(kind, "carlson-langer", n=6, ell=1.0, nu=1e-3, nu_f=0.2, u0=u0, events=1, dt=0.1)
