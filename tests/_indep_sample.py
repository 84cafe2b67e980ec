"""Which of the independent-reference cases (tests/test_indep_*.py) the suite runs.

Each reference is computed at test time in mpmath (40–50 digits), up to ~40 s per case: the sample the
slow suite runs (23 cases: the first case of each list and every ``step``-th one after it) took 248 s on
the 2-core development machine; the whole set (73) would add roughly three times that to README's test
command. Set ``BIFURCATION_INDEP=all`` to run every case:

    BIFURCATION_INDEP=all python -m pytest -m slow tests/test_indep_*.py
"""

from __future__ import annotations

import os

ALL = os.environ.get("BIFURCATION_INDEP", "") == "all"


def sample(cases, step: int) -> list:
    """``cases`` whole under BIFURCATION_INDEP=all, else every ``step``-th one from the first."""
    cases = list(cases)
    return cases if ALL else cases[::step]
