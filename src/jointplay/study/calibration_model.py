"""Calibration, part 1: the data sets, the parameters and the model evaluated for them.

:class:`Dataset` (one measured response), :class:`Parameter` (start, bounds, scale),
:class:`DynamicSettings` (the clearance model), the default parameters of a mechanism and
:class:`_Model`, which evaluates every data set's response for a parameter vector: the
nominal (ideal-joint) mechanism, or the steady cycle of the clearance model once a dynamic
parameter is fitted. Units are SI. The whole method is described in
:mod:`jointplay.study.calibration`, which stays the import path of everything here.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
from numpy.typing import ArrayLike, NDArray

from jointplay.dynamics.cycles import settle_revolutions
from jointplay.dynamics.setup import (
    DEFAULT_IMPACT,
    ContactSettings,
    FrictionSettings,
    clearance_joints,
)
from jointplay.dynamics.simulate import SolverOptions, Start, simulate
from jointplay.errors import ConfigError
from jointplay.io.measurements import Measurements
from jointplay.kinematics.analysis import analyse
from jointplay.model.mechanism import Mechanism, RevoluteJoint
from jointplay.model.templates import with_lengths
from jointplay.study.comparison import nominal_cycle
from jointplay.tolerance.spec import template_lengths

FloatArray = NDArray[np.float64]

#: Parameters of the nominal model (the template lengths add ``<length>-length``).
KINEMATIC_PARAMETERS = ("crank-speed", "phase")
#: Parameters of the clearance model's contact and friction laws.
DYNAMIC_PARAMETERS = ("k", "c_max", "clearance", "restitution", "friction")
_ANGULAR_SPEED = "rad/s"


# --- data sets and responses ---------------------------------------------------------------


def response_unit(quantity: str) -> tuple[str, bool]:
    """The SI unit of a simulated response column and whether it is signed.

    ``omega{k}`` rad/s, ``alpha{k}`` rad/s², ``F_{joint}``/``Fn_{joint}`` N (magnitudes),
    ``Ft_{joint}`` N, ``torque`` N·m, ``{slider}_x``/``_v``/``_a`` m, m/s, m/s².

    Raises:
        ConfigError: not a response jointplay can fit.
    """
    if quantity.startswith("omega"):
        return _ANGULAR_SPEED, True
    if quantity.startswith("alpha"):
        return "rad/s^2", True
    if quantity.startswith(("F_", "Fn_")):
        return "N", False
    if quantity.startswith("Ft_"):
        return "N", True
    if quantity == "torque":
        return "N*m", True
    for suffix, unit in (("_x", "m"), ("_v", "m/s"), ("_a", "m/s^2")):
        if quantity.endswith(suffix) and len(quantity) > 2:
            return unit, True
    raise ConfigError(
        f"cannot fit {quantity!r}: give a simulated response such as omega4 (rad/s), alpha4 "
        "(rad/s^2), F_O2 (N) or torque (N*m)"
    )


@dataclass(frozen=True, eq=False)
class Dataset:
    """One measurement file: a response at crank angles, and the crank speed of the run.

    Attributes:
        measurements: crank angles and values with their conventions
            (:mod:`jointplay.io.measurements`). For an angular speed (``omega…``) the
            conventions' unit and sign apply; for any other response ``unit_factor`` does.
        quantity: the simulated response measured (:func:`response_unit`), default the rocker
            speed ``omega4``.
        crank_speed: the crank speed of the run, rad/s (``None``: the mechanism's).
        unit_factor: SI units per unit of the file's values, for responses other than angular
            speeds (e.g. 1 for N, π/180 for deg/s²); signed responses take the conventions'
            ``speed_sign`` too.
        unit: the file's unit, for reports.
        label: a short name (the file's stem), for parameter names and reports.
        sigma: optional standard deviation of the measurement errors, SI (weights the data
            set; default: see the module docstring).
    """

    measurements: Measurements
    quantity: str = "omega4"
    crank_speed: float | None = None
    unit_factor: float = 1.0
    unit: str = ""
    label: str = "data"
    sigma: float | None = None

    def __post_init__(self) -> None:
        _, _ = response_unit(self.quantity)
        if self.crank_speed is not None and not (
            math.isfinite(self.crank_speed) and self.crank_speed > 0
        ):
            raise ConfigError(f"Dataset {self.label}: crank_speed must be > 0 rad/s")
        if not (math.isfinite(self.unit_factor) and self.unit_factor > 0):
            raise ConfigError(f"Dataset {self.label}: unit_factor must be > 0")
        if self.sigma is not None and not (math.isfinite(self.sigma) and self.sigma > 0):
            raise ConfigError(f"Dataset {self.label}: sigma must be > 0 (SI)")
        if not self.unit:
            unit = (
                self.measurements.conventions.unit
                if self.angular_speed
                else response_unit(self.quantity)[0]
            )
            object.__setattr__(self, "unit", unit)

    @property
    def angular_speed(self) -> bool:
        return self.quantity.startswith("omega")

    @property
    def si_unit(self) -> str:
        return response_unit(self.quantity)[0]

    @property
    def crank_deg_model(self) -> FloatArray:
        """Crank angles, degrees counter-clockwise from the ground line (before any phase)."""
        return self.measurements.crank_deg_model

    def to_si(self, values: ArrayLike) -> FloatArray:
        """File values → SI (counter-clockwise positive for signed responses)."""
        conventions = self.measurements.conventions
        if self.angular_speed:
            return conventions.speed_to_si(values)
        sign = conventions.speed_sign if response_unit(self.quantity)[1] else 1
        return sign * self.unit_factor * np.asarray(values, dtype=float)

    def from_si(self, values: ArrayLike) -> FloatArray:
        """SI → the file's unit and sign."""
        conventions = self.measurements.conventions
        if self.angular_speed:
            return conventions.speed_from_si(values)
        sign = conventions.speed_sign if response_unit(self.quantity)[1] else 1
        return sign * np.asarray(values, dtype=float) / self.unit_factor

    @property
    def values_si(self) -> FloatArray:
        """The measured values, SI."""
        return self.to_si(self.measurements.speed)


# --- the parameters --------------------------------------------------------------------------


@dataclass(frozen=True)
class Parameter:
    """A parameter to fit: its start value, bounds and unit (SI).

    Attributes:
        name: ``crank-speed``, ``crank-speed@LABEL``, ``phase``, ``<length>-length``, ``k``,
            ``c_max``, ``clearance``, ``restitution`` or ``friction``.
        initial: start value, SI.
        lower, upper: bounds, SI.
        unit: SI unit.
        scale: typical size (the optimiser works on value / scale).
        dynamic: needs the clearance model.
    """

    name: str
    initial: float
    lower: float
    upper: float
    unit: str
    scale: float
    dynamic: bool = False

    def __post_init__(self) -> None:
        if not (self.lower <= self.initial <= self.upper):
            raise ConfigError(
                f"parameter {self.name}: start {self.initial:g} {self.unit} lies outside its "
                f"bounds [{self.lower:g}, {self.upper:g}]"
            )
        if not (math.isfinite(self.scale) and self.scale > 0):
            raise ConfigError(f"parameter {self.name}: scale must be > 0, got {self.scale}")


@dataclass(frozen=True)
class DynamicSettings:
    """The clearance model fitted when a dynamic parameter is (SI).

    Attributes:
        contact: the contact law and its parameters (default: the paper's IMPACT, Table 3,
            whose stiffness ``k`` is the parameter a calibration fits; ``jointplay
            calibrate`` passes its contact options, the physical default without them).
        friction: the friction law (default off; fitting ``friction`` switches it on).
        clearance: radial clearance of every clearance joint, m (default: the fit data).
        joints: clearance joints (default: every joint with a clearance in its fit data).
        settle: start-up revolutions left out before the evaluated one (default 2).
        solver: integration settings.
    """

    contact: ContactSettings = field(default_factory=lambda: ContactSettings(law="impact"))
    friction: FrictionSettings = field(default_factory=FrictionSettings)
    clearance: float | None = None
    joints: tuple[str, ...] | None = None
    settle: int = 2
    solver: SolverOptions | None = None

    def __post_init__(self) -> None:
        settle_revolutions(self.settle, "DynamicSettings: settle")


def parameter_names(mechanism: Mechanism, datasets: Sequence[Dataset]) -> tuple[str, ...]:
    """Every parameter that can be fitted for ``mechanism`` and ``datasets``."""
    speeds = (
        ("crank-speed",)
        if len(datasets) <= 1
        else tuple(f"crank-speed@{d.label}" for d in datasets)
    )
    lengths = tuple(f"{name}-length" for name in template_lengths(mechanism))
    return (*speeds, "phase", *lengths, *DYNAMIC_PARAMETERS)


def _expand(names: Sequence[str], datasets: Sequence[Dataset]) -> list[str]:
    """``crank-speed`` expands to one parameter per data set when there are several."""
    out: list[str] = []
    for name in names:
        if name == "crank-speed" and len(datasets) > 1:
            out += [f"crank-speed@{d.label}" for d in datasets]
        else:
            out.append(name)
    return list(dict.fromkeys(out))


def _stiffness_unit(exponent: float) -> str:
    return "N/m" if exponent == 1 else f"N/m^{exponent:g}"


def default_parameters(
    mechanism: Mechanism,
    datasets: Sequence[Dataset],
    names: Sequence[str],
    settings: DynamicSettings | None = None,
    *,
    initial: Mapping[str, float] | None = None,
) -> list[Parameter]:
    """Start values, bounds, units and scales of the parameters ``names`` (module docstring).

    Args:
        initial: start values (SI) that replace the defaults, by name.

    Raises:
        ConfigError: unknown name, a length without a tolerance, a start outside its bounds.
    """
    settings = settings or DynamicSettings()
    initial = dict(initial or {})
    known = parameter_names(mechanism, datasets)
    expanded = _expand(names, datasets)
    unknown = [n for n in list(initial) + expanded if n not in known and n != "crank-speed"]
    if unknown:
        raise ConfigError(
            f"unknown parameter(s) {', '.join(dict.fromkeys(unknown))}; "
            f"fit some of {', '.join(known)}"
        )
    lengths = template_lengths(mechanism)
    tolerances = {t.length: t for t in mechanism.tolerances}
    contact = settings.contact
    out = []
    for name in expanded:
        start = initial.get(name)
        if name.startswith("crank-speed"):
            label = name.partition("@")[2]
            data = next((d for d in datasets if d.label == label), datasets[0])
            omega = data.crank_speed or mechanism.driver.speed
            start = initial.get("crank-speed", omega) if start is None else start
            out.append(Parameter(name, start, omega / 4, omega * 4, "rad/s", omega))
        elif name == "phase":
            out.append(
                Parameter(name, 0.0 if start is None else start, -math.pi, math.pi, "rad", 1.0)
            )
        elif name.endswith("-length"):
            length = name.removesuffix("-length")
            if length not in tolerances:
                raise ConfigError(
                    f"parameter {name}: the mechanism has no tolerance on its {length} length; "
                    'add one under [tolerances] (e.g. general = "m") to bound the fit'
                )
            nominal = lengths[length]
            tol = tolerances[length]
            value = nominal if start is None else start
            out.append(
                Parameter(name, value, nominal + tol.lower, nominal + tol.upper, "m", nominal)
            )
        elif name == "k":
            k0 = contact.stiffness if contact.stiffness is not None else _default_stiffness(contact)
            value = k0 if start is None else start
            exponent = stiffness_exponent(contact)
            out.append(
                Parameter(name, value, k0 / 1e3, k0 * 1e3, _stiffness_unit(exponent), k0, True)
            )
        elif name == "c_max":
            if contact.law != "impact":
                raise ConfigError(f"c_max is a parameter of the impact law, not of {contact.law!r}")
            c0 = contact.c_max if contact.c_max is not None else DEFAULT_IMPACT.c_max
            value = c0 if start is None else start
            out.append(Parameter(name, value, 0.0, c0 * 1e3, "N*s/m", c0, True))
        elif name == "restitution":
            if contact.law in ("impact", "hertz", "kelvin-voigt"):
                raise ConfigError(
                    f"the {contact.law!r} law has no restitution; fit it with the restitution "
                    "or a Hunt-Crossley-type law"
                )
            e0 = contact.restitution if contact.restitution is not None else 0.8
            value = e0 if start is None else start
            out.append(Parameter(name, value, 0.05, 1.0, "1", 1.0, True))
        elif name == "friction":
            mu0 = settings.friction.coefficient or 0.05
            value = mu0 if start is None else start
            out.append(Parameter(name, value, 0.0, 0.5, "1", 0.1, True))
        elif name == "clearance":
            c0, low, high = _clearance_range(mechanism, settings)
            value = c0 if start is None else start
            out.append(Parameter(name, value, low, high, "m", c0, True))
    return out


def stiffness_exponent(contact: ContactSettings) -> float:
    """The force exponent of ``contact``'s law (default 1.5; 1 for ``restitution``)."""
    if contact.exponent is not None:
        return contact.exponent
    if contact.law == "restitution":
        return 1.0
    return DEFAULT_IMPACT.exponent if contact.law == "impact" else 1.5


def _default_stiffness(contact: ContactSettings) -> float:
    if contact.law == "impact":
        return DEFAULT_IMPACT.stiffness
    raise ConfigError(
        f"fitting k with the {contact.law!r} law needs a start value: give the stiffness"
    )


def _clearance_range(mechanism: Mechanism, settings: DynamicSettings) -> tuple[float, float, float]:
    """Start, lower and upper radial clearance, m (ISO 286 fit range when the joints have one)."""
    joints = [j for j in mechanism.revolute_joints if j.fit is not None]
    if settings.joints is not None:
        joints = [j for j in joints if j.name in settings.joints]
    fitted = [j for j in joints if j.fit is not None and j.fit.clearance]
    c0 = settings.clearance
    if c0 is None:
        if not fitted:
            raise ConfigError(
                "fitting the clearance needs a start value: the joints have no clearance"
            )
        fit0 = fitted[0].fit
        assert fit0 is not None and fit0.clearance is not None
        c0 = float(fit0.clearance)
    low, high = c0 / 10, c0 * 3
    first: RevoluteJoint | None = fitted[0] if fitted else None
    if first is not None and first.fit is not None and first.fit.fit:
        from jointplay.tolerance.iso286 import fit as iso_fit

        try:
            bearing = iso_fit(first.fit.fit, first.fit.diameter)
        except Exception:  # any unreadable designation: keep the generic range
            bearing = None
        if bearing is not None and bearing.radial_clearance_max > 0:
            low = max(bearing.radial_clearance_min, c0 / 100)
            high = bearing.radial_clearance_max
            low, high = min(low, c0), max(high, c0)
    return c0, low, high


# --- the model ------------------------------------------------------------------------------


def _nominal_at(mechanism: Mechanism, quantity: str, theta_deg: FloatArray) -> FloatArray:
    """A response of the ideal mechanism at crank angles (deg CCW), SI."""
    if quantity.startswith("omega"):
        return nominal_cycle(mechanism, quantity=quantity, step_deg=60.0).at(theta_deg)
    from jointplay.dynamics.inverse import inverse_dynamics
    from jointplay.dynamics.nominal import kinematics_table

    driver = mechanism.driver
    start = math.degrees(driver.start_angle)
    travelled = np.mod(driver.direction * (theta_deg - start), 360.0)
    order = np.argsort(travelled, kind="stable")
    kin = analyse(mechanism, np.radians(start + driver.direction * travelled[order]))
    table = kinematics_table(kin, inverse_dynamics(kin))
    if quantity not in table:
        raise ConfigError(
            f"the nominal model has no response {quantity!r}; it has "
            f"{', '.join(c for c in table.columns if c != 'crank_deg')}"
        )
    out = np.empty_like(theta_deg)
    out[order] = table[quantity].to_numpy()
    return out


@dataclass(frozen=True, eq=False)
class _Model:
    """Evaluates the responses of every data set for a parameter vector (SI)."""

    mechanism: Mechanism
    datasets: tuple[Dataset, ...]
    parameters: tuple[Parameter, ...]
    settings: DynamicSettings
    dynamic: bool

    def mechanism_for(self, values: Mapping[str, float], dataset: Dataset) -> Mechanism:
        lengths = {
            name.removesuffix("-length"): value
            for name, value in values.items()
            if name.endswith("-length")
        }
        mechanism = with_lengths(self.mechanism, **lengths) if lengths else self.mechanism
        speed = values.get(
            f"crank-speed@{dataset.label}",
            values.get("crank-speed", dataset.crank_speed or self.mechanism.driver.speed),
        )
        if speed != mechanism.driver.speed:
            mechanism = mechanism.with_driver(speed=speed)
        return mechanism

    def response(
        self, values: Mapping[str, float], dataset: Dataset, crank_deg_model: FloatArray
    ) -> FloatArray:
        """The response (SI) at crank angles in degrees CCW (before the phase)."""
        mechanism = self.mechanism_for(values, dataset)
        theta = crank_deg_model + math.degrees(values.get("phase", 0.0))
        if not self.dynamic:
            return _nominal_at(mechanism, dataset.quantity, theta)
        return _steady_response(mechanism, dataset.quantity, theta, values, self.settings)

    def vector(self, x: FloatArray) -> dict[str, float]:
        return {p.name: float(v * p.scale) for p, v in zip(self.parameters, x, strict=True)}


def _steady_response(
    mechanism: Mechanism,
    quantity: str,
    theta_deg: FloatArray,
    values: Mapping[str, float],
    settings: DynamicSettings,
) -> FloatArray:
    """The clearance model's steady revolution at crank angles (deg CCW), SI."""
    contact = settings.contact
    changes: dict[str, Any] = {}
    if "k" in values:
        changes["stiffness"] = values["k"]
    if "c_max" in values:
        changes["c_max"] = values["c_max"]
    if "restitution" in values:
        changes["restitution"] = values["restitution"]
    if changes:
        contact = replace(contact, **changes)
    friction = settings.friction
    if "friction" in values:
        friction = replace(friction, coefficient=values["friction"])
    clearance = values.get("clearance", settings.clearance)
    joints = clearance_joints(
        mechanism,
        list(settings.joints) if settings.joints is not None else None,
        contact=contact,
        friction=friction,
        clearance=clearance,
    )
    result = simulate(
        mechanism,
        joints,
        revolutions=1,
        settle=settings.settle,
        start=Start("steady"),
        solver=settings.solver,
    )
    driver = mechanism.driver
    start = math.degrees(driver.start_angle)
    fraction = np.mod(driver.direction * (theta_deg - start), 360.0) / 360.0
    times = (settings.settle + fraction) * driver.period
    times = np.minimum(times, float(result.t[-1]))
    columns = result.evaluate(np.ascontiguousarray(times, dtype=float))
    if quantity not in columns:
        raise ConfigError(
            f"the clearance model has no response {quantity!r}; it has "
            f"{', '.join(c for c in columns if c not in ('t', 'crank_deg'))}"
        )
    return np.asarray(columns[quantity], dtype=float)
