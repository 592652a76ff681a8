"""Figures of the running behaviour: Poincaré maps of the pins and per-revolution peaks."""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from pathlib import Path

import numpy as np

from jointplay.report._mpl import pyplot
from jointplay.report.figures import SERIES_COLOURS, check_format, save
from jointplay.report.plots import symbol

#: Quantity groups of the per-revolution figure, with their axis labels.
GROUPS = (
    ("omega", "peak |ω| (rad/s)"),
    ("alpha", "peak |α| (rad/s²)"),
    ("F_", "peak joint force (N)"),
    ("torque", "peak |torque| (N·m)"),
)


def poincare_plot(
    points: np.ndarray,
    coordinates: Sequence[str],
    joints: Sequence[str],
    verdict: str,
    path: Path,
    *,
    title: str = "",
    figure_format: str = "png",
) -> Path:
    """The once-per-revolution section of each pin's eccentricity, in units of the clearance.

    Args:
        points: normalised section points, one row per revolution.
        coordinates: column names; ``ex_J/c`` and ``ey_J/c`` are drawn for each joint J.
        joints: the clearance joints.
        verdict: the periodicity verdict, shown in the title.
        path: the PNG to write.
        figure_format: ``"png"``, or ``"svg"``/``"pdf"`` written beside the PNG.
    """
    plt = pyplot()
    check_format(figure_format)
    count = max(len(joints), 1)
    fig, axes = plt.subplots(1, count, figsize=(3.2 * count, 3.4), squeeze=False)
    circle = np.linspace(0.0, 2.0 * np.pi, 200)
    for ax, joint in zip(axes[0], joints, strict=False):
        x = points[:, list(coordinates).index(f"ex_{joint}/c")]
        y = points[:, list(coordinates).index(f"ey_{joint}/c")]
        ax.plot(np.cos(circle), np.sin(circle), color="0.6", lw=0.8, label="clearance")
        ax.plot(x, y, color="0.8", lw=0.6, zorder=1)
        ax.scatter(x, y, c=np.arange(x.size), cmap="viridis", s=14, zorder=2)
        ax.set_aspect("equal")
        ax.set_title(f"joint {joint}", fontsize=9)
        ax.set_xlabel("e_x / c")
        ax.set_ylabel("e_y / c")
        ax.tick_params(labelsize=8)
    fig.suptitle(f"{title} Poincaré section once per revolution: {verdict}".strip(), fontsize=10)
    fig.tight_layout()
    return save(fig, path, figure_format, dpi=110)[0]


def per_revolution_plot(
    per_revolution: Mapping[str, Sequence[float]],
    first_revolution: int,
    path: Path,
    *,
    title: str = "",
    figure_format: str = "png",
) -> Path:
    """Each quantity's peak in every analysed revolution, grouped by kind.

    Args:
        per_revolution: for each quantity, its peak in each analysed revolution.
        first_revolution: the number of the first analysed revolution (1 = the first
            simulated one).
        path: the PNG to write.
        figure_format: ``"png"``, or ``"svg"``/``"pdf"`` written beside the PNG.
    """
    plt = pyplot()
    check_format(figure_format)
    groups = [
        (prefix, label, [q for q in per_revolution if q.startswith(prefix)])
        for prefix, label in GROUPS
    ]
    groups = [g for g in groups if g[2]]
    fig, axes = plt.subplots(
        len(groups), 1, figsize=(7.0, 2.2 * len(groups)), sharex=True, squeeze=False
    )
    for ax, (_, label, names) in zip(axes[:, 0], groups, strict=True):
        for k, name in enumerate(names):
            values = np.asarray(per_revolution[name], dtype=float)
            numbers = first_revolution + np.arange(values.size)
            ax.plot(numbers, values, marker="o", ms=3, lw=1, label=symbol(name),
                    color=SERIES_COLOURS[k % len(SERIES_COLOURS)])  # fmt: skip
        ax.set_ylabel(label, fontsize=8)
        ax.legend(fontsize=7, ncol=4, loc="upper right")
        ax.tick_params(labelsize=8)
        ax.grid(alpha=0.3)
    axes[-1, 0].set_xlabel("crank revolution")
    fig.suptitle(f"{title} peaks per revolution".strip(), fontsize=10)
    fig.tight_layout()
    return save(fig, path, figure_format, dpi=110)[0]
