"""The engine: slip cycles at finite ν and the direct ν → 0 limit."""

from .cycle import slip
from .result import FIELDS, SlipResult, Status

__all__ = ["FIELDS", "SlipResult", "Status", "slip"]
