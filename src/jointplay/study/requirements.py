"""Design requirements: a small grammar, parsed once at the edge.

Grammar (spaces optional around the comparison and the ``@``)::

    requirement := RESPONSE COMPARISON VALUE [UNIT] ["@" CONFIDENCE ["%"]]
    COMPARISON  := "<=" | "<" | ">=" | ">"
    RESPONSE    := a response name of the design study, e.g. rocker_speed_error,
                   joint_force, F_A_peak, contact_pressure, wear_rate, life
    UNIT        := any unit convertible to the response's SI unit ("N", "kN", "MPa",
                   "um/h", "h", ...); "%" for dimensionless responses (1 % = 0.01)
    CONFIDENCE  := the share of parts that must meet the requirement, in % (default:
                   the study's confidence level)

Examples: ``"rocker_speed_error <= 1 %"``, ``"joint_force <= 150 N @99.73"``,
``"life >= 2000 h"``.

**Life quantiles** (issue 43): ``"B10 >= 2000 h"`` — generally ``Bp >= VALUE UNIT`` with p in
(0, 100) — is met when at most p % of the population fails before VALUE, i.e. when the yield
of "functional life ≥ VALUE" is at least (100 − p) %. It parses to a :class:`Requirement` on
the response :data:`FUNCTIONAL_LIFE` (s) with ``quantile`` p (a fraction) and ``confidence``
1 − p; it takes no ``@`` (p sets the share) and only ``>=``/``>`` (a B_p is a lower bound
on the life). A malformed requirement is a one-line :class:`ConfigError` that says
what was expected.

**Units are required.** A bare number is refused with a suggestion in the response's usual
unit (:data:`USUAL_UNITS`): ``rocker_speed_error <= 3`` → "3 %", ``life >= 200`` → "200 h",
``contact_pressure <= 500`` → "500 MPa", since reading it as SI (300 %, 200 s, 500 Pa) would
silently answer another question. A confidence level (``@`` here, the confidence on the
command line: :func:`parse_confidence`) is always in %, the sign optional; a level of 1 or
less without the sign (``@0.9973``) is refused as a likely fraction, suggesting "99.73 %".
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

__all__ = [
    "COMPARISONS",
    "FUNCTIONAL_LIFE",
    "USUAL_UNITS",
    "Requirement",
    "parse_confidence",
    "parse_requirement",
]

#: The response a life-quantile requirement (``"B10 >= 2000 h"``) bounds: each sample's
#: functional life, s, censored at the requirement's hours (:mod:`jointplay.study.life`).
FUNCTIONAL_LIFE = "functional_life"

Comparison = Literal["<=", "<", ">=", ">"]
#: The comparisons a requirement may use.
COMPARISONS: tuple[str, ...] = ("<=", "<", ">=", ">")

_PATTERN = re.compile(
    r"^\s*(?P<name>[A-Za-z_][A-Za-z0-9_]*)\s*(?P<op><=|>=|<|>)\s*(?P<value>[^@]+?)\s*"
    r"(?:@\s*(?P<confidence>[^%\s]+\s*%?)\s*)?$"
)
#: The unit a designer writes for each SI unit of a response (display and suggestions).
USUAL_UNITS: Mapping[str, str] = {
    "1": "%",
    "Pa": "MPa",
    "m/s": "um/h",
    "s": "h",
    "m": "um",
    "rad/s^2": "rad/s^2",
}

#: ``Bp`` then a comparison: a life-quantile requirement (the number checked apart).
_QUANTILE = re.compile(r"^\s*B(?P<p>[0-9.eE+-]*)\s*(?=[<>=!])")

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
        quantile: a life-quantile requirement (``"B10 >= 2000 h"``): p as a fraction (0.10),
            the response :data:`FUNCTIONAL_LIFE` and ``confidence`` 1 − p; else ``None``.
    """

    response: str
    comparison: Comparison
    limit: float
    unit: str
    confidence: float | None = None
    text: str = ""
    quantile: float | None = None

    def __post_init__(self) -> None:
        if self.comparison not in COMPARISONS:
            raise ConfigError(f"requirement: comparison must be one of {COMPARISONS}")
        if not math.isfinite(self.limit):
            raise ConfigError(f"requirement {self.text!r}: the limit must be finite")
        if self.confidence is not None and not 0.0 < self.confidence < 1.0:
            raise ConfigError(f"requirement {self.text!r}: confidence must lie between 0 and 100 %")
        if self.quantile is not None and not 0.0 < self.quantile < 1.0:
            raise ConfigError(f"requirement {self.text!r}: p of B_p must lie between 0 and 100")

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
            **({"quantile": self.quantile} if self.quantile is not None else {}),
        }


def parse_requirement(text: str, units: Mapping[str, str]) -> Requirement:
    """Parse ``text`` against the known responses ``units`` (name → SI unit; ``"1"``:
    dimensionless).

    Raises:
        ConfigError: one line naming what was expected.
    """
    from jointplay.units import parse_quantity

    if _QUANTILE.match(text or ""):
        return _parse_quantile(text)
    _check_comparisons(text or "")
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
    if _is_number(value):
        usual = USUAL_UNITS.get(unit, unit)
        hint = f"'{name} {op} {value} {usual}'"
        if unit == "1" and abs(float(value)) < 1.0:
            hint += f" (or '{float(value) * 100:g} %' if {value} is a fraction)"
        raise ConfigError(
            f"{field}: the limit needs its unit ({name} is in {_unit_words(unit)}); did you "
            f"mean {hint}?"
        )
    if unit == "1":
        number = value.removesuffix("%").strip()
        if not value.endswith("%") or not _is_number(number):
            raise ConfigError(
                f"{field}: {name} is dimensionless; expected a number with %, e.g. "
                f"'{name} {op} 3 %', got {value!r}"
            )
        limit = float(number) / 100.0
    else:
        limit = parse_quantity(value, unit, field=field)
    confidence = None
    if match["confidence"] is not None:
        confidence = parse_confidence(match["confidence"], f"{field}: the confidence after '@'")
    return Requirement(name, op, float(limit), unit, confidence, text.strip())  # type: ignore[arg-type]


def _parse_quantile(text: str) -> Requirement:
    """``"Bp >= VALUE UNIT"`` → a requirement on :data:`FUNCTIONAL_LIFE` with its yield target
    1 − p (module docstring).

    Raises:
        ConfigError: one line: p outside (0, 100), an upper bound, an ``@``, a bare number or
            a limit that is not a positive time.
    """
    from jointplay.units import parse_quantity

    field = f"requirement {text!r}"
    example = "e.g. 'B10 >= 2000 h' (at most 10 % of the mechanisms fail before 2000 h)"
    head = _QUANTILE.match(text)
    assert head is not None
    p = head["p"]
    if not _is_number(p) or not 0.0 < float(p) < 100.0:
        raise ConfigError(
            f"{field}: B_p needs p between 0 and 100 (the % of the population failed), got "
            f"B{p}; {example}"
        )
    name = f"B{p}"
    _check_comparisons(text)
    match = _PATTERN.match("B " + text[head.end() :])
    if match is None:
        raise ConfigError(f"{field}: expected Bp >= VALUE UNIT, {example}")
    op, value = match["op"], match["value"].strip()
    if op in ("<=", "<"):
        raise ConfigError(
            f"{field}: {name} is a lower bound on the life (at most {p} % fail before it); "
            f"write '{name} >= {value}'"
        )
    if match["confidence"] is not None:
        raise ConfigError(
            f"{field}: {name} sets its own share ({100 - float(p):g} % must outlive the hours); "
            f"drop the '@{match['confidence']}'"
        )
    if _is_number(value):
        raise ConfigError(
            f"{field}: the limit needs its unit ({name} is a life); did you mean "
            f"'{name} {op} {value} h'?"
        )
    limit = parse_quantity(value, "s", field=field)
    if not limit > 0.0:
        raise ConfigError(f"{field}: the hours must be > 0, got {value!r}; {example}")
    share = float(p) / 100.0
    comparison: Comparison = ">" if op == ">" else ">="
    return Requirement(
        FUNCTIONAL_LIFE, comparison, float(limit), "s", 1.0 - share, text.strip(), quantile=share
    )


def parse_confidence(text: str, field: str = "confidence") -> float:
    """A confidence level in % (the sign optional) → a fraction in (0, 1).

    ``"99.73"`` and ``"99.73 %"`` give 0.9973. A bare number of 1 or less (``"0.9973"``) is
    refused as a likely fraction, with the suggestion "99.73 %"; write ``"0.9973 %"`` to mean
    that level.

    Raises:
        ConfigError: one line naming ``field``.
    """
    value = str(text).strip()
    number = value.removesuffix("%").strip()
    if not _is_number(number):
        raise ConfigError(f"{field}: expected a confidence in %, e.g. '99.73 %', got {value!r}")
    percent = float(number)
    if not 0.0 < percent < 100.0:
        raise ConfigError(f"{field} must lie between 0 and 100 %, got {value!r}")
    if percent <= 1.0 and not value.endswith("%"):
        raise ConfigError(
            f"{field} is in %: {value} reads as {value} %; did you mean '{percent * 100:g} %'? "
            f"(write '{value} %' if you mean {value} %)"
        )
    return percent / 100.0


#: A run of comparison characters: each must be one of :data:`COMPARISONS`, and there is one.
_COMPARISON_RUN = re.compile(r"[<>=!]+")


def _check_comparisons(text: str) -> None:
    """Token by token: a response name, then exactly one comparison, then the value.

    A second comparison (``"joint_force <= <= 150 N"``, ``">= <="``, ``"< ="``, or one after
    the value) would leave which side is bounded to a guess, so it is refused, naming it.

    Raises:
        ConfigError: one line naming the stray comparison and the form to write.
    """
    name = re.match(r"\s*[A-Za-z_][A-Za-z0-9_]*\s*", text)
    runs = list(_COMPARISON_RUN.finditer(text))
    if name is None or not runs:
        return  # the pattern's own message: expected RESPONSE <=|<|>=|> VALUE ...
    first = runs[0]
    if first[0] not in COMPARISONS:
        raise ConfigError(
            f"requirement {text!r}: {first[0]!r} (character {first.start() + 1}) is not a "
            f"comparison; write one of <=, <, >=, >, e.g. 'joint_force <= 150 N'"
        )
    if len(runs) > 1:
        second = runs[1]
        raise ConfigError(
            f"requirement {text!r}: one comparison only, found {first[0]!r} and then "
            f"{second[0]!r} (character {second.start() + 1}); write RESPONSE <=|<|>=|> VALUE "
            f"UNIT, e.g. 'joint_force <= 150 N'"
        )


def _is_number(text: str) -> bool:
    try:
        return math.isfinite(float(text))
    except ValueError:
        return False


def _unit_words(unit: str) -> str:
    return "%, dimensionless" if unit == "1" else f"{unit} (SI)"
