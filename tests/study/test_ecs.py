"""The ECS method on a mechanism (paper eqs. 9–13): loads, sources, the sweep, hysteresis.

Values computed from the nominal kinematics are compared with rel 1e-12 (same arithmetic,
different order). The formulas themselves are tested in tests/contact/test_ecs.py.
"""

from __future__ import annotations

import dataclasses
import math

import numpy as np
import pytest

from jointplay.contact.ecs import (
    COMPARISON_MODELS,
    CONTACT_TYPES,
    EcsConventions,
    comparison_factors,
    ecs_hysteresis_factor,
    eq13_load,
    impact_velocity_estimate,
    modulus_by_convention,
    spherical_contact,
    spherical_load_lower_bound,
)
from jointplay.contact.laws import ImpactLaw, RestitutionLaw
from jointplay.contact.stiffness import HertzStiffness
from jointplay.dynamics.nominal import nominal_analysis
from jointplay.errors import ConfigError
from jointplay.model.mechanism import STEEL, JointFit, Mechanism
from jointplay.study.ecs import EcsResult, ecs_analysis, ecs_parameters, ecs_sweep
from jointplay.study.published import PAPER_PUBLISHED

#: Same quantity computed along two paths in double precision.
SAME = 1e-12


@pytest.fixture(scope="module")
def paper_ecs(paper_fourbar: Mechanism) -> EcsResult:
    return ecs_analysis(paper_fourbar)


# --- eq. 13 and the mechanism -----------------------------------------------------------------


def test_eq13_load_by_hand_for_the_rocker_pivot(
    paper_fourbar: Mechanism, paper_ecs: EcsResult
) -> None:
    """O4 (ground–rocker): F = max |α₄| r m, r = 5 mm, m = 20 g; max |α₄| ≈ 411 rad/s² → 0.0411 N."""
    table = nominal_analysis(paper_fourbar).table
    alpha4 = table["alpha4"].to_numpy()
    by_hand = np.max(np.abs(alpha4)) * 0.005 * 0.02
    o4 = paper_ecs.joint("O4").load
    assert by_hand == pytest.approx(0.0411, rel=1e-3)
    assert o4.load == pytest.approx(by_hand, rel=SAME)
    assert o4.alpha_link == "rocker"
    assert o4.crank_deg == table["crank_deg"].iloc[int(np.argmax(np.abs(alpha4)))]
    assert float(np.max(eq13_load(alpha4, 0.005, 0.02))) == pytest.approx(by_hand, rel=SAME)


def test_crank_pivot_has_no_eq13_load(paper_ecs: EcsResult) -> None:
    """The crank runs at constant speed (α₂ = 0), so O2 gets no eq. 13 load and no stiffness."""
    o2 = paper_ecs.joint("O2")
    assert o2.load.load == 0.0
    assert o2.spherical.status == o2.cylindrical.status == "zero-load"
    assert o2.spherical.stiffness == o2.cylindrical.stiffness == 0.0
    assert paper_ecs.overall_joint == "A"  # A, B, O4 tie at 0.0411 N; the first wins


def test_alpha_link_convention(paper_fourbar: Mechanism) -> None:
    result = ecs_analysis(paper_fourbar, EcsConventions(alpha_link="bearing"))
    assert result.joint("A").load.load == 0.0  # A's bearing is in the crank
    assert result.joint("B").load.alpha_link == "coupler"
    result = ecs_analysis(paper_fourbar, EcsConventions(alpha_link="pin"))
    assert result.joint("A").load.alpha_link == "coupler"


def test_reaction_load_is_the_largest_ideal_joint_force(paper_fourbar: Mechanism) -> None:
    table = nominal_analysis(paper_fourbar).table
    result = ecs_analysis(paper_fourbar, EcsConventions(load="reaction"))
    for joint in ("O2", "A", "B", "O4"):
        assert result.joint(joint).load.load == pytest.approx(table[f"F_{joint}"].max(), rel=SAME)
    assert result.overall_joint == "O2"


def test_paper_fourbar_golden_values(paper_ecs: EcsResult) -> None:
    """The 200 RPM values quoted in docs/ecs.md (keep both in step; rel 1e-4 = their
    4-5 printed figures). History: first computed with jointplay.contact.ecs, 2024."""
    sph, cyl = paper_ecs.estimate("spherical"), paper_ecs.estimate("cylindrical")
    assert sph.contact_size * 1e6 == pytest.approx(68.83, rel=1e-4)
    assert sph.stiffness * 1e-3 == pytest.approx(7778.0, rel=1e-4)
    assert sph.penetration * 1e3 == pytest.approx(3.9629e-6, rel=1e-4)
    assert cyl.contact_size * 1e6 == pytest.approx(7.4403, rel=1e-4)
    assert cyl.log_term == pytest.approx(17.184, rel=1e-4)
    assert cyl.stiffness * 1e-3 == pytest.approx(233811.5, rel=1e-4)
    assert cyl.penetration * 1e3 == pytest.approx(1.8735e-7, rel=1e-4)
    assert cyl.length == 0.010  # the links' 10 mm thickness


def test_pin_length_convention(paper_fourbar: Mechanism) -> None:
    """l = 20 mm pins (joint A) instead of the 10 mm links: K +84 % (docs/ecs.md)."""
    result = ecs_analysis(paper_fourbar, EcsConventions(contact_length="pin-length"))
    cyl = result.estimate("cylindrical")
    assert cyl.length == 0.020
    assert cyl.stiffness * 1e-3 / 242348.0 == pytest.approx(1.845, rel=1e-3)


def test_literal_eq11_with_long_pins_is_flagged(paper_fourbar: Mechanism) -> None:
    """ln(4d/l) summed minus 1 is negative for l > 4 sqrt(d1 d2 / e) ≈ 24 mm."""
    conventions = EcsConventions(contact_length=0.030, eq11_log_argument="length")
    cyl = ecs_analysis(paper_fourbar, conventions).estimate("cylindrical")
    assert cyl.penetration < 0 and cyl.status == "invalid"
    with pytest.raises(ConfigError, match="unusable"):
        ecs_parameters(paper_fourbar, "cylindrical", conventions=conventions)


def test_missing_fit_data_is_a_config_error(paper_fourbar: Mechanism) -> None:
    no_clearance = paper_fourbar.with_joint_fits(
        {name: JointFit(diameter=0.01, pin_mass=0.02) for name in ("O2", "A", "B", "O4")}
    )
    with pytest.raises(ConfigError, match="clearance"):
        ecs_analysis(no_clearance)
    assert ecs_analysis(no_clearance, EcsConventions(radius="pin")).estimate("spherical").ok
    no_mass = paper_fourbar.with_joint_fits(
        {name: JointFit(diameter=0.01, clearance=2.1e-5) for name in ("O2", "A", "B", "O4")}
    )
    with pytest.raises(ConfigError, match="pin_mass"):
        ecs_analysis(no_mass)
    assert ecs_analysis(no_mass, EcsConventions(load="reaction")).estimate("spherical").ok


# --- damping ----------------------------------------------------------------------------------


@pytest.mark.parametrize("ratio", [0.0, 0.01, 0.05])
def test_damping_ratio_is_honoured(paper_fourbar: Mechanism, ratio: float) -> None:
    """D = ρ K for every joint and contact; ρ in s, so it holds in SI and in N–mm alike."""
    result = ecs_analysis(paper_fourbar, EcsConventions(damping_ratio=ratio))
    for entry in result.joints:
        for contact in CONTACT_TYPES:
            est = entry.estimate(contact)
            assert est.damping == pytest.approx(ratio * est.stiffness, rel=SAME, abs=0.0)
            paper_units = est.as_dict()["paper_units"]
            assert paper_units["damping_N_s_per_mm"] == pytest.approx(
                ratio * paper_units["stiffness_N_per_mm"], rel=SAME, abs=0.0
            )
    params = ecs_parameters(paper_fourbar, "spherical", conventions=result.conventions)
    assert params.c_max == pytest.approx(ratio * params.ecs_stiffness, rel=SAME, abs=0.0)


def test_published_damping_is_one_hundredth_of_stiffness() -> None:
    """Tables 4 and 5: D/K = 0.01 s to the 4 figures printed (2423/242348 = 0.009998)."""
    for published in PAPER_PUBLISHED.values():
        assert published.damping_ratio == pytest.approx(0.01, rel=5e-4)


# --- the paper's published values as a parameter source ---------------------------------------


def test_published_values_are_reachable(paper_fourbar: Mechanism) -> None:
    cyl = ecs_parameters(paper_fourbar, "cylindrical", source="paper")
    assert cyl.ecs_stiffness == pytest.approx(242348e3)  # N/m from 242348 N/mm
    assert cyl.ecs_penetration == pytest.approx(2.69e-13)  # m from 2.69e-10 mm
    assert cyl.ecs_damping == pytest.approx(2423e3)  # N·s/m from 2423 N·s/mm
    sph = ecs_parameters(paper_fourbar, "spherical", source="paper")
    assert (sph.ecs_stiffness, sph.ecs_penetration, sph.ecs_damping) == pytest.approx(
        (2500e3, 3.67e-8, 25e3)
    )
    # IMPACT: c_max = D, d_max = δ; the paper's K number read as N/mm^1.5.
    assert (sph.c_max, sph.d_max, sph.exponent) == pytest.approx((25e3, 3.67e-8, 1.5))
    assert sph.as_dict()["impact"]["stiffness_N_per_mm^e"] == pytest.approx(2500.0)
    assert sph.stiffness == pytest.approx(2500.0 * 1000.0**1.5)  # N/m^1.5
    assert isinstance(sph.impact_law(), ImpactLaw)
    rm = sph.restitution_law(0.8)
    assert isinstance(rm, RestitutionLaw) and rm.penalty == pytest.approx(2500e3)
    assert "warning" not in sph.derivation


def test_published_values_at_another_speed_are_flagged(paper_fourbar: Mechanism) -> None:
    faster = paper_fourbar.with_driver(speed=300 * math.pi / 30)
    params = ecs_parameters(faster, "spherical", source="paper")
    assert "200" in params.derivation["warning"]


def test_ifm_stiffness_conventions(paper_fourbar: Mechanism, paper_ecs: EcsResult) -> None:
    sph = paper_ecs.estimate("spherical")
    linear = ecs_parameters(
        paper_fourbar, conventions=EcsConventions(ifm_stiffness="linear"), result=paper_ecs
    )
    assert (linear.stiffness, linear.exponent) == (sph.stiffness, 1.0)
    paper = ecs_parameters(paper_fourbar, result=paper_ecs)
    assert paper.stiffness == pytest.approx(sph.stiffness * 1000.0**0.5, rel=SAME)
    # "matched" passes through (δ, F): for spherical contact that is Hertz's (4/3) E* √R.
    matched = ecs_parameters(
        paper_fourbar, conventions=EcsConventions(ifm_stiffness="matched"), result=paper_ecs
    )
    hertz = HertzStiffness.from_materials(
        bearing_radius=5.021e-3, pin_radius=5e-3, length=0.01, bearing=STEEL, pin=STEEL
    )
    assert matched.stiffness == pytest.approx(hertz.stiffness, rel=1e-9)
    with pytest.raises(ConfigError, match="matched"):
        ecs_parameters(
            paper_fourbar, source="paper", conventions=EcsConventions(ifm_stiffness="matched")
        )


def test_unknown_contact_and_source(paper_fourbar: Mechanism) -> None:
    with pytest.raises(ConfigError, match="contact type"):
        ecs_parameters(paper_fourbar, "elliptical")
    with pytest.raises(ConfigError, match="source"):
        ecs_parameters(paper_fourbar, "spherical", "handbook")


def test_table5_needs_three_times_our_load(paper_ecs: EcsResult) -> None:
    """(4/3) K δ = 0.1223 N bounds Table 5's load from below, whatever E*, R, a₀ (docs/ecs.md)."""
    table5 = PAPER_PUBLISHED["spherical"]
    bound = spherical_load_lower_bound(table5.stiffness, table5.penetration)
    assert bound == pytest.approx(4 / 3 * 2500e3 * 3.67e-8, rel=SAME)  # 0.12233 N
    assert bound / paper_ecs.estimate("spherical").load == pytest.approx(2.977, rel=1e-3)
    # The bound is reached with a₀ = 0 and not exceeded with a₀ > 0.
    modulus = modulus_by_convention(STEEL, STEEL)
    for a0 in (0.0, 1e-5):
        _, k, d = spherical_contact(0.3, 0.01, modulus, a0)
        assert spherical_load_lower_bound(k, d) <= 0.3 * (1 + SAME)


# --- crank-speed sweep and hysteresis ---------------------------------------------------------


def test_sweep_k_and_delta_increase_with_speed(paper_fourbar: Mechanism) -> None:
    """The paper: "equivalent contact stiffness and deformation ... increased with crank speed"."""
    sweep = ecs_sweep(paper_fourbar, [50, 100, 200, 350, 500])
    table = sweep.table
    for contact in CONTACT_TYPES:
        for column in (f"K_{contact}_N_per_m", f"delta_{contact}_m", f"D_{contact}_N_s_per_m"):
            assert np.all(np.diff(table[column]) > 0), column
        assert np.all(np.diff(table[f"chi_ecs_{contact}"]) < 0)
    # Constant crank speed: α ∝ ω², so the eq. 13 load ∝ ω² and the spherical K ∝ F^(1/3).
    assert table["load_N"].iloc[-1] / table["load_N"].iloc[0] == pytest.approx(100.0, rel=1e-9)
    k = table["K_spherical_N_per_m"]
    assert k.iloc[-1] / k.iloc[0] == pytest.approx(100.0 ** (1 / 3), rel=1e-9)
    paper_units = sweep.paper_units_table()
    assert paper_units["K_spherical_N_per_mm"].iloc[2] == pytest.approx(7778.0, rel=1e-4)


def test_hysteresis_comparison_definitions(paper_fourbar: Mechanism) -> None:
    sweep = ecs_sweep(paper_fourbar, [200], restitution=0.8)
    row = sweep.table.iloc[0]
    result = sweep.results[0]
    est = result.estimate("spherical")
    v0 = impact_velocity_estimate(411.0 * 0.005, 2.1e-5)
    assert row["impact_velocity_m_s"] == pytest.approx(v0, rel=1e-4)
    assert row["chi_ecs_spherical"] == pytest.approx(0.01 * v0 / est.penetration, rel=1e-4)
    assert row["chi_ecs_spherical"] == pytest.approx(
        ecs_hysteresis_factor(0.01, row["impact_velocity_m_s"], est.penetration), rel=SAME
    )
    factors = comparison_factors(0.8)
    assert set(factors) == set(COMPARISON_MODELS)
    assert factors == pytest.approx(
        {"lankarani-nikravesh": 0.27, "hunt-crossley": 0.3, "flores": 0.4, "hu-guo": 0.375}
    )
    for name, chi in factors.items():
        assert row[f"c_eq_{name}_spherical_N_s_per_m"] == pytest.approx(
            chi * est.stiffness * est.penetration / row["impact_velocity_m_s"], rel=SAME
        )
    assert 0.0 < row["e_eff_ecs_spherical"] < 1e-4  # the ECS damping is essentially plastic


def test_given_impact_velocity(paper_fourbar: Mechanism) -> None:
    result = ecs_analysis(paper_fourbar, EcsConventions(impact_velocity=0.1))
    assert result.impact_velocity == 0.1 and result.impact_velocity_source == "given"


def test_sweep_rejects_bad_speeds(paper_fourbar: Mechanism) -> None:
    with pytest.raises(ConfigError, match="crank speed"):
        ecs_sweep(paper_fourbar, [100, -5])
    with pytest.raises(ConfigError, match="at least one"):
        ecs_sweep(paper_fourbar, [])


def test_result_record_is_json_ready(paper_ecs: EcsResult) -> None:
    import json

    record = paper_ecs.as_dict()
    text = json.dumps(record)  # NaN allowed by json; the CLI turns them into null
    assert "conformal" in text
    assert record["overall"]["cylindrical"]["paper_units"]["stiffness_N_per_mm"] == pytest.approx(
        233811.5, rel=1e-4
    )
    assert dataclasses.is_dataclass(paper_ecs)
