"""The model contract: what a model declares, and what the engine, workflows, store and reports read.

A model is a frozen declaration (``Model``), in the spirit of heyoka's model factories (the equations
as ``[(variable, rhs)]`` built on demand) and scipy's ``METHODS`` registry (a name → implementation
table behind one documented contract). Everything downstream of a model reads its declaration:

- the **workflow** schema (``[model] name``, one ``[grid.<axis>]`` per ``Axis``, ``[tiles]`` keys),
- the **tiles** and the **store** (dimensions ``(labels.name, *axes)``, one variable per ``Output``
  with its CF attributes, ``status`` flag values from ``statuses``),
- **queries** and the CLI (one option per axis, matched with ``bifurcation.store.labels``),
- the **engine** (state, equations, events, runtime parameter slots, how raw outcomes become
  statuses and fields),
- the **report**, the **bench** and the **CLI**, through the model's ``hooks`` (lazy
  ``"module:attribute"`` references to what it can do beyond the declaration): no layer asks which
  model it holds.

See docs/models.md for the contract in prose with the single block as the example.
"""

from __future__ import annotations

import math
from collections.abc import Callable, Mapping
from dataclasses import dataclass, field

import numpy as np

from ..outcome import Status

__all__ = ["ACTIONS", "Axis", "Event", "Hooks", "Labels", "Model", "Output", "Slots", "StateVar", "System"]

#: What an event does when it fires (``Event.action``):
#: ``end``     terminal: the run of this point ends here (the single block's stop);
#: ``switch``  terminal: the piece selector of the friction law moves up or down one piece;
#: ``maximum`` records the running maximum of the output named by ``Event.records``;
#: ``first``   records the time of its first occurrence into ``Event.records``;
#: ``set``     terminal: sets runtime slots to the values ``System.sets[name][instance]`` gives (a load
#:             history's step, say: the event function is t − t_k);
#: ``step``    terminal: ends the Taylor step there and does nothing else (a rung of a ladder that keeps
#:             a step from stepping over friction that fades).
#: ``maximum`` and ``first`` events are terminal (exact time and state at the event); in batch mode
#: they record in heyoka's callback and the integration goes on (a return stops every SIMD lane).
ACTIONS = ("end", "first", "maximum", "set", "step", "switch")
_SCALES = ("linear", "log")
_DTYPES = ("float64", "int64", "int8", "bool")


@dataclass(frozen=True)
class Axis:
    """A numeric parameter axis of a study: one ``[grid.<name>]`` table, one store dimension.

    ``bounds`` are the closed range a workflow accepts (the range the engine is checked on).
    ``scale`` says how values are spaced and compared when a query asks for the nearest label
    (``log``: by ratio). ``structural`` axes change the compiled system itself (the number of blocks
    of a chain, say): the engine compiles one integrator per value; the others are runtime
    parameters (``parameter``: the name of the runtime slot the axis sets, its own name by default).
    """

    name: str                         # identifier: TOML key, store dimension, Python keyword
    symbol: str                       # as printed: "ν_f"
    long_name: str                    # CF long_name
    bounds: tuple[float, float]
    units: str = "1"
    scale: str = "linear"
    example: float = 1.0              # shown in error messages ("such as 0.4")
    default_tile: int = 64
    dtype: str = "float64"            # "int64" for counts (blocks, seeds)
    structural: bool = False
    parameter: str | None = None      # runtime slot set by this axis (default: ``name``)
    #: The one point a workflow without a ``[grid.<name>]`` table takes (None: the table is required),
    #: so that a model of many axes keeps simple workflows short.
    default: float | None = None
    #: Words for the values 0, 1, … of an integer axis that is a choice (a chain's ends: "free",
    #: "periodic"): printed by query and the reports, accepted by query, the store keeps the integers.
    names: tuple[str, ...] = ()

    def __post_init__(self) -> None:
        if not self.name.isidentifier():
            raise ValueError(f"axis name {self.name!r} is not an identifier")
        if self.scale not in _SCALES:
            raise ValueError(f"axis {self.name}: scale {self.scale!r} is not one of {_SCALES}")
        lo, hi = self.bounds
        if not (lo < hi) or (self.scale == "log" and lo <= 0):
            raise ValueError(f"axis {self.name}: bounds {self.bounds} are not an increasing (positive for log) pair")
        if self.dtype not in ("float64", "int64"):
            raise ValueError(f"axis {self.name}: dtype {self.dtype!r} is not float64 or int64")
        if self.default is not None and not lo <= self.default <= hi:
            raise ValueError(f"axis {self.name}: default {self.default} is outside its bounds {self.bounds}")

    def cast(self, value):
        """``value`` as this axis's Python type (int for counts)."""
        return int(value) if self.dtype == "int64" else float(value)

    def shown(self, value):
        """``value`` as printed: its word for a choice axis (``names``), an int for counts."""
        if self.names and float(value).is_integer() and 0 <= int(value) < len(self.names):
            return self.names[int(value)]
        return self.cast(value) if self.dtype == "int64" and float(value).is_integer() else value

    def parse(self, text):
        """A query value: a number, or one of ``names`` (its index)."""
        if self.names and str(text).strip() in self.names:
            return float(self.names.index(str(text).strip()))
        return text

    @property
    def slot(self) -> str:
        return self.parameter or self.name

    @property
    def option(self) -> str:
        """The CLI option of this axis: ``--nu-f``."""
        return "--" + self.name.replace("_", "-")

    def attrs(self) -> dict:
        """CF attributes of the store coordinate."""
        return {"long_name": self.long_name, "units": self.units, "symbol": self.symbol,
                "scale": self.scale, "valid_min": self.bounds[0], "valid_max": self.bounds[1]}


@dataclass(frozen=True)
class Labels:
    """The categorical leading dimension of a model (the friction law of the single block).

    ``resolve(text)`` validates a label (raising ``InputError``); ``identity(text)`` is what two
    labels must share to be the same (a formula's parsed expression, not its text), so
    ``1/(1+x/2)**2`` and ``1/(1+x/2)^2`` are one law in workflows and queries alike.
    """

    name: str                                   # store dimension and record key: "law"
    long_name: str
    workflow_key: str                           # the [engine] key listing them: "laws"
    resolve: Callable[[str], object]
    identity: Callable[[str], object]
    example: str = ""


@dataclass(frozen=True)
class StateVar:
    """One state variable of the integrated system (scaled as the engine integrates it)."""

    name: str
    long_name: str


@dataclass(frozen=True)
class Event:
    """An event of the integration: its ``action`` (``ACTIONS``), what it records, why it exists.

    ``per_piece`` events are declared once and instantiated per breakpoint of the law.
    """

    name: str
    action: str
    description: str
    records: str = ""        # raw outcome written by a "first" or "maximum" event
    per_piece: bool = False
    of: str = ""             # the state variable whose running maximum a "maximum" event records

    def __post_init__(self) -> None:
        if self.action not in ACTIONS:
            raise ValueError(f"event {self.name}: action {self.action!r} is not one of {ACTIONS}")
        if self.action in ("first", "maximum") and not self.records:
            raise ValueError(f"event {self.name}: a {self.action!r} event must name what it records")
        if self.action == "maximum" and not self.of:
            raise ValueError(f"event {self.name}: a 'maximum' event must name the state variable (of=...)")

    @property
    def terminal(self) -> bool:
        """Terminal in batch mode too (it changes the integration, not just a record)."""
        return self.action in ("end", "set", "step", "switch")


@dataclass(frozen=True)
class Output:
    """A result of one point: a store variable with its CF attributes and fill value.

    ``per_event`` outputs are catalogs (one value per event of a run, ragged across runs); a store
    format for them is the business of the model that first declares one (see docs/models.md).
    """

    name: str
    long_name: str
    units: str = "1"
    dtype: str = "float64"
    fill: float | int | bool = math.nan
    per_event: bool = False
    #: Words for the codes 0, 1, … of an integer output that is a category (rate-state's criticality):
    #: query and the reports print the word ("" for a code that means no value); the store keeps codes.
    names: tuple[str, ...] = ()

    def shown(self, value):
        """``value`` as printed: its word where ``names`` has one (None for ""), else the value."""
        if self.names and isinstance(value, (int, np.integer)) and 0 <= int(value) < len(self.names):
            return self.names[int(value)] or None
        return value

    def __post_init__(self) -> None:
        if self.dtype not in _DTYPES:
            raise ValueError(f"output {self.name}: dtype {self.dtype!r} is not one of {_DTYPES}")


class Slots:
    """Named runtime parameter slots: ``slots.index("nu_f")`` instead of a magic ``par[1]``.

    The model's ``parameters`` come first, in order; a law with several pieces adds one one-hot
    selector per piece after them (``piece(k)``).
    """

    def __init__(self, names: tuple[str, ...], n_pieces: int = 1) -> None:
        self.names = tuple(names)
        self._index = {name: i for i, name in enumerate(self.names)}
        self.n_pieces = n_pieces
        self.piece0 = len(self.names)
        self.size = len(self.names) + (n_pieces if n_pieces > 1 else 0)

    def index(self, name: str) -> int:
        return self._index[name]

    def piece(self, k: int) -> int:
        """The slot of the one-hot selector of piece ``k`` (only for laws of several pieces)."""
        return self.piece0 + k

    def par(self, name: str):
        """The heyoka runtime parameter of slot ``name``."""
        import heyoka as hy

        return hy.par[self._index[name]]

    def piece_par(self, k: int):
        import heyoka as hy

        return hy.par[self.piece(k)]


@dataclass(frozen=True)
class System:
    """What ``Model.equations`` returns: heyoka state variables, their right-hand sides, and one
    event expression (with its heyoka direction name: "negative", "positive" or "any") per declared
    event, instantiated per piece for ``per_piece`` events: ``events[name]`` is
    ``(expression, direction)`` or a list of them; a name left out is not registered."""

    state: tuple
    rhs: tuple
    events: Mapping
    #: ``(record, breakpoint index)``: the up-crossing of that breakpoint's switch is also the "first"
    #: event ``record`` (declared absent from ``events``: one event function, not two at one x);
    #: its later crossings are kept in order (``crossings`` of the raw outcomes).
    first_on_switch: tuple = ("", -1)
    #: For each "set" event: one ``{slot name: value}`` per instance (what it sets when it fires).
    sets: Mapping = field(default_factory=dict)
    #: Facts about this compiled system that ``classify`` needs (passed as ``raw["info"]``), e.g. the
    #: range of the state a ladder of events vouches for.
    info: Mapping = field(default_factory=dict)


@dataclass(frozen=True)
class Hooks:
    """What a model can do beyond its declaration: lazy ``"module:attribute"`` references ("" = none).

    Imported only when called (``Model.hook(name)``), so declaring them costs nothing and a hook may
    live in any layer (a report section in ``report/``, CLI commands in ``cli/``): the generic layers
    call the hook and never compare ``model.name``. The contract of each:

    - ``describe_label(label)`` → an object with ``equation`` and ``source``: the row of a label in
      ``bifurcation report --store`` (a friction law: ``bifurcation.laws.resolve_law``).
    - ``report(ds, model, out, figures, stem)`` → a list of report blocks (``bifurcation.report.document``;
      the older tuples are read too) of the model's part of a store's section (after the common
      tables of labels, axes and statuses); ``figures`` collects the files it writes into ``out``
      (names start with ``stem``).
    - ``bench(echo=..., **options)`` → a dict: ``bifurcation bench --suite <model name>``; it is
      handed those of the CLI's options (``points``, ``subset``, ``pipeline_points``) its signature
      names. ``bench_needs``: modules its baselines import (checked before any work starts).
    - ``commands``: a list of click commands the CLI adds (``bifurcation <command>``).
    - ``study``: a click command that runs the model's own study from its workflow (a report beyond what
      ``submit`` computes); the CLI adds it as ``bifurcation study <model name>``.
    - ``presets(name)`` → (axis values, (label,)): a workflow's ``[model] preset = "NAME"`` (published
      parameter sets); raises ``InputError`` for an unknown name.
    - ``workflow``: a ``bifurcation.workflow.validate.WorkflowKind`` (or a tuple of them): the model's own
      workflows besides ``submit``'s (rate-state's ``continue``), so that every command names the right
      one when given another's file; the model reads them with that module's ``read_toml`` and ``Table``.
    - ``check_grid(workflow)``: the model's own bounds across a workflow's axes, checked when the workflow
      is built (before any work): raises ``InputError`` naming the ``grid.*`` key (the chain's N × events).
    - ``check_batch(workflow)``: with ``[engine] batch`` > 1 (a runner that batches), checked once the
      tiles are set: raises ``InputError`` where no tile holds points the runner's lanes can share.
    """

    describe_label: str = ""
    report: str = ""
    bench: str = ""
    bench_needs: tuple[str, ...] = ()
    commands: str = ""
    presets: str = ""
    study: str = ""
    workflow: str = ""
    check_grid: str = ""
    check_batch: str = ""

    def __post_init__(self) -> None:
        for name in ("describe_label", "report", "bench", "commands", "presets", "study", "workflow", "check_grid",
                     "check_batch"):
            value = getattr(self, name)
            module, _, attribute = value.partition(":")
            if value and not (module and attribute.isidentifier()
                              and all(part.isidentifier() for part in module.split("."))):
                raise ValueError(f"hook {name}={value!r}: give 'package.module:attribute'")

    def resolve(self, name: str):
        """The object hook ``name`` refers to (imported now), or None if the model declares none."""
        import importlib

        value = getattr(self, name)
        if not value:
            return None
        module, attribute = value.split(":")
        return getattr(importlib.import_module(module), attribute)


@dataclass(frozen=True)
class Model:
    """A model's declaration (see the module docstring and docs/models.md).

    ``equations(law, slots, num, *, precision, **structure)`` builds the system for a resolved label
    (``num`` makes a constant in the integrator's ``precision``, "double" or "quad"; ``structure``
    holds the values of the ``structural`` axes, e.g. ``n=64`` blocks: the engine compiles one system
    per distinct value). ``classify(raw, points)`` turns the engine's raw outcomes (arrays
    over the points: the recorded outcomes, ``time``, the final state by name, ``steps``, ``status``
    and ``messages``) into the model's ``outputs`` and messages; ``points`` maps every runtime
    parameter to its per-point values. ``fixed`` sets the runtime slots no axis sets.

    A model whose point is not one integration of declared equations (a chain's event loop and its
    catalog, a rate-and-state limit cycle found by shooting) declares a ``runner`` instead of
    ``equations``/``classify`` (both None): ``runner(model, label, points, *, precision, t_max,
    max_steps, batch) -> (fields, messages)`` with ``points`` the flat per-axis arrays and ``fields``
    one array per output over them. ``bifurcation.engine.solve`` calls it, so tiles, the serial
    reference, the store, queries and reports serve such a model like any other.
    """

    name: str
    title: str
    description: str
    source: str
    labels: Labels
    axes: tuple[Axis, ...]
    parameters: tuple[str, ...]
    state: tuple[StateVar, ...]
    events: tuple[Event, ...]
    outputs: tuple[Output, ...]
    statuses: tuple[Status, ...]
    equations: Callable | None
    classify: Callable | None
    fixed: Mapping = field(default_factory=dict)
    initial_state: tuple = ()
    checkpoint: bool = False      # a run long enough to checkpoint its state between chunks of work
    #: ``initial_state`` for a structural value (an N-block chain's 2N zeros), if it depends on one.
    initial: Callable | None = None
    #: The model's own engine for one label over flat points (see above); None: the generic engine.
    runner: Callable | None = None
    #: For models with ``per_event`` outputs (catalogs): the axis whose value is the most events a run
    #: catalogs (its capacity in the store), and the per-run output that counts the events catalogued.
    catalog_size: str | None = None
    catalog_count: str | None = None
    #: Its capabilities beyond the declaration (report section, bench suite, CLI commands, ...).
    hooks: Hooks = field(default_factory=Hooks)
    #: One line for reports: the units its numbers are in.
    units_note: str = ""
    #: The command that writes this declaration's stores whole (``"continue"``: rate-state's branches of
    #: cycles, each point continued from the one before): no engine runs its points one by one, so it
    #: declares neither equations nor a runner, and a ``submit`` workflow cannot name it.
    written_by: str = ""
    #: A runtime slot that, set to 0 with the state at ``initial_state``, holds the system exactly at rest
    #: (the single block's ``forcing``: W = V = 0 stays there). The batch engine parks a lane whose point
    #: has ended there and reloads parked lanes together (engine/_batch.py); empty: no parking.
    rest_slot: str = ""
    #: The engine's revision for this model: raised when a change moves the last bits of its numbers, so a
    #: store half-made by the older engine is not resumed with runs of the newer (it enters the workflow's
    #: fingerprint when above 0; 0 keeps the fingerprints of stores made before revisions were counted).
    revision: int = 0
    #: A runner that can run a tile's points in SIMD lanes (``[engine] batch`` > 1; rs-chain's run_batch):
    #: above 0 a workflow may ask for a batch, and the value enters its fingerprint with the batch (raised
    #: when the batch engine's last bits move). 0: a runner model refuses ``batch`` (the generic engine's
    #: batches do not read it).
    batch_revision: int = 0

    def __post_init__(self) -> None:
        if self.rest_slot and self.rest_slot not in self.parameters:
            raise ValueError(f"model {self.name}: rest_slot {self.rest_slot!r} is not one of its parameters")
        if self.runner is None and (self.equations is None or self.classify is None) and not self.written_by:
            raise ValueError(f"model {self.name}: declare equations and classify, or a runner (or written_by)")
        names = [self.labels.name, *(a.name for a in self.axes)]
        if len(set(names)) != len(names):
            raise ValueError(f"model {self.name}: dimension names {names} repeat")
        slots = set(self.parameters)
        generic = self.runner is None and not self.written_by   # the generic engine sets its runtime slots
        for axis in self.axes:
            if generic and not axis.structural and axis.slot not in slots:
                raise ValueError(f"model {self.name}: axis {axis.name} sets no runtime parameter")
        unset = set() if not generic else slots - {a.slot for a in self.axes if not a.structural} - set(self.fixed)
        if unset:
            raise ValueError(f"model {self.name}: runtime parameters {sorted(unset)} set by no axis")
        outputs = [o.name for o in self.outputs]
        if len(set(outputs)) != len(outputs) or "done" in outputs:
            raise ValueError(f"model {self.name}: outputs {outputs} repeat or use the reserved name 'done'")
        if any(o.per_event for o in self.outputs):
            if self.catalog_size not in [a.name for a in self.axes] or self.catalog_count not in outputs \
                    or self.output(self.catalog_count).per_event:
                raise ValueError(f"model {self.name}: per-event outputs need catalog_size (an axis: the most "
                                 "events of a run) and catalog_count (a per-run output: the events catalogued)")
        if not self.initial_state:
            object.__setattr__(self, "initial_state", (0.0,) * len(self.state))

    # -- derived ---------------------------------------------------------------------------------
    @property
    def dims(self) -> tuple[str, ...]:
        """Store dimensions: the labels, then the axes in order."""
        return (self.labels.name, *(a.name for a in self.axes))

    def axis(self, name: str) -> Axis:
        for a in self.axes:
            if a.name == name:
                return a
        raise KeyError(name)

    def output(self, name: str) -> Output:
        for o in self.outputs:
            if o.name == name:
                return o
        raise KeyError(name)

    def status_name(self, code: int) -> str:
        """The name of stored status ``code``: the model's own (``statuses``), else ``bifurcation.Status``'s."""
        for status in self.statuses:
            if int(status) == int(code):
                return str(status)
        try:
            return str(Status(int(code)))
        except ValueError:
            return f"code {int(code)}"

    def hook(self, name: str):
        """The model's hook ``name`` (see ``Hooks``), imported on first use; None if it declares none."""
        return self.hooks.resolve(name)

    @property
    def float_outputs(self) -> tuple[str, ...]:
        return tuple(o.name for o in self.outputs if o.dtype == "float64" and not o.per_event)

    @property
    def catalog_outputs(self) -> tuple[Output, ...]:
        """The ``per_event`` outputs (catalogs, one value per event of a run)."""
        return tuple(o for o in self.outputs if o.per_event)

    def slots(self, n_pieces: int = 1) -> Slots:
        return Slots(self.parameters, n_pieces)

    @property
    def structural(self) -> tuple[Axis, ...]:
        return tuple(a for a in self.axes if a.structural)

    def start(self, structure: Mapping) -> tuple:
        """The initial state for the structural values ``structure``."""
        return tuple(self.initial(**structure)) if self.initial is not None else tuple(self.initial_state)

    def runtime(self, points: Mapping) -> dict:
        """Per-point values of every runtime parameter from the axes' ``points`` and ``fixed``."""
        size = np.size(next(iter(points.values()))) if points else 1
        out = {name: np.full(size, float(value)) for name, value in self.fixed.items()}
        for axis in self.axes:
            if not axis.structural:
                out[axis.slot] = np.asarray(points[axis.name], dtype=float).ravel()
        return out
