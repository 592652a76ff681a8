"""The paper report's first screen marks implausible values where they are shown, with the
reason one click away (a footnote the mark links to), and names every claim that does not hold
with its error. Built from a small hand-made study (no simulation): the numbers are the
shape of the full study's (the IFM cylindrical ECS run with the paper's values peaks at
71 942 N at O4, 2 969x the ideal joint's 24.23 N)."""

from __future__ import annotations

import math
import re
from pathlib import Path
from types import SimpleNamespace
from typing import Any

from jointplay.report.html import HtmlReport
from jointplay.report.paper_summary import _Page, _summary_section
from jointplay.study.claims import Claim
from jointplay.study.paper import PAPER_CLEARANCE, PEAK_KEYS, SimOutcome, SimTask

NOMINAL = {q: 10.0 for q in PEAK_KEYS} | {"F_O4": 24.23, "omega4": 16.0}


def outcome(method: str, source: str, peaks: dict[str, float], depth: float, **kw: Any) -> Any:
    task = SimTask(f"steady/{method}/{source}", method, source, (), 1.0, 200.0, 10.0, settle=2)
    summary = {
        "peaks": {q: {"value": peaks.get(q, NOMINAL[q])} for q in PEAK_KEYS},
        "cycles": {"deepest_penetration_m": {"A": depth}},
        "diagnostics": kw.get("diagnostics", []),
    }
    return SimOutcome(task, summary, None, None, None, None, None, 1.0)


def study(*outcomes: Any) -> Any:
    return SimpleNamespace(
        options=SimpleNamespace(rpm=200.0),
        outcomes={o.task.key: o for o in outcomes},
        nominal_peaks=NOMINAL,
        experiment=None,
    )


def first_screen(tmp_path: Path, the_study: Any, claims: list[Claim]) -> str:
    page = _Page(HtmlReport("t", toc=False), tmp_path, "png")
    _summary_section(page, the_study, claims)
    return page.report.render()


def cell(text: str, content: str) -> str:
    """The <td> whose text starts with ``content``."""
    found = re.search(r"<td[^>]*>" + re.escape(content) + r".*?</td>", text)
    assert found, content
    return found.group(0)


def test_a_force_far_above_ideal_and_a_deep_penetration_are_marked_with_a_reason(
    tmp_path: Path,
) -> None:
    cylindrical = outcome("ifm-ecs-cylindrical", "paper", {"F_O4": 71942.0}, 0.5 * PAPER_CLEARANCE)
    soft = outcome("ifm-conventional", "-", {"F_O4": 9.0 * 24.23}, 3.0 * PAPER_CLEARANCE)
    text = first_screen(tmp_path, study(cylindrical, soft), [])
    force = cell(text, "71,942 (O4)")
    assert 'class="text flag"' in force
    link = re.search(r'href="#(flag-\d+)"', force)
    assert link, force
    # the reason is one click away: the footnote the mark links to, with the rule
    note = re.search(rf'<li id="{link.group(1)}"[^>]*>(.*?)</li>', text)
    assert note and "2,969× the ideal" in note.group(1) and "above 10×" in note.group(1)
    assert 'class="flag"' in cell(text, "2,969")  # the multiple carries the same mark
    # 9x the ideal peak is not marked; its penetration, 3x the clearance, is
    assert "flag" not in cell(text, "218.1 (O4)")
    deep = cell(text, "63.00")
    assert "flag" in deep and "deeper than the 21 µm radial clearance" in text
    # the rules are stated under the table
    assert "⚠ marks an implausible value" in text


def test_a_peak_of_a_run_that_has_not_settled_is_marked(tmp_path: Path) -> None:
    warning = {
        "level": "warning",
        "code": "not-settled",
        "joint": None,
        "message": "omega4's peak in the first analysed revolution lies 12.0% outside",
    }
    run = outcome("rm-conventional", "-", {"omega4": 17.5}, 0.0, diagnostics=[warning])
    text = first_screen(tmp_path, study(run), [])
    speed = cell(text, "17.50")
    assert "flag" in speed and "Not converged" in text and "12.0% outside" in text


def test_every_claim_that_does_not_hold_is_named_with_its_error(tmp_path: Path) -> None:
    claims = [
        Claim("ECS (Table 5)", "spherical contact K at 200 RPM", 100.0, 250.0, "N/mm", "s", "n"),
        Claim("ECS (Table 5)", "spherical contact delta at 200 RPM", 2.0, 1.0, "mm", "s", "n"),
        Claim("Tolerance stack", "increase of the rocker's peak", 27.0, 30.5, "%", "s", "n"),
        Claim("Start-up", "rocker angular velocity", 20.46, 20.5, "rad/s", "s", "n"),
        Claim("Start-up", "coupler angular velocity", 18.21, math.nan, "rad/s", "s", "n"),
    ]
    the_study = study(outcome("ifm-conventional", "-", {}, 0.0))
    text = first_screen(tmp_path, the_study, claims)
    summary = text[text.index('<ul class="summary">') : text.index("</ul></li></ul>")]
    assert "3 do not" in summary
    failing = re.findall(r"<li>([^<]*)</li>", summary[summary.index("Does not hold") :])
    assert failing == [
        "ECS (Table 5): spherical contact K at 200 RPM: +150 %; spherical contact delta at "
        "200 RPM: -50.0 %.",
        "Tolerance stack: increase of the rocker&#x27;s peak: +3.50 points.",
    ]
    assert "rocker angular velocity" not in "".join(failing)  # it holds
