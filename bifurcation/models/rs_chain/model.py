"""The rate-and-state Burridge–Knopoff chain as a model of the registry: one run (an event catalog) per point.

A study is a workflow with ``[model] name = "rs-chain"`` (docs/rs-chain.md): labels are the slider's
state laws (``aging``, ``slip``, ``prz``; rate_state.laws), the axes the chain's parameters (all but N
and k with defaults), and each point one run of ``simulate.run`` — the first ``events`` events from
steady sliding at V_lp with ln V_j perturbed by A r_j (seeded). Per run the store keeps ``status``,
``events_done``, ``t_end``, ``steps``, ``balance_max`` (the largest stress-balance residual of its
events) and ``resumed``; per event, in the Burridge–Knopoff chain's catalog schema, ``t_start``, ``hypocentre``,
``n_blocks``, ``potency``, ``duration`` and ``max_velocity``. ``[engine] t_max`` and ``max_steps`` bound
one event (and the wait for it): beyond them the run stops with ``no-stop`` and keeps the events before;
a run whose deviations from stable steady sliding are seen to decay ends ``steady`` first (simulate.STEADY_BAND).

Runs are long (10^5 events of N = 256: hours), so the model checkpoints (``checkpoint=True``) through
the store's ``Checkpoints`` as the Burridge–Knopoff chain does: the runner saves the integrator's state
once the events done reach each multiple of the catalog chunk, and a run that finds a checkpoint resumes
from it with the same catalog bit for bit (``rs_chain.checkpoint``). ``[engine] batch = L`` runs a tile's
chains of one structure L at a time in SIMD lanes (``batch.run_batch``, each lane checkpointing its chain;
equal to ``batch = 1`` to rounding; docs/rs-chain.md, "Batch mode in workflows").
"""

from __future__ import annotations

import numpy as np

from ...errors import InputError
from .._base import Axis, Hooks, Labels, Model, Output
from .result import RSChainStatus

__all__ = ["AXES", "OUTPUTS", "RS_CHAIN", "run_rs_chains"]


def _resolve(text):
    from ..rate_state.laws import resolve_state_law

    if not isinstance(text, str) or not text.strip():
        raise InputError("state_law", text, "is not a state law name", "give aging, slip or prz")
    return resolve_state_law(text).name


LABELS = Labels(name="state_law", long_name="state evolution law of every block (aging, slip, prz)",
                workflow_key="laws", resolve=_resolve, identity=_resolve, example="aging")

AXES = (
    Axis("n", "N", "number of blocks N", bounds=(1, 1 << 16), example=16, default_tile=1, dtype="int64",
         structural=True),
    Axis("k", "k", "loading-spring stiffness k per block (σ = 1)", bounds=(1e-9, 1e9), units="1/length",
         scale="log", example=0.1, default_tile=1),
    Axis("ell", "ℓ", "coupling ℓ: neighbour springs of stiffness ℓ²k", bounds=(0.0, 1e3), example=3.0,
         default_tile=1, default=1.0),
    Axis("v_lp", "V_lp", "plate (load-point) velocity V_lp", bounds=(1e-12, 1e6), units="length/time",
         scale="log", example=1.0, default_tile=1, default=1.0),
    Axis("a", "a", "direct-effect parameter a (> 0)", bounds=(1e-6, 1.0), scale="log", example=0.01,
         default_tile=1, default=0.01),
    Axis("b", "b", "evolution-effect parameter b (>= 0)", bounds=(0.0, 1.0), example=0.015, default_tile=1,
         default=0.015),
    Axis("dc", "D_c", "critical slip distance Dc (> 0)", bounds=(1e-9, 1e6), units="length", scale="log",
         example=0.01, default_tile=1, default=0.01),
    Axis("mass", "M", "block mass M per unit normal force (0: quasi-dynamic)", bounds=(0.0, 1e30),
         units="time^2/length", example=0.0, default_tile=1, default=0.0),
    Axis("eta", "η", "radiation damping η: τ_load − ηV = μ(V, θ)", bounds=(0.0, 1e6), units="time/length",
         example=1e-3, default_tile=1, default=1e-3),
    Axis("v_th", "v_th", "slip-velocity threshold: a block slips while V > v_th (> V_lp)", bounds=(1e-12, 1e12),
         units="length/time", scale="log", example=10.0, default_tile=1, default=10.0),
    Axis("amplitude", "A", "amplitude A of the initial perturbation ln V_j = ln V_lp + A r_j", bounds=(0.0, 50.0),
         example=1.0, default_tile=1, default=1.0),
    Axis("seed", "S", "seed of numpy.random.default_rng for r_j", bounds=(0, 2**62), example=1, default_tile=1,
         dtype="int64", default=1),
    Axis("events", "K", "events computed per run", bounds=(1, 10**9), example=1000, default_tile=1,
         dtype="int64"),
    Axis("periodic", "ends", "chain ends: 0 free, 1 periodic", bounds=(0, 1), example=0, default_tile=1,
         dtype="int64", default=0, names=("free", "periodic")),   # shown and queried as the chain's are
)

#: Per-event outputs: the Burridge–Knopoff chain's catalog schema (bifurcation/models/chain/model.py).
_CATALOG = {
    "t_start": ("time the first block of the event exceeded v_th", "time", "float64"),
    "hypocentre": ("0-based index of the first block above v_th", "1", "int64"),
    "n_blocks": ("distinct blocks above v_th during the event", "1", "int64"),
    "potency": ("P = sum_j (δ_j(end) − δ_j(start))", "length", "float64"),
    "duration": ("time from the first up-crossing of v_th until every block is below it", "time", "float64"),
    "max_velocity": ("largest block velocity during the event (at an exact maximum)", "length/time", "float64"),
}

OUTPUTS = (
    Output("status", "outcome of the run (see bifurcation.models.rs_chain.RSChainStatus)", dtype="int8", fill=0),
    Output("events_done", "events catalogued (K unless the run stopped early)", dtype="int64", fill=0),
    Output("t_end", "end of the last catalogued event (NaN: no event)", "time"),
    Output("steps", "Taylor steps of the run", dtype="int64", fill=0),
    Output("balance_max", "largest |ΔΣ(μ+z+ηV) − k(N V_lp Δt − ΔP)| / |ΔΣ| over the run's events"),
    Output("resumed", "events restored from a checkpoint when this run was last computed (0: none)",
           dtype="int64", fill=0),
    *(Output(name, long, units, dtype=dtype, fill=-1 if dtype == "int64" else np.nan, per_event=True)
      for name, (long, units, dtype) in _CATALOG.items()),
)


def check_grid(workflow) -> None:
    """A workflow's largest run within ``bounds.RS_CHAIN_MAX_N_EVENTS`` (about a day of one core at the
    worst measured cost a block-event): the grid is a product, so its largest N and most events are one run."""
    from ... import bounds
    from ..chain._validate import check_n_events

    check_n_events(max(workflow.axes["n"]), max(workflow.axes["events"]), n_key="grid.n", events_key="grid.events",
                   what="one rs-chain run of a workflow", cap=bounds.RS_CHAIN_MAX_N_EVENTS,
                   why="~2.5 ms of CPU a block-event at worst, so about a day",
                   more=", or a smaller grid.n (a larger study is several runs: more seeds, or several workflows)")


def _structure(point: dict) -> tuple | None:
    """What chains must share to run in one batch (``run_rs_chains``), or None: a chain ``run_batch``
    refuses (massless and undamped)."""
    mass, eta = float(point["mass"]), float(point["eta"])
    if not (mass > 0 or eta > 0):
        return None
    return int(point["n"]), int(point["periodic"]), mass > 0, eta > 0, int(point["events"])


def check_batch(workflow) -> None:
    """``[engine] batch`` > 1 with no tile holding two chains of one structure (N, ends, inertia, damping,
    events; M = 0 and η = 0 never batch) would run every chain one by one: refused, naming the fix."""
    import itertools
    import math

    names = [name for name, _ in workflow.grid]
    chunks = [[values[i:i + size] for i in range(0, len(values), size)]
              for size, (_, values) in zip(workflow.tiles, workflow.grid)]
    tiles = math.prod(len(c) for c in chunks)
    if tiles > 100_000:         # a grid this large surely has its fellows; not worth the look
        return
    for tile in itertools.product(*chunks):
        seen = set()
        for values in itertools.product(*tile):
            key = _structure(dict(zip(names, values)))
            if key is not None and key in seen:
                return
            seen.add(key)
    raise InputError("engine.batch", workflow.batch, "has no lanes to fill: no tile holds two chains of one "
                     "structure (N, ends, mass > 0, η > 0, events; M = 0 with η = 0 never batches), so every "
                     "chain would run one by one", "give [tiles] a larger size on an axis other than n, "
                     "periodic and events (e.g. seed = 4), or leave batch out")


def run_rs_chains(model, label, points, *, precision="double", t_max=1e5, max_steps=1_000_000, batch=1,
                  checkpoints=None) -> tuple[dict, dict]:
    """The runner: one chain run per point (flat per-axis arrays in ``points``); catalogs as object arrays.

    ``checkpoints`` (optional, ``bifurcation.store.catalog.Checkpoints``): ``load(i)`` gives point ``i``'s
    saved state and stored catalog (or None) and the run resumes from it; ``save(i, state, catalog)``
    is called once the events done reach each multiple of ``checkpoints.every`` (``checkpoint.Snapshot``).

    ``batch`` > 1 (``[engine] batch``): the points that share a structure (N, ends, inertia, damping) and
    their events, at least two of them, run ``batch`` at a time in the SIMD lanes of ``batch.run_batch``
    (equal to the scalar runs to rounding, not bit for bit), each lane saving and resuming its chain's
    checkpoints as a scalar run does; the rest, and massless undamped chains (which ``run_batch`` refuses:
    they may blow up), run one by one as with ``batch = 1``.
    """
    from ...bounds import RS_CHAIN_EVENT_WORK
    from .checkpoint import Snapshot
    from .simulate import RSChainSpec, initial_state, run

    size = np.size(points["n"])
    per_run = {o.name: np.full(size, o.fill, dtype=o.dtype) for o in OUTPUTS if not o.per_event}
    catalogs = {o.name: np.empty(size, dtype=object) for o in OUTPUTS if o.per_event}
    messages = {}

    def empty(i) -> None:
        for name, (_, _, dtype) in _CATALOG.items():
            catalogs[name][i] = np.empty(0, dtype=dtype)

    def keep(i, r, spec, steps_cap, resumed) -> None:
        per_run["resumed"][i] = resumed
        for name, (_, _, dtype) in _CATALOG.items():
            catalogs[name][i] = np.asarray(getattr(r, name), dtype=dtype)
        per_run["status"][i] = int(r.status)
        per_run["events_done"][i] = r.events
        per_run["t_end"][i] = r.t_end
        per_run["steps"][i] = r.steps
        per_run["balance_max"][i] = r.balance_max
        if r.message:
            messages[i] = r.message + (f" (max_steps {int(max_steps)} lowered to {steps_cap} at N = {spec.n}: "
                                       f"bounds.RS_CHAIN_EVENT_WORK = {RS_CHAIN_EVENT_WORK:.0e} block-steps an event)"
                                       if steps_cap < int(max_steps) and r.status == RSChainStatus.NO_STOP else "")

    chains = {}      # point -> (spec, start) of the valid chains
    for i in range(size):
        p = {name: points[name][i] for name in points}
        if precision != "double":
            per_run["status"][i] = RSChainStatus.NOT_RESOLVED
            messages[i] = f"precision {precision!r}: rs-chain runs are computed in double (see docs/rs-chain.md)"
            empty(i)
            continue
        try:
            spec = RSChainSpec(n=int(p["n"]), state_law=label, a=float(p["a"]), b=float(p["b"]), dc=float(p["dc"]),
                               k=float(p["k"]), ell=float(p["ell"]), v_lp=float(p["v_lp"]), mass=float(p["mass"]),
                               eta=float(p["eta"]), v_th=float(p["v_th"]), periodic=bool(int(p["periodic"])))
            chains[i] = (spec, initial_state(spec, float(p["amplitude"]), int(p["seed"])))
        except InputError as exc:     # a point of the grid that is no valid chain: said per point
            per_run["status"][i] = RSChainStatus.NOT_APPLICABLE
            messages[i] = str(exc)
            empty(i)

    def restore(i, state0):
        """Point ``i``'s checkpoint (a ``Snapshot``, or None) and its saver (None without checkpoints)."""
        if checkpoints is None:
            return None, None
        every = checkpoints.every
        saved = checkpoints.load(i)
        resume = None
        if saved is not None:
            try:
                resume = Snapshot.from_saved(saved["state"], saved["catalog"])
            except (KeyError, ValueError):
                resume = None     # a checkpoint of another layout: the run starts from the beginning
            if resume is not None and np.size(resume.state) != np.size(state0):
                resume = None

        # only the events since the last save (those before are in the store): the whole catalog
        # rebuilt at each checkpoint was a cost growing as events²
        stored = [len(saved["catalog"]["t_start"]) if resume is not None else 0]

        def to_store(snap):
            upto = snap.boundary(every)
            checkpoints.save(i, snap.arrays(every), snap.catalog(_CATALOG, upto, stored[0]), steps=snap.steps[0],
                             first=stored[0])
            stored[0] = upto
        return resume, to_store

    def cap(spec) -> int:
        # the steps of one event bounded by its work too (bounds.RS_CHAIN_EVENT_WORK, ~3 h of one core):
        # max_steps alone allowed ~8 days for one event at N = 65536
        return min(int(max_steps), max(1, RS_CHAIN_EVENT_WORK // spec.n))

    if int(batch) > 1:
        from .batch import run_batch

        groups: dict = {}
        for i, (spec, _) in chains.items():
            events = int(points["events"][i])
            if spec.inertial or spec.eta > 0:
                key = (spec.n, spec.periodic, spec.inertial, spec.eta > 0, events)
                groups.setdefault(key, []).append(i)
        for key, members in groups.items():
            if len(members) < 2:      # one chain in lanes of its own would cost the lanes' work alone
                continue
            spec0 = chains[members[0]][0]
            restored = [restore(i, chains[i][1]) for i in members]
            resumes = [res for res, _ in restored]
            savers = [saver for _, saver in restored]
            results = run_batch([chains[i][0] for i in members], [chains[i][1] for i in members], key[-1],
                                t_max=float(t_max), max_steps=cap(spec0), lanes=int(batch),
                                every=checkpoints.every if checkpoints is not None else None,
                                save=(lambda c, snap: savers[c](snap)) if checkpoints is not None else None,
                                resume=resumes)
            for i, r, res in zip(members, results, resumes):
                keep(i, r, r.spec, cap(r.spec), len(res.rows) if res is not None else 0)
                del chains[i]

    for i, (spec, state0) in chains.items():
        resume, save = restore(i, state0)
        every = checkpoints.every if checkpoints is not None else None
        steps_cap = cap(spec)
        r = run(spec, state0, int(points["events"][i]), t_max=float(t_max), max_steps=steps_cap, every=every,
                save=save, resume=resume)
        keep(i, r, spec, steps_cap, len(resume.rows) if resume is not None else 0)
    return {**per_run, **catalogs}, messages


RS_CHAIN = Model(
    name="rs-chain",
    title="rate-and-state Burridge–Knopoff chain: N sliders, neighbour springs, events by a slip-velocity threshold",
    description=("M V̇_j = k(δ_lp − δ_j) + ℓ²k(δ_{j+1} − 2δ_j + δ_{j−1}) − μ(V_j, θ_j) − ηV_j with the slider's "
                 "rate-and-state friction per block; one run of K events per point, its catalog (t_start, "
                 "hypocentre, n_blocks, potency, duration, max_velocity) stored per event (docs/rs-chain.md)"),
    source=("Burridge and Knopoff, BSSA 57, 341 (1967); Kawamura, Hatano, Kato, Biswas, Chakrabarti, Rev. Mod. "
            "Phys. 84, 839 (2012), §III.1.7; Erickson, Birnir, Lavallée, Nonlin. Processes Geophys. 15, 1 (2008)"),
    labels=LABELS,
    axes=AXES,
    parameters=(),
    state=(),
    events=(),
    outputs=OUTPUTS,
    statuses=tuple(RSChainStatus),
    equations=None,
    classify=None,
    checkpoint=True,
    runner=run_rs_chains,
    catalog_size="events",
    catalog_count="events_done",
    hooks=Hooks(describe_label="bifurcation.models.rs_chain.store_report:describe_label",
                report="bifurcation.models.rs_chain.store_report:blocks",
                bench="bifurcation.models.rs_chain._bench:run_rs_chain_bench", bench_needs=("scipy", "numba"),
                check_grid="bifurcation.models.rs_chain.model:check_grid",
                check_batch="bifurcation.models.rs_chain.model:check_batch"),
    units_note="those of the workflow's own V_lp, Dc, k (σ = 1: stresses in units of the normal stress)",
    # 1: velocity-maximum events scaled so they no longer shorten heyoka's steps (2026-11-26), which moved
    # the catalogs' last bits; 2: a run whose steady sliding is seen to be stable ends "steady" (it ran to
    # its bounds as "no-stop" before). A store begun before must not be resumed with this engine's runs.
    revision=2,
    # 1: [engine] batch > 1 runs a tile's chains of one structure in run_batch's SIMD lanes (rounding only)
    batch_revision=1,
)
