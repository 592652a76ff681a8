"""The clearance-joint dynamic response models: :class:`DynamicResponses` (the batch engine,
every sample of a block at once), :class:`PeakResponses`, the per-sample checks of a
simulation and :func:`dynamic_model`. :mod:`jointplay.tolerance.responses` describes the
models.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable, Mapping, Sequence
from dataclasses import dataclass, field
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from jointplay._kernels.capabilities import engine_of, refusal
from jointplay.dynamics.cycles import DEFAULT_SETTLE, analysed_revolutions, settle_revolutions
from jointplay.errors import ConfigError, PartialInterrupt, SettingError
from jointplay.execution.backends import Backend
from jointplay.execution.interrupts import interrupts_noted
from jointplay.model.mechanism import Mechanism
from jointplay.model.templates import TemplateSpec, template_of

if TYPE_CHECKING:  # the dynamics import Numba: loaded only by dynamic studies
    from jointplay.contact.friction import FrictionLaw
    from jointplay.contact.laws import ContactLaw
    from jointplay.dynamics.clearance import ClearanceJoint, JointFilm, JointStiffness
    from jointplay.dynamics.settings import RunSettings
    from jointplay.dynamics.setup import ContactModel
    from jointplay.dynamics.simulate import SimulationResult, SolverOptions, Start
from jointplay.tolerance.response_base import (
    ELASTIC_RATIO,
    ELASTIC_RATIO_DEFINITION,
    PENETRATION_RATIO,
    PENETRATION_RATIO_DEFINITION,
    REGIME_CHECKS,
    Evaluation,
    ResponseModel,
    _check_inputs,
    regime_check_names,
)

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


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
        capture_speed: the sustained-contact mode's capture speed of every clearance joint,
            m/s (0, the default: the mode is off; :class:`ContactModel`'s
            ``sustained_contact``). The batch engine then runs the implicit lanes.
        film_damping: a fixed film damping c_e of every clearance joint, N·s/m (0, the
            default: dry, unless ``film_from``; :class:`ContactModel`'s ``film_damping``).
        film_from: joint → how its film damping follows its geometry and lubricant
            (:class:`~jointplay.dynamics.clearance.JointFilm`), recomputed for every
            sample's clearance. With a film the batch engine runs the implicit lanes.
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
    capture_speed: float = 0.0
    film_damping: float = 0.0
    film_from: Mapping[str, JointFilm] = field(default_factory=dict)
    lubrication: Mapping[str, Mapping[str, Any]] = field(default_factory=dict)
    lubrication_text: str = ""

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
        object.__setattr__(self, "film_from", dict(self.film_from))
        if self.backend.on_device and (self.film_damping > 0 or self.film_from):
            reynolds = any(rule.model != "linear" for rule in self.film_from.values())
            refused = refusal(
                engine_of(self.backend.kind, self.method),
                ["film_damping", *(["film_model"] if reynolds else [])],
                named=lambda need: (
                    "a Reynolds film ({film_model})"
                    if need == "film_model"
                    else "the pins' lubricant film ({lubricant_viscosity})"
                ),
            )
            if refused is not None:
                raise SettingError(refused)
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
    def lubricated_joints(self) -> tuple[str, ...]:
        """The clearance joints that run in a film (a fixed film damping > 0, or a film from
        their geometry and lubricant), in :attr:`clearance_joints` order."""
        return tuple(
            joint
            for joint in self.clearance_joints
            if self.film_damping > 0 or joint in self.film_from
        )

    @property
    def check_names(self) -> tuple[str, ...]:
        """``penetration_ratio_<joint>`` then ``elastic_ratio_<joint>`` per clearance joint
        (see the module docstring), then per lubricated joint (:attr:`lubricated_joints`)
        the fractions of the analysed time in each lubrication regime, ``full_film_<joint>``,
        ``mixed_<joint>``, ``boundary_<joint>`` (:data:`REGIME_CHECKS`,
        :mod:`jointplay.dynamics.regimes`)."""
        return (
            *(
                f"{prefix}{joint}"
                for prefix in (PENETRATION_RATIO, ELASTIC_RATIO)
                for joint in self.clearance_joints
            ),
            *regime_check_names(self.lubricated_joints),
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
            **({"lubrication": dict(self.lubrication)} if self.lubrication else {}),
            **({"lubrication_text": self.lubrication_text} if self.lubrication_text else {}),
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
            **({"capture_speed_m_s": self.capture_speed} if self.capture_speed > 0 else {}),
            **({"film_damping_N_s_m": self.film_damping} if self.film_damping > 0 else {}),
            **(
                {"film_from_geometry": {j: fields_of(r) for j, r in self.film_from.items()}}
                if self.film_from
                else {}
            ),
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
            text += "; no friction"
        else:
            mu = getattr(friction, "mu", getattr(friction, "mu_static", math.nan))
            text += f"; {friction.name} friction, coefficient {mu:g}"
        viscosities = {rule.viscosity for rule in self.film_from.values()}
        forms = sorted({rule.model for rule in self.film_from.values()} - {"linear"})
        film = f"{', '.join(forms)} Reynolds film" if forms else "film damping"
        if viscosities:
            return text + (
                f"; lubricated pins, a {', '.join(f'{v:g}' for v in sorted(viscosities))} Pa*s "
                f"lubricant: {film} from each joint's geometry and every sample's clearance"
            )
        if self.film_damping > 0:
            return text + f"; lubricated pins, film damping {self.film_damping:g} N*s/m"
        return text + "; dry joints"

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
            capture_speed=self.capture_speed,
            film_damping=self.film_damping,
            film_from=self.film_from.get(joint),
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
        x = _check_inputs(x, len(self.input_names))
        if len(x) == 0:
            return Evaluation(
                np.empty((0, len(self.response_names))),
                np.zeros(0, bool),
                (),
                np.empty((0, len(self.check_names))),
            )
        return self._evaluate_batch(x, self._evaluation)

    def _evaluate_batch(
        self,
        x: FloatArray,
        evaluation_of: Callable[[FloatArray, Any, BoolArray | None], Evaluation],
        running: Any = None,
    ) -> Evaluation:
        """The block ``x`` (checked, not empty) through the batch engine, its result made an
        :class:`Evaluation` by ``evaluation_of(x, result, finished)``; ``running``: the
        running responses asked of the lanes
        (:class:`~jointplay.dynamics.batch_running.RunningOutputs`)."""
        from jointplay.dynamics.batch import BatchInterrupted, simulate_batch
        from jointplay.dynamics.integrate import IntegrationStatus

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
                running=running,
            )
        except BatchInterrupted as stopped:  # the finished samples go on with the interrupt
            finished = stopped.result.status != IntegrationStatus.INTERRUPTED
            with interrupts_noted():  # a second Ctrl-C here must not lose them
                evaluation = evaluation_of(x, stopped.result, finished)
            raise PartialInterrupt(evaluation) from None
        with interrupts_noted() as noted:  # the block ran: an interrupt now keeps it
            evaluation = evaluation_of(x, result, None)
        if noted:
            raise PartialInterrupt(evaluation)
        return evaluation

    def _evaluation(
        self, x: FloatArray, result: Any, finished: BoolArray | None = None
    ) -> Evaluation:
        """The :class:`Evaluation` of the block ``x`` from its batch result."""
        values = result.peaks[list(self.peak_keys)].to_numpy(dtype=float)
        penetration = result.statistics[[f"pen_{j}" for j in self.clearance_joints]]
        deepest = penetration.to_numpy(dtype=float)
        clearance = self.clearances(x)
        forces = result.peaks[[f"F_{j}" for j in self.clearance_joints]].to_numpy(dtype=float)
        regimes = list(regime_check_names(self.lubricated_joints))
        checks = np.hstack(
            [
                _ratio(deepest, clearance),
                _elastic_ratios(self.mechanism, self.clearance_joints, self.journal_radius,
                                clearance, deepest, forces),
                result.statistics[regimes].to_numpy(dtype=float).reshape(len(x), len(regimes)),
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


def sample_checks(result: SimulationResult, lubricated: Sequence[str] = ()) -> FloatArray:
    """(2c + 3l,) the checks of a single-engine simulation, in the order of
    :attr:`DynamicResponses.check_names`: :func:`penetration_ratios`, then the elastic
    ratios (``elastic_ratio_<joint>``), then per joint of ``lubricated`` its time fractions
    in full film, mixed and boundary lubrication
    (:attr:`~jointplay.dynamics.simulate.SimulationResult.film_regimes`; NaN where the joint
    ran dry).

    Raises:
        IntegrationError: the simulation stopped at its initial state.
    """
    joints = result.system.clearances
    names = [joint.joint for joint in joints]
    deepest = result.running.max_penetration
    fractions = []
    if lubricated:
        regimes = result.film_regimes
        for joint in lubricated:
            regime = regimes.get(joint)
            fractions += (
                [math.nan] * len(REGIME_CHECKS)
                if regime is None
                else [regime.full_film, regime.mixed, regime.boundary]
            )
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
            np.array(fractions, dtype=float),
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
    return Evaluation(
        values, evaluation.ok & result.ok, errors, evaluation.checks, evaluation.finished
    )


#: Responses :class:`RunningResponses` adds to the dynamic peaks, with SI units.


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
        joint force and contact pressure from them, then the kinematic responses; an
        interrupted block's finished samples get them too (its
        :class:`~jointplay.errors.PartialInterrupt` carries the whole row of responses)."""
        x = _check_inputs(x, len(self.input_names))
        try:
            peaks = super().evaluate(x)
        except PartialInterrupt as stopped:
            raise PartialInterrupt(self._with_derived(x, stopped.partial)) from None
        return self._with_derived(x, peaks)

    def _with_derived(self, x: FloatArray, peaks: Any) -> Evaluation:
        """``peaks`` (the base evaluation of the block ``x``) with the derived responses."""
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
        evaluation = Evaluation(values, peaks.ok, peaks.errors, peaks.checks, peaks.finished)
        return _add_kinematic(self.kinematic, self.kinematic_names, self.input_names, x, evaluation)


def contact_parts(mechanism: Mechanism, contact: ContactModel) -> dict[str, Any]:
    """The ``law``, ``friction``, ``stiffness_from``, ``capture_speed``, ``film_damping`` and
    ``film_from`` of :class:`DynamicResponses` for the contact ``contact``: with a stiffness
    from the geometry, the law's stiffness and exponent are placeholders that every joint
    refits to its clearance (:meth:`DynamicResponses._joint`)."""
    from jointplay.dynamics.setup import joint_stiffness, make_law

    if contact.law is not None:
        return {
            "law": contact.law,
            "friction": contact.friction.build(),
            "stiffness_from": {},
            **_film_parts(mechanism, contact),
        }
    geometric = contact.settings.geometry_law is not None
    return {
        "law": make_law(contact.settings, stiffness=1.0 if geometric else None),
        "friction": contact.friction.build(),
        "stiffness_from": {
            joint.name: rule
            for joint in mechanism.revolute_joints
            if (rule := joint_stiffness(mechanism, joint.name, contact.settings)) is not None
        },
        **_film_parts(mechanism, contact),
    }


def _film_parts(mechanism: Mechanism, contact: ContactModel) -> dict[str, Any]:
    """The ``capture_speed``, ``film_damping``, ``film_from`` and ``lubrication`` (in words,
    over the joints with a fit) of ``contact``."""
    films = {j.name: contact.film_of(mechanism, j.name) for j in mechanism.revolute_joints}
    fitted = [j.name for j in mechanism.revolute_joints if j.fit is not None]
    return {
        "capture_speed": contact.capture,
        "film_damping": contact.fixed_film or 0.0,
        "film_from": {name: rule for name, rule in films.items() if rule is not None},
        "lubrication": contact.lubrication_table(mechanism, fitted),
        "lubrication_text": contact.regime_words(mechanism, fitted) if fitted else "",
    }


def run_model(
    mechanism: Mechanism,
    input_names: Sequence[str],
    run: RunSettings,
    *,
    journal_radius: Mapping[str, float] | None = None,
    **options: Any,
) -> DynamicResponses:
    """The dynamic response model of ``mechanism`` run as ``run`` says: its contact
    (:func:`contact_parts`: the law, friction, stiffness and film per joint, the
    sustained-contact mode), start, settle, revolutions and solver, read here, the one place a
    study's :class:`~jointplay.dynamics.settings.RunSettings` becomes the batch engine's
    model (:func:`dynamic_model`); ``options``: its others (``backend``, ``method``,
    ``friction`` in place of the contact's, ...)."""
    return dynamic_model(
        mechanism,
        input_names,
        journal_radius=journal_radius,
        **{
            **contact_parts(mechanism, run.contact),
            "start": run.start,
            "settle": run.settle,
            "revolutions": run.revolutions,
            "solver": run.solver,
            **options,
        },
    )


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
