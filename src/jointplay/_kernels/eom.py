"""Compiled equations of motion of a mechanism with ideal and clearance revolute joints.

The model arrives as two flat buffers, as in Hairer's RADAU5 (``rpar``/``ipar``), packed by
:mod:`jointplay.dynamics.system`; :func:`views` unpacks them. State vector::

    y = [q (3 nb), q̇ (3 nb), W_motor, W_contact, v0 (n_clear)]

- q, q̇: centre-of-mass position and angle of every moving link and their rates;
- W_motor = ∫ τ ω_crank dt, the work of the motor (J);
- W_contact = ∫ Σ (F_N δ̇ + F_T v_T) dt, the work absorbed by the clearance contacts (J) —
  so KE + V_gravity − W_motor + W_contact is constant (energy balance);
- v0: penetration rate at the start of the current contact event of each clearance joint
  (m/s, 0 while free); it has zero time derivative and is set by :func:`after_step`.

Ideal joints and the driver are constraints Φ(q, t) = 0 (see :mod:`constraints`); with the
diagonal mass matrix M the accelerations follow from the Schur complement
(Φ_q M⁻¹ Φ_qᵀ) λ = Φ_q M⁻¹ Q − γ, q̈ = M⁻¹ (Q − Φ_qᵀ λ), and the motor torque is −λ_driver.
Position and velocity drift is removed after every accepted step by mass-weighted projection
(Hairer, Lubich & Wanner, *Geometric Numerical Integration*, §IV.4).

Clearance joint (Flores et al., *Kinematics and Dynamics of Multibody Systems with Imperfect
Joints*, 2008; shared/reference/contact-models.md §5): bearing on body a, journal on body b,
eccentricity e = r_J − r_B, penetration δ = |e| − c, normal n = e/|e|, δ̇ = ė·n,
v_T = ė·t + R_J ω_b − R_B ω_a with t = ẑ × n. The force on the journal, −F_N n − F_T t, acts
at Q_J = r_J + R_J n; its opposite acts on the bearing at Q_B = r_B + R_B n.
"""

from __future__ import annotations

import numpy as np
from numba import njit, types

from jointplay._kernels.constraints import (
    acceleration_rhs,
    jacobian,
    point_global,
    residual,
    velocity_rhs,
)
from jointplay._kernels.contact import FRICTION_NONE, friction_force, normal_force

# ipar header (counts); the arrays follow in the order of :func:`views`.
I_NB, I_NJ, I_NC, I_PLAW, I_PFRIC = 0, 1, 2, 3, 4
HEADER = 8
# settings block in rpar
S_ONSET_TOL, S_PROJ_TOL, S_V_MARK = 0, 1, 2
N_SETTINGS = 4
# stats block in rpar (written by after_step)
T_MAX_VIOLATION, T_PROJECTIONS = 0, 1
N_STATS = 4
# clearance geometry columns
G_R_BEARING, G_R_JOURNAL, G_CLEARANCE = 0, 1, 2
N_GEOM = 3

rhs_signature = types.float64[::1](
    types.float64, types.float64[::1], types.Tuple((types.float64[::1], types.int64[::1]))
)


@njit(cache=True)
def views(rpar: np.ndarray, ipar: np.ndarray):  # type: ignore[no-untyped-def]
    """Unpack the model buffers into named views (no copies)."""
    nb, nj, nc, plaw, pfric = ipar[I_NB], ipar[I_NJ], ipar[I_NC], ipar[I_PLAW], ipar[I_PFRIC]
    n = 3 * nb
    o = HEADER
    joint_int = ipar[o : o + 3 * nj].reshape((nj, 3))
    o += 3 * nj
    active = ipar[o : o + nj]
    o += nj
    clear_joint = ipar[o : o + nc]
    o += nc
    law_id = ipar[o : o + nc]
    o += nc
    fric_id = ipar[o : o + nc]
    r = 0
    mass = rpar[r : r + n]
    r += n
    gravity = rpar[r : r + n]
    r += n
    joint_f = rpar[r : r + 6 * nj].reshape((nj, 6))
    r += 6 * nj
    driver = rpar[r : r + 4]
    r += 4
    geom = rpar[r : r + N_GEOM * nc].reshape((nc, N_GEOM))
    r += N_GEOM * nc
    law_p = rpar[r : r + plaw * nc].reshape((nc, plaw))
    r += plaw * nc
    fric_p = rpar[r : r + pfric * nc].reshape((nc, pfric))
    r += pfric * nc
    settings = rpar[r : r + N_SETTINGS]
    r += N_SETTINGS
    stats = rpar[r : r + N_STATS]
    return (
        n, nc, joint_int, active, clear_joint, law_id, fric_id,
        mass, gravity, joint_f, driver, geom, law_p, fric_p, settings, stats,
    )  # fmt: skip


@njit(cache=True)
def _velocity(q: np.ndarray, qd: np.ndarray, body: int, px: float, py: float) -> tuple[float, float]:
    """Velocity of the global point (px, py) attached to ``body``."""
    if body < 0:
        return 0.0, 0.0
    w = qd[3 * body + 2]
    return qd[3 * body] - w * (py - q[3 * body + 1]), qd[3 * body + 1] + w * (px - q[3 * body])


@njit(cache=True)
def contact_kinematics(
    q: np.ndarray, qd: np.ndarray, joint_int: np.ndarray, joint_f: np.ndarray, j: int, geom_row: np.ndarray
) -> tuple[float, float, float, float, float, float, float]:
    """(δ, δ̇, v_T, n_x, n_y, e_x, e_y) of clearance joint row ``j`` (§5 of contact-models.md)."""
    a, b = joint_int[j, 1], joint_int[j, 2]
    bx, by = point_global(q, a, joint_f[j, 0], joint_f[j, 1])
    jx, jy = point_global(q, b, joint_f[j, 2], joint_f[j, 3])
    ex, ey = jx - bx, jy - by
    emag = np.sqrt(ex * ex + ey * ey)
    if emag > 0.0:
        nx, ny = ex / emag, ey / emag
    else:  # centred pin: any direction; the penetration is −c, so no force follows from it
        nx, ny = 1.0, 0.0
    vbx, vby = _velocity(q, qd, a, bx, by)
    vjx, vjy = _velocity(q, qd, b, jx, jy)
    edx, edy = vjx - vbx, vjy - vby
    wa = qd[3 * a + 2] if a >= 0 else 0.0
    wb = qd[3 * b + 2] if b >= 0 else 0.0
    delta = emag - geom_row[G_CLEARANCE]
    delta_dot = edx * nx + edy * ny
    v_t = -edx * ny + edy * nx + geom_row[G_R_JOURNAL] * wb - geom_row[G_R_BEARING] * wa
    return delta, delta_dot, v_t, nx, ny, ex, ey


@njit(cache=True)
def _apply(force: np.ndarray, q: np.ndarray, body: int, px: float, py: float, fx: float, fy: float) -> None:
    if body < 0:
        return
    force[3 * body] += fx
    force[3 * body + 1] += fy
    force[3 * body + 2] += (px - q[3 * body]) * fy - (py - q[3 * body + 1]) * fx


@njit(cache=True)
def evaluate(t: float, y: np.ndarray, rpar: np.ndarray, ipar: np.ndarray, contact_out: np.ndarray):  # type: ignore[no-untyped-def]
    """q̈, motor torque, contact power and multipliers λ (ideal joints' rows, then the driver's).

    Per clearance joint, (F_N, F_T, δ, δ̇, v_T, e_x, e_y) is written into ``contact_out``.
    """
    (n, nc, joint_int, active, clear_joint, law_id, fric_id,
     mass, gravity, joint_f, driver, geom, law_p, fric_p, settings, stats) = views(rpar, ipar)  # fmt: skip
    q = y[:n]
    qd = y[n : 2 * n]
    force = gravity.copy()
    contact_power = 0.0
    for c in range(nc):
        j = clear_joint[c]
        delta, delta_dot, v_t, nx, ny, ex, ey = contact_kinematics(q, qd, joint_int, joint_f, j, geom[c])
        f_n = 0.0
        f_t = 0.0
        if delta > 0.0:
            f_n = normal_force(law_id[c], law_p[c], delta, delta_dot, y[2 * n + 2 + c])
            if fric_id[c] != FRICTION_NONE:
                f_t = friction_force(fric_id[c], fric_p[c], v_t, f_n)
            # force on the journal: −F_N n − F_T t with t = (−n_y, n_x)
            fx = -f_n * nx + f_t * ny
            fy = -f_n * ny - f_t * nx
            a, b = joint_int[j, 1], joint_int[j, 2]
            bx, by = point_global(q, a, joint_f[j, 0], joint_f[j, 1])
            jx, jy = point_global(q, b, joint_f[j, 2], joint_f[j, 3])
            r_j, r_b = geom[c, G_R_JOURNAL], geom[c, G_R_BEARING]
            _apply(force, q, b, jx + r_j * nx, jy + r_j * ny, fx, fy)
            _apply(force, q, a, bx + r_b * nx, by + r_b * ny, -fx, -fy)
            contact_power += f_n * delta_dot + f_t * v_t
        contact_out[c, 0] = f_n
        contact_out[c, 1] = f_t
        contact_out[c, 2] = delta
        contact_out[c, 3] = delta_dot
        contact_out[c, 4] = v_t
        contact_out[c, 5] = ex
        contact_out[c, 6] = ey
    phi_q = jacobian(q, joint_int, joint_f, active, driver)
    gamma = acceleration_rhs(q, qd, t, joint_int, joint_f, active, driver)
    inv_mass = 1.0 / mass
    if phi_q.shape[0] == 0:  # no ideal joint and no driver: every body moves freely
        return inv_mass * force, 0.0, contact_power, np.zeros(0)
    weighted = phi_q * inv_mass  # Φ_q M⁻¹ (rows scaled column-wise)
    schur = weighted @ phi_q.T
    lam = np.linalg.solve(schur, weighted @ force - gamma)
    qdd = inv_mass * (force - phi_q.T @ lam)
    torque = -lam[-1] if driver[0] >= 0 else 0.0
    return qdd, torque, contact_power, lam


@njit(rhs_signature, cache=True)
def rhs(t: float, y: np.ndarray, args: tuple[np.ndarray, np.ndarray]) -> np.ndarray:
    """ẏ for the state layout of the module docstring."""
    rpar, ipar = args
    n = 3 * ipar[I_NB]
    nc = ipar[I_NC]
    scratch = np.empty((nc, 7))
    qdd, torque, contact_power, _ = evaluate(t, y, rpar, ipar, scratch)
    out = np.zeros(y.shape[0])
    out[:n] = y[n : 2 * n]
    out[n : 2 * n] = qdd
    crank = int(rpar[2 * n + 6 * ipar[I_NJ]])  # driver[0]: the driven body (< 0: none)
    if crank >= 0:
        out[2 * n] = torque * y[n + 3 * crank + 2]
    out[2 * n + 1] = contact_power
    return out


step_check_signature = types.float64(
    types.float64,
    types.float64[::1],
    types.float64,
    types.float64[::1],
    types.Tuple((types.float64[::1], types.int64[::1])),
)


@njit(step_check_signature, cache=True)
def step_check(
    t_old: float, y_old: np.ndarray, t_new: float, y_new: np.ndarray, args: tuple[np.ndarray, np.ndarray]
) -> float:
    """Contact-onset control: a step that enters contact deeper than the onset tolerance is
    retried, shortened by the secant estimate of the crossing (Flores & Ambrósio 2010).

    Endpoint checks suffice: the free region |e| <= c is convex, so a pin cannot pass into and
    back out of the wall along a (locally straight) step without ending in contact.
    """
    rpar, ipar = args
    (n, nc, joint_int, active, clear_joint, law_id, fric_id,
     mass, gravity, joint_f, driver, geom, law_p, fric_p, settings, stats) = views(rpar, ipar)  # fmt: skip
    tolerance = settings[S_ONSET_TOL]
    theta = 1.0
    for c in range(nc):
        j = clear_joint[c]
        old = contact_kinematics(y_old[:n], y_old[n : 2 * n], joint_int, joint_f, j, geom[c])[0]
        if old > 0.0:
            continue
        new = contact_kinematics(y_new[:n], y_new[n : 2 * n], joint_int, joint_f, j, geom[c])[0]
        if new > tolerance:
            theta = min(theta, (0.5 * tolerance - old) / (new - old))
    return theta


after_step_signature = types.boolean(
    types.float64, types.float64[::1], types.Tuple((types.float64[::1], types.int64[::1]))
)


@njit(after_step_signature, cache=True)
def after_step(t: float, y: np.ndarray, args: tuple[np.ndarray, np.ndarray]) -> bool:
    """Update each joint's contact-event memory v0 and project onto the ideal constraints."""
    rpar, ipar = args
    (n, nc, joint_int, active, clear_joint, law_id, fric_id,
     mass, gravity, joint_f, driver, geom, law_p, fric_p, settings, stats) = views(rpar, ipar)  # fmt: skip
    changed = False
    q = y[:n]
    qd = y[n : 2 * n]
    for c in range(nc):
        j = clear_joint[c]
        delta, delta_dot, _, _, _, _, _ = contact_kinematics(q, qd, joint_int, joint_f, j, geom[c])
        slot = 2 * n + 2 + c
        if delta > 0.0 and y[slot] <= 0.0:
            y[slot] = max(delta_dot, settings[S_V_MARK])  # a new contact event begins
            changed = True
        elif delta <= 0.0 and y[slot] > 0.0:
            y[slot] = 0.0  # the event has ended
            changed = True
    phi = residual(q, t, joint_int, joint_f, active, driver)
    if phi.shape[0] == 0:
        return changed
    violation = np.max(np.abs(phi))
    stats[T_MAX_VIOLATION] = max(stats[T_MAX_VIOLATION], violation)
    if violation > settings[S_PROJ_TOL]:
        inv_mass = 1.0 / mass
        for _ in range(3):
            phi_q = jacobian(q, joint_int, joint_f, active, driver)
            weighted = phi_q * inv_mass
            q -= inv_mass * (phi_q.T @ np.linalg.solve(weighted @ phi_q.T, phi))
            phi = residual(q, t, joint_int, joint_f, active, driver)
            if np.max(np.abs(phi)) <= 1e-3 * settings[S_PROJ_TOL]:
                break
        phi_q = jacobian(q, joint_int, joint_f, active, driver)
        weighted = phi_q * inv_mass
        drift = phi_q @ qd - velocity_rhs(t, active, driver)
        qd -= inv_mass * (phi_q.T @ np.linalg.solve(weighted @ phi_q.T, drift))
        stats[T_PROJECTIONS] += 1.0
        changed = True
    return changed


@njit(cache=True)
def diagnostics(t: np.ndarray, y: np.ndarray, rpar: np.ndarray, ipar: np.ndarray):  # type: ignore[no-untyped-def]
    """Per recorded state: q̈ (N, 3nb), torque (N,), contacts (N, nc, 7), ideal-joint reactions
    (N, nj, 2: force of the joint's link a on its link b, N; zero rows for clearance joints)
    and the constraint violation max |Φ| (N,)."""
    n = 3 * ipar[I_NB]
    nc = ipar[I_NC]
    count = t.shape[0]
    (_, _, joint_int, active, _, _, _, _, _, joint_f, driver, _, _, _, _, _) = views(rpar, ipar)
    nj = joint_int.shape[0]
    qdd = np.empty((count, n))
    torque = np.empty(count)
    contacts = np.empty((count, nc, 7))
    reactions = np.zeros((count, nj, 2))
    violation = np.empty(count)
    for i in range(count):
        yi = np.ascontiguousarray(y[i])
        qdd[i], torque[i], _, lam = evaluate(t[i], yi, rpar, ipar, contacts[i])
        row = 0
        for j in range(nj):
            if active[j] == 1:
                reactions[i, j, 0] = lam[row]
                reactions[i, j, 1] = lam[row + 1]
                row += 2
        phi = residual(yi[:n], t[i], joint_int, joint_f, active, driver)
        violation[i] = np.max(np.abs(phi)) if phi.shape[0] else 0.0
    return qdd, torque, contacts, reactions, violation
