"""Equivalent Contact Stiffness (ECS): contact parameters from Hertz theory (paper eqs. 9–13).

Akhadkar, Deoghare & Vaidya propose to estimate the contact parameters of a clearance revolute
joint, instead of tuning them, in three steps (paper, "ECS approach", a–c):

a) **Load** (eq. 13). Over one cycle of the *nominal* (ideal-joint) mechanism, the highest
   "tangential force" of each joint, ``F = max_t |α(t) r m|``, with α the angular acceleration
   of the link, r and m the radius and mass of the pin. It is taken as the normal contact load.
b) **Hertz** with that load. Spherical contact: ``K = a E*`` (eq. 9) and
   ``δ = (a²/R) [1 − (2/3)(a₀/a)^(3/2)]`` (eq. 10). Cylindrical contact, with the line load
   ``P = F/l``: ``δ = P/(π E*) {Σᵢ ln(4dᵢ/b) − 1}`` (eq. 11) and
   ``K = π l E* / {Σᵢ ln(4dᵢ/b) − 2}`` (eq. 12).
c) **Damping** ``D = 0.01 K``. The text says "0.01 percent", but Tables 4 and 5 give
   D/K = 0.01 exactly (2423/242348, 25/2500), in N·s/mm over N/mm, so the ratio is 0.01 *s*; it
   has the same value in SI (paper-notes.md, ECS paragraph).

Johnson 1985 = K. L. Johnson, *Contact Mechanics*, Cambridge University Press (ch. 4, Hertz
theory; chapter cited from memory, as in contact-models.md §3). Everything here is SI (N, m, Pa,
s). The paper quotes K in N/mm, δ in mm and D in N·s/mm;
:meth:`EcsEstimate.as_dict` gives both. The paper's published results are in
:data:`PAPER_PUBLISHED`, and :func:`ecs_parameters` hands the simulator either those or ours.

Conventions the paper leaves open (:class:`EcsConventions`; defaults first)
-------------------------------------------------------------------------------
* ``radius``, the equivalent radius R of the pin (R_J) and bearing (R_B) pair:
  ``"conformal"`` ``R = R_J R_B / (R_B − R_J)`` (a pin inside a hole, Johnson 1985 ch. 4; the
  choice of Lankarani/Flores and of :class:`~jointplay.contact.stiffness.HertzStiffness`),
  ``"pin"`` ``R = R_J`` (the pin against a flat), ``"sum"`` ``1/R = 1/R_J + 1/R_B`` (two convex
  bodies, the textbook sphere–sphere case). Geometry from the joint's
  :class:`~jointplay.model.mechanism.JointFit`: ``R_J = diameter/2``, ``R_B = R_J + clearance``.
* ``modulus``, E* of the two materials: ``"johnson"``
  ``1/E* = (1 − ν₁²)/E₁ + (1 − ν₂²)/E₂`` (Johnson 1985 ch. 4; 113.0 GPa for the paper's steel),
  ``"rigid-bearing"`` ``E* = E_pin/(1 − ν_pin²)`` (an elastic pin on a rigid bearing; 226 GPa),
  ``"no-poisson"`` ``1/E* = 1/E₁ + 1/E₂`` (103.5 GPa). Materials: the bearing is the joint's
  ``link_a`` (the ground takes the mechanism's material), the pin has the material of
  ``link_b``, which carries it.
* ``initial_contact_radius`` a₀ of eq. 10, m, default 0. Eq. 10 is the JKR approach
  ``δ = a²/R − (2/3) a^(1/2) a₀^(3/2) / R`` with a₀ the contact radius under zero load due to
  adhesion (Johnson, Kendall & Roberts 1971, Proc. R. Soc. A 324:301–313, citation recalled);
  a₀ = 0 gives Hertz ``δ = a²/R``. As in the paper, a stays Hertz's ``(3FR/(4E*))^(1/3)``.
* ``contact_length`` l of eqs. 11–12: ``"link-thickness"`` (the bore of the link the pin bears
  on; the thinner of the joint's two moving links, 10 mm for the paper) or ``"pin-length"``
  (``JointFit.pin_length``: 20 or 30 mm), or a length in m.
* ``eq11_log_argument``: eq. 11 prints ``ln(4dᵢ/l)``, eq. 12 ``ln(4dᵢ/b)``. We read eq. 11 with
  b (``"half-width"``): then eq. 12 is exactly its tangent stiffness ``dF/dδ`` [DERIVED: with
  ``b ∝ √P``, ``d/dP Σ ln(4dᵢ/b) = −1/P``], while the literal ``"length"`` reading turns δ
  negative as soon as ``l > 4 √(d₁d₂/e) ≈ 24 mm``, e.g. for the paper's 30 mm pins. The half-width
  is Hertz's line contact ``b = √(4 P R/(π E*))`` (Johnson 1985 ch. 4) with the same R;
  ``dᵢ`` are the diameters ``2R_J`` and ``2R_B`` ("d_i is the internal diameter").
* ``alpha_link``: whose α enters eq. 13 at a joint between two links: ``"max"`` (the larger
  |α| of the two, conservative), ``"pin"`` (``link_b``), ``"bearing"`` (``link_a``). The crank
  turns at constant speed (α₂ = 0), so the crank–ground joint O2 gets no eq. 13 load at all.
* ``load``: ``"eq13"`` (the paper) or ``"reaction"``: the largest ideal-joint reaction
  ``max_t |F_joint|`` from inverse dynamics (:mod:`jointplay.dynamics.inverse`). Eq. 13 is a
  pin's *own* inertia; the reaction is the force the joint actually transmits, 10³ times larger
  here (46 N at O2 against 0.041 N). Users who want the contact stiffness at the working load
  want ``"reaction"``.
* ``damping_ratio`` D/K, s, default 0.01.
* ``ifm_stiffness``, how the linear ECS K becomes the IMPACT (IFM) stiffness k of
  ``F = k δ^e + c(δ) δ̇`` (paper eqs. 1–3): ``"paper"`` (the paper's unit leap, below),
  ``"linear"`` (k = K in N/m, e = 1: a consistent linear spring) or ``"matched"``
  (``k = F/δ^e``: the IMPACT spring passes through the ECS design point (δ, F); for spherical
  contact with a₀ = 0 that is exactly Hertz's ``(4/3) E* √R``). ``ifm_exponent`` e, default 1.5.
* ``impact_velocity`` v0 for the hysteresis comparison, m/s, default estimated (below).

The IFM unit leap, stated honestly. Eqs. 9 and 12 give a *linear* stiffness (N/m: a·E* is
m·N/m²). The paper enters its number in N/mm into ADAMS IMPACT with a force exponent (Table 3
uses 1.5), where the stiffness is read in N/mm^1.5; the exponent of the ECS runs is not stated.
``ifm_stiffness="paper"`` reproduces that recipe: the number is kept in N/mm and read as
N/mm^e, i.e. ``k = K_[N/mm] · 1000^e`` N/m^e ``= K_SI · 1000^(e−1)`` (×31.6 for e = 1.5). The
result depends on the length unit the number was quoted in; it is a recipe, not physics.
δ becomes IMPACT's penetration depth d_max (full damping) and D its c_max (N·s/mm → ×1000
N·s/m). For the Restitution Method the ECS K is the penalty p, a linear stiffness, so there is
no leap: ``p = K`` in N/m (:class:`~jointplay.contact.laws.RestitutionLaw` with exponent 1).

Two more facts worth knowing. Eq. 9's ``K = a E*`` is half the Hertz tangent stiffness
``dF/dδ = 2 a E*`` and 3/4 of the secant ``F/δ = (4/3) a E*``. And because
``F = (4/3) E* a³/R ≥ (4/3) K δ`` for any E*, R and a₀ ≥ 0 (equality at a₀ = 0), a published
pair (K, δ) of spherical contact fixes a *lower bound of the load* that produced it,
independently of every convention (:func:`spherical_load_lower_bound`).

Do any conventions reproduce Tables 4 and 5? (paper-fourbar, 200 RPM)
------------------------------------------------------------------------
Nominal kinematics: ``max |α₃| = max |α₄| = 411.0 rad/s²`` (coupler and rocker, 1° grid),
α₂ = 0; pin r = 5 mm, m = 20 g, so eq. 13 gives ``F = 0.0411 N`` at A, B and O4, 0 at O2.
With the defaults (conformal R = 1.1955 m, Johnson E* = 113.0 GPa, a₀ = 0, l = 10 mm):

==================  ===============================  ==================================
quantity            spherical (Table 5)              cylindrical (Table 4)
==================  ===============================  ==================================
a or b              a = 68.8 µm                      b = 7.44 µm (Σ ln(4dᵢ/b) = 17.18)
K, N/mm             7 778 (paper 2 500: ×3.11)       233 812 (paper 242 348: −3.5 %)
δ, mm               3.96e-6 (paper 3.67e-5: ×0.108)  1.87e-7 (paper 2.69e-10: ×696)
D, N·s/mm           77.8 (paper 25)                  2 338 (paper 2 423)
==================  ===============================  ==================================

With the ``"reaction"`` load (46.0 N at O2) instead: K = 80 765 N/mm, δ = 4.27e-4 mm
(spherical); K = 434 907 N/mm, δ = 1.19e-4 mm (cylindrical).

* **Table 5 (spherical) is not reproduced by any conventions.** K = 2500 N/mm and
  δ = 3.67e-5 mm need a load of at least ``(4/3) K δ = 0.122 N`` whatever E*, R and a₀ ≥ 0
  (above), 2.98 times eq. 13's 0.0411 N. With a₀ = 0 the pair fixes ``a = K/E*`` and
  ``R = a²/δ``: R = 13.3 mm for Johnson's E*, 3.3 mm for E/(1 − ν²), 4.0 mm for E — none of
  them a radius of this joint (5, 5.021, 2.5 or 1195 mm). The nearest combinations we found
  mix two unnatural choices, e.g. E* = E/(1 − ν²), R = R_J and r = the pin *diameter* in eq. 13:
  K = 2506 N/mm but δ = 2.46e-5 mm (−33 %). We do not adopt them.
* **Table 4 (cylindrical): K is reproduced, δ is not (by 3 orders of magnitude).** K depends on
  the load only through a logarithm, so it is set by ``π l E*``: the natural set with the
  link thickness l = 10 mm gives −3.5 % (with the pin length l = 20 mm, +84 %). Eq. 11 then gives
  δ = 1.87e-7 mm, 700 times the published 2.69e-10 mm; for *any* E*, R, l the two eqs. give
  ``K δ = F (L − 1)/(L − 2) ≈ F``, so the published pair implies a load of only 6.5e-5 N.
  Read as **metres**, the published δ (2.69e-10 m = 2.69e-7 mm) lies within 45 % of ours and,
  with the published K, implies F = 0.061 N and R = 1.37 m (ours 0.041 N, 1.1955 m). A unit slip
  in Table 4's δ is the simplest explanation we see; it is a conjecture, not established.
* The two tables are not consistent with a single load under eqs. 9–12: Table 5 needs
  F ≥ 0.122 N, Table 4 (δ as printed) 6.5e-5 N, or 0.061 N with δ read in metres.

Hysteresis damping factor (the paper's Fig. 6)
---------------------------------------------
The paper compares a "hysteresis damping factor of the ECS model" with those of
Lankarani–Nikravesh, Hunt–Crossley, Flores and Hu–Guo over crank speed, but never defines it,
nor the impact velocity or restitution behind the others; **Fig. 6 cannot be reconstructed.**
What :func:`ecs_sweep` shows instead, defined here:

* The Hunt–Crossley family writes ``F = K δ^n (1 + χ δ̇/v0)``, a damping coefficient
  ``χ K δ^n / v0`` (contact-models.md §2.1). Linearising the ECS law at its design point
  (n = 1, the ECS K and δ) and equating that coefficient with ``D = ρ K`` gives the
  **ECS hysteresis factor** ``χ_ECS = ρ v0 / δ`` (dimensionless, unit-independent).
* v0 is estimated from the nominal kinematics as the speed of a pin that starts at rest on one
  side of its bearing and crosses the diametral clearance 2c under eq. 13's tangential
  acceleration ``a_t = max |α| r``: ``v0 = √(4 a_t c)`` (the largest a_t over the joints;
  0.0131 m/s at 200 RPM). It is an order-of-magnitude estimate; set
  ``EcsConventions.impact_velocity`` to use your own.
* Beside it: χ(e) of LN, HC, Flores and Hu–Guo at a restitution e (default 0.8, the paper's
  steel value), constant over speed, their equivalent damping coefficients
  ``χ(e) K δ / v0`` at the same design point, and the restitution the ECS damping would give in
  one impact, ``effective_restitution(χ_ECS)`` (contact-models.md §2.3).

Result, stated plainly (paper-fourbar, defaults, 50–500 RPM): χ_ECS falls with crank speed,
∝ ω^(−1/3) for spherical contact (5.3e4 → 2.4e4) and roughly ∝ ω^(−0.9) for cylindrical
(2.4e6 → 3.2e5), as the paper says its factor does; but it is 10⁴–10⁶ times χ(0.8) of the other
models (0.27–0.40), and the restitution it implies is ≈ 0 (2e-5 … 4e-5 spherical): the damping
D = 0.01 K is far *larger* than the Hunt–Crossley models' at these penetrations, not smaller as
the paper reports. Their Fig. 6 must plot a different quantity.
"""

from __future__ import annotations

import math
from collections.abc import Iterable, Mapping
from dataclasses import asdict, dataclass, field
from types import MappingProxyType
from typing import TYPE_CHECKING, Any, Literal, cast

import numpy as np
import numpy.typing as npt
import pandas as pd

from jointplay.contact.laws import CONTACT_LAWS, HuntCrossleyTypeLaw, ImpactLaw, RestitutionLaw
from jointplay.contact.restitution import effective_restitution
from jointplay.errors import ConfigError
from jointplay.model.mechanism import GROUND, STEEL, Material, Mechanism, RevoluteJoint

if TYPE_CHECKING:
    from jointplay.dynamics.nominal import NominalResult

FloatArray = npt.NDArray[np.float64]
ContactType = Literal["spherical", "cylindrical"]

#: The two contact types of the paper: eqs. 9–10 and eqs. 11–12.
CONTACT_TYPES: tuple[ContactType, ...] = ("spherical", "cylindrical")

#: Equivalent radius conventions of the pin/bearing pair (see the module docstring).
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

#: Paper units: 1 N/mm = 1000 N/m, 1 mm = 1e-3 m, 1 N·s/mm = 1000 N·s/m.
_MM = 1e-3


# --- the formulas (pure functions, SI) --------------------------------------------------------


def _check_positive(name: str, value: float, unit: str, *, allow_zero: bool = False) -> float:
    value = float(value)
    ok = value >= 0.0 if allow_zero else value > 0.0
    if not (math.isfinite(value) and ok):
        bound = ">= 0" if allow_zero else "> 0"
        raise ConfigError(f"{name} must be finite and {bound} {unit}, got {value!r}")
    return value


def _check_choice(owner: str, name: str, value: str, choices: Mapping[str, str]) -> str:
    if value not in choices:
        raise ConfigError(f"{owner}.{name} = {value!r} is invalid: use one of {', '.join(choices)}")
    return value


def effective_modulus(bearing: Material, pin: Material, convention: str = "johnson") -> float:
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
    _check_choice("effective_modulus", "convention", convention, MODULUS_CONVENTIONS)
    if convention == "johnson":
        return 1.0 / (
            (1.0 - bearing.poisson_ratio**2) / bearing.youngs_modulus
            + (1.0 - pin.poisson_ratio**2) / pin.youngs_modulus
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
        return r_j * r_b / (r_j + r_b)
    if not r_b > r_j:
        raise ConfigError(
            f"equivalent_radius: the conformal radius needs a bearing larger than the pin, got "
            f"R_B = {r_b!r} m, R_J = {r_j!r} m; give the joint a clearance or use radius='pin'"
        )
    return r_j * r_b / (r_b - r_j)


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
    a = (3.0 * load * radius / (4.0 * modulus)) ** (1.0 / 3.0)
    delta = a * a / radius * (1.0 - 2.0 / 3.0 * (a0 / a) ** 1.5)
    return a, a * modulus, delta


def line_contact_half_width(line_load: float, radius: float, modulus: float) -> float:
    """Hertz line-contact half-width ``b = √(4 P R/(π E*))``, m (Johnson 1985 ch. 4).

    Args:
        line_load: load per unit length P = F/l ≥ 0, N/m.
        radius: equivalent radius R > 0, m.
        modulus: effective modulus E* > 0, Pa.
    """
    line_load = _check_positive(
        "line_contact_half_width: line_load", line_load, "N/m", allow_zero=True
    )
    radius = _check_positive("line_contact_half_width: radius", radius, "m")
    modulus = _check_positive("line_contact_half_width: modulus", modulus, "Pa")
    return math.sqrt(4.0 * line_load * radius / (math.pi * modulus))


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
    b = line_contact_half_width(line_load, radius, modulus)
    log_term = math.log(4.0 * d1 / b) + math.log(4.0 * d2 / b)
    stiffness = math.pi * length * modulus / (log_term - 2.0)
    eq11_log = (
        log_term
        if log_argument == "half-width"
        else (math.log(4.0 * d1 / length) + math.log(4.0 * d2 / length))
    )
    delta = line_load / (math.pi * modulus) * (eq11_log - 1.0)
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
    comparison (module docstring).

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
    design point with n = 1 (module docstring). ``nan`` when δ = 0.

    Args:
        damping_ratio: ρ = D/K, s.
        impact_velocity: v0, m/s.
        penetration: the ECS δ, m.
    """
    if penetration <= 0.0:
        return math.nan
    return damping_ratio * impact_velocity / penetration


# --- conventions and results ------------------------------------------------------------------


@dataclass(frozen=True)
class EcsConventions:
    """Every choice the paper leaves open, with its default (see the module docstring).

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
            self._number("contact_length", self.contact_length, "m", "> 0", lambda v: v > 0)
        self._number(
            "initial_contact_radius", self.initial_contact_radius, "m", ">= 0", lambda v: v >= 0
        )
        self._number("damping_ratio", self.damping_ratio, "s", ">= 0", lambda v: v >= 0)
        self._number("ifm_exponent", self.ifm_exponent, "", "> 0", lambda v: v > 0)
        if self.impact_velocity is not None:
            self._number("impact_velocity", self.impact_velocity, "m/s", "> 0", lambda v: v > 0)

    def _number(self, name: str, value: Any, unit: str, bound: str, ok: Any) -> None:
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
                "effective_modulus_N_per_mm2": self.modulus * _MM**2,
                "equivalent_radius_mm": self.radius / _MM,
                f"{size}_mm": self.contact_size / _MM,
                "length_mm": self.length / _MM,
                "stiffness_N_per_mm": self.stiffness * _MM,
                "penetration_mm": self.penetration / _MM,
                "damping_N_s_per_mm": self.damping * _MM,
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
        return cast(EcsEstimate, getattr(self, _contact(contact)))


@dataclass(frozen=True)
class EcsResult:
    """ECS of a mechanism at one crank speed: per joint and overall.

    Attributes:
        mechanism: mechanism name.
        crank_speed: rad/s.
        conventions: the conventions used.
        joints: one entry per revolute joint with fit data, in the mechanism's order.
        overall_joint: the joint with the largest load (ties: the first); its estimates are
            the mechanism's ECS values, as the paper's single K, δ, D per contact type.
        impact_velocity: v0 for the hysteresis comparison, m/s.
        impact_velocity_source: ``"estimated"`` or ``"given"``.
    """

    mechanism: str
    crank_speed: float
    conventions: EcsConventions
    joints: tuple[EcsJoint, ...]
    overall_joint: str
    impact_velocity: float
    impact_velocity_source: str

    @property
    def crank_speed_rpm(self) -> float:
        """Crank speed, rev/min."""
        return self.crank_speed * 30.0 / math.pi

    @property
    def overall(self) -> EcsJoint:
        """The joint with the largest load."""
        return self.joint(self.overall_joint)

    def joint(self, name: str) -> EcsJoint:
        """The entry of joint ``name``."""
        for entry in self.joints:
            if entry.load.joint == name:
                return entry
        raise ConfigError(
            f"no ECS entry for joint {name!r}; joints: {[j.load.joint for j in self.joints]}"
        )

    def estimate(self, contact: str) -> EcsEstimate:
        """The mechanism's (overall) estimate for ``contact``."""
        return self.overall.estimate(contact)

    def hysteresis_factor(self, contact: str) -> float:
        """χ_ECS = (D/K) v0/δ of the overall estimate (module docstring), dimensionless."""
        est = self.estimate(contact)
        return ecs_hysteresis_factor(
            self.conventions.damping_ratio, self.impact_velocity, est.penetration
        )

    def as_dict(self) -> dict[str, Any]:
        """A JSON-ready record: conventions, loads, estimates (SI and paper units)."""
        joints = []
        for entry in self.joints:
            load = entry.load
            joints.append(
                {
                    "joint": load.joint,
                    "load": {
                        "source": load.source,
                        "load_N": load.load,
                        "at_crank_deg": load.crank_deg,
                        "alpha_link": load.alpha_link,
                        "alpha_max_rad_s2": load.alpha_max,
                        "tangential_acceleration_m_s2": load.tangential_acceleration,
                        "pin_radius_m": load.pin_radius,
                        "bearing_radius_m": load.bearing_radius,
                        "clearance_m": load.clearance,
                        "pin_mass_kg": load.pin_mass,
                        "contact_length_m": load.length,
                        "bearing_material": load.bearing_material.name,
                        "pin_material": load.pin_material.name,
                    },
                    "spherical": entry.spherical.as_dict(),
                    "cylindrical": entry.cylindrical.as_dict(),
                }
            )
        return {
            "mechanism": self.mechanism,
            "crank_speed_rad_s": self.crank_speed,
            "crank_speed_rpm": self.crank_speed_rpm,
            "conventions": self.conventions.as_dict(),
            "overall_joint": self.overall_joint,
            "overall": {c: self.estimate(c).as_dict() for c in CONTACT_TYPES},
            "joints": joints,
            "hysteresis": {
                "impact_velocity_m_s": self.impact_velocity,
                "impact_velocity_source": self.impact_velocity_source,
                "chi_ecs": {c: self.hysteresis_factor(c) for c in CONTACT_TYPES},
            },
        }


def _contact(contact: str) -> ContactType:
    if contact not in CONTACT_TYPES:
        raise ConfigError(
            f"unknown contact type {contact!r}; use one of {', '.join(CONTACT_TYPES)}"
        )
    return cast(ContactType, contact)


def _material(mechanism: Mechanism, body: str) -> Material:
    if body != GROUND:
        name = mechanism.link(body).material
        if name is not None and name in mechanism.materials:
            return mechanism.materials[name]
    return next(iter(mechanism.materials.values()), STEEL)


def _contact_length(mechanism: Mechanism, joint: RevoluteJoint, convention: str | float) -> float:
    if not isinstance(convention, str):
        return float(convention)
    assert joint.fit is not None
    if convention == "link-thickness":
        thicknesses = [
            t
            for name in (joint.link_a, joint.link_b)
            if name != GROUND and (t := mechanism.link(name).thickness) is not None
        ]
        if thicknesses:
            return min(thicknesses)
        if joint.fit.pin_length is not None:
            return joint.fit.pin_length
        raise ConfigError(
            f"joint {joint.name!r}: neither link has a thickness and the fit has no pin_length; "
            "give the links a thickness, or use contact_length='pin-length' with a pin_length, "
            "or a length in m"
        )
    if joint.fit.pin_length is None:
        raise ConfigError(
            f"joint {joint.name!r}: contact_length='pin-length' needs JointFit.pin_length; set "
            f"joints.{joint.name}.pin_length or use contact_length='link-thickness'"
        )
    return joint.fit.pin_length


def _alpha(nominal: NominalResult, body: str) -> FloatArray:
    if body == GROUND:
        return np.zeros_like(nominal.kinematics.crank_angle)
    return np.asarray(nominal.kinematics.alpha(body), dtype=np.float64)


def _joint_load(
    mechanism: Mechanism,
    joint: RevoluteJoint,
    nominal: NominalResult,
    conventions: EcsConventions,
) -> JointLoad:
    fit = joint.fit
    assert fit is not None
    crank_deg = nominal.table["crank_deg"].to_numpy()
    pin_radius = fit.diameter / 2.0
    clearance = fit.clearance or 0.0
    candidates = {
        "max": (joint.link_a, joint.link_b),
        "pin": (joint.link_b,),
        "bearing": (joint.link_a,),
    }[conventions.alpha_link]
    best_link, best_alpha, best_index = "", 0.0, 0
    for body in candidates:
        alpha = np.abs(_alpha(nominal, body))
        index = int(np.argmax(alpha))
        if alpha[index] > best_alpha:
            best_link, best_alpha, best_index = body, float(alpha[index]), index
    if conventions.load == "eq13":
        if fit.pin_mass is None:
            raise ConfigError(
                f"joint {joint.name!r}: eq. 13 needs the pin mass; set joints.{joint.name}."
                "pin_mass in the configuration, or use the 'reaction' load"
            )
        load = best_alpha * pin_radius * fit.pin_mass
        index = best_index
    else:
        reaction = nominal.dynamics.joint_force(joint.name)
        index = int(np.argmax(reaction))
        load = float(reaction[index])
    return JointLoad(
        joint=joint.name,
        source=conventions.load,
        load=load,
        crank_deg=float(crank_deg[index]),
        alpha_link=best_link,
        alpha_max=best_alpha,
        tangential_acceleration=best_alpha * pin_radius,
        pin_radius=pin_radius,
        bearing_radius=pin_radius + clearance,
        clearance=clearance,
        pin_mass=fit.pin_mass if fit.pin_mass is not None else math.nan,
        length=_contact_length(mechanism, joint, conventions.contact_length),
        bearing_material=_material(mechanism, joint.link_a),
        pin_material=_material(mechanism, joint.link_b),
    )


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
    modulus = effective_modulus(load.bearing_material, load.pin_material, conventions.modulus)
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


def ecs_analysis(
    mechanism: Mechanism,
    conventions: EcsConventions | None = None,
    *,
    nominal: NominalResult | None = None,
    step_deg: float = 1.0,
) -> EcsResult:
    """The ECS method on ``mechanism`` at its crank speed (paper eqs. 9–13).

    Args:
        mechanism: the nominal mechanism; every revolute joint with a
            :class:`~jointplay.model.mechanism.JointFit` gets an estimate.
        conventions: the open choices (defaults: :class:`EcsConventions`).
        nominal: a precomputed :func:`~jointplay.dynamics.nominal.nominal_analysis` of
            ``mechanism`` (computed here if ``None``).
        step_deg: crank-angle step of the nominal cycle, deg (1° as the paper's analysis).

    Returns:
        An :class:`EcsResult`.

    Raises:
        ConfigError: no revolute joint with fit data, a fit lacking what the conventions need,
            or an invalid convention.
    """
    from jointplay.dynamics.nominal import nominal_analysis

    conventions = conventions or EcsConventions()
    joints = [j for j in mechanism.revolute_joints if j.fit is not None]
    if not joints:
        raise ConfigError(
            f"mechanism {mechanism.name!r}: no revolute joint has fit data (diameter, clearance, "
            "pin_mass); add a [joints.NAME] table to the configuration"
        )
    if nominal is None:
        nominal = nominal_analysis(mechanism, step_deg=step_deg)
    entries = tuple(
        estimate_joint(_joint_load(mechanism, j, nominal, conventions), conventions) for j in joints
    )
    overall = max(entries, key=lambda e: e.load.load).load.joint
    if conventions.impact_velocity is not None:
        v0, v0_source = conventions.impact_velocity, "given"
    else:
        driver = max(entries, key=lambda e: e.load.tangential_acceleration).load
        v0 = impact_velocity_estimate(driver.tangential_acceleration, driver.clearance)
        v0_source = "estimated"
    return EcsResult(
        mechanism=mechanism.name,
        crank_speed=mechanism.driver.speed,
        conventions=conventions,
        joints=entries,
        overall_joint=overall,
        impact_velocity=v0,
        impact_velocity_source=v0_source,
    )


# --- the paper's published values -------------------------------------------------------------


@dataclass(frozen=True)
class PublishedEcs:
    """ECS values published in the paper, in its units.

    Attributes:
        contact: ``"spherical"`` or ``"cylindrical"``.
        table: where they are printed.
        crank_speed_rpm: crank speed they were estimated for, rev/min.
        stiffness_n_per_mm: K, N/mm.
        penetration_mm: δ, mm (as printed; see the module docstring on Table 4's unit).
        damping_n_s_per_mm: D, N·s/mm.
    """

    contact: str
    table: str
    crank_speed_rpm: float
    stiffness_n_per_mm: float
    penetration_mm: float
    damping_n_s_per_mm: float

    @property
    def stiffness(self) -> float:
        """K, N/m."""
        return self.stiffness_n_per_mm / _MM

    @property
    def penetration(self) -> float:
        """δ, m."""
        return self.penetration_mm * _MM

    @property
    def damping(self) -> float:
        """D, N·s/m."""
        return self.damping_n_s_per_mm / _MM

    @property
    def damping_ratio(self) -> float:
        """D/K, s (0.01 for both tables, to 4 significant figures)."""
        return self.damping_n_s_per_mm / self.stiffness_n_per_mm

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: the printed values and their SI equivalents."""
        return {
            "source": f"Akhadkar et al., {self.table}",
            "crank_speed_rpm": self.crank_speed_rpm,
            "paper_units": {
                "stiffness_N_per_mm": self.stiffness_n_per_mm,
                "penetration_mm": self.penetration_mm,
                "damping_N_s_per_mm": self.damping_n_s_per_mm,
            },
            "si": {
                "stiffness_N_per_m": self.stiffness,
                "penetration_m": self.penetration,
                "damping_N_s_per_m": self.damping,
            },
        }


#: The paper's ECS results at 200 RPM: Table 4 (cylindrical) and Table 5 (spherical).
PAPER_PUBLISHED: Mapping[str, PublishedEcs] = MappingProxyType(
    {
        "cylindrical": PublishedEcs("cylindrical", "Table 4", 200.0, 242348.0, 2.69e-10, 2423.0),
        "spherical": PublishedEcs("spherical", "Table 5", 200.0, 2500.0, 3.67e-5, 25.0),
    }
)


# --- what the simulator needs -----------------------------------------------------------------


@dataclass(frozen=True)
class EcsParameters:
    """Contact parameters for the simulator from the ECS method, and how they were derived.

    IMPACT (IFM, paper eqs. 1–3): ``F = k δ^e + STEP(δ, 0, 0, d_max, c_max) δ̇``.
    Restitution (RM, eq. 8 surrogate): penalty ``p`` (linear), restitution chosen by the user.

    Attributes:
        contact: ``"spherical"`` or ``"cylindrical"``.
        source: ``"computed"`` or ``"paper"``.
        stiffness: IMPACT k, N/m^e (SI; see ``EcsConventions.ifm_stiffness``).
        exponent: IMPACT e.
        c_max: IMPACT maximum damping = D, N·s/m.
        d_max: IMPACT full-damping penetration = δ, m.
        penalty: RM penalty p = K, N/m (exponent 1).
        ecs_stiffness: the linear ECS K, N/m.
        ecs_penetration: the ECS δ, m.
        ecs_damping: the ECS D, N·s/m.
        derivation: JSON-ready record of sources, conventions and intermediate values.
    """

    contact: str
    source: str
    stiffness: float
    exponent: float
    c_max: float
    d_max: float
    penalty: float
    ecs_stiffness: float
    ecs_penetration: float
    ecs_damping: float
    derivation: Mapping[str, Any] = field(default_factory=dict)

    def impact_law(self) -> ImpactLaw:
        """The IMPACT law with these parameters."""
        return ImpactLaw(
            stiffness=self.stiffness, exponent=self.exponent, c_max=self.c_max, d_max=self.d_max
        )

    def restitution_law(self, restitution: float = 0.8) -> RestitutionLaw:
        """The RM surrogate with penalty p = K (exponent 1) and coefficient ``restitution``."""
        return RestitutionLaw(penalty=self.penalty, restitution=restitution, exponent=1.0)

    def as_dict(self) -> dict[str, Any]:
        """JSON-ready: SI values, the same in the paper's units, and the derivation."""
        e = self.exponent
        return {
            "contact": self.contact,
            "source": self.source,
            "impact": {
                "stiffness_N_per_m^e": self.stiffness,
                "stiffness_N_per_mm^e": self.stiffness * _MM**e,
                "exponent": e,
                "c_max_N_s_per_m": self.c_max,
                "c_max_N_s_per_mm": self.c_max * _MM,
                "d_max_m": self.d_max,
                "d_max_mm": self.d_max / _MM,
            },
            "restitution_method": {
                "penalty_N_per_m": self.penalty,
                "penalty_N_per_mm": self.penalty * _MM,
            },
            "derivation": dict(self.derivation),
        }


def ecs_parameters(
    mechanism: Mechanism,
    contact: str = "spherical",
    source: str = "computed",
    conventions: EcsConventions | None = None,
    *,
    result: EcsResult | None = None,
) -> EcsParameters:
    """IMPACT and RM parameters from the ECS method (``"computed"``) or the paper (``"paper"``).

    Args:
        mechanism: the nominal mechanism (its crank speed sets the computed load).
        contact: ``"spherical"`` (eqs. 9–10, Table 5) or ``"cylindrical"`` (eqs. 11–12,
            Table 4).
        source: ``"computed"`` (:func:`ecs_analysis`) or ``"paper"`` (:data:`PAPER_PUBLISHED`,
            estimated by the paper at 200 RPM for its own mechanism).
        conventions: the open choices, including how K becomes the IMPACT stiffness.
        result: a precomputed :func:`ecs_analysis` of ``mechanism`` with these conventions.

    Returns:
        :class:`EcsParameters` (SI) with a derivation record.

    Raises:
        ConfigError: unknown contact or source, an unusable estimate (zero load, K or δ not
            positive), or ``ifm_stiffness="matched"`` with the paper's values (no load is
            published).
    """
    contact = _contact(contact)
    conventions = conventions or EcsConventions()
    if source not in ("computed", "paper"):
        raise ConfigError(f"unknown ECS source {source!r}; use 'computed' or 'paper'")
    record: dict[str, Any] = {"contact": contact, "source": source}
    if source == "paper":
        published = PAPER_PUBLISHED[contact]
        k_lin, delta = published.stiffness, published.penetration
        damping = published.damping
        load = math.nan
        record["published"] = published.as_dict()
        rpm = mechanism.driver.speed * 30.0 / math.pi
        if not math.isclose(rpm, published.crank_speed_rpm, rel_tol=1e-6):
            record["warning"] = (
                f"the published values are for {published.crank_speed_rpm:g} RPM; the mechanism "
                f"runs at {rpm:.6g} RPM"
            )
        record["damping"] = "D as published (D/K = 0.01 s)"
    else:
        result = result or ecs_analysis(mechanism, conventions)
        est = result.estimate(contact)
        if not est.ok:
            raise ConfigError(
                f"ECS {contact} estimate at joint {est.joint!r} is unusable: {est.message}"
            )
        k_lin, delta, damping, load = est.stiffness, est.penetration, est.damping, est.load
        record["estimate"] = est.as_dict()
        record["conventions"] = conventions.as_dict()
        record["damping"] = f"D = {conventions.damping_ratio:g} s x K"
    mode = conventions.ifm_stiffness
    if mode == "paper":
        exponent = conventions.ifm_exponent
        stiffness = k_lin * _MM ** (1.0 - exponent)
        record["ifm_stiffness"] = (
            f"paper: K = {k_lin * _MM:.6g} N/mm kept as the number and read as N/mm^{exponent:g}"
            f" => k = {stiffness:.6g} N/m^{exponent:g} (a unit leap, not physics)"
        )
    elif mode == "linear":
        exponent, stiffness = 1.0, k_lin
        record["ifm_stiffness"] = f"linear: k = K = {k_lin:.6g} N/m, exponent 1"
    else:
        if source == "paper":
            raise ConfigError(
                "ifm_stiffness='matched' needs the contact load, which the paper does not "
                "publish; use source='computed' or ifm_stiffness='paper'/'linear'"
            )
        exponent = conventions.ifm_exponent
        stiffness = load / delta**exponent
        record["ifm_stiffness"] = (
            f"matched: k = F / delta^{exponent:g} = {load:.6g} N / ({delta:.6g} m)^{exponent:g}"
        )
    record["impact"] = "c_max = D, d_max = delta"
    record["restitution_method"] = "penalty p = K (linear, N/m)"
    return EcsParameters(
        contact=contact,
        source=source,
        stiffness=stiffness,
        exponent=exponent,
        c_max=damping,
        d_max=delta,
        penalty=k_lin,
        ecs_stiffness=k_lin,
        ecs_penetration=delta,
        ecs_damping=damping,
        derivation=MappingProxyType(record),
    )


# --- crank-speed sweep and the hysteresis comparison ------------------------------------------


def comparison_factors(restitution: float) -> dict[str, float]:
    """χ(e) of the Hunt–Crossley-type models of the paper's Fig. 6 (contact-models.md §2.2).

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


@dataclass(frozen=True)
class EcsSweep:
    """K, δ, D and the hysteresis comparison over crank speed (SI).

    Attributes:
        mechanism: mechanism name.
        conventions: the conventions used.
        restitution: e of the comparison models.
        results: the :class:`EcsResult` at each speed.
        table: one row per speed. Columns: ``rpm``, ``load_N``, ``load_joint``,
            ``impact_velocity_m_s``; per contact c: ``K_{c}_N_per_m``, ``delta_{c}_m``,
            ``D_{c}_N_s_per_m``, ``chi_ecs_{c}``, ``e_eff_ecs_{c}`` (restitution of one
            impact with χ_ECS) and ``c_eq_{model}_{c}_N_s_per_m`` (χ(e) K δ/v0); per model
            ``chi_{model}``.
    """

    mechanism: str
    conventions: EcsConventions
    restitution: float
    results: tuple[EcsResult, ...]
    table: pd.DataFrame

    def paper_units_table(self) -> pd.DataFrame:
        """The table with K in N/mm, δ in mm and damping in N·s/mm (columns renamed)."""
        out = self.table.copy()
        names = {}
        for column in out.columns:
            if column.endswith("_N_per_m") or column.endswith("_N_s_per_m"):
                out[column] = out[column] * _MM
                names[column] = column + "m"
            elif column.startswith("delta_") and column.endswith("_m"):
                out[column] = out[column] / _MM
                names[column] = column + "m"
        return out.rename(columns=names)
        return out


def ecs_sweep(
    mechanism: Mechanism,
    speeds_rpm: Iterable[float],
    conventions: EcsConventions | None = None,
    *,
    restitution: float = 0.8,
    step_deg: float = 1.0,
) -> EcsSweep:
    """ECS values and hysteresis factors over crank speed (the paper's Fig. 6 discussion).

    Each speed runs the nominal analysis of ``mechanism`` with that constant crank speed.
    What is compared is defined in the module docstring ("Hysteresis damping factor").

    Args:
        mechanism: the nominal mechanism.
        speeds_rpm: crank speeds, rev/min (each > 0).
        conventions: the open choices.
        restitution: e of the comparison models LN, HC, Flores, Hu–Guo.
        step_deg: crank-angle step of each nominal cycle, deg.

    Raises:
        ConfigError: no speed, a speed not positive, or e outside (0, 1].
    """
    conventions = conventions or EcsConventions()
    speeds = [float(s) for s in speeds_rpm]
    if not speeds:
        raise ConfigError("ecs_sweep: give at least one crank speed")
    for speed in speeds:
        _check_positive("ecs_sweep: crank speed", speed, "rpm")
    chi_models = comparison_factors(restitution)
    rows = []
    results = []
    for rpm in speeds:
        result = ecs_analysis(
            mechanism.with_driver(speed=rpm * math.pi / 30.0), conventions, step_deg=step_deg
        )
        results.append(result)
        v0 = result.impact_velocity
        row: dict[str, Any] = {
            "rpm": rpm,
            "load_N": result.overall.load.load,
            "load_joint": result.overall_joint,
            "impact_velocity_m_s": v0,
        }
        for contact in CONTACT_TYPES:
            est = result.estimate(contact)
            chi = result.hysteresis_factor(contact)
            row[f"K_{contact}_N_per_m"] = est.stiffness
            row[f"delta_{contact}_m"] = est.penetration
            row[f"D_{contact}_N_s_per_m"] = est.damping
            row[f"chi_ecs_{contact}"] = chi
            row[f"e_eff_ecs_{contact}"] = (
                effective_restitution(chi) if math.isfinite(chi) else math.nan
            )
            for name, chi_model in chi_models.items():
                row[f"c_eq_{name}_{contact}_N_s_per_m"] = (
                    chi_model * est.stiffness * est.penetration / v0 if v0 > 0 else math.nan
                )
        for name, chi_model in chi_models.items():
            row[f"chi_{name}"] = chi_model
        rows.append(row)
    return EcsSweep(
        mechanism=mechanism.name,
        conventions=conventions,
        restitution=float(restitution),
        results=tuple(results),
        table=pd.DataFrame(rows),
    )
