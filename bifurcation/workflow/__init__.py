"""Workflows: TOML study files → validated, frozen ``Workflow`` objects (schema in ``spec``)."""

from .spec import NU_BOUNDS, NU_F_BOUNDS, Workflow, load_workflow, parse_workflow

__all__ = ["NU_BOUNDS", "NU_F_BOUNDS", "Workflow", "load_workflow", "parse_workflow"]
