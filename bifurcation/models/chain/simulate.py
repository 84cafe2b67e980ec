"""``chain``: the event catalog of a Burridge–Knopoff chain, every stop, start and switch exact."""

from __future__ import annotations

import numpy as np

from ...engine._validate import check_nu, check_nu_f, check_precision, check_work
from ...errors import InputError
from ...laws import resolve_law
from ._validate import (check_engine, check_events, check_initial, check_sigma, check_size, check_v_threshold,
                        check_verify)
from .result import ChainResult, ChainStatus

__all__ = ["chain"]


def chain(law=None, *, n: int | None = None, ell: float | None = None, nu: float | None = None,
          nu_f: float | None = None, ends: str | None = None, u0=None, amplitude=None, seed=None, events: int,
          precision: str = "double", energy: bool = False, t_max: float = 1e5, max_steps: int = 1_000_000,
          sigma: float | None = None, v_threshold=None, preset: str | None = None,
          progress=None, engine: str = "exact", tol: float | None = None, verify: float = 0.0,
          max_work: int | None = None, max_run_work: int | None = None) -> ChainResult:
    r"""The first ``events`` events of a chain of ``n`` blocks (docs/chain.md).

    Stress on block j (dimensionless as in Vasconcelos, PRL 76, 4865 (1996)):

    .. math:: \sigma_j = \ell^2 (U_{j+1} - 2U_j + U_{j-1}) - U_j + \nu t,

    with free ends (U_0 ≡ U_1, U_{N+1} ≡ U_N) or periodic ones (U_0 ≡ U_N, U_{N+1} ≡ U_1). A slipping
    block obeys U̇_j = V_j, V̇_j = σ_j − Φ(V_j/ν_f); a stuck one starts when σ_j reaches 1 and a
    slipping one sticks when V_j returns to 0 (no back-slip). Quiescent phases are jumped exactly.
    With a friction drop σ > 0 a slipping block feels Φ_σ(x) = (1 − σ)Φ(x/(1 − σ)) (static threshold 1,
    dynamic friction 1 − σ at V → 0⁺: Carlson, Langer, Shaw and Tang, PRA 44, 884 (1991)).

    Parameters
    ----------
    law : str or FrictionLaw
        A name of ``bifurcation.law_names()`` or a formula in x.
    n, ell : int, float
        Number of blocks N ≥ 1 and coupling ℓ ≥ 0 (ℓ² = k_c/k_p).
    nu, nu_f : float or str
        Pulling speed ν > 0 and friction velocity ν_f > 0. With ``precision="quad"`` a decimal given
        as text (``"1e-3"``, a ``Decimal``, an mpmath number; so are ``ell`` and ``u0``) is read in
        real128, not through the nearest double (``engine._exact``).
    ends : {"free", "periodic"}
    u0 : array_like, optional
        Initial displacements (all σ_j(0) < 1). Or ``amplitude`` A and ``seed`` (both required): u_j = −A r_j,
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
    max_work : int, optional
        A bound on the work of one event, in block-steps (steps × the width of the window integrated;
        the compiled engine, which does not count widths, takes max_steps ≤ max_work // n instead):
        beyond it the run stops with status ``no-stop``, as at max_steps. The CLI's bound
        (``cli/_chain.py``, ``MAX_WORK``) on an event that may never end (N·ν ≥ 1 at large N).
        ``max_run_work`` bounds the block-steps of all the events together (exact engine only).
    sigma : float
        Friction drop 0 ≤ σ < 1 (docs/chain.md, "Friction drop"); 0 (default) is the seed's model,
        computed by exactly the code of before σ existed.
    preset : str, optional
        A published parameter set (``bifurcation.models.chain.presets``): fills law, n, ell, nu, nu_f,
        sigma and ends where they are not given (given values win).
    v_threshold : None, float or "default"
        Event membership (docs/chain.md, "Event membership"). None (default): every block that moved
        belongs to the event, which runs until all blocks are stuck. V_th > 0 (or "default": 10 ν):
        ``n_blocks`` and ``potency`` count only the blocks whose velocity exceeded V_th during the
        event (``n_blocks_all``, ``potency_all`` keep the others); ``membership`` records which.
    progress : callable, optional
        ``progress(events_done, events, t)``, called about every second of computing (the CLI's line
        on stderr for a long run); the events are the same with or without it (either engine; not
        called when the compiled engine runs with ``verify``). With it, the compiled engine also says
        on stderr when it is about to compile its loop (no disk cache yet for this kind of law), and sets
        ``progress.compiling`` (if it has that attribute) to when it compiles ("first run only", ...).
    engine : {"exact", "compiled"}
        ``"exact"``: heyoka's Taylor integrator (the reference). ``"compiled"``: the numba engine
        (``_compiled``; double precision, no energy budget), an order-20 Taylor method for
        Carlson–Langer and DOP853 for the other laws at tolerance ``tol``, with the same exact event
        location; its catalog adds ``error_estimate`` per event (docs/chain.md,
        "Engines").
    tol : float, optional
        The compiled engine's tolerance (Taylor or DOP853 steps; default ``_compiled.TOL`` = 1e-11).
    verify : float
        With the compiled engine: re-run this fraction of the events (every ⌈1/verify⌉-th, the first
        included) with the exact engine from the same pre-event state; ``result.verification`` holds
        the largest relative differences and the events whose hypocentre or size differ.

    Returns
    -------
    ChainResult
    """
    given = {"law": law, "n": n, "ell": ell, "nu": nu, "nu_f": nu_f, "sigma": sigma, "ends": ends}
    if preset is not None:
        from .presets import get_preset

        given = {k: (v if v is not None else get_preset(preset).parameters()[k]) for k, v in given.items()}
    defaults = {"sigma": 0.0, "ends": "free"}
    given = {k: (defaults[k] if v is None and k in defaults else v) for k, v in given.items()}
    missing = [k for k, v in given.items() if v is None]
    if missing:
        raise InputError(missing[0], None, "is missing", "give it, or a preset= such as 'carlson-langer-1991'")
    law, n, ell, nu, nu_f, sigma, ends = (given[k] for k in ("law", "n", "ell", "nu", "nu_f", "sigma", "ends"))
    law = resolve_law(law)
    given = {"nu": nu, "nu_f": nu_f, "ell": ell, "sigma": sigma}   # as given: "quad" reads decimals at its own precision
    if u0 is not None:
        given["u0"] = list(np.ravel(np.asarray(u0, dtype=object)))
    n, ell, ends = check_size(n, ell, ends)
    nu = float(check_nu(nu))
    nu_f = float(check_nu_f(nu_f))
    check_precision(precision)
    events = check_events(events)
    sigma = check_sigma(sigma)
    v_threshold = check_v_threshold(v_threshold, nu)
    check_work(t_max, max_steps)   # one event's bounds: refused (not a no-stop run) when not > 0 or NaN
    for name, value in (("max_work", max_work), ("max_run_work", max_run_work)):
        if value is not None and (isinstance(value, bool) or not isinstance(value, (int, np.integer)) or value < 1):
            raise InputError(name, value, "is not an integer >= 1", "give a number of block-steps, or None")
    u = check_initial(n, ell, ends, u0, amplitude, seed)
    engine, sigma, tol = check_engine(engine, sigma, tol, precision, energy)
    verify = check_verify(verify, engine, sigma)
    if engine == "compiled":
        _check_compiled_drop(law, sigma)
        if v_threshold:
            raise InputError("v_threshold", v_threshold, "is not available in the compiled engine",
                             "use engine='exact' for membership by a slip-velocity threshold")
        if max_work is not None:   # (its steps are not counted by width: every block, conservatively)
            max_steps = max(1, min(max_steps, max_work // n))
        return _compiled_run(law, n, ell, nu, nu_f, ends, u, events, sigma, tol, t_max, max_steps, verify, progress)
    from ._loop import ChainLoop

    loop = ChainLoop(law, n, ell, nu, nu_f, ends, u, precision=precision, energy=energy,
                     t_max=t_max, max_steps=max_steps, drop=sigma, v_threshold=v_threshold or 0.0,
                     exact=given if precision == "quad" else None, max_work=max_work,
                     max_run_work=max_run_work)
    out = loop.run(events) if progress is None else _run_reporting(loop, events, progress)
    cat = out["catalog"]
    f = lambda k: np.array([float(x) for x in cat[k]], dtype=float)  # noqa: E731
    energy_fields = {k: f(k) for k in ("driver_work", "dissipation", "elastic_change")} if energy else None
    return ChainResult(
        law=law.name, n=n, ell=ell, nu=nu, nu_f=nu_f, ends=ends, precision=precision, u0=u,
        t_start=f("t_start"), hypocentre=np.array(cat["hypocentre"], dtype=np.int64),
        n_blocks=np.array(cat["n_blocks"], dtype=np.int64), potency=f("potency"), duration=f("duration"),
        max_velocity=f("max_velocity"), steps=np.array(cat["steps"], dtype=np.int64),
        t=float(loop.t), u=np.array([float(x) for x in loop.u]), stress=np.array([float(x) for x in loop.sigma]),
        status=ChainStatus(out["status"]), message=out["message"], energy=energy_fields, sigma=sigma,
        v_threshold=v_threshold,
        n_blocks_all=np.array(cat["n_blocks_all"], dtype=np.int64) if v_threshold else None,
        potency_all=f("potency_all") if v_threshold else None)


def _run_reporting(loop, events: int, progress, every: float = 1.0) -> dict:
    """``loop.run(events)`` in pieces of about ``every`` seconds, calling ``progress`` after each."""
    import time

    out = {"catalog": None, "status": ChainStatus.COMPLETE, "message": ""}
    done, chunk = 0, 1
    while done < events:
        started = time.perf_counter()
        part = loop.run(min(chunk, events - done))
        if out["catalog"] is None:   # lists (the exact engine) or arrays (the compiled one: joined at the end)
            out["catalog"] = {k: v if isinstance(v, list) else [v] for k, v in part["catalog"].items()}
            arrays = not isinstance(part["catalog"]["t_start"], list)
        else:
            for key, values in part["catalog"].items():
                out["catalog"][key].extend(values if not arrays else [values])
        done += len(part["catalog"]["t_start"])
        if part["status"] != ChainStatus.COMPLETE:
            out["status"], out["message"] = part["status"], part["message"]
            break
        elapsed = time.perf_counter() - started
        chunk = max(1, min(chunk * 2, int(chunk * every / elapsed) if elapsed > 0 else chunk * 2))
        progress(done, events, float(loop.t))
    if arrays:
        out["catalog"] = {k: np.concatenate(v) for k, v in out["catalog"].items()}
    return out


#: Largest friction drop at which the compiled engine was checked against the exact one with friction
#: that fades (a law with rungs, laws/_fading.py). Random chains (tests/test_chain_compiled.py,
#: ``_random_chain``; N = 1-8, both ends, ν = 1e-9 … 1e-2, 12 events each, event by event from the exact
#: engine's state): at σ ≤ 0.95 none of 209 with exp(-x), exp(-x-4x^2) differed (largest 1.0e-10, a
#: duration); at σ in (0.95, 0.999) exp(-x-4x^2) was 2.7e-7 off in a duration (1 of 40 chains) and 1.3e-9
#: in another, while the per-event error estimate said 6e-12 (exp(-x): 2.4e-11 at most in 40).
COMPILED_FADING_SIGMA = 0.95


def _check_compiled_drop(law, sigma: float) -> None:
    """Refuse what the compiled engine cannot vouch for: a drop above ``COMPILED_FADING_SIGMA`` on friction
    that fades, whose onset (steep on the scale 1 − σ) near a stop DOP853 does not resolve as the exact
    engine's rungs do."""
    if sigma <= COMPILED_FADING_SIGMA:
        return
    from ...laws._fading import ladder

    if ladder(law, "double").rungs:
        raise InputError("sigma", sigma, f"is above {COMPILED_FADING_SIGMA:g} with friction that fades "
                         f"({law.name}), where the compiled engine was measured 2.7e-7 off the exact one "
                         "(exp(-x-4x^2), σ = 0.993) with an error estimate of 6e-12", "use the exact engine here (engine='exact', --engine exact: the default)")


def compile_when() -> str:
    """How often numba compiles the compiled engine here: once (its disk cache), or every run."""
    from ._compiled import _CACHE

    return ("first run only" if _CACHE else
            "every run: numba cannot write its disk cache (give NUMBA_CACHE_DIR a writable directory)")


def compile_notice(law_name: str) -> str:
    """The line said before numba compiles the compiled engine for a law (``chain --engine compiled``,
    ``bench --suite chain``): how often, and its measured cost (``_compiled.COMPILE_SECONDS``)."""
    from ._compiled import COMPILE_SECONDS

    return (f"compiling the chain engine for {law_name} ({compile_when()}; ~{COMPILE_SECONDS} s of CPU, longer in "
            "wall time on a busy machine)")


def _compiled_run(law, n, ell, nu, nu_f, ends, u, events, sigma, tol, t_max, max_steps, verify,
                  progress=None) -> ChainResult:
    from ._compiled import CompiledChain, run_verified

    run = CompiledChain(law, n, ell, nu, nu_f, ends, u, sigma=sigma, tol=tol, t_max=t_max, max_steps=max_steps)
    if progress is not None and not run.compiled():   # (the CLI: say why the first line is late)
        import sys

        when = compile_when()
        print(f"bifurcation: chain: {compile_notice(law.name)}", file=sys.stderr, flush=True)
        if hasattr(progress, "compiling"):   # the CLI's still-running line: compiling, not an event sliding
            progress.compiling = when
    report = None
    if verify > 0:
        out, report = run_verified(run, events, verify)
    elif progress is not None:   # in growing pieces, as the exact engine: the same events (tests)
        out = _run_reporting(run, events, progress)
    else:
        out = run.run(events)
    cat = out["catalog"]
    return ChainResult(
        law=law.name, n=n, ell=ell, nu=nu, nu_f=nu_f, ends=ends, precision="double", u0=u,
        t_start=cat["t_start"], hypocentre=cat["hypocentre"], n_blocks=cat["n_blocks"], potency=cat["potency"],
        duration=cat["duration"], max_velocity=cat["max_velocity"], steps=cat["steps"], t=run.t,
        u=run.u.copy(), stress=run.stress, status=out["status"], message=out["message"],
        error_estimate=cat["error_estimate"], verification=report, sigma=sigma)
