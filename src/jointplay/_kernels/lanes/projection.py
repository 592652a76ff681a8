"""The projection onto the ideal constraints with LAPACK's solve: the CPU's ``project`` hook.

After every accepted step, q and q̇ are projected onto Φ(q, t) = 0 and Φ_q q̇ = ν when the
constraints are violated beyond the projection tolerance (mass-weighted; Hairer, Lubich &
Wanner, *Geometric Numerical Integration*, §IV.4). Written like the lane source (the packed
model ``rp``, ``ip`` read through ``lay``; the source's constraint functions called by name)
but for the CPU only (it allocates and calls NumPy's ``linalg.solve``), and handed to
:func:`jointplay._kernels.lanes.build.build` as the ``project`` hook by both CPU targets: the
single engine (:mod:`jointplay._kernels.shared`) and the CPU lanes
(:mod:`jointplay._kernels.lanes.cpu`), so that they keep the same bits. The CUDA kernel runs
the source's own :func:`~jointplay._kernels.lanes.source.project` (Cholesky; the same
projection to round-off).
"""

from __future__ import annotations

import numpy as np

# Resolved in the namespace build.py makes; imported here so that a reader and the linters
# find them.
from jointplay._kernels.ids import N_WORK, S_PROJ_TOL, W_MAX_VIOLATION, W_PROJECTIONS
from jointplay._kernels.lanes.source import (
    LY_DRIVER,
    LY_MASS,
    LY_N,
    LY_NIDEAL,
    LY_SETTINGS,
    constraint_jacobian,
    constraint_residual,
    constraint_rows,
    driver_angle,
    driver_speed,
)

__all__ = ["N_WORK", "project_lapack"]


def project_lapack(t, y, rp, ip, lay, work, phi_q, schur, lam):
    """Project q and q̇ onto the ideal constraints when they are violated beyond the
    projection tolerance: at most three Newton steps q ← q − M⁻¹ Φ_qᵀ (Φ_q M⁻¹ Φ_qᵀ)⁻¹ Φ until
    max |Φ| ≤ 10⁻³ of the tolerance, then q̇ ← q̇ − M⁻¹ Φ_qᵀ (Φ_q M⁻¹ Φ_qᵀ)⁻¹ (Φ_q q̇ − ν);
    the largest violation and the number of projections into ``work`` (``W_*`` of
    :mod:`jointplay._kernels.ids`). ``phi_q``, ``schur``, ``lam``: the hook's work arrays,
    unused (it allocates its own). Returns: the state changed."""
    n = lay[LY_N]
    o_driver = lay[LY_DRIVER]
    tolerance = rp[lay[LY_SETTINGS] + S_PROJ_TOL]
    crank = int(rp[o_driver])
    if lay[LY_NIDEAL] == 0:  # the driver alone: check |φ_k − φ_d(t)| without building Φ
        if crank < 0:
            return False
        violation = abs(y[3 * crank + 2] - driver_angle(t, rp, o_driver))
        work[W_MAX_VIOLATION] = max(work[W_MAX_VIOLATION], violation)
        if violation <= tolerance:
            return False
    rows = constraint_rows(rp, lay)
    if rows == 0:
        return False
    phi = np.zeros(rows)
    constraint_residual(t, y, rp, ip, lay, phi)
    violation = np.max(np.abs(phi))
    work[W_MAX_VIOLATION] = max(work[W_MAX_VIOLATION], violation)
    if violation <= tolerance:
        return False
    inv_mass = 1.0 / rp[lay[LY_MASS] : lay[LY_MASS] + n]
    q = y[:n]
    qd = y[n : 2 * n]
    jac = np.zeros((rows, n))
    for _ in range(3):
        constraint_jacobian(y, rp, ip, lay, jac)
        weighted = jac * inv_mass
        q -= inv_mass * (jac.T @ np.linalg.solve(weighted @ jac.T, phi))
        constraint_residual(t, y, rp, ip, lay, phi)
        if np.max(np.abs(phi)) <= 1e-3 * tolerance:
            break
    constraint_jacobian(y, rp, ip, lay, jac)
    weighted = jac * inv_mass
    nu = np.zeros(rows)
    if crank >= 0:
        nu[rows - 1] = driver_speed(t, rp, o_driver)
    qd -= inv_mass * (jac.T @ np.linalg.solve(weighted @ jac.T, jac @ qd - nu))
    work[W_PROJECTIONS] += 1.0
    return True
