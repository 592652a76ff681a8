"""Clearance revolute joints: which joints rattle, by how much, and with which laws."""

from __future__ import annotations

import contextlib
import dataclasses
import math
from dataclasses import dataclass

import numpy as np

from jointplay._kernels import ids
from jointplay.contact.friction import FrictionLaw
from jointplay.contact.laws import ContactLaw
from jointplay.contact.stiffness import STIFFNESS_LAWS, get_stiffness_law
from jointplay.errors import ConfigError, SettingError

#: The smallest radial clearance modelled, m (1 nm): below it the joint is ideal in practice
#: and the contact arithmetic (onset tolerance, eccentricity ratios) underflows.
MIN_CLEARANCE = 1e-9


#: Penetrations over which a geometric stiffness law is fitted by ``F = k δ^n``, m: the fit
#: covers (FIT_DEPTH/100, FIT_DEPTH), the µm penetrations of steel pins at 10-1000 N.
FIT_DEPTH = 5e-6


@dataclass(frozen=True)
class JointStiffness:
    """How a joint's contact stiffness follows from its geometry and materials.

    A pin-in-hole law of :mod:`jointplay.contact.stiffness`, fitted by ``F = k δ^n`` over
    penetrations up to ``fit_depth`` (:meth:`PinInHoleStiffness.power_law_fit`), for the
    joint's pin radius and each clearance it is given (:meth:`fit`).

    Attributes:
        law: registry name of the pin-in-hole law (``liu``, ``hertz``, ``pereira``, ...).
        length: axial contact length L, m.
        bearing_youngs_modulus, bearing_poisson_ratio: the bearing's E (Pa) and ν.
        pin_youngs_modulus, pin_poisson_ratio: the pin's E (Pa) and ν.
        fit_depth: the largest penetration of the fit, m.
    """

    law: str
    length: float
    bearing_youngs_modulus: float
    bearing_poisson_ratio: float
    pin_youngs_modulus: float
    pin_poisson_ratio: float
    fit_depth: float = FIT_DEPTH

    def __post_init__(self) -> None:
        if self.law not in STIFFNESS_LAWS:
            raise ConfigError(
                f"unknown stiffness law {self.law!r}; known: {', '.join(sorted(STIFFNESS_LAWS))}"
            )
        if not (math.isfinite(self.fit_depth) and self.fit_depth > 0):
            raise ConfigError(f"the stiffness fit depth must be > 0 m, got {self.fit_depth!r}")

    def fit(self, pin_radius: float, clearance: float) -> tuple[float, float]:
        """``(k, n)`` of ``F = k δ^n`` (k in N/m^n) for a pin of ``pin_radius`` (m) in a hole
        ``clearance`` (m) larger in radius.

        Raises:
            ConfigError: the geometry is outside the law's range (e.g. Pereira's fit).
        """
        law = get_stiffness_law(
            self.law,
            bearing_radius=pin_radius + clearance,
            pin_radius=pin_radius,
            length=self.length,
            bearing_youngs_modulus=self.bearing_youngs_modulus,
            bearing_poisson_ratio=self.bearing_poisson_ratio,
            pin_youngs_modulus=self.pin_youngs_modulus,
            pin_poisson_ratio=self.pin_poisson_ratio,
        )
        return law.power_law_fit(self.fit_depth)

    def fits(self, pin_radius: float, clearances: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
        """:meth:`fit` of every clearance (``NaN`` where it fails), arrays of k and n."""
        k = np.full(len(clearances), np.nan)
        n = np.full(len(clearances), np.nan)
        for i, c in enumerate(np.asarray(clearances, dtype=float)):
            if math.isfinite(c) and c > 0:
                with contextlib.suppress(ConfigError):  # NaN: that sample fails
                    k[i], n[i] = self.fit(pin_radius, float(c))
        return k, n


#: The largest film damping c_e a joint's geometry gives, N·s/m (docs/contact.md, "Lubricated
#: by default"): above it the paper four-bar's settled peaks change by < 0.01 % (measured at 6
#: and 60 µm, 1e6 against 1e7), while a stiffer film costs more steps.
FILM_DAMPING_CAP = 1e6
#: The film forms a joint's film may take (docs/contact.md, "Reynolds films"), and their ids
#: in the kernels' ``geom`` table (``G_FILM_MODEL``): the linear isotropic damper −c_e ė
#: (a fixed film damping's form), the short-bearing Reynolds film with Gümbel's half-film
#: cavitation (:data:`DEFAULT_FILM_MODEL`), the short-bearing full (2π, uncavitated) film.
FILM_MODELS = {
    "linear": ids.FILM_LINEAR,
    "short-bearing-pi": ids.FILM_SHORT_PI,
    "short-bearing-full": ids.FILM_SHORT_FULL,
}
#: The film of a lubricated joint whose film follows its geometry and lubricant: the π-film,
#: the cavitated short-bearing film used for lubricated revolute clearance joints by Flores,
#: Ambrósio, Claro & Lankarani (2006) (docs/contact.md, "Reynolds films").
DEFAULT_FILM_MODEL = "short-bearing-pi"

#: Rq/Ra of a Gaussian surface profile, √(π/2) ≈ 1.25 (Whitehouse, *Handbook of Surface and
#: Nanometrology*; the usual Rq ≈ 1.25 Ra).
RQ_PER_RA = math.sqrt(math.pi / 2.0)
#: The default composite RMS roughness σ = √(Rq_pin² + Rq_hole²) of a ground pin (Ra 0.4 µm)
#: in a reamed hole (Ra 0.8 µm), m (≈ 1.12 µm): the Ra of grinding and of reaming in the
#: "surface roughness produced by common production methods" table of ASME B46.1 (Machinery's
#: Handbook), the finer half of each range (grinding 0.1–1.6 µm, reaming 0.4–3.2 µm), the
#: values ISO 1302 drawings give an H7/H8 bore and its pin (docs/contact.md, "The
#: film-to-contact transition").
DEFAULT_ROUGHNESS = RQ_PER_RA * math.hypot(0.4e-6, 0.8e-6)
#: The largest composite roughness a joint takes, m (a rough casting's Rq is ~ 30 µm; more is
#: a unit slip: '1.1 um', not 1.1).
MAX_ROUGHNESS = 1e-4


def film_model_id(model: str) -> int:
    """The kernels' id of the film form ``model`` (a key of :data:`FILM_MODELS`)."""
    if model not in FILM_MODELS:
        raise SettingError(
            "{film_model} must be one of " + ", ".join(FILM_MODELS) + ", got {got!r}",
            got=model,
        )
    return FILM_MODELS[model]


@dataclass(frozen=True)
class JointFilm:
    """How a lubricated joint's film coefficient follows from its geometry and its lubricant.

    The short-bearing squeeze-film coefficient of an open-ended, uncavitated film with the
    journal centred (docs/contact.md, "Lubricated by default")::

        C0 = π μ R L³ / c³

    the linear film's c_e, capped at ``cap``; a Reynolds film (``model``
    ``short-bearing-pi`` or ``short-bearing-full``, docs/contact.md, "Reynolds films") takes
    it uncapped, as the scale K = C0/π of its pressure integrals.

    Attributes:
        viscosity: the lubricant's dynamic viscosity μ, Pa·s (> 0).
        length: the bearing's axial length L, m.
        cap: the largest c_e of the linear film, N·s/m.
        model: the film's form, a key of :data:`FILM_MODELS` (default
            :data:`DEFAULT_FILM_MODEL`, the π-film).
    """

    viscosity: float
    length: float
    cap: float = FILM_DAMPING_CAP
    model: str = DEFAULT_FILM_MODEL

    def __post_init__(self) -> None:
        for name in ("viscosity", "length", "cap"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ConfigError(f"the film's {name} must be > 0, got {value!r}")
        film_model_id(self.model)

    def damping(self, journal_radius: float, clearance: float | np.ndarray) -> float | np.ndarray:
        """The film coefficient (N·s/m) of a journal of radius ``journal_radius`` (m) at
        radial clearance ``clearance`` (m; an array gives an array): the linear film's capped
        c_e, a Reynolds film's C0."""
        c = np.asarray(clearance, dtype=float)
        squeeze = math.pi * self.viscosity * journal_radius * self.length**3 / c**3
        film = np.minimum(squeeze, self.cap) if self.model == "linear" else squeeze
        return float(film) if film.ndim == 0 else film


def stiffness_field(law: ContactLaw) -> str:
    """The name of the stiffness field of a contact law (``penalty`` for ``restitution``), as
    the law declares it (:attr:`~jointplay.contact.laws.ContactLaw.stiffness_name`)."""
    return law.stiffness_name


@dataclass(frozen=True)
class ClearanceJoint:
    """A revolute joint modelled as a pin moving freely in its bearing until it hits the wall.

    Attributes:
        joint: name of a revolute joint of the mechanism (its ``link_a`` carries the bearing,
            its ``link_b`` the journal).
        clearance: radial clearance c = R_bearing − R_journal, m (> 0).
        journal_radius: pin radius R_J, m (> 0); the bearing radius is R_J + c.
        law: normal contact force law (an instance from :mod:`jointplay.contact.laws`).
        friction: friction law, or ``None`` (frictionless, the default).
        stiffness_from: the law's stiffness and exponent follow the joint's geometry this
            way (:meth:`with_clearance` refits them), or ``None``: they are fixed.
        capture_speed: the sustained-contact mode (docs/contact.md): a compliant contact
            whose normal relative speed |δ̇| falls below this speed (m/s) is locked onto
            |e| = c, its normal force a constraint multiplier, until that force turns
            tensile; 0 (the default): the compliant law throughout. Every clearance joint
            of one simulation takes the same value.
        film_damping: the film damping c_e (N·s/m, docs/contact.md): a lubricant film's
            squeeze damping lumped into −c_e ė on the journal's centre (ė: its velocity
            relative to the bearing's centre) and +c_e ė on the bearing's, in contact or
            not; 0 (the default): a dry joint. A simulation applies the smallest of its
            clearance joints' values to all of them (the engines take one); not with the
            sustained-contact mode.
        film_from: the film damping follows the joint's geometry and lubricant this way
            (:meth:`JointFilm.damping`, recomputed by :meth:`with_clearance`), or ``None``:
            ``film_damping`` is fixed.
        film_model: the film's form (:data:`FILM_MODELS`; ``film_from``'s when given):
            ``"linear"`` (the default), the damper above; ``"short-bearing-pi"`` or
            ``"short-bearing-full"``, the short-bearing Reynolds film (docs/contact.md,
            "Reynolds films"), its force from the eccentricity, its rate and the wedge, with
            ``film_damping`` its coefficient C0 = π μ R L³ / c³.
        roughness: the composite RMS roughness σ = √(Rq_pin² + Rq_hole²) of the pin and the
            hole, m (≥ 0; default :data:`DEFAULT_ROUGHNESS`, a ground pin in a reamed hole).
            Under a Reynolds film the asperities touch where the film thins to
            h_min = c − |e| = λ_t σ (λ_t = 3, :data:`jointplay._kernels.ids.LAMBDA_FULL_FILM`)
            and the contact law (with its friction) carries their share of the load beside
            the film (docs/contact.md, "The film-to-contact transition"); 0: the contact at
            the wall, as a dry joint's. Dry joints and the linear film do not use it for the
            forces (their contact is at |e| = c); the regimes reported use it for all.
    """

    joint: str
    clearance: float
    journal_radius: float
    law: ContactLaw
    friction: FrictionLaw | None = None
    stiffness_from: JointStiffness | None = None
    capture_speed: float = 0.0
    film_damping: float = 0.0
    film_from: JointFilm | None = None
    film_model: str = "linear"
    roughness: float = DEFAULT_ROUGHNESS

    def __post_init__(self) -> None:
        where = f"clearance joint {self.joint!r}"
        sigma = self.roughness
        if (
            isinstance(sigma, bool)
            or not isinstance(sigma, int | float)
            or not (math.isfinite(sigma) and 0 <= sigma <= MAX_ROUGHNESS)
        ):
            raise ConfigError(
                f"{where}: roughness must be a composite RMS roughness from 0 to "
                f"{MAX_ROUGHNESS:g} m, got {sigma!r}; give it in metres, e.g. 1.1e-6"
            )
        object.__setattr__(self, "roughness", float(sigma))
        if self.film_from is not None:
            object.__setattr__(self, "film_model", self.film_from.model)
        film_model_id(self.film_model)
        film = self.film_damping
        if (
            isinstance(film, bool)
            or not isinstance(film, int | float)
            or not (math.isfinite(film) and film >= 0)
        ):
            raise ConfigError(
                f"{where}: film_damping must be a damping coefficient >= 0 N*s/m (0: no "
                f"film), got {film!r}"
            )
        object.__setattr__(self, "film_damping", float(film))
        if film > 0 and self.capture_speed > 0:
            raise ConfigError(
                f"{where}: film damping does not combine with the sustained-contact mode "
                "(capture_speed > 0): use one of the two"
            )
        speed = self.capture_speed
        if (
            isinstance(speed, bool)
            or not isinstance(speed, int | float)
            or not (math.isfinite(speed) and speed >= 0)
        ):
            raise ConfigError(
                f"{where}: capture_speed must be a speed >= 0 m/s (0: no sustained-contact "
                f"mode), got {speed!r}"
            )
        object.__setattr__(self, "capture_speed", float(speed))
        if not isinstance(self.joint, str) or not self.joint:
            raise ConfigError(f"ClearanceJoint.joint must be a joint name, got {self.joint!r}")
        for field in ("clearance", "journal_radius"):
            value = getattr(self, field)
            if isinstance(value, bool) or not isinstance(value, int | float):
                raise ConfigError(
                    f"{where}: {field} must be a number in metres, got {value!r}; convert "
                    "text with units first, e.g. jointplay.units.parse_quantity('21 um', 'm', "
                    f"field='{field}')"
                )
            object.__setattr__(self, field, float(value))
        if not math.isfinite(self.clearance) or self.clearance < 0:
            raise ConfigError(
                f"{where}: radial clearance must be positive, got {self.clearance * 1e3:g} mm "
                "(a negative value would be an interference fit, which jointplay does not model)"
            )
        if 0 < self.clearance < MIN_CLEARANCE:
            raise ConfigError(
                f"{where}: a radial clearance of {self.clearance:.3g} m is below "
                f"{MIN_CLEARANCE:g} m (1 nm), smaller than any machined fit: leave the joint "
                "ideal instead, or check the unit (e.g. '0.021 mm')"
            )
        if self.clearance == 0:
            raise SettingError(
                "{where}: zero clearance — leave the joint ideal instead (omit it from {joints})",
                where=where,
            )
        if not (math.isfinite(self.journal_radius) and self.journal_radius > 0):
            raise ConfigError(
                f"{where}: journal (pin) radius must be > 0 m, got {self.journal_radius}"
            )
        if not isinstance(self.law, ContactLaw):
            raise ConfigError(
                f"{where}: law must be a ContactLaw instance, got {type(self.law).__name__}"
            )
        if self.friction is not None and not isinstance(self.friction, FrictionLaw):
            raise ConfigError(
                f"{where}: friction must be a FrictionLaw instance or None, got "
                f"{type(self.friction).__name__}"
            )
        if self.film_from is not None:
            film = float(self.film_from.damping(self.journal_radius, self.clearance))
            object.__setattr__(self, "film_damping", film)

    def with_clearance(self, clearance: float) -> ClearanceJoint:
        """This joint with another radial clearance (m); a geometric stiffness is refitted,
        a geometric film damping recomputed."""
        if self.stiffness_from is None:
            return dataclasses.replace(self, clearance=clearance)
        k, n = self.stiffness_from.fit(self.journal_radius, clearance)
        law = dataclasses.replace(self.law, **{stiffness_field(self.law): k, "exponent": n})
        return dataclasses.replace(self, clearance=clearance, law=law)

    @property
    def bearing_radius(self) -> float:
        """R_B = R_J + c, m."""
        return self.journal_radius + self.clearance
