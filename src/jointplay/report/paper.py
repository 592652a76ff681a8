"""The paper study's report: one self-contained HTML page, results.json and the figures.

Only consumes a :class:`~jointplay.study.paper.PaperStudy`; no physics here. The first screen
answers: how many of the paper's claims hold and which, which do not and why, and the running
mechanism's numbers (rocker speed, joint forces, penetration flagged where it goes beyond the
clearance, error against the measurements) in one small table, then the measured and simulated
rocker speed. The peaks from rest, the paper's setting, come further down as what they are:
start-up impacts. Supporting tables and figures are folded (``<details>``) so the page stays
short; every figure is a palette PNG, so the page stays small. The page has a table of
contents; every table has headers in words with units and numbers
in the one format of :mod:`jointplay.report.format`; every response is defined where it is
reported; every figure is a PNG embedded in the page (and SVG or PDF beside it on request).
"""

from __future__ import annotations

import json
import math
import time
from collections.abc import Sequence
from pathlib import Path
from typing import Any

import pandas as pd

from jointplay import __version__
from jointplay.io.output import write_json
from jointplay.report.figures import check_format
from jointplay.report.format import number, percent, quantity
from jointplay.report.html import HtmlReport
from jointplay.report.overlays import overlay_plots
from jointplay.report.paper_figures import (
    JOINT_WORDS,
    QUANTITIES,
    axis_label,
    mechanism_figure,
    method_figure,
    nominal_figure,
    orbit_extents,
    orbit_figure,
    orbit_table,
)
from jointplay.report.plots import ecs_sweep_plots
from jointplay.study.claims import Claim, paper_claims
from jointplay.study.methods import METHODS
from jointplay.study.paper import (
    JOINTS,
    PAPER_CLEARANCE,
    PEAK_KEYS,
    STARTUP_PLOT_DEG,
    PaperStudy,
    corner_words,
    geometry_figures,
    method_words,
    worst_corners,
)

PAPER = (
    'C. A. Akhadkar, A. B. Deoghare, A. M. Vaidya, "Simulation and experimental response of '
    'four-bar mechanism with tolerance stack"'
)
#: A claim "holds" when our value lies within this relative difference of the paper's, %.
AGREEMENT_PCT = 10.0
#: Column headers of the peak quantities (symbol and unit).
LABELS = {key: axis_label(key) for key in QUANTITIES}
PEAK_DEFINITION = (
    "Peak: the largest |value| over the analysed crank revolution(s), located on the continuous "
    "solution between integrator steps (not on an output grid)."
)
INCREASE_DEFINITION = (
    "Increase: (peak − nominal peak) / nominal peak × 100, where the nominal peak is that of "
    "the ideal-joint mechanism with the same crank speed, running steadily."
)


def write_paper_report(
    study: PaperStudy,
    folder: Path,
    provenance: dict[str, Any],
    *,
    figure_format: str = "png",
) -> dict[str, Any]:
    """Write ``report.html``, ``results.json`` and ``figures/*.png`` into ``folder``.

    Args:
        study: the study to report.
        folder: the output folder (exists).
        provenance: version, command line and settings, written into both files.
        figure_format: ``"png"`` (embedded), or ``"svg"``/``"pdf"``: every figure also
            written in that format beside its PNG and linked from the page.

    Returns:
        The ``results.json`` document.
    """
    check_format(figure_format)
    wall = time.perf_counter()
    figures = folder / "figures"
    figures.mkdir(exist_ok=True)
    claims = paper_claims(study)
    results = results_document(study, claims, provenance)
    write_json(folder / "results.json", results)
    page = _Page(
        HtmlReport(
            "jointplay: the four-bar with tolerance stack of Akhadkar et al., reproduced",
            contents_before="claims",  # the summary fills the first screen
        ),
        folder,
        figure_format,
    )
    _summary_section(page, study, claims)
    _claims_section(page, claims)
    _mechanism_section(page, study)
    _ecs_section(page, study)
    _methods_section(page, study)
    _tolerance_section(page, study)
    _experiment_section(page, study)
    _solver_section(page, study, provenance, time.perf_counter() - wall)
    page.report.write(folder / "report.html")
    return results


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


# --- results.json -----------------------------------------------------------------------------


def _records(table: pd.DataFrame) -> list[dict[str, Any]]:
    return json.loads(table.to_json(orient="records"))


def _rows(table: pd.DataFrame) -> list[Any]:
    """The rows of ``table`` as objects with one attribute per column."""
    from types import SimpleNamespace

    return [
        SimpleNamespace(**{str(k): v for k, v in row.items()})
        for row in table.to_dict(orient="records")
    ]


def results_document(
    study: PaperStudy, claims: list[Claim], provenance: dict[str, Any]
) -> dict[str, Any]:
    """Every number of the report's tables, JSON-ready."""
    methods = {}
    for key, outcome in study.outcomes.items():
        summary = outcome.summary or {}
        methods[key] = {
            "method": outcome.task.method,
            "ecs_source": outcome.task.ecs_source,
            "description": outcome.task.label,
            "lengths_m": dict(outcome.task.lengths),
            "error": outcome.error,
            "peaks": summary.get("peaks") if outcome.ok else None,
            "increase_percent": summary.get("increase_percent") if outcome.ok else None,
            "start": outcome.task.start,
            "settle_revolutions": outcome.task.settle,
            "startup_peaks": outcome.startup_peaks,
            "sampled_peaks": outcome.sampled_peaks,
            "solver": summary.get("solver") if outcome.ok else None,
            "clearance_joints": summary.get("clearance_joints") if outcome.ok else None,
            "diagnostics": summary.get("diagnostics") if outcome.ok else None,
            "wall_s": outcome.wall_s,
        }
    return {
        "paper": PAPER,
        "definitions": {
            "peak": PEAK_DEFINITION,
            "increase_percent": INCREASE_DEFINITION,
            "startup_peaks": f"largest |value| in the first {study.options.startup_deg:g}° of "
            "crank after the start from rest",
            "sampled_peaks": "the same run's peak seen every 0.5° of crank (an output grid, as "
            "a post-processor's curve shows it)",
            "ecs_source": "paper: K, δ, D as printed in the paper's Tables 4 and 5; computed: "
            "our estimate from eqs. 9-13 with the conventions in ecs.conventions",
        },
        "start_up_vs_running": _start_up_vs_running(study),
        "options": {k: getattr(study.options, k) for k in study.options.__dataclass_fields__},
        "mechanism": geometry_figures(study.mechanism),
        "nominal_peaks": study.nominal_peaks,
        "ecs": study.ecs,
        "ecs_sweep": _records(study.ecs_sweep.paper_units_table()),
        "simulations": methods,
        "length_cases": _records(study.length_cases),
        "worst_corners": _records(
            worst_corners(study.length_cases, study.options.tolerance_method)
        ),
        "sensitivities": _records(study.sensitivities),
        "experiment": None if study.experiment is None else study.experiment.as_dict(),
        "table7_explained": study.extra.get("table7_explained"),
        "claims": [{**c.as_dict(), "verdict": claim_verdict(c)} for c in claims],
        "wall_s": study.wall_s,
        "provenance": provenance,
    }


def claim_verdict(claim: Claim) -> str:
    """``"holds"`` (within :data:`AGREEMENT_PCT` of the paper's value), ``"differs"``, or
    ``"no paper value"``."""
    difference = claim.difference_pct
    if not math.isfinite(difference):
        return "no paper value" if not math.isfinite(claim.paper) else "not computed"
    return "holds" if abs(difference) <= AGREEMENT_PCT else "differs"


def _difference(claim: Claim) -> str:
    """Ours against the paper's: in points for a claim in %, else in % of the paper's value."""
    if claim.unit == "%":
        if not (math.isfinite(claim.paper) and math.isfinite(claim.ours)):
            return "—"
        return f"{number(claim.ours - claim.paper, 3, signed=True)} points"
    return percent(claim.difference_pct)


# --- the summary --------------------------------------------------------------------------------


def claim_counts(claims: Sequence[Claim]) -> dict[str, list[Claim]]:
    """The claims by verdict (:func:`claim_verdict`), in the order holds, differs, no paper
    value, not computed; every claim is in exactly one list."""
    counts: dict[str, list[Claim]] = {
        v: [] for v in ("holds", "differs", "no paper value", "not computed")
    }
    for claim in claims:
        counts[claim_verdict(claim)].append(claim)
    return counts


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
    sections: dict[str, int] = {}
    for c in differs:
        sections[c.section] = sections.get(c.section, 0) + 1
    report.bullets(
        [
            f"Of the paper's {len(claims)} quantitative claims, {len(holds)} hold (within "
            f"{AGREEMENT_PCT:g} % of its number), {len(differs)} do not"
            + "".join(f", {other}" for other in others)
            + ".",
            "Holds: " + ("; ".join(f"{c.claim} ({c.section})" for c in holds) or "none") + ".",
            "Does not hold: "
            + "; ".join(f"{section} ({n})" for section, n in sections.items())
            + ". The ECS values because no reading of eqs. 9-13 gives Tables 4 and 5; the peaks "
            "because the paper takes them from rest, where they are the start-up impact.",
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
        rows.append(
            (
                words,
                speed,
                100.0 * (speed / study.nominal_peaks["omega4"] - 1.0),
                f"{number(forces[joint])} ({joint.removeprefix('F_')})",
                forces[joint] / study.nominal_peaks[joint],
                max(depth, 0.0) * 1e6,
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
        "they are shown as such under From rest and running steadily.",
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


# --- the claims ---------------------------------------------------------------------------------


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


# --- the mechanism ------------------------------------------------------------------------------


def _mechanism_section(page: _Page, study: PaperStudy) -> None:
    report = page.report
    report.heading("The mechanism", anchor="mechanism")
    info = geometry_figures(study.mechanism)
    geometry = study.extra["configuration"]["geometry_m"]
    tolerances = {t.length: (t.lower, t.upper, t.source) for t in study.mechanism.tolerances}
    rows = []
    for name in ("crank", "coupler", "rocker", "ground"):
        link = next((lk for lk in study.mechanism.links if lk.name == name), None)
        lower, upper, source = tolerances.get(name, (math.nan, math.nan, ""))
        rows.append(
            (
                name,
                geometry[name] * 1e3,
                lower * 1e3,
                upper * 1e3,
                source,
                link.mass if link else math.nan,
                link.inertia if link else math.nan,
            )
        )
    report.table(
        rows,
        [
            "link",
            "length (mm)",
            "lower deviation (mm)",
            "upper deviation (mm)",
            "tolerance source",
            "mass (kg)",
            "moment of inertia (kg·m²)",
        ],
        text_columns=(0, 4),
        caption="Links (the ground's mass and inertia do not enter: it does not move)",
    )
    low, high = info["transmission_angle_deg"]
    report.paragraph(
        f"Grashof class: {info['grashof']}. Rocker swing {number(info['rocker_swing_deg'])}°. "
        f"Transmission angle between {number(low)}° and {number(high)}° (the usual design "
        "guideline keeps it within 40°–140°). Joints Ø10 H8/g7: radial clearance 2.5–21 µm; "
        "simulated at 21 µm, the largest."
    )
    with report.side_by_side():
        page.figure(
            mechanism_figure(study, page.figures / "mechanism.png", page.figure_format),
            "The linkage at 12 crank angles, to scale, and the path of the rocker tip B.",
        )
        _animation(page, study)
    with report.details("The nominal mechanism (ideal joints): its motion and its peaks"):
        _nominal(page, study)


def _nominal(page: _Page, study: PaperStudy) -> None:
    page.figure(
        nominal_figure(study, page.figures / "nominal.png", page.figure_format),
        f"The nominal mechanism (ideal joints) over one revolution at {study.options.rpm:g} rpm: "
        "angular velocities, angular accelerations and joint forces (the reaction at each joint "
        "that keeps the links together).",
    )
    page.report.table(
        [
            (QUANTITIES[k][0], QUANTITIES[k][1], v, QUANTITIES[k][2])
            for k, v in study.nominal_peaks.items()
        ],
        ["quantity", "symbol", "nominal peak", "unit"],
        text_columns=(0, 1, 3),
        caption="Nominal peaks",
        note="Nominal peak: the largest |value| over one revolution of the ideal-joint "
        f"mechanism at {study.options.rpm:g} rpm (every 0.1° of crank).",
    )


def _animation(page: _Page, study: PaperStudy) -> None:
    """The running mechanism, each pin's play magnified (the factor is in every frame)."""
    result = study.running_example
    if result is None:
        return
    try:
        from jointplay.report.animation import write_animation
    except ImportError:  # pragma: no cover - the module ships with jointplay
        return
    path = page.figures / "animation.gif"
    info = write_animation(result, path, frames=48, fps=16, dpi=80, figure_size=(8.0, 5.0))
    largest = max(info.largest_displacement.values(), default=math.nan)
    page.figure(
        path,
        f"One steady revolution of the mechanism with clearance ("
        f"{method_words(study.options.tolerance_method, study.options.tolerance_source)}), "
        f"each pin's displacement in its bearing magnified {number(info.magnification, 3)} times "
        f"(largest displacement {number(largest * 1e6, 3)} µm, the clearance "
        f"{PAPER_CLEARANCE * 1e6:g} µm).",
    )


# --- ECS ----------------------------------------------------------------------------------------

CONVENTION_WORDS = {
    "radius": ("equivalent radius R of the pin in its hole", None),
    "modulus": ("effective modulus E*", None),
    "initial_contact_radius": ("initial contact radius a₀ of eq. 10", "mm"),
    "contact_length": ("contact length l of eqs. 11-12", None),
    "eq11_log_argument": ("argument of the logarithm of eq. 11", None),
    "alpha_link": ("whose angular acceleration enters eq. 13", None),
    "load": ("contact load", None),
    "damping_ratio": ("damping D / stiffness K", "s"),
    "ifm_stiffness": ("ECS K as the IMPACT stiffness", None),
    "ifm_exponent": ("IMPACT force exponent e", "–"),
    "impact_velocity": ("impact velocity v0 of the damping comparison", "m/s"),
}


def _convention_rows(conventions: dict[str, Any]) -> list[tuple[str, str, str]]:
    descriptions = conventions.get("descriptions", {})
    rows = []
    for key, (words, unit) in CONVENTION_WORDS.items():
        if key not in conventions:
            continue
        value = conventions[key]
        if value is None:
            shown = "estimated"
        elif isinstance(value, float) and unit == "mm":
            shown = f"{number(value * 1e3)} mm" + (" (Hertz)" if value == 0 else "")
        elif isinstance(value, float):
            shown = f"{number(value)} {unit}" if unit and unit != "–" else number(value)
        else:
            shown = str(value)
        rows.append((words, shown, descriptions.get(key, "")))
    return rows


def _ecs_section(page: _Page, study: PaperStudy) -> None:
    report = page.report
    report.heading("Equivalent contact stiffness (paper eqs. 9–13)", anchor="ecs")
    computed = study.ecs["computed"]
    report.paragraph(
        "Load: eq. 13, the largest |α r m| of the nominal mechanism at each joint (α the "
        "angular acceleration of the link, r and m the pin's radius and mass). The conventions "
        "the paper leaves open are explicit (folded below)."
    )
    with report.details("The ECS conventions: each choice the paper leaves open"):
        report.table(
            _convention_rows(study.ecs["conventions"]),
            ["convention", "choice", "what it means"],
            text_columns=(0, 1, 2),
            caption="ECS conventions",
        )
    rows: list[tuple[Any, ...]] = []
    unloaded = []
    for data in computed["joints"]:
        load = data.get("load", {}).get("load_N")
        if load == 0:
            unloaded.append(data["joint"])
        for contact in ("spherical", "cylindrical"):
            if contact not in data:
                continue
            est = data[contact]["paper_units"]
            rows.append(
                (
                    f"{data['joint']} ({JOINT_WORDS.get(data['joint'], '')})",
                    contact,
                    est.get("load_N"),
                    est.get("effective_modulus_N_per_mm2"),
                    est.get("equivalent_radius_mm"),
                    est.get("contact_radius_mm", est.get("half_width_mm")),
                    est.get("stiffness_N_per_mm"),
                    est.get("penetration_mm"),
                    est.get("damping_N_s_per_mm"),
                )
            )
    why_zero = ""
    if unloaded:
        why_zero = (
            f" The row(s) of {', '.join(unloaded)} are zero: eq. 13 takes the angular "
            "acceleration of the joint's moving link, and the crank turns at constant speed "
            "(α2 = 0) about a fixed pivot, so the paper's load there is zero and the ECS "
            "undefined; the joint is simulated with the overall values below."
        )
    with report.details("The ECS of each joint: loads, intermediate values and results"):
        _ecs_joints(report, rows, why_zero)
    _ecs_beside_paper(page, study)
    with report.details("The ECS over crank speed, and its damping against the hysteresis laws"):
        _ecs_sweep(page, study)


def _ecs_joints(report: HtmlReport, rows: list[tuple[Any, ...]], why_zero: str) -> None:
    report.table(
        rows,
        [
            "joint",
            "contact",
            "load F (N)",
            "E* (N/mm²)",
            "R (mm)",
            "contact radius a or half-width b (mm)",
            "K (N/mm)",
            "δ (mm)",
            "D (N·s/mm)",
        ],
        caption="ECS per joint: intermediate values and results, in the paper's units",
        text_columns=(0, 1),
        note="K: contact stiffness; δ: penetration under the load F; D = 0.01 s × K: damping "
        "(eqs. 9-13)." + why_zero,
    )


def _ecs_beside_paper(page: _Page, study: PaperStudy) -> None:
    computed = study.ecs["computed"]
    published = study.ecs["published"]
    rows = []
    for contact, table in (("spherical", "Table 5"), ("cylindrical", "Table 4")):
        ours = computed["overall"][contact]["paper_units"]
        paper = published[contact]
        for label, our_key in (
            ("stiffness K (N/mm)", "stiffness_N_per_mm"),
            ("penetration δ (mm)", "penetration_mm"),
            ("damping D (N·s/mm)", "damping_N_s_per_mm"),
        ):
            paper_value = _published_value(paper, our_key)
            rows.append(
                (
                    f"{contact} ({table})",
                    label,
                    paper_value,
                    ours[our_key],
                    ours[our_key] / paper_value if paper_value else math.nan,
                )
            )
    page.report.table(
        rows,
        ["contact", "quantity", "paper", "jointplay", "jointplay / paper"],
        caption=f"ECS at {study.options.rpm:g} rpm, joint {computed.get('overall_joint', 'A')} "
        "(the most loaded): ours and the paper's",
        text_columns=(0, 1),
    )


def _ecs_sweep(page: _Page, study: PaperStudy) -> None:
    paths = ecs_sweep_plots(
        study.ecs_sweep,
        ("spherical", "cylindrical"),
        page.figures,
        figure_format=page.figure_format,
    )
    page.figure(
        paths[0],
        "ECS stiffness, penetration and damping over crank speed for both contacts (crosses: "
        "the paper's values at 200 rpm). Log scales: the contacts differ by orders of "
        "magnitude.",
    )
    models = dict(study.ecs_sweep.chi_models)
    spread = max(models.values()) / min(models.values()) if models else math.nan
    page.figure(
        paths[1],
        "Left: the hysteresis damping factor of the ECS model (our definition χ = (D/K)·v0/δ; "
        "the paper does not define its Fig. 6 quantity) beside χ(e) of "
        + ", ".join(f"{name} ({number(v, 3)})" for name, v in models.items())
        + f" at e = {study.ecs_sweep.restitution:g}: these four do not depend on speed and lie "
        f"within a factor {number(spread, 3)} of each other, so their lines nearly coincide. "
        "Right: the ECS damping D against the equivalent damping χ(e)·K·δ/v0 of the four "
        "laws, drawn as one band per contact (the band's width is their spread).",
    )
    _sweep_tables(page, study)


def _published_value(paper: dict[str, Any], key: str) -> float:
    return float(paper["paper_units"].get(key, math.nan))


SWEEP_ROWS = (
    ("load_N", "eq. 13 load F (N)", 1.0),
    ("impact_velocity_m_s", "impact velocity v0 (mm/s)", 1e3),
    ("K_{c}_N_per_mm", "stiffness K (N/mm)", 1.0),
    ("delta_{c}_mm", "penetration δ (mm)", 1.0),
    ("D_{c}_N_s_per_mm", "damping D (N·s/mm)", 1.0),
    ("chi_ecs_{c}", "hysteresis factor χ_ECS (–)", 1.0),
    ("e_eff_ecs_{c}", "restitution of one impact with χ_ECS (–)", 1.0),
)


def _sweep_tables(page: _Page, study: PaperStudy) -> None:
    """The crank-speed sweep, transposed: one column per crank speed."""
    data = study.ecs_sweep.paper_units_table()
    speeds = [f"{float(r):g} rpm" for r in data["rpm"]]
    rows: list[tuple[Any, ...]] = []
    groups: list[tuple[int, str]] = []
    for contact in (None, "spherical", "cylindrical"):
        if contact:
            groups.append((len(rows), f"{contact} contact"))
        for key, words, factor in SWEEP_ROWS:
            has_contact = "{c}" in key
            if (contact is None) == has_contact:
                continue
            column = key.format(c=contact)
            if column in data:
                rows.append((words, *(float(v) * factor for v in data[column])))
    report = page.report
    report.table(
        rows,
        ["quantity", *speeds],
        caption="ECS over crank speed (joint A, the most loaded; the paper's units)",
        groups=groups,
        widths=("17%",),
        note="The equivalent damping χ(e)·K·δ/v0 of each law is in results.json "
        "(ecs_sweep, columns c_eq_*).",
    )


# --- the six methods ----------------------------------------------------------------------------


def _method_keys(study: PaperStudy) -> list[str]:
    return [k for k in study.outcomes if k.startswith("method/")]


def _methods_section(page: _Page, study: PaperStudy) -> None:
    report = page.report
    report.heading("The six simulation methods (paper Table 2)", anchor="methods")
    report.paragraph(
        f"Each method with clearance {PAPER_CLEARANCE * 1e3:g} mm in all four joints, basic "
        "lengths, started from rest as in the paper (pins centred, the crank at full speed "
        f"from t = 0), {study.options.revolutions:g} revolution(s). IFM: impact-function "
        "method (MSC ADAMS IMPACT force); RM: restitution method. Conventional: the usual "
        "contact parameters; ECS: the equivalent contact stiffness, with the paper's values "
        "(Tables 4-5) or ours."
    )
    quantities = PEAK_KEYS
    rows = []
    for key in _method_keys(study):
        outcome = study.outcomes[key]
        rows.append(
            [
                method_words(outcome.task.method, outcome.task.ecs_source),
                *[outcome.peak(q) if outcome.ok else math.nan for q in quantities],
            ]
        )
    rows.append(["nominal (ideal joints)", *[study.nominal_peaks[q] for q in quantities]])
    increases = []
    for key in _method_keys(study):
        outcome = study.outcomes[key]
        increase = (outcome.summary or {}).get("increase_percent", {}) if outcome.ok else {}
        increases.append(
            [
                method_words(outcome.task.method, outcome.task.ecs_source),
                *[increase.get(q, math.nan) for q in quantities],
            ]
        )
    with report.details(
        "The peaks of each method from rest, and their increase over the nominal peaks"
    ):
        report.table(
            rows,
            ["method (ECS source)", *[LABELS[q] for q in quantities]],
            caption="Peaks from rest",
            note=PEAK_DEFINITION,
        )
        report.table(
            increases,
            ["method (ECS source)", *[f"{QUANTITIES[q][1]} (%)" for q in quantities]],
            caption="Increase of each peak over the nominal peak, from rest",
            note=INCREASE_DEFINITION,
        )
    report.heading("Start-up and steady running, method by method", level=3, anchor="figures")
    report.paragraph(
        f"Each figure: one quantity, one row per method in the method's colour (the same in "
        f"every figure). Left: the first {STARTUP_PLOT_DEG:g}° of crank from rest, the paper's "
        "setting, with both ECS sources (solid: the paper's values; dotted: ours). Right: one "
        "revolution of the mechanism running steadily (started on the nominal motion, two "
        "revolutions left to settle). Nominal dashed black. Linear axes, each panel on its own "
        "scale: the start-up impacts are orders of magnitude above the running values."
    )

    def draw(quantity: str) -> None:
        words, symbol, unit = QUANTITIES[quantity]
        page.figure(
            method_figure(
                study, quantity, page.figures / f"methods_{quantity}.png", page.figure_format
            ),
            f"{words.capitalize()} {symbol} ({unit}) of the six methods: start-up from rest "
            "(left) and the steady revolution (right), nominal dashed.",
        )

    draw("omega4")
    with report.details(
        "Seven more figures, the same for the rocker's acceleration α4, the coupler (ω3, α3) "
        "and the joint forces at A, O4, O2 and B"
    ):
        for folded in ("alpha4", "F_A", "F_O4", "omega3", "alpha3", "F_O2", "F_B"):
            draw(folded)
    _running_subsection(page, study)
    _orbits_subsection(page, study)


def _orbits_subsection(page: _Page, study: PaperStudy) -> None:
    extents = orbit_extents(study)
    if not extents:
        return
    report = page.report
    report.heading("Journal orbits", level=3, anchor="orbits")
    c_um = PAPER_CLEARANCE * 1e6
    beyond = [e for e in extents if e.penetration > 0]
    deepest = max(extents, key=lambda e: e.penetration)
    if beyond:
        text = (
            f"{len(beyond)} of {len(extents)} orbits go beyond the clearance circle: the pin "
            "presses into its bearing (the contact law's penetration). The deepest: "
            f"{number(deepest.penetration * 1e6, 3)} µm beyond the {c_um:g} µm clearance, "
            f"{METHODS[deepest.method].title}, {deepest.setting}, joint {deepest.joint}."
        )
    else:
        text = "Every orbit stays inside its clearance circle."
    report.paragraph(text)
    with report.details("The orbits, drawn: every method and joint"):
        page.figure(
            orbit_figure(study, page.figures / "orbits.png", page.figure_format),
            "The centre of each pin relative to its bearing's centre, to scale (µm), for every "
            f"method (rows) and joint (columns); black circle: the clearance c = {c_um:g} µm; "
            "faint: the revolution from rest; solid: the steady revolution. Each panel takes in "
            "its whole orbit.",
        )
    report.table(
        orbit_table(extents),
        ["method", "start", *[f"{j} (µm)" for j in JOINTS]],
        caption="Largest eccentricity |e| of each journal",
        text_columns=(0, 1),
        note=f"|e|: the distance of the pin's centre from its bearing's centre; above c = "
        f"{c_um:g} µm the surfaces overlap by |e| − c (penetration).",
    )


def _start_up_vs_running(study: PaperStudy) -> dict[str, Any]:
    """Per method: peaks from rest (the paper's setting) and running steadily, with the
    nominal ones, and the sentence that says why they differ; JSON-ready."""
    out: dict[str, Any] = {}
    for key, running in study.outcomes.items():
        if not key.startswith("steady/"):
            continue
        _, method, source = key.split("/")
        start_up = study.outcomes.get(f"method/{method}/{source}")
        out[f"{method}/{source}"] = {
            quantity: {
                "from_rest": None
                if start_up is None or not start_up.ok
                else start_up.peak(quantity),
                "running": None if not running.ok else running.peak(quantity),
                "nominal": study.nominal_peaks[quantity],
            }
            for quantity in PEAK_KEYS
        }
    return {"why": _why(study, out), "methods": out}


def _why(study: PaperStudy, methods: dict[str, Any]) -> str:
    """One sentence on why the paper's start-up peaks and the running ones differ, with the
    ranges this study found (rocker speed above the ideal joints', largest joint force as a
    multiple of the ideal one)."""

    def spread(setting: str) -> tuple[float, float, float, float]:
        speed, force = [], []
        for values in methods.values():
            if values["omega4"][setting] is None:
                continue
            speed.append(100 * (values["omega4"][setting] / values["omega4"]["nominal"] - 1))
            force.append(
                max(
                    values[q][setting] / values[q]["nominal"]
                    for q in PEAK_KEYS
                    if q.startswith("F_")
                )
            )
        if not speed:
            return (math.nan,) * 4
        return min(speed), max(speed), min(force), max(force)

    rest, running = spread("from_rest"), spread("running")
    return (
        "The paper starts every simulation from rest with the pins centred, so the crank is "
        "jerked to full speed at t = 0 and the pins strike their bearings: its first-revolution "
        f"peaks are that start-up impact (rocker speed {rest[0]:.0f}–{rest[1]:.0f} % above the "
        f"ideal joints', joint forces {rest[2]:,.0f}–{rest[3]:,.0f} times theirs). Started on "
        f"the nominal motion and left {_settle(study)} revolutions to settle, the same methods "
        f"run with the rocker speed {running[0]:.1f}–{running[1]:.1f} % above the ideal and "
        f"joint forces {running[2]:.3g}–{running[3]:,.0f} times the ideal ones: what the "
        "contact law does to the running mechanism, the stiffest ECS contacts still rattling."
    )


def _settle(study: PaperStudy) -> int:
    return next((o.task.settle for k, o in study.outcomes.items() if k.startswith("steady/")), 0)


def _running_subsection(page: _Page, study: PaperStudy) -> None:
    document = _start_up_vs_running(study)
    comparison = document["methods"]
    if not comparison:
        return
    report = page.report
    report.heading(
        "From rest (the paper's setting) and running steadily", level=3, anchor="running"
    )
    report.paragraph(document["why"], css="note")
    quantities = ("omega3", "omega4", "F_O2", "F_A", "F_B", "F_O4", "torque")
    rows: list[list[Any]] = []
    groups: list[tuple[int, str]] = []
    for label, values in comparison.items():
        method, source = label.split("/")
        groups.append((len(rows), method_words(method, source)))
        for setting in ("from_rest", "running"):
            rows.append(
                [
                    "from rest (the paper)" if setting == "from_rest" else "running steadily",
                    *[
                        math.nan if values[q][setting] is None else values[q][setting]
                        for q in quantities
                    ],
                ]
            )
    groups.append((len(rows), "ideal joints"))
    rows.append(["nominal", *[study.nominal_peaks[q] for q in quantities]])
    report.table(
        rows,
        ["start", *[LABELS[q] for q in quantities]],
        caption="Peaks from rest and running steadily",
        groups=groups,
        note=PEAK_DEFINITION
        + f" Running steadily: the revolution after {_settle(study)} revolutions to settle, "
        "started on the nominal motion.",
    )
    findings: dict[tuple[str, str], list[str]] = {}
    for key, outcome in study.outcomes.items():
        if key.startswith(("method/", "steady/")) and outcome.ok:
            for finding in (outcome.summary or {}).get("diagnostics", []):
                if finding["level"] == "warning":
                    findings.setdefault((finding["code"], key.split("/")[0]), []).append(key)
    if findings:
        report.paragraph(
            "Plausibility warnings (jointplay simulate writes each in its summary.json): "
            + "; ".join(
                f"{code.replace('-', ' ')} in {len(keys)} "
                f"{'start-up' if kind == 'method' else 'steady'} run(s)"
                for (code, kind), keys in sorted(findings.items())
            )
            + ".",
            css="note",
        )


# --- nominal vs actual ----------------------------------------------------------------------------

TOLERANCE_QUANTITIES = ("omega3", "omega4", "alpha4", "F_A", "F_O4")


def _case_words(case: str) -> tuple[str, str]:
    """A length case as (signs, words): ``corner/+-+-`` → ("+ − + −", "crank upper, ...")."""
    kind, _, rest = case.partition("/")
    if kind == "corner":
        return " ".join("+" if s == "+" else "−" for s in rest), corner_words(rest)
    sign = "+" if rest == "upper" else "−"
    return " ".join([sign] * 4), f"every length at its {rest} limit"


def _tolerance_section(page: _Page, study: PaperStudy) -> None:
    report = page.report
    report.heading("Nominal vs actual mechanism (tolerance stack)", anchor="tolerance")
    method = study.options.tolerance_method
    report.paragraph(
        "Actual = link lengths at their ISO 2768-1 class c limits and clearance "
        f"{PAPER_CLEARANCE * 1e3:g} mm in all four joints, simulated from rest with "
        f"{method_words(method, study.options.tolerance_source)} (the cylindrical cases with "
        "IFM and cylindrical ECS). Lengths: + at the upper limit, − at the lower, in the order "
        "crank, coupler, rocker, ground. Change: (peak − nominal peak) / nominal peak × 100, "
        "against the basic lengths with ideal joints; the ideal-joint change isolates the "
        "effect of the lengths from that of the clearance."
    )
    table = study.length_cases
    if table.empty:
        report.paragraph("No length cases were simulated.")
        return
    cases = [_case_words(c) for c in table["case"]]
    kinds = ["cylindrical" if m == "ifm-ecs-cylindrical" else "spherical" for m in table["method"]]

    def lengths_table(caption: str, suffix: str, note: str) -> None:
        headers = [
            "lengths",
            "ECS contact",
            *[
                (LABELS[q] if not suffix else f"{QUANTITIES[q][1]} (%)")
                for q in TOLERANCE_QUANTITIES
            ],
        ]
        rows = [
            (signs, kind, *[table[f"{q}{suffix}"].iloc[i] for q in TOLERANCE_QUANTITIES])
            for i, ((signs, _), kind) in enumerate(zip(cases, kinds, strict=True))
        ]
        report.table(rows, headers, caption=caption, text_columns=(0, 1), note=note)

    with report.details("The peaks of every length case"):
        lengths_table("Peaks with clearance and toleranced lengths", "", PEAK_DEFINITION)
    with report.side_by_side():
        lengths_table(
            "Change of each peak with clearance (%)",
            "_change_pct",
            "Clearance and lengths together: mostly the start-up impacts.",
        )
        lengths_table(
            "Change of each peak with ideal joints (%)",
            "_ideal_change_pct",
            "The same lengths without clearance: the effect of the lengths alone.",
        )
    worst = worst_corners(table, method)
    if not worst.empty:
        worst_rows = [
            (
                f"{QUANTITIES[r.output][0]} {QUANTITIES[r.output][1]} ({QUANTITIES[r.output][2]})",
                _case_words(f"corner/{r.worst_corner}")[0],
                r.peak,
                r.change_pct,
                _case_words(f"corner/{r.ideal_worst_corner}")[0],
                r.ideal_peak,
            )
            for r in _rows(worst)
        ]
        report.table(
            worst_rows,
            [
                "output",
                "worst corner with clearance",
                "peak",
                "change (%)",
                "worst corner, ideal joints",
                "peak, ideal joints",
            ],
            caption=f"Worst corner for each output ({method_words(method, study.options.tolerance_source)})",
            text_columns=(0, 1, 4),
            note="Worst corner: the length corner with the largest peak; the peak is in the "
            "output's unit.",
        )
    report.heading(
        "Sensitivity of the rocker's peak angular acceleration", level=3, anchor="sensitivity"
    )
    report.paragraph(
        "One length at its upper limit, the others at basic size. Kinematic: ideal joints, "
        "steady motion. Dynamic: with clearance, from rest — dominated by the start-up impacts. "
        "The paper reports 2.7 % (crank) and 1.3 % (ground)."
    )
    rows = [
        (
            r.length,
            r.basic_mm,
            r.deviation_mm,
            r.kinematic_alpha4,
            r.kinematic_change_pct,
            r.dynamic_alpha4,
            r.dynamic_change_pct,
        )
        for r in _rows(study.sensitivities)
    ]
    report.table(
        rows,
        [
            "length",
            "basic (mm)",
            "upper deviation (mm)",
            "α4 peak, kinematic (rad/s²)",
            "change, kinematic (%)",
            "α4 peak, with clearance (rad/s²)",
            "change, with clearance (%)",
        ],
        caption="Sensitivities",
        note="Change: against the basic lengths in the same setting (kinematic against the "
        "nominal mechanism, with clearance against the basic lengths with clearance).",
    )


# --- the experiment -------------------------------------------------------------------------------

METHOD_SHORT = {
    "nominal": "nominal",
    "ifm-ecs-spherical": "IFM spherical",
    "rm-ecs-spherical": "RM spherical",
    "ifm-ecs-cylindrical": "IFM cylindrical",
    "rm-ecs-cylindrical": "RM cylindrical",
}


def _experiment_section(page: _Page, study: PaperStudy) -> None:
    report = page.report
    report.heading("Comparison with the experiment (paper Table 7)", anchor="experiment")
    comparison = study.experiment
    if comparison is None:
        report.paragraph("Not run.")
        return
    conventions = comparison.measurements.conventions
    report.paragraph(
        f"Measured rocker speed (Table 7) read with these conventions: {conventions.describe()}. "
        "Each simulation is the steady cycle — started from the nominal motion, "
        f"{study.options.experiment_revolutions} revolution(s), the last one used, ECS methods "
        f"with the {study.options.tolerance_source} values — sampled at the measured crank "
        "angles."
    )
    report.paragraph(comparison.discrepancy.summary(), css="note")
    report.paragraph(comparison.verdict(), css="note")
    if comparison.printed_check is not None:
        report.paragraph(comparison.printed_check.summary(), css="small")
    unit = conventions.unit
    rows = [
        (
            METHOD_SHORT.get(r.method, r.method),
            r.rms_error_percent,
            r.max_abs_error_percent,
            r.max_error_at_deg,
            r.rms_difference_in_unit,
            r.max_abs_difference_in_unit,
            r.n_percent_points,
        )
        for r in _rows(comparison.table)
    ]
    report.table(
        rows,
        [
            "simulation",
            "RMS error (%)",
            "largest |error| (%)",
            "at crank angle (deg)",
            f"RMS difference ({unit})",
            f"largest |difference| ({unit})",
            "points in the % statistics",
        ],
        caption="Error statistics per simulation",
        note="Error = (measured − simulated) / simulated × 100, as the paper computes it; "
        "points where the simulated speed is below 10 % of its largest value are left out of "
        "the % statistics (the % error explodes near zero speed) but kept in the differences.",
    )
    points = comparison.points_table()
    methods = list(dict.fromkeys(points["method"]))
    angles = list(dict.fromkeys(points["crank_deg"]))
    by = points.set_index(["crank_deg", "method"])
    measured = points.drop_duplicates("crank_deg").set_index("crank_deg")["measured"]
    with report.details(f"The {len(angles)} measured points: each simulation's speed and error"):
        rows = [
            (f"{angle:g}", measured[angle], *[by.loc[(angle, m), "simulated"] for m in methods])
            for angle in angles
        ]
        report.table(
            rows,
            [
                "crank angle (deg)",
                f"measured ({unit})",
                *[f"{METHOD_SHORT.get(m, m)} ({unit})" for m in methods],
            ],
            caption="Per point: measured and simulated rocker speed",
            text_columns=(),
        )
        rows = [
            (f"{angle:g}", *[by.loc[(angle, m), "error_percent"] for m in methods])
            for angle in angles
        ]
        report.table(
            rows,
            ["crank angle (deg)", *[f"{METHOD_SHORT.get(m, m)} (%)" for m in methods]],
            caption="Per point: error of each simulation",
            text_columns=(),
            note="Error = (measured − simulated) / simulated × 100.",
        )
    _explained_subsection(page, study.extra.get("table7_explained"))
    report.paragraph(
        "The measured and simulated rocker speeds are drawn in the figure of the summary.",
        css="small",
    )


def _explained_subsection(page: _Page, explained: dict[str, Any] | None) -> None:
    """Which crank speed and phase make the nominal model match each Table 7 column."""
    if not explained:
        return
    report = page.report
    report.heading(
        "The experiment, explained: calibrated crank speed and phase", level=3, anchor="explained"
    )
    report.paragraph(explained["method"], css="small")
    rows = []
    for column, fit in explained["columns"].items():
        rpm, phase = fit["crank_rpm"], fit["phase_deg"]
        rows.append(
            [
                column.replace("_", " "),
                rpm["value"],
                f"{number(rpm['ci95'][0])} – {number(rpm['ci95'][1])}",
                phase["value"],
                f"{number(phase['ci95'][0])} – {number(phase['ci95'][1])}",
                fit["rms_before"],
                fit["rms_after"],
                fit["residual_rms_deg_s"],
            ]
        )
    report.table(
        rows,
        [
            "Table 7 column",
            "crank speed (rpm)",
            "95 % interval (rpm)",
            "phase (deg)",
            "95 % interval (deg)",
            "RMS error before (%)",
            "RMS error after (%)",
            "residual RMS (deg/s)",
        ],
        caption="Nominal kinematics fitted to each column (the paper's crank: 200 rpm)",
        text_columns=(0, 2, 4),
    )
    report.bullets(
        f"{column.replace('_', ' ')}: {fit['unexplained']}"
        for column, fit in explained["columns"].items()
    )


# --- solver and provenance ------------------------------------------------------------------------


def _solver_section(
    page: _Page, study: PaperStudy, provenance: dict[str, Any], report_s: float
) -> None:
    report = page.report
    report.heading("Solver statistics and provenance", anchor="solver")
    rows: list[tuple[Any, ...]] = []
    groups = []
    kinds = {
        "method": "The six methods from rest",
        "steady": "Running steadily",
        "corner": "Length corners",
        "sensitivity": "Sensitivities",
        "cylindrical": "Cylindrical ECS at the length limits",
    }
    last = None
    order = list(kinds)

    def rank(key: str) -> int:
        kind = key.split("/")[0]
        return order.index(kind) if kind in order else len(order)

    for key, outcome in sorted(study.outcomes.items(), key=lambda item: rank(item[0])):
        kind = key.split("/")[0]
        if kind != last:
            groups.append((len(rows), kinds.get(kind, kind)))
            last = kind
        label = outcome.task.label
        if not outcome.ok:
            rows.append((label, outcome.error, None, None, None, None, None, None, outcome.wall_s))
            continue
        s = (outcome.summary or {})["solver"]
        rows.append(
            (
                label,
                "ok",
                s["steps"],
                s["rejected_steps"],
                s["rhs_evaluations"],
                sum(s["impacts"].values()),
                s["max_penetration_m"] * 1e6,
                s["energy_residual"],
                outcome.wall_s,
            )
        )
    with report.details(f"Solver statistics of the {len(rows)} simulations"):
        report.table(
            rows,
            [
                "simulation",
                "status",
                "steps",
                "rejected steps",
                "right-hand-side evaluations",
                "impacts",
                "largest penetration (µm)",
                "energy residual (–)",
                "wall time (s)",
            ],
            text_columns=(0, 1),
            groups=groups,
            note="Integrator: Radau IIA of order 5 (compiled), contact onset located by step "
            "control, ideal constraints projected after every step. Energy residual: "
            "|KE + V − W_motor + W_contact − E0| / max(KE, W_motor), dimensionless. Wall time: "
            "of the simulation alone, in its worker.",
        )
    report.paragraph(
        f"Simulations and analyses: {study.wall_s:.1f} s; this page and its figures: "
        f"{report_s:.1f} s before the provenance was written.",
        css="small",
    )
    with report.details("Provenance: version, command line and settings"):
        report.preformatted(json.dumps(provenance, indent=2, default=str))
