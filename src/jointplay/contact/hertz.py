"""Hertz contact formulas: effective modulus, radii, point and line contact (SI).

The textbook elastic contact of two bodies (Johnson 1985 = K. L. Johnson, *Contact
Mechanics*, Cambridge University Press, ch. 4 and 5; chapters cited from memory, as in
docs/contact-laws.md §3). Every function takes and returns plain numbers in SI units (N, m, Pa);
the Equivalent Contact Stiffness method (:mod:`jointplay.contact.ecs`) and the pin-in-hole
stiffness laws (:mod:`jointplay.contact.stiffness`) both build on these, so each formula is
written once, here.

Notation: pin (journal) radius R_J, bearing (hole) radius R_B ≥ R_J, equivalent radius R,
effective modulus E*, normal load F, load per unit length P = F/l, contact radius a,
line-contact half-width b, approach (penetration) δ.
"""

from __future__ import annotations

import math

from jointplay.errors import ConfigError


def _check_positive(name: str, value: float, unit: str, *, allow_zero: bool = False) -> float:
    """``value`` as a float if finite and > 0 (≥ 0 with ``allow_zero``), else ConfigError.

    Args:
        name: what the value is, as the message shows it (``"function: argument"``).
        value: the number to check.
        unit: its unit, for the message.
        allow_zero: accept 0.
    """
    value = float(value)
    ok = value >= 0.0 if allow_zero else value > 0.0
    if not (math.isfinite(value) and ok):
        bound = ">= 0" if allow_zero else "> 0"
        raise ConfigError(f"{name} must be finite and {bound} {unit}, got {value!r}")
    return value


def effective_modulus(
    youngs_modulus_1: float, poisson_ratio_1: float, youngs_modulus_2: float, poisson_ratio_2: float
) -> float:
    """Effective (combined) modulus ``1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂``, Pa (Johnson 1985 ch. 4).

    Args:
        youngs_modulus_1: E₁ of the first body (the bearing, by this package's habit), Pa.
        poisson_ratio_1: ν₁ of the first body.
        youngs_modulus_2: E₂ of the second body (the pin), Pa.
        poisson_ratio_2: ν₂ of the second body.
    """
    return 1.0 / (
        (1.0 - poisson_ratio_1**2) / youngs_modulus_1
        + (1.0 - poisson_ratio_2**2) / youngs_modulus_2
    )


def conformal_radius(pin_radius: float, bearing_radius: float) -> float:
    """Equivalent radius of a pin inside a hole, ``R = R_J R_B/(R_B − R_J)``, m (Johnson 1985 ch. 4).

    The curvatures subtract (1/R = 1/R_J − 1/R_B): the contact is conformal, and R grows
    without bound as the clearance R_B − R_J goes to 0.

    Args:
        pin_radius: R_J, m.
        bearing_radius: R_B > R_J, m.
    """
    return pin_radius * bearing_radius / (bearing_radius - pin_radius)


def convex_radius(radius_1: float, radius_2: float) -> float:
    """Equivalent radius of two convex bodies, ``1/R = 1/R₁ + 1/R₂``, m (Johnson 1985 ch. 4).

    Args:
        radius_1: R₁, m.
        radius_2: R₂, m.
    """
    return radius_1 * radius_2 / (radius_1 + radius_2)


def point_contact_radius(load: float, radius: float, modulus: float) -> float:
    """Hertz contact radius of point (sphere) contact ``a = (3 F R/(4 E*))^(1/3)``, m.

    Johnson 1985 ch. 4.

    Args:
        load: normal load F ≥ 0, N.
        radius: equivalent radius R > 0, m.
        modulus: effective modulus E* > 0, Pa.
    """
    return (3.0 * load * radius / (4.0 * modulus)) ** (1.0 / 3.0)


def point_contact_penetration(contact_radius: float, radius: float) -> float:
    """Hertz approach of point contact ``δ = a²/R``, m (Johnson 1985 ch. 4).

    Args:
        contact_radius: a, m.
        radius: equivalent radius R > 0, m.
    """
    return contact_radius * contact_radius / radius


def point_contact_stiffness(radius: float, modulus: float) -> float:
    """Hertz point-contact stiffness K of ``F = K δ^(3/2)``: ``K = (4/3) E* √R``, N/m^1.5.

    Johnson 1985 ch. 4 (``F = (4/3) E* √R δ^(3/2)``); docs/contact-laws.md §3.1.

    Args:
        radius: equivalent radius R > 0, m.
        modulus: effective modulus E* > 0, Pa.
    """
    return 4.0 / 3.0 * modulus * math.sqrt(radius)


def line_contact_half_width(line_load: float, radius: float, modulus: float) -> float:
    """Hertz line-contact half-width ``b = √(4 P R/(π E*))``, m (Johnson 1985 ch. 4).

    Args:
        line_load: load per unit length P = F/l ≥ 0, N/m.
        radius: equivalent radius R > 0, m.
        modulus: effective modulus E* > 0, Pa.

    Raises:
        ConfigError: an argument not finite or out of range.
    """
    line_load = _check_positive(
        "line_contact_half_width: line_load", line_load, "N/m", allow_zero=True
    )
    radius = _check_positive("line_contact_half_width: radius", radius, "m")
    modulus = _check_positive("line_contact_half_width: modulus", modulus, "Pa")
    return math.sqrt(4.0 * line_load * radius / (math.pi * modulus))


def line_contact_log_term(diameters: tuple[float, float], width: float) -> float:
    """The logarithm of the cylinders' approach, ``L = Σᵢ ln(4dᵢ/w)`` (dimensionless).

    Appears in the approach and the stiffness of line contact (Johnson 1985 ch. 5; the
    paper's eqs. 11–12 with w = b, or w = l as eq. 11 is printed).

    Args:
        diameters: the two diameters ``(d₁, d₂)``, m.
        width: w > 0, m: the half-width b (or a length of the same unit).
    """
    d1, d2 = diameters
    return math.log(4.0 * d1 / width) + math.log(4.0 * d2 / width)


def line_contact_approach(line_load: float, modulus: float, log_term: float) -> float:
    """Approach of two cylinders in line contact ``δ = P/(π E*) (L − 1)``, m.

    Johnson 1985 ch. 5; the paper's eq. 11.

    Args:
        line_load: load per unit length P ≥ 0, N/m.
        modulus: effective modulus E* > 0, Pa.
        log_term: L of :func:`line_contact_log_term`.
    """
    return line_load / (math.pi * modulus) * (log_term - 1.0)


def line_contact_stiffness(length: float, modulus: float, log_term: float) -> float:
    """Tangent stiffness of line contact ``K = π l E*/(L − 2)``, N/m (the paper's eq. 12).

    With ``L = Σᵢ ln(4dᵢ/b)`` and ``b ∝ √P`` it is ``dF/dδ`` of :func:`line_contact_approach`
    (``d/dP L = −1/P``). Negative for L ≤ 2.

    Args:
        length: contact length l > 0, m.
        modulus: effective modulus E* > 0, Pa.
        log_term: L with the half-width b, dimensionless.
    """
    return math.pi * length * modulus / (log_term - 2.0)
