"""Measurement files: their conventions (units, directions, origin) and the reader, with the
shipped copy of the paper's Table 7."""

from __future__ import annotations

import io
import itertools
import math
from pathlib import Path

import numpy as np
import pytest

from jointplay.errors import ConfigError
from jointplay.io.measurements import (
    DIRECTIONS,
    SPEED_UNITS,
    MeasurementConventions,
    paper_table7,
    read_measurements,
)

#: A unit conversion multiplies by the unit's rad/s factor and divides on the way back; both
#: are correctly rounded, so a round trip is off by at most one unit in the last place
#: (relative 2**-52 ≈ 2.2e-16). Two ulp of margin.
ROUND_TRIP_RTOL = 2 * 2.0**-52

PAPER = MeasurementConventions()
ALL_CONVENTIONS = [
    MeasurementConventions(unit, crank, angle, origin, sign)
    for unit, crank, angle, origin, sign in itertools.product(
        SPEED_UNITS, DIRECTIONS, DIRECTIONS, (0.0, 37.25, -90.0), (1, -1)
    )
]


def _id(c: MeasurementConventions) -> str:
    directions = f"crank{c.crank_direction}-angle{c.angle_direction}"
    return f"{c.unit}-{directions}-{c.angle_origin:g}-{c.speed_sign:+d}"


# --- conventions -------------------------------------------------------------------------------


@pytest.mark.parametrize("conventions", ALL_CONVENTIONS, ids=_id)
def test_conventions_round_trip(conventions: MeasurementConventions) -> None:
    rng = np.random.default_rng(7)
    angles = np.concatenate([np.arange(0.0, 361.0, 30.0), rng.uniform(-720, 720, 200)])
    speeds = np.concatenate([[927.0, -554.0, 0.0, 1e-9], rng.normal(0, 500, angles.size - 4)])
    theta, omega = conventions.to_model(angles, speeds)
    back_angles, back_speeds = conventions.from_model(theta, omega)
    np.testing.assert_allclose(back_speeds, speeds, rtol=ROUND_TRIP_RTOL, atol=0)
    # the angle offset is added and subtracted: one rounding of the larger of the two
    np.testing.assert_allclose(back_angles, angles, rtol=0, atol=4 * np.spacing(1000.0))
    theta2, omega2 = conventions.to_model(*conventions.from_model(theta, omega))
    np.testing.assert_allclose(omega2, omega, rtol=ROUND_TRIP_RTOL, atol=0)
    np.testing.assert_allclose(theta2, theta, rtol=0, atol=4 * np.spacing(1000.0))
    if conventions.unit == "rad/s" and conventions.angle_origin == 0:
        # changes of sign and direction alone are exact
        assert np.array_equal(back_angles, angles) and np.array_equal(back_speeds, speeds)


def test_conventions_mean_what_they_say() -> None:
    # Table 7 as read in docs/paper-reading.md: 30° clockwise from the ground line, deg/s, CCW +
    theta, omega = PAPER.to_model([30.0], [644.0])
    assert theta[0] == -30.0
    assert omega[0] == pytest.approx(math.radians(644.0), rel=1e-15)
    assert PAPER.driver_direction == -1
    rpm = MeasurementConventions(unit="rpm", angle_direction="ccw", angle_origin=90.0)
    theta, omega = rpm.to_model([30.0], [60.0])
    assert theta[0] == 120.0 and omega[0] == pytest.approx(2 * math.pi, rel=1e-15)
    cw_positive = MeasurementConventions(unit="rad/s", speed_sign=-1)
    assert cw_positive.speed_to_si([2.5])[0] == -2.5
    assert "clockwise positive" in cw_positive.describe()


@pytest.mark.parametrize(
    ("field", "value", "message"),
    [
        ("unit", "furlong/s", "unit must be one of deg/s, rpm, rad/s"),
        ("crank_direction", "up", "crank_direction must be cw or ccw"),
        ("angle_direction", "", "angle_direction must be cw or ccw"),
        ("angle_origin", math.nan, "angle_origin must be a finite number"),
        ("angle_origin", "0 deg", "angle_origin must be a finite number"),
        ("speed_sign", 0, "speed_sign must be +1"),
        ("speed_sign", True, "speed_sign must be +1"),
    ],
)
def test_conventions_are_validated(field: str, value: object, message: str) -> None:
    with pytest.raises(ConfigError, match="MeasurementConventions") as info:
        MeasurementConventions(**{field: value})  # type: ignore[arg-type]
    assert message in str(info.value)


def test_conventions_normalise_case() -> None:
    c = MeasurementConventions(unit="RPM", crank_direction="CCW", angle_direction=" cw ")
    assert (c.unit, c.crank_direction, c.angle_direction) == ("rpm", "ccw", "cw")


# --- reading files -------------------------------------------------------------------------------


def test_paper_table7_is_shipped_and_read_with_its_columns() -> None:
    table = paper_table7()
    assert table.crank_deg.tolist() == list(range(0, 361, 30))
    assert table.speed[:3].tolist() == [927.0, 644.0, 358.0]
    assert table.model is not None and table.model[1] == 760.0
    assert table.printed_error is not None and table.printed_error[1] == -15.26
    assert (table.speed_column, table.conventions) == ("experiment_printed", PAPER)
    assert "Table 7" in table.source
    with pytest.raises(ValueError):
        table.speed[0] = 1.0  # frozen data


def test_read_measurements_two_columns_comments_and_blank_lines(tmp_path: Path) -> None:
    path = tmp_path / "rig.csv"
    path.write_text("# rig run 3\n\nangle, w\n# mid-file comment\n0, 1.5\n 90 ,-2\n")
    data = read_measurements(path, angle_column="angle", conventions=MeasurementConventions("rpm"))
    assert data.speed_column == "w" and data.speed.tolist() == [1.5, -2.0]
    assert data.crank_deg.tolist() == [0.0, 90.0] and data.conventions.unit == "rpm"
    stream = io.StringIO("crank_deg,a,b\n0,1,2\n")
    assert read_measurements(stream, speed_column="b").speed.tolist() == [2.0]


@pytest.mark.parametrize(
    ("text", "kwargs", "message"),
    [
        ("", {}, "no header line"),
        ("# only a comment\n", {}, "no header line"),
        ("crank_deg,v\n", {}, "no data rows"),
        ("crank_deg,v\n0,1\n30,abc\n", {}, "line 3, column 'v' has 'abc', not a finite number"),
        ("crank_deg,v\n0,\n", {}, "line 2, column 'v' is empty"),
        ("crank_deg,v\n0,nan\n", {}, "not a finite number"),
        ("crank_deg,v\n0,1,5\n", {}, "line 2 has 3 fields, the header has 2"),
        ("crank_deg,v,w\n0,1,2\n", {}, "cannot tell which column holds the speed"),
        ("angle,v\n0,1\n", {}, "cannot tell which column"),
        ("crank_deg,v\n0,1\n", {"speed_column": "w"}, "no column 'w'; columns: crank_deg, v"),
        ("crank_deg,v\n0,1\n", {"angle_column": "v", "speed_column": "v"}, "both 'v'"),
        ("crank_deg,crank_deg\n0,1\n", {}, "column names must be unique"),
    ],
)
def test_malformed_files_give_clear_errors(
    tmp_path: Path, text: str, kwargs: dict[str, str], message: str
) -> None:
    path = tmp_path / "bad.csv"
    path.write_text(text)
    with pytest.raises(ConfigError) as info:
        read_measurements(path, **kwargs)  # type: ignore[arg-type]
    assert message in str(info.value) and "bad.csv" in str(info.value)
    assert "\n" not in str(info.value)


def test_missing_file(tmp_path: Path) -> None:
    with pytest.raises(ConfigError, match="not found"):
        read_measurements(tmp_path / "nope.csv")
