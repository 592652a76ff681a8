"""The bridge from the object model to the compiled equations of motion.

The one place that turns a mechanism, its clearance joints and the solver's contact
settings into the data the kernels of :mod:`jointplay._kernels.eom` read: an
:class:`~jointplay._kernels.eom.EomModel`, a named tuple of flat, read-only arrays (the
mechanism from :func:`~jointplay.model.flat.flatten`, each clearance joint's geometry, and
each contact and friction law's ``law_id`` and ``params()``). A :class:`System` holds it and
never changes; what an integration writes (its statistics) goes to a workspace new for each
run (:meth:`System.kernel_args`), so one System can be integrated any number of times, from
any number of threads.
"""

from __future__ import annotations

import math
from collections.abc import Sequence
from dataclasses import dataclass, fields

import numpy as np
from numpy.typing import ArrayLike, NDArray

from jointplay._kernels import eom, ids
from jointplay._kernels.ids import FRICTION_NONE
from jointplay.dynamics.clearance import ClearanceJoint, film_model_id
from jointplay.errors import ConfigError, SettingError
from jointplay.model.flat import FlatModel, flatten
from jointplay.model.mechanism import Mechanism, RevoluteJoint

FloatArray = NDArray[np.float64]
#: Width of a row of contact-law and friction parameters in :attr:`EomModel.law_p` and
#: :attr:`EomModel.fric_p`.
PARAMS_WIDTH = 8
#: The default contact-onset tolerance, as a fraction of the smallest clearance, where no
#: clearance joint's law reads the impact velocity: 1 % (0.21 µm at 21 µm). Their force is
#: the state's alone (IMPACT, Hertz, Kelvin–Voigt): a contact entered within it starts where
#: the force is still small, and 0.01 % was measured no better for them (docs/performance.md).
ONSET_FRACTION = 1e-2
#: The default where a clearance joint's law reads the impact velocity v0
#: (:attr:`~jointplay.contact.laws.ContactLaw.needs_impact_velocity`: the Hunt–Crossley
#: family, restitution, Lankarani–Nikravesh, Flores, ...): 0.01 % (2.1 nm at 21 µm). Their
#: damping for the whole impact is set by v0, which the step entering contact records; for
#: stiff multi-impact contact (LN or Flores, K 1e10 N/m^1.5, e 0.8, dry, 21 µm in all four
#: joints of the paper four-bar, 0.1 revolution) the onset tolerance controls the error: at
#: 1 % the force and α peaks were 8.5 % (LN) and 1.5 % (Flores) off a converged reference
#: (rtol or atol tightened alone do not cure it), at 0.01 % 2.7e-4 and 7.7e-5, in as many
#: steps; over 18 such cases (18–24 µm, e 0.7–0.9) 17 missed 1e-3 at 1 %, 1 at 0.01 %,
#: for 7 % more steps. The default lubricated run takes the same steps (docs/performance.md,
#: "Stiff multi-impact contact: the onset tolerance"). The batch engine takes the same
#: fraction of each sample's smallest clearance.
ONSET_FRACTION_IMPACT_VELOCITY = 1e-4


def onset_fraction(clearances: Sequence[ClearanceJoint]) -> float:
    """The default onset tolerance's fraction of the smallest clearance for ``clearances``:
    :data:`ONSET_FRACTION_IMPACT_VELOCITY` where a joint's law reads the impact velocity,
    else :data:`ONSET_FRACTION`."""
    if any(getattr(c.law, "needs_impact_velocity", False) for c in clearances):
        return ONSET_FRACTION_IMPACT_VELOCITY
    return ONSET_FRACTION


@dataclass(frozen=True)
class System:
    """A mechanism ready for the compiled equations of motion; immutable.

    Attributes:
        mechanism: the mechanism (template and joint data).
        flat: its flat model with clearance joints removed from the constraints (arrays
            read-only).
        clearances: the clearance joints, in kernel order.
        model: what the kernels read, with read-only arrays.
    """

    mechanism: Mechanism
    flat: FlatModel
    clearances: tuple[ClearanceJoint, ...]
    model: eom.EomModel

    @property
    def n_coordinates(self) -> int:
        return self.flat.n_coordinates

    @property
    def n_state(self) -> int:
        """q, q̇, motor work, contact work, one impact-velocity slot per clearance joint."""
        return 2 * self.n_coordinates + 2 + len(self.clearances)

    @property
    def film_dampings(self) -> FloatArray:
        """Each clearance joint's film damping c_e as the kernels read it (N·s/m; 0: dry)."""
        return self.model.geom[ids.G_FILM :: ids.N_GEOM]

    @property
    def lubricated(self) -> bool:
        """Whether some clearance joint has film damping."""
        return bool(np.any(self.film_dampings > 0.0))

    @property
    def sustained_mode(self) -> bool:
        """Whether some clearance joint has the sustained-contact mode (capture speed > 0):
        the kernels' gate, the largest of the joints' capture speeds."""
        return bool(self.model.settings[ids.S_CAPTURE_MAX] > 0.0)

    def kernel_args(self) -> eom.EomArgs:
        """The kernels' ``args`` for one integration: the model packed for the integrator's
        hooks (:func:`~jointplay._kernels.eom.pack`) and a new workspace."""
        rpar, ipar = eom.pack(self.model)
        return rpar, ipar, eom.new_workspace(len(self.clearances))


def _frozen(values: ArrayLike, dtype: type) -> NDArray[np.generic]:
    """A C-contiguous read-only copy of ``values``."""
    array: NDArray[np.generic] = np.array(values, dtype=dtype, order="C")
    array.flags.writeable = False
    return array


def check_onset_tolerance(onset_tolerance: float, smallest_clearance: float) -> None:
    """Refuse an onset tolerance (m) that is not > 0 or not below the smallest clearance
    (m): a step could then enter a contact deeper than the gap it crossed."""
    if not (math.isfinite(onset_tolerance) and onset_tolerance > 0.0):
        raise SettingError(
            "{onset_tolerance} must be a length > 0, e.g. 2 nm, got {got!r} m",
            got=onset_tolerance,
        )
    if onset_tolerance >= smallest_clearance:
        raise SettingError(
            "{onset_tolerance} {got:.3g} m is not below the smallest clearance "
            "{clearance:.3g} m; give a small fraction of it (default 0.01 % or 1 % of it)",
            got=onset_tolerance,
            clearance=smallest_clearance,
        )


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
        onset_tolerance: largest penetration (m) accepted in the step where a contact begins,
            > 0 and below the smallest clearance; default :func:`onset_fraction` of the
            smallest clearance (0.01 % where a law reads the impact velocity, else 1 %).
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
    for item in fields(flat):
        value = getattr(flat, item.name)
        if isinstance(value, np.ndarray):
            value.flags.writeable = False
    nc = len(clearances)
    law_p = np.zeros((nc, PARAMS_WIDTH))
    fric_p = np.zeros((nc, PARAMS_WIDTH))
    law_id = np.zeros(nc, dtype=np.int64)
    fric_id = np.full(nc, FRICTION_NONE, dtype=np.int64)
    geom = np.zeros((nc, ids.N_GEOM))
    for c, clearance in enumerate(clearances):
        params = clearance.law.params()
        law_p[c, : len(params)] = params
        law_id[c] = clearance.law.law_id
        if clearance.friction is not None:
            fparams = clearance.friction.params()
            fric_p[c, : len(fparams)] = fparams
            fric_id[c] = clearance.friction.law_id
        geom[c, ids.G_R_BEARING] = clearance.bearing_radius
        geom[c, ids.G_R_JOURNAL] = clearance.journal_radius
        geom[c, ids.G_CLEARANCE] = clearance.clearance
        geom[c, ids.G_FILM] = clearance.film_damping  # each joint its own c_e; 0: dry
        geom[c, ids.G_CAPTURE] = clearance.capture_speed  # 0: sustained contact off
        geom[c, ids.G_FILM_MODEL] = film_model_id(clearance.film_model)  # 0: linear
        geom[c, ids.G_ROUGHNESS] = clearance.roughness  # σ: a Reynolds film's asperities
    smallest = min((c.clearance for c in clearances), default=1e-5)
    if onset_tolerance is None:
        onset_tolerance = onset_fraction(clearances) * smallest
    if clearances:
        check_onset_tolerance(onset_tolerance, smallest)
    settings = np.zeros(ids.N_SETTINGS)
    settings[ids.S_ONSET_TOL] = onset_tolerance
    settings[ids.S_PROJ_TOL] = projection_tolerance
    settings[ids.S_V_MARK] = 1e-12  # marks an active contact event whose entry rate was <= 0
    # the kernels' one-comparison gate of the sustained-contact mode: the largest capture speed
    settings[ids.S_CAPTURE_MAX] = max((c.capture_speed for c in clearances), default=0.0)
    model = eom.EomModel(
        mass=_frozen(flat.mass_vector(), np.float64),
        gravity=_frozen(flat.gravity_forces(), np.float64),
        joint_int=_frozen(flat.joint_int.ravel(), np.int64),
        joint_f=_frozen(flat.joint_f.ravel(), np.float64),
        active=_frozen(flat.active, np.int64),
        driver=_frozen(flat.driver, np.float64),
        clear_joint=_frozen([flat.joint_index(name) for name in names], np.int64),
        geom=_frozen(geom.ravel(), np.float64),
        law_id=_frozen(law_id, np.int64),
        law_p=_frozen(law_p.ravel(), np.float64),
        fric_id=_frozen(fric_id, np.int64),
        fric_p=_frozen(fric_p.ravel(), np.float64),
        settings=_frozen(settings, np.float64),
    )
    return System(mechanism, flat, tuple(clearances), model)
