"""Packing a mechanism with clearance joints into the flat buffers of the compiled kernels.

This is the seam between the readable model (mechanism, clearance joints, laws) and
:mod:`jointplay._kernels.eom`: one function builds ``rpar``/``ipar`` and the layout of the
state vector; the kernel module's :func:`~jointplay._kernels.eom.views` unpacks them.
"""

from __future__ import annotations

from collections.abc import Sequence
from dataclasses import dataclass

import numpy as np
from numpy.typing import NDArray

from jointplay._kernels import eom
from jointplay._kernels.contact import FRICTION_NONE
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.errors import ConfigError
from jointplay.model.flat import FlatModel, flatten
from jointplay.model.mechanism import Mechanism, RevoluteJoint

FloatArray = NDArray[np.float64]
#: Width of a row of contact-law and friction parameters in ``rpar``.
PARAMS_WIDTH = 8


@dataclass(frozen=True)
class System:
    """A mechanism ready for the compiled equations of motion.

    Attributes:
        mechanism: the mechanism (template and joint data).
        flat: its flat model with clearance joints removed from the constraints.
        clearances: the clearance joints, in kernel order.
        rpar, ipar: the kernel buffers.
    """

    mechanism: Mechanism
    flat: FlatModel
    clearances: tuple[ClearanceJoint, ...]
    rpar: FloatArray
    ipar: NDArray[np.int64]

    @property
    def n_coordinates(self) -> int:
        return self.flat.n_coordinates

    @property
    def n_state(self) -> int:
        """q, q̇, motor work, contact work, one impact-velocity slot per clearance joint."""
        return 2 * self.n_coordinates + 2 + len(self.clearances)

    @property
    def args(self) -> tuple[FloatArray, NDArray[np.int64]]:
        return self.rpar, self.ipar

    def stats(self) -> FloatArray:
        """The kernel's statistics block (max constraint violation, projections)."""
        return self.rpar[-eom.N_STATS :]


def build_system(
    mechanism: Mechanism,
    clearances: Sequence[ClearanceJoint],
    *,
    ramp_time: float = 0.0,
    onset_tolerance: float | None = None,
    projection_tolerance: float = 1e-10,
    driven: bool = True,
) -> System:
    """Pack ``mechanism`` with ``clearances`` for the kernels.

    Args:
        ramp_time: duration of the driver's smooth speed ramp, s (0: full speed at t = 0).
        onset_tolerance: largest penetration (m) accepted in the step where a contact begins;
            default 1 % of the smallest clearance.
        projection_tolerance: constraint violation (m or rad) above which a step's state is
            projected back onto the ideal constraints.
        driven: ``False`` switches the motor off (the crank turns freely).
    """
    names = [c.joint for c in clearances]
    if len(set(names)) != len(names):
        raise ConfigError(f"a joint is listed twice among the clearance joints: {names}")
    for clearance in clearances:
        if not isinstance(mechanism.joint(clearance.joint), RevoluteJoint):
            raise ConfigError(
                f"joint {clearance.joint!r} is not a revolute joint; only revolute joints take clearance"
            )
    flat = flatten(mechanism, clearance_joints=names, ramp_time=ramp_time, driven=driven)
    rows = [flat.joint_index(name) for name in names]
    nc = len(clearances)
    law_p = np.zeros((nc, PARAMS_WIDTH))
    fric_p = np.zeros((nc, PARAMS_WIDTH))
    law_id = np.zeros(nc, dtype=np.int64)
    fric_id = np.full(nc, FRICTION_NONE, dtype=np.int64)
    geom = np.zeros((nc, eom.N_GEOM))
    for c, clearance in enumerate(clearances):
        params = clearance.law.params()
        law_p[c, : len(params)] = params
        law_id[c] = clearance.law.law_id
        if clearance.friction is not None:
            fparams = clearance.friction.params()
            fric_p[c, : len(fparams)] = fparams
            fric_id[c] = clearance.friction.law_id
        geom[c, eom.G_R_BEARING] = clearance.bearing_radius
        geom[c, eom.G_R_JOURNAL] = clearance.journal_radius
        geom[c, eom.G_CLEARANCE] = clearance.clearance
    if onset_tolerance is None:
        onset_tolerance = 0.01 * min((c.clearance for c in clearances), default=1e-5)
    settings = np.zeros(eom.N_SETTINGS)
    settings[eom.S_ONSET_TOL] = onset_tolerance
    settings[eom.S_PROJ_TOL] = projection_tolerance
    settings[eom.S_V_MARK] = 1e-12  # marks an active contact event whose entry rate was <= 0
    nj = flat.joint_int.shape[0]
    header = np.zeros(eom.HEADER, dtype=np.int64)
    header[[eom.I_NB, eom.I_NJ, eom.I_NC, eom.I_PLAW, eom.I_PFRIC]] = (
        flat.n_bodies,
        nj,
        nc,
        PARAMS_WIDTH,
        PARAMS_WIDTH,
    )
    ipar = np.concatenate(
        [
            header,
            flat.joint_int.ravel(),
            flat.active,
            np.array(rows, dtype=np.int64),
            law_id,
            fric_id,
        ]
    ).astype(np.int64)
    rpar = np.concatenate(
        [
            flat.mass_vector(),
            flat.gravity_forces(),
            flat.joint_f.ravel(),
            flat.driver,
            geom.ravel(),
            law_p.ravel(),
            fric_p.ravel(),
            settings,
            np.zeros(eom.N_STATS),
        ]
    )
    return System(
        mechanism, flat, tuple(clearances), np.ascontiguousarray(rpar), np.ascontiguousarray(ipar)
    )
