"""The running response model: :class:`RunningResponses`, the dynamic peaks plus each
sample's running responses (rocker-speed error, joint force, contact pressure, wear rate),
computed by the batch engine's lanes as reductions
(:mod:`jointplay.dynamics.batch_running`), the sustained-contact mode included (on the
implicit lanes); the single engine on request (``engine="single"``).
:mod:`jointplay.tolerance.responses` describes the models.
"""

from __future__ import annotations

import dataclasses
from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError, JointplayError, PartialInterrupt
from jointplay.execution.backends import Backend

if TYPE_CHECKING:  # the dynamics import Numba: loaded only by dynamic studies
    from jointplay.dynamics.wear import OutputSpeedReference, WearSettings
from jointplay.tolerance.response_base import (
    Evaluation,
    ResponseModel,
)
from jointplay.tolerance.response_dynamic import (
    DynamicResponses,
    _add_kinematic,
    _check_inputs,
    _kinematic_names,
    peak_contact_pressure,
    sample_checks,
)

FloatArray = NDArray[np.float64]
BoolArray = NDArray[np.bool_]


RUNNING_RESPONSES: Mapping[str, str] = {
    "rocker_speed_error": "1",
    "joint_force": "N",
    "contact_pressure": "Pa",
    "wear_rate": "m/s",
}
#: The engines of :attr:`RunningResponses.engine`.
ENGINES = ("auto", "batch", "single")


@dataclass(frozen=True)
class RunningResponses:
    """The mechanism as it runs: the dynamic peaks (:class:`DynamicResponses`) plus the
    rocker-speed error against the ideal linkage, the largest joint force, the largest Hertz
    contact pressure and the Archard wear rate of the radial clearance (the fastest and per
    joint). Used by ``tolerance_study(responses="running")`` and the design study.

    A block of samples runs on the batch engine (:meth:`DynamicResponses.evaluate`'s
    lanes on ``backend``), the running responses computed in the lanes as reductions
    (:mod:`jointplay.dynamics.batch_running`), a locked joint's contact force in the
    sustained-contact mode its multiplier as on the single engine; the single engine (one
    simulation per sample) on request.

    Attributes:
        base: the tolerance study's dynamic model (inputs, contact law, start, settle).
        reference: the nominal ideal-joint output speed.
        wear: Archard parameters.
        kinematic: optionally, the ideal-joint kinematic model of the same length inputs:
            its responses that the dynamics do not give (``rocker_swing``,
            ``transmission_angle_min``, …) are added for each sample's lengths, so
            requirements may mix kinematic and dynamic responses.
        chunk_size: samples per block (0: the base model's block on the batch engine, one
            sample per task on the single engine).
        engine: ``"auto"`` or ``"batch"`` (the batch engine) or ``"single"`` (one
            single-engine simulation per sample: the path before the lanes had the running
            responses; the comparisons and benchmarks).
        backend: where a block's lanes run (default the base model's; ``None`` on the
            single engine, whose samples the study's executor spreads one task each).
    """

    base: DynamicResponses
    reference: OutputSpeedReference
    wear: WearSettings
    kinematic: ResponseModel | None = None
    chunk_size: int = 0
    engine: str = "auto"
    backend: Backend | None = None

    #: Cost of one sample on one core on the batch engine (the lubricated default, measured
    #: 40 samples/s: docs/performance.md), s.
    seconds_per_sample = 0.025

    def __post_init__(self) -> None:
        if self.engine not in ENGINES:
            raise ConfigError(
                f"RunningResponses: engine must be one of {', '.join(ENGINES)}, got {self.engine!r}"
            )
        batch = self.on_batch
        if self.chunk_size <= 0:
            object.__setattr__(self, "chunk_size", self.base.chunk_size if batch else 1)
        if batch and self.backend is None:
            object.__setattr__(self, "backend", self.base.backend)
        elif not batch:
            object.__setattr__(self, "backend", None)

    @property
    def on_batch(self) -> bool:
        """Whether a block runs on the batch engine (else one single-engine simulation per
        sample)."""
        return self.engine != "single"

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
        base = self.base.describe()
        if self.on_batch:
            return {
                **base,
                "model": (
                    f"{base.get('model', 'clearance-joint dynamics')}; the running responses "
                    "in the same lanes (jointplay.dynamics.batch_running)"
                ),
                "rocker_speed_error": (
                    "largest |omega_out - omega_ideal(crank)| over the analysed revolutions, "
                    "located on the continuous solution like the peaks, over the nominal "
                    "ideal speed's largest |omega|"
                ),
                "wear": self.wear.describe(self.base.mechanism),
            }
        return {
            "model": (
                "clearance-joint dynamics, one single-engine simulation per sample "
                "(jointplay.dynamics.simulate, Radau IIA)"
            ),
            **{k: v for k, v in base.items() if k not in batch_only},
            "peaks": (
                f"largest |value| over the {self.base.revolutions:g} revolution(s) after "
                f"{self.base.settle} start-up revolution(s), located on the continuous "
                "solution (SimulationResult.peaks)"
            ),
            "wear": self.wear.describe(self.base.mechanism),
        }

    def evaluate(self, x: FloatArray) -> Evaluation:
        """The block ``x`` on the batch engine (the running responses in its lanes), or one
        single-engine simulation per sample (:attr:`engine`); failures are marked, not
        raised; an interrupted block's finished samples keep their whole row."""
        x = _check_inputs(x, len(self.input_names))
        if not self.on_batch:
            return self._evaluate_single(x)
        if len(x) == 0:
            return Evaluation(
                np.empty((0, len(self.response_names))),
                np.zeros(0, bool),
                (),
                np.empty((0, len(self.check_names))),
            )
        from jointplay.dynamics.batch_running import RunningOutputs

        base = self.base
        if self.backend is not None and self.backend != base.backend:
            base = dataclasses.replace(base, backend=self.backend)
        try:
            evaluation = base._evaluate_batch(
                x, self._from_batch, RunningOutputs(self.reference, self.wear)
            )
        except PartialInterrupt as stopped:
            partial = stopped.partial
            assert isinstance(partial, Evaluation)
            raise PartialInterrupt(self._with_kinematic(x, partial)) from None
        return self._with_kinematic(x, evaluation)

    def _with_kinematic(self, x: FloatArray, evaluation: Evaluation) -> Evaluation:
        return _add_kinematic(self.kinematic, self.kinematic_names, self.input_names, x, evaluation)

    def _from_batch(self, x: FloatArray, result: Any, finished: BoolArray | None) -> Evaluation:
        """The :class:`Evaluation` of the block ``x`` from its batch result with the running
        responses (``omega<k>_deviation``, ``wear_rate_<joint>``)."""
        from jointplay.dynamics.batch_running import speed_error_of

        base = self.base._evaluation(x, result, finished)
        joints = self.joints
        deviation = result.peaks[f"omega{self.reference.link_number}_deviation"].to_numpy(
            dtype=float
        )
        forces = result.peaks[[f"F_{j}" for j in joints]].to_numpy(dtype=float)
        clearances = self.base.clearances(x)
        radius = [self.base.journal_radius[j] for j in joints]
        pressures = np.array(
            [
                [
                    peak_contact_pressure(self.base.mechanism, joint, force, r, clearance)
                    for joint, force, r, clearance in zip(joints, row, radius, gaps, strict=True)
                ]
                for row, gaps in zip(forces, clearances, strict=True)
            ]
        ).reshape(len(x), len(joints))
        rates = result.statistics[[f"wear_rate_{j}" for j in joints]].to_numpy(dtype=float)
        values = np.column_stack(
            [
                base.values,
                speed_error_of(deviation, self.reference),
                forces.max(axis=1, initial=0.0),
                pressures.max(axis=1, initial=0.0),
                rates.max(axis=1, initial=0.0),
                rates,
                np.full((len(x), len(self.kinematic_names)), np.nan),
            ]
        )
        return Evaluation(values, base.ok, base.errors, base.checks, base.finished)

    def _evaluate_single(self, x: FloatArray) -> Evaluation:
        """One single-engine simulation per sample (:meth:`DynamicResponses.simulate_one`);
        failures are marked, not raised; checks from :func:`sample_checks`."""
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
                checks[i] = sample_checks(result, self.base.lubricated_joints)
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
        return self._with_kinematic(x, evaluation)


def check_running_backend(base: DynamicResponses, backend: Backend | None, what: str) -> None:
    """Refuse, in one line, a ``backend`` whose engine cannot give ``base``'s running
    responses: the batch lanes compute them (every CPU backend and the CUDA lanes), the
    sustained-contact mode's on the CPU backends' implicit lanes only. ``what`` names the
    requirements concerned.

    Raises:
        ConfigError: the backend's engine lacks them (e.g. ``gpu``, the JAX kernel; ``cuda``
            with the sustained-contact mode).
    """
    from jointplay._kernels.capabilities import engine_of, refusal

    if backend is None:
        return
    sustained = base.capture_speed > 0.0
    refused = refusal(
        engine_of(backend.kind, "implicit" if sustained else "auto"),
        ["running_responses", *(["sustained_contact"] if sustained else [])],
        named=lambda need: what if need == "running_responses" else "the sustained-contact mode",
    )
    if refused:
        raise ConfigError(f"backend {backend.kind}: {refused}")
