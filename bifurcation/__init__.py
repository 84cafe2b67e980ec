"""bifurcation: high-precision bifurcation studies of the spring-block earthquake model.

Vasconcelos, "First-order phase transition in a model for earthquakes", PRL 76, 4865 (1996).
"""

from .engine import FIELDS, LIMIT_FIELDS, LimitResult, SlipResult, Status, limit, slip
from .errors import InputError
from .laws import FrictionLaw, law_names, resolve_law

__all__ = sorted([
    "FIELDS", "FrictionLaw", "InputError", "LIMIT_FIELDS", "LimitResult", "SlipResult", "Status",
    "law_names", "limit", "resolve_law", "slip",
])
__version__ = "0.1.0"
