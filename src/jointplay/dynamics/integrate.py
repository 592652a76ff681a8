"""Time integration: the Python face of the compiled Radau IIA, RODAS4 and DOPRI5 kernels.

:func:`integrate` checks its inputs (raising :class:`~jointplay.errors.ConfigError` that
names the argument and the fix), runs the compiled loop (:mod:`jointplay._kernels.driver`)
with the steps of the method named (its record in :data:`METHODS`), and returns a frozen
:class:`IntegrationResult`. Failure is data, as in diffrax: the
result carries its :class:`IntegrationStatus` (each member says what it means) and a
message saying what to change; with ``throw=True`` (the default) a failure raises
:class:`~jointplay.errors.IntegrationError` with that message instead, with ``throw=False``
it comes back as a partial result (so that a Monte Carlo study can count failures instead
of dropping them).

The method is SciPy's ``solve_ivp(method="Radau")`` (Radau IIA of order 5; Hairer &
Wanner, *Solving ODEs II*, §IV.8) compiled with Numba, plus two hooks for contact
simulation: ``step_check`` (retry a step with a shorter one, to land on contact onset)
and ``after_step`` (project the state, update contact memory). The algorithm:
:mod:`jointplay._kernels.lanes.source_radau`; the hooks' contract:
:func:`jointplay._kernels.driver.run_core`. ``method="rodas4"`` is a linearly implicit method (Rosenbrock, order 4,
Hairer & Wanner §IV.7) with the same hooks and results: one LU per step and no Newton
iteration, faster where the simplified Newton iteration of Radau keeps failing (contact
whose damping dominates, see :mod:`jointplay._kernels.lanes.source_rodas`); ``method="dopri5"``
is the explicit Dormand–Prince 5(4) pair with the same hooks, for equations that are not stiff
at the accuracy step. Each runs the lanes' own steps in the lanes' loop, every engine's
(:mod:`jointplay._kernels.driver`). Time is in seconds when the
dynamics engine calls this; the integrator itself is unit-agnostic.

Example:
    >>> import numba, numpy as np
    >>> @numba.njit
    ... def decay(t, y, args):
    ...     return -args[0] * y
    >>> result = integrate(decay, (0.0, 1.0), [1.0], args=(np.array([2.0]),), rtol=1e-8)
    >>> bool(abs(result.y[-1, 0] - np.exp(-2.0)) < 1e-7)
    True
"""

from __future__ import annotations

import enum
import math
from collections.abc import Sequence
from dataclasses import dataclass
from typing import TYPE_CHECKING, Any

import numba
import numpy as np
import numpy.typing as npt
from numba.core.dispatcher import Dispatcher

from jointplay._kernels import driver as _driver
from jointplay._kernels import ids
from jointplay._kernels.integrators import INTEGRATORS, Integrator
from jointplay.errors import ConfigError, IntegrationError
from jointplay.execution.interrupts import interrupts_watched as _interrupts_watched

if TYPE_CHECKING:
    import pandas as pd

__all__ = ["METHODS", "IntegrationResult", "IntegrationStatus", "integrate", "integrate_mechanism"]

#: The integration methods by name, their records: Radau IIA (order 5), RODAS4 (order 4) and
#: DOPRI5 (order 5, explicit), each run by the generic loop (:mod:`jointplay._kernels.driver`)
#: for :func:`integrate`, and by the lanes' loop for a mechanism (:func:`integrate_mechanism`).
METHODS: dict[str, Integrator] = {
    name: integrator for name, integrator in INTEGRATORS.items() if "single" in integrator.engines
}

_EPS = float(np.finfo(np.float64).eps)
_SMALLEST_RTOL = 100.0 * _EPS


class IntegrationStatus(enum.IntEnum):
    """How an integration ended: the kernel's status codes, each with what it means.

    ``IntegrationStatus.X.summary`` is the one statement of what status ``X`` means; the
    messages of :func:`integrate` and :func:`jointplay.dynamics.simulate.simulate` start
    from it and add where it happened and what to change.
    """

    SUCCESS = ids.STATUS_SUCCESS
    STEP_TOO_SMALL = ids.STATUS_STEP_TOO_SMALL
    TOO_MANY_STEPS = ids.STATUS_TOO_MANY_STEPS
    NON_FINITE = ids.STATUS_NON_FINITE
    INTERRUPTED = ids.STATUS_INTERRUPTED

    @property
    def summary(self) -> str:
        """One line saying what the status means."""
        return _SUMMARIES[self]


_SUMMARIES = {
    IntegrationStatus.SUCCESS: "the integration reached the end of the interval",
    IntegrationStatus.STEP_TOO_SMALL: "the step size fell below the smallest step",
    IntegrationStatus.TOO_MANY_STEPS: "the integration needed more than max_steps steps",
    IntegrationStatus.NON_FINITE: "a non-finite value (inf or NaN) appeared",
    IntegrationStatus.INTERRUPTED: "the integration was interrupted (SIGINT or SIGTERM)",
}


@dataclass(frozen=True)
class IntegrationResult:
    """The outcome of :func:`integrate`: every accepted step, the status and the counters.

    The arrays are read-only.

    Attributes:
        t: Times of the initial point and of every accepted step, shape (m,).
        y: States at those times (after ``after_step``), shape (m, n).
        status: How the integration ended; anything but ``SUCCESS`` is a failure.
        message: What happened, and for a failure what to change.
        nfev: Evaluations of ``fun`` outside the finite-difference Jacobians (SciPy's
            count).
        njev: Finite-difference Jacobians (each costs ``n`` to ``2n`` evaluations).
        nlu: LU factorisations (two per Newton-matrix update: real and complex).
        n_steps: Accepted steps.
        n_rejected: Rejected step attempts, all causes together.
        n_rejected_error: Attempts rejected by the error test.
        n_rejected_newton: Attempts whose Newton iteration did not converge.
        n_rejected_check: Attempts that ``step_check`` sent back with a shorter step.
    """

    t: npt.NDArray[np.float64]
    y: npt.NDArray[np.float64]
    status: IntegrationStatus
    message: str
    nfev: int
    njev: int
    nlu: int
    n_steps: int
    n_rejected: int
    n_rejected_error: int
    n_rejected_newton: int
    n_rejected_check: int

    @property
    def success(self) -> bool:
        """Whether the integration reached the end of the interval."""
        return self.status is IntegrationStatus.SUCCESS

    def to_frame(self, names: Sequence[str] | None = None) -> pd.DataFrame:
        """The recorded steps as a DataFrame: a column ``t`` and one column per state.

        Args:
            names: Names of the state components (default ``y0``, ``y1``, ...).

        Returns:
            One row per recorded point.

        Raises:
            ConfigError: ``names`` does not have one name per state component.
        """
        import pandas as pd

        n = self.y.shape[1]
        columns = [f"y{i}" for i in range(n)] if names is None else list(names)
        if len(columns) != n:
            raise ConfigError(f"names has {len(columns)} entries; give one per state ({n})")
        frame = pd.DataFrame(np.array(self.y), columns=columns)
        frame.insert(0, "t", np.array(self.t))
        return frame


def integrate(
    fun: Any,
    t_span: tuple[float, float],
    y0: npt.ArrayLike,
    *,
    args: tuple[Any, ...] = (),
    rtol: float = 1e-3,
    atol: float | npt.ArrayLike = 1e-6,
    max_step: float = math.inf,
    first_step: float | None = None,
    max_steps: int = 100_000,
    step_check: Any = None,
    after_step: Any = None,
    n_second: int = 0,
    n_active: int | None = None,
    hold_after_failure: bool = False,
    jac: Any = None,
    throw: bool = True,
    method: str = "radau",
    autonomous: bool = False,
) -> IntegrationResult:
    """Integrate ``y' = fun(t, y, args)`` over ``t_span`` with compiled Radau IIA (order 5),
    RODAS4 or DOPRI5.

    With the options off, Radau IIA is SciPy's ``solve_ivp(method="Radau")`` (its constants
    and decisions; the same steps, up to round-off, on a smooth problem: its own LU and
    loop-ordered sums; a non-finite state or f after a step ends with ``NON_FINITE`` where
    SciPy carries NaN on); RODAS4 is Hairer's ``rodas.f`` (its first method, with its
    predictive step control; the Jacobian afresh at every step's start); DOPRI5 is Hairer's
    ``dopri5``. An empty interval returns at once, without evaluating ``fun``.

    Args:
        fun: Numba-jitted right-hand side ``fun(t, y, args) -> float64[:]`` returning a
            new array of the shape of ``y``.
        t_span: ``(t0, t_bound)``; ``t_bound < t0`` integrates backwards.
        y0: Initial state, shape (n,), finite; not modified.
        args: Tuple of NumPy arrays, or of (named) tuples of them, handed untouched to
            ``fun`` and the hooks (which may modify the arrays in place, e.g. for contact
            memory or statistics).
        rtol: Relative tolerance, in ``[100·eps, 1)``.
        atol: Absolute tolerance, a scalar or one per state component, ``>= 0``.
        max_step: Largest step size, ``> 0`` (``inf`` for no limit).
        first_step: First step size in ``(0, |t_bound − t0|]``; ``None`` lets the
            integrator choose (as SciPy's ``select_initial_step`` does).
        max_steps: Largest number of accepted steps, ``>= 1``.
        step_check: Optional Numba-jitted ``step_check(t_old, y_old, t_new, y_new, args)
            -> float``, called on every step that passed the method's tests: ``1.0``
            accepts it, ``θ`` in (0, 1) retries it from ``t_old`` with the step multiplied
            by ``θ`` (for example to land a step on contact onset; counted in
            ``n_rejected_check``). A retry shorter than ``10·spacing(t)``, not shorter at
            all, or the 65th of one step is not made: the step is accepted.
        after_step: Optional Numba-jitted ``after_step(t, y, args) -> bool`` called on
            each accepted step; it may modify ``y`` in place (projection onto
            constraints) and the arrays in ``args``, and returns ``True`` when the state
            or the right-hand side changed discontinuously (Radau IIA's next Newton
            iteration then starts from zero, its Jacobian kept but marked stale).
            ``fun`` is evaluated afresh after it either way.
        n_second: Second-order structure: ``fun(t, y)[:m] == y[m:2m]`` exactly for
            ``m = n_second`` (positions, then their velocities); the implicit methods'
            linear systems are then solved on the other active components only
            (Hairer & Wanner §IV.8, RADAU5's ``M1``: ``dx = h/γ (b_x + dv)``). ``0``: none.
        n_active: Components from ``n_active`` on are passive: ``fun`` does not depend on
            them, or they are constant in the ODE (memory that only ``after_step``
            changes); their Jacobian columns are neither computed nor used. ``None``: all
            are active. Needs ``0 <= 2·n_second <= n_active <= n``.
        hold_after_failure: After a step accepted only once its error test or Newton
            iteration had failed, do not let the next step grow (Hairer's RADAU5,
            ``IF (REJECT) HNEW = MIN(HNEW, H)``; every mechanism's run); ``False``: SciPy's
            controller, which on a piecewise-smooth ``fun`` may retry, again and again, a
            step at which Newton just failed.
        jac: Optional Numba-jitted ``jac(t, y, f, args, out) -> bool`` writing ``∂fun/∂y``
            into ``out`` (n, n; zeroed before each call, so only the non-zero entries need
            writing) and returning ``True``, or returning ``False`` to have the kernel
            difference ``fun`` (as SciPy's ``num_jac`` does). ``None``: always
            difference. Counted in ``njev`` either way; the differences' evaluations of
            ``fun`` are not in ``nfev`` (as in SciPy).
        throw: Raise :class:`~jointplay.errors.IntegrationError` when the integration
            fails (default); with ``False``, return the partial result with its status.
        method: ``"radau"`` (Radau IIA, order 5; default), ``"rodas4"`` (RODAS4, order
            4, linearly implicit: ``jac`` at every step's start, no Newton iteration, so
            ``n_rejected_newton`` is 0) or ``"dopri5"`` (Dormand–Prince 5(4), explicit: no
            Jacobian, ``njev`` and ``nlu`` are 0).
        autonomous: ``fun`` does not depend on ``t``: RODAS4 then takes no difference of
            ``fun`` in ``t`` (one evaluation a step saved; the same result, that difference
            being exactly zero); the other methods need none.

    Returns:
        The initial point and every accepted step (after ``after_step``), the status
        (:class:`IntegrationStatus`) and the counters.

    Raises:
        ConfigError: An argument is malformed or out of range (the message names it).
        IntegrationError: The integration failed and ``throw`` is true.
        KeyboardInterrupt: SIGINT or SIGTERM arrived (checked before every step).
    """
    if method not in METHODS:
        raise ConfigError(
            f"unknown integration method {method!r}; choose one of {', '.join(METHODS)}"
        )
    t0, t_bound = _check_span(t_span)
    y0_array = _check_state(y0)
    n = y0_array.shape[0]
    args = _check_args(args)
    rtol = _check_rtol(rtol)
    atol_array = _check_atol(atol, n)
    max_step = _check_max_step(max_step)
    first = _check_first_step(first_step, t0, t_bound)
    max_steps = _check_max_steps(max_steps)
    n_active = _check_structure(n_second, n_active, n)
    step_check = _driver.accept_every_step if step_check is None else step_check
    after_step = _driver.no_after_step if after_step is None else after_step
    _check_functions(fun, step_check, after_step, jac, t0, y0_array, args)

    with _interrupts_watched() as flags:
        status_code, t, y, counters = _driver.run_core(
            METHODS[method].steps,
            fun,
            step_check,
            after_step,
            t0,
            y0_array,
            t_bound,
            args,
            rtol,
            atol_array,
            max_step,
            first,
            max_steps,
            n_second=n_second,
            n_active=n_active,
            hold_after_failure=hold_after_failure,
            jac=jac,
            autonomous=bool(autonomous),
            interrupt=flags,
        )
    counts = dict(zip(ids.COUNTER_NAMES, (int(c) for c in counters), strict=True))
    return _result(status_code, t, y, counts, t0, t_bound, rtol, max_steps, throw, method)


def integrate_mechanism(
    args: tuple[npt.NDArray[np.float64], npt.NDArray[np.int64], npt.NDArray[np.float64]],
    t_end: float,
    y0: npt.NDArray[np.float64],
    *,
    method: str,
    rtol: float,
    atol: npt.NDArray[np.float64],
    max_step: float,
    max_steps: int,
    throw: bool = True,
) -> tuple[IntegrationResult, npt.NDArray[np.float64]]:
    """A mechanism's equations of motion (:mod:`jointplay._kernels.eom`'s model and state)
    from t = 0 to ``t_end`` by the batch lanes' loop and steps with the trajectory recorded
    (:data:`jointplay._kernels.lanes.cpu.traced`), the one loop of every engine: the
    coordinates' rates are their velocities, the work integrals and the impact-velocity memory
    passive, RADAU5's hold after failures.

    Args:
        args: :meth:`~jointplay.dynamics.system.System.kernel_args`: the model packed
            (``eom.pack``'s ``rpar``, ``ipar``); its workspace is not read.
        t_end: the interval's end, s.
        method: an integrator's name (:data:`METHODS`).
        rtol, atol, max_step, max_steps, throw: as :func:`integrate`'s (checked by the
            caller).

    Returns:
        The result, and the projection's statistics (``ids.W_*``).
    """
    from jointplay._kernels.eom import lay_of
    from jointplay._kernels.lanes import cpu

    rpar, ipar = args[0], args[1]
    with _interrupts_watched() as flags:
        code, t, y, counters, work = cpu.traced[method](
            ipar, rpar, lay_of(ipar), np.ascontiguousarray(y0, dtype=np.float64), float(t_end),
            float(max_step), float(rtol), np.ascontiguousarray(atol, dtype=np.float64),
            int(max_steps), _driver.NO_INTERRUPT if flags is None else flags,
        )  # fmt: skip
    rejected = {"n_rejected_newton": int(counters[ids.K_REJ_NEWTON]),
                "n_rejected_check": int(counters[ids.K_REJ_CHECK])}  # fmt: skip
    counts = {
        "nfev": int(counters[ids.K_RHS]),
        "njev": int(counters[ids.K_JAC]),
        "nlu": int(counters[ids.K_LU]),
        "n_steps": int(counters[ids.K_STEPS]),
        "n_rejected_error": int(counters[ids.K_REJECTED]) - sum(rejected.values()),
        **rejected,
    }
    return _result(code, t, y, counts, 0.0, t_end, rtol, max_steps, throw, method), work


def _result(
    status_code: int,
    t: npt.NDArray[np.float64],
    y: npt.NDArray[np.float64],
    counts: dict[str, int],
    t0: float,
    t_bound: float,
    rtol: float,
    max_steps: int,
    throw: bool,
    method: str,
) -> IntegrationResult:
    """The result of a run of the loop by ``method`` (a :data:`METHODS` name), ``counts`` by
    :data:`ids.COUNTER_NAMES`; an interrupt raises ``KeyboardInterrupt``, a failure
    :class:`IntegrationError` when ``throw``."""
    status = IntegrationStatus(status_code)
    if status is IntegrationStatus.INTERRUPTED:
        raise KeyboardInterrupt(status.summary)
    message = _message(
        status, t, t0, t_bound, rtol, max_steps, METHODS[method], initial=counts["nfev"] == 1
    )
    if throw and status is not IntegrationStatus.SUCCESS:
        raise IntegrationError(message)
    t.flags.writeable = False
    y.flags.writeable = False
    return IntegrationResult(
        t=t,
        y=y,
        status=status,
        message=message,
        nfev=counts["nfev"],
        njev=counts["njev"],
        nlu=counts["nlu"],
        n_steps=counts["n_steps"],
        n_rejected=counts["n_rejected_error"]
        + counts["n_rejected_newton"]
        + counts["n_rejected_check"],
        n_rejected_error=counts["n_rejected_error"],
        n_rejected_newton=counts["n_rejected_newton"],
        n_rejected_check=counts["n_rejected_check"],
    )


def _message(
    status: IntegrationStatus,
    t: npt.NDArray[np.float64],
    t0: float,
    t_bound: float,
    rtol: float,
    max_steps: int,
    integrator: Integrator,
    *,
    initial: bool,
) -> str:
    """The message for a status, naming the method, with the time it stopped at and what to
    change.

    ``initial`` tells that only the initial ``fun`` evaluation was made.
    """
    t_last = float(t[-1])
    failed = f"The {integrator.name} integration failed"
    # A method stable only below a step size shrinks its step to that size where f is stiff.
    stiff = ", or choose method='radau'" if integrator.explicit else ""
    if status is IntegrationStatus.SUCCESS:
        return f"{status.summary} (t = {t_bound:.9g}) in {t.shape[0] - 1} steps"
    if status is IntegrationStatus.STEP_TOO_SMALL:
        direction = math.copysign(math.inf, t_bound - t0)
        min_step = 10.0 * abs(math.nextafter(t_last, direction) - t_last)
        return (
            f"{failed}: {status.summary} ({min_step:.3g}) at t = {t_last:.9g}: the"
            f" solution is too stiff or not smooth there for rtol = {rtol:g}. Loosen"
            f" rtol/atol{stiff}; look for a discontinuity of fun near that time (land a step on it"
            " with step_check, or smooth the contact law), or for a finite-time blow-up."
        )
    if status is IntegrationStatus.TOO_MANY_STEPS:
        return (
            f"{failed}: {status.summary} (max_steps = {max_steps}); it stopped at"
            f" t = {t_last:.9g} of [{t0:.9g}, {t_bound:.9g}]. Raise max_steps, loosen"
            f" rtol/atol{stiff} or shorten t_span; if the steps became tiny, look for"
            " chattering contact or a step_check that keeps shortening steps."
        )
    where = "the initial state" if initial else f"the step after t = {t_last:.9g}"
    return (
        f"{failed}: {status.summary} in the state or in fun at {where}."
        " Check fun for a division by zero, a negative base under a fractional power or an"
        " overflow at that state, and check what after_step writes into y."
    )


# ---------------------------------------------------------------------------------------
# Argument checks: each names the argument and the fix.
# ---------------------------------------------------------------------------------------
def _check_span(t_span: tuple[float, float]) -> tuple[float, float]:
    try:
        t0, t_bound = (float(v) for v in t_span)
    except (TypeError, ValueError):
        raise ConfigError(f"t_span must be two numbers (t0, t_bound), got {t_span!r}") from None
    if not (math.isfinite(t0) and math.isfinite(t_bound)):
        raise ConfigError(f"t_span must be finite, got ({t0}, {t_bound})")
    return t0, t_bound


def _check_state(y0: npt.ArrayLike) -> npt.NDArray[np.float64]:
    try:
        y = np.array(y0, dtype=np.float64)
    except (TypeError, ValueError):
        raise ConfigError(f"y0 must be an array of real numbers, got {y0!r}") from None
    if y.ndim != 1 or y.shape[0] == 0:
        raise ConfigError(f"y0 must be a non-empty 1-D array, got shape {y.shape}")
    if not np.all(np.isfinite(y)):
        bad = np.flatnonzero(~np.isfinite(y)).tolist()
        raise ConfigError(f"y0 must be finite; components {bad} are not")
    return y


def _check_args(args: tuple[Any, ...]) -> tuple[Any, ...]:
    if not isinstance(args, tuple):
        raise ConfigError(f"args must be a tuple of NumPy arrays, got {type(args).__name__}")
    _check_arrays(args, "args")
    return args


def _check_arrays(items: tuple[Any, ...], where: str) -> None:
    """Every leaf of the (nested) tuple ``items`` is a NumPy array."""
    for i, a in enumerate(items):
        if isinstance(a, tuple):
            _check_arrays(a, f"{where}[{i}]")
        elif not isinstance(a, np.ndarray):
            raise ConfigError(
                f"{where}[{i}] must be a NumPy array (or a tuple of them), got"
                f" {type(a).__name__}; wrap scalars as np.array([value])"
            )


def _check_structure(n_second: int, n_active: int | None, n: int) -> int:
    active = n if n_active is None else n_active
    for name, value in (("n_second", n_second), ("n_active", active)):
        if isinstance(value, bool) or not isinstance(value, int | np.integer):
            raise ConfigError(f"{name} must be an integer, got {type(value).__name__}")
    if not 0 <= 2 * n_second <= active <= n:
        raise ConfigError(
            f"need 0 <= 2·n_second <= n_active <= n = {n} (the state's size), got n_second ="
            f" {n_second} and n_active = {active}"
        )
    return int(active)


def _check_rtol(rtol: float) -> float:
    rtol = float(rtol)
    if not (_SMALLEST_RTOL <= rtol < 1.0):
        raise ConfigError(f"rtol must lie in [{_SMALLEST_RTOL:.3g}, 1) (100·eps to 1), got {rtol}")
    return rtol


def _check_atol(atol: float | npt.ArrayLike, n: int) -> npt.NDArray[np.float64]:
    a = np.array(atol, dtype=np.float64)
    if a.ndim == 0:
        a = np.full(n, float(a))
    if a.shape != (n,):
        raise ConfigError(f"atol must be a scalar or have shape ({n},) like y0, got {a.shape}")
    if not np.all(np.isfinite(a) & (a >= 0.0)):
        raise ConfigError(f"atol must be finite and >= 0, got {a.tolist()}")
    return a


def _check_max_step(max_step: float) -> float:
    max_step = float(max_step)
    if not max_step > 0.0:
        raise ConfigError(f"max_step must be > 0 (inf for no limit), got {max_step}")
    return max_step


def _check_first_step(first_step: float | None, t0: float, t_bound: float) -> float:
    if first_step is None:
        return 0.0
    first = float(first_step)
    span = abs(t_bound - t0)
    if not (0.0 < first <= span):
        raise ConfigError(
            f"first_step must lie in (0, |t_bound - t0|] = (0, {span:.9g}], got {first};"
            " or pass None to let the integrator choose"
        )
    return first


def _check_max_steps(max_steps: int) -> int:
    if isinstance(max_steps, bool) or not isinstance(max_steps, int | np.integer):
        raise ConfigError(f"max_steps must be an integer, got {type(max_steps).__name__}")
    if max_steps < 1:
        raise ConfigError(f"max_steps must be >= 1, got {max_steps}")
    return int(max_steps)


def _check_functions(
    fun: Any,
    step_check: Any,
    after_step: Any,
    jac: Any,
    t0: float,
    y0: npt.NDArray[np.float64],
    args: tuple[Any, ...],
) -> None:
    """Check that the functions compile to the kernel's signatures, and fun's shape."""
    signatures = _driver.kernel_signatures(numba.typeof(args))
    forms = {
        "fun": "fun(t: float, y: float64[:], args) -> float64[:]",
        "step_check": "step_check(t_old, y_old, t_new, y_new, args) -> float",
        "after_step": "after_step(t, y, args) -> bool",
        "jac": "jac(t, y, f, args, out: float64[:, ::1]) -> bool",
    }
    functions = {"fun": fun, "step_check": step_check, "after_step": after_step}
    if jac is not None:
        functions["jac"] = jac
    for name, function in functions.items():
        if not isinstance(function, Dispatcher):
            raise ConfigError(
                f"{name} must be a Numba-jitted function (decorate it with @numba.njit),"
                f" got {type(function).__name__}"
            )
        if tuple(signatures[name].args) in function.signatures:
            continue  # compiled already (an explicit signature disables compiling more)
        try:
            function.compile(signatures[name])
        except Exception as exc:  # Numba raises several error types while typing.
            first_line = str(exc).strip().splitlines()[0] if str(exc).strip() else repr(exc)
            raise ConfigError(
                f"{name} does not compile as {forms[name]} with these args: {first_line}"
            ) from None
    f0 = np.asarray(fun(t0, y0.copy(), args))
    if f0.shape != y0.shape:
        raise ConfigError(
            f"fun must return an array of the shape of y0 {y0.shape}, got shape {f0.shape}"
        )
