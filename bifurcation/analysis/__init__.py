"""Analysis of stored results: Δ(ν → 0) extrapolation, the recurrence-time expansion, the claims table.

Data flow: store (xarray Dataset, dims law × nu_f × nu) → ``extrapolate_delta`` / ``fit_period`` →
``claims_table`` → ``bifurcation.report``.
"""

from ._data import (FALLBACK_GRID, Series, coordinate_values, cycles_along_nu, fallback_grid, find_stores,
                    load_stores, series_along_nu, series_along_nu_f, slip_dataset)
from .claims import CLAIM_KEYS, Claim, claims_table
from .extrapolate import ExtrapolationResult, ModelRow, critical_epsilon, extrapolate_delta, paper_value
from .period_fit import PeriodFit, Term, expansion_terms, fit_period

__all__ = ["CLAIM_KEYS", "Claim", "ExtrapolationResult", "FALLBACK_GRID", "ModelRow", "PeriodFit", "Series",
           "Term", "claims_table", "coordinate_values", "critical_epsilon", "cycles_along_nu",
           "expansion_terms", "extrapolate_delta", "fallback_grid", "find_stores", "fit_period",
           "load_stores", "paper_value", "series_along_nu", "series_along_nu_f", "slip_dataset"]
