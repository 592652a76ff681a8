"""The sustained-contact mode: a locked clearance joint is the bilateral constraint |e| = c, its
normal force a multiplier; its accelerations, its release control and its switches (capture,
release) after a step.

The CPU's own functions, written like the lane source
(:mod:`jointplay._kernels.lanes.source`: the packed model ``rp``, ``ip`` read through ``lay``;
the source's functions called by name) and compiled into the same namespace by both CPU
targets, the single engine (:mod:`jointplay._kernels.shared`) and the CPU lanes
(:mod:`jointplay._kernels.lanes.cpu`), with :func:`jointplay._kernels.lanes.build.build`'s
``own`` (:data:`OWN`) and ``hooks`` (:data:`HOOKS`: they fill the source's
``locked_accelerations``, ``release_fraction`` and ``switch_contacts``), so that the
right-hand side, the contact forces and the laws they use are the source's and both engines
take the same steps. They run on the CPU only (they allocate, and the projection calls
LAPACK: the mode's linear system changes size with the locked set), which is why the GPU
lanes refuse the mode (:mod:`jointplay._kernels.capabilities`). A joint is locked when its
v0 slot is negative (:data:`jointplay._kernels.ids.LOCKED`).

Units are SI (m, rad, s, kg, N).
"""

from __future__ import annotations

from collections.abc import Callable
from typing import Any

import numpy as np

# Resolved in the namespace build.py makes (the source's functions and constants); imported
# here so that a reader and the linters find them.
from jointplay._kernels.ids import (
    G_CAPTURE,
    LOCKED,
    RELEASE_TOL,
    S_PROJ_TOL,
    W_MAX_VIOLATION,
    W_PROJECTIONS,
)
from jointplay._kernels.lanes.source import (
    FRICTION_NONE,
    G_CLEARANCE,
    G_R_BEARING,
    G_R_JOURNAL,
    LY_DRIVER,
    LY_FRIC_ID,
    LY_FRIC_P,
    LY_GEOM,
    LY_GRAVITY,
    LY_MASS,
    LY_N,
    LY_NC,
    LY_PFRIC,
    LY_SETTINGS,
    LY_SIZE,
    N_GEOM,
    constraint_jacobian,
    constraint_residual,
    constraint_rows,
    constraint_terms,
    driver_speed,
    friction_force,
    joint_kinematics,
    locked,
    penetration_and_rate,
    push,
    rhs,
)
from jointplay._kernels.lanes.source_radau import lu_real, lu_solve_real

__all__ = [
    "HOOKS", "OWN", "contact_records", "locked_count", "locked_row", "mechanical_energy", "project_locked",
    "sustained_accelerations", "sustained_locked_accelerations", "sustained_release_fraction",
    "sustained_switch_contacts",
]  # fmt: skip


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


def locked_count(y, lay):
    """How many clearance joints are locked at ``y`` (their v0 slot negative)."""
    n = lay[LY_N]
    m = 0
    for c in range(lay[LY_NC]):
        if y[2 * n + 2 + c] < 0.0:
            m += 1
    return m


def sustained_accelerations(t, y, rp, ip, lay, f, record, recording, lam):
    """The accelerations with the locked clearance joints as constraints.

    Unknowns x = [λ (ideal joints' rows, then the driver's), F_N of every locked joint];
    rows A = [Φ_q; G_c], force columns B = [Φ_qᵀ, −h_c] (:func:`locked_row`):

        q̈ = M⁻¹ (Q − B x),   (A M⁻¹ B) x = A M⁻¹ Q − [γ; γ_c],

    solved by LU with partial pivoting (A M⁻¹ B is not symmetric with friction). The
    normal force of a locked joint is its multiplier F_N (tensile if < 0: the joint is
    released after the step, :func:`sustained_release_fraction`), its friction
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
    m = locked_count(y, lay)
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


def contact_records(t, y, rp, ip, lay, record):
    """Every joint's contact record at ``(t, y)`` into ``record`` (7 per joint: F_N, F_T, δ,
    δ̇, v_T, e_x, e_y; a locked joint's F_N its multiplier), by the source's ``rhs``."""
    n = lay[LY_N]
    rows = constraint_rows(rp, lay)
    f = np.empty(lay[LY_SIZE])
    rhs(t, y, rp, ip, lay, f, record, True, np.empty((rows, n)), np.empty((rows, rows)),
        np.zeros(rows))  # fmt: skip


def sustained_release_fraction(t_old, y_old, t_new, y_new, rp, ip, lay):
    """The step's fraction that ends where the first locked joint's multiplier F_N turns
    tensile (secant between the step's ends, aiming at −RELEASE_TOL/2 · max(F_N, 1 N)); 1 if
    none turns tensile beyond the tolerance (the source's ``release_fraction`` hook; as the
    onset control for an onset)."""
    n = lay[LY_N]
    nc = lay[LY_NC]
    old = np.zeros(7 * nc)
    new = np.zeros(7 * nc)
    contact_records(t_old, y_old, rp, ip, lay, old)
    contact_records(t_new, y_new, rp, ip, lay, new)
    theta = 1.0
    for c in range(nc):
        if not y_new[2 * n + 2 + c] < 0.0:
            continue
        f_old, f_new = old[7 * c], new[7 * c]
        tolerance = RELEASE_TOL * max(f_old, 1.0)
        if f_old > 0.0 and f_new < -tolerance:
            theta = min(theta, (f_old + 0.5 * tolerance) / (f_old - f_new))
    return theta


def mechanical_energy(y, rp, lay):
    """KE + V_gravity at ``y``, J (V = −Σ Q_gravity,i q_i: gravity is constant)."""
    n = lay[LY_N]
    o_mass = lay[LY_MASS]
    o_gravity = lay[LY_GRAVITY]
    e = 0.0
    for i in range(n):
        e += 0.5 * rp[o_mass + i] * y[n + i] * y[n + i] - rp[o_gravity + i] * y[i]
    return e


def project_locked(t, y, rp, ip, lay, work, drift):
    """Mass-weighted projection of q onto Φ = 0 and |e| = c of every locked joint, and of q̇
    onto Φ_q q̇ = ν, G_c q̇ = 0 (as the ``project`` hook, with the rows of :func:`locked_row`);
    the mechanical energy it removes (KE + V before minus after, J) is added to W_contact, so
    that the energy balance still closes. ``drift``: the violation is drift, recorded in
    ``work`` as the largest violation (``False`` at a capture, where it is the penetration
    the capture removes). Returns: the positions moved by more than the projection
    tolerance."""
    n = lay[LY_N]
    nc = lay[LY_NC]
    o_mass = lay[LY_MASS]
    q = y[:n]
    qd = y[n : 2 * n]
    tolerance = rp[lay[LY_SETTINGS] + S_PROJ_TOL]
    before = mechanical_energy(y, rp, lay)
    rows = constraint_rows(rp, lay)
    m = locked_count(y, lay)
    k = rows + m
    a = np.zeros((k, n))
    h = np.empty(n)
    value = np.empty(k)
    inv_mass = 1.0 / rp[o_mass : o_mass + n]
    moved = False
    for iteration in range(4):
        constraint_jacobian(y, rp, ip, lay, a)  # rows 0 … rows − 1
        constraint_residual(t, y, rp, ip, lay, value)
        r = rows
        for c in range(nc):
            if y[2 * n + 2 + c] < 0.0:
                value[r] = locked_row(y, rp, ip, lay, c, a[r], h)[1]
                r += 1
        violation = np.max(np.abs(value))
        if iteration == 0:
            if drift:
                work[W_MAX_VIOLATION] = max(work[W_MAX_VIOLATION], violation)
            moved = violation > tolerance
        if violation <= 1e-3 * tolerance or iteration == 3:
            break
        weighted = a * inv_mass
        q -= inv_mass * (a.T @ np.linalg.solve(weighted @ a.T, value))
    rate = np.zeros(k)
    nu = np.zeros(rows)  # ν = −Φ_t: zero for joints, the crank speed for the driver's row
    if rp[lay[LY_DRIVER]] >= 0:
        nu[rows - 1] = driver_speed(t, rp, lay[LY_DRIVER])
    for r in range(k):
        s = -nu[r] if r < rows else 0.0
        for i in range(n):
            s += a[r, i] * qd[i]
        rate[r] = s
    weighted = a * inv_mass
    qd -= inv_mass * (a.T @ np.linalg.solve(weighted @ a.T, rate))
    y[2 * n + 1] += before - mechanical_energy(y, rp, lay)
    work[W_PROJECTIONS] += 1.0
    return moved


def sustained_switch_contacts(t, y, rp, ip, lay, work, before):
    """The sustained-contact mode's switches after an accepted step (the source's
    ``switch_contacts`` hook, called with the mode on only).

    Release: a locked joint whose multiplier F_N is negative (tensile) at ``y`` becomes a
    free compliant joint (v0 = 0). Capture: a compliant contact in progress (v0 > 0, δ > 0)
    whose normal relative speed |δ̇| is below its capture speed (``geom`` column
    ``G_CAPTURE``) at both ends of the step (``before``: the contact records at its start,
    7 per joint) becomes locked (v0 = :data:`LOCKED`). Both ends: the turning point of an
    impact (δ̇ = 0 at the deepest penetration) passes within a step, so it is not captured,
    and its rebound is kept; a pressed pin whose radial oscillation has a speed amplitude of
    a few capture speeds is. The joints locked before the step are projected onto |e| = c
    with δ̇ = 0 (:func:`project_locked`, drift) before the capture test, and again after a
    capture (removing the captured pin's small penetration and normal speed). Returns: a
    joint switched or the positions moved beyond the tolerance.
    """
    n = lay[LY_N]
    nc = lay[LY_NC]
    o_geom = lay[LY_GEOM]
    changed = False
    if locked(y, rp, lay):
        record = np.zeros(7 * nc)
        contact_records(t, y, rp, ip, lay, record)
        for c in range(nc):
            if y[2 * n + 2 + c] < 0.0 and record[7 * c] < 0.0:
                y[2 * n + 2 + c] = 0.0
                changed = True
    if locked(y, rp, lay) and project_locked(t, y, rp, ip, lay, work, True):
        changed = True
    memory = y[2 * n + 2 :].copy()
    captured = False
    for c in range(nc):
        capture = rp[o_geom + N_GEOM * c + G_CAPTURE]
        if not (y[2 * n + 2 + c] > 0.0 and capture > 0.0):
            continue
        delta, delta_dot = penetration_and_rate(y, rp, ip, lay, c)
        slow = abs(delta_dot) < capture
        slow = slow and before[7 * c + 2] > 0.0 and abs(before[7 * c + 3]) < capture
        if delta > 0.0 and slow:
            y[2 * n + 2 + c] = LOCKED
            captured = True
    if captured:  # a joint whose multiplier would be tensile at once is left compliant
        record = np.zeros(7 * nc)
        contact_records(t, y, rp, ip, lay, record)
        captured_one = False
        for c in range(nc):
            if y[2 * n + 2 + c] < 0.0 and memory[c] > 0.0:
                if record[7 * c] < 0.0:
                    y[2 * n + 2 + c] = memory[c]
                else:
                    captured_one = True
        if captured_one:
            project_locked(t, y, rp, ip, lay, work, False)
            changed = True
    return changed


#: The mode's functions each CPU target compiles apart, not inlined (they allocate and run
#: only while a joint is locked, or with the mode on after a step).
OWN: dict[str, Callable[..., Any]] = {
    "locked_count": locked_count,
    "sustained_accelerations": sustained_accelerations,
    "locked_row": locked_row,
    "contact_records": contact_records,
    "mechanical_energy": mechanical_energy,
    "project_locked": project_locked,
}
#: The source's hooks the CPU targets fill with the mode's functions.
HOOKS: dict[str, Callable[..., Any]] = {
    "locked_accelerations": sustained_locked_accelerations,
    "release_fraction": sustained_release_fraction,
    "switch_contacts": sustained_switch_contacts,
}
