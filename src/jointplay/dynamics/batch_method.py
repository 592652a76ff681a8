"""The batch engine's method: explicit Dormand–Prince 5(4) for contact laws that do not make
the equations stiff at the accuracy step, Radau IIA otherwise, with the reason
(:func:`choose_method`). :mod:`jointplay.dynamics.batch` runs the chosen one.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import Any

import numpy as np
from numpy.typing import NDArray

from jointplay._kernels.contact import normal_force
from jointplay.dynamics.batch_inputs import BatchSamples
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.simulate import (
    EXPLICIT_TOLERANCE_SCALE,
    EXPLICIT_TOLERANCES,
    SolverOptions,
)
from jointplay.dynamics.system import PARAMS_WIDTH
from jointplay.errors import JointplayError
from jointplay.model.mechanism import Mechanism
from jointplay.model.templates import (
    TemplateSpec,
)

__all__ = [
    "EXPLICIT_TOLERANCES",
    "EXPLICIT_TOLERANCE_SCALE",
    "STIFFNESS_RATIO",
    "MethodChoice",
    "choose_method",
]

FloatArray = NDArray[np.float64]


# --- the method ------------------------------------------------------------------------------------
#: DOPRI5's stability boundary on the negative real axis (Hairer & Wanner, Solving ODEs II,
#: §IV.2, Fig. 2.1: about −3.3).
DOPRI5_STABILITY = 3.3
#: The explicit method is chosen when its stability limit allows steps of at least this
#: fraction of the largest (accuracy) step; below it the contact is stiff at that step.
STIFFNESS_RATIO = 1.0 / 10.0


@dataclass(frozen=True)
class MethodChoice:
    """The integration method of a batch and why.

    Attributes:
        method: ``"explicit"`` (Dormand–Prince 5(4)) or ``"implicit"`` (Radau IIA).
        reason: one sentence for the user.
        stable_step: the explicit method's stability limit estimated for the stiffest contact
            law, s (``inf``: none found).
        max_step: the largest (accuracy) step, s.
    """

    method: str
    reason: str
    stable_step: float
    max_step: float


def _contact_rate(law: Any, friction: Any, delta: float, rate: float, mass: float) -> float:
    """Largest |eigenvalue| (1/s) of one contact linearised about (δ, δ̇) with mass ``mass``:
    c/m + √(k/m), with k = ∂F_N/∂δ, c = ∂F_N/∂δ̇ (+ the friction law's slope times F_N)."""
    params = np.zeros(PARAMS_WIDTH)
    packed = law.params()
    params[: len(packed)] = packed
    force = normal_force(law.law_id, params, 0, delta, rate, rate)
    h = 1e-6 * delta
    stiffness = (normal_force(law.law_id, params, 0, delta + h, rate, rate) - force) / h
    h = 1e-6 * abs(rate)
    damping = (normal_force(law.law_id, params, 0, delta, rate + h, rate) - force) / h
    if friction is not None:
        from jointplay._kernels.contact import friction_force

        fparams = np.zeros(PARAMS_WIDTH)
        fpacked = friction.params()
        fparams[: len(fpacked)] = fpacked
        slip = 1e-6 * abs(rate)
        slope = max(
            abs(
                friction_force(friction.law_id, fparams, 0, v, force)
                - friction_force(friction.law_id, fparams, 0, v - slip, force)
            )
            / slip
            for v in (slip, abs(rate))
        )
        damping += slope
    return float(abs(damping) / mass + math.sqrt(max(stiffness, 0.0) / mass))


def choose_method(
    mechanism: Mechanism,
    clearances: Sequence[ClearanceJoint],
    *,
    samples: BatchSamples | None = None,
    solver: SolverOptions | None = None,
) -> MethodChoice:
    """Explicit or implicit integration for this mechanism, contact laws and samples.

    Each clearance joint's contact law is linearised at a penetration equal to its clearance
    and a penetration rate of 10 % of the crank pin's speed (the scale of the impacts), over
    the lightest moving link: its largest rate |λ| = c/m + √(k/m) bounds the explicit step to
    ``DOPRI5_STABILITY / |λ|``. When that bound is below ``STIFFNESS_RATIO`` of the largest
    step (1° of crank by default) the contact is stiff — the ECS parameter sets with their
    huge damping reached at nanometre depths are — and Radau IIA is chosen; so it is for the
    Hunt–Crossley family (a damping divided by the impact velocity: stiff in slow contacts,
    where the linearisation at 10 % of the crank pin's speed does not look); otherwise
    Dormand–Prince 5(4), whose steps then follow the accuracy it is asked for. With samples,
    the stiffest combination of the sampled law parameters (each at its extremes) decides.
    A heuristic: both methods solve every set; the choice only decides which is faster.
    The sustained-contact mode (a clearance joint with a capture speed) and film damping run
    on Radau only.
    """
    solver = solver or SolverOptions()
    driver = mechanism.driver
    period = driver.period
    max_step = solver.max_step if solver.max_step is not None else period / 360.0
    if any(c.capture_speed > 0 for c in clearances):
        return MethodChoice(
            "implicit",
            "implicit: the sustained-contact mode runs on the Radau lanes only",
            math.nan,
            max_step,
        )
    if any(c.film_damping > 0 for c in clearances):
        return MethodChoice(
            "implicit", "implicit: film damping runs on the Radau lanes only", math.nan, max_step
        )
    spec = mechanism.template
    crank_pin = (
        (float(getattr(spec.geometry, "crank", 0.0)) if isinstance(spec, TemplateSpec) else 0.0)
        or max(math.hypot(*link.com) for link in mechanism.links) * 2.0
        or 0.1
    )
    rate = 0.1 * driver.speed * crank_pin
    lightest = min(link.mass for link in mechanism.links)
    worst = 0.0
    for joint in clearances:
        variants = [joint.law]
        if samples is not None and samples.law:
            for pick in (np.min, np.max):
                try:
                    variants.append(
                        dataclasses.replace(
                            joint.law, **{k: float(pick(v)) for k, v in samples.law.items()}
                        )
                    )
                except JointplayError:
                    continue
        clearance = joint.clearance
        if samples is not None and joint.joint in samples.clearances:
            clearance = float(np.nanmin(samples.clearances[joint.joint]))
        for law in variants:
            worst = max(worst, _contact_rate(law, joint.friction, clearance, rate, lightest))
    stable = DOPRI5_STABILITY / worst if worst > 0 else math.inf
    remembering = sorted({j.law.name for j in clearances if j.law.needs_impact_velocity})
    if remembering:
        return MethodChoice(
            "implicit",
            f"implicit Radau IIA: the {', '.join(remembering)} law divides its damping by the "
            "impact velocity, which makes slow (grazing) contacts stiff: on the paper's RM set "
            "the explicit lanes needed 4.6 times Radau's steps for its accuracy",
            stable,
            max_step,
        )
    if not math.isfinite(worst):
        return MethodChoice(
            "implicit", "the contact law's slopes are not finite: Radau IIA", stable, max_step
        )
    if stable >= STIFFNESS_RATIO * max_step:
        return MethodChoice(
            "explicit",
            f"explicit Dormand-Prince 5(4): the contact laws allow explicit steps up to "
            f"{stable:.3g} s, not far below the largest step {max_step:.3g} s (the contact "
            f"is not stiff at the accuracy asked for); {EXPLICIT_TOLERANCES}",
            stable,
            max_step,
        )
    return MethodChoice(
        "implicit",
        f"implicit Radau IIA: the contact laws are stiff (explicit steps would be limited to "
        f"{stable:.3g} s by stability, under {STIFFNESS_RATIO:g} of the largest step "
        f"{max_step:.3g} s)",
        stable,
        max_step,
    )
