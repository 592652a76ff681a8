"""Step-size helpers shared by the compiled integrators, as SciPy's ``_ivp/common.py``.

The pieces of :mod:`jointplay._kernels.radau` that are not the Radau IIA method itself:
the status codes and counter names an integration returns, the RMS error norm and the
tolerance scales, the predictive step-size factor ([HW96]_ §IV.8, (8.25)), the initial step
selection (Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4) and the forward-difference
Jacobian (SciPy's ``num_jac``, dense branch), each ported from SciPy 1.17 with its constants.
Everything is ``njit(cache=True, error_model="numpy")`` (:data:`jit`): a division by zero
gives inf/NaN, as in SciPy, instead of raising.

References:
    .. [HW96] E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II: Stiff and
       Differential-Algebraic Problems*, 2nd ed., Springer, 1996, §IV.8.
"""

from __future__ import annotations

import numba
import numpy as np

from jointplay._kernels.ids import (
    NUM_JAC_DIFF_BIG,
    NUM_JAC_DIFF_REJECT,
    NUM_JAC_DIFF_SMALL,
    NUM_JAC_FACTOR_DECREASE,
    NUM_JAC_FACTOR_INCREASE,
    NUM_JAC_MAX_FACTOR,
    NUM_JAC_MIN_FACTOR,
)
from jointplay._kernels.lanes.cpu import compiled as _lanes
from jointplay._kernels.shared import compiled as _shared

__all__ = [
    "all_finite",
    "copy_vector",
    "jit",
    "num_jac",
    "py_max",
    "py_min",
    "select_initial_step",
]


# error_model="numpy": a division by zero gives inf/NaN (as in SciPy) instead of raising.
jit = numba.njit(cache=True, error_model="numpy")


# ---------------------------------------------------------------------------------------
# Scalar and vector helpers.
# ---------------------------------------------------------------------------------------
@jit
def py_min(a, b):
    """Python's ``min(a, b)``: ``a`` unless ``b < a`` (so ``min(1, nan) == 1``, as in SciPy)."""
    return b if b < a else a


@jit
def py_max(a, b):
    """Python's ``max(a, b)``: ``a`` unless ``b > a`` (so ``max(0.2, nan) == 0.2``)."""
    return b if b > a else a


#: SciPy's initial step, its two halves (the lane source's, :func:`select_initial_step`).
_initial_trial = _lanes["initial_trial"]
_initial_choice = _lanes["initial_choice"]
#: ``all_finite(x, size)``: whether ``x[:size]`` is all finite (the lane source's).
all_finite = _shared["all_finite"]


@jit
def copy_vector(x):
    """``x`` as a new C-contiguous float64 array (``fun`` may return any layout)."""
    n = x.shape[0]
    out = np.empty(n)
    for j in range(n):
        out[j] = x[j]
    return out


# ---------------------------------------------------------------------------------------
# Finite-difference Jacobian (SciPy's num_jac, dense branch).
# ---------------------------------------------------------------------------------------
@jit
def _column_difference(f, f_col, j, diff, max_diff, scale):
    """Column ``j`` of ``f_new − f``, its largest entry and the scale of that entry."""
    n = f.shape[0]
    for i in range(n):
        diff[i, j] = f_col[i] - f[i]
    # np.argmax(np.abs(diff), axis=0): the first largest entry.
    imax = 0
    vmax = abs(diff[0, j])
    for i in range(1, n):
        v = abs(diff[i, j])
        if v > vmax:
            vmax = v
            imax = i
    max_diff[j] = vmax
    scale[j] = max(abs(f[imax]), abs(f_col[imax]))


@jit
def num_jac(fun, args, t, y, f, threshold, factor, n_active):
    """Forward-difference Jacobian ``∂f/∂y`` with adaptive steps (SciPy's ``num_jac``).

    Args:
        fun: Right-hand side ``fun(t, y, args)``.
        args: Passed through to ``fun``.
        t: Time.
        y: State, shape (n,).
        f: ``fun(t, y, args)``, shape (n,).
        threshold: Floor of ``|y|`` in the step (``atol``), shape (n,).
        factor: Relative steps, shape (n,); adapted in place for the next call.
        n_active: Only the columns ``[0, n_active)`` are differenced; the others are zero
            (passive components, see :func:`radau_integrate`; ``n`` in SciPy).

    Returns:
        The Jacobian, shape (n, n).
    """
    n = y.shape[0]
    na = n_active
    y_scale = np.empty(n)
    h = np.empty(n)
    for j in range(n):
        # Step in the direction the ODE goes, hoping it stays in the problem's domain.
        f_sign = 1.0 if f[j] >= 0 else -1.0
        y_scale[j] = f_sign * max(threshold[j], abs(y[j]))
        h[j] = (y[j] + factor[j] * y_scale[j]) - y[j]
        while h[j] == 0:  # Ends, as in SciPy, once the step is non-zero or NaN.
            factor[j] *= 10.0
            h[j] = (y[j] + factor[j] * y_scale[j]) - y[j]

    diff = np.empty((n, n))
    max_diff = np.empty(n)
    scale = np.empty(n)
    ytmp = y.copy()
    for j in range(na):
        ytmp[j] = y[j] + h[j]
        f_col = fun(t, ytmp, args)
        ytmp[j] = y[j]
        _column_difference(f, f_col, j, diff, max_diff, scale)

    # A column whose difference drowns in round-off is retried with a 10x larger step,
    # and the retry is kept if its difference is larger relative to its scale.
    diff_new = np.empty((n, n))
    max_diff_new = np.empty(n)
    scale_new = np.empty(n)
    for j in range(na):
        if not max_diff[j] < NUM_JAC_DIFF_REJECT * scale[j]:
            continue
        new_factor = NUM_JAC_FACTOR_INCREASE * factor[j]
        h_new = (y[j] + new_factor * y_scale[j]) - y[j]
        ytmp[j] = y[j] + h_new
        f_col = fun(t, ytmp, args)
        ytmp[j] = y[j]
        _column_difference(f, f_col, j, diff_new, max_diff_new, scale_new)
        if max_diff[j] * scale_new[j] < max_diff_new[j] * scale[j]:
            factor[j] = new_factor
            h[j] = h_new
            for i in range(n):
                diff[i, j] = diff_new[i, j]
            scale[j] = scale_new[j]
            max_diff[j] = max_diff_new[j]

    jac = np.zeros((n, n))
    for j in range(na):
        for i in range(n):
            jac[i, j] = diff[i, j] / h[j]
        if max_diff[j] < NUM_JAC_DIFF_SMALL * scale[j]:
            factor[j] *= NUM_JAC_FACTOR_INCREASE
        elif max_diff[j] > NUM_JAC_DIFF_BIG * scale[j]:
            factor[j] *= NUM_JAC_FACTOR_DECREASE
        factor[j] = min(max(factor[j], NUM_JAC_MIN_FACTOR), NUM_JAC_MAX_FACTOR)
    return jac


# ---------------------------------------------------------------------------------------
# Initial step.
# ---------------------------------------------------------------------------------------
@jit
def select_initial_step(fun, args, t0, y0, t_bound, max_step, f0, direction, rtol, atol):
    """SciPy's ``select_initial_step`` for an error estimator of order 3 (the lane source's
    ``initial_trial`` and ``initial_choice`` around ``fun``).

    Returns:
        ``(h_abs, nfev)``.
    """
    n = y0.shape[0]
    interval_length = abs(t_bound - t0)
    if interval_length == 0.0:
        return 0.0, 0
    scale = np.empty(n)
    h0, d1 = _initial_trial(y0, f0, rtol, atol, scale, interval_length, n)
    y1 = np.empty(n)
    for j in range(n):
        y1[j] = y0[j] + h0 * direction * f0[j]
    f1 = fun(t0 + h0 * direction, y1, args)
    df = np.empty(n)
    return _initial_choice(f0, f1, df, scale, d1, h0, interval_length, max_step, n), 1
