"""The range of golog++ numbers (docs/semantics.md, "Numbers").

A number is a whole number (exact) or a 64-bit float. Every number, whole or not, lies within
±MAX_NUMBER, the largest finite 64-bit float (about 1.8e308): whole numbers stay exact and can
always be written as text and mixed with floats, and no number is infinite or NaN. A result
outside that range is a run-time error (R0001), a literal outside it a syntax error (E0004),
and a number from outside (a scenario, a world, a robot) outside it is rejected where it comes
in.
"""

from __future__ import annotations

import math
import sys

MAX_NUMBER = sys.float_info.max
# The largest whole number: the largest float, exactly (309 digits).
MAX_WHOLE = int(MAX_NUMBER)
# How the range reads in messages.
RANGE_TEXT = "numbers range from -1.8e308 to 1.8e308"


def in_range(v: int | float) -> bool:
    """True for a finite float and for a whole number within ±MAX_WHOLE."""
    if isinstance(v, float):
        return math.isfinite(v)
    return -MAX_WHOLE <= v <= MAX_WHOLE


def literal_value(text: str) -> int | float | None:
    """The value of a number literal (digits, an optional fraction and exponent), or None when
    it is beyond the range of numbers. A literal too small to tell from 0 is 0.0."""
    if text.isdigit():
        # More digits than MAX_WHOLE has (leading zeros aside) cannot be in range; checked
        # before int(), which refuses very long digit strings.
        digits = text.lstrip("0") or "0"
        if len(digits) > len(str(MAX_WHOLE)):
            return None
        whole = int(digits)
        return whole if whole <= MAX_WHOLE else None
    value = float(text)
    return value if math.isfinite(value) else None


def describe(v: int | float) -> str:
    """A number for a message about its range: never thousands of digits."""
    if isinstance(v, int) and not isinstance(v, bool) and not in_range(v):
        if v.bit_length() > 14_000:  # beyond what str() writes (sys.get_int_max_str_digits)
            return "a whole number of thousands of digits"
        return f"a whole number of {len(str(abs(v)))} digits"
    return repr(v) if isinstance(v, float) else str(v)


# The longest time a data file (a scenario, a world) may name, in seconds: about 31 years. Up to
# it a 64-bit float still resolves the microseconds the trace writes.
MAX_SECONDS = 1e9


def bound_text(x: float) -> str:
    """A bound of a range for a message: `0.01`, `10000`, `1e9`."""
    return f"{x:g}".replace("e+0", "e").replace("e+", "e")
