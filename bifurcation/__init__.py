"""bifurcation: high-precision bifurcation studies of the spring-block earthquake model.

Vasconcelos, "First-order phase transition in a model for earthquakes", PRL 76, 4865 (1996).

Public names are imported on first use (PEP 562), so ``bifurcation --help`` does not load heyoka,
dask or matplotlib.
"""

from __future__ import annotations

from ._lazy import lazy_names

__version__ = "0.1.0"

_LAZY = {
    "FIELDS": "engine",
    "FrictionLaw": "laws",
    "InputError": "errors",
    "LIMIT_FIELDS": "engine",
    "LimitResult": "engine",
    "SlipResult": "engine",
    "Status": "engine",
    "chain": "models.chain",
    "law_names": "laws",
    "limit": "engine",
    "open_store": "store",
    "read_catalog": "store",
    "resolve_law": "laws",
    "slip": "engine",
    "submit": "run",
}

__all__ = ["FIELDS", "FrictionLaw", "InputError", "LIMIT_FIELDS", "LimitResult", "SlipResult", "Status", "chain",
           "law_names", "limit", "open_store", "read_catalog", "resolve_law", "slip", "submit"]

__getattr__, __dir__ = lazy_names(__name__, globals(), _LAZY)
