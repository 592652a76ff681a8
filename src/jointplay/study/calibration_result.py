"""Calibration, part 3: what a fit found, as data (estimates, error statistics, the points
and curves before and after) and its JSON shapes; :mod:`jointplay.report.calibration` writes
the files and plots. SI units unless a column says otherwise. ``jointplay.study.calibration``
stays the import path.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from jointplay.errors import IntegrationError
from jointplay.model.mechanism import Mechanism
from jointplay.study.calibration_model import Dataset, FloatArray, _Model
from jointplay.study.comparison import LOW_SPEED_FRACTION

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


# --- the points and curves before and after the fit ----------------------------------------


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
