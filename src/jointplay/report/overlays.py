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
from jointplay.report.figures import NOMINAL, check_format, method_colour, save, style
from jointplay.study.comparison import (
    NOMINAL as NOMINAL_METHOD,
)
from jointplay.study.comparison import (
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


def overlay_plots(
    result: MethodsComparison,
    folder: Path,
    *,
    title: str = "",
    individual: bool = True,
    figure_format: str = "png",
) -> list[Path]:
    """Measured points, each simulated steady cycle and the nominal (dashed), like Figs. 17–20.

    Writes ``overlay_{method}.png`` per method (with ``individual``; the nominal plot also
    shows the labelled what-if curve at the implied crank speed) and ``overlay.png`` with one
    panel per method. Units and crank angles are the measurement file's; each method in its
    colour of :data:`~jointplay.report.figures.METHOD_COLOURS`.

    Args:
        result: the comparison.
        folder: where the figures go.
        title: the figures' title.
        individual: also write one figure per method (``overlay.png`` is always written).
        figure_format: ``"png"``, or ``"svg"``/``"pdf"`` written beside the PNG.

    Returns:
        The PNGs written, ``overlay.png`` last.
    """
    plt = pyplot()
    check_format(figure_format)
    measurements = result.measurements
    conventions = measurements.conventions
    lo = float(np.min(measurements.crank_deg))
    nominal = next((c for c in result.comparisons if c.method == NOMINAL_METHOD), None)
    nominal_xy = None if nominal is None else _curve(nominal.cycle, conventions, lo)
    ylabel = f"rocker angular velocity ({conventions.unit}, " + (
        "CCW +)" if conventions.speed_sign == 1 else "CW +)"
    )
    xlabel = f"crank angle (deg, {conventions.angle_direction} from {conventions.angle_origin:g}°)"

    def draw(ax: Any, comparison: ExperimentComparison, *, what_if: bool) -> None:
        x, y = _curve(comparison.cycle, conventions, lo)
        if comparison.method != NOMINAL_METHOD:
            ax.plot(x, y, "-", linewidth=1.3, color=method_colour(comparison.method),
                    label=f"{comparison.method} (steady cycle)")  # fmt: skip
        if nominal_xy is not None:
            ax.plot(*nominal_xy, **NOMINAL, label="nominal (ideal joints)")
        if what_if and nominal_xy is not None:
            d = result.discrepancy
            ax.plot(
                nominal_xy[0],
                d.speed_factor * nominal_xy[1],
                ":",
                color="0.45",
                linewidth=1.2,
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
            f"{comparison.method}: RMS error {s.rms_error_percent:.1f} %, "
            f"largest {s.max_abs_error_percent:.1f} %",
            fontsize=9,
        )
        ax.legend(loc="best", fontsize=7)

    written = []
    with style():
        if individual:
            for comparison in result.comparisons:
                fig, ax = plt.subplots(figsize=(8, 4.5))
                draw(ax, comparison, what_if=comparison.method == NOMINAL_METHOD)
                ax.set_xlabel(xlabel)
                ax.set_ylabel(ylabel)
                if title:
                    fig.suptitle(title, fontsize=10)
                fig.tight_layout()
                path = folder / f"overlay_{comparison.method}.png"
                written.append(save(fig, path, figure_format)[0])
        n = len(result.comparisons)
        cols = min(n, 3)
        rows = math.ceil(n / cols)
        fig, axes = plt.subplots(rows, cols, figsize=(3.8 * cols, 2.9 * rows), squeeze=False,
                                 sharex=True, sharey=True)  # fmt: skip
        for ax, comparison in zip(axes.flat, result.comparisons, strict=False):
            draw(ax, comparison, what_if=False)
        for ax in axes[-1]:
            ax.set_xlabel(xlabel, fontsize=8)
        for ax in axes[:, 0]:
            ax.set_ylabel(ylabel, fontsize=8)
        for ax in list(axes.flat)[n:]:
            ax.set_visible(False)
        if title:
            fig.suptitle(title, fontsize=10)
        fig.tight_layout()
        written.append(save(fig, folder / "overlay.png", figure_format)[0])
    return written
