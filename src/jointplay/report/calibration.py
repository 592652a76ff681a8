"""Files and plots of a calibration (:mod:`jointplay.study.calibration`).

Per data set an overlay (measured points, the model at the start values, dashed, and at the
estimates) and a residual plot (measured − simulated before and after, in the file's unit);
``calibration.json`` (everything), ``calibration_points.csv`` and ``calibration_curves.csv``;
and the calibrated configuration ``calibrated.toml`` (:mod:`jointplay.io.config_writer`).
Only consumes a :class:`~jointplay.study.calibration.CalibrationResult`.
"""

from __future__ import annotations

import math
import re
from collections.abc import Mapping
from pathlib import Path
from typing import Any

from jointplay.io.config_writer import calibrated_config, write_config
from jointplay.io.output import write_csv, write_json
from jointplay.report._mpl import pyplot
from jointplay.report.figures import save
from jointplay.study.calibration import CalibrationResult, Dataset


def _slug(text: str) -> str:
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", text).strip("_") or "data"


def _axis_labels(dataset: Dataset) -> tuple[str, str]:
    conventions = dataset.measurements.conventions
    x = f"crank angle (deg, {conventions.angle_direction} from {conventions.angle_origin:g}°)"
    return x, f"{dataset.quantity} ({dataset.unit})"


def calibration_plots(
    result: CalibrationResult, folder: Path, figure_format: str = "png"
) -> list[Path]:
    """``overlay_{label}.png`` and ``residuals_{label}.png`` per data set (and their SVG or
    PDF copies when ``figure_format`` asks for one)."""
    plt = pyplot()
    written = []
    fitted = ", ".join(p.name for p in result.parameters)
    for dataset in result.datasets:
        label = dataset.label
        points = result.points[result.points["dataset"] == label]
        curves = result.curves[result.curves["dataset"] == label]
        xlabel, ylabel = _axis_labels(dataset)
        fig, ax = plt.subplots(figsize=(7.5, 4.5))
        if not curves.empty:
            ax.plot(curves["crank_deg"], curves["before"], "--", color="0.4", label="start values")
            ax.plot(curves["crank_deg"], curves["after"], "-", color="tab:blue", label="calibrated")
        ax.plot(points["crank_deg"], points["measured"], "o", color="k", ms=4, label="measured")
        ax.set_title(
            f"{label}: {result.model} model, fitted {fitted}\n"
            f"RMS error {result.rms_before:.2f} % → {result.rms_after:.2f} %",
            fontsize=9,
        )
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        written += save(fig, folder / f"overlay_{_slug(label)}.png", figure_format, dpi=120)

        fig, ax = plt.subplots(figsize=(7.5, 3.5))
        for column, style, name in (
            ("residual_before", "s--", "start values"),
            ("residual_after", "o-", "calibrated"),
        ):
            residual = dataset.from_si(points[column].to_numpy(dtype=float))
            ax.plot(points["crank_deg"], residual, style, ms=4, label=name)
        ax.axhline(0.0, color="0.5", linewidth=0.8)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(f"measured − simulated ({dataset.unit})")
        ax.set_title(f"{label}: residuals", fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        written += save(fig, folder / f"residuals_{_slug(label)}.png", figure_format, dpi=120)
    return written


def config_values(result: CalibrationResult) -> dict[str, float]:
    """The estimates that belong in a configuration file (one crank speed only)."""
    values = {k: v for k, v in result.values.items() if not k.startswith("crank-speed@")}
    return values


def config_header(result: CalibrationResult, source: str) -> str:
    """The comment lines of ``calibrated.toml``."""
    lines = [
        f"Calibrated by `jointplay calibrate` from {source}.",
        "Fitted (SI; 95 % interval):",
    ]
    for p in result.parameters:
        lines.append(f"  {p.name} = {p.value:.6g} {p.unit} ({p.ci95[0]:.6g} .. {p.ci95[1]:.6g})")
    if "phase" in result.values:
        lines.append(
            f"The phase ({math.degrees(result.values['phase']):+.3f} deg, counter-clockwise) "
            "belongs to the measurements: add it to their angle origin."
        )
    if any(p.name.startswith("crank-speed@") for p in result.parameters):
        lines.append("Each file had its own crank speed: the driver speed is left as it was.")
    lines.append(
        f"RMS error {result.rms_before:.3f} % -> {result.rms_after:.3f} % (paper's definition)."
    )
    for warning in result.warnings:
        lines.append(f"WARNING: {warning}")
    return "\n".join(lines)


def write_calibration(
    result: CalibrationResult,
    folder: Path,
    *,
    config_data: Mapping[str, Any] | None = None,
    config_source: str = "",
    exponent: float = 1.5,
    contact_law: str | None = None,
    extra: Mapping[str, Any] | None = None,
    plots: bool = True,
    figure_format: str = "png",
) -> list[Path]:
    """Write the calibration's files into ``folder`` (which exists).

    Args:
        config_data: the raw TOML of the mechanism's configuration; with it,
            ``calibrated.toml`` is written.
        config_source: where it came from, for the header.
        exponent, contact_law: the contact law's force exponent and name (for ``k``).
        extra: more entries for ``calibration.json`` (provenance).
    """
    written = []
    path = folder / "calibration.json"
    write_json(path, {**result.as_dict(), **(extra or {})})
    written.append(path)
    path = folder / "calibration_points.csv"
    write_csv(result.points, path)
    written.append(path)
    path = folder / "calibration_curves.csv"
    write_csv(result.curves, path)
    written.append(path)
    if config_data is not None:
        data = calibrated_config(
            config_data, config_values(result), exponent=exponent, contact_law=contact_law
        )
        path = folder / "calibrated.toml"
        write_config(path, data, config_header(result, config_source))
        written.append(path)
    if plots:
        written += calibration_plots(result, folder, figure_format)
    return written
