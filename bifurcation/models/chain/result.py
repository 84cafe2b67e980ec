"""Outcome of a chain run: the event catalog, the final state and a status (light: no heyoka)."""

from __future__ import annotations

from dataclasses import dataclass
from enum import IntEnum

import numpy as np

__all__ = ["CATALOG_ATTRS", "CATALOG_FIELDS", "ChainResult", "ChainStatus", "ENERGY_FIELDS"]

#: Per-event fields of the catalog, in order (issue 10; docs/chain.md).
CATALOG_FIELDS = ("t_start", "hypocentre", "n_blocks", "potency", "duration", "max_velocity")
#: Per-event energy budget, present when the run was made with ``energy=True``.
ENERGY_FIELDS = ("driver_work", "dissipation", "elastic_change")

CATALOG_ATTRS = {
    "t_start": ("time of the first failure of the event", "sqrt(m/k)"),
    "hypocentre": ("0-based index of the first failing block", "1"),
    "n_blocks": ("distinct blocks that slipped during the event", "1"),
    "potency": ("P = sum_j (U_j(end) - U_j(start))", "F0/k"),
    "duration": ("time from the first failure until all blocks are stuck again", "sqrt(m/k)"),
    "max_velocity": ("largest block velocity during the event", "V0"),
    "steps": ("Taylor steps taken by the event", "1"),
    "driver_work": ("work of the pulling springs during the event", "F0^2/k"),
    "dissipation": ("work of friction during the event", "F0^2/k"),
    "elastic_change": ("change of the elastic energy over the event", "F0^2/k"),
}


class ChainStatus(IntEnum):
    """Outcome of a run. Codes agree with ``bifurcation.Status`` where the meaning is shared."""

    COMPLETE = 1    #: all requested events computed
    NO_STOP = 3     #: an event did not end before its time or step bound (the catalog holds the rest)
    #: a slipping block's velocity went negative without a stop event (a missed event): the engine
    #: cannot vouch for the event, so the run stops there
    BACK_SLIP = 4
    NONFINITE = 5   #: the integrator produced a non-finite state

    def __str__(self) -> str:
        return self.name.lower().replace("_", "-")


@dataclass(frozen=True)
class ChainResult:
    """The catalog of the first events of a chain run and the state after the last one.

    Catalog fields (numpy arrays, one entry per completed event): ``t_start``, ``hypocentre``,
    ``n_blocks``, ``potency``, ``duration``, ``max_velocity``, ``steps`` and, with ``energy=True``,
    ``driver_work``, ``dissipation``, ``elastic_change``. Final state: time ``t``, displacements ``u``
    and stresses ``stress`` (all blocks stuck). ``status`` says whether all events were computed.
    """

    law: str
    n: int
    ell: float
    nu: float
    nu_f: float
    ends: str
    precision: str
    u0: np.ndarray
    t_start: np.ndarray
    hypocentre: np.ndarray
    n_blocks: np.ndarray
    potency: np.ndarray
    duration: np.ndarray
    max_velocity: np.ndarray
    steps: np.ndarray
    t: float
    u: np.ndarray
    stress: np.ndarray
    status: ChainStatus
    message: str = ""
    energy: dict | None = None
    #: friction drop σ of the run (0: the seed's model)
    sigma: float = 0.0
    #: event membership: None, every block that moved (the event runs until all are stuck); V_th > 0,
    #: ``n_blocks`` and ``potency`` count the blocks faster than V_th, ``*_all`` every block that moved
    v_threshold: float | None = None
    n_blocks_all: np.ndarray | None = None
    potency_all: np.ndarray | None = None

    @property
    def membership(self) -> str:
        """Which event definition ``n_blocks`` and ``potency`` follow: "all-stuck" or "v-threshold=<V_th>"."""
        return "all-stuck" if self.v_threshold is None else f"v-threshold={float(self.v_threshold)!r}"
    #: per event, the compiled engine's error estimate of the potency (relative; None for "exact")
    error_estimate: np.ndarray | None = None
    #: ``verify``: events re-run by the exact engine and the largest differences (``_compiled.run_verified``)
    verification: dict | None = None

    @property
    def events(self) -> int:
        return int(self.t_start.size)

    def __getitem__(self, key: str):
        if self.energy is not None and key in self.energy:
            return self.energy[key]
        return getattr(self, key)

    def catalog(self) -> dict:
        """The catalog as a dict of arrays (energy fields included when computed)."""
        out = {k: getattr(self, k) for k in (*CATALOG_FIELDS, "steps")}
        if self.energy is not None:
            out.update(self.energy)
        return out

    def to_json(self) -> dict:
        """A JSON-ready dict: parameters, catalog fields as lists, final state, status."""
        rec = {"law": self.law, "n": self.n, "ell": self.ell, "nu": self.nu, "nu_f": self.nu_f,
               "ends": self.ends, "precision": self.precision, "events": self.events,
               "status": str(self.status), "sigma": self.sigma, "membership": self.membership}
        for k, v in self.catalog().items():
            rec[k] = np.asarray(v).tolist()
        if self.v_threshold is not None:
            rec["v_threshold"] = self.v_threshold
            rec["n_blocks_all"] = np.asarray(self.n_blocks_all).tolist()
            rec["potency_all"] = np.asarray(self.potency_all).tolist()
        rec["t"] = float(self.t)
        rec["u"] = np.asarray(self.u, dtype=float).tolist()
        rec["stress"] = np.asarray(self.stress, dtype=float).tolist()
        if self.message:
            rec["message"] = self.message
        if self.error_estimate is not None:    # the compiled engine
            rec["error_estimate"] = np.asarray(self.error_estimate, dtype=float).tolist()
        if self.verification is not None:
            rec["verification"] = {k: (dict(v) if isinstance(v, dict) else v) for k, v in self.verification.items()}
        return rec
