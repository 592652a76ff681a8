"""ISO 286-1/-2:2010 limits and fits: published values, the standard's special cases, errors.

Published limit deviations come from the ISO 286-2 tables (and, where noted, from Technical
Corrigendum 1:2006 to ISO 286-2:1988, whose corrected values ISO 286-2:2010 carries). Each one is
cross-checked in :func:`test_published_value_is_consistent` against two independent readings of
ISO 286-1:2010: the standard tolerance IT of Table 1 and the fundamental deviation of Tables 2 to 5
(with Δ of Table 3 where the rule needs it). Values are µm; sizes mm. Comparisons are exact after
rounding to 1e-6 µm: the standard's values are decimal multiples of 0.05 µm and no arithmetic
beyond sums and halving is involved.
"""

from __future__ import annotations

import itertools
import math

import pytest
from hypothesis import given
from hypothesis import strategies as st

from jointplay.errors import StandardsError
from jointplay.tolerance import iso286
from jointplay.tolerance.iso286 import (
    DELTA_UM,
    SHAFT_LOWER_DEVIATIONS_UM,
    SHAFT_UPPER_DEVIATIONS_UM,
    STANDARD_TOLERANCES_IT01_IT0_UM,
    STANDARD_TOLERANCES_UM,
    Fit,
    ToleranceClass,
    fit,
    parse_designation,
    size_range_mm,
    standard_tolerance,
    tolerance_class,
)

MM = 1e-3


def um(value_m: float) -> float:
    return round(value_m * 1e6, 6)


# ---------------------------------------------------------------------------------------------
# Standard tolerances (ISO 286-1:2010 Table 1 and Table A.1)
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("grade", "size_mm", "expected_um"),
    [
        ("IT7", 10, 15),  # docs/contact-laws.md §6c (band over 6 up to 10 mm)
        ("IT8", 10, 22),  # §6c
        ("IT6", 10, 9),  # §6c
        ("IT7", 25, 21),
        ("IT11", 100, 220),
        ("IT14", 10, 360),  # "at 10 mm IT14 allows 0.36 mm" (IT grade article citing ISO 286)
        ("IT14", 100, 870),  # "at 100 mm IT14 allows 0.87 mm"
        ("IT1", 1, 0.8),
        ("IT01", 2, 0.3),
        ("IT0", 2, 0.5),
        ("IT0", 500, 6),
        ("IT16", 500, 4000),
        ("IT5", 600, 32),
        ("IT5", 3000, 96),
        ("IT18", 3150, 33000),
        (7, 10, 15),  # grades may be given as numbers
        ("6", 10, 9),
        ("01", 10, 0.4),
        (0, 10, 0.6),
    ],
)
def test_standard_tolerance_published(grade: str | int, size_mm: float, expected_um: float) -> None:
    assert um(standard_tolerance(grade, size_mm * MM)) == expected_um


def test_standard_tolerance_band_boundary_belongs_to_lower_band() -> None:
    # 10 mm is "over 6 up to and including 10"; just above it is "over 10 up to 18".
    assert um(standard_tolerance("IT7", 10 * MM)) == 15
    assert um(standard_tolerance("IT7", 10.001 * MM)) == 18
    assert size_range_mm(10 * MM) == (6.0, 10.0)
    assert size_range_mm(10.001 * MM) == (10.0, 18.0)
    assert size_range_mm(2 * MM) == (0.0, 3.0)
    # metres that are not exact binary fractions still land on the boundary
    assert size_range_mm(0.12) == (80.0, 120.0)


@pytest.mark.parametrize(
    ("grade", "size_mm", "message"),
    [
        ("IT19", 10, "IT01, IT0, IT1"),
        ("IT00", 10, "IT01, IT0, IT1"),
        ("ITx", 10, "IT01, IT0, IT1"),
        (True, 10, "unknown standard tolerance grade"),
        ("IT01", 600, "up to 500 mm"),
        ("IT0", 500.001, "up to 500 mm"),
        ("IT14", 1, "shall not be used for nominal sizes up to 1 mm"),
        ("IT18", 0.5, "shall not be used for nominal sizes up to 1 mm"),
        ("IT7", 3150.001, "up to 3150 mm"),
        ("IT7", 0, "> 0 mm"),
        ("IT7", -5, "> 0 mm"),
    ],
)
def test_standard_tolerance_errors(grade: str | int, size_mm: float, message: str) -> None:
    with pytest.raises(StandardsError, match=message):
        standard_tolerance(grade, size_mm * MM)


def test_standard_tolerance_rejects_non_finite_size() -> None:
    with pytest.raises(StandardsError, match="finite"):
        standard_tolerance("IT7", math.nan)


def test_it14_is_fine_just_above_1mm() -> None:
    assert um(standard_tolerance("IT14", 1.001 * MM)) == 250


# ---------------------------------------------------------------------------------------------
# Consistency of the transcribed tables (catches transcription slips)
# ---------------------------------------------------------------------------------------------
def test_table1_rows_increase_with_grade_and_columns_with_size() -> None:
    previous: tuple[float, ...] | None = None
    previous_limit = 0.0
    for limit, row in STANDARD_TOLERANCES_UM:
        assert limit > previous_limit
        assert len(row) == 18
        assert all(a < b for a, b in itertools.pairwise(row)), limit
        if previous is not None:
            assert all(a <= b for a, b in zip(previous, row, strict=True)), limit
        previous, previous_limit = row, limit
    assert previous_limit == 3150


def test_it01_and_it0_are_finer_than_it1() -> None:
    for (limit, (it01, it0)), (limit1, row) in zip(
        STANDARD_TOLERANCES_IT01_IT0_UM, STANDARD_TOLERANCES_UM, strict=False
    ):
        assert limit == limit1
        assert it01 < it0 < row[0]


def test_delta_is_the_difference_of_adjacent_grades() -> None:
    """Table 3's Δ columns equal ITn − IT(n−1) of Table 1 over 3 up to 500 mm (two tables agree)."""
    rows = dict(STANDARD_TOLERANCES_UM)
    for limit, deltas in DELTA_UM:
        if limit <= 3:
            assert deltas == (0, 0, 0, 0, 0, 0)  # Δ is zero up to 3 mm by definition
            continue
        it = rows[limit]
        for n, delta in zip(range(3, 9), deltas, strict=True):
            assert delta == pytest.approx(it[n - 1] - it[n - 2]), (limit, n)


def _defined_value(column: tuple[tuple[float, float | None], ...], size_mm: float) -> float | None:
    lower = 0.0
    for upper, value in column:
        if lower < size_mm <= upper:
            return value
        lower = upper
    return None


def _probe_sizes() -> list[float]:
    limits: set[float] = set()
    for columns in (SHAFT_UPPER_DEVIATIONS_UM, SHAFT_LOWER_DEVIATIONS_UM):
        for column in columns.values():
            limits.update(limit for limit, _ in column)
    return sorted(limits)


def test_fundamental_deviations_are_ordered_by_letter_at_every_size() -> None:
    """Away from the zero line the letters follow the alphabet at every tabulated size."""
    order = [
        *("a", "b", "c", "cd", "d", "e", "ef", "f", "fg", "g", "h"),
        *("m", "n", "p", "r", "s", "t", "u", "v", "x", "y", "z", "za", "zb", "zc"),
    ]
    for size in _probe_sizes():
        values = []
        for letter in order:
            column = SHAFT_UPPER_DEVIATIONS_UM.get(letter) or SHAFT_LOWER_DEVIATIONS_UM[letter]
            value = _defined_value(column, size)
            if value is not None:
                values.append((letter, value))
        for (a, va), (b, vb) in itertools.pairwise(values):
            assert va < vb, f"{a}={va} not below {b}={vb} at {size} mm"


def test_fundamental_deviations_grow_with_size() -> None:
    """Each letter's distance from the zero line never shrinks as the size grows."""
    for columns in (SHAFT_UPPER_DEVIATIONS_UM, SHAFT_LOWER_DEVIATIONS_UM):
        for letter, column in columns.items():
            values = [abs(v) for _, v in column if v is not None]
            assert all(a <= b for a, b in itertools.pairwise(values)), letter
            limits = [limit for limit, _ in column]
            assert limits == sorted(set(limits)), letter


# ---------------------------------------------------------------------------------------------
# Published limit deviations (ISO 286-2), each with its ISO 286-1 derivation
# ---------------------------------------------------------------------------------------------
# (class, size mm, upper µm, lower µm, IT µm from Table 1, fundamental deviation µm from
#  Tables 2–5; for K, M, N ≤ IT8 and P…ZC ≤ IT7 over 3 mm it includes Δ of Table 3)
PUBLISHED = [
    # --- holes A … H: EI = −es (Table 4 mirrored, Table 2) ---
    ("H8", 10, 22, 0, 22, 0),  # docs/contact-laws.md §6c (H8/f7 row at 10 mm)
    ("H7", 10, 15, 0, 15, 0),  # §6c (torqyx 10 mm row)
    ("H7", 25, 21, 0, 21, 0),
    ("H7", 50, 25, 0, 25, 0),
    ("H11", 100, 220, 0, 220, 0),
    ("H7", 600, 70, 0, 70, 0),  # over 500 up to 630
    ("A11", 25, 430, 300, 130, 300),
    ("A13", 350, 2090, 1200, 890, 1200),  # ISO 286-2:1988/Cor.1:2006, Table 2 (corrected value)
    ("B11", 25, 290, 160, 130, 160),
    ("C11", 25, 240, 110, 130, 110),
    ("D10", 25, 149, 65, 84, 65),
    ("E9", 25, 92, 40, 52, 40),
    ("E8", 100, 126, 72, 54, 72),  # Cor.1:2006, Table 3 (corrected value)
    ("F7", 25, 41, 20, 21, 20),
    ("G7", 10, 20, 5, 15, 5),
    # --- holes J: ES from Table 2 ---
    ("J6", 10, 5, -4, 9, 5),
    ("J7", 25, 12, -9, 21, 12),
    ("J8", 10, 12, -10, 22, 12),
    # --- holes K, M, N up to IT8: ES = −ei + Δ (Table 2/3) ---
    ("K6", 10, 2, -7, 9, 2),  # −1 + Δ6 (3)
    ("K7", 25, 6, -15, 21, 6),  # −2 + Δ7 (8), the worked example of Table 3
    ("K7", 120, 10, -25, 35, 10),  # −3 + Δ7 (13)
    ("K7", 6, 3, -9, 12, 3),  # boundary: 6 mm is in "over 3 up to 6": −1 + 4
    ("K7", 3, 0, -10, 10, 0),  # up to 3 mm: Δ = 0
    ("M6", 50, -4, -20, 16, -4),  # −9 + Δ6 (5)
    ("M6", 300, -9, -41, 32, -9),  # special case of Table 2 (−20 + 9 would give −11)
    ("M7", 10, 0, -15, 15, 0),  # −6 + Δ7 (6)
    ("N7", 10, -4, -19, 15, -4),  # −10 + Δ7 (6)
    ("N7", 25, -7, -28, 21, -7),  # −15 + Δ7 (8)
    ("N7", 3, -4, -14, 10, -4),  # up to 3 mm: −4
    # --- N above IT8: ES = 0 over 3 mm, −4 up to 3 mm (keyway widths, N9) ---
    ("N9", 10, 0, -36, 36, 0),
    ("N9", 3, -4, -29, 25, -4),
    # --- holes P … ZC: ES = −ei + Δ up to IT7, ES = −ei above ---
    ("P7", 30, -14, -35, 21, -14),  # −22 + Δ7 (8), the worked example for P7 18–30
    ("P9", 6, -12, -42, 30, -12),  # keyway widths, P9
    ("R7", 50, -25, -50, 25, -25),  # −34 + Δ7 (9)
    ("R7", 100, -38, -73, 35, -38),  # −51 + Δ7 (13)
    ("R10", 25, -28, -112, 84, -28),  # Cor.1:2006, Table 11 (corrected value); no Δ above IT7
    ("S7", 50, -34, -59, 25, -34),  # −43 + Δ7 (9)
    ("S7", 25, -27, -48, 21, -27),  # −35 + Δ7 (8)
    ("T7", 25, -33, -54, 21, -33),  # −41 + Δ7 (8), T starts over 24 mm
    ("U7", 10, -22, -37, 15, -22),  # −28 + Δ7 (6)
    ("U7", 20, -33, -54, 21, -33),  # −41 + Δ7 (8), sub-range 18–24
    ("U7", 25, -40, -61, 21, -40),  # −48 + Δ7 (8), sub-range 24–30
    # --- above 500 mm: no Δ ---
    ("K7", 600, 0, -70, 70, 0),
    ("M7", 600, -26, -96, 70, -26),
    ("N7", 600, -44, -114, 70, -44),
    ("P7", 600, -78, -148, 70, -78),
    # --- shafts a … h: es from Table 4 ---
    ("g7", 10, -5, -20, 15, -5),  # §6c
    ("g6", 10, -5, -14, 9, -5),  # §6c
    ("f7", 25, -20, -41, 21, -20),
    ("f9", 300, -56, -186, 130, -56),  # Cor.1:2006, Table 20 (corrected value)
    ("h6", 25, 0, -13, 13, 0),
    ("h7", 50, 0, -25, 25, 0),
    ("e8", 25, -40, -73, 33, -40),
    ("d9", 25, -65, -117, 52, -65),
    ("c11", 10, -80, -170, 90, -80),
    ("a11", 25, -300, -430, 130, -300),
    # --- shafts j: ei from Table 4 ---
    ("j5", 10, 4, -2, 6, -2),
    ("j6", 25, 9, -4, 13, -4),
    ("j7", 50, 15, -10, 25, -10),
    # --- shafts k … u: ei from Table 5 ---
    ("k6", 10, 10, 1, 9, 1),
    ("k6", 25, 15, 2, 13, 2),
    ("k6", 50, 18, 2, 16, 2),
    ("k6", 120, 25, 3, 22, 3),
    ("m6", 25, 21, 8, 13, 8),
    ("m6", 600, 70, 26, 44, 26),
    ("n6", 25, 28, 15, 13, 15),
    ("p6", 25, 35, 22, 13, 22),
    ("r6", 50, 50, 34, 16, 34),
    ("s6", 20, 48, 35, 13, 35),
    ("s6", 50, 59, 43, 16, 43),
    ("u6", 25, 61, 48, 13, 48),
]

_LOWER_IS_FUNDAMENTAL = set("ABCDEFGH") | {"CD", "EF", "FG"} | set("jkmnprstuvxyz")
_LOWER_IS_FUNDAMENTAL |= {"za", "zb", "zc"}


def _letters(designation: str) -> str:
    return designation.rstrip("0123456789")


@pytest.mark.parametrize(
    ("designation", "size_mm", "upper", "lower", "it", "fundamental"),
    PUBLISHED,
    ids=[f"{d}@{s}mm" for d, s, *_ in PUBLISHED],
)
def test_published_limit_deviations(
    designation: str, size_mm: float, upper: float, lower: float, it: float, fundamental: float
) -> None:
    result = tolerance_class(designation, size_mm * MM)
    assert (result.upper_um, result.lower_um) == (upper, lower)


@pytest.mark.parametrize(
    ("designation", "size_mm", "upper", "lower", "it", "fundamental"),
    PUBLISHED,
    ids=[f"{d}@{s}mm" for d, s, *_ in PUBLISHED],
)
def test_published_value_is_consistent(
    designation: str, size_mm: float, upper: float, lower: float, it: float, fundamental: float
) -> None:
    """Second derivation: IT from Table 1 and the fundamental deviation give the published pair."""
    grade = designation[len(_letters(designation)) :]
    assert um(standard_tolerance(grade, size_mm * MM)) == it
    assert upper - lower == it
    side = lower if _letters(designation) in _LOWER_IS_FUNDAMENTAL else upper
    assert side == fundamental


def test_at_least_forty_published_values() -> None:
    assert len(PUBLISHED) >= 40


@pytest.mark.parametrize(
    ("designation", "size_mm", "half_um"),
    [
        ("JS7", 25, 10),  # IT7 = 21 is odd: rounded down to 20 (footnote, Tables 2/4) → ±10
        ("js7", 25, 10),
        ("JS7", 100, 17),  # IT7 = 35 → 34 → ±17
        ("JS9", 15, 21),  # IT9 = 43 → 42 → ±21
        ("js11", 25, 65),  # IT11 = 130, even: ±65
        ("js6", 25, 6.5),  # grade 6 is outside the rounding rule: ±13/2
        ("JS6", 10, 4.5),  # ±9/2
        ("js12", 25, 105),  # IT12 = 210
        ("JS9", 10, 18),  # IT9 = 36
    ],
)
def test_js_is_symmetric_with_rounding_rule(
    designation: str, size_mm: float, half_um: float
) -> None:
    result = tolerance_class(designation, size_mm * MM)
    assert (result.upper_um, result.lower_um) == (half_um, -half_um)


def test_js_rounding_can_be_switched_off() -> None:
    result = tolerance_class("JS7", 25 * MM, round_js=False)
    assert (result.upper_um, result.lower_um) == (10.5, -10.5)


# ---------------------------------------------------------------------------------------------
# Range boundaries and the standard's special cases
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("designation", "size_mm", "upper", "lower"),
    [
        ("H7", 10, 15, 0),  # 10 mm: over 6 up to 10
        ("H7", 10.001, 18, 0),  # over 10 up to 18
        ("g6", 3, -2, -8),  # up to 3 mm
        ("g6", 3.001, -4, -12),
        ("K7", 120, 10, -25),  # over 80 up to 120: −3 + 13
        ("K7", 120.001, 12, -28),  # over 120 up to 180: −3 + 15, IT7 = 40
        ("u6", 24, 54, 41),  # sub-range 18–24 of Table 5
        ("u6", 24.001, 61, 48),  # sub-range 24–30
        ("H7", 500, 63, 0),
        ("H7", 500.001, 70, 0),
        ("P7", 500, -45, -108),  # −68 + Δ7 (23): Δ still applies at 500 mm
        ("P7", 500.001, -78, -148),  # no Δ above 500 mm
    ],
)
def test_band_boundaries_belong_to_the_lower_band(
    designation: str, size_mm: float, upper: float, lower: float
) -> None:
    result = tolerance_class(designation, size_mm * MM)
    assert (result.upper_um, result.lower_um) == (upper, lower)


def test_size_in_metres_that_is_not_a_binary_fraction_is_on_the_boundary() -> None:
    # 0.12 m * 1000 is 120.00000000000001 in floating point; it must still be "up to 120".
    assert tolerance_class("K7", 0.12).upper_um == 10


@pytest.mark.parametrize(
    ("designation", "size_mm", "upper", "lower"),
    [
        ("K4", 5, 0.5, -3.5),  # −1 + Δ4 (1.5): half-µm Δ
        ("K9", 2, 0, -25),  # K above IT8 exists up to 3 mm with ES = 0
        ("M9", 10, -6, -42),  # M above IT8 over 3 mm: ES = −m, no Δ
        ("N9", 1.5, -4, -29),  # N above IT8 is allowed just above 1 mm
        ("N11", 600, -44, -484),  # over 500 mm N is −n for every grade
        ("a9", 1.001, -270, -295),  # A/a are allowed just above 1 mm
        ("H14", 1.5, 250, 0),
        ("cd8", 10, -56, -78),  # CD/cd are tabulated up to 10 mm
        ("CD8", 10, 78, 56),
        ("j8", 3, 8, -6),  # j8 only up to 3 mm
        ("t6", 24.001, 54, 41),  # t starts over 24 mm
        ("h01", 2, 0, -0.3),
        ("K2", 2, 0, -1.2),  # up to 3 mm no Δ is needed
        ("k4", 10, 5, 1),  # k for IT4 … IT7
        ("k8", 10, 22, 0),  # k above IT7: ei = 0
        ("k3", 10, 2.5, 0),  # k up to IT3: ei = 0
        ("zc10", 10, 155, 97),
        ("ZC10", 10, -97, -155),  # above IT7: ES = −ei
        ("ZC7", 10, -91, -106),  # up to IT7: −97 + Δ7 (6)
    ],
)
def test_special_cases(designation: str, size_mm: float, upper: float, lower: float) -> None:
    result = tolerance_class(designation, size_mm * MM)
    assert (result.upper_um, result.lower_um) == (upper, lower)


@pytest.mark.parametrize(
    ("designation", "size_mm", "message"),
    [
        ("K9", 10, "K above IT8 only for nominal sizes up to 3 mm"),
        ("K9", 600, "K above IT8 only"),
        ("N9", 1, "N above IT8 shall not be used for nominal sizes up to 1 mm"),
        ("a11", 1, "A, B, a and b shall not be used"),
        ("B11", 0.5, "A, B, a and b shall not be used"),
        ("H14", 1, "IT14 to IT18 shall not be used"),
        ("h18", 0.8, "IT14 to IT18 shall not be used"),
        ("a11", 600, "up to and including 500 mm"),
        ("x6", 600, "up to and including 500 mm"),
        ("CD8", 12, "tabulated only up to 10 mm"),
        ("fg6", 10.5, "tabulated only up to 10 mm"),
        ("T7", 24, "over 24 up to and including 3150 mm"),
        ("v6", 14, "over 14 up to and including 500 mm"),
        ("Y7", 18, "over 18 up to and including 500 mm"),
        ("j4", 10, "j5, j6, j7"),
        ("j8", 5, "up to and including 3 mm"),
        ("j6", 600, "up to and including 500 mm"),
        ("J9", 10, "J6, J7 and J8"),
        ("J5", 10, "J6, J7 and J8"),
        ("J7", 600, "up to and including 500 mm"),
        ("K2", 10, "Δ, which ISO 286-1:2010 Table 3 gives only for IT3 to IT8"),
        ("P01", 10, "Table 3 gives only for IT3 to IT8"),
        ("H01", 600, "up to 500 mm"),
        ("H7", 3150.001, "up to 3150 mm"),
        ("H7", 0, "> 0 mm"),
        ("H7", -10, "> 0 mm"),
    ],
)
def test_classes_the_standard_does_not_define(
    designation: str, size_mm: float, message: str
) -> None:
    with pytest.raises(StandardsError, match=message):
        tolerance_class(designation, size_mm * MM)


# ---------------------------------------------------------------------------------------------
# Designations
# ---------------------------------------------------------------------------------------------
@pytest.mark.parametrize(
    ("text", "expected"),
    [
        ("H8", ("H", "8", "hole")),
        ("g7", ("g", "7", "shaft")),
        ("JS7", ("JS", "7", "hole")),
        ("js6", ("js", "6", "shaft")),
        ("ZC10", ("ZC", "10", "hole")),
        (" h6 ", ("h", "6", "shaft")),
        ("H 7", ("H", "7", "hole")),
        ("h01", ("h", "01", "shaft")),
        ("H0", ("H", "0", "hole")),
    ],
)
def test_parse_designation(text: str, expected: tuple[str, str, str]) -> None:
    assert parse_designation(text) == expected


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("I7", "no fundamental deviation 'I'; holes use A B C CD"),
        ("l6", "no fundamental deviation 'l'; shafts use a b c cd"),
        ("W7", "no fundamental deviation"),
        ("ZD7", "no fundamental deviation"),
        ("H19", "no standard tolerance grade IT19; the grades are IT01, IT0, IT1"),
        ("H00", "no standard tolerance grade IT00"),
        ("Js7", "upper case for a hole \\(JS7\\) or all in lower case for a shaft \\(js7\\)"),
        ("H", "expected fundamental-deviation letters"),
        ("7", "expected fundamental-deviation letters"),
        ("", "expected fundamental-deviation letters"),
        ("H7.5", "expected fundamental-deviation letters"),
    ],
)
def test_parse_designation_errors(text: str, message: str) -> None:
    with pytest.raises(StandardsError, match=message):
        parse_designation(text)


def test_tolerance_class_result() -> None:
    result = tolerance_class(" k6 ", 25 * MM)
    assert result.designation == "k6"
    assert result.kind == "shaft"
    assert (result.letter, result.grade) == ("k", "6")
    assert result.upper == pytest.approx(15e-6, rel=1e-12)
    assert result.lower == pytest.approx(2e-6, rel=1e-12)
    assert result.tolerance_um == 13
    assert result.max_size == pytest.approx(25.015e-3, rel=1e-12)
    assert result.min_size == pytest.approx(25.002e-3, rel=1e-12)
    hole = tolerance_class("H7", 25 * MM)
    assert hole.kind == "hole"
    assert math.copysign(1.0, hole.lower) == 1.0  # EI = −0 is stored as +0


def test_tolerance_class_validates_its_fields() -> None:
    with pytest.raises(StandardsError, match="upper deviation"):
        ToleranceClass("H7", "hole", upper=-1e-6, lower=1e-6, nominal_size=0.01)
    with pytest.raises(StandardsError, match="kind"):
        ToleranceClass("H7", "pin", upper=1e-6, lower=0.0, nominal_size=0.01)  # type: ignore[arg-type]


# ---------------------------------------------------------------------------------------------
# Fits
# ---------------------------------------------------------------------------------------------
def test_h8_g7_at_10mm_matches_reference() -> None:
    """docs/contact-laws.md §6c: diametral clearance 5 … 42 µm, mean 23.5; radial 2.5 … 21, 11.75."""
    result = fit("H8/g7", 10 * MM)
    assert result.designation == "H8/g7"
    assert result.fit_type == "clearance"
    assert (result.clearance_min_um, result.clearance_max_um, result.clearance_mean_um) == (
        5,
        42,
        23.5,
    )
    rel = 1e-12  # metres are the µm values divided by 1e6; only representation error remains
    assert result.clearance_min == pytest.approx(5e-6, rel=rel)
    assert result.clearance_max == pytest.approx(42e-6, rel=rel)
    assert result.clearance_mean == pytest.approx(23.5e-6, rel=rel)
    assert result.radial_clearance_min == pytest.approx(2.5e-6, rel=rel)
    assert result.radial_clearance_max == pytest.approx(21e-6, rel=rel)
    assert result.radial_clearance_mean == pytest.approx(11.75e-6, rel=rel)
    assert result.nominal_size == 10 * MM


def test_h8_g7_just_above_10mm_uses_the_next_band() -> None:
    # §6c: "if Ø10 were put in the 10–18 band: H8 0/+27, g7 −6/−24 ⇒ 6 … 51 µm"
    result = fit("H8/g7", 10.5 * MM)
    assert (result.clearance_min_um, result.clearance_max_um) == (6, 51)


@pytest.mark.parametrize(
    ("designation", "size_mm", "fit_type", "low", "high"),
    [
        ("H7/h6", 25, "clearance", 0, 34),  # zero minimum clearance is still a clearance fit
        ("H7 / k6", 25, "transition", -15, 19),
        ("H7/s6", 50, "interference", -59, -18),
        ("H7/n6", 25, "transition", -28, 6),
        ("H7/p6", 25, "interference", -35, -1),
    ],
)
def test_fit_types(
    designation: str, size_mm: float, fit_type: str, low: float, high: float
) -> None:
    result = fit(designation, size_mm * MM)
    assert result.fit_type == fit_type
    assert (result.clearance_min_um, result.clearance_max_um) == (low, high)


def test_fit_as_dict_um() -> None:
    assert fit("H8/g7", 10 * MM).as_dict_um() == {
        "hole": {"designation": "H8", "upper_um": 22, "lower_um": 0},
        "shaft": {"designation": "g7", "upper_um": -5, "lower_um": -20},
        "fit_type": "clearance",
        "clearance_um": {"min": 5, "max": 42, "mean": 23.5},
        "radial_clearance_um": {"min": 2.5, "max": 21, "mean": 11.75},
    }


@pytest.mark.parametrize(
    ("text", "message"),
    [
        ("g7/H8", "hole/shaft with the hole in upper case"),
        ("H8/H7", "got a hole then a hole"),
        ("h8/g7", "got a shaft then a shaft"),
        ("H8", "write the hole class, a slash and the shaft class"),
        ("H8/g7/k6", "write the hole class, a slash and the shaft class"),
        ("H8/", "expected fundamental-deviation letters"),
        ("H8/i7", "no fundamental deviation 'i'"),
    ],
)
def test_fit_designation_errors(text: str, message: str) -> None:
    with pytest.raises(StandardsError, match=message):
        fit(text, 10 * MM)


def test_fit_needs_a_hole_and_a_shaft_of_one_size() -> None:
    hole = tolerance_class("H7", 10 * MM)
    shaft = tolerance_class("g6", 10 * MM)
    with pytest.raises(StandardsError, match="needs a hole then a shaft"):
        Fit(hole=shaft, shaft=hole)
    with pytest.raises(StandardsError, match="one nominal size"):
        Fit(hole=hole, shaft=tolerance_class("g6", 12 * MM))


# ---------------------------------------------------------------------------------------------
# Properties over the whole range
# ---------------------------------------------------------------------------------------------
_LETTERS = sorted(iso286.SHAFT_LETTERS) + sorted(iso286.HOLE_LETTERS)


@given(
    letter=st.sampled_from(_LETTERS),
    grade=st.sampled_from(iso286.GRADES),
    size_mm=st.floats(min_value=0.01, max_value=3150.0),
)
def test_every_defined_class_has_width_it(letter: str, grade: str, size_mm: float) -> None:
    """Where a class is defined its width is the IT value (JS/js 7 … 11 possibly 1 µm less)."""
    try:
        result = tolerance_class(f"{letter}{grade}", size_mm * MM)
    except StandardsError:
        return  # not every letter exists at every size and grade; those raise, as tested above
    it = um(standard_tolerance(grade, size_mm * MM))
    width = result.upper_um - result.lower_um
    if letter in ("JS", "js"):
        assert result.upper_um == -result.lower_um
        assert it - 1 <= width <= it
    else:
        assert width == pytest.approx(it, abs=1e-6)
    if letter in ("H", "h"):
        assert (result.lower_um if letter == "H" else result.upper_um) == 0
    assert result.kind == ("hole" if letter.isupper() else "shaft")
