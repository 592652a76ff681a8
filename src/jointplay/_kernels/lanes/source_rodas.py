"""RODAS4's steps in the lane (:func:`jointplay._kernels.lanes.source.lane`): the linearly
implicit method of the single engine, in the one loop.

RODAS4 of Hairer & Wanner [HW96]_ §IV.7 (the coefficients of Hairer's ``rodas.f``, its first
method): six stages, order 4 with an embedded order-3 solution, stiffly accurate and
L-stable. Per step: the Jacobian at the step's start (:func:`source_radau.lane_jacobian`,
the differences started afresh from their initial step at every call: a Rosenbrock method
needs the Jacobian itself, and adapted steps can grow across a kink of f), ∂f/∂t by one
forward difference (as ``rodas.f``; none without the driver's speed ramp, the only place t
enters), one LU of ``1/(γh)·I − J`` reduced to the velocities as Radau's Newton matrices
are, five evaluations of f and six solves; no Newton iteration, hence no Newton failure.
Why the simulator has it beside Radau IIA (issue 22; docs/performance.md, "From rest: a
Rosenbrock method for the paper's ECS sets"): on the paper's IFM ECS contact sets, whose
damping (25 and 2 423 N·s/mm) is full at a negligible penetration, Radau's simplified Newton
iteration, its Jacobian frozen at the step's start, fails on most steps (1 253 and 24 241
failures in a revolution from rest). Our reading: the damping force ``c δ̇ n`` of a pin
whirling round its bearing turns with the contact normal ``n``, and the frozen Jacobian's
error ``c·Δθ`` (``Δθ`` the normal's turn within the step) outgrows the Newton matrix's
inertia term ``m/(γh)`` at steps of ~1e-5 s. A Rosenbrock method linearises once per step
and lets its error estimate set the step: on those sets it takes as many steps as Radau or
fewer, at about half the cost each. Elsewhere Radau's higher order wins, and at the same
tolerance RODAS4's global error is larger. The step-control variants measured: five
variants of the bounds and the safety factor took 24 700–33 400 steps on the cylindrical
set; these took the fewest.

Step control as ``rodas.f`` with its predictive (Gustafsson) controller: the factor
``0.9·err^(−1/4)``, after an accepted step also at most
``0.9·(h/h_prev)·(err_prev/err²)^(1/4)``, within [1/5, 5]; a rejected step is retried with
that factor, with no growth right after a rejection (:func:`source.hold_after_failure`:
always for a mechanism, as ``rodas.f``; an option of :func:`jointplay.integrate`); a
non-finite stage is a rejection with ``h/5``. The error norm is taken over every component of
the state. ``after_step``'s discontinuity changes nothing: every step starts afresh.

This module is one integrator for every engine that compiles the lane source: its tableau
and its steps (``rodas_*``, the loop's contract), its record
:data:`LANE` (the integrator, the lane, the work allocator), found by
:data:`jointplay._kernels.lanes.SOURCES`: nothing else names it. Written in the lane source's
subset (no allocation but the CPU's work allocator; the tableau in tuples).

References:
    .. [HW96] E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II: Stiff and
       Differential-Algebraic Problems*, 2nd ed., Springer, 1996, §IV.7 (Table 7.2 and
       Hairer's ``rodas.f``, ``ROCOEF`` method 1).
"""

from __future__ import annotations

import math

import numpy as np  # the work allocator: the CPU's

# Names the build's namespace binds for every target (the shared ids and the other source
# modules' constants and functions); imported here only so that a reader can find them.
from jointplay._kernels.ids import EPS, K_JAC, K_LU, K_REJECTED, K_RHS
from jointplay._kernels.lanes.source import (
    LY_KEPT,
    LY_N,
    LY_SECOND,
    LY_SIZE,
    RECORD,
    contact_forces,
    hold_after_failure,
    initial_step,
    rhs,
    rhs_and_quantities,
    time_enters,
)
from jointplay._kernels.lanes.source_radau import (
    RULE_RATES,
    hermite,
    lane_jacobian,
    lu_real,
    newton_matrix,
    solve_real,
)

# --- the tableau: rodas.f, ROCOEF method 1 ([HW96] §IV.7, Table 7.2) -------------------------
RODAS_GAMMA = 0.25
#: a_si: stage s is evaluated at y + Σ_i A[s][i] k_i (stage 6 adds k_5 to stage 5's point).
RODAS_A = (
    (0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    (1.544, 0.0, 0.0, 0.0, 0.0, 0.0),
    (0.9466785280815826, 0.2557011698983284, 0.0, 0.0, 0.0, 0.0),
    (3.314825187068521, 2.896124015972201, 0.9986419139977817, 0.0, 0.0, 0.0),
    (1.221224509226641, 6.019134481288629, 12.53708332932087, -0.6878860361058950, 0.0, 0.0),
    (1.221224509226641, 6.019134481288629, 12.53708332932087, -0.6878860361058950, 1.0, 0.0),
)
#: C_si / h couple the earlier stages into stage s's right-hand side.
RODAS_C = (
    (0.0, 0.0, 0.0, 0.0, 0.0, 0.0),
    (-5.6688, 0.0, 0.0, 0.0, 0.0, 0.0),
    (-2.430093356833875, -0.2063599157091915, 0.0, 0.0, 0.0, 0.0),
    (-0.1073529058151375, -9.594562251023355, -20.47028614809616, 0.0, 0.0, 0.0),
    (7.496443313967647, -10.24680431464352, -33.99990352819905, 11.70890893206160, 0.0, 0.0),
    (8.083246795921522, -7.981132988064893, -31.52159432874371, 16.31930543123136,
     -6.058818238834054, 0.0),
)  # fmt: skip
#: Nodes c_s and the coefficients d_s = γ_s of the ∂f/∂t term.
RODAS_NODES = (0.0, 0.386, 0.21, 0.63, 1.0, 1.0)
RODAS_D = (0.25, -0.1043, 0.1035, -0.0362, 0.0, 0.0)
RODAS_SAFETY, RODAS_MIN_FACTOR, RODAS_MAX_FACTOR = 0.9, 0.2, 5.0

#: RODAS4's slots in its scalars (``ws[0]``): the last accepted step's size (0: none yet), its
#: error norm (at least 1e-2: rodas.f's ERRACC), the passing try's error norm, whether a try
#: of this step failed, whether the linearisation is of an earlier point.
RO_H_ACCEPTED, RO_ERROR_ACCEPTED, RO_ERROR, RO_FAILED, RO_STALE = range(5)
N_RODAS_SCALARS = 5
#: RODAS4's lane record (``source.LANE`` says what each entry is).
LANE = {
    "integrator": {
        "name": "rodas4", "title": "RODAS4 (order 4, linearly implicit)", "order": 4,
        "explicit": False, "tolerance_scale": 1.0, "engines": ("single",),
    },
    "lane": "rodas_lane", "steps": "rodas", "work": "rodas_work",
    "LAND_SETTLE": False, "REGIMES": True, "RTOL_FLOOR": 100.0 * EPS,
}  # fmt: skip


def rodas_work(lay):
    """RODAS4's ``ws`` (:func:`rodas_start`'s docstring); it allocates: the CPU's."""
    size = lay[LY_SIZE]
    m2 = lay[LY_SECOND]
    nk = lay[LY_KEPT]
    v = np.empty((8, size))
    return (
        np.zeros(N_RODAS_SCALARS), np.empty((size - m2, m2 + nk)), v[0], v[1],
        np.empty((6, size)), v[2], v[3], v[4], v[5], v[6], v[7], np.empty(nk),
        np.empty((nk, nk)), np.empty(nk, dtype=np.int64),
    )  # fmt: skip


def rodas_stage(k, y, s, stage, size):
    """Stage ``s``'s point ``y + Σ_i a_si k_i`` into ``stage``."""
    for j in range(size):
        acc = y[j]
        for i in range(s):
            acc += RODAS_A[s][i] * k[i, j]
        stage[j] = acc


def rodas_right_side(fs, ft, k, s, h, x, size):
    """Stage ``s``'s right-hand side ``f_s + d_s h ∂f/∂t + Σ_i (c_si / h) k_i`` into ``x``;
    whether it is finite."""
    finite = True
    for j in range(size):
        acc = fs[j] + RODAS_D[s] * h * ft[j]
        for i in range(s):
            acc += (RODAS_C[s][i] / h) * k[i, j]
        x[j] = acc
        finite = finite and math.isfinite(acc)
    return finite


def rodas_error(k, stage, y, y_new, atol, rtol, size):
    """The new state ``stage + k₆`` into ``y_new`` and the error norm of ``k₆``: the RMS of
    ``k₆ / (atol + rtol·max(|y|, |y_new|))`` (the source's ``rms`` arithmetic)."""
    total = 0.0
    for j in range(size):
        y_new[j] = stage[j] + k[5, j]
        scaled = k[5, j] / (atol[j] + max(abs(y[j]), abs(y_new[j])) * rtol)
        total += scaled * scaled
    return math.sqrt(total) / math.sqrt(size)


def rodas_growth(h, h_accepted, error_accepted, error_norm, hold):
    """The next step's factor after an accepted one: ``0.9·err^(−1/4)``, after an accepted
    step (``h_accepted`` > 0) also at most Gustafsson's
    ``0.9·(h/h_prev)·(err_prev/err²)^(1/4)``, within [1/5, 5], at most 1 with ``hold`` (a try
    of this step failed)."""
    grow = RODAS_MAX_FACTOR if error_norm == 0.0 else RODAS_SAFETY * error_norm**-0.25
    if h_accepted > 0.0 and error_norm > 0.0:  # Gustafsson's predictive controller
        gus = RODAS_SAFETY * (h / h_accepted) * (error_accepted / error_norm**2) ** 0.25
        grow = min(grow, gus)
    grow = max(RODAS_MIN_FACTOR, min(RODAS_MAX_FACTOR, grow))
    if hold:
        grow = min(grow, 1.0)
    return grow


def rodas_start(ws, t, y, f, t_end, max_step, rtol, atol, rp, ip, lay, pen, f_mid, record_mid,
                phi_q, schur, lam, counts):  # fmt: skip
    """RODAS4's state at the first point: SciPy's initial step (one evaluation of f).
    ``ws``: the scalars (N_RODAS_SCALARS); ``jac`` (S − m2, m2 + nk), ``jfactor``, ``ft``
    (S), the stages ``k`` (6, S), ``stage``, ``x``, ``ytmp``, ``f_col``, ``diff``,
    ``diff_new`` (S), ``work`` (nk), ``lu`` (nk, nk), ``piv`` (nk, int) (m2, nk:
    ``LY_SECOND``, ``LY_KEPT``)."""
    ms, stage, x = ws[0], ws[5], ws[6]
    ms[RO_H_ACCEPTED] = 0.0
    ms[RO_ERROR_ACCEPTED] = 1.0
    return initial_step(t, y, t_end, max_step, f, rtol, atol, rp, ip, lay, stage, f_mid, x,
                        record_mid, phi_q, schur, lam, counts)  # fmt: skip


def rodas_begin(ws, t, y, f, h, max_step, min_step, rtol, atol, size):
    """A step's first try: at most the largest step (rodas.f's HMAX); the linearisation is
    due at the step's start (the first try makes it, :func:`rodas_linearise`)."""
    ms = ws[0]
    ms[RO_FAILED] = 0.0
    ms[RO_STALE] = 1.0
    return min(h, max_step)


def rodas_land(t, h, target):
    """The try's end, cut to land on ``target``; the step is the difference."""
    t_new = t + h
    if t_new - target > 0:
        t_new = target
    return t_new, t_new - t


def rodas_linearise(ws, t, y, f, atol, rp, ip, lay, record_mid, phi_q, schur, lam, counts):
    """The Jacobian at ``(t, y)`` (the differences from their initial step) and ∂f/∂t by one
    forward difference (rodas.f's ``DELT``; zero where t does not enter f:
    :func:`source.time_enters`)."""
    (ms, jac, jfactor, ft, _, _, _, ytmp, f_col, diff, diff_new, _, _, _) = ws
    size = lay[LY_SIZE]
    for j in range(size):
        jfactor[j] = EPS**0.5
    lane_jacobian(t, y, f, atol, jfactor, rp, ip, lay, jac, ytmp, f_col, diff, diff_new,
                  record_mid, phi_q, schur, lam)  # fmt: skip
    if RECORD:
        counts[K_JAC] += 1
    if time_enters(rp, lay):
        dt = math.sqrt(EPS * max(1e-5, abs(t)))
        rhs(t + dt, y, rp, ip, lay, f_col, record_mid, False, phi_q, schur, lam)
        counts[K_RHS] += 1
        for j in range(size):
            ft[j] = (f_col[j] - f[j]) / dt
    else:
        for j in range(size):
            ft[j] = 0.0
    ms[RO_STALE] = 0.0


def rodas_attempt(ws, t, y, f, h, t_new, y_new, t_old, y_old, rtol, atol, rp, ip, lay,
                  record_new, qb, pen, f_mid, record_mid, phi_q, schur, lam, counts):  # fmt: skip
    """A try of the step ``h``: the LU of ``1/(γh)·I − J``, the six stages, ``y_new``, the
    error test on ``k₆`` ([HW96] §IV.7) and the end's contact records."""
    if ws[0][RO_STALE] > 0.0:
        rodas_linearise(ws, t, y, f, atol, rp, ip, lay, record_mid, phi_q, schur, lam, counts)
    (ms, jac, _, ft, k, stage, x, _, _, _, _, work, lu, piv) = ws
    m2 = lay[LY_SECOND]
    nk = lay[LY_KEPT]
    size = lay[LY_SIZE]
    alpha = 1.0 / (h * RODAS_GAMMA)
    newton_matrix(jac, alpha, lu, m2, nk)
    lu_real(lu, piv, nk)
    if RECORD:
        counts[K_LU] += 1
    finite = True
    for s in range(6):
        if s > 0:
            rodas_stage(k, y, s, stage, size)
            rhs(t + RODAS_NODES[s] * h, stage, rp, ip, lay, f_mid, record_mid, False, phi_q,
                schur, lam)  # fmt: skip
            counts[K_RHS] += 1
        finite = rodas_right_side(f_mid if s > 0 else f, ft, k, s, h, x, size)
        if not finite:
            break
        solve_real(lu, piv, jac, alpha, x, work, m2, nk, size)
        for j in range(size):
            k[s, j] = x[j]
    error_norm = rodas_error(k, stage, y, y_new, atol, rtol, size) if finite else 0.0
    if not (finite and error_norm <= 1.0):  # NaN fails too
        shrink = RODAS_SAFETY * error_norm**-0.25 if finite else RODAS_MIN_FACTOR
        ms[RO_FAILED] = 1.0
        counts[K_REJECTED] += 1
        return False, h * max(RODAS_MIN_FACTOR, min(1.0, shrink))
    contact_forces(y_new, rp, ip, lay, f_mid, record_new, True)
    ms[RO_ERROR] = error_norm
    return True, h


def rodas_retry(ws):
    """Nothing of RODAS4's state depends on the step's size (the LU is each try's)."""
    return


def rodas_refresh(ws, t_new, y_new, f_new, changed, rp, ip, lay, record, qb, pen, phi_q, schur,
                  lam, counts):  # fmt: skip
    """f, the records and the quantities at the accepted end (no last stage to reuse)."""
    rhs_and_quantities(t_new, y_new, rp, ip, lay, f_new, record, qb, pen, phi_q, schur, lam)
    counts[K_RHS] += 1
    return True


def rodas_accept(ws, t_new, y_new, f_new, h, changed, atol, rp, ip, lay, pen, f_mid,
                 record_mid, phi_q, schur, lam, counts):  # fmt: skip
    """The next step's size: ``0.9·err^(−1/4)``, after an accepted step also at most
    Gustafsson's ``0.9·(h/h_prev)·(err_prev/err²)^(1/4)``, within [1/5, 5], not larger after
    a failed try (a discontinuity changes nothing: every step starts afresh)."""
    ms = ws[0]
    error_norm = ms[RO_ERROR]
    grow = rodas_growth(h, ms[RO_H_ACCEPTED], ms[RO_ERROR_ACCEPTED], error_norm,
                        ms[RO_FAILED] > 0.0 and hold_after_failure(rp))  # fmt: skip
    ms[RO_H_ACCEPTED] = h
    ms[RO_ERROR_ACCEPTED] = max(1e-2, error_norm)
    return h * grow


def rodas_dense(ws, t_old, y_old, t, y, f, t_new, y_new, f_new, h, tau, theta, out, lay):
    """The interpolant between steps: the cubic Hermite of the two ends' states and rates
    (:func:`source_radau.hermite`)."""
    hermite(t_old, y_old, t, y, f, t_new, y_new, f_new, lay[LY_N], lay[LY_SIZE], tau, out,
            RULE_RATES)  # fmt: skip
