"""Files, plots and the HTML section of the design study and of the wear life.

:func:`write_design` writes ``design.parquet`` and ``design.csv`` (one row per scheme),
``samples.parquet`` (one row per sample), ``summary.json``, PNG plots (cost against yield
with the Pareto front; each required response per scheme with its spread) and
``report.html`` (dynamic designs whose pins sink deeper than the radial clearance in some
samples: one warning callout per joint under the verdict, and the count of those samples per
scheme in the scheme table). :func:`write_wear` writes ``wear.csv`` (the history), ``profiles.csv`` (the
worn profiles), ``summary.json``, plots (clearance, peak force and rocker-speed error over the
life; the worn profile of each bearing and journal, polar) and ``report.html``.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from jointplay.dynamics.wear import WearHistory
from jointplay.io.output import write_json
from jointplay.report._mpl import pyplot
from jointplay.report.figures import encode
from jointplay.report.html import HtmlReport
from jointplay.study.design import DesignResult
from jointplay.study.sensitivity import ModelSensitivity

__all__ = [
    "design_plots",
    "design_section",
    "display",
    "wear_plots",
    "wear_section",
    "write_design",
    "write_wear",
]

#: Display unit and factor of each SI unit of a response.
_DISPLAY: Mapping[str, tuple[str, float]] = {
    "1": ("%", 100.0),
    "Pa": ("MPa", 1e-6),
    "m/s": ("µm/h", 3.6e9),
    "s": ("h", 1.0 / 3600.0),
    "m": ("µm", 1e6),
}


def display(unit: str) -> tuple[str, float]:
    """Display unit and the factor from SI of a response unit."""
    return _DISPLAY.get(unit, (unit, 1.0))


def _encode(fig: Any, stem: str, figure_format: str) -> dict[str, bytes]:
    return encode(fig, stem, figure_format, dpi=110, bbox_inches="tight")


def design_plots(
    result: DesignResult, units: Mapping[str, str], figure_format: str = "png"
) -> dict[str, bytes]:
    """PNG plots of a design study by file name."""
    plt = pyplot()
    table = result.table
    images: dict[str, bytes] = {}
    if not len(table):
        return images
    fig, ax = plt.subplots(figsize=(7, 4.5))
    feasible = table["feasible"].to_numpy(dtype=bool)
    ax.scatter(table["cost"][~feasible], table["yield"][~feasible], c="tab:red", label="fails")
    ax.scatter(table["cost"][feasible], table["yield"][feasible], c="tab:green", label="meets all")
    front = table[table["pareto_yield"]].sort_values("cost")
    ax.step(front["cost"], front["yield"], where="post", c="k", lw=1, label="Pareto front")
    for _, row in table.iterrows():
        ax.annotate(row["scheme"], (row["cost"], row["yield"]), fontsize=6)
    ax.set_xlabel("relative cost")
    ax.set_ylabel("yield (all requirements), %")
    ax.set_title(f"{result.mechanism.name}: cost against yield")
    ax.legend(fontsize=7)
    images.update(_encode(fig, "design_pareto", figure_format))
    responses = list(dict.fromkeys(r.response for r in result.requirements))
    for name in responses:
        if f"{name}_mean" not in table:
            continue
        unit, scale = display(units.get(name, ""))
        fig, ax = plt.subplots(figsize=(max(6, 0.35 * len(table)), 4))
        x = np.arange(len(table))
        ax.errorbar(
            x,
            table[f"{name}_mean"] * scale,
            yerr=table[f"{name}_std"].fillna(0.0) * scale,
            fmt="o",
            capsize=3,
            label="mean ± std",
        )
        ax.scatter(
            x,
            table[f"{name}_at_confidence"] * scale,
            marker="_",
            s=200,
            c="k",
            label=f"at {100 * result.confidence:g} %",
        )
        for r in result.requirements:
            if r.response == name:
                ax.axhline(r.limit * scale, c="tab:red", ls="--", lw=1, label=r.text)
        ax.set_xticks(x, table["scheme"], rotation=60, ha="right", fontsize=7)
        ax.set_ylabel(f"{name} ({unit})")
        ax.legend(fontsize=7)
        images.update(_encode(fig, f"design_{name}", figure_format))
    return images


def design_section(
    report: HtmlReport, result: DesignResult, units: Mapping[str, str], images: Mapping[str, bytes]
) -> None:
    """The design study's section of an HTML report."""
    from jointplay.tolerance.definitions import response_definition

    summary = result.summary()
    report.heading("Design: fit and length class", anchor="design")
    report.paragraph(summary["verdict"])
    for finding in result.diagnostics:  # right under the verdict they qualify
        d = finding.diagnostic
        where = f", joint {d.joint}" if d.joint else ""
        report.paragraph(f"Warning ({d.code}{where}): {d.message}.", css="note")
    settings = result.settings
    report.bullets(
        [f"requirement: {r.text}" for r in result.requirements]
        + [
            f"confidence level: {100 * result.confidence:g} %",
            f"responses: {result.responses}; samples per scheme: {settings.get('samples')}",
        ]
        + [f"contact: {c}" for c in [settings.get("model", {}).get("contact")] if c]
    )
    sampling = settings.get("sampling_distributions")
    if sampling:
        report.paragraph(f"Sampling: {sampling}.", css="note")
    if result.interrupted:
        report.paragraph("Interrupted: only the finished schemes are listed.", css="note")
    table = result.table
    if len(table):
        columns = {
            "scheme": "scheme (fit, length class)",
            "cost": "relative cost",
            "yield": "yield (%)",
            "dpm": "defects per million",
            "feasible": "meets every requirement",
            "failed": "failed samples",
        }
        shown = table[list(columns)].rename(columns=columns)
        shown[columns["feasible"]] = table["feasible"].map({True: "yes", False: "no"})
        for r in result.reported_responses:
            unit, scale = display(units.get(r, ""))
            label = f"{r} at {100 * result.confidence:g} % ({unit})"
            shown[label] = table[f"{r}_at_confidence"] * scale
        for finding in result.diagnostics:  # the joints whose pins pass the clearance
            if finding.diagnostic.code != "penetration-exceeds-clearance":
                continue
            joint = finding.diagnostic.joint
            shown[f"samples beyond the clearance in {joint}"] = table[
                f"penetration_exceeds_{joint}"
            ]
        report.table(
            shown.sort_values(columns["cost"]),
            caption="Schemes by cost",
            text_columns=(0, 4),
        )
        report.heading("What each response means", level=3, anchor="design-definitions")
        report.table(
            [
                [name, display(units.get(name, ""))[0], response_definition(name)]
                for name in result.reported_responses
            ],
            ["response", "unit", "definition"],
            text_columns=(0, 1, 2),
        )
    for name, data in images.items():
        if name.endswith(".png"):  # the others are print copies beside the report
            report.figure(data, name.removesuffix(".png").replace("_", " "))


def _sensitivity_section(report: HtmlReport, sensitivity: ModelSensitivity) -> None:
    """The model-sensitivity table: the chosen scheme's yields under each contact model."""
    report.heading("Model sensitivity of the choice", anchor="model-sensitivity")
    report.paragraph(sensitivity.verdict)
    requirements = list(sensitivity.rows[0].yields)
    rows = [
        (row.parameter, str(row.value), *row.yields.values(), "yes" if row.meets else "no")
        for row in sensitivity.rows
    ]
    report.table(
        rows,
        headers=["contact parameter", "value", *(f"yield: {r} (%)" for r in requirements),
                 "meets all"],
        text_columns=(0, 1, len(requirements) + 2),
        note="one parameter at a time at the ends of its documented range (docs/contact.md), "
        "the others as the study ran; the study's samples and seed",
    )  # fmt: skip


def write_design(
    result: DesignResult,
    folder: Path,
    units: Mapping[str, str],
    *,
    plots: bool = True,
    provenance: Mapping[str, Any] | None = None,
    figure_format: str = "png",
    sensitivity: ModelSensitivity | None = None,
) -> list[Path]:
    """Write the design study's files into ``folder`` (existing); returns them.
    ``sensitivity``: the chosen scheme under the contact model's ranges
    (:mod:`jointplay.study.sensitivity`), in ``summary.json`` and the report."""
    folder = Path(folder)
    table = result.to_dataframe()
    written = [folder / "design.parquet", folder / "design.csv", folder / "samples.parquet"]
    table.to_parquet(written[0], index=False)
    table.to_csv(written[1], index=False)
    result.samples.to_parquet(written[2], index=False)
    summary = result.summary()
    if sensitivity is not None:
        summary["model_sensitivity"] = sensitivity.as_dict()
    if provenance is not None:
        summary["provenance"] = dict(provenance)
    written.append(folder / "summary.json")
    write_json(written[-1], summary)
    images = design_plots(result, units, figure_format) if plots else {}
    for name, data in images.items():
        (folder / name).write_bytes(data)
        written.append(folder / name)
    report = HtmlReport(f"jointplay design — {result.mechanism.name}")
    design_section(report, result, units, images)
    if sensitivity is not None:
        _sensitivity_section(report, sensitivity)
    written.append(report.write(folder / "report.html"))
    return written


def wear_plots(history: WearHistory, figure_format: str = "png") -> dict[str, bytes]:
    """PNG plots of a wear life by file name."""
    plt = pyplot()
    images: dict[str, bytes] = {}
    hours = np.asarray(history.hours)
    fig, axes = plt.subplots(3, 1, figsize=(7, 8), sharex=True)
    for name, values in history.clearance.items():
        (line,) = axes[0].plot(hours, np.asarray(values) * 1e6, marker=".", label=name)
        axes[0].axhline(history.limit[name] * 1e6, c=line.get_color(), ls=":", lw=1)
        axes[1].plot(hours, history.peak_force[name], marker=".", label=name)
    axes[2].plot(hours, np.asarray(history.speed_error) * 100.0, marker=".", c="k")
    axes[0].set_ylabel("radial clearance (µm)")
    axes[1].set_ylabel("peak contact force (N)")
    axes[2].set_ylabel("rocker speed error (%)")
    axes[2].set_xlabel("operating hours")
    axes[0].legend(fontsize=7)
    axes[0].set_title(f"wear over the life at {history.rpm:g} RPM (dotted: limits)")
    images.update(_encode(fig, "wear_history", figure_format))
    names = list(history.bearing_profile)
    fig, axes = plt.subplots(
        1, len(names), figsize=(3.2 * len(names), 3.6), subplot_kw={"projection": "polar"}
    )
    for ax, name in zip(np.atleast_1d(axes), names, strict=True):
        bearing = history.bearing_profile[name]
        theta = (np.arange(len(bearing)) + 0.5) * 2 * math.pi / len(bearing)
        ax.plot(theta, bearing * 1e6, label="bearing")
        ax.plot(theta, history.journal_profile[name] * 1e6, label="journal")
        ax.set_title(f"{name}: worn depth (µm)", fontsize=8)
        ax.tick_params(labelsize=6)
    np.atleast_1d(axes)[0].legend(fontsize=6, loc="lower left")
    images.update(_encode(fig, "wear_profiles", figure_format))
    return images


def wear_section(report: HtmlReport, history: WearHistory, images: Mapping[str, bytes]) -> None:
    """The wear life's section of an HTML report."""
    report.heading("Joint wear and life", anchor="wear")
    report.paragraph(f"Geometric assumption: {history.assumption}.")
    rows = []
    for name, life in history.life.items():
        rows.append(
            (
                name,
                history.clearance[name][0] * 1e6,
                history.clearance[name][-1] * 1e6,
                history.limit[name] * 1e6,
                history.growth_per_hour[name][-1] * 1e6,
                life,
                "extrapolated" if history.life_extrapolated[name] else "simulated",
            )
        )
    report.table(
        rows,
        headers=[
            "joint",
            "radial clearance at the start (µm)",
            "radial clearance at the end (µm)",
            "clearance limit (µm)",
            "clearance growth (µm/h)",
            "life (h)",
            "life from",
        ],
        text_columns=(0, 6),
    )
    for name, data in images.items():
        if name.endswith(".png"):  # the others are print copies beside the report
            report.figure(data, name.removesuffix(".png").replace("_", " "))


def write_wear(
    history: WearHistory,
    folder: Path,
    *,
    plots: bool = True,
    provenance: Mapping[str, Any] | None = None,
    figure_format: str = "png",
) -> list[Path]:
    """Write the wear life's files into ``folder`` (existing); returns them."""
    folder = Path(folder)
    written = [folder / "wear.csv", folder / "profiles.csv", folder / "summary.json"]
    history.to_dataframe().to_csv(written[0], index=False)
    bins = len(next(iter(history.bearing_profile.values()))) if history.bearing_profile else 0
    profiles: dict[str, Any] = {"angle_deg": (np.arange(bins) + 0.5) * 360.0 / max(bins, 1)}
    for name in history.bearing_profile:
        profiles[f"bearing_{name}_m"] = history.bearing_profile[name]
        profiles[f"journal_{name}_m"] = history.journal_profile[name]
    pd.DataFrame(profiles).to_csv(written[1], index=False)
    summary = history.summary()
    if provenance is not None:
        summary["provenance"] = dict(provenance)
    write_json(written[2], summary)
    images = wear_plots(history, figure_format) if plots else {}
    for name, data in images.items():
        (folder / name).write_bytes(data)
        written.append(folder / name)
    report = HtmlReport("jointplay wear")
    wear_section(report, history, images)
    written.append(report.write(folder / "report.html"))
    return written
