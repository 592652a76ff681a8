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

Layout, as SciPy's: this module holds the method (its constants, the Newton iteration on
the collocation system, the error estimate, the driver); :mod:`jointplay._kernels.common`
the step-size helpers (status codes, counter names, error norm, step factor, initial step,
finite-difference Jacobian); :mod:`jointplay._kernels.linalg` the LU factorisation with
partial pivoting, one generic routine compiled for float64 and complex128.

Compilation: everything is ``njit(cache=True)``. The user's functions reach the driver as
first-class function values (``numba.types.FunctionType``) rather than as dispatcher
objects, because Numba keys a dispatcher-typed argument by the object's address: such a
specialisation is never found again in the cache of a new process (and adds a cache file
every time). :func:`radau_integrate` therefore compiles the driver for explicit
signatures, one per type of ``args`` (see :func:`kernel_signatures`), and Numba converts
each jitted user function to that type at the call (so :func:`radau_integrate` is called
from Python, not from compiled code). Element-wise loops replace NumPy array expressions
throughout: the same arithmetic, compiled faster.

References:
    .. [HW96] E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II: Stiff and
       Differential-Algebraic Problems*, 2nd ed., Springer, 1996, §IV.8.
    .. [SciPy] P. Virtanen et al., "SciPy 1.0", *Nature Methods* 17, 261–272 (2020);
       ``scipy/integrate/_ivp/radau.py`` and ``common.py``.
"""

from __future__ import annotations

import math
from typing import Any

import numpy as np
import numpy.typing as npt

from jointplay._kernels.common import (
    error_scale,
    jit,
    num_jac,
    plus,
    predict_factor,
    py_max,
    py_min,
    rms_norm,
    tolerance_scale,
)
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
from jointplay._kernels.linalg import lu_factor_in_place, lu_solve_in_place

__all__ = [
    "MAX_CHECK_REJECTIONS",
    "STEPS",
    "accept_every_step",
    "finite_differences",
    "kernel_signatures",
    "no_after_step",
    "radau_integrate",
]

# ---------------------------------------------------------------------------------------
# Method constants, verbatim from SciPy's radau.py ([HW96] §IV.8).
# ---------------------------------------------------------------------------------------
S6 = 6.0**0.5

#: Collocation nodes c_i of the three-stage Radau IIA method.
C = np.array([(4.0 - S6) / 10.0, (4.0 + S6) / 10.0, 1.0])
#: Weights of the embedded error estimate (applied to Z / h).
E = np.array([-13.0 - 7.0 * S6, -13.0 + 7.0 * S6, -1.0]) / 3.0

#: Eigenvalues of A⁻¹: one real, one complex-conjugate pair (A = T Λ T⁻¹).
MU_REAL = 3.0 + 3.0 ** (2.0 / 3.0) - 3.0 ** (1.0 / 3.0)
MU_COMPLEX = (3.0 + 0.5 * (3.0 ** (1.0 / 3.0) - 3.0 ** (2.0 / 3.0))) - 0.5j * (
    3.0 ** (5.0 / 6.0) + 3.0 ** (7.0 / 6.0)
)

#: Transformation matrices of the eigen-decomposition.
T = np.array(
    [
        [0.09443876248897524, -0.14125529502095421, 0.03002919410514742],
        [0.25021312296533332, 0.20412935229379994, -0.38294211275726192],
        [1.0, 1.0, 0.0],
    ]
)
TI = np.array(
    [
        [4.17871859155190428, 0.32768282076106237, 0.52337644549944951],
        [-4.17871859155190428, -0.32768282076106237, 0.47662355450055044],
        [0.50287263494578682, -2.57192694985560522, 0.59603920482822492],
    ]
)
TI_REAL = TI[0].copy()
TI_COMPLEX = TI[1] + 1j * TI[2]

#: Coefficients of the collocation polynomial (dense output / Newton start).
P = np.array(
    [
        [13.0 / 3.0 + 7.0 * S6 / 3.0, -23.0 / 3.0 - 22.0 * S6 / 3.0, 10.0 / 3.0 + 5.0 * S6],
        [13.0 / 3.0 - 7.0 * S6 / 3.0, -23.0 / 3.0 + 22.0 * S6 / 3.0, 10.0 / 3.0 - 5.0 * S6],
        [1.0 / 3.0, -8.0 / 3.0, 10.0 / 3.0],
    ]
)

NEWTON_MAXITER = 6  # Maximum number of Newton iterations.
MIN_FACTOR = 0.2  # Minimum allowed decrease in a step size.
MAX_FACTOR = 10.0  # Maximum allowed increase in a step size.


# ---------------------------------------------------------------------------------------
# Stage norm.
# ---------------------------------------------------------------------------------------
@jit
def _rms_norm_stages(x, scale):
    """SciPy's ``norm(x / scale)`` for ``x`` of shape (3, n), ``scale`` broadcast on rows."""
    n = x.shape[1]
    s = 0.0
    for i in range(3):
        for j in range(n):
            v = x[i, j] / scale[j]
            s += v * v
    return math.sqrt(s) / math.sqrt(3 * n)


# ---------------------------------------------------------------------------------------
# Newton matrices (reduced to the active, non-position components).
# ---------------------------------------------------------------------------------------
@jit
def reduced_newton_matrix(jac, mu_over_h, a, n_second, n_active):
    """Fill ``a`` (float64 or complex128, the dtype of ``mu_over_h``) with the kept block of
    ``γ/h·I − J`` for ``mu_over_h = γ/h``, the positions' columns folded in (see
    :func:`_factor_newton_matrices`); RODAS4's matrix too (:mod:`jointplay._kernels.rodas`)."""
    m2 = n_second
    nk = n_active - m2
    for i in range(nk):
        for j in range(nk):
            a[i, j] = -jac[m2 + i, m2 + j]
        a[i, i] += mu_over_h
        for j in range(m2):  # dx = h/γ (b_x + dv): the positions' columns fold into dv's
            a[i, j] -= jac[m2 + i, j] / mu_over_h
    return a


@jit
def _factor_newton_matrices(jac, h, n_second, n_active):
    """LU factors of the Newton matrices ``MU_REAL/h·I − J`` and ``MU_COMPLEX/h·I − J``,
    reduced to the components that :func:`_newton_solve` keeps.

    For ``γ`` = ``MU_REAL`` or ``MU_COMPLEX``, the kept block ``K = [n_second, n_active)``
    (velocities and other active components) of ``γ/h·I − J`` minus ``h/γ·J_Kx`` in the
    columns of the velocities, ``x`` being the positions ``[0, n_second)`` ([HW96] §IV.8,
    the ``M1`` option of RADAU5). With ``n_second = 0`` and ``n_active = n`` this is the
    full matrix, as in SciPy.

    Returns:
        ``(lu_real, piv_real, lu_complex, piv_complex)``, new arrays.
    """
    nk = n_active - n_second
    lu_real = np.empty((nk, nk))
    piv_real = np.empty(nk, dtype=np.int64)
    lu_complex = np.empty((nk, nk), dtype=np.complex128)
    piv_complex = np.empty(nk, dtype=np.int64)
    _factor_into(jac, h, n_second, n_active, lu_real, piv_real, lu_complex, piv_complex)
    return lu_real, piv_real, lu_complex, piv_complex


@jit
def _factor_into(jac, h, n_second, n_active, lu_real, piv_real, lu_complex, piv_complex):
    """:func:`_factor_newton_matrices` into the given arrays (nk, nk), (nk,) each."""
    reduced_newton_matrix(jac, MU_REAL / h, lu_real, n_second, n_active)
    reduced_newton_matrix(jac, MU_COMPLEX / h, lu_complex, n_second, n_active)
    lu_factor_in_place(lu_real, piv_real)
    lu_factor_in_place(lu_complex, piv_complex)


@jit
def _newton_solve_in_place(lu, piv, jac, mu_over_h, x, work, n_second, n_active):
    """Solve ``(γ/h·I − J) x = b`` from the reduced factors of :func:`_factor_newton_matrices`.

    The Jacobian is taken to have the structure that ``n_second`` and ``n_active`` declare
    (see :func:`radau_integrate`): rows ``[0, m)`` (``m = n_second``) are ``[0, I, 0]``
    (``x' = v``), and the columns from ``n_active`` on are zero. Then
    ``dx = h/γ (b_x + dv)``; the kept block ``K = [m, n_active)`` solves
    ``(γ/h·I − J_KK − h/γ·J_Kx E) d_K = b_K + h/γ·J_Kx b_x`` (``E`` picks dv out of d_K);
    and each passive component ``p`` follows as ``h/γ (b_p + J_p,active x_active)``. In
    exact arithmetic this is the solution of the full system.

    Args:
        lu: Packed LU of the reduced matrix for ``γ``.
        piv: Its row interchanges.
        jac: The Jacobian, shape (n, n) (only the rows from ``n_second`` on are read).
        mu_over_h: ``γ/h`` (real or complex, the dtype of ``lu``).
        x: ``b`` on entry, the solution on return, shape (n,), the dtype of ``lu``.
        work: Scratch of shape (n_active − n_second,), the dtype of ``lu``.
        n_second: Number of positions ``m``.
        n_active: Number of active components.
    """
    n = x.shape[0]
    m2 = n_second
    nk = n_active - m2
    h_over_mu = 1.0 / mu_over_h
    for i in range(nk):
        s = x[m2 + i]
        for j in range(m2):
            s += h_over_mu * jac[m2 + i, j] * x[j]
        work[i] = s
    lu_solve_in_place(lu, piv, work)
    for j in range(m2):
        x[j] = h_over_mu * (x[j] + work[j])
    for i in range(nk):
        x[m2 + i] = work[i]
    for p in range(n_active, n):
        s = x[p]
        for j in range(n_active):
            s += jac[p, j] * x[j]
        x[p] = h_over_mu * s


@jit
def _newton_solve(lu, piv, jac, mu_over_h, b, n_second, n_active):
    """:func:`_newton_solve_in_place` into a new array (``b`` is not modified)."""
    x = b.copy()
    work = np.empty(n_active - n_second, dtype=b.dtype)
    _newton_solve_in_place(lu, piv, jac, mu_over_h, x, work, n_second, n_active)
    return x


# ---------------------------------------------------------------------------------------
# Pieces of the collocation step.
# ---------------------------------------------------------------------------------------
@jit
def _mat3_dot_into(m, z, out):
    """``out[:] = m @ z`` for a 3×3 ``m`` and (3, n) ``z`` and ``out``."""
    n = z.shape[1]
    for i in range(3):
        for j in range(n):
            out[i, j] = 0.0
        for k in range(3):
            mik = m[i, k]
            for j in range(n):
                out[i, j] += mik * z[k, j]


@jit
def _newton_increment(f_stages, w, h, scale, lu_real, piv_real, lu_complex, piv_complex, jac,
                      n_second, n_active, dw, x_real, x_complex, work_real, work_complex):  # fmt: skip
    """One simplified-Newton increment ``dW`` in the transformed variables; its norm.

    Args:
        f_stages: ``F[i] = f(t + c_i h, y + Z[i])``, shape (3, n).
        w: Current transformed stage increments ``W = TI @ Z``, shape (3, n).
        h: Signed step.
        scale: ``atol + rtol·|y|``, shape (n,).
        lu_real: Packed LU of ``MU_REAL/h·I − J`` (reduced, :func:`_factor_newton_matrices`).
        piv_real: Its row interchanges.
        lu_complex: Packed LU of ``MU_COMPLEX/h·I − J`` (reduced).
        piv_complex: Its row interchanges.
        jac: The Jacobian the factors were made from.
        n_second: Number of positions (see :func:`radau_integrate`).
        n_active: Number of active components (see :func:`radau_integrate`).
        dw: Receives ``dW``, shape (3, n).
        x_real, x_complex, work_real, work_complex: Scratch, shapes (n,), (n,), (nk,),
            (nk,) with ``nk = n_active − n_second``.

    Returns:
        ``||dW / scale||_rms``.
    """
    n = w.shape[1]
    m_real = MU_REAL / h
    m_complex = MU_COMPLEX / h
    for j in range(n):
        fr = 0.0
        fc = 0.0j
        for i in range(3):
            fr += f_stages[i, j] * TI_REAL[i]
            fc += f_stages[i, j] * TI_COMPLEX[i]
        x_real[j] = fr - m_real * w[0, j]
        x_complex[j] = fc - m_complex * (w[1, j] + 1j * w[2, j])
    _newton_solve_in_place(lu_real, piv_real, jac, m_real, x_real, work_real, n_second, n_active)
    _newton_solve_in_place(
        lu_complex, piv_complex, jac, m_complex, x_complex, work_complex, n_second, n_active
    )
    for j in range(n):
        dw[0, j] = x_real[j]
        dw[1, j] = x_complex[j].real
        dw[2, j] = x_complex[j].imag
    return _rms_norm_stages(dw, scale)


@jit
def _error_estimate(z, f, h, lu_real, piv_real, jac, n_second, n_active):
    """Embedded error estimate ``(MU_REAL/h·I − J)⁻¹ (f + ZE)`` and ``ZE = Zᵀ E / h``."""
    n = z.shape[1]
    ze = np.empty(n)
    rhs = np.empty(n)
    for j in range(n):
        ze[j] = (z[0, j] * E[0] + z[1, j] * E[1] + z[2, j] * E[2]) / h
        rhs[j] = f[j] + ze[j]
    return ze, _newton_solve(lu_real, piv_real, jac, MU_REAL / h, rhs, n_second, n_active)


@jit
def _extrapolate(q, t_old, y_old, t, y, h):
    """Newton start ``Z0[i] = sol(t + c_i h) − y`` from the last step's collocation polynomial.

    ``sol(τ) = y_old + Q·[x, x², x³]`` with ``x = (τ − t_old)/(t − t_old)`` and
    ``Q = Zᵀ P`` of the previous step (SciPy's ``RadauDenseOutput``).
    """
    n = y.shape[0]
    h_prev = t - t_old
    z0 = np.empty((3, n))
    for i in range(3):
        x = (t + h * C[i] - t_old) / h_prev
        x2 = x * x
        x3 = x2 * x
        for j in range(n):
            z0[i, j] = (q[j, 0] * x + q[j, 1] * x2 + q[j, 2] * x3) + y_old[j] - y[j]
    return z0


@jit
def _interpolant_coefficients_into(z, q):
    """``Q = Zᵀ P`` into ``q`` (n, 3)."""
    n = z.shape[1]
    for j in range(n):
        for k in range(3):
            s = 0.0
            for i in range(3):
                s += z[i, j] * P[i, k]
            q[j, k] = s


# ---------------------------------------------------------------------------------------
# Collocation system.
# ---------------------------------------------------------------------------------------
@jit
def _solve_collocation_system(
    fun,
    args,
    t,
    y,
    h,
    z0,
    scale,
    tol,
    lu_real,
    piv_real,
    lu_complex,
    piv_complex,
    jac,
    n_second,
    n_active,
    workspace,
):
    """Simplified Newton iteration for the collocation system ([HW96] §IV.8; SciPy).

    Args:
        fun: Right-hand side ``fun(t, y, args)``.
        args: Passed through to ``fun``.
        t: Current time.
        y: Current state, shape (n,).
        h: Signed step.
        z0: Initial guess of ``Z`` (stage values minus ``y``), shape (3, n).
        scale: ``atol + rtol·|y|``, shape (n,).
        tol: Newton tolerance (on the scaled RMS norm).
        lu_real: Packed LU of ``MU_REAL/h·I − J`` (reduced, :func:`_factor_newton_matrices`).
        piv_real: Its row interchanges.
        lu_complex: Packed LU of ``MU_COMPLEX/h·I − J`` (reduced).
        piv_complex: Its row interchanges.
        jac: The Jacobian the factors were made from.
        n_second: Number of positions (see :func:`radau_integrate`).
        n_active: Number of active components (see :func:`radau_integrate`).
        workspace: Scratch arrays from :func:`_newton_workspace`, reused from call to call.

    Returns:
        ``(converged, n_iter, Z, rate, nfev)``; ``rate`` is NaN while undefined. ``Z`` is
        one of the ``workspace`` arrays: valid until the next call.
    """
    n = y.shape[0]
    w, z, f_stages, ytmp, dw, x_real, x_complex, work_real, work_complex = workspace
    _mat3_dot_into(TI, z0, w)
    for i in range(3):
        for j in range(n):
            z[i, j] = z0[i, j]
    dw_norm_old = 0.0
    has_old = False  # SciPy's ``dW_norm_old is not None``.
    rate = np.nan  # NaN stands for SciPy's ``rate = None``.
    converged = False
    finite = True
    nfev = 0
    k = 0
    for k in range(NEWTON_MAXITER):
        for i in range(3):
            for j in range(n):
                ytmp[j] = y[j] + z[i, j]
            f_i = fun(t + h * C[i], ytmp, args)
            nfev += 1
            for j in range(n):
                f_stages[i, j] = f_i[j]
                finite = finite and math.isfinite(f_i[j])
        if not finite:
            break
        dw_norm = _newton_increment(
            f_stages, w, h, scale, lu_real, piv_real, lu_complex, piv_complex, jac,
            n_second, n_active, dw, x_real, x_complex, work_real, work_complex,
        )  # fmt: skip
        if has_old:
            rate = dw_norm / dw_norm_old
        if has_old and (rate >= 1 or rate ** (NEWTON_MAXITER - k) / (1 - rate) * dw_norm > tol):
            break
        for i in range(3):
            for j in range(n):
                w[i, j] += dw[i, j]
        _mat3_dot_into(T, w, z)
        if dw_norm == 0 or (has_old and rate / (1 - rate) * dw_norm < tol):
            converged = True
            break
        dw_norm_old = dw_norm
        has_old = True
    return converged, k + 1, z, rate, nfev


@jit
def _newton_workspace(n, n_second, n_active):
    """Scratch arrays of :func:`_solve_collocation_system`: W, Z, F, a stage state, dW,
    and the right-hand sides and reduced vectors of the real and complex solves."""
    nk = n_active - n_second
    return (
        np.empty((3, n)),
        np.empty((3, n)),
        np.empty((3, n)),
        np.empty(n),
        np.empty((3, n)),
        np.empty(n),
        np.empty(n, dtype=np.complex128),
        np.empty(nk),
        np.empty(nk, dtype=np.complex128),
    )


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


@jit
def _jacobian_into(problem, t, y, f, factor, out):
    """The user's Jacobian where ``jac`` gives one, SciPy's ``num_jac`` otherwise, into
    ``out`` (n, n); ``factor`` is ``num_jac``'s, adapted in place."""
    if not problem.jac(t, y, f, problem.args, out):
        out[:, :] = num_jac(
            problem.fun, problem.args, t, y, f, problem.atol, factor, problem.n_active
        )


@jit
def _start(problem, t0, y0, f0, counters):
    """The state at ``(t0, y0)``: the Jacobian there (counted), no factors, no polynomial.

    Returns:
        ``(sc, jac, jac_factor, lu_real, piv_real, lu_complex, piv_complex, workspace,
        newton_scale, q, y_old)``: the scalars (slots ``_H_PROPOSED`` …), the Jacobian
        (n, n), ``num_jac``'s factors, the reduced Newton factors, Newton's scratch, the
        step's Newton scale, the collocation polynomial ``Q`` (n, 3) and its start ``y_old``.
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
        np.empty((nk, nk), dtype=np.complex128), np.zeros(nk, dtype=np.int64),
        _newton_workspace(n, problem.n_second, problem.n_active),
        np.empty(n), np.zeros((n, 3)), y0.copy(),
    )  # fmt: skip


@step_jit
def _begin(state, problem, t, y, f, h_abs, min_step, counters):
    """A step from ``(t, y)``: the proposed size clamped to ``[min_step, max_step]`` (a
    clamp forgets the last step for the controller, as SciPy), the Newton scale
    ``atol + rtol·|y|``. Returns the first try's size and no cap on the retries (SciPy's)."""
    sc, newton_scale = state[0], state[8]
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
    newton_scale[:] = tolerance_scale(y, problem.atol, problem.rtol)  # per step, as SciPy
    sc[_REJECTED] = 0.0
    return h_abs, np.inf


@step_jit
def _newton(state, problem, t, y, f, h, counters):
    """The collocation system at step ``h`` solved by simplified Newton, started from the
    last step's polynomial; on failure with a stale Jacobian, once more with a fresh one.
    Returns ``(converged, n_iter, Z, rate)``."""
    sc, jac, jac_factor, lu_real, piv_real, lu_complex, piv_complex, workspace = state[:8]
    newton_scale, q, y_old = state[8], state[9], state[10]
    n_second, n_active = problem.n_second, problem.n_active
    if sc[_HAS_SOL] != 0.0:
        z0 = _extrapolate(q, sc[_T_OLD], y_old, t, y, h)
    else:
        z0 = np.zeros((3, y.shape[0]))
    while True:
        if sc[_LU_VALID] == 0.0:
            _factor_into(jac, h, n_second, n_active, lu_real, piv_real, lu_complex, piv_complex)
            counters[NLU] += 2
            sc[_LU_VALID] = 1.0
        converged, n_iter, z, rate, nfev = _solve_collocation_system(
            problem.fun, problem.args, t, y, h, z0, newton_scale, sc[_NEWTON_TOL],
            lu_real, piv_real, lu_complex, piv_complex, jac, n_second, n_active, workspace,
        )  # fmt: skip
        counters[NFEV] += nfev
        if converged or sc[_CURRENT_JAC] != 0.0:
            return converged, n_iter, z, rate
        _jacobian_into(problem, t, y, f, jac_factor, jac)
        counters[NJEV] += 1
        sc[_CURRENT_JAC] = 1.0
        sc[_LU_VALID] = 0.0


@step_jit
def _attempt(state, problem, t, y, f, h, y_new, counters):
    """One try of the step ``h`` ([HW96] §IV.8; SciPy's ``Radau._step_impl``): Newton on
    the collocation system, ``y_new = y + Z₃``, the embedded error estimate (re-estimated
    with one more ``f`` after a rejection), the error test. Returns ``(passed, h_abs)``:
    ``h_abs`` to retry with after a failure (half after a Newton failure, else the
    predictive controller's, [HW96] (8.25)), counted in ``NREJ_NEWTON`` or ``NREJ_ERROR``."""
    sc, jac, lu_real, piv_real = state[0], state[1], state[3], state[4]
    n_second, n_active = problem.n_second, problem.n_active
    h_abs = abs(h)
    converged, n_iter, z, rate = _newton(state, problem, t, y, f, h, counters)
    if not converged:
        sc[_LU_VALID] = 0.0
        counters[NREJ_NEWTON] += 1
        return False, h_abs * 0.5

    for j in range(y.shape[0]):
        y_new[j] = y[j] + z[2, j]
    ze, error = _error_estimate(z, f, h, lu_real, piv_real, jac, n_second, n_active)
    scale = error_scale(y, y_new, problem.atol, problem.rtol)
    error_norm = rms_norm(error, scale)
    safety = 0.9 * (2 * NEWTON_MAXITER + 1) / (2 * NEWTON_MAXITER + n_iter)

    if sc[_REJECTED] != 0.0 and error_norm > 1:
        f_err = problem.fun(t, plus(y, error), problem.args)
        counters[NFEV] += 1
        error = _newton_solve(
            lu_real, piv_real, jac, MU_REAL / h, plus(f_err, ze), n_second, n_active
        )
        error_norm = rms_norm(error, scale)

    if error_norm > 1:
        factor = predict_factor(h_abs, sc[_H_OLD_STEP], error_norm, sc[_ERR_OLD_STEP])
        sc[_LU_VALID] = 0.0
        sc[_REJECTED] = 1.0
        counters[NREJ_ERROR] += 1
        return False, h_abs * py_max(MIN_FACTOR, safety * factor)
    sc[_N_ITER] = n_iter
    sc[_RATE] = rate
    sc[_ERROR] = error_norm
    sc[_SAFETY] = safety
    return True, h_abs


@step_jit
def _retry(state):
    """``step_check`` shortened the step: the factors are of the old step size."""
    state[0][_LU_VALID] = 0.0


@step_jit
def _accept(state, problem, t, y, t_new, y_new, f, h_abs, failed, changed, counters):
    """The accepted step ``(t, y) → (t_new, y_new)``, ``f = f(t_new, y_new)``: the next
    step's size from the predictive controller ([HW96] (8.25)), at most ``MAX_FACTOR``
    times larger, not larger at all after a failed try with ``hold_after_failure``, kept
    (with the factors) when it would grow less than 1.2 and Newton converged fast; the
    Jacobian recomputed at the new point when Newton converged slowly; the collocation
    polynomial for the next Newton start, unless ``after_step`` declared a discontinuity.
    Returns the next step's proposed size."""
    sc, jac, jac_factor, workspace, q, y_old = (
        state[0], state[1], state[2], state[7], state[9], state[10]
    )  # fmt: skip
    error_norm = sc[_ERROR]
    recompute_jac = sc[_N_ITER] > 2 and sc[_RATE] > 1e-3

    factor = predict_factor(h_abs, sc[_H_OLD_STEP], error_norm, sc[_ERR_OLD_STEP])
    factor = py_min(MAX_FACTOR, sc[_SAFETY] * factor)
    if problem.hold_after_failure and failed:
        factor = py_min(factor, 1.0)  # RADAU5: IF (REJECT) HNEW = MIN(HNEW, H)
    if not recompute_jac and factor < 1.2:
        factor = 1.0
    else:
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
    _interpolant_coefficients_into(workspace[1], q)
    sc[_HAS_SOL] = 0.0 if changed else 1.0
    return h_abs * factor


#: Radau IIA's steps for the loop (:func:`jointplay._kernels.driver.drive`).
STEPS = Steps(_start, _begin, _attempt, _retry, evaluate_f, _accept)


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
            :func:`jointplay._kernels.common.interrupt_pending`): once they hold SIGINT or
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
