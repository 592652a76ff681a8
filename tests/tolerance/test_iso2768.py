"""ISO 2768-1:1989 (= IS 2102-1:1993) general tolerances: every cell, boundaries, errors.

The expected tables are written out again here, independently of the module, from
docs/contact-laws.md §7 (Table 1, linear dimensions) and from the issue text
(Table 2, broken edges; Table 3, angular dimensions).
"""

from __future__ import annotations

import math

import pytest

from jointplay.errors import StandardsError
from jointplay.tolerance.iso2768 import (
    GeneralTolerance,
    angular_tolerance,
    broken_edge_tolerance,
    general_tolerance,
    linear_tolerance,
    parse_class,
)

MM = 1e-3

# (over mm, up to and including mm, text of the range); the first range includes 0.5 mm.
LINEAR_RANGES = [
    (0.5, 3, "0.5 up to and including 3 mm"),
    (3, 6, "over 3 up to and including 6 mm"),
    (6, 30, "over 6 up to and including 30 mm"),
    (30, 120, "over 30 up to and including 120 mm"),
    (120, 400, "over 120 up to and including 400 mm"),
    (400, 1000, "over 400 up to and including 1000 mm"),
    (1000, 2000, "over 1000 up to and including 2000 mm"),
    (2000, 4000, "over 2000 up to and including 4000 mm"),
]
# docs/contact-laws.md §7, ± mm; None = "—"
LINEAR: dict[str, list[float | None]] = {
    "f": [0.05, 0.05, 0.1, 0.15, 0.2, 0.3, 0.5, None],
    "m": [0.1, 0.1, 0.2, 0.3, 0.5, 0.8, 1.2, 2],
    "c": [0.2, 0.3, 0.5, 0.8, 1.2, 2, 3, 4],
    "v": [None, 0.5, 1, 1.5, 2.5, 4, 6, 8],
}
LINEAR_CELLS = [
    (cls, index, value) for cls, column in LINEAR.items() for index, value in enumerate(column)
]


def _probe_sizes(index: int) -> list[float]:
    """The lower end (inclusive only for the first range), a middle value and the upper end."""
    lower, upper, _ = LINEAR_RANGES[index]
    first = lower if index == 0 else lower + 0.001
    return [first, (lower + upper) / 2, upper]


@pytest.mark.parametrize(
    ("cls", "index", "value"), LINEAR_CELLS, ids=[f"{c}-{i}" for c, i, _ in LINEAR_CELLS]
)
def test_every_linear_cell(cls: str, index: int, value: float | None) -> None:
    for size_mm in _probe_sizes(index):
        if value is None:
            with pytest.raises(StandardsError, match=r"leaves class . \(.*\) empty"):
                linear_tolerance(cls, size_mm * MM)
            with pytest.raises(StandardsError, match="state the tolerance on the dimension"):
                general_tolerance(cls, size_mm * MM)
            continue
        result = linear_tolerance(cls, size_mm * MM)
        assert result.deviation_mm == value
        assert result.size_range == LINEAR_RANGES[index][2]
        assert result.feature == "linear"
        assert result.tolerance_class == cls
        # SI: the deviation in metres is the mm value / 1000, to the last bit
        assert general_tolerance(cls, size_mm * MM) == value / 1000


@pytest.mark.parametrize(
    ("cls", "size_mm", "expected_mm", "size_range"),
    [
        ("m", 120, 0.3, "over 30 up to and including 120 mm"),  # boundary → lower range
        ("m", 120.001, 0.5, "over 120 up to and including 400 mm"),
        ("c", 3, 0.2, "0.5 up to and including 3 mm"),
        ("c", 3.0001, 0.3, "over 3 up to and including 6 mm"),
        ("f", 2000, 0.5, "over 1000 up to and including 2000 mm"),
        ("m", 4000, 2, "over 2000 up to and including 4000 mm"),
        ("f", 0.5, 0.05, "0.5 up to and including 3 mm"),
    ],
)
def test_linear_boundaries(cls: str, size_mm: float, expected_mm: float, size_range: str) -> None:
    result = linear_tolerance(cls, size_mm * MM)
    assert (result.deviation_mm, result.size_range) == (expected_mm, size_range)


def test_paper_four_bar_links_in_class_c() -> None:
    """docs/contact-laws.md §7: links of 108, 270.5 and 279.4 mm in class c: ±0.8, ±1.2, ±1.2 mm."""
    assert [general_tolerance("c", length * MM) * 1e3 for length in (108, 270.5, 279.4)] == [
        pytest.approx(0.8, rel=1e-12),
        pytest.approx(1.2, rel=1e-12),
        pytest.approx(1.2, rel=1e-12),
    ]
    assert linear_tolerance("c", 0.2705).text == "±1.2 mm"


def test_size_in_metres_that_is_not_a_binary_fraction_is_on_the_boundary() -> None:
    assert linear_tolerance("m", 0.12).deviation_mm == 0.3  # 0.12 m · 1000 = 120.00000000000001


@pytest.mark.parametrize(
    ("cls", "size_mm", "message"),
    [
        ("m", 0.499, "tolerance must be stated on the dimension itself"),
        ("f", 0.1, "below 0.5 mm"),
        ("m", 4000.001, "ends at 4000 mm"),
        ("f", 2500, r"leaves class f \(fine\) empty .* use class m, c or v"),
        ("v", 2, r"leaves class v \(very coarse\) empty .* use class f, m or c"),
        ("m", 0, "> 0 mm"),
        ("m", -1, "> 0 mm"),
        ("x", 10, "f \\(fine\\), m \\(medium\\), c \\(coarse\\) and v \\(very coarse\\)"),
    ],
)
def test_linear_errors(cls: str, size_mm: float, message: str) -> None:
    with pytest.raises(StandardsError, match=message):
        linear_tolerance(cls, size_mm * MM)


@pytest.mark.parametrize("size", [math.nan, math.inf, "10 mm", None])
def test_size_must_be_a_finite_number(size: object) -> None:
    with pytest.raises(StandardsError, match="finite length in metres"):
        linear_tolerance("m", size)  # type: ignore[arg-type]


# --- broken edges (Table 2): 0.5–3 / >3–6 / >6 mm; f, m ±0.2/±0.5/±1; c, v ±0.4/±1/±2 -----------
BROKEN_EDGE = {"f": (0.2, 0.5, 1), "m": (0.2, 0.5, 1), "c": (0.4, 1, 2), "v": (0.4, 1, 2)}
BROKEN_EDGE_PROBES = [
    (0, 0.5, "0.5 up to and including 3 mm"),
    (0, 3, "0.5 up to and including 3 mm"),
    (1, 3.001, "over 3 up to and including 6 mm"),
    (1, 6, "over 3 up to and including 6 mm"),
    (2, 6.001, "over 6 mm"),
    (2, 500, "over 6 mm"),
]


@pytest.mark.parametrize("cls", ["f", "m", "c", "v"])
@pytest.mark.parametrize(("index", "size_mm", "size_range"), BROKEN_EDGE_PROBES)
def test_every_broken_edge_cell(cls: str, index: int, size_mm: float, size_range: str) -> None:
    result = broken_edge_tolerance(cls, size_mm * MM)
    assert result.deviation_mm == BROKEN_EDGE[cls][index]
    assert result.size_range == size_range
    assert result.feature == "broken edge"


def test_broken_edge_below_half_a_millimetre() -> None:
    with pytest.raises(StandardsError, match="stated on the dimension itself"):
        broken_edge_tolerance("m", 0.3 * MM)


# --- angular (Table 3), by the shorter side: ≤10 / >10–50 / >50–120 / >120–400 / >400 mm ------
ANGULAR_ARCMIN = {
    "f": (60, 30, 20, 10, 5),
    "m": (60, 30, 20, 10, 5),
    "c": (90, 60, 30, 15, 10),
    "v": (180, 120, 60, 30, 20),
}
ANGULAR_TEXT = {
    "f": ("±1°", "±0°30'", "±0°20'", "±0°10'", "±0°5'"),
    "m": ("±1°", "±0°30'", "±0°20'", "±0°10'", "±0°5'"),
    "c": ("±1°30'", "±1°", "±0°30'", "±0°15'", "±0°10'"),
    "v": ("±3°", "±2°", "±1°", "±0°30'", "±0°20'"),
}
ANGULAR_PROBES = [
    (0, 0.1, "up to and including 10 mm"),
    (0, 10, "up to and including 10 mm"),
    (1, 10.001, "over 10 up to and including 50 mm"),
    (1, 50, "over 10 up to and including 50 mm"),
    (2, 120, "over 50 up to and including 120 mm"),
    (3, 400, "over 120 up to and including 400 mm"),
    (4, 400.001, "over 400 mm"),
    (4, 10000, "over 400 mm"),
]


@pytest.mark.parametrize("cls", ["f", "m", "c", "v"])
@pytest.mark.parametrize(("index", "side_mm", "size_range"), ANGULAR_PROBES)
def test_every_angular_cell(cls: str, index: int, side_mm: float, size_range: str) -> None:
    result = angular_tolerance(cls, side_mm * MM)
    arcmin = ANGULAR_ARCMIN[cls][index]
    assert result.deviation == pytest.approx(math.radians(arcmin / 60), rel=1e-15)
    assert result.deviation_arcmin == arcmin
    assert result.deviation_deg == arcmin / 60
    assert result.text == ANGULAR_TEXT[cls][index]
    assert result.size_range == size_range
    assert result.feature == "angular"


def test_angular_needs_a_positive_side() -> None:
    with pytest.raises(StandardsError, match="> 0 mm"):
        angular_tolerance("m", 0.0)


def test_units_of_a_result_follow_its_feature() -> None:
    with pytest.raises(StandardsError, match="deviation_deg"):
        _ = angular_tolerance("m", 0.03).deviation_mm
    with pytest.raises(StandardsError, match="no deviation in degrees"):
        _ = linear_tolerance("m", 0.03).deviation_deg


@pytest.mark.parametrize(
    ("text", "letter"),
    [
        ("m", "m"),
        ("M", "m"),
        (" c ", "c"),
        ("medium", "m"),
        ("Very coarse", "v"),
        ("very-coarse", "v"),
    ],
)
def test_parse_class(text: str, letter: str) -> None:
    assert parse_class(text) == letter


@pytest.mark.parametrize("text", ["x", "", "mk", "fine-ish", 3])
def test_parse_class_errors(text: object) -> None:
    with pytest.raises(StandardsError, match="unknown ISO 2768-1 tolerance class"):
        parse_class(text)  # type: ignore[arg-type]


def test_result_type_is_frozen_and_validated() -> None:
    result = linear_tolerance("m", 0.05)
    assert result == GeneralTolerance(
        "m", "linear", 0.05, 0.3e-3, "over 30 up to and including 120 mm"
    )
    assert result.class_name == "medium"
    assert result.nominal_size_mm == 50
    with pytest.raises(AttributeError):
        result.deviation = 1.0  # type: ignore[misc]
    with pytest.raises(StandardsError, match="deviation must be finite and > 0"):
        GeneralTolerance("m", "linear", 0.05, -1.0, "x")
    with pytest.raises(StandardsError, match="class must be one of"):
        GeneralTolerance("q", "linear", 0.05, 1.0, "x")
