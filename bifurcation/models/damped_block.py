r"""A documented example of a second model: the single block with viscous damping γ as a third axis.

.. math:: \ddot U = \nu t - U + 1 - \Phi(\dot U/\nu_f) - \gamma \dot U, \qquad \gamma \ge 0,

scaled as the single block (U = νW): Ẅ = c·t − W − γẆ + g(x)/ν. γ = 0 is the single block bit for
bit (the damping term adds exact zeros). Linearised about the ν = 0 fixed point,
Ü = −U + (1/ν_f − γ)U̇: the fixed point is an unstable node (stick-slip as ν → 0) for
1/ν_f − γ ≥ 2 and a focus (creep) above ν_f* = 1/(2 + γ) (docs/physics.md, "Regimes").

This module is the whole model: its axes, its equations (the single block's with one extra force)
and its classification (creep above ν_f*). Nothing else in the package names it; it is registered
in ``bifurcation.models`` like any model, so workflows, submit, the store, queries and reports serve it.
"""

from __future__ import annotations

from ._base import Axis, Hooks, Model
from .single_block import (BLOCK_UNITS, LAW, NU, NU_F, OUTPUTS, SINGLE_BLOCK, STOP_EVENTS, block_equations,
                           classify_cycles)

__all__ = ["DAMPED_BLOCK", "GAMMA"]

GAMMA = Axis("gamma", "γ", "viscous damping coefficient γ (force −γU̇)", bounds=(0.0, 10.0), example=0.1)


def _equations(law, slots, num, *, precision="double"):
    return block_equations(law, slots, num, damping=slots.par("gamma"), precision=precision)


def _classify(raw: dict, points: dict):
    return classify_cycles(raw, points, critical_nu_f=1.0 / (2.0 + points["gamma"]))


DAMPED_BLOCK = Model(
    name="damped-block",
    title="one block with viscous damping γ (example model)",
    description="Ü = νt − U + 1 − Φ(U̇/ν_f) − γU̇; one slip cycle per point, as the single block",
    source="the single block of Vasconcelos, PRL 76, 4865 (1996), with a dashpot (docs/models.md)",
    labels=LAW,
    axes=(GAMMA, NU_F, NU),
    parameters=("nu", "nu_f", "forcing", "gamma"),
    fixed={"forcing": 1.0},
    state=SINGLE_BLOCK.state,
    events=STOP_EVENTS,
    outputs=OUTPUTS,
    statuses=SINGLE_BLOCK.statuses,
    equations=_equations,
    classify=_classify,
    hooks=Hooks(describe_label="bifurcation.laws:resolve_law", report="bifurcation.report.study:block_section"),
    units_note=BLOCK_UNITS,
)
