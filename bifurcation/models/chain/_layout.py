"""Named slots of a chain window integrator: its runtime parameters (``WindowParams``) and its state
variables (``WindowState``), one layout read by the builder (``_integrator``, which makes the heyoka
expressions) and the event loop (``_loop``, which fills and reads the numbers), so no module computes
an index by hand.

Order of the parameters (heyoka ``par[i]``, docs/chain.md):

* the globals ν, ν_f and ℓ² (``nu``, ``nu_f``, ``l2``);
* per window position i = 0 … M − 1, group by group: ``p`` (1 slipping, 0 stuck), ``d`` = σ_i − 1 at
  the segment's start, ``q`` (the start event's stress scale), ``bond`` (b_i: position i is bonded to
  i + 1) and ``selfc`` (s_i: the ghost coupling of a free chain end);
* for a law of K > 1 pieces, the one-hot piece selectors, piece-major (K × M);
* for a friction drop σ > 0 only, ``sigma`` and ``c`` = 1 − σ, after everything else: the σ = 0
  layout (and integrator) is the one without them, so its catalogs stay bit-identical.

Order of the state: the scaled slips w_i of the M positions, their scaled velocities v_i, and with the
energy integrals (tests) the scaled dissipation and the scaled displacement sum.
"""

from __future__ import annotations

from dataclasses import dataclass, field
from typing import ClassVar

__all__ = ["WindowParams", "WindowState"]


@dataclass(frozen=True)
class WindowParams:
    """The runtime parameter slots of a window of ``m`` positions for a law of ``n_pieces`` pieces,
    with the friction drop's two slots if ``drop``."""

    m: int
    n_pieces: int = 1
    drop: bool = False

    GLOBALS: ClassVar[tuple] = ("nu", "nu_f", "l2")
    PER_POSITION: ClassVar[tuple] = ("p", "d", "q", "bond", "selfc")
    DROP: ClassVar[tuple] = ("sigma", "c")

    #: slot of each global name, and first slot of each per-position group (computed once)
    _slot: dict = field(init=False, repr=False, compare=False)
    _selectors: int = field(init=False, repr=False, compare=False)
    size: int = field(init=False, compare=False)

    def __post_init__(self) -> None:
        if self.m < 1 or self.n_pieces < 1:
            raise ValueError(f"a window needs m >= 1 positions and n_pieces >= 1, not m = {self.m}, "
                             f"n_pieces = {self.n_pieces}")
        slot = {name: i for i, name in enumerate(self.GLOBALS)}
        first = len(self.GLOBALS)
        for name in self.PER_POSITION:
            slot[name], first = first, first + self.m
        selectors = first
        if self.n_pieces > 1:
            first += self.n_pieces * self.m
        if self.drop:
            for name in self.DROP:
                slot[name], first = first, first + 1
        object.__setattr__(self, "_slot", slot)
        object.__setattr__(self, "_selectors", selectors)
        object.__setattr__(self, "size", first)

    # -- slot numbers (the loop writes the integrator's parameter array at these) -------------------
    def index(self, name: str) -> int:
        """The slot of a global (``nu``, ``nu_f``, ``l2``; ``sigma``, ``c`` with a drop)."""
        if name in self.PER_POSITION:
            raise KeyError(f"{name!r} has one slot per position: use at({name!r}, i)")
        return self._slot[name]

    def at(self, name: str, i: int) -> int:
        """The slot of group ``name`` (one of ``PER_POSITION``) at window position ``i``."""
        return self._slot[name] + i

    def selector(self, k: int, i: int) -> int:
        """The slot of the one-hot selector of piece ``k`` at position ``i`` (laws of several pieces)."""
        return self._selectors + k * self.m + i

    # -- heyoka expressions (the builder) -----------------------------------------------------------
    def par(self, name: str):
        """The heyoka parameter of a global slot."""
        import heyoka as hy

        return hy.par[self.index(name)]

    def group(self, name: str) -> list:
        """The heyoka parameters of group ``name``, one per position."""
        import heyoka as hy

        return [hy.par[self.at(name, i)] for i in range(self.m)]

    def selectors(self) -> list | None:
        """Per piece, its one-hot selector parameters per position (None for a one-piece law)."""
        import heyoka as hy

        if self.n_pieces == 1:
            return None
        return [[hy.par[self.selector(k, i)] for i in range(self.m)] for k in range(self.n_pieces)]

    # -- numbers (the loop) -------------------------------------------------------------------------
    def pack(self, *, nu, nu_f, l2, p: list, d: list, q: list, bond: list, selfc: list,
             pieces: list | None = None, drop: tuple = ()) -> list:
        """Every slot's value, in slot order (one write of the integrator's parameters per segment).

        ``p`` … ``selfc``: M values each; ``pieces``: each position's piece (laws of several pieces);
        ``drop``: (σ, 1 − σ) for a friction drop. Python lists throughout: this runs once per segment
        on the loop's hot path."""
        values = [nu, nu_f, l2] + p + d + q + bond + selfc
        if self.n_pieces > 1:
            m = self.m
            onehot = [0.0] * (self.n_pieces * m)
            for i, pc in enumerate(pieces):
                onehot[pc * m + i] = 1.0
            values += onehot
        if self.drop:
            values += drop
        return values


@dataclass(frozen=True)
class WindowState:
    """The state slots of a window of ``m`` positions: w_i at ``i``, v_i at ``v0 + i``, and with
    ``energy`` the integrals at ``diss`` and ``disp`` (-1 without)."""

    m: int
    energy: bool = False
    v0: int = field(init=False)
    diss: int = field(init=False)
    disp: int = field(init=False)
    size: int = field(init=False)

    def __post_init__(self) -> None:
        if self.m < 1:
            raise ValueError(f"a window needs m >= 1 positions, not m = {self.m}")
        m = self.m
        object.__setattr__(self, "v0", m)
        object.__setattr__(self, "diss", 2 * m if self.energy else -1)
        object.__setattr__(self, "disp", 2 * m + 1 if self.energy else -1)
        object.__setattr__(self, "size", 2 * m + (2 if self.energy else 0))

    def slips(self, k: int) -> slice:
        """The w of the first ``k`` positions."""
        return slice(0, k)

    def velocities(self, k: int) -> slice:
        """The v of the first ``k`` positions."""
        return slice(self.v0, self.v0 + k)
