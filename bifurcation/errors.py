"""Errors raised for bad user input.

Every input error names the argument, shows the value and says how to fix it, so the CLI can print it
as one line (exit status 2) and tests can match the text.
"""

from __future__ import annotations

__all__ = ["InputError"]


class InputError(ValueError):
    """Bad user input: ``argument``, the offending ``value`` and the ``fix``."""

    def __init__(self, argument: str, value: object, problem: str, fix: str) -> None:
        self.argument = argument
        self.value = value
        self.problem = problem
        self.fix = fix
        super().__init__(f"{argument}={value!r}: {problem}; {fix}")
