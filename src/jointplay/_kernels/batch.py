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
  :func:`jointplay._kernels.eom.quantities` defines them;
- ``stats`` (M = 2 nb + nc), STATS ORDER: time-mean of ω_b, RMS of ω_b (trapezoidal rule over
  the accepted steps, rad/s), largest penetration δ = |e| − c of every clearance joint at the
  accepted steps (m; negative: never touched);
- ``status`` (:mod:`jointplay._kernels.common` ``STATUS_*``), ``t_reached``, ``n_steps``,
  ``n_rejected``, ``n_rhs`` (right-hand-side evaluations; the quantity evaluations of the
  peak search are not counted).

**"explicit"** — Dormand–Prince 5(4) (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.5,
Table 5.2: the DOPRI5 tableau, FSAL), propagating the 5th-order solution:

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
  (:func:`~jointplay._kernels.eom.rhs_and_quantities`);
- after the error test, the contact-onset check of the Radau kernel's ``step_check``, on those
  records (:func:`~jointplay._kernels.eom.onset_check_recorded`), may retry the step shorter
  (``MAX_CHECK_REJECTIONS``); each retry counts as a rejection but does not cap the next
  step's growth;
- after acceptance, the Radau kernel's ``after_step`` (contact memory v0 from the records,
  then the projection onto the ideal constraints); f, the records and the quantities are
  evaluated again only if it changed the state (FSAL otherwise); a non-finite state or f ends
  the lane with ``STATUS_NON_FINITE``.

**"implicit"** — the Radau IIA kernel of :mod:`jointplay._kernels.radau`, one lane at a time,
with exactly the settings of :func:`jointplay.dynamics.simulate.simulate`; its accepted steps
are then reduced by :func:`_trajectory_reduce` (compiled), the interpolant being the cubic
Hermite one of the single engine (q with q̇, q̇ with q̈).

**Peak rule** (both methods; the JAX backend applies the same one). Let ``Q_a``, ``Q_b`` be the
quantities at the two ends of an accepted step inside the window (``Q_b`` after
``after_step``), ``peak`` the running largest |value| including ``|Q_b|``. The step is
*refined* when, for any quantity p that may trigger (every quantity except ω and α of the
driven body and of bodies held by an ideal prismatic joint to the ground),
``max(|Q_a,p|, |Q_b,p|) >= (1 − REFINE_MARGIN)·peak_p > 0``. A refined step evaluates the
method's interpolant at the seven ``REFINE_POINTS`` θ = 1/8, 2/8, …, 7/8 (DOPRI5: SciPy's
free 4th-order dense output ``P`` below; Radau: cubic Hermite), the quantities at those
states, and for every quantity takes ``s_0..s_8 = |Q|`` at θ = 0, 1/8, …, 7/8, 1: with ``m``
the first index of the largest, ``0 < m < 8`` and ``c = s_{m−1} − 2 s_m + s_{m+1} < 0``, the
vertex of the parabola through the three points, ``s_m − (s_{m−1} − s_{m+1})² / (8 c)``
(offset clipped to ±1/2 spacing), else ``s_m``; the peak becomes the larger of that and the running peak. The first step of
the window (whose start sets the peaks) is therefore always refined.

Lanes are independent: the kernel's result for a lane does not depend on the other lanes,
on the chunk it runs in, or on the thread that runs it.
"""

from __future__ import annotations

import math
from typing import Any, NamedTuple, TypeVar

import numba
import numpy as np
import numpy.typing as npt

from jointplay._kernels import eom
from jointplay._kernels.common import (
    STATUS_INTERRUPTED,
    STATUS_NON_FINITE,
    STATUS_RUNNING,
    STATUS_STEP_TOO_SMALL,
    STATUS_SUCCESS,
    STATUS_TOO_MANY_STEPS,
    all_finite,
    interrupt_pending,
)
from jointplay._kernels.lanes import build as lane_build
from jointplay._kernels.lanes import cpu as lane_cpu
from jointplay._kernels.radau import MAX_CHECK_REJECTIONS, radau_integrate

__all__ = [
    "METHODS",
    "REFINE_MARGIN",
    "BatchKernelOutput",
    "layout",
    "run_batch",
    "run_chunk",
]

#: Integration methods of :func:`run_batch`.
METHODS = ("explicit", "implicit")

#: Relative margin below the running peak at which a step is refined (module docstring).
REFINE_MARGIN = 0.01
#: Interior points of a refined step, as fractions of the step.
REFINE_POINTS = np.arange(1, 8) / 8.0

# --- DOPRI5 (Hairer, Nørsett & Wanner, Solving ODEs I, Table II.5.2) -------------------------
C2, C3, C4, C5 = 1.0 / 5.0, 3.0 / 10.0, 4.0 / 5.0, 8.0 / 9.0
A21 = 1.0 / 5.0
A31, A32 = 3.0 / 40.0, 9.0 / 40.0
A41, A42, A43 = 44.0 / 45.0, -56.0 / 15.0, 32.0 / 9.0
A51, A52, A53, A54 = 19372.0 / 6561.0, -25360.0 / 2187.0, 64448.0 / 6561.0, -212.0 / 729.0
A61, A62, A63, A64, A65 = (
    9017.0 / 3168.0, -355.0 / 33.0, 46732.0 / 5247.0, 49.0 / 176.0, -5103.0 / 18656.0,
)  # fmt: skip
#: 5th-order weights (b2 = b7 = 0).
B1, B3, B4, B5, B6 = 35.0 / 384.0, 500.0 / 1113.0, 125.0 / 192.0, -2187.0 / 6784.0, 11.0 / 84.0
#: Error weights E = b − b̂ (e2 = 0).
E1, E3, E4, E5, E6, E7 = (
    71.0 / 57600.0, -71.0 / 16695.0, 71.0 / 1920.0, -17253.0 / 339200.0, 22.0 / 525.0,
    -1.0 / 40.0,
)  # fmt: skip
#: Dense output (SciPy's ``RK45.P``, 7 × 4): y(t + θh) = y + h Σ_j k_j Σ_m P[j, m] θ^(m+1).
DENSE = np.array(
    [
        [1.0, -8048581381.0 / 2820520608.0, 8663915743.0 / 2820520608.0,
         -12715105075.0 / 11282082432.0],
        [0.0, 0.0, 0.0, 0.0],
        [0.0, 131558114200.0 / 32700410799.0, -68118460800.0 / 10900136933.0,
         87487479700.0 / 32700410799.0],
        [0.0, -1754552775.0 / 470086768.0, 14199869525.0 / 1410260304.0,
         -10690763975.0 / 1880347072.0],
        [0.0, 127303824393.0 / 49829197408.0, -318862633887.0 / 49829197408.0,
         701980252875.0 / 199316789632.0],
        [0.0, -282668133.0 / 205662961.0, 2019193451.0 / 616988883.0,
         -1453857185.0 / 822651844.0],
        [0.0, 40617522.0 / 29380423.0, -110615467.0 / 29380423.0, 69997945.0 / 29380423.0],
    ]
)  # fmt: skip

SAFETY, MIN_FACTOR, MAX_FACTOR = 0.9, 0.2, 10.0

# counters per lane
K_STEPS, K_REJECTED, K_RHS = 0, 1, 2

jit = numba.njit(cache=True, error_model="numpy")


class BatchKernelOutput(NamedTuple):
    """What :func:`run_batch` returns, per lane (module docstring for the orders and units)."""

    peaks: npt.NDArray[np.float64]
    stats: npt.NDArray[np.float64]
    status: npt.NDArray[np.int64]
    t_reached: npt.NDArray[np.float64]
    n_steps: npt.NDArray[np.int64]
    n_rejected: npt.NDArray[np.int64]
    n_rhs: npt.NDArray[np.int64]


def layout(ipar: npt.NDArray[np.int64]) -> tuple[int, int, int, int]:
    """``(nb, nj, nc, n_state)`` of the model packed in ``ipar``."""
    n = int(ipar[eom.L_MASS])
    nj = int(ipar[eom.L_ACTIVE])
    nc = int(ipar[eom.L_CLEAR_JOINT])
    return n // 3, nj, nc, 2 * n + 2 + nc


# --- pieces shared by both methods -----------------------------------------------------------
@jit
def _triggers(model: eom.EomModel) -> np.ndarray:
    """Which quantities may trigger a refinement (module docstring): all but ω and α of the
    driven body and of bodies held by an ideal prismatic joint to the ground."""
    nb = model.mass.shape[0] // 3
    nj = model.active.shape[0]
    mask = np.ones(2 * nb + nj + 1, dtype=np.bool_)
    crank = int(model.driver[0])
    for b in range(nb):
        fixed = b == crank
        for j in range(nj):
            if (
                model.active[j] == 1
                and model.joint_int[3 * j] == 1  # prismatic
                and model.joint_int[3 * j + 1] < 0
                and model.joint_int[3 * j + 2] == b
            ):
                fixed = True
        if fixed:
            mask[b] = False
            mask[nb + b] = False
    return mask


@jit
def _wants_refinement(qa: np.ndarray, qb: np.ndarray, peaks: np.ndarray, mask: np.ndarray) -> bool:
    for p in range(peaks.shape[0]):
        if not mask[p]:
            continue
        high = max(abs(qa[p]), abs(qb[p]))
        if peaks[p] > 0.0 and high >= (1.0 - REFINE_MARGIN) * peaks[p]:
            return True
    return False


@jit
def _refine_peaks(samples: np.ndarray, peaks: np.ndarray) -> None:
    """Raise ``peaks`` to the parabolic vertex through the largest of the samples of |Q| at
    θ = 0, REFINE_POINTS, 1 (rows of ``samples``) and its two neighbours."""
    last = samples.shape[0] - 1
    for p in range(peaks.shape[0]):
        m = 0
        for i in range(1, last + 1):
            if abs(samples[i, p]) > abs(samples[m, p]):
                m = i
        best = abs(samples[m, p])
        if 0 < m < last:
            low, high = abs(samples[m - 1, p]), abs(samples[m + 1, p])
            curvature = low - 2.0 * best + high
            if curvature < 0.0:
                offset = 0.5 * (low - high) / curvature
                offset = min(max(offset, -0.5), 0.5)
                best = best - 0.25 * (low - high) * offset
        if best > peaks[p]:
            peaks[p] = best


@jit
def _open_window(
    q: np.ndarray, pen: np.ndarray, peaks: np.ndarray, stats: np.ndarray, nb: int
) -> None:
    """Start the window's running values from its first point."""
    for p in range(peaks.shape[0]):
        peaks[p] = abs(q[p])
    for k in range(2 * nb):
        stats[k] = 0.0
    for c in range(pen.shape[0]):
        stats[2 * nb + c] = pen[c]


@jit
def _accumulate(
    qa: np.ndarray, qb: np.ndarray, pen: np.ndarray, h: float, peaks: np.ndarray,
    stats: np.ndarray, nb: int,
) -> None:  # fmt: skip
    """Add one step to the trapezoidal sums, the penetrations and the end-point peaks."""
    for b in range(nb):
        stats[b] += 0.5 * h * (qa[b] + qb[b])
        stats[nb + b] += 0.5 * h * (qa[b] * qa[b] + qb[b] * qb[b])
    for c in range(pen.shape[0]):
        if pen[c] > stats[2 * nb + c]:
            stats[2 * nb + c] = pen[c]
    for p in range(peaks.shape[0]):
        if abs(qb[p]) > peaks[p]:
            peaks[p] = abs(qb[p])


@jit
def _close_window(stats: np.ndarray, nb: int, span: float) -> None:
    """Turn the trapezoidal sums into the mean and the RMS."""
    for b in range(nb):
        stats[b] /= span
        stats[nb + b] = math.sqrt(max(stats[nb + b] / span, 0.0))


# --- explicit: Dormand–Prince 5(4) ---------------------------------------------------------------
@jit
def _dense(y: np.ndarray, k: np.ndarray, h: float, theta: float, out: np.ndarray) -> None:
    """DOPRI5's free interpolant at t + θh (SciPy's RK45 dense output)."""
    t1 = theta
    t2 = theta * theta
    t3 = t2 * theta
    t4 = t3 * theta
    for i in range(y.shape[0]):
        s = 0.0
        for j in range(7):
            w = DENSE[j, 0] * t1 + DENSE[j, 1] * t2 + DENSE[j, 2] * t3 + DENSE[j, 3] * t4
            s += k[j, i] * w
        out[i] = y[i] + h * s


@jit
def _explicit_lane(
    ipar, rpar, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, counts,
):  # fmt: skip
    """One lane of the explicit method; fills ``peaks``, ``stats``, ``counts``.

    Returns:
        ``(status, t_reached)``.
    """
    model = eom.unpack(rpar, ipar)
    n = model.mass.shape[0]
    nb = n // 3
    n_active = 2 * n
    size = y0.shape[0]
    work = np.zeros(eom.N_WORK)
    mask = _triggers(model)
    n_q = peaks.shape[0]
    qa = np.empty(n_q)
    qb = np.empty(n_q)
    n_points = len(REFINE_POINTS)
    samples = np.empty((n_points + 2, n_q))
    pen = np.empty(model.clear_joint.shape[0])
    record = np.empty(7 * model.clear_joint.shape[0])  # the joints' contact records at y
    record_new = np.empty(7 * model.clear_joint.shape[0])  # and at y_new
    lam = np.zeros(eom.count_rows(model.active, model.driver))
    k = np.empty((7, size))
    ys = np.empty(size)
    y_new = np.empty(size)
    y_mid = np.empty(size)
    for p in range(n_q):
        peaks[p] = np.nan
    for m in range(stats.shape[0]):
        stats[m] = np.nan
    counts[:] = 0

    t = 0.0
    y = y0.copy()
    f = np.empty(size)
    eom.rhs_and_quantities(t, y, model, f, record, lam, qa, pen)
    counts[K_RHS] += 1
    if not (all_finite(y) and all_finite(f)):
        return STATUS_NON_FINITE, t
    in_window = t_settle <= 0.0
    if in_window:
        _open_window(qa, pen, peaks, stats, nb)
    h = max_step / 10.0
    status = STATUS_RUNNING
    while status == STATUS_RUNNING:
        if t >= t_end:
            status = STATUS_SUCCESS
            break
        if counts[K_STEPS] >= max_steps:
            status = STATUS_TOO_MANY_STEPS
            break
        if interrupt_pending(interrupt):
            status = STATUS_INTERRUPTED
            break
        target = t_settle if t < t_settle else t_end
        min_step = 10.0 * abs(np.nextafter(t, np.inf) - t)
        h = min(h, max_step)
        had_rejection = False
        n_check = 0
        err = 0.0
        t_new = t
        while True:
            if h < min_step:
                status = STATUS_STEP_TOO_SMALL
                break
            t_new = t + h
            if t_new >= target:
                t_new = target
                h = target - t
            for i in range(size):
                k[0, i] = f[i]
            for i in range(size):
                ys[i] = y[i] + h * (A21 * k[0, i])
            eom.rhs_into(t + C2 * h, ys, model, k[1])
            for i in range(size):
                ys[i] = y[i] + h * (A31 * k[0, i] + A32 * k[1, i])
            eom.rhs_into(t + C3 * h, ys, model, k[2])
            for i in range(size):
                ys[i] = y[i] + h * (A41 * k[0, i] + A42 * k[1, i] + A43 * k[2, i])
            eom.rhs_into(t + C4 * h, ys, model, k[3])
            for i in range(size):
                ys[i] = y[i] + h * (A51 * k[0, i] + A52 * k[1, i] + A53 * k[2, i] + A54 * k[3, i])
            eom.rhs_into(t + C5 * h, ys, model, k[4])
            for i in range(size):
                ys[i] = y[i] + h * (
                    A61 * k[0, i] + A62 * k[1, i] + A63 * k[2, i] + A64 * k[3, i]
                    + A65 * k[4, i]
                )  # fmt: skip
            eom.rhs_into(t + h, ys, model, k[5])
            for i in range(size):
                y_new[i] = y[i] + h * (
                    B1 * k[0, i] + B3 * k[2, i] + B4 * k[3, i] + B5 * k[4, i] + B6 * k[5, i]
                )
            # the last stage also gives the contact records and the quantities at the step's end
            eom.rhs_and_quantities(t_new, y_new, model, k[6], record_new, lam, qb, pen)
            counts[K_RHS] += 6
            total = 0.0
            for i in range(n_active):
                e = h * (
                    E1 * k[0, i] + E3 * k[2, i] + E4 * k[3, i] + E5 * k[4, i] + E6 * k[5, i]
                    + E7 * k[6, i]
                )  # fmt: skip
                scale = atol[i] + rtol * max(abs(y[i]), abs(y_new[i]))
                total += (e / scale) ** 2
            err = math.sqrt(total / n_active)
            if err > 1.0:
                h *= max(MIN_FACTOR, SAFETY * err**-0.2)
                had_rejection = True
                counts[K_REJECTED] += 1
                continue
            theta = eom.onset_check_recorded(record, record_new, model)
            h_try = h * theta
            if theta < 1.0 and min_step <= h_try < h and n_check < MAX_CHECK_REJECTIONS:
                h = h_try
                n_check += 1
                counts[K_REJECTED] += 1
                continue
            break
        if status != STATUS_RUNNING:
            break
        factor = MAX_FACTOR if err == 0.0 else min(MAX_FACTOR, max(MIN_FACTOR, SAFETY * err**-0.2))
        if had_rejection:
            factor = min(factor, 1.0)
        changed = eom.contact_memory(y_new, model, record_new, record)
        changed = eom.project(t_new, y_new, model, work) or changed
        if changed:
            eom.rhs_and_quantities(t_new, y_new, model, f, record, lam, qb, pen)
            counts[K_RHS] += 1
        else:
            f[:] = k[6]
            record, record_new = record_new, record  # the end's records become the start's
        if not (all_finite(y_new) and all_finite(f)):
            status = STATUS_NON_FINITE
            break
        if in_window:
            _accumulate(qa, qb, pen, h, peaks, stats, nb)
            if _wants_refinement(qa, qb, peaks, mask):
                samples[0] = qa
                samples[n_points + 1] = qb
                for r in range(n_points):
                    _dense(y, k, h, REFINE_POINTS[r], y_mid)
                    eom.quantities(t + REFINE_POINTS[r] * h, y_mid, model, samples[r + 1], pen)
                _refine_peaks(samples, peaks)
            qa, qb = qb, qa
        elif t_new == t_settle:
            in_window = True
            qa[:] = qb
            _open_window(qa, pen, peaks, stats, nb)
        t = t_new
        y, y_new = y_new, y
        counts[K_STEPS] += 1
        h = h * factor
    if status == STATUS_SUCCESS:
        _close_window(stats, nb, t_end - t_settle)
    return status, t


@jit
def _explicit_serial(
    ipar, rpar, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, status, t_reached, counts,
):  # fmt: skip
    for lane in range(y0.shape[0]):
        code, t = _explicit_lane(
            ipar, rpar[lane], y0[lane], t_settle[lane], t_end[lane], max_step[lane], rtol,
            atol, max_steps, interrupt, peaks[lane], stats[lane], counts[lane],
        )  # fmt: skip
        status[lane] = code
        t_reached[lane] = t


@numba.njit(cache=True, error_model="numpy", parallel=True)
def _explicit_parallel(
    ipar, rpar, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt,
    peaks, stats, status, t_reached, counts,
):  # fmt: skip
    for lane in numba.prange(y0.shape[0]):
        code, t = _explicit_lane(
            ipar, rpar[lane], y0[lane], t_settle[lane], t_end[lane], max_step[lane], rtol,
            atol, max_steps, interrupt, peaks[lane], stats[lane], counts[lane],
        )  # fmt: skip
        status[lane] = code
        t_reached[lane] = t


# --- implicit: Radau IIA per lane, then a compiled reduction of its steps -------------------------
@jit
def _hermite(
    t0: float, y0: np.ndarray, a0: np.ndarray, t1: float, y1: np.ndarray, a1: np.ndarray,
    n: int, tau: float, out: np.ndarray,
) -> None:  # fmt: skip
    """The single engine's interpolant (:func:`jointplay.dynamics.simulate._interpolate`):
    cubic Hermite on q (with q̇) and on q̇ (with q̈); the other components linear, except the
    impact memory, held at the step's start."""
    h = t1 - t0
    s = (tau - t0) / h
    h00 = 2 * s**3 - 3 * s**2 + 1
    h10 = s**3 - 2 * s**2 + s
    h01 = -2 * s**3 + 3 * s**2
    h11 = s**3 - s**2
    for i in range(n):
        out[i] = h00 * y0[i] + h10 * h * y0[n + i] + h01 * y1[i] + h11 * h * y1[n + i]
        out[n + i] = h00 * y0[n + i] + h10 * h * a0[i] + h01 * y1[n + i] + h11 * h * a1[i]
    for i in range(2 * n, 2 * n + 2):
        out[i] = (1 - s) * y0[i] + s * y1[i]
    for i in range(2 * n + 2, y0.shape[0]):
        out[i] = y0[i]


@jit
def _trajectory_reduce(ipar, rpar, ts, ys, t_settle, t_end, peaks, stats):
    """Peaks and statistics over [t_settle, t_end] of a recorded trajectory (Radau's steps).

    The window opens at ``t_settle`` (interpolated inside its step when it falls there);
    every later step is reduced with the peak rule of the module docstring, the cubic Hermite
    interpolant standing in for the method's dense output.
    """
    model = eom.unpack(rpar, ipar)
    n = model.mass.shape[0]
    nb = n // 3
    n_q = peaks.shape[0]
    mask = _triggers(model)
    qa = np.empty(n_q)
    qb = np.empty(n_q)
    n_points = len(REFINE_POINTS)
    samples = np.empty((n_points + 2, n_q))
    pen = np.empty(model.clear_joint.shape[0])
    y_mid = np.empty(ys.shape[1])
    m = ts.shape[0]
    acc = np.empty((m, n))
    for i in range(m):
        acc[i] = eom.quantities(ts[i], ys[i], model, qb, pen)
    first = 0
    while first < m - 1 and ts[first + 1] <= t_settle:
        first += 1
    t_a = ts[first]
    y_a = ys[first].copy()
    if t_a < t_settle and first < m - 1:  # the window opens inside this step
        _hermite(ts[first], ys[first], acc[first], ts[first + 1], ys[first + 1], acc[first + 1],
                 n, t_settle, y_a)  # fmt: skip
        t_a = t_settle
    a_a = eom.quantities(t_a, y_a, model, qa, pen)
    _open_window(qa, pen, peaks, stats, nb)
    for i in range(first + 1, m):
        t_b = ts[i]
        y_b = ys[i]
        eom.quantities(t_b, y_b, model, qb, pen)
        _accumulate(qa, qb, pen, t_b - t_a, peaks, stats, nb)
        if _wants_refinement(qa, qb, peaks, mask):
            h = t_b - t_a
            samples[0] = qa
            samples[n_points + 1] = qb
            for r in range(n_points):
                tau = t_a + REFINE_POINTS[r] * h
                _hermite(t_a, y_a, a_a, t_b, y_b, acc[i], n, tau, y_mid)
                eom.quantities(tau, y_mid, model, samples[r + 1], pen)
            _refine_peaks(samples, peaks)
        qa, qb = qb, qa
        t_a = t_b
        y_a = ys[i].copy()
        a_a = acc[i].copy()
    _close_window(stats, nb, t_end - t_settle)


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
    for lane in lanes:
        code = _implicit_lane(
            ipar, rpar, y0, t_settle, t_end, max_step, rtol, atol, max_steps, interrupt, out, lane
        )
        if code == STATUS_INTERRUPTED:
            return


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
        eom.rhs,
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
            ipar, rpar[lane], ts, ys, t_settle[lane], t_end[lane], peaks[lane], stats[lane]
        )
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


def _readonly(array: npt.NDArray[_Scalar]) -> npt.NDArray[_Scalar]:
    array = np.ascontiguousarray(array)
    if array.flags.writeable:
        array = array.copy()
        array.flags.writeable = False
    return array


_NO_INTERRUPT = np.zeros(1, dtype=np.uint8)


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
    ipar_a = _readonly(np.asarray(ipar, dtype=np.int64))
    rpar_a = _readonly(np.atleast_2d(np.asarray(rpar, dtype=np.float64)))
    y0_a = np.ascontiguousarray(np.atleast_2d(np.asarray(y0, dtype=np.float64)))
    lanes = y0_a.shape[0]
    settle_a, end_a, step_a = (
        np.ascontiguousarray(np.broadcast_to(np.asarray(v, dtype=np.float64), (lanes,)))
        for v in (t_settle, t_end, max_step)
    )
    atol_a = np.ascontiguousarray(np.asarray(atol, dtype=np.float64))
    nb, nj, nc, size = layout(ipar_a)
    if y0_a.shape[1] != size or atol_a.shape != (size,) or rpar_a.shape[0] != lanes:
        raise ValueError(
            f"run_batch: y0 must be (n, {size}) and atol ({size},), rpar (n, R); got y0 "
            f"{y0_a.shape}, atol {atol_a.shape}, rpar {rpar_a.shape}"
        )
    peaks = np.full((lanes, 2 * nb + nj + 1), np.nan)
    stats = np.full((lanes, 2 * nb + nc), np.nan)
    status = np.full(lanes, STATUS_RUNNING, dtype=np.int64)
    t_reached = np.zeros(lanes)
    counts = np.zeros((lanes, 3), dtype=np.int64)
    flags = _NO_INTERRUPT if interrupt is None else interrupt
    if lanes:
        if method == "explicit":  # the lane of the single source (jointplay._kernels.lanes)
            lanes_kernel: Any = (
                lane_cpu.explicit_lanes_parallel if parallel else lane_cpu.explicit_lanes
            )
            lanes_kernel(
                ipar_a, rpar_a, lane_build.lane_layout(ipar_a), y0_a, settle_a, end_a, step_a,
                float(rtol), atol_a, int(max_steps), flags,
                peaks, stats, status, t_reached, counts,
            )  # fmt: skip
        elif method == "explicit":
            kernel: Any = _explicit_parallel if parallel else _explicit_serial
            kernel(
                ipar_a, rpar_a, y0_a, settle_a, end_a, step_a, float(rtol), atol_a,
                int(max_steps), flags,
                peaks, stats, status, t_reached, counts,
            )  # fmt: skip
        else:
            _implicit_lanes(
                ipar_a, rpar_a, y0_a, settle_a, end_a, step_a, float(rtol), atol_a,
                int(max_steps), flags,
                (peaks, stats, status, t_reached, counts),
                threads=numba.get_num_threads() if parallel else 1,
            )  # fmt: skip
    failed = status != STATUS_SUCCESS
    peaks[failed] = np.nan
    stats[failed] = np.nan
    return BatchKernelOutput(
        peaks=peaks,
        stats=stats,
        status=status,
        t_reached=t_reached,
        n_steps=counts[:, K_STEPS].copy(),
        n_rejected=counts[:, K_REJECTED].copy(),
        n_rhs=counts[:, K_RHS].copy(),
    )
