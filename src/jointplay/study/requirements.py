"""Design requirements: a small grammar, parsed once at the edge.

Grammar (spaces optional around the comparison and the ``@``)::

    requirement := RESPONSE COMPARISON VALUE [UNIT] ["@" CONFIDENCE ["%"]]
    COMPARISON  := "<=" | "<" | ">=" | ">"
    RESPONSE    := a response name of the design study, e.g. rocker_speed_error,
                   joint_force, F_A_peak, contact_pressure, wear_rate, life
    UNIT        := any unit convertible to the response's SI unit ("N", "kN", "MPa",
                   "um/h", "h", ...); "%" for dimensionless responses (1 % = 0.01)
    CONFIDENCE  := the share of samples that must meet the requirement, in % (default:
                   the study's confidence level)

Examples: ``"rocker_speed_error <= 1 %"``, ``"joint_force <= 150 N @99.73"``,
``"life >= 2000 h"``. A malformed requirement is a one-line :class:`ConfigError` that says
what was expected.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from dataclasses import dataclass
from typing import Any, Literal

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError

__all__ = ["COMPARISONS", "Requirement", "parse_requirement"]

Comparison = Literal["<=", "<", ">=", ">"]
#: The comparisons a requirement may use.
COMPARISONS: tuple[str, ...] = ("<=", "<", ">=", ">")

_PATTERN = re.compile(
    r"^\s*(?P<name>[A-Za-z_][A-Za-z0-9_]*)\s*(?P<op><=|>=|<|>)\s*(?P<value>[^@]+?)\s*"
    r"(?:@\s*(?P<confidence>[^%\s]+)\s*%?\s*)?$"
)
_EXPECTED = (
    "expected RESPONSE <=|<|>=|> VALUE [UNIT] [@CONFIDENCE], e.g. 'joint_force <= 150 N @99.73'"
)


@dataclass(frozen=True)
class Requirement:
    """One requirement on a response.

    Attributes:
        response: response name.
        comparison: ``"<="``, ``"<"``, ``">="`` or ``">"``.
        limit: the limit, SI (dimensionless responses as fractions).
        unit: the response's SI unit (``"1"``: dimensionless).
        confidence: share of samples that must meet it, in (0, 1), or ``None`` (the study's).
        text: the requirement as written.
    """

    response: str
    comparison: Comparison
    limit: float
    unit: str
    confidence: float | None = None
    text: str = ""

    def __post_init__(self) -> None:
        if self.comparison not in COMPARISONS:
            raise ConfigError(f"requirement: comparison must be one of {COMPARISONS}")
        if not math.isfinite(self.limit):
            raise ConfigError(f"requirement {self.text!r}: the limit must be finite")
        if self.confidence is not None and not 0.0 < self.confidence < 1.0:
            raise ConfigError(f"requirement {self.text!r}: confidence must lie between 0 and 100 %")

    @property
    def upper(self) -> bool:
        """The requirement bounds the response from above."""
        return self.comparison in ("<=", "<")

    def met(self, values: NDArray[np.float64]) -> NDArray[np.bool_]:
        """Per sample: the value meets the requirement (NaN never does)."""
        values = np.asarray(values, dtype=float)
        with np.errstate(invalid="ignore"):
            if self.comparison == "<=":
                return values <= self.limit
            if self.comparison == "<":
                return values < self.limit
            if self.comparison == ">=":
                return values >= self.limit
            return values > self.limit

    def describe(self) -> dict[str, Any]:
        return {
            "text": self.text,
            "response": self.response,
            "comparison": self.comparison,
            "limit": self.limit,
            "unit": self.unit,
            "confidence": self.confidence,
        }


def parse_requirement(text: str, units: Mapping[str, str]) -> Requirement:
    """Parse ``text`` against the known responses ``units`` (name → SI unit; ``"1"``:
    dimensionless).

    Raises:
        ConfigError: one line naming what was expected.
    """
    from jointplay.units import parse_quantity

    match = _PATTERN.match(text or "")
    if match is None:
        raise ConfigError(f"requirement {text!r}: {_EXPECTED}")
    name, op, value = match["name"], match["op"], match["value"].strip()
    if name not in units:
        raise ConfigError(
            f"requirement {text!r}: unknown response {name!r}; expected one of "
            f"{', '.join(sorted(units))}"
        )
    unit = units[name]
    field = f"requirement {text!r}"
    if unit == "1":
        percent = value.endswith("%")
        number = value.removesuffix("%").strip()
        try:
            magnitude = float(number)
        except ValueError:
            raise ConfigError(
                f"{field}: {name} is dimensionless; expected a number, optionally with %, "
                f"got {value!r}"
            ) from None
        limit = magnitude / 100.0 if percent else magnitude
    else:
        try:
            limit = float(value)  # a bare number: SI
        except ValueError:
            limit = parse_quantity(value, unit, field=field)
    confidence = None
    if match["confidence"] is not None:
        try:
            percent = float(match["confidence"])
        except ValueError:
            raise ConfigError(
                f"{field}: expected a confidence in % after '@', e.g. '@99.73'"
            ) from None
        if not 0.0 < percent < 100.0:
            raise ConfigError(f"{field}: the confidence after '@' must lie between 0 and 100 %")
        confidence = percent / 100.0
    return Requirement(name, op, float(limit), unit, confidence, text.strip())  # type: ignore[arg-type]
