"""Response models: what a tolerance study computes for each sample of the inputs.

A response model is a small frozen object with ``input_names`` (the columns of its input
matrix, SI), ``response_names``, ``units`` and one method, :meth:`evaluate`, that maps an
(m, k) block of input samples to an :class:`Evaluation` — the (m, r) responses plus, per
sample, whether it succeeded and why not. Failures are data, never exceptions: a sample whose
linkage cannot be assembled or whose integration fails is marked and kept. Models hold plain
data only, so they can be sent to worker processes and Dask workers.

Models:

* :class:`FourBarKinematics` — the ideal-joint kinematics of a four-bar template, vectorised
  over (samples × crank angles) with :mod:`jointplay.kinematics.batch` (the closed form of
  :mod:`jointplay.kinematics.fourbar` without trigonometric functions in the inner loop);
  peaks refined by parabolic interpolation around the grid maximum. Responses: ``rocker_swing``, ``theta3_min``,
  ``theta3_max``, ``theta4_min``, ``theta4_max`` (rad), ``omega3_peak``, ``omega4_peak``
  (largest |ω|, rad/s), ``alpha3_peak``, ``alpha4_peak`` (rad/s²),
  ``transmission_angle_min`` (the smallest of min(μ, π − μ) over the cycle, rad, exact),
  ``path_deviation_<point>`` (largest distance between a coupler point and the same point of
  the nominal linkage at the same crank angle, m).
* :class:`GeneralKinematics` — any template mechanism (e.g. the slider-crank), one sample at a
  time with :func:`jointplay.kinematics.analysis.analyse`: ``theta{k}_min``/``_max``,
  ``omega{k}_peak``, ``alpha{k}_peak`` per rotating link, ``{slider}_stroke``,
  ``{slider}_v_peak``, ``{slider}_a_peak`` per slider.
* :class:`DynamicResponses` — the clearance-joint dynamics of every sample of a block at once
  with the batch engine (:func:`jointplay.dynamics.batch.simulate_batch`: compiled lanes, no
  trajectories): ``omega{k}_peak``, ``alpha{k}_peak``, ``F_<joint>_peak`` (N),
  ``torque_peak`` (N·m), largest |value| over the analysed revolutions; checks
  ``penetration_ratio_<joint>``.
* :class:`RunningResponses` — the dynamic peaks plus the running responses of each sample's
  single-engine simulation (rocker-speed error, joint force, contact pressure, wear rate);
  the same checks, from each simulation (:func:`penetration_ratios`).
* :class:`LinearModel` — a linear stack ``y = c + Σ aᵢ xᵢ`` whose worst case, RSS and
  Monte Carlo answers are known in closed form (verification), with an analytic Jacobian.

Per-sample checks: a model that can tell a non-physical sample (:class:`CheckedModel`: the
two dynamic models) names dimensionless ``check_names`` and returns their values per sample
in :attr:`Evaluation.checks` beside the responses: ``penetration_ratio_<joint>``, the deepest
penetration δ = |e| − c of the joint over the analysed revolutions divided by that sample's
radial clearance c (above 1: the pin sinks deeper into its bearing than the clearance, the
peaks are not physical; negative: the pin never touched its bearing). The kinematic models
have none.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any, Protocol, runtime_checkable

import numpy as np
from numpy.typing import NDArray

from jointplay.dynamics.cycles import DEFAULT_SETTLE, analysed_revolutions, settle_revolutions
from jointplay.errors import ConfigError, JointplayError, PartialInterrupt, SettingError
from jointplay.execution.backends import Backend
from jointplay.kinematics import batch, fourbar
from jointplay.model.mechanism import Mechanism
from jointplay.model.templates import FourBarGeometry, TemplateSpec, template_of

if TYPE_CHECKING:  # the dynamics import Numba: loaded only by dynamic studies
    from jointplay.contact.friction import FrictionLaw
    from jointplay.contact.laws import ContactLaw
    from jointplay.dynamics.clearance import ClearanceJoint, JointStiffness
    from jointplay.dynamics.setup import ContactModel
    from jointplay.dynamics.simulate import SimulationResult, SolverOptions, Start
    from jointplay.dynamics.wear import OutputSpeedReference, WearSettings
    from jointplay.model.mechanism import PrismaticJoint

__all__ = [
    "RUNNING_RESPONSES",
    "CheckedModel",
    "DifferentiableModel",
    "DynamicResponses",
    "Evaluation",
    "FourBarKinematics",
    "GeneralKinematics",
    "LinearModel",
    "PeakResponses",
    "ResponseModel",
    "RunningResponses",
    "dynamic_model",
    "kinematic_model",
    "penetration_ratios",
    "sample_checks",
]

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


# --- four-bar kinematics, vectorised -----------------------------------------------------------


def _refine_peak(values: FloatArray, index: NDArray[np.intp]) -> FloatArray:
    """Parabola through the grid extreme ``values[i, index[i]]`` and its periodic neighbours.

    Returns the vertex value (for a maximum or a minimum alike; equal to the grid value where
    the three points are collinear).
    """
    n = values.shape[1]
    rows = np.arange(values.shape[0])
    y0 = values[rows, index]
    ym = values[rows, (index - 1) % n]
    yp = values[rows, (index + 1) % n]
    curvature = ym - 2.0 * y0 + yp
    with np.errstate(divide="ignore", invalid="ignore"):
        offset = np.where(curvature != 0.0, 0.5 * (ym - yp) / curvature, 0.0)
    offset = np.clip(offset, -0.5, 0.5)
    return np.asarray(y0 - 0.25 * (ym - yp) * offset, dtype=float)


def _peak_abs(values: FloatArray) -> FloatArray:
    magnitude = np.abs(values)
    return _refine_peak(magnitude, np.argmax(magnitude, axis=1))


@dataclass(frozen=True)
class FourBarKinematics:
    """Kinematic responses of a four-bar template with ideal joints (vectorised).

    Attributes:
        geometry: nominal link lengths, m.
        input_names: toleranced lengths as ``length_<name>`` (others stay nominal).
        angular_velocity: signed crank angular velocity, rad/s.
        branch: assembly branch (+1/−1, see :mod:`jointplay.model.templates`).
        start_angle: crank angle of the first grid point, rad.
        coupler_points: points on the coupler in its frame (origin A, x-axis towards B), m,
            whose path deviation is reported; default: the template's coupler points, or
            the nominal coupler's mid-point ``mid`` if it has none.
        n_angles: crank-angle grid points per revolution (360: 1° steps).
        block: samples per vectorised block: bounds memory to ~30 arrays of
            ``block × n_angles`` doubles; 32 × 360 doubles (92 kB) stay in cache and below the
            allocator's mmap threshold, which matters when several processes run at once.
        chunk_size: samples per task sent to a worker.
    """

    geometry: FourBarGeometry
    input_names: tuple[str, ...]
    angular_velocity: float
    branch: int = 1
    start_angle: float = 0.0
    coupler_points: Mapping[str, tuple[float, float]] = field(default_factory=dict)
    n_angles: int = 360
    block: int = 32
    chunk_size: int = 4096
    _grid: dict[str, FloatArray] = field(default_factory=dict, repr=False, compare=False)

    #: Cost of one sample on one core, s (100 000 samples in ~2.7 s): the process backend
    #: starts workers only when they pay for themselves (:func:`~jointplay.tolerance.execution.run`).
    seconds_per_sample = 3e-5

    def __post_init__(self) -> None:
        object.__setattr__(self, "input_names", tuple(self.input_names))
        object.__setattr__(self, "coupler_points", dict(self.coupler_points))
        lengths = self.geometry.length_names
        for name in self.input_names:
            if not (name.startswith("length_") and name.removeprefix("length_") in lengths):
                raise ConfigError(
                    f"four-bar kinematics: unknown input {name!r}; toleranced lengths are "
                    f"named {['length_' + n for n in lengths]}"
                )
        if not (isinstance(self.n_angles, int) and self.n_angles >= 8):
            raise ConfigError(f"four-bar kinematics: n_angles must be >= 8, got {self.n_angles}")
        if self.branch not in (1, -1):
            raise ConfigError(f"four-bar kinematics: branch must be +1 or -1, got {self.branch}")
        fourbar.check_full_rotation(self.geometry)
        if not self.coupler_points:
            object.__setattr__(self, "coupler_points", {"mid": (self.geometry.coupler / 2, 0.0)})
        theta2 = self.start_angle + 2.0 * np.pi * np.arange(self.n_angles) / self.n_angles
        grid: dict[str, FloatArray] = {"c2": np.cos(theta2), "s2": np.sin(theta2)}
        g = self.geometry
        nominal = np.array([[g.crank, g.coupler, g.rocker, g.ground]])
        state = batch.positions(nominal, grid["c2"], grid["s2"], self.branch)
        # Reference directions: the mean nominal coupler and rocker directions, so that the
        # angles of a rocking link never wrap within its swing.
        grid["ref3"] = np.array(math.atan2(state.s3.mean(), state.c3.mean()))
        grid["ref4"] = np.array(math.atan2(state.s4.mean(), state.c4.mean()))
        for name, (px, py) in self.coupler_points.items():
            x, y = batch.coupler_point(state, px, py)
            grid[f"path_x_{name}"], grid[f"path_y_{name}"] = x[0], y[0]
        object.__setattr__(self, "_grid", grid)

    @classmethod
    def from_mechanism(
        cls, mechanism: Mechanism, input_names: Sequence[str], **options: Any
    ) -> FourBarKinematics:
        """The model of a four-bar template mechanism (its lengths, speed, branch, points)."""
        spec = template_of(mechanism)
        if not isinstance(spec.geometry, FourBarGeometry):
            raise ConfigError(
                f"mechanism {mechanism.name!r} is a {spec.geometry.kind}, not a four-bar"
            )
        options.setdefault("coupler_points", dict(spec.coupler_points))
        return cls(
            geometry=spec.geometry,
            input_names=tuple(input_names),
            angular_velocity=mechanism.driver.angular_velocity,
            branch=mechanism.branch,
            start_angle=mechanism.driver.start_angle,
            **options,
        )

    @property
    def response_names(self) -> tuple[str, ...]:
        return (
            "rocker_swing",
            "theta3_min",
            "theta3_max",
            "theta4_min",
            "theta4_max",
            "omega3_peak",
            "omega4_peak",
            "alpha3_peak",
            "alpha4_peak",
            "transmission_angle_min",
            *(f"path_deviation_{name}" for name in self.coupler_points),
        )

    @property
    def units(self) -> Mapping[str, str]:
        units = {name: "rad" for name in self.response_names}
        units.update({"omega3_peak": "rad/s", "omega4_peak": "rad/s"})
        units.update({"alpha3_peak": "rad/s^2", "alpha4_peak": "rad/s^2"})
        units.update({f"path_deviation_{name}": "m" for name in self.coupler_points})
        return units

    def describe(self) -> dict[str, Any]:
        return {
            "model": "four-bar kinematics (closed form, ideal joints)",
            "crank_angle_points": self.n_angles,
            "peak_refinement": "parabolic interpolation around the grid extreme",
            "angular_velocity_rad_s": self.angular_velocity,
            "branch": self.branch,
            "coupler_points_m": {k: list(v) for k, v in self.coupler_points.items()},
            "transmission_angle": "min over the cycle of min(mu, pi - mu), exact (crank at 0 and 180 deg)",
            "path_deviation": "largest distance to the nominal coupler point at the same crank angle",
        }

    def lengths(self, x: FloatArray) -> FloatArray:
        """(m, 4) crank, coupler, rocker, ground lengths of the samples ``x``, m."""
        g = self.geometry
        out = np.tile([g.crank, g.coupler, g.rocker, g.ground], (len(x), 1)).astype(float)
        for column, name in enumerate(self.input_names):
            out[:, g.length_names.index(name.removeprefix("length_"))] = x[:, column]
        return out

    def evaluate(self, x: FloatArray) -> Evaluation:
        """Responses of the samples ``x`` (m, k); unassemblable samples are marked failed."""
        x = _check_inputs(x, len(self.input_names))
        lengths = self.lengths(x)
        ok = batch.turns_fully(lengths)
        g = self.geometry
        safe = np.where(ok[:, None], lengths, [g.crank, g.coupler, g.rocker, g.ground])
        values = np.empty((len(x), len(self.response_names)))
        for start in range(0, len(x), self.block):
            values[start : start + self.block] = self._responses(safe[start : start + self.block])
        finite = np.all(np.isfinite(values), axis=1)
        errors = []
        for i in range(len(x)):
            if not ok[i]:
                errors.append(_assembly_message(lengths[i]))
            elif not finite[i]:
                errors.append(
                    "AssemblyError: the coupler and rocker become collinear (a change-point "
                    "linkage): velocities are undefined there"
                )
            else:
                errors.append("")
        ok &= finite
        values[~ok] = np.nan
        return Evaluation(values, ok, tuple(errors))

    def _responses(self, lengths: FloatArray) -> FloatArray:
        grid = self._grid
        c2, s2 = grid["c2"], grid["s2"]
        w2 = self.angular_velocity
        state = batch.positions(lengths, c2, s2, self.branch)
        omega3, omega4 = batch.velocities(lengths, state, c2, s2, w2)
        alpha3, alpha4 = batch.accelerations(lengths, state, c2, s2, w2, omega3, omega4)
        out = np.empty((len(lengths), len(self.response_names)))
        theta3 = self._extremes(state.c3, state.s3, float(grid["ref3"]))
        theta4 = self._extremes(state.c4, state.s4, float(grid["ref4"]))
        out[:, 0] = theta4[1] - theta4[0]
        out[:, 1], out[:, 2] = theta3
        out[:, 3], out[:, 4] = theta4
        out[:, 5] = _peak_abs(omega3)
        out[:, 6] = _peak_abs(omega4)
        out[:, 7] = _peak_abs(alpha3)
        out[:, 8] = _peak_abs(alpha4)
        out[:, 9] = batch.transmission_angle_min(lengths)
        for column, (name, (px, py)) in enumerate(self.coupler_points.items(), start=10):
            x, y = batch.coupler_point(state, px, py)
            dist2 = (x - grid[f"path_x_{name}"]) ** 2 + (y - grid[f"path_y_{name}"]) ** 2
            distance = np.sqrt(dist2)
            out[:, column] = _refine_peak(distance, np.argmax(dist2, axis=1))
        return out

    @staticmethod
    def _extremes(cos: FloatArray, sin: FloatArray, ref: float) -> tuple[FloatArray, FloatArray]:
        """Smallest and largest link angle (rad) over the grid, refined, unwrapped about ``ref``.

        The angle relative to ``ref`` is φ = 2 atan(v/(1 + u)) with (u, v) the direction
        turned by −ref; φ is monotonic in v/(1 + u), so only the extremes need an atan.
        """
        cr, sr = math.cos(ref), math.sin(ref)
        u = cos * cr + sin * sr
        v = sin * cr - cos * sr
        with np.errstate(divide="ignore", invalid="ignore"):
            half = v / (1.0 + u)
        rows = np.arange(len(cos))
        n = cos.shape[1]
        result = []
        for index in (np.argmin(half, axis=1), np.argmax(half, axis=1)):
            neighbours = np.stack([(index - 1) % n, index, (index + 1) % n], axis=1)
            phi = 2.0 * np.arctan2(v[rows[:, None], neighbours], 1.0 + u[rows[:, None], neighbours])
            result.append(ref + _refine_peak(phi, np.ones(len(cos), dtype=np.intp)))
        return result[0], result[1]


def _assembly_message(lengths: FloatArray) -> str:
    try:
        geometry = FourBarGeometry(
            crank=float(lengths[0]),
            coupler=float(lengths[1]),
            rocker=float(lengths[2]),
            ground=float(lengths[3]),
        )
        fourbar.check_full_rotation(geometry)
    except JointplayError as exc:
        return _error(exc)
    return "AssemblyError: the crank cannot turn fully"


# --- any template mechanism, one sample at a time -----------------------------------------------


@dataclass(frozen=True)
class GeneralKinematics:
    """Kinematic responses of any template mechanism (per sample, general analysis).

    Attributes:
        mechanism: the nominal mechanism (a template: its lengths can change).
        input_names: toleranced lengths as ``length_<name>``.
        n_angles: crank-angle grid points per revolution.
        chunk_size: samples per task sent to a worker.
    """

    mechanism: Mechanism
    input_names: tuple[str, ...]
    n_angles: int = 360
    chunk_size: int = 64

    def __post_init__(self) -> None:
        object.__setattr__(self, "input_names", tuple(self.input_names))
        names = template_of(self.mechanism).geometry.length_names
        for name in self.input_names:
            if not (name.startswith("length_") and name.removeprefix("length_") in names):
                raise ConfigError(
                    f"kinematics of {self.mechanism.name!r}: unknown input {name!r}; toleranced "
                    f"lengths are named {['length_' + n for n in names]}"
                )

    def _layout(self) -> tuple[list[tuple[str, int]], list[PrismaticJoint]]:
        from jointplay.model.columns import rotating_links, sliders

        return rotating_links(self.mechanism), sliders(self.mechanism)

    @property
    def response_names(self) -> tuple[str, ...]:
        links, slides = self._layout()
        names: list[str] = []
        for _, number in links:
            names += [f"theta{number}_min", f"theta{number}_max"]
            names += [f"omega{number}_peak", f"alpha{number}_peak"]
        for joint in slides:
            names += [f"{joint.link_b}_stroke", f"{joint.link_b}_v_peak", f"{joint.link_b}_a_peak"]
        return tuple(names)

    @property
    def units(self) -> Mapping[str, str]:
        suffixes = {
            "_min": "rad",
            "_max": "rad",
            "_stroke": "m",
            "_v_peak": "m/s",
            "_a_peak": "m/s^2",
        }
        units = {}
        for name in self.response_names:
            if name.startswith("omega"):
                units[name] = "rad/s"
            elif name.startswith("alpha"):
                units[name] = "rad/s^2"
            else:
                units[name] = next(u for s, u in suffixes.items() if name.endswith(s))
        return units

    def describe(self) -> dict[str, Any]:
        return {
            "model": "kinematics (general analysis, ideal joints)",
            "crank_angle_points": self.n_angles,
            "peak_refinement": "parabolic interpolation around the grid extreme",
        }

    def evaluate(self, x: FloatArray) -> Evaluation:
        from jointplay.kinematics.analysis import analyse
        from jointplay.model.templates import with_lengths

        x = _check_inputs(x, len(self.input_names))
        links, slides = self._layout()
        driver = self.mechanism.driver
        angles = driver.start_angle + driver.direction * 2 * np.pi * np.arange(self.n_angles) / (
            self.n_angles
        )
        values = np.full((len(x), len(self.response_names)), np.nan)
        ok = np.zeros(len(x), dtype=bool)
        errors = []
        for i, row in enumerate(x):
            lengths = {
                n.removeprefix("length_"): float(v)
                for n, v in zip(self.input_names, row, strict=True)
            }
            try:
                kin = analyse(with_lengths(self.mechanism, **lengths), angles)
            except (JointplayError, np.linalg.LinAlgError) as exc:
                errors.append(_error(exc))
                continue
            out: list[FloatArray] = []
            for name, _ in links:
                phi = np.unwrap(kin.angle(name))[None, :]
                out += [
                    -_refine_peak(-phi, np.argmin(phi, axis=1)),
                    _refine_peak(phi, np.argmax(phi, axis=1)),
                    _peak_abs(kin.omega(name)[None, :]),
                    _peak_abs(kin.alpha(name)[None, :]),
                ]
            for joint in slides:
                axis = np.array([math.cos(joint.axis_angle), math.sin(joint.axis_angle)])
                pos, vel, acc = kin.point(joint.link_b, joint.point_b)
                s = (pos @ axis)[None, :]
                stroke = _refine_peak(s, np.argmax(s, axis=1)) + _refine_peak(
                    -s, np.argmin(s, axis=1)
                )
                out += [stroke, _peak_abs((vel @ axis)[None, :]), _peak_abs((acc @ axis)[None, :])]
            values[i] = np.concatenate(out)
            ok[i] = bool(np.all(np.isfinite(values[i])))
            errors.append(
                "" if ok[i] else "AssemblyError: non-finite kinematics (singular position)"
            )
        values[~ok] = np.nan
        return Evaluation(values, ok, tuple(errors))


def kinematic_model(
    mechanism: Mechanism, input_names: Sequence[str], **options: Any
) -> FourBarKinematics | GeneralKinematics:
    """The kinematic response model of ``mechanism``: vectorised for four-bars, general otherwise."""
    spec = mechanism.template
    if not isinstance(spec, TemplateSpec):
        raise SettingError(
            "mechanism {name!r} has no template: tolerance studies of link lengths need a "
            "four-bar or slider-crank template (use {responses} dynamic for clearances)",
            name=mechanism.name,
        )
    if isinstance(spec.geometry, FourBarGeometry):
        return FourBarKinematics.from_mechanism(mechanism, input_names, **options)
    return GeneralKinematics(mechanism, tuple(input_names), **options)


# --- clearance dynamics, one simulation per sample -----------------------------------------------


def _steady_start() -> Start:
    from jointplay.dynamics.simulate import Start

    return Start("steady")


def _default_solver() -> SolverOptions:
    from jointplay.dynamics.simulate import SolverOptions

    return SolverOptions()


@dataclass(frozen=True)
class DynamicResponses:
    """Peaks of the clearance-joint dynamics, one simulation per sample.

    Attributes:
        mechanism: the nominal mechanism.
        input_names: ``length_<name>`` (template lengths) and ``clearance_<joint>`` inputs.
        law: normal contact law of every clearance joint (a :class:`ContactLaw` instance).
        journal_radius: pin radius per clearance joint, m.
        fixed_clearances: radial clearance (m) of clearance joints that are not inputs.
        start: start of motion (:class:`jointplay.dynamics.simulate.Start`; default: the
            nominal steady motion — the mechanism as it runs, not its start-up).
        settle: start-up revolutions simulated first and left out of the peaks (default 2).
        revolutions: analysed crank revolutions after them.
        solver: integration settings (:class:`jointplay.dynamics.simulate.SolverOptions`).
        friction: friction law of every clearance joint, or ``None``.
        method: integration method of the batch engine: ``"explicit"`` (Dormand–Prince
            5(4)), ``"implicit"`` (Radau IIA) or ``"auto"`` (chosen from the nominal contact
            laws, the same for every block: :func:`jointplay.dynamics.batch.choose_method`).
        backend: where the lanes of a block run
            (:class:`~jointplay.execution.backends.Backend`, the backend of
            :func:`jointplay.dynamics.batch.simulate_batch`): ``"local"`` (threads over the
            cores of this process), ``"processes"`` (this process's pool of worker processes,
            kept from block to block), ``"dask"`` or ``"gpu"`` (JAX). A study's execution
            backend sets it (:func:`jointplay.tolerance.execution.run`).
        chunk_size: samples per block.
        stiffness_from: joint → how its contact stiffness follows its geometry
            (:class:`~jointplay.dynamics.clearance.JointStiffness`): the law's stiffness and
            exponent are refitted to every sample's clearance of those joints.
    """

    mechanism: Mechanism
    input_names: tuple[str, ...]
    law: ContactLaw
    journal_radius: Mapping[str, float]
    fixed_clearances: Mapping[str, float] = field(default_factory=dict)
    start: Start = field(default_factory=_steady_start)
    settle: int = DEFAULT_SETTLE
    revolutions: float = 1.0
    solver: SolverOptions = field(default_factory=_default_solver)
    friction: FrictionLaw | None = None
    method: str = "auto"
    backend: Backend = field(default_factory=lambda: Backend("local"))
    chunk_size: int = 64
    stiffness_from: Mapping[str, JointStiffness] = field(default_factory=dict)

    #: Rough cost of one sample on one core (the conventional four-bar, one revolution), s:
    #: the execution backend starts worker processes only when they pay for themselves.
    seconds_per_sample = 0.015

    def __post_init__(self) -> None:
        from jointplay.contact.laws import ContactLaw

        if self.method not in ("auto", "explicit", "implicit"):
            raise ConfigError(
                f"dynamic responses: method must be auto, explicit or implicit, got {self.method!r}"
            )
        if not isinstance(self.backend, Backend):
            raise ConfigError(
                f"dynamic responses: backend must be a Backend (jointplay.execution), got "
                f"{type(self.backend).__name__}"
            )

        object.__setattr__(self, "input_names", tuple(self.input_names))
        object.__setattr__(self, "journal_radius", dict(self.journal_radius))
        object.__setattr__(self, "fixed_clearances", dict(self.fixed_clearances))
        object.__setattr__(self, "stiffness_from", dict(self.stiffness_from))
        if not isinstance(self.law, ContactLaw):
            raise ConfigError(
                f"dynamic responses: law must be a ContactLaw instance, got {type(self.law).__name__}"
            )
        analysed_revolutions(self.revolutions, "dynamic responses: revolutions")
        settle_revolutions(self.settle, "dynamic responses: settle")
        lengths = (
            template_of(self.mechanism).geometry.length_names
            if isinstance(self.mechanism.template, TemplateSpec)
            else ()
        )
        joints = {j.name for j in self.mechanism.revolute_joints}
        for name in self.input_names:
            if name.startswith("length_") and name.removeprefix("length_") in lengths:
                continue
            if name.startswith("clearance_") and name.removeprefix("clearance_") in joints:
                if name.removeprefix("clearance_") not in self.journal_radius:
                    raise ConfigError(f"dynamic responses: no journal radius for input {name!r}")
                continue
            raise ConfigError(
                f"dynamic responses: unknown input {name!r}; inputs are length_<length> "
                f"({list(lengths)}) and clearance_<joint> ({sorted(joints)})"
            )
        for joint in self.fixed_clearances:
            if joint not in self.journal_radius:
                raise ConfigError(f"dynamic responses: no journal radius for joint {joint!r}")

    @property
    def clearance_joints(self) -> tuple[str, ...]:
        """Joints modelled with clearance, in the mechanism's joint order."""
        chosen = {
            n.removeprefix("clearance_") for n in self.input_names if n.startswith("clearance_")
        }
        chosen |= set(self.fixed_clearances)
        return tuple(j.name for j in self.mechanism.joints if j.name in chosen)

    @property
    def peak_keys(self) -> tuple[str, ...]:
        """Keys of :attr:`SimulationResult.peaks` reported, in column order."""
        from jointplay.model.columns import rotating_links

        numbers = [number for _, number in rotating_links(self.mechanism)]
        return (
            *(f"omega{k}" for k in numbers),
            *(f"alpha{k}" for k in numbers),
            *(f"F_{j.name}" for j in self.mechanism.joints),
            "torque",
        )

    @property
    def response_names(self) -> tuple[str, ...]:
        return tuple(f"{key}_peak" for key in self.peak_keys)

    @property
    def check_names(self) -> tuple[str, ...]:
        """``penetration_ratio_<joint>`` then ``elastic_ratio_<joint>`` per clearance joint
        (see the module docstring)."""
        return tuple(
            f"{prefix}{joint}"
            for prefix in (PENETRATION_RATIO, ELASTIC_RATIO)
            for joint in self.clearance_joints
        )

    def clearances(self, x: FloatArray) -> FloatArray:
        """(m, c) radial clearance of every clearance joint of the samples ``x``, m: the
        ``clearance_<joint>`` input, else the joint's fixed clearance."""
        x = _check_inputs(x, len(self.input_names))
        columns = []
        for joint in self.clearance_joints:
            name = f"clearance_{joint}"
            if name in self.input_names:
                columns.append(x[:, self.input_names.index(name)])
            else:
                columns.append(np.full(len(x), self.fixed_clearances[joint]))
        return np.stack(columns, axis=1) if columns else np.empty((len(x), 0))

    @property
    def units(self) -> Mapping[str, str]:
        units = {}
        for key in self.peak_keys:
            prefix = key.rstrip("0123456789")
            units[f"{key}_peak"] = {
                "omega": "rad/s",
                "alpha": "rad/s^2",
                "torque": "N*m",
            }.get(prefix, "N")
        return units

    def describe(self) -> dict[str, Any]:
        def fields_of(obj: Any) -> dict[str, Any]:
            return {k: v for k, v in vars(obj).items() if not k.startswith("_")}

        choice = self.method_choice()
        return {
            "model": "clearance-joint dynamics (batch engine, jointplay.dynamics.batch)",
            "contact": self.contact_text,
            "method": choice.method,
            "method_reason": choice.reason,
            "clearance_joints": list(self.clearance_joints),
            "journal_radius_m": dict(self.journal_radius),
            "fixed_clearances_m": dict(self.fixed_clearances),
            "contact_law": {"name": self.law.name, **self._law_fields()},
            "stiffness_from_geometry": {
                nominal.joint: {
                    **fields_of(rule),
                    "nominal_joint_law": fields_of(nominal.law),
                    "nominal_clearance_m": nominal.clearance,
                }
                for nominal in self._nominal_joints(None)
                if (rule := self.stiffness_from.get(nominal.joint)) is not None
            },
            "friction": None
            if self.friction is None
            else {"name": self.friction.name, **fields_of(self.friction)},
            "start": self.start.mode,
            "settle_revolutions": self.settle,
            "revolutions": self.revolutions,
            "solver": fields_of(self.solver),
            "peaks": (
                f"largest |value| over the {self.revolutions:g} revolution(s) after "
                f"{self.settle} start-up revolution(s), searched between the integrator's "
                "steps near every running peak (jointplay._kernels.batch)"
            ),
            "checks": {
                name: PENETRATION_RATIO_DEFINITION
                if name.startswith(PENETRATION_RATIO)
                else ELASTIC_RATIO_DEFINITION
                for name in self.check_names
            },
        }

    def _law_fields(self) -> dict[str, Any]:
        """The contact law's parameters; a stiffness from the geometry is named as such."""
        from jointplay.dynamics.clearance import stiffness_field

        fields = {k: v for k, v in vars(self.law).items() if not k.startswith("_")}
        if self.stiffness_from:
            for name in (stiffness_field(self.law), "exponent"):
                fields[name] = "per joint and sample, from its geometry (stiffness_from_geometry)"
        return fields

    @property
    def contact_text(self) -> str:
        """The contact of the clearance joints in words (summaries and reports)."""
        from jointplay.dynamics.clearance import stiffness_field

        law = self.law
        text = f"{law.name} law"
        if hasattr(law, "restitution"):
            text += f", coefficient of restitution {law.restitution:g}"
        rules = {rule.law for rule in self.stiffness_from.values()}
        if rules:
            depth = min(rule.fit_depth for rule in self.stiffness_from.values())
            text += (
                f", stiffness from each joint's geometry ({', '.join(sorted(rules))} law, "
                f"F = k δ^n fitted over δ ≤ {depth * 1e6:g} µm, refitted to every sample's "
                "clearance)"
            )
        else:
            k = getattr(law, stiffness_field(law), math.nan)
            text += f", stiffness {k:.4g} N/m^{getattr(law, 'exponent', 1.0):g}"
        friction = self.friction
        if friction is None:
            return text + "; no friction"
        mu = getattr(friction, "mu", getattr(friction, "mu_static", math.nan))
        return text + f"; {friction.name} friction, coefficient {mu:g}"

    def method_choice(self) -> Any:
        """The batch engine's method for this model (the nominal contact laws decide, so
        every block of samples uses the same one)."""
        from jointplay.dynamics.batch import MethodChoice, choose_method

        if self.method != "auto":
            return MethodChoice(self.method, f"{self.method}, as asked", math.nan, math.nan)
        return choose_method(self.mechanism, self._nominal_joints(None), solver=self.solver)

    def _nominal_joints(self, x: FloatArray | None) -> list[Any]:
        """The clearance joints with the fixed clearances, the input ones at their first
        sample in ``x`` (any valid value: the samples replace it), else at their fit's
        nominal clearance (what :meth:`method_choice` linearises the contact law at)."""
        joints = []
        for joint in self.clearance_joints:
            name = f"clearance_{joint}"
            if joint in self.fixed_clearances:
                value = self.fixed_clearances[joint]
            elif x is not None and len(x) and name in self.input_names:
                column = x[:, self.input_names.index(name)]
                valid = column[np.isfinite(column) & (column > 0)]
                value = float(valid[0]) if valid.size else 0.01 * self.journal_radius[joint]
            else:  # the fit's nominal clearance, else 1 % of the pin radius
                fit = getattr(self.mechanism.joint(joint), "fit", None)
                value = (
                    float(fit.clearance)
                    if fit is not None and fit.clearance
                    else 0.01 * self.journal_radius[joint]
                )
            joints.append(self._joint(joint, value))
        return joints

    def _joint(self, joint: str, clearance: float) -> ClearanceJoint:
        """Clearance joint ``joint`` at ``clearance`` (m), its stiffness fitted to it when it
        follows the geometry."""
        from jointplay.dynamics.clearance import ClearanceJoint, stiffness_field

        rule = self.stiffness_from.get(joint)
        law = self.law
        if rule is not None:
            k, n = rule.fit(self.journal_radius[joint], clearance)
            law = dataclasses.replace(law, **{stiffness_field(law): k, "exponent": n})
        return ClearanceJoint(
            joint,
            clearance=clearance,
            journal_radius=self.journal_radius[joint],
            law=law,
            friction=self.friction,
            stiffness_from=rule,
        )

    def batch_samples(self, x: FloatArray) -> Any:
        """The :class:`~jointplay.dynamics.batch.BatchSamples` of the input block ``x``."""
        from jointplay.dynamics.batch import BatchSamples

        lengths = {}
        clearances = {}
        for k, name in enumerate(self.input_names):
            if name.startswith("length_"):
                lengths[name.removeprefix("length_")] = x[:, k]
            else:
                clearances[name.removeprefix("clearance_")] = x[:, k]
        return BatchSamples(lengths=lengths, clearances=clearances, size=len(x))

    def simulate_one(self, row: FloatArray) -> SimulationResult:
        """The simulation of one sample; a failed integration is returned, not raised.

        Its :attr:`~jointplay.dynamics.simulate.SimulationResult.status` and ``message`` say
        how it ended (``simulate(..., throw=False)``); nominal peaks are not computed.

        Raises:
            JointplayError: the sample's mechanism cannot be assembled or set up.
        """
        from jointplay.dynamics.simulate import simulate
        from jointplay.model.templates import with_lengths

        lengths: dict[str, float] = {}
        clearance = dict(self.fixed_clearances)
        for name, value in zip(self.input_names, row, strict=True):
            if name.startswith("length_"):
                lengths[name.removeprefix("length_")] = float(value)
            else:
                clearance[name.removeprefix("clearance_")] = float(value)
        mechanism = with_lengths(self.mechanism, **lengths) if lengths else self.mechanism
        joints = [self._joint(joint, clearance[joint]) for joint in self.clearance_joints]
        return simulate(
            mechanism,
            joints,
            revolutions=self.revolutions,
            settle=self.settle,
            start=self.start,
            solver=self.solver,
            throw=False,
        )

    def evaluate(self, x: FloatArray) -> Evaluation:
        """Simulate every sample of the block at once with the batch engine
        (:func:`jointplay.dynamics.batch.simulate_batch`); integration and assembly failures
        are marked, not raised. The results of a sample do not depend on the block.

        The checks are the engine's deepest penetration per joint (``pen_<joint>`` of
        :attr:`~jointplay.dynamics.batch.BatchResult.statistics`, m) over each sample's
        radial clearance (:meth:`clearances`, m)."""
        from jointplay.dynamics.batch import BatchInterrupted, simulate_batch
        from jointplay.dynamics.integrate import IntegrationStatus

        x = _check_inputs(x, len(self.input_names))
        if len(x) == 0:
            return Evaluation(
                np.empty((0, len(self.response_names))),
                np.zeros(0, bool),
                (),
                np.empty((0, len(self.check_names))),
            )
        try:
            result = simulate_batch(
                self.mechanism,
                self._nominal_joints(x),
                self.batch_samples(x),
                revolutions=self.revolutions,
                settle=self.settle,
                start=self.start,
                solver=self.solver,
                method=self.method_choice().method,
                backend=self.backend,
            )
        except BatchInterrupted as stopped:  # the finished samples go on with the interrupt
            finished = stopped.result.status != IntegrationStatus.INTERRUPTED
            raise PartialInterrupt(self._evaluation(x, stopped.result, finished)) from None
        return self._evaluation(x, result)

    def _evaluation(
        self, x: FloatArray, result: Any, finished: BoolArray | None = None
    ) -> Evaluation:
        """The :class:`Evaluation` of the block ``x`` from its batch result."""
        values = result.peaks[list(self.peak_keys)].to_numpy(dtype=float)
        penetration = result.statistics[[f"pen_{j}" for j in self.clearance_joints]]
        deepest = penetration.to_numpy(dtype=float)
        clearance = self.clearances(x)
        forces = result.peaks[[f"F_{j}" for j in self.clearance_joints]].to_numpy(dtype=float)
        checks = np.hstack(
            [
                _ratio(deepest, clearance),
                _elastic_ratios(self.mechanism, self.clearance_joints, self.journal_radius,
                                clearance, deepest, forces),
            ]
        )  # fmt: skip
        ok = np.asarray(result.ok, dtype=bool)
        return Evaluation(values, ok, tuple(result.errors), checks, finished)


def _ratio(penetration: FloatArray, clearance: FloatArray) -> FloatArray:
    """Penetration over clearance, elementwise (a zero clearance gives ±inf, or NaN)."""
    with np.errstate(divide="ignore", invalid="ignore"):
        return np.asarray(penetration / clearance, dtype=float)


def penetration_ratios(result: SimulationResult) -> FloatArray:
    """(c,) ``penetration_ratio_<joint>`` of a single-engine simulation, in the order of its
    clearance joints: the deepest penetration δ = |e| − c over the analysed revolutions (at
    the accepted steps, as the batch engine's ``pen_<joint>``) over the radial clearance c.

    Raises:
        IntegrationError: the simulation stopped at its initial state.
    """
    deepest = result.running.max_penetration
    joints = result.system.clearances
    return _ratio(
        np.array([deepest[joint.joint] for joint in joints]),
        np.array([joint.clearance for joint in joints]),
    )


def _elastic_ratios(
    mechanism: Mechanism,
    joints: Sequence[str],
    journal_radius: Mapping[str, float],
    clearance: FloatArray,
    deepest: FloatArray,
    force: FloatArray,
) -> FloatArray:
    """(m, c) ``elastic_ratio_<joint>``: ``deepest`` (m) over the Hertz approach at ``force``
    (N) for each sample's ``clearance`` (m) (NaN where a value is missing)."""
    from jointplay.dynamics.diagnostics import hertz_approach

    out = np.full(deepest.shape, np.nan)
    for c, joint in enumerate(joints):
        spec = mechanism.joint(joint)
        bearing, pin = mechanism.material_of(spec.link_a), mechanism.material_of(spec.link_b)
        for i in range(len(deepest)):
            f, gap = force[i, c], clearance[i, c]
            if math.isfinite(f) and math.isfinite(gap) and f > 0 and gap > 0:
                approach = hertz_approach(float(f), journal_radius[joint], float(gap), bearing, pin)
                out[i, c] = deepest[i, c] / approach
    return out


def sample_checks(result: SimulationResult) -> FloatArray:
    """(2c,) the checks of a single-engine simulation, in the order of
    :attr:`DynamicResponses.check_names`: :func:`penetration_ratios`, then the elastic
    ratios (``elastic_ratio_<joint>``).

    Raises:
        IntegrationError: the simulation stopped at its initial state.
    """
    joints = result.system.clearances
    names = [joint.joint for joint in joints]
    deepest = result.running.max_penetration
    return np.concatenate(
        [
            penetration_ratios(result),
            _elastic_ratios(
                result.system.mechanism,
                names,
                {joint.joint: joint.journal_radius for joint in joints},
                np.array([[joint.clearance for joint in joints]]),
                np.array([[deepest[name] for name in names]]),
                np.array([[result.peaks[f"F_{name}"]["value"] for name in names]]),
            )[0],
        ]
    )


def peak_contact_pressure(
    mechanism: Mechanism, joint: str, force: float, journal_radius: float, clearance: float
) -> float:
    """The Hertz line-contact pressure (Pa) of a peak contact force ``force`` (N) in the pin
    joint ``joint`` with radial clearance ``clearance`` (m), over its bearing width
    (:func:`jointplay.dynamics.diagnostics.line_contact_pressure`); NaN when the width is not
    known (no link thickness or pin length)."""
    from jointplay.dynamics.diagnostics import line_contact_pressure

    width = mechanism.bearing_width(joint)
    if not width or not math.isfinite(force):
        return math.nan
    spec = mechanism.joint(joint)
    return line_contact_pressure(
        force,
        width,
        journal_radius,
        max(clearance, 1e-9),
        mechanism.material_of(spec.link_a),
        mechanism.material_of(spec.link_b),
    )


def _kinematic_names(kinematic: ResponseModel | None, dynamic: Sequence[str]) -> tuple[str, ...]:
    """The responses of ``kinematic`` that the dynamic ones do not give."""
    if kinematic is None:
        return ()
    return tuple(n for n in kinematic.response_names if n not in set(dynamic))


def _add_kinematic(
    kinematic: ResponseModel | None,
    names: Sequence[str],
    input_names: Sequence[str],
    x: FloatArray,
    evaluation: Evaluation,
) -> Evaluation:
    """``evaluation`` with the ideal-joint responses ``names`` of each sample's lengths
    written into its last columns (one vectorised call); a sample they fail for fails."""
    if not names or kinematic is None:
        return evaluation
    columns = [list(input_names).index(n) for n in kinematic.input_names]
    result = kinematic.evaluate(np.asarray(x, dtype=float)[:, columns])
    chosen = [kinematic.response_names.index(n) for n in names]
    values = evaluation.values.copy()
    values[:, values.shape[1] - len(chosen) :] = result.values[:, chosen]
    errors = tuple(
        error or ("" if result.ok[i] else result.errors[i])
        for i, error in enumerate(evaluation.errors)
    )
    return Evaluation(values, evaluation.ok & result.ok, errors, evaluation.checks)


#: Responses :class:`RunningResponses` adds to the dynamic peaks, with SI units.
RUNNING_RESPONSES: Mapping[str, str] = {
    "rocker_speed_error": "1",
    "joint_force": "N",
    "contact_pressure": "Pa",
    "wear_rate": "m/s",
}


@dataclass(frozen=True)
class RunningResponses:
    """The mechanism as it runs: the dynamic peaks (:class:`DynamicResponses`) plus the
    rocker-speed error against the ideal linkage, the largest joint force, the largest Hertz
    contact pressure and the Archard wear rate of the radial clearance (the fastest and per
    joint). Used by ``tolerance_study(responses="running")`` and the design study.

    Attributes:
        base: the tolerance study's dynamic model (inputs, contact law, start, settle).
        reference: the nominal ideal-joint output speed.
        wear: Archard parameters.
        kinematic: optionally, the ideal-joint kinematic model of the same length inputs:
            its responses that the dynamics do not give (``rocker_swing``,
            ``transmission_angle_min``, …) are added for each sample's lengths, so
            requirements may mix kinematic and dynamic responses.
        chunk_size: samples per task.
    """

    base: DynamicResponses
    reference: OutputSpeedReference
    wear: WearSettings
    kinematic: ResponseModel | None = None
    chunk_size: int = 1

    #: Cost of one sample on one core (one single-engine simulation), s.
    seconds_per_sample = 0.05

    @property
    def kinematic_names(self) -> tuple[str, ...]:
        """The kinematic responses added (those the dynamics do not give themselves)."""
        return _kinematic_names(self.kinematic, self.base.response_names)

    @property
    def input_names(self) -> tuple[str, ...]:
        return self.base.input_names

    @property
    def joints(self) -> tuple[str, ...]:
        return self.base.clearance_joints

    @property
    def check_names(self) -> tuple[str, ...]:
        return self.base.check_names

    @property
    def response_names(self) -> tuple[str, ...]:
        return (
            *self.base.response_names,
            "rocker_speed_error",
            "joint_force",
            "contact_pressure",
            "wear_rate",
            *(f"wear_rate_{j}" for j in self.joints),
            *self.kinematic_names,
        )

    @property
    def units(self) -> Mapping[str, str]:
        units = dict(self.base.units)
        units.update(RUNNING_RESPONSES)
        units.update({f"wear_rate_{j}": "m/s" for j in self.joints})
        if self.kinematic is not None:
            units.update({n: self.kinematic.units[n] for n in self.kinematic_names})
        return units

    def describe(self) -> dict[str, Any]:
        batch_only = ("model", "method", "method_reason", "peaks")
        return {
            "model": (
                "clearance-joint dynamics, one single-engine simulation per sample "
                "(jointplay.dynamics.simulate, Radau IIA)"
            ),
            **{k: v for k, v in self.base.describe().items() if k not in batch_only},
            "peaks": (
                f"largest |value| over the {self.base.revolutions:g} revolution(s) after "
                f"{self.base.settle} start-up revolution(s), located on the continuous "
                "solution (SimulationResult.peaks)"
            ),
            "wear": self.wear.describe(self.base.mechanism),
        }

    def evaluate(self, x: FloatArray) -> Evaluation:
        """One single-engine simulation per sample (:meth:`DynamicResponses.simulate_one`);
        failures are marked, not raised; checks from :func:`penetration_ratios`."""
        from jointplay.dynamics.wear import cycle_wear, speed_error

        mechanism = self.base.mechanism
        names = self.response_names
        values = np.full((len(x), len(names)), np.nan)
        checks = np.full((len(x), len(self.check_names)), np.nan)
        ok = np.zeros(len(x), dtype=bool)
        errors: list[str] = []
        for i, row in enumerate(np.asarray(x, dtype=float)):
            try:
                result = self.base.simulate_one(row)
                if not result.success:
                    errors.append(f"IntegrationError: {result.message}")
                    continue
                peaks = [result.peaks[key]["value"] for key in self.base.peak_keys]
                checks[i] = sample_checks(result)
                wear = cycle_wear(result, self.wear)
                rates = [wear.joints[j].per_hour(wear.rpm) / 3600.0 for j in self.joints]
                forces = [float(result.peaks[f"F_{j}"]["value"]) for j in self.joints]
                pressures = [
                    peak_contact_pressure(
                        mechanism,
                        c.joint,
                        float(result.peaks[f"F_{c.joint}"]["value"]),
                        c.journal_radius,
                        c.clearance,
                    )
                    for c in result.system.clearances
                ]
                values[i, : len(names) - len(self.kinematic_names)] = [
                    *peaks,
                    speed_error(result, self.reference),
                    max(forces),
                    max(pressures),
                    max(rates),
                    *rates,
                ]
            except (JointplayError, np.linalg.LinAlgError) as exc:
                errors.append(f"{type(exc).__name__}: {exc}")
                continue
            ok[i] = True
            errors.append("")
        evaluation = Evaluation(values, ok, tuple(errors), checks)
        return _add_kinematic(self.kinematic, self.kinematic_names, self.input_names, x, evaluation)


@dataclass(frozen=True)
class PeakResponses(DynamicResponses):
    """The dynamic peaks of the batch engine (:class:`DynamicResponses`) plus the largest
    joint force and the largest Hertz contact pressure of each sample, both from its peak
    contact forces: the design study's model when no requirement needs a sample's trajectory
    (the rocker-speed error and the wear do; :class:`RunningResponses` gives those). It runs
    on every backend of the batch engine, the GPU included.

    Attributes:
        kinematic: optionally, the ideal-joint kinematic model of the same length inputs (as
            :attr:`RunningResponses.kinematic`).
    """

    kinematic: ResponseModel | None = None

    @property
    def kinematic_names(self) -> tuple[str, ...]:
        """The kinematic responses added (those the dynamics do not give themselves)."""
        return _kinematic_names(self.kinematic, super().response_names)

    @property
    def response_names(self) -> tuple[str, ...]:
        return (
            *super().response_names, "joint_force", "contact_pressure", *self.kinematic_names
        )  # fmt: skip

    @property
    def units(self) -> Mapping[str, str]:
        units = dict(super().units)
        units.update(joint_force="N", contact_pressure="Pa")
        if self.kinematic is not None:
            units.update({n: self.kinematic.units[n] for n in self.kinematic_names})
        return units

    def describe(self) -> dict[str, Any]:
        return {
            **super().describe(),
            "joint_force": "largest peak contact force over the clearance joints",
            "contact_pressure": (
                "largest Hertz line-contact pressure of the clearance joints' peak forces, "
                "with each sample's radial clearance"
            ),
        }

    def evaluate(self, x: FloatArray) -> Evaluation:
        """The batch engine's peaks of the block (:meth:`DynamicResponses.evaluate`), the
        joint force and contact pressure from them, then the kinematic responses."""
        x = _check_inputs(x, len(self.input_names))
        peaks = super().evaluate(x)
        joints = self.clearance_joints
        keys = list(self.peak_keys)
        forces = peaks.values[:, [keys.index(f"F_{j}") for j in joints]]
        clearances = self.clearances(x)
        radius = [self.journal_radius[joint] for joint in joints]
        pressures = np.array(
            [
                [
                    peak_contact_pressure(self.mechanism, joint, force, r, clearance)
                    for joint, force, r, clearance in zip(joints, row, radius, gaps, strict=True)
                ]
                for row, gaps in zip(forces, clearances, strict=True)
            ]
        ).reshape(len(x), len(joints))
        with np.errstate(invalid="ignore"):
            derived = np.column_stack(
                [forces.max(axis=1, initial=0.0), pressures.max(axis=1, initial=0.0)]
            )
        values = np.column_stack(
            [peaks.values, derived, np.full((len(x), len(self.kinematic_names)), np.nan)]
        )
        evaluation = Evaluation(values, peaks.ok, peaks.errors, peaks.checks)
        return _add_kinematic(self.kinematic, self.kinematic_names, self.input_names, x, evaluation)


def contact_parts(mechanism: Mechanism, contact: ContactModel) -> dict[str, Any]:
    """The ``law``, ``friction`` and ``stiffness_from`` of :class:`DynamicResponses` for the
    contact ``contact``: with a stiffness from the geometry, the law's stiffness and exponent
    are placeholders that every joint refits to its clearance (:meth:`DynamicResponses._joint`)."""
    from jointplay.dynamics.setup import joint_stiffness, make_law

    if contact.law is not None:
        return {"law": contact.law, "friction": contact.friction.build(), "stiffness_from": {}}
    geometric = contact.settings.geometry_law is not None
    return {
        "law": make_law(contact.settings, stiffness=1.0 if geometric else None),
        "friction": contact.friction.build(),
        "stiffness_from": {
            joint.name: rule
            for joint in mechanism.revolute_joints
            if (rule := joint_stiffness(mechanism, joint.name, contact.settings)) is not None
        },
    }


def dynamic_model(
    mechanism: Mechanism,
    input_names: Sequence[str],
    law: ContactLaw,
    *,
    journal_radius: Mapping[str, float] | None = None,
    **options: Any,
) -> DynamicResponses:
    """The dynamic response model of ``mechanism``.

    Clearance joints are those with a ``clearance_<joint>`` input plus the revolute joints
    whose fit data give a fixed ``clearance``; pin radii default to half the fit diameter.
    """
    radius = {j.name: j.fit.diameter / 2.0 for j in mechanism.revolute_joints if j.fit is not None}
    radius.update(journal_radius or {})
    inputs = {n.removeprefix("clearance_") for n in input_names if n.startswith("clearance_")}
    fixed = {
        j.name: j.fit.clearance
        for j in mechanism.revolute_joints
        if j.fit is not None and j.fit.clearance and j.name not in inputs
    }
    return DynamicResponses(
        mechanism,
        tuple(input_names),
        law,
        journal_radius=radius,
        fixed_clearances=fixed,
        **options,
    )
