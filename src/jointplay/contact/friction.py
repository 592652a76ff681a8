"""Joint friction laws, as small frozen objects.

Sign convention (docs/contact-laws.md §5): ``v_T`` is the tangential slip velocity of the journal
relative to the bearing, m/s; the laws return the signed ``F_T = μ(v_T) F_N sgn(v_T)``, N,
and the friction force on the journal is ``-F_T t`` (on the bearing ``+F_T t``), so friction
always opposes the slip. Each law's :meth:`~FrictionLaw.force` is the readable NumPy
reference of the compiled kernel :func:`jointplay._kernels.contact.friction_force`;
``law.law_id`` and ``law.params()`` (generic: the attributes the class's ``packing`` names)
are what the kernel takes. Laws are registered by name in
:data:`FRICTION_LAWS`; :func:`get_friction` accepts a name plus parameters, or an instance.
"""

from __future__ import annotations

from abc import ABC, abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, ClassVar

import numpy as np
import numpy.typing as npt

from jointplay._kernels import ids
from jointplay.contact.laws import FloatArray, _Packed, _resolve, _Validated, layout, step3


@dataclass(frozen=True)
class FrictionLaw(_Packed, _Validated, ABC):
    """Base of the friction laws: ``name``, ``law_id``, ``packing`` (the attributes in the
    order of the kernel's packed layout), ``citation``, ``equation``."""

    name: ClassVar[str]
    law_id: ClassVar[int]
    citation: ClassVar[str]
    equation: ClassVar[str]

    @abstractmethod
    def coefficient(self, v_t: npt.ArrayLike) -> FloatArray:
        """Signed effective coefficient ``F_T / F_N`` (odd in v_T, dimensionless)."""

    def force(self, v_t: npt.ArrayLike, f_n: npt.ArrayLike) -> FloatArray:
        """Signed friction force ``F_T = coefficient(v_T) · F_N``, N. Arguments broadcast.

        Args:
            v_t: slip velocity of the journal relative to the bearing, m/s.
            f_n: normal contact force, N (≥ 0).
        """
        return self.coefficient(v_t) * np.asarray(f_n, dtype=np.float64)


@dataclass(frozen=True)
class NoFriction(FrictionLaw):
    """Frictionless joint: F_T = 0."""

    name: ClassVar[str] = "none"
    law_id: ClassVar[int] = ids.FRICTION_NONE
    packing: ClassVar[tuple[str, ...]] = layout(ids.NONE_SIZE, {})
    citation: ClassVar[str] = "frictionless contact"
    equation: ClassVar[str] = "F_T = 0"

    def coefficient(self, v_t: npt.ArrayLike) -> FloatArray:
        """Zero everywhere."""
        return np.zeros_like(np.asarray(v_t, dtype=np.float64))

    def force(self, v_t: npt.ArrayLike, f_n: npt.ArrayLike) -> FloatArray:
        """Zero everywhere, N (broadcast shape of the arguments)."""
        v, _ = np.broadcast_arrays(np.asarray(v_t, dtype=np.float64), np.asarray(f_n))
        return np.zeros_like(v)


@dataclass(frozen=True)
class AmbrosioFriction(FrictionLaw):
    """Coulomb friction with Ambrósio's dynamic correction coefficient (docs/contact-laws.md §4).

    ``F_T = μ c_d(v_T) F_N sgn(v_T)`` with ``c_d = 0`` for |v_T| ≤ v0,
    ``(|v_T| − v0)/(v1 − v0)`` for v0 < |v_T| < v1 and 1 for |v_T| ≥ v1. Below v0 there is no
    friction at all (no stiction): the ramp only removes Coulomb's jump at v_T = 0 so that the
    integrator does not chatter.

    Attributes:
        mu: friction coefficient μ ≥ 0 (0.01–0.1 is typical of dry clearance-joint studies).
        v0: slip speed below which friction vanishes, m/s, ≥ 0 (default 1e-4; a recalled,
            unconfirmed value from Flores' papers).
        v1: slip speed from which full Coulomb friction applies, m/s, > v0 (default 1e-3;
            recalled, unconfirmed).
    """

    name: ClassVar[str] = "ambrosio"
    law_id: ClassVar[int] = ids.FRICTION_AMBROSIO
    packing: ClassVar[tuple[str, ...]] = layout(
        ids.AMBROSIO_SIZE, {ids.AMBROSIO_MU: "mu", ids.AMBROSIO_V0: "v0", ids.AMBROSIO_V1: "v1"}
    )
    citation: ClassVar[str] = (
        "Ambrósio (2003), Impact of rigid and flexible multibody systems; Flores et al.; "
        "docs/contact-laws.md §4"
    )
    equation: ClassVar[str] = "F_T = μ c_d(v_T) F_N sgn(v_T),  c_d linear from 0 at v0 to 1 at v1"
    aliases: ClassVar[Mapping[str, str]] = MappingProxyType(
        {"μ": "mu", "friction_coefficient": "mu"}
    )

    mu: float
    v0: float = 1e-4
    v1: float = 1e-3

    def _validate(self) -> None:
        self._require("mu", self.mu >= 0.0, "must be >= 0")
        self._require("v0", self.v0 >= 0.0, "must be >= 0 m/s", "the default is 1e-4")
        self._require(
            "v1", self.v1 > self.v0, f"must be > v0 = {self.v0} m/s", "the default is 1e-3"
        )

    def correction(self, v_t: npt.ArrayLike) -> FloatArray:
        """Dynamic correction coefficient c_d(v_T) in [0, 1] (even in v_T)."""
        speed = np.abs(np.asarray(v_t, dtype=np.float64))
        ramp = (speed - self.v0) / (self.v1 - self.v0)
        return np.where(speed <= self.v0, 0.0, np.where(speed >= self.v1, 1.0, ramp))

    def coefficient(self, v_t: npt.ArrayLike) -> FloatArray:
        """``μ c_d(v_T) sgn(v_T)``."""
        v = np.asarray(v_t, dtype=np.float64)
        return self.mu * self.correction(v) * np.sign(v)

    def force(self, v_t: npt.ArrayLike, f_n: npt.ArrayLike) -> FloatArray:
        """``μ c_d(v_T) F_N sgn(v_T)``, N (same operation order as the kernel)."""
        v = np.asarray(v_t, dtype=np.float64)
        return self.mu * self.correction(v) * np.asarray(f_n, dtype=np.float64) * np.sign(v)


@dataclass(frozen=True)
class AdamsFriction(FrictionLaw):
    """MSC ADAMS CONTACT friction, μ(v) built from cubic STEPs (docs/contact-laws.md §1.4).

    In our sign convention (the ADAMS μ(v) of the docs opposes v; ours is its negative)::

        |v| ≤ v_s:          μ(v) = STEP(v, −v_s, −μ_s, v_s, μ_s)      (0 at v = 0)
        v_s < |v| < v_d:    μ(v) = sgn(v) STEP(|v|, v_s, μ_s, v_d, μ_d)
        |v| ≥ v_d:          μ(v) = sgn(v) μ_d
        F_T = μ(v_T) F_N

    μ is continuous, passes ±μ_s at ±v_s and reaches ±μ_d at ±v_d.

    Attributes:
        mu_static: static coefficient μ_s ≥ 0 (ADAMS MU_STATIC).
        mu_dynamic: dynamic coefficient μ_d ≥ 0 (ADAMS MU_DYNAMIC).
        v_static: stiction transition velocity v_s > 0, m/s (ADAMS
            STICTION_TRANSITION_VELOCITY; Altair's default is 1e-3 m/s).
        v_dynamic: friction transition velocity v_d > v_s, m/s (ADAMS
            FRICTION_TRANSITION_VELOCITY).
    """

    name: ClassVar[str] = "adams"
    law_id: ClassVar[int] = ids.FRICTION_ADAMS
    packing: ClassVar[tuple[str, ...]] = layout(
        ids.ADAMS_SIZE,
        {
            ids.ADAMS_MU_STATIC: "mu_static",
            ids.ADAMS_MU_DYNAMIC: "mu_dynamic",
            ids.ADAMS_V_STATIC: "v_static",
            ids.ADAMS_V_DYNAMIC: "v_dynamic",
        },
    )
    citation: ClassVar[str] = (
        "MSC ADAMS contact friction (adams.thisaray.com/adams_view/contact_friction_force.html); "
        "docs/contact-laws.md §1.4"
    )
    equation: ClassVar[str] = (
        "μ = STEP(v,-v_s,-μ_s,v_s,μ_s) | sgn(v) STEP(|v|,v_s,μ_s,v_d,μ_d) | sgn(v) μ_d; F_T = μ F_N"
    )
    aliases: ClassVar[Mapping[str, str]] = MappingProxyType(
        {
            "mu_s": "mu_static",
            "mu_d": "mu_dynamic",
            "v_s": "v_static",
            "v_d": "v_dynamic",
            "vs": "v_static",
            "vd": "v_dynamic",
        }
    )

    mu_static: float
    mu_dynamic: float
    v_static: float
    v_dynamic: float

    def _validate(self) -> None:
        self._require("mu_static", self.mu_static >= 0.0, "must be >= 0")
        self._require("mu_dynamic", self.mu_dynamic >= 0.0, "must be >= 0")
        self._require("v_static", self.v_static > 0.0, "must be > 0 m/s")
        self._require(
            "v_dynamic",
            self.v_dynamic > self.v_static,
            f"must be > v_static = {self.v_static} m/s",
            "ADAMS requires the friction transition above the stiction transition velocity",
        )

    def coefficient(self, v_t: npt.ArrayLike) -> FloatArray:
        """Signed μ(v_T) (odd, continuous)."""
        v = np.asarray(v_t, dtype=np.float64)
        speed = np.abs(v)
        sign = np.sign(v)
        stiction = step3(v, -self.v_static, -self.mu_static, self.v_static, self.mu_static)
        transition = sign * step3(
            speed, self.v_static, self.mu_static, self.v_dynamic, self.mu_dynamic
        )
        sliding = sign * self.mu_dynamic
        return np.where(
            speed <= self.v_static,
            stiction,
            np.where(speed < self.v_dynamic, transition, sliding),
        )


#: Every friction law by registry name.
FRICTION_LAWS: dict[str, type[FrictionLaw]] = {
    law.name: law for law in (NoFriction, AmbrosioFriction, AdamsFriction)
}


def get_friction(law: str | FrictionLaw, /, **params: Any) -> FrictionLaw:
    """A friction law from a registry name plus parameters, or an instance.

    Names are case-insensitive; ``_`` and spaces count as ``-``. Given an instance and
    parameters, returns a copy with those parameters replaced.

    Raises:
        ConfigError: unknown name (the message lists the known ones), unknown or missing
            parameter, or a parameter out of range.
    """
    return _resolve(FRICTION_LAWS, "friction law", law, params)
