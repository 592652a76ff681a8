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
from jointplay.io.output import signals_held, write_csv, write_json
from jointplay.report._mpl import pyplot
from jointplay.report.figures import encode
from jointplay.report.html import HtmlReport
from jointplay.study.design import DesignResult, kept_lives
from jointplay.study.design_result import regime_rows
from jointplay.study.life_result import LifeResult
from jointplay.study.requirements import Requirement
from jointplay.study.sensitivity import ModelSensitivity, SensitivityRow

__all__ = [
    "YIELD_ALL",
    "binding_requirement",
    "design_plots",
    "design_section",
    "display",
    "evidence_line",
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
    "rad": ("deg", 180.0 / math.pi),
}


def display(unit: str) -> tuple[str, float]:
    """Display unit and the factor from SI of a response unit."""
    return _DISPLAY.get(unit, (unit, 1.0))


#: Columns of the scheme table in %: yields and their interval bounds, overall and per
#: requirement (longest prefix first).
_PERCENT_PREFIXES = ("yield_low", "yield_high", "yield", "verdict_low", "verdict_high")


def csv_table(table: pd.DataFrame, units: Mapping[str, str]) -> pd.DataFrame:
    """The scheme table as ``design.csv`` shows it: each response column in its display unit
    with the unit in its name (``joint_force_mean_N``, ``life_at_confidence_h``,
    ``contact_pressure_std_MPa``, ``rocker_speed_error_mean_pct``), yields ``..._pct``, the
    relative cost ``cost_relative``; ``design.parquet`` keeps SI and the plain names."""
    renamed: dict[str, str] = {"cost": "cost_relative"}
    out = table.copy()
    for column in table.columns:
        name = str(column)
        for suffix in ("_mean", "_std", "_at_confidence"):
            response = name.removesuffix(suffix)
            if response != name and response in units:
                unit, scale = display(units[response])
                out[name] = table[name] * scale
                renamed[name] = f"{name}_{_unit_tag(unit)}"
        for prefix in _PERCENT_PREFIXES:
            if name == prefix or name.startswith(f"{prefix}_"):
                renamed[name] = f"{prefix}_pct{name.removeprefix(prefix)}"
                break
    return out.rename(columns=renamed)


def _unit_tag(unit: str) -> str:
    """A unit as a column-name suffix: ``%`` → ``pct``, ``µm/h`` → ``um_per_h``."""
    tag = unit.replace("%", "pct").replace("µ", "u").replace("*", "_").replace("^", "")
    return tag.replace("/", "_per_") or "1"


def binding_requirement(result: DesignResult, row: Mapping[Any, Any]) -> Requirement | None:
    """The requirement of a scheme closest to failing: the lowest lower bound of its
    yield's 95 % interval; among equal bounds (every sample meeting every requirement, say)
    the smallest margin of the response at the confidence level to its limit, relative to
    the limit."""
    if not result.requirements:
        return None

    def margin(r: Requirement) -> float:
        value = float(row.get(f"{r.response}_at_confidence", math.nan))
        if not (math.isfinite(value) and r.limit != 0):
            return math.inf
        return (r.limit - value if r.upper else value - r.limit) / abs(r.limit)

    return min(result.requirements, key=lambda r: (row[f"yield_low_{r.text}"], margin(r)))


#: The label of a scheme's yield over all its requirements, the same in the evidence line,
#: the report's table, the terminal table and the cost-yield plot.
YIELD_ALL = "yield (all requirements)"


def evidence_line(result: DesignResult, row: Mapping[Any, Any]) -> str:
    """The evidence for a scheme in one line: its yield over all requirements (the quantity
    and label of the scheme tables) with its exact 95 % interval and DPM bound, then its
    binding requirement: failures in samples and that requirement's own yield, labelled as
    such."""
    overall = (
        f"{YIELD_ALL} {row['yield']:.2f} % (95 % CI {row['yield_low']:.2f}-"
        f"{row['yield_high']:.2f} %), at most {row['dpm_high']:,.0f} DPM"
    )
    r = binding_requirement(result, row)
    if r is None:
        return f"{row['samples']:,} samples"
    t = r.text
    level = r.confidence if r.confidence is not None else result.confidence
    return (
        f"{overall}; binding requirement {t!r} at {100 * level:g} %: "
        f"{row[f'failures_{t}']:,} failures in {row['samples']:,} samples, yield of {t!r} "
        f"{row[f'yield_{t}']:.2f} % (95 % CI {row[f'yield_low_{t}']:.3f}-"
        f"{row[f'yield_high_{t}']:.3f} %), at most {row[f'dpm_high_{t}']:,.0f} DPM "
        f"({row[f'verdict_{t}']})"
    )


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
    colours = {"meets": "tab:green", "undecided": "tab:orange", "fails": "tab:red"}
    for name, colour in colours.items():
        part = table[table["verdict"] == name]
        if not len(part):
            continue
        ax.errorbar(
            part["cost"],
            part["yield"],
            yerr=[part["yield"] - part["yield_low"], part["yield_high"] - part["yield"]],
            fmt="o",
            c=colour,
            capsize=3,
            label=f"{name} (95 % interval)",
        )
    front = table[table["pareto_yield"]].sort_values("cost")
    ax.step(front["cost"], front["yield"], where="post", c="k", lw=1, label="Pareto front")
    ax.axhline(
        100 * result.confidence, c="k", ls=":", lw=1, label=f"level {100 * result.confidence:g} %"
    )
    for k, (_, row) in enumerate(table.sort_values("cost").iterrows()):
        ax.annotate(  # staggered: schemes of nearly the same cost and yield stay legible
            f"{row['scheme']} (n={row['samples']:,})",
            (row["cost"], row["yield"]),
            xytext=(4, 4 - 9 * (k % 4)),
            textcoords="offset points",
            fontsize=6,
        )
    ax.set_xlabel("relative cost")
    ax.set_ylabel(f"{YIELD_ALL}, %")
    ax.set_title(f"{result.mechanism.name}: cost against yield (exact 95 % intervals)")
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


def verdict_interval(result: DesignResult) -> str:
    """The interval the study's verdicts were decided on, in words."""
    from jointplay.tolerance.confidence import RULE_INTERVALS

    rule = str(result.settings.get("verdict_rule", "fixed"))
    return RULE_INTERVALS.get(rule, RULE_INTERVALS["fixed"])


def looks_text(settings: Mapping[str, Any]) -> str:
    """The looks at the verdicts in words: ``one look at 200`` or ``looks every 100 up to
    4,000``."""
    looks = [int(n) for n in settings.get("looks", [])]
    if len(looks) == 1:
        return f"one look at {looks[0]:,}"
    if not looks:
        return "no look"
    return f"looks every {looks[0]:,} up to {looks[-1]:,}"


#: What the ``stopped`` column says, in words.
STOPPED = {
    "decided": "decided",
    "dearer": "dearer than a scheme shown to meet",
    "max-samples": "at the most samples",
    "time": "at the time budget",
    "interrupted": "interrupted",
}


def stop_line(result: DesignResult) -> str:
    """How many schemes stopped for each reason, e.g. ``stopped: 5 decided, 3 dearer than a
    scheme shown to meet``; empty without a ``stopped`` column."""
    table = result.table
    if not len(table) or "stopped" not in table:
        return ""
    counts = table["stopped"].value_counts()
    parts = [f"{int(counts[k])} {STOPPED[k]}" for k in STOPPED if k in counts]
    waiting = [r.get("stopped") for r in result.settings.get("not_run") or ()]
    not_run = [f"{waiting.count(k)} {STOPPED[k]}" for k in STOPPED if k in waiting]
    if not_run:  # dearer schemes that waited for a cheaper one (the cost-ordered schedule)
        parts.append(f"not run: {', '.join(not_run)}")
    return "stopped: " + ", ".join(parts)


def life_scheme(result: DesignResult) -> Mapping[str, Any] | None:
    """The scheme whose lives the report shows for a B_p requirement: the answer, else the
    cheapest scheme (``None`` without a B_p requirement or a finished scheme)."""
    if not any(r.quantile is not None for r in result.requirements) or not len(result.table):
        return None
    best = result.best_row
    if best is not None:
        return best
    cheapest = result.table.sort_values("cost").iloc[0]
    return {str(k): v for k, v in cheapest.items()}


def scheme_lives(result: DesignResult, scheme: str) -> LifeResult | None:
    """A scheme's functional lives (a B_p requirement's samples) as a population-life result,
    for :mod:`jointplay.report.life`'s Weibull-paper plot; ``None`` without them."""
    from jointplay.study.life_result import LifeResult
    from jointplay.study.requirements import FUNCTIONAL_LIFE

    frame = result.samples
    if FUNCTIONAL_LIFE not in frame or not len(frame):
        return None
    rows = frame[frame["scheme"] == scheme].sort_values("sample")
    hours = (result.settings.get("functional_life") or {}).get("hours_s")
    if not len(rows) or hours is None:
        return None
    n = len(rows)
    lives = kept_lives(rows, float(hours))
    return LifeResult(
        mechanism_name=result.mechanism.name,
        criteria=tuple((result.settings.get("functional_life") or {}).get("criteria", ())),
        input_names=(),
        feature_names=(),
        features=np.empty((n, 0)),
        inputs=np.empty((n, 0)),
        lives=lives,
        settings={"scheme": scheme},
    )


def life_quantile_lines(result: DesignResult) -> list[str]:
    """Per B_p requirement, the first-screen answer for the scheme shown
    (:func:`life_scheme`): its verdict on the interval it was decided on, how many samples
    failed before the hours, the order-statistic B_p with its exact interval, and the
    requirement that ended most lives."""
    from jointplay.study.life_result import quantile_text
    from jointplay.study.weibull import INTERVAL_LEVEL, empirical_quantile

    row = life_scheme(result)
    if row is None:
        return []
    population = scheme_lives(result, str(row["scheme"]))
    out = []
    for r in result.requirements:
        if r.quantile is None:
            continue
        t = r.text
        n = int(row["samples"])
        text = (
            f"{t}: {row[f'verdict_{t}']} for {row['scheme']} — {int(row[f'failures_{t}'])} of "
            f"{n} samples fail before {r.limit / 3600.0:g} h (a failed simulation counts); the "
            f"share outliving it is {row[f'verdict_low_{t}']:.3g}–"
            f"{row[f'verdict_high_{t}']:.3g} % ({_decision_interval(result)}) against the "
            f"{100 * (1 - r.quantile):g} % required"
        )
        if population is not None:
            q = empirical_quantile(population.lives.life, population.lives.censored, r.quantile)
            text += (
                f"; B{100 * r.quantile:g} {quantile_text(q, population.lives.hours)} (order statistic, "
                f"{100 * INTERVAL_LEVEL:g} %)"
            )
            shares = population.shares
            if shares:
                top, share = next(iter(shares.items()))
                text += f"; {top} ends {100 * share:.0f} % of the lives that end"
        out.append(text)
    return out


def _decision_interval(result: DesignResult) -> str:
    rule = result.settings.get("verdict_rule", "fixed")
    return "95 % confidence sequence" if rule == "sequential" else "exact 95 % interval"


def design_section(
    report: HtmlReport,
    result: DesignResult,
    units: Mapping[str, str],
    images: Mapping[str, bytes],
    sensitivity: ModelSensitivity | None = None,
) -> None:
    """The design study's section of an HTML report: the answer, its evidence and warnings,
    then, on the same first screen, the model-sensitivity table of the choice
    (``sensitivity``, :mod:`jointplay.study.sensitivity`); the study's settings, the schemes,
    the lubricated joints' regimes and the figures below."""
    from jointplay.tolerance.definitions import response_definition

    report.heading("Design: fit and length class", anchor="design")
    report.paragraph(f"Answer: {result.verdict}.")
    for line in life_quantile_lines(result):  # B_p: the population's life, on the first screen
        report.paragraph(f"Life: {line}.")
    best = result.best_row
    if best is not None:
        report.paragraph(f"Evidence: {evidence_line(result, best)}.")
        report.bullets([f"drawing: {c.text}" for c in result.drawing])
    elif len(result.table):
        cheapest = result.table.sort_values("cost").iloc[0].to_dict()
        report.paragraph(
            f"Cheapest scheme, {cheapest['scheme']}: {evidence_line(result, cheapest)}."
        )
    for finding in result.diagnostics:  # right under the verdict they qualify
        d = finding.diagnostic
        where = f", joint {d.joint}" if d.joint else ""
        report.paragraph(f"Warning ({d.code}{where}): {d.message}.", css="note")
    if sensitivity is not None:  # the answer's robustness, beside it on the first screen
        _sensitivity_section(report, sensitivity, units, result.confidence)
    settings = result.settings
    report.bullets(
        [f"requirement: {r.text}" for r in result.requirements]
        + [
            f"confidence level: {100 * result.confidence:g} %: a scheme meets a requirement "
            f"when the lower bound of its yield's {verdict_interval(result)} reaches it, fails "
            "when the upper bound stays below it, and is undecided otherwise; the yields "
            "reported carry their exact (Clopper-Pearson) 95 % interval",
            f"responses: {result.responses}; samples per scheme: {settings.get('samples')} "
            f"({looks_text(settings)})",
        ]
        + [line for line in [stop_line(result)] if line]
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
            "verdict": "verdict",
            "samples": "samples (what the verdict took)",
            "stopped": "stopped",
            "yield": f"{YIELD_ALL} (%)",
            "yield_low": f"{YIELD_ALL}, 95 % lower bound (%)",
            "dpm_high": "DPM, 95 % upper bound",
            "failed": "failed simulations",
        }
        shown = table[list(columns)].rename(columns=columns)
        for r in result.reported_responses:
            unit, scale = display(units.get(r, ""))
            label = f"{r} at {100 * result.confidence:g} % ({unit})"
            shown[label] = table[f"{r}_at_confidence"] * scale
            shown[f"{r}: basis"] = table[f"{r}_at_confidence_basis"]
        for finding in result.diagnostics:  # the joints whose pins pass the clearance
            if finding.diagnostic.code != "penetration-exceeds-clearance":
                continue
            joint = finding.diagnostic.joint
            shown[f"samples beyond the clearance in {joint}"] = table[
                f"penetration_exceeds_{joint}"
            ]
        report.table(
            shown.sort_values(columns["cost"]),
            caption="Schemes by cost; values at the level: 'order-statistic' = a "
            "distribution-free 95 % bound, 'normal-model' = mean + z·std, an estimate",
            text_columns=tuple(
                i
                for i, c in enumerate(shown.columns)
                if c in (columns["scheme"], "verdict", "stopped") or str(c).endswith(": basis")
            ),
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
        _regime_section(report, result)
    for name, data in images.items():
        if name.endswith(".png"):  # the others are print copies beside the report
            report.figure(data, name.removesuffix(".png").replace("_", " "))


def _regime_section(report: HtmlReport, result: DesignResult) -> None:
    """The lubricated joints' regimes of the chosen scheme (else the cheapest one): per joint,
    the mean fractions of time in full film, mixed and boundary lubrication and the samples
    that ever left full film; nothing for a dry or kinematic design."""
    row: Mapping[str, Any] | None = result.best_row
    if row is None and len(result.table):
        row = {str(k): v for k, v in result.table.sort_values("cost").iloc[0].items()}
    if row is None:
        return
    rows = regime_rows(row)
    if not rows:
        return
    report.heading("Lubrication regimes", level=3, anchor="design-regimes")
    report.table(
        rows,
        headers=["joint", "full film (%)", "mixed (%)", "boundary (%)",
                 "samples that left full film"],
        text_columns=(0, 4),
        caption=f"Scheme {row['scheme']}: mean share of the analysed time in each regime over "
        "its successful samples (lambda = h_min/sigma >= 3 full film, < 1 boundary; "
        "docs/contact.md)",
    )  # fmt: skip


def _sensitivity_section(
    report: HtmlReport,
    sensitivity: ModelSensitivity,
    units: Mapping[str, str],
    confidence: float,
) -> None:
    """The model-sensitivity table: the chosen scheme's yields, and each required response
    at the confidence level (in ``units``' display units), under each contact model."""
    report.heading("Model sensitivity of the choice", level=3, anchor="model-sensitivity")
    report.paragraph(sensitivity.verdict)
    requirements = list(sensitivity.rows[0].yields)
    responses = list(sensitivity.rows[0].values)
    scales = {name: display(units.get(name, "")) for name in responses}

    def interval(row: SensitivityRow, text: str) -> str:
        low, high = row.intervals.get(text, (math.nan, math.nan))
        return f"{low:.2f}–{high:.2f}"

    rows = [
        (
            row.parameter,
            str(row.value),
            *(
                cell
                for text in requirements
                for cell in (row.yields[text], interval(row, text), row.worse.get(text, 0))
            ),
            *(row.values.get(name, math.nan) * scales[name][1] for name in responses),
            row.verdict or ("meets" if row.meets else "no"),
        )
        for row in sensitivity.rows
    ]
    level = f"{100 * confidence:g} %"
    estimated = any(b == "normal-model" for row in sensitivity.rows for b in row.bases.values())
    on = f"{sensitivity.on}, " if sensitivity.on else ""
    headers = [
        "contact parameter",
        "value",
        *(
            header
            for r in requirements
            for header in (f"yield: {r} (%)", "95 % interval (%)", "parts worse")
        ),
        *(f"{name} at {level} ({scales[name][0]})" for name in responses),
        f"verdict at {sensitivity.samples:,} samples" if sensitivity.samples else "verdict",
    ]
    report.table(
        rows,
        headers=headers,
        text_columns=(
            0,
            1,
            *(2 + 3 * k + 1 for k in range(len(requirements))),
            len(headers) - 1,
        ),
        note="one parameter at a time at the ends of its documented range (docs/contact.md), "
        f"the others as the study ran; {on}the first of the chosen scheme's sample stream, "
        "the same parts in every row (the study's seed); exact 95 % intervals at that fixed "
        "number; parts worse: those parts that fail the requirement under the row's model and "
        "met it as chosen"
        + (
            "; values at the level: normal-model estimates where the samples are too few for "
            "a 95 % order-statistic bound"
            if estimated
            else ""
        ),
    )


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
    (:mod:`jointplay.study.sensitivity`), in ``summary.json`` and the report.

    The data files and ``summary.json`` come first, each whole whatever the signals, so that
    an interrupt while the figures are drawn keeps them."""
    folder = Path(folder)
    written = [folder / "design.parquet", folder / "design.csv", folder / "samples.parquet"]
    written.append(folder / "summary.json")
    with signals_held():  # from here: an interrupt before the files are whole would lose them
        table = result.to_dataframe()
        summary = result.summary()
        if sensitivity is not None:
            summary["model_sensitivity"] = sensitivity.as_dict()
        if provenance is not None:
            summary["provenance"] = dict(provenance)
        table.to_parquet(written[0], index=False)
        write_csv(csv_table(table, units), written[1], float_format=None)
        result.samples.to_parquet(written[2], index=False)
        write_json(written[-1], summary)
    images = design_plots(result, units, figure_format) if plots else {}
    if plots:
        images.update(design_life_plots(result, figure_format))
    for name, data in images.items():
        (folder / name).write_bytes(data)
        written.append(folder / name)
    report = HtmlReport(f"jointplay design — {result.mechanism.name}")
    design_section(report, result, units, images, sensitivity)
    written.append(report.write(folder / "report.html"))
    return written


def design_life_plots(result: DesignResult, figure_format: str = "png") -> dict[str, bytes]:
    """A B_p requirement: the shown scheme's functional lives on Weibull probability paper
    (:func:`jointplay.report.life.probability_figure`: the failures at their median ranks,
    the lives censored at the hours as right-censored points, the censored fit with its
    band when at least two samples failed), ``design_life.png``; none without a failure."""
    from jointplay.report.life import probability_figure

    row = life_scheme(result)
    population = None if row is None else scheme_lives(result, str(row["scheme"]))
    if population is None:
        return {}
    fig = probability_figure(population)
    if fig is None:
        return {}
    fig.axes[0].set_title(f"functional life of {row['scheme']} on Weibull paper")  # type: ignore[index]
    return _encode(fig, "design_life", figure_format)


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
    images.update(_encode(wear_profile_figure(history), "wear_profiles", figure_format))
    return images


def wear_profile_figure(history: WearHistory) -> Any:
    """The worn depth of each joint's bearing and journal around the pin, one polar panel per
    joint: angle labels every 90° outside the circle, depth labels on a ray of their own,
    panels far enough apart that one's 0° never meets the next one's 180°, and the legend
    under the panels, where it covers no label."""
    plt = pyplot()
    names = list(history.bearing_profile)
    fig, axes = plt.subplots(
        1,
        len(names),
        figsize=(3.3 * len(names), 3.9),
        subplot_kw={"projection": "polar"},
        layout="constrained",
    )
    fig.get_layout_engine().set(wspace=0.12)
    for ax, name in zip(np.atleast_1d(axes), names, strict=True):
        bearing = history.bearing_profile[name]
        theta = (np.arange(len(bearing)) + 0.5) * 2 * math.pi / len(bearing)
        ax.plot(theta, bearing * 1e6, label="bearing")
        ax.plot(theta, history.journal_profile[name] * 1e6, label="journal")
        ax.set_title(f"{name}: worn depth (µm)", fontsize=8, pad=12)
        ax.set_thetagrids([0, 90, 180, 270])
        ax.set_rlabel_position(67.5)
        ax.yaxis.set_major_locator(plt.MaxNLocator(3))
        ax.tick_params(labelsize=6)
        ax.tick_params(axis="x", pad=1)
    handles, labels = np.atleast_1d(axes)[0].get_legend_handles_labels()
    fig.legend(handles, labels, loc="outside lower center", ncol=2, fontsize=7)
    return fig


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
    lubrication: Mapping[str, Any] | None = None,
) -> list[Path]:
    """Write the wear life's files into ``folder`` (existing); returns them. ``lubrication``:
    the regime each joint ran in (``summary.json``'s ``lubrication``,
    :meth:`jointplay.dynamics.setup.ContactModel.joint_lubrication`)."""
    folder = Path(folder)
    written = [folder / "wear.csv", folder / "profiles.csv", folder / "summary.json"]
    write_csv(history.to_dataframe(), written[0], float_format=None)
    bins = len(next(iter(history.bearing_profile.values()))) if history.bearing_profile else 0
    profiles: dict[str, Any] = {"angle_deg": (np.arange(bins) + 0.5) * 360.0 / max(bins, 1)}
    for name in history.bearing_profile:
        profiles[f"bearing_{name}_m"] = history.bearing_profile[name]
        profiles[f"journal_{name}_m"] = history.journal_profile[name]
    write_csv(pd.DataFrame(profiles), written[1], float_format=None)
    summary = history.summary()
    if lubrication is not None:
        summary["lubrication"] = dict(lubrication)
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
