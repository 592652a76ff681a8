"""Compiled variable-step RODAS4 for the generic loop (:func:`jointplay.integrate`): a linearly
implicit (Rosenbrock) method for stiff ODEs, the method of
:mod:`jointplay._kernels.lanes.source_rodas` (its tableau, stages, error norm and step
control, compiled for the CPU) around a user's ``fun`` and ``jac``: the Jacobian at the step's
start (the user's closed form where ``jac`` gives one, else SciPy's ``num_jac`` started
afresh from its initial step at every call) and ``∂f/∂t`` by one forward difference (none
when the caller declares ``fun`` autonomous).

Why the contact simulator has it beside Radau IIA (issue 22, docs/performance.md, "From
rest: a Rosenbrock method for the paper's ECS sets"): on the paper's IFM ECS contact sets,
whose damping (25 and 2 423 N·s/mm) is full at a negligible penetration, Radau's simplified
Newton iteration, its Jacobian frozen at the step's start, fails on most steps (1 253 and
24 241 failures in a revolution from rest). Our reading: the damping force ``c δ̇ n`` of a
pin whirling round its bearing turns with the contact normal ``n``, and the frozen
Jacobian's error ``c·Δθ`` (``Δθ`` the normal's turn within the step) outgrows the Newton
matrix's inertia term ``m/(γh)`` at steps of ~1e-5 s, the steps Radau ends up taking. A
Rosenbrock method linearises once per step and lets its error estimate set the step: on
those sets it takes as many steps as Radau or fewer, at about half the cost each. Elsewhere
Radau's higher order wins, and at the same tolerance RODAS4's global error is larger.

Interface and results as :func:`jointplay._kernels.radau.radau_integrate` (the same
arguments, hooks, statuses and counters; ``n_rejected_newton`` stays 0):

* ``step_check`` is called on every step that passed the error test and may shorten it
  (contact onset), as in the Radau driver;
* ``after_step`` is called on every accepted step and may modify ``y`` and ``args``; its
  return value (a discontinuity) changes nothing here, as the method starts every step
  afresh from ``(t, y)``;
* step-size control as ``rodas.f`` with its predictive (Gustafsson) controller: the factor
  ``0.9·err^(−1/4)``, after an accepted step also at most
  ``0.9·(h/h_prev)·(err_prev/err²)^(1/4)``, within [1/5, 5] (five measured variants of the
  bounds and the safety factor took 24 700–33 400 steps on the cylindrical set; these took
  the fewest); a rejected step retried with that factor, and with ``hold_after_failure`` no
  growth right after a rejection (``rodas.f`` always holds);
* a non-finite stage is a rejection with ``h/5``; a non-finite state or ``f`` after a step
  ends the integration with status −3.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.typing as npt

from jointplay._kernels.common import jit, num_jac, py_max, py_min
from jointplay._kernels.driver import Steps, evaluate_f, no_retry, run_core, step_jit
from jointplay._kernels.ids import EPS, NFEV, NJEV, NLU, NREJ_ERROR
from jointplay._kernels.lanes.cpu import compiled
from jointplay._kernels.lanes.source_rodas import (
    RODAS_GAMMA,
    RODAS_MIN_FACTOR,
    RODAS_NODES,
    RODAS_SAFETY,
)

__all__ = ["STEPS", "rodas_integrate"]

# The tableau, the stages' arithmetic, the error norm and the step control are the lane
# source's (:mod:`jointplay._kernels.lanes.source_rodas`, the single engine's RODAS4),
# compiled for the CPU; so are Radau's reduced real Newton matrix, its LU and solve
# (:mod:`jointplay._kernels.lanes.source_radau`).
newton_matrix = compiled["newton_matrix"]
lu_real = compiled["lu_real"]
solve_real = compiled["solve_real"]
_stage = compiled["rodas_stage"]
_right_side = compiled["rodas_right_side"]
_error = compiled["rodas_error"]
_growth = compiled["rodas_growth"]


@jit
def _factor(jac, alpha, n_second, n_active, lu, piv):
    """LU of ``α·I − J`` reduced to the kept block, as Radau's real Newton matrix, into
    ``lu`` (nk, nk) and ``piv`` (nk,), ``nk = n_active − n_second``."""
    nk = n_active - n_second
    newton_matrix(jac[n_second:], alpha, lu, n_second, nk)
    lu_real(lu, piv, nk)


@jit
def _stages(fun, args, t, y, f, ft, h, jac, lu, piv, n_second, n_active, k, stage, x, work):
    """The six stages of one step from ``(t, y)``; ``stage + k[5]`` is the new state and
    ``k[5]`` its error estimate. Returns the number of evaluations and whether every stage
    was finite."""
    n = y.shape[0]
    alpha = 1.0 / (h * RODAS_GAMMA)
    nfev = 0
    for s in range(6):
        fs = f
        if s > 0:
            _stage(k, y, s, stage, n)
            fs = fun(t + RODAS_NODES[s] * h, stage, args)
            nfev += 1
        if not _right_side(fs, ft, k, s, h, x, n):
            return nfev, False
        solve_real(lu, piv, jac[n_second:], alpha, x, work, n_second, n_active - n_second, n)
        for j in range(n):
            k[s, j] = x[j]
    return nfev, True


# Slots of the state's scalars.
_H_ACCEPTED = 0  # the last accepted step's size (0: none yet)
_ERROR_ACCEPTED = 1  # its error norm, at least 1e-2 (rodas.f's ERRACC)
_ERROR = 2  # the error norm of the try that passed
_N_SCALARS = 3


@jit
def _rodas_start(problem, t0, y0, f0, counters):
    """The state: ``(sc, jac, jac_factor, ft, k, stage, x, work, lu, piv)``, the scalars
    (slots ``_H_ACCEPTED`` …), the Jacobian (n, n) and ``num_jac``'s factors, ``∂f/∂t`` (n,),
    the stages (6, n), scratch, the reduced LU (nk, nk) and its pivots."""
    n = y0.shape[0]
    nk = problem.n_active - problem.n_second
    sc = np.zeros(_N_SCALARS)
    sc[_ERROR_ACCEPTED] = 1.0
    return (
        sc, np.empty((n, n)), np.full(n, EPS**0.5), np.empty(n), np.empty((6, n)),
        np.empty(n), np.empty(n), np.empty(nk), np.empty((nk, nk)), np.empty(nk, dtype=np.int64),
    )  # fmt: skip


@step_jit
def _rodas_begin(state, problem, t, y, f, h_abs, min_step, counters):
    """The linearisation at ``(t, y)``, kept for every try of this step: ``J`` (the user's,
    else SciPy's differences, each call from the initial relative step √eps) and ``∂f/∂t``
    by one forward difference (rodas.f's ``DELT``; 0 for an autonomous ``f``). Returns the
    first try's size and the cap on every try, ``max_step`` (rodas.f's ``HMAX``)."""
    jac, jac_factor, ft = state[1], state[2], state[3]
    n = y.shape[0]
    if not problem.jac(t, y, f, problem.args, jac):
        for j in range(n):
            jac_factor[j] = EPS**0.5
        jac[:, :] = num_jac(problem.fun, problem.args, t, y, f, problem.atol, jac_factor,
                            problem.n_active)  # fmt: skip
    counters[NJEV] += 1
    if problem.autonomous:
        ft[:] = 0.0
    else:
        dt = problem.direction * math.sqrt(EPS * py_max(1e-5, abs(t)))  # rodas.f's DELT
        f_later = problem.fun(t + dt, y, problem.args)
        counters[NFEV] += 1
        for j in range(n):
            ft[j] = (f_later[j] - f[j]) / dt
    return h_abs, problem.max_step


@step_jit
def _rodas_attempt(state, problem, t, y, f, h, y_new, counters):
    """One try of the step ``h``: the LU of ``1/(γh)·I − J``, the six stages, ``y_new`` and
    the error test on ``k₆`` ([HW96] §IV.7). Returns ``(passed, h_abs)``, after a failure
    ``h_abs·max(1/5, min(1, 0.9·err^(−1/4)))`` (``h/5`` for a non-finite stage), counted
    in ``NREJ_ERROR``."""
    sc, jac = state[0], state[1]
    ft, k, stage, x, work, lu, piv = state[3:]
    h_abs = abs(h)
    _factor(jac, 1.0 / (h * RODAS_GAMMA), problem.n_second, problem.n_active, lu, piv)
    counters[NLU] += 1
    nfev, finite = _stages(
        problem.fun, problem.args, t, y, f, ft, h, jac, lu, piv, problem.n_second,
        problem.n_active, k, stage, x, work,
    )  # fmt: skip
    counters[NFEV] += nfev
    error_norm = 0.0
    if finite:
        error_norm = _error(k, stage, y, y_new, problem.atol, problem.rtol, y.shape[0])
    if not (finite and error_norm <= 1.0):  # NaN fails too
        shrink = RODAS_SAFETY * error_norm**-0.25 if finite else RODAS_MIN_FACTOR
        counters[NREJ_ERROR] += 1
        return False, h_abs * py_max(RODAS_MIN_FACTOR, py_min(1.0, shrink))
    sc[_ERROR] = error_norm
    return True, h_abs


@step_jit
def _rodas_accept(state, problem, t, y, t_new, y_new, f, h_abs, failed, changed, counters):
    """The next step's size after an accepted one: ``0.9·err^(−1/4)``, after an accepted
    step also at most Gustafsson's ``0.9·(h/h_prev)·(err_prev/err²)^(1/4)``, within
    [1/5, 5], not larger after a failed try with
    ``hold_after_failure`` (``after_step``'s discontinuity changes nothing: every step
    starts afresh from ``(t, y)``)."""
    sc = state[0]
    error_norm = sc[_ERROR]
    grow = _growth(h_abs, sc[_H_ACCEPTED], sc[_ERROR_ACCEPTED], error_norm,
                   problem.hold_after_failure and failed)  # fmt: skip
    sc[_H_ACCEPTED] = h_abs
    sc[_ERROR_ACCEPTED] = py_max(1e-2, error_norm)
    return h_abs * grow


#: RODAS4's steps for the generic loop (:mod:`jointplay._kernels.driver`: the lanes' loop).
STEPS = Steps(_rodas_start, _rodas_begin, _rodas_attempt, no_retry, evaluate_f, _rodas_accept)


def rodas_integrate(
    *args: Any, **kwargs: Any
) -> tuple[int, npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.int64]]:
    """Integrate ``y' = fun(t, y, args)`` with RODAS4; arguments, hooks and results as
    :func:`jointplay._kernels.radau.radau_integrate` (``jac`` is used at every step's start;
    ``n_rejected_newton`` is always 0)."""
    return run_core("rodas", STEPS, *args, **kwargs)
