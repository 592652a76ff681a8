"""``jointplay calibrate``: fit the model's uncertain parameters to measurements.

Crank speed, crank-angle phase and link lengths on the nominal model; contact stiffness,
damping, restitution, clearance and friction on the steady cycle of the clearance model; with
standard errors, 95 % intervals, correlations and identifiability warnings (see
:mod:`jointplay.study.calibration` and docs/calibration.md). Measurement files are read as
``jointplay compare`` reads them, with the same conventions and options.

The module imports only Typer and Rich at the top; the study, NumPy and SciPy are imported
when the command runs, so that ``jointplay --help`` stays fast.
"""

from __future__ import annotations

import math
import sys
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
    provenance,
    status,
    whole_headers,
)
from jointplay.errors import ConfigError
from jointplay.units import parse_quantity

if TYPE_CHECKING:
    from jointplay.io.measurements import MeasurementConventions
    from jointplay.study.calibration import CalibrationResult, Dataset

#: Width of the tables when the output is not a terminal (files, pipes, tests), characters.
PIPE_WIDTH = 140
#: Units in which ``--initial`` values may be given without one (SI), per parameter.
_INITIAL_UNITS = {
    "crank-speed": "rad/s",
    "phase": "rad",
    "clearance": "m",
    "c_max": "N*s/m",
    "restitution": "",
    "friction": "",
}


def _opt(help_text: str, *names: str) -> Any:
    return typer.Option(*names, help=help_text)


def _split(values: list[str] | None) -> list[str]:
    return [item.strip() for text in values or [] for item in text.split(",") if item.strip()]


def _pairs(values: list[str] | None, option: str) -> dict[str, str]:
    out = {}
    for text in values or []:
        name, sep, value = text.partition("=")
        if not sep or not name.strip() or not value.strip():
            raise ConfigError(f"{option} must read NAME=VALUE, got {text!r}")
        out[name.strip()] = value.strip()
    return out


@app.command("calibrate")
def calibrate_command(
    preset: PresetOption = None,
    config: ConfigOption = None,
    rpm: RpmOption = None,
    measurements: Annotated[
        list[Path] | None,
        _opt(
            "CSV of crank angle (deg) and a measured response; '#' lines are comments. "
            "Repeat for several files (fitted jointly). Default: the paper's Table 7.",
            "--measurements",
            "-m",
        ),
    ] = None,
    column: Annotated[
        str | None,
        _opt(
            "Column of measured values (default: the other column of a two-column file; "
            "experiment_printed for Table 7, whose mbd_printed is the paper's simulation).",
            "--column",
            "--speed-column",
        ),
    ] = None,
    angle_column: Annotated[
        str, _opt("Column of crank angles, degrees.", "--angle-column")
    ] = "crank_deg",
    quantity: Annotated[
        str,
        _opt(
            "The simulated response measured: omega4 (rocker speed, default), omega3, alpha4 "
            "(rad/s^2), F_O2 (N), torque (N*m), ...",
            "--quantity",
        ),
    ] = "omega4",
    unit: Annotated[
        str | None,
        _opt(
            "Unit of the measured values: for angular speeds deg/s (default; Table 7's 'RPM' "
            "read as deg/s), rpm or rad/s; for other responses any unit of their kind "
            "(default SI: rad/s^2, N, N*m).",
            "--unit",
        ),
    ] = None,
    crank_direction: CrankDirectionOption = "cw",
    angle_direction: AngleDirectionOption = "cw",
    angle_origin: AngleOriginOption = "0 deg",
    speed_positive: SpeedPositiveOption = "ccw",
    rpm_of: Annotated[
        list[str] | None,
        _opt(
            "Crank speed of one file's run, FILE=SPEED with a unit (e.g. run2.csv=300rpm); "
            "repeatable. Files without one ran at the mechanism's speed (or --rpm).",
            "--rpm-of",
        ),
    ] = None,
    fit: Annotated[
        list[str] | None,
        _opt(
            "Parameters to fit, comma-separated: crank-speed, phase, crank-length, "
            "coupler-length, rocker-length, ground-length (default crank-speed,phase).",
            "--fit",
        ),
    ] = None,
    fit_more: Annotated[
        list[str] | None,
        _opt(
            "Contact parameters fitted on the clearance model's steady cycle, comma-separated: "
            "k, c_max, clearance, restitution, friction.",
            "--fit-more",
        ),
    ] = None,
    initial: Annotated[
        list[str] | None,
        _opt(
            "Start value NAME=VALUE with a unit, e.g. crank-speed=230rpm, phase=2deg, "
            "k=3e4N/mm^1.5 (repeatable).",
            "--initial",
        ),
    ] = None,
    loss: Annotated[
        str,
        _opt(
            "linear (least squares, default) or a robust loss: soft_l1, huber, cauchy, arctan.",
            "--loss",
        ),
    ] = "linear",
    max_nfev: Annotated[
        int | None, _opt("Largest number of model evaluations.", "--max-nfev")
    ] = None,
    contact: Annotated[
        str | None,
        _opt(
            "Contact law of the clearance model (default: the config's [simulation] contact, "
            "else impact with the paper's Table 3 values).",
            "--contact",
        ),
    ] = None,
    joints: Annotated[
        str | None,
        _opt(
            "Clearance joints, comma-separated (default: every joint with a clearance).", "--joints"
        ),
    ] = None,
    settle: Annotated[
        int,
        _opt("Start-up revolutions left out before the evaluated one (default 2).", "--settle"),
    ] = 2,
    as_json: Annotated[
        bool,
        typer.Option("--json", help="Print parameters, RMS before/after and warnings as JSON."),
    ] = False,
    out: Annotated[
        Path | None,
        typer.Option(
            "--out",
            "-o",
            help="Write calibration.json, points/curves CSV, overlay and residual PNGs and "
            "calibrated.toml to this folder.",
        ),
    ] = None,
    plots: Annotated[bool, typer.Option("--plots/--no-plots", help="Write PNG plots.")] = True,
    force: ForceOption = False,
    progress: ProgressOption = True,
    figure_format: FigureFormatOption = "png",
) -> None:
    """Fit crank speed, phase, link lengths or contact parameters to measurements.

    Least squares (scipy.optimize.least_squares) within bounds from physics and tolerances.

    Standard errors from the Jacobian at the optimum: cov = s^2 (J^T J)^-1, s^2 = RSS/(m - p).

    95 % intervals with Student-t; warns when the data cannot determine a parameter.

    Error % = (measured - simulated) / simulated x 100, as the paper defines it.
    See docs/calibration.md.
    """
    figure_format = check_figure_format(figure_format)
    from jointplay.dynamics.cycles import settle_revolutions
    from jointplay.dynamics.setup import contact_from_strings
    from jointplay.io.config import simulation_settings
    from jointplay.io.config_writer import source_config
    from jointplay.io.measurements import DIRECTIONS, SPEED_UNITS, MeasurementConventions
    from jointplay.io.output import json_text, output_dir
    from jointplay.model.summary import mechanism_summary
    from jointplay.settings.mechanism import mechanism_from_options
    from jointplay.study import calibration as cal

    angular = quantity.startswith("omega")
    si_unit, _ = cal.response_unit(quantity)
    conventions = MeasurementConventions(
        unit=choice(unit or "deg/s", "--unit", tuple(SPEED_UNITS)) if angular else "rad/s",
        crank_direction=choice(crank_direction, "--crank-direction", DIRECTIONS),
        angle_direction=choice(angle_direction, "--angle-direction", DIRECTIONS),
        angle_origin=math.degrees(parse_quantity(angle_origin, "rad", field="--angle-origin")),
        speed_sign=1 if choice(speed_positive, "--speed-positive", DIRECTIONS) == "ccw" else -1,
    )
    unit_text = (unit or si_unit) if not angular else conventions.unit
    unit_factor = 1.0 if angular else _unit_factor(unit_text, si_unit)
    if loss not in cal.LOSSES:
        raise ConfigError(f"--loss must be one of {', '.join(cal.LOSSES)}, got {loss!r}")
    if max_nfev is not None and max_nfev < 1:
        raise ConfigError(f"--max-nfev must be >= 1, got {max_nfev}")
    settle_revolutions(settle, "--settle")
    names = _split(fit) or ["crank-speed", "phase"]
    more = _split(fit_more)
    for name in more:
        if name not in cal.DYNAMIC_PARAMETERS:
            raise ConfigError(
                f"--fit-more: {name!r} is not a contact parameter; use some of "
                f"{', '.join(cal.DYNAMIC_PARAMETERS)} (kinematic ones go in --fit)"
            )
    names = list(dict.fromkeys(names + more))
    speeds = {
        key: parse_quantity(value, "rad/s", field=f"--rpm-of {key}")
        for key, value in _pairs(rpm_of, "--rpm-of").items()
    }
    datasets = _datasets(
        measurements, column, angle_column, conventions, quantity, unit_factor, unit_text, speeds
    )
    mechanism = mechanism_from_options(preset, config, rpm)
    table = simulation_settings(config)
    if contact is not None:
        table = {**table, "contact": contact}
    # the IMPACT law unless told: its stiffness k is what a calibration fits (the physical
    # default's stiffness comes from the geometry; docs/contact.md)
    contact_settings = contact_from_strings({"contact": "impact", **table})
    joint_list = tuple(_split([joints])) if joints else None
    if joint_list is None and table.get("joints"):
        raw = table["joints"]
        joint_list = tuple(raw) if isinstance(raw, list) else tuple(_split([str(raw)]))
    settings = cal.DynamicSettings(
        contact=contact_settings,
        clearance=None
        if table.get("clearance") is None
        else parse_quantity(table["clearance"], "m", field="[simulation] clearance"),
        joints=joint_list,
        settle=settle,
    )
    starts = _initial_values(_pairs(initial, "--initial"), contact_settings)
    unused = [
        name
        for name in starts
        if name not in names and not (name.startswith("crank-speed") and "crank-speed" in names)
    ]
    if unused:
        raise ConfigError(
            f"--initial names {', '.join(unused)}, which is not fitted; add it to --fit or "
            "--fit-more"
        )
    config_data = source_config(preset, config) if out is not None else None

    def run() -> CalibrationResult:
        what = "clearance model" if any(n in cal.DYNAMIC_PARAMETERS for n in names) else "nominal"
        with (
            compiling_kernels(needed=what != "nominal"),
            status(progress, f"fitting {', '.join(names)} on the {what} model"),
        ):
            return cal.calibrate(
                mechanism,
                datasets,
                names,
                settings=settings,
                initial=starts,
                loss=loss,
                max_nfev=max_nfev,
            )

    if out is not None:
        from jointplay.report.calibration import write_calibration

        with output_dir(out, force=force, inputs=(config, *(measurements or ()))) as folder:
            result = run()
            write_calibration(
                result,
                folder,
                config_data=config_data,
                config_source=str(config)
                if config is not None
                else f"preset {preset or 'paper-fourbar'}",
                exponent=cal.stiffness_exponent(contact_settings),
                contact_law=contact_settings.law,
                extra={"provenance": provenance({"mechanism": mechanism_summary(mechanism)})},
                plots=plots,
                figure_format=figure_format,
            )
    else:
        result = run()
    for warning in result.warnings:
        print(f"jointplay: warning: {warning}", file=sys.stderr)
    if as_json:
        print(json_text(result.as_json()))
        return
    _print(result, out)


def _unit_factor(unit: str, si_unit: str) -> float:
    """SI units per ``unit`` (e.g. deg/s^2 → π/180)."""
    return parse_quantity(f"1 {unit}", si_unit, field="--unit")


def _initial_values(pairs: dict[str, str], contact: Any) -> dict[str, float]:
    from jointplay.study.calibration import stiffness_exponent

    out = {}
    for name, text in pairs.items():
        field = f"--initial {name}"
        if name == "k":
            exponent = stiffness_exponent(contact)
            unit = "N/m" if exponent == 1 else f"N/m^{exponent:g}"
            out[name] = parse_quantity(text, unit, field=field)
        elif name.endswith("-length"):
            out[name] = parse_quantity(text, "m", field=field)
        elif name.startswith("crank-speed"):
            out[name] = parse_quantity(text, "rad/s", field=field)
        elif name in _INITIAL_UNITS:
            unit = _INITIAL_UNITS[name]
            out[name] = parse_quantity(text, unit or "1", field=field, allow_bare=not unit)
        else:
            out[name] = math.nan  # unknown: calibrate names the parameters it knows
    return out


def _datasets(
    paths: list[Path] | None,
    column: str | None,
    angle_column: str,
    conventions: MeasurementConventions,
    quantity: str,
    unit_factor: float,
    unit: str,
    speeds: dict[str, float],
) -> list[Dataset]:
    """One data set per file (or Table 7's column), each with its run's crank speed."""
    from jointplay.io.measurements import PAPER_TABLE7_COLUMNS, paper_table7, read_measurements
    from jointplay.study.calibration import Dataset

    found: list[Dataset] = []
    if not paths:
        table = paper_table7(conventions)
        chosen = column or PAPER_TABLE7_COLUMNS["speed"]
        if angle_column != PAPER_TABLE7_COLUMNS["angle"]:
            raise ConfigError(
                f"--angle-column: Table 7's crank angles are in {PAPER_TABLE7_COLUMNS['angle']!r}"
            )
        if chosen == PAPER_TABLE7_COLUMNS["model"]:
            assert table.model is not None
            from dataclasses import replace

            table = replace(table, speed=table.model, speed_column=chosen)
        elif chosen != PAPER_TABLE7_COLUMNS["speed"]:
            raise ConfigError(
                f"--column: Table 7 has no value column {chosen!r}; use "
                f"{PAPER_TABLE7_COLUMNS['speed']} or {PAPER_TABLE7_COLUMNS['model']}"
            )
        unknown = set(speeds) - {"table7", chosen}
        if unknown:
            raise ConfigError(f"--rpm-of names no measurement file: {', '.join(sorted(unknown))}")
        speed = speeds.get("table7", speeds.get(chosen))
        found.append(Dataset(table, quantity, speed, unit_factor, unit, label=chosen))
        return found
    used: set[str] = set()
    labels: set[str] = set()
    for path in paths:
        data = read_measurements(
            path, angle_column=angle_column, speed_column=column, conventions=conventions
        )
        keys = [key for key in (str(path), path.name, path.stem) if key in speeds]
        used.update(keys)
        label = path.stem or "data"
        n = 2
        while label in labels:
            label, n = f"{path.stem}-{n}", n + 1
        labels.add(label)
        found.append(
            Dataset(
                data,
                quantity,
                speeds[keys[0]] if keys else None,
                unit_factor,
                unit,
                label=label,
            )
        )
    unknown = set(speeds) - used
    if unknown:
        raise ConfigError(f"--rpm-of names no measurement file: {', '.join(sorted(unknown))}")
    return found


def _print(result: CalibrationResult, out: Path | None) -> None:
    console = Console(highlight=False, soft_wrap=True)
    if not console.is_terminal:
        console.width = PIPE_WIDTH
    for d in result.datasets:
        console.print(
            f"measurements: {d.measurements.source} ({d.label}: {d.quantity} in {d.unit}, "
            f"{d.measurements.crank_deg.size} points)"
        )
    console.print(
        f"model: {result.model}; loss {result.loss}; {result.nfev} evaluations; "
        f"{result.dof} degrees of freedom; {result.message}"
    )
    table = Table(title="fitted parameters (SI; 95 % interval, Student-t)", box=None)
    for name in ("parameter", "value", "stderr", "95 % interval", "unit", "start", "as"):
        table.add_column(name, justify="left" if name in ("parameter", "unit", "as") else "right")
    for p in result.parameters:
        table.add_row(
            p.name,
            f"{p.value:.6g}",
            f"{p.stderr:.3g}",
            f"{p.ci95[0]:.6g} .. {p.ci95[1]:.6g}",
            p.unit,
            f"{p.initial:.6g}",
            _friendly(p.name, p.value, p.ci95),
        )
    console.print(whole_headers(table))
    names = [p.name for p in result.parameters]
    if len(names) > 1:
        corr = Table(title="correlation", box=None)
        corr.add_column("")
        for name in names:
            corr.add_column(name, justify="right")
        for name, row in zip(names, result.correlation, strict=True):
            corr.add_row(name, *(f"{v:+.3f}" if math.isfinite(v) else "-" for v in row))
        console.print(whole_headers(corr))
    b, a = result.before, result.after
    console.print(
        f"RMS error {b.rms_error_percent:.2f} % -> {a.rms_error_percent:.2f} %, max |error| "
        f"{b.max_abs_error_percent:.2f} % -> {a.max_abs_error_percent:.2f} % "
        f"({a.n_percent_points} points; error % = (measured - simulated) / simulated x 100)"
    )
    if result.warnings:
        for warning in result.warnings:
            console.print(f"warning: {warning}")
    else:
        console.print("no identifiability warnings")
    if out is not None:
        console.print(f"results written to {out}")


def _friendly(name: str, value: float, ci: tuple[float, float]) -> str:
    """The value in everyday units (RPM, degrees, mm, µm)."""
    if name.startswith("crank-speed"):
        f = 30 / math.pi
        return f"{value * f:.2f} RPM ({ci[0] * f:.2f} .. {ci[1] * f:.2f})"
    if name == "phase":
        f = 180 / math.pi
        return f"{value * f:+.3f} deg ({ci[0] * f:+.3f} .. {ci[1] * f:+.3f})"
    if name.endswith("-length"):
        return f"{value * 1e3:.4f} mm ({ci[0] * 1e3:.4f} .. {ci[1] * 1e3:.4f})"
    if name == "clearance":
        return f"{value * 1e6:.3f} µm ({ci[0] * 1e6:.3f} .. {ci[1] * 1e6:.3f})"
    return ""
