"""Static figures (PNG) of results; only consumers of result tables, no physics here.

Matplotlib is imported lazily with the non-interactive Agg backend, so the core of jointplay
imports without it.
"""

from __future__ import annotations

from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pandas as pd

UNITS = {"omega": "rad/s", "alpha": "rad/s²", "F": "N", "torque": "N·m"}


def _pyplot() -> Any:
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    return plt


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
    plt = _pyplot()
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
