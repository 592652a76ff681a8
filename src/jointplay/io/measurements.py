"""Measured speed against crank angle: the files, their conventions and the paper's Table 7.

The paper measured the rocker's angular speed at 13 crank positions (30° steps) on a test rig
running at 200 RPM (Table 7). This module reads such measurements (a CSV file of crank angle and
speed) together with the conventions that say how to read them; the comparison with a
simulation is :mod:`jointplay.study.comparison`.

Conventions of a measurement file (:class:`MeasurementConventions`)
    A file has a crank-angle column (degrees) and a speed column. Its conventions are
    explicit, with the defaults of ``docs/paper-reading.md`` for Table 7:

    * ``unit``: ``"deg/s"`` (default), ``"rpm"`` or ``"rad/s"``. Table 7's header says
      "RPM", but with a 200 RPM crank and a 52.6° rocker swing 932 RPM is impossible; the
      numbers have the shape and size of the rocker's angular velocity in degrees per second.
    * ``crank_direction``: the rig's crank turns ``"cw"`` (default) or ``"ccw"``. The
      simulated mechanism is driven in this direction.
    * ``angle_direction`` and ``angle_origin``: crank angles are counted ``"cw"`` (default) or
      ``"ccw"`` from the crank position ``angle_origin`` (degrees counter-clockwise from the
      ground line O2→O4; default 0°: the crank pointing at the rocker pivot O4).
    * ``speed_sign``: +1 (default) when a positive speed in the file means the rocker turns
      counter-clockwise, -1 when it means clockwise. The rig's tachometer measures a
      magnitude; in Table 7 the authors "measured in positive values" readings 5–11
      (120°–300°) and made them negative "due to the change in the direction of oscillation
      of rocker", so the printed signs are theirs and read as counter-clockwise positive.

    Every direction is seen in the mechanism's own frame: O2 at the origin, O4 on the positive
    x-axis, the mechanism's assembly branch (for ``paper-fourbar``: the coupler–rocker joint B
    above the ground line). The mirror image of a rig (seen from behind) is the same data with
    all three directions flipped *and* the other assembly branch.

    Inside jointplay the crank angle is counter-clockwise from the ground line (degrees here,
    as in the ``crank_deg`` columns) and the rocker speed is in rad/s, counter-clockwise
    positive. :meth:`MeasurementConventions.to_model` and
    :meth:`MeasurementConventions.from_model` convert both ways; they round-trip to within one
    unit in the last place (exactly for changes of sign and direction alone).
"""

from __future__ import annotations

import csv
import io
import math
from dataclasses import asdict, dataclass, field, replace
from importlib import resources
from pathlib import Path
from typing import IO, Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from jointplay.errors import ConfigError, SettingError
from jointplay.io.config import read_text_file

FloatArray = NDArray[np.float64]

#: rad/s per unit of each supported speed unit.
SPEED_UNITS: dict[str, float] = {"deg/s": math.pi / 180.0, "rpm": math.pi / 30.0, "rad/s": 1.0}
#: Rotation senses, as written in files and on the command line.
DIRECTIONS = ("cw", "ccw")
#: The shipped copy of the paper's Table 7 (package data).
PAPER_TABLE7_FILE = "paper_table7_rocker_speed.csv"
#: Its columns.
PAPER_TABLE7_COLUMNS = {
    "angle": "crank_deg",
    "speed": "experiment_printed",
    "model": "mbd_printed",
    "error": "error_percent_printed",
}


# --- conventions --------------------------------------------------------------------------------


@dataclass(frozen=True)
class MeasurementConventions:
    """How a measurement file states crank angle and rocker speed (see the module docstring).

    Attributes:
        unit: unit of the speed column: ``"deg/s"`` (default, Table 7 as read in
            docs/paper-reading.md), ``"rpm"`` or ``"rad/s"``.
        crank_direction: the rig's crank turns ``"cw"`` (default) or ``"ccw"``.
        angle_direction: crank angles in the file are counted ``"cw"`` (default) or ``"ccw"``.
        angle_origin: crank position of the file's 0°, degrees counter-clockwise from the
            ground line O2→O4 (default 0: the crank pointing at the rocker pivot O4).
        speed_sign: +1 (default) if a positive speed in the file is a counter-clockwise rocker
            rotation, -1 if clockwise. (Table 7's negative readings 5–11 were measured as
            magnitudes and given their sign by the authors.)
    """

    unit: str = "deg/s"
    crank_direction: str = "cw"
    angle_direction: str = "cw"
    angle_origin: float = 0.0
    speed_sign: int = 1

    def __post_init__(self) -> None:
        unit = str(self.unit).strip().lower()
        if unit not in SPEED_UNITS:
            raise ConfigError(
                f"MeasurementConventions: unit must be one of {', '.join(SPEED_UNITS)}, "
                f"got {self.unit!r}"
            )
        object.__setattr__(self, "unit", unit)
        for name in ("crank_direction", "angle_direction"):
            value = str(getattr(self, name)).strip().lower()
            if value not in DIRECTIONS:
                raise ConfigError(
                    f"MeasurementConventions: {name} must be cw or ccw, got {getattr(self, name)!r}"
                )
            object.__setattr__(self, name, value)
        origin = self.angle_origin
        if (
            isinstance(origin, bool)
            or not isinstance(origin, int | float)
            or not math.isfinite(origin)
            or abs(origin) > MAX_ANGLE_DEG
        ):
            raise ConfigError(
                f"MeasurementConventions: angle_origin must be a finite number of degrees "
                f"within ±{MAX_ANGLE_DEG:g}, got {origin!r}"
            )
        object.__setattr__(self, "angle_origin", float(origin))
        if isinstance(self.speed_sign, bool) or self.speed_sign not in (1, -1):
            raise ConfigError(
                "MeasurementConventions: speed_sign must be +1 (counter-clockwise positive) or "
                f"-1 (clockwise positive), got {self.speed_sign!r}"
            )
        object.__setattr__(self, "speed_sign", int(self.speed_sign))

    @property
    def unit_factor(self) -> float:
        """rad/s per unit of the file's speeds."""
        return SPEED_UNITS[self.unit]

    @property
    def driver_direction(self) -> int:
        """The rig's crank direction as a :class:`~jointplay.model.mechanism.Driver` direction."""
        return 1 if self.crank_direction == "ccw" else -1

    @property
    def angle_sign(self) -> int:
        """+1 if the file counts crank angles counter-clockwise, -1 if clockwise."""
        return 1 if self.angle_direction == "ccw" else -1

    def crank_to_model(self, crank_deg: ArrayLike) -> FloatArray:
        """File crank angles (deg) → degrees CCW from the ground line (unwrapped)."""
        return self.angle_origin + self.angle_sign * np.asarray(crank_deg, dtype=float)

    def crank_from_model(self, crank_deg_ccw: ArrayLike) -> FloatArray:
        """Degrees counter-clockwise from the ground line → the file's crank angles (deg)."""
        return self.angle_sign * (np.asarray(crank_deg_ccw, dtype=float) - self.angle_origin)

    def speed_to_si(self, speed: ArrayLike) -> FloatArray:
        """File speeds (``unit``, ``speed_sign``) → rad/s, counter-clockwise positive."""
        return self.speed_sign * (np.asarray(speed, dtype=float) * self.unit_factor)

    def speed_from_si(self, omega: ArrayLike) -> FloatArray:
        """rad/s, counter-clockwise positive → the file's unit and sign."""
        return self.speed_sign * (np.asarray(omega, dtype=float) / self.unit_factor)

    def to_model(self, crank_deg: ArrayLike, speed: ArrayLike) -> tuple[FloatArray, FloatArray]:
        """(crank angle, speed) as in the file → (deg CCW from the ground line, rad/s CCW+)."""
        return self.crank_to_model(crank_deg), self.speed_to_si(speed)

    def from_model(
        self, crank_deg_ccw: ArrayLike, omega: ArrayLike
    ) -> tuple[FloatArray, FloatArray]:
        """The inverse of :meth:`to_model`."""
        return self.crank_from_model(crank_deg_ccw), self.speed_from_si(omega)

    def describe(self) -> str:
        """One line for reports."""
        sense = {"cw": "clockwise", "ccw": "counter-clockwise"}
        positive = "counter-clockwise" if self.speed_sign == 1 else "clockwise"
        return (
            f"speed in {self.unit}, {positive} positive; crank turning "
            f"{sense[self.crank_direction]}; crank angle counted {sense[self.angle_direction]} "
            f"from {self.angle_origin:g}° (CCW from the ground line O2→O4)"
        )

    def as_dict(self) -> dict[str, Any]:
        return {**asdict(self), "description": self.describe()}


# --- reading measurements ---------------------------------------------------------------------


#: The largest crank angle a measurement may give, degrees (unwrapped: 100 revolutions).
MAX_ANGLE_DEG = 36_000.0
#: The largest magnitude of a measured speed or published value, in the file's unit.
MAX_MAGNITUDE = 1e9


def frozen_array(values: ArrayLike) -> FloatArray:
    """A read-only float copy of ``values`` (for the arrays of frozen results)."""
    array = np.array(values, dtype=float)
    array.setflags(write=False)
    return array


@dataclass(frozen=True, eq=False)
class Measurements:
    """Measured speed against crank angle, as in the file, with the file's conventions.

    Attributes:
        crank_deg: crank angles, degrees, in the file's convention.
        speed: measured speeds in ``conventions.unit`` with the file's sign.
        conventions: how to read them.
        source: where they came from (for reports).
        angle_column, speed_column: the columns they were read from.
        model: optional published simulation values at the same angles (Table 7's "MBD
            Simulation" column), in the same unit and sign convention.
        printed_error: optional published error % per point (Table 7's last column).
    """

    crank_deg: FloatArray
    speed: FloatArray
    conventions: MeasurementConventions = field(default_factory=MeasurementConventions)
    source: str = ""
    angle_column: str = "crank_deg"
    speed_column: str = "speed"
    model: FloatArray | None = None
    model_column: str | None = None
    printed_error: FloatArray | None = None
    error_column: str | None = None

    def __post_init__(self) -> None:
        for name in ("crank_deg", "speed", "model", "printed_error"):
            value = getattr(self, name)
            if value is None:
                continue
            array = frozen_array(value)
            if array.ndim != 1 or array.shape != np.shape(self.crank_deg):
                raise ConfigError(
                    f"Measurements: {name} must be a 1-D array as long as crank_deg "
                    f"({np.size(self.crank_deg)}), got shape {array.shape}"
                )
            if not np.all(np.isfinite(array)):
                raise ConfigError(f"Measurements: {name} has non-finite values")
            limit = MAX_ANGLE_DEG if name == "crank_deg" else MAX_MAGNITUDE
            if array.size and np.max(np.abs(array)) > limit:
                worst = float(array[np.argmax(np.abs(array))])
                raise ConfigError(
                    f"Measurements: {name} has {worst:g}, beyond the plausible ±{limit:g}"
                    + (
                        " degrees (unwrapped angles of at most 100 revolutions)"
                        if name == "crank_deg"
                        else ""
                    )
                )
            object.__setattr__(self, name, array)
        if self.crank_deg.size == 0:
            raise ConfigError("Measurements: no data points")
        values, counts = np.unique(self.crank_deg, return_counts=True)
        if np.any(counts > 1):
            raise ConfigError(
                f"Measurements: crank angle {float(values[np.argmax(counts > 1)]):g} deg appears "
                f"{int(counts.max())} times; give one measurement per angle (average repeats)"
            )

    @property
    def crank_deg_model(self) -> FloatArray:
        """Crank angles, degrees counter-clockwise from the ground line (unwrapped)."""
        return self.conventions.crank_to_model(self.crank_deg)

    @property
    def speed_si(self) -> FloatArray:
        """Measured speeds, rad/s, counter-clockwise positive."""
        return self.conventions.speed_to_si(self.speed)

    def with_conventions(self, conventions: MeasurementConventions) -> Measurements:
        """The same numbers read with other conventions."""
        return replace(self, conventions=conventions)


def read_measurements(
    source: str | Path | IO[str],
    *,
    angle_column: str = "crank_deg",
    speed_column: str | None = None,
    conventions: MeasurementConventions | None = None,
    model_column: str | None = None,
    error_column: str | None = None,
) -> Measurements:
    """Read measured speed against crank angle from a CSV file.

    Lines starting with ``#`` are comments. The first non-comment line names the columns.

    Args:
        source: path of the CSV file (or an open text stream).
        angle_column: column of crank angles, degrees (default ``crank_deg``).
        speed_column: column of measured speeds; by default the other column of a two-column
            file (a file with more columns must name it).
        conventions: unit and direction conventions of the file (default: those of Table 7 as
            read in docs/paper-reading.md).
        model_column: optional column of a published simulation at the same angles.
        error_column: optional column of published error percentages.

    Raises:
        ConfigError: the file is missing, unreadable, lacks a column, or has an empty or
            non-numeric value (the message names the file, column and data row).
    """
    conventions = conventions or MeasurementConventions()
    name = getattr(source, "name", None) if not isinstance(source, str | Path) else str(source)
    label = str(name) if name else "measurement data"
    header, rows = _read_rows(source, label)
    columns = header
    if speed_column is None:
        others = [c for c in columns if c != angle_column]
        if angle_column not in columns or len(others) != 1:
            raise SettingError(
                "{label}: cannot tell which column holds the speed (columns: {columns}); "
                "name it with {speed_column}",
                label=label,
                columns=", ".join(columns),
            )
        speed_column = others[0]
    if speed_column == angle_column:
        raise ConfigError(f"{label}: the angle and speed columns are both {angle_column!r}")
    wanted = [angle_column, speed_column, model_column, error_column]
    for column in wanted:
        if column is not None and column not in columns:
            raise SettingError(
                "{label}: no column {column!r}; columns: {columns} (choose with {angle_column} "
                "/ {speed_column})",
                label=label,
                column=column,
                columns=", ".join(columns),
            )
    if not rows:
        raise ConfigError(f"{label}: no data rows (only a header)")
    values = {c: _numeric_column(rows, columns.index(c), c, label) for c in wanted if c is not None}
    return Measurements(
        values[angle_column],
        values[speed_column],
        conventions,
        label,
        angle_column,
        speed_column,
        None if model_column is None else values[model_column],
        model_column,
        None if error_column is None else values[error_column],
        error_column,
    )


def _read_rows(
    source: str | Path | IO[str], label: str
) -> tuple[list[str], list[tuple[int, list[str]]]]:
    """Header and (line number, fields) of the data rows; ``#`` lines and blank lines skipped."""
    try:
        if isinstance(source, str | Path):
            text = read_text_file(source, "measurement file").removeprefix("\ufeff")
        else:
            text = source.read()
    except (OSError, UnicodeDecodeError) as exc:
        raise ConfigError(f"{label}: cannot read the file ({exc})") from None
    header: list[str] | None = None
    rows: list[tuple[int, list[str]]] = []
    try:
        for number, line in enumerate(text.splitlines(), start=1):
            if not line.strip() or line.lstrip().startswith("#"):
                continue
            fields = [f.strip() for f in next(csv.reader([line]))]
            if header is None:
                header = fields
                if len(set(header)) != len(header) or "" in header:
                    raise ConfigError(
                        f"{label}: line {number}: column names must be unique and non-empty, "
                        f"got {', '.join(header)}"
                    )
                continue
            if len(fields) != len(header):
                raise ConfigError(
                    f"{label}: line {number} has {len(fields)} fields, the header has "
                    f"{len(header)} ({', '.join(header)})"
                )
            rows.append((number, fields))
    except csv.Error as exc:
        raise ConfigError(f"{label}: cannot read as CSV ({exc})") from None
    if header is None:
        raise ConfigError(f"{label}: no header line and no data")
    return header, rows


def _numeric_column(
    rows: list[tuple[int, list[str]]], index: int, column: str, label: str
) -> FloatArray:
    numbers = np.empty(len(rows))
    for i, (line, fields) in enumerate(rows):
        text = fields[index]
        try:
            numbers[i] = float(text)
        except ValueError:
            numbers[i] = math.nan
        if not math.isfinite(numbers[i]):
            what = "is empty" if not text else f"has {text!r}, not a finite number"
            raise ConfigError(f"{label}: line {line}, column {column!r} {what}")
    return numbers


def paper_table7_path() -> Any:
    """The shipped copy of the paper's Table 7 (an ``importlib.resources`` traversable)."""
    return resources.files("jointplay") / "data" / PAPER_TABLE7_FILE


def paper_table7(conventions: MeasurementConventions | None = None) -> Measurements:
    """The paper's Table 7: measured rocker speed ("Experimentation") at 200 RPM, 30° steps.

    The "MBD Simulation" column becomes :attr:`Measurements.model` and the printed error %
    :attr:`Measurements.printed_error`. Conventions default to the docs/paper-reading.md reading
    (deg/s, crank clockwise, angle clockwise from the ground line, CCW-positive speeds).
    """
    text = paper_table7_path().read_text(encoding="utf-8")
    measurements = read_measurements(
        io.StringIO(text),
        angle_column=PAPER_TABLE7_COLUMNS["angle"],
        speed_column=PAPER_TABLE7_COLUMNS["speed"],
        conventions=conventions,
        model_column=PAPER_TABLE7_COLUMNS["model"],
        error_column=PAPER_TABLE7_COLUMNS["error"],
    )
    return replace(measurements, source=f"paper Table 7 (jointplay/data/{PAPER_TABLE7_FILE})")
