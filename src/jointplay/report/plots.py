"""Static figures of results; only consumers of result tables, no physics here.

Every figure is written as PNG and, when ``figure_format`` asks, also as SVG or PDF
(:func:`jointplay.report.figures.save`). Lines are thinned to what the eye can see
(:func:`jointplay.report.figures.thin`, extremes kept), axes are linear and labelled with
their unit. Matplotlib is imported lazily with the non-interactive Agg backend, so the core of
jointplay imports without it.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from jointplay.report._mpl import pyplot
from jointplay.report.figures import (
    CONTACT_COLOURS,
    LAW_COLOURS,
    NOMINAL_STYLES,
    SERIES_COLOURS,
    check_format,
    save,
    style,
    thin,
    tick_formatter,
)
from jointplay.study.published import PAPER_PUBLISHED

if TYPE_CHECKING:
    from jointplay.dynamics.simulate import SimulationResult
    from jointplay.study.ecs import EcsSweep

UNITS = {"omega": "rad/s", "alpha": "rad/s²", "F": "N", "torque": "N·m"}
#: Column prefixes drawn by the simulation and kinematics figures: file, words, unit, and
#: the factor from the SI column to the plotted unit.
GROUPS = (
    ("omega", "angular_velocity", "angular velocity", "rad/s", 1.0),
    ("alpha", "angular_acceleration", "angular acceleration", "rad/s²", 1.0),
    ("F_", "joint_forces", "joint force", "N", 1.0),
)
#: The slider of a slider-crank: column, words, unit and factor from SI.
SLIDER = (
    ("slider_x", "slider position", "mm", 1e3),
    ("slider_v", "slider velocity", "m/s", 1.0),
    ("slider_a", "slider acceleration", "m/s²", 1.0),
)
#: Crank angle shown as the start-up when no settling revolutions were simulated, deg.
STARTUP_DEG = 30.0


def symbol(column: str) -> str:
    """``omega3`` → ``ω3``, ``alpha4`` → ``α4``, ``F_A`` → ``F A``."""
    for prefix, greek in (("omega", "ω"), ("alpha", "α")):
        if column.startswith(prefix):
            return greek + column[len(prefix) :]
    return column.replace("_", " ")


def line_plot(
    path: Path,
    x: Any,
    series: Sequence[tuple[str, Any]],
    *,
    xlabel: str,
    ylabel: str,
    title: str,
    overlays: Sequence[tuple[str, Any, Any]] = (),
    figure_format: str = "png",
) -> Path:
    """Plot ``series`` (label, y) against ``x`` and ``overlays`` (label, x, y), one distinct
    line style each; every line thinned. Returns the PNG."""
    plt = pyplot()
    check_format(figure_format)
    with style():
        fig, ax = plt.subplots(figsize=(8, 4.2))
        for colour, (label, y) in zip(_colours(len(series)), series, strict=True):
            ax.plot(*thin(x, y), label=label, linewidth=1.2, color=colour)
        for k, (label, ox, oy) in enumerate(overlays):
            ax.plot(
                *thin(ox, oy),
                linestyle=NOMINAL_STYLES[k % len(NOMINAL_STYLES)],
                label=label,
                linewidth=1.0,
                color="0.2",
            )
        ax.set_xlabel(xlabel)
        ax.set_ylabel(ylabel)
        ax.yaxis.set_major_formatter(tick_formatter())
        ax.set_title(title)
        if series or overlays:
            ax.legend(loc="best")
        fig.tight_layout()
        return save(fig, path, figure_format)[0]


def _colours(n: int) -> list[str]:
    return [SERIES_COLOURS[i % len(SERIES_COLOURS)] for i in range(n)]


def kinematics_plots(
    table: pd.DataFrame, folder: Path, title: str, *, figure_format: str = "png"
) -> list[Path]:
    """Angular velocities, accelerations, the slider (if any), joint forces and the driving
    torque against crank angle (ideal joints, one revolution)."""
    x = table["crank_deg"]
    written = []
    for prefix, name, words, unit, _ in GROUPS:
        columns = [c for c in table.columns if c.startswith(prefix)]
        if columns:
            written.append(
                line_plot(
                    folder / f"{name}.png",
                    x,
                    [(f"{symbol(c)}", table[c]) for c in columns],
                    xlabel="crank angle (deg)",
                    ylabel=f"{words} ({unit})",
                    title=f"{title}: {words}",
                    figure_format=figure_format,
                )
            )
    for column, words, unit, factor in SLIDER:
        if column in table:
            written.append(
                line_plot(
                    folder / f"{column}.png",
                    x,
                    [(words, table[column] * factor)],
                    xlabel="crank angle (deg)",
                    ylabel=f"{words} ({unit})",
                    title=f"{title}: {words}",
                    figure_format=figure_format,
                )
            )
    written.append(
        line_plot(
            folder / "torque.png",
            x,
            [("driving torque", table["torque"])],
            xlabel="crank angle (deg)",
            ylabel="torque (N·m)",
            title=f"{title}: driving torque",
            figure_format=figure_format,
        )
    )
    return written


def _tiled_nominal(nominal: pd.DataFrame, column: str, crank: Any) -> tuple[Any, Any]:
    """The nominal periodic curve repeated over the crank-angle range of a simulation."""
    lo, hi = float(np.min(crank)), float(np.max(crank))
    base = nominal["crank_deg"].to_numpy() - nominal["crank_deg"].iloc[0]
    start = nominal["crank_deg"].iloc[0]
    turns = range(int(np.floor((lo - start) / 360.0)), int(np.ceil((hi - start) / 360.0)) + 1)
    x = np.concatenate([start + base + 360.0 * k for k in turns])
    y = np.concatenate([nominal[column].to_numpy() for _ in turns])
    keep = (x >= lo) & (x <= hi)
    return x[keep], y[keep]


def _panels(crank: np.ndarray, analysed_from_deg: float | None) -> list[tuple[str, np.ndarray]]:
    """The crank-angle windows drawn side by side: the start-up (if one was simulated) and
    the analysed (steady) revolutions; one window over everything without ``analysed_from_deg``."""
    if analysed_from_deg is None or crank.size == 0:
        return [("", np.ones(crank.shape, dtype=bool))]
    start = float(crank[0])
    if analysed_from_deg > start:
        startup = crank < analysed_from_deg
        steady = crank >= analysed_from_deg
        return [("start-up (settling, left out of the statistics)", startup), ("analysed", steady)]
    early = crank <= start + STARTUP_DEG
    return [
        (f"start-up: the first {STARTUP_DEG:g}° of crank", early),
        (f"after the first {STARTUP_DEG:g}°", ~early),
    ]


def simulation_plots(
    steps: pd.DataFrame,
    nominal: pd.DataFrame,
    clearances: Sequence[Any],
    folder: Path,
    title: str,
    *,
    analysed_from_deg: float | None = None,
    figure_format: str = "png",
) -> list[Path]:
    """ω, α, the slider (if any) and joint forces against crank angle with the nominal curves
    (each in its series' colour, a distinct dash per series), and the journal orbits.

    Args:
        steps: one row per integrator step (``SimulationResult.steps``).
        nominal: the nominal (ideal-joint) table over one revolution.
        clearances: the clearance joints (their orbits are drawn).
        folder: where the PNGs (and SVG/PDF) go.
        title: the mechanism's name, in the figure titles.
        analysed_from_deg: the crank angle where the analysed revolutions begin; when the
            simulation started earlier (settling revolutions) or not steadily, the start-up
            and the analysed revolutions are drawn in separate panels, each on its own scale,
            so that a start-up impact does not flatten the running curves. ``None``: one panel.
        figure_format: ``"png"``, or ``"svg"``/``"pdf"`` written beside the PNG.

    Returns:
        The PNGs written.
    """
    check_format(figure_format)
    crank = steps["crank_deg"].to_numpy()
    panels = _panels(crank, analysed_from_deg)
    written = []
    for prefix, name, words, unit, factor in GROUPS:
        columns = [c for c in steps.columns if c.startswith(prefix)]
        if columns:
            written.append(
                _time_figure(
                    folder / f"{name}.png",
                    steps,
                    nominal,
                    [(c, symbol(c), factor) for c in columns],
                    panels,
                    ylabel=f"{words} ({unit})",
                    title=f"{title}: {words} with clearance (nominal: ideal joints)",
                    figure_format=figure_format,
                )
            )
    slider = [(c, w, u, f) for c, w, u, f in SLIDER if c in steps]
    for column, words, unit, factor in slider:
        written.append(
            _time_figure(
                folder / f"{column}.png",
                steps,
                nominal,
                [(column, words, factor)],
                panels,
                ylabel=f"{words} ({unit})",
                title=f"{title}: {words} with clearance (nominal: ideal joints)",
                figure_format=figure_format,
            )
        )
    if clearances:
        written.append(
            orbit_plot(
                steps,
                clearances,
                folder / "journal_orbits.png",
                title,
                analysed_from_deg=analysed_from_deg,
                figure_format=figure_format,
            )
        )
    return written


def simulation_figures(
    result: SimulationResult, folder: Path, title: str, *, figure_format: str = "png"
) -> list[Path]:
    """:func:`simulation_plots` of a simulation: start-up and analysed revolutions apart
    whenever settling revolutions were simulated or the start was not steady."""
    steps = result.steps
    crank = steps["crank_deg"].to_numpy()
    analysed: float | None = None
    if crank.size and (result.settle > 0 or result.start.mode != "steady"):
        direction = 1.0 if crank[-1] >= crank[0] else -1.0
        analysed = float(crank[0]) + direction * 360.0 * result.settle
    nominal = result.nominal
    if nominal is None:
        raise ValueError("simulation_figures needs simulate(..., nominal=True)")
    return simulation_plots(
        steps,
        nominal,
        result.system.clearances,
        folder,
        title,
        analysed_from_deg=analysed,
        figure_format=figure_format,
    )


def _time_figure(
    path: Path,
    steps: pd.DataFrame,
    nominal: pd.DataFrame,
    series: Sequence[tuple[str, str, float]],
    panels: Sequence[tuple[str, np.ndarray]],
    *,
    ylabel: str,
    title: str,
    figure_format: str,
) -> Path:
    """Series against crank angle in one panel per window, nominal curves in the series'
    colours with a distinct dash each."""
    plt = pyplot()
    crank = steps["crank_deg"].to_numpy()
    widths = [1.0 if len(panels) == 1 or i else 0.6 for i in range(len(panels))]
    with style():
        fig, axes = plt.subplots(
            1,
            len(panels),
            figsize=(9 if len(panels) == 1 else 11, 4.2),
            squeeze=False,
            gridspec_kw={"width_ratios": widths},
        )
        for ax, (label, mask) in zip(axes[0], panels, strict=True):
            x = crank[mask]
            for k, (column, words, factor) in enumerate(series):
                colour = SERIES_COLOURS[k % len(SERIES_COLOURS)]
                ax.plot(
                    *thin(x, steps[column].to_numpy()[mask] * factor),
                    color=colour,
                    linewidth=1.1,
                    label=f"{words} with clearance",
                )
                if x.size and column in nominal:
                    nx, ny = _tiled_nominal(nominal, column, x)
                    ax.plot(
                        nx,
                        ny * factor,
                        color=colour,
                        alpha=0.8,
                        linewidth=1.3,
                        linestyle=NOMINAL_STYLES[k % len(NOMINAL_STYLES)],
                        label=f"{words} nominal",
                    )
            ax.yaxis.set_major_formatter(tick_formatter())
            if x.size:
                revolution_axis(ax, float(crank[0]), float(x.min()), float(x.max()))
            else:
                ax.set_xlabel("crank angle (deg)")
            if label:
                ax.set_title(label, fontsize=9, pad=14)  # above the revolutions' numbers
        axes[0, 0].set_ylabel(ylabel)
        axes[0, -1].legend(loc="best", ncol=2 if len(series) > 2 else 1)
        fig.suptitle(title, fontsize=10)
        fig.tight_layout()
        return save(fig, path, figure_format)[0]


def revolution_axis(ax: Any, start: float, low: float, high: float) -> None:
    """A crank-angle axis read per revolution: ticks every 90° show the angle turned within
    the revolution (0-360), each revolution's number labels the top edge at its middle
    (outside the data), and the boundaries between revolutions are faint lines
    (``start``: the crank angle the run started at)."""
    from matplotlib.ticker import FuncFormatter, MultipleLocator

    def within(x: float, _: Any = None) -> str:
        turned = (x - start) % 360.0
        return "360" if turned < 1e-6 and x > low and abs(x - high) < 1e-6 else f"{turned:.0f}"

    ax.set_xlim(low, high)
    ax.xaxis.set_major_locator(MultipleLocator(90.0, offset=start % 90.0))
    ax.xaxis.set_major_formatter(FuncFormatter(within))
    middles, names = [], []
    for k in range(int(np.floor((low - start) / 360.0)), int(np.ceil((high - start) / 360.0))):
        left, right = start + 360.0 * k, start + 360.0 * (k + 1)
        if left > low:
            ax.axvline(left, color="0.75", linewidth=0.6, zorder=0)
        if min(right, high) - max(left, low) > 0.15 * (high - low):
            middles.append((max(left, low) + min(right, high)) / 2.0)
            names.append(f"revolution {k + 1}")
    top = ax.secondary_xaxis("top")
    top.set_xticks(middles, names, fontsize=7, color="0.35")
    top.tick_params(length=0)
    ax.set_xlabel("crank angle within the revolution (deg)")


def orbit_plot(
    steps: pd.DataFrame,
    clearances: Sequence[Any],
    path: Path,
    title: str,
    *,
    analysed_from_deg: float | None = None,
    figure_format: str = "png",
) -> Path:
    """Journal-centre orbit of each clearance joint and its clearance circle, to scale (µm).

    Each panel's limits take in the whole orbit, so a trace beyond the circle (penetration)
    shows; the panel title gives the largest eccentricity. With ``analysed_from_deg``, the
    start-up is drawn faint and the analysed revolutions solid.
    """
    plt = pyplot()
    count = len(clearances)
    crank = steps["crank_deg"].to_numpy()
    analysed = (
        np.ones(crank.shape, dtype=bool)
        if analysed_from_deg is None or analysed_from_deg <= crank[0]
        else crank >= analysed_from_deg
    )
    circle = np.linspace(0, 2 * np.pi, 181)
    with style():
        fig, axes = plt.subplots(1, count, figsize=(3.4 * count, 3.7), squeeze=False)
        for ax, clearance in zip(axes[0], clearances, strict=True):
            name = clearance.joint
            c_um = clearance.clearance * 1e6
            ex = steps[f"ex_{name}"].to_numpy() * 1e6
            ey = steps[f"ey_{name}"].to_numpy() * 1e6
            ax.plot(c_um * np.cos(circle), c_um * np.sin(circle), color="black", linewidth=1.0)
            if not analysed.all():
                ax.plot(ex[~analysed], ey[~analysed], color=SERIES_COLOURS[0], alpha=0.3,
                        linewidth=0.6, label="start-up")  # fmt: skip
            ax.plot(ex[analysed], ey[analysed], color=SERIES_COLOURS[0], linewidth=0.7,
                    label="analysed" if not analysed.all() else None)  # fmt: skip
            reach = max(c_um, float(np.max(np.hypot(ex, ey)))) if ex.size else c_um
            lim = 1.08 * reach
            ax.set_xlim(-lim, lim)
            ax.set_ylim(-lim, lim)
            ax.set_aspect("equal")
            largest = reach / c_um if c_um else float("nan")
            ax.set_title(
                f"joint {name}: c = {c_um:g} µm, largest |e| = {largest:.2f} c", fontsize=9
            )
            ax.set_xlabel("e_x (µm)")
            ax.set_ylabel("e_y (µm)")
        if not analysed.all():
            axes[0, 0].legend(loc="upper right", fontsize=7)
        fig.suptitle(
            f"{title}: journal-centre orbits (black circle: clearance; beyond it: penetration)",
            fontsize=10,
        )
        fig.tight_layout()
        return save(fig, path, figure_format)[0]


def ecs_sweep_plots(
    swept: EcsSweep, contacts: tuple[str, ...], folder: Path, *, figure_format: str = "png"
) -> list[Path]:
    """``ecs_sweep.png`` (K, δ, D over crank speed, the paper's values marked) and
    ``ecs_damping.png`` (the ECS hysteresis factor beside the Hunt–Crossley family)."""
    plt = pyplot()
    check_format(figure_format)
    data = swept.paper_units_table()
    rpm = data["rpm"]
    paths = []
    with style():
        fig, axes = plt.subplots(1, 3, figsize=(11, 3.8))
        for ax, prefix, unit, label, words in zip(
            axes,
            ("K_{c}_N_per_mm", "delta_{c}_mm", "D_{c}_N_s_per_mm"),
            ("N/mm", "mm", "N·s/mm"),
            ("K", "δ", "D"),
            ("stiffness", "penetration", "damping"),
            strict=True,
        ):
            for c in contacts:
                colour = CONTACT_COLOURS.get(c, "0.4")
                ax.plot(rpm, data[prefix.format(c=c)], marker="o", ms=3, color=colour,
                        label=f"ours, {c}")  # fmt: skip
                published = PAPER_PUBLISHED[c]
                value = {
                    "K": published.stiffness_n_per_mm,
                    "δ": published.penetration_mm,
                    "D": published.damping_n_s_per_mm,
                }[label]
                ax.plot([published.crank_speed_rpm], [value], "x", color=colour, markersize=9,
                        mew=2, label=f"paper, {c} ({published.table})")  # fmt: skip
            ax.set_yscale("log")
            ax.set_xlabel("crank speed (rpm)")
            ax.set_ylabel(f"{label} ({unit})")
            ax.set_title(f"{words} {label}")
            ax.grid(True, which="both", alpha=0.3)
        axes[0].legend(fontsize=7)
        fig.suptitle(
            f"{swept.mechanism}: equivalent contact stiffness over crank speed "
            "(log scale: the contacts differ by orders of magnitude)",
            fontsize=10,
        )
        fig.tight_layout()
        paths.append(save(fig, folder / "ecs_sweep.png", figure_format)[0])

        fig, (left, right) = plt.subplots(1, 2, figsize=(11, 4.2))
        models = dict(swept.chi_models)
        for c in contacts:
            left.plot(rpm, data[f"chi_ecs_{c}"], marker="o", ms=3,
                      color=CONTACT_COLOURS.get(c, "0.4"), label=f"χ_ECS, {c}")  # fmt: skip
        for name, value in models.items():
            left.axhline(value, color=LAW_COLOURS.get(name, "0.4"), linewidth=1.2,
                         label=f"{name}: χ(e = {swept.restitution:g}) = {value:.3g}")  # fmt: skip
        left.set_yscale("log")
        left.set_xlabel("crank speed (rpm)")
        left.set_ylabel("hysteresis damping factor χ (–)")
        left.set_title("χ_ECS = (D/K)·v0/δ against χ(e) of the Hunt–Crossley family")
        left.grid(True, which="both", alpha=0.3)
        left.legend(fontsize=7, loc="center right")
        for c in contacts:
            colour = CONTACT_COLOURS.get(c, "0.4")
            right.plot(rpm, data[f"D_{c}_N_s_per_mm"], marker="o", ms=3, color=colour,
                       label=f"ECS D, {c}")  # fmt: skip
            band = np.array([data[f"c_eq_{name}_{c}_N_s_per_mm"] for name in models])
            right.fill_between(rpm, band.min(axis=0), band.max(axis=0), color=colour, alpha=0.3,
                               label=f"χ(e)·K·δ/v0 of the {len(models)} laws, {c}")  # fmt: skip
        right.set_yscale("log")
        right.set_xlabel("crank speed (rpm)")
        right.set_ylabel("damping coefficient (N·s/mm)")
        right.set_title("ECS damping against the laws' equivalent damping")
        right.grid(True, which="both", alpha=0.3)
        right.legend(fontsize=7, loc="center right")
        fig.tight_layout()
        paths.append(save(fig, folder / "ecs_damping.png", figure_format)[0])
    return paths
