"""Calibration: the model's uncertain parameters fitted to measurements, with uncertainties.

A user with a test rig measured some response of the mechanism (the rocker speed, an
acceleration, a joint force) at known crank angles. This module fits the parameters of the
model that the user is unsure of to those measurements by nonlinear least squares and says
how well the data determine them.

The parameters (:data:`KINEMATIC_PARAMETERS`, :data:`DYNAMIC_PARAMETERS`)
    * ``crank-speed`` (rad/s): the rig's crank speed. With several data sets each has its own,
      named ``crank-speed@LABEL`` (runs at different speeds); bounds ¼ to 4 times the start.
    * ``phase`` (rad): an offset of the crank-angle origin, shared by all data sets. The model
      is evaluated at the file's crank angle (converted as :mod:`jointplay.io.measurements`
      says) *plus* ``phase``, counter-clockwise; bounds ±180°.
    * ``<length>-length`` (m) for each template length (four-bar: ``crank``, ``coupler``,
      ``rocker``, ``ground``): bounds from the mechanism's length tolerances.
    * ``k`` (N/m^exponent), ``c_max`` (N·s/m), ``restitution`` (-), ``friction`` (-, the
      Coulomb coefficient of the Ambrós friction law) and ``clearance`` (m, radial, every
      clearance joint): the contact model. Bounds: 10⁻³ to 10³ times the start for ``k``,
      0 to 10³ times for ``c_max``, (0.05, 1] for ``restitution``, [0, 0.5] for ``friction``,
      and the radial clearance range of the joints' ISO 286 fit for ``clearance`` (else a tenth
      to three times the start).

The model
    With only kinematic parameters the model is the nominal (ideal-joint) mechanism: angular
    speeds come from :func:`jointplay.study.comparison.nominal_cycle` (closed form for the
    four-bar), other responses from the kinematics and inverse dynamics at exactly the measured
    angles. As soon as a dynamic parameter is fitted every evaluation is the *steady cycle of
    the clearance model*: :func:`jointplay.dynamics.simulate.simulate` from the nominal steady
    motion with :attr:`DynamicSettings.settle` start-up revolutions left out, the response read
    on the continuous solution of the next revolution at the measured crank angles.

The fit (:func:`calibrate`)
    :func:`scipy.optimize.least_squares` (trust-region reflective, bounds, optional robust
    ``loss``) minimises Σ wᵢ² (simulatedᵢ − measuredᵢ)². Every data set's residuals are in SI
    units (w = 1) when all data sets measure the same kind of response; with mixed kinds each
    is divided by the RMS of its measurements, so that they count alike (or by ``sigma`` when a
    :class:`Dataset` gives one). The parameters are scaled by their start values for the
    optimiser; the Jacobian is by forward differences (relative step :data:`KINEMATIC_STEP` on
    the nominal model, :data:`DYNAMIC_STEP` on the clearance model, whose solution carries the
    integrator's error).

Uncertainties
    From the Jacobian J at the optimum, the usual linearisation: cov = s² (JᵀJ)⁻¹ with
    s² = RSS / (m − p), m residuals and p parameters (the residual variance estimated from
    the fit itself: it assumes independent errors of equal variance within the weighting, and
    a model that can explain the data). 95 % intervals are value ± t₀.₉₇₅(m − p) · stderr
    (Student-t). With a robust loss, scipy's Jacobian is the loss-weighted one and RSS is that
    of the raw residuals: the intervals are then approximate.

Identifiability warnings
    A parameter the data cannot determine is flagged when the column-normalised JᵀJ is
    near-singular (condition number above :data:`CONDITION_LIMIT`; its smallest singular
    direction names the parameters that trade off), when a parameter has no effect (a zero
    Jacobian column), when its 95 % interval is wider than its bounds, or when it ends on a
    bound (where the linearised interval is meaningless). On the clearance model a parameter
    whose forward differences at 1× and 3× the step disagree by more than
    :data:`ROUGHNESS_LIMIT` is flagged too: its response is rough (the impact sequence
    changes with it), so a local fit and its interval cannot be trusted. An interval that
    reaches beyond a bound (e.g. a stiffness interval that includes zero) is reported as
    poorly determined, and strong correlations (|r| > :data:`CORRELATION_LIMIT`) as
    parameters determined only in combination.

Errors as the paper defines them
    error % = (measured − simulated) / simulated × 100 (Table 7), with points whose |simulated|
    is below :data:`jointplay.study.comparison.LOW_SPEED_FRACTION` of the largest left out,
    as :func:`jointplay.study.comparison.compare` does. ``rms_before``/``rms_after`` are RMS
    error % before and after the fit.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field, replace
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray
from scipy import optimize, stats

from jointplay.dynamics.cycles import settle_revolutions
from jointplay.dynamics.setup import (
    DEFAULT_IMPACT,
    ContactSettings,
    FrictionSettings,
    clearance_joints,
)
from jointplay.dynamics.simulate import SolverOptions, Start, simulate
from jointplay.errors import ConfigError, IntegrationError, SettingError
from jointplay.io.measurements import Measurements, frozen_array, paper_table7
from jointplay.kinematics.analysis import analyse
from jointplay.model.mechanism import Mechanism, RevoluteJoint
from jointplay.model.templates import with_lengths
from jointplay.study.comparison import (
    LOW_SPEED_FRACTION,
    error_percent,
    nominal_cycle,
    rig_mechanism,
)
from jointplay.tolerance.spec import template_lengths

FloatArray = NDArray[np.float64]

#: Parameters of the nominal model (the template lengths add ``<length>-length``).
KINEMATIC_PARAMETERS = ("crank-speed", "phase")
#: Parameters of the clearance model's contact and friction laws.
DYNAMIC_PARAMETERS = ("k", "c_max", "clearance", "restitution", "friction")
#: Robust losses of :func:`scipy.optimize.least_squares`.
LOSSES = ("linear", "soft_l1", "huber", "cauchy", "arctan")
#: Condition number of the column-normalised JᵀJ above which the fit is called unidentifiable
#: (a correlation of 1 − 2e-6 between two parameters; finite-difference noise keeps exact
#: trade-offs far above it, at 1e8 or more).
CONDITION_LIMIT = 1e6
#: |correlation| above which a pair is reported as determined only in combination.
CORRELATION_LIMIT = 0.99
#: Relative forward-difference step on the nominal (closed-form, smooth) model.
KINEMATIC_STEP = 1e-7
#: Relative forward-difference step on the clearance model: well above the integrator's
#: relative error (1e-6) so that the differences measure the parameter, not the solver.
DYNAMIC_STEP = 1e-2
#: On the clearance model the Jacobian is also taken with steps of 1 and 3 times
#: :data:`DYNAMIC_STEP`; a parameter whose two columns differ by more than this fraction has a
#: rough response (impact sequences that change with it) and gets an identifiability warning.
ROUGHNESS_LIMIT = 0.3
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


# --- results --------------------------------------------------------------------------------


@dataclass(frozen=True)
class ParameterEstimate:
    """A fitted parameter (SI).

    Attributes:
        name, unit: as in :class:`Parameter`.
        value: the estimate.
        stderr: its standard error from the Jacobian (``inf`` if not determined).
        ci95: 95 % interval, value ± t·stderr (Student-t, m − p degrees of freedom).
        initial, lower, upper: start and bounds.
    """

    name: str
    value: float
    stderr: float
    ci95: tuple[float, float]
    unit: str
    initial: float
    lower: float
    upper: float

    def as_dict(self) -> dict[str, Any]:
        """The issue's shape: value, stderr, ci95, unit."""
        return {
            "value": self.value,
            "stderr": self.stderr,
            "ci95": list(self.ci95),
            "unit": self.unit,
        }


@dataclass(frozen=True)
class ErrorStatistics:
    """Agreement with the measurements (the paper's error %, and residuals in SI)."""

    rms_error_percent: float
    max_abs_error_percent: float
    n_percent_points: int
    rms_residual: float

    def as_dict(self) -> dict[str, Any]:
        return {
            "rms_error_percent": self.rms_error_percent,
            "max_abs_error_percent": self.max_abs_error_percent,
            "n_percent_points": self.n_percent_points,
            "rms_weighted_residual": self.rms_residual,
        }


@dataclass(frozen=True, eq=False)
class CalibrationResult:
    """What a calibration found.

    Attributes:
        parameters: the estimates, in the order fitted.
        covariance: their covariance, SI (``inf`` rows for undetermined parameters).
        correlation: their correlation matrix (NaN where undefined).
        warnings: identifiability and convergence warnings, one line each.
        before, after: error statistics at the start values and at the estimates.
        points: one row per measured point: ``dataset``, ``quantity``, ``crank_deg`` (file),
            ``measured``, ``before``, ``after`` (file unit), ``residual_before``/``_after``
            (measured − simulated, SI), ``error_percent_before``/``_after`` and ``low_speed``.
        curves: the simulated response over a revolution before and after (file units), for
            plots: ``dataset``, ``crank_deg`` (file), ``before``, ``after``.
        datasets: the data sets fitted.
        model: ``"nominal"`` (ideal joints) or ``"clearance"`` (steady cycle).
        loss, dof, s2, condition_number: the fit's loss, m − p, residual variance
            RSS / (m − p) (weighted units) and condition number of the column-normalised JᵀJ.
        nfev, status, message: scipy's counters and verdict.
        mechanism: the mechanism as driven in the rig's direction (before the fit).
    """

    parameters: tuple[ParameterEstimate, ...]
    covariance: FloatArray
    correlation: FloatArray
    warnings: tuple[str, ...]
    before: ErrorStatistics
    after: ErrorStatistics
    points: pd.DataFrame
    curves: pd.DataFrame
    datasets: tuple[Dataset, ...]
    model: str
    loss: str
    dof: int
    s2: float
    condition_number: float
    nfev: int
    status: int
    message: str
    mechanism: Mechanism

    @property
    def values(self) -> dict[str, float]:
        """The estimates by name, SI."""
        return {p.name: p.value for p in self.parameters}

    def estimate(self, name: str) -> ParameterEstimate:
        for p in self.parameters:
            if p.name == name:
                return p
        raise KeyError(name)

    @property
    def rms_before(self) -> float:
        return self.before.rms_error_percent

    @property
    def rms_after(self) -> float:
        return self.after.rms_error_percent

    def as_json(self) -> dict[str, Any]:
        """The issue's JSON shape (SI units)."""
        return {
            "parameters": {p.name: p.as_dict() for p in self.parameters},
            "rms_before": self.rms_before,
            "rms_after": self.rms_after,
            "warnings": list(self.warnings),
        }

    def as_dict(self) -> dict[str, Any]:
        """Everything, for calibration.json."""
        names = [p.name for p in self.parameters]
        return {
            **self.as_json(),
            "parameter_details": {
                p.name: {**p.as_dict(), "initial": p.initial, "bounds": [p.lower, p.upper]}
                for p in self.parameters
            },
            "correlation": {"parameters": names, "matrix": self.correlation.tolist()},
            "covariance": {"parameters": names, "matrix": self.covariance.tolist()},
            "error_definition": "(measured - simulated) / simulated * 100 (paper, Table 7); "
            f"points with |simulated| < {LOW_SPEED_FRACTION:g} x max left out",
            "uncertainty": "cov = s^2 (J^T J)^-1 at the optimum, s^2 = RSS / (m - p); "
            "ci95 = value +- t_0.975(m - p) * stderr",
            "before": self.before.as_dict(),
            "after": self.after.as_dict(),
            "model": self.model,
            "loss": self.loss,
            "dof": self.dof,
            "s2": self.s2,
            "condition_number": self.condition_number,
            "nfev": self.nfev,
            "status": self.status,
            "message": self.message,
            "datasets": [
                {
                    "label": d.label,
                    "source": d.measurements.source,
                    "quantity": d.quantity,
                    "unit": d.unit,
                    "si_unit": d.si_unit,
                    "points": int(d.measurements.crank_deg.size),
                    "crank_speed_rad_s": d.crank_speed or self.mechanism.driver.speed,
                    "conventions": d.measurements.conventions.as_dict(),
                }
                for d in self.datasets
            ],
            "points": self.points.to_dict(orient="records"),
        }


# --- the fit --------------------------------------------------------------------------------


def _weights(datasets: Sequence[Dataset]) -> list[float]:
    mixed = len({d.si_unit for d in datasets}) > 1
    out = []
    for d in datasets:
        if d.sigma is not None:
            out.append(1.0 / d.sigma)
        elif mixed:
            rms = float(np.sqrt(np.mean(d.values_si**2)))
            out.append(1.0 / rms if rms > 0 else 1.0)
        else:
            out.append(1.0)
    return out


def _statistics(
    measured: Sequence[FloatArray], simulated: Sequence[FloatArray], weights: Sequence[float]
) -> tuple[ErrorStatistics, list[FloatArray], list[NDArray[np.bool_]]]:
    errors: list[FloatArray] = []
    lows: list[NDArray[np.bool_]] = []
    residuals: list[FloatArray] = []
    for meas, sim, w in zip(measured, simulated, weights, strict=True):
        err = error_percent(meas, sim)
        threshold = LOW_SPEED_FRACTION * float(np.max(np.abs(sim))) if sim.size else 0.0
        low = (np.abs(sim) < threshold) | ~np.isfinite(err)
        errors.append(err)
        lows.append(low)
        residuals.append(w * (meas - sim))
    kept = np.concatenate([e[~lo] for e, lo in zip(errors, lows, strict=True)])
    res = np.concatenate(residuals)
    return (
        ErrorStatistics(
            rms_error_percent=float(np.sqrt(np.mean(kept**2))) if kept.size else math.nan,
            max_abs_error_percent=float(np.max(np.abs(kept))) if kept.size else math.nan,
            n_percent_points=int(kept.size),
            rms_residual=float(np.sqrt(np.mean(res**2))),
        ),
        errors,
        lows,
    )


def _uncertainty(
    jac: FloatArray, residuals: FloatArray, scales: FloatArray
) -> tuple[FloatArray, FloatArray, float, float, int, FloatArray]:
    """Covariance (SI), stderr, s², condition number, dof, and the weakest direction."""
    m, p = jac.shape
    dof = m - p
    rss = float(residuals @ residuals)
    s2 = rss / dof if dof > 0 else math.nan
    norms = np.sqrt(np.sum(jac**2, axis=0))
    safe = np.where(norms > 0, norms, 1.0)
    normalised = jac / safe
    _, sv, vt = np.linalg.svd(normalised, full_matrices=False)
    smax = float(sv[0]) if sv.size else 0.0
    condition = (smax / float(sv[-1])) ** 2 if sv.size and sv[-1] > 0 else math.inf
    tiny = sv <= smax * 1e-12
    with np.errstate(divide="ignore"):
        inv_sv2 = np.where(tiny, np.inf, 1.0 / np.where(tiny, 1.0, sv) ** 2)
    v = vt.T  # columns: singular directions
    # cov_n = s² V diag(1/σ²) Vᵀ in normalised coordinates; undetermined directions → inf.
    finite = ~tiny
    cov_n = (v[:, finite] * inv_sv2[finite]) @ v[:, finite].T
    undetermined = np.any(np.abs(v[:, tiny]) > 1e-6, axis=1) if np.any(tiny) else np.zeros(p, bool)
    undetermined |= norms == 0
    cov = s2 * cov_n / np.outer(safe, safe) * np.outer(scales, scales)
    cov[undetermined, :] = np.inf
    cov[:, undetermined] = np.inf
    with np.errstate(invalid="ignore"):
        stderr = np.sqrt(np.diag(cov))
    return cov, stderr, s2, condition, dof, v[:, -1] if sv.size else np.zeros(p)


def calibrate(
    mechanism: Mechanism,
    datasets: Sequence[Dataset],
    fit: Sequence[str],
    *,
    settings: DynamicSettings | None = None,
    initial: Mapping[str, float] | None = None,
    parameters: Sequence[Parameter] | None = None,
    loss: str = "linear",
    max_nfev: int | None = None,
    curve_step_deg: float = 2.0,
) -> CalibrationResult:
    """Fit the parameters ``fit`` to the data sets (see the module docstring).

    Args:
        mechanism: the model (driven in the rig's crank direction here if it is not).
        datasets: one or more measurement files; they must share the crank direction.
        fit: parameter names (:func:`parameter_names`); ``crank-speed`` expands to one per data
            set when there are several.
        settings: the clearance model, used when a dynamic parameter is fitted.
        initial: start values (SI) by name, replacing the defaults.
        parameters: ready :class:`Parameter` objects (start, bounds, scale) instead of
            ``fit``/``initial``'s defaults.
        loss: ``linear`` (least squares) or a robust loss of scipy (:data:`LOSSES`).
        max_nfev: cap on model evaluations (default: 100 per parameter on the nominal model,
            20 per parameter on the clearance model).
        curve_step_deg: crank-angle step of the plotted curves, degrees.

    Raises:
        ConfigError: no data, an unknown parameter or loss, mixed crank directions.
        IntegrationError: a simulation of the clearance model failed.
    """
    if not datasets:
        raise ConfigError("calibrate: no measurements")
    if loss not in LOSSES:
        raise ConfigError(f"unknown loss {loss!r}; use one of {', '.join(LOSSES)}")
    labels = [d.label for d in datasets]
    if len(set(labels)) != len(labels):
        raise ConfigError(f"calibrate: data set labels must differ, got {', '.join(labels)}")
    directions = {d.measurements.conventions.crank_direction for d in datasets}
    if len(directions) > 1:
        raise ConfigError("calibrate: the data sets disagree on the crank direction")
    mechanism = rig_mechanism(mechanism, datasets[0].measurements.conventions)
    settings = settings or DynamicSettings()
    params = (
        tuple(parameters)
        if parameters is not None
        else tuple(default_parameters(mechanism, datasets, fit, settings, initial=initial))
    )
    if not params:
        raise SettingError("calibrate: no parameter to fit; name some with {fit}")
    dynamic = any(p.dynamic for p in params)
    model = _Model(mechanism, tuple(datasets), params, settings, dynamic)
    weights = _weights(datasets)
    measured = [d.values_si for d in datasets]
    angles = [d.crank_deg_model for d in datasets]
    m = sum(a.size for a in angles)

    def simulate_all(x: FloatArray) -> list[FloatArray]:
        values = model.vector(x)
        return [model.response(values, d, a) for d, a in zip(datasets, angles, strict=True)]

    def residuals(x: FloatArray) -> FloatArray:
        try:
            sims = simulate_all(x)
        except IntegrationError:
            return np.full(m, 1e6)  # a failed simulation: a large, finite penalty
        return np.concatenate(
            [w * (s - y) for s, y, w in zip(sims, measured, weights, strict=True)]
        )

    scales = np.array([p.scale for p in params])
    x0 = np.array([p.initial / p.scale for p in params])
    lower = np.array([p.lower / p.scale for p in params])
    upper = np.array([p.upper / p.scale for p in params])
    # least_squares needs lower < upper; a fixed interval (zero tolerance) gets a sliver
    upper = np.where(upper > lower, upper, lower + 1e-12)
    step = DYNAMIC_STEP if dynamic else KINEMATIC_STEP
    cap = max_nfev or (20 if dynamic else 100) * len(params)
    sims_before = simulate_all(x0)
    solution = optimize.least_squares(
        residuals,
        x0,
        bounds=(lower, upper),
        loss=loss,
        diff_step=step,
        max_nfev=cap,
        x_scale=1.0,
        method="trf",
    )
    x = solution.x
    sims_after = simulate_all(x)
    raw = np.concatenate(
        [w * (s - y) for s, y, w in zip(sims_after, measured, weights, strict=True)]
    )
    cov, stderr, s2, condition, dof, weakest = _uncertainty(
        np.asarray(solution.jac, dtype=float), raw, scales
    )
    t = float(stats.t.ppf(0.975, dof)) if dof > 0 else math.nan
    estimates = []
    for i, p in enumerate(params):
        value = float(x[i] * p.scale)
        half = t * float(stderr[i])
        estimates.append(
            ParameterEstimate(
                p.name, value, float(stderr[i]), (value - half, value + half), p.unit,
                p.initial, p.lower, p.upper,
            )
        )  # fmt: skip
    with np.errstate(invalid="ignore", divide="ignore"):
        correlation = cov / np.outer(stderr, stderr)
    correlation[~np.isfinite(correlation)] = np.nan
    np.fill_diagonal(correlation, [1.0 if math.isfinite(s) else math.nan for s in stderr])
    warnings = _warnings(params, estimates, correlation, condition, weakest, dof, solution)
    if dynamic:
        warnings += _roughness(residuals, x, raw, params, lower, upper)
    before, err_b, _ = _statistics(measured, sims_before, weights)
    after, err_a, low_a = _statistics(measured, sims_after, weights)
    points = _points(datasets, measured, sims_before, sims_after, err_b, err_a, low_a)
    curves = _curves(model, datasets, x0, x, curve_step_deg)
    return CalibrationResult(
        parameters=tuple(estimates),
        covariance=frozen_array(cov),
        correlation=frozen_array(correlation),
        warnings=tuple(warnings),
        before=before,
        after=after,
        points=points,
        curves=curves,
        datasets=tuple(datasets),
        model="clearance" if dynamic else "nominal",
        loss=loss,
        dof=dof,
        s2=s2,
        condition_number=condition,
        nfev=int(solution.nfev),
        status=int(solution.status),
        message=str(solution.message),
        mechanism=mechanism,
    )


def _warnings(
    params: Sequence[Parameter],
    estimates: Sequence[ParameterEstimate],
    correlation: FloatArray,
    condition: float,
    weakest: FloatArray,
    dof: int,
    solution: Any,
) -> list[str]:
    out: list[str] = []
    if dof <= 0:
        out.append(
            f"not identifiable: {len(params)} parameter(s) from "
            f"{len(params) + dof} point(s) leave no degree of freedom for the uncertainties"
        )
    if solution.status <= 0:
        out.append(f"the optimiser did not converge: {solution.message}")
    if condition > CONDITION_LIMIT:
        involved = [p.name for p, w in zip(params, weakest, strict=True) if abs(w) > 0.1] or [
            p.name for p in params
        ]
        out.append(
            f"not identifiable: J^T J is near-singular (condition number {condition:.3g} > "
            f"{CONDITION_LIMIT:g}); the data cannot separate {', '.join(involved)}"
        )
    for p, e in zip(params, estimates, strict=True):
        width = e.ci95[1] - e.ci95[0]
        if not math.isfinite(e.stderr):
            out.append(f"not identifiable: {p.name} is not determined by the data")
        elif width > p.upper - p.lower:
            out.append(
                f"not identifiable: the 95 % interval of {p.name} ({width:.4g} {p.unit} wide) "
                f"is wider than its bounds ({p.upper - p.lower:.4g} {p.unit})"
            )
        elif e.ci95[0] < p.lower or e.ci95[1] > p.upper:
            out.append(
                f"poorly determined: the 95 % interval of {p.name} ({e.ci95[0]:.4g} .. "
                f"{e.ci95[1]:.4g} {p.unit}) reaches beyond its bounds ({p.lower:.4g} .. "
                f"{p.upper:.4g})"
            )
        span = p.upper - p.lower
        if span > 0 and min(e.value - p.lower, p.upper - e.value) <= 1e-6 * span:
            out.append(
                f"{p.name} ended on a bound ({e.value:.6g} {p.unit}): its interval is not "
                "meaningful; widen the bound or fix the parameter"
            )
    n = len(params)
    for i in range(n):
        for j in range(i + 1, n):
            r = correlation[i, j]
            if math.isfinite(r) and abs(r) > CORRELATION_LIMIT:
                out.append(
                    f"{params[i].name} and {params[j].name} are correlated (r = {r:+.4f}): "
                    "the data determine them only in combination"
                )
    return out


def _roughness(
    residuals: Any,
    x: FloatArray,
    f0: FloatArray,
    params: Sequence[Parameter],
    lower: FloatArray,
    upper: FloatArray,
) -> list[str]:
    """Warnings for parameters whose forward differences at 1× and 3× the step disagree."""
    out = []
    for i, p in enumerate(params):
        columns = []
        for factor in (1.0, 3.0):
            h = factor * DYNAMIC_STEP * max(1.0, abs(float(x[i])))
            if x[i] + h > upper[i]:
                h = -h
            shifted = x.copy()
            shifted[i] += h
            columns.append((residuals(shifted) - f0) / h)
        size = max(float(np.linalg.norm(columns[0])), float(np.linalg.norm(columns[1])))
        if size == 0:
            continue
        change = float(np.linalg.norm(columns[0] - columns[1])) / size
        if change > ROUGHNESS_LIMIT:
            out.append(
                f"not identifiable: the clearance model's response to {p.name} is rough here "
                f"(finite differences with steps of {100 * DYNAMIC_STEP:g} % and "
                f"{300 * DYNAMIC_STEP:g} % differ by {100 * change:.0f} %): the fit may have "
                "stopped in a local minimum and its interval is not reliable"
            )
    return out


def _points(
    datasets: Sequence[Dataset],
    measured: Sequence[FloatArray],
    before: Sequence[FloatArray],
    after: Sequence[FloatArray],
    err_before: Sequence[FloatArray],
    err_after: Sequence[FloatArray],
    low_after: Sequence[NDArray[np.bool_]],
) -> pd.DataFrame:
    frames = []
    for i, d in enumerate(datasets):
        frames.append(
            pd.DataFrame(
                {
                    "dataset": d.label,
                    "quantity": d.quantity,
                    "unit": d.unit,
                    "crank_deg": d.measurements.crank_deg,
                    "measured": d.measurements.speed,
                    "before": d.from_si(before[i]),
                    "after": d.from_si(after[i]),
                    "residual_before": measured[i] - before[i],
                    "residual_after": measured[i] - after[i],
                    "error_percent_before": err_before[i],
                    "error_percent_after": err_after[i],
                    "low_speed": low_after[i],
                }
            )
        )
    return pd.concat(frames, ignore_index=True)


def _curves(
    model: _Model,
    datasets: Sequence[Dataset],
    x0: FloatArray,
    x: FloatArray,
    step_deg: float,
) -> pd.DataFrame:
    frames = []
    for d in datasets:
        file_deg = np.arange(0.0, 360.0 + 0.5 * step_deg, step_deg)
        model_deg = d.measurements.conventions.crank_to_model(file_deg)
        try:
            before = model.response(model.vector(x0), d, model_deg)
            after = model.response(model.vector(x), d, model_deg)
        except IntegrationError:
            continue
        frames.append(
            pd.DataFrame(
                {
                    "dataset": d.label,
                    "crank_deg": file_deg,
                    "before": d.from_si(before),
                    "after": d.from_si(after),
                }
            )
        )
    if not frames:
        return pd.DataFrame(columns=["dataset", "crank_deg", "before", "after"])
    return pd.concat(frames, ignore_index=True)


# --- synthetic data (tests, examples) -------------------------------------------------------


def synthetic_dataset(
    mechanism: Mechanism,
    template: Dataset,
    truth: Mapping[str, float],
    *,
    noise: float = 0.0,
    rng: np.random.Generator | None = None,
    settings: DynamicSettings | None = None,
) -> Dataset:
    """``template`` with its values replaced by the model's at ``truth`` plus Gaussian noise.

    Args:
        truth: parameter values (SI) by name; a dynamic one selects the clearance model.
        noise: standard deviation of the added noise, SI.
        rng: the random generator (default: seed 0).
    """
    rng = rng or np.random.default_rng(0)
    mechanism = rig_mechanism(mechanism, template.measurements.conventions)
    dynamic = any(name in DYNAMIC_PARAMETERS for name in truth)
    model = _Model(mechanism, (template,), (), settings or DynamicSettings(), dynamic)
    exact = model.response(dict(truth), template, template.crank_deg_model)
    noisy = exact + noise * rng.standard_normal(exact.shape)
    values = template.from_si(noisy)
    return replace(
        template, measurements=replace(template.measurements, speed=frozen_array(values))
    )


# --- the paper's experiment -------------------------------------------------------------------

#: Table 7's value columns fitted by :func:`explain_table7`.
TABLE7_VALUE_COLUMNS = ("experiment_printed", "mbd_printed")
#: Standard deviation of rounding to whole printed numbers (uniform on ±0.5): 1/√12.
ROUNDING_SIGMA = 1.0 / math.sqrt(12.0)


def table7_dataset(column: str = "experiment_printed") -> Dataset:
    """One value column of the paper's Table 7 as a :class:`Dataset` (docs/paper-reading.md reading)."""
    from jointplay.io.measurements import PAPER_TABLE7_COLUMNS

    table = paper_table7()
    if column == PAPER_TABLE7_COLUMNS["speed"]:
        measurements = table
    elif column == PAPER_TABLE7_COLUMNS["model"]:
        assert table.model is not None
        measurements = replace(table, speed=table.model, speed_column=column)
    else:
        raise ConfigError(
            f"Table 7 has no value column {column!r}; use one of {', '.join(TABLE7_VALUE_COLUMNS)}"
        )
    return Dataset(measurements, quantity="omega4", label=column)


def explain_table7(
    mechanism: Mechanism | None = None,
    *,
    columns: Sequence[str] = TABLE7_VALUE_COLUMNS,
    fit: Sequence[str] = ("crank-speed", "phase"),
    lengths: Sequence[str] = ("coupler-length", "rocker-length", "ground-length"),
) -> dict[str, Any]:
    """Which crank speed and phase make the nominal model match each column of Table 7.

    For each value column (the measurements ``experiment_printed`` and the paper's own MBD
    simulation ``mbd_printed``) the crank speed and the crank-angle phase of the ideal
    mechanism are fitted (:func:`calibrate`), with 95 % intervals, the RMS error % before
    (200 RPM, no phase) and after, and what remains unexplained: the residual scatter in
    deg/s against the printing resolution (whole numbers: σ = 1/√12 ≈ 0.29 deg/s) and the
    points that deviate most. As a check of the other explanation docs/paper-reading.md names
    (real links of other lengths), the fit is repeated with ``lengths`` free within their
    tolerances too (the crank's is kept: angular speeds depend only on length ratios, so the
    four lengths and the crank speed cannot all be fitted); its residual is reported under
    ``with_lengths``.

    Args:
        mechanism: the model (default: the ``paper-fourbar`` preset).
        columns: Table 7's value columns to fit.
        fit: the parameters (default crank speed and phase).
        lengths: the lengths also freed for the check (empty: no check).

    Returns:
        A JSON-ready dict: ``{"columns": {column: {...}}, "summary": "...", "method": "..."}``.
    """
    if mechanism is None:
        from jointplay.io.config import load_preset

        mechanism = load_preset("paper-fourbar")
    out: dict[str, Any] = {}
    lines = []
    for column in columns:
        data = table7_dataset(column)
        result = calibrate(mechanism, [data], fit)
        points = result.points
        residual = (points["measured"] - points["after"]).to_numpy(dtype=float)  # deg/s
        rms = float(np.sqrt(np.mean(residual**2)))
        angles = points["crank_deg"].to_numpy(dtype=float)
        measured = points["measured"].to_numpy(dtype=float)
        fitted = points["after"].to_numpy(dtype=float)
        errors = points["error_percent_after"].to_numpy(dtype=float)
        largest = [
            {
                "crank_deg": float(angles[i]),
                "value": float(measured[i]),
                "fitted": float(fitted[i]),
                "residual_deg_s": float(residual[i]),
                "error_percent": float(errors[i]),
            }
            for i in np.argsort(-np.abs(residual), kind="stable")[:3]
        ]
        entry: dict[str, Any] = {
            **result.as_json(),
            "crank_rpm": _rpm_entry(result),
            "phase_deg": _deg_entry(result) if "phase" in result.values else None,
            "nominal_rpm": result.mechanism.driver.speed * 30 / math.pi,
            "max_abs_error_percent_before": result.before.max_abs_error_percent,
            "max_abs_error_percent_after": result.after.max_abs_error_percent,
            "residual_rms_deg_s": rms,
            "rounding_sigma_deg_s": ROUNDING_SIGMA,
            "largest_residuals": largest,
            "correlation": result.correlation.tolist(),
        }
        entry["unexplained"] = (
            f"after the fit the points scatter by {rms:.1f} deg/s RMS about the nominal "
            f"kinematics, {rms / ROUNDING_SIGMA:.0f} times what printing whole numbers "
            f"explains; largest at {largest[0]['crank_deg']:g} deg "
            f"({largest[0]['residual_deg_s']:+.1f} deg/s, "
            f"{largest[0]['error_percent']:+.1f} %)"
        )
        if lengths:
            free = calibrate(mechanism, [data], [*fit, *lengths])
            points = free.points
            rms_free = float(np.sqrt(np.mean((points["measured"] - points["after"]) ** 2)))
            on_bound = [
                w.split(" ended on a bound")[0] for w in free.warnings if " ended on a bound" in w
            ]
            entry["with_lengths"] = {
                "fitted": [p.name for p in free.parameters],
                "parameters": {p.name: p.as_dict() for p in free.parameters},
                "rms_after": free.rms_after,
                "residual_rms_deg_s": rms_free,
                "on_bounds": on_bound,
                "warnings": list(free.warnings),
            }
            entry["unexplained"] += (
                f"; freeing the {', '.join(n.removesuffix('-length') for n in lengths)} "
                f"lengths within their tolerances leaves {rms_free:.1f} deg/s "
                f"(RMS error {free.rms_after:.2f} %)"
                + (f", with {', '.join(on_bound)} on a bound" if on_bound else "")
            )
        out[column] = entry
        rpm = entry["crank_rpm"]
        phase = entry["phase_deg"]
        text = (
            f"{column}: crank {rpm['value']:.1f} RPM (95 % {rpm['ci95'][0]:.1f}–"
            f"{rpm['ci95'][1]:.1f})"
        )
        if phase is not None:
            text += (
                f", phase {phase['value']:+.2f}° ({phase['ci95'][0]:+.2f}…{phase['ci95'][1]:+.2f})"
            )
        text += (
            f"; RMS error {result.rms_before:.2f} % → {result.rms_after:.2f} %; "
            + entry["unexplained"]
        )
        lines.append(text)
    return {
        "method": "nominal (ideal-joint) kinematics of the mechanism fitted by least squares "
        "(jointplay.study.calibration.calibrate); 95 % intervals from the Jacobian, "
        "cov = s^2 (J^T J)^-1, s^2 = RSS/(m - p), Student-t; Table 7 read as docs/paper-reading.md "
        "says (deg/s, crank clockwise)",
        "columns": out,
        "summary": " | ".join(lines),
    }


def _rpm_entry(result: CalibrationResult) -> dict[str, Any] | None:
    speeds = [p for p in result.parameters if p.name.startswith("crank-speed")]
    if not speeds:
        return None
    p = speeds[0]
    factor = 30.0 / math.pi
    return {
        "value": p.value * factor,
        "stderr": p.stderr * factor,
        "ci95": [p.ci95[0] * factor, p.ci95[1] * factor],
        "unit": "rpm",
    }


def _deg_entry(result: CalibrationResult) -> dict[str, Any]:
    p = result.estimate("phase")
    factor = 180.0 / math.pi
    return {
        "value": p.value * factor,
        "stderr": p.stderr * factor,
        "ci95": [p.ci95[0] * factor, p.ci95[1] * factor],
        "unit": "deg",
    }
