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

The equations are the lane source's (:mod:`jointplay._kernels.lanes.source`:
``constraint_residual``, ``constraint_jacobian``, ``constraint_terms`` (Φ_q and γ), the driver's
motion),
compiled for the single engine (:mod:`jointplay._kernels.shared`); this module gives them to
the model layer (the kinematics solver, inverse dynamics, initial states) with the joint
tables as 2-D arrays and the results allocated.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from jointplay._kernels.lanes.source import (
    LY_ACTIVE,
    LY_DRIVER,
    LY_JOINT_F,
    LY_JOINT_INT,
    LY_N,
    LY_NIDEAL,
    LY_NJ,
    N_LAY,
)
from jointplay._kernels.shared import compiled, pick

# The equations, written once in the lane source (jointplay._kernels.lanes.source).
_driver_angle, _driver_speed, _driver_acceleration, _constraint_rows = pick(
    compiled, "driver_angle driver_speed driver_acceleration constraint_rows"
)
_constraint_residual, _constraint_jacobian, _constraint_terms = pick(
    compiled, "constraint_residual constraint_jacobian constraint_terms"
)


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
def _packed(
    q: np.ndarray, qd: np.ndarray, joint_int: np.ndarray, joint_f: np.ndarray,
    active: np.ndarray, driver: np.ndarray,
):  # fmt: skip
    """The state (q, q̇) and the joint tables as the lane source reads them: ``(y, rp, ip,
    lay)`` with the joints' floats then the driver in ``rp``, their integers then ``active`` in
    ``ip``, and the offsets and sizes in ``lay``."""
    n = q.shape[0]
    nj = joint_int.shape[0]
    y = np.empty(2 * n)
    y[:n] = q
    y[n:] = qd
    rp = np.empty(6 * nj + 4)
    rp[: 6 * nj] = joint_f.ravel()
    rp[6 * nj :] = driver
    ip = np.empty(4 * nj, dtype=np.int64)
    ip[: 3 * nj] = joint_int.ravel()
    ip[3 * nj :] = active
    lay = np.zeros(N_LAY, dtype=np.int64)
    lay[LY_DRIVER] = 6 * nj
    lay[LY_ACTIVE] = 3 * nj
    lay[LY_N] = n
    lay[LY_NJ] = nj
    lay[LY_NIDEAL] = active.sum()
    lay[LY_JOINT_F] = 0
    lay[LY_JOINT_INT] = 0
    return y, rp, ip, lay


@njit(cache=True)
def count_rows(active: np.ndarray, driver: np.ndarray) -> int:
    """2 rows per active joint, plus 1 for the driver unless it is off (body index < 0)."""
    return 2 * int(active.sum()) + (1 if driver[0] >= 0 else 0)


@njit(cache=True)
def residual(
    q: np.ndarray, t: float, joint_int: np.ndarray, joint_f: np.ndarray, active: np.ndarray,
    driver: np.ndarray,
) -> np.ndarray:  # fmt: skip
    """Constraint violation Φ(q, t), m (joint rows) and rad (angle rows)."""
    y, rp, ip, lay = _packed(q, q, joint_int, joint_f, active, driver)
    out = np.zeros(count_rows(active, driver))
    _constraint_residual(t, y, rp, ip, lay, out)
    return out


@njit(cache=True)
def jacobian(
    q: np.ndarray, joint_int: np.ndarray, joint_f: np.ndarray, active: np.ndarray,
    driver: np.ndarray,
) -> np.ndarray:  # fmt: skip
    """Constraint Jacobian Φ_q, shape (rows, 3 nb) (revolute Φ = r_a + A_a s_a − r_b − A_b s_b
    with ∂(A s)/∂φ = B s = rot90(A s); prismatic; the driver's row)."""
    y, rp, ip, lay = _packed(q, q, joint_int, joint_f, active, driver)
    out = np.zeros((count_rows(active, driver), q.shape[0]))
    _constraint_jacobian(y, rp, ip, lay, out)
    return out


@njit(cache=True)
def velocity_rhs(t: float, active: np.ndarray, driver: np.ndarray) -> np.ndarray:
    """ν = −Φ_t: zero for joints, the prescribed crank speed for the driver row."""
    out = np.zeros(count_rows(active, driver))
    if driver[0] >= 0:
        out[-1] = _driver_speed(t, driver, 0)
    return out


@njit(cache=True)
def acceleration_rhs(
    q: np.ndarray, qd: np.ndarray, t: float, joint_int: np.ndarray, joint_f: np.ndarray,
    active: np.ndarray, driver: np.ndarray,
) -> np.ndarray:  # fmt: skip
    """γ with Φ_q q̈ = γ (Nikravesh 1988, §6): quadratic velocity terms and the driver's φ̈."""
    y, rp, ip, lay = _packed(q, qd, joint_int, joint_f, active, driver)
    rows = count_rows(active, driver)
    out = np.zeros(rows)
    _constraint_terms(t, y, rp, ip, lay, np.empty((rows, q.shape[0])), out, True)
    return out
