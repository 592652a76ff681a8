"""The figures of the paper report: the linkage, the nominal motion, each method's start-up and
steady cycle, and the journal orbits.

Only consumes a :class:`~jointplay.study.paper.PaperStudy`. Every method has one colour in
every figure (:data:`~jointplay.report.figures.METHOD_COLOURS`), the nominal mechanism is black
and dashed, axes are linear and labelled with their unit, and every line is thinned to what
the eye can see (:func:`~jointplay.report.figures.thin`) so that the figures are drawn in
seconds.
"""

from __future__ import annotations

import math
from dataclasses import dataclass
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from jointplay.report._mpl import pyplot
from jointplay.report.figures import (
    METHOD_COLOURS,
    NOMINAL,
    SERIES_COLOURS,
    save,
    style,
    thin,
    tick_formatter,
)
from jointplay.study.methods import METHODS
from jointplay.study.paper import JOINTS, PAPER_CLEARANCE, STARTUP_PLOT_DEG, PaperStudy

#: Each plotted quantity: its words, symbol and unit.
QUANTITIES = {
    "omega3": ("coupler angular velocity", "ω3", "rad/s"),
    "omega4": ("rocker angular velocity", "ω4", "rad/s"),
    "alpha3": ("coupler angular acceleration", "α3", "rad/s²"),
    "alpha4": ("rocker angular acceleration", "α4", "rad/s²"),
    "F_O2": ("crank–ground joint force", "F O2", "N"),
    "F_A": ("crank–coupler joint force", "F A", "N"),
    "F_B": ("coupler–rocker joint force", "F B", "N"),
    "F_O4": ("rocker–ground joint force", "F O4", "N"),
    "torque": ("driving torque", "torque", "N·m"),
}
JOINT_WORDS = {
    "O2": "crank–ground",
    "A": "crank–coupler",
    "B": "coupler–rocker",
    "O4": "rocker–ground",
}
#: Columns of the x range a line of the method figures is thinned to.
METHOD_BINS = 600


def axis_label(quantity: str) -> str:
    """``"ω4 (rad/s)"``: a quantity's symbol and unit."""
    _, symbol, unit = QUANTITIES[quantity]
    return f"{symbol} ({unit})"


def mechanism_figure(study: PaperStudy, path: Path, figure_format: str = "png") -> list[Path]:
    """The linkage at 12 crank angles and the path of B, to scale (mm)."""
    plt = pyplot()
    geometry = study.extra["configuration"]["geometry_m"]
    a, c, d = (geometry[k] * 1e3 for k in ("crank", "rocker", "ground"))
    table = study.nominal
    with style():
        fig, ax = plt.subplots(figsize=(7, 4.6))
        theta2 = np.radians(table["crank_deg"].to_numpy())
        theta4 = np.radians(table["theta4_deg"].to_numpy())
        bx, by = d + c * np.cos(theta4), c * np.sin(theta4)
        ax.plot(bx, by, color="0.5", linewidth=1.2, label="path of B (rocker tip)")
        step = max(1, len(table) // 12)
        for k, i in enumerate(range(0, len(table) - 1, step)):
            ax_, ay_ = a * np.cos(theta2[i]), a * np.sin(theta2[i])
            ax.plot(
                [0, ax_, bx[i], d],
                [0, ay_, by[i], 0],
                "-o",
                color=SERIES_COLOURS[0],
                linewidth=0.9,
                markersize=2.5,
                alpha=0.35 if k else 1.0,
                label="crank, coupler, rocker every 30° (solid: crank at 0°)" if not k else None,
            )
        ax.plot([0, d], [0, 0], "k-", linewidth=3, label="ground O2–O4")
        ax.annotate("O2", (0, 0), textcoords="offset points", xytext=(-12, -12))
        ax.annotate("O4", (d, 0), textcoords="offset points", xytext=(4, -12))
        ax.set_aspect("equal")
        ax.set_xlabel("x (mm)")
        ax.set_ylabel("y (mm)")
        ax.set_title("The paper's crank-rocker to scale (crank counter-clockwise)")
        ax.legend(loc="lower right")
        fig.tight_layout()
        return save(fig, path, figure_format)


def nominal_figure(study: PaperStudy, path: Path, figure_format: str = "png") -> list[Path]:
    """The nominal (ideal-joint) motion over one revolution: speeds, accelerations, forces."""
    plt = pyplot()
    table = study.nominal
    x = table["crank_deg"].to_numpy()
    with style():
        fig, axes = plt.subplots(1, 3, figsize=(11, 3.4))
        for ax, columns, ylabel in (
            (axes[0], ("omega3", "omega4"), "angular velocity (rad/s)"),
            (axes[1], ("alpha3", "alpha4"), "angular acceleration (rad/s²)"),
            (axes[2], tuple(f"F_{j}" for j in JOINTS), "joint force (N)"),
        ):
            for colour, column in zip(SERIES_COLOURS, columns, strict=False):
                words, symbol, _ = QUANTITIES[column]
                ax.plot(x, table[column], color=colour, linewidth=1.2, label=f"{symbol}: {words}")
            ax.set_xlabel("crank angle (deg)")
            ax.set_ylabel(ylabel)
            ax.set_xlim(0, 360)
            ax.set_xticks(range(0, 361, 60))
            ax.legend(fontsize=7, loc="best")
        fig.suptitle(
            f"Nominal mechanism (ideal joints), one revolution at {study.options.rpm:g} rpm",
            fontsize=10,
        )
        fig.tight_layout()
        return save(fig, path, figure_format)


def _steady_key(study: PaperStudy, method: str) -> str:
    source = study.options.tolerance_source if METHODS[method].uses_ecs else "-"
    return f"steady/{method}/{source}"


def method_figure(
    study: PaperStudy, quantity: str, path: Path, figure_format: str = "png"
) -> list[Path]:
    """One quantity for each of the six methods: the start-up from rest (the first
    :data:`~jointplay.study.paper.STARTUP_PLOT_DEG` of crank, both ECS sources) on the left,
    the steady cycle (one revolution after settling) on the right, nominal dashed black."""
    plt = pyplot()
    words, symbol, unit = QUANTITIES[quantity]
    nominal = study.nominal
    crank = nominal["crank_deg"].to_numpy()
    values = nominal[quantity].to_numpy()
    early = crank <= STARTUP_PLOT_DEG
    methods = list(METHODS.values())
    with style():
        fig, axes = plt.subplots(
            len(methods),
            2,
            figsize=(11, 1.35 * len(methods) + 1.0),
            sharex="col",
            squeeze=False,
            gridspec_kw={"left": 0.08, "right": 0.99, "top": 0.88, "bottom": 0.07,
                         "hspace": 0.5, "wspace": 0.13},
        )  # fmt: skip
        for row, method in zip(axes, methods, strict=True):
            colour = METHOD_COLOURS[method.name]
            for key, outcome in study.outcomes.items():
                if not key.startswith(f"method/{method.name}/") or outcome.trace is None:
                    continue
                trace = outcome.trace
                turned = trace["crank_deg"].to_numpy() - float(trace["crank_deg"].iloc[0])
                window = turned <= STARTUP_PLOT_DEG
                primary = outcome.task.ecs_source in ("paper", "-")
                row[0].plot(
                    *thin(turned[window], trace[quantity].to_numpy()[window], METHOD_BINS),
                    color=colour,
                    linewidth=1.0 if primary else 0.9,
                    linestyle="-" if primary else ":",
                )
            steady = study.outcomes.get(_steady_key(study, method.name))
            if steady is not None and steady.trace is not None:
                phase = np.mod(steady.trace["crank_deg"].to_numpy(), 360.0)
                order = np.argsort(phase, kind="stable")
                row[1].plot(
                    *thin(phase[order], steady.trace[quantity].to_numpy()[order], METHOD_BINS),
                    color=colour,
                    linewidth=1.0,
                )
            row[0].plot(crank[early], values[early], **NOMINAL)
            row[1].plot(crank[::5], values[::5], **NOMINAL)
            row[0].set_title(method.title, loc="left", fontsize=9, color=colour)
            row[0].set_ylabel(f"{symbol} ({unit})")
            for ax in row:
                ax.yaxis.set_major_locator(_locator())
                ax.yaxis.set_major_formatter(tick_formatter())
        axes[0, 0].set_xlim(0, STARTUP_PLOT_DEG)
        axes[0, 0].set_xticks(np.arange(0, STARTUP_PLOT_DEG + 1, 5))
        axes[0, 1].set_xlim(0, 360)
        axes[0, 1].set_xticks(range(0, 361, 60))
        axes[-1, 0].set_xlabel("crank angle turned from rest (deg)")
        axes[-1, 1].set_xlabel("crank angle in the steady revolution (deg)")
        fig.suptitle(f"{words.capitalize()} {symbol} ({unit})", fontsize=11, y=0.995)
        fig.text(0.08, 0.935, "Start-up from rest (the paper's setting)", fontsize=10)
        fig.text(0.545, 0.935, "Running steadily (after settling)", fontsize=10)
        handles = [
            _handle("-", "0.3", "paper's ECS values (or conventional)"),
            _handle(":", "0.3", "our computed ECS values"),
            _handle("--", "black", "nominal (ideal joints)"),
        ]
        fig.legend(handles=handles, loc="upper right", ncol=3, frameon=False, fontsize=8,
                   bbox_to_anchor=(0.99, 0.975))  # fmt: skip
        return save(fig, path, figure_format)


def _locator() -> Any:
    from matplotlib.ticker import MaxNLocator

    return MaxNLocator(4)


def _handle(linestyle: Any, colour: str, label: str) -> Any:
    from matplotlib.lines import Line2D

    return Line2D([], [], linestyle=linestyle, color=colour, linewidth=1.2, label=label)


@dataclass(frozen=True)
class OrbitExtent:
    """How far one journal centre went from its bearing's centre in one run."""

    method: str
    setting: str  # "from rest" or "running steadily"
    joint: str
    largest_eccentricity: float  # m
    clearance: float  # m

    @property
    def penetration(self) -> float:
        """Largest eccentricity beyond the clearance, m (0: the pin stayed inside)."""
        return max(0.0, self.largest_eccentricity - self.clearance)


def orbit_extents(study: PaperStudy) -> list[OrbitExtent]:
    """The largest eccentricity of every journal in every run with a kept orbit."""
    out = []
    for key, outcome in study.outcomes.items():
        kind = key.split("/")[0]
        if kind not in ("method", "steady") or outcome.orbits is None:
            continue
        if kind == "method" and outcome.task.ecs_source == "computed":
            continue
        setting = "from rest" if kind == "method" else "running steadily"
        for joint in JOINTS:
            e = np.hypot(outcome.orbits[f"ex_{joint}"], outcome.orbits[f"ey_{joint}"])
            out.append(
                OrbitExtent(outcome.task.method, setting, joint, float(e.max()), PAPER_CLEARANCE)
            )
    return out


def orbit_figure(study: PaperStudy, path: Path, figure_format: str = "png") -> list[Path]:
    """Journal-centre orbits of every method and joint, to scale in µm, inside the clearance
    circle: from rest faint, running steadily solid, in the method's colour. Each panel's
    limits take in the whole orbit, so a trace beyond the circle (penetration) is seen."""
    plt = pyplot()
    methods = list(METHODS.values())
    circle = np.linspace(0, 2 * np.pi, 181)
    c_um = PAPER_CLEARANCE * 1e6
    with style():
        fig, axes = plt.subplots(
            len(methods),
            len(JOINTS),
            figsize=(9.5, 2.25 * len(methods) + 0.6),
            squeeze=False,
            gridspec_kw={"left": 0.07, "right": 0.99, "top": 0.93, "bottom": 0.04,
                         "hspace": 0.45, "wspace": 0.3},
        )  # fmt: skip
        for index, (row, method) in enumerate(zip(axes, methods, strict=True)):
            colour = METHOD_COLOURS[method.name]
            source = study.options.tolerance_source if method.uses_ecs else "-"
            runs = [
                (study.outcomes.get(f"method/{method.name}/{source}"), 0.35, 0.6),
                (study.outcomes.get(_steady_key(study, method.name)), 1.0, 0.8),
            ]
            for ax, joint in zip(row, JOINTS, strict=True):
                reach = c_um
                ax.plot(c_um * np.cos(circle), c_um * np.sin(circle), color="0.2", linewidth=1.0)
                for outcome, alpha, width in runs:
                    if outcome is None or outcome.orbits is None:
                        continue
                    ex = outcome.orbits[f"ex_{joint}"].to_numpy() * 1e6
                    ey = outcome.orbits[f"ey_{joint}"].to_numpy() * 1e6
                    ax.plot(ex, ey, color=colour, alpha=alpha, linewidth=width)
                    reach = max(reach, float(np.max(np.hypot(ex, ey))))
                lim = 1.08 * reach
                ax.set_xlim(-lim, lim)
                ax.set_ylim(-lim, lim)
                ax.set_aspect("equal")
                ax.tick_params(labelsize=7)
                ax.xaxis.set_major_locator(_locator())
                ax.yaxis.set_major_locator(_locator())
                if index == 0:
                    ax.set_title(f"joint {joint} ({JOINT_WORDS[joint]})", fontsize=9)
            row[0].set_ylabel(f"{method.family} {method.parameters}\ne_y (µm)", fontsize=8,
                              color=colour)  # fmt: skip
        for ax in axes[-1]:
            ax.set_xlabel("e_x (µm)", fontsize=8)
        fig.suptitle(
            f"Journal-centre orbits: the clearance circle (c = {c_um:g} µm) in black, "
            "from rest faint, running steadily solid",
            fontsize=10,
        )
        return save(fig, path, figure_format)


def orbit_table(extents: list[OrbitExtent]) -> pd.DataFrame:
    """Largest eccentricity (µm) per method, setting and joint, wide by joint."""
    rows: dict[tuple[str, str], dict[str, Any]] = {}
    for e in extents:
        row = rows.setdefault((e.method, e.setting), {})
        row[e.joint] = e.largest_eccentricity * 1e6
    return pd.DataFrame(
        [
            {"method": METHODS[m].title, "setting": s, **{j: r.get(j, math.nan) for j in JOINTS}}
            for (m, s), r in rows.items()
        ]
    )
