"""Commands about the mechanism itself: presets, show, kinematics."""

from __future__ import annotations

import math
import sys
from typing import Annotated

import typer
from rich.console import Console
from rich.table import Table

from jointplay.cli._app import app
from jointplay.cli._common import (
    ConfigOption,
    DirectionOption,
    FigureFormatOption,
    ForceOption,
    GravityOption,
    OutOption,
    PresetOption,
    RpmOption,
    StartAngleOption,
    check_figure_format,
    provenance,
    whole_headers,
)
from jointplay.cli._simulation import SETTING_OPTIONS
from jointplay.errors import ConfigError
from jointplay.settings.mechanism import mechanism_from_options, quantity_option

console = Console()


@app.command("presets")
def presets_command() -> None:
    """List the mechanisms that ship with jointplay: each with its source and what a run of
    it reproduces (`jointplay show PRESET` prints the whole file)."""
    from jointplay.io.config import list_presets

    table = Table("preset", "description", box=None)
    for preset in list_presets():
        table.add_row(
            preset.name,
            f"{preset.description}\nsource: {preset.source}\nreproduces: {preset.reproduces}",
        )
    console.print(whole_headers(table), markup=False, highlight=False)


@app.command("show")
def show_command(
    preset: Annotated[str, typer.Argument(help="Preset name (see `jointplay presets`).")],
) -> None:
    """Print a preset as TOML that you can copy, edit and pass with --config.

    Its [mechanism] table states its source and what it reproduces; a [simulation] table,
    where it has one, the contact of that source (the command line's options override it).
    """
    from jointplay.io.config import preset_text

    print(preset_text(preset), end="")


#: The most rows ``jointplay kinematics`` writes (one per crank step).
MAX_ROWS = 1_000_000


@app.command("kinematics")
def kinematics_command(
    out: OutOption,
    force: ForceOption = False,
    preset: PresetOption = None,
    config: ConfigOption = None,
    rpm: RpmOption = None,
    direction: DirectionOption = None,
    start_angle: StartAngleOption = None,
    gravity: GravityOption = None,
    step: Annotated[
        str,
        typer.Option(
            "--step", help="Crank-angle step with a unit, e.g. '1 deg' (must divide a turn)."
        ),
    ] = "1 deg",
    method: Annotated[
        str,
        typer.Option("--method", help="auto (closed form if available), closed-form or general."),
    ] = "auto",
    plots: Annotated[bool, typer.Option("--plots/--no-plots", help="Write PNG plots.")] = True,
    figure_format: FigureFormatOption = "png",
) -> None:
    """Nominal kinematics and inverse dynamics (ideal joints) over one crank revolution.

    Writes DIR/kinematics.csv (one row per crank step), DIR/summary.json and PNG plots.
    A four-bar whose transmission angle leaves 40°–140° (the design guideline, Norton,
    Design of Machinery §3.3) gets a warning, in the summary's diagnostics and on stderr.
    """
    from jointplay.dynamics.diagnostics import check_transmission_angle
    from jointplay.dynamics.nominal import nominal_analysis
    from jointplay.io.output import output_dir, write_csv, write_json

    figure_format = check_figure_format(figure_format)
    with output_dir(out, force=force, inputs=(config,)) as folder:
        mechanism = mechanism_from_options(preset, config, rpm, direction, start_angle, gravity)
        step_deg = math.degrees(
            quantity_option(step, "rad", "--step", example="deg", positive=True)
        )
        if 360.0 / step_deg > MAX_ROWS:
            raise ConfigError(
                f"--step {step!r} gives {360.0 / step_deg:.3g} rows (at most {MAX_ROWS:.0e}); "
                f"give at least '{360.0 / MAX_ROWS:g} deg'"
            )
        result = nominal_analysis(mechanism, step_deg=step_deg, method=method)
        findings = [d for d in [check_transmission_angle(mechanism)] if d is not None]
        write_csv(result.table, folder / "kinematics.csv")
        write_json(
            folder / "summary.json",
            {
                **result.summary,
                "diagnostics": [finding.as_dict() for finding in findings],
                "provenance": provenance(result.summary["configuration"]),
            },
        )
        if plots:
            from jointplay.report.plots import kinematics_plots

            kinematics_plots(result.table, folder, mechanism.name, figure_format=figure_format)
    _print_summary(result.summary, out)
    for finding in findings:  # one line each, on stderr, as simulate's diagnostics
        print(f"jointplay: {finding.line(SETTING_OPTIONS)}", file=sys.stderr)


#: The unit of each column of kinematics.csv, by prefix (SI, as the file and summary.json).
COLUMN_UNITS = (
    ("theta", "deg"),
    ("omega", "rad/s"),
    ("alpha", "rad/s²"),
    ("F_", "N"),
    ("M_", "N·m"),
    ("torque", "N·m"),
    ("slider_x", "m"),
    ("slider_v", "m/s"),
    ("slider_a", "m/s²"),
)


def column_unit(name: str) -> str | None:
    """The unit of a kinematics.csv column (``None``: not printed)."""
    return next((unit for prefix, unit in COLUMN_UNITS if name.startswith(prefix)), None)


def _print_summary(summary: dict, out: object) -> None:
    columns = summary["columns"]
    table = Table("quantity", "unit", "min", "max", "peak |value|", "at crank (deg)", box=None)
    for name, stats in columns.items():
        unit = column_unit(name)
        if unit is not None:
            table.add_row(
                name,
                unit,
                f"{stats['min']:.4g}",
                f"{stats['max']:.4g}",
                f"{stats['peak_abs']:.4g}",
                f"{stats['peak_abs_at_crank_deg']:.0f}",
            )
    console.print(whole_headers(table))
    if "grashof" in summary:
        console.print(
            f"Grashof class: {summary['grashof']['class']}; transmission angle "
            f"{summary['transmission_angle_deg']['min']:.1f}°–{summary['transmission_angle_deg']['max']:.1f}°"
            + (
                f"; rocker swing {summary['rocker_swing_deg']:.2f}°"
                if "rocker_swing_deg" in summary
                else ""
            )
        )
    console.print(f"results written to {out}")
