"""From user-level settings (law names, quantities with units) to clearance joints.

Shared by the Python API, the TOML ``[simulation]`` table and every command that simulates.
The default contact is physical (docs/contact.md): per joint, a stiffness from the joint's
radii and materials (:data:`DEFAULT_STIFFNESS_LAW`), Hunt–Crossley damping with exactly the
coefficient of restitution :data:`DEFAULT_RESTITUTION` (the ``restitution`` law), friction
:data:`DEFAULT_FRICTION` at the wall, and lubricated pins: each joint's film damping from its
geometry and a lubricant of viscosity :data:`DEFAULT_VISCOSITY` (0: dry joints). The paper's
conventional IMPACT set, :data:`DEFAULT_IMPACT`, is the method ``ifm-conventional``.

Errors about a setting are :class:`~jointplay.errors.SettingError`: they call it by its
setting name (``stiffness``, ``c_max``, …), and the command line by its option.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import Any

from jointplay.contact.friction import FrictionLaw, get_friction
from jointplay.contact.laws import CONTACT_LAWS, ContactLaw, ImpactLaw, get_law
from jointplay.contact.stiffness import STIFFNESS_LAWS
from jointplay.dynamics.clearance import (
    DEFAULT_FILM_MODEL,
    FILM_DAMPING_CAP,
    FIT_DEPTH,
    MAX_ROUGHNESS,
    ClearanceJoint,
    JointFilm,
    JointStiffness,
    film_model_id,
)
from jointplay.dynamics.declared import setting, unit_of
from jointplay.errors import ConfigError, QuantityError, SettingError
from jointplay.model.lubricants import grade_viscosity, grade_words, parse_grade, split_regime
from jointplay.model.mechanism import REGIMES, Lubrication, Mechanism, RevoluteJoint
from jointplay.units import parse_quantity

#: The default IMPACT law: k = 1e4 N/mm^1.5 (= 1e4 · 1000^1.5 N/m^1.5), e = 1.5,
#: c_max = 10 N·s/mm (1e4 N·s/m), d_max = 0.1 mm (1e-4 m). These are the paper's conventional
#: Impact Force Method parameters (Table 3), so a default simulation is the paper's
#: conventional approach; this constant owns the numbers and
#: :data:`jointplay.study.published.TABLE3_IMPACT` names them for the paper study. Each field
#: is used where a setting leaves it unset.
DEFAULT_IMPACT = ImpactLaw(stiffness=1e4 * 1000**1.5, exponent=1.5, c_max=1e4, d_max=1e-4)

#: The physical default (docs/contact.md): the normal law (Hunt–Crossley damping with the
#: exact χ of the coefficient of restitution), the pin-in-hole stiffness law of every law
#: given no stiffness (Liu et al.'s elastic foundation for conformal cylinders), the
#: coefficient of restitution (steel on steel, as the paper cites) and the friction
#: coefficient of the command line (greased steel pins, boundary lubrication).
DEFAULT_LAW = "restitution"
DEFAULT_STIFFNESS_LAW = "liu"
DEFAULT_RESTITUTION = 0.8
DEFAULT_FRICTION = 0.1
#: The default capture speed of the sustained-contact mode, m/s (0.1 mm/s): a pin locked at
#: this normal speed rather than left to rebound with e·v would fly at most
#: (e v)² / (2 a) ≈ 3e-10 m from the wall under a relative acceleration a >= 10 m/s², far
#: below the ~6e-8 m Hertz approach of the pressed pins (docs/performance.md, issue 22).
DEFAULT_CAPTURE_SPEED = 1e-4
#: The lubricant of the physical default's pins, its dynamic viscosity in Pa·s
#: (docs/contact.md, "Lubricated by default"): a light machine oil at its working temperature
#: (ISO VG 46–68 at 40 °C, 0.04–0.06 Pa·s). Each joint's film damping follows from it and the
#: joint's geometry (:class:`~jointplay.dynamics.clearance.JointFilm`); 0: dry joints.
DEFAULT_VISCOSITY = 0.05

_HC_FAMILY = {name for name, cls in CONTACT_LAWS.items() if hasattr(cls, "chi_of")}

#: The numeric parameters of ContactSettings (each also names its setting in messages).
_PARAMETERS = ("stiffness", "exponent", "c_max", "depth", "restitution", "damping")
#: The parameters each contact law uses (any other one given is an error, not ignored).
_USES = {
    "impact": ("stiffness", "exponent", "c_max", "depth"),
    "restitution": ("stiffness", "exponent", "restitution"),
    "hertz": ("stiffness", "exponent"),
    "kelvin-voigt": ("stiffness", "exponent", "damping"),  # exponent: 1 only (linear)
    **{name: ("stiffness", "exponent", "restitution") for name in _HC_FAMILY},
}


def law_exponent(law: str, exponent: float | None = None) -> float:
    """The force exponent of contact law ``law``: ``exponent`` if given, else the law's
    default (1 for the linear laws ``restitution`` and ``kelvin-voigt``, else 1.5). It fixes
    the unit of the stiffness: N/m^exponent."""
    if exponent is not None:
        return exponent
    return 1.0 if law in ("restitution", "kelvin-voigt") else 1.5


def _real(value: Any, setting: str, *, text: bool = False) -> float:
    """``value`` as a finite float, or a SettingError about ``setting``; ``text``: a string
    holding a plain number is read too (settings that come as strings)."""
    if isinstance(value, bool) or not isinstance(value, int | float):
        try:
            if not (text and isinstance(value, str)):
                raise ValueError
            number = float(value)
        except ValueError:
            raise SettingError(
                f"{{{setting}}} must be a number, got {{got!r}}", got=value
            ) from None
    else:
        number = float(value)
    if not math.isfinite(number):
        raise SettingError(f"{{{setting}}} must be a finite number, got {{got!r}}", got=value)
    return number


def _zero_or_quantity(value: Any, unit: str, setting: str) -> float:
    """``value`` in ``unit``: a number, or text with a unit (:func:`_quantity`); a plain zero
    (``"0"``) needs no unit."""
    if not isinstance(value, str):
        return _real(value, setting)
    try:
        if float(value) == 0.0:
            return 0.0
    except ValueError:
        pass
    return _quantity(value, unit, setting)


def _quantity(value: Any, unit: str, setting: str, hint: str = "") -> float:
    """``value`` as a quantity in ``unit`` (:func:`~jointplay.units.parse_quantity`), or a
    SettingError about ``setting`` (``hint`` added to its message)."""
    try:
        return parse_quantity(value, unit, field=setting)
    except QuantityError as exc:  # the setting is named by the template, the rest is detail
        raise SettingError(
            f"{{{setting}}}: {{detail}}{{hint}}", detail=exc.detail, hint=hint
        ) from None


@dataclass(frozen=True)
class ContactSettings:
    """Which contact law and parameters the clearance joints use (SI; ``None`` = default).

    Attributes:
        law: registry name of the normal-force law (``impact``, ``restitution``, ``hertz``,
            ``kelvin-voigt``, ``hunt-crossley``, ``lankarani-nikravesh``, ``flores``, …).
        stiffness: k (N/m^exponent); penalty p for ``restitution``; K for the others.
        exponent: force exponent (default 1.5; 1.0 for ``restitution``).
        c_max: IMPACT's maximum damping, N·s/m.   depth: IMPACT's full-damping depth d, m.
        restitution: coefficient of restitution of ``restitution`` and the Hunt–Crossley
            family (default 0.8, steel on steel as the paper cites).
        damping: Kelvin–Voigt damping coefficient, N·s/m.
        stiffness_law: derive stiffness and exponent from the joint geometry and materials
            with this pin-in-hole law (``hertz``, ``johnson``, ``esdu-78035``, ``pereira``,
            ``liu``, ``radzimovsky``), fitted over penetrations up to ``fit_depth``; without
            it and without a stiffness, :data:`DEFAULT_STIFFNESS_LAW` (except ``impact``,
            whose default stiffness is the conventional one, and ``kelvin-voigt``): see
            :attr:`geometry_law`.
        fit_depth: the largest penetration of that fit, m.
    """

    law: str = DEFAULT_LAW
    stiffness: float | None = None
    exponent: float | None = None
    c_max: float | None = None
    depth: float | None = None
    restitution: float | None = None
    damping: float | None = None
    stiffness_law: str | None = None
    fit_depth: float = FIT_DEPTH

    @property
    def geometry_law(self) -> str | None:
        """The pin-in-hole law the stiffness comes from (``None``: a given or fixed one)."""
        if self.stiffness_law is not None:
            return self.stiffness_law
        if self.stiffness is None and self.law not in ("impact", "kelvin-voigt"):
            return DEFAULT_STIFFNESS_LAW
        return None

    def describe(self) -> str:
        """The contact in words, for summaries and reports."""
        if self.geometry_law is not None:
            stiffness = f"stiffness from each joint's geometry ({self.geometry_law} law)"
        elif self.stiffness is not None:
            stiffness = (
                f"stiffness {self.stiffness:.4g} N/m^{law_exponent(self.law, self.exponent):g}"
            )
        else:
            stiffness = "the conventional stiffness 1e4 N/mm^1.5"
        if self.law in ("restitution", *_HC_FAMILY):
            e = DEFAULT_RESTITUTION if self.restitution is None else self.restitution
            return f"{self.law} law, {stiffness}, coefficient of restitution {e:g}"
        return f"{self.law} law, {stiffness}"

    def __post_init__(self) -> None:
        if self.law not in CONTACT_LAWS:
            raise ConfigError(
                f"unknown contact law {self.law!r}; known: {', '.join(sorted(CONTACT_LAWS))}"
            )
        if self.stiffness_law is not None and self.stiffness_law not in STIFFNESS_LAWS:
            raise ConfigError(
                f"unknown stiffness law {self.stiffness_law!r}; known: {', '.join(sorted(STIFFNESS_LAWS))}"
            )
        for field in _PARAMETERS:
            value = getattr(self, field)
            if value is not None:
                _real(value, field)
        uses = _USES.get(self.law, _PARAMETERS)
        stray = [
            field for field in _PARAMETERS if getattr(self, field) is not None and field not in uses
        ]
        if stray:
            given = ", ".join(f"{{{field}}}" for field in stray)
            used = ", ".join(f"{{{field}}}" for field in uses)
            raise SettingError(
                f"{given} {'does' if len(stray) == 1 else 'do'} not apply to the contact law "
                f"{{name!r}}, which takes {used}; drop it or choose a law that uses it ({{law}})",
                name=self.law,
            )
        if self.law == "kelvin-voigt" and self.exponent not in (None, 1.0):
            _not_linear(self.exponent)
        if self.stiffness_law is not None and self.stiffness is not None:
            raise SettingError(
                "give either a stiffness ({stiffness}) or a stiffness law ({stiffness_law}), "
                "not both"
            )
        if self.stiffness_law is not None and self.law == "kelvin-voigt":
            raise SettingError(
                "{stiffness_law} fits a power law with its own exponent; the contact law "
                "'kelvin-voigt' is linear: drop {stiffness_law} or choose another {law}"
            )


def _not_linear(exponent: float) -> None:
    """Kelvin–Voigt is linear: refuse an ``exponent`` other than 1."""
    raise SettingError(
        "{exponent} {got:g} does not apply to the contact law 'kelvin-voigt', which is linear "
        "(F = K δ + D δ̇, stiffness in N/m): drop {exponent}",
        got=exponent,
    )


@dataclass(frozen=True)
class FrictionSettings:
    """Joint friction: ``law`` (``ambrosio`` or ``adams``) and its coefficient(s), off by default."""

    law: str = "ambrosio"
    coefficient: float = 0.0
    dynamic_coefficient: float | None = None

    def __post_init__(self) -> None:
        if self.law not in ("ambrosio", "adams"):
            raise SettingError(
                "{friction_law} must be ambrosio or adams, got {got!r}", got=self.law
            )
        mu = _real(self.coefficient, "friction")
        if mu < 0:
            raise SettingError(
                "{friction} must be >= 0 (0: no friction), got {got!r}", got=self.coefficient
            )
        object.__setattr__(self, "coefficient", mu)
        if self.dynamic_coefficient is not None:
            dynamic = _real(self.dynamic_coefficient, "dynamic friction coefficient")
            if dynamic < 0:
                raise ConfigError(
                    f"the dynamic friction coefficient must be >= 0, got {self.dynamic_coefficient!r}"
                )

    @property
    def enabled(self) -> bool:
        return self.coefficient > 0.0

    def build(self) -> FrictionLaw | None:
        if not self.enabled:
            return None
        if self.law == "ambrosio":
            return get_friction("ambrosio", mu=self.coefficient)
        if self.law == "adams":
            dynamic = (
                self.dynamic_coefficient
                if self.dynamic_coefficient is not None
                else self.coefficient
            )
            return get_friction(
                "adams",
                mu_static=self.coefficient,
                mu_dynamic=dynamic,
                v_static=1e-4,
                v_dynamic=1e-3,
            )
        raise ConfigError(f"unknown friction law {self.law!r}; use ambrosio or adams")


@dataclass(frozen=True)
class ContactModel:
    """The contact of every clearance joint, as every command that simulates takes it.

    Either ``settings`` (a law and its parameters, the stiffness from each joint's geometry
    unless given) or ``law``, a ready law object, e.g. one of the paper's six methods named
    ``method`` (its parameter record in ``record``); and the joints' friction.

    The default is the physical contact of docs/contact.md, with dry friction
    :data:`DEFAULT_FRICTION` (with a ``law`` too: give ``FrictionSettings()`` for none, as
    the command line does with its method option).

    ``sustained_contact`` (off by default) turns on the sustained-contact mode
    (docs/contact.md): a compliant contact whose normal speed falls below
    ``capture_speed`` (m/s, or text with a unit such as ``"0.1 mm/s"``; default
    :data:`DEFAULT_CAPTURE_SPEED`) is locked onto the bearing wall, its normal force a
    constraint multiplier, until that force turns tensile.

    The pins are lubricated (docs/contact.md, "Lubricated by default"): a film damps each
    journal's motion relative to its bearing, −c_e ė on the journal's centre, in contact or
    not. ``lubricant_viscosity`` (Pa·s, or text with a unit such as ``"0.05 Pa*s"``) gives
    c_e per joint from its geometry (:class:`~jointplay.dynamics.clearance.JointFilm`,
    recomputed for every sample's clearance); ``None`` takes :data:`DEFAULT_VISCOSITY` for
    the physical contact and none for a ready ``law`` (the paper's methods) or the
    sustained-contact mode; 0: dry joints. ``film_damping`` (N·s/m, or text such as
    ``"100 N*s/m"``) instead fixes c_e for every joint (the viscosity is then not used; 0:
    dry joints). Neither with ``sustained_contact``. ``film_model`` chooses the film's form
    (:data:`~jointplay.dynamics.clearance.FILM_MODELS`, docs/contact.md, "Reynolds films"):
    ``"short-bearing-pi"`` (the default) or ``"short-bearing-full"``, the short-bearing
    Reynolds film (π-film or full film) of each joint's geometry and lubricant
    (C0 = π μ R L³ / c³, uncapped; not with a fixed ``film_damping`` > 0), or ``"linear"``,
    the damper above (the default with a fixed ``film_damping``).
    """

    settings: ContactSettings = dataclasses.field(default_factory=ContactSettings)
    friction: FrictionSettings = dataclasses.field(
        default_factory=lambda: FrictionSettings(coefficient=DEFAULT_FRICTION)
    )
    law: ContactLaw | None = None
    method: str | None = None
    record: Mapping[str, Any] | None = None
    sustained_contact: bool = False
    capture_speed: float | str = DEFAULT_CAPTURE_SPEED
    film_damping: float | str | None = None
    lubricant_viscosity: float | str | None = None
    film_model: str | None = None
    lubrication: str | None = None
    roughness: float | str | None = None
    grade: int | None = None

    def __post_init__(self) -> None:
        self._take_grade()
        if self.film_model is not None:
            film_model_id(self.film_model)
        if self.roughness is not None:  # every joint's composite roughness σ, m
            sigma = _zero_or_quantity(self.roughness, unit_of("roughness"), "roughness")
            if not 0 <= sigma <= MAX_ROUGHNESS:
                raise SettingError(
                    f"{{roughness}} must be from 0 to {MAX_ROUGHNESS * 1e6:g} um, got {{got!r}}",
                    got=self.roughness,
                )
            object.__setattr__(self, "roughness", sigma)
        if not isinstance(self.sustained_contact, bool):
            raise SettingError(
                "{sustained_contact} must be true or false, got {got!r}",
                got=self.sustained_contact,
            )
        speed = (
            _quantity(self.capture_speed, "m/s", "capture_speed")
            if isinstance(self.capture_speed, str)
            else _real(self.capture_speed, "capture_speed")
        )
        if not speed > 0:
            raise SettingError(
                "{capture_speed} must be > 0 m/s (turn the mode off with "
                "{sustained_contact} instead), got {got!r}",
                got=self.capture_speed,
            )
        object.__setattr__(self, "capture_speed", speed)
        if self.lubrication is not None and self.lubrication not in REGIMES:
            raise SettingError(
                "{lubrication} must be one of " + ", ".join(REGIMES) + ", got {got!r} (an oil "
                "or a grease's base oil may be named by its ISO VG grade: 'oil ISO VG 46')",
                got=self.lubrication,
            )
        if self.film_damping is None:
            if self.lubricant_viscosity is not None:
                object.__setattr__(self, "lubricant_viscosity", self._given_viscosity())
        else:
            unit = unit_of("film_damping")
            film = _zero_or_quantity(self.film_damping, unit, "film_damping")
            if film < 0:
                raise SettingError(
                    f"{{film_damping}} must be >= 0 {unit} (0: dry joints), got {{got!r}}",
                    got=self.film_damping,
                )
            object.__setattr__(self, "film_damping", film)
            object.__setattr__(self, "lubricant_viscosity", None)  # not used
        self._check_regime()
        if self.film_model is None:  # a fixed film damping is the linear damper's c_e
            fixed = (self.fixed_film or 0.0) > 0
            object.__setattr__(self, "film_model", "linear" if fixed else DEFAULT_FILM_MODEL)
        if self.film_model != "linear" and (self.fixed_film or 0.0) > 0:
            raise SettingError(
                f"{{film_model}} {self.film_model} takes its coefficient from each joint's "
                "geometry and {lubricant_viscosity}: give no {film_damping} with it"
            )
        if self.lubricated and self.sustained_contact:
            raise SettingError(
                "{sustained_contact} runs dry joints: give {film_damping} 0 (or no "
                "{lubricant_viscosity}) with it"
            )

    def _take_grade(self) -> None:
        """An ISO VG grade named with the regime (``lubrication="oil ISO VG 46"``, or
        ``grade``) gives the lubricant's viscosity at 40 °C
        (:mod:`jointplay.model.lubricants`); not beside a viscosity or a film damping."""
        grade = self.grade
        if isinstance(self.lubrication, str):
            try:
                regime, named = split_regime(self.lubrication)
            except ConfigError as exc:
                detail = str(exc).split(": ", 1)[-1]
                raise SettingError("{lubrication}: {detail}", detail=detail) from None
            if named is not None:
                if grade is not None and grade != named:
                    raise SettingError(
                        "{lubrication} names ISO VG {named}, the grade given is ISO VG {grade}",
                        named=named,
                        grade=grade,
                    )
                object.__setattr__(self, "lubrication", regime)
                grade = named
        if grade is None:
            return
        try:
            grade = parse_grade(grade)
        except ConfigError as exc:
            detail = str(exc).split(": ", 1)[-1]
            raise SettingError("{lubrication}: {detail}", detail=detail) from None
        object.__setattr__(self, "grade", grade)
        if self.lubrication not in ("oil", "grease"):
            raise SettingError(
                "an ISO VG grade names an oil: give it as {lubrication} 'oil ISO VG {grade}' "
                "(or 'grease ISO VG {grade}', the base oil's)",
                grade=grade,
            )
        if self.lubricant_viscosity is not None or self.film_damping is not None:
            raise SettingError(
                "{lubrication} '{regime} ISO VG {grade}' names the lubricant's viscosity (at "
                "40 °C): give no {lubricant_viscosity} or {film_damping} with it (a joint at "
                "another temperature: {lubricant_viscosity} alone)",
                regime=self.lubrication,
                grade=grade,
            )

    def _given_viscosity(self) -> float:
        """The given lubricant's viscosity, Pa·s (>= 0; 0: dry)."""
        unit = unit_of("lubricant_viscosity")
        viscosity = _zero_or_quantity(self.lubricant_viscosity, unit, "lubricant_viscosity")
        if viscosity < 0:
            raise SettingError(
                f"{{lubricant_viscosity}} must be >= 0 {unit} (0: dry joints), got {{got!r}}",
                got=self.lubricant_viscosity,
            )
        return viscosity

    def _check_regime(self) -> None:
        """A named ``lubrication`` agrees with the viscosity or film damping given with it."""
        regime = self.lubrication
        given = self.lubricant_viscosity if self.film_damping is None else self.film_damping
        if regime == "dry" and given is not None and float(given) > 0:
            what = "{lubricant_viscosity}" if self.film_damping is None else "{film_damping}"
            raise SettingError(
                "{lubrication} dry runs the joints without a film: drop " + what + ", or name "
                "the film's lubricant ({lubrication} oil or grease)"
            )
        if regime in ("oil", "grease") and given is not None and float(given) == 0:
            raise SettingError(
                "{lubrication} " + regime + " needs a lubricant: give {lubricant_viscosity} > 0, "
                "or {lubrication} dry"
            )
        if regime == "grease" and given is None and self.grade is None:
            raise SettingError(
                "{lubrication} grease needs its base oil's viscosity: give {lubricant_viscosity}, "
                "e.g. '0.15 Pa*s'"
            )

    @property
    def overrides(self) -> bool:
        """The lubrication is named here (:attr:`lubrication`, :attr:`lubricant_viscosity`
        or :attr:`film_damping`): it holds at every joint, over the mechanism's declarations."""
        return (
            self.lubrication is not None
            or self.lubricant_viscosity is not None
            or self.film_damping is not None
        )

    @property
    def default_dry(self) -> bool:
        """Undeclared joints run dry by default: a contact law named (another than the
        physical default's :data:`DEFAULT_LAW`, or a ready law such as the paper's
        methods) or the sustained-contact mode; the physical default runs them in
        :data:`DEFAULT_VISCOSITY` oil (docs/contact.md, "Lubrication, declared per joint")."""
        return self.law is not None or self.sustained_contact or self.settings.law != DEFAULT_LAW

    @property
    def regime(self) -> str:
        """The regime of every joint that declares none (of every joint where
        :attr:`overrides`): ``dry``, ``oil`` or ``grease``."""
        if self.lubrication is not None:
            return self.lubrication
        if self.film_damping is not None:
            return "oil" if float(self.film_damping) > 0 else "dry"
        if self.lubricant_viscosity is not None:
            return "oil" if float(self.lubricant_viscosity) > 0 else "dry"
        return "dry" if self.default_dry else "oil"

    @property
    def viscosity(self) -> float:
        """The lubricant's viscosity of :attr:`regime`, Pa·s (0: dry, or a fixed film
        damping)."""
        if self.regime == "dry" or self.film_damping is not None:
            return 0.0
        if self.lubricant_viscosity is not None:
            return float(self.lubricant_viscosity)
        if self.grade is not None:
            return grade_viscosity(self.grade)
        return DEFAULT_VISCOSITY

    def lubrication_of(self, mechanism: Mechanism, joint: str) -> Lubrication:
        """The lubrication joint ``joint`` of ``mechanism`` runs in: this contact's where it
        :attr:`overrides`, else the joint's declaration (:meth:`Mechanism.lubrication_of`;
        an oil without a viscosity: :data:`DEFAULT_VISCOSITY`), else :attr:`regime`. A fixed
        film damping is an oil of no stated viscosity."""
        declared = None if self.overrides else mechanism.lubrication_of(joint)
        if declared is None:
            if self.regime == "dry":
                return Lubrication("dry")
            return Lubrication(self.regime, self.viscosity or None, self.grade)
        if declared.regime == "oil" and declared.viscosity is None:
            return Lubrication("oil", DEFAULT_VISCOSITY)
        return declared

    @property
    def integrator(self) -> str | None:
        """The integrator the paper method of this contact names (its parameter record's
        ``"integrator"``, :attr:`jointplay.study.methods.Method.integrator`); ``None``: no
        method, the solver's choice."""
        return None if self.record is None else self.record.get("integrator")

    @property
    def fixed_film(self) -> float | None:
        """The fixed film damping of every joint, N·s/m (0: dry joints), or ``None``: each
        joint's follows its geometry and the lubricant (:meth:`film_of`)."""
        return None if self.film_damping is None else float(self.film_damping)

    @property
    def lubricated(self) -> bool:
        """The joints that declare no lubrication (every joint where :attr:`overrides`) run
        in a film: a lubricant, or a fixed film damping > 0."""
        return self.regime != "dry"

    def film_of(self, mechanism: Mechanism, joint: str) -> JointFilm | None:
        """How joint ``joint``'s film damping follows its geometry (``None``: a fixed
        ``film_damping``, or dry): its lubricant (:meth:`lubrication_of`) and the bearing's
        width (:meth:`Mechanism.bearing_width`, else 10 mm, as the stiffness takes it)."""
        if self.fixed_film is not None:
            return None
        lubrication = self.lubrication_of(mechanism, joint)
        if lubrication.viscosity is None:  # dry
            return None
        width = mechanism.bearing_width(joint)
        return JointFilm(
            lubrication.viscosity, width or 0.01, model=self.film_model or DEFAULT_FILM_MODEL
        )

    @property
    def capture(self) -> float:
        """The clearance joints' capture speed, m/s: :attr:`capture_speed` with the
        sustained-contact mode on, 0 (off) otherwise."""
        return float(self.capture_speed) if self.sustained_contact else 0.0

    def joints(
        self,
        mechanism: Mechanism,
        names: Sequence[str] | None = None,
        *,
        clearance: float | None = None,
    ) -> list[ClearanceJoint]:
        """The clearance joints of ``mechanism`` with this contact (:func:`clearance_joints`)."""
        joints = clearance_joints(
            mechanism,
            names,
            contact=self.settings,
            friction=self.friction,
            clearance=clearance,
            law=self.law,
        )
        fixed = self.fixed_film
        if fixed is None:  # from each joint's geometry and the lubricant (None: dry)
            joints = [
                dataclasses.replace(joint, film_from=self.film_of(mechanism, joint.joint))
                for joint in joints
            ]
        elif fixed > 0:
            joints = [dataclasses.replace(joint, film_damping=fixed) for joint in joints]
        if self.roughness is not None:  # else each joint's own (DEFAULT_ROUGHNESS)
            sigma = float(self.roughness)
            joints = [dataclasses.replace(joint, roughness=sigma) for joint in joints]
        if not self.sustained_contact:
            return joints
        return [dataclasses.replace(joint, capture_speed=self.capture) for joint in joints]

    def describe(self, mechanism: Mechanism | None = None) -> dict[str, Any]:
        """The contact used, for ``summary.json`` and the reports: ``text`` in words, the
        method, the law's settings and the friction; with ``mechanism``, whose file declares
        lubrication this contact does not override, the text says the joints run as
        declared (:meth:`joint_lubrication` gives each)."""
        if self.law is not None:
            text = f"the paper's method {self.method}" if self.method else f"{self.law.name} law"
        else:
            text = self.settings.describe()
        friction = self.friction
        text += (
            f"; {friction.law} friction, coefficient {friction.coefficient:g}"
            if friction.enabled
            else "; no friction"
        )
        if self.sustained_contact:
            text += f"; sustained contact (captured below {self.capture * 1e3:g} mm/s)"
        fixed = self.fixed_film
        declares = mechanism is not None and bool(
            mechanism.lubrication or mechanism.joint_lubrication
        )
        if declares and not self.overrides:
            text += (
                "; each joint lubricated as the mechanism declares ([lubrication]; "
                f"undeclared joints {self.regime})"
            )
        elif not self.lubricated:
            text += "; dry joints (no film damping)"
        elif self.film_model != "linear":  # a Reynolds film: from the geometry, uncapped
            text += (
                f"; lubricated pins, {self._lubricant()}: "
                f"{self.film_model} Reynolds film from each joint's geometry"
            )
        elif fixed is None:
            text += (
                f"; lubricated pins, {self._lubricant()}: film damping "
                f"from each joint's geometry (squeeze film, at most {FILM_DAMPING_CAP:g} N*s/m)"
            )
        else:
            text += f"; lubricated pins, film damping {fixed:g} N*s/m"
        settings = {k: v for k, v in vars(self.settings).items() if v is not None}
        described: dict[str, Any] = {
            "text": text,
            "method": self.method,
            "settings": None if self.law is not None else settings,
            "stiffness_from_geometry": None if self.law is not None else self.settings.geometry_law,
            "friction": {"law": friction.law, "coefficient": friction.coefficient},
        }
        if self.sustained_contact:
            described["capture_speed_m_s"] = self.capture
        described["lubrication"] = {
            "regime": self.regime,
            "lubricated": self.lubricated,
            "lubricant_viscosity_Pa_s": self.viscosity or None,
            "film_damping_N_s_m": "from each joint's geometry"
            if fixed is None and self.lubricated
            else float(fixed or 0.0),
        }
        if self.grade is not None and self.lubricated:
            described["lubrication"]["iso_vg_grade"] = self.grade
        if self.film_model != "linear":
            described["lubrication"]["film_model"] = self.film_model
            described["lubrication"]["roughness_m"] = (
                "each joint's" if self.roughness is None else self.roughness
            )
        return described

    def _lubricant(self) -> str:
        """The lubricant of :attr:`regime` in words (``a 0.05 Pa*s oil``, ``an oil ISO VG 46
        (0.040 Pa*s at 40 °C)``)."""
        if self.grade is not None:
            base = "a grease of base oil" if self.regime == "grease" else "an oil"
            return f"{base} {grade_words(self.grade)}"
        if self.regime == "grease":
            return f"a grease of {self.viscosity:g} Pa*s base oil"
        return f"a {self.viscosity:g} Pa*s oil"

    def joint_lubrication(
        self, mechanism: Mechanism, joints: Sequence[ClearanceJoint]
    ) -> dict[str, dict[str, Any]]:
        """Per clearance joint, the lubrication it ran in, for ``summary.json``: ``regime``
        (``dry``, ``oil``, ``grease``), ``viscosity_Pa_s`` (``None``: dry, or a fixed film
        damping), ``film_model`` (``None``: dry), ``film_damping_N_s_m`` (its film
        coefficient; 0: dry) and ``declared`` (where the regime comes from: ``"command"``,
        ``"mechanism"`` or ``"default"``); with a lubricant named by its ISO VG grade,
        ``iso_vg_grade`` (the viscosity is then the grade's at 40 °C)."""
        out: dict[str, dict[str, Any]] = {}
        for joint in joints:
            entry = self._entry(mechanism, joint.joint)
            entry.pop("fixed_film_N_s_m")
            declared = entry.pop("declared")
            if joint.film_damping == 0:
                entry.update(regime="dry", viscosity_Pa_s=None, film_model=None)
                entry.pop("iso_vg_grade", None)
            out[joint.joint] = {
                **entry,
                "film_damping_N_s_m": joint.film_damping,
                "declared": declared,
            }
        return out

    def _entry(self, mechanism: Mechanism, joint: str) -> dict[str, Any]:
        """Joint ``joint``'s regime, viscosity, film model and where they are declared."""
        lubrication = self.lubrication_of(mechanism, joint)
        fixed = self.fixed_film
        dry = lubrication.regime == "dry" if fixed is None else fixed == 0
        declared = (
            "command"
            if self.overrides
            else "mechanism"
            if mechanism.lubrication_of(joint) is not None
            else "default"
        )
        entry = {
            "regime": "dry" if dry else lubrication.regime,
            "viscosity_Pa_s": None if dry else lubrication.viscosity,
            "film_model": None if dry else self.film_model,
            "fixed_film_N_s_m": fixed,
            "declared": declared,
        }
        if not dry and lubrication.grade is not None:
            entry["iso_vg_grade"] = lubrication.grade
        return entry

    def lubrication_table(
        self, mechanism: Mechanism, joints: Sequence[str]
    ) -> dict[str, dict[str, Any]]:
        """Per joint of ``joints`` (names), its ``regime``, ``viscosity_Pa_s``,
        ``film_model`` and ``declared`` (as :meth:`joint_lubrication`, before any clearance
        is known: a study's)."""
        out = {}
        for name in joints:
            entry = self._entry(mechanism, name)
            entry.pop("fixed_film_N_s_m")
            out[name] = entry
        return out

    def regime_words(self, mechanism: Mechanism, joints: Sequence[str]) -> str:
        """The lubrication of the clearance joints ``joints`` (names) in words, for the
        first line of a run and the verdicts: ``lubricated, 0.05 Pa*s oil`` where every
        joint runs in one lubricant, ``dry`` where none has a film, else joint by joint
        (``O2 dry; A, B lubricated, 0.05 Pa*s oil``)."""
        groups: dict[str, list[str]] = {}
        for name in joints:
            groups.setdefault(_regime_words(self._entry(mechanism, name)), []).append(name)
        if len(groups) == 1:
            return next(iter(groups))
        return "; ".join(f"{', '.join(names)} {text}" for text, names in groups.items())


def regime_line(contact: ContactModel, mechanism: Mechanism, joints: Sequence[str]) -> str:
    """The first line of a dynamic run: the lubrication of its clearance joints ``joints``
    (names): ``lubrication: lubricated, 0.05 Pa*s oil (O2, A, B, O4)``, ``lubrication: dry
    (O2)``, or joint by joint."""
    words = contact.regime_words(mechanism, joints)
    if ";" in words:
        return f"lubrication: {words}"
    return f"lubrication: {words} ({', '.join(joints)})"


def _regime_words(entry: Mapping[str, Any]) -> str:
    """One joint's :meth:`ContactModel._entry` in words."""
    if entry["regime"] == "dry":
        return "dry"
    viscosity = entry["viscosity_Pa_s"]
    if viscosity is None:
        return f"lubricated, film damping {entry['fixed_film_N_s_m']:g} N*s/m"
    lubricant = "grease base oil" if entry["regime"] == "grease" else "oil"
    # the film is named where it is not the default π-film (summary.json names it always)
    film = "" if entry["film_model"] == DEFAULT_FILM_MODEL else f", {entry['film_model']} film"
    grade = entry.get("iso_vg_grade")
    if grade is not None:  # "lubricated, oil ISO VG 46 (0.040 Pa*s at 40 °C)"
        return f"lubricated, {lubricant} {grade_words(grade)}{film}"
    return f"lubricated, {viscosity:g} Pa*s {lubricant}{film}"


#: The name of the paper's conventional contact set: its method ``ifm-conventional`` (the
#: command line's method option takes the same name), the IMPACT law :data:`DEFAULT_IMPACT`
#: without friction. Not the default: a tuned convenience, one argument away
#: (``contact="ifm-conventional"`` in the Python API).
CONVENTIONAL = "ifm-conventional"


def conventional_contact() -> ContactModel:
    """The paper's conventional contact set :data:`CONVENTIONAL` as a :class:`ContactModel`:
    :data:`DEFAULT_IMPACT` for every joint, no friction (as the method ``ifm-conventional`` on the command line)."""
    return ContactModel(friction=FrictionSettings(), law=DEFAULT_IMPACT, method=CONVENTIONAL)


def resolve_contact(contact: str | ContactLaw | ContactModel | None) -> ContactModel | ContactLaw:
    """The contact a Python API call means: ``None`` the physical default ``ContactModel()``
    (as every command), :data:`CONVENTIONAL` the paper's conventional set
    (:func:`conventional_contact`), another name the contact law of that name with its default
    parameters (frictionless), an object itself."""
    if contact is None:
        return ContactModel()
    if isinstance(contact, str):
        named = contact.strip().lower().replace("_", "-").replace(" ", "-")
        return conventional_contact() if named == CONVENTIONAL else get_law(contact)
    return contact


def make_law(
    settings: ContactSettings, *, stiffness: float | None = None, exponent: float | None = None
) -> ContactLaw:
    """The contact law of ``settings``; ``stiffness``/``exponent`` override (geometry fits)."""
    k = stiffness if stiffness is not None else settings.stiffness
    n = exponent if exponent is not None else settings.exponent
    name = settings.law
    if name == "impact":
        return get_law(
            "impact",
            stiffness=DEFAULT_IMPACT.stiffness if k is None else k,
            exponent=DEFAULT_IMPACT.exponent if n is None else n,
            c_max=DEFAULT_IMPACT.c_max if settings.c_max is None else settings.c_max,
            d_max=DEFAULT_IMPACT.d_max if settings.depth is None else settings.depth,
        )
    if k is None:
        raise SettingError(
            "contact law {name!r} needs a stiffness: give {stiffness} (or stiffness in "
            "[simulation])",
            name=name,
        )
    if name == "restitution":
        return get_law(
            name,
            penalty=k,
            restitution=DEFAULT_RESTITUTION
            if settings.restitution is None
            else settings.restitution,
            exponent=1.0 if n is None else n,
        )
    if name == "hertz":
        return get_law(name, stiffness=k, exponent=1.5 if n is None else n)
    if name == "kelvin-voigt":
        if settings.damping is None:
            raise SettingError(
                "contact law 'kelvin-voigt' needs a damping coefficient: give {damping}"
            )
        return get_law(name, stiffness=k, damping=settings.damping)
    if name in _HC_FAMILY:
        return get_law(
            name,
            stiffness=k,
            restitution=DEFAULT_RESTITUTION
            if settings.restitution is None
            else settings.restitution,
            exponent=1.5 if n is None else n,
        )
    raise ConfigError(f"contact law {name!r} cannot be built from these settings")


def clearance_joints(
    mechanism: Mechanism,
    joints: Sequence[str] | None = None,
    *,
    contact: ContactSettings | None = None,
    friction: FrictionSettings | None = None,
    clearance: float | None = None,
    journal_radius: float | None = None,
    law: ContactLaw | None = None,
) -> list[ClearanceJoint]:
    """Clearance joints for ``joints`` (default: every revolute joint with a clearance in its fit).

    The clearance and the journal radius come from each joint's fit data (diameter / 2) unless
    given; a joint with neither gets a clear error. ``law`` (a ready contact-law object, e.g.
    one of the paper's methods) takes the place of ``contact``.
    ``contact`` and ``friction`` are the bare settings (``None``: the default law,
    frictionless); the physical default of every command, friction included, is
    ``ContactModel().joints(mechanism)``.
    """
    contact = contact or ContactSettings()
    friction = friction or FrictionSettings()
    revolute = {j.name: j for j in mechanism.joints if isinstance(j, RevoluteJoint)}
    if joints is None:
        joints = [name for name, j in revolute.items() if j.fit is not None and j.fit.clearance]
        if not joints:
            raise SettingError(
                "mechanism {name!r} has no joint with a clearance; name them with {joints}",
                name=mechanism.name,
            )
    result = []
    for name in joints:
        if name not in revolute:
            raise ConfigError(
                f"no revolute joint {name!r} in {mechanism.name!r}; revolute joints: {', '.join(revolute)}"
            )
        fit = revolute[name].fit
        c = clearance if clearance is not None else (fit.clearance if fit else None)
        if c is None:
            raise SettingError(
                "joint {name!r} has no clearance in its fit data: give {clearance}", name=name
            )
        r = journal_radius if journal_radius is not None else (fit.diameter / 2 if fit else None)
        if r is None:
            r = 0.005
        _check_fits(mechanism, name, c, r)
        geometry = None if law is not None else joint_stiffness(mechanism, name, contact)
        joint = ClearanceJoint(
            name,
            clearance=c,
            journal_radius=r,
            # a stiffness from the geometry: a placeholder, fitted by with_clearance
            law=law or make_law(contact, stiffness=None if geometry is None else 1.0),
            friction=friction.build(),
            stiffness_from=geometry,
        )
        result.append(joint if geometry is None else joint.with_clearance(c))
    return result


def _check_fits(mechanism: Mechanism, joint: str, clearance: float, radius: float) -> None:
    """A bearing of diameter 2 (radius + clearance) must fit on the shortest link."""
    sizes = [
        max(math.dist(p, q) for p in link.points.values() for q in link.points.values())
        for link in mechanism.links
        if len(link.points) > 1
    ]
    if not sizes:
        return
    shortest = min(sizes)
    bearing = 2.0 * (radius + clearance)
    if bearing >= shortest:
        raise ConfigError(
            f"clearance joint {joint!r}: a radial clearance of {clearance * 1e3:g} mm makes a "
            f"bearing {bearing * 1e3:g} mm across, larger than the shortest link "
            f"({shortest * 1e3:g} mm): impossible geometry (radial clearances are µm, e.g. "
            "'0.021 mm')"
        )


def joint_stiffness(
    mechanism: Mechanism, joint: str, contact: ContactSettings
) -> JointStiffness | None:
    """How joint ``joint``'s stiffness follows its geometry under ``contact`` (``None``: it
    does not): the law :attr:`ContactSettings.geometry_law`, the bearing's and the pin's
    materials (the links ``link_a`` and ``link_b`` of the joint) and the contact length
    (:meth:`Mechanism.bearing_width`, else 10 mm)."""
    name = contact.geometry_law
    if name is None:
        return None
    spec = mechanism.joint(joint)
    bearing = mechanism.material_of(spec.link_a)
    pin = mechanism.material_of(spec.link_b)
    length = mechanism.bearing_width(joint)
    return JointStiffness(
        law=name,
        length=length if length is not None else 0.01,
        bearing_youngs_modulus=bearing.youngs_modulus,
        bearing_poisson_ratio=bearing.poisson_ratio,
        pin_youngs_modulus=pin.youngs_modulus,
        pin_poisson_ratio=pin.poisson_ratio,
        fit_depth=contact.fit_depth,
    )


def parse_stiffness(text: Any, exponent: float, *, setting: str = "stiffness") -> float:
    """A stiffness with units for force exponent ``exponent``: ``"1e4 N/mm^1.5"`` → N/m^1.5.

    Raises:
        SettingError: not such a quantity (about ``setting``).
    """
    unit = "N/m" if exponent == 1 else f"N/m^{exponent:g}"
    written = "N/mm" if exponent == 1 else f"N/mm^{exponent:g}"
    hint = f" (with force exponent {exponent:g} the stiffness is in {written} or {unit})"
    return _quantity(text, unit, setting, hint)


def _declared(values: Mapping[str, Any], key: str) -> Any:
    """``values[key]`` (``None``: not given) read as its declared setting
    (:func:`jointplay.dynamics.declared.setting`) says: a quantity in its unit, a plain number
    (a string holding one too), or text as it is."""
    value = values.get(key)
    if value is None:
        return None
    declared = setting(key)
    if declared.unit is not None:
        return _quantity(value, declared.unit, declared.name)
    if declared.kind is float:
        return _real(value, declared.name, text=True)
    return value


def contact_from_strings(values: Mapping[str, Any]) -> ContactSettings:
    """ContactSettings from strings with units (CLI options or the TOML ``[simulation]`` table).

    Keys: contact, k, exponent, cmax, depth, restitution, damping, stiffness_law, fit_depth
    (:data:`~jointplay.dynamics.declared.CONTACT_SETTINGS` declares their units).
    """
    law = values.get("contact") or DEFAULT_LAW
    if not isinstance(law, str):
        raise SettingError("{law} must be the name of a contact law, got {got!r}", got=law)
    exponent = _declared(values, "exponent")
    if exponent is None and values.get("contact") is None and values.get("k") is not None:
        exponent = 1.5  # a stiffness given to the default law: a power law as Hertz's
    if exponent is not None and not exponent > 0:
        raise SettingError("{exponent} must be > 0, got {got}", got=exponent)
    if law == "kelvin-voigt" and exponent not in (None, 1.0):
        _not_linear(exponent)
    stiffness = values.get("k")
    fit_depth = _declared(values, "fit_depth")
    settings = ContactSettings(
        law=law,
        stiffness=None
        if stiffness is None
        else parse_stiffness(stiffness, law_exponent(law, exponent)),
        exponent=exponent,
        c_max=_declared(values, "cmax"),
        depth=_declared(values, "depth"),
        restitution=_declared(values, "restitution"),
        damping=_declared(values, "damping"),
        stiffness_law=_declared(values, "stiffness_law"),
        fit_depth=FIT_DEPTH if fit_depth is None else fit_depth,
    )
    # Validate the parameters early, with the law's own messages (a geometry-derived
    # stiffness is only known per joint, so a placeholder stands in for it here).
    make_law(settings, stiffness=1.0 if settings.geometry_law else None)
    return settings
