"""The generic ``jointplay.integrate`` on the one integrator loop: a user's ODE, its hooks and
an integrator's own steps run by the lanes' loop (:func:`jointplay._kernels.lanes.source.lane`).

The loop of every engine is the lane source's: it owns the step budget, the interrupt, the
tries and their landing on ``t_bound``, the onset retry (``step_check``), the hooks after a
step (``after_step``), finiteness and the record. The steps are every engine's too: each
integrator's ``<prefix>_*`` of the lane source (:mod:`~jointplay._kernels.lanes.source`'s
``dopri_*``, :mod:`~jointplay._kernels.lanes.source_radau`'s ``radau_*``,
:mod:`~jointplay._kernels.lanes.source_rodas`'s ``rodas_*``; the prefix is its record's
``steps``, :func:`steps_of`). This module binds them to a user's problem:

- **adapters** (:data:`ADAPTERS`) take the place of the lane source's functions that read a
  mechanism: the right-hand side is the user's ``fun``, the Jacobian the user's ``jac`` or the
  source's differences of ``fun`` (:func:`problem_jacobian`), the onset check calls the user's
  ``step_check``, the projection its ``after_step``; the first step, the growth limit after a
  failure and the dependence on t are the user's options; the contact forces, the contact
  memory, the sustained-contact mode, the window's quantities and the running responses do
  nothing (the window never opens: ``t_settle`` is infinite). ``rp`` is the :class:`Problem`:
  the user's functions as first-class function values, its ``args`` and options.
- **structure**: ``lay`` holds the state's size and the implicit methods' structure
  (``LY_SECOND`` = ``n_second``, ``LY_KEPT`` = ``n_active − n_second``), which a mechanism
  sets to its n and n.
- **time**: the loop runs forwards from :func:`problem_start_time`; its time is ``direction·t``
  and its f ``direction·fun(direction·t, y)``, so that an integration backwards is the same
  loop (signs, exact: negation commutes with IEEE rounding, so every step, Newton iterate and
  error norm is the user-time method's to the bit; the differences step in the direction of
  the user's f, as SciPy's).

Statuses, counters and the hooks' contract are :func:`run_core`'s.

Compilation: Numba keys a dispatcher passed as an argument (or held in a closure or a tuple)
by the object's address, which a new process never finds again in the on-disk cache; a call to
a global function it caches. So each method gets its own copy of the loop and of
:func:`drive`, the entry (``<name>_core``), whose globals are the method's steps
(:func:`_core`). The entry is compiled for explicit signatures, one per type of ``args``
(:func:`kernel_signatures`), and cached on disk as ``driver.<name>_core-<line>.py3X.nbi``;
the user's jitted functions reach it as first-class function values
(``numba.types.FunctionType``), converted at the call (so :func:`run_core` is called from
Python, not from compiled code). An edit of a kernel source clears the caches
(:func:`jointplay._kernels.drop_stale_caches`).

References:
    .. [HW96] E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II: Stiff and
       Differential-Algebraic Problems*, 2nd ed., Springer, 1996, §IV.7–8.
    .. [SciPy] P. Virtanen et al., "SciPy 1.0", *Nature Methods* 17, 261–272 (2020);
       ``scipy/integrate/_ivp/ivp.py``, ``base.py``, ``radau.py`` and ``common.py``.
"""

from __future__ import annotations

import functools
import threading
from collections.abc import Callable
from typing import Any, NamedTuple

import numba
import numpy as np
import numpy.typing as npt

from jointplay._kernels.ids import (
    COUNTER_NAMES,
    EPS,
    K_JAC,
    K_LU,
    K_REJ_CHECK,
    K_REJ_NEWTON,
    K_REJECTED,
    K_RHS,
    K_STEPS,
    N_TRACE_COUNTS,
    NFEV,
    NJEV,
    NLU,
    NREJ_CHECK,
    NREJ_ERROR,
    NREJ_NEWTON,
    NSTEPS,
    STATUS_SUCCESS,
)
from jointplay._kernels.lanes import build
from jointplay._kernels.lanes.contract import NO_INTERRUPT
from jointplay._kernels.lanes.source import (
    LY_KEPT,
    LY_SECOND,
    LY_SIZE,
    MAX_CHECK_REJECTIONS,
    N_LAY,
    rhs,  # resolved in the namespace: problem_rhs
)
from jointplay._kernels.lanes.source_radau import jacobian_differences  # an adapter's callee

__all__ = [
    "MAX_CHECK_REJECTIONS",
    "NO_INTERRUPT",
    "Problem",
    "accept_every_step",
    "drive",
    "finite_differences",
    "kernel_signatures",
    "no_after_step",
    "run_core",
    "step_jit",
    "steps_of",
]

# error_model="numpy": a division by zero gives inf/NaN (as in SciPy) instead of raising.
jit = numba.njit(cache=True, error_model="numpy")
#: The decorator of a method's steps in the generic loop: compiled and cached as
#: :data:`jit`, and inlined into the loop (Numba's IR inlining),
#: as the CPU lanes inline theirs.
step_jit = numba.njit(cache=True, error_model="numpy", inline="always")
_N_COUNTERS = len(COUNTER_NAMES)


class Problem(NamedTuple):
    """What the adapters read of the problem (``rp``; built by :func:`drive`)."""

    fun: Any  # f(t, y, args) -> float64[:]
    jac: Any  # jac(t, y, f, args, out) -> bool (False: difference f)
    args: Any  # the user's tuple of arrays
    direction: float  # +1 forwards in t, −1 backwards
    hold_after_failure: bool  # no growth right after a failed try
    autonomous: bool  # f does not depend on t
    step_check: Any  # step_check(t, y, t_new, y_new, args) -> θ (the onset retry)
    after_step: Any  # after_step(t, y, args) -> changed
    t0: float  # the start
    first_step: float  # the first step's size (0: SciPy's choice)
    jac_out: Any  # (n, n): where the user's jac writes ∂f/∂y


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


def problem_rhs(t, y, rp, ip, lay, f, record, recording, phi_q, schur, lam):
    """The user's ``fun`` in lane time (the lanes' steps): ``direction·fun(direction·t, y)``."""
    value = rp.fun(rp.direction * t, y, rp.args)
    for j in range(f.shape[0]):
        f[j] = rp.direction * value[j]


def problem_rhs_and_quantities(t, y, rp, ip, lay, f, record, qty, pen, phi_q, schur, lam):
    """:func:`problem_rhs` (the namespace's ``rhs``; no quantities: the window never opens)."""
    rhs(t, y, rp, ip, lay, f, record, False, phi_q, schur, lam)


def problem_jacobian(t, y, f, atol, factor, rp, ip, lay, jac, ytmp, f_col, diff, diff_new,
                     record, phi_q, schur, lam):  # fmt: skip
    """∂f/∂y in lane time (``direction·J``), rows ``m2 …`` and the kept columns into ``jac``
    (``source_radau.lane_jacobian``'s layout): the user's ``jac`` where it gives one, else
    SciPy's differences of ``fun`` (``source_radau.jacobian_differences``, stepping in the
    direction of the user's f)."""
    size = lay[LY_SIZE]
    m2 = lay[LY_SECOND]
    for j in range(size):
        diff[j] = rp.direction * f[j]  # the user's f
    rp.jac_out[:, :] = 0.0  # the user's jac may write only its non-zero entries
    if rp.jac(rp.direction * t, y, diff, rp.args, rp.jac_out):
        for i in range(m2, size):
            for j in range(m2 + lay[LY_KEPT]):
                jac[i - m2, j] = rp.direction * rp.jac_out[i, j]
    else:
        jacobian_differences(t, y, f, atol, factor, rp.direction, rp, ip, lay, jac, ytmp, f_col,
                             diff, diff_new, record, phi_q, schur, lam)  # fmt: skip


def problem_first_step(rp):
    """The user's ``first_step`` (0: SciPy's choice, the source's ``initial_step``)."""
    return rp.first_step


def problem_hold(rp):
    """The user's ``hold_after_failure``."""
    return rp.hold_after_failure


def problem_time_enters(rp, lay):
    """Unless the user declared ``fun`` autonomous."""
    return not rp.autonomous


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
    "rhs": problem_rhs, "rhs_and_quantities": problem_rhs_and_quantities,
    "first_step": problem_first_step,
    "lane_jacobian": problem_jacobian, "hold_after_failure": problem_hold,
    "time_enters": problem_time_enters, "onset_check": problem_step_check,
    "project": problem_after_step, "release_fraction": no_release,
    "penetration_and_rate": no_penetration,
    **dict.fromkeys(("locked", "contact_memory", "sustained_on", "switch_contacts", "any_film"),
                    no_flag),
    **dict.fromkeys(("contact_forces", "quantities", "speed_deviation", "running_point",
                     "open_regimes", "accumulate_regimes", "close_window", "close_running"),
                    no_contact),
}  # fmt: skip

#: The loop's constants for a user's problem: no landing on a window that never opens, no
#: regimes, SciPy's floor on rtol, the trajectory recorded (no running responses: the
#: source's default).
_LOOP_CONSTANTS = {"LAND_SETTLE": False, "REGIMES": False, "RTOL_FLOOR": 100.0 * EPS,
                   "RECORD": True}  # fmt: skip
LANE: Any = None  # the loop with the method's steps, bound in each method's entry
WORK: Any = None  # the method's work allocator, bound in each method's entry


def drive(fun, step_check, after_step, jac_fun, t0, y0, t_bound, args, rtol, atol,
          max_step, first_step, max_steps, n_second, n_active, hold_after_failure, autonomous,
          interrupt):  # fmt: skip
    """Integrate ``y' = fun(t, y, args)`` from ``t0`` to ``t_bound`` by the lanes' loop
    (``source.lane``) with the method whose steps are this copy's ``LANE``'s (:func:`_core`);
    the arguments and the results are :func:`run_core`'s (times in the units of ``t0``).

    The loop owns everything: ``f(t0, y0)`` and its finiteness, the first step (the method's
    start: ``first_step``, else SciPy's choice), the step budget ``max_steps``, the interrupt
    flags, the tries (cut to end on ``t_bound``) until one passes the method's ``attempt``
    and ``step_check`` does not shorten it, a step below ``min_step = 10·spacing(t)``
    (SciPy's) ending the integration with status −1, ``after_step`` (its hook ``project``),
    ``f`` at the new point (the method's ``refresh``), the finiteness of both, the method's
    ``accept`` and the record. Its counters become the user's.
    """
    n = y0.shape[0]
    direction = 1.0 if t_bound >= t0 else -1.0
    problem = Problem(fun, jac_fun, args, direction, hold_after_failure, autonomous, step_check,
                      after_step, t0, first_step, np.empty((n, n)))  # fmt: skip
    lay = np.zeros(N_LAY, dtype=np.int64)
    lay[LY_SIZE] = n
    lay[LY_SECOND] = n_second
    lay[LY_KEPT] = n_active - n_second
    counts = np.zeros(N_TRACE_COUNTS, dtype=np.int64)
    one = np.zeros(1)
    status, _, times, states = LANE(
        np.zeros(1, dtype=np.int64), problem, lay, y0, np.inf, direction * t_bound, max_step,
        rtol, atol, max_steps, interrupt, one, one, counts, np.zeros(1, dtype=np.int64),
        np.empty((9, n)), np.zeros((2, 1)), np.zeros((9, 1)), np.zeros((2, 1)),
        np.zeros((3, 1)), np.zeros((1, 1)), np.zeros((1, 1)), one, one, WORK(lay),
    )  # fmt: skip
    counters = np.zeros(_N_COUNTERS, dtype=np.int64)
    counters[NFEV] = counts[K_RHS]
    counters[NJEV] = counts[K_JAC]
    counters[NLU] = counts[K_LU]
    counters[NSTEPS] = counts[K_STEPS]
    counters[NREJ_ERROR] = counts[K_REJECTED] - counts[K_REJ_CHECK] - counts[K_REJ_NEWTON]
    counters[NREJ_NEWTON] = counts[K_REJ_NEWTON]
    counters[NREJ_CHECK] = counts[K_REJ_CHECK]
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


def _core(name: str) -> Any:
    """Method ``name``'s entry: a copy of :func:`drive` named ``<name>_core`` (its cache
    files' name) whose ``LANE`` is the lanes' loop with the method's own steps (its lane
    record's, :func:`steps_of`; inlined) and the adapters (:data:`ADAPTERS`) for the
    mechanism's hooks, and whose ``WORK`` is the record's work allocator."""
    entry = _entries.get(name)
    if entry is None:
        record = steps_of(name)
        bound = {**_namespace(), **_LOOP_CONSTANTS}
        for alias in build.STEPS:
            function = build.source_function(f"{record['steps']}_{alias}")
            bound[f"step_{alias}"] = step_jit(
                build.rebound(function, bound, f"{function.__name__}_{name}_generic")
            )
        work = build.source_function(record["work"])
        method = {
            "LANE": jit(build.rebound(build.source_function("lane"), bound, f"lane_{name}")),
            "WORK": step_jit(build.rebound(work, bound, f"{work.__name__}_{name}_generic")),
        }
        entry = build.rebound(drive, {**drive.__globals__, **method}, f"{name}_core")
        entry.__doc__ = f"The loop (:func:`drive`) with {name}'s steps."
        _entries[name] = entry
    return entry


def _namespace() -> dict[str, Any]:
    """The lane source compiled for a user's problem (once): the functions the loop and the
    methods' steps call, the mechanism's hooks replaced by :data:`ADAPTERS`."""
    if "" not in _entries:
        direct = [name for name in build.source_function("lane").__code__.co_names
                  if name in build.FUNCTIONS]  # fmt: skip
        for record in build.LANES.values():
            direct += [f"{record['steps']}_{step}" for step in build.STEPS] + [record["work"]]
        only = {*build.closed(tuple(direct), own=ADAPTERS), *ADAPTERS}
        _entries[""] = build.build(jit, hooks=ADAPTERS, extras={"np": np, "RECORD": True},
                                   only=tuple(only), tag="generic")  # fmt: skip
    namespace: dict[str, Any] = _entries[""]
    return namespace


def _specialised_core(args_type: Any, name: str) -> Any:
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
                )(_core(name))  # nogil: the batch engine runs implicit lanes on threads
                _specialisations[key] = core
    return core


@functools.cache
def steps_of(prefix: str) -> dict[str, Any]:
    """The lane record (``build.LANES``) whose steps' prefix is ``prefix``, an
    :attr:`~jointplay._kernels.integrators.Integrator.steps`: the steps the loop runs."""
    for record in build.LANES.values():
        if record["steps"] == prefix:
            return record
    raise ValueError(f"no integrator's steps are called {prefix!r}")


def run_core(
    name: str,
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
    """Integrate ``y' = fun(t, y, args)`` from ``t0`` to ``t_bound`` with the method whose
    steps' prefix is ``name`` (``"radau"``, ``"rodas"``, ``"dopri"``: an
    :attr:`~jointplay._kernels.integrators.Integrator.steps`): coerce the scalars and arrays
    to the compiled types and call its entry's specialisation for ``numba.typeof(args)``. The
    integration itself never raises: failures are returned as a status.

    The arguments and their contract are :func:`jointplay.integrate`'s (which checks them and
    names what to fix), with the defaults filled in: ``step_check``, ``after_step`` jitted
    functions (:func:`accept_every_step`, :func:`no_after_step` for none), ``atol`` an array
    (n,), ``first_step`` ``0.0`` for SciPy's choice, ``rtol`` raised to ``100·eps`` (SciPy's
    floor), ``interrupt`` the uint8 flags read before every step
    (:func:`jointplay._kernels.lanes.source.interrupt_pending`; ``None``: never).

    Returns:
        ``(status, t_out, y_out, counters)``: status ``0`` reached ``t_bound``, ``-1`` the
        step size fell below ``10·spacing(t)``, ``-2`` more than ``max_steps`` steps were
        needed, ``-3`` a non-finite value appeared in the state or in ``f``, ``-4`` an
        interrupt arrived; ``t_out`` (m,) and ``y_out`` (m, n) hold the initial point and
        every accepted step (after ``after_step``); ``counters`` (int64, 7) as named in
        ``ids.COUNTER_NAMES``.

    Raises:
        TypeError: From Numba, when a function does not compile to the signature that
            :func:`kernel_signatures` gives (:func:`jointplay.integrate` checks this first
            and says what to fix).
        ValueError: ``n_second`` and ``n_active`` do not satisfy
            ``0 <= 2·n_second <= n_active <= n``.
    """
    n = np.shape(y0)[0]
    n_active = n if n_active is None else int(n_active)
    if not 0 <= 2 * n_second <= n_active <= n:
        raise ValueError(
            f"need 0 <= 2·n_second <= n_active <= n = {n}, got {n_second} and {n_active}"
        )
    y0 = np.array(y0, dtype=np.float64, order="C")
    if n == 0 or t0 == t_bound:  # SciPy: at once, no evaluation of f; an empty system jumps
        t_out = np.array([t0] if t0 == t_bound else [t0, t_bound], dtype=np.float64)
        return STATUS_SUCCESS, t_out, np.tile(y0, (t_out.size, 1)), np.zeros(_N_COUNTERS, np.int64)
    core = _specialised_core(numba.typeof(args), name)
    status, t_out, y_out, counters = core(
        fun,
        step_check,
        after_step,
        finite_differences if jac is None else jac,
        float(t0),
        y0,
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
