"""The one integrator loop of the single engine: budget, interrupt, step tries, onset retry,
hooks, finiteness and recording, for every method (Radau IIA, RODAS4, DOPRI5).

The shape is SciPy's ``solve_ivp`` loop around an ``OdeSolver._step_impl`` (and diffrax's
``_integrate.py``): :func:`drive` owns what every variable-step method does around its step,
and a method brings only its step, as compiled functions bundled in :class:`Steps`:

``start(problem, t0, y0, f0, counters) -> state``
    The method's arrays and scalars (a tuple it alone reads), made once, at ``(t0, y0)``.
``begin(state, problem, t, y, f, h_abs, min_step, counters) -> (h_abs, h_cap)``
    Prepares a step from ``(t, y)`` (RODAS4: the Jacobian and ``∂f/∂t``) and returns the size
    of its first try and the cap that :func:`drive` puts on every try (the methods after
    Hairer's codes cap at ``max_step``; Radau, as SciPy, clamps once, here, and not its retries).
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

A new integrator is therefore one file: its tableau and these functions. Between
``attempt`` and ``accept`` the loop alone asks ``step_check`` (contact onset: the step is
retried shorter) and calls ``after_step``; a non-finite state or ``f`` after a step ends the
integration with status −3.

``problem`` (:class:`Problem`) holds the user's functions and options, the same for every
method. Statuses, counters and the hooks' contract are
:func:`jointplay._kernels.radau.radau_integrate`'s.

Compilation: the methods' functions reach the loop as compile-time constants, not as
values. Numba keys a dispatcher passed as an argument (or held in a closure or a tuple) by the
object's address, which a new process never finds again in the on-disk cache; a call to a
global function it caches. So each method gets its own copy of :func:`drive`: the same code
under the name ``<name>_core``, whose globals ``START`` … ``ACCEPT`` are the method's
:class:`Steps` (:func:`_core`). That copy is compiled for explicit signatures, one per type of
``args`` (:func:`kernel_signatures`), and cached on disk as ``driver.<name>_core-<line>.py3X.nbi``;
the user's jitted functions reach it as first-class function values
(``numba.types.FunctionType``), converted at the call (so :func:`run_core` is called from
Python, not from compiled code). Numba's cache does not follow the functions a compiled
function calls: after editing a method's file, clear the caches (the README's
``find src -name "*.nb[ic]" -delete``), as after editing :mod:`jointplay._kernels.common`.

References:
    .. [HW96] E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II: Stiff and
       Differential-Algebraic Problems*, 2nd ed., Springer, 1996, §IV.8.
    .. [SciPy] P. Virtanen et al., "SciPy 1.0", *Nature Methods* 17, 261–272 (2020);
       ``scipy/integrate/_ivp/ivp.py`` and ``base.py``.
"""

from __future__ import annotations

import importlib
import threading
import types
from typing import Any, NamedTuple

import numba
import numpy as np
import numpy.typing as npt

from jointplay._kernels.common import (
    all_finite,
    copy_vector,
    interrupt_pending,
    jit,
    py_min,
    select_initial_step,
)
from jointplay._kernels.ids import (
    EPS,
    NFEV,
    NREJ_CHECK,
    NSTEPS,
    STATUS_INTERRUPTED,
    STATUS_NON_FINITE,
    STATUS_RUNNING,
    STATUS_STEP_TOO_SMALL,
    STATUS_SUCCESS,
    STATUS_TOO_MANY_STEPS,
)
from jointplay._kernels.lanes.cpu import compiled as _lanes

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

#: Consecutive ``step_check`` rejections of one step after which the step is accepted.
MAX_CHECK_REJECTIONS = 64

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


@numba.njit(cache=True, error_model="numpy", inline="always")  # in the loop
def onset_retry(step_check, args, t, y, t_new, y_new, h_abs, min_step, n_check):
    """``step_check``'s verdict on a step that passed the method's tests: the shorter step
    to retry it with (it asks for ``h·θ``, ``θ < 1``, not below ``min_step``, and this step
    has been retried fewer than ``MAX_CHECK_REJECTIONS`` times), else 0 (accept)."""
    theta = step_check(t, y, t_new, y_new, args)
    h_try = h_abs * theta
    if theta < 1.0 and min_step <= h_try < h_abs and n_check < MAX_CHECK_REJECTIONS:
        return h_try
    return 0.0


# ---------------------------------------------------------------------------------------
# The loop.
# ---------------------------------------------------------------------------------------
# The method's functions, bound in each method's copy of the loop (:func:`_core`); ``None``
# here, as :func:`drive` itself is never compiled. They are globals, not an argument: Numba
# caches a call to a global function, not a function held as a value (a dispatcher's address).
START: Any = None
BEGIN: Any = None
ATTEMPT: Any = None
RETRY: Any = None
REFRESH: Any = None
ACCEPT: Any = None


def drive(fun, step_check, after_step, jac_fun, t0, y0, t_bound, args, rtol, atol,
          max_step, first_step, max_steps, n_second, n_active, hold_after_failure, autonomous,
          interrupt):  # fmt: skip
    """Integrate ``y' = fun(t, y, args)`` from ``t0`` to ``t_bound`` with the method whose
    :class:`Steps` are this copy's globals ``START`` … ``ACCEPT`` (:func:`_core`); the
    arguments and the results are :func:`jointplay._kernels.radau.radau_integrate`'s (times
    in the units of ``t0``).

    Per step: the step budget ``max_steps`` and the interrupt flags; the method's
    ``begin``; tries of size ``h`` (cut to end on ``t_bound``) until one passes the
    method's ``attempt`` and ``step_check`` does not shorten it, a step below
    ``min_step = 10·spacing(t)`` (SciPy's) ending the integration with status −1; then
    ``after_step``, ``f`` at the new point (the method's ``refresh``), the finiteness of
    both, the method's ``accept`` (the next step's size) and the record.
    """
    n = y0.shape[0]
    rtol = max(rtol, 100.0 * EPS)
    direction = 1.0 if t_bound >= t0 else -1.0
    t = t0
    y = y0.copy()
    status, counters, ts, ys, m, f, h_abs = driver_start(
        fun, args, t0, y, t_bound, max_step, first_step, direction, rtol, atol
    )
    if status != STATUS_RUNNING:
        return status, ts[:m].copy(), ys[:m].copy(), counters
    problem = Problem(fun, jac_fun, args, rtol, atol, max_step, direction, n_second, n_active,
                      hold_after_failure, autonomous)  # fmt: skip
    state = START(problem, t, y, f, counters)
    y_new = np.empty(n)

    while status == STATUS_RUNNING:
        if counters[NSTEPS] >= max_steps:
            status = STATUS_TOO_MANY_STEPS
            break
        if interrupt_pending(interrupt):  # Ctrl-C or SIGTERM: stop with a status, not raise
            status = STATUS_INTERRUPTED
            break

        min_step = 10.0 * abs(np.nextafter(t, direction * np.inf) - t)
        h_abs, h_cap = BEGIN(state, problem, t, y, f, h_abs, min_step, counters)
        failed = False  # a try failed the method's tests (RADAU5's REJECT)
        n_check = 0
        t_new = t
        while True:
            h_abs = py_min(h_abs, h_cap)
            if h_abs < min_step:
                status = STATUS_STEP_TOO_SMALL
                break
            t_new = t + h_abs * direction
            if direction * (t_new - t_bound) > 0:
                t_new = t_bound
            h = t_new - t
            h_abs = abs(h)

            passed, h_retry = ATTEMPT(state, problem, t, y, f, h, y_new, counters)
            if not passed:
                h_abs = h_retry
                failed = True
                continue

            h_try = onset_retry(step_check, args, t, y, t_new, y_new, h_abs, min_step, n_check)
            if h_try > 0.0:  # land a step on contact onset
                h_abs = h_try
                n_check += 1
                counters[NREJ_CHECK] += 1
                RETRY(state)
                continue
            break
        if status != STATUS_RUNNING:
            break

        # Hook: projection / contact memory; then f at the (possibly modified) state.
        changed = after_step(t_new, y_new, args)
        REFRESH(state, problem, t_new, y_new, f, changed, counters)
        if not (all_finite(y_new, n) and all_finite(f, n)):
            status = STATUS_NON_FINITE
            break
        h_abs = ACCEPT(state, problem, t, y, t_new, y_new, f, h_abs, failed, changed, counters)
        t = t_new
        y, y_new = y_new, y
        counters[NSTEPS] += 1
        ts, ys = _record(ts, ys, m, t, y, n)
        m += 1
        if direction * (t - t_bound) >= 0:
            status = STATUS_SUCCESS

    return status, ts[:m].copy(), ys[:m].copy(), counters


# ---------------------------------------------------------------------------------------
# Entry points: one cached specialisation per method and type of ``args``.
# ---------------------------------------------------------------------------------------
_ARRAY = numba.types.float64[::1]
_compile_lock = threading.Lock()
#: Flags that never hold a signal: what a loop is given when nothing watches (off the main
#: thread, :func:`jointplay.execution.interrupts.interrupts_watched` yields ``None``).
NO_INTERRUPT = np.zeros(1, dtype=np.uint8)
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


def _core(name: str, steps: Steps) -> Any:
    """Method ``name``'s entry: a copy of :func:`drive` named ``<name>_core`` (its cache
    files' name) whose globals ``START`` … ``ACCEPT`` are ``steps``'s functions."""
    entry = _entries.get(name)
    if entry is None:
        method = {field.upper(): function for field, function in steps._asdict().items()}
        entry = types.FunctionType(drive.__code__, {**drive.__globals__, **method}, f"{name}_core")
        entry.__qualname__ = f"{name}_core"
        entry.__doc__ = f"The loop (:func:`drive`) with {name}'s steps."
        _entries[name] = entry
    return entry


def _specialised_core(args_type: Any, name: str, steps: Steps) -> Any:
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


def steps_of(module: str) -> Steps:
    """The :class:`Steps` of the method in :mod:`jointplay._kernels` module ``module`` (an
    :attr:`~jointplay._kernels.integrators.Integrator.module`)."""
    steps: Steps = importlib.import_module(f"jointplay._kernels.{module}").STEPS
    return steps


def run_core(
    name: str,
    steps: Steps,
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
