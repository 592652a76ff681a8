"""The paper study's report: one self-contained HTML page, results.json and the figures.

Only consumes a :class:`~jointplay.study.paper.PaperStudy`; no physics here.
"""

from __future__ import annotations

import json
import math
from pathlib import Path
from typing import Any

import numpy as np
import pandas as pd

from jointplay import __version__
from jointplay.io.output import write_json
from jointplay.report._mpl import pyplot
from jointplay.report.html import HtmlReport
from jointplay.report.overlays import overlay_plots
from jointplay.report.plots import ecs_sweep_plots
from jointplay.study.claims import paper_claims
from jointplay.study.methods import METHODS
from jointplay.study.paper import JOINTS, PEAK_KEYS, PaperStudy, geometry_figures, worst_corners

PAPER = (
    'C. A. Akhadkar, A. B. Deoghare, A. M. Vaidya, "Simulation and experimental response of '
    'four-bar mechanism with tolerance stack"'
)
LABELS = {
    "omega3": "ω3 (rad/s)", "omega4": "ω4 (rad/s)", "alpha3": "α3 (rad/s²)", "alpha4": "α4 (rad/s²)",
    "F_O2": "F O2 (N)", "F_A": "F A (N)", "F_B": "F B (N)", "F_O4": "F O4 (N)", "torque": "torque (N·m)",
}  # fmt: skip


def write_paper_report(
    study: PaperStudy, folder: Path, provenance: dict[str, Any]
) -> dict[str, Any]:
    """Write ``report.html``, ``results.json`` and ``figures/*.png`` into ``folder``."""
    figures = folder / "figures"
    figures.mkdir(exist_ok=True)
    claims = paper_claims(study)
    results = results_document(study, claims, provenance)
    write_json(folder / "results.json", results)
    page = HtmlReport("jointplay: the four-bar with tolerance stack of Akhadkar et al., reproduced")
    _introduction(page, study)
    _claims_section(page, claims)
    _mechanism_section(page, study, figures)
    _ecs_section(page, study, figures)
    _methods_section(page, study, figures)
    _tolerance_section(page, study)
    _experiment_section(page, study, figures)
    _solver_section(page, study, provenance)
    page.write(folder / "report.html")
    return results


# --- results.json -----------------------------------------------------------------------------


def _records(table: pd.DataFrame) -> list[dict[str, Any]]:
    return json.loads(table.to_json(orient="records"))


def results_document(study: PaperStudy, claims: list, provenance: dict[str, Any]) -> dict[str, Any]:
    """Every number of the report's tables, JSON-ready."""
    methods = {}
    for key, outcome in study.outcomes.items():
        methods[key] = {
            "method": outcome.task.method,
            "ecs_source": outcome.task.ecs_source,
            "lengths_m": dict(outcome.task.lengths),
            "error": outcome.error,
            "peaks": None if not outcome.ok else outcome.summary["peaks"],  # type: ignore[index]
            "increase_percent": None if not outcome.ok else outcome.summary["increase_percent"],  # type: ignore[index]
            "start": outcome.task.start,
            "settle_revolutions": outcome.task.settle,
            "startup_peaks": outcome.startup_peaks,
            "sampled_peaks": outcome.sampled_peaks,
            "solver": None if not outcome.ok else outcome.summary["solver"],  # type: ignore[index]
            "clearance_joints": None if not outcome.ok else outcome.summary["clearance_joints"],  # type: ignore[index]
            "diagnostics": None if not outcome.ok else outcome.summary["diagnostics"],  # type: ignore[index]
            "wall_s": outcome.wall_s,
        }
    return {
        "paper": PAPER,
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
        "claims": [c.as_dict() for c in claims],
        "wall_s": study.wall_s,
        "provenance": provenance,
    }


# --- sections ---------------------------------------------------------------------------------


def _introduction(page: HtmlReport, study: PaperStudy) -> None:
    o = study.options
    page.paragraph(
        f"This page reproduces the workflow of {PAPER} with jointplay {__version__}: the crank-rocker of "
        "the paper's Table 1 (read as in shared/reference/paper-notes.md: crank 108 mm, coupler and rocker "
        "270.5 mm, ground 279.4 mm), radial clearance 0.021 mm (the largest of Ø10 H8/g7) in all four joints, "
        f"crank at {o.rpm:g} RPM started from rest, the paper's six simulation methods (Table 2), the "
        "tolerance stack (ISO 2768-1 class c) and the measured rocker speed (Table 7)."
    )
    page.paragraph(
        f"Every simulation covers {o.revolutions:g} crank revolution(s) from rest; ECS-based methods ran with "
        f"the paper's published parameters (Tables 4 and 5) and with ours ({', '.join(o.ecs_sources)}). "
        f"Peaks are taken over every integrator step. Total run time {study.wall_s:.1f} s.",
        css="small",
    )


def _claims_section(page: HtmlReport, claims: list) -> None:
    page.heading("The paper's claims beside ours", anchor="claims")
    page.paragraph(
        "Every quantitative claim of the paper, the number jointplay finds for it, the difference and a "
        "one-line explanation. Differences are ours relative to the paper's."
    )
    rows = [
        (
            c.section,
            c.claim,
            c.paper,
            c.ours,
            c.ours_sampled,
            c.unit,
            c.difference_pct,
            c.ours_source,
            c.note,
        )
        for c in claims
    ]
    page.table(
        rows,
        [
            "section",
            "claim",
            "paper",
            "jointplay",
            "sampled",
            "unit",
            "difference %",
            "our value is",
            "why they differ",
        ],
        text_columns=(0, 1, 5, 7, 8),
    )


def _mechanism_section(page: HtmlReport, study: PaperStudy, figures: Path) -> None:
    page.heading("The mechanism", anchor="mechanism")
    figures_info = geometry_figures(study.mechanism)
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
                f"{lower * 1e3:+g} / {upper * 1e3:+g} ({source})",
                link.mass if link else math.nan,
                link.inertia if link else math.nan,
            )
        )
    page.table(
        rows,
        ["link", "length (mm)", "tolerance (mm)", "mass (kg)", "inertia (kg·m²)"],
        text_columns=(0, 2),
    )
    page.paragraph(
        f"Grashof class {figures_info['grashof']}; rocker swing {figures_info['rocker_swing_deg']:.2f}°; "
        f"transmission angle {figures_info['transmission_angle_deg'][0]:.1f}°–{figures_info['transmission_angle_deg'][1]:.1f}°. "
        "Joints Ø10 H8/g7: radial clearance 2.5–21 µm; simulated at 21 µm."
    )
    page.figure(
        _mechanism_figure(study, figures / "mechanism.png"),
        "Linkage at 12 crank angles and the path of B (crank counter-clockwise).",
    )
    page.figure(
        _nominal_figure(study, figures / "nominal.png"),
        "Nominal mechanism (ideal joints), one revolution at 200 RPM.",
    )
    peaks = [(LABELS[k], v) for k, v in study.nominal_peaks.items()]
    page.table(
        peaks,
        ["nominal peak", "value"],
        caption="Nominal peaks (largest |value| over a revolution)",
    )


def _ecs_section(page: HtmlReport, study: PaperStudy, figures: Path) -> None:
    page.heading("Equivalent contact stiffness (paper eqs. 9–13)", anchor="ecs")
    computed = study.ecs["computed"]
    conventions = study.ecs["conventions"]
    page.paragraph(
        "Load: eq. 13, the largest |α r m| of the nominal mechanism at each joint (α of the link, r and m the "
        "pin's radius and mass). The conventions the paper leaves open are explicit:"
    )
    page.table(
        [(k, str(v)) for k, v in conventions.items()], ["convention", "value"], text_columns=(0, 1)
    )
    rows: list[tuple[Any, ...]] = []
    for data in computed["joints"]:
        for contact in ("spherical", "cylindrical"):
            if contact not in data:
                continue
            est = data[contact]["paper_units"]
            rows.append(
                (
                    data["joint"],
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
    page.table(
        rows,
        [
            "joint",
            "contact",
            "load F (N)",
            "E* (N/mm²)",
            "R (mm)",
            "a or b (mm)",
            "K (N/mm)",
            "δ (mm)",
            "D (N·s/mm)",
        ],
        caption="ECS per joint (intermediate values and results, the paper's units)",
        text_columns=(0, 1),
    )
    published = study.ecs["published"]
    rows = []
    for contact, table in (("spherical", "Table 5"), ("cylindrical", "Table 4")):
        ours = computed["overall"][contact]["paper_units"]
        paper = published[contact]
        for label, our_key in (
            ("K (N/mm)", "stiffness_N_per_mm"),
            ("δ (mm)", "penetration_mm"),
            ("D (N·s/mm)", "damping_N_s_per_mm"),
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
    page.table(
        rows,
        ["contact", "quantity", "paper", "jointplay", "ratio"],
        caption="ECS at 200 RPM: ours and the paper's",
        text_columns=(0, 1),
    )
    paths = ecs_sweep_plots(study.ecs_sweep, ("spherical", "cylindrical"), figures)
    page.figure(
        paths[0],
        "ECS stiffness, penetration and damping over crank speed (crosses: the paper's values at 200 RPM).",
    )
    page.figure(
        paths[1],
        "Hysteresis damping factor of the ECS model (our definition χ = (D/K)·v0/δ; the paper does not define its "
        "Fig. 6 quantity) beside χ(e) of Lankarani–Nikravesh, Hunt–Crossley, Flores and Hu–Guo.",
    )
    page.table(
        study.ecs_sweep.paper_units_table().round(6), caption="Crank-speed sweep (paper units)"
    )


def _published_value(paper: dict[str, Any], key: str) -> float:
    return float(paper["paper_units"].get(key, math.nan))


def _method_keys(study: PaperStudy) -> list[str]:
    return [k for k in study.outcomes if k.startswith("method/")]


def _methods_section(page: HtmlReport, study: PaperStudy, figures: Path) -> None:
    page.heading("The six simulation methods (paper Table 2)", anchor="methods")
    page.paragraph(
        "Each method with clearance 0.021 mm in all four joints, basic lengths, started from rest. "
        "Peaks over every integrator step; the % increase is against the nominal peak (ideal joints)."
    )
    rows = []
    for key in _method_keys(study):
        outcome = study.outcomes[key]
        row: list[Any] = [METHODS[outcome.task.method].title, outcome.task.ecs_source]
        for quantity in PEAK_KEYS:
            row.append(outcome.peak(quantity) if outcome.ok else math.nan)
        rows.append(row)
    page.table(
        rows,
        ["method", "ECS source", *[LABELS[k] for k in PEAK_KEYS]],
        caption="Peaks",
        text_columns=(0, 1),
    )
    rows = []
    for key in _method_keys(study):
        outcome = study.outcomes[key]
        increase = outcome.summary["increase_percent"] if outcome.ok else {}  # type: ignore[index]
        rows.append(
            [
                METHODS[outcome.task.method].title,
                outcome.task.ecs_source,
                *[increase.get(k, math.nan) for k in PEAK_KEYS],
            ]
        )
    page.table(
        rows,
        ["method", "ECS source", *PEAK_KEYS],
        caption="Increase over the nominal peak (%)",
        text_columns=(0, 1),
    )
    for quantity, title in (
        ("omega3", "coupler angular velocity"),
        ("omega4", "rocker angular velocity"),
        ("alpha3", "coupler angular acceleration"),
        ("alpha4", "rocker angular acceleration"),
        ("F_O2", "crank–ground joint force"),
        ("F_A", "crank–coupler joint force"),
        ("F_B", "coupler–rocker joint force"),
        ("F_O4", "rocker–ground joint force"),
    ):
        path = _method_grid(study, quantity, figures / f"methods_{quantity}.png", title)
        page.figure(
            path,
            f"{title.capitalize()} of the six methods (paper's ECS values solid, ours thin) with the nominal curve dashed.",
        )
    _running_subsection(page, study)
    key = f"method/{study.options.tolerance_method}/{study.options.tolerance_source}"
    reference = study.outcomes.get(key)
    if reference is not None and reference.orbits is not None:
        page.figure(
            _orbit_figure(reference.orbits, figures / "orbits.png", key),
            f"Journal-centre orbits inside the 21 µm clearance circles, {key}.",
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


def _running_subsection(page: HtmlReport, study: PaperStudy) -> None:
    document = _start_up_vs_running(study)
    comparison = document["methods"]
    if not comparison:
        return
    page.heading("From rest (the paper's setting) and running steadily", level=3, anchor="running")
    page.paragraph(document["why"], css="note")
    quantities = ("omega3", "omega4", "F_O2", "F_A", "F_B", "F_O4", "torque")
    rows = []
    for label, values in comparison.items():
        method, source = label.split("/")
        for setting in ("from_rest", "running"):
            rows.append(
                [
                    METHODS[method].title,
                    source,
                    "from rest (paper)" if setting == "from_rest" else "running steadily",
                    *[
                        math.nan if values[q][setting] is None else values[q][setting]
                        for q in quantities
                    ],
                ]
            )
    rows.append(["ideal joints", "—", "nominal", *[study.nominal_peaks[q] for q in quantities]])
    page.table(
        rows,
        ["method", "ECS source", "start", *[LABELS[q] for q in quantities]],
        caption="Peaks from rest and running steadily",
        text_columns=(0, 1, 2),
    )
    findings: dict[tuple[str, str], list[str]] = {}
    for key, outcome in study.outcomes.items():
        if key.startswith(("method/", "steady/")) and outcome.ok:
            for finding in outcome.summary["diagnostics"]:  # type: ignore[index]
                if finding["level"] == "warning":
                    findings.setdefault((finding["code"], key.split("/")[0]), []).append(key)
    if findings:
        page.paragraph(
            "Plausibility warnings (see summary.json of `jointplay simulate` for each): "
            + "; ".join(
                f"{code} in {len(keys)} {'start-up' if kind == 'method' else 'running'} run(s)"
                for (code, kind), keys in sorted(findings.items())
            )
            + ".",
            css="note",
        )


def _tolerance_section(page: HtmlReport, study: PaperStudy) -> None:
    page.heading("Nominal vs actual mechanism (tolerance stack)", anchor="tolerance")
    method = study.options.tolerance_method
    page.paragraph(
        f"Actual = link lengths at their ISO 2768-1 c limits + clearance 0.021 mm in all four joints, simulated "
        f"with {method} ({study.options.tolerance_source} parameters) from rest; the corner label gives crank, "
        "coupler, rocker, ground at their upper (+) or lower (−) limit. '(ideal)' columns: the same lengths with "
        "ideal joints, to separate the effect of the lengths from that of the clearance."
    )
    table = study.length_cases
    columns = ["case", "method"]
    for quantity in ("omega3", "omega4", "alpha4", "F_A", "F_O4"):
        columns += [quantity, f"{quantity}_change_pct", f"{quantity}_ideal_change_pct"]
    page.table(
        table[columns],
        caption="Peaks and % change against the nominal mechanism",
        text_columns=(0, 1),
    )
    page.table(
        worst_corners(table, method),
        caption=f"Worst corner for each output ({method}; ideal-joint worst corner beside it)",
        text_columns=(0, 1, 4),
    )
    page.heading("Sensitivity of the rocker's peak angular acceleration", level=3)
    page.paragraph(
        "One length at its upper limit, the others at basic size. Kinematic: ideal joints, steady motion. Dynamic: "
        "with clearance, from rest — dominated by the start-up impacts. The paper reports 2.7 % (crank) and 1.3 % (ground)."
    )
    page.table(study.sensitivities, text_columns=(0,))


def _experiment_section(page: HtmlReport, study: PaperStudy, figures: Path) -> None:
    page.heading("Comparison with the experiment (paper Table 7)", anchor="experiment")
    comparison = study.experiment
    if comparison is None:
        page.paragraph("Not run.")
        return
    conventions = comparison.measurements.conventions
    page.paragraph(
        f"Measured rocker speed (Table 7) read with these conventions: {conventions.describe()}. "
        "Each simulation is the steady cycle — started from the nominal motion, "
        f"{study.options.experiment_revolutions} revolutions, the last one used — sampled at the measured "
        "crank angles. Error % = (measured − simulated) / simulated × 100, as the paper computes it; points "
        "where the simulated speed is below 10 % of its largest value are left out of the % statistics "
        "(the % error explodes near zero speed) but kept in the rad/s statistics."
    )
    page.paragraph(comparison.discrepancy.summary(), css="note")
    page.paragraph(comparison.verdict(), css="note")
    if comparison.printed_check is not None:
        page.paragraph(comparison.printed_check.summary(), css="small")
    columns = ["method", "rms_error_percent", "max_abs_error_percent", "max_error_at_deg",
               "rms_difference_in_unit", "max_abs_difference_in_unit", "n_percent_points"]  # fmt: skip
    page.table(
        comparison.table[columns],
        caption="Error statistics per simulation (differences in deg/s)",
        text_columns=(0,),
    )
    points = comparison.points_table()
    wide = points.pivot_table(
        index="crank_deg", columns="method", values=["simulated", "error_percent"]
    )
    wide.columns = [f"{pair[1]} {pair[0]}" for pair in wide.columns]
    measured = points.drop_duplicates("crank_deg").set_index("crank_deg")["measured"]
    table = wide.assign(measured=measured).reset_index()
    table = table[
        [
            "crank_deg",
            "measured",
            *sorted(c for c in table.columns if c not in ("crank_deg", "measured")),
        ]
    ]
    page.table(
        table,
        caption="Per point: measured and simulated rocker speed (deg/s) and error %",
        text_columns=(),
    )
    _explained_subsection(page, study.extra.get("table7_explained"))
    for path in overlay_plots(comparison, figures, title="Rocker speed at 200 RPM"):
        if path.name == "overlay.png":
            page.figure(
                path,
                "Measured rocker speed (points) and the simulated steady cycles (like the paper's Figs. 17–20).",
            )


def _explained_subsection(page: HtmlReport, explained: dict[str, Any] | None) -> None:
    """Which crank speed and phase make the nominal model match each Table 7 column."""
    if not explained:
        return
    page.heading("The experiment, explained: calibrated crank speed and phase", level=3)
    page.paragraph(explained["method"], css="small")
    rows = []
    for column, fit in explained["columns"].items():
        rpm, phase = fit["crank_rpm"], fit["phase_deg"]
        rows.append(
            [
                column,
                rpm["value"],
                f"{rpm['ci95'][0]:.1f} – {rpm['ci95'][1]:.1f}",
                phase["value"],
                f"{phase['ci95'][0]:.2f} – {phase['ci95'][1]:.2f}",
                fit["rms_before"],
                fit["rms_after"],
                fit["residual_rms_deg_s"],
            ]
        )
    page.table(
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
    page.bullets(f"{column}: {fit['unexplained']}" for column, fit in explained["columns"].items())


def _solver_section(page: HtmlReport, study: PaperStudy, provenance: dict[str, Any]) -> None:
    page.heading("Solver statistics and provenance", anchor="solver")
    rows = []
    for key, outcome in study.outcomes.items():
        if not outcome.ok:
            rows.append((key, outcome.error, None, None, None, None, None, None, outcome.wall_s))
            continue
        s = outcome.summary["solver"]  # type: ignore[index]
        rows.append(
            (
                key,
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
    page.table(
        rows,
        [
            "simulation",
            "status",
            "steps",
            "rejected",
            "rhs evaluations",
            "impacts",
            "max penetration (µm)",
            "energy residual",
            "wall (s)",
        ],
        text_columns=(0, 1),
    )
    page.paragraph(
        "Integrator: Radau IIA of order 5 (compiled), contact onset located by step control, ideal constraints "
        "projected after every step; energy residual = |KE + V − W_motor + W_contact − E0| / max(KE, W_motor)."
    )
    page.preformatted(json.dumps(provenance, indent=2, default=str))


# --- figures ----------------------------------------------------------------------------------


def _mechanism_figure(study: PaperStudy, path: Path) -> Path:
    plt = pyplot()
    geometry = study.extra["configuration"]["geometry_m"]
    a, c, d = (geometry[k] * 1e3 for k in ("crank", "rocker", "ground"))
    table = study.nominal
    fig, ax = plt.subplots(figsize=(7, 5), dpi=110)
    theta2 = np.radians(table["crank_deg"].to_numpy())
    theta4 = np.radians(table["theta4_deg"].to_numpy())
    bx, by = d + c * np.cos(theta4), c * np.sin(theta4)
    ax.plot(bx, by, color="0.6", linewidth=1, label="path of B")
    for i in range(0, len(table) - 1, len(table) // 12):
        ax_, ay_ = a * np.cos(theta2[i]), a * np.sin(theta2[i])
        ax.plot([0, ax_, bx[i], d], [0, ay_, by[i], 0], "-o", linewidth=1, markersize=3, alpha=0.6)
    ax.plot([0, d], [0, 0], "k-", linewidth=3)
    ax.set_aspect("equal")
    ax.set_xlabel("x (mm)")
    ax.set_ylabel("y (mm)")
    ax.grid(True, alpha=0.3)
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def _nominal_figure(study: PaperStudy, path: Path) -> Path:
    plt = pyplot()
    table = study.nominal
    fig, axes = plt.subplots(1, 3, figsize=(13, 3.8), dpi=110)
    x = table["crank_deg"]
    for column in ("omega3", "omega4"):
        axes[0].plot(x, table[column], label=column)
    for column in ("alpha3", "alpha4"):
        axes[1].plot(x, table[column], label=column)
    for joint in JOINTS:
        axes[2].plot(x, table[f"F_{joint}"], label=f"F_{joint}")
    for ax, ylabel in zip(axes, ("rad/s", "rad/s²", "N"), strict=True):
        ax.set_xlabel("crank angle (deg)")
        ax.set_ylabel(ylabel)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def _method_grid(study: PaperStudy, quantity: str, path: Path, title: str) -> Path:
    plt = pyplot()
    fig, axes = plt.subplots(2, 3, figsize=(14, 7), dpi=100, sharex=True)
    nominal = study.nominal
    for ax, method in zip(axes.ravel(), METHODS.values(), strict=True):
        for key in _method_keys(study):
            outcome = study.outcomes[key]
            if outcome.task.method != method.name or outcome.trace is None:
                continue
            primary = outcome.task.ecs_source in ("paper", "-")
            ax.plot(
                outcome.trace["crank_deg"],
                outcome.trace[quantity],
                linewidth=1.0 if primary else 0.6,
                alpha=1.0 if primary else 0.6,
                label=f"{outcome.task.ecs_source}" if method.uses_ecs else "simulated",
            )
        ax.plot(nominal["crank_deg"], nominal[quantity], "k--", linewidth=0.9, label="nominal")
        ax.set_title(method.title, fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=7)
        if quantity.startswith(("alpha", "F_")):
            ax.set_yscale("symlog", linthresh=max(1.0, float(nominal[quantity].abs().max())))
    for ax in axes[-1]:
        ax.set_xlabel("crank angle (deg)")
    fig.suptitle(f"{title} ({LABELS[quantity]})")
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path


def _orbit_figure(orbits: pd.DataFrame, path: Path, title: str) -> Path:
    plt = pyplot()
    fig, axes = plt.subplots(1, len(JOINTS), figsize=(3.3 * len(JOINTS), 3.4), dpi=110)
    circle = np.linspace(0, 2 * np.pi, 361)
    for ax, joint in zip(axes, JOINTS, strict=True):
        ax.plot(21 * np.cos(circle), 21 * np.sin(circle), color="0.5", linewidth=0.8)
        ax.plot(orbits[f"ex_{joint}"] * 1e6, orbits[f"ey_{joint}"] * 1e6, linewidth=0.6)
        ax.set_aspect("equal")
        ax.set_title(f"joint {joint}", fontsize=9)
        ax.set_xlabel("e_x (µm)", fontsize=8)
        ax.set_ylabel("e_y (µm)", fontsize=8)
    fig.suptitle(title, fontsize=10)
    fig.tight_layout()
    fig.savefig(path)
    plt.close(fig)
    return path
