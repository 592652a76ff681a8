"""The generic ``jointplay.integrate`` on the one integrator loop: a user's ODE, its hooks and
a method's steps run by the lanes' loop (:func:`jointplay._kernels.lanes.source.lane`).

The loop of every engine is the lane source's: it owns the step budget, the interrupt, the
tries and their landing on ``t_bound``, the onset retry (``step_check``), the hooks after a
step (``after_step``), finiteness and the record. This module binds it to a user's problem:

- **adapters** (:data:`ADAPTERS`) take the place of the lane source's functions that read a
  mechanism: the onset check calls the user's ``step_check``, the projection its
  ``after_step``, the start's evaluation is :func:`driver_start`'s; the contact memory, the
  sustained-contact mode, the window's quantities and the running responses do nothing (the
  window never opens: ``t_settle`` is infinite). ``rp`` is the :class:`Problem`: the user's
  functions as first-class function values, its ``args`` and options.
- **time**: the loop runs forwards from :func:`problem_start_time`; its time is ``direction·t``, so
  that an integration backwards is the same loop (a sign, exact: the steps see the user's
  time and the signed step).
- **steps**: DOPRI5 runs the lanes' own steps (``source.dopri_*``, in lane time: the
  adapter ``rhs`` is ``direction·fun(direction·t, y)``; the first step is
  :func:`driver_start`'s), its record's ``module`` naming their prefix (:func:`steps_of`).
  Radau IIA and RODAS4 still bring their steps as compiled functions bundled in
  :class:`Steps` (``radau.py``, ``rodas.py``), which :data:`_GENERIC_STEPS` puts in the
  lanes' step contract:

``start(problem, t0, y0, f0, counters) -> state``
    The method's arrays and scalars (a tuple it alone reads), made once, at ``(t0, y0)``.
``begin(state, problem, t, y, f, h_abs, min_step, counters) -> (h_abs, h_cap)``
    Prepares a step from ``(t, y)`` (RODAS4: the Jacobian and ``∂f/∂t``) and returns the size
    of its first try and the cap on every try (the methods after Hairer's codes cap at
    ``max_step``; Radau, as SciPy, clamps once, here, and not its retries).
``attempt(state, problem, t, y, f, h, y_new, counters) -> (passed, h_abs)``
    Tries the signed step ``h``: writes the new state into ``y_new`` and returns whether it
    passed the method's own tests (error test, Newton convergence); if not, the size to retry
    with, the rejection counted under its cause.
``retry(state)``
    ``step_check`` shortened the step that passed (Radau IIA: its factors are of the old
    size); :func:`no_retry` for a method that keeps nothing that depends on the step size.
``refresh(state, problem, t_new, y_new, f, changed, counters)``
    Writes ``f(t_new, y_new)`` into ``f`` after ``after_step`` (``changed``: it declared a
    discontinuity); :func:`evaluate_f` for a method without a last stage to reuse.
``accept(state, problem, t, y, t_new, y_new, f, h_abs, failed, changed, counters) -> h_abs``
    Takes the accepted step into the method's state and returns the next step's size
    (``failed``: a try of this step had failed the method's tests).

Statuses, counters and the hooks' contract are
:func:`jointplay._kernels.radau.radau_integrate`'s; the results are those of the loop this
module had until 2026-11-30 (its own copy of the same control), to the bit.

Compilation: the methods' functions reach the loop as compile-time constants, not as
values. Numba keys a dispatcher passed as an argument (or held in a closure or a tuple) by the
object's address, which a new process never finds again in the on-disk cache; a call to a
global function it caches. So each method gets its own copy of the loop and of
:func:`drive`, the entry (``<name>_core``), whose globals are the method's :class:`Steps`
(:func:`_core`). The entry is compiled for explicit signatures, one per type of ``args``
(:func:`kernel_signatures`), and cached on disk as ``driver.<name>_core-<line>.py3X.nbi``;
the user's jitted functions reach it as first-class function values
(``numba.types.FunctionType``), converted at the call (so :func:`run_core` is called from
Python, not from compiled code). An edit of a kernel source clears the caches
(:func:`jointplay._kernels.drop_stale_caches`).

References:
    .. [HW96] E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II: Stiff and
       Differential-Algebraic Problems*, 2nd ed., Springer, 1996, §IV.8.
    .. [SciPy] P. Virtanen et al., "SciPy 1.0", *Nature Methods* 17, 261–272 (2020);
       ``scipy/integrate/_ivp/ivp.py`` and ``base.py``.
"""

from __future__ import annotations

import functools
import importlib
import importlib.util
import threading
from collections.abc import Callable
from typing import Any, NamedTuple

import numba
import numpy as np
import numpy.typing as npt

from jointplay._kernels.common import all_finite, copy_vector, jit, py_min, select_initial_step
from jointplay._kernels.ids import (
    EPS,
    K_REJ_CHECK,
    K_REJECTED,
    K_RHS,
    K_STEPS,
    N_TRACE_COUNTS,
    NFEV,
    NREJ_CHECK,
    NREJ_ERROR,
    NSTEPS,
    STATUS_NON_FINITE,
    STATUS_RUNNING,
    STATUS_SUCCESS,
)
from jointplay._kernels.lanes import build
from jointplay._kernels.lanes.contract import NO_INTERRUPT
from jointplay._kernels.lanes.cpu import compiled as _lanes
from jointplay._kernels.lanes.source import LY_SIZE, MAX_CHECK_REJECTIONS, N_LAY
from jointplay._kernels.lanes.source_radau import radau_land

__all__ = [
    "MAX_CHECK_REJECTIONS",
    "NO_INTERRUPT",
    "Problem",
    "Steps",
    "accept_every_step",
    "drive",
    "evaluate_f",
    "finite_differences",
    "kernel_signatures",
    "no_after_step",
    "no_retry",
    "run_core",
    "step_jit",
    "steps_of",
]

#: The decorator of a method's per-step functions (``begin``, ``attempt``, ``retry``,
#: ``refresh``, ``accept``): compiled and cached as :data:`~jointplay._kernels.common.jit`,
#: and inlined into the loop (Numba's IR inlining), as that code was inline in each method's
#: own driver before there was one loop.
step_jit = numba.njit(cache=True, error_model="numpy", inline="always")


class Problem(NamedTuple):
    """What every method's step reads of the problem (built by :func:`drive`)."""

    fun: Any  # f(t, y, args) -> float64[:]
    jac: Any  # jac(t, y, f, args, out) -> bool (False: difference f)
    args: Any  # the user's tuple of arrays
    rtol: float  # relative tolerance, at least 100·eps
    atol: Any  # absolute tolerances, (n,)
    max_step: float  # largest step size, s
    direction: float  # +1 forwards in t, −1 backwards
    n_second: int  # positions with x' = v (see radau_integrate)
    n_active: int  # components [n_active, n) are passive
    hold_after_failure: bool  # no growth right after a failed try
    autonomous: bool  # f does not depend on t
    step_check: Any  # step_check(t, y, t_new, y_new, args) -> θ (the onset retry)
    after_step: Any  # after_step(t, y, args) -> changed
    t0: float  # the start
    f0: Any  # f(t0, y0), (n,), as the loop holds it (its steps' time: see _core)
    h0: float  # the first step's size


class Steps(NamedTuple):
    """A method's compiled step functions (module docstring): what :func:`drive` calls."""

    start: Any
    begin: Any
    attempt: Any
    retry: Any
    refresh: Any
    accept: Any


# ---------------------------------------------------------------------------------------
# Default hooks.
# ---------------------------------------------------------------------------------------
@jit
def accept_every_step(t_old, y_old, t_new, y_new, args):
    """``step_check`` that accepts every step (returns 1.0)."""
    return 1.0


@jit
def no_after_step(t, y, args):
    """``after_step`` that changes nothing (returns False)."""
    return False


@jit
def finite_differences(t, y, f, args, out):
    """``jac`` that provides no Jacobian (returns False): the kernel differences ``fun``."""
    return False


# ---------------------------------------------------------------------------------------
# Pieces of the loop that a method may reuse.
# ---------------------------------------------------------------------------------------
@step_jit
def no_retry(state):
    """``retry`` of a method that keeps nothing that depends on the step size."""
    return None


@step_jit
def evaluate_f(state, problem, t_new, y_new, f, changed, counters):
    """``refresh`` of a method without a last stage to reuse: ``f = fun(t_new, y_new)``."""
    f[:] = problem.fun(t_new, y_new, problem.args)
    counters[NFEV] += 1


#: Store ``(t, y)`` as row ``m`` of the record, doubling its arrays first when they are full
#: (the lane source's ``trace_add``, the traced lanes' record); its first row
#: (``trace_start``).
_record = _lanes["trace_add"]
_record_start = _lanes["trace_start"]


@jit
def driver_start(fun, args, t0, y0, t_bound, max_step, first_step, direction, rtol, atol):
    """What the loop does before the first step: record ``(t0, y0)``; an empty interval or
    system ends at once (SciPy: an empty system jumps to ``t_bound``); ``f(t0, y0)``, a
    non-finite one ends with status −3; the first step, ``first_step`` or SciPy's choice
    (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4).

    Returns:
        ``(status, counters, ts, ys, m, f, h_abs)``: ``STATUS_RUNNING`` to go on, else the
        final status of an integration that ends here; the recording arrays and their
        length ``m``.
    """
    n = y0.shape[0]
    counters = np.zeros(7, dtype=np.int64)
    ts, ys = _record_start(t0, y0, n)
    m = 1
    f = np.zeros(n)
    if n == 0 or t0 == t_bound:
        if n == 0 and t0 != t_bound:  # SciPy: an empty system jumps to t_bound.
            ts, ys = _record(ts, ys, m, t_bound, y0, n)
            m += 1
        return STATUS_SUCCESS, counters, ts, ys, m, f, 0.0
    f = copy_vector(fun(t0, y0, args))
    counters[NFEV] += 1
    if not (all_finite(y0, y0.shape[0]) and all_finite(f, f.shape[0])):
        return STATUS_NON_FINITE, counters, ts, ys, m, f, 0.0
    h_abs = first_step
    if not first_step > 0:
        h_abs, nfev_initial = select_initial_step(
            fun, args, t0, y0, t_bound, max_step, f, direction, rtol, atol
        )
        counters[NFEV] += nfev_initial
    return STATUS_RUNNING, counters, ts, ys, m, f, h_abs


# ---------------------------------------------------------------------------------------
# The loop: the lanes' (source.lane), with adapters for a user's problem.
# ---------------------------------------------------------------------------------------
# The lane source's functions that the loop calls and that read a mechanism (its ``rp``),
# in the generic problem's terms: ``rp`` is the :class:`Problem`; lane time is ``direction·t``
# (so that the loop, which runs forwards, integrates backwards too: exact, a sign).
def problem_start_time(rp):
    """The lane time of ``t0``."""
    return rp.direction * rp.t0


def problem_outputs(ip, rp, lay, mask, peaks, stats, counts):
    """No peaks: the counters zero."""
    for m in range(counts.shape[0]):
        counts[m] = 0


def problem_start_f(t, y, rp, ip, lay, f, record, qty, pen, phi_q, schur, lam):
    """f at the start: :func:`driver_start`'s evaluation (counted there)."""
    for j in range(f.shape[0]):
        f[j] = rp.f0[j]


def problem_rhs(t, y, rp, ip, lay, f, record, recording, phi_q, schur, lam):
    """The user's ``fun`` in lane time (the lanes' steps): ``direction·fun(direction·t, y)``."""
    value = rp.fun(rp.direction * t, y, rp.args)
    for j in range(f.shape[0]):
        f[j] = rp.direction * value[j]


def problem_rhs_and_quantities(t, y, rp, ip, lay, f, record, qty, pen, phi_q, schur, lam):
    """:func:`problem_rhs` (no quantities: the window never opens)."""
    value = rp.fun(rp.direction * t, y, rp.args)
    for j in range(f.shape[0]):
        f[j] = rp.direction * value[j]


def problem_first_step(ws, t, y, f, t_end, max_step, rtol, atol, rp, ip, lay, pen, f_mid,
                       record_mid, phi_q, schur, lam, counts):  # fmt: skip
    """The first step's size (:func:`driver_start`'s): every method's ``step_start``."""
    return rp.h0


def problem_step_check(t, y, t_new, y_new, old, new, rp, lay):
    """The user's ``step_check`` on the step, in its time."""
    return rp.step_check(rp.direction * t, y, rp.direction * t_new, y_new, rp.args)


def problem_after_step(t, y, rp, ip, lay, scratch, phi_q, schur, lam):
    """The user's ``after_step`` at the accepted end, in its time."""
    return rp.after_step(rp.direction * t, y, rp.args)


def no_contact(*unused):
    """A contact or running hook of the mechanism's loop: nothing for a user's problem."""
    return None


def no_flag(*unused):
    """A contact hook's question (locked joints, sustained contact, contact memory): no."""
    return False


def no_release(t, y, t_new, y_new, rp, ip, lay):
    """No locked joint to release: the whole step."""
    return 1.0


def no_penetration(y, rp, ip, lay, c):
    """No contact."""
    return 0.0, 0.0


#: The adapters by the lane source's names (:func:`jointplay._kernels.lanes.build.build`'s
#: ``hooks``).
ADAPTERS: dict[str, Callable[..., Any]] = {
    "start_time": problem_start_time, "start_outputs": problem_outputs,
    "start_rhs": problem_start_f, "rhs": problem_rhs,
    "rhs_and_quantities": problem_rhs_and_quantities, "onset_check": problem_step_check,
    "project": problem_after_step, "release_fraction": no_release,
    "penetration_and_rate": no_penetration,
    **dict.fromkeys(("locked", "contact_memory", "sustained_on", "switch_contacts"), no_flag),
    **dict.fromkeys(("quantities", "speed_deviation", "running_point", "open_regimes",
                     "accumulate_regimes", "close_running"), no_contact),
}  # fmt: skip

# The method's functions (:class:`Steps`), bound in each method's copy of the steps below
# (:func:`_core`); ``None`` here, as those are never compiled as written.
START: Any = None
BEGIN: Any = None
ATTEMPT: Any = None
RETRY: Any = None
REFRESH: Any = None
ACCEPT: Any = None
#: Slots of the loop's scalars in the steps' work (``ws[2]``): the cap on every try
#: (:class:`Steps`' ``begin``), whether a try of this step failed the method's tests, the
#: step's start (in the user's time).
G_CAP, G_FAILED, G_T = range(3)


# A method's :class:`Steps` in the lanes' step contract (``source.lane``'s docstring): ``ws``
# is ``(state, problem, scalars, counters, y_start)``; the loop's times are lane times.
def generic_work(problem, t0, y0, f0, counters, lay):
    """The steps' ``ws``: the method's ``start`` and the wrappers' own."""
    return (START(problem, t0, y0, f0, counters), problem, np.zeros(3), counters,
            np.empty(y0.shape[0]))  # fmt: skip


def lane_work(problem, t0, y0, f0, counters, lay):
    """The lanes' own steps' ``ws``: their work allocator's."""
    return STEP_WORK(lay)


def generic_begin(ws, t, y, f, h, max_step, min_step, rtol, atol, size):
    """The method's ``begin``; the first try at most its cap."""
    state, problem, sc, counters, y_start = ws
    sc[G_T] = problem.direction * t
    sc[G_FAILED] = 0.0
    for j in range(size):
        y_start[j] = y[j]
    h_abs, cap = BEGIN(state, problem, sc[G_T], y, f, h, min_step, counters)
    sc[G_CAP] = cap
    return py_min(h_abs, cap)


def generic_attempt(ws, t, y, f, h, t_new, y_new, t_old, y_old, rtol, atol, rp, ip, lay,
                    record_new, qb, pen, f_mid, record_mid, phi_q, schur, lam, counts):  # fmt: skip
    """The method's ``attempt`` of the signed step; a retry at most the cap."""
    state, problem, sc, counters, _ = ws
    passed, h_abs = ATTEMPT(state, problem, sc[G_T], y, f, problem.direction * h, y_new,
                            counters)  # fmt: skip
    if not passed:
        sc[G_FAILED] = 1.0
        return False, py_min(h_abs, sc[G_CAP])
    return True, h


def generic_retry(ws):
    """The method's ``retry``."""
    RETRY(ws[0])


def generic_refresh(ws, t_new, y_new, f_new, changed, rp, ip, lay, record, qb, pen, phi_q,
                    schur, lam, counts):  # fmt: skip
    """The method's ``refresh``: f at the accepted end."""
    REFRESH(ws[0], ws[1], ws[1].direction * t_new, y_new, f_new, changed, ws[3])
    return True


def generic_accept(ws, t_new, y_new, f_new, h, changed, atol, rp, ip, lay, pen, f_mid,
                   record_mid, phi_q, schur, lam, counts):  # fmt: skip
    """The method's ``accept``: the next step's size."""
    state, problem, sc, counters, y_start = ws
    return ACCEPT(state, problem, sc[G_T], y_start, problem.direction * t_new, y_new, f_new, h,
                  sc[G_FAILED] > 0.0, changed, counters)  # fmt: skip


def generic_dense(ws, t_old, y_old, t, y, f, t_new, y_new, f_new, h, tau, theta, out, lay):
    """No interpolant: the loop's window never opens for a user's problem."""
    return None


#: The steps in the loop's order (``build.STEPS``); the landing is Radau IIA's lane's (SciPy's:
#: the step is the difference of its ends).
_GENERIC_STEPS: tuple[Callable[..., Any], ...] = (
    problem_first_step, generic_begin, radau_land, generic_attempt, generic_retry, generic_refresh,
    generic_accept, generic_dense,
)  # fmt: skip
#: The loop's constants for a user's problem: no landing on a window that never opens, no
#: regimes, SciPy's floor on rtol, the trajectory recorded (no running responses: the
#: source's default).
_LOOP_CONSTANTS = {"LAND_SETTLE": False, "REGIMES": False, "RTOL_FLOOR": 100.0 * EPS,
                   "RECORD": True}  # fmt: skip
LANE: Any = None  # the loop with the method's steps, bound in each method's entry
WORK: Any = None  # the steps' work: generic_work or lane_work, bound in each method's entry
STEP_WORK: Any = None  # the lanes' own steps' work allocator, bound in lane_work's copy
#: Whether the method's steps are the lanes' own, in lane time (bound in each entry).
ON_LANE_STEPS = False


def drive(fun, step_check, after_step, jac_fun, t0, y0, t_bound, args, rtol, atol,
          max_step, first_step, max_steps, n_second, n_active, hold_after_failure, autonomous,
          interrupt):  # fmt: skip
    """Integrate ``y' = fun(t, y, args)`` from ``t0`` to ``t_bound`` by the lanes' loop
    (``source.lane``) with the method whose :class:`Steps` are this copy's ``LANE``'s
    (:func:`_core`); the arguments and the results are
    :func:`jointplay._kernels.radau.radau_integrate`'s (times in the units of ``t0``).

    Before the loop: :func:`driver_start` (``f(t0, y0)``, the first step) and the method's
    ``start``. The loop owns the step budget ``max_steps``, the interrupt flags, the tries
    (cut to end on ``t_bound``) until one passes the method's ``attempt`` and ``step_check``
    does not shorten it, a step below ``min_step = 10·spacing(t)`` (SciPy's) ending the
    integration with status −1, ``after_step`` (its hook ``project``), ``f`` at the new point
    (the method's ``refresh``), the finiteness of both, the method's ``accept`` and the record.
    """
    n = y0.shape[0]
    rtol = max(rtol, 100.0 * EPS)
    direction = 1.0 if t_bound >= t0 else -1.0
    y = y0.copy()
    status, counters, ts, ys, m, f, h_abs = driver_start(
        fun, args, t0, y, t_bound, max_step, first_step, direction, rtol, atol
    )
    if status != STATUS_RUNNING:
        return status, ts[:m].copy(), ys[:m].copy(), counters
    # the loop's f is in its steps' time: the user's for Steps, lane time for the lanes' own
    f_loop = direction * f if ON_LANE_STEPS else f
    problem = Problem(fun, jac_fun, args, rtol, atol, max_step, direction, n_second, n_active,
                      hold_after_failure, autonomous, step_check, after_step, t0, f_loop,
                      h_abs)  # fmt: skip
    lay = np.zeros(N_LAY, dtype=np.int64)
    lay[LY_SIZE] = n
    ws = WORK(problem, t0, y, f, counters, lay)
    counts = np.zeros(N_TRACE_COUNTS, dtype=np.int64)
    one = np.zeros(1)
    t_end = direction * t_bound
    status, _, times, states = LANE(
        np.zeros(1, dtype=np.int64), problem, lay, y, np.inf, t_end, max_step, rtol, atol,
        max_steps, interrupt, one, one, counts, np.zeros(1, dtype=np.int64), np.empty((9, n)),
        np.zeros((2, 1)), np.zeros((9, 1)), np.zeros((2, 1)), np.zeros((3, 1)),
        np.zeros((1, 1)), np.zeros((1, 1)), one, one, ws,
    )  # fmt: skip
    counters[NSTEPS] = counts[K_STEPS]
    counters[NREJ_CHECK] = counts[K_REJ_CHECK]
    # the lanes' own steps count in the loop's counters (Steps count their own: these add 0);
    # the start's evaluation is driver_start's
    counters[NFEV] += counts[K_RHS] - 1
    counters[NREJ_ERROR] += counts[K_REJECTED] - counts[K_REJ_CHECK]
    return status, direction * times, states.copy(), counters


# ---------------------------------------------------------------------------------------
# Entry points: one cached specialisation per method and type of ``args``.
# ---------------------------------------------------------------------------------------
_ARRAY = numba.types.float64[::1]
_compile_lock = threading.Lock()
_entries: dict[str, Any] = {}
_specialisations: dict[Any, Any] = {}


def kernel_signatures(args_type: Any) -> dict[str, Any]:
    """Numba signatures that the user's functions must compile to, for this ``args`` type.

    Args:
        args_type: ``numba.typeof(args)``.

    Returns:
        ``{"fun": ..., "step_check": ..., "after_step": ..., "jac": ...}``. ``fun`` may
        return any 1-D float64 array (any layout); every ``y`` it is given is C-contiguous;
        ``jac`` writes into a C-contiguous (n, n) array.
    """
    f8 = numba.types.float64
    return {
        "fun": numba.types.float64[:](f8, _ARRAY, args_type),
        "step_check": f8(f8, _ARRAY, f8, _ARRAY, args_type),
        "after_step": numba.types.boolean(f8, _ARRAY, args_type),
        "jac": numba.types.boolean(f8, _ARRAY, _ARRAY, args_type, numba.types.float64[:, ::1]),
    }


def _core_signature(args_type: Any) -> tuple[Any, ...]:
    """Argument types of a method's entry for this ``args`` type."""
    sigs = kernel_signatures(args_type)
    f8 = numba.types.float64
    i8 = numba.types.int64
    function_type = numba.types.FunctionType
    return (
        function_type(sigs["fun"]),
        function_type(sigs["step_check"]),
        function_type(sigs["after_step"]),
        function_type(sigs["jac"]),
        f8, _ARRAY, f8, args_type, f8, _ARRAY, f8, f8, i8, i8, i8,
        numba.types.boolean, numba.types.boolean, numba.types.uint8[::1],
    )  # fmt: skip


def _core(name: str, steps: Steps | dict[str, Any]) -> Any:
    """Method ``name``'s entry: a copy of :func:`drive` named ``<name>_core`` (its cache
    files' name) whose ``LANE`` is the lanes' loop with ``steps`` in the lanes' contract
    (:data:`_GENERIC_STEPS` bound to ``steps``' functions, inlined) and the adapters
    (:data:`ADAPTERS`) for the mechanism's hooks."""
    entry = _entries.get(name)
    if entry is None:
        bound = {**_namespace(), **_LOOP_CONSTANTS}
        if isinstance(steps, Steps):
            method = {field.upper(): function for field, function in steps._asdict().items()}
            bound.update(method)
            for alias, function in zip(build.STEPS, _GENERIC_STEPS, strict=True):
                bound[f"step_{alias}"] = step_jit(
                    build.rebound(function, {**globals(), **method}, f"{function.__name__}_{name}")
                )
            method["WORK"] = step_jit(build.rebound(generic_work, {**globals(), **method},
                                                    f"generic_work_{name}"))  # fmt: skip
        else:  # a lane record: the lanes' own steps, in lane time, the start driver_start's
            for alias in build.STEPS:
                function = (problem_first_step if alias == "start"
                            else build.source_function(f"{steps['steps']}_{alias}"))  # fmt: skip
                bound[f"step_{alias}"] = step_jit(
                    build.rebound(function, bound, f"{function.__name__}_{name}_generic")
                )
            own = {**globals(), "STEP_WORK": bound[steps["work"]]}
            method = {"WORK": step_jit(build.rebound(lane_work, own, f"lane_work_{name}")),
                      "ON_LANE_STEPS": True}  # fmt: skip
        lane = jit(build.rebound(build.source_function("lane"), bound, f"lane_{name}"))
        entry = build.rebound(drive, {**drive.__globals__, **method, "LANE": lane}, f"{name}_core")
        entry.__doc__ = f"The loop (:func:`drive`) with {name}'s steps."
        _entries[name] = entry
    return entry


def _namespace() -> dict[str, Any]:
    """The lane source compiled for a user's problem (once): the functions the loop calls,
    the mechanism's hooks replaced by :data:`ADAPTERS`."""
    if "" not in _entries:
        direct = [name for name in build.source_function("lane").__code__.co_names
                  if name in build.FUNCTIONS]  # fmt: skip
        for record in _lane_records():  # and the lanes' own steps that the generic runs
            direct += [f"{record['steps']}_{step}" for step in build.STEPS] + [record["work"]]
        only = {*build.closed(tuple(n for n in direct if n not in ADAPTERS)), *ADAPTERS}
        _entries[""] = build.build(jit, hooks=ADAPTERS, extras={"np": np},
                                   only=tuple(only), tag="generic")  # fmt: skip
    namespace: dict[str, Any] = _entries[""]
    return namespace


def _specialised_core(args_type: Any, name: str, steps: Steps | dict[str, Any]) -> Any:
    """Method ``name``'s entry compiled, or loaded from Numba's on-disk cache, for this
    type of ``args``.

    One dispatcher per method and ``args`` type, each compiled only for its explicit
    signature, so that Numba, unable to compile at call time, converts each jitted function
    passed in to its first-class function type (compiling it for that signature if needed)
    instead of specialising the entry on the function object, which could not be cached.
    """
    key = (name, args_type)
    core = _specialisations.get(key)
    if core is None:
        with _compile_lock:
            core = _specialisations.get(key)
            if core is None:
                core = numba.njit(
                    [_core_signature(args_type)], cache=True, error_model="numpy", nogil=True
                )(_core(name, steps))  # nogil: the batch engine runs implicit lanes on threads
                _specialisations[key] = core
    return core


@functools.cache  # called by every integrate: the module search once
def steps_of(module: str) -> Steps | dict[str, Any]:
    """The steps of an :attr:`~jointplay._kernels.integrators.Integrator.module`: the
    :class:`Steps` of that :mod:`jointplay._kernels` module (Radau IIA, RODAS4), or, where no
    such module is and the lane source holds the method's steps under that prefix (DOPRI5),
    the lane's record (``build.LANES``): the loop runs the lanes' own steps."""
    if importlib.util.find_spec(f"jointplay._kernels.{module}") is not None:
        steps: Steps = importlib.import_module(f"jointplay._kernels.{module}").STEPS
        return steps
    for record in _lane_records():
        if record["steps"] == module:
            return record
    raise ValueError(f"no integrator's steps are called {module!r}")


@functools.cache
def _lane_records() -> tuple[dict[str, Any], ...]:
    """The lane records whose steps the generic integrate runs: the integrators in it
    (``module`` set) that no kernel module of their own holds :class:`Steps` for."""
    return tuple(
        record
        for record in build.LANES.values()
        if record["integrator"]["module"] is not None
        and importlib.util.find_spec(f"jointplay._kernels.{record['integrator']['module']}") is None
    )


def run_core(
    name: str,
    steps: Steps | dict[str, Any],
    fun: Any,
    step_check: Any,
    after_step: Any,
    t0: float,
    y0: npt.NDArray[np.float64],
    t_bound: float,
    args: tuple[npt.NDArray[Any], ...],
    rtol: float,
    atol: npt.NDArray[np.float64],
    max_step: float,
    first_step: float,
    max_steps: int,
    n_second: int = 0,
    n_active: int | None = None,
    hold_after_failure: bool = False,
    jac: Any = None,
    autonomous: bool = False,
    interrupt: npt.NDArray[np.uint8] | None = None,
) -> tuple[int, npt.NDArray[np.float64], npt.NDArray[np.float64], npt.NDArray[np.int64]]:
    """Run the loop with method ``name``'s ``steps``: coerce the scalars and arrays to the
    compiled types and call its entry's specialisation for ``numba.typeof(args)``. The
    arguments after ``steps`` are :func:`jointplay._kernels.radau.radau_integrate`'s."""
    core = _specialised_core(numba.typeof(args), name, steps)
    n = np.shape(y0)[0]
    n_active = n if n_active is None else int(n_active)
    if not 0 <= 2 * n_second <= n_active <= n:
        raise ValueError(
            f"need 0 <= 2·n_second <= n_active <= n = {n}, got {n_second} and {n_active}"
        )
    status, t_out, y_out, counters = core(
        fun,
        step_check,
        after_step,
        finite_differences if jac is None else jac,
        float(t0),
        np.array(y0, dtype=np.float64, order="C"),
        float(t_bound),
        args,
        float(rtol),
        np.array(atol, dtype=np.float64, order="C"),
        float(max_step),
        float(first_step),
        int(max_steps),
        int(n_second),
        n_active,
        bool(hold_after_failure),
        bool(autonomous),
        NO_INTERRUPT if interrupt is None else interrupt,
    )
    return int(status), t_out, y_out, counters
