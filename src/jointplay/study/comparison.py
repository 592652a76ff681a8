"""Comparison of the simulated rocker speed with measurements (the paper's Table 7, Figs. 17–20).

The paper measured the rocker's angular speed at 13 crank positions (30° steps) on a test rig
running at 200 RPM and compared it with its MBD simulations (Table 7, Figs. 17–20). This
module simulates the *steady* cycle of the mechanism, samples it at the measured crank angles
and reports the errors, without ever rescaling anything silently. Measurements and their
conventions (units, directions, the angle origin) are read by :mod:`jointplay.io.measurements`;
the overlay plots are drawn by :mod:`jointplay.report.overlays`.

The steady cycle (:func:`steady_cycle`)
    ``"nominal"`` (ideal joints) is the closed-form kinematics evaluated directly at the
    measured angles. A clearance method (one of the paper's Table 2 names,
    :mod:`jointplay.study.methods`) is simulated from the nominal steady motion
    (``Start("steady")``: pins centred, links moving as in the ideal mechanism) for
    ``revolutions`` crank periods (default 3); only the LAST full revolution is used, the earlier
    ones are discarded as the transient. The speed is interpolated linearly between the
    integrator's steps (at most 1° of crank apart) at the measured crank angles taken modulo
    360° in the driving direction, so the unwrapped, possibly decreasing (clockwise) crank angle
    of the simulation does not matter. How much the last revolution differs from the one before
    it is recorded (``cycle_change_rad_s``) as a check that the motion is steady.

Errors (:func:`compare`)
    As the paper defines them (Table 7): error % = (measured − simulated) / simulated × 100,
    with signed speeds (e.g. 30°: (644 − 760) / 760 = −15.26 %). Per point the error %, and the
    difference measured − simulated (rad/s and the file's unit); over the points the RMS and
    the largest absolute value of both. Error % explodes where the simulated speed is near zero
    (the rocker reverses twice per revolution), so points whose |simulated| is below
    ``low_speed_fraction`` (default 10 %) of the largest |simulated| at the measured angles are
    flagged ``low_speed`` and left out of the % statistics (they stay in the table and in the
    rad/s statistics). Points are used as given: Table 7 lists 0° and 360°, the same crank
    position, and both count.

The discrepancy (:class:`Discrepancy`)
    The measurements lie some 15–20 % above the nominal kinematics at 200 RPM (docs/paper-reading.md).
    The least-squares speed factor s = Σ(sim · meas) / Σ(sim²) between the measurements and the
    nominal kinematics quantifies it; for ideal joints the rocker speed is proportional to the
    crank speed, so s is exactly the factor by which the crank would have had to run faster
    (200 · s RPM). This is reported as a labelled *what-if* and never applied. The paper's own
    printed MBD column is compared with our nominal kinematics the same way.

The paper's printed errors (:func:`check_printed_errors`)
    Recomputed from the printed (whole-number) speeds, (exp − sim) / sim reproduces the printed
    error % only at some rows (30°, 60°, 240°); at the others (e.g. 0°: −0.54 vs printed
    −0.50, 90°: 7.95 vs 7.58) neither (exp − sim) / sim nor (exp − sim) / exp gives the
    printed value. The check reports these rows and whether the printed value is at least consistent
    with the formula applied to speeds that were rounded to whole numbers for printing.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import asdict, dataclass, field, replace
from typing import TYPE_CHECKING, Any

import numpy as np
import pandas as pd
from numpy.typing import ArrayLike, NDArray

from jointplay.errors import ConfigError
from jointplay.io.measurements import MeasurementConventions, Measurements, frozen_array
from jointplay.kinematics.analysis import analyse, cycle_angles
from jointplay.model.columns import rotating_links
from jointplay.model.mechanism import Mechanism

if TYPE_CHECKING:
    from jointplay.dynamics.simulate import SolverOptions

FloatArray = NDArray[np.float64]

#: The label of the ideal-joint (closed-form kinematics) simulation.
NOMINAL = "nominal"
#: The label of the physical default contact (docs/contact.md).
PHYSICAL = "physical"
#: The paper study's comparison: the nominal kinematics and the paper's four ECS methods
#: (Figs. 17–20).
DEFAULT_METHODS = (
    NOMINAL,
    "ifm-ecs-spherical",
    "rm-ecs-spherical",
    "ifm-ecs-cylindrical",
    "rm-ecs-cylindrical",
)
#: ``jointplay compare``'s default: the physical default contact beside them.
COMPARE_METHODS = (NOMINAL, PHYSICAL, *DEFAULT_METHODS[1:])
#: Default fraction of the largest |simulated| below which a point is left out of the % stats.
LOW_SPEED_FRACTION = 0.10


#: What each ECS source means, in words (console, JSON and plot captions say which was used).
ECS_SOURCE_TEXT = {
    "computed": "computed (our estimate of the paper's eqs. 9–13, docs/ecs.md)",
    "paper": "the paper's published values (its Tables 4 and 5)",
}


# --- the simulated steady cycle ---------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class SteadyCycle:
    """One steady crank revolution of a simulated angular velocity.

    Attributes:
        method: ``"nominal"`` or the paper method's name.
        description: how the cycle was obtained (for reports).
        quantity: the column compared, e.g. ``omega4`` (the rocker).
        mechanism: the simulated mechanism (driven in the rig's direction).
        crank_deg: crank angle over the revolution in time order, degrees counter-clockwise
            from the ground line, unwrapped (decreasing for a clockwise crank).
        values: the quantity at those angles, rad/s, counter-clockwise positive.
        window_start_deg: crank angle at the start of the revolution, degrees (CCW, unwrapped).
        ideal: True for the nominal kinematics, evaluated in closed form by :meth:`at`.
        record: method parameters, solver statistics and the steadiness check.
    """

    method: str
    description: str
    quantity: str
    mechanism: Mechanism
    crank_deg: FloatArray
    values: FloatArray
    window_start_deg: float
    ideal: bool
    record: Mapping[str, Any] = field(default_factory=dict)

    @property
    def direction(self) -> int:
        """+1 if the crank turned counter-clockwise, -1 clockwise."""
        return int(self.mechanism.driver.direction)

    @property
    def crank_rpm(self) -> float:
        """The crank speed, rev/min."""
        return self.mechanism.driver.speed * 30.0 / math.pi

    @property
    def ecs_source(self) -> str | None:
        """Where an ECS method took K, δ and D from (``"computed"`` or ``"paper"``); None
        for the nominal cycle and the conventional methods, which use no ECS."""
        source = self.record.get("ecs_source")
        return None if source is None else str(source)

    def at(self, crank_deg: ArrayLike) -> FloatArray:
        """The quantity (rad/s, CCW positive) at crank angles (deg CCW from the ground line).

        Angles may lie on any turn: they are taken modulo 360° within this revolution. The
        nominal cycle is the closed-form kinematics at exactly these angles; a simulated one is
        interpolated linearly between the integrator's steps.
        """
        theta = np.asarray(crank_deg, dtype=float)
        if self.ideal:
            return _ideal_values(self.mechanism, self.quantity, theta)
        travelled = self.direction * (self.crank_deg - self.window_start_deg)
        target = np.mod(self.direction * (theta - self.window_start_deg), 360.0)
        return np.interp(target, travelled, self.values)


def _link_of(mechanism: Mechanism, quantity: str) -> str:
    names = {f"omega{number}": name for name, number in rotating_links(mechanism)}
    if quantity not in names:
        raise ConfigError(
            f"cannot compare {quantity!r}: the angular velocities of {mechanism.name!r} are "
            f"{', '.join(names) or 'none'}"
        )
    return names[quantity]


def _ideal_values(mechanism: Mechanism, quantity: str, theta_deg: FloatArray) -> FloatArray:
    """Closed-form (or general-solver) kinematics at the given crank angles, in driving order."""
    link = _link_of(mechanism, quantity)
    flat = np.atleast_1d(theta_deg).ravel()
    driver = mechanism.driver
    start = math.degrees(driver.start_angle)
    travelled = np.mod(driver.direction * (flat - start), 360.0)
    order = np.argsort(travelled, kind="stable")
    angles = np.radians(start + driver.direction * travelled[order])
    kin = analyse(mechanism, angles)
    out = np.empty_like(flat)
    out[order] = kin.omega(link)
    return out.reshape(np.shape(theta_deg))


def nominal_cycle(
    mechanism: Mechanism, *, quantity: str = "omega4", step_deg: float = 0.5
) -> SteadyCycle:
    """The ideal-joint mechanism's revolution (closed-form kinematics) as a :class:`SteadyCycle`.

    ``step_deg`` only sets the plotted curve; :meth:`SteadyCycle.at` is exact.
    """
    link = _link_of(mechanism, quantity)
    kin = analyse(mechanism, cycle_angles(mechanism, step_deg))
    return SteadyCycle(
        method=NOMINAL,
        description=f"ideal joints: {kin.method} kinematics at the measured angles",
        quantity=quantity,
        mechanism=mechanism,
        crank_deg=frozen_array(np.degrees(kin.crank_angle)),
        values=frozen_array(kin.omega(link)),
        window_start_deg=math.degrees(mechanism.driver.start_angle),
        ideal=True,
        record={"method": NOMINAL, "kinematics": kin.method},
    )


def steady_cycle(
    mechanism: Mechanism,
    method: str = NOMINAL,
    *,
    revolutions: float = 3.0,
    ecs_source: str = "computed",
    joints: Sequence[str] | None = None,
    clearance: float | None = None,
    quantity: str = "omega4",
    solver: SolverOptions | None = None,
) -> SteadyCycle:
    """The steady revolution of ``mechanism`` (driven as it is) with method ``method``.

    Args:
        mechanism: the mechanism, driven in the rig's direction (see
            :func:`rig_mechanism`).
        method: ``"nominal"`` (ideal joints, closed-form kinematics), ``"physical"`` (the
            default contact of docs/contact.md) or one of the paper's methods
            (:data:`jointplay.study.methods.METHODS`).
        revolutions: simulated crank periods (>= 1, default 3), starting from the nominal
            steady motion; only the last full revolution is used.
        ecs_source: ``"computed"`` (our ECS estimate) or ``"paper"`` (Tables 4 and 5).
        joints: clearance joints (default: every joint with a clearance in its fit data; for
            ``paper-fourbar`` O2, A, B and O4).
        clearance: radial clearance of every clearance joint, m (default: from the fit data;
            0.021 mm for ``paper-fourbar``).
        quantity: the angular velocity compared (default ``omega4``, the rocker).
        solver: :class:`~jointplay.dynamics.simulate.SolverOptions` (default settings).

    Raises:
        ConfigError: unknown method, bad number of revolutions or joints.
        IntegrationError: the simulation failed.
    """
    if method == NOMINAL:
        return nominal_cycle(mechanism, quantity=quantity)
    from jointplay.dynamics.setup import ContactModel, clearance_joints
    from jointplay.dynamics.simulate import SolverOptions, Start, preferred_integrator, simulate
    from jointplay.study.methods import METHODS, get_method, method_law

    if method not in METHODS and method != PHYSICAL:
        raise ConfigError(
            f"unknown method {method!r}; use {NOMINAL}, {PHYSICAL} or one of the paper's: "
            f"{', '.join(METHODS)}"
        )
    if not (math.isfinite(revolutions) and revolutions >= 1):
        raise ConfigError(
            f"revolutions must be >= 1 (the last full revolution is used), got {revolutions}"
        )
    _link_of(mechanism, quantity)
    uses_ecs = method != PHYSICAL and get_method(method).uses_ecs
    if method == PHYSICAL:
        contact = ContactModel()
        record: dict[str, Any] = {"method": PHYSICAL, "contact": contact.describe()}
        clear = contact.joints(mechanism, joints, clearance=clearance)
    else:
        law, record = method_law(method, mechanism, ecs_source=ecs_source)
        if uses_ecs:
            record = {**record, "ecs_source": ecs_source}
        clear = clearance_joints(mechanism, joints, clearance=clearance, law=law)
    if method != PHYSICAL and (solver is None or solver.integrator is None):
        preferred = preferred_integrator(get_method(method).integrator, mechanism, clear)
        solver = replace(solver or SolverOptions(), integrator=preferred)
    result = simulate(
        mechanism, clear, revolutions=revolutions, settle=0, start=Start("steady"), solver=solver
    )
    steps = result.steps
    t = steps["t"].to_numpy()
    crank = steps["crank_deg"].to_numpy()
    values = steps[quantity].to_numpy()
    period = mechanism.driver.period
    t_end = float(t[-1])
    t_start = t_end - period
    first = max(int(np.searchsorted(t, t_start, side="right")) - 1, 0)
    window_start = float(np.interp(t_start, t, crank))
    travelled = mechanism.driver.direction * (crank[first:] - window_start)
    if np.any(np.diff(travelled) < 0):  # the driver constraint keeps the crank monotonic
        raise ConfigError(f"{method}: the crank angle did not advance monotonically")
    record = {
        **record,
        "revolutions": revolutions,
        "start": "steady (nominal motion, pins centred)",
        "window_s": [t_start, t_end],
        "joints": [c.joint for c in clear],
        "clearance_m": {c.joint: c.clearance for c in clear},
        "solver": {
            key: result.solver_stats.get(key)
            for key in (
                "integrator",
                "steps",
                "rejected_steps",
                "impacts",
                "max_penetration_m",
                "wall_s",
            )
        },
        "cycle_change_rad_s": _cycle_change(t, crank, values, t_start, period, mechanism),
    }
    description = (
        f"{method}: last of {revolutions:g} revolution(s) from the nominal steady motion "
        f"(t = {t_start:.4g}–{t_end:.4g} s), clearance in {', '.join(c.joint for c in clear)}"
        + (f"; ECS parameters {ECS_SOURCE_TEXT[ecs_source]}" if uses_ecs else "")
    )
    return SteadyCycle(
        method=method,
        description=description,
        quantity=quantity,
        mechanism=mechanism,
        crank_deg=frozen_array(crank[first:]),
        values=frozen_array(values[first:]),
        window_start_deg=window_start,
        ideal=False,
        record=record,
    )


def _cycle_change(
    t: FloatArray,
    crank: FloatArray,
    values: FloatArray,
    t_start: float,
    period: float,
    mechanism: Mechanism,
) -> float | None:
    """Largest |last − previous revolution| of the quantity on a 1° grid, rad/s (None if < 2)."""
    if t_start - period < -1e-9 * period:
        return None
    grid = (np.arange(360) + 0.5) / 360.0
    last = np.interp(t_start + grid * period, t, values)
    previous = np.interp(t_start - period + grid * period, t, values)
    return float(np.max(np.abs(last - previous)))


def rig_mechanism(mechanism: Mechanism, conventions: MeasurementConventions) -> Mechanism:
    """``mechanism`` driven in the rig's crank direction (its speed unchanged)."""
    if mechanism.driver.direction == conventions.driver_direction:
        return mechanism
    return mechanism.with_driver(direction=conventions.driver_direction)


# --- errors ------------------------------------------------------------------------------------


def error_percent(measured: ArrayLike, simulated: ArrayLike) -> FloatArray:
    """The paper's error (Table 7): (measured − simulated) / simulated × 100, signed speeds.

    NaN where the simulated value is exactly zero.
    """
    meas = np.asarray(measured, dtype=float)
    sim = np.asarray(simulated, dtype=float)
    out = np.full(np.broadcast(meas, sim).shape, np.nan)
    np.divide(100.0 * (meas - sim), sim, out=out, where=sim != 0)
    return out


def speed_factor(measured: ArrayLike, simulated: ArrayLike) -> float:
    """Least-squares factor s minimising Σ(meas − s·sim)²: s = Σ(sim·meas) / Σ(sim²)."""
    meas = np.asarray(measured, dtype=float)
    sim = np.asarray(simulated, dtype=float)
    denominator = float(np.sum(sim * sim))
    return float(np.sum(sim * meas)) / denominator if denominator > 0 else math.nan


def _rms(values: FloatArray) -> float:
    return float(np.sqrt(np.mean(values**2))) if values.size else math.nan


def _largest(values: FloatArray, angles: FloatArray) -> tuple[float, float]:
    if not values.size:
        return math.nan, math.nan
    i = int(np.argmax(np.abs(values)))
    return float(abs(values[i])), float(angles[i])


@dataclass(frozen=True)
class ComparisonStatistics:
    """Agreement of one simulation with the measurements.

    Attributes:
        n_points: measured points.
        n_percent_points: points in the % statistics (the others are ``low_speed``).
        low_speed_threshold: |simulated| below which a point is left out of the % statistics,
            rad/s.
        rms_error_percent: RMS of the paper's error % over those points.
        max_abs_error_percent: largest |error %| over those points, and
            ``max_error_at_deg`` its crank angle (the file's convention).
        rms_difference: RMS of measured − simulated over all points, rad/s.
        max_abs_difference: largest |measured − simulated|, rad/s, at ``max_difference_at_deg``.
        speed_factor: WHAT-IF, not applied: least-squares factor s with measured ≈ s · simulated.
        rms_error_percent_if_scaled: WHAT-IF: RMS error % against s · simulated.
    """

    n_points: int
    n_percent_points: int
    low_speed_threshold: float
    rms_error_percent: float
    max_abs_error_percent: float
    max_error_at_deg: float
    rms_difference: float
    max_abs_difference: float
    max_difference_at_deg: float
    speed_factor: float
    rms_error_percent_if_scaled: float

    def as_dict(self, unit_factor: float = 1.0) -> dict[str, Any]:
        """The fields (SI), plus the differences in the file's unit (``unit_factor`` rad/s)."""
        return {
            **asdict(self),
            "rms_difference_in_unit": self.rms_difference / unit_factor,
            "max_abs_difference_in_unit": self.max_abs_difference / unit_factor,
        }


@dataclass(frozen=True, eq=False)
class ExperimentComparison:
    """One simulation against the measurements.

    Attributes:
        method: ``"nominal"`` or the paper method's name.
        description: how the simulated values were obtained.
        source: the measurements' source.
        conventions: the measurements' conventions.
        crank_rpm: the simulated crank speed, rev/min.
        points: one row per measured point: ``crank_deg`` (file convention), ``crank_deg_ccw``
            (ours), ``measured``/``simulated``/``difference`` (measured − simulated) in the
            file's unit, the same with ``_rad_s`` (rad/s, CCW positive), ``error_percent``
            (the paper's definition) and ``low_speed`` (left out of the % statistics).
        statistics: RMS and maxima, and the what-if speed factor.
        cycle: the simulated steady revolution.
    """

    method: str
    description: str
    source: str
    conventions: MeasurementConventions
    crank_rpm: float
    points: pd.DataFrame
    statistics: ComparisonStatistics
    cycle: SteadyCycle

    def as_dict(self) -> dict[str, Any]:
        unit = self.conventions.unit
        return {
            "method": self.method,
            "description": self.description,
            "measurements": self.source,
            "conventions": self.conventions.as_dict(),
            "unit": unit,
            "crank_rpm": self.crank_rpm,
            "ecs_source": self.cycle.ecs_source,
            "error_definition": "(measured - simulated) / simulated * 100 (paper, Table 7)",
            "statistics": self.statistics.as_dict(self.conventions.unit_factor),
            "what_if": {
                "note": "not applied: the factor s with measured ~ s * simulated (least squares)",
                "speed_factor": self.statistics.speed_factor,
                "rms_error_percent_if_scaled": self.statistics.rms_error_percent_if_scaled,
            },
            "simulation": dict(self.cycle.record),
            "points": self.points.to_dict(orient="records"),
        }


def compare(
    measurements: Measurements,
    cycle: SteadyCycle,
    *,
    low_speed_fraction: float = LOW_SPEED_FRACTION,
) -> ExperimentComparison:
    """Compare ``measurements`` with the steady cycle ``cycle`` at the measured crank angles.

    Args:
        measurements: measured speeds and their conventions.
        cycle: the simulated revolution; its crank must turn in the rig's direction.
        low_speed_fraction: points whose |simulated| is below this fraction of the largest
            |simulated| at the measured angles are left out of the % statistics (0: none).

    Raises:
        ConfigError: the cycle's crank turns the other way than the rig's, or a bad fraction.
    """
    conventions = measurements.conventions
    if cycle.direction != conventions.driver_direction:
        raise ConfigError(
            f"{cycle.method}: the simulated crank turns "
            f"{'ccw' if cycle.direction == 1 else 'cw'} but the rig's turned "
            f"{conventions.crank_direction}; simulate rig_mechanism(mechanism, conventions)"
        )
    if not (math.isfinite(low_speed_fraction) and 0 <= low_speed_fraction < 1):
        raise ConfigError(f"low_speed_fraction must be in [0, 1), got {low_speed_fraction}")
    theta = measurements.crank_deg_model
    measured = measurements.speed_si
    simulated = cycle.at(theta)
    difference = measured - simulated
    errors = error_percent(measured, simulated)
    threshold = low_speed_fraction * float(np.max(np.abs(simulated)))
    low = (np.abs(simulated) < threshold) | ~np.isfinite(errors)
    use = ~low
    factor = speed_factor(measured, simulated)
    angles = measurements.crank_deg
    max_err, max_err_at = _largest(errors[use], angles[use])
    max_diff, max_diff_at = _largest(difference, angles)
    statistics = ComparisonStatistics(
        n_points=int(theta.size),
        n_percent_points=int(use.sum()),
        low_speed_threshold=threshold,
        rms_error_percent=_rms(errors[use]),
        max_abs_error_percent=max_err,
        max_error_at_deg=max_err_at,
        rms_difference=_rms(difference),
        max_abs_difference=max_diff,
        max_difference_at_deg=max_diff_at,
        speed_factor=factor,
        rms_error_percent_if_scaled=_rms(error_percent(measured, factor * simulated)[use]),
    )
    points = pd.DataFrame(
        {
            "crank_deg": angles,
            "crank_deg_ccw": theta,
            "measured": measurements.speed,
            "simulated": conventions.speed_from_si(simulated),
            "difference": conventions.speed_from_si(difference),
            "measured_rad_s": measured,
            "simulated_rad_s": simulated,
            "difference_rad_s": difference,
            "error_percent": errors,
            "low_speed": low,
        }
    )
    return ExperimentComparison(
        method=cycle.method,
        description=cycle.description,
        source=measurements.source,
        conventions=conventions,
        crank_rpm=cycle.crank_rpm,
        points=points,
        statistics=statistics,
        cycle=cycle,
    )


# --- the discrepancy and the paper's printed values ---------------------------------------------


@dataclass(frozen=True, eq=False)
class Discrepancy:
    """How far the measurements (and the paper's own MBD column) lie from our nominal kinematics.

    Attributes:
        speed_factor: least-squares s with measured ≈ s · nominal (all points).
        range_factor: the same discrepancy read from the swing, ptp(measured) / ptp(nominal)
            at the measured angles (insensitive to a small phase error; weights the extremes);
            NaN where the nominal has no swing there (one point, or equal speeds), and the
            summary says so.
        crank_rpm: the crank speed of the nominal kinematics, rev/min.
        implied_crank_rpm: WHAT-IF, not applied: ``crank_rpm · s``, the crank speed at which
            the ideal mechanism would best match the measurements (the rocker speed of ideal
            kinematics is proportional to the crank speed).
        rms_error_percent: RMS error % of the nominal kinematics as they are.
        rms_error_percent_if_scaled: WHAT-IF: RMS error % of the nominal at ``implied_crank_rpm``.
        model_factor: least-squares factor between the paper's printed simulation column and
            our nominal kinematics (None without that column).
        measured_vs_model_factor: least-squares factor between the measurements and the paper's
            printed simulation column (None without it).
        model_points: per point: the paper's simulation and our nominal (file unit), their
            difference and ``error_percent`` = (paper − ours) / ours × 100.
        model_rms_error_percent, model_max_abs_error_percent: statistics of that error %
            (points with low nominal speed left out, as for the measurements).
    """

    speed_factor: float
    range_factor: float
    crank_rpm: float
    implied_crank_rpm: float
    rms_error_percent: float
    rms_error_percent_if_scaled: float
    model_factor: float | None = None
    measured_vs_model_factor: float | None = None
    model_points: pd.DataFrame | None = None
    model_rms_error_percent: float | None = None
    model_max_abs_error_percent: float | None = None

    def summary(self) -> str:
        """The discrepancy and the what-if in words."""
        excess = 100.0 * (self.speed_factor - 1.0)
        swing = (
            f"swing ratio {self.range_factor:.3f}"
            if math.isfinite(self.range_factor)
            else "no swing ratio: it needs two or more points of different nominal speed"
        )
        text = (
            f"measured ≈ {self.speed_factor:.3f} × nominal kinematics at {self.crank_rpm:g} RPM "
            f"(least squares; {excess:+.1f} %; {swing}). "
            "WHAT-IF, not applied: the ideal mechanism "
            f"matches best with the crank at {self.implied_crank_rpm:.1f} RPM "
            f"(RMS error {self.rms_error_percent:.2f} % → "
            f"{self.rms_error_percent_if_scaled:.2f} %); "
            "the data cannot tell a faster crank from different real link lengths."
        )
        if self.model_factor is not None:
            text += (
                f" The paper's printed MBD column ≈ {self.model_factor:.3f} × our nominal "
                f"kinematics (RMS {self.model_rms_error_percent:.2f} %, max "
                f"{self.model_max_abs_error_percent:.2f} %), and measured ≈ "
                f"{self.measured_vs_model_factor:.3f} × the paper's MBD."
            )
        return text

    def as_dict(self) -> dict[str, Any]:
        data = {k: v for k, v in asdict(self).items() if k != "model_points"}
        data["what_if_note"] = "implied_crank_rpm and rms_error_percent_if_scaled are not applied"
        data["summary"] = self.summary()
        data["model_points"] = (
            None if self.model_points is None else self.model_points.to_dict(orient="records")
        )
        return data


def discrepancy(measurements: Measurements, nominal: ExperimentComparison) -> Discrepancy:
    """The discrepancy between ``measurements`` and the nominal comparison ``nominal``."""
    if nominal.method != NOMINAL:
        raise ConfigError(f"the discrepancy is measured against the nominal, not {nominal.method}")
    stats = nominal.statistics
    points = nominal.points
    extra: dict[str, Any] = {}
    if measurements.model is not None:
        conventions = measurements.conventions
        ours = points["simulated_rad_s"].to_numpy()
        paper = conventions.speed_to_si(measurements.model)
        errors = error_percent(paper, ours)
        use = ~points["low_speed"].to_numpy()
        extra = {
            "model_factor": speed_factor(paper, ours),
            "measured_vs_model_factor": speed_factor(measurements.speed_si, paper),
            "model_points": pd.DataFrame(
                {
                    "crank_deg": measurements.crank_deg,
                    "paper_model": measurements.model,
                    "our_nominal": conventions.speed_from_si(ours),
                    "difference": conventions.speed_from_si(paper - ours),
                    "error_percent": errors,
                    "low_speed": ~use,
                }
            ),
            "model_rms_error_percent": _rms(errors[use]),
            "model_max_abs_error_percent": _largest(errors[use], measurements.crank_deg[use])[0],
        }
    return Discrepancy(
        speed_factor=stats.speed_factor,
        range_factor=_swing_ratio(measurements.speed_si, points["simulated_rad_s"].to_numpy()),
        crank_rpm=nominal.crank_rpm,
        implied_crank_rpm=nominal.crank_rpm * stats.speed_factor,
        rms_error_percent=stats.rms_error_percent,
        rms_error_percent_if_scaled=stats.rms_error_percent_if_scaled,
        **extra,
    )


def _swing_ratio(measured: FloatArray, nominal: FloatArray) -> float:
    """ptp(measured) / ptp(nominal); NaN where the nominal has no swing (a one-row file: NumPy
    printed its raw "invalid value encountered in scalar divide" there)."""
    swing = float(np.ptp(nominal)) if len(nominal) else 0.0
    return float(np.ptp(measured)) / swing if swing > 0 else math.nan


@dataclass(frozen=True, eq=False)
class PrintedErrorCheck:
    """The paper's printed error % recomputed from its printed speeds.

    Attributes:
        table: per row: ``crank_deg``, ``simulation``, ``experiment`` and ``printed`` (as
            printed), ``by_simulation`` = (exp − sim)/sim × 100, ``by_experiment`` =
            (exp − sim)/exp × 100, ``follows_simulation``/``follows_experiment`` (that
            formula rounds to the printed value), ``rounding_low``/``rounding_high`` (range of
            (exp − sim)/sim for speeds within half a printed unit of the printed ones) and
            ``consistent_with_rounding``.
        unexplained: crank angles where neither formula reproduces the printed value.
        inconsistent: crank angles where even rounding of the printed speeds cannot explain it.
    """

    table: pd.DataFrame
    unexplained: tuple[float, ...]
    inconsistent: tuple[float, ...]

    def summary(self) -> str:
        follows = self.table.loc[self.table["follows_simulation"], "crank_deg"]
        text = (
            "printed errors follow (exp − sim)/sim × 100 from the printed speeds at "
            f"{_angles(follows)}; at {_angles(self.unexplained) or 'no row'} neither "
            "(exp − sim)/sim nor (exp − sim)/exp gives the printed value (largest gap "
            f"{self.table['gap'].abs().max():.2f} points)"
        )
        if self.inconsistent:
            return text + f"; at {_angles(self.inconsistent)} not even rounding explains it"
        return text + (
            "; all printed values are consistent with (exp − sim)/sim of speeds that were "
            "rounded to whole numbers for printing"
        )

    def as_dict(self) -> dict[str, Any]:
        return {
            "summary": self.summary(),
            "unexplained_at_deg": list(self.unexplained),
            "inconsistent_at_deg": list(self.inconsistent),
            "rows": self.table.to_dict(orient="records"),
        }


def _angles(values: Any) -> str:
    return ", ".join(f"{float(v):g}°" for v in values)


def check_printed_errors(
    measurements: Measurements, *, error_decimals: int = 2, speed_resolution: float = 1.0
) -> PrintedErrorCheck | None:
    """Recompute the printed error % (None unless the file has model and error columns).

    Args:
        measurements: with :attr:`Measurements.model` and :attr:`Measurements.printed_error`.
        error_decimals: decimals of the printed error % (Table 7: 2).
        speed_resolution: resolution of the printed speeds (Table 7: whole numbers, 1).
    """
    if measurements.model is None or measurements.printed_error is None:
        return None
    sim = measurements.model
    exp = measurements.speed
    printed = measurements.printed_error
    tolerance = 0.5 * 10.0**-error_decimals + 1e-9
    by_sim = error_percent(exp, sim)
    with np.errstate(divide="ignore", invalid="ignore"):
        by_exp = np.where(exp != 0, 100.0 * (exp - sim) / exp, np.nan)
    h = 0.5 * speed_resolution
    corners = np.array([error_percent(exp + de, sim + ds) for de in (-h, h) for ds in (-h, h)])
    spans_zero = (sim - h <= 0) & (sim + h >= 0)
    low = np.where(spans_zero, -np.inf, corners.min(axis=0))
    high = np.where(spans_zero, np.inf, corners.max(axis=0))
    follows_sim = np.abs(by_sim - printed) <= tolerance
    follows_exp = np.abs(by_exp - printed) <= tolerance
    consistent = (printed >= low - tolerance) & (printed <= high + tolerance)
    table = pd.DataFrame(
        {
            "crank_deg": measurements.crank_deg,
            "simulation": sim,
            "experiment": exp,
            "printed": printed,
            "by_simulation": by_sim,
            "by_experiment": by_exp,
            "gap": printed - by_sim,
            "follows_simulation": follows_sim,
            "follows_experiment": follows_exp,
            "rounding_low": low,
            "rounding_high": high,
            "consistent_with_rounding": consistent,
        }
    )
    angles = measurements.crank_deg
    return PrintedErrorCheck(
        table=table,
        unexplained=tuple(float(a) for a in angles[~(follows_sim | follows_exp)]),
        inconsistent=tuple(float(a) for a in angles[~consistent]),
    )


# --- several methods at once ---------------------------------------------------------------------


@dataclass(frozen=True, eq=False)
class MethodsComparison:
    """Several simulations against the same measurements.

    Attributes:
        measurements: the measurements.
        comparisons: one per method, in the order run.
        table: one row per method: RMS and max |error %|, RMS and max |difference| (rad/s and
            the file's unit), the what-if speed factor, and the points in the % statistics.
        best: the method with the lowest RMS error % (``best_by_difference``: the lowest RMS
            difference).
        discrepancy: the measurements against our nominal kinematics.
        printed_check: the paper's printed errors recomputed (None for other files).
    """

    measurements: Measurements
    comparisons: tuple[ExperimentComparison, ...]
    table: pd.DataFrame
    best: str
    best_by_difference: str
    discrepancy: Discrepancy
    printed_check: PrintedErrorCheck | None

    @property
    def ecs_source(self) -> str | None:
        """Where the compared ECS methods took K, δ and D from: ``"computed"``, ``"paper"``,
        ``"mixed"`` (comparisons gathered from runs with both), or None (no ECS method)."""
        sources = {c.cycle.ecs_source for c in self.comparisons} - {None}
        if not sources:
            return None
        return sources.pop() if len(sources) == 1 else "mixed"

    def ecs_source_line(self) -> str:
        """One line saying which ECS parameters the comparison used (console, captions)."""
        source = self.ecs_source
        if source is None:
            return "ECS parameters: not used (no ECS method compared)"
        return f"ECS parameters: {ECS_SOURCE_TEXT.get(source, source)}"

    def comparison(self, method: str) -> ExperimentComparison:
        for item in self.comparisons:
            if item.method == method:
                return item
        raise ConfigError(
            f"no comparison for {method!r}; compared: {', '.join(self.table['method'])}"
        )

    def verdict(self) -> str:
        """Which simulation agrees best, and whether the ranking means anything."""
        rms = self.table.set_index("method")["rms_error_percent"]
        text = f"best agreement (lowest RMS error %): {self.best} ({rms[self.best]:.2f} %)"
        if len(rms) > 1:
            spread = float(rms.max() - rms.min())
            text += (
                f"; the {len(rms)} simulations differ by {spread:.2f} points of RMS error, "
                f"against a common RMS error of {float(rms.min()):.1f} %"
            )
            if spread < 0.1 * float(rms.min()):
                text += ": the ranking is not significant next to the common discrepancy"
        if self.best_by_difference != self.best:
            text += f" (lowest RMS difference in rad/s: {self.best_by_difference})"
        return text

    def points_table(self) -> pd.DataFrame:
        """All per-point rows, long format with a ``method`` column (``comparison.csv``)."""
        return pd.concat(
            [
                c.points.assign(method=c.method)[["method", *c.points.columns]]
                for c in self.comparisons
            ],
            ignore_index=True,
        )

    def as_dict(self) -> dict[str, Any]:
        conventions = self.measurements.conventions
        return {
            "measurements": self.measurements.source,
            "columns": {
                "angle": self.measurements.angle_column,
                "speed": self.measurements.speed_column,
            },
            "conventions": conventions.as_dict(),
            "unit": conventions.unit,
            "error_definition": "(measured - simulated) / simulated * 100 (paper, Table 7)",
            "ecs_source": self.ecs_source,
            "ecs_source_meaning": self.ecs_source_line(),
            "best": {
                "by_rms_error_percent": self.best,
                "by_rms_difference": self.best_by_difference,
                "verdict": self.verdict(),
            },
            "methods": self.table.to_dict(orient="records"),
            "discrepancy": self.discrepancy.as_dict(),
            "printed_errors": None if self.printed_check is None else self.printed_check.as_dict(),
            "comparisons": [c.as_dict() for c in self.comparisons],
        }


def summarize_comparisons(
    measurements: Measurements,
    comparisons: Sequence[ExperimentComparison],
    nominal: ExperimentComparison | None = None,
) -> MethodsComparison:
    """Tabulate ``comparisons`` and pick the best; ``nominal`` defaults to the one among them."""
    if not comparisons:
        raise ConfigError("nothing to compare: give at least one method")
    if nominal is None:
        found = [c for c in comparisons if c.method == NOMINAL]
        if not found:
            raise ConfigError("the nominal comparison is needed for the discrepancy")
        nominal = found[0]
    factor = measurements.conventions.unit_factor
    rows = []
    for c in comparisons:
        s = c.statistics
        rows.append(
            {
                "method": c.method,
                "rms_error_percent": s.rms_error_percent,
                "max_abs_error_percent": s.max_abs_error_percent,
                "max_error_at_deg": s.max_error_at_deg,
                "rms_difference_rad_s": s.rms_difference,
                "max_abs_difference_rad_s": s.max_abs_difference,
                "rms_difference_in_unit": s.rms_difference / factor,
                "max_abs_difference_in_unit": s.max_abs_difference / factor,
                "n_percent_points": s.n_percent_points,
                "n_points": s.n_points,
                "speed_factor_what_if": s.speed_factor,
                "description": c.description,
            }
        )
    table = pd.DataFrame(rows)
    rms_percent = table["rms_error_percent"].fillna(np.inf).to_numpy()
    best = str(table["method"].iloc[int(np.argmin(rms_percent))])
    best_diff = str(table["method"].iloc[int(np.argmin(table["rms_difference_rad_s"].to_numpy()))])
    return MethodsComparison(
        measurements=measurements,
        comparisons=tuple(comparisons),
        table=table,
        best=best,
        best_by_difference=best_diff,
        discrepancy=discrepancy(measurements, nominal),
        printed_check=check_printed_errors(measurements),
    )


def compare_methods(
    measurements: Measurements,
    mechanism: Mechanism,
    methods: Sequence[str] = DEFAULT_METHODS,
    *,
    revolutions: float = 3.0,
    ecs_source: str = "computed",
    joints: Sequence[str] | None = None,
    clearance: float | None = None,
    quantity: str = "omega4",
    low_speed_fraction: float = LOW_SPEED_FRACTION,
    solver: SolverOptions | None = None,
) -> MethodsComparison:
    """Simulate ``mechanism`` with each method and compare each with ``measurements``.

    The mechanism is driven in the rig's crank direction (``measurements.conventions``) at its
    own crank speed. The nominal kinematics are always computed (for the discrepancy) and
    listed only if ``methods`` contains ``"nominal"``. See :func:`steady_cycle` for the other
    arguments.
    """
    names = list(dict.fromkeys(methods))
    if not names:
        raise ConfigError("nothing to compare: give at least one method")
    rig = rig_mechanism(mechanism, measurements.conventions)
    nominal = compare(
        measurements, nominal_cycle(rig, quantity=quantity), low_speed_fraction=low_speed_fraction
    )
    comparisons = []
    for name in names:
        if name == NOMINAL:
            comparisons.append(nominal)
            continue
        cycle = steady_cycle(
            rig,
            name,
            revolutions=revolutions,
            ecs_source=ecs_source,
            joints=joints,
            clearance=clearance,
            quantity=quantity,
            solver=solver,
        )
        comparisons.append(compare(measurements, cycle, low_speed_fraction=low_speed_fraction))
    return summarize_comparisons(measurements, comparisons, nominal)
