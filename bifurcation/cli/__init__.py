"""The ``bifurcation`` command line: a thin layer over the package.

Subcommands live in one small module each group of concerns (engine, service, analysis); heavy
imports happen inside the commands so ``bifurcation --help`` is instant.
"""

from __future__ import annotations

import click

from ._common import Group

__all__ = ["cli", "main"]


@click.group(cls=Group, context_settings={"help_option_names": ["-h", "--help"]})
@click.version_option(package_name="bifurcation")
def cli() -> None:
    """High-precision bifurcation studies of the spring-block earthquake model."""


def _register() -> None:
    import importlib

    from ..models import get_model, model_names

    from ._study import study

    for name in ("_engine", "_service", "_analysis", "_verify", "_status", "_study"):
        for command in importlib.import_module(f"{__name__}.{name}").COMMANDS:
            cli.add_command(command)
    for name in model_names():   # a model's own commands: its declaration's commands and study hooks
        for command in get_model(name).hook("commands") or ():
            cli.add_command(command)
        if (command := get_model(name).hook("study")) is not None:
            study.add_command(command, name=name)


_register()


def main() -> None:
    """Console-script entry point: native libraries' prints go to stderr, never into stdout's JSON."""
    from ._common import native_stdout_to_stderr

    with native_stdout_to_stderr():
        cli.main()
