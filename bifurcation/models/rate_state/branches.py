"""The store of ``bifurcation continue``: branches of cycles of the rate-state slider, as a declaration.

``RATE_STATE_BRANCHES`` (registry name ``rate-state-branches``) declares the store's dimensions — the
branch (its label in the workflow) × the point along it (0 nearest the Hopf point) — and one output per
array, so that ``bifurcation.store`` writes it with the layout, CRC-32C checksums, ``done`` mask and
consolidated metadata of every store, and ``status``, ``query``, ``verify``, ``export`` and ``report
--store`` read it like any other. Its points are continued one from the other, not solved one by one:
``Model.written_by`` says the command that writes its stores whole (``write_branch_store``).

A branch shorter than the longest ends in points of status ``past-end`` (every value NaN; its ``stop``
attribute says why it ended). The per-branch values (``k_c``, ``omega_c``, ``lyapunov_coefficient``,
``criticality``, ``mass``, ``damping``, ``fold_kappa``) are repeated at each point of their branch, so one
record of ``query`` carries them; the group attributes ``stop`` and ``parameter`` list, per branch, why
its continuation stopped and what it was continued in (``kappa`` or ``v_lp``).
"""

from __future__ import annotations

import hashlib
import json
from dataclasses import asdict
from enum import IntEnum

import numpy as np

from ...errors import InputError
from .._base import Axis, Hooks, Labels, Model, Output
from .model import CRITICALITY, RATE_STATE
from .study import MAX_POINTS

__all__ = ["RATE_STATE_BRANCHES", "BranchStatus", "branch_values", "write_branch_store"]


class BranchStatus(IntEnum):
    """A stored branch point (0 is the store's "not computed")."""

    NOT_COMPUTED = 0
    PERIODIC_ORBIT = 1      #: Newton converged on the periodic orbit (stable or not: see multiplier_max)
    NO_CONVERGENCE = 2      #: kept on the branch, but its Newton iteration did not converge
    PAST_END = 3            #: beyond the end of a branch shorter than the longest (no point: NaN)

    def __str__(self) -> str:
        return self.name.lower().replace("_", "-")


def _label(text) -> str:
    if not isinstance(text, str) or not text.strip():
        raise InputError("branch", text, "is not a branch label", "give the label of a [[branch]] of the workflow")
    return text.strip()


_PER_BRANCH = ("k_c", "omega_c", "lyapunov_coefficient", "criticality", "mass", "damping", "fold_kappa")

OUTPUTS = (
    Output("kappa", "spring stiffness over its critical value at the point's V_lp, k/k_c"),
    Output("k", "spring stiffness k", "1/length"),
    Output("v_lp", "load-point velocity V_lp", "length/time"),
    Output("period", "cycle period", "time"),
    Output("period_check", "|T(direct simulation)/T − 1|"),
    Output("ln_v_max", "max ln V over the cycle"),
    Output("ln_v_min", "min ln V over the cycle"),
    Output("slip", "slip per cycle, V_lp T", "length"),
    Output("multiplier_max", "largest |Floquet multiplier| (nontrivial)"),
    Output("k_c", "critical stiffness k_c at the branch's Hopf point", "1/length"),
    Output("omega_c", "angular frequency ω_c at the branch's Hopf point", "1/time"),
    Output("lyapunov_coefficient", "first Lyapunov coefficient l1 at the branch's Hopf point"),
    Output("criticality", "the branch's Hopf point: 1 subcritical, 2 supercritical, 3 degenerate", dtype="int8",
           fill=0, names=("", *sorted(CRITICALITY, key=CRITICALITY.get))),
    Output("mass", "block mass M of the branch (0: quasi-static)", "time^2/length"),
    Output("damping", "radiation damping η of the branch", "time/length"),
    Output("fold_kappa", "κ at the branch's first fold (NaN: none)"),
    Output("status", "outcome code (see BranchStatus)", dtype="int8", fill=0),
)

RATE_STATE_BRANCHES = Model(
    name="rate-state-branches",
    title="branches of cycles of the rate-state spring-slider (bifurcation continue)",
    description=("cycles continued from the Hopf point of steady sliding in κ = k/k_c or in V_lp, each a periodic "
                 "orbit found by Newton with its Floquet multipliers and its period checked by direct simulation "
                 "(docs/rate-state.md)"),
    source=RATE_STATE.source,
    labels=Labels(name="branch", long_name="branch of cycles (its label in the workflow)", workflow_key="branch",
                  resolve=_label, identity=_label, example="prz, quasi-static"),
    axes=(Axis("point", "i", "index of the point along its branch (0: nearest the Hopf point)",
               bounds=(0.0, float(MAX_POINTS)), dtype="int64", example=0, default_tile=MAX_POINTS),),
    parameters=(),
    state=(),
    events=(),
    outputs=OUTPUTS,
    statuses=tuple(s for s in BranchStatus if s != BranchStatus.NOT_COMPUTED),
    equations=None,
    classify=None,
    written_by="continue",
    hooks=Hooks(report="bifurcation.models.rate_state.branches:blocks"),
    units_note=RATE_STATE.units_note,
)


def branch_values(results) -> tuple[list[str], int, dict]:
    """``(labels, points, values)``: the arrays of the store of continuation ``results`` (``run_study``'s),
    over (branch, point), ``done`` included (every cell: a point or past the end of its branch)."""
    labels = [r["spec"].label for r in results]
    n_points = max(len(r["branch"].points) for r in results)
    shape = (len(results), n_points)
    values = {o.name: np.full(shape, o.fill, dtype=o.dtype) for o in OUTPUTS}
    values["status"][:] = BranchStatus.PAST_END
    for i, r in enumerate(results):
        branch = r["branch"]
        h = branch.hopf
        per_branch = {"k_c": h.k_c, "omega_c": h.omega_c, "lyapunov_coefficient": h.lyapunov_coefficient,
                      "criticality": CRITICALITY.get(h.criticality, 0), "mass": branch.spec.mass or 0.0,
                      "damping": branch.spec.damping,
                      "fold_kappa": branch.points[branch.folds[0]].kappa if branch.folds else np.nan}
        for j, p in enumerate(branch.points):
            point = {"kappa": p.kappa, "k": p.k, "v_lp": p.v_lp if np.isfinite(p.v_lp) else branch.v_lp,
                     "period": p.period, "period_check": r["period_check"][j], "ln_v_max": p.ln_v_max,
                     "ln_v_min": p.ln_v_min, "slip": p.slip,
                     "multiplier_max": max(abs(z) for z in p.multipliers),
                     "status": BranchStatus.PERIODIC_ORBIT if p.status == "ok" else BranchStatus.NO_CONVERGENCE,
                     **per_branch}
            for name, value in point.items():
                values[name][i, j] = value
    values["done"] = np.ones(shape, dtype=bool)
    return labels, n_points, values


def write_branch_store(path, spec, results, *, command: str | None = None) -> dict:
    """Write the store of a continuation study (``spec``: its ``StudySpec``; ``results``: ``run_study``'s)
    at ``path`` through ``bifurcation.store`` (built beside it and renamed into place); returns its attrs."""
    from ...store.layout import store_attrs
    from ...store.zarr_store import write_whole_store

    labels, n_points, values = branch_values(results)
    # what determines the numbers: the branches (after --damping) and the closed-form grid, not the text
    fingerprint = hashlib.sha256(json.dumps(
        {"branches": [asdict(b) for b in spec.branches], "hopf": [spec.hopf_b_over_a, spec.hopf_v_lp, spec.hopf_eta]},
        sort_keys=True, default=repr).encode()).hexdigest()
    attrs = store_attrs(RATE_STATE_BRANCHES, title=spec.name, description=spec.description, text=spec.text,
                        fingerprint=fingerprint, command=command)
    attrs.update(stop=[r["branch"].meta["stop"] for r in results],
                 parameter=[r["branch"].meta.get("parameter", "kappa") for r in results], submits=[])
    return write_whole_store(path, RATE_STATE_BRANCHES, labels, (("point", list(range(n_points))),), values, attrs)


def blocks(ds, model, out, figures, stem) -> list:
    """The ``report`` hook: per branch, what it was continued in, its Hopf point, fold and why it stopped."""
    from ...report.document import Paragraph, Table

    labels = [str(x) for x in ds[model.labels.name].values]
    status = np.asarray(ds["status"].values)
    stop, parameter = (_per_branch_attr(ds.attrs, name, len(labels)) for name in ("stop", "parameter"))
    criticality = model.output("criticality")
    rows = []
    for i, label in enumerate(labels):
        on = status[i] != BranchStatus.PAST_END
        first = int(np.argmax(on)) if on.any() else 0

        def at(name, i=i, first=first):
            return np.asarray(ds[name].values)[i, first]

        kappa = np.asarray(ds["kappa"].values)[i][on]
        fold = at("fold_kappa")
        rows.append([label, parameter[i], str(int(on.sum())),
                     f"{kappa.min():.6g} … {kappa.max():.6g}" if kappa.size else "—",
                     str(criticality.shown(int(at("criticality"))) or "—"), f"{at('k_c'):.10g}",
                     f"{at('lyapunov_coefficient'):.4g}", "—" if np.isnan(fold) else f"{fold:.6g}", stop[i]])
    return [Paragraph("Branches of cycles continued from the Hopf point (the report of `bifurcation continue` "
                      "beside the store has the verdicts and the figure):"),
            Table(["branch", "in", "points", "κ range", "Hopf point", "k_c", "l1", "fold κ", "stop"], rows)]


def _per_branch_attr(attrs, name: str, n: int) -> list:
    """A per-branch list attribute (``open_store`` gives lists as JSON text, for netCDF)."""
    value = attrs.get(name, [""] * n)
    return list(json.loads(value) if isinstance(value, str) else value)
