"""Equivalent Contact Stiffness (ECS): the paper's eqs. 9–13 and the conventions it leaves open.

Akhadkar, Deoghare & Vaidya estimate the contact parameters of a clearance revolute joint from
a load and Hertz theory instead of tuning them: the load of eq. 13 (``max |α r m|`` over the
nominal cycle), then spherical (eqs. 9–10) or cylindrical (eqs. 11–12) contact stiffness K and
penetration δ, and damping ``D = 0.01 K`` (the ratio in s). This module holds those formulas
as pure functions of numbers and small frozen dataclasses: the conventions the paper leaves
open (:class:`EcsConventions`), one joint's load (:class:`JointLoad`) and estimates
(:func:`estimate_joint`), and the hysteresis comparison (:func:`ecs_hysteresis_factor`,
:func:`comparison_factors`). The Hertz formulas underneath are those of
:mod:`jointplay.contact.hertz`.

The analysis of a whole mechanism (the loads from its nominal cycle, the crank-speed sweep,
the simulator parameters) is :mod:`jointplay.study.ecs`; the paper's published values
(Tables 4 and 5) are :mod:`jointplay.study.published`. Everything is SI (N, m, Pa, s); the
paper's units (N/mm, mm, N·s/mm) only appear in the ``as_dict`` records.

``docs/ecs.md`` explains each convention, the IMPACT unit leap, why Tables 4 and 5 cannot both
be reproduced, and the hysteresis factor; it quotes the values the tests keep.
"""

from __future__ import annotations

import math
from collections.abc import Mapping
from dataclasses import asdict, dataclass
from types import MappingProxyType
from typing import Any, Literal, cast

import numpy as np
import numpy.typing as npt

from jointplay.contact import hertz
from jointplay.contact.hertz import _check_positive
from jointplay.contact.laws import CONTACT_LAWS, FloatArray, HuntCrossleyTypeLaw
from jointplay.errors import ConfigError
from jointplay.model.mechanism import Material

ContactType = Literal["spherical", "cylindrical"]

#: The two contact types of the paper: eqs. 9–10 and eqs. 11–12.
CONTACT_TYPES: tuple[ContactType, ...] = ("spherical", "cylindrical")

#: Equivalent radius conventions of the pin/bearing pair (docs/ecs.md).
RADIUS_CONVENTIONS: Mapping[str, str] = MappingProxyType(
    {
        "conformal": "R = R_J R_B / (R_B - R_J) (pin inside a hole)",
        "pin": "R = R_J (pin against a flat)",
        "sum": "1/R = 1/R_J + 1/R_B (two convex bodies)",
    }
)
#: Effective modulus conventions.
MODULUS_CONVENTIONS: Mapping[str, str] = MappingProxyType(
    {
        "johnson": "1/E* = (1 - nu1^2)/E1 + (1 - nu2^2)/E2 (Johnson 1985 ch. 4)",
        "rigid-bearing": "E* = E_pin / (1 - nu_pin^2) (elastic pin, rigid bearing)",
        "no-poisson": "1/E* = 1/E1 + 1/E2",
    }
)
#: Contact length conventions of eqs. 11–12 (or a length in m).
LENGTH_CONVENTIONS: Mapping[str, str] = MappingProxyType(
    {
        "link-thickness": "l = the thinner moving link's thickness (the bore the pin bears on)",
        "pin-length": "l = JointFit.pin_length",
    }
)
#: The argument of the logarithm in eq. 11.
EQ11_LOG_ARGUMENTS: Mapping[str, str] = MappingProxyType(
    {
        "half-width": "ln(4 d_i / b), as in eq. 12 (eq. 12 is then dF/dδ of eq. 11)",
        "length": "ln(4 d_i / l), eq. 11 as printed",
    }
)
#: Whose angular acceleration enters eq. 13.
ALPHA_LINKS: Mapping[str, str] = MappingProxyType(
    {
        "max": "the larger |alpha| of the joint's two links",
        "pin": "the link carrying the pin (link_b)",
        "bearing": "the link carrying the bearing (link_a)",
    }
)
#: Contact load sources.
LOAD_SOURCES: Mapping[str, str] = MappingProxyType(
    {
        "eq13": "max |alpha r m| of the nominal cycle (paper eq. 13)",
        "reaction": "max ideal-joint reaction |F| of the nominal cycle (inverse dynamics)",
    }
)
#: How the linear ECS K becomes the IMPACT stiffness.
IFM_STIFFNESS_CONVENTIONS: Mapping[str, str] = MappingProxyType(
    {
        "paper": "k = K's number in N/mm read as N/mm^e (the paper's unit leap)",
        "linear": "k = K in N/m, exponent 1",
        "matched": "k = F / delta^e (passes through the ECS design point)",
    }
)
#: The Hunt–Crossley-type models the paper's Fig. 6 compares with (registry names).
COMPARISON_MODELS: tuple[str, ...] = ("lankarani-nikravesh", "hunt-crossley", "flores", "hu-guo")

#: The paper's length unit in m: 1 N/mm = 1/MM N/m, 1 mm = MM m, 1 N·s/mm = 1/MM N·s/m.
MM = 1e-3


# --- the formulas (pure functions, SI) --------------------------------------------------------


def _check_choice(owner: str, name: str, value: str, choices: Mapping[str, str]) -> str:
    if value not in choices:
        raise ConfigError(f"{owner}.{name} = {value!r} is invalid: use one of {', '.join(choices)}")
    return value


def modulus_by_convention(bearing: Material, pin: Material, convention: str = "johnson") -> float:
    """Effective (combined) Young's modulus E* of the bearing and the pin, Pa.

    Args:
        bearing: material of the bearing (hole).
        pin: material of the pin.
        convention: ``"johnson"`` ``1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂`` (Johnson 1985,
            ch. 4), ``"rigid-bearing"`` ``E* = E_pin/(1 − ν_pin²)`` or ``"no-poisson"``
            ``1/E* = 1/E₁ + 1/E₂``.

    Raises:
        ConfigError: unknown convention.
    """
    _check_choice("modulus_by_convention", "convention", convention, MODULUS_CONVENTIONS)
    if convention == "johnson":
        return hertz.effective_modulus(
            bearing.youngs_modulus, bearing.poisson_ratio, pin.youngs_modulus, pin.poisson_ratio
        )
    if convention == "rigid-bearing":
        return pin.youngs_modulus / (1.0 - pin.poisson_ratio**2)
    return 1.0 / (1.0 / bearing.youngs_modulus + 1.0 / pin.youngs_modulus)


def equivalent_radius(
    pin_radius: float, bearing_radius: float, convention: str = "conformal"
) -> float:
    """Equivalent radius of curvature R of the pin/bearing pair, m.

    Args:
        pin_radius: R_J, m.
        bearing_radius: R_B, m (the hole; ≥ R_J).
        convention: ``"conformal"`` ``R = R_J R_B/(R_B − R_J)`` (pin inside a hole; needs
            R_B > R_J), ``"pin"`` ``R = R_J`` or ``"sum"`` ``1/R = 1/R_J + 1/R_B`` (two convex
            bodies: use it for the textbook sphere–sphere case).

    Raises:
        ConfigError: unknown convention, radii not positive, or a conformal radius without
            clearance.
    """
    _check_choice("equivalent_radius", "convention", convention, RADIUS_CONVENTIONS)
    r_j = _check_positive("equivalent_radius: pin_radius", pin_radius, "m")
    r_b = _check_positive("equivalent_radius: bearing_radius", bearing_radius, "m")
    if convention == "pin":
        return r_j
    if convention == "sum":
        return hertz.convex_radius(r_j, r_b)
    if not r_b > r_j:
        raise ConfigError(
            f"equivalent_radius: the conformal radius needs a bearing larger than the pin, got "
            f"R_B = {r_b!r} m, R_J = {r_j!r} m; give the joint a clearance or use radius='pin'"
        )
    return hertz.conformal_radius(r_j, r_b)


def eq13_load(alpha: npt.ArrayLike, pin_radius: float, pin_mass: float) -> FloatArray:
    """The tangential force of paper eq. 13 at each instant, ``|α| r m``, N.

    The paper's load is the largest value over one cycle (take ``.max()``).

    Args:
        alpha: angular acceleration of the link, rad/s².
        pin_radius: r, m.
        pin_mass: m, kg.
    """
    return np.abs(np.asarray(alpha, dtype=np.float64)) * pin_radius * pin_mass


def spherical_contact(
    load: float, radius: float, modulus: float, initial_contact_radius: float = 0.0
) -> tuple[float, float, float]:
    """Hertz point contact of the ECS method: contact radius, K (eq. 9) and δ (eq. 10).

    ``a = (3 F R/(4 E*))^(1/3)`` (Johnson 1985 ch. 4), ``K = a E*`` (eq. 9),
    ``δ = (a²/R) [1 − (2/3)(a₀/a)^(3/2)]`` (eq. 10; a₀ = 0 gives Hertz's ``a²/R``).

    Args:
        load: normal load F ≥ 0, N.
        radius: equivalent radius R > 0, m.
        modulus: effective modulus E* > 0, Pa.
        initial_contact_radius: a₀ ≥ 0, m.

    Returns:
        ``(a in m, K in N/m, δ in m)``; all 0 for F = 0. δ is negative when a₀ exceeds
        ``(3/2)^(2/3) a`` (eq. 10 then has no physical meaning; :class:`EcsEstimate` flags it).
    """
    load = _check_positive("spherical_contact: load", load, "N", allow_zero=True)
    radius = _check_positive("spherical_contact: radius", radius, "m")
    modulus = _check_positive("spherical_contact: modulus", modulus, "Pa")
    a0 = _check_positive(
        "spherical_contact: initial_contact_radius", initial_contact_radius, "m", allow_zero=True
    )
    if load == 0.0:
        return 0.0, 0.0, 0.0
    a = hertz.point_contact_radius(load, radius, modulus)
    delta = hertz.point_contact_penetration(a, radius) * (1.0 - 2.0 / 3.0 * (a0 / a) ** 1.5)
    return a, a * modulus, delta


def cylindrical_contact(
    load: float,
    length: float,
    radius: float,
    modulus: float,
    diameters: tuple[float, float],
    log_argument: str = "half-width",
) -> tuple[float, float, float, float]:
    """Cylindrical contact of the ECS method: half-width, log term, K (eq. 12) and δ (eq. 11).

    With ``P = F/l`` and ``b = √(4 P R/(π E*))``, ``L = Σᵢ ln(4dᵢ/b)``:
    ``K = π l E*/(L − 2)`` (eq. 12) and ``δ = P/(π E*) (L' − 1)`` (eq. 11) with ``L' = L``
    (``log_argument="half-width"``) or ``L' = Σᵢ ln(4dᵢ/l)`` (``"length"``, eq. 11 as printed).

    Args:
        load: normal load F ≥ 0, N.
        length: contact length l > 0, m.
        radius: equivalent radius R > 0, m (for the half-width b).
        modulus: effective modulus E* > 0, Pa.
        diameters: the two diameters ``(d₁, d₂)`` of eqs. 11–12, m.
        log_argument: ``"half-width"`` or ``"length"`` (see above).

    Returns:
        ``(b in m, L, K in N/m, δ in m)``; ``(0, inf, 0, 0)`` for F = 0 (K → 0 as b → 0).
        K is negative if L ≤ 2 and δ may be negative with ``"length"``; :class:`EcsEstimate`
        flags both.
    """
    _check_choice("cylindrical_contact", "log_argument", log_argument, EQ11_LOG_ARGUMENTS)
    load = _check_positive("cylindrical_contact: load", load, "N", allow_zero=True)
    length = _check_positive("cylindrical_contact: length", length, "m")
    d1 = _check_positive("cylindrical_contact: diameters[0]", diameters[0], "m")
    d2 = _check_positive("cylindrical_contact: diameters[1]", diameters[1], "m")
    if load == 0.0:
        _check_positive("cylindrical_contact: radius", radius, "m")
        _check_positive("cylindrical_contact: modulus", modulus, "Pa")
        return 0.0, math.inf, 0.0, 0.0
    line_load = load / length
    b = hertz.line_contact_half_width(line_load, radius, modulus)
    log_term = hertz.line_contact_log_term((d1, d2), b)
    stiffness = hertz.line_contact_stiffness(length, modulus, log_term)
    eq11_log = (
        log_term if log_argument == "half-width" else hertz.line_contact_log_term((d1, d2), length)
    )
    delta = hertz.line_contact_approach(line_load, modulus, eq11_log)
    return b, log_term, stiffness, delta


def spherical_load_lower_bound(stiffness: float, penetration: float) -> float:
    """Smallest load that gives a spherical-contact pair (K, δ) under eqs. 9–10, N.

    ``F = (4/3) E* a³/R ≥ (4/3) K δ`` for every E*, R and a₀ ≥ 0 (equality at a₀ = 0), since
    ``K = a E*`` and ``δ ≤ a²/R``. Units must be consistent (N/m and m, or N/mm and mm).
    """
    return 4.0 / 3.0 * stiffness * penetration


def impact_velocity_estimate(tangential_acceleration: float, clearance: float) -> float:
    """Impact speed of a pin crossing its bearing's diametral clearance from rest, m/s.

    ``v0 = √(2 a_t · 2c)``: the pin starts at rest against one side and is accelerated by
    ``a_t`` (eq. 13's ``|α| r``) across 2c. An order-of-magnitude estimate for the hysteresis
    comparison (docs/ecs.md).

    Args:
        tangential_acceleration: a_t ≥ 0, m/s².
        clearance: radial clearance c ≥ 0, m.
    """
    a_t = _check_positive(
        "impact_velocity_estimate: tangential_acceleration",
        tangential_acceleration,
        "m/s^2",
        allow_zero=True,
    )
    c = _check_positive("impact_velocity_estimate: clearance", clearance, "m", allow_zero=True)
    return math.sqrt(4.0 * a_t * c)


def ecs_hysteresis_factor(
    damping_ratio: float, impact_velocity: float, penetration: float
) -> float:
    """The ECS damping read as a Hunt–Crossley factor: ``χ_ECS = (D/K) v0/δ`` (dimensionless).

    Equates ``D = ρ K`` with the Hunt–Crossley damping coefficient ``χ K δ^n/v0`` at the ECS
    design point with n = 1 (docs/ecs.md). ``nan`` when δ = 0.

    Args:
        damping_ratio: ρ = D/K, s.
        impact_velocity: v0, m/s.
        penetration: the ECS δ, m.
    """
    if penetration <= 0.0:
        return math.nan
    return damping_ratio * impact_velocity / penetration


# --- conventions, one joint's load and its estimates ------------------------------------------------------------------


@dataclass(frozen=True)
class EcsConventions:
    """Every choice the paper leaves open, with its default (docs/ecs.md explains each).

    Attributes:
        radius: equivalent radius of the pin/bearing pair: ``"conformal"``, ``"pin"``,
            ``"sum"`` (:data:`RADIUS_CONVENTIONS`).
        modulus: E* convention: ``"johnson"``, ``"rigid-bearing"``, ``"no-poisson"``
            (:data:`MODULUS_CONVENTIONS`).
        initial_contact_radius: a₀ of eq. 10, m (≥ 0; 0 = Hertz).
        contact_length: l of eqs. 11–12: ``"link-thickness"``, ``"pin-length"`` or a length
            in m (> 0).
        eq11_log_argument: ``"half-width"`` (b, consistent with eq. 12) or ``"length"`` (l, as
            printed).
        alpha_link: whose α enters eq. 13: ``"max"``, ``"pin"``, ``"bearing"``.
        load: ``"eq13"`` (the paper) or ``"reaction"`` (largest ideal-joint reaction).
        damping_ratio: D/K, s (≥ 0; the paper's 0.01).
        ifm_stiffness: ECS K → IMPACT stiffness: ``"paper"``, ``"linear"``, ``"matched"``.
        ifm_exponent: IMPACT force exponent e (> 0) for ``"paper"`` and ``"matched"``.
        impact_velocity: v0 for the hysteresis comparison, m/s (> 0), or ``None`` to estimate
            it from the nominal kinematics (:func:`impact_velocity_estimate`).

    Raises:
        ConfigError: (at construction) an unknown name or a value out of range, naming the
            field and the accepted values.
    """

    radius: str = "conformal"
    modulus: str = "johnson"
    initial_contact_radius: float = 0.0
    contact_length: str | float = "link-thickness"
    eq11_log_argument: str = "half-width"
    alpha_link: str = "max"
    load: str = "eq13"
    damping_ratio: float = 0.01
    ifm_stiffness: str = "paper"
    ifm_exponent: float = 1.5
    impact_velocity: float | None = None

    def __post_init__(self) -> None:
        owner = "EcsConventions"
        _check_choice(owner, "radius", self.radius, RADIUS_CONVENTIONS)
        _check_choice(owner, "modulus", self.modulus, MODULUS_CONVENTIONS)
        _check_choice(owner, "eq11_log_argument", self.eq11_log_argument, EQ11_LOG_ARGUMENTS)
        _check_choice(owner, "alpha_link", self.alpha_link, ALPHA_LINKS)
        _check_choice(owner, "load", self.load, LOAD_SOURCES)
        _check_choice(owner, "ifm_stiffness", self.ifm_stiffness, IFM_STIFFNESS_CONVENTIONS)
        if isinstance(self.contact_length, str):
            _check_choice(owner, "contact_length", self.contact_length, LENGTH_CONVENTIONS)
        else:
            self._set_number("contact_length", self.contact_length, "m", "> 0", lambda v: v > 0)
        self._set_number(
            "initial_contact_radius", self.initial_contact_radius, "m", ">= 0", lambda v: v >= 0
        )
        self._set_number("damping_ratio", self.damping_ratio, "s", ">= 0", lambda v: v >= 0)
        self._set_number("ifm_exponent", self.ifm_exponent, "", "> 0", lambda v: v > 0)
        if self.impact_velocity is not None:
            self._set_number("impact_velocity", self.impact_velocity, "m/s", "> 0", lambda v: v > 0)

    def _set_number(self, name: str, value: Any, unit: str, bound: str, ok: Any) -> None:
        if isinstance(value, bool) or not isinstance(value, int | float):
            raise ConfigError(
                f"EcsConventions.{name}: expected a number in {unit or '1'}, got {value!r}"
            )
        if not (math.isfinite(value) and ok(value)):
            hint = " (the paper uses 0.01 s: D = 0.01 K)" if name == "damping_ratio" else ""
            raise ConfigError(
                f"EcsConventions.{name} = {value!r} is invalid: must be finite and {bound}"
                f"{' ' + unit if unit else ''}{hint}"
            )
        object.__setattr__(self, name, float(value))

    def as_dict(self) -> dict[str, Any]:
        """The conventions with a one-line description of each choice (JSON-ready)."""
        out = asdict(self)
        length = self.contact_length
        out["descriptions"] = {
            "radius": RADIUS_CONVENTIONS[self.radius],
            "modulus": MODULUS_CONVENTIONS[self.modulus],
            "contact_length": LENGTH_CONVENTIONS[length]
            if isinstance(length, str)
            else "fixed (m)",
            "eq11_log_argument": EQ11_LOG_ARGUMENTS[self.eq11_log_argument],
            "alpha_link": ALPHA_LINKS[self.alpha_link],
            "load": LOAD_SOURCES[self.load],
            "ifm_stiffness": IFM_STIFFNESS_CONVENTIONS[self.ifm_stiffness],
            "damping_ratio": "D/K in s",
            "impact_velocity": (
                "sqrt(4 a_t c) from the nominal kinematics"
                if self.impact_velocity is None
                else "given (m/s)"
            ),
        }
        return out


@dataclass(frozen=True)
class JointLoad:
    """The ECS contact load of one joint and the joint's geometry (SI).

    Attributes:
        joint: joint name.
        source: ``"eq13"`` or ``"reaction"``.
        load: F, N (the cycle maximum).
        crank_deg: crank angle of the maximum, deg (as the nominal table's ``crank_deg``).
        alpha_link: the link whose α gave eq. 13's maximum (``""`` if α = 0 throughout).
        alpha_max: max |α| of the link(s) selected by ``alpha_link``, rad/s².
        tangential_acceleration: ``alpha_max · r``, m/s² (eq. 13 divided by the pin mass).
        pin_radius: R_J = diameter/2, m.
        bearing_radius: R_B = R_J + clearance, m.
        clearance: radial clearance c, m (0 if the fit gives none).
        pin_mass: kg (``nan`` if not given).
        length: contact length l of eqs. 11–12, m.
        bearing_material: material of ``link_a``.
        pin_material: material of ``link_b``.
    """

    joint: str
    source: str
    load: float
    crank_deg: float
    alpha_link: str
    alpha_max: float
    tangential_acceleration: float
    pin_radius: float
    bearing_radius: float
    clearance: float
    pin_mass: float
    length: float
    bearing_material: Material
    pin_material: Material


@dataclass(frozen=True)
class EcsEstimate:
    """ECS result of one contact type at one joint, with its intermediate values (SI).

    Attributes:
        contact: ``"spherical"`` or ``"cylindrical"``.
        joint: joint name.
        load: F, N.
        modulus: E*, Pa.
        radius: equivalent radius R, m.
        contact_size: Hertz contact radius a (spherical) or half-width b (cylindrical), m.
        length: contact length l, m (cylindrical; ``nan`` for spherical).
        log_term: ``Σᵢ ln(4dᵢ/b)`` of eq. 12 (cylindrical; ``nan`` for spherical).
        stiffness: K, N/m (eq. 9 or 12).
        penetration: δ, m (eq. 10 or 11).
        damping: D = ρ K, N·s/m.
        status: ``"ok"``, ``"zero-load"`` (F = 0: Hertz gives no stiffness) or ``"invalid"``
            (K ≤ 0 or δ ≤ 0 with the chosen conventions).
        message: a readable account of ``status``.
    """

    contact: str
    joint: str
    load: float
    modulus: float
    radius: float
    contact_size: float
    length: float
    log_term: float
    stiffness: float
    penetration: float
    damping: float
    status: str
    message: str

    @property
    def ok(self) -> bool:
        """Whether K and δ are usable."""
        return self.status == "ok"

    def as_dict(self) -> dict[str, Any]:
        """SI values and the paper's units (N, mm, N/mm, N·s/mm, N/mm²), JSON-ready."""
        size = "contact_radius" if self.contact == "spherical" else "half_width"
        return {
            "contact": self.contact,
            "joint": self.joint,
            "status": self.status,
            "message": self.message,
            "si": {
                "load_N": self.load,
                "effective_modulus_Pa": self.modulus,
                "equivalent_radius_m": self.radius,
                f"{size}_m": self.contact_size,
                "length_m": self.length,
                "log_term": self.log_term,
                "stiffness_N_per_m": self.stiffness,
                "penetration_m": self.penetration,
                "damping_N_s_per_m": self.damping,
            },
            "paper_units": {
                "load_N": self.load,
                "effective_modulus_N_per_mm2": self.modulus * MM**2,
                "equivalent_radius_mm": self.radius / MM,
                f"{size}_mm": self.contact_size / MM,
                "length_mm": self.length / MM,
                "stiffness_N_per_mm": self.stiffness * MM,
                "penetration_mm": self.penetration / MM,
                "damping_N_s_per_mm": self.damping * MM,
            },
        }


@dataclass(frozen=True)
class EcsJoint:
    """The load of one joint and both ECS estimates for it."""

    load: JointLoad
    spherical: EcsEstimate
    cylindrical: EcsEstimate

    def estimate(self, contact: str) -> EcsEstimate:
        """The estimate for ``contact`` (``"spherical"`` or ``"cylindrical"``)."""
        return cast(EcsEstimate, getattr(self, contact_type(contact)))


def contact_type(contact: str) -> ContactType:
    """``contact`` checked against :data:`CONTACT_TYPES`.

    Raises:
        ConfigError: an unknown contact type.
    """
    if contact not in CONTACT_TYPES:
        raise ConfigError(
            f"unknown contact type {contact!r}; use one of {', '.join(CONTACT_TYPES)}"
        )
    return cast(ContactType, contact)


def _status(load: float, stiffness: float, penetration: float) -> tuple[str, str]:
    if load == 0.0:
        return "zero-load", "no load (the link does not accelerate): Hertz gives no stiffness"
    if not (stiffness > 0.0 and penetration > 0.0):
        return "invalid", (
            f"K = {stiffness:.4g} N/m, delta = {penetration:.4g} m: not positive with these "
            "conventions (see a0 / eq11_log_argument)"
        )
    return "ok", "ok"


def estimate_joint(load: JointLoad, conventions: EcsConventions) -> EcsJoint:
    """Both ECS estimates (eqs. 9–12) for one joint's load and geometry.

    Raises:
        ConfigError: the radius convention cannot be applied (e.g. conformal without
            clearance).
    """
    modulus = modulus_by_convention(load.bearing_material, load.pin_material, conventions.modulus)
    radius = equivalent_radius(load.pin_radius, load.bearing_radius, conventions.radius)
    a, k_sph, d_sph = spherical_contact(
        load.load, radius, modulus, conventions.initial_contact_radius
    )
    b, log_term, k_cyl, d_cyl = cylindrical_contact(
        load.load,
        load.length,
        radius,
        modulus,
        (2.0 * load.pin_radius, 2.0 * load.bearing_radius),
        conventions.eq11_log_argument,
    )
    ratio = conventions.damping_ratio
    estimates = []
    for contact, size, length, log, k, d in (
        ("spherical", a, math.nan, math.nan, k_sph, d_sph),
        ("cylindrical", b, load.length, log_term, k_cyl, d_cyl),
    ):
        status, message = _status(load.load, k, d)
        estimates.append(
            EcsEstimate(
                contact=contact,
                joint=load.joint,
                load=load.load,
                modulus=modulus,
                radius=radius,
                contact_size=size,
                length=length,
                log_term=log,
                stiffness=k,
                penetration=d,
                damping=ratio * k,
                status=status,
                message=message,
            )
        )
    return EcsJoint(load, estimates[0], estimates[1])


def comparison_factors(restitution: float) -> dict[str, float]:
    """χ(e) of the Hunt–Crossley-type models of the paper's Fig. 6 (docs/contact-laws.md §2.2).

    Args:
        restitution: coefficient of restitution e in (0, 1].

    Returns:
        ``{registry name: χ(e)}`` for :data:`COMPARISON_MODELS` (Hu–Guo's constant is
        unconfirmed; see :class:`~jointplay.contact.laws.HuGuoLaw`).
    """
    e = float(restitution)
    if not (math.isfinite(e) and 0.0 < e <= 1.0):
        raise ConfigError(f"restitution must lie in (0, 1], got {restitution!r}")
    out = {}
    for name in COMPARISON_MODELS:
        law = cast(type[HuntCrossleyTypeLaw], CONTACT_LAWS[name])
        out[name] = float(law.chi_of(e))
    return out
