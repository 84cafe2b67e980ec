"""The rate-state section of ``bifurcation report --store`` (a store of the ``rate-state`` model).

Per label: the Hopf point(s) of the store (k_c, ω_c, l1 and criticality per parameter set), a figure of
the attracting state against κ = k/k_c (max and min ln V of the cycle; steady sliding drawn at
ln(V/V_lp) = 0; unbounded growth and unresolved points marked, never given a value), and a table of
the points where the outcome changes along κ (the grid's labels either side).
"""

from __future__ import annotations

import numpy as np

__all__ = ["blocks", "describe_label"]

_MAX_ROWS = 24
_CRIT = {0: "—", 1: "subcritical", 2: "supercritical", 3: "degenerate"}


def describe_label(label: str):
    """A label's equation(s) and source(s), in the shape of a friction law's row (the model's
    ``describe_label`` hook)."""
    from types import SimpleNamespace

    from .laws import resolve_state_law
    from .model import resolve_label

    laws = [resolve_state_law(name) for name in resolve_label(label)]
    return SimpleNamespace(equation="; ".join(law.equation for law in laws),
                           source="; ".join(law.source for law in laws))


def _flat(ds, model, i):
    """The points of label ``i`` as (other-axes index tuples, κ array, arrays over κ) groups."""
    sub = ds.isel({model.labels.name: i})
    others = [a.name for a in model.axes if a.name != "kappa"]
    sub = sub.transpose(*others, "kappa")
    kappa = np.asarray(sub["kappa"].values, dtype=float)
    shape = [sub.sizes[o] for o in others]
    values = {v: np.asarray(sub[v].values) for v in ("status", "done", "k_c", "omega_c", "lyapunov_coefficient",
                                                      "criticality", "ln_v_max", "ln_v_min", "period")}
    for index in np.ndindex(*shape):
        at = {o: float(sub[o].values[j]) for o, j in zip(others, index)}
        yield at, kappa, {k: v[index] for k, v in values.items()}


def _where(at: dict, model) -> str:
    return ", ".join(f"{model.axis(name).symbol} = {value:.6g}" for name, value in at.items())


def blocks(ds, model, out, figures: list, stem: str) -> list:
    """Report blocks for a rate-state store (the model's ``report`` hook)."""
    from ...report import figures as F
    from ...report.document import Figure, Paragraph, Section, Table

    b: list = []
    labels = [str(x) for x in ds[model.labels.name].values]
    for i, label in enumerate(labels):
        hopf_rows, change_rows = [], []
        groups = list(_flat(ds, model, i))
        fig, panels = F._figure(6.4, 4.0)
        ax = panels[0][0]
        for g, (at, kappa, v) in enumerate(groups):
            done = v["done"].astype(bool)
            if done.any():
                j = int(np.flatnonzero(done)[0])
                hopf_rows.append([_where(at, model), f"{v['k_c'][j]:.12g}", f"{v['omega_c'][j]:.12g}",
                                  f"{v['lyapunov_coefficient'][j]:.6g}", _CRIT.get(int(v["criticality"][j]), "?")])
            status = v["status"]
            for s in range(len(kappa) - 1):
                if done[s] and done[s + 1] and status[s] != status[s + 1]:
                    change_rows.append([_where(at, model), f"{kappa[s]:.6g} ({model.status_name(status[s])}) → "
                                        f"{kappa[s + 1]:.6g} ({model.status_name(status[s + 1])})"])
            if g >= 6:
                continue
            cyc = done & (status == 2)
            # the legend names only the axes this store varies (the others are in the table above)
            varying = {n: x for n, x in at.items() if ds.sizes[n] > 1}
            line = ax.plot(kappa[cyc], v["ln_v_max"][cyc], ".-", ms=4, lw=1, label=_where(varying, model) or label)[0]
            ax.plot(kappa[cyc], v["ln_v_min"][cyc], ".-", ms=4, lw=1, color=line.get_color())
            steady = done & (status == 1)
            ax.plot(kappa[steady], np.log(at.get("v_lp", 1.0)) * np.ones(steady.sum()), "s", ms=4,
                    color=line.get_color(), mfc="none")
            for code, marker in ((3, "^"), (4, "x")):
                m = done & (status == code)
                ax.plot(kappa[m], np.full(m.sum(), np.log(at.get("v_lp", 1.0))), marker, ms=6,
                        color=line.get_color())
        ax.set_xscale("log")
        ax.set_xlabel("κ = k/k_c")
        ax.set_ylabel("max and min ln V of the cycle")
        ax.set_title(f"{label}: □ steady sliding, ▲ unbounded growth, × not resolved", fontsize=9)
        if len(groups) > 1:
            ax.legend(fontsize=6)
        name = f"{stem}_rate_state{i}.png"
        F.save(fig, out / name)
        figures.append(out / name)
        section = [Table(["at", "k_c", "ω_c", "l1", "Hopf point"], hopf_rows[:_MAX_ROWS]),
                   Figure(name, f"Where steady sliding perturbed by 1e-2 in ln V goes, against κ ({label}).")]
        if change_rows:
            section += [Paragraph("Where the outcome changes along κ (neighbouring grid labels):"),
                        Table(["at", "between"], change_rows[:_MAX_ROWS])]
        else:
            section.append(Paragraph("The outcome does not change along κ on this grid."))
        b.append(Section(f"State law {label}", section, level=3))
    return b
