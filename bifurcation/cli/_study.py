"""``bifurcation study MODEL WORKFLOW``: a model's own study, beyond what ``submit`` computes.

The group names no model: each model that declares a ``study`` hook (a click command) is added under
its own name when the CLI starts (``cli._register``).
"""

from __future__ import annotations

import re

import click

from ._common import Group, examples

__all__ = ["COMMANDS", "study"]


class _Studies(Group):
    """The group's examples are those of the models' study commands added to it."""

    def format_epilog(self, ctx, formatter) -> None:
        lines = [line for command in self.commands.values()
                 for line in re.findall(r"^\s*\$ (bifurcation .+)$", command.epilog or "", re.M)]
        if lines:
            formatter.write_paragraph()
            with formatter.indentation():
                formatter.write_text(examples(*lines))


@click.group("study", cls=_Studies)
def study() -> None:
    """Run a model's own study from its workflow: `bifurcation study MODEL WORKFLOW` (the models with one
    are listed below)."""


COMMANDS = [study]
