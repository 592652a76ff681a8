"""The paper study's page, its checks against tolerances, measurements and the solver:
nominal vs actual (the tolerance corners), the experiment (Table 7, and what a fit of the crank
speed and phase explains) and the solver with the run's provenance.
"""

from __future__ import annotations

import json
from typing import Any

from jointplay.report.format import number
from jointplay.report.paper_figures import QUANTITIES
from jointplay.report.paper_results import (
    LABELS,
    PEAK_DEFINITION,
    _rows,
)
from jointplay.report.paper_summary import _Page
from jointplay.study.paper import (
    PAPER_CLEARANCE,
    PaperStudy,
    corner_words,
    method_words,
    worst_corners,
)

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
            note="Integrator: Radau IIA of order 5 (compiled), RODAS4 (linearly implicit, order "
            "4) for the two IFM ECS methods, on whose damping Radau's Newton iteration keeps "
            "failing; contact onset located by step control, ideal constraints projected "
            "after every step. Energy residual: "
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
