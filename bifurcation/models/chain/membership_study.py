"""How much the event definition changes b and the large-event excess (issue 17, item 2).

One catalog per case, computed once with a velocity threshold: the same run gives both definitions
(``n_blocks_all``/``potency_all``: every block that moved, until all are stuck; ``n_blocks``/``potency``:
the blocks faster than V_th). Per definition: the report's Page b of the multi-block events and the
excess of system-spanning events (``report._catalog_stats``, docs/chain.md "Magnitude–frequency"), and
the Clauset–Shalizi–Newman fit of all events with size > 0 (``clauset.clauset_fit``).

    python -m bifurcation.models.chain.membership_study      # the small study of docs/chain.md
"""

from __future__ import annotations

import math
import time

import numpy as np

from .clauset import clauset_fit

__all__ = ["CASES", "compare_membership", "main"]

#: the small study of docs/chain.md, "Event membership": (law, N, ℓ, ν, ν_f, σ, events)
CASES = (
    ("carlson-langer", 64, 1.0, 1e-3, 0.45, 0.0, 3000),
    ("carlson-langer", 64, 1.0, 1e-3, 0.45, 0.01, 3000),
    ("carlson-langer", 16, 1.0, 1e-3, 0.45, 0.0, 3000),
    ("carlson-langer", 16, 1.0, 1e-3, 0.45, 0.01, 3000),
)


def _stats(n, p, nb, t_start, bootstrap, seed) -> dict:
    from .study import _catalog_stats

    keep = nb > 0     # events with no member block (threshold definition) have no size
    p, nb, t = p[keep], nb[keep], t_start[keep]
    base = _catalog_stats({"n": n, "nu_f": math.nan, "potency": p, "n_blocks": nb, "t_start": t,
                           "seconds": 0.0, "status": "", "one_block": None})
    fit = clauset_fit(p, bootstrap=bootstrap, block_bootstrap=200, seed=seed)
    return {"events": int(p.size), "multi": int(np.sum(nb >= 2)), "spanning": int(np.sum(nb == n)),
            "b_page": base["fit"]["b"], "b_page_sigma": base["fit"]["sigma"], "m_min": base["fit"]["m_min"],
            "ks": base["fit"]["ks"], "ks_crit": base["fit"]["ks_crit"], "excess": base["spanning"]["excess"],
            "csn": fit}


def compare_membership(law, n, ell, nu, nu_f, sigma, events, *, v_threshold="default", seed=1, amplitude=0.5,
                       transient=200, bootstrap=10) -> dict:
    """Both definitions on one catalog (the first ``transient`` events dropped)."""
    from .simulate import chain

    t0 = time.process_time()
    r = chain(law, n=n, ell=ell, nu=nu, nu_f=nu_f, amplitude=amplitude, seed=seed, events=events + transient,
              sigma=sigma, v_threshold=v_threshold)
    cpu = time.process_time() - t0
    s = slice(transient, None)
    return {"case": (law, n, ell, nu, nu_f, sigma, events), "v_threshold": r.v_threshold, "status": str(r.status),
            "cpu": cpu,
            "all_stuck": _stats(n, r.potency_all[s], r.n_blocks_all[s], r.t_start[s], bootstrap, seed),
            "threshold": _stats(n, r.potency[s], r.n_blocks[s], r.t_start[s], bootstrap, seed),
            "creep_only": int(np.sum(r.n_blocks[s] == 0))}


def main(cases=CASES) -> None:
    for case in cases:
        out = compare_membership(*case)
        print(f"{out['case']}: V_th = {out['v_threshold']:g}, {out['status']}, {out['cpu']:.0f} CPU s, "
              f"{out['creep_only']} events without a block above V_th")
        for key in ("all_stuck", "threshold"):
            st = out[key]
            f = st["csn"]
            print(f"  {key:10s} events {st['events']:5d} multi {st['multi']:5d} spanning {st['spanning']:4d} | "
                  f"Page b_P = {st['b_page']:.3f} ± {st['b_page_sigma']:.3f} (KS {st['ks']:.3f} vs {st['ks_crit']:.3f}), "
                  f"spanning excess {st['excess']:.3g} | CSN alpha = {f.alpha:.3f} ± {f.alpha_error:.3f} "
                  f"(block; iid {f.alpha_err:.3f}), x_min = {f.xmin:.3g}, n_tail = {f.n_tail}, p = {f.p_value:.2f}, "
                  f"b_P = {f.b_potency:.3f}, b_M = {f.b_magnitude:.3f}; LR "
                  + ", ".join(f"{k} R={r:.2f} p={p:.2g}" for k, (r, p) in f.ratios.items()), flush=True)


if __name__ == "__main__":
    main()
