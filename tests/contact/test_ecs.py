"""The Equivalent Contact Stiffness formulas (paper eqs. 9–12): Hertz, conventions, units.

Hand-computed cases are written out step by step; their tolerance (rel 1e-5) is the rounding of
the written intermediate numbers. The ECS of a whole mechanism is tested in
tests/study/test_ecs.py.
"""

from __future__ import annotations

import math
from typing import Any

import pint
import pytest

from jointplay.contact.ecs import (
    CONTACT_TYPES,
    EcsConventions,
    cylindrical_contact,
    equivalent_radius,
    modulus_by_convention,
    spherical_contact,
)
from jointplay.contact.hertz import line_contact_half_width
from jointplay.errors import ConfigError
from jointplay.model.mechanism import STEEL, Material

#: Rounding of the hand-written intermediate numbers (6 significant figures).
HAND = 1e-5
#: Same quantity computed along two paths in double precision.
SAME = 1e-12

TEXTBOOK_STEEL = Material("steel-200", density=7800.0, youngs_modulus=200e9, poisson_ratio=0.3)


# --- Hertz formulas against hand computation --------------------------------------------------


def test_textbook_sphere_on_sphere() -> None:
    """The classic problem: a Ø50 mm steel ball pressed by 500 N against an identical ball.

    E = 200 GPa, ν = 0.3 (Johnson 1985 ch. 4):
      E* = E / (2 (1 − ν²)) = 200e9 / 1.82          = 1.098901e11 Pa
      R  = R1 R2 / (R1 + R2) = 0.025 / 2             = 0.0125 m
      a  = (3 F R / (4 E*))^(1/3) = (18.75 / 4.395604e11)^(1/3)
         = (4.265625e-11)^(1/3)                      = 3.494037e-4 m  (0.349 mm)
      δ  = a² / R = 1.220830e-7 / 0.0125             = 9.766638e-6 m
      K  = a E* (eq. 9)                              = 3.839602e7 N/m
      p0 = 3 F / (2 π a²)                            = 1.955493e9 Pa
    """
    modulus = modulus_by_convention(TEXTBOOK_STEEL, TEXTBOOK_STEEL, "johnson")
    radius = equivalent_radius(0.025, 0.025, "sum")
    a, stiffness, delta = spherical_contact(500.0, radius, modulus)
    assert modulus == pytest.approx(1.098901e11, rel=HAND)
    assert radius == pytest.approx(0.0125, rel=SAME)
    assert a == pytest.approx(3.494037e-4, rel=HAND)
    assert delta == pytest.approx(9.766638e-6, rel=HAND)
    assert stiffness == pytest.approx(3.839602e7, rel=HAND)
    assert 3 * 500.0 / (2 * math.pi * a * a) == pytest.approx(1.955493e9, rel=HAND)
    # The same ball on a flat (R = R_ball, the "pin" convention): a = 0.440 mm.
    a_flat, _, _ = spherical_contact(500.0, equivalent_radius(0.025, 0.025, "pin"), modulus)
    assert a_flat == pytest.approx(4.402211e-4, rel=HAND)


def test_internal_pin_in_hole() -> None:
    """Ø10 pin in a hole with 21 µm radial clearance, paper steel, F = 10 N.

    E* = 207e9 / (2 (1 − 0.29²)) = 207e9 / 1.8318  = 1.130036e11 Pa
    R  = R_J R_B / (R_B − R_J) = 5 · 5.021 / 0.021 mm = 1.195476 m
    a  = (3 · 10 · 1.195476 / (4 · 1.130036e11))^(1/3) = (7.934371e-11)^(1/3)
                                                   = 4.297046e-4 m
    δ  = a² / R = 1.846460e-7 / 1.195476          = 1.544539e-7 m
    K  = a E*                                      = 4.855816e7 N/m
    """
    modulus = modulus_by_convention(STEEL, STEEL)
    radius = equivalent_radius(5e-3, 5.021e-3)
    a, stiffness, delta = spherical_contact(10.0, radius, modulus)
    assert modulus == pytest.approx(1.130036e11, rel=HAND)
    assert radius == pytest.approx(1.195476, rel=HAND)
    assert a == pytest.approx(4.297046e-4, rel=HAND)
    assert delta == pytest.approx(1.544539e-7, rel=HAND)
    assert stiffness == pytest.approx(4.855816e7, rel=HAND)


def test_line_contact_half_width() -> None:
    """b = sqrt(4 P R / (π E*)) with P = 1000 N/m, R = 1.195476 m, E* = 1.130036e11 Pa:
    4 · 1000 · 1.195476 / (π · 1.130036e11) = 1.346972e-8 m², b = 1.160591e-4 m.
    Cross-check (Johnson 1985 ch. 4): the peak pressure 2P/(π b) equals sqrt(P E*/(π R)).
    """
    modulus = modulus_by_convention(STEEL, STEEL)
    radius = equivalent_radius(5e-3, 5.021e-3)
    b = line_contact_half_width(1000.0, radius, modulus)
    assert b == pytest.approx(1.160591e-4, rel=HAND)
    assert 2 * 1000.0 / (math.pi * b) == pytest.approx(
        math.sqrt(1000.0 * modulus / (math.pi * radius)), rel=SAME
    )


def test_modulus_and_radius_conventions() -> None:
    nu, e = STEEL.poisson_ratio, STEEL.youngs_modulus
    assert modulus_by_convention(STEEL, STEEL, "johnson") == pytest.approx(e / (2 * (1 - nu**2)))
    assert modulus_by_convention(STEEL, STEEL, "rigid-bearing") == pytest.approx(e / (1 - nu**2))
    assert modulus_by_convention(STEEL, STEEL, "no-poisson") == pytest.approx(e / 2)
    assert equivalent_radius(5e-3, 5.021e-3, "pin") == 5e-3
    assert equivalent_radius(5e-3, 5e-3, "sum") == pytest.approx(2.5e-3)
    with pytest.raises(ConfigError, match="conformal"):
        equivalent_radius(5e-3, 5e-3, "conformal")
    with pytest.raises(ConfigError, match="use one of conformal, pin, sum"):
        equivalent_radius(5e-3, 5.021e-3, "convex")


def test_eq9_is_half_the_hertz_tangent_stiffness() -> None:
    """K = a E* (eq. 9) = ½ dF/dδ of F = (4/3) E* √R δ^1.5 at the load's δ."""
    modulus, radius = modulus_by_convention(STEEL, STEEL), 1.2
    _, stiffness, delta = spherical_contact(5.0, radius, modulus)
    tangent = 2.0 * modulus * math.sqrt(radius) * math.sqrt(delta)
    assert stiffness == pytest.approx(tangent / 2.0, rel=SAME)
    assert 4 / 3 * modulus * math.sqrt(radius) * delta**1.5 == pytest.approx(5.0, rel=SAME)


def test_eq12_is_the_tangent_of_eq11_read_with_b() -> None:
    """K of eq. 12 equals dF/dδ of eq. 11 (central difference, relative step 1e-4: error ~1e-8)."""
    args = (0.01, 1.1955, modulus_by_convention(STEEL, STEEL), (0.01, 0.010042))
    _, _, stiffness, _ = cylindrical_contact(0.05, *args)
    h = 1e-4
    delta_hi = cylindrical_contact(0.05 * (1 + h), *args)[3]
    delta_lo = cylindrical_contact(0.05 * (1 - h), *args)[3]
    assert stiffness == pytest.approx(2 * 0.05 * h / (delta_hi - delta_lo), rel=1e-7)


def test_initial_contact_radius_lowers_the_penetration() -> None:
    """Eq. 10 with a₀ = a/2: δ = (a²/R)(1 − (2/3)(1/2)^1.5) = 0.764298 a²/R; K unchanged."""
    modulus = modulus_by_convention(STEEL, STEEL)
    a, stiffness, delta = spherical_contact(10.0, 1.2, modulus)
    a2, stiffness2, delta2 = spherical_contact(10.0, 1.2, modulus, a / 2)
    assert (a2, stiffness2) == (a, stiffness)
    assert delta2 / delta == pytest.approx(1 - 2 / 3 * 0.5**1.5, rel=SAME)
    assert delta2 / delta == pytest.approx(0.764298, rel=HAND)


def test_zero_load_gives_no_stiffness() -> None:
    assert spherical_contact(0.0, 1.0, 1e11) == (0.0, 0.0, 0.0)
    b, log_term, stiffness, delta = cylindrical_contact(0.0, 0.01, 1.0, 1e11, (0.01, 0.01))
    assert (b, stiffness, delta) == (0.0, 0.0, 0.0) and log_term == math.inf


# --- units ------------------------------------------------------------------------------------


def test_units_eq9_is_newton_per_metre() -> None:
    """a·E* is m · N/m² = N/m; a²/R is m; b is m; π l E* is N/m."""
    ureg: Any = pint.UnitRegistry()
    a = ureg.Quantity(1e-4, "m")
    modulus = ureg.Quantity(1e11, "Pa")
    assert (a * modulus).to("N/m").magnitude == pytest.approx(1e7)
    assert (a**2 / ureg.Quantity(1.0, "m")).to("m").magnitude == pytest.approx(1e-8)
    line_load = ureg.Quantity(1000.0, "N/m")
    b = (4 * line_load * ureg.Quantity(1.0, "m") / (math.pi * modulus)) ** 0.5
    assert b.to("m").magnitude == pytest.approx(line_contact_half_width(1000.0, 1.0, 1e11))
    assert (math.pi * ureg.Quantity(0.01, "m") * modulus).to("N/m").magnitude == pytest.approx(
        math.pi * 1e9
    )


@pytest.mark.parametrize("contact", CONTACT_TYPES)
def test_formulas_are_dimensionally_homogeneous(contact: str) -> None:
    """The same case in SI and in N–mm–MPa: K scales by 1e-3 (N/m → N/mm), δ and a by 1e3."""
    modulus = modulus_by_convention(STEEL, STEEL)
    si_radius, mm_radius = 1.195476, 1195.476
    if contact == "spherical":
        si = spherical_contact(0.05, si_radius, modulus)
        mm = spherical_contact(0.05, mm_radius, modulus * 1e-6)
        (a_si, k_si, d_si), (a_mm, k_mm, d_mm) = si, mm
    else:
        a_si, _, k_si, d_si = cylindrical_contact(0.05, 0.01, si_radius, modulus, (0.01, 0.010042))
        a_mm, _, k_mm, d_mm = cylindrical_contact(
            0.05, 10.0, mm_radius, modulus * 1e-6, (10.0, 10.042)
        )
    assert a_mm == pytest.approx(a_si * 1e3, rel=SAME)
    assert k_mm == pytest.approx(k_si * 1e-3, rel=SAME)
    assert d_mm == pytest.approx(d_si * 1e3, rel=SAME)


# --- conventions ----------------------------------------------------------------------------------


@pytest.mark.parametrize(
    ("field", "value", "match"),
    [
        ("radius", "convex", "EcsConventions.radius"),
        ("modulus", "steel", "EcsConventions.modulus"),
        ("load", "torque", "EcsConventions.load"),
        ("damping_ratio", -0.01, "EcsConventions.damping_ratio"),
        ("damping_ratio", math.nan, "EcsConventions.damping_ratio"),
        ("initial_contact_radius", -1e-6, "EcsConventions.initial_contact_radius"),
        ("contact_length", "bore", "EcsConventions.contact_length"),
        ("contact_length", 0.0, "EcsConventions.contact_length"),
        ("ifm_exponent", 0.0, "EcsConventions.ifm_exponent"),
    ],
)
def test_conventions_are_validated(field: str, value: object, match: str) -> None:
    with pytest.raises(ConfigError, match=match):
        EcsConventions(**{field: value})  # type: ignore[arg-type]
