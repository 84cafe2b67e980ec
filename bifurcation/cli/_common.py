"""Shared CLI plumbing: one-line errors with exit status 2, JSON output, shared options."""

from __future__ import annotations

import json
import math
import sys

import click

from ..errors import InputError

__all__ = ["Group", "echo_json", "fail", "number"]


def fail(message: str) -> None:
    """Print one line to stderr and exit with status 2 (bad input), without a traceback."""
    click.echo(f"bifurcation: error: {message}", err=True)
    sys.exit(2)


class Group(click.Group):
    """A command group whose usage and input errors are one line and exit with status 2."""

    def main(self, args=None, prog_name=None, complete_var=None, standalone_mode=True, **extra):
        try:
            return super().main(args=args, prog_name=prog_name or "bifurcation",
                                complete_var=complete_var, standalone_mode=False, **extra)
        except click.exceptions.Exit as exc:
            sys.exit(exc.exit_code)
        except click.exceptions.Abort:
            click.echo("bifurcation: aborted", err=True)
            sys.exit(1)
        except click.UsageError as exc:
            fail(" ".join(exc.format_message().split()))
        except InputError as exc:
            fail(" ".join(str(exc).split()))
        except click.ClickException as exc:
            click.echo(f"bifurcation: error: {exc.format_message()}", err=True)
            sys.exit(exc.exit_code)


def _clean(obj):
    if isinstance(obj, float) and not math.isfinite(obj):
        return None
    if isinstance(obj, dict):
        return {k: _clean(v) for k, v in obj.items()}
    if isinstance(obj, (list, tuple)):
        return [_clean(v) for v in obj]
    return obj


def echo_json(obj) -> None:
    """Print ``obj`` as strict JSON (NaN and inf become null)."""
    click.echo(json.dumps(_clean(obj), indent=2, allow_nan=False))


def number(name: str, example: str = "0.5"):
    """A click callback that parses a float itself, so a bad value gets our one-line message."""

    def convert(ctx, param, value):
        if value is None:
            return None
        try:
            return float(value)
        except ValueError:
            raise click.BadParameter(f"{value!r} is not a number; give e.g. {example}",
                                     param_hint=name) from None

    return convert
