"""Compiled constraint equations of planar joints and the driver (absolute coordinates).

Coordinates per body k: ``q[3k:3k+3] = (x, y, φ)`` of its centre of mass; ``A(φ)`` rotates
the body's local vectors into the global frame and ``B(φ) = dA/dφ``. The equations follow
Nikravesh, *Computer-Aided Analysis of Mechanical Systems* (1988), ch. 4–5:

- revolute (joint i–j):  Φ = r_i + A_i s_i − r_j − A_j s_j = 0                         (2 rows)
- prismatic (guide i, slider j): φ_j − φ_i − θ0 = 0 and n_i·d = 0 with
  d = r_j + A_j s_j − r_i − A_i s_i and n_i = A_i n'_i normal to the axis                  (2 rows)
- driver on body k:  φ_k − φ_d(t) = 0                                                    (1 row)
  (absent when the driver is off, body index < 0: the mechanism coasts)

Velocity equations Φ_q q̇ = ν and acceleration equations Φ_q q̈ = γ use the right-hand sides
computed here. Body index −1 is the ground (its point is global and fixed).
"""

from __future__ import annotations

import numpy as np
from numba import njit

from jointplay._kernels.shared import compiled

#: The driver's prescribed motion, written once in the lane source
#: (:func:`jointplay._kernels.lanes.source.driver_angle`, ``driver_speed``,
#: ``driver_acceleration``).
_driver_angle = compiled["driver_angle"]
_driver_speed = compiled["driver_speed"]
_driver_acceleration = compiled["driver_acceleration"]


@njit(cache=True)
def driver_motion(t: float, driver: np.ndarray) -> tuple[float, float, float]:
    """Prescribed crank angle, speed and acceleration at time ``t``.

    Constant speed ω (signed) from t = 0, or a smooth ramp of duration T = driver[3] > 0 in
    which ω(t) = ω·h(t/T) with the quintic STEP5 h(u) = u³(10 − 15u + 6u²) (MSC ADAMS STEP5),
    so the angle is φ0 + ωT·u⁴(2.5 − 3u + u²) and, after the ramp, φ0 + ωT/2 + ω(t − T).
    """
    return (
        _driver_angle(t, driver, 0),
        _driver_speed(t, driver, 0),
        _driver_acceleration(t, driver, 0),
    )


@njit(cache=True)
def _pose(q: np.ndarray, body: int) -> tuple[float, float, float]:
    if body < 0:
        return 0.0, 0.0, 0.0
    return q[3 * body], q[3 * body + 1], q[3 * body + 2]


@njit(cache=True)
def _rot(phi: float, sx: float, sy: float) -> tuple[float, float]:
    c = np.cos(phi)
    s = np.sin(phi)
    return c * sx - s * sy, s * sx + c * sy


@njit(cache=True)
def point_global(q: np.ndarray, body: int, sx: float, sy: float) -> tuple[float, float]:
    """Global position of the point with local coordinates (sx, sy) on ``body``."""
    x, y, phi = _pose(q, body)
    if body < 0:
        return sx, sy
    ax, ay = _rot(phi, sx, sy)
    return x + ax, y + ay


@njit(cache=True)
def count_rows(active: np.ndarray, driver: np.ndarray) -> int:
    """2 rows per active joint, plus 1 for the driver unless it is off (body index < 0)."""
    return 2 * int(active.sum()) + (1 if driver[0] >= 0 else 0)


@njit(cache=True)
def residual(
    q: np.ndarray,
    t: float,
    joint_int: np.ndarray,
    joint_f: np.ndarray,
    active: np.ndarray,
    driver: np.ndarray,
) -> np.ndarray:
    """Constraint violation Φ(q, t), m (joint rows) and rad (angle rows)."""
    out = np.zeros(count_rows(active, driver))
    row = 0
    for j in range(joint_int.shape[0]):
        if active[j] == 0:
            continue
        kind, a, b = joint_int[j, 0], joint_int[j, 1], joint_int[j, 2]
        pax, pay = point_global(q, a, joint_f[j, 0], joint_f[j, 1])
        pbx, pby = point_global(q, b, joint_f[j, 2], joint_f[j, 3])
        if kind == 0:
            out[row] = pax - pbx
            out[row + 1] = pay - pby
        else:
            phi_a = _pose(q, a)[2]
            phi_b = _pose(q, b)[2]
            out[row] = phi_b - phi_a - joint_f[j, 5]
            nx, ny = _rot(phi_a + joint_f[j, 4], 0.0, 1.0)
            out[row + 1] = nx * (pbx - pax) + ny * (pby - pay)
        row += 2
    body = int(driver[0])
    if body >= 0:
        out[row] = q[3 * body + 2] - driver_motion(t, driver)[0]
    return out


@njit(cache=True)
def jacobian(
    q: np.ndarray,
    joint_int: np.ndarray,
    joint_f: np.ndarray,
    active: np.ndarray,
    driver: np.ndarray,
) -> np.ndarray:
    """Constraint Jacobian Φ_q, shape (rows, 3 nb)."""
    n = q.shape[0]
    out = np.zeros((count_rows(active, driver), n))
    row = 0
    for j in range(joint_int.shape[0]):
        if active[j] == 0:
            continue
        kind, a, b = joint_int[j, 0], joint_int[j, 1], joint_int[j, 2]
        if kind == 0:
            # Φ = r_a + A_a s_a − r_b − A_b s_b ;  ∂(A s)/∂φ = B s = rot90(A s)
            for body, sx, sy, sign in (
                (a, joint_f[j, 0], joint_f[j, 1], 1.0),
                (b, joint_f[j, 2], joint_f[j, 3], -1.0),
            ):
                if body < 0:
                    continue
                ax, ay = _rot(q[3 * body + 2], sx, sy)
                out[row, 3 * body] += sign
                out[row + 1, 3 * body + 1] += sign
                out[row, 3 * body + 2] += -sign * ay
                out[row + 1, 3 * body + 2] += sign * ax
        else:
            phi_a = _pose(q, a)[2]
            pax, pay = point_global(q, a, joint_f[j, 0], joint_f[j, 1])
            pbx, pby = point_global(q, b, joint_f[j, 2], joint_f[j, 3])
            nx, ny = _rot(phi_a + joint_f[j, 4], 0.0, 1.0)
            dx, dy = pbx - pax, pby - pay
            if a >= 0:
                out[row, 3 * a + 2] = -1.0
                sax, say = _rot(phi_a, joint_f[j, 0], joint_f[j, 1])
                # ∂(n·d)/∂φ_a = (B n')·d − n·(B s_a) with B v = rot90(A v)
                out[row + 1, 3 * a] = -nx
                out[row + 1, 3 * a + 1] = -ny
                out[row + 1, 3 * a + 2] = (-ny * dx + nx * dy) - (nx * -say + ny * sax)
            if b >= 0:
                out[row, 3 * b + 2] = 1.0
                sbx, sby = _rot(q[3 * b + 2], joint_f[j, 2], joint_f[j, 3])
                out[row + 1, 3 * b] = nx
                out[row + 1, 3 * b + 1] = ny
                out[row + 1, 3 * b + 2] = nx * -sby + ny * sbx
        row += 2
    body = int(driver[0])
    if body >= 0:
        out[row, 3 * body + 2] = 1.0
    return out


@njit(cache=True)
def velocity_rhs(t: float, active: np.ndarray, driver: np.ndarray) -> np.ndarray:
    """ν = −Φ_t: zero for joints, the prescribed crank speed for the driver row."""
    out = np.zeros(count_rows(active, driver))
    if driver[0] >= 0:
        out[-1] = driver_motion(t, driver)[1]
    return out


@njit(cache=True)
def acceleration_rhs(
    q: np.ndarray,
    qd: np.ndarray,
    t: float,
    joint_int: np.ndarray,
    joint_f: np.ndarray,
    active: np.ndarray,
    driver: np.ndarray,
) -> np.ndarray:
    """γ with Φ_q q̈ = γ (Nikravesh 1988, eq. 4.x): quadratic velocity terms and the driver's φ̈."""
    out = np.zeros(count_rows(active, driver))
    row = 0
    for j in range(joint_int.shape[0]):
        if active[j] == 0:
            continue
        kind, a, b = joint_int[j, 0], joint_int[j, 1], joint_int[j, 2]
        if kind == 0:
            # γ = A_a s_a φ̇_a² − A_b s_b φ̇_b²
            for body, sx, sy, sign in (
                (a, joint_f[j, 0], joint_f[j, 1], 1.0),
                (b, joint_f[j, 2], joint_f[j, 3], -1.0),
            ):
                if body < 0:
                    continue
                ax, ay = _rot(q[3 * body + 2], sx, sy)
                w2 = qd[3 * body + 2] ** 2
                out[row] += sign * ax * w2
                out[row + 1] += sign * ay * w2
        else:
            phi_a = _pose(q, a)[2]
            wa = qd[3 * a + 2] if a >= 0 else 0.0
            wb = qd[3 * b + 2] if b >= 0 else 0.0
            nx, ny = _rot(phi_a + joint_f[j, 4], 0.0, 1.0)
            pax, pay = point_global(q, a, joint_f[j, 0], joint_f[j, 1])
            pbx, pby = point_global(q, b, joint_f[j, 2], joint_f[j, 3])
            dx, dy = pbx - pax, pby - pay
            sax, say = (0.0, 0.0) if a < 0 else _rot(phi_a, joint_f[j, 0], joint_f[j, 1])
            sbx, sby = (0.0, 0.0) if b < 0 else _rot(q[3 * b + 2], joint_f[j, 2], joint_f[j, 3])
            vax = (qd[3 * a] if a >= 0 else 0.0) - say * wa
            vay = (qd[3 * a + 1] if a >= 0 else 0.0) + sax * wa
            vbx = (qd[3 * b] if b >= 0 else 0.0) - sby * wb
            vby = (qd[3 * b + 1] if b >= 0 else 0.0) + sbx * wb
            ddx, ddy = vbx - vax, vby - vay
            # γ2 = n·d φ̇_a² − 2 φ̇_a (B_a n')·ḋ + n·(A_b s_b φ̇_b² − A_a s_a φ̇_a²)
            bnx, bny = -ny, nx
            out[row + 1] = (
                (nx * dx + ny * dy) * wa * wa
                - 2.0 * wa * (bnx * ddx + bny * ddy)
                + nx * (sbx * wb * wb - sax * wa * wa)
                + ny * (sby * wb * wb - say * wa * wa)
            )
        row += 2
    if driver[0] >= 0:
        out[row] = driver_motion(t, driver)[2]
    return out
