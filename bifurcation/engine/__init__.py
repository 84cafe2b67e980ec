"""The engine: slip cycles at finite ν and the direct ν → 0 limit."""

from .cycle import slip
from .limit import LIMIT_FIELDS, LimitResult, limit
from .result import FIELDS, SlipResult, Status

__all__ = ["FIELDS", "LIMIT_FIELDS", "LimitResult", "SlipResult", "Status", "limit", "slip"]
