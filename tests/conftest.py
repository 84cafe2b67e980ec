"""Fixtures shared between test modules."""

import functools

import pytest

from bifurcation.theory.reference import carlson_langer_mp


@pytest.fixture(scope="session")
def carlson_langer_reference():
    """``carlson_langer_mp(nu, 0.4, dps=30)`` memoised per ν: ~2 s a point, wanted by two modules."""
    return functools.cache(lambda nu: carlson_langer_mp(nu, 0.4, dps=30))
