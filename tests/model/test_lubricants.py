"""ISO VG grades by name (issue 39, item 3): a grade stands for its ISO 3448 midpoint
kinematic viscosity at 40 °C times the documented density; an unknown grade is one error
naming the valid grades."""

from __future__ import annotations

import pytest

from jointplay.errors import ConfigError
from jointplay.model.lubricants import (
    GRADE_DENSITY,
    ISO_VG_GRADES,
    grade_viscosity,
    grade_words,
    parse_grade,
    split_regime,
)
from jointplay.model.mechanism import Lubrication


def test_the_grades_are_iso_3448s() -> None:
    assert ISO_VG_GRADES == (
        2, 3, 5, 7, 10, 15, 22, 32, 46, 68, 100, 150, 220, 320, 460, 680, 1000, 1500, 2200, 3200,
    )  # fmt: skip


@pytest.mark.parametrize("grade", [2, 46, 68, 220, 3200])
def test_a_grade_is_its_kinematic_midpoint_times_the_density(grade: int) -> None:
    # ν_40 = grade mm²/s = grade·1e-6 m²/s; μ = ν ρ
    assert grade_viscosity(grade) == pytest.approx(grade * 1e-6 * GRADE_DENSITY, rel=1e-12)
    assert GRADE_DENSITY == 870.0


def test_vg_46_reads_0_040_pa_s_at_40_c() -> None:
    assert grade_viscosity(46) == pytest.approx(0.04002, rel=1e-12)
    assert grade_words(46) == "ISO VG 46 (0.040 Pa*s at 40 °C)"
    assert Lubrication("oil", grade=46).words() == "oil ISO VG 46 (0.040 Pa*s at 40 °C)"
    assert Lubrication("oil", grade=46).viscosity == grade_viscosity(46)
    assert Lubrication("grease", grade=220).words() == (
        "grease, base oil ISO VG 220 (0.19 Pa*s at 40 °C)"
    )


@pytest.mark.parametrize("text", ["ISO VG 46", "iso vg 46", "ISO VG46", " ISO  VG 46 ", "46", 46])
def test_the_grade_reads_as_written(text: str | int) -> None:
    assert parse_grade(text) == 46


def test_the_regime_may_carry_its_grade() -> None:
    assert split_regime("oil ISO VG 68") == ("oil", 68)
    assert split_regime("Grease iso vg 220") == ("grease", 220)
    assert split_regime("oil") == ("oil", None)
    assert split_regime("dry") == ("dry", None)


@pytest.mark.parametrize("text", ["ISO VG 45", "ISO VG", "VG 46", "46.0", 47, True, 0.04])
def test_an_unknown_grade_names_the_valid_ones(text: object) -> None:
    with pytest.raises(ConfigError) as caught:
        parse_grade(text, "lubrication.grade")
    message = str(caught.value)
    assert message.startswith("lubrication.grade")
    if not isinstance(text, bool | float):
        assert ", ".join(str(g) for g in ISO_VG_GRADES) in message


def test_a_grade_is_not_dry_and_not_beside_another_viscosity() -> None:
    with pytest.raises(ConfigError, match="a dry joint has no lubricant"):
        Lubrication("dry", grade=46)
    with pytest.raises(ConfigError, match="grade or its viscosity, not both"):
        Lubrication("oil", 0.05, grade=46)
    assert Lubrication("oil", grade_viscosity(46), grade=46).grade == 46  # the same: kept
