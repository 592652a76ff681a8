"""What every response model shares: :class:`Evaluation`, the :class:`ResponseModel`
protocols, the per-sample check names, and :class:`LinearModel` (verification).
:mod:`jointplay.tolerance.responses` describes the models.
"""

from __future__ import annotations

from collections.abc import Mapping, Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError

if TYPE_CHECKING:  # the dynamics import Numba: loaded only by dynamic studies
    pass

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]

#: Prefix of the per-sample penetration checks of the dynamic models (+ the joint's name).
PENETRATION_RATIO = "penetration_ratio_"
#: What a ``penetration_ratio_<joint>`` is, in words (reports, summary.json).
PENETRATION_RATIO_DEFINITION = (
    "deepest penetration of the pin into its bearing over the analysed revolutions, taken at "
    "the integrator's accepted steps (sampled, not located between them), divided by the "
    "sample's radial clearance (above 1: not physical; negative: never touched)"
)
#: Prefix of the per-sample elastic checks of the dynamic models (+ the joint's name).
ELASTIC_RATIO = "elastic_ratio_"
#: What an ``elastic_ratio_<joint>`` is, in words (reports, summary.json).
ELASTIC_RATIO_DEFINITION = (
    "deepest penetration of the pin over the analysed revolutions (as penetration_ratio_) "
    "divided by the elastic approach the joint's own Hertz law gives at the joint's peak "
    "force (jointplay.dynamics.diagnostics.hertz_approach; above "
    "jointplay.dynamics.diagnostics.ELASTIC_FACTOR = 3: far softer than the joint's materials)"
)

#: The lubrication regimes whose time fractions a dynamic study reports per lubricated joint,
#: as the checks ``<regime>_<joint>`` (the batch engine's statistics of the same names;
#: :mod:`jointplay.dynamics.regimes`: full film for λ = h_min/σ ≥ 3, boundary below 1).
REGIME_CHECKS = ("full_film", "mixed", "boundary")
#: What the regime fractions are, in words (reports, summary.json).
REGIME_DEFINITION = (
    "fractions of the analysed time each lubricated joint ran in full film (film thickness "
    "ratio lambda = h_min/sigma >= 3), mixed (1 <= lambda < 3) and boundary lubrication "
    "(lambda < 1), h_min = c - |e| its thinnest film and sigma its composite roughness, each "
    "accepted integration step counted by lambda at its midpoint "
    "(jointplay.dynamics.regimes); means over the successful samples, and the samples whose "
    "full-film fraction is below 1 (they ever left full film)"
)
#: A sample "left full film" where its full-film fraction is below 1 by more than this (the
#: round-off of summing its steps' lengths against the window's).
FULL_FILM_TOLERANCE = 1e-9


def regime_check_names(joints: Sequence[str]) -> tuple[str, ...]:
    """``full_film_<joint>``, ``mixed_<joint>``, ``boundary_<joint>`` of every joint of
    ``joints``, joint by joint."""
    return tuple(f"{regime}_{joint}" for joint in joints for regime in REGIME_CHECKS)


def regime_fractions(
    check_names: Sequence[str], checks: FloatArray | None, ok: BoolArray
) -> dict[str, dict[str, Any]]:
    """Per lubricated joint of a study (its ``full_film_<joint>`` checks), over its
    successful samples ``ok`` that report one: the mean fractions of the analysed time in
    full film, mixed and boundary lubrication (``full_film_mean``, ``mixed_mean``,
    ``boundary_mean``), how many samples report them (``samples``), and how many of them
    ever left full film (``left_full_film``: a full-film fraction below 1, and its share
    ``left_full_film_share``); ``{}`` for a study without them (dry joints, kinematics)."""
    if checks is None:
        return {}
    names = list(check_names)
    out: dict[str, dict[str, Any]] = {}
    for name in names:
        if not name.startswith("full_film_"):
            continue
        joint = name.removeprefix("full_film_")
        columns = [checks[:, names.index(f"{regime}_{joint}")] for regime in REGIME_CHECKS]
        rows = np.asarray(ok, dtype=bool) & np.isfinite(columns[0])
        n = int(rows.sum())
        entry: dict[str, Any] = {
            f"{regime}_mean": float(column[rows].mean()) if n else None
            for regime, column in zip(REGIME_CHECKS, columns, strict=True)
        }
        left = int(np.sum(columns[0][rows] < 1.0 - FULL_FILM_TOLERANCE))
        entry.update(samples=n, left_full_film=left, left_full_film_share=left / n if n else None)
        out[joint] = entry
    return out


@dataclass(frozen=True)
class Evaluation:
    """Responses of a block of samples.

    Attributes:
        values: (m, r) responses, SI; NaN where a sample failed.
        ok: (m,) True where the sample succeeded.
        errors: m messages, ``""`` where the sample succeeded, else ``"ErrorType: message"``.
        checks: (m, c) per-sample checks of a :class:`CheckedModel`, in its
            ``check_names`` order (dimensionless; NaN where a sample failed); ``None`` for a
            model without checks.
        finished: (m,) False where an interrupt stopped the sample before it finished (the
            evaluation a :class:`~jointplay.errors.PartialInterrupt` carries); ``None``:
            every sample finished.
    """

    values: FloatArray
    ok: BoolArray
    errors: tuple[str, ...]
    checks: FloatArray | None = None
    finished: BoolArray | None = None

    def __post_init__(self) -> None:
        m = self.values.shape[0]
        if self.ok.shape != (m,) or len(self.errors) != m:
            raise ValueError("Evaluation: values, ok and errors must describe the same samples")
        if self.checks is not None and (self.checks.ndim != 2 or self.checks.shape[0] != m):
            raise ValueError("Evaluation: checks must have one row per sample")
        if self.finished is not None and self.finished.shape != (m,):
            raise ValueError("Evaluation: finished must have one value per sample")

    @classmethod
    def concatenate(cls, parts: Sequence[Evaluation], n_responses: int) -> Evaluation:
        """Join blocks in order (checks only if every block has them)."""
        if not parts:
            return cls(np.empty((0, n_responses)), np.zeros(0, dtype=bool), ())
        checks = [p.checks for p in parts if p.checks is not None]
        return cls(
            np.concatenate([p.values for p in parts], axis=0),
            np.concatenate([p.ok for p in parts]),
            tuple(e for p in parts for e in p.errors),
            np.concatenate(checks, axis=0) if len(checks) == len(parts) else None,
        )


@runtime_checkable
class ResponseModel(Protocol):
    """What the methods and the execution backends need from a model.

    Any object with these members is a model (no base class needed); it must be picklable by
    reference to run on the process and Dask backends.
    """

    @property
    def input_names(self) -> tuple[str, ...]: ...

    @property
    def response_names(self) -> tuple[str, ...]: ...

    @property
    def units(self) -> Mapping[str, str]: ...

    @property
    def chunk_size(self) -> int:
        """Samples per task sent to a worker (large for vectorised models)."""
        ...

    def evaluate(self, x: FloatArray) -> Evaluation:
        """Responses of the (m, k) input block ``x`` (SI)."""
        ...

    def describe(self) -> dict[str, Any]:
        """JSON-ready description of the model and its settings."""
        ...


@runtime_checkable
class DifferentiableModel(ResponseModel, Protocol):
    """A response model with analytic sensitivities (for ``Rss(sensitivity="analytic")``)."""

    def jacobian(self, x0: FloatArray) -> FloatArray:
        """(r, k) sensitivities ∂y_j/∂x_i at the input point ``x0`` (SI)."""
        ...


@runtime_checkable
class CheckedModel(ResponseModel, Protocol):
    """A response model that also checks each sample for plausibility (see the module
    docstring): its :meth:`evaluate` fills :attr:`Evaluation.checks`."""

    @property
    def check_names(self) -> tuple[str, ...]:
        """Names of the per-sample checks (dimensionless), e.g. ``penetration_ratio_A``."""
        ...


def _error(exc: BaseException) -> str:
    return f"{type(exc).__name__}: {exc}"


def _check_inputs(x: FloatArray, k: int) -> FloatArray:
    x = np.asarray(x, dtype=float)
    if x.ndim != 2 or x.shape[1] != k:
        raise ConfigError(f"input block must have shape (m, {k}), got {x.shape}")
    return x


# --- verification model ----------------------------------------------------------------------


@dataclass(frozen=True)
class LinearModel:
    """A linear stack ``y_j = intercept_j + Σ_i coefficients[j][i] x_i``.

    Its worst-case half-range is Σ|aᵢ|hᵢ (arithmetic sum), its standard deviation
    √(Σ aᵢ² σᵢ²) (root sum of squares) — the textbook answers the methods must reproduce.

    Attributes:
        input_names: names of the inputs x_i.
        coefficients: (r, k) sensitivities a_ji.
        intercept: (r,) constants (default 0).
        response_names: names of the responses (default ``y``, ``y1``, ...).
        unit: unit of every response (reports only).
    """

    input_names: tuple[str, ...]
    coefficients: tuple[tuple[float, ...], ...]
    intercept: tuple[float, ...] = ()
    response_names: tuple[str, ...] = ()
    unit: str = ""
    chunk_size: int = 100_000

    def __post_init__(self) -> None:
        matrix = np.atleast_2d(np.asarray(self.coefficients, dtype=float))
        r, k = matrix.shape
        if k != len(self.input_names):
            raise ConfigError(
                f"LinearModel: coefficients have {k} columns for {len(self.input_names)} inputs"
            )
        object.__setattr__(self, "input_names", tuple(self.input_names))
        object.__setattr__(self, "coefficients", tuple(tuple(map(float, row)) for row in matrix))
        object.__setattr__(
            self, "intercept", tuple(map(float, self.intercept)) if self.intercept else (0.0,) * r
        )
        if not self.response_names:
            names = ("y",) if r == 1 else tuple(f"y{j + 1}" for j in range(r))
            object.__setattr__(self, "response_names", names)
        if len(self.response_names) != r or len(self.intercept) != r:
            raise ConfigError("LinearModel: one intercept and one name per response row")

    @property
    def units(self) -> Mapping[str, str]:
        return {name: self.unit for name in self.response_names}

    @property
    def matrix(self) -> FloatArray:
        """(r, k) coefficients."""
        return np.asarray(self.coefficients, dtype=float)

    def evaluate(self, x: FloatArray) -> Evaluation:
        """y = intercept + x Aᵀ for every row of ``x``."""
        x = _check_inputs(x, len(self.input_names))
        values = x @ self.matrix.T + np.asarray(self.intercept)
        return Evaluation(values, np.ones(len(x), dtype=bool), ("",) * len(x))

    def jacobian(self, x0: FloatArray) -> FloatArray:
        """Analytic sensitivities ∂y_j/∂x_i, (r, k) (constant)."""
        return self.matrix

    def describe(self) -> dict[str, Any]:
        return {
            "model": "linear",
            "coefficients": [list(row) for row in self.coefficients],
            "intercept": list(self.intercept),
        }
