"""The paper study's page, the model's sections: the mechanism, the equivalent contact
stiffness (ECS) and the six methods (their peaks from rest, the orbits, the running
mechanism). Tables in the one number format of :mod:`jointplay.report.format`; figures from
:mod:`jointplay.report.paper_figures`.
"""

from __future__ import annotations

import math
from typing import Any

from jointplay.dynamics.diagnostics import IDEAL_FORCE_FACTOR
from jointplay.report.format import number
from jointplay.report.html import HtmlReport
from jointplay.report.paper_figures import (
    JOINT_WORDS,
    QUANTITIES,
    mechanism_figure,
    method_figure,
    nominal_figure,
    orbit_extents,
    orbit_figure,
    orbit_table,
)
from jointplay.report.paper_results import (
    INCREASE_DEFINITION,
    LABELS,
    PEAK_DEFINITION,
    _settle,
    _start_up_vs_running,
)
from jointplay.report.paper_summary import _Page, flag_force
from jointplay.report.plots import ecs_sweep_plots
from jointplay.study.methods import METHODS
from jointplay.study.paper import (
    JOINTS,
    PAPER_CLEARANCE,
    PEAK_KEYS,
    STARTUP_PLOT_DEG,
    PaperStudy,
    geometry_figures,
    method_words,
)


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
                *[
                    flag_force(outcome.peak(q), study.nominal_peaks[q], start_up=True)
                    if q.startswith("F_")
                    else outcome.peak(q)
                    for q in quantities
                ],
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
            note=PEAK_DEFINITION + f" ⚠: a joint force above {IDEAL_FORCE_FACTOR:g}× the ideal "
            "joint's peak (the footnote says why).",
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
            cells: list[Any] = []
            for q in quantities:
                value = math.nan if values[q][setting] is None else values[q][setting]
                if q.startswith("F_"):
                    value = flag_force(value, values[q]["nominal"], start_up=setting == "from_rest")
                cells.append(value)
            rows.append(
                [
                    "from rest (the paper)" if setting == "from_rest" else "running steadily",
                    *cells,
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
        "started on the nominal motion. ⚠: a joint force above "
        f"{IDEAL_FORCE_FACTOR:g}× the ideal joint's peak (the footnote says why).",
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
