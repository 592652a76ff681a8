"""The sustained-contact mode's accelerations: a locked clearance joint is the bilateral
constraint |e| = c, its normal force a multiplier.

The single engine's own functions, written like the lane source
(:mod:`jointplay._kernels.lanes.source`: the packed model ``rp``, ``ip`` read through ``lay``;
the source's functions called by name) and compiled into the same namespace by
:mod:`jointplay._kernels.shared` (:func:`jointplay._kernels.lanes.build.build`'s ``own``), so
that the right-hand side, the contact forces and the laws they use are the source's. They run
on the CPU only (they allocate: the mode's linear system changes size with the locked set),
which is why the lanes refuse the mode (:mod:`jointplay._kernels.capabilities`). A joint is
locked when its v0 slot is negative (:data:`jointplay._kernels.ids.LOCKED`); the switches
(capture, release) are :func:`jointplay._kernels.eom.switch_contacts`'.

Units are SI (m, rad, s, kg, N).
"""

from __future__ import annotations

import numpy as np

# Resolved in the namespace build.py makes (the source's functions and constants); imported
# here so that a reader and the linters find them.
from jointplay._kernels.lanes.source import (
    FRICTION_NONE,
    G_CLEARANCE,
    G_R_BEARING,
    G_R_JOURNAL,
    LY_DRIVER,
    LY_FRIC_ID,
    LY_FRIC_P,
    LY_GEOM,
    LY_MASS,
    LY_N,
    LY_NC,
    LY_PFRIC,
    N_GEOM,
    constraint_rows,
    constraint_terms,
    friction_force,
    joint_kinematics,
    push,
)
from jointplay._kernels.lanes.source_radau import lu_real, lu_solve_real

__all__ = ["locked_row", "sustained_accelerations", "sustained_locked_accelerations"]


def locked_row(y, rp, ip, lay, c, g_row, h_col):
    """The constraint |e| = c of locked clearance joint ``c`` at the state ``y``.

    Writes ``g_row`` (3 nb) = G_c = ∂δ/∂q = nᵀ ∂e/∂q: +[n_x, n_y, n·(ẑ×r_b)] on the
    journal's body b, −[n_x, n_y, n·(ẑ×r_a)] on the bearing's body a; and ``h_col`` (3 nb),
    the generalised force of a unit normal force F_N = 1 N with its friction F_T = μ(v_T):
    −(n + μ t) on the journal at r_b + R_J n, its opposite on the bearing at r_a + R_B n
    (as the source's ``contact_forces``; its normal part is −G_cᵀ). δ̈ = 0 reads
    G_c q̈ = γ_c with

        γ_c = −[(ė·t)² / |e| + n·(ω_a² r_a − ω_b² r_b)]

    (δ̈ = n·ë + ṅ·ė with ṅ = t (ė·t)/|e|, and n·ë = G_c q̈ + n·(ω_a² r_a − ω_b² r_b)
    since a centre at arm r accelerates as ẍ + φ̈ ẑ×r − ω² r).

    Returns:
        (γ_c in m/s², δ = |e| − c in m, δ̇ in m/s, v_T in m/s, μ = F_T / F_N).
    """
    o_geom = lay[LY_GEOM]
    a, b, rax, ray, rbx, rby, length, nx, ny, wa, wb, edx, edy = joint_kinematics(y, rp, ip, lay, c)
    tx, ty = -ny, nx
    delta_dot = edx * nx + edy * ny
    slide = edx * tx + edy * ty
    r_j = rp[o_geom + N_GEOM * c + G_R_JOURNAL]
    r_b = rp[o_geom + N_GEOM * c + G_R_BEARING]
    v_t = slide + r_j * wb - r_b * wa
    mu = 0.0
    fric = ip[lay[LY_FRIC_ID] + c]
    if fric != FRICTION_NONE:
        mu = friction_force(fric, rp, lay[LY_FRIC_P] + lay[LY_PFRIC] * c, v_t, 1.0)
    for i in range(g_row.shape[0]):
        g_row[i] = 0.0
        h_col[i] = 0.0
    if b >= 0:
        g_row[3 * b] = nx
        g_row[3 * b + 1] = ny
        g_row[3 * b + 2] = -nx * rby + ny * rbx
    if a >= 0:
        g_row[3 * a] -= nx
        g_row[3 * a + 1] -= ny
        g_row[3 * a + 2] -= -nx * ray + ny * rax
    fx = -nx - mu * tx
    fy = -ny - mu * ty
    push(h_col, 0, b, rbx + r_j * nx, rby + r_j * ny, fx, fy)
    push(h_col, 0, a, rax + r_b * nx, ray + r_b * ny, -fx, -fy)
    centripetal = nx * (wa * wa * rax - wb * wb * rbx) + ny * (wa * wa * ray - wb * wb * rby)
    gamma = -(slide * slide / length + centripetal)
    return gamma, length - rp[o_geom + N_GEOM * c + G_CLEARANCE], delta_dot, v_t, mu


def sustained_accelerations(t, y, rp, ip, lay, f, record, recording, lam):
    """The accelerations with the locked clearance joints as constraints.

    Unknowns x = [λ (ideal joints' rows, then the driver's), F_N of every locked joint];
    rows A = [Φ_q; G_c], force columns B = [Φ_qᵀ, −h_c] (:func:`locked_row`):

        q̈ = M⁻¹ (Q − B x),   (A M⁻¹ B) x = A M⁻¹ Q − [γ; γ_c],

    solved by LU with partial pivoting (A M⁻¹ B is not symmetric with friction). The
    normal force of a locked joint is its multiplier F_N (tensile if < 0: the joint is
    released after the step, :func:`jointplay._kernels.eom.release_check`), its friction
    F_T = μ(v_T) F_N.

    Args:
        f: ẏ being built: Q (without the locked joints' forces) in ``f[n:2n]`` on entry, q̈
            on return.
        record: the contact records (7 per joint), whose F_N and F_T of the locked joints
            are written here when ``recording``.
        lam: receives λ, as many rows as it has (none: nothing).

    Returns:
        (motor torque, N·m; the power absorbed by the locked contacts Σ F_N δ̇ + F_T v_T, W).
    """
    n = lay[LY_N]
    nc = lay[LY_NC]
    o_mass = lay[LY_MASS]
    rows = constraint_rows(rp, lay)
    phi_q = np.zeros((rows, n))
    gamma = np.zeros(rows)
    constraint_terms(t, y, rp, ip, lay, phi_q, gamma, True)
    m = 0
    for c in range(nc):
        if y[2 * n + 2 + c] < 0.0:
            m += 1
    k = rows + m
    rows_a = np.zeros((k, n))
    cols_b = np.zeros((k, n))  # B transposed
    rhs = np.empty(k)
    state = np.empty((m, 3))  # δ̇, v_T, μ of each locked joint
    which = np.empty(m, dtype=np.int64)
    for r in range(rows):
        for i in range(n):
            rows_a[r, i] = phi_q[r, i]
            cols_b[r, i] = phi_q[r, i]
        rhs[r] = gamma[r]
    r = rows
    for c in range(nc):
        if not y[2 * n + 2 + c] < 0.0:
            continue
        g, _, rate, slip, mu = locked_row(y, rp, ip, lay, c, rows_a[r], cols_b[r])
        for i in range(n):
            cols_b[r, i] = -cols_b[r, i]
        rhs[r] = g
        state[r - rows, 0] = rate
        state[r - rows, 1] = slip
        state[r - rows, 2] = mu
        which[r - rows] = c
        r += 1
    system = np.zeros((k, k))
    for p in range(k):
        s = -rhs[p]
        for i in range(n):
            w = rows_a[p, i] / rp[o_mass + i]
            if w != 0.0:
                s += w * f[n + i]
                for s2 in range(k):
                    system[p, s2] += w * cols_b[s2, i]
        rhs[p] = s
    piv = np.empty(k, dtype=np.int64)
    lu_real(system, piv, k)
    lu_solve_real(system, piv, rhs, k)
    for i in range(n):
        s = f[n + i]
        for p in range(k):
            s -= cols_b[p, i] * rhs[p]
        f[n + i] = s / rp[o_mass + i]
    for p in range(min(lam.shape[0], rows)):
        lam[p] = rhs[p]
    power = 0.0
    for i in range(m):
        f_n = rhs[rows + i]
        f_t = state[i, 2] * f_n
        power += f_n * state[i, 0] + f_t * state[i, 1]
        if recording:
            record[7 * which[i]] = f_n
            record[7 * which[i] + 1] = f_t
    torque = -rhs[rows - 1] if rp[lay[LY_DRIVER]] >= 0 and rows > 0 else 0.0
    return torque, power


def sustained_locked_accelerations(t, y, rp, ip, lay, f, record, recording, lam):
    """The single engine's ``locked_accelerations`` hook in the source's ``rhs``:
    :func:`sustained_accelerations` (compiled apart, not inlined into every caller)."""
    return sustained_accelerations(t, y, rp, ip, lay, f, record, recording, lam)
