"""Files, plots and the HTML report of a tolerance study.

:func:`write_study` writes a :class:`~jointplay.tolerance.analysis.ToleranceStudyResult` into
a folder:

* ``samples.parquet`` — one row per evaluated point: ``sample``, ``role``, the inputs (SI),
  the responses (SI, NaN where the point failed), for dynamic and running studies
  ``penetration_ratio_<joint>`` (deepest penetration over the radial clearance; above 1:
  not physical), ``status`` (ok / failed / not run) and ``error``;
* ``summary.json`` — method, seed, inputs, statistics and contributions per response,
  failures with their inputs, ``diagnostics`` (plausibility warnings over the points, e.g.
  ``penetration-exceeds-clearance``: how many, the worst ratio and its inputs; empty when
  all is physical), settings, execution record and provenance (SI), the
  definition of every response (``response_definitions``) and, for Monte Carlo, how the
  inputs were sampled (``sampling_distributions``: normal inputs truncated at their limits
  by default);
* ``tornado.png`` (contributions per response), and for Monte Carlo ``histograms.png``
  (with nominal, mean, ideal-joint value and spec limits marked) and ``scatter.png`` (the most
  influential input against each response);
* ``report.html`` — a self-contained page (:class:`~jointplay.report.html.HtmlReport`) with
  the diagnostics in a callout at the top, the tables and the plots embedded.

Reports show lengths in mm, clearances in µm and angles in degrees; files stay SI.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from pathlib import Path
from typing import Any

import numpy as np

from jointplay.io.output import write_json
from jointplay.report._mpl import pyplot
from jointplay.report.figures import encode
from jointplay.report.html import HtmlReport
from jointplay.tolerance.analysis import ToleranceStudyResult
from jointplay.tolerance.definitions import response_definitions

__all__ = [
    "display_scale",
    "format_value",
    "input_label",
    "sampling_note",
    "study_plots",
    "write_study",
]

#: Failures listed in the HTML report (samples.parquet and summary.json have more).
MAX_REPORTED_FAILURES = 100


def display_scale(unit: str, kind: str = "") -> tuple[str, float]:
    """(label, factor) that turns an SI value into report units: mm, µm (clearances), deg."""
    if unit == "m":
        return ("µm", 1e6) if kind == "clearance" else ("mm", 1e3)
    if unit == "rad":
        return "deg", 180.0 / math.pi
    return unit.replace("^2", "²").replace("*", "·"), 1.0


def format_value(value: float | None, scale: float = 1.0) -> str:
    """``value × scale`` with 5 significant digits; ``–`` for a missing or non-finite value."""
    if value is None:
        return "–"
    scaled = float(value) * scale
    return f"{scaled:.5g}" if math.isfinite(scaled) else "–"


def input_label(name: str) -> str:
    """Short label of an input for plots and tables: ``crank`` for ``length_crank``."""
    return name.replace("length_", "").replace("clearance_", "clearance ").replace("_", " ")


def write_study(
    study: ToleranceStudyResult,
    folder: Path,
    *,
    plots: bool = True,
    provenance: Mapping[str, Any] | None = None,
    figure_format: str = "png",
) -> list[Path]:
    """Write ``samples.parquet``, ``summary.json``, the PNG plots and ``report.html``.

    Args:
        study: the finished (or interrupted) study.
        folder: an existing folder.
        plots: draw the PNG plots (and embed them in the report).
        provenance: recorded under ``provenance`` in ``summary.json`` (versions, command).
        figure_format: ``"png"``, or ``"svg"``/``"pdf"`` written beside each PNG.

    Returns:
        The files written.
    """
    folder = Path(folder)
    written = [folder / "samples.parquet", folder / "summary.json"]
    study.to_dataframe().to_parquet(written[0], index=False)
    summary = study.summary()
    summary["response_definitions"] = response_definitions(study.result.response_names)
    note = sampling_note(study)
    if note:
        summary["sampling_distributions"] = note
    if provenance is not None:
        summary["provenance"] = dict(provenance)
    write_json(written[1], summary)
    images: dict[str, bytes] = {}
    if plots:
        images = study_plots(study, figure_format)
        for name, data in images.items():
            path = folder / name
            path.write_bytes(data)
            written.append(path)
    written.append(_report(study, summary, images).write(folder / "report.html"))
    return written


def _input_scale(study: ToleranceStudyResult, name: str) -> tuple[str, float]:
    item = study.spec[name]
    return display_scale(item.unit, item.kind)


#: Ticks per numeric axis (at most): matplotlib's automatic choice, up to 9 on these panels,
#: made the ticks most of the drawing time (0.4 s per nine-panel figure here; 0.27 s so).
_TICKS = 5


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


def study_plots(study: ToleranceStudyResult, figure_format: str = "png") -> dict[str, bytes]:
    """The study's images by file name: tornado, and for Monte Carlo histograms and scatter;
    PNG, and also ``figure_format`` (svg, pdf) for print."""
    plt = pyplot()
    r = study.result
    names = list(r.response_names)
    images = {}
    fig, axes = _grid(plt, len(names), left=0.1, numeric="x")
    what = "share of the worst-case stack" if r.method == "worst-case" else "share of variance"
    for ax, name in zip(axes, names, strict=True):
        shares = r.summaries[name].contributions
        order = sorted(shares, key=lambda k: shares[k])
        ax.barh([input_label(k) for k in order], [100.0 * shares[k] for k in order], color="C0")
        ax.set_xlim(0, 100)
        ax.set_title(name, fontsize=9, y=1.0)
        ax.set_xlabel(f"{what} (%)", fontsize=8)
        ax.tick_params(labelsize=7)
        ax.grid(True, axis="x", alpha=0.3)
    fig.suptitle(f"{study.mechanism.name}: contributions ({r.method})", fontsize=10)
    images.update(encode(fig, "tornado", figure_format))
    if r.method != "monte-carlo":
        return images
    ok = r.run.status == 0
    fig, axes = _grid(plt, len(names))
    legend: dict[str, Any] = {}  # one legend for the figure: the same lines in every panel
    for j, (ax, name) in enumerate(zip(axes, names, strict=True)):
        unit, scale = display_scale(r.units[name])
        values = r.run.values[ok, j] * scale
        summary = r.summaries[name]
        if len(values):
            ax.hist(
                values,
                bins=min(60, max(10, int(math.sqrt(len(values))))),
                color="0.75",
                histtype="stepfilled",  # one patch, not one per bin: fast to draw
            )
        ax.axvline(summary.nominal * scale, color="k", linewidth=1.2, label="nominal")
        if summary.mean is not None:
            ax.axvline(summary.mean * scale, color="C0", linestyle="--", linewidth=1, label="mean")
        if study.ideal is not None and name in study.ideal:
            ax.axvline(
                study.ideal[name] * scale,
                color="C2",
                linestyle="-.",
                linewidth=1,
                label="ideal joints",
            )
        if summary.limits is not None:
            for value in (summary.limits.lower, summary.limits.upper):
                if value is not None:
                    ax.axvline(
                        value * scale, color="C3", linestyle=":", linewidth=1.5, label="spec limit"
                    )
        ax.set_title(name, fontsize=9, y=1.0)
        ax.set_xlabel(unit, fontsize=8)
        ax.tick_params(labelsize=7)
        handles, labels = ax.get_legend_handles_labels()
        legend.update(zip(labels, handles, strict=True))
    fig.legend(legend.values(), legend.keys(), loc="upper right", ncol=len(legend), fontsize=8)
    fig.suptitle(f"{study.mechanism.name}: Monte Carlo, {int(ok.sum())} samples", fontsize=10)
    images.update(encode(fig, "histograms", figure_format))
    fig, axes = _grid(plt, len(names))
    shown = np.flatnonzero(ok)[:5000]
    for j, (ax, name) in enumerate(zip(axes, names, strict=True)):
        summary = r.summaries[name]
        driver = summary.most_influential or r.input_names[0]
        i = r.input_names.index(driver)
        x_unit, x_scale = _input_scale(study, driver)
        y_unit, y_scale = display_scale(r.units[name])
        ax.scatter(r.x[shown, i] * x_scale, r.run.values[shown, j] * y_scale, s=3, alpha=0.4)
        nominal_x = study.spec.nominal[i] * x_scale
        ax.plot([nominal_x], [summary.nominal * y_scale], "k+", markersize=10, label="nominal")
        share = 100.0 * summary.contributions.get(driver, 0.0)
        ax.set_title(f"{name} ({share:.0f} % from {input_label(driver)})", fontsize=9, y=1.0)
        ax.set_xlabel(f"{input_label(driver)} ({x_unit})", fontsize=8)
        ax.set_ylabel(y_unit, fontsize=8)
        ax.tick_params(labelsize=7)
    fig.suptitle(f"{study.mechanism.name}: most influential input per response", fontsize=10)
    images.update(encode(fig, "scatter", figure_format))
    return images


def _scaled(value: float | None, scale: float = 1.0) -> float | None:
    """``value × scale`` for a report table (the table writes numbers in the report's one
    format); None (an em dash) for a missing or non-finite value."""
    if value is None or not math.isfinite(float(value)):
        return None
    return float(value) * scale


#: Method settings in words, for the report.
_SETTING_WORDS = {
    "samples": "samples",
    "seed": "seed",
    "sampling": "sampling",
    "truncated_at_limits": "normal inputs truncated at their limits",
    "corners": "corners",
    "fd_step": "finite-difference step (fraction of each half-width)",
    "sensitivity": "sensitivities",
}


def sampling_note(study: ToleranceStudyResult) -> str:
    """How the inputs were sampled (Monte Carlo), in one sentence; "" for other methods."""
    from jointplay.tolerance.methods import distribution_note

    r = study.result
    if r.method != "monte-carlo":
        return ""
    truncate = bool(r.settings.get("truncated_at_limits", False))
    return distribution_note(study.spec, truncate)


def _report(
    study: ToleranceStudyResult, summary: Mapping[str, Any], images: Mapping[str, bytes]
) -> HtmlReport:
    from jointplay.tolerance.definitions import response_definition

    r = study.result
    counts = summary["counts"]
    page = HtmlReport(f"Tolerance study of {study.mechanism.name}")
    settings = "; ".join(f"{_SETTING_WORDS.get(k, k)}: {v}" for k, v in r.settings.items())
    page.paragraph(
        f"Method {r.method}, {study.responses} responses. Settings: {settings}. "
        f"Points: {counts['points']}, ok {counts['ok']}, failed {counts['failed']}, "
        f"not run {counts['not_run']}{' (interrupted)' if r.interrupted else ''}."
    )
    for finding in study.diagnostics:
        d = finding.diagnostic
        where = f", joint {d.joint}" if d.joint else ""
        page.paragraph(f"Warning ({d.code}{where}): {d.message}.", css="note")
    note = sampling_note(study)
    if note:
        page.paragraph(f"Sampling: {note}.", css="note")
    page.heading("Inputs", anchor="inputs")
    rows = []
    for item in study.spec.inputs:
        unit, scale = display_scale(item.unit, item.kind)
        t = item.tolerance
        rows.append(
            [
                input_label(item.name),
                unit,
                *(_scaled(v, scale) for v in (item.nominal, t.lower, t.upper)),
                t.distribution,
                _scaled(t.mean, scale),
                _scaled(t.std, scale),
                item.source,
            ]
        )
    headers = [
        "input",
        "unit",
        "nominal",
        "lower limit",
        "upper limit",
        "distribution",
        "mean",
        "standard deviation",
        "source",
    ]
    page.table(rows, headers, text_columns=(0, 1, 5, 8))
    page.heading("Responses", anchor="responses")
    columns = ["nominal", "mean", "std", "minimum", "maximum", "half_range"]
    words = {"std": "standard deviation", "half_range": "half range"}
    extra = {"out_of_spec_percent": "out of spec (%)", "cp": "Cp", "cpk": "Cpk"}
    headers = ["response", "unit", *(words.get(c, c) for c in columns)]
    if study.ideal is not None:
        headers.append("ideal joints")
    headers += [*extra.values(), "most influential input (share)"]
    rows = []
    for name, response in r.summaries.items():
        unit, scale = display_scale(response.unit)
        cells = [_scaled(getattr(response, c), scale) for c in columns]
        if study.ideal is not None:
            cells.append(_scaled(study.ideal.get(name), scale))
        cells += [_scaled(getattr(response, c)) for c in extra]
        top = response.most_influential
        influence = (
            f"{input_label(top)} ({100 * response.contributions[top]:.0f} %)" if top else "—"
        )
        rows.append([name, unit, *cells, influence])
    page.table(rows, headers, text_columns=(0, 1, len(headers) - 1))
    page.heading("What each response means", level=3, anchor="definitions")
    page.table(
        [
            [name, display_scale(r.units[name])[0], response_definition(name)]
            for name in r.summaries
        ],
        ["response", "unit", "definition"],
        text_columns=(0, 1, 2),
    )
    failures = r.failures
    page.heading(f"Failures ({len(failures)})", anchor="failures")
    if failures:
        rows = [
            [
                str(f.index),
                f.role,
                *(_scaled(f.inputs[n], _input_scale(study, n)[1]) for n in r.input_names),
                f.error,
            ]
            for f in failures[:MAX_REPORTED_FAILURES]
        ]
        headers = [
            "sample",
            "role",
            *(f"{input_label(n)} ({_input_scale(study, n)[0]})" for n in r.input_names),
            "error",
        ]
        page.table(rows, headers, text_columns=(0, 1, len(headers) - 1))
        if len(failures) > MAX_REPORTED_FAILURES:
            page.paragraph(
                f"… and {len(failures) - MAX_REPORTED_FAILURES} more (see samples.parquet)."
            )
    else:
        page.paragraph("None.")
    for name, data in images.items():
        if not name.endswith(".png"):
            continue  # print copies: files beside the report
        title = _FIGURE_TITLES.get(name, name.removesuffix(".png"))
        page.heading(title, anchor=name.removesuffix(".png"))
        page.figure(data, name)
    return page


#: Report headings of the study's figures.
_FIGURE_TITLES = {
    "tornado.png": "Contributions of the inputs",
    "histograms.png": "Distributions of the responses",
    "scatter.png": "Each response against its most influential input",
}
