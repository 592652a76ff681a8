"""The one number format of jointplay's reports: significant digits, thousands separators.

Every table of a report writes its numbers through :func:`number`, so that a column never
mixes ``120.0`` with ``90`` or ``43`` with ``46.01``:

* a float shows :data:`DIGITS` significant digits, trailing zeros kept (``43.00`` beside
  ``46.01``): the digits say how precisely the number is known;
* from ``10**DIGITS`` on, a float is rounded to a whole number with thousands separators
  (``242,348``, ``56,410``): no digit of the integer part is hidden in an exponent;
* below ``10**-3`` or from ``10**9`` on, scientific notation with a real superscript
  (``3.670 × 10⁻⁵``);
* an integer (Python or NumPy) keeps every digit, with thousands separators (``1,662``);
* a missing value (``None``, NaN, ±inf) is an em dash, never ``nan``.

No physics here and nothing but the standard library, so every report module can use it.
"""

from __future__ import annotations

import math
import numbers
from typing import Any

#: Significant digits of a float in a report table.
DIGITS = 4
#: Shown for a missing or non-finite value.
MISSING = "—"
_SUPERSCRIPT = str.maketrans("-0123456789", "⁻⁰¹²³⁴⁵⁶⁷⁸⁹")


def number(value: Any, digits: int = DIGITS, *, signed: bool = False) -> str:
    """``value`` in the report's number format (see the module docstring).

    Args:
        value: a number (int, float, NumPy scalar), ``None`` or anything else (returned as
            ``str(value)``: text passes through unchanged).
        digits: significant digits of a float (>= 1).
        signed: prefix positive numbers with ``+`` (for changes and differences).
    """
    if value is None:
        return MISSING
    if isinstance(value, bool) or not isinstance(value, numbers.Number):
        return str(value)
    if isinstance(value, numbers.Integral):
        text = f"{int(value):,}"
        return f"+{text}" if signed and int(value) > 0 else text
    x = float(value)  # type: ignore[arg-type]
    if not math.isfinite(x):
        return MISSING
    if x == 0.0:
        return "0"
    magnitude = abs(x)
    if magnitude < 1e-3 or magnitude >= 1e9:
        mantissa, exponent = f"{x:.{digits - 1}e}".split("e")
        text = f"{mantissa} × 10{str(int(exponent)).translate(_SUPERSCRIPT)}"
    elif magnitude >= 10 ** (digits - 1):
        text = f"{x:,.0f}"
    else:
        decimals = digits - 1 - math.floor(math.log10(magnitude))
        text = f"{x:,.{max(decimals, 0)}f}"
        # rounding may carry into a new digit (9.9996 -> 10.000): one decimal too many then
        if len(text.replace("-", "").replace(",", "").replace(".", "").lstrip("0")) > digits:
            text = f"{x:,.{max(decimals - 1, 0)}f}"
    if text in ("-0", "-0.0"):
        text = text[1:]
    return f"+{text}" if signed and x > 0 else text


def percent(value: Any, digits: int = 3) -> str:
    """A change in percent: signed, ``digits`` significant digits, with the ``%`` sign."""
    text = number(value, digits, signed=True)
    return text if text == MISSING else f"{text} %"


def quantity(value: Any, unit: str, digits: int = DIGITS) -> str:
    """``value`` and its unit, separated by a (narrow) space: ``21.00 µm``."""
    text = number(value, digits)
    return text if text == MISSING or not unit else f"{text} {unit}"
