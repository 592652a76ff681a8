"""Small dense linear algebra for the compiled integrators: LU with partial pivoting.

One generic routine, compiled for float64 and complex128 (Radau IIA factors one real and
one complex Newton matrix per step): the same pivots as LAPACK ``?getrf`` (largest
``|re| + |im|``, as ``i?amax``), not the same round-off. A singular matrix is not an error:
its zero pivot stays in place and the solve gives inf/NaN, which the integrator treats as a
failed Newton iteration (kernels never raise).
"""

from __future__ import annotations

import numpy as np

from jointplay._kernels.common import jit

__all__ = ["lu_factor", "lu_factor_in_place", "lu_solve", "lu_solve_in_place"]


@jit
def lu_factor(a):
    """LU factorisation with partial pivoting, ``P·A = L·U`` (as LAPACK ``?getrf``).

    Args:
        a: Square matrix, float64 or complex128, shape (n, n); not modified.

    Returns:
        ``(lu, piv)``: ``L`` (unit lower, below the diagonal) and ``U`` packed in one
        matrix, and the row interchanges (row ``k`` was swapped with row ``piv[k]``).
        A zero pivot is left in place (the matrix is singular): solving then gives
        inf/NaN, which the integrator treats as a failed Newton iteration.
    """
    lu = a.copy()
    piv = np.empty(a.shape[0], dtype=np.int64)
    lu_factor_in_place(lu, piv)
    return lu, piv


@jit
def lu_factor_in_place(lu, piv):
    """:func:`lu_factor` overwriting ``lu`` (the matrix on entry) with its factors and
    ``piv`` (int64, (n,)) with the row interchanges: no allocation."""
    n = lu.shape[0]
    for k in range(n):
        p = k
        amax = abs(lu[k, k].real) + abs(lu[k, k].imag)
        for i in range(k + 1, n):
            v = abs(lu[i, k].real) + abs(lu[i, k].imag)
            if v > amax:
                amax = v
                p = i
        piv[k] = p
        if p != k:
            for j in range(n):
                tmp = lu[k, j]
                lu[k, j] = lu[p, j]
                lu[p, j] = tmp
        pivot = lu[k, k]
        if pivot != 0:
            for i in range(k + 1, n):
                lu[i, k] = lu[i, k] / pivot
            for i in range(k + 1, n):
                lik = lu[i, k]
                if lik != 0:
                    for j in range(k + 1, n):
                        lu[i, j] -= lik * lu[k, j]


@jit
def lu_solve_in_place(lu, piv, x):
    """:func:`lu_solve` overwriting ``x`` (the right-hand side) with the solution."""
    n = lu.shape[0]
    for k in range(n):
        p = piv[k]
        if p != k:
            tmp = x[k]
            x[k] = x[p]
            x[p] = tmp
    for i in range(n):
        s = x[i]
        for j in range(i):
            s -= lu[i, j] * x[j]
        x[i] = s
    for i in range(n - 1, -1, -1):
        s = x[i]
        for j in range(i + 1, n):
            s -= lu[i, j] * x[j]
        x[i] = s / lu[i, i]


@jit
def lu_solve(lu, piv, b):
    """Solve ``A x = b`` from ``lu_factor(A)``.

    Args:
        lu: Packed factors from :func:`lu_factor`, shape (n, n).
        piv: Row interchanges from :func:`lu_factor`, shape (n,).
        b: Right-hand side, shape (n,), same dtype as ``lu``; not modified.

    Returns:
        The solution ``x``, shape (n,).
    """
    x = b.copy()
    lu_solve_in_place(lu, piv, x)
    return x
