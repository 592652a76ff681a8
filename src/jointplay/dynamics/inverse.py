"""Inverse dynamics with ideal joints: joint reactions and the driving torque.

Newton–Euler equations of all moving links in absolute coordinates (Nikravesh 1988, §6.5;
Haug 1989, §6.3):

    M q̈ + Φ_qᵀ λ = Q_g,

with M = diag(m_k, m_k, J_k), Q_g the gravity forces and λ the Lagrange multipliers of the
joint and driver constraints. Given the motion (q, q̇, q̈) from kinematics, the multipliers
follow from the square linear system Φ_qᵀ λ = Q_g − M q̈. For a revolute joint between links
a and b with Φ = r_a + A_a s_a − r_b − A_b s_b, the force that link a exerts on link b at the
joint is +λ (and −λ on a). For the driver row φ_crank − φ_d(t) = 0 the motor torque on the
crank is −λ_driver. Prismatic joints report the normal force on the slider and the constraint
couple on it.
"""

from __future__ import annotations

from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from jointplay._kernels import constraints as ck
from jointplay.errors import AssemblyError
from jointplay.kinematics.analysis import KinematicsResult
from jointplay.kinematics.solver import driver_at
from jointplay.model.flat import REVOLUTE

FloatArray = NDArray[np.float64]


@dataclass(frozen=True)
class InverseDynamicsResult:
    """Joint reactions and driving torque over the analysed crank angles.

    Attributes:
        kinematics: the motion the reactions belong to.
        joint_names: joints in column order.
        force: (N, nj, 2) force exerted by the joint's ``link_a`` on its ``link_b``, N.
        couple: (N, nj) constraint couple on ``link_b`` (prismatic joints; 0 for revolute), N·m.
        torque: (N,) motor torque on the crank, N·m, counter-clockwise positive.
        multipliers: (N, rows) the Lagrange multipliers λ.
    """

    kinematics: KinematicsResult
    joint_names: tuple[str, ...]
    force: FloatArray
    couple: FloatArray
    torque: FloatArray
    multipliers: FloatArray

    @property
    def magnitude(self) -> FloatArray:
        """(N, nj) reaction force magnitudes, N."""
        return np.hypot(self.force[..., 0], self.force[..., 1])

    def joint_force(self, joint: str) -> FloatArray:
        """(N,) reaction force magnitude at ``joint``, N."""
        return self.magnitude[:, self.joint_names.index(joint)]

    def kinetic_energy(self) -> FloatArray:
        """(N,) total kinetic energy of the moving links, J."""
        m = self.kinematics.flat.mass_vector()
        return 0.5 * np.sum(m * self.kinematics.qd**2, axis=1)

    def power_balance(self) -> tuple[FloatArray, FloatArray]:
        """(motor power, dT/dt − gravity power), W — equal for ideal, frictionless joints."""
        kin = self.kinematics
        m = kin.flat.mass_vector()
        d_kinetic = np.sum(m * kin.qd * kin.qdd, axis=1)
        gravity_power = kin.qd @ kin.flat.gravity_forces()
        crank = 3 * kin.flat.body_index(kin.mechanism.driver.link) + 2
        return self.torque * kin.qd[:, crank], d_kinetic - gravity_power


def inverse_dynamics(kinematics: KinematicsResult) -> InverseDynamicsResult:
    """Solve Φ_qᵀ λ = Q_g − M q̈ at every analysed crank angle."""
    flat = kinematics.flat
    mass = flat.mass_vector()
    gravity = flat.gravity_forces()
    n = len(kinematics.crank_angle)
    nj = flat.joint_int.shape[0]
    rows = flat.n_constraints
    multipliers = np.empty((n, rows))
    for i, angle in enumerate(kinematics.crank_angle):
        driver = driver_at(flat, float(angle))
        jac = ck.jacobian(kinematics.q[i], flat.joint_int, flat.joint_f, flat.active, driver)
        rhs = gravity - mass * kinematics.qdd[i]
        try:
            multipliers[i] = np.linalg.solve(jac.T, rhs)
        except np.linalg.LinAlgError:
            raise AssemblyError(
                f"joint reactions are indeterminate at crank angle {np.degrees(angle):.2f}° "
                "(singular position)"
            ) from None
    force = np.zeros((n, nj, 2))
    couple = np.zeros((n, nj))
    for j in range(nj):
        lam = multipliers[:, 2 * j : 2 * j + 2]
        if flat.joint_int[j, 0] == REVOLUTE:
            force[:, j] = lam
        else:
            # Rows: relative angle (λ1) and normal distance n·d (λ2): on the slider the
            # force is −n λ2 and the couple −λ1.
            guide = int(flat.joint_int[j, 1])
            phi_guide = kinematics.q[:, 3 * guide + 2] if guide >= 0 else np.zeros(n)
            axis = phi_guide + flat.joint_f[j, 4]
            normal = np.column_stack([-np.sin(axis), np.cos(axis)])
            force[:, j] = -normal * lam[:, 1:2]
            couple[:, j] = -lam[:, 0]
    return InverseDynamicsResult(
        kinematics=kinematics,
        joint_names=flat.joint_names,
        force=force,
        couple=couple,
        torque=-multipliers[:, -1],
        multipliers=multipliers,
    )
