"""Which of the independent-reference cases (tests/test_indep_*.py) the suite runs.

Each reference is computed at test time in mpmath (40–50 digits), 1–2 CPU minutes per case: the whole
set (≈ 70 cases) would make README's test command take over an hour on 2 cores. By default the slow
suite runs a spread sample (the first case of each list and every ``step``-th one after it); set
``BIFURCATION_INDEP=all`` to run every case:

    BIFURCATION_INDEP=all python -m pytest -m slow tests/test_indep_*.py
"""

from __future__ import annotations

import os

ALL = os.environ.get("BIFURCATION_INDEP", "") == "all"


def sample(cases, step: int) -> list:
    """``cases`` whole under BIFURCATION_INDEP=all, else every ``step``-th one from the first."""
    cases = list(cases)
    return cases if ALL else cases[::step]
