"""Static figures (PNG) of results; only consumers of result tables, no physics here.

Matplotlib is imported lazily with the non-interactive Agg backend, so the core of jointplay
imports without it.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd

from jointplay.report._mpl import pyplot
from jointplay.study.published import PAPER_PUBLISHED

if TYPE_CHECKING:
    from jointplay.study.ecs import EcsSweep

UNITS = {"omega": "rad/s", "alpha": "rad/s²", "F": "N", "torque": "N·m"}


def line_plot(
    path: Path,
    x: Any,
    series: Sequence[tuple[str, Any]],
    *,
    xlabel: str,
    ylabel: str,
    title: str,
    overlays: Sequence[tuple[str, Any, Any]] = (),
) -> Path:
    """Plot ``series`` (label, y) against ``x`` and dashed ``overlays`` (label, x, y)."""
    plt = pyplot()
    fig, ax = plt.subplots(figsize=(8, 4.5), dpi=110)
    for label, y in series:
        ax.plot(x, y, label=label, linewidth=1.2)
    for label, ox, oy in overlays:
        ax.plot(ox, oy, "--", label=label, linewidth=1.0, color="0.3")
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.set_title(title)
    ax.grid(True, alpha=0.3)
    if series or overlays:
        ax.legend(loc="best", fontsize=8)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def kinematics_plots(table: pd.DataFrame, folder: Path, title: str) -> list[Path]:
    """Angular velocities, accelerations and joint forces/torque against crank angle."""
    x = table["crank_deg"]
    written = []
    for prefix, name, quantity in (
        ("omega", "angular_velocity.png", "angular velocity"),
        ("alpha", "angular_acceleration.png", "angular acceleration"),
    ):
        columns = [c for c in table.columns if c.startswith(prefix)]
        if columns:
            written.append(
                line_plot(
                    folder / name,
                    x,
                    [(c, table[c]) for c in columns],
                    xlabel="crank angle (deg)",
                    ylabel=f"{quantity} ({UNITS[prefix]})",
                    title=f"{title}: {quantity}",
                )
            )
    forces = [c for c in table.columns if c.startswith("F_")]
    written.append(
        line_plot(
            folder / "joint_forces.png",
            x,
            [(c, table[c]) for c in forces],
            xlabel="crank angle (deg)",
            ylabel="joint reaction (N)",
            title=f"{title}: joint reactions",
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


def simulation_plots(
    steps: pd.DataFrame, nominal: pd.DataFrame, clearances: Sequence[Any], folder: Path, title: str
) -> list[Path]:
    """ω and α against crank angle with the nominal overlaid, contact forces, journal orbits."""
    crank = steps["crank_deg"]
    written = []
    for prefix, name, quantity in (
        ("omega", "angular_velocity.png", "angular velocity"),
        ("alpha", "angular_acceleration.png", "angular acceleration"),
    ):
        columns = [c for c in steps.columns if c.startswith(prefix)]
        overlays = [
            (f"{c} nominal", *_tiled_nominal(nominal, c, crank)) for c in columns if c in nominal
        ]
        written.append(
            line_plot(
                folder / name,
                crank,
                [(c, steps[c]) for c in columns],
                xlabel="crank angle (deg)",
                ylabel=f"{quantity} ({UNITS[prefix]})",
                title=f"{title}: {quantity} with clearance (nominal dashed)",
                overlays=overlays,
            )
        )
    forces = [c for c in steps.columns if c.startswith("F_")]
    written.append(
        line_plot(
            folder / "joint_forces.png",
            crank,
            [(c, steps[c]) for c in forces],
            xlabel="crank angle (deg)",
            ylabel="joint force (N)",
            title=f"{title}: joint forces (contact force in clearance joints)",
        )
    )
    if clearances:
        written.append(orbit_plot(steps, clearances, folder / "journal_orbits.png", title))
    return written


def orbit_plot(steps: pd.DataFrame, clearances: Sequence[Any], path: Path, title: str) -> Path:
    """Journal-centre orbit of each clearance joint inside its clearance circle (µm)."""
    plt = pyplot()
    count = len(clearances)
    fig, axes = plt.subplots(1, count, figsize=(3.2 * count, 3.4), dpi=110, squeeze=False)
    circle = np.linspace(0, 2 * np.pi, 361)
    for ax, clearance in zip(axes[0], clearances, strict=True):
        name = clearance.joint
        c_um = clearance.clearance * 1e6
        ax.plot(c_um * np.cos(circle), c_um * np.sin(circle), color="0.5", linewidth=0.8)
        ax.plot(steps[f"ex_{name}"] * 1e6, steps[f"ey_{name}"] * 1e6, linewidth=0.6)
        ax.set_aspect("equal")
        ax.set_title(f"joint {name} (c = {c_um:g} µm)", fontsize=9)
        ax.set_xlabel("e_x (µm)", fontsize=8)
        ax.set_ylabel("e_y (µm)", fontsize=8)
        ax.tick_params(labelsize=7)
    fig.suptitle(f"{title}: journal-centre orbits", fontsize=10)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def ecs_sweep_plots(swept: EcsSweep, contacts: tuple[str, ...], folder: Path) -> list[Path]:
    """ecs_sweep.png (K, δ, D over speed) and ecs_damping.png (hysteresis comparison)."""
    plt = pyplot()
    data = swept.paper_units_table()
    rpm = data["rpm"]
    fig, axes = plt.subplots(1, 3, figsize=(12, 4), dpi=110)
    for ax, prefix, unit, label in zip(
        axes,
        ("K_{c}_N_per_mm", "delta_{c}_mm", "D_{c}_N_s_per_mm"),
        ("N/mm", "mm", "N·s/mm"),
        ("K", "δ", "D"),
        strict=True,
    ):
        for c in contacts:
            (line,) = ax.plot(rpm, data[prefix.format(c=c)], marker="o", label=f"ECS {c}")
            published = PAPER_PUBLISHED[c]
            value = {
                "K": published.stiffness_n_per_mm,
                "δ": published.penetration_mm,
                "D": published.damping_n_s_per_mm,
            }[label]
            ax.plot(
                [published.crank_speed_rpm],
                [value],
                "x",
                color=line.get_color(),
                markersize=9,
                label=f"paper {c} ({published.table})",
            )
        ax.set_yscale("log")
        ax.set_xlabel("crank speed (rpm)")
        ax.set_ylabel(f"{label} ({unit})")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    fig.suptitle(f"{swept.mechanism}: ECS over crank speed")
    fig.tight_layout()
    paths = [folder / "ecs_sweep.png"]
    fig.savefig(paths[0])
    plt.close(fig)

    fig, (left, right) = plt.subplots(1, 2, figsize=(12, 4.5), dpi=110)
    for c in contacts:
        left.plot(rpm, data[f"chi_ecs_{c}"], marker="o", label=f"χ_ECS {c}")
    models = swept.chi_models
    for name in models:
        left.plot(rpm, data[f"chi_{name}"], "--", label=f"{name} χ(e={swept.restitution:g})")
    left.set_yscale("log")
    left.set_xlabel("crank speed (rpm)")
    left.set_ylabel("hysteresis damping factor χ (–)")
    left.set_title("χ_ECS = (D/K) v0/δ vs χ(e) of the Hunt–Crossley family")
    left.grid(True, which="both", alpha=0.3)
    left.legend(fontsize=7)
    c = contacts[0]
    right.plot(rpm, data[f"D_{c}_N_s_per_mm"], marker="o", label=f"ECS D {c}")
    for name in models:
        right.plot(rpm, data[f"c_eq_{name}_{c}_N_s_per_mm"], "--", label=f"{name} χKδ/v0")
    right.set_yscale("log")
    right.set_xlabel("crank speed (rpm)")
    right.set_ylabel("damping coefficient (N·s/mm)")
    right.set_title(f"equivalent damping at the ECS design point ({c})")
    right.grid(True, which="both", alpha=0.3)
    right.legend(fontsize=7)
    fig.tight_layout()
    paths.append(folder / "ecs_damping.png")
    fig.savefig(paths[1])
    plt.close(fig)
    return paths
