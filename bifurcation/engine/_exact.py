"""Inputs read at the precision of the run: a verification mode (``precision="quad"``) parses a decimal
the user wrote (``"0.03"``, the CLI's text, a ``Decimal``, an mpmath number) directly into heyoka's
real128, not through the nearest double first (whose rounding, 1e-17 relative, the dynamics amplify:
a chain started from −0.03 read in double agreed with a 50-digit reference only to 7e-16 after five
events). A Python float is a binary number already and is taken exactly as it is.
"""

from __future__ import annotations

from decimal import Decimal
from fractions import Fraction

__all__ = ["Text", "at_precision", "decimal_text"]


class Text(float):
    """A float that remembers the decimal text it was parsed from (the CLI's numbers)."""

    text: str

    def __new__(cls, text: str):
        # Python's float() also reads '1_0e-10' and non-ASCII digits ('１'): not numbers a user typed on purpose
        if "_" in str(text) or not str(text).isascii():
            raise ValueError(f"{text!r}: write the number in ASCII digits without '_'")
        value = super().__new__(cls, text)
        value.text = str(text).strip()
        if value in (float("inf"), float("-inf")) and "inf" not in value.text.lower():   # '1e400': not inf
            raise ValueError(f"{text!r}: overflows to infinity")
        if value == 0.0:
            if any(c in "123456789" for c in value.text.lower().split("e")[0]):   # '1e-400': not silently 0
                raise ValueError(f"{text!r}: underflows to 0")
            if value.text.startswith("-"):   # '-0.0' is 0 for every input; printed and stored as 0, not '-0'
                value = super().__new__(cls, "0")
                value.text = "0"
        return value


def decimal_text(x) -> str | None:
    """The decimal text of ``x`` when it was given as one (str, ``Text``, ``Decimal``, mpmath), else None."""
    if isinstance(x, Text):
        return x.text
    if isinstance(x, str):
        return x.strip()
    if isinstance(x, Decimal):
        return str(x)
    if type(x).__module__.startswith("mpmath"):
        import mpmath

        return mpmath.nstr(x, 50, strip_zeros=False)
    return None


def at_precision(x, dtype):
    """``x`` in ``dtype`` (numpy float64 or heyoka real128), from its decimal text where it has one."""
    if dtype is float or getattr(dtype, "__name__", "") == "float64":
        return dtype(float(x))
    if isinstance(x, Fraction):
        return dtype(x.numerator) / dtype(x.denominator)
    text = decimal_text(x)
    if text is not None:
        return dtype(text)
    return x if isinstance(x, dtype) else dtype(float(x))
