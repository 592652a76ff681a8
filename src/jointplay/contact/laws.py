"""Normal contact force laws for clearance joints, as small frozen objects.

Every law is a frozen dataclass whose fields are its parameters (SI, validated at
construction) and whose :meth:`~ContactLaw.force` is the readable NumPy reference of the
compiled kernel :func:`jointplay._kernels.contact.normal_force`. Each law declares, as data
on its class, what the kernel takes: ``law_id`` (the kernel's force form) and ``packing``
(the attributes, in slot order, of the packed ``float64`` array ``law.params()``), plus
``stiffness_name`` (the field a geometric stiffness refit replaces). Packing is generic:
nothing outside the law inspects its type or probes its fields. Laws are registered by name
in :data:`CONTACT_LAWS`; :func:`get_law` accepts a name plus parameters, or an instance.
docs/contact-laws.md, "Adding a law", says what a new law takes.

Conventions (the dynamics engine relies on them):

* penetration δ in m, > 0 in contact; penetration rate δ̇ in m/s, > 0 while approaching;
  force in N, ≥ 0 (no sticking), 0 for δ ≤ 0.
* ``v0`` is the penetration rate at the start of the current contact event (the impact
  speed), kept per contact by the engine. Laws that need it (``needs_impact_velocity``) use
  ``v_eff = max(v0, v_floor)``, or ``max(δ̇, v_floor)`` while ``v0`` is unknown
  (``v0 is None`` or ``v0 <= 0``). The floor ``v_floor`` (default 1e-4 m/s) keeps the
  damping coefficient ``χ K δ^n / v_eff`` finite in continuous contact, where the journal
  slides on the bearing and v0 of the last small rebound can be tiny. It changes a single
  impact only when the impact is slower than ``v_floor``.

Sources: docs/contact-laws.md (§1 MSC ADAMS, §2 continuous laws) and the paper's Impact Force
Method (IFM, eqs. 1–3) and Restitution Method (RM, eq. 8).
"""

from __future__ import annotations

import dataclasses
import functools
import math
from abc import ABC, abstractmethod
from collections.abc import Mapping
from dataclasses import dataclass
from types import MappingProxyType
from typing import Any, ClassVar, TypeVar, cast

import numpy as np
import numpy.typing as npt

from jointplay._kernels import ids
from jointplay.contact.restitution import chi_for_restitution
from jointplay.errors import ConfigError

FloatArray = npt.NDArray[np.float64]

#: Default floor on the impact velocity of the Hunt–Crossley family, m/s.
DEFAULT_V_FLOOR = 1e-4

_NO_ALIASES: Mapping[str, str] = MappingProxyType({})


# --- shared helpers (also used by the friction and stiffness modules) -------------------------


class _Validated:
    """Mixin for frozen parameter dataclasses: fields become floats, then ``_validate``."""

    #: Other accepted spellings of field names, e.g. ``{"k": "stiffness"}``.
    aliases: ClassVar[Mapping[str, str]] = _NO_ALIASES

    def __post_init__(self) -> None:
        owner = type(self).__name__
        for item in dataclasses.fields(self):  # type: ignore[arg-type]
            value = getattr(self, item.name)
            if isinstance(value, bool) or not isinstance(value, int | float | np.number):
                raise ConfigError(
                    f"{owner}.{item.name}: expected a number, got {value!r}; "
                    "give a plain SI value (convert units at the edge)"
                )
            value = float(value)
            if not math.isfinite(value):
                raise ConfigError(f"{owner}.{item.name}: must be finite, got {value!r}")
            object.__setattr__(self, item.name, value)
        self._validate()

    def _validate(self) -> None:
        """Check ranges; raise :class:`ConfigError` naming class, field and fix."""

    def _require(self, field: str, ok: bool, requirement: str, fix: str = "") -> None:
        if not ok:
            value = getattr(self, field)
            hint = f"; {fix}" if fix else ""
            raise ConfigError(
                f"{type(self).__name__}.{field} = {value!r} is invalid: {requirement}{hint}"
            )


_T = TypeVar("_T")


def _resolve(registry: Mapping[str, type[_T]], kind: str, law: Any, params: dict[str, Any]) -> _T:
    """Build or adjust a registered law from a name plus parameters, or an instance."""
    if isinstance(law, str):
        key = law.strip().lower().replace("_", "-").replace(" ", "-")
        if key not in registry:
            raise ConfigError(f"unknown {kind} {law!r}; known names: {', '.join(sorted(registry))}")
        cls = registry[key]
        return cls(**_canonical(cls, params, require_all=True))
    if isinstance(law, tuple(registry.values())):
        if not params:
            return cast(_T, law)
        changes = _canonical(type(law), params, require_all=False)
        return cast(_T, dataclasses.replace(cast(Any, law), **changes))
    raise ConfigError(
        f"expected a {kind} name ({', '.join(sorted(registry))}) or instance, "
        f"got {type(law).__name__}"
    )


def _canonical(cls: type, params: Mapping[str, Any], *, require_all: bool) -> dict[str, Any]:
    """Map aliases to field names; reject unknown and (optionally) missing parameters."""
    aliases: Mapping[str, str] = getattr(cls, "aliases", _NO_ALIASES)
    fields = {item.name: item for item in dataclasses.fields(cls)}
    out: dict[str, Any] = {}
    for key, value in params.items():
        name = aliases.get(key, key)
        if name not in fields:
            raise ConfigError(
                f"{cls.__name__}: unknown parameter {key!r}; its parameters are {', '.join(fields)}"
            )
        if name in out:
            raise ConfigError(f"{cls.__name__}: parameter {name!r} given twice (via {key!r})")
        out[name] = value
    if require_all:
        missing = [
            name
            for name, item in fields.items()
            if name not in out
            and item.default is dataclasses.MISSING
            and item.default_factory is dataclasses.MISSING
        ]
        if missing:
            raise ConfigError(f"{cls.__name__}: missing parameter(s) {', '.join(missing)}")
    return out


def _as_array(value: npt.ArrayLike) -> FloatArray:
    return np.asarray(value, dtype=np.float64)


def step3(x: npt.ArrayLike, x0: float, h0: float, x1: float, h1: float) -> FloatArray:
    """ADAMS cubic STEP, vectorised (docs/contact-laws.md §1.1).

    ``h0`` for x ≤ x0, ``h1`` for x ≥ x1, else ``h0 + (h1 - h0) u² (3 - 2u)`` with
    ``u = (x - x0)/(x1 - x0)``; C¹, the second derivative jumps at x0 and x1. Reference of
    :func:`jointplay._kernels.contact.step3`. ``step3([2, 3, 3.5, 4, 5], 3, 0, 4, 1)`` gives
    ``[0, 0, 0.5, 1, 1]``.

    Raises:
        ConfigError: ``x1 <= x0``.
    """
    if not x1 > x0:
        raise ConfigError(f"step3: x1 must be greater than x0, got x0 = {x0!r}, x1 = {x1!r}")
    x = _as_array(x)
    u = (np.clip(x, x0, x1) - x0) / (x1 - x0)
    ramp = h0 + (h1 - h0) * u * u * (3.0 - 2.0 * u)
    return np.where(x <= x0, h0, np.where(x >= x1, h1, ramp))


def layout(size: int, slots: Mapping[int, str]) -> tuple[str, ...]:
    """A law's ``packing``: the attribute names of a kernel layout's slots, in slot order.

    ``slots`` maps each slot index (the layout constants of :mod:`jointplay._kernels.contact`)
    to the attribute packed there, so the kernel module stays the one place where a layout is
    defined.

    Raises:
        ConfigError: the slots are not exactly ``0 .. size - 1``.
    """
    if sorted(slots) != list(range(size)):
        raise ConfigError(f"packed layout: slots {sorted(slots)} do not fill 0..{size - 1}")
    return tuple(slots[index] for index in range(size))


class _Packed:
    """Mixin for the laws the kernels evaluate: ``packing`` declares the packed parameters."""

    #: Attribute names packed into the kernel's parameter array, slot by slot (fields, or
    #: derived values such as the hysteresis factor ``chi``); see :func:`layout`.
    packing: ClassVar[tuple[str, ...]]

    def params(self) -> FloatArray:
        """Packed float64 parameters in the kernel's layout for ``law_id``: the attributes
        named by ``packing``, in order."""
        return np.array([getattr(self, name) for name in self.packing], dtype=np.float64)

    @classmethod
    def packed_slot(cls, field: str) -> int | None:
        """The slot where the dataclass field ``field`` is packed as it is, or ``None`` when it
        is packed transformed (a restitution, packed as its hysteresis factor) or not at all."""
        return cls.packing.index(field) if field in cls.packing else None


def _prepare(
    delta: npt.ArrayLike, delta_dot: npt.ArrayLike
) -> tuple[FloatArray, FloatArray, npt.NDArray[np.bool_]]:
    """Broadcast δ and δ̇; return (penetration, 0 where δ ≤ 0), δ̇ and the contact mask."""
    delta_arr, rate = np.broadcast_arrays(_as_array(delta), _as_array(delta_dot))
    in_contact = delta_arr > 0.0
    return np.where(in_contact, delta_arr, 0.0), rate, in_contact


def _clamped(force: FloatArray, in_contact: npt.NDArray[np.bool_]) -> FloatArray:
    return np.where(in_contact & (force > 0.0), force, 0.0)


# --- the laws ---------------------------------------------------------------------------------


@dataclass(frozen=True)
class ContactLaw(_Packed, _Validated, ABC):
    """Base of the normal contact force laws.

    Class attributes: ``name`` (registry key), ``law_id`` (the kernel's force form, a
    ``LAW_*`` id of :mod:`jointplay._kernels.contact`), ``packing`` (attributes in the order of
    that form's packed layout), ``stiffness_name``, ``needs_impact_velocity``, ``citation`` and
    ``equation``.
    """

    name: ClassVar[str]
    law_id: ClassVar[int]
    #: The field holding the stiffness K of ``K δ^n`` (a geometric refit replaces it and
    #: ``exponent``).
    stiffness_name: ClassVar[str] = "stiffness"
    needs_impact_velocity: ClassVar[bool] = False
    citation: ClassVar[str]
    equation: ClassVar[str]

    @abstractmethod
    def force(
        self,
        delta: npt.ArrayLike,
        delta_dot: npt.ArrayLike,
        v0: npt.ArrayLike | None = None,
    ) -> FloatArray:
        """Normal force magnitude F ≥ 0, N; 0 where δ ≤ 0. Arguments broadcast.

        Args:
            delta: penetration δ, m.
            delta_dot: penetration rate δ̇, m/s (> 0 approaching).
            v0: impact velocity of the current contact event, m/s; ignored by laws that do
                not need it. ``None`` or values ≤ 0 mean "not known yet".
        """


@dataclass(frozen=True)
class ImpactLaw(ContactLaw):
    """MSC ADAMS IMPACT (the paper's Impact Force Method, eqs. 1–3; docs/contact-laws.md §1.2).

    ``F = max(0, k δ^e + STEP(δ, 0, 0, d_max, c_max) δ̇)`` for δ > 0, else 0.
    The damping coefficient rises as a cubic STEP from 0 at first touch to ``c_max`` at
    ``δ = d_max``, so the force is continuous when contact starts. The effective restitution
    is not an input: it depends on mass, impact speed, k, c_max and d_max (§1.7); measure it
    with :func:`jointplay.contact.restitution.single_impact`.

    Attributes:
        stiffness: k ≥ 0, N/m^e (ADAMS STIFFNESS).
        exponent: force exponent e > 0 (ADAMS EXPONENT; 1.5 for Hertzian point contact).
        c_max: maximum damping coefficient ≥ 0, N·s/m (ADAMS DAMPING; "about 1 % of the
            stiffness" in ADAMS's guidance).
        d_max: penetration at which the full damping applies, m, > 0 (ADAMS DMAX; 0.01 mm is
            the documented "reasonable value").
    """

    name: ClassVar[str] = "impact"
    law_id: ClassVar[int] = ids.LAW_IMPACT
    packing: ClassVar[tuple[str, ...]] = layout(
        ids.IMPACT_SIZE,
        {
            ids.IMPACT_STIFFNESS: "stiffness",
            ids.IMPACT_EXPONENT: "exponent",
            ids.IMPACT_C_MAX: "c_max",
            ids.IMPACT_D_MAX: "d_max",
        },
    )
    citation: ClassVar[str] = (
        "MSC ADAMS IMPACT function (adams.thisaray.com/adams_solver/func_impact.html); "
        "paper eqs. (1)-(3); docs/contact-laws.md §1.2"
    )
    equation: ClassVar[str] = "F = max(0, k δ^e + STEP(δ, 0, 0, d_max, c_max) δ̇)"
    aliases: ClassVar[Mapping[str, str]] = MappingProxyType(
        {
            "k": "stiffness",
            "e": "exponent",
            "cmax": "c_max",
            "damping": "c_max",
            "d": "d_max",
            "dmax": "d_max",
        }
    )

    stiffness: float
    exponent: float
    c_max: float
    d_max: float

    def _validate(self) -> None:
        self._require("stiffness", self.stiffness >= 0.0, "must be >= 0 N/m^e")
        self._require("exponent", self.exponent > 0.0, "must be > 0", "1.5 is Hertzian")
        self._require("c_max", self.c_max >= 0.0, "must be >= 0 N·s/m", "use 0 for no damping")
        self._require("d_max", self.d_max > 0.0, "must be > 0 m", "ADAMS suggests 1e-5 m (0.01 mm)")

    def force(
        self,
        delta: npt.ArrayLike,
        delta_dot: npt.ArrayLike,
        v0: npt.ArrayLike | None = None,
    ) -> FloatArray:
        """ADAMS IMPACT force, N. See the class docstring; ``v0`` is ignored."""
        penetration, rate, in_contact = _prepare(delta, delta_dot)
        damping = step3(penetration, 0.0, 0.0, self.d_max, self.c_max)
        force = self.stiffness * penetration**self.exponent + damping * rate
        return _clamped(force, in_contact)


@dataclass(frozen=True)
class HertzLaw(ContactLaw):
    """Hertz elastic contact ``F = K δ^n`` (no dissipation; docs/contact-laws.md §2.1).

    Attributes:
        stiffness: K > 0, N/m^n; from geometry with :mod:`jointplay.contact.stiffness`.
        exponent: n > 0; 3/2 for point contact (default), about 1–1.1 for cylinders.
    """

    name: ClassVar[str] = "hertz"
    law_id: ClassVar[int] = ids.LAW_HERTZ
    packing: ClassVar[tuple[str, ...]] = layout(
        ids.HERTZ_SIZE, {ids.HERTZ_STIFFNESS: "stiffness", ids.HERTZ_EXPONENT: "exponent"}
    )
    citation: ClassVar[str] = (
        "Hertz (1882); Johnson (1985) Contact Mechanics; docs/contact-laws.md §2.1"
    )
    equation: ClassVar[str] = "F = K δ^n"
    aliases: ClassVar[Mapping[str, str]] = MappingProxyType(
        {"k": "stiffness", "K": "stiffness", "n": "exponent"}
    )

    stiffness: float
    exponent: float = 1.5

    def _validate(self) -> None:
        self._require("stiffness", self.stiffness > 0.0, "must be > 0 N/m^n")
        self._require("exponent", self.exponent > 0.0, "must be > 0", "use 1.5 for point contact")

    def force(
        self,
        delta: npt.ArrayLike,
        delta_dot: npt.ArrayLike,
        v0: npt.ArrayLike | None = None,
    ) -> FloatArray:
        """Hertz force ``K δ^n``, N; ``delta_dot`` only sets the broadcast shape."""
        penetration, _, in_contact = _prepare(delta, delta_dot)
        return _clamped(self.stiffness * penetration**self.exponent, in_contact)


@dataclass(frozen=True)
class KelvinVoigtLaw(ContactLaw):
    """Linear spring–dashpot ``F = max(0, K δ + D δ̇)`` (docs/contact-laws.md §2.1).

    The force jumps from 0 to ``D v0`` at first contact (the only law here that is not
    continuous there), and near separation the unclamped law would pull; the clamp F ≥ 0
    removes the pull, which raises the restitution above the classical
    ``exp(-π ζ / sqrt(1 - ζ²))``, ζ = D / (2 sqrt(m K)).

    Attributes:
        stiffness: K > 0, N/m.
        damping: D ≥ 0, N·s/m.
    """

    name: ClassVar[str] = "kelvin-voigt"
    law_id: ClassVar[int] = ids.LAW_KELVIN_VOIGT
    packing: ClassVar[tuple[str, ...]] = layout(
        ids.KV_SIZE, {ids.KV_STIFFNESS: "stiffness", ids.KV_DAMPING: "damping"}
    )
    citation: ClassVar[str] = "Kelvin–Voigt viscoelastic element; docs/contact-laws.md §2.1"
    equation: ClassVar[str] = "F = max(0, K δ + D δ̇)"
    aliases: ClassVar[Mapping[str, str]] = MappingProxyType(
        {"k": "stiffness", "K": "stiffness", "D": "damping", "c": "damping"}
    )

    stiffness: float
    damping: float

    def _validate(self) -> None:
        self._require("stiffness", self.stiffness > 0.0, "must be > 0 N/m")
        self._require("damping", self.damping >= 0.0, "must be >= 0 N·s/m")

    def force(
        self,
        delta: npt.ArrayLike,
        delta_dot: npt.ArrayLike,
        v0: npt.ArrayLike | None = None,
    ) -> FloatArray:
        """Clamped spring–dashpot force, N; ``v0`` is ignored."""
        penetration, rate, in_contact = _prepare(delta, delta_dot)
        force = self.stiffness * penetration + self.damping * rate
        return _clamped(force, in_contact)


def _hunt_crossley_force(
    stiffness: float,
    exponent: float,
    chi: float,
    v_floor: float,
    delta: npt.ArrayLike,
    delta_dot: npt.ArrayLike,
    v0: npt.ArrayLike | None,
) -> FloatArray:
    """``max(0, K δ^n (1 + χ δ̇ / v_eff))`` with ``v_eff`` as in the module docstring."""
    penetration, rate, in_contact = _prepare(delta, delta_dot)
    impact = np.full_like(rate, -1.0) if v0 is None else _as_array(v0)
    v_ref = np.where(impact > 0.0, impact, rate)
    v_eff = np.maximum(v_ref, v_floor)
    force = stiffness * penetration**exponent * (1.0 + chi * rate / v_eff)
    return _clamped(force, in_contact)


@dataclass(frozen=True)
class RestitutionLaw(ContactLaw):
    """The paper's Restitution Method (RM) as a documented surrogate with exact restitution.

    ``F = p δ^n (1 + χ(ε) δ̇ / v_eff)``, clamped ≥ 0, with χ(ε) from
    :func:`~jointplay.contact.restitution.chi_for_restitution`, so one impact rebounds with
    exactly the coefficient ε for any exponent, penalty, mass and speed (docs/contact-laws.md
    §1.5, §2.3).

    This is **not** ADAMS's POISSON law. ADAMS does not publish that law: the form quoted in
    the paper, ``F = p (ε - 1) ẋ`` (eq. 8), depends on velocity only, stores no elastic energy
    and vanishes for ε = 1, so it cannot be the whole model (ADAMS evidently keeps unpublished
    internal state). Here the penalty ``p`` acts as a contact stiffness and the dissipation is
    calibrated exactly; do not expect force histories identical to ADAMS.

    Attributes:
        penalty: p > 0, N/m^n (ADAMS PENALTY, in SI).
        restitution: coefficient of restitution ε in (0, 1] (ADAMS RESTITUTION_COEFFICIENT).
        exponent: n > 0 of the penalty spring, default 1 (linear, like a penalty).
        v_floor: floor on the impact velocity, m/s (default 1e-4; module docstring).
    """

    name: ClassVar[str] = "restitution"
    law_id: ClassVar[int] = ids.LAW_RESTITUTION
    packing: ClassVar[tuple[str, ...]] = layout(
        ids.HC_SIZE,
        {ids.HC_STIFFNESS: "penalty", ids.HC_EXPONENT: "exponent", ids.HC_CHI: "chi",
         ids.HC_V_FLOOR: "v_floor"},
    )  # fmt: skip
    stiffness_name: ClassVar[str] = "penalty"
    needs_impact_velocity: ClassVar[bool] = True
    citation: ClassVar[str] = (
        "Surrogate for the paper's Restitution Method (eq. 8, ADAMS POISSON, law unpublished); "
        "exact Hunt–Crossley restitution of docs/contact-laws.md §2.3 "
        "(Carvalho & Martins 2019, Mech. Mach. Theory 139:174–194, citation recalled)"
    )
    equation: ClassVar[str] = "F = p δ^n (1 + χ(ε) δ̇ / v0),  g(χ) = g(-χ ε),  g(x) = x - ln(1+x)"
    aliases: ClassVar[Mapping[str, str]] = MappingProxyType(
        {
            "p": "penalty",
            "epsilon": "restitution",
            "e": "restitution",
            "cor": "restitution",
            "n": "exponent",
        }
    )

    penalty: float
    restitution: float
    exponent: float = 1.0
    v_floor: float = DEFAULT_V_FLOOR

    def _validate(self) -> None:
        self._require("penalty", self.penalty > 0.0, "must be > 0 N/m^n")
        self._require(
            "restitution",
            0.0 < self.restitution <= 1.0,
            "must lie in (0, 1]",
            "for a nearly plastic impact use a small value such as 0.01",
        )
        self._require("exponent", self.exponent > 0.0, "must be > 0", "1 is a linear penalty")
        self._require("v_floor", self.v_floor > 0.0, "must be > 0 m/s", "the default is 1e-4")

    @functools.cached_property
    def chi(self) -> float:
        """Exact hysteresis factor χ(ε) of §2.3 (dimensionless)."""
        return chi_for_restitution(self.restitution)

    def force(
        self,
        delta: npt.ArrayLike,
        delta_dot: npt.ArrayLike,
        v0: npt.ArrayLike | None = None,
    ) -> FloatArray:
        """Penalty force with exactly calibrated hysteresis damping, N."""
        return _hunt_crossley_force(
            self.penalty, self.exponent, self.chi, self.v_floor, delta, delta_dot, v0
        )


@dataclass(frozen=True)
class HuntCrossleyTypeLaw(ContactLaw):
    """Base of the Hunt–Crossley family ``F = K δ^n (1 + χ(e) δ̇ / v_eff)``, clamped ≥ 0.

    Subclasses differ only in the hysteresis factor χ(e) (docs/contact-laws.md §2.1–2.2). The
    restitution a law really produces is
    ``effective_restitution(law.chi)`` (§2.3), generally not ``e``.

    Attributes:
        stiffness: K > 0, N/m^n; from geometry with :mod:`jointplay.contact.stiffness`.
        restitution: the coefficient of restitution e in (0, 1] fed to χ(e).
        exponent: n > 0, default 1.5.
        v_floor: floor on the impact velocity, m/s (default 1e-4; module docstring).
    """

    #: The kernel evaluates every id from ``HC_FIRST`` to ``HC_LAST`` as this one force form;
    #: the registered laws carry their own ids only to be told apart, and a new χ(e) law may
    #: keep this inherited one (docs/contact-laws.md, "Adding a law").
    law_id: ClassVar[int] = ids.LAW_HUNT_CROSSLEY
    packing: ClassVar[tuple[str, ...]] = layout(
        ids.HC_SIZE,
        {ids.HC_STIFFNESS: "stiffness", ids.HC_EXPONENT: "exponent", ids.HC_CHI: "chi",
         ids.HC_V_FLOOR: "v_floor"},
    )  # fmt: skip
    needs_impact_velocity: ClassVar[bool] = True
    aliases: ClassVar[Mapping[str, str]] = MappingProxyType(
        {
            "k": "stiffness",
            "K": "stiffness",
            "e": "restitution",
            "cor": "restitution",
            "n": "exponent",
        }
    )

    stiffness: float
    restitution: float
    exponent: float = 1.5
    v_floor: float = DEFAULT_V_FLOOR

    def _validate(self) -> None:
        self._require("stiffness", self.stiffness > 0.0, "must be > 0 N/m^n")
        self._require(
            "restitution",
            0.0 < self.restitution <= 1.0,
            "must lie in (0, 1]",
            "use 1 for no damping, a small value such as 0.01 for a nearly plastic impact",
        )
        self._require("exponent", self.exponent > 0.0, "must be > 0", "use 1.5 for point contact")
        self._require("v_floor", self.v_floor > 0.0, "must be > 0 m/s", "the default is 1e-4")

    @staticmethod
    @abstractmethod
    def chi_of(e: float) -> float:
        """Hysteresis factor χ(e) of this model (dimensionless)."""

    @property
    def chi(self) -> float:
        """Hysteresis factor χ(e) for this law's restitution (dimensionless)."""
        return self.chi_of(self.restitution)

    def force(
        self,
        delta: npt.ArrayLike,
        delta_dot: npt.ArrayLike,
        v0: npt.ArrayLike | None = None,
    ) -> FloatArray:
        """Hunt–Crossley-type force, N. See the class and module docstrings."""
        return _hunt_crossley_force(
            self.stiffness, self.exponent, self.chi, self.v_floor, delta, delta_dot, v0
        )


@dataclass(frozen=True)
class HuntCrossleyLaw(HuntCrossleyTypeLaw):
    """Hunt & Crossley (1975): χ = 3(1 − e)/2, first order in 1 − e (docs/contact-laws.md §2.2).

    Attributes: see :class:`HuntCrossleyTypeLaw`.
    """

    name: ClassVar[str] = "hunt-crossley"
    law_id: ClassVar[int] = ids.LAW_HUNT_CROSSLEY
    citation: ClassVar[str] = "Hunt & Crossley (1975), J. Appl. Mech. 42:440–445; §2.2"
    equation: ClassVar[str] = "F = K δ^n (1 + 3(1-e)/2 · δ̇/v0)"

    @staticmethod
    def chi_of(e: float) -> float:
        """χ = 3(1 − e)/2."""
        return 3.0 * (1.0 - e) / 2.0


@dataclass(frozen=True)
class LankaraniNikraveshLaw(HuntCrossleyTypeLaw):
    """Lankarani & Nikravesh (1990): χ = 3(1 − e²)/4 (docs/contact-laws.md §2.2).

    Accurate only for e close to 1. Attributes: see :class:`HuntCrossleyTypeLaw`.
    """

    name: ClassVar[str] = "lankarani-nikravesh"
    law_id: ClassVar[int] = ids.LAW_LANKARANI_NIKRAVESH
    citation: ClassVar[str] = "Lankarani & Nikravesh (1990), J. Mech. Des. 112:369–376; §2.2"
    equation: ClassVar[str] = "F = K δ^n (1 + 3(1-e²)/4 · δ̇/v0)"

    @staticmethod
    def chi_of(e: float) -> float:
        """χ = 3(1 − e²)/4."""
        return 3.0 * (1.0 - e * e) / 4.0


@dataclass(frozen=True)
class FloresLaw(HuntCrossleyTypeLaw):
    """Flores et al. (2011): χ = 8(1 − e)/(5e) (docs/contact-laws.md §2.2).

    Attributes: see :class:`HuntCrossleyTypeLaw`.
    """

    name: ClassVar[str] = "flores"
    law_id: ClassVar[int] = ids.LAW_FLORES
    citation: ClassVar[str] = "Flores et al. (2011), Multibody Syst. Dyn. 25:357–375; §2.2"
    equation: ClassVar[str] = "F = K δ^n (1 + 8(1-e)/(5e) · δ̇/v0)"

    @staticmethod
    def chi_of(e: float) -> float:
        """χ = 8(1 − e)/(5e)."""
        return 8.0 * (1.0 - e) / (5.0 * e)


@dataclass(frozen=True)
class GonthierLaw(HuntCrossleyTypeLaw):
    """Gonthier et al. (2004): χ = (1 − e²)/e (docs/contact-laws.md §2.2).

    Attributes: see :class:`HuntCrossleyTypeLaw`.
    """

    name: ClassVar[str] = "gonthier"
    law_id: ClassVar[int] = ids.LAW_GONTHIER
    citation: ClassVar[str] = "Gonthier et al. (2004), Multibody Syst. Dyn. 11:209–233; §2.2"
    equation: ClassVar[str] = "F = K δ^n (1 + (1-e²)/e · δ̇/v0)"

    @staticmethod
    def chi_of(e: float) -> float:
        """χ = (1 − e²)/e."""
        return (1.0 - e * e) / e


@dataclass(frozen=True)
class HuGuoLaw(HuntCrossleyTypeLaw):
    """Hu & Guo (2015): χ = 3(1 − e)/(2e) — **constant unconfirmed** (docs/contact-laws.md §2.2).

    The paper's value is recalled, not checked: Skrinjar's code has 3(1 − e)/(4e) instead. We
    use 3(1 − e)/(2e) because it has the correct first-order limit 1.5(1 − e) as e → 1, which
    the code's value does not. Attributes: see :class:`HuntCrossleyTypeLaw`.
    """

    name: ClassVar[str] = "hu-guo"
    law_id: ClassVar[int] = ids.LAW_HU_GUO
    citation: ClassVar[str] = (
        "Hu & Guo (2015), Multibody Syst. Dyn. 35:131–151 (DOI 10.1007/s11044-015-9453-z); "
        "constant UNCONFIRMED, §2.2"
    )
    equation: ClassVar[str] = "F = K δ^n (1 + 3(1-e)/(2e) · δ̇/v0)"

    @staticmethod
    def chi_of(e: float) -> float:
        """χ = 3(1 − e)/(2e) (unconfirmed constant)."""
        return 3.0 * (1.0 - e) / (2.0 * e)


@dataclass(frozen=True)
class HerbertMcWhannellLaw(HuntCrossleyTypeLaw):
    """Herbert & McWhannell (1977): χ = 6(1 − e)/[(2e − 1)² + 3] (docs/contact-laws.md §2.2).

    Attributes: see :class:`HuntCrossleyTypeLaw`.
    """

    name: ClassVar[str] = "herbert-mcwhannell"
    law_id: ClassVar[int] = ids.LAW_HERBERT_MCWHANNELL
    citation: ClassVar[str] = "Herbert & McWhannell (1977), J. Eng. Ind. 99:513–518; §2.2"
    equation: ClassVar[str] = "F = K δ^n (1 + 6(1-e)/((2e-1)²+3) · δ̇/v0)"

    @staticmethod
    def chi_of(e: float) -> float:
        """χ = 6(1 − e)/[(2e − 1)² + 3]."""
        return 6.0 * (1.0 - e) / ((2.0 * e - 1.0) ** 2 + 3.0)


@dataclass(frozen=True)
class LeeWangLaw(HuntCrossleyTypeLaw):
    """Lee & Wang (1983): χ = 3(1 − e)/4 (docs/contact-laws.md §2.2).

    Attributes: see :class:`HuntCrossleyTypeLaw`.
    """

    name: ClassVar[str] = "lee-wang"
    law_id: ClassVar[int] = ids.LAW_LEE_WANG
    citation: ClassVar[str] = "Lee & Wang (1983), J. Mech. Transm. Autom. Des. 105:534–540; §2.2"
    equation: ClassVar[str] = "F = K δ^n (1 + 3(1-e)/4 · δ̇/v0)"

    @staticmethod
    def chi_of(e: float) -> float:
        """χ = 3(1 − e)/4."""
        return 3.0 * (1.0 - e) / 4.0


@dataclass(frozen=True)
class ZhiyingQishaoLaw(HuntCrossleyTypeLaw):
    """Zhiying & Qishao (2006): χ = 3(1 − e²) exp[2(1 − e)]/4 (docs/contact-laws.md §2.2).

    Attributes: see :class:`HuntCrossleyTypeLaw`.
    """

    name: ClassVar[str] = "zhiying-qishao"
    law_id: ClassVar[int] = ids.LAW_ZHIYING_QISHAO
    citation: ClassVar[str] = "Zhiying & Qishao (2006), J. Dyn. Control 4:294–298 (Chinese); §2.2"
    equation: ClassVar[str] = "F = K δ^n (1 + 3(1-e²) exp(2(1-e))/4 · δ̇/v0)"

    @staticmethod
    def chi_of(e: float) -> float:
        """χ = 3(1 − e²) exp[2(1 − e)]/4."""
        return 3.0 * (1.0 - e * e) * math.exp(2.0 * (1.0 - e)) / 4.0


#: Every normal contact law by registry name.
CONTACT_LAWS: dict[str, type[ContactLaw]] = {
    law.name: law
    for law in (
        ImpactLaw,
        RestitutionLaw,
        HertzLaw,
        KelvinVoigtLaw,
        HuntCrossleyLaw,
        LankaraniNikraveshLaw,
        FloresLaw,
        GonthierLaw,
        HuGuoLaw,
        HerbertMcWhannellLaw,
        LeeWangLaw,
        ZhiyingQishaoLaw,
    )
}


def get_law(law: str | ContactLaw, /, **params: Any) -> ContactLaw:
    """A normal contact law from a registry name plus parameters, or an instance.

    Names are case-insensitive; ``_`` and spaces count as ``-``. Parameters are the field names
    or their documented aliases (e.g. ``k``, ``e``, ``cmax``, ``d`` for ``impact``). Given an
    instance and parameters, returns a copy with those parameters replaced.

    Examples:
        >>> round(get_law("lankarani-nikravesh", stiffness=6.6e10, restitution=0.9).chi, 4)
        0.1425

    Raises:
        ConfigError: unknown name (the message lists the known ones), unknown or missing
            parameter, or a parameter out of range.
    """
    return _resolve(CONTACT_LAWS, "contact law", law, params)
