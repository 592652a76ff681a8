"""Forward dynamics of a mechanism with clearance joints: set-up, integration, results.

:func:`simulate` packs the mechanism (:mod:`jointplay.dynamics.system`, the bridge to the
kernels), chooses the initial state (:class:`Start`), integrates the compiled equations of
motion (:mod:`jointplay._kernels.eom`) with :func:`jointplay.dynamics.integrate.integrate`
(compiled Radau IIA), and returns a frozen :class:`SimulationResult`: the integrator's own
steps, a uniformly sampled time series (both built when first read), the solver
statistics, the status and its message, and, when asked, the nominal (ideal-joint) peaks.
What the mechanism does as it runs — peaks located on the continuous solution, per-revolution
statistics after ``settle`` start-up revolutions, periodicity and plausibility diagnostics —
is :attr:`SimulationResult.running` (:mod:`jointplay.dynamics.running`), computed when first
read.
"""

from __future__ import annotations

import math
import time
from collections.abc import Sequence
from dataclasses import dataclass, field
from functools import cached_property
from typing import Any, Literal

import numpy as np
import pandas as pd
from numpy.typing import NDArray

from jointplay._kernels import constraints as ck
from jointplay._kernels import eom, ids
from jointplay._kernels.integrators import DEFAULT as DEFAULT_INTEGRATOR
from jointplay._kernels.integrators import INTEGRATORS
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.cycles import DEFAULT_SETTLE, analysed_revolutions, settle_revolutions
from jointplay.dynamics.diagnostics import Diagnostic
from jointplay.dynamics.integrate import METHODS as INTEGRATION_METHODS
from jointplay.dynamics.integrate import (
    IntegrationResult,
    IntegrationStatus,
    integrate_mechanism,
)
from jointplay.dynamics.nominal import nominal_analysis
from jointplay.dynamics.regimes import asperity_play
from jointplay.dynamics.running import PEAK_KEYS, RunningBehaviour, characterise
from jointplay.dynamics.system import System, build_system
from jointplay.errors import ConfigError, IntegrationError, SettingError
from jointplay.kinematics.analysis import analyse
from jointplay.model.columns import rotating_links, sliders
from jointplay.model.flat import REVOLUTE
from jointplay.model.mechanism import Mechanism

FloatArray = NDArray[np.float64]
StartMode = Literal["rest", "impulsive", "steady", "ramp"]

#: The start modes and their initial states (pins centred in their bearings in every mode).
START_MODES = {
    "rest": "every link at rest except the crank, which turns about its pivot at full speed "
    "(the paper's case), projected through the ideal and the lubricated joints (a lubricated "
    "pin starts moving with its bearing)",
    "impulsive": "the outcome of an impulsive start from rest: zero velocities projected, "
    "mass-weighted, onto the driver constraint (and the ideal and lubricated joints), so with "
    "every joint dry the crank at first spins about its centre of mass",
    "steady": "every link moving as in the nominal (ideal-joint) mechanism",
    "ramp": "everything at rest, the crank speed rising smoothly (quintic STEP5) to full "
    "speed over ramp_time",
}


@dataclass(frozen=True)
class Start:
    """How the motion starts.

    Attributes:
        mode: ``"rest"`` — the paper's case: pins centred, every link at rest except the
            crank, which turns about its pivot at full speed from t = 0; ``"impulsive"`` —
            zero velocities projected (mass-weighted) onto the driver constraint and the
            ideal joints, the consistent outcome of an impulsive start, in which the crank at
            first spins about its centre of mass; ``"steady"`` — all links moving as in the
            nominal (ideal-joint) mechanism; ``"ramp"`` — everything at rest, the crank speed
            rising smoothly (quintic STEP5) to full speed over ``ramp_time``. Pins start
            centred in their bearings in every mode. (:data:`START_MODES` says the same.)
        ramp_time: duration of the speed ramp, s (``"ramp"`` only; > 0).
        driven: ``False`` switches the motor off after the initial state is set: the mechanism
            coasts (used to check conservation of energy and momentum).
    """

    mode: StartMode = "rest"
    ramp_time: float = 0.0
    driven: bool = True

    def __post_init__(self) -> None:
        if not isinstance(self.mode, str) or self.mode not in START_MODES:
            raise ConfigError(
                f"start mode must be one of {', '.join(START_MODES)}, got {self.mode!r}"
            )
        _real(self.ramp_time, "Start.ramp_time")
        if self.mode == "ramp" and not self.ramp_time > 0:
            raise ConfigError(f"a ramp start needs a ramp duration > 0 s, got {self.ramp_time}")
        if self.mode != "ramp" and self.ramp_time != 0:
            raise ConfigError("a ramp duration applies only to the 'ramp' start")


#: The explicit method (DOPRI5: the batch engine's explicit lanes, the single engine's
#: ``integrator="dopri5"``) runs at this fraction of the solver's rtol and velocity atol. For
#: the same tolerances Dormand–Prince 5(4) lands ~2.5 times further from the exact solution than
#: the single engine's Radau IIA (its error estimate is less conservative: on random samples
#: of the paper's four-bar, ω peaks off a converged solution by up to 2.9e-5 against Radau's
#: 1.2e-5, α peaks by 5.7e-3 against 7e-4); at a fifth of them by 7.1e-6 and 1.2e-3, for
#: ~30 % more steps (docs/performance.md, "Against a converged solution"). The single engine,
#: measured on the paper's conventional set: at the solver's own tolerances ω peaks off by up
#: to 2.3e-5 (steady running, A clear), at a fifth of them by up to 8.8e-6 (docs/performance.md,
#: "From rest: DOPRI5 for the conventional set").
EXPLICIT_TOLERANCE_SCALE = INTEGRATORS["dopri5"].tolerance_scale  # 0.2, the record's
EXPLICIT_TOLERANCES = (
    f"at {EXPLICIT_TOLERANCE_SCALE:g} times the solver's rtol and velocity atol, as close to "
    "the exact solution as Radau IIA at them"
)


@dataclass(frozen=True)
class SolverOptions:
    """Integration settings (Radau IIA order 5 or RODAS4, with contact-onset control).

    Attributes:
        rtol: relative error tolerance.
        atol_position: absolute tolerance on positions (m) and angles (rad).
        atol_velocity: absolute tolerance on velocities (m/s, rad/s).
        max_step: largest step, s (default: the time of 1° of crank rotation).
        onset_tolerance: largest penetration accepted in the step where a contact begins, m,
            > 0 and below the smallest clearance (default: 0.01 % of the smallest clearance
            where a joint's law reads the impact velocity, else 1 %:
            :func:`~jointplay.dynamics.system.onset_fraction`; the control of stiff
            multi-impact contact's accuracy: docs/performance.md, "Stiff multi-impact
            contact: the onset tolerance").
        max_steps: give up after this many accepted steps.
        integrator: ``"radau"`` (Radau IIA, order 5), ``"rodas4"`` (RODAS4, order 4,
            linearly implicit: one LU per step and no Newton iteration) or ``"dopri5"``
            (Dormand–Prince 5(4), explicit, run at ``EXPLICIT_TOLERANCE_SCALE`` of rtol and
            atol_velocity); ``None`` (the default): Radau IIA, or the one the paper method
            of a run's contact names where it holds
            (:func:`jointplay.dynamics.settings.simulate_run`, :func:`preferred_integrator`).
            RODAS4 is measured 1.6–2.8× faster on the paper's IFM ECS contact sets with
            every joint clear, whose damping, full at a negligible penetration, defeats
            Radau's simplified Newton iteration, and slower or no faster on the other
            contacts measured, and 2–30× slower with ideal joints; at the same rtol its
            global error is larger (docs/performance.md, "From rest: a Rosenbrock method for
            the paper's ECS sets"). DOPRI5 is measured 1.4–2.5× faster on the paper's
            conventional IMPACT set, which is not stiff at the accuracy step, and useless on
            stiff contact (its steps then limited by stability: docs/performance.md, "From
            rest: DOPRI5 for the conventional set"). The paper's methods name theirs
            (:attr:`jointplay.study.methods.Method.integrator`).
    """

    rtol: float = 1e-6
    atol_position: float = 1e-10
    atol_velocity: float = 1e-6
    max_step: float | None = None
    onset_tolerance: float | None = None
    max_steps: int = 2_000_000
    integrator: str | None = None

    def __post_init__(self) -> None:
        if self.integrator is not None and self.integrator not in INTEGRATION_METHODS:
            *first, last = INTEGRATION_METHODS
            raise SettingError(
                "{integrator} must be " + ", ".join(first) + f" or {last}, got {{got!r}}",
                got=self.integrator,
            )
        for name in ("rtol", "atol_position", "atol_velocity", "max_step", "onset_tolerance"):
            if getattr(self, name) is not None:
                _real(getattr(self, name), f"solver option {name}")
        if isinstance(self.max_steps, bool) or not isinstance(self.max_steps, int | np.integer):
            raise ConfigError(f"solver option max_steps must be an integer, got {self.max_steps!r}")
        if self.max_steps < 1:
            raise ConfigError(f"solver option max_steps must be >= 1, got {self.max_steps}")
        for name in ("rtol", "atol_position", "atol_velocity"):
            value = getattr(self, name)
            if not (math.isfinite(value) and value > 0):
                raise ConfigError(f"solver option {name} must be > 0, got {value}")
        if self.rtol >= 0.1:
            raise ConfigError(
                f"solver option rtol must be well below 1 (e.g. 1e-6), got {self.rtol}"
            )
        if self.max_step is not None and not self.max_step > 0:
            raise ConfigError(f"solver option max_step must be > 0 s, got {self.max_step}")

    def tightened(self, factor: float = 10.0) -> SolverOptions:
        """The same options with every error tolerance divided by ``factor``."""
        return SolverOptions(
            rtol=self.rtol / factor,
            atol_position=self.atol_position / factor,
            atol_velocity=self.atol_velocity / factor,
            max_step=self.max_step,
            onset_tolerance=None if self.onset_tolerance is None else self.onset_tolerance / factor,
            max_steps=self.max_steps,
            integrator=self.integrator,
        )


def preferred_integrator(
    preferred: str | None, mechanism: Mechanism, clearances: Sequence[ClearanceJoint]
) -> str | None:
    """``preferred`` (a paper method's :attr:`jointplay.study.methods.Method.integrator`)
    where it holds, else ``None`` (Radau IIA): RODAS4 only when every joint of ``mechanism``
    is a clearance joint. With ideal joints beside (their constraints projected, the
    Jacobian differenced) RODAS4 was measured 2–30× slower than Radau on the very contact
    sets it is chosen for (docs/performance.md, "From rest: a Rosenbrock method for the
    paper's ECS sets"). DOPRI5 holds with ideal joints too (no Jacobian: measured 1.8× and
    2.5× faster than Radau from rest with A, or B and O4, clear)."""
    clear = {c.joint for c in clearances}
    if preferred == "rodas4" and any(j.name not in clear for j in mechanism.joints):
        return None
    return preferred


@dataclass(frozen=True)
class SimulationResult:
    """Everything a simulation produced (failure included, as data).

    The arrays are read-only; :attr:`steps` and :attr:`timeseries` are built when first
    read, once.

    Attributes:
        system: the packed mechanism (mechanism, clearance joints, kernel model).
        start, solver: the settings used.
        t: times of the initial point and of every accepted step, s, shape (m,).
        y: states at those times (layout of :mod:`jointplay._kernels.eom`), shape (m, n).
        status: how the integration ended; anything but ``SUCCESS`` is a failure, and then
            ``t``, ``y``, the peaks and the statistics cover the steps up to where it stopped.
        message: what happened, and for a failure what to change.
        nominal_peaks: largest |value| of each quantity in the nominal (ideal-joint) steady
            motion (empty unless ``simulate(..., nominal=True)``).
        solver_stats: method, steps, rejections, evaluations, impacts per joint, maximum
            penetration, energy residual, constraint violation, wall time; with the
            sustained-contact mode on, ``sustained_contact``: per joint the share of the
            simulated time spent locked, the captures and the releases.
        revolutions: the analysed time asked for, in crank periods (after ``settle``).
        settle: start-up revolutions simulated first and left out of the statistics.
        sample_deg: sampling interval of the sampled peaks, deg of crank (``None``: none).
        output_step: sampling interval of :attr:`timeseries`, s.
        nominal: the nominal analysis table, or ``None`` unless asked for.
    """

    system: System
    start: Start
    solver: SolverOptions
    t: FloatArray
    y: FloatArray
    status: IntegrationStatus
    message: str
    nominal_peaks: dict[str, float]
    solver_stats: dict[str, Any]
    revolutions: float
    settle: int
    sample_deg: float | None
    output_step: float
    nominal: pd.DataFrame | None = field(repr=False)
    #: The columns of :attr:`steps`, the accelerations q̈ and the joints' contacts at the
    #: steps (for the interpolation of :attr:`timeseries`), kept to build the tables when
    #: first read.
    _step_columns: dict[str, FloatArray] = field(repr=False)
    _step_accelerations: FloatArray = field(repr=False)
    _step_touching: NDArray[np.bool_] = field(repr=False)

    @property
    def success(self) -> bool:
        """Whether the integration reached the end of the simulated time."""
        return self.status is IntegrationStatus.SUCCESS

    @property
    def mechanism(self) -> Mechanism:
        return self.system.mechanism

    @property
    def clearance_joints(self) -> tuple[str, ...]:
        return tuple(c.joint for c in self.system.clearances)

    @cached_property
    def running(self) -> RunningBehaviour:
        """Exact peaks, per-revolution statistics, periodicity and diagnostics (built when
        first read; see :mod:`jointplay.dynamics.running`)."""
        if self.t.shape[0] < 2:
            raise IntegrationError(
                f"the simulation stopped at its initial state ({self.message}); nothing ran"
            )
        stats = self.solver_stats
        return characterise(
            mechanism=self.mechanism,
            clearances=self.system.clearances,
            t=self.t,
            step_columns=self._step_columns,
            evaluate=self.evaluate,
            settle=self.settle,
            steady_start=self.start.mode == "steady",
            driven=self.start.driven,
            sample_deg=self.sample_deg,
            nominal_peaks=self.nominal_peaks,
            energy_residual=stats["energy_residual"],
            tolerances=(self.solver.atol_position, self.solver.atol_velocity),
        )

    @property
    def peaks(self) -> dict[str, dict[str, float]]:
        r"""Largest \|value\| of each quantity over the analysed revolutions, located on the
        continuous solution, with its time, crank angle and revolution."""
        return self.running.peaks

    @property
    def increase_percent(self) -> dict[str, float | None]:
        """(peak − nominal peak) / nominal peak × 100 (empty without the nominal peaks)."""
        if not self.nominal_peaks:
            return {}
        return {
            key: 100.0 * (peak["value"] - self.nominal_peaks[key]) / self.nominal_peaks[key]
            if self.nominal_peaks.get(key)
            else None
            for key, peak in self.peaks.items()
        }

    @property
    def diagnostics(self) -> tuple[Diagnostic, ...]:
        """The plausibility findings (warnings first)."""
        return self.running.diagnostics

    def evaluate(self, times: FloatArray) -> dict[str, FloatArray]:
        """Every documented column at ``times`` on the continuous solution."""
        states = _interpolate(
            self.system, self.t, self.y, self._step_accelerations, self._step_touching, times
        )
        columns, _ = _columns(self.system, times, states)
        return columns

    @cached_property
    def steps(self) -> pd.DataFrame:
        """One row per accepted integrator step (the columns of :attr:`timeseries`)."""
        return pd.DataFrame(self._step_columns)

    @cached_property
    def timeseries(self) -> pd.DataFrame:
        """Rows every :attr:`output_step` seconds: Hermite interpolation of the state between
        steps, forces re-evaluated from the interpolated state."""
        t, y = self.t, self.y
        samples = np.arange(0.0, t[-1] + 0.5 * self.output_step, self.output_step)
        samples = samples[samples <= t[-1]]
        if t.shape[0] < 2:  # stopped at the initial state: nothing to interpolate
            states = np.ascontiguousarray(y[: samples.shape[0]])
        else:
            states = _interpolate(
                self.system, t, y, self._step_accelerations, self._step_touching, samples
            )
        columns, _ = _columns(self.system, samples, states)
        return pd.DataFrame(columns)

    @cached_property
    def film_regimes(self) -> dict[str, Any]:
        """Each clearance joint's lubrication regimes over the analysed revolutions (full film,
        mixed, boundary by λ = h_min/σ: :mod:`jointplay.dynamics.regimes`; ``None``: dry)."""
        from jointplay.dynamics.regimes import regimes_of

        t0 = float(self.t[-1]) - self.revolutions * self.mechanism.driver.period
        return regimes_of(self.system.clearances, self._step_columns, t0)

    def summary(self) -> dict[str, Any]:
        """The stable ``summary.json`` content (without provenance)."""
        running = self.running
        behaviour = running.summary()
        return {
            "status": self.status.name.lower(),
            "message": self.message,
            "peaks": self.peaks,
            "peaks_over": (
                f"revolutions {running.settle + 1} to {len(running.windows)} (after "
                f"{running.settle} start-up revolution(s))"
            ),
            "peaks_located": behaviour["cycles"]["peaks_located"],
            "nominal_peaks": self.nominal_peaks,
            "increase_percent": self.increase_percent,
            **behaviour,
            "solver": self.solver_stats,
            "start": {
                "mode": self.start.mode,
                "meaning": START_MODES[self.start.mode],
                "ramp_time_s": self.start.ramp_time,
            },
            "revolutions": self.revolutions,
            "settle_revolutions": self.settle,
            "clearance_joints": {
                c.joint: {
                    "clearance_m": c.clearance,
                    "journal_radius_m": c.journal_radius,
                    "law": c.law.name,
                    "law_parameters": _law_fields(c.law),
                    "friction": None
                    if c.friction is None
                    else {"law": c.friction.name, **_law_fields(c.friction)},
                    "film_damping_N_s_m": c.film_damping,  # the joint's own; 0: dry
                    # a Reynolds film: film_damping is its coefficient C0 = π μ R L³ / c³
                    **({"film_model": c.film_model} if c.film_model != "linear" else {}),
                }
                for c in self.system.clearances
            },
            # the time in full film / mixed / boundary lubrication (λ = h_min / σ)
            "film_regimes": {
                name: None if regime is None else regime.describe()
                for name, regime in self.film_regimes.items()
            },
        }


def _law_fields(law: object) -> dict[str, Any]:
    return {k: v for k, v in vars(law).items() if not k.startswith("_")}


def start_constraints(system: System) -> NDArray[np.int64]:
    """The joints a start's velocities are projected onto (1 per joint of the flat model):
    the ideal joints and every lubricated clearance joint (docs/contact.md, "A start
    consistent with the film"). A pin centred in its film starts moving with its bearing: a
    film admits no finite relative velocity ė of the centres at t = 0 (its force −c_e ė
    would be an impulse, ~2e5 N for the paper's pins at a rest start's 2.3 m/s), so the
    start's impulse passes through the lubricated joints as through ideal ones. A dry pin
    keeps the start's ė and crosses its clearance (the paper's start-up impacts)."""
    active = np.array(system.flat.active, dtype=np.int64, copy=True)
    filmed = {c.joint for c in system.clearances if c.film_damping > 0}
    for row, name in enumerate(system.flat.joint_names):
        if name in filmed:
            active[row] = 1
    return active


def initial_state(system: System, start: Start) -> FloatArray:
    """y0: nominal assembly with every pin centred in its bearing, velocities per ``start``,
    projected onto the ideal joints, the driver and the lubricated clearance joints
    (:func:`start_constraints`: each lubricated pin starts with ė = 0)."""
    mechanism = system.mechanism
    kin = analyse(mechanism, np.array([mechanism.driver.start_angle]))
    q0 = kin.q[0].copy()
    n = system.n_coordinates
    crank = system.flat.body_index(mechanism.driver.link)
    if start.mode == "steady":
        qd0 = kin.qd[0].copy()
    elif start.mode == "rest":
        qd0 = np.zeros(n)
        qd0[3 * crank : 3 * crank + 3] = kin.qd[
            0, 3 * crank : 3 * crank + 3
        ]  # crank turning about its pivot
    else:  # impulsive (the projection below does it) and ramp (the driver starts at rest)
        qd0 = np.zeros(n)
    flat = system.flat
    # The ideal constraints (and the driver): project the velocities onto them, mass-weighted
    # — the velocity change an impulsive start gives (q̇ ← q̇ − M⁻¹Φqᵀ(ΦqM⁻¹Φqᵀ)⁻¹(Φq q̇ − ν)).
    active = start_constraints(system)
    phi_q = ck.jacobian(q0, flat.joint_int, flat.joint_f, active, flat.driver)
    if phi_q.shape[0]:
        nu = ck.velocity_rhs(0.0, active, flat.driver)
        inv_mass = 1.0 / flat.mass_vector()
        weighted = phi_q * inv_mass
        qd0 -= inv_mass * (phi_q.T @ np.linalg.solve(weighted @ phi_q.T, phi_q @ qd0 - nu))
    return np.concatenate([q0, qd0, np.zeros(2 + len(system.clearances))])


#: The most rows a time series (or a sampled-peak table) may have: a guard against an output
#: step so fine that the tables would not fit in memory (1e7 rows of ~60 columns: ~5 GB).
MAX_OUTPUT_ROWS = 10_000_000


def _real(value: Any, name: str) -> float:
    """``value`` as a float, or a ConfigError naming ``name`` (a type check: no range)."""
    if isinstance(value, bool) or not isinstance(value, int | float | np.integer | np.floating):
        raise ConfigError(f"{name} must be a number, got {value!r}")
    return float(value)


def _check_arguments(
    mechanism: Any,
    clearances: Any,
    start: Any,
    solver: Any,
    revolutions: Any,
    output_step: Any,
    sample_deg: Any,
) -> None:
    """Type checks of :func:`simulate`'s arguments, each naming the argument and the fix."""
    if not isinstance(mechanism, Mechanism):
        raise ConfigError(
            f"mechanism must be a Mechanism (e.g. load_preset('paper-fourbar')), got "
            f"{type(mechanism).__name__}"
        )
    if isinstance(clearances, str | bytes) or not isinstance(clearances, Sequence):
        raise ConfigError(
            f"clearances must be a list of ClearanceJoint (see clearance_joints()), got "
            f"{type(clearances).__name__}"
        )
    for item in clearances:
        if not isinstance(item, ClearanceJoint):
            raise ConfigError(
                f"clearances must hold ClearanceJoint objects, got {type(item).__name__}"
            )
    if start is not None and not isinstance(start, Start):
        raise ConfigError(
            f"start must be a Start, e.g. Start({start!r}) for a mode name, got "
            f"{type(start).__name__}"
            if isinstance(start, str)
            else f"start must be a Start or None, got {type(start).__name__}"
        )
    if solver is not None and not isinstance(solver, SolverOptions):
        raise ConfigError(
            f"solver must be a SolverOptions (e.g. SolverOptions(rtol=1e-6)), got "
            f"{type(solver).__name__}"
        )
    _real(revolutions, "revolutions")
    if output_step is not None:
        _real(output_step, "output_step")
    if sample_deg is not None:
        _real(sample_deg, "sample_deg")


def check_outputs(
    mechanism: Mechanism,
    revolutions: float,
    settle: int,
    output_step: float | None,
    sample_deg: float | None,
) -> float:
    """The output step (s; default half a degree of crank) after checking the revolutions and
    the outputs asked of :func:`simulate`, before any work (the command line calls it before
    it compiles the kernels, so that bad input stays one line).

    Raises:
        ConfigError, SettingError: a setting out of range, or outputs too large to hold.
    """
    analysed_revolutions(revolutions)
    settle_revolutions(settle)
    if sample_deg is not None and not (math.isfinite(sample_deg) and 0 < sample_deg <= 360):
        raise ConfigError(f"sample_deg must lie in (0, 360] degrees, got {sample_deg}")
    period = mechanism.driver.period
    output_step = output_step if output_step is not None else period / 720.0
    if not output_step > 0:
        raise ConfigError(f"output step must be > 0 s, got {output_step}")
    _check_output_size(period, int(settle) + revolutions, output_step, sample_deg)
    return output_step


def _check_output_size(
    period: float, turns: float, output_step: float, sample_deg: float | None
) -> None:
    """Refuse, before allocating, a time series or sampled table of more than
    :data:`MAX_OUTPUT_ROWS` rows."""
    rows = turns * period / output_step
    if rows > MAX_OUTPUT_ROWS:
        finest = turns * period / MAX_OUTPUT_ROWS
        raise SettingError(
            f"an output step of {output_step:.3g} s over {turns:g} revolution(s) of "
            f"{period:.3g} s gives {rows:.3g} rows of time series (at most "
            f"{MAX_OUTPUT_ROWS:.0e}); give an output step of at least {finest:.3g} s "
            "({output_step}) or fewer revolutions"
        )
    if sample_deg is not None and turns * 360.0 / sample_deg > MAX_OUTPUT_ROWS:
        raise SettingError(
            f"sample_deg = {sample_deg:g} over {turns:g} revolution(s) gives more than "
            f"{MAX_OUTPUT_ROWS:.0e} samples; give at least {turns * 360.0 / MAX_OUTPUT_ROWS:.3g}"
            " degrees ({sample_deg})"
        )


def simulate(
    mechanism: Mechanism,
    clearances: Sequence[ClearanceJoint],
    *,
    revolutions: float = 1.0,
    settle: int | None = None,
    start: Start | None = None,
    solver: SolverOptions | None = None,
    output_step: float | None = None,
    sample_deg: float | None = None,
    nominal: bool | pd.DataFrame = False,
    nominal_step_deg: float = 0.1,
    throw: bool = True,
) -> SimulationResult:
    """Simulate ``settle + revolutions`` crank periods of ``mechanism`` with ``clearances``.

    Args:
        revolutions: analysed time in periods of the nominal crank speed (> 0).
        settle: start-up revolutions simulated first and left out of the peaks and the
            statistics (>= 0; default: 2 with the steady start, 0 with the others, whose
            start-up is what they show), as ``jointplay simulate``.
        start: initial state and driver ramp (default: ``Start("steady")``, the nominal
            motion, as ``jointplay simulate``; ``Start("rest")`` is the paper's case).
        solver: integration settings.
        output_step: sampling interval of :attr:`SimulationResult.timeseries`, s (default: the
            time of 0.5° of crank rotation).
        sample_deg: also report the peaks of the solution sampled every ``sample_deg``
            degrees of crank, labelled as sampled (default: none).
        nominal: also run the nominal (ideal-joint) analysis, for
            :attr:`SimulationResult.nominal`, ``nominal_peaks`` and ``increase_percent``
            (default: no, they stay empty). Or that analysis's table
            (``SimulationResult.nominal`` of an earlier run of the same mechanism), taken as
            it is: an interactive caller that changes only the clearance skips its cost.
        nominal_step_deg: crank-angle step of that nominal analysis, degrees.
        throw: raise :class:`~jointplay.errors.IntegrationError` when the integration fails
            (default); with ``False``, return the partial result, whose ``status`` and
            ``message`` say what happened (for studies that count failures).

    Raises:
        ConfigError: a setting is out of range.
        IntegrationError: the integration failed and ``throw`` is true.
    """
    _check_arguments(mechanism, clearances, start, solver, revolutions, output_step, sample_deg)
    start = start or Start("steady")
    if settle is None:
        settle = DEFAULT_SETTLE if start.mode == "steady" else 0
    solver = solver or SolverOptions()
    output_step = check_outputs(mechanism, revolutions, settle, output_step, sample_deg)
    period = mechanism.driver.period
    if solver.max_step is not None:
        fewest = (int(settle) + revolutions) * period / solver.max_step
        if fewest > solver.max_steps:
            raise SettingError(
                f"a max step of {solver.max_step:.3g} s needs at least {fewest:.3g} steps for "
                f"{int(settle) + revolutions:g} revolution(s), more than max_steps = "
                f"{solver.max_steps}; give a larger max step ({{max_step}}) or fewer revolutions"
            )
    system = build_system(
        mechanism,
        clearances,
        ramp_time=start.ramp_time,
        onset_tolerance=solver.onset_tolerance,
        driven=start.driven,
    )
    y0 = initial_state(system, start)
    n = system.n_coordinates
    # the explicit method at a fifth of the tolerances, as close to the exact solution as Radau
    integrator = solver.integrator or DEFAULT_INTEGRATOR
    scale = INTEGRATORS[integrator].tolerance_scale
    atol = np.concatenate(
        [
            np.full(n, solver.atol_position),
            np.full(n, scale * solver.atol_velocity),
            np.full(2, 1e-6),  # energy quadratures, J
            np.full(len(clearances), 1.0),  # impact-velocity memory: piecewise constant
        ]
    )
    t_end = (int(settle) + revolutions) * period
    args = system.kernel_args()
    wall = time.perf_counter()
    max_step = solver.max_step if solver.max_step is not None else period / 360.0
    run, work = integrate_mechanism(
        args, t_end, y0, method=integrator, rtol=scale * solver.rtol, atol=atol,
        max_step=max_step, max_steps=solver.max_steps, throw=False,
    )  # fmt: skip
    wall = time.perf_counter() - wall
    message = _message(run, t_end, solver)
    if throw and not run.success:
        raise IntegrationError(message)
    columns, qdd = _columns(system, run.t, run.y)
    table: pd.DataFrame | None
    if isinstance(nominal, pd.DataFrame):  # this mechanism's, computed before
        table = nominal
    else:
        table = nominal_analysis(mechanism, step_deg=nominal_step_deg).table if nominal else None
    nominal_peaks = (
        {}
        if table is None
        else {
            key: float(np.max(np.abs(table[key])))
            for key in columns
            if key.startswith(PEAK_KEYS) and key in table
        }
    )
    return SimulationResult(
        system=system,
        start=start,
        solver=solver,
        t=run.t,
        y=run.y,
        status=run.status,
        message=message,
        nominal_peaks=nominal_peaks,
        solver_stats=_solver_stats(system, run, columns, work, wall, integrator),
        revolutions=revolutions,
        settle=int(settle),
        sample_deg=sample_deg,
        output_step=output_step,
        nominal=table,
        _step_columns=columns,
        _step_accelerations=qdd,
        _step_touching=np.column_stack(
            [columns[f"contact_{c.joint}"] > 0 for c in system.clearances]
            or [np.zeros(len(run.t), dtype=bool)]
        ),
    )


def _message(run: IntegrationResult, t_end: float, solver: SolverOptions) -> str:
    """What the integration did, in the terms of :func:`simulate`'s options."""
    t_last = float(run.t[-1])
    status = run.status
    if status is IntegrationStatus.SUCCESS:
        return f"{status.summary} (t = {t_end:.6g} s) in {run.n_steps} steps"
    where = f"simulation stopped at t = {t_last:.6g} s of {t_end:.6g} s: {status.summary}"
    if status is IntegrationStatus.TOO_MANY_STEPS:
        return (
            f"{where} (SolverOptions.max_steps = {solver.max_steps}). Raise"
            " SolverOptions.max_steps or simulate fewer revolutions; if the steps became tiny,"
            " look for chattering contact (a stiffer contact law, more damping, or a larger"
            " SolverOptions.onset_tolerance)."
        )
    if status is IntegrationStatus.STEP_TOO_SMALL:
        return (
            f"{where}. Loosen SolverOptions.rtol, atol_position"
            " or atol_velocity, and check that the contact stiffness and damping are"
            " physically sensible."
        )
    return (
        f"{where}. Check that the contact law's stiffness, exponent and damping are physically"
        " sensible (a value far out of range overflows) and that the mechanism assembles."
    )


def hermite(
    t: FloatArray, values: FloatArray, rates: FloatArray, samples: FloatArray
) -> FloatArray:
    """Cubic Hermite interpolation of ``values`` (rows at the times ``t``) with their time
    derivatives ``rates`` at ``samples``: 4th-order accurate between accepted steps, like the
    integrator's own dense output."""
    index = np.clip(np.searchsorted(t, samples, side="right") - 1, 0, len(t) - 2)
    t0, t1 = t[index], t[index + 1]
    h = (t1 - t0)[:, None]
    s = ((samples - t0) / (t1 - t0))[:, None]
    h00, h10, h01, h11 = (
        2 * s**3 - 3 * s**2 + 1,
        s**3 - 2 * s**2 + s,
        -2 * s**3 + 3 * s**2,
        s**3 - s**2,
    )
    return (
        h00 * values[index]
        + h10 * h * rates[index]
        + h01 * values[index + 1]
        + h11 * h * rates[index + 1]
    )


def hermite_derivative(
    t: FloatArray, values: FloatArray, rates: FloatArray, samples: FloatArray
) -> FloatArray:
    """Time derivative at ``samples`` of :func:`hermite`'s interpolant of ``values`` (with
    ``rates``): uses only the values and their rates at the step's ends, one order less
    accurate than a Hermite interpolant of the rates themselves."""
    index = np.clip(np.searchsorted(t, samples, side="right") - 1, 0, len(t) - 2)
    t0, t1 = t[index], t[index + 1]
    h = (t1 - t0)[:, None]
    s = ((samples - t0) / (t1 - t0))[:, None]
    dh10, dh01, dh11 = 3 * s**2 - 4 * s + 1, -6 * s**2 + 6 * s, 3 * s**2 - 2 * s
    return (
        dh01 * (values[index + 1] - values[index]) / h
        + dh10 * rates[index]
        + dh11 * rates[index + 1]
    )


def hermite_three_points(
    t: FloatArray,
    values: FloatArray,
    rates: FloatArray,
    samples: FloatArray,
    index: NDArray[np.intp],
) -> tuple[FloatArray, FloatArray]:
    """The quintic through ``values`` and ``rates`` at the three step ends ``t[index − 1]``,
    ``t[index]``, ``t[index + 1]`` (confluent Hermite, Newton's divided-difference form),
    and its time derivative, at ``samples`` (each inside its step ``index >= 1``).

    Where the motion is smooth the rates are 5th-order accurate (the cubic's derivative on
    one step, 3rd); unlike a Hermite that takes q̈, they take no acceleration, which a stiff
    film or contact turns from a small velocity error into a large one."""
    t0, t1, t2 = t[index - 1][:, None], t[index][:, None], t[index + 1][:, None]
    q0, q1, q2 = values[index - 1], values[index], values[index + 1]
    v0, v1, v2 = rates[index - 1], rates[index], rates[index + 1]
    c = _divided_differences(t0, t1, t2, q0, q1, q2, v0, v1, v2)
    nodes = (t0, t0, t1, t1, t2)
    tau = samples[:, None]
    value, rate = c[5], np.zeros_like(c[5])
    for k in range(4, -1, -1):  # Horner on the Newton form, with its derivative
        rate = rate * (tau - nodes[k]) + value
        value = value * (tau - nodes[k]) + c[k]
    return value, rate


def _divided_differences(t0, t1, t2, q0, q1, q2, v0, v1, v2):
    """Newton's coefficients of the quintic through (q, v) at t0, t1, t2 (nodes t0, t0, t1,
    t1, t2, t2); the arithmetic of the lanes' ``source_radau.hermite``."""
    s01 = (q1 - q0) / (t1 - t0)
    s12 = (q2 - q1) / (t2 - t1)
    f012 = (s01 - v0) / (t1 - t0)
    f123 = (v1 - s01) / (t1 - t0)
    f234 = (s12 - v1) / (t2 - t1)
    f345 = (v2 - s12) / (t2 - t1)
    f0123 = (f123 - f012) / (t1 - t0)
    f1234 = (f234 - f123) / (t2 - t0)
    f2345 = (f345 - f234) / (t2 - t1)
    f01234 = (f1234 - f0123) / (t2 - t0)
    f12345 = (f2345 - f1234) / (t2 - t0)
    return q0, v0, f012, f0123, f01234, (f12345 - f01234) / (t2 - t0)


def smooth_steps(touching: NDArray[np.bool_]) -> NDArray[np.bool_]:
    """Which accepted steps the three-point quintic may take (with film damping): those
    over which no joint starts or ends its contact, and whose preceding step did not either
    (the first step has none before it: no).

    ``touching`` (m, nc): whether each clearance joint's pin touches (δ > 0) at each step.
    Returns (m − 1,) booleans.
    """
    change = np.any(touching[1:] != touching[:-1], axis=1)
    before = np.concatenate([[True], change[:-1]])
    return ~(change | before)


def _interpolate(
    system: System,
    t: FloatArray,
    y: FloatArray,
    qdd: FloatArray,
    touching: NDArray[np.bool_],
    samples: FloatArray,
) -> FloatArray:
    """The state at ``samples`` between accepted steps (``qdd`` q̈ and ``touching`` the
    joints' contacts at the steps): q by cubic Hermite (with q̇), q̇ by cubic Hermite (with
    q̈); with film damping, q and q̇ from the quintic through q and q̇ at the step's ends and
    the step end before it (:func:`hermite_three_points`) where :func:`smooth_steps`
    allows, else q̇ the derivative of q's cubic.

    Why the film changes the rule: it turns a velocity error into a force, c_e ė (c_e up to
    1e6 N·s/m), so the interpolant's error in q̇ decides the located force and α peaks.
    The cubic Hermite of q̇ with q̈ swings where q̈ changes fast inside a step (a contact
    onset: spurious α peaks of 5× at c_e = 1e5), and any rule that takes q̈ at the steps
    carries its noise (q̈ is c_e/m times the velocities' error). The derivative of q's
    cubic uses q and q̇ only but is 3rd-order (peaks ~1e-3 off at the default tolerances);
    the three-point quintic is 5th-order (peaks ~1e-6 off, docs/performance.md, "Peak
    location with a film"). Next to a contact's start or end the motion is not smooth over
    three step ends, so those steps keep the cubic's derivative. The work integrals are
    linear, the impact memory held at the step's start.
    """
    n = system.n_coordinates
    index = np.clip(np.searchsorted(t, samples, side="right") - 1, 0, len(t) - 2)
    t0, t1 = t[index], t[index + 1]
    out = y[index].copy()  # work and impact-velocity memory: value at the step's start
    out[:, :n] = hermite(t, y[:, :n], y[:, n : 2 * n], samples)
    if system.lubricated:
        out[:, n : 2 * n] = hermite_derivative(t, y[:, :n], y[:, n : 2 * n], samples)
        quintic = smooth_steps(touching)[index]
        if quintic.any():
            out[quintic, :n], out[quintic, n : 2 * n] = hermite_three_points(
                t, y[:, :n], y[:, n : 2 * n], samples[quintic], index[quintic]
            )
    else:
        out[:, n : 2 * n] = hermite(t, y[:, n : 2 * n], qdd, samples)
    w = (samples - t0) / (t1 - t0)
    out[:, 2 * n : 2 * n + 2] = (1 - w)[:, None] * y[index, 2 * n : 2 * n + 2] + w[:, None] * y[
        index + 1, 2 * n : 2 * n + 2
    ]
    return np.ascontiguousarray(out)


def _columns(
    system: System, t: FloatArray, y: FloatArray
) -> tuple[dict[str, FloatArray], FloatArray]:
    """The documented columns at times ``t`` with states ``y``, and the accelerations q̈."""
    mechanism = system.mechanism
    flat = system.flat
    n = system.n_coordinates
    rpar, ipar = eom.pack(system.model)
    states = np.ascontiguousarray(y)
    qdd, torque, contacts, lam_pairs, violation = eom.diagnostics(
        np.ascontiguousarray(t), states, rpar, ipar
    )
    film = eom.film_forces(states, rpar, ipar, contacts)  # (N, nc, 2): zeros when off
    crank = flat.body_index(mechanism.driver.link)
    columns: dict[str, FloatArray] = {
        "t": t,
        "crank_deg": np.degrees(y[:, 3 * crank + 2]),
    }
    links = rotating_links(mechanism)
    for name, number in links:
        columns[f"theta{number}_deg"] = np.degrees(y[:, 3 * flat.body_index(name) + 2])
    for name, number in links:
        columns[f"omega{number}"] = y[:, n + 3 * flat.body_index(name) + 2]
    for name, number in links:
        columns[f"alpha{number}"] = qdd[:, 3 * flat.body_index(name) + 2]
    for joint in sliders(mechanism):
        k = flat.body_index(joint.link_b)
        origin = np.array(mechanism.ground.point(joint.point_a))
        axis = np.array([math.cos(joint.axis_angle), math.sin(joint.axis_angle)])
        s = np.array(mechanism.link(joint.link_b).point(joint.point_b)) - np.array(
            mechanism.link(joint.link_b).com
        )
        phi = y[:, 3 * k + 2]
        rs = np.column_stack(
            [np.cos(phi) * s[0] - np.sin(phi) * s[1], np.sin(phi) * s[0] + np.cos(phi) * s[1]]
        )
        w = y[:, n + 3 * k + 2][:, None]
        perp = np.column_stack([-rs[:, 1], rs[:, 0]])
        columns[f"{joint.link_b}_x"] = (y[:, 3 * k : 3 * k + 2] + rs - origin) @ axis
        columns[f"{joint.link_b}_v"] = (y[:, n + 3 * k : n + 3 * k + 2] + w * perp) @ axis
        acc = qdd[:, 3 * k : 3 * k + 2] + qdd[:, 3 * k + 2][:, None] * perp - w**2 * rs
        columns[f"{joint.link_b}_a"] = acc @ axis
    clear_index = {c.joint: i for i, c in enumerate(system.clearances)}
    play = asperity_play(np.asarray(rpar)[None, :], ipar, len(clear_index))[0]
    for j, name in enumerate(flat.joint_names):
        if name in clear_index:
            c = clear_index[name]
            columns[f"F_{name}"] = np.hypot(
                contacts[:, c, 0] + film[:, c, 0], contacts[:, c, 1] + film[:, c, 1]
            )
        elif flat.joint_int[j, 0] == REVOLUTE:
            columns[f"F_{name}"] = np.hypot(lam_pairs[:, j, 0], lam_pairs[:, j, 1])
        else:
            columns[f"F_{name}"] = np.abs(lam_pairs[:, j, 1])  # normal force of a prismatic joint
    columns["torque"] = torque
    for name, c in clear_index.items():
        ex, ey = contacts[:, c, 5], contacts[:, c, 6]
        columns[f"ex_{name}"] = ex
        columns[f"ey_{name}"] = ey
        rate = _eccentricity_rate(flat, flat.joint_index(name), y, n)
        columns[f"dex_{name}"] = rate[:, 0]
        columns[f"dey_{name}"] = rate[:, 1]
        columns[f"e_{name}"] = np.hypot(ex, ey)
        # δ = |e| − c, the wall's; the kernels' δ (contacts[..., 2]) is the asperities' under
        # a Reynolds film (docs/contact.md, "The film-to-contact transition"): the dry law acts
        columns[f"pen_{name}"] = contacts[:, c, 2] - play[c]
        columns[f"contact_{name}"] = (contacts[:, c, 2] > 0).astype(np.int8)
        columns[f"Fn_{name}"] = contacts[:, c, 0]
        columns[f"Ft_{name}"] = contacts[:, c, 1]
    columns["constraint_violation"] = violation
    return columns, qdd


def _eccentricity_rate(flat: Any, row: int, y: FloatArray, n: int) -> FloatArray:
    """ė = v_pin − v_bearing of a clearance joint (m/s), from the states ``y``: the velocity
    of each joint point is v_com + ω × (R(φ) s), s the point in its link's frame."""

    def point_velocity(body: int, arm: FloatArray) -> FloatArray:
        if body < 0:
            return np.zeros((y.shape[0], 2))
        phi, omega = y[:, 3 * body + 2], y[:, n + 3 * body + 2]
        rx = np.cos(phi) * arm[0] - np.sin(phi) * arm[1]
        ry = np.sin(phi) * arm[0] + np.cos(phi) * arm[1]
        return y[:, n + 3 * body : n + 3 * body + 2] + np.column_stack([-omega * ry, omega * rx])

    bearing, pin = int(flat.joint_int[row, 1]), int(flat.joint_int[row, 2])
    return point_velocity(pin, flat.joint_f[row, 2:4]) - point_velocity(
        bearing, flat.joint_f[row, 0:2]
    )


def _solver_stats(
    system: System,
    run: IntegrationResult,
    columns: dict[str, FloatArray],
    work: FloatArray,
    wall: float,
    integrator: str,
) -> dict[str, Any]:
    n = system.n_coordinates
    flat = system.flat
    y = run.y
    mass = flat.mass_vector()
    kinetic = 0.5 * np.sum(mass * y[:, n : 2 * n] ** 2, axis=1)
    potential = -(y[:, :n] @ flat.gravity_forces())
    balance = kinetic + potential - y[:, 2 * n] + y[:, 2 * n + 1]
    residual = float(np.max(np.abs(balance - balance[0])))
    scale = float(max(np.max(kinetic), np.max(np.abs(y[:, 2 * n])), 1e-300))
    impacts = {}
    max_pen = {}
    for c, clearance in enumerate(system.clearances):
        memory = y[:, 2 * n + 2 + c]
        impacts[clearance.joint] = int(np.sum((memory[1:] > 0) & (memory[:-1] <= 0)))
        max_pen[clearance.joint] = float(max(0.0, np.max(columns[f"pen_{clearance.joint}"])))
    stats = {
        "method": f"{INTEGRATORS[integrator].title}, compiled; contact-onset step control;"
        " constraint projection"
        + (f"; {EXPLICIT_TOLERANCES}" if INTEGRATORS[integrator].tolerance_scale != 1 else ""),
        "integrator": integrator,
        "steps": run.n_steps,
        "rejected_steps": run.n_rejected,
        "rejected_by_error": run.n_rejected_error,
        "rejected_by_newton": run.n_rejected_newton,
        "rejected_for_contact_onset": run.n_rejected_check,
        "rhs_evaluations": run.nfev,
        "jacobian_evaluations": run.njev,
        "lu_decompositions": run.nlu,
        "impacts": impacts,
        "max_penetration_m": max(max_pen.values(), default=0.0),
        "max_penetration_per_joint_m": max_pen,
        "energy_residual": residual / scale,
        "energy_residual_J": residual,
        "max_constraint_violation": float(work[ids.W_MAX_VIOLATION]),
        "projections": int(work[ids.W_PROJECTIONS]),
        "wall_s": wall,
    }
    if system.sustained_mode:
        stats["sustained_contact"] = _sustained_stats(system, run.t, y)
    return stats


def _sustained_stats(system: System, t: FloatArray, y: FloatArray) -> dict[str, Any]:
    """Per clearance joint, with the sustained-contact mode on: the share of the simulated
    time it spent locked (a step's mode is the one its start records), its captures and
    its releases."""
    n = system.n_coordinates
    locked = y[:, 2 * n + 2 :] < 0
    dt = np.diff(t)
    total = max(float(dt.sum()), 1e-300)
    names = [c.joint for c in system.clearances]
    return {
        "locked_share": {j: float(dt @ locked[:-1, c]) / total for c, j in enumerate(names)},
        "captures": {j: int(np.sum(locked[1:, c] & ~locked[:-1, c])) for c, j in enumerate(names)},
        "releases": {j: int(np.sum(~locked[1:, c] & locked[:-1, c])) for c, j in enumerate(names)},
    }
