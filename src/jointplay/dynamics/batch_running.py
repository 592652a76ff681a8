"""The running responses on the batch engine: what the lanes compute beside the peaks when
asked (:class:`RunningOutputs`, ``simulate_batch(..., running=...)``).

Two reductions, in the lanes of every backend that has them (the CPU's explicit lanes and
Radau steps, the CUDA lanes; the lane source's ``running_*`` functions,
:mod:`jointplay._kernels.lanes.source`):

- the output link's speed deviation ``ω_out(t) − ω_ideal(θ_crank(t))`` (rad/s) as one more
  quantity of the peak rule (its largest |value| located on the continuous solution, like
  every peak): the nominal ideal speed is a table periodic in the crank angle, interpolated
  linearly (:class:`~jointplay.dynamics.wear.OutputSpeedReference`); over the reference's
  largest |ω| it is :func:`~jointplay.dynamics.wear.speed_error`;
- per clearance joint the Archard wear rate of the radial clearance (m/s):
  ``k/H ∫ F_N |v_T| dt`` on the integrator's steps from the first step at or after the
  window's start (trapezoidal rule), each step's amount spread over the Hertz arc on the
  bearing's and the journal's profile (``bins`` per turn), the rate the deepest bearing
  wear plus the deepest journal wear over the window's time — as
  :func:`~jointplay.dynamics.wear.cycle_wear` and ``growth_per_revolution`` per period
  compute it. F_N is the contact law's (under a Reynolds film the asperities' share only).

The tail that carries them to the lanes follows each sample's packed model in ``rpar``
(``source.RUN_*``): the same for every sample (the nominal reference, bearing widths and
materials); each lane reads its own radii and clearance from its geometry. Without it the
lanes compute nothing more (the peaks and statistics of a batch without running responses
are bit-identical to those before they existed).
"""

from __future__ import annotations

import math
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from jointplay._kernels.lanes import source
from jointplay.contact.hertz import effective_modulus
from jointplay.dynamics.system import System
from jointplay.dynamics.wear import SURFACE_SHARE, OutputSpeedReference, WearSettings
from jointplay.errors import ConfigError
from jointplay.model.columns import rotating_links
from jointplay.model.mechanism import Mechanism

__all__ = ["RunningOutputs"]

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class RunningOutputs:
    """The running responses a batch computes beside its peaks.

    Attributes:
        reference: the nominal ideal-joint output speed (the speed deviation's reference).
        wear: Archard parameters (coefficient, hardness, bins of the profiles).
    """

    reference: OutputSpeedReference
    wear: WearSettings

    def output_link(self, mechanism: Mechanism) -> str:
        """The name of the output link (the reference's ``omega<k>``)."""
        for name, number in rotating_links(mechanism):
            if number == self.reference.link_number:
                return name
        raise ConfigError(
            f"the speed reference's output link omega{self.reference.link_number} is not a "
            "rotating link of this mechanism"
        )

    def tail(self, mechanism: Mechanism, system: System) -> FloatArray:
        """The running tail of every sample's ``rpar`` row (``source.RUN_*``).

        Raises:
            ConfigError: a clearance joint without a bearing width (link thickness or pin
                length), or the output link is not the mechanism's.
        """
        crank = np.asarray(self.reference.crank, dtype=float)
        omega = np.asarray(self.reference.omega, dtype=float)
        keep = np.concatenate([[True], np.diff(crank) > 0.0])  # one value per angle
        crank, omega = crank[keep], omega[keep]
        joints = []
        for clearance in system.clearances:
            name = clearance.joint
            width = mechanism.bearing_width(name)
            if width is None:
                raise ConfigError(
                    f"wear of joint {name!r}: no bearing width; give its links a thickness or "
                    "the pin a pin_length"
                )
            joint = mechanism.joint(name)
            a, b = mechanism.material_of(joint.link_a), mechanism.material_of(joint.link_b)
            k, hardness = self.wear.of(name, mechanism)
            modulus = effective_modulus(
                a.youngs_modulus, a.poisson_ratio, b.youngs_modulus, b.poisson_ratio
            )
            joints += [float(width), modulus, SURFACE_SHARE * k / hardness]
        head = np.zeros(source.RUN_TABLE)
        head[source.RUN_OUTPUT] = system.flat.body_index(self.output_link(mechanism))
        head[source.RUN_POINTS] = len(crank)
        head[source.RUN_BINS] = self.wear.bins
        return np.concatenate([head, crank, omega, np.array(joints, dtype=float)])

    @property
    def peak_speed(self) -> float:
        """The reference's largest ideal |ω| (rad/s): the speed error's denominator."""
        return self.reference.peak


def speed_error_of(deviation: FloatArray, reference: OutputSpeedReference) -> FloatArray:
    """The rocker-speed error (dimensionless) from the batch's largest speed deviation
    (rad/s): over the reference's largest ideal |ω|."""
    peak = reference.peak
    return np.asarray(deviation, dtype=float) / (peak if peak > 0 else math.nan)
