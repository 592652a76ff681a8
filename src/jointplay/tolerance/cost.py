"""Relative manufacturing cost of a tolerance scheme: cost–tolerance models from the literature.

A cost–tolerance model gives the cost of producing one feature to a tolerance band T (m).
Two classic forms, surveyed by Chase, Greenwood, Loosli & Hauglund (*Manufacturing Review*
3:49–59, 1990) and by Dong, Hu & Xue (*J. Eng. Ind.* 116:199–206, 1994):

* ``"reciprocal-power"`` (Sutherland & Roth, *J. Eng. Ind.* 97:283–286, 1975; Chase &
  Greenwood 1988): ``C(T) = a + b (T_ref/T)^k``;
* ``"exponential"`` (Speckhart, *J. Eng. Ind.* 94:447–453, 1972):
  ``C(T) = a + b exp(−m (T − T_ref)/T_ref)``.

Both fall monotonically as T grows, so a looser tolerance never costs more. The defaults
(a = 1, b = 1, k = 1, T_ref = 0.1 mm: a feature held to 0.1 mm costs twice a free one) are a
neutral reciprocal choice inside the range those surveys report (k ≈ 0.5–2); they give
*relative* costs to rank schemes, not prices.

A scheme's cost is the sum over its features: every template length at the width of its ISO
2768-1 band (2 × the Table 1 deviation), and every pin joint at the width of its hole's and
its shaft's ISO 286 IT grade at the joint's diameter. A table (e.g. ``[cost]`` in a TOML file
of the design study) may replace the model's parameters, or give the cost of an IT grade
(``[cost.it]``, e.g. ``IT7 = 2.5``) or of an ISO 2768 class (``[cost.iso2768]``) per feature
outright.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass, field
from typing import Any, ClassVar, Literal

from jointplay.errors import ConfigError
from jointplay.tolerance import iso286, iso2768

__all__ = [
    "COST_MODELS",
    "CostModel",
    "fit_cost",
    "length_class_cost",
]

ModelName = Literal["reciprocal-power", "exponential"]
#: The cost–tolerance forms.
COST_MODELS: tuple[str, ...] = ("reciprocal-power", "exponential")


@dataclass(frozen=True)
class CostModel:
    """A cost–tolerance model with optional fixed costs per IT grade and ISO 2768 class.

    Attributes:
        model: ``"reciprocal-power"`` or ``"exponential"`` (module docstring).
        a: fixed cost of a feature, whatever its tolerance (relative units, >= 0).
        b: tolerance-dependent cost at T_ref (> 0).
        k: exponent of the reciprocal-power form, or rate m of the exponential (> 0).
        reference: T_ref, m (> 0).
        it_cost: cost of one feature of an IT grade, e.g. ``{"IT7": 2.5}``; replaces the
            formula for that grade.
        class_cost: cost of one length of an ISO 2768-1 class, e.g. ``{"m": 1.2}``.
    """

    name: ClassVar[str] = "cost-tolerance"

    model: ModelName = "reciprocal-power"
    a: float = 1.0
    b: float = 1.0
    k: float = 1.0
    reference: float = 1e-4
    it_cost: Mapping[str, float] = field(default_factory=dict)
    class_cost: Mapping[str, float] = field(default_factory=dict)

    def __post_init__(self) -> None:
        if self.model not in COST_MODELS:
            raise ConfigError(
                f"CostModel: model must be one of {', '.join(COST_MODELS)}, got {self.model!r}"
            )
        for name, allow_zero in (("a", True), ("b", False), ("k", False), ("reference", False)):
            value = getattr(self, name)
            if not (math.isfinite(value) and (value >= 0 if allow_zero else value > 0)):
                raise ConfigError(
                    f"CostModel: {name} must be finite and {'>= 0' if allow_zero else '> 0'}, "
                    f"got {value!r}"
                )
        grades = {}
        for key, value in self.it_cost.items():
            text = str(key).upper().removeprefix("IT")
            if not text.isdigit():
                raise ConfigError(f"CostModel: it_cost key {key!r} must be an IT grade like IT7")
            grades[f"IT{int(text)}"] = _positive_cost(f"it_cost[{key!r}]", value)
        classes = {}
        for key, value in self.class_cost.items():
            letter = iso2768.parse_class(str(key))
            classes[letter] = _positive_cost(f"class_cost[{key!r}]", value)
        object.__setattr__(self, "it_cost", grades)
        object.__setattr__(self, "class_cost", classes)

    def feature_cost(self, tolerance: float) -> float:
        """Cost of one feature held to a band of ``tolerance`` m (> 0)."""
        if not (math.isfinite(tolerance) and tolerance > 0):
            raise ConfigError(f"CostModel: a tolerance band must be > 0 m, got {tolerance!r}")
        ratio = tolerance / self.reference
        if self.model == "reciprocal-power":
            return self.a + self.b * ratio ** (-self.k)
        return self.a + self.b * math.exp(-self.k * (ratio - 1.0))

    def grade_cost(self, grade: str | int, size: float) -> float:
        """Cost of one feature of IT grade ``grade`` at nominal size ``size`` (m)."""
        key = f"IT{str(grade).upper().removeprefix('IT')}"
        if key in self.it_cost:
            return self.it_cost[key]
        return self.feature_cost(iso286.standard_tolerance(grade, size))

    def length_cost(self, tolerance_class: str, length: float) -> float:
        """Cost of one length of ``length`` m in ISO 2768-1 class ``tolerance_class``."""
        letter = iso2768.parse_class(tolerance_class)
        if letter in self.class_cost:
            return self.class_cost[letter]
        return self.feature_cost(2.0 * iso2768.general_tolerance(letter, abs(length)))

    def describe(self) -> dict[str, Any]:
        return {
            "model": self.model,
            "a": self.a,
            "b": self.b,
            "k": self.k,
            "reference_m": self.reference,
            "it_cost": dict(self.it_cost),
            "class_cost": dict(self.class_cost),
            "source": (
                "Sutherland & Roth 1975 (reciprocal power) / Speckhart 1972 (exponential), "
                "surveyed by Chase et al. 1990 and Dong, Hu & Xue 1994"
            ),
        }

    @classmethod
    def from_table(cls, table: Mapping[str, Any]) -> CostModel:
        """A model from a config table: ``model``, ``a``, ``b``, ``k``, ``reference`` (a length
        with its unit, e.g. ``"0.1 mm"``; a bare number is refused, as everywhere in config
        files), ``it`` and ``iso2768`` sub-tables.

        Raises:
            ConfigError: an unknown key or a bad value, naming it.
        """
        from jointplay.units import parse_quantity

        known = {"model", "a", "b", "k", "reference", "it", "iso2768"}
        unknown = sorted(set(table) - known)
        if unknown:
            raise ConfigError(
                f"[cost]: unknown key(s) {unknown}; expected {', '.join(sorted(known))}"
            )
        options: dict[str, Any] = {}
        if "model" in table:
            options["model"] = str(table["model"])
        for key in ("a", "b", "k"):
            if key in table:
                options[key] = _number(f"[cost] {key}", table[key])
        if "reference" in table:
            options["reference"] = parse_quantity(table["reference"], "m", field="[cost] reference")
        for key, target in (("it", "it_cost"), ("iso2768", "class_cost")):
            if key in table:
                if not isinstance(table[key], Mapping):
                    raise ConfigError(f"[cost.{key}] must be a table of costs")
                options[target] = {
                    k: _number(f"[cost.{key}] {k}", v) for k, v in table[key].items()
                }
        return cls(**options)


def _number(field: str, value: Any) -> float:
    if isinstance(value, bool) or not isinstance(value, int | float):
        raise ConfigError(f"{field} must be a number, got {value!r}")
    return float(value)


def _positive_cost(field: str, value: Any) -> float:
    number = _number(f"CostModel: {field}", value)
    if not (math.isfinite(number) and number >= 0):
        raise ConfigError(f"CostModel: {field} must be >= 0, got {value!r}")
    return number


def fit_cost(designation: str, diameter: float, model: CostModel | None = None) -> float:
    """Relative cost of one pin joint in fit ``designation`` at ``diameter`` (m): the hole's
    and the shaft's IT grade."""
    model = model or CostModel()
    result = iso286.fit(designation, diameter)
    return model.grade_cost(result.hole.grade, diameter) + model.grade_cost(
        result.shaft.grade, diameter
    )


def length_class_cost(
    tolerance_class: str, lengths: Mapping[str, float], model: CostModel | None = None
) -> float:
    """Relative cost of holding every length in ``lengths`` (m) to an ISO 2768-1 class
    (lengths under 0.5 mm, outside the standard, are free)."""
    model = model or CostModel()
    return sum(
        model.length_cost(tolerance_class, value)
        for value in lengths.values()
        if abs(value) >= 0.5e-3
    )
