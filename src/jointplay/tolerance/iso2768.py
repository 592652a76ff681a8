"""ISO 2768-1:1989 general tolerances (identical to IS 2102 (Part 1):1993).

General tolerances apply to dimensions drawn without an individual tolerance, in one of four
classes: f (fine), m (medium), c (coarse), v (very coarse). The three tables of the standard are
kept here as data:

* Table 1 — permissible deviations for linear dimensions except broken edges, 0.5 … 4000 mm;
* Table 2 — permissible deviations for broken edges (external radii and chamfer heights);
* Table 3 — permissible deviations of angular dimensions, by the length of the shorter side.

A cell that the standard leaves empty ("—": class f over 2000 mm, class v up to 3 mm) raises
:class:`~jointplay.errors.StandardsError`, as does a nominal size below 0.5 mm, for which the
standard requires the deviation to be indicated next to the dimension. A size exactly on a
range boundary belongs to the lower range ("over 30 up to and including 120").

Sizes are SI (m) at the API and deviations are returned in m (linear) or rad (angular); the
results also offer mm and degrees, the units of the standard.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Literal

from jointplay.errors import StandardsError

__all__ = [
    "CLASS_NAMES",
    "GeneralTolerance",
    "angular_tolerance",
    "broken_edge_tolerance",
    "general_tolerance",
    "linear_tolerance",
    "parse_class",
]

Feature = Literal["linear", "broken edge", "angular"]

#: The four tolerance classes of ISO 2768-1 and their names.
CLASS_NAMES: Mapping[str, str] = MappingProxyType(
    {"f": "fine", "m": "medium", "c": "coarse", "v": "very coarse"}
)

#: ISO 2768-1:1989 Table 1 — range limits in mm: the first range is "0.5 up to and including
#: 3", the next "over 3 up to and including 6", …, the last "over 2000 up to and including 4000".
LINEAR_LIMITS_MM: tuple[float, ...] = (0.5, 3, 6, 30, 120, 400, 1000, 2000, 4000)

#: ISO 2768-1:1989 Table 1 — permissible deviations ± mm for linear dimensions, one value per
#: range of :data:`LINEAR_LIMITS_MM`; ``None`` is a cell the standard leaves empty.
LINEAR_DEVIATIONS_MM: Mapping[str, tuple[float | None, ...]] = MappingProxyType({
    #      0.5–3  >3–6  >6–30  >30–120  >120–400  >400–1000  >1000–2000  >2000–4000
    "f": (0.05, 0.05, 0.1, 0.15, 0.2, 0.3, 0.5, None),
    "m": (0.1, 0.1, 0.2, 0.3, 0.5, 0.8, 1.2, 2.0),
    "c": (0.2, 0.3, 0.5, 0.8, 1.2, 2.0, 3.0, 4.0),
    "v": (None, 0.5, 1.0, 1.5, 2.5, 4.0, 6.0, 8.0),
})  # fmt: skip

#: ISO 2768-1:1989 Table 2 — range limits in mm for broken edges (external radii and chamfer
#: heights): "0.5 up to and including 3", "over 3 up to and including 6", "over 6".
BROKEN_EDGE_LIMITS_MM: tuple[float, ...] = (0.5, 3, 6, math.inf)

#: ISO 2768-1:1989 Table 2 — permissible deviations ± mm for broken edges.
BROKEN_EDGE_DEVIATIONS_MM: Mapping[str, tuple[float, ...]] = MappingProxyType({
    #      0.5–3  >3–6  >6
    "f": (0.2, 0.5, 1.0),
    "m": (0.2, 0.5, 1.0),
    "c": (0.4, 1.0, 2.0),
    "v": (0.4, 1.0, 2.0),
})  # fmt: skip

#: ISO 2768-1:1989 Table 3 — ranges of the length of the shorter side of the angle, mm:
#: "up to 10", "over 10 up to 50", "over 50 up to 120", "over 120 up to 400", "over 400".
ANGULAR_LIMITS_MM: tuple[float, ...] = (0.0, 10, 50, 120, 400, math.inf)

#: ISO 2768-1:1989 Table 3 — permissible deviations of angular dimensions, ± arc minutes
#: (the standard writes them as ±1°, ±0°30′, …).
ANGULAR_DEVIATIONS_ARCMIN: Mapping[str, tuple[float, ...]] = MappingProxyType({
    #     ≤10  >10–50  >50–120  >120–400  >400
    "f": (60, 30, 20, 10, 5),
    "m": (60, 30, 20, 10, 5),
    "c": (90, 60, 30, 15, 10),
    "v": (180, 120, 60, 30, 20),
})  # fmt: skip


@dataclass(frozen=True)
class GeneralTolerance:
    """One permissible deviation of ISO 2768-1.

    Attributes:
        tolerance_class: ``"f"``, ``"m"``, ``"c"`` or ``"v"``.
        feature: ``"linear"`` (Table 1), ``"broken edge"`` (Table 2) or ``"angular"`` (Table 3).
        nominal_size: the nominal size, m (for angles: the length of the shorter side).
        deviation: the symmetric permissible deviation ±, m (linear, broken edge) or rad
            (angular).
        size_range: the range of the table the size falls in, e.g.
            ``"over 120 up to and including 400 mm"``.
    """

    tolerance_class: str
    feature: Feature
    nominal_size: float
    deviation: float
    size_range: str

    def __post_init__(self) -> None:
        owner = f"GeneralTolerance {self.tolerance_class!r}"
        if self.tolerance_class not in CLASS_NAMES:
            raise StandardsError(f"{owner}: class must be one of f, m, c, v")
        if self.feature not in ("linear", "broken edge", "angular"):
            raise StandardsError(f"{owner}: unknown feature {self.feature!r}")
        if not (math.isfinite(self.deviation) and self.deviation > 0.0):
            raise StandardsError(f"{owner}: deviation must be finite and > 0, got {self.deviation}")

    @property
    def class_name(self) -> str:
        """``"fine"``, ``"medium"``, ``"coarse"`` or ``"very coarse"``."""
        return CLASS_NAMES[self.tolerance_class]

    @property
    def nominal_size_mm(self) -> float:
        """Nominal size (or shorter side), mm."""
        return round(self.nominal_size * 1e3, 9)

    @property
    def deviation_mm(self) -> float:
        """Deviation ± in mm (linear and broken-edge features only)."""
        if self.feature == "angular":
            raise StandardsError(
                "an angular general tolerance has no deviation in mm; use deviation_deg"
            )
        return round(self.deviation * 1e3, 9)

    @property
    def deviation_arcmin(self) -> float:
        """Deviation ± in minutes of arc (angular feature only), as Table 3 states it."""
        if self.feature != "angular":
            raise StandardsError(f"a {self.feature} general tolerance has no deviation in degrees")
        return round(math.degrees(self.deviation) * 60.0, 9)

    @property
    def deviation_deg(self) -> float:
        """Deviation ± in degrees (angular feature only), e.g. 0.5 for ±0°30′."""
        return self.deviation_arcmin / 60.0

    @property
    def text(self) -> str:
        """The deviation as the standard writes it, e.g. ``"±1.2 mm"`` or ``"±0°30'"``."""
        if self.feature == "angular":
            degrees, minutes = divmod(round(self.deviation_arcmin), 60)
            return f"±{degrees}°{minutes}'" if minutes else f"±{degrees}°"
        return f"±{self.deviation_mm:g} mm"


def parse_class(tolerance_class: str) -> str:
    """Normalise a class given as a letter or a name (``"m"``, ``"M"``, ``"medium"``) to its letter.

    Raises:
        StandardsError: not one of the four classes.
    """
    if isinstance(tolerance_class, str):
        text = " ".join(tolerance_class.strip().lower().replace("-", " ").split())
        if text in CLASS_NAMES:
            return text
        for letter, name in CLASS_NAMES.items():
            if text == name:
                return letter
    raise StandardsError(
        f"unknown ISO 2768-1 tolerance class {tolerance_class!r}; the classes are "
        "f (fine), m (medium), c (coarse) and v (very coarse)"
    )


def linear_tolerance(tolerance_class: str, size: float) -> GeneralTolerance:
    """General tolerance of a linear dimension (ISO 2768-1:1989 Table 1).

    Args:
        tolerance_class: ``"f"``, ``"m"``, ``"c"`` or ``"v"`` (or its name).
        size: nominal size, m (0.5 mm ≤ size ≤ 4000 mm).

    Raises:
        StandardsError: unknown class, a size below 0.5 mm or above 4000 mm, or a cell the
            standard leaves empty.
    """
    letter = parse_class(tolerance_class)
    size_mm = _size_mm(size)
    if size_mm < LINEAR_LIMITS_MM[0]:
        raise StandardsError(
            f"ISO 2768-1 gives no general tolerance below 0.5 mm ({size_mm:g} mm): for nominal "
            "sizes below 0.5 mm the tolerance must be stated on the dimension itself"
        )
    if size_mm > LINEAR_LIMITS_MM[-1]:
        raise StandardsError(
            f"ISO 2768-1 Table 1 ends at 4000 mm; {size_mm:g} mm needs an individual tolerance"
        )
    index, size_range = _range(LINEAR_LIMITS_MM, size_mm, first_inclusive=True)
    value = LINEAR_DEVIATIONS_MM[letter][index]
    if value is None:
        others = [c for c, column in LINEAR_DEVIATIONS_MM.items() if column[index] is not None]
        raise StandardsError(
            f"ISO 2768-1 Table 1 leaves class {letter} ({CLASS_NAMES[letter]}) empty for "
            f"{size_mm:g} mm ({size_range}); use class {_either(others)} or state the "
            "tolerance on the dimension"
        )
    return GeneralTolerance(letter, "linear", size, value / 1e3, size_range)


def general_tolerance(tolerance_class: str, size: float) -> float:
    """The ± general tolerance of a linear dimension, m (ISO 2768-1:1989 Table 1).

    Example:
        ``general_tolerance("c", 0.2705)`` is 0.0012 (±1.2 mm).

    Raises:
        StandardsError: see :func:`linear_tolerance`.
    """
    return linear_tolerance(tolerance_class, size).deviation


def broken_edge_tolerance(tolerance_class: str, size: float) -> GeneralTolerance:
    """General tolerance of a broken edge, i.e. external radius or chamfer height (Table 2).

    Args:
        tolerance_class: ``"f"``, ``"m"``, ``"c"`` or ``"v"`` (or its name).
        size: radius or chamfer height, m (≥ 0.5 mm).

    Raises:
        StandardsError: unknown class or a size below 0.5 mm.
    """
    letter = parse_class(tolerance_class)
    size_mm = _size_mm(size)
    if size_mm < BROKEN_EDGE_LIMITS_MM[0]:
        raise StandardsError(
            f"ISO 2768-1 gives no broken-edge tolerance below 0.5 mm ({size_mm:g} mm): for "
            "nominal sizes below 0.5 mm the tolerance must be stated on the dimension itself"
        )
    index, size_range = _range(BROKEN_EDGE_LIMITS_MM, size_mm, first_inclusive=True)
    value = BROKEN_EDGE_DEVIATIONS_MM[letter][index]
    return GeneralTolerance(letter, "broken edge", size, value / 1e3, size_range)


def angular_tolerance(tolerance_class: str, shorter_side: float) -> GeneralTolerance:
    """General tolerance of an angular dimension (ISO 2768-1:1989 Table 3).

    Args:
        tolerance_class: ``"f"``, ``"m"``, ``"c"`` or ``"v"`` (or its name).
        shorter_side: length of the shorter side of the angle, m (> 0).

    Returns:
        The tolerance; ``deviation`` is in rad, ``deviation_deg`` in degrees.

    Raises:
        StandardsError: unknown class or a non-positive length.
    """
    letter = parse_class(tolerance_class)
    size_mm = _size_mm(shorter_side)
    index, size_range = _range(ANGULAR_LIMITS_MM, size_mm, first_inclusive=False)
    arcmin = ANGULAR_DEVIATIONS_ARCMIN[letter][index]
    return GeneralTolerance(
        letter, "angular", shorter_side, math.radians(arcmin / 60.0), size_range
    )


def _either(letters: list[str]) -> str:
    return letters[0] if len(letters) == 1 else f"{', '.join(letters[:-1])} or {letters[-1]}"


def _size_mm(size: float) -> float:
    """Validate a length in m and return it in mm, snapped to 1 pm so boundaries stay exact."""
    if isinstance(size, bool) or not isinstance(size, int | float) or not math.isfinite(size):
        raise StandardsError(f"nominal size must be a finite length in metres, got {size!r}")
    size_mm = round(float(size) * 1e3, 9)
    if size_mm <= 0.0:
        raise StandardsError(f"nominal size must be > 0 mm, got {size_mm:g} mm")
    return size_mm


def _range(limits: tuple[float, ...], size_mm: float, *, first_inclusive: bool) -> tuple[int, str]:
    """Index and text of the range ``limits[i] < size ≤ limits[i + 1]`` that holds ``size_mm``.

    With ``first_inclusive`` the first range also holds its lower limit (Table 1 and 2 start
    at "0.5 up to and including 3"). Callers have checked the size lies within the limits.
    """
    for index in range(len(limits) - 1):
        lower, upper = limits[index], limits[index + 1]
        if size_mm <= upper:
            if math.isinf(upper):
                return index, f"over {lower:g} mm"
            if index == 0 and first_inclusive:
                return index, f"{lower:g} up to and including {upper:g} mm"
            if lower == 0.0:
                return index, f"up to and including {upper:g} mm"
            return index, f"over {lower:g} up to and including {upper:g} mm"
    raise LookupError(f"{size_mm} mm is beyond the last range (internal: callers check the range)")
