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

Where things are
    :mod:`~jointplay.study.calibration_model` holds the data sets, parameters, settings and
    the model; :mod:`~jointplay.study.calibration_result` what a fit found; this module the
    fit itself (:func:`calibrate`), synthetic data and the paper's Table 7, and gathers the
    others: ``jointplay.study.calibration`` stays the import path of them all.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import replace
from typing import Any

import numpy as np
from numpy.typing import NDArray
from scipy import optimize, stats

from jointplay.errors import ConfigError, IntegrationError, SettingError
from jointplay.io.measurements import frozen_array, paper_table7
from jointplay.model.mechanism import Mechanism
from jointplay.study.calibration_model import (
    DYNAMIC_PARAMETERS,
    KINEMATIC_PARAMETERS,
    Dataset,
    DynamicSettings,
    FloatArray,
    Parameter,
    _Model,
    default_parameters,
    parameter_names,
    response_unit,
    stiffness_exponent,
)
from jointplay.study.calibration_result import (
    CalibrationResult,
    ErrorStatistics,
    ParameterEstimate,
    _curves,
    _points,
)
from jointplay.study.comparison import LOW_SPEED_FRACTION, error_percent, rig_mechanism

__all__ = [
    "CONDITION_LIMIT",
    "CORRELATION_LIMIT",
    "DYNAMIC_PARAMETERS",
    "DYNAMIC_STEP",
    "KINEMATIC_PARAMETERS",
    "KINEMATIC_STEP",
    "LOSSES",
    "ROUGHNESS_LIMIT",
    "ROUNDING_SIGMA",
    "TABLE7_VALUE_COLUMNS",
    "CalibrationResult",
    "Dataset",
    "DynamicSettings",
    "ErrorStatistics",
    "Parameter",
    "ParameterEstimate",
    "calibrate",
    "default_parameters",
    "explain_table7",
    "parameter_names",
    "response_unit",
    "stiffness_exponent",
    "synthetic_dataset",
    "table7_dataset",
]

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
