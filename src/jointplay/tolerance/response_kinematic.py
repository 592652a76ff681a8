"""The ideal-joint kinematic response models: :class:`FourBarKinematics` (vectorised) and
:class:`GeneralKinematics` (any template, one sample at a time); :func:`kinematic_model`
chooses. :mod:`jointplay.tolerance.responses` describes the models.
"""

from __future__ import annotations

import math
from collections.abc import Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError, JointplayError, SettingError
from jointplay.kinematics import batch, fourbar
from jointplay.model.mechanism import Mechanism
from jointplay.model.templates import FourBarGeometry, TemplateSpec, template_of

if TYPE_CHECKING:  # the dynamics import Numba: loaded only by dynamic studies
    from jointplay.model.mechanism import PrismaticJoint
from jointplay.tolerance.response_base import (
    Evaluation,
    _check_inputs,
    _error,
)

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


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
