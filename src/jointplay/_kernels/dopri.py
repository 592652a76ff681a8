"""Compiled variable-step DOPRI5: the explicit Dormand–Prince 5(4) pair for non-stiff ODEs.

The method of Dormand & Prince [DP80]_ as tabulated in [HNW93]_ §II.5, Table 5.2 (the
coefficients, the stages' states and the error norm are the lane source's,
:mod:`jointplay._kernels.lanes.source`'s ``dopri_stage`` and ``dopri_error``, in their CPU
compilation: the batch engine's explicit lane computes them with the same functions):
seven stages, six evaluations of ``f`` per step (the last stage is ``f`` at the new point,
reused as the next step's first), order 5 propagated, the embedded order-4 solution for
the error estimate. No Jacobian, no linear algebra.

Why the contact simulator has it beside Radau IIA and RODAS4 (issue 22, docs/performance.md,
"From rest: DOPRI5 for the conventional set"): on the paper's *conventional* IMPACT set
(k = 1e4 N/mm^1.5, c_max = 10 N·s/mm reached at 0.1 mm) the contact is soft enough that an
explicit step's stability limit (~1.5e-4 s on the paper's four-bar) lies above the steps the
accuracy asks for, so the equations are not stiff there and Radau's implicit stages buy
nothing: a revolution from rest takes 1.4 times Radau's steps (DOPRI5 at a fifth of the
tolerances, as the single engine runs it), each at about a third of the cost. On stiff
contact its steps are set by stability (on the spherical ECS set, at rtol 1e-6, it used up
2 000 000 steps 47 % into the revolution that RODAS4 runs in 3 801): those sets keep Radau
IIA or RODAS4 (the batch engine draws the same line,
:func:`jointplay.dynamics.batch_method.choose_method`).

Interface and results as :func:`jointplay._kernels.radau.radau_integrate` (the same
arguments, hooks, statuses and counters; ``jac``, ``n_second``, ``hold_after_failure`` and
``autonomous`` are accepted and not needed; ``n_rejected_newton``, ``n_jac`` and ``n_lu``
stay 0):

* ``step_check`` is called on every step that passed the error test and may shorten it
  (contact onset), as in the Radau driver;
* ``after_step`` is called on every accepted step and may modify ``y`` and ``args``; when it
  returns True (a discontinuity: a projection, a change of contact memory) ``f`` is
  evaluated afresh at the new point, otherwise the last stage's is kept (first same as last);
* step-size control as ``dopri5.f`` without its PI term ([HNW93] §II.4): the factor
  ``0.9·err^(−1/5)`` within [1/5, 10], no growth right after a rejection; a non-finite
  stage is a rejection with ``h/5``; a non-finite state or ``f`` after a step ends the
  integration with status −3.

References:
    .. [DP80] J. R. Dormand, P. J. Prince, "A family of embedded Runge-Kutta formulae",
       *J. Comput. Appl. Math.* 6 (1980) 19–26.
    .. [HNW93] E. Hairer, S. P. Nørsett, G. Wanner, *Solving Ordinary Differential Equations
       I: Nonstiff Problems*, 2nd ed., Springer, 1993, §II.4–II.5.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.typing as npt

from jointplay._kernels.common import all_finite, jit, py_max, py_min
from jointplay._kernels.driver import Steps, no_retry, run_core, step_jit
from jointplay._kernels.ids import NFEV, NREJ_ERROR
from jointplay._kernels.lanes.cpu import compiled
from jointplay._kernels.lanes.source import C2, C3, C4, C5, MAX_FACTOR, MIN_FACTOR, SAFETY

__all__ = ["STEPS", "dopri_integrate"]

# The step's numerics: the lane source's CPU compilation, the CPU lanes' (as radau.py's).
dopri_stage = compiled["dopri_stage"]
dopri_error = compiled["dopri_error"]


@jit
def _step(fun, args, t, y, h, k, stage, y_new, atol, rtol):
    """One DOPRI5 step of size ``h`` from ``(t, y)`` with ``k[0] = f(t, y)``: the stages
    ``k[1..6]`` (``k[6]`` = f at the new point), ``y_new`` (the lane source's
    ``dopri_stage``). Returns the RMS error norm in units of ``atol + rtol·max(|y|,
    |y_new|)`` over every component (``dopri_error``; NaN when a stage is not finite)."""
    n = y.shape[0]
    dopri_stage(k, y, h, 1, stage, n)
    k[1, :] = fun(t + C2 * h, stage, args)
    dopri_stage(k, y, h, 2, stage, n)
    k[2, :] = fun(t + C3 * h, stage, args)
    dopri_stage(k, y, h, 3, stage, n)
    k[3, :] = fun(t + C4 * h, stage, args)
    dopri_stage(k, y, h, 4, stage, n)
    k[4, :] = fun(t + C5 * h, stage, args)
    dopri_stage(k, y, h, 5, stage, n)
    k[5, :] = fun(t + h, stage, args)
    dopri_stage(k, y, h, 6, y_new, n)
    k[6, :] = fun(t + h, y_new, args)
    error_norm = dopri_error(k, h, y, y_new, atol, rtol, n)
    if not (all_finite(y_new, y_new.shape[0]) and all_finite(k[6], k[6].shape[0])):
        return math.nan
    return error_norm


_ERROR = 0  # the slot of the error norm of the try that passed, in the state's scalars


@jit
def _dopri_start(problem, t0, y0, f0, counters):
    """The state: ``(sc, k, stage)``, the scalars, the stages (7, n) and a stage's state."""
    n = y0.shape[0]
    return np.zeros(1), np.empty((7, n)), np.empty(n)


@step_jit
def _dopri_begin(state, problem, t, y, f, h_abs, min_step, counters):
    """Nothing to prepare; the cap on every try is ``max_step`` (dopri5.f's ``HMAX``)."""
    return h_abs, problem.max_step


@step_jit
def _dopri_attempt(state, problem, t, y, f, h, y_new, counters):
    """One try of the step ``h`` (:func:`_step`, ``k₁ = f``). Returns ``(passed, h_abs)``,
    after a failure ``h_abs·max(1/5, min(1, 0.9·err^(−1/5)))`` (``h/5`` for a non-finite
    stage), counted in ``NREJ_ERROR``."""
    sc, k, stage = state
    h_abs = abs(h)
    k[0, :] = f
    error_norm = _step(problem.fun, problem.args, t, y, h, k, stage, y_new, problem.atol,
                       problem.rtol)  # fmt: skip
    counters[NFEV] += 6
    if not error_norm <= 1.0:  # NaN fails too
        shrink = SAFETY * error_norm**-0.2 if math.isfinite(error_norm) else 0.2
        counters[NREJ_ERROR] += 1
        return False, h_abs * py_max(MIN_FACTOR, py_min(1.0, shrink))
    sc[_ERROR] = error_norm
    return True, h_abs


@step_jit
def _dopri_refresh(state, problem, t_new, y_new, f, changed, counters):
    """``f`` at the new point: the last stage's (first same as last), evaluated afresh
    when ``after_step`` changed the state."""
    if changed:
        f[:] = problem.fun(t_new, y_new, problem.args)
        counters[NFEV] += 1
    else:
        f[:] = state[1][6]


@step_jit
def _dopri_accept(state, problem, t, y, t_new, y_new, f, h_abs, failed, changed, counters):
    """The next step's size: ``0.9·err^(−1/5)`` within ``[MIN_FACTOR, MAX_FACTOR]``, not
    larger right after a failed try (dopri5.f)."""
    error_norm = state[0][_ERROR]
    grow = MAX_FACTOR if error_norm == 0.0 else SAFETY * error_norm**-0.2
    grow = py_max(MIN_FACTOR, py_min(MAX_FACTOR, grow))
    if failed:
        grow = py_min(grow, 1.0)
    return h_abs * grow


#: DOPRI5's steps for the generic loop (:mod:`jointplay._kernels.driver`: the lanes' loop).
STEPS = Steps(_dopri_start, _dopri_begin, _dopri_attempt, no_retry, _dopri_refresh, _dopri_accept)


def dopri_integrate(
    *args: Any, **kwargs: Any
) -> tuple[int, npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.int64]]:
    """Integrate ``y' = fun(t, y, args)`` with DOPRI5; arguments, hooks and results as
    :func:`jointplay._kernels.radau.radau_integrate` (``jac``, ``n_second``,
    ``hold_after_failure`` and ``autonomous`` unused: an explicit method; ``n_rejected_newton``, ``n_jac`` and
    ``n_lu`` are always 0)."""
    return run_core("dopri", STEPS, *args, **kwargs)
