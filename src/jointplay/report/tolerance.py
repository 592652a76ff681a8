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
from collections.abc import Callable, Mapping
from concurrent.futures import BrokenExecutor, Executor, Future
from pathlib import Path
from typing import Any

import numpy as np

from jointplay.io.output import signals_held, write_json
from jointplay.report.figures import FIGURE_FORMATS
from jointplay.report.html import HtmlReport
from jointplay.report.tolerance_plots import (
    display_scale,
    histograms,
    input_label,
    scatter,
    tornado,
)
from jointplay.tolerance.analysis import ToleranceStudyResult
from jointplay.tolerance.definitions import response_definitions
from jointplay.tolerance.response_base import REGIME_CHECKS

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


def format_value(value: float | None, scale: float = 1.0) -> str:
    """``value × scale`` with 5 significant digits; ``–`` for a missing or non-finite value."""
    if value is None:
        return "–"
    scaled = float(value) * scale
    return f"{scaled:.5g}" if math.isfinite(scaled) else "–"


def write_study(
    study: ToleranceStudyResult,
    folder: Path,
    *,
    plots: bool = True,
    provenance: Mapping[str, Any] | None = None,
    figure_format: str = "png",
    executor: Executor | None = None,
) -> list[Path]:
    """Write ``samples.parquet`` and ``summary.json`` (both whole, whatever the signals),
    then the PNG plots and ``report.html``.

    Args:
        study: the finished (or interrupted) study.
        folder: an existing folder.
        plots: draw the PNG plots (and embed them in the report).
        provenance: recorded under ``provenance`` in ``summary.json`` (versions, command).
        figure_format: ``"png"``, or ``"svg"``/``"pdf"`` written beside each PNG.
        executor: worker processes that draw some of the plots (:func:`study_plots`).

    Returns:
        The files written.
    """
    folder = Path(folder)
    written = [folder / "samples.parquet", folder / "summary.json"]
    with signals_held():  # the data first, whole: an interrupt in the figures keeps them
        summary = study.summary()
        summary["response_definitions"] = response_definitions(study.result.response_names)
        note = sampling_note(study)
        if note:
            summary["sampling_distributions"] = note
        if provenance is not None:
            summary["provenance"] = dict(provenance)
        study.to_dataframe().to_parquet(written[0], index=False)
        write_json(written[1], summary)
    images: dict[str, bytes] = {}
    if plots:
        images = study_plots(study, figure_format, executor)
        for name, data in images.items():
            path = folder / name
            path.write_bytes(data)
            written.append(path)
    written.append(_report(study, summary, images).write(folder / "report.html"))
    return written


def _input_scale(study: ToleranceStudyResult, name: str) -> tuple[str, float]:
    item = study.spec[name]
    return display_scale(item.unit, item.kind)


def study_plots(
    study: ToleranceStudyResult, figure_format: str = "png", executor: Executor | None = None
) -> dict[str, bytes]:
    """The study's images by file name: tornado, and for Monte Carlo histograms and scatter;
    PNG, and also ``figure_format`` (svg, pdf) for print.

    Args:
        executor: worker processes that draw all figures but the last while this process
            draws that one (the same images; default: all drawn here, one after the other).
            A pool that is shut down or broken leaves its figures to this process.
    """
    jobs = _figure_jobs(study, figure_format)
    pending: list[Future[dict[str, bytes]]] = []
    if executor is not None:
        try:
            pending = [executor.submit(function, *args) for function, args in jobs[:-1]]
        except (RuntimeError, BrokenExecutor):  # shut down (RuntimeError) or broken
            pending = []
    images: dict[str, bytes] = {}
    for function, args in jobs[len(pending) :]:
        images.update(function(*args))
    for (function, args), future in zip(jobs, pending, strict=False):
        try:
            images.update(future.result())
        except BrokenExecutor:  # a worker died: draw its figure here
            images.update(function(*args))
    return {name: images[name] for name in sorted(images, key=_FIGURE_ORDER.index)}


#: The files of :func:`study_plots`, in the order the report shows them.
_FIGURE_ORDER = [
    f"{stem}.{suffix}" for stem in ("tornado", "histograms", "scatter") for suffix in FIGURE_FORMATS
]


def _figure_jobs(
    study: ToleranceStudyResult, figure_format: str
) -> list[tuple[Callable[..., dict[str, bytes]], tuple[Any, ...]]]:
    """(drawing function of :mod:`jointplay.report.tolerance_plots`, its arguments) per figure:
    the study's numbers in report units."""
    r = study.result
    names = list(r.response_names)
    what = "share of the worst-case stack" if r.method == "worst-case" else "share of variance"
    shares = [
        (name, {input_label(k): v for k, v in r.summaries[name].contributions.items()})
        for name in names
    ]
    title = study.mechanism.name
    jobs: list[tuple[Callable[..., dict[str, bytes]], tuple[Any, ...]]] = [
        (tornado, (f"{title}: contributions ({r.method})", what, shares, figure_format))
    ]
    if r.method != "monte-carlo":
        return jobs
    ok = r.run.status == 0
    shown = np.flatnonzero(ok)[:5000]
    counts, points = [], []
    for j, name in enumerate(names):
        summary = r.summaries[name]
        unit, scale = display_scale(r.units[name])
        ideal = study.ideal.get(name) if study.ideal is not None else None
        limits = (summary.limits.lower, summary.limits.upper) if summary.limits else ()
        counts.append(
            {
                "name": name,
                "unit": unit,
                "values": r.run.values[ok, j] * scale,
                "nominal": summary.nominal * scale,
                "mean": None if summary.mean is None else summary.mean * scale,
                "ideal": None if ideal is None else ideal * scale,
                "limits": [value * scale for value in limits if value is not None],
            }
        )
        driver = summary.most_influential or r.input_names[0]
        i = r.input_names.index(driver)
        x_unit, x_scale = _input_scale(study, driver)
        share = 100.0 * summary.contributions.get(driver, 0.0)
        points.append(
            {
                "title": f"{name} ({share:.0f} % from {input_label(driver)})",
                "x_label": f"{input_label(driver)} ({x_unit})",
                "y_label": unit,
                "x": r.x[shown, i] * x_scale,
                "y": r.run.values[shown, j] * scale,
                "nominal": (study.spec.nominal[i] * x_scale, summary.nominal * scale),
            }
        )
    jobs.append(
        (histograms, (f"{title}: Monte Carlo, {int(ok.sum())} samples", counts, figure_format))
    )
    jobs.append((scatter, (f"{title}: most influential input per response", points, figure_format)))
    return jobs


def _percent(fraction: float | None) -> float | None:
    """A fraction in %, ``None`` kept."""
    return None if fraction is None else 100.0 * fraction


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
    contact = study.model.get("contact") if isinstance(study.model, Mapping) else None
    if contact:
        page.paragraph(f"Contact: {contact}.")
    for finding in study.diagnostics:
        d = finding.diagnostic
        where = f", joint {d.joint}" if d.joint else ""
        label = "Warning" if d.level == "warning" else "Note"  # the convergence rule's note
        page.paragraph(f"{label} ({d.code}{where}): {d.message}.", css="note")
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
    regimes = summary.get("lubrication_regimes")
    if regimes:
        page.heading("Lubrication regimes", level=3, anchor="regimes")
        page.table(
            [
                [
                    joint,
                    *(_percent(entry[f"{regime}_mean"]) for regime in REGIME_CHECKS),
                    f"{entry['left_full_film']} of {entry['samples']}",
                ]
                for joint, entry in regimes["joints"].items()
            ],
            ["joint", "full film (%)", "mixed (%)", "boundary (%)",
             "samples that left full film"],
            text_columns=(0, 4),
            note=regimes["definition"],
        )  # fmt: skip
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
