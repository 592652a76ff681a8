"""ISO VG viscosity grades by name (ISO 3448; docs/contact.md, "Lubricants by ISO VG grade").

ISO 3448 names an industrial oil's grade by its kinematic viscosity at 40 °C: grade VG n has
a midpoint of n mm²/s, within ±10 %. The film needs the dynamic viscosity, so a grade names

    μ = ν_40 · ρ = n · 1e-6 m²/s · :data:`GRADE_DENSITY`  (Pa·s, at 40 °C)

with one documented density for every grade, a mineral oil's at 40 °C. The number stands for
the oil at 40 °C and for nothing else: a joint running hotter or colder has another viscosity
(an ISO VG 46 mineral oil is about 0.02 Pa·s at 60 °C), which is given in Pa·s instead
(``viscosity = "0.02 Pa*s"``, ``--lubricant-viscosity``).
"""

from __future__ import annotations

import re

from jointplay.errors import ConfigError

#: The viscosity grades of ISO 3448: the midpoint kinematic viscosity at 40 °C, mm²/s.
ISO_VG_GRADES = (
    2, 3, 5, 7, 10, 15, 22, 32, 46, 68, 100, 150, 220, 320, 460, 680, 1000, 1500, 2200, 3200,
)  # fmt: skip
#: The density every grade's dynamic viscosity is taken with, kg/m³: a mineral oil at 40 °C
#: (about 0.86–0.88 g/cm³ for the light to middle grades; 15 °C densities are ~1 % higher).
GRADE_DENSITY = 870.0
#: The temperature a grade's viscosity stands for, °C (ISO 3448's reference temperature).
GRADE_TEMPERATURE_C = 40.0
#: ISO 3448's tolerance on a grade's kinematic viscosity about its midpoint.
GRADE_TOLERANCE = 0.10

_GRADE = re.compile(r"^\s*ISO\s*VG\s*(\S+)\s*$", re.IGNORECASE)
_REGIME_GRADE = re.compile(r"^\s*(oil|grease)\s+(ISO\s*VG.*)$", re.IGNORECASE)


def grade_viscosity(grade: int) -> float:
    """The dynamic viscosity of ISO VG ``grade`` at 40 °C, Pa·s (midpoint × :data:`GRADE_DENSITY`)."""
    return grade * 1e-6 * GRADE_DENSITY


def grade_words(grade: int) -> str:
    """``ISO VG 46 (0.040 Pa*s at 40 °C)``: the grade and the viscosity it stands for."""
    return f"ISO VG {grade} ({grade_viscosity(grade):#.2g} Pa*s at {GRADE_TEMPERATURE_C:g} °C)"


def _valid() -> str:
    return ", ".join(str(g) for g in ISO_VG_GRADES)


def parse_grade(text: object, where: str = "grade") -> int:
    """The grade number of ``text`` (``"ISO VG 46"``, ``"iso vg 46"``, ``"ISO VG46"``), or a
    ConfigError naming ``where`` and the valid grades."""
    if isinstance(text, bool) or not isinstance(text, str | int):
        raise ConfigError(f"{where} must be an ISO VG grade such as 'ISO VG 46', got {text!r}")
    match = _GRADE.match(text) if isinstance(text, str) else None
    number = match.group(1) if match else str(text).strip()
    try:
        grade = int(number)
    except ValueError:
        grade = -1
    if grade not in ISO_VG_GRADES:
        raise ConfigError(
            f"{where}: {text!r} is not an ISO 3448 viscosity grade; the grades are ISO VG "
            f"{_valid()} (e.g. 'ISO VG 46')"
        )
    return grade


def split_regime(text: str, where: str = "lubrication") -> tuple[str, int | None]:
    """``"oil ISO VG 46"`` → ``("oil", 46)``; a bare regime (``"oil"``, ``"dry"``) → ``(text,
    None)``. A grade after anything but ``oil`` or ``grease`` is left to the regime's check."""
    match = _REGIME_GRADE.match(text)
    if match is None:
        return text, None
    return match.group(1).lower(), parse_grade(match.group(2).strip(), where)
