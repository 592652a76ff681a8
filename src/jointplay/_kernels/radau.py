"""Compiled variable-step Radau IIA (order 5) integrator for stiff, nonsmooth ODEs.

A faithful Numba port of SciPy's ``scipy.integrate._ivp.radau`` (SciPy 1.17), which
follows Hairer & Wanner [HW96]_, §IV.8: the three-stage Radau IIA collocation method
(order 5); its simplified Newton iteration on the eigen-decomposed (one real, one
complex) linear systems, started from the previous step's collocation polynomial; the
third-order embedded error estimate, re-estimated with one more evaluation of ``f`` after
a rejection; and the predictive (Gustafsson) step-size controller. Constants, tolerances
and decisions are SciPy's, so that on the same problem and tolerances the kernel takes
nearly the same steps as ``solve_ivp(method="Radau")`` with its default finite-difference
Jacobian (the same steps, up to round-off, on smooth problems).

Added for the contact simulator, and not in SciPy:

* ``step_check(t_old, y_old, t_new, y_new, args) -> float`` is called on every step that
  passed the error test. ``1.0`` accepts; ``θ`` in (0, 1) rejects the step and retries it
  from ``t_old`` with step ``h·θ`` (to land a step on contact onset). A retry that would
  be shorter than the minimum step (``10·spacing(t)``, as in SciPy), not shorter at all,
  or the ``MAX_CHECK_REJECTIONS + 1``-th of one step is not made: the step is accepted.
* ``after_step(t, y, args) -> bool`` is called on every accepted step and may modify ``y``
  and the arrays in ``args`` in place (projection, contact memory). ``True`` declares a
  discontinuity: the next Newton iteration starts from zero instead of the collocation
  extrapolation, and the Jacobian is kept but marked stale (recomputed as soon as Newton
  fails). ``f`` is always re-evaluated after ``after_step``.
* Every accepted step is recorded; statuses replace exceptions (the kernel never raises);
  ``max_steps`` bounds the number of accepted steps.

Where it departs from SciPy (none of which changes a step on a smooth problem):

* After a step, a non-finite state or ``f`` ends the integration with status −3 (SciPy
  carries NaN on: a NaN error norm passes its error test). A non-finite ``f`` inside the
  Newton iteration is, as in SciPy, a failed iteration (smaller step).
* The error is re-estimated after a rejection only, as in SciPy (Hairer's RADAU5 also does
  it on the first step).
* ``rtol`` below ``100·eps`` is raised to it silently (SciPy warns); an empty interval
  returns at once without evaluating ``f``.
* Own LU and loop-ordered sums: the same pivots and arithmetic as SciPy/LAPACK, but not
  the same round-off. No dense output is built: only the last collocation polynomial is
  kept, for the Newton start, as SciPy does.
* A difference factor is capped at ``NUM_JAC_MAX_FACTOR`` (SciPy lets it grow without
  bound on a column f hardly depends on, until the step is infinite and the Jacobian NaN).

Options, each off by default (then the kernel is SciPy's algorithm, as above), for
mechanical systems (:func:`radau_integrate` says how to switch them on):

* **second-order structure** (``n_second``): when ``y = (x, v, …)`` with ``x' = v``, the
  Newton systems ``(γ/h·I − J) d = b`` are solved on the ``v`` block and the other active
  components only, after eliminating ``dx = h/γ (b_x + dv)`` ([HW96] §IV.8, the ``M1``
  option of RADAU5): for a mechanism, 9×9 instead of 24×24 matrices;
* **passive components** (``n_active``): trailing components that do not feed back (work
  integrals) or are constant in the ODE (contact memory); their Jacobian columns are not
  differenced and their Newton increments follow from the active ones;
* **a Jacobian function** (``jac``), used whenever it returns one (``True``);
* **RADAU5's growth limit** (``hold_after_failure``): after a step that was accepted only
  after a failed error test or Newton iteration, the next step may not grow
  (``IF (REJECT) HNEW = MIN(HNEW, H)`` in Hairer's radau5.f). SciPy lets it grow at once.

In exact arithmetic the first two give the same iterates as the full algorithm; an exact
Jacobian changes the simplified-Newton iterates, not the solution they converge to; the
growth limit changes step-size decisions, and only after a rejection.

Jacobian: SciPy's ``num_jac`` (dense branch) is ported whole: forward differences with
step ``factor_j·max(|y_j|, atol_j)`` in the direction of ``f``, where the per-column
``factor`` (initially ``sqrt(eps)``) is adapted from call to call so the difference stays
well above its round-off (a column drowned in round-off is retried with a 10x step). As
in SciPy, its ``n`` (up to ``2n``) evaluations of ``fun`` count in ``njev``, not ``nfev``.

Layout: the step's numerics are written once, in the lane source
(:mod:`jointplay._kernels.lanes.source_radau`: the method's constants, the reduced Newton
matrices and their LU with partial pivoting, complex numbers as pairs of floats, the
simplified Newton iteration, the error estimate, the controller's factor), in the subset that
Numba's CPU and CUDA targets both compile; the lanes' steps and this module's run them in the
one loop (:func:`jointplay._kernels.lanes.source.lane`, this module's through
:mod:`jointplay._kernels.driver`), with the CPU lanes' compilation of them
(:data:`jointplay._kernels.lanes.cpu.compiled`): here are only
the method's state, its Newton loop over ``fun`` and its steps ``_radau_start`` …
``_radau_accept``.
:mod:`jointplay._kernels.common` holds the initial step and SciPy's finite-difference
Jacobian.

Compilation: :mod:`jointplay._kernels.driver`'s (one cached copy of the loop per method and
type of ``args``, the user's functions passed as first-class function values, so
:func:`radau_integrate` is called from Python).

References: Hairer & Wanner 1996, §IV.8, and SciPy 1.0 (:mod:`jointplay._kernels.driver`'s
[HW96] and [SciPy]), ``scipy/integrate/_ivp/radau.py`` and ``common.py``.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt

from jointplay._kernels.common import jit, num_jac
from jointplay._kernels.driver import (
    MAX_CHECK_REJECTIONS,
    Steps,
    accept_every_step,
    evaluate_f,
    finite_differences,
    kernel_signatures,
    no_after_step,
    run_core,
    step_jit,
)
from jointplay._kernels.ids import EPS, NFEV, NJEV, NLU, NREJ_ERROR, NREJ_NEWTON
from jointplay._kernels.lanes.cpu import compiled
from jointplay._kernels.lanes.source_radau import NEWTON_MAXITER, RC1, RC2, RC3
from jointplay._kernels.lanes.source_radau import R_MIN_FACTOR as MIN_FACTOR

__all__ = [
    "MAX_CHECK_REJECTIONS",
    "STEPS",
    "accept_every_step",
    "finite_differences",
    "kernel_signatures",
    "no_after_step",
    "radau_integrate",
]

# The step's numerics: the lane source's CPU compilation, the CPU lanes' (module docstring;
# not inlined into the loop, as the step's own functions are: compiled once, as before).
factor_newton = compiled["factor_newton"]
newton_start = compiled["newton_start"]
newton_iteration = compiled["newton_iteration"]
error_estimate = compiled["error_estimate"]
error_again = compiled["error_again"]
polynomial = compiled["polynomial"]
predict = compiled["predict"]
next_factor = compiled["next_factor"]
pmin = compiled["pmin"]
pmax = compiled["pmax"]

# ---------------------------------------------------------------------------------------
# The method's steps for the loop (jointplay._kernels.driver): SciPy's Radau._step_impl.
# ---------------------------------------------------------------------------------------
# Slots of the state's scalars (float64; flags 0/1, the Newton iteration count exact).
_H_PROPOSED = 0  # the step size proposed before this step (SciPy's self.h_abs)
_H_OLD = 1  # the one proposed before the last step (SciPy's self.h_abs_old; NaN: None)
_ERR_OLD = 2  # the last step's error norm (SciPy's self.error_norm_old; NaN: None)
_H_OLD_STEP = 3  # _H_OLD for this step's controller, NaN after a clamp of the step size
_ERR_OLD_STEP = 4  # _ERR_OLD likewise
_NEWTON_TOL = 5  # Newton tolerance on the scaled RMS norm
_CURRENT_JAC = 6  # the Jacobian is at the current point
_LU_VALID = 7  # the factors are of the Jacobian at the current step size
_HAS_SOL = 8  # the last step's collocation polynomial starts Newton (no discontinuity)
_T_OLD = 9  # the last step's start, s
_REJECTED = 10  # a try of this step failed the error test (SciPy's ``rejected``)
_N_ITER = 11  # Newton iterations of the try that passed
_RATE = 12  # its convergence rate (NaN: undefined)
_ERROR = 13  # its error norm
_SAFETY = 14  # its safety factor, 0.9·(2·NEWTON_MAXITER + 1)/(2·NEWTON_MAXITER + n_iter)
_N_SCALARS = 15
# Rows of the state's (n,) vectors and its (nk,) ones.
_YTMP, _XR, _XCR, _XCI, _ZE, _ESCALE, _SCALE = range(7)


@jit
def _jacobian_into(problem, t, y, f, factor, out):
    """The user's Jacobian where ``jac`` gives one, SciPy's ``num_jac`` otherwise, into
    ``out`` (n, n); ``factor`` is ``num_jac``'s, adapted in place."""
    if not problem.jac(t, y, f, problem.args, out):
        out[:, :] = num_jac(
            problem.fun, problem.args, t, y, f, problem.atol, factor, problem.n_active
        )


@jit
def _radau_start(problem, t0, y0, f0, counters):
    """The state at ``(t0, y0)``: the Jacobian there (counted), no factors, no polynomial.

    Returns:
        ``(sc, jac, jac_factor, a_re, piv_re, c_re, c_im, piv_c, stages, vectors, kept, cq,
        y_old)``: the scalars (slots ``_H_PROPOSED`` …), the Jacobian (n, n), ``num_jac``'s
        factors, the reduced real and complex Newton factors (nk, nk; ``nk = n_active −
        n_second``) and their pivots, the Newton iteration's W, Z, F and dW (4, 3, n), its
        vectors (7, n: rows ``_YTMP`` …, ``_SCALE`` the step's Newton scale) and the kept
        block's (3, nk), the collocation polynomial ``Q`` (3, n) and its start ``y_old``.
    """
    n = y0.shape[0]
    nk = problem.n_active - problem.n_second
    rtol = problem.rtol
    sc = np.zeros(_N_SCALARS)
    sc[_H_OLD] = np.nan  # NaN stands for SciPy's None.
    sc[_ERR_OLD] = np.nan
    sc[_NEWTON_TOL] = max(10.0 * EPS / rtol, min(0.03, rtol**0.5))
    jac_factor = np.full(n, EPS**0.5)
    jac = np.empty((n, n))
    _jacobian_into(problem, t0, y0, f0, jac_factor, jac)
    counters[NJEV] += 1
    sc[_CURRENT_JAC] = 1.0
    sc[_T_OLD] = t0
    return (
        sc, jac, jac_factor,
        np.empty((nk, nk)), np.zeros(nk, dtype=np.int64),
        np.empty((nk, nk)), np.empty((nk, nk)), np.zeros(nk, dtype=np.int64),
        np.empty((4, 3, n)), np.empty((7, n)), np.empty((3, nk)), np.zeros((3, n)), y0.copy(),
    )  # fmt: skip


@step_jit
def _radau_begin(state, problem, t, y, f, h_abs, min_step, counters):
    """A step from ``(t, y)``: the proposed size clamped to ``[min_step, max_step]`` (a
    clamp forgets the last step for the controller, as SciPy), the Newton scale
    ``atol + rtol·|y|``. Returns the first try's size and no cap on the retries (SciPy's)."""
    sc, scale = state[0], state[9][_SCALE]
    sc[_H_PROPOSED] = h_abs
    if h_abs > problem.max_step:
        h_abs = problem.max_step
        sc[_H_OLD_STEP] = np.nan
        sc[_ERR_OLD_STEP] = np.nan
    elif h_abs < min_step:
        h_abs = min_step
        sc[_H_OLD_STEP] = np.nan
        sc[_ERR_OLD_STEP] = np.nan
    else:
        sc[_H_OLD_STEP] = sc[_H_OLD]
        sc[_ERR_OLD_STEP] = sc[_ERR_OLD]
    for j in range(y.shape[0]):  # per step, as SciPy
        scale[j] = problem.atol[j] + abs(y[j]) * problem.rtol
    sc[_REJECTED] = 0.0
    return h_abs, np.inf


@jit  # not inlined into the loop: a function of its own, as SciPy's
def _collocation(state, problem, t, y, h):
    """The simplified Newton iteration of the collocation system on ``fun`` (the source's
    pieces, as the lane's :func:`~jointplay._kernels.lanes.source_radau.collocation` on its
    right-hand side). Returns ``(converged, n_iter, rate, nfev)``; Z in ``state[8][1]``."""
    sc, jac, a_re, piv_re, c_re, c_im, piv_c = (
        state[0], state[1], state[3], state[4], state[5], state[6], state[7]
    )  # fmt: skip
    stages, vectors, kept, cq, y_old = state[8], state[9], state[10], state[11], state[12]
    w, z, fst, dw = stages[0], stages[1], stages[2], stages[3]
    ytmp, scale, xr, xcr, xci = (
        vectors[_YTMP], vectors[_SCALE], vectors[_XR], vectors[_XCR], vectors[_XCI]
    )  # fmt: skip
    wk, wkr, wki = kept[0], kept[1], kept[2]
    n = y.shape[0]
    m2 = problem.n_second
    nk = problem.n_active - m2
    rows = jac[m2:]
    tol = sc[_NEWTON_TOL]
    newton_start(t, y, h, sc[_HAS_SOL] != 0.0, cq, sc[_T_OLD], y_old, z, w, n)
    converged = False
    dw_norm = 0.0
    rate = np.nan
    k = 0
    for k in range(NEWTON_MAXITER):
        for i in range(3):  # the stage points (the source's stage_point, inline here)
            for j in range(n):
                ytmp[j] = y[j] + z[i, j]
            f_i = problem.fun(t + h * (RC1 if i == 0 else (RC2 if i == 1 else RC3)), ytmp,
                              problem.args)  # fmt: skip
            for j in range(n):
                fst[i, j] = f_i[j]
        done, converged, dw_norm, rate = newton_iteration(
            fst, h, w, z, dw, scale, tol, k, dw_norm, rate, rows, a_re, piv_re, c_re, c_im,
            piv_c, xr, xcr, xci, wk, wkr, wki, m2, nk, n,
        )  # fmt: skip
        if done:
            break
    return converged, k + 1, rate, 3 * (k + 1)


@step_jit
def _newton(state, problem, t, y, f, h, counters):
    """The collocation system at step ``h`` solved by simplified Newton, started from the
    last step's polynomial; on failure with a stale Jacobian, once more with a fresh one.
    Returns ``(converged, n_iter, rate)``."""
    sc, jac, jac_factor, a_re, piv_re, c_re, c_im, piv_c = state[:8]
    m2 = problem.n_second
    while True:
        if sc[_LU_VALID] == 0.0:
            factor_newton(jac[m2:], h, a_re, piv_re, c_re, c_im, piv_c, m2,
                          problem.n_active - m2)  # fmt: skip
            counters[NLU] += 2
            sc[_LU_VALID] = 1.0
        converged, n_iter, rate, nfev = _collocation(state, problem, t, y, h)
        counters[NFEV] += nfev
        if converged or sc[_CURRENT_JAC] != 0.0:
            return converged, n_iter, rate
        _jacobian_into(problem, t, y, f, jac_factor, jac)
        counters[NJEV] += 1
        sc[_CURRENT_JAC] = 1.0
        sc[_LU_VALID] = 0.0


@step_jit
def _radau_attempt(state, problem, t, y, f, h, y_new, counters):
    """One try of the step ``h`` ([HW96] §IV.8; SciPy's ``Radau._step_impl``): Newton on
    the collocation system, ``y_new = y + Z₃``, the embedded error estimate (re-estimated
    with one more ``f`` after a rejection), the error test. Returns ``(passed, h_abs)``:
    ``h_abs`` to retry with after a failure (half after a Newton failure, else the
    predictive controller's, [HW96] (8.25)), counted in ``NREJ_NEWTON`` or ``NREJ_ERROR``."""
    sc, jac, a_re, piv_re = state[0], state[1], state[3], state[4]
    z, vectors, wk = state[8][1], state[9], state[10][0]
    n = y.shape[0]
    m2 = problem.n_second
    nk = problem.n_active - m2
    h_abs = abs(h)
    converged, n_iter, rate = _newton(state, problem, t, y, f, h, counters)
    if not converged:
        sc[_LU_VALID] = 0.0
        counters[NREJ_NEWTON] += 1
        return False, h_abs * 0.5

    for j in range(n):
        y_new[j] = y[j] + z[2, j]
    error_norm = error_estimate(
        z, f, h, y, y_new, problem.atol, problem.rtol, vectors[_ZE], vectors[_XR], wk,
        vectors[_ESCALE], jac[m2:], a_re, piv_re, m2, nk, n,
    )  # fmt: skip
    safety = 0.9 * (2 * NEWTON_MAXITER + 1) / (2 * NEWTON_MAXITER + n_iter)

    if sc[_REJECTED] != 0.0 and error_norm > 1:
        ytmp = vectors[_YTMP]
        for j in range(n):
            ytmp[j] = y[j] + vectors[_XR, j]
        f_err = problem.fun(t, ytmp, problem.args)
        counters[NFEV] += 1
        error_norm = error_again(f_err, vectors[_ZE], h, vectors[_XR], wk, vectors[_ESCALE],
                                 jac[m2:], a_re, piv_re, m2, nk, n)  # fmt: skip

    if error_norm > 1:
        factor = predict(h_abs, sc[_H_OLD_STEP], error_norm, sc[_ERR_OLD_STEP])
        sc[_LU_VALID] = 0.0
        sc[_REJECTED] = 1.0
        counters[NREJ_ERROR] += 1
        return False, h_abs * pmax(MIN_FACTOR, safety * factor)
    sc[_N_ITER] = n_iter
    sc[_RATE] = rate
    sc[_ERROR] = error_norm
    sc[_SAFETY] = safety
    return True, h_abs


@step_jit
def _radau_retry(state):
    """``step_check`` shortened the step: the factors are of the old step size."""
    state[0][_LU_VALID] = 0.0


@step_jit
def _radau_accept(state, problem, t, y, t_new, y_new, f, h_abs, failed, changed, counters):
    """The accepted step ``(t, y) → (t_new, y_new)``, ``f = f(t_new, y_new)``: the next
    step's size from the predictive controller ([HW96] (8.25)), at most ``MAX_FACTOR``
    times larger, not larger at all after a failed try with ``hold_after_failure``, kept
    (with the factors) when it would grow less than 1.2 and Newton converged fast; the
    Jacobian recomputed at the new point when Newton converged slowly; the collocation
    polynomial for the next Newton start, unless ``after_step`` declared a discontinuity.
    Returns the next step's proposed size."""
    sc, jac, jac_factor, z, cq, y_old = (
        state[0], state[1], state[2], state[8][1], state[11], state[12]
    )  # fmt: skip
    error_norm = sc[_ERROR]
    recompute_jac = sc[_N_ITER] > 2 and sc[_RATE] > 1e-3

    factor, kept = next_factor(h_abs, sc[_H_OLD_STEP], error_norm, sc[_ERR_OLD_STEP],
                               sc[_SAFETY], problem.hold_after_failure and failed,
                               recompute_jac)  # fmt: skip
    if not kept:
        sc[_LU_VALID] = 0.0

    if recompute_jac:
        _jacobian_into(problem, t_new, y_new, f, jac_factor, jac)
        counters[NJEV] += 1
        sc[_CURRENT_JAC] = 1.0
    else:
        sc[_CURRENT_JAC] = 0.0

    # As SciPy: the "old" step size is the one proposed before this step.
    sc[_H_OLD] = sc[_H_PROPOSED]
    sc[_ERR_OLD] = error_norm
    sc[_T_OLD] = t
    y_old[:] = y
    polynomial(z, cq, y.shape[0])
    sc[_HAS_SOL] = 0.0 if changed else 1.0
    return h_abs * factor


#: Radau IIA's steps for the generic loop (:mod:`jointplay._kernels.driver`: the lanes' loop).
STEPS = Steps(_radau_start, _radau_begin, _radau_attempt, _radau_retry, evaluate_f, _radau_accept)


def radau_integrate(
    *args: Any, **kwargs: Any
) -> tuple[int, npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.int64]]:
    """Integrate ``y' = fun(t, y, args)`` from ``t0`` to ``t_bound`` with Radau IIA (order 5).

    A port of ``solve_ivp(method="Radau")`` with the ``step_check``/``after_step`` hooks
    described in the module docstring. The numerical work runs in one compiled,
    disk-cached function; this entry point only coerces scalars and arrays to the
    compiled types and picks the specialisation for ``numba.typeof(args)``. The
    integration itself never raises: failures are returned as a status.

    Args:
        fun: Numba-jitted right-hand side ``fun(t, y, args) -> float64[:]`` (a new array).
        step_check: Numba-jitted ``step_check(t_old, y_old, t_new, y_new, args) -> float``:
            ``1.0`` accepts a step that passed the error test; ``θ`` in (0, 1) retries it
            from ``t_old`` with ``h·θ`` (counted in ``n_rejected_check``).
            :func:`accept_every_step` for none.
        after_step: Numba-jitted ``after_step(t, y, args) -> bool``, called on each
            accepted step; may modify ``y`` and ``args`` in place; ``True`` marks a
            discontinuity (zero Newton start next, Jacobian marked stale).
            :func:`no_after_step` for none.
        t0: Initial time.
        y0: Initial state, shape (n,); not modified.
        t_bound: Final time (may be below ``t0`` to integrate backwards).
        args: Tuple of NumPy arrays passed untouched to the three functions.
        rtol: Relative tolerance (raised to ``100·eps`` if smaller, as SciPy does).
        atol: Absolute tolerances, shape (n,), each ``>= 0``.
        max_step: Largest step size (``np.inf`` for none).
        first_step: First step size; ``0.0`` chooses it as SciPy's
            ``select_initial_step`` does.
        max_steps: Largest number of accepted steps.
        n_second: Declares a second-order structure: ``fun(t, y)[:m] == y[m:2m]`` exactly
            for ``m = n_second`` (positions, then their velocities). The Jacobian's first
            ``m`` rows are then known (``[0, I, 0]``) and the Newton systems are solved on
            the ``n_active − m`` other active components only ([HW96] §IV.8, RADAU5's
            ``M1``): ``dx = h/γ (b_x + dv)``. ``0`` (default): none, as SciPy.
        n_active: Components ``[n_active, n)`` are passive: either ``fun`` does not depend
            on them (quadratures such as work integrals), or they are constant in the ODE
            (``fun`` returns 0 for them; memory that only ``after_step`` changes). Their
            Jacobian columns are neither computed nor used (in both cases the Newton
            increments and the error estimate do not depend on them), and their Newton
            increments follow from the active ones. ``None`` (default): ``n``, as SciPy.
        hold_after_failure: After a step that was accepted only once its error test or
            its Newton iteration had failed, do not let the next step grow, as Hairer's
            RADAU5 does (``IF (REJECT) HNEW = MIN(HNEW, H)``). SciPy lets it grow at once,
            which on a right-hand side that is only piecewise smooth (contact forces
            clipped at zero) makes the controller retry, again and again, a step at which
            Newton just failed. ``False`` (default): SciPy's controller.
        jac: Numba-jitted ``jac(t, y, f, args, out) -> bool`` writing ``∂fun/∂y`` at
            ``(t, y)`` (``f = fun(t, y, args)``) into ``out`` (n, n) and returning
            ``True``, or returning ``False`` to let the kernel difference ``fun`` as SciPy
            does. ``None`` (default): always difference. Counted in ``njev`` either way.
        autonomous: ``fun`` does not depend on ``t`` (``∂f/∂t = 0``): RODAS4 then leaves out
            the difference of ``fun`` in ``t`` it takes at every step's start (one
            evaluation of the 7–8 a step; the same result to the bit, as that difference is
            exactly 0 then). Radau IIA and DOPRI5 need no ``∂f/∂t``. ``False`` (default):
            RODAS4 differences.
        interrupt: uint8 C-contiguous flags read before every step (see
            :func:`jointplay._kernels.lanes.source.interrupt_pending`): once they hold SIGINT or
            SIGTERM the integration stops with status ``-4``. ``None`` (default): never.

    Returns:
        ``(status, t_out, y_out, counters)``: status ``0`` reached ``t_bound``, ``-1`` the
        step size fell below ``10·spacing(t)``, ``-2`` more than ``max_steps`` steps were
        needed, ``-3`` a non-finite value appeared in the state or in ``f``, ``-4`` an
        interrupt arrived; ``t_out``
        (m,) and ``y_out`` (m, n) hold the initial point and every accepted step (after
        ``after_step``); ``counters`` (int64, 7) as named in ``COUNTER_NAMES``. ``nfev``
        leaves out the evaluations inside finite-difference Jacobians, as SciPy does.

    Raises:
        TypeError: From Numba, when a function does not compile to the signature that
            :func:`kernel_signatures` gives. :func:`jointplay.dynamics.integrate.integrate`
            checks this first and says what to fix.
        ValueError: ``n_second`` and ``n_active`` do not satisfy
            ``0 <= 2·n_second <= n_active <= n``.
    """
    return run_core("radau", STEPS, *args, **kwargs)
