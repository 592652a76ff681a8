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

The models live in :mod:`~jointplay.tolerance.response_base` (what they share, and the
linear verification model), :mod:`~jointplay.tolerance.response_kinematic`,
:mod:`~jointplay.tolerance.response_dynamic` and :mod:`~jointplay.tolerance.response_running`;
this module gathers them, and ``jointplay.tolerance.responses`` stays their import path.
"""

from __future__ import annotations

from jointplay.tolerance.response_base import (
    ELASTIC_RATIO,
    ELASTIC_RATIO_DEFINITION,
    PENETRATION_RATIO,
    PENETRATION_RATIO_DEFINITION,
    CheckedModel,
    DifferentiableModel,
    Evaluation,
    LinearModel,
    ResponseModel,
)
from jointplay.tolerance.response_dynamic import (
    DynamicResponses,
    PeakResponses,
    contact_parts,
    dynamic_model,
    peak_contact_pressure,
    penetration_ratios,
    run_model,
    sample_checks,
)
from jointplay.tolerance.response_kinematic import (
    FourBarKinematics,
    GeneralKinematics,
    kinematic_model,
)
from jointplay.tolerance.response_running import (
    RUNNING_RESPONSES,
    RunningResponses,
)

__all__ = [
    "ELASTIC_RATIO",
    "ELASTIC_RATIO_DEFINITION",
    "PENETRATION_RATIO",
    "PENETRATION_RATIO_DEFINITION",
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
    "contact_parts",
    "dynamic_model",
    "kinematic_model",
    "peak_contact_pressure",
    "penetration_ratios",
    "run_model",
    "sample_checks",
]
