"""``jointplay compare``: simulated rocker speed against measurements (Table 7, Figs. 17–20).

Prints the per-point table (measured and simulated speeds and the paper's error % per method,
in the measurement's unit), the statistics per method, the best-agreeing method, the
discrepancy with the nominal kinematics and its labelled what-if (never applied), and — for
the paper's Table 7 — how its printed error column follows from its printed speeds. See
:mod:`jointplay.io.measurements` for the conventions and
:mod:`jointplay.study.comparison` for the definitions.

The module imports only Typer and Rich at the top; the study, NumPy and pandas are imported
when the command runs, so that ``jointplay --help`` stays fast.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import TYPE_CHECKING, Annotated, Any

import typer
from rich.console import Console
from rich.table import Table

from jointplay.cli._app import app
from jointplay.cli._common import (
    AngleDirectionOption,
    AngleOriginOption,
    ConfigOption,
    CrankDirectionOption,
    FigureFormatOption,
    ForceOption,
    PresetOption,
    ProgressOption,
    RpmOption,
    SpeedPositiveOption,
    check_figure_format,
    choice,
    compiling_kernels,
    maybe_output_dir,
    provenance,
    status,
    whole_headers,
)
from jointplay.errors import ConfigError
from jointplay.settings.mechanism import mechanism_from_options
from jointplay.units import parse_quantity

if TYPE_CHECKING:
    from jointplay.io.measurements import MeasurementConventions, Measurements
    from jointplay.model.mechanism import Mechanism
    from jointplay.study.comparison import MethodsComparison

#: Width of the tables when the output is not a terminal (files, pipes, tests), characters.
PIPE_WIDTH = 160


def _opt(help_text: str, *names: str) -> Any:
    return typer.Option(*names, help=help_text)


@app.command("compare")
def compare_command(
    preset: PresetOption = None,
    config: ConfigOption = None,
    rpm: RpmOption = None,
    measurements: Annotated[
        Path | None,
        _opt(
            "CSV of crank angle (deg) and measured rocker speed; '#' lines are comments. "
            "Default: the paper's Table 7 (shipped with jointplay).",
            "--measurements",
            "-m",
        ),
    ] = None,
    angle_column: Annotated[
        str, _opt("Column of crank angles, degrees.", "--angle-column")
    ] = "crank_deg",
    speed_column: Annotated[
        str | None,
        _opt(
            "Column of measured speeds (default: the other column of a two-column file; "
            "experiment_printed for Table 7).",
            "--speed-column",
        ),
    ] = None,
    unit: Annotated[
        str,
        _opt(
            "Unit of the measured speeds: deg/s (default; Table 7's 'RPM' read as deg/s, see "
            "docs/paper-reading.md), rpm or rad/s.",
            "--unit",
        ),
    ] = "deg/s",
    crank_direction: CrankDirectionOption = "cw",
    angle_direction: AngleDirectionOption = "cw",
    angle_origin: AngleOriginOption = "0 deg",
    speed_positive: SpeedPositiveOption = "ccw",
    method: Annotated[
        list[str] | None,
        _opt(
            "Simulation to compare (repeatable): nominal (ideal joints), physical (the default "
            "contact, docs/contact.md) or one of the paper's methods ifm-conventional, "
            "rm-conventional, ifm-ecs-cylindrical, rm-ecs-cylindrical, ifm-ecs-spherical, "
            "rm-ecs-spherical. Default: nominal, physical and the four ECS methods.",
            "--method",
        ),
    ] = None,
    ecs_source: Annotated[
        str,
        _opt(
            "ECS parameters: computed (our estimate, default) or paper (Tables 4 and 5); the "
            "console, comparison.json and the plots say which was used.",
            "--ecs-source",
        ),
    ] = "computed",
    revolutions: Annotated[
        float,
        _opt(
            "Simulated crank periods from the nominal steady motion; only the last full "
            "revolution is compared (default 3, at least 1).",
            "--revolutions",
        ),
    ] = 3.0,
    low_speed: Annotated[
        float,
        _opt(
            "Leave points whose |simulated| is below this fraction of the largest out of the "
            "error-% statistics (default 0.1).",
            "--low-speed",
        ),
    ] = 0.1,
    as_json: Annotated[
        bool, typer.Option("--json", help="Print the comparison as JSON instead of tables.")
    ] = False,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out",
            "-o",
            help="Write comparison.csv, comparison.json and overlay PNGs to this folder.",
        ),
    ] = None,
    force: ForceOption = False,
    progress: ProgressOption = True,
    figure_format: FigureFormatOption = "png",
) -> None:
    """Compare the simulated steady-cycle rocker speed with measurements.

    Error % = (measured − simulated) / simulated × 100, as the paper defines it (Table 7).
    Nothing is rescaled: the discrepancy with the nominal kinematics is reported as a
    labelled what-if (the crank speed that would explain it).
    """
    from jointplay.io.measurements import DIRECTIONS, SPEED_UNITS, MeasurementConventions
    from jointplay.io.output import json_text, write_csv, write_json
    from jointplay.model.summary import mechanism_summary
    from jointplay.report.overlays import overlay_plots
    from jointplay.study import comparison as cmp
    from jointplay.study.methods import ECS_SOURCES, METHODS

    figure_format = check_figure_format(figure_format)
    with maybe_output_dir(out, force, inputs=(config, measurements)) as folder:
        conventions = MeasurementConventions(
            unit=choice(unit, "--unit", tuple(SPEED_UNITS)),
            crank_direction=choice(crank_direction, "--crank-direction", DIRECTIONS),
            angle_direction=choice(angle_direction, "--angle-direction", DIRECTIONS),
            angle_origin=_angle_origin(angle_origin),
            speed_sign=1 if choice(speed_positive, "--speed-positive", DIRECTIONS) == "ccw" else -1,
        )
        methods = list(dict.fromkeys(method or cmp.COMPARE_METHODS))
        for name in methods:
            if name not in (cmp.NOMINAL, cmp.PHYSICAL) and name not in METHODS:
                raise ConfigError(
                    f"--method: unknown method {name!r}; use {cmp.NOMINAL}, {cmp.PHYSICAL} or "
                    f"one of {', '.join(METHODS)}"
                )
        if ecs_source not in ECS_SOURCES:
            raise ConfigError(f"--ecs-source must be computed or paper, got {ecs_source!r}")
        if not (math.isfinite(revolutions) and revolutions >= 1):
            raise ConfigError(
                f"--revolutions must be >= 1 (the last full revolution is compared), got {revolutions}"
            )
        if not (math.isfinite(low_speed) and 0 <= low_speed < 1):
            raise ConfigError(f"--low-speed must be a fraction in [0, 1), got {low_speed}")
        data = _measurements(measurements, angle_column, speed_column, conventions)
        mechanism = cmp.rig_mechanism(mechanism_from_options(preset, config, rpm), conventions)
        nominal = cmp.compare(data, cmp.nominal_cycle(mechanism), low_speed_fraction=low_speed)
        comparisons = []
        for name in methods:
            if name == cmp.NOMINAL:
                comparisons.append(nominal)
                continue
            with (
                compiling_kernels(),  # says so only while no compiled kernels are cached
                status(
                    progress,
                    f"simulating {name}: {revolutions:g} revolution(s) of {mechanism.name}",
                ),
            ):
                cycle = cmp.steady_cycle(
                    mechanism, name, revolutions=revolutions, ecs_source=ecs_source
                )
            comparisons.append(cmp.compare(data, cycle, low_speed_fraction=low_speed))
        result = cmp.summarize_comparisons(data, comparisons, nominal)
        document = result.as_dict()
        if folder is not None:
            write_csv(result.points_table(), folder / "comparison.csv")
            write_json(
                folder / "comparison.json",
                {
                    **document,
                    "provenance": provenance({"mechanism": mechanism_summary(mechanism)}),
                },
            )
            overlay_plots(
                result,
                folder,
                title=f"{mechanism.name}: rocker speed, {data.source}\n{result.ecs_source_line()}",
                figure_format=figure_format,
            )
    if as_json:
        print(json_text(document))
        return
    _print(result, mechanism, out)


def _angle_origin(text: str) -> float:
    """``--angle-origin`` in degrees, within one turn either way."""
    degrees = math.degrees(parse_quantity(text, "rad", field="--angle-origin"))
    if not abs(degrees) <= 360.0:
        raise ConfigError(f"--angle-origin must lie within ±360 deg, got {text!r}")
    return degrees


def _measurements(
    path: Path | None,
    angle_column: str,
    speed_column: str | None,
    conventions: MeasurementConventions,
) -> Measurements:
    """The measurements of ``path``, or of the shipped Table 7 when no file is given."""
    from jointplay.io.measurements import (
        PAPER_TABLE7_COLUMNS,
        paper_table7,
        paper_table7_path,
        read_measurements,
    )

    if path is not None:
        return read_measurements(
            path, angle_column=angle_column, speed_column=speed_column, conventions=conventions
        )
    columns = PAPER_TABLE7_COLUMNS
    if angle_column == columns["angle"] and speed_column in (None, columns["speed"]):
        return paper_table7(conventions)
    with paper_table7_path().open("r", encoding="utf-8") as stream:
        return read_measurements(
            stream,
            angle_column=angle_column,
            speed_column=speed_column or columns["speed"],
            conventions=conventions,
        )


def _format_number(value: float, digits: str = ".1f") -> str:
    """``value`` formatted with ``digits``; an empty cell for NaN and infinities."""
    return "" if not math.isfinite(value) else format(value, digits)


def _print(result: MethodsComparison, mechanism: Mechanism, out: Path | None) -> None:
    console = Console(highlight=False, soft_wrap=True)
    if not console.is_terminal:
        console.width = PIPE_WIDTH
    data = result.measurements
    conventions = data.conventions
    unit = conventions.unit
    console.print(f"measurements: {data.source} (columns {data.angle_column}, {data.speed_column})")
    console.print(f"conventions: {conventions.describe()}")
    console.print(
        f"mechanism: {mechanism.name}, crank {conventions.crank_direction} at "
        f"{mechanism.driver.speed * 30 / math.pi:g} RPM; error % = (measured − simulated) / "
        "simulated × 100 (the paper's definition)"
    )
    console.print(result.ecs_source_line())
    for c in result.comparisons:
        console.print(f"  {c.description}")
    points = Table(title=f"rocker speed ({unit}) and error % per point", box=None)
    points.add_column("crank (deg)", justify="right")
    points.add_column("measured", justify="right")
    for c in result.comparisons:
        points.add_column(c.method, justify="right")
        points.add_column("err %", justify="right")
    frames = [c.points for c in result.comparisons]
    for i in range(len(data.crank_deg)):
        row = [f"{data.crank_deg[i]:g}", f"{data.speed[i]:.4g}"]
        for frame in frames:
            flag = "*" if bool(frame["low_speed"].iloc[i]) else ""
            row += [
                f"{frame['simulated'].iloc[i]:.1f}",
                _format_number(float(frame["error_percent"].iloc[i]), "+.2f") + flag,
            ]
        points.add_row(*row)
    console.print(whole_headers(points))
    flagged = [c for c in result.comparisons if c.points["low_speed"].any()]
    if flagged:
        console.print(
            "  * |simulated| below the low-speed threshold: left out of the error-% statistics"
        )
    stats = Table(title="agreement per simulation", box=None)
    for name in (
        "method",
        "RMS err %",
        "max |err %|",
        "at (deg)",
        f"RMS diff ({unit})",
        f"max |diff| ({unit})",
        "RMS diff (rad/s)",
        "points in %",
        "what-if factor",
    ):
        stats.add_column(name, justify="left" if name == "method" else "right")
    for record in result.table.to_dict(orient="records"):
        stats.add_row(
            str(record["method"]),
            _format_number(record["rms_error_percent"], ".2f"),
            _format_number(record["max_abs_error_percent"], ".2f"),
            _format_number(record["max_error_at_deg"], "g"),
            _format_number(record["rms_difference_in_unit"], ".1f"),
            _format_number(record["max_abs_difference_in_unit"], ".1f"),
            _format_number(record["rms_difference_rad_s"], ".3f"),
            f"{record['n_percent_points']}/{record['n_points']}",
            _format_number(record["speed_factor_what_if"], ".3f"),
        )
    console.print(whole_headers(stats))
    console.print(result.verdict())
    console.print(f"discrepancy: {result.discrepancy.summary()}")
    if result.printed_check is not None:
        console.print(f"paper's printed errors: {result.printed_check.summary()}")
    if out is not None:
        console.print(f"results written to {out}")
