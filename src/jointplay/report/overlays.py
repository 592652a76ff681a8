"""The overlay plots of a comparison with measurements, like the paper's Figs. 17–20.

Measured points, each simulated steady cycle and the nominal kinematics (dashed), in the
measurement file's units and crank angles; only consumes a
:class:`~jointplay.study.comparison.MethodsComparison`.
"""

from __future__ import annotations

import math
from pathlib import Path
from typing import Any

import numpy as np

from jointplay.io.measurements import MeasurementConventions
from jointplay.report._mpl import pyplot
from jointplay.study.comparison import (
    NOMINAL,
    ExperimentComparison,
    MethodsComparison,
    SteadyCycle,
)


def _curve(cycle: SteadyCycle, conventions: MeasurementConventions, lo: float) -> tuple[Any, Any]:
    """The cycle against the file's crank angle in [lo, lo + 360], in the file's unit."""
    phi = conventions.crank_from_model(cycle.crank_deg)
    phi = lo + np.mod(phi - lo, 360.0)
    order = np.argsort(phi, kind="stable")
    x = np.append(phi[order], phi[order][0] + 360.0)
    y = conventions.speed_from_si(np.append(cycle.values[order], cycle.values[order][0]))
    return x, y


def overlay_plots(result: MethodsComparison, folder: Path, *, title: str = "") -> list[Path]:
    """Measured points, each simulated steady cycle and the nominal (dashed), like Figs. 17–20.

    Writes ``overlay_{method}.png`` per method (the nominal plot also shows the labelled what-if
    curve at the implied crank speed) and ``overlay.png`` with one panel per method. Units and
    crank angles are the measurement file's.
    """
    plt = pyplot()
    measurements = result.measurements
    conventions = measurements.conventions
    lo = float(np.min(measurements.crank_deg))
    nominal = next((c for c in result.comparisons if c.method == NOMINAL), None)
    nominal_xy = None if nominal is None else _curve(nominal.cycle, conventions, lo)
    ylabel = f"rocker angular velocity ({conventions.unit}, " + (
        "CCW +)" if conventions.speed_sign == 1 else "CW +)"
    )
    xlabel = f"crank angle (deg, {conventions.angle_direction} from {conventions.angle_origin:g}°)"

    def draw(ax: Any, comparison: ExperimentComparison, *, what_if: bool) -> None:
        x, y = _curve(comparison.cycle, conventions, lo)
        if comparison.method != NOMINAL:
            ax.plot(x, y, "-", linewidth=1.0, label=f"{comparison.method} (steady cycle)")
        if nominal_xy is not None:
            ax.plot(*nominal_xy, "--", color="0.3", linewidth=1.0, label="nominal (ideal joints)")
        if what_if and nominal_xy is not None:
            d = result.discrepancy
            ax.plot(
                nominal_xy[0],
                d.speed_factor * nominal_xy[1],
                ":",
                color="tab:red",
                linewidth=1.0,
                label=f"what-if, not applied: nominal at {d.implied_crank_rpm:.0f} RPM",
            )
        ax.plot(
            measurements.crank_deg,
            measurements.speed,
            "o",
            color="k",
            markersize=4,
            label="measured",
        )
        s = comparison.statistics
        ax.set_title(
            f"{comparison.method}: RMS {s.rms_error_percent:.1f} %, "
            f"max {s.max_abs_error_percent:.1f} %",
            fontsize=9,
        )
        ax.grid(True, alpha=0.3)
        ax.legend(loc="best", fontsize=7)

    written = []
    for comparison in result.comparisons:
        fig, ax = plt.subplots(figsize=(8, 4.5), dpi=110)
        draw(ax, comparison, what_if=comparison.method == NOMINAL)
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        if title:
            fig.suptitle(title, fontsize=10)
        fig.tight_layout()
        path = folder / f"overlay_{comparison.method}.png"
        fig.savefig(path)
        plt.close(fig)
        written.append(path)
    n = len(result.comparisons)
    cols = min(n, 2)
    rows = math.ceil(n / cols)
    fig, axes = plt.subplots(rows, cols, figsize=(6 * cols, 3.6 * rows), dpi=110, squeeze=False)
    for ax, comparison in zip(axes.flat, result.comparisons, strict=False):
        draw(ax, comparison, what_if=False)
        ax.set_xlabel(xlabel, fontsize=8)
        ax.set_ylabel(ylabel, fontsize=8)
    for ax in list(axes.flat)[n:]:
        ax.set_visible(False)
    if title:
        fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    path = folder / "overlay.png"
    fig.savefig(path)
    plt.close(fig)
    written.append(path)
    return written
