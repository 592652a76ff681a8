"""The figures of a tolerance study, drawn from plain data (numbers, labels, arrays).

Each function draws one nine-panel figure and returns its files (:func:`encode`). They take
no study object and import only NumPy and matplotlib, so that a worker process can draw one
while this process draws another (:func:`jointplay.report.tolerance.study_plots`): the three
figures are a second and a half of a 1 000-sample study's command on one core.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from typing import Any

import numpy as np

from jointplay.report._mpl import pyplot
from jointplay.report.figures import encode

__all__ = ["display_scale", "histograms", "input_label", "scatter", "tornado"]

#: Ticks per numeric axis (at most): matplotlib's automatic choice, up to 9 on these panels,
#: made the ticks most of the drawing time (0.4 s per nine-panel figure here; 0.27 s so).
_TICKS = 5


def display_scale(unit: str, kind: str = "") -> tuple[str, float]:
    """(label, factor) that turns an SI value into report units: mm, µm (clearances), deg."""
    if unit == "m":
        return ("µm", 1e6) if kind == "clearance" else ("mm", 1e3)
    if unit == "rad":
        return "deg", 180.0 / math.pi
    return unit.replace("^2", "²").replace("*", "·"), 1.0


def input_label(name: str) -> str:
    """Short label of an input for plots and tables: ``crank`` for ``length_crank``."""
    return name.replace("length_", "").replace("clearance_", "clearance ").replace("_", " ")


def _grid(
    plt: Any, count: int, *, left: float = 0.07, numeric: str = "both"
) -> tuple[Any, list[Any]]:
    """A figure of ``count`` panels, three per row, with fixed margins; the ``numeric`` axes
    ("x", "y" or "both") get at most :data:`_TICKS` ticks. The panels' titles are set at
    ``y=1.0`` (just above the panel, where matplotlib would put them here) so that drawing
    skips the automatic placement, which measures every tick label."""
    columns = min(3, max(1, count))
    rows = math.ceil(count / columns)
    height = 3.0 * rows + 0.6
    fig, axes = plt.subplots(rows, columns, figsize=(4.8 * columns, height), dpi=100, squeeze=False)
    # Fixed margins: tight_layout doubles the drawing time of these many-panel figures.
    fig.subplots_adjust(
        left=left / columns * 3 if columns < 3 else left,
        right=0.98,
        bottom=0.55 / height,
        top=1.0 - 0.9 / height,
        hspace=0.65,
        wspace=0.25 + 2.5 * left,
    )
    flat = list(axes.ravel())
    for ax in flat[count:]:
        ax.set_visible(False)
    for ax in flat[:count]:
        ax.locator_params(axis=numeric, nbins=_TICKS)
    return fig, flat[:count]


def tornado(
    title: str,
    what: str,
    panels: Sequence[tuple[str, Mapping[str, float]]],
    figure_format: str = "png",
) -> dict[str, bytes]:
    """``tornado.png``: per response (panel title), the inputs' shares (fractions) as bars.

    Args:
        title: the figure's title.
        what: what the shares are (the x label, in %).
        panels: (response name, {input label: share}) per panel.
    """
    fig, axes = _grid(pyplot(), len(panels), left=0.1, numeric="x")
    for ax, (name, shares) in zip(axes, panels, strict=True):
        order = sorted(shares, key=lambda k: shares[k])
        ax.barh(order, [100.0 * shares[k] for k in order], color="C0")
        ax.set_xlim(0, 100)
        ax.set_title(name, fontsize=9, y=1.0)
        ax.set_xlabel(f"{what} (%)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, axis="x", alpha=0.3)
    fig.suptitle(title, fontsize=10)
    return encode(fig, "tornado", figure_format)


#: The vertical lines of a histogram panel: key of the panel, label, style.
_MARKS = (
    ("nominal", "nominal", {"color": "k", "linewidth": 1.2}),
    ("mean", "mean", {"color": "C0", "linestyle": "--", "linewidth": 1}),
    ("ideal", "ideal joints", {"color": "C2", "linestyle": "-.", "linewidth": 1}),
)


def histograms(
    title: str, panels: Sequence[Mapping[str, Any]], figure_format: str = "png"
) -> dict[str, bytes]:
    """``histograms.png``: per response, the histogram of its successful samples.

    Args:
        title: the figure's title.
        panels: per response, in report units: ``name``, ``unit``, ``values`` (array),
            ``nominal``, ``mean`` and ``ideal`` (None where there is none) and ``limits``
            (the spec limits given, a list).
    """
    fig, axes = _grid(pyplot(), len(panels))
    legend: dict[str, Any] = {}  # one legend for the figure: the same lines in every panel
    for ax, panel in zip(axes, panels, strict=True):
        values = np.asarray(panel["values"])
        if len(values):
            ax.hist(
                values,
                bins=min(60, max(10, int(math.sqrt(len(values))))),
                color="0.75",
                histtype="stepfilled",  # one patch, not one per bin: fast to draw
            )
        for key, label, style in _MARKS:
            if panel[key] is not None:
                ax.axvline(panel[key], label=label, **style)
        for value in panel["limits"]:
            ax.axvline(value, color="C3", linestyle=":", linewidth=1.5, label="spec limit")
        ax.set_title(panel["name"], fontsize=9, y=1.0)
        ax.set_xlabel(panel["unit"], fontsize=8)
        ax.tick_params(labelsize=7)
        handles, labels = ax.get_legend_handles_labels()
        legend.update(zip(labels, handles, strict=True))
    fig.legend(legend.values(), legend.keys(), loc="upper right", ncol=len(legend), fontsize=8)
    fig.suptitle(title, fontsize=10)
    return encode(fig, "histograms", figure_format)


def scatter(
    title: str, panels: Sequence[Mapping[str, Any]], figure_format: str = "png"
) -> dict[str, bytes]:
    """``scatter.png``: per response, its samples against one input, the nominal point marked.

    Args:
        title: the figure's title.
        panels: ``title``, ``x_label``, ``y_label``, ``x`` and ``y`` (arrays) and
            ``nominal`` (x, y), in report units.
    """
    fig, axes = _grid(pyplot(), len(panels))
    for ax, panel in zip(axes, panels, strict=True):
        ax.scatter(panel["x"], panel["y"], s=3, alpha=0.4)
        ax.plot(*([v] for v in panel["nominal"]), "k+", markersize=10, label="nominal")
        ax.set_title(panel["title"], fontsize=9, y=1.0)
        ax.set_xlabel(panel["x_label"], fontsize=8)
        ax.set_ylabel(panel["y_label"], fontsize=8)
        ax.tick_params(labelsize=7)
    fig.suptitle(title, fontsize=10)
    return encode(fig, "scatter", figure_format)
