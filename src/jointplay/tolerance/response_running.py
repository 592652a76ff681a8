"""The running response model: :class:`RunningResponses`, the dynamic peaks plus each
sample's single-engine running responses (rocker-speed error, joint force, contact
pressure, wear rate). :mod:`jointplay.tolerance.responses` describes the models.
"""

from __future__ import annotations

from collections.abc import Mapping
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import JointplayError

if TYPE_CHECKING:  # the dynamics import Numba: loaded only by dynamic studies
    from jointplay.dynamics.wear import OutputSpeedReference, WearSettings
from jointplay.tolerance.response_base import (
    Evaluation,
    ResponseModel,
)
from jointplay.tolerance.response_dynamic import (
    DynamicResponses,
    _add_kinematic,
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
        return _add_kinematic(self.kinematic, self.kinematic_names, self.input_names, x, evaluation)
