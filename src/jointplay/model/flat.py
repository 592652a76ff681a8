"""A mechanism as flat arrays: the geometry that the compiled constraint kernels read.

:func:`flatten` turns a :class:`~jointplay.model.mechanism.Mechanism` into flat NumPy arrays
(:class:`FlatModel`): the kinematics solves its constraints
(:mod:`jointplay._kernels.constraints`) on them, and the dynamics' one bridge to the compiled
equations of motion, :mod:`jointplay.dynamics.system`, builds its kernel model from them (with
the clearance joints and their contact laws, which this layer does not know).

Generalised coordinates: for every moving link k (in the mechanism's order) the position of its
centre of mass and the angle of its frame, ``q[3k:3k+3] = (x_cm, y_cm, φ)``. Joint points are
stored relative to the centre of mass, in the link frame; ground points are global.
"""

from __future__ import annotations

from collections.abc import Collection
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from jointplay.errors import ConfigError
from jointplay.model.mechanism import GROUND, Mechanism, PrismaticJoint, RevoluteJoint

#: Joint kinds in :attr:`FlatModel.joint_int` column 0.
REVOLUTE = 0
PRISMATIC = 1

#: Driver parameter layout in :attr:`FlatModel.driver`.
DRV_BODY, DRV_PHI0, DRV_OMEGA, DRV_RAMP = 0, 1, 2, 3


@dataclass(frozen=True)
class FlatModel:
    """A mechanism as flat arrays (SI).

    Attributes:
        link_names: moving links in coordinate order.
        joint_names: joints in row order.
        mass: (nb,) kg.  inertia: (nb,) kg·m² about the centre of mass.
        com_local: (nb, 2) centre of mass in the link frame, m.
        joint_int: (nj, 3) int64: kind, body a, body b (−1 = ground).
        joint_f: (nj, 6) float64: s_a (x, y), s_b (x, y) relative to the centres of mass
            (ground: global), prismatic axis angle in a's frame, relative angle φ_b − φ_a.
        active: (nj,) int64, 1 where the joint is an ideal constraint, 0 where it is not
            (a clearance joint, modelled by contact forces instead).
        driver: (4,) float64: body index, φ at t = 0 (rad), signed ω (rad/s), ramp time (s).
        gravity: (2,) m/s².
    """

    link_names: tuple[str, ...]
    joint_names: tuple[str, ...]
    mass: NDArray[np.float64]
    inertia: NDArray[np.float64]
    com_local: NDArray[np.float64]
    joint_int: NDArray[np.int64]
    joint_f: NDArray[np.float64]
    active: NDArray[np.int64]
    driver: NDArray[np.float64]
    gravity: NDArray[np.float64]

    @property
    def n_bodies(self) -> int:
        return len(self.link_names)

    @property
    def n_coordinates(self) -> int:
        return 3 * self.n_bodies

    @property
    def n_constraints(self) -> int:
        """Rows of the constraint vector: 2 per active joint plus 1 for the driver (if on)."""
        return 2 * int(self.active.sum()) + (1 if self.driver[DRV_BODY] >= 0 else 0)

    def body_index(self, name: str) -> int:
        return -1 if name == GROUND else self.link_names.index(name)

    def joint_index(self, name: str) -> int:
        try:
            return self.joint_names.index(name)
        except ValueError:
            raise ConfigError(f"no joint {name!r}; joints: {list(self.joint_names)}") from None

    def kernel_args(
        self,
    ) -> tuple[NDArray[np.int64], NDArray[np.float64], NDArray[np.int64], NDArray[np.float64]]:
        """The arrays the constraint kernels take, in their order."""
        return self.joint_int, self.joint_f, self.active, self.driver

    def mass_vector(self) -> NDArray[np.float64]:
        """Diagonal of the mass matrix, (3 nb,): m, m, J per body."""
        return np.column_stack([self.mass, self.mass, self.inertia]).ravel()

    def gravity_forces(self) -> NDArray[np.float64]:
        """Generalised gravity forces, (3 nb,)."""
        forces = np.zeros((self.n_bodies, 3))
        forces[:, 0] = self.mass * self.gravity[0]
        forces[:, 1] = self.mass * self.gravity[1]
        return forces.ravel()


def flatten(
    mechanism: Mechanism,
    *,
    clearance_joints: Collection[str] = (),
    ramp_time: float = 0.0,
    driven: bool = True,
) -> FlatModel:
    """Convert ``mechanism`` to flat arrays; joints in ``clearance_joints`` are not constraints.

    With ``driven=False`` the driver is off (body index −1): the crank turns freely.
    """
    link_names = tuple(link.name for link in mechanism.links)
    com = {link.name: np.array(link.com) for link in mechanism.links}
    unknown = set(clearance_joints) - {j.name for j in mechanism.joints}
    if unknown:
        raise ConfigError(
            f"clearance requested in unknown joint(s) {sorted(unknown)}; "
            f"joints: {[j.name for j in mechanism.joints]}"
        )

    def index(name: str) -> int:
        return -1 if name == GROUND else link_names.index(name)

    def local(body: str, point: str) -> tuple[float, float]:
        x, y = mechanism.body(body).point(point)
        if body == GROUND:
            return x, y
        return x - com[body][0], y - com[body][1]

    joint_int = np.zeros((len(mechanism.joints), 3), dtype=np.int64)
    joint_f = np.zeros((len(mechanism.joints), 6))
    active = np.ones(len(mechanism.joints), dtype=np.int64)
    for row, joint in enumerate(mechanism.joints):
        kind = REVOLUTE if isinstance(joint, RevoluteJoint) else PRISMATIC
        if joint.name in clearance_joints and kind != REVOLUTE:
            raise ConfigError(
                f"joint {joint.name!r} is prismatic; clearance is modelled in revolute joints only"
            )
        joint_int[row] = kind, index(joint.link_a), index(joint.link_b)
        joint_f[row, 0:2] = local(joint.link_a, joint.point_a)
        joint_f[row, 2:4] = local(joint.link_b, joint.point_b)
        if isinstance(joint, PrismaticJoint):
            joint_f[row, 4] = joint.axis_angle
            joint_f[row, 5] = joint.relative_angle
        active[row] = 0 if joint.name in clearance_joints else 1
    driver = mechanism.driver
    if ramp_time < 0:
        raise ConfigError(f"speed ramp duration must be >= 0 s, got {ramp_time}")
    return FlatModel(
        link_names=link_names,
        joint_names=tuple(j.name for j in mechanism.joints),
        mass=np.array([link.mass for link in mechanism.links]),
        inertia=np.array([link.inertia for link in mechanism.links]),
        com_local=np.array([link.com for link in mechanism.links], dtype=float),
        joint_int=joint_int,
        joint_f=joint_f,
        active=active,
        driver=np.array(
            [
                index(driver.link) if driven else -1,
                driver.start_angle,
                driver.angular_velocity,
                ramp_time,
            ],
            dtype=float,
        ),
        gravity=np.array(mechanism.gravity, dtype=float),
    )
