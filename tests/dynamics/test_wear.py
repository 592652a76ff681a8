"""Archard wear: by hand, volume conservation of the profiles, life, and the coupled loop."""

from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.reference import ReferenceModel
from jointplay.dynamics.setup import DEFAULT_IMPACT
from jointplay.dynamics.simulate import Start, simulate
from jointplay.dynamics.wear import (
    DEFAULT_HARDNESS,
    DEFAULT_WEAR_COEFFICIENT,
    WearSettings,
    archard_volume,
    cycle_wear,
    life_hours,
    profile_volume,
    wear_from_series,
    wear_life,
)
from jointplay.errors import ConfigError
from jointplay.model.mechanism import GROUND

#: Sums of a few thousand positive terms: relative rounding well under 1e-12.
SUM_RTOL = 1e-12
STEEL_MODULUS = 113.7e9  # E* of steel on steel, Pa (reference notes §3.7)


def _constant_case(bins: int = 720):
    """F = 40 N at a fixed angle, sliding at 0.25 m/s for 2 s: s = 0.5 m."""
    t = np.linspace(0.0, 2.0, 2001)
    force = np.full_like(t, 40.0)
    slip = np.full_like(t, -0.25)  # the sign of v_T does not matter
    angle = np.full_like(t, math.radians(100.0))
    return wear_from_series(
        t, force, slip, angle, angle - 0.5,
        joint="A", journal_radius=5e-3, clearance=20e-6, width=10e-3,
        coefficient=1e-4, hardness=2e9, modulus=STEEL_MODULUS, bins=bins,
    )  # fmt: skip


def test_archard_by_hand() -> None:
    # V = k F s / H = 1e-4 * 40 N * 0.5 m / 2e9 Pa = 1e-12 m³
    assert archard_volume(40.0, 0.5, 1e-4, 2e9) == pytest.approx(1e-12, rel=1e-15)
    wear = _constant_case()
    assert wear.sliding == pytest.approx(0.5, rel=SUM_RTOL)
    assert wear.work == pytest.approx(40.0 * 0.5, rel=SUM_RTOL)
    assert wear.volume_bearing == pytest.approx(1e-12, rel=SUM_RTOL)
    # the wear sits around the contact angle (100° on the bearing, 100° - 0.5 rad on the pin)
    peak = (np.argmax(wear.bearing_profile) + 0.5) * 360.0 / len(wear.bearing_profile)
    assert peak == pytest.approx(100.0, abs=0.5)


@pytest.mark.parametrize("bins", [36, 360, 720])
def test_depth_integrated_over_the_bearing_is_the_worn_volume(bins: int) -> None:
    wear = _constant_case(bins)
    assert profile_volume(wear.bearing_profile, wear.bearing_radius, wear.width) == pytest.approx(
        wear.volume_bearing, rel=SUM_RTOL
    )
    assert profile_volume(wear.journal_profile, wear.journal_radius, wear.width) == pytest.approx(
        wear.volume_journal, rel=SUM_RTOL
    )


def test_no_force_no_wear() -> None:
    t = np.linspace(0, 1, 11)
    wear = wear_from_series(
        t, np.zeros(11), np.ones(11), np.zeros(11), np.zeros(11), joint="O2",
        journal_radius=5e-3, clearance=1e-5, width=1e-2, coefficient=1e-4, hardness=1e9,
        modulus=STEEL_MODULUS,
    )  # fmt: skip
    assert wear.volume_bearing == 0.0 and wear.growth_per_revolution == 0.0


def test_life_of_a_constant_wear_rate_is_limit_over_rate() -> None:
    # from 10 µm to 40 µm at 3 µm/h: 10 h
    assert life_hours(10e-6, 40e-6, 3e-6) == pytest.approx(10.0, rel=1e-12)
    assert life_hours(50e-6, 40e-6, 3e-6) == 0.0
    assert life_hours(10e-6, 40e-6, 0.0) == math.inf


def test_settings_validate_and_override_per_joint() -> None:
    settings = WearSettings(joints={"A": {"coefficient": 1e-6}})
    assert settings.of("A")[0] == 1e-6 and settings.of("B") == (
        DEFAULT_WEAR_COEFFICIENT,
        DEFAULT_HARDNESS,
    )
    with pytest.raises(ConfigError, match="coefficient must be finite and > 0"):
        WearSettings(coefficient=0.0)
    with pytest.raises(ConfigError, match="unknown field 'k'"):
        WearSettings(joints={"A": {"k": 1.0}})


def _joints(mechanism, clearance: float = 21e-6) -> list[ClearanceJoint]:
    return [
        ClearanceJoint(j.name, clearance=clearance, journal_radius=5e-3, law=DEFAULT_IMPACT)
        for j in mechanism.revolute_joints
    ]


#: Archard work of one revolution recomputed from the states with the plain NumPy model against
#: cycle_wear's (the same trapezoids on the same steps): round-off of a ~4300-term sum, measured
#: ≤ 6e-15; 1e-13 leaves room for another libm.
REFERENCE_WORK_RTOL = 1e-13


def _reference_work(result, name: str) -> float:
    """∫ F_N |v_T| dt over the last revolution from the integrator's states, with the contact
    geometry, velocities and force of :class:`ReferenceModel` (not the kernel's columns)."""
    model = ReferenceModel(result.system)
    joint, clearance = result.mechanism.joint(name), model.clear[name]
    c = list(model.clear).index(name)
    n, flat = model.n, result.system.flat
    keep = result.t >= result.t[-1] - result.mechanism.driver.period - 1e-12
    power = []
    for y in result.y[keep]:
        q, qd = y[:n], y[n : 2 * n]
        r_b = model.point(q, joint.link_a, joint.point_a)
        r_j = model.point(q, joint.link_b, joint.point_b)
        e = r_j - r_b
        delta = np.linalg.norm(e) - clearance.clearance
        if delta <= 0:
            power.append(0.0)
            continue
        normal = e / np.linalg.norm(e)
        e_dot = model.point_velocity(q, qd, joint.link_b, r_j) - model.point_velocity(
            q, qd, joint.link_a, r_b
        )
        w_a = 0.0 if joint.link_a == GROUND else qd[3 * flat.body_index(joint.link_a) + 2]
        w_b = 0.0 if joint.link_b == GROUND else qd[3 * flat.body_index(joint.link_b) + 2]
        v_t = e_dot @ np.array([-normal[1], normal[0]])
        v_t += clearance.journal_radius * w_b - clearance.bearing_radius * w_a
        v0 = y[2 * n + 2 + c]
        f_n = clearance.law.force(
            np.array([delta]), np.array([e_dot @ normal]), v0=v0 if v0 > 0 else None
        )[0]
        power.append(max(f_n, 0.0) * abs(v_t))
    return float(np.trapezoid(power, result.t[keep]))


def test_cycle_wear_of_the_paper_mechanism(paper_fourbar) -> None:
    result = simulate(paper_fourbar, _joints(paper_fourbar), settle=2, start=Start("steady"))
    wear = cycle_wear(result)
    assert wear.rpm == pytest.approx(200.0)
    for name, joint in wear.joints.items():
        assert joint.sliding > 0 and joint.volume_bearing > 0
        assert joint.work == pytest.approx(_reference_work(result, name), rel=REFERENCE_WORK_RTOL)
        assert profile_volume(
            joint.bearing_profile, joint.bearing_radius, joint.width
        ) == pytest.approx(joint.volume_bearing, rel=SUM_RTOL)
        # Archard over the whole cycle, V = (k/H) ∫ F_N |v_T| dt, is the pair's: half of it
        # comes off the bearing, half off the journal (it used to come off each in full)
        archard = joint.coefficient * joint.work / joint.hardness
        assert joint.volume_bearing == pytest.approx(0.5 * archard, rel=SUM_RTOL)
        assert joint.volume_journal == pytest.approx(0.5 * archard, rel=SUM_RTOL)
        assert profile_volume(
            joint.journal_profile, joint.journal_radius, joint.width
        ) == pytest.approx(joint.volume_journal, rel=SUM_RTOL)


def test_coupled_wear_opens_the_joints_and_gives_a_life(paper_fourbar) -> None:
    hardened = WearSettings(coefficient=1.3e-4, hardness=850 * 9.80665e6)  # slow: 3 points
    history = wear_life(
        paper_fourbar, _joints(paper_fourbar), hours=4.0, update_hours=2.0,
        clearance_limit=60e-6, settings=hardened,
    )  # fmt: skip
    assert history.hours == (0.0, 2.0, 4.0)
    for name, values in history.clearance.items():
        assert values[0] == pytest.approx(21e-6)
        assert all(b > a for a, b in itertools.pairwise(values))
        assert history.life[name] > 0
    assert history.mechanism_life == min(history.life.values())
    assert "effective radial clearance" in history.assumption


def test_wear_data_follow_the_materials(paper_fourbar) -> None:
    """The presets' steel is mild (ASTM A36's yield strength): it wears as mild steel, not as
    the hardened tool steel the defaults used to be; an unknown material asks for values."""
    import dataclasses

    from jointplay.dynamics.wear import MATERIAL_WEAR, material_wear

    assert paper_fourbar.material_of("crank").name == "steel"
    data = material_wear(paper_fourbar, "A")
    assert (data.coefficient, data.hardness) == (7e-3, pytest.approx(1.824e9, rel=1e-3))
    assert "mild steel" in data.source
    assert WearSettings().of("A", paper_fourbar) == (data.coefficient, data.hardness)
    tool = dataclasses.replace(paper_fourbar.materials["steel"], name="tool-steel")
    hardened = dataclasses.replace(paper_fourbar, materials={"steel": tool})
    assert WearSettings().of("A", hardened) == (1.3e-4, MATERIAL_WEAR["tool-steel"].hardness)
    assert WearSettings(coefficient=1e-6).of("A", hardened)[0] == 1e-6
    bronze = dataclasses.replace(paper_fourbar.materials["steel"], name="bronze")
    odd = dataclasses.replace(paper_fourbar, materials={"steel": bronze})
    with pytest.raises(ConfigError, match="no wear data for material 'bronze'"):
        WearSettings().of("A", odd)
    assert WearSettings(coefficient=1e-6, hardness=1e9).of("A", odd) == (1e-6, 1e9)
