"""Compiled batch engine: many samples of one mechanism, peaks and steady-cycle statistics.

Every sample ("lane") is one integration of the equations of motion of
:mod:`jointplay._kernels.eom` from its own initial state; all lanes share the integer
structure ``ipar`` and differ in ``rpar`` (link geometry, masses, clearances, law parameters,
crank speed) and ``y0``. No trajectory is kept: each lane keeps running peaks and sums.
:func:`run_batch` is the entry point (the contract shared with the JAX backend,
:mod:`jointplay._kernels.jax_batch`)::

    run_batch(ipar, rpar (n, R), y0 (n, S), t_settle (n), t_end (n), max_step (n), rtol,
              atol (S), max_steps, method) -> BatchKernelOutput

Outputs per lane, over the window [t_settle, t_end]:

- ``peaks`` (P = 2 nb + nj + 1), QUANTITY ORDER: ω_b of every body (rad/s), α_b (rad/s²), the
  force transmitted by every joint (N), the motor torque (N·m) — largest |value|, as
  :func:`jointplay._kernels.eom.batch_quantities` defines them (the lane source's
  ``rhs_and_quantities``);
- ``stats`` (M = 2 nb + 4 nc), STATS ORDER: time-mean of ω_b, RMS of ω_b (trapezoidal rule
  over the accepted steps, rad/s), largest penetration δ = |e| − c of every clearance joint at
  the accepted steps (m; negative: never touched), then per clearance joint the fractions of
  the window in full film, mixed and boundary lubrication (each accepted step counted by
  λ = h_min/σ at its midpoint, as :mod:`jointplay.dynamics.regimes`; NaN for a dry joint, and
  on the JAX backend, whose stats stop at the penetrations: it runs no film);
- with the running responses (``rpar``'s rows carry the running tail after the packed model,
  :mod:`jointplay.dynamics.batch_running`; ``lay``'s quantities one more:
  :func:`jointplay._kernels.lanes.build.running_layout`): one more peak, the output link's
  speed deviation ω_out − ω_ideal(θ_crank) (rad/s; refined on every step, not only near its
  running peak, and never the trigger of the other quantities' refinement, so their peaks are
  those without it, bit for bit), and after the statistics above, per clearance joint the Archard wear rate
  of the radial clearance (m/s), then the lanes' working slots (the last point per joint, a
  flag, the bearing's and the journal's worn amounts per bin: the lane source's
  ``running_stats``); without the tail the lanes compute and return nothing more;
- ``status`` (:mod:`jointplay._kernels.ids` ``STATUS_*``), ``t_reached``, ``n_steps``,
  ``n_rejected``, ``n_rhs`` (right-hand-side evaluations; the quantity evaluations of the
  peak search are not counted).

**"explicit"** — Dormand–Prince 5(4) (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.5,
Table 5.2: the DOPRI5 tableau, FSAL), propagating the 5th-order solution; the lane is
the lanes' one loop :func:`jointplay._kernels.lanes.source.lane` with DOPRI5's steps
(``dopri_*``), written once for the CPU (compiled by
:mod:`jointplay._kernels.lanes.cpu`) and NVIDIA GPUs (:mod:`jointplay._kernels.lanes.cuda`):

- error ``err_i = h Σ_j E_j k_j,i``, norm ``sqrt(mean_i (err_i / sc_i)²)`` over the first
  ``2·n_coordinates`` components (q, q̇: the work integrals and the impact memory v0 do not
  feed back, as ``n_active`` in the Radau kernel), ``sc_i = atol_i + rtol·max(|y_i|, |y_new_i|)``;
- a step is rejected when ``err > 1`` and retried with ``h·max(0.2, 0.9·err^(−1/5))``;
  an accepted step proposes ``h·min(10, max(0.2, 0.9·err^(−1/5)))`` (10 when ``err = 0``),
  at most ``h`` if this step had a rejection; ``h <= max_step``; first step ``max_step/10``;
  a step that would pass the next landmark (``t_settle``, then ``t_end``) is cut to land on
  it exactly; a step below ``10·spacing(t)`` ends the lane with ``STATUS_STEP_TOO_SMALL``;
- the last stage's evaluation, at the step's end, also records every joint's contact
  (penetration, its rate, forces) and the quantities of the peak rule
  (the lane source's ``rhs_and_quantities``);
- after the error test, the contact-onset check on those records (the lane source's
  ``onset_check``), may retry the step shorter
  (``MAX_CHECK_REJECTIONS``); each retry counts as a rejection but does not cap the next
  step's growth;
- after acceptance, the contact memory v0 from the records, then the projection onto the
  ideal constraints; f, the records and the quantities are
  evaluated again only if it changed the state (FSAL otherwise); a non-finite state or f ends
  the lane with ``STATUS_NON_FINITE``.

**"implicit"** — the lanes' loop with Radau IIA's steps
(:mod:`jointplay._kernels.lanes.source_radau`, compiled by :mod:`jointplay._kernels.lanes.cpu`:
``DRIVERS["implicit"]``), which takes the single engine's steps with exactly the settings of
:func:`jointplay.dynamics.simulate.simulate` (the sustained-contact mode included: its hooks
are the single engine's, :mod:`jointplay._kernels.sustained`) and reduces each accepted step
as it is taken, the interpolant being the single engine's (the lane source's ``hermite``:
cubic Hermite of q with q̇ and of q̇ with q̈; with film damping the quintic through q and q̇
at three step ends, or next to a contact's start or end q̇ the derivative of q's cubic).

**Peak rule** (both methods; the JAX backend applies the same one). Let ``Q_a``, ``Q_b`` be the
quantities at the two ends of an accepted step inside the window (``Q_b`` after the
contact memory and the projection), ``peak`` the running largest |value| including
``|Q_b|``. The step is
*refined* when, for any quantity p that may trigger (every quantity except ω and α of the
driven body and of bodies held by an ideal prismatic joint to the ground),
``max(|Q_a,p|, |Q_b,p|) >= (1 − REFINE_MARGIN)·peak_p > 0``. A refined step evaluates the
method's interpolant at the seven ``REFINE_POINTS`` θ = 1/8, 2/8, …, 7/8 (DOPRI5: SciPy's
free 4th-order dense output ``P`` below; Radau: the Hermite interpolant above), the quantities at those
states, and for every quantity takes ``s_0..s_8 = |Q|`` at θ = 0, 1/8, …, 7/8, 1: with ``m``
the first index of the largest, ``0 < m < 8`` and ``c = s_{m−1} − 2 s_m + s_{m+1} < 0``, the
vertex of the parabola through the three points, ``s_m − (s_{m−1} − s_{m+1})² / (8 c)``
(offset clipped to ±1/2 spacing), else ``s_m``; the peak becomes the larger of that and the running peak. The first step of
the window (whose start sets the peaks) is therefore always refined.

Lanes are independent: the kernel's result for a lane does not depend on the other lanes,
on the chunk it runs in, or on the thread that runs it.
"""

from __future__ import annotations

from typing import TypeVar

import numpy as np
import numpy.typing as npt

from jointplay._kernels import ids
from jointplay._kernels.integrators import lane_methods
from jointplay._kernels.lanes import build as lane_build
from jointplay._kernels.lanes import cpu as lane_cpu
from jointplay._kernels.lanes.contract import (  # noqa: F401 (re-exported: the peak rule's)
    DENSE,
    NO_INTERRUPT,
    REFINE_MARGIN,
    REFINE_POINTS,
    BatchKernelOutput,
    finished,
    lane_inputs,
    lane_outputs,
)

__all__ = [
    "METHODS",
    "REFINE_MARGIN",
    "BatchKernelOutput",
    "layout",
    "run_batch",
    "run_chunk",
]

#: Integration methods of :func:`run_batch`: those of the integrators its lanes have.
METHODS = lane_methods("lanes-explicit", "batch-implicit")


def layout(ipar: npt.NDArray[np.int64]) -> tuple[int, int, int, int]:
    """``(nb, nj, nc, n_state)`` of the model packed in ``ipar``."""
    length = dict(zip(ids.MODEL_FIELDS, (int(k) for k in ipar), strict=False))
    n, nj, nc = length["mass"], length["active"], length["clear_joint"]
    return n // 3, nj, nc, 2 * n + 2 + nc


def run_chunk(
    shared: tuple[npt.NDArray[np.int64], float, npt.NDArray[np.float64], int, str],
    chunk: tuple[npt.NDArray[np.float64], ...],
) -> BatchKernelOutput:
    """A worker's task: ``chunk = (rpar, y0, t_settle, t_end, max_step)`` through the serial
    kernel, ``shared = (ipar, rtol, atol, max_steps, method)``. It lives here so that a worker
    imports only the kernels (not pandas nor the rest of jointplay)."""
    ipar, rtol, atol, max_steps, method = shared
    rpar, y0, t_settle, t_end, max_step = chunk
    return run_batch(
        ipar, rpar, y0, t_settle, t_end, max_step, rtol, atol, max_steps, method, parallel=False
    )


_Scalar = TypeVar("_Scalar", bound=np.generic)


def _read_only_copy(array: npt.NDArray[_Scalar]) -> npt.NDArray[_Scalar]:
    array = np.ascontiguousarray(array)
    if array.flags.writeable:
        array = array.copy()
        array.flags.writeable = False
    return array


def run_batch(
    ipar: npt.ArrayLike,
    rpar: npt.ArrayLike,
    y0: npt.ArrayLike,
    t_settle: npt.ArrayLike,
    t_end: npt.ArrayLike,
    max_step: npt.ArrayLike,
    rtol: float,
    atol: npt.ArrayLike,
    max_steps: int,
    method: str,
    *,
    parallel: bool = True,
    interrupt: npt.NDArray[np.uint8] | None = None,
) -> BatchKernelOutput:
    """Integrate every lane; peaks and statistics per lane (module docstring).

    Args:
        ipar: (I,) int64, the integer structure shared by every lane (:func:`eom.pack`).
        rpar: (n, R) float64, each lane's model floats.
        y0: (n, S) initial states.
        t_settle, t_end: (n,) window of the peaks and statistics, s (0 <= t_settle < t_end).
        max_step: (n,) largest step, s.
        rtol: relative tolerance; atol: (S,) absolute tolerances.
        max_steps: most accepted steps per lane.
        method: ``"explicit"`` (Dormand–Prince 5(4)) or ``"implicit"`` (Radau IIA).
        parallel: threads over lanes (``numba.prange``); ``False``: one thread.
        interrupt: uint8 flags that stop every lane with ``STATUS_INTERRUPTED`` once they hold
            SIGINT or SIGTERM (:func:`jointplay._kernels.lanes.source.interrupt_pending`).

    Returns:
        :class:`BatchKernelOutput`; a lane that did not succeed has NaN peaks and statistics.
    """
    if method not in METHODS:
        raise ValueError(f"method must be one of {METHODS}, got {method!r}")
    ipar_a = _read_only_copy(np.asarray(ipar, dtype=np.int64))
    rpar_a = _read_only_copy(np.atleast_2d(np.asarray(rpar, dtype=np.float64)))
    nb, nj, _, size = layout(ipar_a)
    y0_a, settle_a, end_a, step_a, atol_a = lane_inputs(
        y0, t_settle, t_end, max_step, atol, rpar_a, size, ValueError
    )
    lanes = y0_a.shape[0]
    nq_model = 2 * nb + nj + 1
    lay = lane_build.running_layout(ipar_a, rpar_a)
    n_peaks, n_stats = lane_build.output_widths(lay, rpar_a)
    peaks, stats, status, t_reached, counts = lane_outputs(lanes, n_peaks, n_stats)
    flags = NO_INTERRUPT if interrupt is None else interrupt
    if lanes:  # the running reductions (n_peaks > nq_model): their own compilation of the lane
        lane_cpu.DRIVERS[method][n_peaks > nq_model, parallel](
            ipar_a, rpar_a, lay, y0_a, settle_a, end_a, step_a,
            float(rtol), atol_a, int(max_steps), flags,
            peaks, stats, status, t_reached, counts,
        )  # fmt: skip
    return finished(peaks, stats, status, t_reached, counts)
