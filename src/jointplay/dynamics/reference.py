"""A plain NumPy right-hand side of the clearance-joint equations of motion.

Written from the readable model objects (mechanism, contact-law objects), independently of
the compiled kernels: joint points are placed with NumPy, contact forces come from the laws'
``force`` methods, ideal joints are differentiated numerically and the constrained
accelerations come from the full augmented (KKT) system rather than the kernel's Schur
complement. It is the "plain path" the compiled kernel is tested against and the baseline of
``benchmarks/bench_clearance.py``; it is far too slow for real work.
"""

from __future__ import annotations

import numpy as np
from numpy.typing import NDArray

from jointplay._kernels.constraints import driver_motion
from jointplay.dynamics.system import System
from jointplay.model.mechanism import GROUND, PrismaticJoint

FloatArray = NDArray[np.float64]

#: Step of the central differences of the ideal-joint constraints (their round-off and
#: truncation errors are both ~1e-9 relative at this step for lengths of order 0.1 m).
DIFFERENCE_STEP = 1e-5


def _rotation(angle: float) -> FloatArray:
    c, s = np.cos(angle), np.sin(angle)
    return np.array([[c, -s], [s, c]])


class ReferenceModel:
    """Equations of motion of ``system`` evaluated with NumPy (see the module docstring)."""

    def __init__(self, system: System) -> None:
        self.system = system
        self.mechanism = system.mechanism
        self.flat = system.flat
        self.n = system.n_coordinates
        self.mass = system.flat.mass_vector()
        self.clear = {c.joint: c for c in system.clearances}
        self.ideal = [j for j in self.mechanism.joints if j.name not in self.clear]
        self.com = {link.name: np.array(link.com) for link in self.mechanism.links}

    def point(self, q: FloatArray, body: str, name: str) -> FloatArray:
        """Global position of the named point of ``body``."""
        local = np.array(self.mechanism.body(body).point(name))
        if body == GROUND:
            return local
        k = self.flat.body_index(body)
        return q[3 * k : 3 * k + 2] + _rotation(q[3 * k + 2]) @ (local - self.com[body])

    def point_velocity(
        self, q: FloatArray, qd: FloatArray, body: str, position: FloatArray
    ) -> FloatArray:
        if body == GROUND:
            return np.zeros(2)
        k = self.flat.body_index(body)
        r = position - q[3 * k : 3 * k + 2]
        return qd[3 * k : 3 * k + 2] + qd[3 * k + 2] * np.array([-r[1], r[0]])

    def joint_residual(self, q: FloatArray) -> FloatArray:
        """Constraint violation of the ideal joints (not the driver)."""
        rows = []
        for joint in self.ideal:
            pa = self.point(q, joint.link_a, joint.point_a)
            pb = self.point(q, joint.link_b, joint.point_b)
            if isinstance(joint, PrismaticJoint):
                phi_a = (
                    0.0 if joint.link_a == GROUND else q[3 * self.flat.body_index(joint.link_a) + 2]
                )
                phi_b = q[3 * self.flat.body_index(joint.link_b) + 2]
                normal = _rotation(phi_a + joint.axis_angle) @ np.array([0.0, 1.0])
                rows += [phi_b - phi_a - joint.relative_angle, normal @ (pb - pa)]
            else:
                rows += list(pa - pb)
        return np.array(rows)

    def forces(self, y: FloatArray) -> tuple[FloatArray, float]:
        """Generalised applied forces (gravity + contact) and the power absorbed by contacts."""
        n = self.n
        q, qd = y[:n], y[n : 2 * n]
        force = self.flat.gravity_forces().copy()
        power = 0.0
        for c, (name, clearance) in enumerate(self.clear.items()):
            joint = self.mechanism.joint(name)
            r_b = self.point(q, joint.link_a, joint.point_a)
            r_j = self.point(q, joint.link_b, joint.point_b)
            e = r_j - r_b
            norm = np.linalg.norm(e)
            delta = norm - clearance.clearance
            if delta <= 0:
                continue
            normal = e / norm
            tangent = np.array([-normal[1], normal[0]])
            e_dot = self.point_velocity(q, qd, joint.link_b, r_j) - self.point_velocity(
                q, qd, joint.link_a, r_b
            )
            w_a = 0.0 if joint.link_a == GROUND else qd[3 * self.flat.body_index(joint.link_a) + 2]
            w_b = 0.0 if joint.link_b == GROUND else qd[3 * self.flat.body_index(joint.link_b) + 2]
            delta_dot = float(e_dot @ normal)
            v_t = (
                float(e_dot @ tangent)
                + clearance.journal_radius * w_b
                - clearance.bearing_radius * w_a
            )
            v0 = y[2 * n + 2 + c]
            f_n = float(
                clearance.law.force(
                    np.array([delta]), np.array([delta_dot]), v0=v0 if v0 > 0 else None
                )[0]
            )
            f_t = (
                0.0
                if clearance.friction is None
                else float(clearance.friction.force(np.array([v_t]), np.array([f_n]))[0])
            )
            on_journal = -f_n * normal - f_t * tangent
            for body, centre, radius, sign in (
                (joint.link_b, r_j, clearance.journal_radius, 1.0),
                (joint.link_a, r_b, clearance.bearing_radius, -1.0),
            ):
                if body == GROUND:
                    continue
                k = self.flat.body_index(body)
                at = centre + radius * normal - q[3 * k : 3 * k + 2]
                f = sign * on_journal
                force[3 * k : 3 * k + 2] += f
                force[3 * k + 2] += at[0] * f[1] - at[1] * f[0]
            power += f_n * delta_dot + f_t * v_t
        return force, power

    def rhs(self, t: float, y: FloatArray) -> FloatArray:
        """ẏ in the state layout of :mod:`jointplay._kernels.eom`."""
        n = self.n
        q, qd = y[:n], y[n : 2 * n]
        force, power = self.forces(y)
        h = DIFFERENCE_STEP
        eye = np.eye(n)
        jac_rows = [
            (self.joint_residual(q + h * eye[i]) - self.joint_residual(q - h * eye[i])) / (2 * h)
            for i in range(n)
        ]
        phi_q = np.array(jac_rows).T.reshape(-1, n)
        # γ = −(d²/ds²) Φ(q + s q̇) at s = 0, for time-independent joint constraints.
        gamma = (
            -(
                self.joint_residual(q + h * qd)
                - 2 * self.joint_residual(q)
                + self.joint_residual(q - h * qd)
            )
            / h**2
        )
        driver = self.flat.driver
        crank = int(driver[0])
        if crank >= 0:
            row = np.zeros((1, n))
            row[0, 3 * crank + 2] = 1.0
            phi_q = np.vstack([phi_q, row])
            gamma = np.append(gamma, driver_motion(t, driver)[2])
        m = phi_q.shape[0]
        kkt = np.zeros((n + m, n + m))
        kkt[:n, :n] = np.diag(self.mass)
        kkt[:n, n:] = phi_q.T
        kkt[n:, :n] = phi_q
        solution = np.linalg.solve(kkt, np.concatenate([force, gamma]))
        qdd, lam = solution[:n], solution[n:]
        torque = -lam[-1] if crank >= 0 else 0.0
        out = np.zeros_like(y)
        out[:n] = qd
        out[n : 2 * n] = qdd
        out[2 * n] = torque * qd[3 * crank + 2] if crank >= 0 else 0.0
        out[2 * n + 1] = power
        return out
