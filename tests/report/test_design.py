"""What the design study puts on the drawing, in design.csv and on the report's first screen;
the wear report's figures."""

from __future__ import annotations

import math

import numpy as np
import pandas as pd
import pytest

from jointplay.dynamics.wear import WearHistory
from jointplay.report.design import (
    binding_requirement,
    csv_table,
    design_plots,
    wear_plots,
    wear_profile_figure,
    write_design,
)
from jointplay.report.figures import overlapping_text
from jointplay.study.design import Scheme, design_study, design_units
from jointplay.tolerance.execution import Backend

SERIAL = Backend("serial")


def test_drawing_callouts_give_the_iso_limits(paper_fourbar) -> None:
    """H8/f7 at Ø10 (ISO 286-2): hole 10.000/10.022 mm, pin 9.972/9.987 mm; ISO 2768-1 m:
    ±0.3 mm over 30-120 mm (the 108 mm crank), ±0.5 mm over 120-400 mm."""
    texts = [c.text for c in Scheme(dict.fromkeys(("O2", "A", "B", "O4"), "H8/f7"), "m").callouts(
        paper_fourbar
    )]  # fmt: skip
    assert "joint A hole Ø10 H8 = 10.000/10.022 mm" in texts
    assert "joint A pin Ø10 f7 = 9.972/9.987 mm" in texts
    assert "length crank 108 ± 0.3 mm (ISO 2768-m)" in texts
    assert "length coupler 270.5 ± 0.5 mm (ISO 2768-m)" in texts
    assert len(texts) == 4 * 2 + 4


def test_csv_columns_carry_their_display_units() -> None:
    table = pd.DataFrame(
        {
            "scheme": ["H8/f7 / m"],
            "cost": [57.0],
            "joint_force_mean": [47.5],
            "life_at_confidence": [7200.0],
            "contact_pressure_std": [2e8],
            "rocker_speed_error_mean": [0.015],
            "yield": [99.9],
            "yield_low_life >= 1 h": [99.0],
        }
    )
    units = {"joint_force": "N", "life": "s", "contact_pressure": "Pa", "rocker_speed_error": "1"}
    shown = csv_table(table, units)
    assert list(shown.columns) == [
        "scheme",
        "cost_relative",
        "joint_force_mean_N",
        "life_at_confidence_h",
        "contact_pressure_std_MPa",
        "rocker_speed_error_mean_pct",
        "yield_pct",
        "yield_low_pct_life >= 1 h",
    ]
    assert shown.iloc[0].tolist()[2:6] == pytest.approx([47.5, 2.0, 200.0, 1.5])


def test_first_screen_is_the_answer_and_its_evidence(paper_fourbar, tmp_path) -> None:
    result = design_study(
        paper_fourbar, ["H8/f7", "H11/c11"], ["m"], ["omega4_peak <= 100 rad/s"],
        backend=SERIAL,
    )  # fmt: skip
    write_design(result, tmp_path, design_units(paper_fourbar, "kinematic"), plots=False)
    html = (tmp_path / "report.html").read_text(encoding="utf-8")
    answer = html.index("Answer: cheapest scheme shown to meet every requirement: H11/c11 / m")
    evidence = html.index("0 failures in 1,600 samples")
    drawing = html.index("joint O2 hole Ø10 H11 = 10.000/10.090 mm")
    assert answer < evidence < drawing < html.index("Schemes by cost")
    csv = pd.read_csv(tmp_path / "design.csv")
    assert "omega4_peak_at_confidence_rad_per_s" in csv.columns


def test_the_cost_yield_plot_is_drawn_when_nothing_passes(paper_fourbar) -> None:
    """All undecided (200 samples cannot show 99.73 %): the plot shows the intervals."""
    result = design_study(
        paper_fourbar, ["H8/f7", "H11/c11"], ["m"], ["omega4_peak <= 100 rad/s"],
        samples=200, backend=SERIAL,
    )  # fmt: skip
    assert result.best is None and (result.table["verdict"] == "undecided").all()
    images = design_plots(result, design_units(paper_fourbar, "kinematic"))
    assert images["design_pareto.png"].startswith(b"\x89PNG")


# --- the wear figures ----------------------------------------------------------------------

JOINTS = ("O2", "A", "B", "O4")


def history() -> WearHistory:
    """A synthetic four-joint wear life: lobed worn profiles of a few µm."""
    theta = (np.arange(360) + 0.5) * 2 * math.pi / 360
    hours = (0.0, 50.0, 100.0)
    return WearHistory(
        rpm=200.0,
        limit=dict.fromkeys(JOINTS, 41e-6),
        hours=hours,
        clearance={j: (21e-6, 22e-6, 23e-6) for j in JOINTS},
        peak_force={j: (40.0, 41.0, 42.0) for j in JOINTS},
        speed_error=(0.01, 0.011, 0.012),
        growth_per_hour={j: (2e-8,) * 3 for j in JOINTS},
        bearing_profile={j: 3e-6 * np.abs(np.cos(k + theta)) ** 8 for k, j in enumerate(JOINTS)},
        journal_profile={j: 5e-6 * np.abs(np.sin(k + theta)) ** 8 for k, j in enumerate(JOINTS)},
        life=dict.fromkeys(JOINTS, 1000.0),
        life_extrapolated=dict.fromkeys(JOINTS, True),
        assumption="synthetic",
    )


def test_the_worn_profiles_have_no_colliding_labels() -> None:
    """Each panel's 0° once met the next panel's 180° (and the depth labels sat among the
    angle labels): the check found three collisions in that layout."""
    from jointplay.report._mpl import pyplot

    fig = wear_profile_figure(history())
    assert overlapping_text(fig) == []
    pyplot().close(fig)


def test_wear_plots_give_both_figures(text_overlaps) -> None:
    images = wear_plots(history())
    assert list(images) == ["wear_history.png", "wear_profiles.png"]
    assert not any(text_overlaps.values()), text_overlaps


def test_the_binding_requirement_of_a_scheme_meeting_both_is_the_one_nearer_its_limit() -> None:
    """Every sample meets both requirements (equal yield bounds): the binding one is the
    requirement whose value at the confidence level is nearer its limit, relative to it —
    the paper four-bar's H9/d9 / c: 63.5 N against 150 N, 1.8 % against 3 %."""
    from types import SimpleNamespace

    from jointplay.study.requirements import Requirement

    force = Requirement("joint_force", "<=", 150.0, "N", text="joint_force <= 150 N")
    speed = Requirement("rocker_speed_error", "<=", 0.03, "1", text="rocker_speed_error <= 3 %")
    row = {
        f"yield_low_{force.text}": 99.77,
        f"yield_low_{speed.text}": 99.77,
        "joint_force_at_confidence": 63.5,
        "rocker_speed_error_at_confidence": 0.018,
    }
    result = SimpleNamespace(requirements=(force, speed))
    assert binding_requirement(result, row) is speed  # type: ignore[arg-type]
    row["rocker_speed_error_at_confidence"] = 0.009  # now the force is nearer its limit
    assert binding_requirement(result, row) is force  # type: ignore[arg-type]
    row[f"yield_low_{force.text}"] = 99.9  # a lower yield bound binds first
    assert binding_requirement(result, row) is speed  # type: ignore[arg-type]


def test_the_evidence_line_and_the_table_quote_the_same_yield_with_the_same_label(
    paper_fourbar, tmp_path
) -> None:
    """The headline used to quote the binding requirement's yield as "yield 28 %" beside a
    table whose "yield (%)" was over all requirements (26 %). Now the headline leads with the
    yield over all requirements, labelled as the table's column, and the binding
    requirement's own yield says whose it is. A kinematic study where the two differ: the
    rocker's peak speed (13.74 rad/s mean, std 0.12 in class v) and the smallest
    transmission angle (36.90 deg, std 0.23) each pass their limit in some samples."""
    import html as markup
    import re

    result = design_study(
        paper_fourbar, ["H11/c11"], ["v"],
        ["omega4_peak <= 13.75 rad/s", "transmission_angle_min >= 36.8 deg"], backend=SERIAL,
    )  # fmt: skip
    write_design(result, tmp_path, design_units(paper_fourbar, "kinematic"), plots=False)
    html = (tmp_path / "report.html").read_text(encoding="utf-8")
    row = result.table.iloc[0]
    evidence = re.search(r"<p>Evidence: (.*?)</p>", html) or re.search(
        r"<p>Cheapest scheme, [^:]*: (.*?)</p>", html
    )
    assert evidence, html[:2000]
    line = evidence.group(1)
    # the headline's first number is the table's: the same quantity, the same label
    assert line.startswith(f"yield (all requirements) {row['yield']:.2f} %"), line
    assert "<th>yield (all requirements) (%)</th>" in html
    quoted = {r.text: markup.escape(repr(r.text)) for r in result.requirements}
    binding = [text for text, q in quoted.items() if f"binding requirement {q}" in line]
    assert len(binding) == 1, line
    own = row[f"yield_{binding[0]}"]
    assert f"yield of {quoted[binding[0]]} {own:.2f} %" in line
    assert own != row["yield"]  # the two yields differ, and each says whose it is
