"""The paper study's page, first screen: the summary (how many claims hold, the running
mechanism's numbers, the measured and simulated rocker speed) and the claims one by one.

:class:`_Page` is the page being written (its figures and their extra format), shared by the
sections of :mod:`jointplay.report.paper_sections` and :mod:`jointplay.report.paper_checks`.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from pathlib import Path
from typing import Any

from jointplay import __version__
from jointplay.dynamics.diagnostics import IDEAL_FORCE_FACTOR
from jointplay.report.format import number, quantity
from jointplay.report.html import Flagged, HtmlReport
from jointplay.report.overlays import overlay_plots
from jointplay.report.paper_results import (
    AGREEMENT_PCT,
    PAPER,
    _difference,
    _settle,
    claim_counts,
    claim_verdict,
)
from jointplay.study.claims import Claim
from jointplay.study.paper import (
    PAPER_CLEARANCE,
    PEAK_KEYS,
    PaperStudy,
    method_words,
)


class _Page:
    """The page being written, where its figures go and in which extra format."""

    def __init__(self, report: HtmlReport, folder: Path, figure_format: str) -> None:
        self.report = report
        self.folder = folder
        self.figures = folder / "figures"
        self.figure_format = figure_format
        self.images = 0

    def figure(self, written: Path | Sequence[Path], caption: str) -> None:
        """Embed a PNG (the first of ``written``); link its print copy, if one was asked for."""
        png = written if isinstance(written, Path) else written[0]
        vector = None
        if self.figure_format != "png":
            candidate = png.with_suffix(f".{self.figure_format}")
            vector = candidate if candidate.exists() else None
        self.report.figure(png, caption, vector=vector, link_base=self.folder)
        self.images += 1


def _summary_section(page: _Page, study: PaperStudy, claims: list[Claim]) -> None:
    """The first screen: what holds, what does not, the running mechanism's numbers."""
    report = page.report
    o = study.options
    report.heading("Summary", anchor="summary")
    report.paragraph(
        f"{PAPER}, reproduced with jointplay {__version__}: the crank-rocker of the paper's "
        f"Table 1 with radial clearance {PAPER_CLEARANCE * 1e3:g} mm in all four joints, the "
        f"crank at {o.rpm:g} rpm, the six contact-modelling methods (Table 2), the ISO 2768-1 "
        "class c tolerance stack and the measured rocker speed (Table 7). Our reading of the "
        "paper's ambiguous parts: docs/paper-reading.md."
    )
    counts = claim_counts(claims)
    holds, differs = counts["holds"], counts["differs"]
    others = [
        f"{len(members)} {'has' if len(members) == 1 else 'have'} "
        + ("no number in the paper" if verdict == "no paper value" else "no value of ours")
        for verdict, members in counts.items()
        if verdict in ("no paper value", "not computed") and members
    ]
    failing: dict[str, list[str]] = {}  # each failing claim and its error, by section
    for c in differs:
        failing.setdefault(c.section, []).append(f"{c.claim}: {_difference(c)}")
    report.bullets(
        [
            f"Of the paper's {len(claims)} quantitative claims, {len(holds)} hold (within "
            f"{AGREEMENT_PCT:g} % of its number), {len(differs)} do not"
            + "".join(f", {other}" for other in others)
            + ".",
            "Holds: " + ("; ".join(f"{c.claim} ({c.section})" for c in holds) or "none") + ".",
            (
                "Does not hold: none."
                if not differs
                else "Does not hold (ours against the paper's, in % of its number or in points "
                "for a claim in %): the ECS values because no reading of eqs. 9-13 gives "
                "Tables 4 and 5; the peaks because the paper takes them from rest, where they "
                "are the start-up impact.",
                [f"{section}: " + "; ".join(items) + "." for section, items in failing.items()],
            ),
        ],
        css="summary",
    )
    _running_answer(page, study)
    if study.experiment is not None:
        page.figure(
            _overlay(page, study),
            "Measured rocker speed (points), the simulated steady cycles in each method's "
            "colour and the nominal (dashed), like the paper's Figs. 17–20; the statistics "
            "are under Comparison with the experiment.",
        )


#: The rules by which a value in the paper report is marked implausible (docs/cli.md, "Reports mark the implausible").
IMPLAUSIBLE_RULES = (
    f"a joint force above {IDEAL_FORCE_FACTOR:g}× the ideal joint's peak (the simulation's own "
    "force-far-above-ideal finding); a penetration deeper than the radial clearance; a peak "
    "of a run that warned it has not settled or that its start-up transient dominates"
)


def flag_force(
    value: float, ideal: float, what: str | None = None, *, start_up: bool = False
) -> float | Flagged:
    """``value`` (N), marked where it is above :data:`IDEAL_FORCE_FACTOR` times ``ideal``.

    ``what`` (e.g. "the peak force at A") makes the reason name the value and its multiple;
    without it the reason is the table's shared footnote. ``start_up``: a peak from rest,
    whose reason is the start-up impact."""
    if not (math.isfinite(value) and ideal > 0) or value <= IDEAL_FORCE_FACTOR * ideal:
        return value
    rule = f"(marked above {IDEAL_FORCE_FACTOR:g}× the ideal joint's peak)"
    if start_up:
        return Flagged(
            value,
            f"Implausible as a load: a joint force far above the ideal joint's {rule}, the "
            "impact of the start from rest with centred pins (the paper's setting), not the "
            "running mechanism.",
        )
    if what is None:
        return Flagged(
            value,
            f"Implausible: a joint force far above the ideal joint's {rule}: impacts in the "
            "clearance dominate it, not the running load; read it as the contact law's "
            "artefact, not as a design load.",
        )
    return Flagged(
        value,
        f"Implausible: {what} {number(value)} N is {number(value / ideal, 3)}× the ideal "
        f"joint's peak of {number(ideal)} N {rule}: impacts in the clearance dominate it, not "
        "the running load; read it as this contact law's artefact, not as a design load.",
    )


def flag_ratio(ratio: float, value: float | Flagged) -> float | Flagged:
    """The force's multiple of the ideal peak, marked with the force's reason."""
    return Flagged(ratio, value.reason) if isinstance(value, Flagged) else ratio


def flag_penetration(depth_um: float, clearance: float) -> float | Flagged:
    """A deepest penetration (µm), marked where it goes deeper than ``clearance`` (m)."""
    if not (math.isfinite(depth_um) and depth_um > clearance * 1e6):
        return depth_um
    return Flagged(
        depth_um,
        f"Not physical: the pin sinks {number(depth_um)} µm into its bearing, deeper than the "
        f"{clearance * 1e6:g} µm radial clearance (marked beyond the clearance): the contact "
        "is far too soft for the load, and this run's forces are not physical.",
    )


def unsettled(summary: dict[str, Any] | None) -> str:
    """The warning of a run whose peaks have not settled (``not-settled`` or
    ``start-transient-dominates``), or an empty string."""
    for finding in (summary or {}).get("diagnostics", []):
        if finding.get("level") == "warning" and finding.get("code") in (
            "not-settled",
            "start-transient-dominates",
        ):
            return str(finding.get("message", finding["code"]))
    return ""


def flag_unsettled(value: float, warning: str) -> float | Flagged:
    """A peak of a run that warned it has not settled: marked with that warning."""
    if not warning or not math.isfinite(value):
        return value
    return Flagged(
        value, f"Not converged: the run warned that its peaks have not settled: {warning}."
    )


def _running_answer(page: _Page, study: PaperStudy) -> None:
    """One small table: each method's running mechanism beside the ideal joints, with the
    penetration flagged where it goes beyond the clearance, and the error against Table 7."""
    rms: dict[str, float] = {}
    if study.experiment is not None:
        rms = {
            str(row["method"]): float(row["rms_error_percent"])
            for row in study.experiment.table.to_dict(orient="records")
        }
    rows = []
    for key, outcome in study.outcomes.items():
        if not key.startswith("steady/"):
            continue
        method = outcome.task.method
        words = method_words(method, outcome.task.ecs_source)
        if not outcome.ok:
            rows.append((words, *[math.nan] * 5, f"failed: {outcome.error}", math.nan))
            continue
        speed = outcome.peak("omega4")
        forces = {q: outcome.peak(q) for q in PEAK_KEYS if q.startswith("F_")}
        joint = max(forces, key=lambda q: forces[q])
        cycles = (outcome.summary or {}).get("cycles", {})
        depth = max(cycles.get("deepest_penetration_m", {}).values(), default=math.nan)
        if not math.isfinite(depth):
            verdict = "not recorded"
        elif depth > PAPER_CLEARANCE:
            verdict = f"non-physical: deeper than the {PAPER_CLEARANCE * 1e6:g} µm clearance"
        else:
            verdict = "within the clearance" if depth > 0 else "no contact"
        name = joint.removeprefix("F_")
        marked = flag_force(forces[joint], study.nominal_peaks[joint], f"the peak force at {name}")
        shown = f"{number(forces[joint])} ({name})"
        force: str | Flagged = (
            Flagged(shown, marked.reason) if isinstance(marked, Flagged) else shown
        )
        rows.append(
            (
                words,
                flag_unsettled(speed, unsettled(outcome.summary)),
                100.0 * (speed / study.nominal_peaks["omega4"] - 1.0),
                force,
                flag_ratio(forces[joint] / study.nominal_peaks[joint], marked),
                flag_penetration(max(depth, 0.0) * 1e6, PAPER_CLEARANCE),
                verdict,
                rms.get(method, math.nan),
            )
        )
    if not rows:
        return
    page.report.table(
        rows,
        [
            "method (ECS source)",
            "rocker peak speed ω4 (rad/s)",
            "above ideal joints (%)",
            "largest joint force (N) (joint)",
            "× ideal joint's peak",
            "deepest penetration (µm)",
            "penetration",
            "RMS error against Table 7 (%)",
        ],
        caption=f"The running mechanism: after {_settle(study)} revolutions to settle, started "
        "on the nominal motion",
        text_columns=(0, 3, 6),
        cards=True,
        note="Peaks located on the continuous solution over the analysed revolution; "
        "penetration |e| − c at the integrator's accepted steps (sampled); RMS error = "
        "(measured − simulated) / simulated over Table 7's points. From rest — the paper's "
        "setting — the same methods' peaks are the start-up impact, not the running mechanism: "
        "they are shown as such under From rest and running steadily. ⚠ marks an implausible "
        f"value, its reason in the footnote it links to: {IMPLAUSIBLE_RULES}.",
    )


def _overlay(page: _Page, study: PaperStudy) -> Path:
    """The figure of the experiment: measured and simulated rocker speed."""
    assert study.experiment is not None
    return overlay_plots(
        study.experiment,
        page.figures,
        title=f"Rocker speed at {study.options.rpm:g} rpm",
        individual=False,
        figure_format=page.figure_format,
    )[-1]


def _claims_section(page: _Page, claims: list[Claim]) -> None:
    report = page.report
    report.heading("The paper's claims beside ours", anchor="claims")
    report.paragraph(
        "Every quantitative claim of the paper, the number jointplay finds for it and the "
        "difference: in % of the paper's value, or in points for a claim that is itself a "
        f"percentage. A claim holds when the two agree within {AGREEMENT_PCT:g} %. Claims are "
        "grouped by the paper's section; what our value is and why it differs are said once "
        "per group, in its shaded row, and beside a claim only where it needs its own note."
    )
    sections: dict[str, list[Claim]] = {}
    for c in claims:
        sections.setdefault(c.section, []).append(c)
    rows: list[tuple[Any, ...]] = []
    groups: list[tuple[int, str, str]] = []
    for section, members in sections.items():
        common_source = _common([c.ours_source for c in members])
        common_note = _common([c.note for c in members])
        detail = []
        if common_source:
            detail.append(f"Our value: {common_source}.")
        if common_note:
            detail.append(f"Why they differ: {common_note}.")
        groups.append((len(rows), section, " ".join(detail)))
        for c in members:
            own = []
            if c.ours_source != common_source:
                own.append(f"our value: {c.ours_source}")
            if c.note != common_note:
                own.append(c.note)
            if math.isfinite(c.ours_sampled):
                own.append(f"on a 0.5° grid: {quantity(c.ours_sampled, c.unit)}")
            rows.append(
                (
                    c.claim,
                    quantity(c.paper, c.unit),
                    quantity(c.ours, c.unit),
                    _difference(c),
                    claim_verdict(c),
                    "; ".join(own),
                )
            )
    report.table(
        rows,
        [
            "claim",
            "paper",
            "jointplay",
            "difference",
            "verdict",
            "note",
        ],
        text_columns=(0, 4, 5),
        groups=groups,
        widths=("30%", None, None, None, None, "35%"),
        cards=True,
        note="On a 0.5° grid: the same run's peak seen every 0.5° of crank, as a "
        "post-processor's curve shows it (given where the claim is a spiky peak; our own peaks "
        "are located between integrator steps).",
    )


def _common(values: list[str]) -> str:
    """The value most items share (at least two, or the only item's), else an empty string."""
    counts: dict[str, int] = {}
    for value in values:
        counts[value] = counts.get(value, 0) + 1
    best = max(counts, key=lambda v: counts[v], default="")
    return best if counts.get(best, 0) >= min(2, len(values)) else ""
