"""Plausibility diagnostics: each code fires on a case built for it and stays silent otherwise."""

from __future__ import annotations

import math

import pytest

from jointplay.dynamics import diagnostics as dg
from jointplay.dynamics.settings import RunSettings, simulate_run
from jointplay.dynamics.setup import ContactModel
from jointplay.model.mechanism import STEEL, Material, Mechanism


def test_line_contact_pressure_equals_hertz_closed_form() -> None:
    # Johnson (1985) eq. 4.45: p0 = sqrt(f E* / (pi R)) with R = R_J R_B / (R_B - R_J).
    force, width, radius, clearance = 75.0, 0.01, 5e-3, 21e-6
    e_star = 1 / (2 * (1 - STEEL.poisson_ratio**2) / STEEL.youngs_modulus)
    big_r = radius * (radius + clearance) / clearance
    expected = math.sqrt(force / width * e_star / (math.pi * big_r))
    pressure = dg.line_contact_pressure(force, width, radius, clearance, STEEL, STEEL)
    assert pressure == pytest.approx(expected, rel=1e-12)
    assert pressure == pytest.approx(15.0e6, rel=0.01)  # ~15 MPa: a steady 75 N is harmless


def test_penetration_beyond_clearance_warns() -> None:
    assert dg.check_penetration("A", 20e-6, 21e-6) is None
    found = dg.check_penetration("A", 168e-6, 21e-6)
    assert found is not None and found.code == "penetration-exceeds-clearance"
    assert (found.level, found.joint, found.value, found.limit) == ("warning", "A", 168e-6, 21e-6)


def test_pressure_beyond_the_allowable_warns_and_unknown_strength_is_said() -> None:
    assert STEEL.contact_pressure_limit == pytest.approx(1.79 * 250e6)
    assert dg.check_pressure("B", 15e6, STEEL, 75.0) is None
    found = dg.check_pressure("B", 4.2e9, STEEL, 5.8e6)
    assert found is not None and found.code == "contact-pressure-exceeds-allowable"
    assert found.limit == pytest.approx(447.5e6)
    unknown = Material("resin", density=1200.0, youngs_modulus=3e9, poisson_ratio=0.35)
    info = dg.check_pressure("B", 1e6, unknown, 1.0)
    assert info is not None and (info.level, info.code) == ("info", "contact-pressure-unchecked")
    given = Material("x", 7800.0, 207e9, 0.3, allowable_contact_pressure=1.5e9)
    assert dg.check_pressure("B", 1.0e9, given, 1.0) is None


def test_force_far_above_ideal_is_information() -> None:
    assert dg.check_force_against_ideal("O2", 400.0, 46.0) is None
    found = dg.check_force_against_ideal("O2", 5400.0, 46.0)
    assert found is not None and (found.level, found.code) == ("info", "force-far-above-ideal")


def test_start_transient() -> None:
    assert dg.check_start_transient("F_A", [80.0, 75.0, 76.0], steady_start=False) is None
    found = dg.check_start_transient("F_A", [5000.0, 75.0, 76.0], steady_start=False)
    assert found is not None and found.code == "start-transient-dominates"
    single = dg.check_start_transient("F_A", [5000.0], steady_start=False, first_peak_crank_deg=2.0)
    assert single is not None and single.code == "start-transient-dominates"
    assert (
        dg.check_start_transient("F_A", [75.0], steady_start=True, first_peak_crank_deg=2.0) is None
    )
    assert (
        dg.check_start_transient("F_A", [75.0], steady_start=False, first_peak_crank_deg=200.0)
        is None
    )


def test_not_settled_and_not_periodic_and_energy() -> None:
    assert dg.check_settled("F_A", [75.0, 75.5, 75.2]) is None
    assert dg.check_settled("F_A", [75.0, 60.0, 90.0, 70.0]) is None  # scatter, no trend
    drifting = dg.check_settled("F_A", [120.0, 100.0, 90.0])
    assert drifting is not None and drifting.code == "not-settled"
    assert drifting.value == pytest.approx(20.0 / 95.0)
    assert dg.check_settled("F_A", [120.0, 100.0]) is None  # too few to tell
    assert dg.check_periodic("periodic (period 1)", 1, 20) is None
    assert dg.check_periodic("undetermined", None, 2) is None
    found = dg.check_periodic("not periodic", None, 20)
    assert found is not None and (found.level, found.code) == ("info", "not-periodic")
    assert dg.check_energy(1e-6) is None
    drift = dg.check_energy(0.02)
    assert drift is not None and drift.code == "energy-drift"


def test_collect_keeps_one_per_code_and_joint_warnings_first() -> None:
    items = [
        dg.check_periodic("not periodic", None, 5),
        dg.check_penetration("A", 1e-4, 2e-5),
        dg.check_penetration("A", 2e-4, 2e-5),
        None,
        dg.check_energy(0.1),
    ]
    found = dg.collect(items)
    assert [(d.code, d.joint) for d in found] == [
        ("energy-drift", None),
        ("penetration-exceeds-clearance", "A"),
        ("not-periodic", None),
    ]
    assert set(dg.as_records(found)[0]) == {"level", "code", "joint", "value", "limit", "message"}


def test_transmission_angle_below_the_guideline_is_a_warning(paper_fourbar) -> None:
    """The paper's crank-rocker runs 36.9°–91.5° (below 40°); a well-proportioned one does not
    warn, nor does a slider-crank. The value is min over a 0.01° grid of min(μ, 180° − μ)."""
    import numpy as np

    from jointplay.kinematics.fourbar import MIN_TRANSMISSION_ANGLE_DEG, transmission_angle
    from jointplay.model.templates import FourBarGeometry, four_bar

    finding = dg.check_transmission_angle(paper_fourbar)
    assert finding is not None and finding.level == "warning"
    assert finding.code == "transmission-angle-low" and finding.limit == 40.0
    geometry = paper_fourbar.template.geometry
    mu = np.degrees(transmission_angle(geometry, np.radians(np.arange(0.0, 360.0, 0.01))))
    assert finding.value == pytest.approx(np.minimum(mu, 180.0 - mu).min(), abs=1e-6)
    assert 36.8 < finding.value < MIN_TRANSMISSION_ANGLE_DEG
    assert "Norton" in finding.message and "36.9°–91.5°" in finding.message
    wide = four_bar(FourBarGeometry(0.03, 0.1, 0.1, 0.1), speed=10.0)  # μ from 41.0° to 81.1°
    assert dg.check_transmission_angle(wide) is None


def test_transmission_angle_is_not_checked_on_a_slider_crank(slider_crank) -> None:
    assert dg.check_transmission_angle(slider_crank) is None


#: docs/contact-laws.md §3.7: Ø10 pin, 21 µm, steel E = 207 GPa, ν = 0.3 → K = 1.66e11 N/m^1.5.
ANCHOR_STEEL = Material("anchor", density=7800.0, youngs_modulus=207e9, poisson_ratio=0.3)


def test_the_hertz_approach_is_the_published_anchor() -> None:
    # F = K δ^1.5 with the anchor's K: 166 N at 1 µm (the table's "Hertz-sphere 166 N")
    approach = dg.hertz_approach(166.0, 5e-3, 21e-6, ANCHOR_STEEL, ANCHOR_STEEL)
    assert approach == pytest.approx(1e-6, rel=5e-3)  # K printed to 3 digits
    assert dg.hertz_approach(0.0, 5e-3, 21e-6, ANCHOR_STEEL, ANCHOR_STEEL) == 0.0


def test_penetration_beyond_the_elastic_approach_warns_even_inside_the_clearance() -> None:
    # the case: 164 µm in a 0.5 mm clearance raised nothing
    approach = dg.hertz_approach(500.0, 9.5e-3, 0.5e-3, STEEL, STEEL)
    assert dg.check_penetration("A", 164e-6, 0.5e-3) is None
    found = dg.check_elastic("A", 164e-6, approach, 500.0)
    assert found is not None and (found.level, found.code) == (
        "warning",
        "penetration-exceeds-elastic",
    )
    assert found.limit == pytest.approx(dg.ELASTIC_FACTOR * approach)
    assert dg.check_elastic("A", 0.99 * dg.ELASTIC_FACTOR * approach, approach, 500.0) is None
    assert dg.check_elastic("A", 1.01 * dg.ELASTIC_FACTOR * approach, approach, 500.0) is not None


def test_a_contact_wider_than_hertz_theory_allows_is_flagged() -> None:
    # the force that gives a half-width b: Johnson eq. 4.43 inverted, f = π E* b² / (4 R)
    radius, clearance, width = 5e-3, 21e-6, 0.01
    e_star = 1 / (2 * (1 - STEEL.poisson_ratio**2) / STEEL.youngs_modulus)
    big_r = radius * (radius + clearance) / clearance

    def force_at(share: float) -> float:
        return math.pi * e_star * (share * radius) ** 2 / (4 * big_r) * width

    args = (width, radius, clearance, STEEL, STEEL)
    assert dg.check_hertz_validity("O2", force_at(0.99 * dg.HERTZ_VALIDITY), *args) is None
    found = dg.check_hertz_validity("O2", force_at(0.57), *args)  # the paper's start from rest
    assert found is not None and found.code == "hertz-validity"
    assert found.value == pytest.approx(0.57, rel=1e-9) and found.limit == dg.HERTZ_VALIDITY


def test_the_slider_crank_says_its_soft_contact_is_not_elastic(slider_crank) -> None:
    """The conventional set sinks the pin 436 µm into a 0.5 mm clearance (inside it, so the
    clearance check is silent); the elastic check fires. The default contact passes both."""
    from jointplay.dynamics.setup import DEFAULT_IMPACT, ContactModel
    from jointplay.dynamics.simulate import simulate

    codes = {}
    for name, contact in (("soft", ContactModel(law=DEFAULT_IMPACT)), ("default", ContactModel())):
        result = simulate(slider_crank, contact.joints(slider_crank), revolutions=1, settle=2)
        codes[name] = {d.code for d in result.diagnostics if d.joint == "B"}
    assert "penetration-exceeds-elastic" in codes["soft"]
    assert "penetration-exceeds-clearance" not in codes["soft"]
    assert not {"penetration-exceeds-elastic", "penetration-exceeds-clearance"} & codes["default"]


def test_advice_names_settings_as_each_caller_calls_them() -> None:
    """The Python API's words in the message and the record; the command line's options
    through ``named``/``line(names)``; the template survives pickling (worker processes)."""
    import pickle

    from jointplay.dynamics.diagnostics import check_energy, check_settled

    energy = check_energy(0.5)
    assert energy is not None and energy.message.endswith("tighten rtol")
    assert energy.line({"rtol": "--rtol"}).endswith("tighten --rtol")
    assert energy.named({"rtol": "--rtol"}).message.endswith("tighten --rtol")
    assert "template" not in energy.as_dict() and energy.as_dict()["message"] == energy.message
    assert pickle.loads(pickle.dumps(energy)).line({"rtol": "--rtol"}) == energy.line(
        {"rtol": "--rtol"}
    )
    settled = check_settled("omega4", [10.0, 12.0, 12.1, 12.05])
    assert settled is not None and settled.line({"settle": "--settle"}).endswith("raise --settle")


def test_dry_joints_with_too_few_revolutions_say_the_peaks_may_be_draws(
    paper_fourbar: Mechanism,
) -> None:
    """A dry run of one revolution cannot be checked for periodicity, and dry pins rattle:
    the run says so; a lubricated one, or a dry one whose verdict is known, does not."""
    found = dg.check_dry_undetermined("undetermined", 1, ["O2", "B"])
    assert found is not None and (found.level, found.code) == ("info", "dry-undetermined")
    assert "O2, B" in found.message and "--ensemble" in found.message
    assert (found.value, found.limit) == (1.0, 3.0)  # JSON-ready: no NaN (explore)
    assert dg.check_dry_undetermined("undetermined", 1, []) is None
    assert dg.check_dry_undetermined("not periodic", 20, ["O2"]) is None
    result = simulate_run(
        paper_fourbar, None, RunSettings(contact=ContactModel(lubrication="dry"), revolutions=0.2)
    )
    assert "dry-undetermined" in {f.code for f in result.diagnostics}
    lubricated = simulate_run(paper_fourbar, None, RunSettings(revolutions=0.2))
    assert "dry-undetermined" not in {f.code for f in lubricated.diagnostics}
