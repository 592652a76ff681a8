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
  :func:`jointplay._kernels.eom.batch_quantities` defines them;
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
- ``status`` (:mod:`jointplay._kernels.common` ``STATUS_*``), ``t_reached``, ``n_steps``,
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
- after the error test, the contact-onset check of the Radau kernel's ``step_check``, on those
  records (the lane source's ``onset_check``), may retry the step shorter
  (``MAX_CHECK_REJECTIONS``); each retry counts as a rejection but does not cap the next
  step's growth;
- after acceptance, the Radau kernel's ``after_step`` (contact memory v0 from the records,
  then the projection onto the ideal constraints); f, the records and the quantities are
  evaluated again only if it changed the state (FSAL otherwise); a non-finite state or f ends
  the lane with ``STATUS_NON_FINITE``.

**"implicit"** — the lanes' loop with Radau IIA's steps
(:mod:`jointplay._kernels.lanes.source_radau`, compiled by :mod:`jointplay._kernels.lanes.cpu`:
``IMPLICIT_DRIVERS``), which takes the single engine's steps with exactly the settings of
:func:`jointplay.dynamics.simulate.simulate` and reduces each accepted step as it is taken
(the same bits as the path below, measured). With the sustained-contact mode (the lanes'
loop does not run it): the Radau IIA kernel of :mod:`jointplay._kernels.radau`, one lane at
a time; its accepted steps then reduced by :func:`_trajectory_reduce` (compiled), the
interpolant being the single engine's (:data:`lanes_hermite`: cubic Hermite of q with q̇ and of q̇ with q̈; with film damping
the quintic through q and q̇ at three step ends, or next to a contact's start or end q̇ the
derivative of q's cubic).

**Peak rule** (both methods; the JAX backend applies the same one). Let ``Q_a``, ``Q_b`` be the
quantities at the two ends of an accepted step inside the window (``Q_b`` after
``after_step``), ``peak`` the running largest |value| including ``|Q_b|``. The step is
*refined* when, for any quantity p that may trigger (every quantity except ω and α of the
driven body and of bodies held by an ideal prismatic joint to the ground),
``max(|Q_a,p|, |Q_b,p|) >= (1 − REFINE_MARGIN)·peak_p > 0``. A refined step evaluates the
method's interpolant at the seven ``REFINE_POINTS`` θ = 1/8, 2/8, …, 7/8 (DOPRI5: SciPy's
free 4th-order dense output ``P`` below; Radau: :data:`lanes_hermite`), the quantities at those
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

import numba
import numpy as np
import numpy.typing as npt

from jointplay._kernels import eom
from jointplay._kernels.common import (
    interrupt_pending,
)
from jointplay._kernels.ids import (
    G_CAPTURE,
    K_REJECTED,
    K_RHS,
    K_STEPS,
    N_GEOM,
    STATUS_INTERRUPTED,
    STATUS_SUCCESS,
)
from jointplay._kernels.integrators import lane_methods
from jointplay._kernels.lanes import build as lane_build
from jointplay._kernels.lanes import cpu as lane_cpu
from jointplay._kernels.lanes.contract import (  # noqa: F401 (re-exported: the peak rule's)
    DENSE,
    REFINE_MARGIN,
    REFINE_POINTS,
    BatchKernelOutput,
    finished,
    lane_inputs,
    lane_outputs,
)
from jointplay._kernels.lanes.source import LY_GEOM, LY_NC
from jointplay._kernels.radau import radau_integrate

# the peak rule's pieces, compiled from the lane source (shared with the explicit lanes)
lanes_triggers = lane_cpu.compiled["triggers"]
lanes_any_film = lane_cpu.compiled["any_film"]
lanes_wants_refinement = lane_cpu.compiled["wants_refinement"]
lanes_refine_peaks = lane_cpu.compiled["refine_peaks"]
lanes_refine_start = lane_cpu.compiled["refine_start"]
lanes_open_window = lane_cpu.compiled["open_window"]
lanes_accumulate = lane_cpu.compiled["accumulate"]
lanes_close_window = lane_cpu.compiled["close_window"]
lanes_open_regimes = lane_cpu.compiled["open_regimes"]
lanes_accumulate_regimes = lane_cpu.compiled["accumulate_regimes"]
lanes_close_regimes = lane_cpu.compiled["close_regimes"]
lanes_running_on = lane_cpu.compiled["running_on"]
lanes_speed_deviation = lane_cpu.compiled["speed_deviation"]
lanes_running_point = lane_cpu.compiled["running_point"]
lanes_start_running = lane_cpu.compiled["start_running"]
lanes_close_running = lane_cpu.compiled["close_running"]

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


jit = numba.njit(cache=True, error_model="numpy")


def layout(ipar: npt.NDArray[np.int64]) -> tuple[int, int, int, int]:
    """``(nb, nj, nc, n_state)`` of the model packed in ``ipar``."""
    n = int(ipar[eom.L_MASS])
    nj = int(ipar[eom.L_ACTIVE])
    nc = int(ipar[eom.L_CLEAR_JOINT])
    return n // 3, nj, nc, 2 * n + 2 + nc


# --- implicit: Radau IIA per lane, then a compiled reduction of its steps -------------------------
#: The single engine's interpolant between steps (``simulate._interpolate``), from the lane
#: source (:func:`jointplay._kernels.lanes.source_radau.hermite`, its rules ``RULE_*``).
lanes_hermite = lane_cpu.compiled["hermite"]
lanes_touching = lane_cpu.compiled["touching"]
lanes_interpolation_rule = lane_cpu.compiled["interpolation_rule"]


@jit
def _step_state(film, ts, ys, fs, bits, i, tau, n, out):  # fmt: skip
    """The interpolated state at ``tau`` inside the recorded step ``i − 1`` → ``i`` (``fs``:
    q̈ at the steps in ``[n:2n]``), by the rule that step takes (``interpolation_rule``)."""
    before = max(i - 2, 0)
    rule = lanes_interpolation_rule(film, i >= 2, bits[before], bits[i - 1], bits[i])
    lanes_hermite(ts[before], ys[before], ts[i - 1], ys[i - 1], fs[i - 1], ts[i], ys[i], fs[i],
                  n, ys.shape[1], tau, out, rule)  # fmt: skip


@jit
def _trajectory_reduce(ipar, rpar, lay, ts, ys, t_settle, t_end, peaks, stats):
    """Peaks and statistics over [t_settle, t_end] of a recorded trajectory (Radau's steps).

    The window opens at ``t_settle`` (interpolated inside its step when it falls there);
    every later step is reduced with the peak rule of the module docstring, the single
    engine's interpolant (:data:`lanes_hermite`) standing in for the method's dense output,
    always on the recorded step (the window's first too). With the running responses
    (``lay``'s one more quantity: ``running_on``) the output speed's deviation joins the
    quantities and every recorded step from ``t_settle`` on the wear profiles.
    """
    model = eom.unpack(rpar, ipar)
    n = model.mass.shape[0]
    nb = n // 3
    nc = model.clear_joint.shape[0]
    n_q = peaks.shape[0]
    mask = np.empty(n_q, dtype=np.int64)
    lanes_triggers(ipar, rpar, lay, mask)
    qa = np.empty(n_q)
    qb = np.empty(n_q)
    n_points = len(REFINE_POINTS)
    samples = np.empty((n_points + 2, n_q))
    pen = np.empty(model.clear_joint.shape[0])
    y_mid = np.empty(ys.shape[1])
    film = lanes_any_film(rpar, lay)
    running = lanes_running_on(lay)
    m = ts.shape[0]
    fs = np.zeros((m, ys.shape[1]))  # q̈ in [n:2n], as the lane source's interpolant takes it
    bits = np.empty(m, dtype=np.int64)
    for i in range(m):
        fs[i, n : 2 * n] = eom.batch_quantities(ts[i], ys[i], rpar, ipar, qb, pen)
        bits[i] = lanes_touching(pen, nc)
    first = 0
    while first < m - 1 and ts[first + 1] <= t_settle:
        first += 1
    t_a = ts[first]
    y_a = ys[first].copy()
    if t_a < t_settle and first < m - 1:  # the window opens inside this step
        _step_state(film, ts, ys, fs, bits, first + 1, t_settle, n, y_a)
        t_a = t_settle
    eom.batch_quantities(t_a, y_a, rpar, ipar, qa, pen)
    if running:
        lanes_speed_deviation(y_a, rpar, lay, qa)
        f_run = np.empty(ys.shape[1])
        record_run = np.empty(7 * max(nc, 1))
        lanes_start_running(rpar, lay, stats)
        for i in range(m):
            h = ts[i] - ts[i - 1] if i > 0 else 0.0
            lanes_running_point(ts[i], h, t_settle, ys[i], rpar, ipar, lay, f_run, record_run,
                                stats)  # fmt: skip
    lanes_open_window(qa, pen, peaks, stats, nb, n_q, nc)
    lanes_open_regimes(rpar, lay, pen, stats, nb, nc)
    for i in range(first + 1, m):
        t_b = ts[i]
        eom.batch_quantities(t_b, ys[i], rpar, ipar, qb, pen)
        if running:
            lanes_speed_deviation(ys[i], rpar, lay, qb)
        lanes_accumulate(qa, qb, pen, t_b - t_a, peaks, stats, nb, n_q, nc)
        lanes_accumulate_regimes(rpar, lay, pen, t_b - t_a, stats, nb, nc)
        every = lanes_wants_refinement(qa, qb, peaks, mask, n_q - 1 if running else n_q)
        if every or running:  # the deviation alone is refined on every step (its own rule)
            h = t_b - t_a
            start = lanes_refine_start(qa, qb, samples, every, n_q)
            for r in range(n_points):
                tau = t_a + REFINE_POINTS[r] * h
                _step_state(film, ts, ys, fs, bits, i, tau, n, y_mid)
                if every:
                    eom.batch_quantities(tau, y_mid, rpar, ipar, samples[r + 1], pen)
                if running:
                    lanes_speed_deviation(y_mid, rpar, lay, samples[r + 1])
            lanes_refine_peaks(samples, peaks, start, n_q)
        qa, qb = qb, qa
        t_a = t_b
    lanes_close_window(stats, nb, t_end - t_settle)
    lanes_close_regimes(stats, nb, nc, t_end - t_settle)
    if running:
        lanes_close_running(rpar, lay, stats, t_end - t_settle)


def _implicit_lanes(
    ipar, rpar, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt, out,
    threads=1,
):  # fmt: skip
    """Radau IIA per lane (:func:`jointplay._kernels.radau.radau_integrate`, the single
    engine's settings), each lane's steps reduced in compiled code; on ``threads`` threads
    (the compiled driver releases the GIL; each lane writes only its own rows)."""
    lanes = range(y0.shape[0])
    if threads > 1 and len(lanes) > 1:
        from concurrent.futures import ThreadPoolExecutor

        def one(lane: int) -> None:
            _implicit_lane(
                ipar, rpar, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
                out, lane,
            )  # fmt: skip

        with ThreadPoolExecutor(max_workers=min(threads, len(lanes))) as pool:
            list(pool.map(one, lanes))
        return
    for lane in lanes:  # after an interrupt each lane left ends at once, STATUS_INTERRUPTED
        _implicit_lane(
            ipar, rpar, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt, out, lane
        )


def _implicit_lane(
    ipar, rpar, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt, out, lane
):  # fmt: skip
    """Lane ``lane`` of :func:`_implicit_lanes`; returns its status."""
    peaks, stats, status, t_reached, counts = out
    n = int(ipar[eom.L_MASS])
    if interrupt_pending(interrupt):
        status[lane] = STATUS_INTERRUPTED
        return STATUS_INTERRUPTED
    args = (rpar[lane], ipar, eom.new_workspace(int(ipar[eom.L_CLEAR_JOINT])))
    eom.start_workspace(y0[lane], args)
    code, ts, ys, counters = radau_integrate(
        eom.state_rhs,
        eom.step_check,
        eom.after_step,
        0.0,
        y0[lane],
        float(t_end[lane]),
        args,
        rtol,
        atol,
        float(max_step[lane]),
        0.0,
        max_steps,
        n_second=n,
        n_active=2 * n,
        hold_after_failure=True,
        jac=eom.jacobian_state,
        interrupt=interrupt,
    )
    status[lane] = code
    t_reached[lane] = ts[-1]
    counts[lane, K_STEPS] = counters[3]
    counts[lane, K_REJECTED] = counters[4] + counters[5] + counters[6]
    counts[lane, K_RHS] = counters[0]
    if code == STATUS_SUCCESS:
        _trajectory_reduce(
            ipar, rpar[lane], lane_build.running_layout(ipar, rpar), ts, ys, t_settle[lane],
            t_end[lane],
            peaks[lane], stats[lane],
        )  # fmt: skip
    return code


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


_NO_INTERRUPT = np.zeros(1, dtype=np.uint8)


def _sustained(ipar: npt.NDArray[np.int64], rpar: npt.NDArray[np.float64]) -> bool:
    """Whether a lane has the sustained-contact mode (a joint's capture speed > 0), which the
    lanes' loop does not run (it changes the constraint set between steps)."""
    lay = lane_build.lane_layout(ipar)
    start = int(lay[LY_GEOM])
    geom = rpar[:, start : start + N_GEOM * int(lay[LY_NC])]
    return bool(np.any(geom[:, G_CAPTURE::N_GEOM] > 0.0))


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
        parallel: threads over lanes (explicit: ``numba.prange``; implicit: a thread pool
            of Numba's thread count, the compiled Radau driver releasing the GIL);
            ``False``: one thread.
        interrupt: uint8 flags that stop every lane with ``STATUS_INTERRUPTED`` once they hold
            SIGINT or SIGTERM (:func:`jointplay._kernels.common.interrupt_pending`).

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
    flags = _NO_INTERRUPT if interrupt is None else interrupt
    if lanes:
        if method == "explicit":  # the lane of the single source (jointplay._kernels.lanes)
            # the running reductions (n_peaks > nq_model): their own compilation of the lane
            lane_cpu.EXPLICIT_DRIVERS[n_peaks > nq_model, parallel](
                ipar_a, rpar_a, lay, y0_a, settle_a, end_a, step_a,
                float(rtol), atol_a, int(max_steps), flags,
                peaks, stats, status, t_reached, counts,
            )  # fmt: skip
        elif not _sustained(ipar_a, rpar_a):  # the lanes' loop with Radau's steps
            lane_cpu.IMPLICIT_DRIVERS[n_peaks > nq_model, parallel](
                ipar_a, rpar_a, lay, y0_a, settle_a, end_a, step_a,
                float(rtol), atol_a, int(max_steps), flags,
                peaks, stats, status, t_reached, counts,
            )  # fmt: skip
        else:  # the sustained-contact mode: the single engine's Radau IIA and hooks
            _implicit_lanes(
                ipar_a, rpar_a, y0_a, settle_a, end_a, step_a, float(rtol), atol_a,
                int(max_steps), flags,
                (peaks, stats, status, t_reached, counts),
                threads=numba.get_num_threads() if parallel else 1,
            )  # fmt: skip
    return finished(peaks, stats, status, t_reached, counts)
