"""Pin-in-hole stiffness laws: the numeric anchors of docs/contact-laws.md §3.7 and properties.

Anchor material: steel–steel, E = 207 GPa, ν = 0.3 ⇒ E* = 113.7 GPa. The "Ø10 H8/g7" rows are
the real Ø10 joint: pin radius R_j = 5 mm, bearing radius R_i = R_j + ΔR (R = R_i R_j / ΔR =
1.195 m for ΔR = 21 µm), as corrected in §3.7 (an earlier version computed them for a 10 mm
bore radius, a Ø20 joint). The Hertz anchors depend on the radius; Liu and Pereira only on ΔR.
"""

from __future__ import annotations

import math

import numpy as np
import pytest

from jointplay.contact import ecs, hertz
from jointplay.contact.stiffness import (
    STIFFNESS_LAWS,
    Esdu78035Stiffness,
    HertzStiffness,
    JohnsonStiffness,
    LiuStiffness,
    PereiraStiffness,
    PinInHoleStiffness,
    RadzimovskyStiffness,
    get_stiffness_law,
)
from jointplay.errors import ConfigError
from jointplay.model.mechanism import STEEL

E_STEEL = 207e9  # Pa
NU_STEEL = 0.3
LENGTH = 10e-3  # m
PIN = 5e-3  # m, pin radius of the Ø10 joint


def joint(name: str, clearance: float, pin_radius: float = PIN) -> PinInHoleStiffness:
    return get_stiffness_law(
        name,
        bearing_radius=pin_radius + clearance,
        pin_radius=pin_radius,
        length=LENGTH,
        bearing_youngs_modulus=E_STEEL,
        bearing_poisson_ratio=NU_STEEL,
        pin_youngs_modulus=E_STEEL,
        pin_poisson_ratio=NU_STEEL,
    )


def test_effective_modulus_of_steel_on_steel() -> None:
    assert joint("hertz", 21e-6).effective_modulus == pytest.approx(113.7e9, rel=5e-4)


@pytest.mark.parametrize(
    ("clearance", "pin_radius", "radius", "stiffness"),
    [
        (0.5e-3, 9.5e-3, 0.19, 6.61e10),  # Flores slider-crank: R_i = 10 mm, R_j = 9.5 mm
        (21e-6, PIN, 1.195, 1.66e11),  # Ø10 H8/g7 c_max
        (11.75e-6, PIN, 2.13, 2.22e11),  # Ø10 H8/g7 c_mean
        (2.5e-6, PIN, 10.0, 4.80e11),  # Ø10 H8/g7 c_min
    ],
)
def test_hertz_anchors(
    clearance: float, pin_radius: float, radius: float, stiffness: float
) -> None:
    """§3.7 table (corrected), three significant digits."""
    law = joint("hertz", clearance, pin_radius)
    assert isinstance(law, HertzStiffness)
    assert law.conformal_radius == pytest.approx(radius, rel=5e-3)
    assert law.stiffness == pytest.approx(stiffness, rel=5e-3)
    assert law.exponent == 1.5


@pytest.mark.parametrize(
    ("clearance_mm", "exponent", "stiffness_n_mm"),
    [(0.021, 1.301, 6.32e6), (0.01175, 1.347, 1.04e7), (0.1, 1.213, 2.20e6), (0.5, 1.163, 1.32e6)],
)
def test_pereira_anchors(clearance_mm: float, exponent: float, stiffness_n_mm: float) -> None:
    """§3.7: n to 3 decimals and K (N/mm^n) to 3 digits, L = 10 mm."""
    law = joint("pereira", clearance_mm * 1e-3)
    assert isinstance(law, PereiraStiffness)
    assert law.exponent == pytest.approx(exponent, abs=5e-4)
    assert law.stiffness_n_mm == pytest.approx(stiffness_n_mm, rel=5e-3)
    # SI at the boundary: K_SI δ_m^n = K_mm δ_mm^n.
    assert law.stiffness == pytest.approx(law.stiffness_n_mm * 1000.0**law.exponent, rel=1e-14)


def test_pereira_branches_meet() -> None:
    """The two Y branches meet at ΔR = 0.34954 mm (§3.4), so n is continuous there."""
    below = joint("pereira", 0.34954e-3 * (1 - 1e-9))
    above = joint("pereira", 0.34954e-3 * (1 + 1e-9))
    assert isinstance(below, PereiraStiffness)
    assert isinstance(above, PereiraStiffness)
    assert below.exponent == pytest.approx(above.exponent, abs=1e-5)


@pytest.mark.parametrize(
    ("name", "force_1um", "force_5um"),
    [("liu", 269, 2770), ("hertz", 166, 1854), ("pereira", 789, 6409)],
)
def test_force_anchors(name: str, force_1um: float, force_5um: float) -> None:
    """§3.7 (corrected): forces at δ = 1 µm and 5 µm, c = 21 µm, L = 10 mm, Ø10 joint."""
    forces = joint(name, 21e-6).elastic_force([1e-6, 5e-6])
    assert forces[0] == pytest.approx(force_1um, abs=0.5)
    assert forces[1] == pytest.approx(force_5um, abs=0.5 if force_5um < 3000 else 1.0)


@pytest.mark.parametrize("name", ["johnson", "radzimovsky", "esdu-78035"])
def test_implicit_laws_invert_their_published_form(name: str) -> None:
    """F(δ) solves δ(F) = δ to rounding, up to the law's maximum penetration."""
    law = joint(name, 21e-6)
    assert isinstance(law, JohnsonStiffness | RadzimovskyStiffness | Esdu78035Stiffness)
    delta = np.geomspace(1e-12, law.max_penetration, 50)
    force = law.elastic_force(delta)
    np.testing.assert_allclose(law.penetration(force), delta, rtol=1e-12)
    assert np.all(np.diff(force) > 0.0)


def test_johnson_by_hand() -> None:
    """δ = f/(π E*) [ln(4π E* ΔR / f) − 1] at F = 500 N."""
    law = joint("johnson", 21e-6)
    e_star = law.effective_modulus
    f = 500.0 / LENGTH
    delta = f / (math.pi * e_star) * (math.log(4 * math.pi * e_star * 21e-6 / f) - 1.0)
    assert float(law.elastic_force(delta)) == pytest.approx(500.0, rel=1e-12)


def test_radzimovsky_by_hand() -> None:
    """δ = f/(π E*) [2/3 + ln(4R_i/b) + ln(4R_j/b)], b = 1.6 sqrt(f R / E*), at F = 500 N."""
    law = joint("radzimovsky", 21e-6)
    e_star, r = law.effective_modulus, law.conformal_radius
    f = 500.0 / LENGTH
    b = 1.6 * math.sqrt(f * r / e_star)
    log_terms = math.log(4 * law.bearing_radius / b) + math.log(4 * law.pin_radius / b)
    delta = f / (math.pi * e_star) * (2.0 / 3.0 + log_terms)
    assert float(law.elastic_force(delta)) == pytest.approx(500.0, rel=1e-10)


def test_implicit_law_beyond_its_range() -> None:
    law = joint("johnson", 21e-6)
    assert law.max_penetration == pytest.approx(4 * 21e-6 * math.exp(-2.0), rel=1e-12)
    with pytest.raises(ConfigError, match="max_penetration"):
        law.elastic_force(1.01 * law.max_penetration)
    with pytest.raises(ConfigError, match="max_penetration"):
        law.power_law_fit(20e-6)


@pytest.mark.parametrize("name", sorted(STIFFNESS_LAWS))
def test_elastic_force_properties(name: str) -> None:
    law = joint(name, 21e-6)
    assert np.all(law.elastic_force([-1e-6, 0.0]) == 0.0)
    delta = np.geomspace(1e-10, 5e-6, 40)
    force = law.elastic_force(delta)
    assert np.all(force > 0.0)
    assert np.all(np.diff(force) > 0.0)


@pytest.mark.parametrize("name", sorted(STIFFNESS_LAWS))
def test_power_law_fit_reproduces_the_law(name: str) -> None:
    """The fitted k δ^n stays within 10 % of the law over (δ_max/100, δ_max), δ_max ≈ 0.1 ΔR.

    The logarithmic laws bend more as δ approaches their maximum penetration: for Johnson
    (limit 0.54 ΔR) the worst error grows to 14 % at δ_max = 5 µm = 0.24 ΔR.
    """
    law = joint(name, 21e-6)
    k, n = law.power_law_fit(2e-6)
    assert 0.9 < n < 1.6
    delta = np.geomspace(2e-8, 2e-6, 30)
    np.testing.assert_allclose(k * delta**n, law.elastic_force(delta), rtol=0.1)


@pytest.mark.parametrize("name", ["hertz", "pereira"])
def test_power_law_fit_is_exact_for_power_laws(name: str) -> None:
    law = joint(name, 21e-6)
    assert isinstance(law, HertzStiffness | PereiraStiffness)
    k, n = law.power_law_fit(5e-6)
    assert n == pytest.approx(law.exponent, rel=1e-10)
    assert k == pytest.approx(law.stiffness, rel=1e-8)


def test_liu_is_nearly_linear_far_beyond_the_clearance() -> None:
    """F ∝ δ^1.5 for δ ≪ ΔR and ∝ δ for δ ≫ ΔR."""
    law = joint("liu", 21e-6)
    _, small = law.power_law_fit(1e-9)
    _, large = law.power_law_fit(1e-2)
    assert small == pytest.approx(1.5, abs=1e-3)
    assert large == pytest.approx(1.0, abs=0.02)
    assert isinstance(law, LiuStiffness)


def test_from_materials() -> None:
    law = HertzStiffness.from_materials(
        bearing_radius=5.011e-3, pin_radius=4.990e-3, length=LENGTH, bearing=STEEL, pin=STEEL
    )
    assert law.effective_modulus == pytest.approx(
        STEEL.youngs_modulus / (2 * (1 - STEEL.poisson_ratio**2)), rel=1e-14
    )


def test_hertz_law_and_ecs_share_the_hertz_formulas() -> None:
    """E*, R and (4/3) E* √R come from jointplay.contact.hertz for both users: equal bitwise."""
    law = HertzStiffness.from_materials(
        bearing_radius=5.021e-3, pin_radius=5e-3, length=LENGTH, bearing=STEEL, pin=STEEL
    )
    modulus = ecs.modulus_by_convention(STEEL, STEEL, "johnson")
    radius = ecs.equivalent_radius(5e-3, 5.021e-3, "conformal")
    assert (law.effective_modulus, law.conformal_radius) == (modulus, radius)
    assert law.stiffness == hertz.point_contact_stiffness(radius, modulus)


def test_registry_and_validation() -> None:
    assert set(STIFFNESS_LAWS) == {
        "hertz",
        "johnson",
        "radzimovsky",
        "esdu-78035",
        "pereira",
        "liu",
    }
    with pytest.raises(ConfigError, match="known names: esdu-78035, hertz"):
        get_stiffness_law("winkler")
    with pytest.raises(ConfigError, match=r"HertzStiffness.bearing_radius"):
        joint("hertz", -1e-6)
    with pytest.raises(ConfigError, match="pin_poisson_ratio"):
        HertzStiffness(
            bearing_radius=5e-3,
            pin_radius=4.9e-3,
            length=LENGTH,
            bearing_youngs_modulus=E_STEEL,
            bearing_poisson_ratio=NU_STEEL,
            pin_youngs_modulus=E_STEEL,
            pin_poisson_ratio=0.5,
        )
    with pytest.raises(ConfigError, match="outside the fitted range"):
        joint("pereira", 2e-6)
    with pytest.raises(ConfigError, match="delta_max"):
        joint("liu", 21e-6).power_law_fit(0.0)
    aliased = get_stiffness_law(
        "liu", R_i=5e-3, R_j=4.99e-3, L=LENGTH, E_i=E_STEEL, nu_i=0.3, E_j=E_STEEL, nu_j=0.3
    )
    assert aliased.clearance == pytest.approx(10e-6, rel=1e-9)
