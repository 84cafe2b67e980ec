"""The Burridge–Knopoff chain as a model of the registry: one run (an event catalog) per point.

A study of chains is a workflow with ``[model] name = "chain"`` (docs/chain.md, "Studies"): labels
are friction laws (the single block's ``LAW``), the axes are the chain's parameters, and each point
of the grid is one run of ``ChainLoop`` — the first ``events`` events of the chain started from the
seeded random state of ``bifurcation.chain(..., amplitude=A, seed=S)``:

    σ_j = ℓ²(U_{j+1} − 2U_j + U_{j−1}) − U_j + νt,   V̇_j = σ_j − Φ(V_j/ν_f) while V_j > 0,

with Φ replaced by Φ_σ(x) = (1 − σ)Φ(x/(1 − σ)) on the axis ``sigma`` (default 0, the seed's model).

Per run the store keeps ``status``, ``events_done``, ``t_end``, ``steps`` and ``resumed``; per event
(a ragged catalog, ``bifurcation.store.catalog``) ``t_start``, ``hypocentre``, ``n_blocks``,
``potency``, ``duration`` and ``max_velocity``. ``t_max`` and ``max_steps`` of the workflow bound one
event (beyond them the run stops with ``no-stop`` and keeps the events before).

Runs are long, so the model checkpoints (``checkpoint=True``): the runner saves its state every
``checkpoint.every`` events (at the catalog's chunk boundaries) and a run that finds a checkpoint
resumes from it; the catalog is the same bit for bit (``chain.checkpoint``).
"""

from __future__ import annotations

import numpy as np

from ...bounds import NU_BOUNDS, NU_F_BOUNDS
from ...workflow.validate import WorkflowKind
from .._base import Axis, Hooks, Model, Output
from ..single_block import BLOCK_UNITS, LAW
from .result import CATALOG_ATTRS, ChainStatus

__all__ = ["AXES", "CHAIN", "CHAIN_OUTPUTS", "run_chains"]

AXES = (
    Axis("n", "N", "number of blocks N", bounds=(1, 1 << 20), example=16, default_tile=1, dtype="int64",
         structural=True),
    Axis("ell", "ℓ", "coupling ℓ (ℓ² = k_c/k_p, the coil spring over the pulling spring)", bounds=(0.0, 1e3),
         example=1.0, default_tile=1),
    Axis("nu", "ν", "pulling speed ν (in V0)", bounds=NU_BOUNDS, scale="log", example=1e-3, default_tile=1),
    Axis("nu_f", "ν_f", "friction velocity ν_f (in V0)", bounds=NU_F_BOUNDS, example=0.3, default_tile=1),
    Axis("amplitude", "A", "amplitude A of the random initial displacements u_j = A r_j + c", bounds=(0.0, 1e3),
         example=0.5, default_tile=1),
    Axis("seed", "S", "seed of numpy.random.default_rng for the initial displacements", bounds=(0, 2**62),
         example=1, default_tile=1, dtype="int64"),
    Axis("events", "K", "events computed per run", bounds=(1, 10**9), example=1000, default_tile=1,
         dtype="int64"),
    Axis("periodic", "ends", "chain ends: 0 free (U_0 ≡ U_1), 1 periodic (U_0 ≡ U_N)", bounds=(0, 1), example=0,
         default_tile=1, dtype="int64", names=("free", "periodic")),
    # last, with a default: workflows written before σ existed keep their meaning (σ = 0, the seed's
    # model, computed by the unmodified code). Closed bounds: σ = 1 leaves no dynamic friction at all
    Axis("sigma", "σ", "friction drop σ: Φ_σ(x) = (1 − σ)Φ(x/(1 − σ)), static threshold 1", bounds=(0.0, 0.99),
         example=0.01, default_tile=1, default=0.0),
    # event membership (docs/chain.md, "Event membership"): 0 (default) every block that moved, until all
    # are stuck; V_th > 0 only the blocks faster than V_th count in n_blocks and potency
    Axis("v_threshold", "V_th", "slip-velocity threshold of event membership (0: every block that moved)",
         bounds=(0.0, 1e3), units="V0", example=0.01, default_tile=1, default=0.0),
)

_PER_EVENT_DTYPES = {"hypocentre": "int64", "n_blocks": "int64"}

CHAIN_OUTPUTS = (
    Output("status", "outcome of the run (see bifurcation.models.chain.ChainStatus)", dtype="int8",
           fill=0),
    Output("events_done", "events catalogued (K unless the run stopped early)", dtype="int64", fill=0),
    Output("t_end", "time after the last event, all blocks stuck (NaN: the run stopped early)", "sqrt(m/k)"),
    Output("steps", "Taylor steps of the catalogued events", dtype="int64", fill=0),
    Output("resumed", "events restored from a checkpoint when this run was last computed (0: none)",
           dtype="int64", fill=0),
    *(Output(name, CATALOG_ATTRS[name][0], CATALOG_ATTRS[name][1], dtype=_PER_EVENT_DTYPES.get(name, "float64"),
             fill=-1 if name in _PER_EVENT_DTYPES else np.nan, per_event=True)
      for name in ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity")),
)


def check_grid(workflow) -> None:
    """A workflow's largest run within the chain's bounds (``bounds.CHAIN_MAX_N_EVENTS``, as ``bifurcation
    chain``): the grid is a product, so its largest N and its most events are one run."""
    from ._validate import check_n_events

    check_n_events(max(workflow.axes["n"]), max(workflow.axes["events"]), n_key="grid.n", events_key="grid.events",
                   what="one chain run of a workflow",
                   more=", or a smaller grid.n (a larger study is several runs: more seeds, or several workflows)")


def _ints(values) -> np.ndarray:
    return np.asarray(values, dtype=np.int64)


def run_chains(model, label, points, *, precision="double", t_max=1e5, max_steps=1_000_000, batch=1,
               checkpoints=None) -> tuple[dict, dict]:
    """The runner: one chain run per point (flat per-axis arrays in ``points``).

    ``checkpoints`` (optional, ``bifurcation.store.catalog.Checkpoints``): ``load(i)`` gives the saved
    state and catalog of point ``i`` (or None), ``save(i, state, catalog)`` is called every
    ``checkpoints.every`` events. Returns the per-run outputs (arrays over the points) and the
    catalogs (object arrays of per-run arrays), and messages (point index → text) for runs that
    stopped early.
    """
    from ...bounds import CHAIN_EVENT_WORK
    from ...laws import resolve_law
    from ._loop import ChainLoop
    from ._validate import check_initial
    from .checkpoint import restore, snapshot

    law = resolve_law(label)
    size = np.size(points["n"])
    per_run = {o.name: np.full(size, o.fill, dtype=o.dtype) for o in CHAIN_OUTPUTS if not o.per_event}
    catalogs = {o.name: np.empty(size, dtype=object) for o in CHAIN_OUTPUTS if o.per_event}
    messages = {}
    every = checkpoints.every if checkpoints is not None else None
    for i in range(size):
        n, seed, events = int(points["n"][i]), int(points["seed"][i]), int(points["events"][i])
        ell = float(points["ell"][i])
        ends = "periodic" if int(points["periodic"][i]) else "free"
        u = check_initial(n, ell, ends, None, float(points["amplitude"][i]), seed)
        sigma = float(points["sigma"][i]) if "sigma" in points else 0.0
        v_th = float(points["v_threshold"][i]) if "v_threshold" in points else 0.0
        loop = ChainLoop(law, n, ell, float(points["nu"][i]), float(points["nu_f"][i]), ends, u,
                         precision=precision, t_max=t_max, max_steps=max_steps, drop=sigma, v_threshold=v_th,
                         max_work=CHAIN_EVENT_WORK["exact", precision])   # as `bifurcation chain`: hours otherwise
        # the catalog as arrays per chunk (48 bytes an event), not Python lists of the whole run (~315 bytes an
        # event measured: a workflow's run of 10^9 events at N <= 10 is within its bounds); ``new`` the pieces
        # since the last checkpoint, the only ones a checkpoint copies and writes
        cat = {name: [] for name in catalogs}
        new = {name: [] for name in catalogs}
        done = steps = 0
        status, message, resumed = ChainStatus.COMPLETE, "", 0
        saved = checkpoints.load(i) if checkpoints is not None else None
        if saved is not None:
            restore(loop, saved["state"])
            for name in catalogs:
                _keep(cat[name], _as_array(name, saved["catalog"][name]))
            steps = int(saved["steps"])      # the steps so far
            done = resumed = len(cat["t_start"][0])
        saved_upto = done
        while done < events:
            chunk = min(_PIECE, events - done) if every is None else min(every - done % every, events - done)
            out = loop.run(chunk)
            loop.wall.clear()      # (per-event timings of the benchmarks: they grew with the run)
            loop.widest.clear()
            for name in catalogs:
                new[name].append(_as_array(name, out["catalog"][name]))
            steps += int(sum(out["catalog"]["steps"]))
            done += len(out["catalog"]["t_start"])
            if out["status"] != ChainStatus.COMPLETE:
                status, message = out["status"], out["message"]
                break
            if every is None or (done % every == 0 and done < events):
                # the new pieces joined once, kept in O(log events) arrays: the whole catalog was joined at
                # every checkpoint before (a copy growing as events², for the same catalog bit for bit)
                piece = {k: new[k][0] if len(new[k]) == 1 else np.concatenate(new[k]) for k in catalogs}
                if every is not None:
                    checkpoints.save(i, snapshot(loop), piece, steps=steps, first=saved_upto)
                    saved_upto = done
                for name in catalogs:
                    _keep(cat[name], piece[name])
                new = {name: [] for name in catalogs}
        for name in catalogs:
            pieces = cat[name] + new[name]
            catalogs[name][i] = (pieces[0] if len(pieces) == 1 else np.concatenate(pieces)) if pieces else \
                _as_array(name, [])
        per_run["status"][i] = int(status)
        per_run["events_done"][i] = done
        # a run that stopped early stopped inside an event: no time at which all blocks are stuck
        per_run["t_end"][i] = float(loop.t) if status == ChainStatus.COMPLETE else np.nan
        per_run["steps"][i] = steps
        per_run["resumed"][i] = resumed
        if message:
            messages[i] = message
    return {**per_run, **catalogs}, messages


def _keep(pieces: list, piece: np.ndarray) -> None:
    """Append ``piece``, joining the last two pieces while the last is at least as long as the one before
    (a binary counter): O(log n) arrays and each event copied O(log n) times, in order."""
    pieces.append(piece)
    while len(pieces) >= 2 and pieces[-1].size >= pieces[-2].size:
        last = pieces.pop()
        pieces[-1] = np.concatenate((pieces[-1], last))


#: Events per piece of a run without checkpoints (its lists of Python numbers stay this short)
_PIECE = 1000


def _as_array(name: str, values) -> np.ndarray:
    if name in _PER_EVENT_DTYPES:
        return _ints(values)
    return np.array([float(x) for x in values], dtype=np.float64)


CHAIN = Model(
    name="chain",
    title="Burridge–Knopoff chain of N blocks, every stop, start and friction switch exact",
    description="σ_j = ℓ²(U_{j+1} − 2U_j + U_{j−1}) − U_j + νt, V̇_j = σ_j − Φ(V_j/ν_f) while a block slips; "
                "one run of K events per point, its catalog (t_start, hypocentre, n_blocks, potency, duration, "
                "max_velocity) stored per event (docs/chain.md)",
    source="Burridge and Knopoff, BSSA 57, 341 (1967); Carlson and Langer, PRA 40, 6470 (1989); "
           "Vasconcelos, PRL 76, 4865 (1996)",
    labels=LAW,
    axes=AXES,
    parameters=(),
    state=(),
    events=(),
    outputs=CHAIN_OUTPUTS,
    statuses=tuple(ChainStatus),
    equations=None,
    classify=None,
    checkpoint=True,
    runner=run_chains,
    catalog_size="events",
    catalog_count="events_done",
    hooks=Hooks(describe_label="bifurcation.laws:resolve_law",
                report="bifurcation.models.chain.store_report:chain_store_blocks",
                bench="bifurcation.models.chain._bench:run_chain_bench",
                commands="bifurcation.cli._chain:COMMANDS",
                presets="bifurcation.models.chain.presets:workflow_preset",
                study="bifurcation.cli._chain_study:chain_study_cmd",
                workflow="bifurcation.models.chain.model:REPORT_WORKFLOW",
                check_grid="bifurcation.models.chain.model:check_grid"),
    units_note=BLOCK_UNITS,
)

#: The chain report's own workflows (``workflows/chain-report.toml``): named when another command is given one.
REPORT_WORKFLOW = WorkflowKind("study chain", ("chain", "sweep", "catalog", "threshold", "near_half"),
                               "a chain study workflow of `bifurcation study chain` ([chain], [sweep])",
                               "run it with `bifurcation study chain FILE`")
