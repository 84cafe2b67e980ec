"""``chain``: the event catalog of a Burridge–Knopoff chain, every stop, start and switch exact."""

from __future__ import annotations

import numpy as np

from ...engine._validate import check_nu, check_nu_f, check_precision, check_work
from ...laws import resolve_law
from ._validate import check_engine, check_events, check_verify, check_initial, check_size
from .result import ChainResult, ChainStatus

__all__ = ["chain"]


def chain(law, *, n: int, ell: float, nu: float, nu_f: float, ends: str = "free", u0=None,
          amplitude=None, seed=None, events: int, precision: str = "double", energy: bool = False,
          t_max: float = 1e5, max_steps: int = 1_000_000, engine: str = "exact", sigma: float = 0.0,
          tol: float | None = None, verify: float = 0.0) -> ChainResult:
    r"""The first ``events`` events of a chain of ``n`` blocks (docs/chain.md).

    Stress on block j (dimensionless as in Vasconcelos, PRL 76, 4865 (1996)):

    .. math:: \sigma_j = \ell^2 (U_{j+1} - 2U_j + U_{j-1}) - U_j + \nu t,

    with free ends (U_0 ≡ U_1, U_{N+1} ≡ U_N) or periodic ones (U_0 ≡ U_N, U_{N+1} ≡ U_1). A slipping
    block obeys U̇_j = V_j, V̇_j = σ_j − Φ(V_j/ν_f); a stuck one starts when σ_j reaches 1 and a
    slipping one sticks when V_j returns to 0 (no back-slip). Quiescent phases are jumped exactly.

    Parameters
    ----------
    law : str or FrictionLaw
        A name of ``bifurcation.law_names()`` or a formula in x.
    n, ell : int, float
        Number of blocks N ≥ 1 and coupling ℓ ≥ 0 (ℓ² = k_c/k_p).
    nu, nu_f : float
        Pulling speed ν > 0 and friction velocity ν_f > 0.
    ends : {"free", "periodic"}
    u0 : array_like, optional
        Initial displacements (all σ_j(0) < 1). Or ``amplitude`` A and ``seed``: u_j = −A r_j,
        r_j uniform in [0, 1) from ``numpy.random.default_rng(seed)``.
    events : int
        Number of events to compute.
    precision : {"double", "quad"}
        ``"quad"`` integrates in heyoka real128 (verification).
    energy : bool
        Also return the per-event energy budget (driver work, friction dissipation, elastic change).
    t_max, max_steps : float, int
        Bounds on the duration and the Taylor steps of one event; beyond them the run stops with
        status ``no-stop`` and the catalog holds the completed events.

    engine : {"exact", "compiled"}
        ``"exact"``: heyoka's Taylor integrator (the reference). ``"compiled"``: the numba engine
        (``_compiled``; double precision, no energy budget), DOP853 at tolerance ``tol`` with the
        same exact event location; its catalog adds ``error_estimate`` per event (docs/chain.md,
        "Engines").
    sigma : float
        Friction drop σ_f ∈ [0, 1): Φ_σ(x) = (1 − σ_f) Φ(x/(1 − σ_f)), static threshold 1 (compiled
        engine only on this branch).
    tol : float, optional
        The compiled engine's DOP853 tolerance (default ``_compiled.TOL`` = 1e-12).
    verify : float
        With the compiled engine: re-run this fraction of the events (every ⌈1/verify⌉-th, the first
        included) with the exact engine from the same pre-event state; ``result.verification`` holds
        the largest relative differences and the events whose hypocentre or size differ.

    Returns
    -------
    ChainResult
    """
    law = resolve_law(law)
    n, ell, ends = check_size(n, ell, ends)
    nu = float(check_nu(nu))
    nu_f = float(check_nu_f(nu_f))
    check_precision(precision)
    events = check_events(events)
    check_work(t_max, max_steps)   # one event's bounds: refused (not a no-stop run) when not > 0 or NaN
    u = check_initial(n, ell, ends, u0, amplitude, seed)
    engine, sigma, tol = check_engine(engine, sigma, tol, precision, energy)
    verify = check_verify(verify, engine, sigma)
    if engine == "compiled":
        return _compiled_run(law, n, ell, nu, nu_f, ends, u, events, sigma, tol, t_max, max_steps, verify)
    from ._loop import ChainLoop

    loop = ChainLoop(law, n, ell, nu, nu_f, ends, u, precision=precision, energy=energy,
                     t_max=t_max, max_steps=max_steps)
    out = loop.run(events)
    cat = out["catalog"]
    f = lambda k: np.array([float(x) for x in cat[k]], dtype=float)  # noqa: E731
    energy_fields = {k: f(k) for k in ("driver_work", "dissipation", "elastic_change")} if energy else None
    return ChainResult(
        law=law.name, n=n, ell=ell, nu=nu, nu_f=nu_f, ends=ends, precision=precision, u0=u,
        t_start=f("t_start"), hypocentre=np.array(cat["hypocentre"], dtype=np.int64),
        n_blocks=np.array(cat["n_blocks"], dtype=np.int64), potency=f("potency"), duration=f("duration"),
        max_velocity=f("max_velocity"), steps=np.array(cat["steps"], dtype=np.int64),
        t=float(loop.t), u=np.array([float(x) for x in loop.u]), stress=np.array([float(x) for x in loop.sigma]),
        status=ChainStatus(out["status"]), message=out["message"], energy=energy_fields)


def _compiled_run(law, n, ell, nu, nu_f, ends, u, events, sigma, tol, t_max, max_steps, verify) -> ChainResult:
    from ._compiled import CompiledChain, run_verified

    run = CompiledChain(law, n, ell, nu, nu_f, ends, u, sigma=sigma, tol=tol, t_max=t_max, max_steps=max_steps)
    report = None
    if verify > 0:
        out, report = run_verified(run, events, verify)
    else:
        out = run.run(events)
    cat = out["catalog"]
    return ChainResult(
        law=law.name, n=n, ell=ell, nu=nu, nu_f=nu_f, ends=ends, precision="double", u0=u,
        t_start=cat["t_start"], hypocentre=cat["hypocentre"], n_blocks=cat["n_blocks"], potency=cat["potency"],
        duration=cat["duration"], max_velocity=cat["max_velocity"], steps=cat["steps"], t=run.t,
        u=run.u.copy(), stress=run.stress, status=out["status"], message=out["message"],
        error_estimate=cat["error_estimate"], verification=report)
