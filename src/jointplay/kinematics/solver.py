"""General position, velocity and acceleration analysis of any mechanism the model describes.

Newton–Raphson on the constraint (loop-closure) equations Φ(q, t) = 0 in absolute coordinates
(Nikravesh 1988, §4.4), then the linear velocity and acceleration equations
Φ_q q̇ = ν and Φ_q q̈ = γ. Works for any single-degree-of-freedom mechanism with revolute and
prismatic joints; the four-bar and slider-crank closed forms are checked against it.
"""

from __future__ import annotations

from collections import deque
from collections.abc import Mapping

import numpy as np
from numpy.typing import NDArray

from jointplay._kernels import constraints as ck
from jointplay.errors import AssemblyError
from jointplay.model.flat import DRV_OMEGA, DRV_PHI0, DRV_RAMP, REVOLUTE, FlatModel

FloatArray = NDArray[np.float64]

#: Newton–Raphson stops when max |Φ| falls below this (m for joint rows, rad for angle rows).
POSITION_TOLERANCE = 1e-13

#: Largest change of any link angle in one Newton–Raphson iteration, rad.
MAX_ANGLE_STEP = 0.25


def driver_at(flat: FlatModel, crank_angle: float, crank_speed: float | None = None) -> FloatArray:
    """Driver parameters that put the crank at ``crank_angle`` at t = 0 (constant speed)."""
    driver = flat.driver.copy()
    driver[DRV_PHI0] = crank_angle
    driver[DRV_RAMP] = 0.0
    if crank_speed is not None:
        driver[DRV_OMEGA] = crank_speed
    return driver


def newton_raphson(
    flat: FlatModel,
    q_guess: FloatArray,
    driver: FloatArray,
    t: float = 0.0,
    *,
    tolerance: float = POSITION_TOLERANCE,
    max_iterations: int = 50,
) -> FloatArray:
    """Solve Φ(q, t) = 0 from ``q_guess``; raise :class:`AssemblyError` if it does not converge."""
    q = np.array(q_guess, dtype=float)
    ji, jf, active = flat.joint_int, flat.joint_f, flat.active
    norm = np.inf
    for _ in range(max_iterations):
        phi = ck.residual(q, t, ji, jf, active, driver)
        norm = float(np.max(np.abs(phi)))
        if norm < tolerance:
            return q
        jac = ck.jacobian(q, ji, jf, active, driver)
        step, *_ = np.linalg.lstsq(jac, -phi, rcond=None)
        # Damp large steps so a poor guess cannot jump to a far-away solution (the other
        # assembly branch): no link turns by more than MAX_ANGLE_STEP per iteration, and a
        # step that does not reduce the loop-closure error is halved (backtracking).
        largest = float(np.max(np.abs(step[2::3]))) if step.size else 0.0
        if largest > MAX_ANGLE_STEP:
            step *= MAX_ANGLE_STEP / largest
        for _ in range(30):
            trial = q + step
            if float(np.max(np.abs(ck.residual(trial, t, ji, jf, active, driver)))) < norm:
                break
            step *= 0.5
        q = trial
    raise AssemblyError(
        f"the mechanism cannot be assembled at crank angle {np.degrees(driver[DRV_PHI0]):.2f}° "
        f"(Newton–Raphson left a loop-closure error of {norm:.3g})"
    )


def velocities(flat: FlatModel, q: FloatArray, driver: FloatArray, t: float = 0.0) -> FloatArray:
    """Solve Φ_q q̇ = ν."""
    jac = ck.jacobian(q, flat.joint_int, flat.joint_f, flat.active, driver)
    return _solve(jac, ck.velocity_rhs(t, flat.active, driver), driver)


def accelerations(
    flat: FlatModel, q: FloatArray, qd: FloatArray, driver: FloatArray, t: float = 0.0
) -> FloatArray:
    """Solve Φ_q q̈ = γ."""
    jac = ck.jacobian(q, flat.joint_int, flat.joint_f, flat.active, driver)
    gamma = ck.acceleration_rhs(q, qd, t, flat.joint_int, flat.joint_f, flat.active, driver)
    return _solve(jac, gamma, driver)


def _solve(jac: FloatArray, rhs: FloatArray, driver: FloatArray) -> FloatArray:
    if jac.shape[0] == jac.shape[1]:
        try:
            cond = np.linalg.cond(jac)
            if cond < 1e12:
                return np.asarray(np.linalg.solve(jac, rhs), dtype=float)
        except np.linalg.LinAlgError:
            pass
    raise AssemblyError(
        f"the mechanism is at a singular position (dead centre) at crank angle "
        f"{np.degrees(driver[DRV_PHI0]):.2f}°: velocities are not determined by the crank"
    )


def solve_cycle(
    flat: FlatModel, crank_angles: FloatArray, q_start: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """q, q̇, q̈ at each crank angle, by continuation from ``q_start`` (keeps its branch).

    Each solution seeds the next angle, extrapolated to first order with q̇ (a tangent
    predictor), so the assembly branch of ``q_start`` is followed through the cycle.
    """
    n = len(crank_angles)
    q_all = np.empty((n, flat.n_coordinates))
    qd_all = np.empty_like(q_all)
    qdd_all = np.empty_like(q_all)
    q = np.asarray(q_start, dtype=float)
    previous_angle = crank_angles[0]
    omega = flat.driver[DRV_OMEGA]
    qd = np.zeros_like(q)
    for i, angle in enumerate(crank_angles):
        driver = driver_at(flat, float(angle))
        guess = q + qd * (angle - previous_angle) / omega if i else q
        q = newton_raphson(flat, guess, driver)
        qd = velocities(flat, q, driver)
        q_all[i], qd_all[i] = q, qd
        qdd_all[i] = accelerations(flat, q, qd, driver)
        previous_angle = angle
    return q_all, qd_all, qdd_all


def revolute_tree(flat: FlatModel) -> list[tuple[int, int, int]]:
    """(joint row, placed body, new body) in breadth-first order from the ground.

    Uses revolute joints only; every moving link must be reachable so that link angles
    determine all positions.
    """
    placed = {-1}
    order: list[tuple[int, int, int]] = []
    queue = deque([-1])
    while queue:
        body = queue.popleft()
        for row in range(flat.joint_int.shape[0]):
            kind, a, b = (int(v) for v in flat.joint_int[row])
            if kind != REVOLUTE or body not in (a, b):
                continue
            other = b if a == body else a
            if other in placed:
                continue
            placed.add(other)
            order.append((row, body, other))
            queue.append(other)
    missing = set(range(flat.n_bodies)) - placed
    if missing:
        names = [flat.link_names[k] for k in sorted(missing)]
        raise AssemblyError(
            f"links {names} are not connected to the ground through revolute joints"
        )
    return order


def state_from_angles(
    flat: FlatModel, phi: FloatArray, omega: FloatArray, alpha: FloatArray
) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Complete q, q̇, q̈ (N, 3nb) from link angles, rates and accelerations (N, nb).

    Centre-of-mass positions follow by walking the revolute joints from the ground (the
    joint points coincide), so a closed-form solution yields the same state arrays as the
    general solver.
    """
    n_samples = phi.shape[0]
    nb = flat.n_bodies
    pos = np.zeros((n_samples, nb, 2))
    vel = np.zeros_like(pos)
    acc = np.zeros_like(pos)

    def point_kinematics(body: int, s: FloatArray) -> tuple[FloatArray, FloatArray, FloatArray]:
        if body < 0:
            zero = np.zeros((n_samples, 2))
            return np.broadcast_to(s, (n_samples, 2)).copy(), zero, zero.copy()
        rs = _rotate(phi[:, body], s)
        w, al = omega[:, body][:, None], alpha[:, body][:, None]
        perp = np.column_stack([-rs[:, 1], rs[:, 0]])
        return pos[:, body] + rs, vel[:, body] + w * perp, acc[:, body] + al * perp - w**2 * rs

    for row, known, new in revolute_tree(flat):
        a = int(flat.joint_int[row, 1])
        s_known = flat.joint_f[row, 0:2] if known == a else flat.joint_f[row, 2:4]
        s_new = flat.joint_f[row, 2:4] if known == a else flat.joint_f[row, 0:2]
        p, v, ac = point_kinematics(known, s_known)
        rs = _rotate(phi[:, new], s_new)
        w, al = omega[:, new][:, None], alpha[:, new][:, None]
        perp = np.column_stack([-rs[:, 1], rs[:, 0]])
        pos[:, new] = p - rs
        vel[:, new] = v - w * perp
        acc[:, new] = ac - (al * perp - w**2 * rs)
    q = np.concatenate([pos, phi[:, :, None]], axis=2).reshape(n_samples, -1)
    qd = np.concatenate([vel, omega[:, :, None]], axis=2).reshape(n_samples, -1)
    qdd = np.concatenate([acc, alpha[:, :, None]], axis=2).reshape(n_samples, -1)
    return q, qd, qdd


def guess_from_angles(flat: FlatModel, angles: Mapping[int, float]) -> FloatArray:
    """A rough q from guessed link angles (rad, by body index; missing ones 0).

    Links are placed along the revolute tree so that tree joints coincide; loop-closing joints
    generally do not, which Newton–Raphson then corrects.
    """
    phi = np.array([[angles.get(k, 0.0) for k in range(flat.n_bodies)]])
    zeros = np.zeros_like(phi)
    q, _, _ = state_from_angles(flat, phi, zeros, zeros)
    return q[0]


def _rotate(phi: FloatArray, s: FloatArray) -> FloatArray:
    c, s_ = np.cos(phi), np.sin(phi)
    return np.column_stack([c * s[0] - s_ * s[1], s_ * s[0] + c * s[1]])
