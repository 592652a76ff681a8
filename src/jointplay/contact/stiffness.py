"""Pin-in-hole contact stiffness: the elastic force–penetration relation from geometry.

Each law is a frozen dataclass of the joint's geometry (bearing radius R_i, pin radius R_j,
contact length L, all in m) and materials (Young's modulus in Pa and Poisson's ratio of
bearing and pin). It gives the elastic force ``elastic_force(δ)`` (N, vectorised) and
``power_law_fit(δ_max) -> (k, n)``, a least-squares fit of ``F = k δ^n`` in log space over
``(δ_max/100, δ_max)``, so a simulation can take the stiffness and exponent of a
:mod:`~jointplay.contact.laws` law from the geometry. Laws are registered by name in
:data:`STIFFNESS_LAWS`; :func:`get_stiffness_law` accepts a name plus parameters, or an
instance.

Notation (docs/contact-laws.md §3): clearance ``ΔR = R_i − R_j``, conformal radius
``R = R_i R_j / ΔR``, effective modulus ``1/E* = (1 − ν_i²)/E_i + (1 − ν_j²)/E_j``, load per
unit length ``f = F/L``. The Hertz formulas (E*, R, the point-contact stiffness) are those of
:mod:`jointplay.contact.hertz`.

The implicit laws (Johnson, Radzimovsky, ESDU-78035 give δ as a function of F) all have the
form ``δ = A x (c − ln x)`` with ``x = f/B``. On ``0 < x < e^(c−1)``, where δ increases with
F, this inverts in closed form with the lower branch of the Lambert W function:
``x = −y / W₋₁(−y e^(−c))``, ``y = δ/A``. That is the exact root the reference code finds by
Newton iteration. Beyond ``δ = A e^(c−1)`` the law has no solution (the penetration would
decrease with load); such penetrations raise :class:`~jointplay.errors.ConfigError`.
"""

from __future__ import annotations

import math
from abc import ABC, abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, ClassVar, Protocol, Self

import numpy as np
import numpy.typing as npt

from jointplay.contact import hertz
from jointplay.contact.laws import FloatArray, _resolve, _Validated
from jointplay.errors import ConfigError

#: Number of log-spaced penetrations used by :meth:`PinInHoleStiffness.power_law_fit`.
FIT_POINTS = 200


class _Material(Protocol):
    @property
    def youngs_modulus(self) -> float: ...

    @property
    def poisson_ratio(self) -> float: ...


@dataclass(frozen=True, kw_only=True)
class PinInHoleStiffness(_Validated, ABC):
    """Base of the pin-in-hole stiffness laws (all fields keyword-only, SI).

    Attributes:
        bearing_radius: hole radius R_i, m.
        pin_radius: pin (journal) radius R_j, m, 0 < R_j < R_i.
        length: axial contact length L, m.
        bearing_youngs_modulus: E_i, Pa.
        bearing_poisson_ratio: ν_i in [0, 0.5).
        pin_youngs_modulus: E_j, Pa.
        pin_poisson_ratio: ν_j in [0, 0.5).
    """

    name: ClassVar[str]
    citation: ClassVar[str]
    equation: ClassVar[str]
    aliases: ClassVar[Mapping[str, str]] = MappingProxyType(
        {
            "R_i": "bearing_radius",
            "R_j": "pin_radius",
            "L": "length",
            "E_i": "bearing_youngs_modulus",
            "nu_i": "bearing_poisson_ratio",
            "E_j": "pin_youngs_modulus",
            "nu_j": "pin_poisson_ratio",
        }
    )

    bearing_radius: float
    pin_radius: float
    length: float
    bearing_youngs_modulus: float
    bearing_poisson_ratio: float
    pin_youngs_modulus: float
    pin_poisson_ratio: float

    @classmethod
    def from_materials(
        cls,
        *,
        bearing_radius: float,
        pin_radius: float,
        length: float,
        bearing: _Material,
        pin: _Material,
    ) -> Self:
        """Build from two material objects (e.g. :data:`jointplay.model.mechanism.STEEL`)."""
        return cls(
            bearing_radius=bearing_radius,
            pin_radius=pin_radius,
            length=length,
            bearing_youngs_modulus=bearing.youngs_modulus,
            bearing_poisson_ratio=bearing.poisson_ratio,
            pin_youngs_modulus=pin.youngs_modulus,
            pin_poisson_ratio=pin.poisson_ratio,
        )

    def _validate(self) -> None:
        self._require("pin_radius", self.pin_radius > 0.0, "must be > 0 m")
        self._require(
            "bearing_radius",
            self.bearing_radius > self.pin_radius,
            f"must exceed pin_radius = {self.pin_radius} m",
            "the hole must be larger than the pin (radial clearance > 0)",
        )
        self._require("length", self.length > 0.0, "must be > 0 m")
        for part in ("bearing", "pin"):
            self._require(
                f"{part}_youngs_modulus",
                getattr(self, f"{part}_youngs_modulus") > 0,
                "must be > 0 Pa",
                "e.g. 207e9 for steel",
            )
            self._require(
                f"{part}_poisson_ratio",
                0.0 <= getattr(self, f"{part}_poisson_ratio") < 0.5,
                "must lie in [0, 0.5)",
                "e.g. 0.29 for steel",
            )

    @property
    def clearance(self) -> float:
        """Radial clearance ΔR = R_i − R_j, m."""
        return self.bearing_radius - self.pin_radius

    @property
    def conformal_radius(self) -> float:
        """Equivalent radius of the internal contact R = R_i R_j / ΔR, m (§3.1)."""
        return hertz.conformal_radius(self.pin_radius, self.bearing_radius)

    @property
    def effective_modulus(self) -> float:
        """E* from ``1/E* = (1 − ν_i²)/E_i + (1 − ν_j²)/E_j``, Pa (§3.1)."""
        return hertz.effective_modulus(
            self.bearing_youngs_modulus,
            self.bearing_poisson_ratio,
            self.pin_youngs_modulus,
            self.pin_poisson_ratio,
        )

    @property
    def max_penetration(self) -> float:
        """Largest penetration for which the law is defined, m (∞ for explicit laws)."""
        return math.inf

    def elastic_force(self, delta: npt.ArrayLike) -> FloatArray:
        """Elastic contact force F(δ) ≥ 0, N; 0 where δ ≤ 0.

        Args:
            delta: penetration δ, m.

        Raises:
            ConfigError: some δ exceeds :attr:`max_penetration`.
        """
        delta = np.asarray(delta, dtype=np.float64)
        if np.any(delta > self.max_penetration):
            raise ConfigError(
                f"{type(self).__name__}: penetration {float(np.max(delta))!r} m exceeds the "
                f"law's range, max_penetration = {self.max_penetration!r} m; use a smaller "
                "penetration or an explicit law such as 'liu' or 'hertz'"
            )
        in_contact = delta > 0.0
        penetration = np.where(in_contact, delta, 0.0)
        return np.where(in_contact, self._force(penetration), 0.0)

    @abstractmethod
    def _force(self, delta: FloatArray) -> FloatArray:
        """The law for δ ≥ 0 (returns 0 at δ = 0)."""

    def power_law_fit(self, delta_max: float) -> tuple[float, float]:
        """Least-squares fit of ``F = k δ^n`` in log space over ``(δ_max/100, δ_max)``.

        Uses :data:`FIT_POINTS` log-spaced penetrations, so every decade weighs the same.

        Args:
            delta_max: largest penetration of interest, m (e.g. the expected peak).

        Returns:
            ``(k, n)``: stiffness in N/m^n and the exponent.

        Raises:
            ConfigError: ``delta_max`` not positive, or beyond :attr:`max_penetration`.
        """
        if not (math.isfinite(delta_max) and delta_max > 0.0):
            raise ConfigError(
                f"{type(self).__name__}.power_law_fit: delta_max must be finite and > 0 m, "
                f"got {delta_max!r}"
            )
        delta = np.geomspace(delta_max / 100.0, delta_max, FIT_POINTS)
        force = self.elastic_force(delta)
        exponent, log_k = np.polyfit(np.log(delta), np.log(force), 1)
        return float(np.exp(log_k)), float(exponent)


@dataclass(frozen=True, kw_only=True)
class HertzStiffness(PinInHoleStiffness):
    """Hertz point contact with the conformal radius (docs/contact-laws.md §3.1).

    ``F = K δ^(3/2)``, ``K = (4/3) E* √R``, ``R = R_i R_j / (R_i − R_j)``: the sphere formula
    applied to the two cylinder radii, as in Lankarani/Flores's revolute-clearance papers (and
    the paper's ECS "spherical contact"). Independent of the length L.
    """

    name: ClassVar[str] = "hertz"
    citation: ClassVar[str] = (
        "Johnson (1985) Contact Mechanics; Lankarani & Nikravesh (1990); docs/contact-laws.md §3.1"
    )
    equation: ClassVar[str] = "F = (4/3) E* sqrt(R_i R_j / ΔR) δ^1.5"

    @property
    def stiffness(self) -> float:
        """K = (4/3) E* √R, N/m^1.5."""
        return hertz.point_contact_stiffness(self.conformal_radius, self.effective_modulus)

    @property
    def exponent(self) -> float:
        """n = 3/2."""
        return 1.5

    def _force(self, delta: FloatArray) -> FloatArray:
        return self.stiffness * delta**1.5


@dataclass(frozen=True, kw_only=True)
class PereiraStiffness(PinInHoleStiffness):
    """Pereira, Ramalho & Ambrósio (2011) internal cylindrical contact (docs/contact-laws.md §3.4).

    ``F = K δ^n`` with, in the N–mm units in which the fit was made (ΔR, L, δ in mm, E* in
    N/mm², F in N)::

        K = (a ΔR + b) L E* / ΔR,   a = 0.965, b = 0.0965 mm
        n = Y ΔR^(−0.005),  Y = 1.51 [ln(1000 ΔR)]^(−0.151)   for 0.005 ≤ ΔR < 0.34954 mm
                            Y = 0.0151 ΔR + 1.151             for 0.34954 ≤ ΔR ≤ 10 mm

    Conversion happens here, at the boundary: inputs and outputs are SI (K in N/m^n). The N–mm
    convention is recalled, consistent with ``b`` in mm and with the two Y branches meeting at
    ΔR = 0.34954 mm. Pereira's law also has hysteresis damping χ = 3(1 − e²)/4 — that is the
    ``lankarani-nikravesh`` contact law with this K and n.

    Raises:
        ConfigError: (at construction) ΔR outside the fitted range 0.005–10 mm.
    """

    name: ClassVar[str] = "pereira"
    citation: ClassVar[str] = (
        "Pereira, Ramalho & Ambrósio (2011), Nonlinear Dyn. 63:681–697; docs/contact-laws.md §3.4"
    )
    equation: ClassVar[str] = "F = (a ΔR + b) L E*/ΔR · δ^n  (N-mm), n = Y(ΔR) ΔR^-0.005"

    #: Coefficients of the internal (pin-in-hole) fit: a (dimensionless), b in mm.
    A: ClassVar[float] = 0.965
    B_MM: ClassVar[float] = 0.0965
    #: Fitted range of the clearance, mm, and where the two Y branches meet.
    CLEARANCE_RANGE_MM: ClassVar[tuple[float, float]] = (0.005, 10.0)
    BRANCH_MM: ClassVar[float] = 0.34954

    def _validate(self) -> None:
        super()._validate()
        low, high = self.CLEARANCE_RANGE_MM
        clearance_mm = self.clearance * 1e3
        if not low <= clearance_mm <= high:
            raise ConfigError(
                f"PereiraStiffness: clearance bearing_radius - pin_radius = {self.clearance!r} m "
                f"is outside the fitted range {low}-{high} mm; use 'hertz', 'liu' or 'johnson'"
            )

    @property
    def exponent(self) -> float:
        """n = Y ΔR^(−0.005), ΔR in mm (dimensionless)."""
        clearance_mm = self.clearance * 1e3
        if clearance_mm < self.BRANCH_MM:
            y = 1.51 * math.log(1000.0 * clearance_mm) ** -0.151
        else:
            y = 0.0151 * clearance_mm + 1.151
        return y * clearance_mm**-0.005

    @property
    def stiffness_n_mm(self) -> float:
        """K in the paper's units, N/mm^n."""
        clearance_mm = self.clearance * 1e3
        modulus_n_mm2 = self.effective_modulus * 1e-6
        return (
            (self.A * clearance_mm + self.B_MM) * self.length * 1e3 * modulus_n_mm2 / (clearance_mm)
        )

    @property
    def stiffness(self) -> float:
        """K in SI, N/m^n (``K_mm · 1000^n``)."""
        return self.stiffness_n_mm * 1000.0**self.exponent

    def _force(self, delta: FloatArray) -> FloatArray:
        return self.stiffness * delta**self.exponent


@dataclass(frozen=True, kw_only=True)
class LiuStiffness(PinInHoleStiffness):
    """Liu, Zhang & Yang improved elastic-foundation law (docs/contact-laws.md §3.5).

    ``F = (π/2) E* L δ sqrt(δ / (2 (ΔR + δ)))``. Its derivative per unit length is the
    nonlinear stiffness of Bai & Zhao's hybrid model (§3.6). The paper and year of the
    cylindrical version (Mech. Mach. Theory 42:183–197, 2007) are recalled.
    """

    name: ClassVar[str] = "liu"
    citation: ClassVar[str] = (
        "Liu, Zhang & Yang (2007), Mech. Mach. Theory 42:183–197 (recalled); docs/contact-laws.md §3.5"
    )
    equation: ClassVar[str] = "F = (π/2) E* L δ sqrt(δ / (2(ΔR + δ)))"

    def _force(self, delta: FloatArray) -> FloatArray:
        return (
            math.pi
            / 2.0
            * self.effective_modulus
            * self.length
            * delta
            * np.sqrt(delta / (2.0 * (self.clearance + delta)))
        )


@dataclass(frozen=True, kw_only=True)
class _LogarithmicStiffness(PinInHoleStiffness):
    """Implicit laws ``δ = A x (c − ln x)``, ``x = f/B`` (module docstring)."""

    @property
    @abstractmethod
    def _scales(self) -> tuple[float, float, float]:
        """``(A in m, B in N/m, c)``."""

    @property
    def max_penetration(self) -> float:
        """``A e^(c−1)``, m: beyond it δ(F) decreases and the law has no solution."""
        length_scale, _, c = self._scales
        return length_scale * math.exp(c - 1.0)

    def penetration(self, force: npt.ArrayLike) -> FloatArray:
        """The law as published: δ(F), m, for F ≥ 0 in N (0 where F ≤ 0)."""
        force = np.asarray(force, dtype=np.float64)
        length_scale, load_scale, c = self._scales
        x = np.where(force > 0.0, force / self.length / load_scale, 1.0)
        return np.where(force > 0.0, length_scale * x * (c - np.log(x)), 0.0)

    def _force(self, delta: FloatArray) -> FloatArray:
        from scipy.special import lambertw  # ~0.1 s: only the logarithmic laws need it

        length_scale, load_scale, c = self._scales
        y_max = math.exp(c - 1.0)
        y = np.minimum(delta / length_scale, y_max)
        safe = np.where(y > 0.0, y, 0.5 * y_max)
        # At the branch point -1/e (δ = max_penetration, or beyond it by rounding)
        # W₋₁ = -1; scipy returns nan there, so set it explicitly.
        argument = -safe * math.exp(-c)
        at_branch_point = argument <= -math.exp(-1.0)
        branch = np.where(
            at_branch_point, -1.0, lambertw(np.where(at_branch_point, -0.1, argument), k=-1).real
        )
        x = np.where(y > 0.0, -safe / branch, 0.0)
        return self.length * load_scale * x


@dataclass(frozen=True, kw_only=True)
class JohnsonStiffness(_LogarithmicStiffness):
    """Johnson's pin-in-hole law (docs/contact-laws.md §3.3, [CODE] form).

    ``δ = (f/(π E*)) [ln(4π E* ΔR / f) − 1]``, f = F/L, solved for F. Defined for
    δ ≤ 4 ΔR e^(−2) ≈ 0.54 ΔR.
    """

    name: ClassVar[str] = "johnson"
    citation: ClassVar[str] = "Johnson (1985) Contact Mechanics; docs/contact-laws.md §3.3"
    equation: ClassVar[str] = "δ = f/(π E*) [ln(4π E* ΔR/f) − 1]"

    @property
    def _scales(self) -> tuple[float, float, float]:
        return 4.0 * self.clearance, 4.0 * math.pi * self.effective_modulus * self.clearance, -1.0


@dataclass(frozen=True, kw_only=True)
class RadzimovskyStiffness(_LogarithmicStiffness):
    """Radzimovsky's law (docs/contact-laws.md §3.3, [CODE] form).

    ``δ = (f/(π E*)) [2/3 + ln(4R_i/b) + ln(4R_j/b)]``, ``b = 1.6 sqrt(f R / E*)``. The radii
    cancel: ``ln(4R_i/b) + ln(4R_j/b) = ln(6.25 E* ΔR / f)``. Defined for
    δ ≤ (6.25/π) e^(−1/3) ΔR ≈ 1.43 ΔR.
    """

    name: ClassVar[str] = "radzimovsky"
    citation: ClassVar[str] = "Radzimovsky (1953); docs/contact-laws.md §3.3"
    equation: ClassVar[str] = "δ = f/(π E*) [2/3 + ln(4R_i/b) + ln(4R_j/b)], b = 1.6 sqrt(f R/E*)"

    @property
    def _scales(self) -> tuple[float, float, float]:
        return (
            6.25 * self.clearance / math.pi,
            6.25 * self.effective_modulus * self.clearance,
            2.0 / 3.0,
        )


@dataclass(frozen=True, kw_only=True)
class Esdu78035Stiffness(_LogarithmicStiffness):
    """ESDU-78035 pin-in-hole law — **placement of π unconfirmed** (docs/contact-laws.md §3.3).

    We use ``δ = (f/(π E*)) [ln(4π E* ΔR / f) + 1]``, i.e.
    ``δ = f σ [ln(4ΔR/(f σ)) + 1]`` with ``σ = σ_i + σ_j``, ``σ_k = (1 − ν_k²)/(π E_k)`` —
    the same load scale ``f/(π E*)`` as Johnson's law, which it then differs from only in the
    constant (+1 instead of −1). The reference code's literal form ``π f (h_i + h_j)`` with
    ``h_k = (1 − ν_k²)/E_k`` would make δ π² ≈ 10 times larger for the same load, which no
    line-contact theory supports; check against Pereira et al. (2011) before relying on it.
    Defined for δ ≤ 4 ΔR.
    """

    name: ClassVar[str] = "esdu-78035"
    citation: ClassVar[str] = (
        "ESDU-78035 (1978); docs/contact-laws.md §3.3 (π placement UNCONFIRMED)"
    )
    equation: ClassVar[str] = "δ = f/(π E*) [ln(4π E* ΔR/f) + 1]"

    @property
    def _scales(self) -> tuple[float, float, float]:
        return 4.0 * self.clearance, 4.0 * math.pi * self.effective_modulus * self.clearance, 1.0


#: Every pin-in-hole stiffness law by registry name.
STIFFNESS_LAWS: dict[str, type[PinInHoleStiffness]] = {
    law.name: law
    for law in (
        HertzStiffness,
        JohnsonStiffness,
        RadzimovskyStiffness,
        Esdu78035Stiffness,
        PereiraStiffness,
        LiuStiffness,
    )
}


def get_stiffness_law(law: str | PinInHoleStiffness, /, **params: Any) -> PinInHoleStiffness:
    """A pin-in-hole stiffness law from a registry name plus geometry and materials, or an instance.

    Raises:
        ConfigError: unknown name (the message lists the known ones), unknown or missing
            parameter, or a parameter out of range.
    """
    return _resolve(STIFFNESS_LAWS, "stiffness law", law, params)
