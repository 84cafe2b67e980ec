"""The chain study's workflow (``workflows/chain-report.toml``, run by ``bifurcation study chain``): read
and checked whole before anything runs.

The study (``report.main``) reads the parsed TOML as a dict; ``load_chain_study`` returns that dict
once every table and key is known, of the right type, within the chain model's bounds (its axes), and
the arrays that are read side by side have one length. Each error is an ``InputError`` naming the
dotted key, the value and the fix (``workflow._toml``).
"""

from __future__ import annotations

import tomllib

from ...errors import InputError
from ...workflow._toml import Table, as_number, check_range, other_command, read_workflow_text

__all__ = ["MAX_WORKERS", "load_chain_study"]

#: Worker processes of one study: its runs are independent, more than the machine's cores only queue.
MAX_WORKERS = 256
_EXAMPLE = "workflows/chain-report.toml"
_TABLES = ("study", "chain", "sweep", "catalog", "threshold", "near_half", "sweep_small_nu")


def _bounds(name: str) -> tuple:
    from .model import CHAIN

    return CHAIN.axis(name).bounds


def _number(key: str, value, axis: str | None = None, *, positive: bool = False) -> float:
    x = as_number(key, value)
    if axis is not None:
        low, high = _bounds(axis)
        check_range(key, x, low, high, f"give a value in [{low:g}, {high:g}], the chain model's bounds of {axis}")
    elif positive and x <= 0:
        raise InputError(key, x, "is not > 0", "give a positive number")
    return x


def _integer(key: str, value, axis: str | None = None, *, low: int = 0) -> int:
    if isinstance(value, bool) or not isinstance(value, int):
        raise InputError(key, value, "is not an integer", "write a whole number without a decimal point")
    high, fix = None, f"give a whole number >= {low}"
    if axis is not None:
        low, high = (int(b) for b in _bounds(axis))
        fix = f"give a whole number in [{low}, {high}], the chain model's bounds of {axis}"
    check_range(key, value, low, high, fix)
    return value


def _numbers(t: Table, name: str, axis: str | None = None, *, positive: bool = False) -> list:
    return [_number(f"{t.path(name)}[{i}]", v, axis, positive=positive) for i, v in enumerate(t.array(name))]


def _integers(t: Table, name: str, axis: str | None = None, *, low: int = 0) -> list:
    return [_integer(f"{t.path(name)}[{i}]", v, axis, low=low) for i, v in enumerate(t.array(name))]


def _same_length(t: Table, names: tuple[str, ...]) -> None:
    """Arrays read side by side (one entry per chain size) must have one length."""
    first = len(t.raw(names[0]))
    for name in names[1:]:
        if len(t.raw(name)) != first:
            raise InputError(t.path(name), t.raw(name), f"has {len(t.raw(name))} entries, {t.path(names[0])} has "
                             f"{first}", f"give one entry per entry of {t.path(names[0])}")


def _check(data: dict) -> None:
    from ...laws import resolve_law

    root = Table(data, "", _TABLES)
    study = root.table("study", ("name", "out", "workers"))
    study.string("name")
    study.string("out", "results/local/chain")
    study.integer("workers", 2, low=1, high=MAX_WORKERS)

    chain = root.table("chain", ("law", "ell", "nu", "ends", "amplitude"))
    law = chain.string("law", fix="give a law name (see `bifurcation laws`) or a formula in x")
    try:
        resolve_law(law)
    except InputError as exc:
        raise InputError("chain.law", law, exc.problem, exc.fix) from None
    _number("chain.ell", chain.raw("ell"), "ell")
    _number("chain.nu", chain.raw("nu"), "nu")
    _number("chain.amplitude", chain.raw("amplitude"), "amplitude")
    if chain.string("ends") not in ("free", "periodic"):
        raise InputError("chain.ends", chain.raw("ends"), "is not a boundary condition", "use 'free' or 'periodic'")

    sweep = root.table("sweep", ("sizes", "seeds", "nu_f", "nu_f_max", "cycles_per_step", "transient_cycles",
                                 "max_events_per_step", "longest_event"))
    _integers(sweep, "sizes", "n")
    _integers(sweep, "seeds", low=1)
    _numbers(sweep, "nu_f", "nu_f")
    _numbers(sweep, "nu_f_max", "nu_f")
    _integers(sweep, "cycles_per_step", low=1)
    _same_length(sweep, ("sizes", "seeds", "nu_f_max", "cycles_per_step"))
    sweep.integer("transient_cycles", low=0)
    _integer("sweep.max_events_per_step", sweep.raw("max_events_per_step"), "events")
    _number("sweep.longest_event", sweep.raw("longest_event"), positive=True)

    catalog = root.table("catalog", ("sizes", "events", "nu_f", "seed", "skip"))
    _integers(catalog, "sizes", "n")
    events = _integers(catalog, "events", "events")
    _same_length(catalog, ("sizes", "events"))
    _numbers(catalog, "nu_f", "nu_f")
    _integer("catalog.seed", catalog.raw("seed"), "seed")
    skip = catalog.integer("skip", low=0)
    if skip >= min(events):
        raise InputError("catalog.skip", skip, f"leaves no event of the shortest catalog ({min(events)} events)",
                         "give a transient shorter than every catalog.events")

    threshold = root.table("threshold", ("ells", "nus", "level", "scan_nu", "scan_points"))
    _numbers(threshold, "ells", "ell")
    _numbers(threshold, "nus", "nu")
    _number("threshold.level", threshold.raw("level"), positive=True)
    _number("threshold.scan_nu", threshold.raw("scan_nu"), "nu")
    threshold.integer("scan_points", low=2, high=10_000)

    near = root.table("near_half", ("nus", "nu_f", "sizes", "cycles", "transient_cycles", "events",
                                    "longest_event", "cpu", "seed"))
    nus = _numbers(near, "nus", "nu")
    _same_length(near, ("nus", "nu_f", "sizes", "cycles"))
    for k in range(len(nus)):
        for name, read in (("nu_f", lambda key, v: _number(key, v, "nu_f")),
                           ("sizes", lambda key, v: _integer(key, v, "n")),
                           ("cycles", lambda key, v: _integer(key, v, low=1))):
            row = near.raw(name)[k]
            key = f"near_half.{name}[{k}]"
            if not isinstance(row, list) or not row:
                raise InputError(key, row, "is not a non-empty array", "give one array per entry of near_half.nus")
            for i, v in enumerate(row):
                read(f"{key}[{i}]", v)
        if len(near.raw("cycles")[k]) != len(near.raw("sizes")[k]):
            raise InputError(f"near_half.cycles[{k}]", near.raw("cycles")[k], "has another length than "
                             f"near_half.sizes[{k}]", "give one number of cycles per chain size")
    transient = near.raw("transient_cycles")
    if isinstance(transient, list):
        _integers(near, "transient_cycles")
        _same_length(near, ("nus", "transient_cycles"))
    else:
        near.integer("transient_cycles", low=0)
    _integer("near_half.events", near.raw("events"), "events")
    _number("near_half.longest_event", near.raw("longest_event"), positive=True)
    _number("near_half.cpu", near.raw("cpu"), positive=True)
    _integer("near_half.seed", near.raw("seed"), "seed")

    small = root.table("sweep_small_nu", ("nu", "nu_f", "sizes", "seeds", "cycles_per_step", "transient_cycles",
                                          "max_events_per_step"))
    _number("sweep_small_nu.nu", small.raw("nu"), "nu")
    if small.has("nu_f"):
        _numbers(small, "nu_f", "nu_f")
    _integers(small, "sizes", "n")
    _integers(small, "seeds", low=1)
    _integers(small, "cycles_per_step", low=1)
    _same_length(small, ("sizes", "seeds", "cycles_per_step"))
    small.integer("transient_cycles", low=0)
    if small.has("max_events_per_step"):
        _integer("sweep_small_nu.max_events_per_step", small.raw("max_events_per_step"), "events")


def load_chain_study(path, argument: str = "WORKFLOW") -> dict:
    """The chain study's workflow at ``path`` as the dict the study reads, checked whole (``InputError``
    naming ``argument`` for the file, the dotted key for a value)."""
    text = read_workflow_text(path, argument, _EXAMPLE)
    try:
        data = tomllib.loads(text)
    except tomllib.TOMLDecodeError as exc:
        raise InputError(argument, str(path), f"is not valid TOML ({exc})", f"fix the file; see {_EXAMPLE}") from None
    other_command(data, "study chain", argument, path)
    _check(data)
    return data
