"""The chain report's workflow (``workflows/chain-report.toml``), read through the workflows' one validator.

``load_report_workflow(path)`` checks every key, type, range and the lengths of the lists the report
zips together (``bifurcation.workflow.validate``: one ``InputError`` line naming the key, the value and
the fix) before any run starts, and returns the document as the report reads it. The bounds of the
chain's parameters are those of the chain model's axes (``model.CHAIN``).
"""

from __future__ import annotations

from ...errors import InputError
from ...workflow.validate import Table, as_number, check_range, read_toml
from ._validate import ENDS, check_n_events
from .model import CHAIN, REPORT_WORKFLOW

__all__ = ["load_report_workflow"]

_TABLES = ("study", "chain", "sweep", "catalog", "threshold", "near_half", "sweep_small_nu", "presets",
           "published_nu", "ell_scan")
_SWEEP = ("sizes", "seeds", "nu_f", "nu_f_max", "cycles_per_step", "transient_cycles", "max_events_per_step",
          "longest_event")
#: Runs per N, steps, events: a typo such as 1e9 is refused here rather than run for days.
_MOST_LIST = 1000


def _n_events(table: Table, n: int, events: int, events_key: str = "events") -> None:
    """One run of the study within the chain's N × events bound (``bounds.CHAIN_MAX_N_EVENTS``, as
    ``bifurcation chain`` and ``submit``)."""
    check_n_events(n, events, n_key="N =", events_key=table.path(events_key), what="one chain run of the study",
                   more=" (the study runs each catalog whole, in one process)")


def _axis(name: str) -> dict:
    low, high = CHAIN.axis(name).bounds
    return {"low": low, "high": high}


def _same_length(table: Table, names, values) -> None:
    """The lists ``names`` of ``table`` are zipped by the report: a shorter one would drop runs silently."""
    lengths = [len(v) for v in values]
    for name, n in zip(names[1:], lengths[1:]):
        if n != lengths[0]:
            raise InputError(table.path(name), f"{n} values", f"has not the {lengths[0]} values of {names[0]}",
                             f"give one value of {name} per value of {names[0]}")


def _nested(table: Table, name: str, outer: int, *, integer: bool, bounds: dict) -> list:
    """``name = [[...], [...]]``: one non-empty list per value of the table's first list (``outer``)."""
    rows = table.array(name)
    if len(rows) != outer:
        raise InputError(table.path(name), f"{len(rows)} lists", f"has not one list per value of nus ({outer})",
                         f"give {outer} lists, [[...], ...]")
    for i, row in enumerate(rows):
        key = f"{table.path(name)}[{i}]"
        if not isinstance(row, list) or not row:
            raise InputError(key, row, "is not a non-empty list", "write it as [a, b, ...]")
        for j, value in enumerate(row):
            if integer and (isinstance(value, bool) or not isinstance(value, int)):
                raise InputError(f"{key}[{j}]", value, "is not an integer", "write whole numbers")
            check_range(f"{key}[{j}]", as_number(f"{key}[{j}]", value), bounds.get("low"), bounds.get("high"))
    return rows


def load_report_workflow(path) -> dict:
    """The validated chain report workflow at ``path`` (the TOML document; one ``InputError`` on the first
    problem)."""
    from ...laws import resolve_law

    _, doc = read_toml(path, REPORT_WORKFLOW, argument="WORKFLOW", example="workflows/chain-report.toml")
    root = Table(doc, "", _TABLES, source=path)
    study = root.table("study", ("name", "out", "workers"))
    study.string("name")
    if not study.string("out", fix='add out = "results/local/chain" (the directory of the report)').strip():
        raise InputError(study.path("out"), "", "is empty (the working directory)",
                         'give the directory of the report, e.g. out = "results/local/chain"')
    study.integer("workers", 2, high=256)

    chain = root.table("chain", ("law", "ell", "nu", "ends", "amplitude"))
    try:
        resolve_law(chain.string("law"))
    except InputError as exc:
        raise InputError(chain.path("law"), chain.raw("law"), exc.problem, exc.fix) from None
    chain.number("ell", **_axis("ell"))
    chain.number("nu", **_axis("nu"))
    chain.number("amplitude", **_axis("amplitude"))
    if chain.string("ends") not in ENDS:
        raise InputError(chain.path("ends"), chain.raw("ends"), "is not a kind of ends", f"use one of {', '.join(ENDS)}")

    sweep = root.table("sweep", _SWEEP)
    _sweep_lists(sweep, nu_f_max=True)
    _ascending(sweep, sweep.numbers("nu_f", most=_MOST_LIST, **_axis("nu_f")))
    for i, top in enumerate(sweep.numbers("nu_f_max")):   # no step below it: a sweep of nothing (walk 6)
        if top < sweep.numbers("nu_f")[0] - 1e-12:
            raise InputError(f"{sweep.path('nu_f_max')}[{i}]", top, f"is below every nu_f (the first is "
                             f"{sweep.numbers('nu_f')[0]:g}): the sweep of N = {sweep.integers('sizes')[i]} has no step",
                             "give nu_f_max at or above the first value of nu_f")
    sweep.number("transient_cycles", low=0)
    sweep.integer("max_events_per_step", **_axis("events"))
    sweep.number("longest_event", 0.5, above=0)

    catalog = root.table("catalog", ("sizes", "events", "nu_f", "seed", "skip"))
    events = catalog.integers("events", most=_MOST_LIST, **_axis("events"))
    _same_length(catalog, ("sizes", "events"), (catalog.integers("sizes", most=_MOST_LIST, **_axis("n")), events))
    for i, (n, k) in enumerate(zip(catalog.integers("sizes"), events)):
        _n_events(catalog, n, k, f"events[{i}]")
    catalog.numbers("nu_f", most=_MOST_LIST, **_axis("nu_f"))
    catalog.integer("seed", **_axis("seed"))
    skip = catalog.integer("skip", low=0)
    if skip >= min(events):
        raise InputError(catalog.path("skip"), skip, f"leaves no event of the shortest catalog ({min(events)})",
                         "give skip below every value of events")

    threshold = root.table("threshold", ("ells", "nus", "level", "scan_nu", "scan_points"))
    threshold.numbers("ells", most=_MOST_LIST, **_axis("ell"))
    threshold.numbers("nus", most=_MOST_LIST, **_axis("nu"))
    threshold.number("level", above=0)
    threshold.number("scan_nu", **_axis("nu"))
    threshold.integer("scan_points", low=2, high=100_000)

    near = root.table("near_half", ("nus", "nu_f", "sizes", "cycles", "transient_cycles", "events",
                                    "longest_event", "cpu", "seed"), required=False)
    if near is not None:
        nus = near.numbers("nus", most=_MOST_LIST, **_axis("nu"))
        _nested(near, "nu_f", len(nus), integer=False, bounds=_axis("nu_f"))
        sizes = _nested(near, "sizes", len(nus), integer=True, bounds=_axis("n"))
        cycles = _nested(near, "cycles", len(nus), integer=False, bounds={"low": 0})
        for i, (s, c) in enumerate(zip(sizes, cycles)):
            if len(c) != len(s):
                raise InputError(f"{near.path('cycles')}[{i}]", c, f"has not one value per size ({len(s)})",
                                 "give the loading cycles of each N of sizes")
        if isinstance(near.raw("transient_cycles"), list):
            _same_length(near, ("nus", "transient_cycles"), (nus, near.numbers("transient_cycles", low=0)))
        else:
            near.number("transient_cycles", low=0)
        near.integer("events", **_axis("events"))
        _n_events(near, max(max(row) for row in sizes), near.integer("events"))
        near.number("longest_event", above=0)
        near.number("cpu", above=0, high=86400)   # CPU s per catalog, as [published_nu]: a typo refused (walk 6)
        near.integer("seed", **_axis("seed"))

    small = root.table("sweep_small_nu", ("nu", *(k for k in _SWEEP if k != "nu_f_max")), required=False)
    if small is not None:   # the sweep of [sweep] at another nu: the keys it gives replace those of [sweep]
        small.number("nu", **_axis("nu"))
        _sweep_lists(small, nu_f_max=False)
        checks = {"nu_f": lambda: _ascending(small, small.numbers("nu_f", most=_MOST_LIST, **_axis("nu_f"))),
                  "transient_cycles": lambda: small.number("transient_cycles", low=0),
                  "max_events_per_step": lambda: small.integer("max_events_per_step", **_axis("events")),
                  "longest_event": lambda: small.number("longest_event", above=0)}
        for name, check in checks.items():
            if small.has(name):
                check()
    presets = root.table("presets", ("transient_cycles", "bootstrap", "block_bootstrap", "resolution", "verify",
                                     "run"), required=False)
    if presets is not None:   # published parameter sets by the compiled engine (_study_presets.py)
        _presets(presets)
    published = root.table("published_nu", ("v_threshold", "events", "cpu", "bootstrap", "transient_cycles", "run"),
                           required=False)
    if published is not None:   # the presets at their own nu, events split by V_th (subevent_study.py)
        _published_nu(published)
    scan = root.table("ell_scan", ("ells", "sizes", "seeds", "ratios", "continuum", "cycles_per_step",
                                   "transient_cycles", "amplitude", "max_events_per_step", "longest_event"), required=False)
    if scan is not None:   # the ℓ scan of the transition (_study_ell.py)
        _ell_scan(scan)
    return doc


def _ell_scan(table: Table) -> None:
    """``[ell_scan]``: every (ℓ, N) within the chain's axes and N × events bound; ratios ascending (a grid
    in units of ν_f*(ℓ), ν_f = ratio · ν_f* within the ν_f axis for every ℓ)."""
    import math

    ells = table.numbers("ells", most=_MOST_LIST, **_axis("ell"))
    sizes = table.integers("sizes", most=_MOST_LIST, **_axis("n"))
    table.integer("seeds", high=_MOST_LIST)
    ratios = table.numbers("ratios", most=_MOST_LIST, above=0)
    if len(ratios) < 4 or any(b <= a for a, b in zip(ratios, ratios[1:])):
        raise InputError(table.path("ratios"), list(ratios), "is not an ascending grid of at least 4 values",
                         "give ν_f/ν_f* in ascending order, e.g. ratios = [0.5, 0.75, 1.0, 1.25, 1.5, 2.0]")
    continuum = table.numbers("continuum", [], most=_MOST_LIST, above=0) if table.has("continuum") else ()
    table.number("cycles_per_step", above=0)
    table.number("transient_cycles", low=0)
    table.number("amplitude", **_axis("amplitude"))
    events = table.integer("max_events_per_step", **_axis("events"))
    table.number("longest_event", 0.5, above=0)
    low, high = _axis("nu_f")["low"], _axis("nu_f")["high"]
    for ell in ells:
        star = 0.5 / math.sqrt(1 + 2 * ell**2)
        for r in (ratios[0], ratios[-1]):
            check_range(f"{table.path('ratios')} × ν_f*(ℓ = {ell:g})", r * star, low, high)
    for ell in ells:
        for c in continuum:
            n = int(round(c * ell))
            check_range(f"{table.path('continuum')} × ℓ = {ell:g} (N)", n, *_axis("n").values())
    _n_events(table, max(sizes + tuple(int(round(c * e)) for c in continuum for e in ells)), events,
              "max_events_per_step")


def _published_nu(table: Table) -> None:
    from .presets import get_preset, preset_names

    table.number("v_threshold", 0.1, above=0)
    events = table.integer("events", 10**6, **_axis("events"))
    table.number("cpu", 600.0, above=0, high=86400)     # CPU s per catalog: a day at most, a typo refused
    table.integer("bootstrap", 100, low=0, high=10_000)
    table.number("transient_cycles", 1.0, low=0)
    for run in table.tables("run", ("preset", "nu_f"), most=_MOST_LIST):
        if run.string("preset") not in preset_names():
            raise InputError(run.path("preset"), run.raw("preset"), "is not a preset",
                             f"use one of {', '.join(preset_names())}")
        if run.has("nu_f"):
            run.number("nu_f", **_axis("nu_f"))
        _n_events(table, get_preset(run.string("preset")).n, events)


def _presets(table: Table) -> None:
    from .presets import get_preset, preset_names

    table.number("transient_cycles", 1.0, low=0)
    table.integer("bootstrap", 10, low=1, high=10_000)
    table.integer("block_bootstrap", 100, low=1, high=100_000)
    table.integer("resolution", 10, low=1, high=1000)
    table.number("verify", 0.0, low=0, high=1)
    for run in table.tables("run", ("preset", "events", "nu", "nu_f", "ell", "n", "sigma", "ends", "amplitude",
                                    "seed", "t_max", "why", "claim", "bootstrap"), most=_MOST_LIST):
        if run.string("preset") not in preset_names():
            raise InputError(run.path("preset"), run.raw("preset"), "is not a preset",
                             f"use one of {', '.join(preset_names())}")
        run.integer("events", 10**5, **_axis("events"))
        for name in ("nu", "nu_f", "ell", "sigma", "amplitude"):
            if run.has(name):
                run.number(name, **_axis(name))
        n = run.integer("n", **_axis("n")) if run.has("n") else get_preset(run.string("preset")).n
        _n_events(run, n, run.integer("events", 10**5))
        if run.has("seed"):
            run.integer("seed", **_axis("seed"))
        if run.has("ends") and run.string("ends") not in ENDS:
            raise InputError(run.path("ends"), run.raw("ends"), "is not a kind of ends", f"use one of {', '.join(ENDS)}")
        if run.has("t_max"):
            run.number("t_max", above=0)
        if run.has("bootstrap"):     # this run's CSN samples in place of the shared [presets] bootstrap
            run.integer("bootstrap", low=1, high=10_000)
        for name in ("why", "claim"):
            if run.has(name):
                run.string(name)


def _ascending(table: Table, values) -> None:
    """A sweep's ν_f steps go up this list, then down it: out of order or repeated, its up and down branches
    were run and reported under each other's names (walk 6)."""
    if any(b <= a for a, b in zip(values, values[1:])):
        raise InputError(table.path("nu_f"), list(values), "is not in ascending order without repeats (the sweep "
                         "runs up this list, then down it)", "list each ν_f once, smallest first")


def _sweep_lists(table: Table, *, nu_f_max: bool) -> None:
    """``sizes``, ``seeds``, (``nu_f_max``), ``cycles_per_step``: one value per N."""
    names = ("sizes", "seeds", *(("nu_f_max",) if nu_f_max else ()), "cycles_per_step")
    values = [table.integers("sizes", most=_MOST_LIST, **_axis("n")), table.integers("seeds", most=_MOST_LIST)]
    if nu_f_max:
        values.append(table.numbers("nu_f_max", most=_MOST_LIST, **_axis("nu_f")))
    values.append(table.numbers("cycles_per_step", above=0, most=_MOST_LIST))   # loading cycles: 0.5 is one
    _same_length(table, names, values)
