"""Compiled equations of motion of a mechanism with ideal and clearance revolute joints.

The model is an :class:`EomModel`: a named tuple (which Numba compiles as a tuple with named
fields) of flat arrays that :mod:`jointplay.dynamics.system` builds once, read-only, and that
nothing writes. The integrator's hooks take ``args = (rpar, ipar, workspace)``: the model
packed into two read-only buffers (:func:`pack`; each kernel opens them with :func:`unpack`,
by name) and a workspace new for every integration, where :func:`after_step` keeps its
statistics (``W_*``). State vector::

    y = [q (3 nb), q̇ (3 nb), W_motor, W_contact, v0 (n_clear)]

- q, q̇: centre-of-mass position and angle of every moving link and their rates;
- W_motor = ∫ τ ω_crank dt, the work of the motor (J);
- W_contact = ∫ Σ (F_N δ̇ + F_T v_T) dt, the work absorbed by the clearance contacts (J) —
  so KE + V_gravity − W_motor + W_contact is constant (energy balance);
- v0: penetration rate at the start of the current contact event of each clearance joint
  (m/s, 0 while free); it has zero time derivative and is set by :func:`after_step`: after
  the step in which the contact begins, at δ̇ interpolated to the instant δ = 0 between the
  step's ends (linear in δ), so that it does not depend on where the step happened to end.
  In the sustained-contact mode (a joint's ``geom`` column ``G_CAPTURE`` > 0) a negative v0
  (:data:`LOCKED`) marks a joint locked onto its bearing's wall: |e| = c is then a
  constraint whose multiplier is the normal force (:func:`sustained_accelerations`); the
  joint is captured and released by :func:`switch_contacts` (after a step) and
  :func:`release_check` (which shortens a step to the release). With the mode off (the
  default) no slot is ever negative and each kernel pays one comparison for the mode.

Ideal joints and the driver are constraints Φ(q, t) = 0 (see :mod:`constraints`); with the
diagonal mass matrix M the accelerations follow from the Schur complement
(Φ_q M⁻¹ Φ_qᵀ) λ = Φ_q M⁻¹ Q − γ, q̈ = M⁻¹ (Q − Φ_qᵀ λ), and the motor torque is −λ_driver.
Position and velocity drift is removed after every accepted step by mass-weighted projection
(Hairer, Lubich & Wanner, *Geometric Numerical Integration*, §IV.4).

The integrator calls four functions, each compiled for one explicit signature (so the
integrator's core is cached on disk): :func:`rhs` (ẏ; allocates nothing but ẏ itself, and
needs no matrix when every joint is clear, the paper's case, since the driver is then the
only constraint), :func:`jacobian_state` (∂ẏ/∂y in closed form in that case),
:func:`step_check` (contact onset) and :func:`after_step` (contact memory, projection).
The integrator is told that q̇ = d/dt q (``n_second``) and that W_motor, W_contact and v0
do not feed back (``n_active``), see :func:`jointplay._kernels.radau.radau_integrate`.
The small helpers those four call are inlined by Numba (``inline="always"``): a compiled call
that takes the unpacked model (13 arrays) cost 100–150 ns however little it did, several
times a step (docs/performance.md, "From rest: DOPRI5 for the conventional set"). After
editing one of them, delete the on-disk caches of the functions that inline it (the README's
``find src -name "*.nb[ic]" -delete``): Numba does not follow that dependency.

Clearance joint (Flores et al., *Kinematics and Dynamics of Multibody Systems with Imperfect
Joints*, 2008; docs/contact-laws.md §5): bearing on body a, journal on body b,
eccentricity e = r_J − r_B, penetration δ = |e| − c, normal n = e/|e|, δ̇ = ė·n,
v_T = ė·t + R_J ω_b − R_B ω_a with t = ẑ × n. The force on the journal, −F_N n − F_T t, acts
at Q_J = r_J + R_J n; its opposite acts on the bearing at Q_B = r_B + R_B n.

Film damping (each joint's ``geom`` column ``G_FILM`` = c_e > 0, the lubricated default;
docs/contact.md): a lubricant film's squeeze damping lumped into −c_e ė on the journal at its
centre and +c_e ė on the bearing at its centre, in contact or not; its power c_e |ė|² is
added to W_contact. Off at a joint (0: dry), the kernels pay one comparison for it there.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit, typeof, types

from jointplay._kernels.constraints import (
    acceleration_rhs,
    count_rows,
    driver_motion,
    jacobian,
    residual,
    velocity_rhs,
)
from jointplay._kernels.contact import friction_force, law_slopes, normal_force
from jointplay._kernels.ids import (
    DIFF_FLOOR,
    DIFF_STEP,
    FRICTION_NONE,
    G_CAPTURE,
    G_CLEARANCE,
    G_FILM,
    G_R_BEARING,
    G_R_JOURNAL,
    LOCKED,
    N_GEOM,
    S_CAPTURE_MAX,
    S_ONSET_TOL,
    S_PROJ_TOL,
    S_V_MARK,
)
from jointplay._kernels.linalg import lu_factor, lu_solve_in_place
from jointplay._kernels.shared import compiled as _shared

#: The lane source's (:mod:`jointplay._kernels.lanes.source`): the Schur solve; the step's
#: fraction that ends at half the onset tolerance; δ̇ at δ = 0 between a step's ends.
cholesky_solve = _shared["cholesky_solve"]
onset_fraction = _shared["onset_fraction"]
impact_rate = _shared["impact_rate"]


class EomModel(NamedTuple):
    """The mechanism as the compiled equations of motion read it: flat arrays, SI units.

    Tables are flat and row-major (joint j's integers at ``joint_int[3j : 3j + 3]``, its
    floats at ``joint_f[6j : 6j + 6]``, clearance joint c's geometry at
    ``geom[N_GEOM c : N_GEOM (c + 1)]``, its law parameters at ``law_p[w c : w (c + 1)]``
    with ``w = law_p.size // nc``), so that the right-hand side slices nothing per call.
    Built, read-only, by :func:`jointplay.dynamics.system.build_system`; never written.

    Attributes:
        mass: (3 nb) diagonal of the mass matrix, m, m, J per body: kg, kg, kg·m².
        gravity: (3 nb) generalised gravity forces: N, N, 0 N·m per body.
        joint_int: (3 nj) int64 per joint: kind, body a, body b (−1 = ground).
        joint_f: (6 nj) per joint: s_a (x, y), s_b (x, y) from the centres of mass in the
            body frames (ground: global), m; prismatic axis angle and relative angle, rad.
        active: (nj) int64: 1 where the joint is an ideal constraint, 0 where it is clear.
        driver: (4) driven body (−1: none), φ at t = 0 (rad), signed ω (rad/s), ramp time (s).
        clear_joint: (nc) int64: joint row of each clearance joint.
        geom: (N_GEOM nc) per clearance joint: bearing radius, journal radius, radial
            clearance (columns ``G_R_BEARING``, ``G_R_JOURNAL``, ``G_CLEARANCE``), m; its
            film damping c_e (``G_FILM``, N·s/m; 0: dry; :func:`add_contact_forces`) and the
            capture speed of its sustained-contact mode (``G_CAPTURE``, m/s; 0: off).
        law_id: (nc) int64: normal-force law (:mod:`jointplay._kernels.contact` ids).
        law_p: (w nc) its parameters, SI.
        fric_id: (nc) int64: friction law (``FRICTION_NONE``: frictionless).
        fric_p: (w nc) its parameters, SI.
        settings: (N_SETTINGS) onset tolerance (m), projection tolerance (m or rad), the
            entry rate marking a contact event entered at a rate <= 0 (m/s) and the largest
            of the joints' capture speeds (m/s; the mode's gate), at ``S_*``.
    The ids, slots and columns (``S_*``, ``G_*``) are :mod:`jointplay._kernels.ids`'.
    """

    mass: np.ndarray
    gravity: np.ndarray
    joint_int: np.ndarray
    joint_f: np.ndarray
    active: np.ndarray
    driver: np.ndarray
    clear_joint: np.ndarray
    geom: np.ndarray
    law_id: np.ndarray
    law_p: np.ndarray
    fric_id: np.ndarray
    fric_p: np.ndarray
    settings: np.ndarray


#: The workspace of one integration (:func:`new_workspace`), written by :func:`after_step`:
#: the largest constraint violation max |Φ| seen after a step (m or rad), the number of
#: projections onto the ideal constraints, whether a step was accepted yet, and from
#: ``N_WORK`` on, per clearance joint, δ and δ̇ at the last accepted step's end.
W_MAX_VIOLATION, W_PROJECTIONS, W_HAS_PREVIOUS = 0, 1, 2
N_WORK = 3

#: :class:`EomModel`'s fields by dtype, in the order they are packed.
_FLOAT_FIELDS = ("mass", "gravity", "joint_f", "driver", "geom", "law_p", "fric_p", "settings")
_INT_FIELDS = ("joint_int", "active", "clear_joint", "law_id", "fric_id")
#: Position of each field's length in the ``ipar`` header (the header is
#: ``EomModel._fields``' lengths, in that order).
_L = {name: i for i, name in enumerate(EomModel._fields)}
L_MASS, L_GRAVITY, L_JOINT_INT, L_JOINT_F, L_ACTIVE, L_DRIVER = (
    _L["mass"], _L["gravity"], _L["joint_int"], _L["joint_f"], _L["active"], _L["driver"],
)  # fmt: skip
L_CLEAR_JOINT, L_GEOM, L_LAW_ID, L_LAW_P, L_FRIC_ID, L_FRIC_P, L_SETTINGS = (
    _L["clear_joint"], _L["geom"], _L["law_id"], _L["law_p"], _L["fric_id"], _L["fric_p"],
    _L["settings"],
)  # fmt: skip
HEADER = len(EomModel._fields)


def new_workspace(n_clear: int = 0) -> np.ndarray:
    """An empty workspace for one integration of a model with ``n_clear`` clearance joints:
    ``N_WORK + 2 n_clear`` zeros (see ``W_*``)."""
    return np.zeros(N_WORK + 2 * n_clear)


def pack(model: EomModel) -> tuple[np.ndarray, np.ndarray]:
    """``model`` as the two read-only buffers the compiled kernels take (:func:`unpack`).

    A first-class function call costs in proportion to the number of arrays it is given, so
    the integrator passes the model as two arrays, ``rpar`` (the float fields) and ``ipar``
    (the field lengths, then the integer fields), rather than as 13.
    """
    lengths = np.array([len(getattr(model, name)) for name in EomModel._fields], dtype=np.int64)
    ipar = np.concatenate([lengths, *(getattr(model, name) for name in _INT_FIELDS)])
    rpar = np.concatenate([getattr(model, name) for name in _FLOAT_FIELDS])
    return _readonly(rpar.astype(np.float64)), _readonly(ipar.astype(np.int64))


def _readonly(array: np.ndarray) -> np.ndarray:
    array.flags.writeable = False
    return array


@njit(cache=True, inline="always")
def unpack(rpar: np.ndarray, ipar: np.ndarray) -> EomModel:
    """The :class:`EomModel` packed by :func:`pack`, as views (no copies)."""
    o = HEADER
    joint_int = ipar[o : o + ipar[L_JOINT_INT]]
    o += ipar[L_JOINT_INT]
    active = ipar[o : o + ipar[L_ACTIVE]]
    o += ipar[L_ACTIVE]
    clear_joint = ipar[o : o + ipar[L_CLEAR_JOINT]]
    o += ipar[L_CLEAR_JOINT]
    law_id = ipar[o : o + ipar[L_LAW_ID]]
    o += ipar[L_LAW_ID]
    fric_id = ipar[o : o + ipar[L_FRIC_ID]]
    r = 0
    mass = rpar[r : r + ipar[L_MASS]]
    r += ipar[L_MASS]
    gravity = rpar[r : r + ipar[L_GRAVITY]]
    r += ipar[L_GRAVITY]
    joint_f = rpar[r : r + ipar[L_JOINT_F]]
    r += ipar[L_JOINT_F]
    driver = rpar[r : r + ipar[L_DRIVER]]
    r += ipar[L_DRIVER]
    geom = rpar[r : r + ipar[L_GEOM]]
    r += ipar[L_GEOM]
    law_p = rpar[r : r + ipar[L_LAW_P]]
    r += ipar[L_LAW_P]
    fric_p = rpar[r : r + ipar[L_FRIC_P]]
    r += ipar[L_FRIC_P]
    settings = rpar[r : r + ipar[L_SETTINGS]]
    return EomModel(
        mass=mass, gravity=gravity, joint_int=joint_int, joint_f=joint_f, active=active,
        driver=driver, clear_joint=clear_joint, geom=geom, law_id=law_id, law_p=law_p,
        fric_id=fric_id, fric_p=fric_p, settings=settings,
    )  # fmt: skip


#: Numba type of the kernels' ``args``: ``(rpar, ipar, workspace)``, the first two
#: read-only (:func:`pack`), the workspace writable (:func:`new_workspace`).
ARGS_TYPE = typeof(
    (
        _readonly(np.zeros(1)),
        _readonly(np.zeros(1, dtype=np.int64)),
        new_workspace(),
    )
)
#: ``args`` as the kernels' annotations spell it.
EomArgs = tuple[np.ndarray, np.ndarray, np.ndarray]

rhs_signature = types.float64[::1](types.float64, types.float64[::1], ARGS_TYPE)


@njit(cache=True, inline="always")
def _rotations(q: np.ndarray) -> np.ndarray:
    """(cos φ_k, sin φ_k) of every body k, flat: one sine and cosine per body and call."""
    nb = q.shape[0] // 3
    rot = np.empty(2 * nb)
    for k in range(nb):
        rot[2 * k] = np.cos(q[3 * k + 2])
        rot[2 * k + 1] = np.sin(q[3 * k + 2])
    return rot


@njit(cache=True, inline="always")
def _arm(
    q: np.ndarray, rot: np.ndarray, body: int, sx: float, sy: float
) -> tuple[float, float, float, float]:
    """(x, y, r_x, r_y): global position of the local point (sx, sy) of ``body`` and its arm
    r = A(φ) s from the centre of mass (the ground's points are global, arm 0)."""
    if body < 0:
        return sx, sy, 0.0, 0.0
    c = rot[2 * body]
    s = rot[2 * body + 1]
    rx = c * sx - s * sy
    ry = s * sx + c * sy
    return q[3 * body] + rx, q[3 * body + 1] + ry, rx, ry


@njit(cache=True, inline="always")
def _rotation_of(
    q: np.ndarray, body: int, last: tuple[int, float, float, int, float, float]
) -> tuple[float, float]:
    """(cos φ, sin φ) of ``body``: from ``last`` (the two bodies of the joint before, with
    theirs) when it is one of them, else computed. Joints listed along a chain share a body
    with the one before (the four-bar's O2, A, B, O4: three rotations instead of six), and the
    values are the same bits either way. The right-hand side's variant of :func:`_rotations`,
    which allocates."""
    if body == last[0]:
        return last[1], last[2]
    if body == last[3]:
        return last[4], last[5]
    if body < 0:
        return 1.0, 0.0
    return np.cos(q[3 * body + 2]), np.sin(q[3 * body + 2])


@njit(cache=True, inline="always")
def _arm_of(q: np.ndarray, body: int, sx: float, sy: float) -> tuple[float, float, float, float]:
    """:func:`_arm` computing the body's rotation itself."""
    if body < 0:
        return sx, sy, 0.0, 0.0
    return _arm_rotated(q, body, np.cos(q[3 * body + 2]), np.sin(q[3 * body + 2]), sx, sy)


@njit(cache=True, inline="always")
def _arm_rotated(
    q: np.ndarray, body: int, c: float, s: float, sx: float, sy: float
) -> tuple[float, float, float, float]:
    """:func:`_arm` with the body's (cos φ, sin φ) given."""
    if body < 0:
        return sx, sy, 0.0, 0.0
    rx = c * sx - s * sy
    ry = s * sx + c * sy
    return q[3 * body] + rx, q[3 * body + 1] + ry, rx, ry


@njit(cache=True, inline="always")
def _penetration(
    q: np.ndarray,
    rot: np.ndarray,
    joint_int: np.ndarray,
    joint_f: np.ndarray,
    j: int,
    clearance: float,
) -> float:
    """δ = |e| − c of joint row ``j`` (flat tables, :class:`EomModel`)."""
    bx, by, _, _ = _arm(q, rot, joint_int[3 * j + 1], joint_f[6 * j], joint_f[6 * j + 1])
    jx, jy, _, _ = _arm(q, rot, joint_int[3 * j + 2], joint_f[6 * j + 2], joint_f[6 * j + 3])
    return np.sqrt((jx - bx) ** 2 + (jy - by) ** 2) - clearance


@njit(cache=True, inline="always")
def _eccentricity_rate(
    qd: np.ndarray, a: int, b: int, rax: float, ray: float, rbx: float, rby: float
) -> tuple[float, float]:
    """ė = v(journal centre on b) − v(bearing centre on a), v = v_com + ω ẑ × r (r: arm)."""
    wa = qd[3 * a + 2] if a >= 0 else 0.0
    wb = qd[3 * b + 2] if b >= 0 else 0.0
    edx = -wb * rby + wa * ray
    edy = wb * rbx - wa * rax
    if b >= 0:
        edx += qd[3 * b]
        edy += qd[3 * b + 1]
    if a >= 0:
        edx -= qd[3 * a]
        edy -= qd[3 * a + 1]
    return edx, edy


@njit(cache=True, inline="always")
def _contact_state(
    q: np.ndarray, qd: np.ndarray, rot: np.ndarray, joint_int: np.ndarray, joint_f: np.ndarray,
    j: int, geom: np.ndarray, c: int,
):  # fmt: skip
    """Kinematics of clearance joint ``c`` (row ``j``), §5 of docs/contact-laws.md.

    Returns:
        (δ, δ̇, v_T, |e|, e_x, e_y, n_x, n_y, ė·t, r_a, r_b, ω_a, ω_b) with the arms r of the
        bearing's and the journal's centres from their bodies' centres of mass as (x, y)
        pairs; n = (1, 0) for a centred pin (δ = −c: no force follows from it).
    """
    a, b = joint_int[3 * j + 1], joint_int[3 * j + 2]
    bx, by, rax, ray = _arm(q, rot, a, joint_f[6 * j], joint_f[6 * j + 1])
    jx, jy, rbx, rby = _arm(q, rot, b, joint_f[6 * j + 2], joint_f[6 * j + 3])
    ex, ey = jx - bx, jy - by
    length = np.sqrt(ex * ex + ey * ey)
    nx, ny = (ex / length, ey / length) if length > 0.0 else (1.0, 0.0)
    wa = qd[3 * a + 2] if a >= 0 else 0.0
    wb = qd[3 * b + 2] if b >= 0 else 0.0
    edx, edy = _eccentricity_rate(qd, a, b, rax, ray, rbx, rby)
    delta = length - geom[N_GEOM * c + G_CLEARANCE]
    delta_dot = edx * nx + edy * ny
    slide = -edx * ny + edy * nx
    v_t = slide + geom[N_GEOM * c + G_R_JOURNAL] * wb - geom[N_GEOM * c + G_R_BEARING] * wa
    return (
        delta, delta_dot, v_t, length, ex, ey, nx, ny, slide,
        (rax, ray), (rbx, rby), wa, wb,
    )  # fmt: skip


@njit(cache=True, inline="always")
def _push(force: np.ndarray, body: int, rx: float, ry: float, fx: float, fy: float) -> None:
    """Add the force (fx, fy) acting at arm (rx, ry) from the centre of mass of ``body``."""
    if body < 0:
        return
    force[3 * body] += fx
    force[3 * body + 1] += fy
    force[3 * body + 2] += rx * fy - ry * fx


@njit(cache=True, inline="always")
def add_contact_forces(
    y: np.ndarray, model: EomModel, force: np.ndarray, record: np.ndarray
) -> float:
    """Add every clearance joint's contact force to the generalised forces ``force`` (3 nb).

    Per joint (module docstring): δ = |e| − c, δ̇ = ė·n, v_T = ė·t + R_J ω_b − R_B ω_a; when
    δ > 0, F_N from the normal law, F_T from the friction law; −F_N n − F_T t acts on the
    journal at Q_J = r_J + R_J n, its opposite on the bearing at Q_B = r_B + R_B n. With
    film damping (the joint's ``G_FILM`` = c_e > 0), −c_e ė acts on the journal at its centre
    and +c_e ė on the bearing at its centre, whether in contact or not (not in the record's
    F_N and F_T, which stay the contact law's: :func:`film_components`). Tables
    are flat (:class:`EomModel`); nothing is allocated. (:func:`_contact_state` computes
    the same kinematics for the Jacobian and the hooks; written out here, the right-hand
    side was measured a third faster.)

    Args:
        record: flat (7 nc) receives (F_N, F_T, δ, δ̇, v_T, e_x, e_y) per joint; an empty
            array records nothing.

    Returns:
        The power absorbed by the contacts, Σ (F_N δ̇ + F_T v_T + c_e |ė|²), W.
    """
    joint_int, joint_f, geom = model.joint_int, model.joint_f, model.geom
    clear_joint, law_id, law_p = model.clear_joint, model.law_id, model.law_p
    fric_id, fric_p = model.fric_id, model.fric_p
    n = model.mass.shape[0]
    q = y[:n]
    qd = y[n : 2 * n]
    nc = clear_joint.shape[0]
    plaw = law_p.shape[0] // max(nc, 1)
    pfric = fric_p.shape[0] // max(nc, 1)
    recording = record.shape[0] > 0
    power = 0.0
    last = (-2, 1.0, 0.0, -2, 1.0, 0.0)  # no body yet (-1 is the ground)
    for c in range(nc):
        film = geom[N_GEOM * c + G_FILM]  # this joint's c_e; 0: dry
        j = clear_joint[c]
        a, b = joint_int[3 * j + 1], joint_int[3 * j + 2]
        cos_a, sin_a = _rotation_of(q, a, last)
        cos_b, sin_b = _rotation_of(q, b, last)
        last = (a, cos_a, sin_a, b, cos_b, sin_b)
        bx, by, rax, ray = _arm_rotated(q, a, cos_a, sin_a, joint_f[6 * j], joint_f[6 * j + 1])
        jx, jy, rbx, rby = _arm_rotated(q, b, cos_b, sin_b, joint_f[6 * j + 2], joint_f[6 * j + 3])
        ex, ey = jx - bx, jy - by
        emag = np.sqrt(ex * ex + ey * ey)
        delta = emag - geom[N_GEOM * c + G_CLEARANCE]
        f_n = 0.0
        f_t = 0.0
        delta_dot = 0.0
        v_t = 0.0
        if film > 0.0:  # the film's damping −c_e ė on the journal's centre, in contact or not
            fdx, fdy = _eccentricity_rate(qd, a, b, rax, ray, rbx, rby)
            _push(force, b, rbx, rby, -film * fdx, -film * fdy)
            _push(force, a, rax, ray, film * fdx, film * fdy)
            power += film * (fdx * fdx + fdy * fdy)
        if delta > 0.0 or recording:
            nx, ny = (ex / emag, ey / emag) if emag > 0.0 else (1.0, 0.0)
            wa = qd[3 * a + 2] if a >= 0 else 0.0
            wb = qd[3 * b + 2] if b >= 0 else 0.0
            edx, edy = _eccentricity_rate(qd, a, b, rax, ray, rbx, rby)
            delta_dot = edx * nx + edy * ny
            r_j = geom[N_GEOM * c + G_R_JOURNAL]
            r_b = geom[N_GEOM * c + G_R_BEARING]
            v_t = -edx * ny + edy * nx + r_j * wb - r_b * wa
            v0 = y[2 * n + 2 + c]
            if delta > 0.0 and v0 >= 0.0:  # v0 < 0: locked, F_N is a multiplier
                f_n = normal_force(law_id[c], law_p, plaw * c, delta, delta_dot, v0)
                if fric_id[c] != FRICTION_NONE:
                    f_t = friction_force(fric_id[c], fric_p, pfric * c, v_t, f_n)
                fx = -f_n * nx + f_t * ny
                fy = -f_n * ny - f_t * nx
                _push(force, b, rbx + r_j * nx, rby + r_j * ny, fx, fy)
                _push(force, a, rax + r_b * nx, ray + r_b * ny, -fx, -fy)
                power += f_n * delta_dot + f_t * v_t
        if recording:
            for k, value in enumerate((f_n, f_t, delta, delta_dot, v_t, ex, ey)):
                record[7 * c + k] = value
    return power


@njit(cache=True, inline="always")
def _driver_only_accelerations(
    t: float, model: EomModel, acc: np.ndarray, lam: np.ndarray
) -> float:
    """:func:`constrained_accelerations` when every joint is clear: the driver is the only
    constraint, λ = Q_φk − I_k φ̈_d, q̈_φk = φ̈_d and q̈ = M⁻¹ Q elsewhere."""
    driver, mass = model.driver, model.mass
    crank = int(driver[0])
    torque = 0.0
    if crank >= 0:
        k = 3 * crank + 2
        multiplier = acc[k] - mass[k] * driver_motion(t, driver)[2]
        acc[k] -= multiplier
        torque = -multiplier
        if lam.shape[0] > 0:
            lam[0] = multiplier
    for i in range(mass.shape[0]):
        acc[i] /= mass[i]
    return torque


@njit(cache=True)
def constrained_accelerations(
    t: float, y: np.ndarray, model: EomModel, acc: np.ndarray, lam: np.ndarray
) -> float:
    """Turn the generalised forces Q in ``acc`` into q̈ (in place); return the motor torque.

    Schur complement of the augmented system: (Φ_q M⁻¹ Φ_qᵀ) λ = Φ_q M⁻¹ Q − γ,
    q̈ = M⁻¹ (Q − Φ_qᵀ λ) (Nikravesh 1988, §6; M diagonal), torque = −λ_driver. When
    every joint is clear and the crank is driven, Φ = φ_k − φ_d(t) is the only constraint:
    λ = Q_φk − I_k φ̈_d, so q̈_φk = φ̈_d and q̈ = M⁻¹ Q elsewhere — no matrix at all.

    Args:
        acc: (3 nb) Q on entry, q̈ on return.
        lam: (rows) receives λ, the ideal joints' rows then the driver's; an array with no
            entries records nothing (the torque is returned either way).
    """
    joint_int, joint_f, active = model.joint_int, model.joint_f, model.active
    driver, mass = model.driver, model.mass
    n = mass.shape[0]
    crank = int(driver[0])
    n_ideal = 0
    for j in range(active.shape[0]):
        n_ideal += active[j]
    if n_ideal == 0:
        return _driver_only_accelerations(t, model, acc, lam)
    q = y[:n]
    qd = y[n : 2 * n]
    nj = active.shape[0]
    joints = joint_int.reshape((nj, 3))
    joint_floats = joint_f.reshape((nj, 6))
    phi_q = jacobian(q, joints, joint_floats, active, driver)
    multipliers = acceleration_rhs(q, qd, t, joints, joint_floats, active, driver)
    rows = phi_q.shape[0]
    schur = np.zeros((rows, rows))
    for r in range(rows):  # multipliers ← Φ_q M⁻¹ Q − γ ; schur ← Φ_q M⁻¹ Φ_qᵀ
        s = -multipliers[r]
        for i in range(n):
            w = phi_q[r, i] / mass[i]
            s += w * acc[i]
            if w != 0.0:
                for p in range(r + 1):
                    schur[r, p] += w * phi_q[p, i]
        multipliers[r] = s
    cholesky_solve(schur, multipliers, schur.shape[0])
    for i in range(n):
        s = acc[i]
        for r in range(rows):
            s -= phi_q[r, i] * multipliers[r]
        acc[i] = s / mass[i]
    for r in range(lam.shape[0]):
        lam[r] = multipliers[r]
    return -multipliers[rows - 1] if crank >= 0 else 0.0


# --- sustained contact: a locked clearance joint is the bilateral constraint |e| = c --------


@njit(cache=True, inline="always")
def _locked(v0: float) -> bool:
    """Whether a clearance joint whose v0 slot holds ``v0`` is locked (:data:`LOCKED`)."""
    return v0 < 0.0


@njit(cache=True, inline="always")
def sustained_mode(model: EomModel) -> bool:
    """Whether some clearance joint has the sustained-contact mode (its ``G_CAPTURE`` > 0),
    read from the settings' ``S_CAPTURE_MAX``, the largest of them, in one comparison."""
    return model.settings[S_CAPTURE_MAX] > 0.0


@njit(cache=True, inline="always")
def any_locked(y: np.ndarray, model: EomModel) -> bool:
    """Whether some clearance joint is locked at ``y`` (in the sustained-contact mode, the
    only one that writes a negative v0: :data:`LOCKED`); ``False`` with the mode off."""
    if not sustained_mode(model):
        return False
    base = 2 * model.mass.shape[0] + 2
    for c in range(model.clear_joint.shape[0]):  # noqa: SIM110 (a plain loop compiles best)
        if _locked(y[base + c]):
            return True
    return False


@njit(cache=True)
def locked_row(
    q: np.ndarray, qd: np.ndarray, model: EomModel, c: int, g_row: np.ndarray, h_col: np.ndarray
) -> tuple[float, float, float, float, float]:
    """The constraint |e| = c of locked clearance joint ``c`` at (q, q̇).

    Writes ``g_row`` (3 nb) = G_c = ∂δ/∂q = nᵀ ∂e/∂q: +[n_x, n_y, n·(ẑ×r_b)] on the
    journal's body b, −[n_x, n_y, n·(ẑ×r_a)] on the bearing's body a; and ``h_col`` (3 nb),
    the generalised force of a unit normal force F_N = 1 N with its friction F_T = μ(v_T):
    −(n + μ t) on the journal at r_b + R_J n, its opposite on the bearing at r_a + R_B n
    (as :func:`add_contact_forces`; its normal part is −G_cᵀ). δ̈ = 0 reads G_c q̈ = γ_c with

        γ_c = −[(ė·t)² / |e| + n·(ω_a² r_a − ω_b² r_b)]

    (δ̈ = n·ë + ṅ·ė with ṅ = t (ė·t)/|e|, and n·ë = G_c q̈ + n·(ω_a² r_a − ω_b² r_b)
    since a centre at arm r accelerates as ẍ + φ̈ ẑ×r − ω² r).

    Returns:
        (γ_c in m/s², δ = |e| − c in m, δ̇ in m/s, v_T in m/s, μ = F_T / F_N).
    """
    joint_int, joint_f, geom = model.joint_int, model.joint_f, model.geom
    j = model.clear_joint[c]
    a, b = joint_int[3 * j + 1], joint_int[3 * j + 2]
    bx, by, rax, ray = _arm_of(q, a, joint_f[6 * j], joint_f[6 * j + 1])
    jx, jy, rbx, rby = _arm_of(q, b, joint_f[6 * j + 2], joint_f[6 * j + 3])
    ex, ey = jx - bx, jy - by
    length = np.sqrt(ex * ex + ey * ey)
    nx, ny = (ex / length, ey / length) if length > 0.0 else (1.0, 0.0)
    tx, ty = -ny, nx
    wa = qd[3 * a + 2] if a >= 0 else 0.0
    wb = qd[3 * b + 2] if b >= 0 else 0.0
    edx, edy = _eccentricity_rate(qd, a, b, rax, ray, rbx, rby)
    delta_dot = edx * nx + edy * ny
    slide = edx * tx + edy * ty
    r_j = geom[N_GEOM * c + G_R_JOURNAL]
    r_b = geom[N_GEOM * c + G_R_BEARING]
    v_t = slide + r_j * wb - r_b * wa
    mu = 0.0
    fric = model.fric_id[c]
    if fric != FRICTION_NONE:
        width = model.fric_p.shape[0] // model.clear_joint.shape[0]
        mu = friction_force(fric, model.fric_p, width * c, v_t, 1.0)
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
    _push(h_col, b, rbx + r_j * nx, rby + r_j * ny, fx, fy)
    _push(h_col, a, rax + r_b * nx, ray + r_b * ny, -fx, -fy)
    centripetal = nx * (wa * wa * rax - wb * wb * rbx) + ny * (wa * wa * ray - wb * wb * rby)
    gamma = -(slide * slide / length + centripetal)
    return gamma, length - geom[N_GEOM * c + G_CLEARANCE], delta_dot, v_t, mu


@njit(cache=True)
def sustained_accelerations(
    t: float, y: np.ndarray, model: EomModel, acc: np.ndarray, lam: np.ndarray,
    contacts: np.ndarray,
) -> tuple[float, float]:  # fmt: skip
    """:func:`constrained_accelerations` with the locked clearance joints as constraints.

    Unknowns x = [λ (ideal joints' rows, then the driver's), F_N of every locked joint];
    rows A = [Φ_q; G_c], force columns B = [Φ_qᵀ, −h_c] (:func:`locked_row`):

        q̈ = M⁻¹ (Q − B x),   (A M⁻¹ B) x = A M⁻¹ Q − [γ; γ_c],

    solved by LU with partial pivoting (A M⁻¹ B is not symmetric with friction). The
    normal force of a locked joint is its multiplier F_N (tensile if < 0: the joint is
    released after the step, :func:`release_check`), its friction F_T = μ(v_T) F_N.

    Args:
        acc: (3 nb) Q on entry (without the locked joints' forces), q̈ on return.
        lam: receives λ unless empty.
        contacts: the records of :func:`add_contact_forces` (7 per joint), whose F_N and F_T
            of the locked joints are written here, unless empty.

    Returns:
        (motor torque, N·m; the power absorbed by the locked contacts Σ F_N δ̇ + F_T v_T, W).
    """
    joint_int, joint_f, active = model.joint_int, model.joint_f, model.active
    driver, mass = model.driver, model.mass
    n = mass.shape[0]
    nc = model.clear_joint.shape[0]
    q = y[:n]
    qd = y[n : 2 * n]
    nj = active.shape[0]
    joints = joint_int.reshape((nj, 3))
    joint_floats = joint_f.reshape((nj, 6))
    phi_q = jacobian(q, joints, joint_floats, active, driver)
    gamma = acceleration_rhs(q, qd, t, joints, joint_floats, active, driver)
    rows = phi_q.shape[0]
    m = 0
    for c in range(nc):
        if _locked(y[2 * n + 2 + c]):
            m += 1
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
        if not _locked(y[2 * n + 2 + c]):
            continue
        g, _, rate, slip, mu = locked_row(q, qd, model, c, rows_a[r], cols_b[r])
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
            w = rows_a[p, i] / mass[i]
            if w != 0.0:
                s += w * acc[i]
                for s2 in range(k):
                    system[p, s2] += w * cols_b[s2, i]
        rhs[p] = s
    lu, piv = lu_factor(system)
    lu_solve_in_place(lu, piv, rhs)
    for i in range(n):
        s = acc[i]
        for p in range(k):
            s -= cols_b[p, i] * rhs[p]
        acc[i] = s / mass[i]
    for p in range(min(lam.shape[0], rows)):
        lam[p] = rhs[p]
    power = 0.0
    for i in range(m):
        f_n = rhs[rows + i]
        f_t = state[i, 2] * f_n
        power += f_n * state[i, 0] + f_t * state[i, 1]
        if contacts.shape[0] > 0:
            contacts[7 * which[i]] = f_n
            contacts[7 * which[i] + 1] = f_t
    torque = -rhs[rows - 1] if int(driver[0]) >= 0 and rows > 0 else 0.0
    return torque, power


#: Tolerance of the release control: a step whose end has a locked joint's F_N below
#: −RELEASE_TOL · max(F_N at its start, 1 N) is retried, shortened to the sign change.
RELEASE_TOL = 1e-3


@njit(cache=True)
def release_check(
    t_old: float, y_old: np.ndarray, t_new: float, y_new: np.ndarray, model: EomModel
) -> float:
    """The step's fraction that ends where the first locked joint's multiplier F_N turns
    tensile (secant between the step's ends, aiming at −RELEASE_TOL/2 · max(F_N, 1 N)); 1 if
    none turns tensile beyond the tolerance. As :func:`onset_check` for an onset."""
    nc = model.clear_joint.shape[0]
    old = np.zeros((nc, 7))
    new = np.zeros((nc, 7))
    evaluate(t_old, y_old, model, old)
    evaluate(t_new, y_new, model, new)
    n = model.mass.shape[0]
    theta = 1.0
    for c in range(nc):
        if not _locked(y_new[2 * n + 2 + c]):
            continue
        f_old, f_new = old[c, 0], new[c, 0]
        tolerance = RELEASE_TOL * max(f_old, 1.0)
        if f_old > 0.0 and f_new < -tolerance:
            theta = min(theta, (f_old + 0.5 * tolerance) / (f_old - f_new))
    return theta


@njit(cache=True)
def _energy(y: np.ndarray, model: EomModel) -> float:
    """KE + V_gravity at ``y``, J (V = −Σ Q_gravity,i q_i: gravity is constant)."""
    n = model.mass.shape[0]
    e = 0.0
    for i in range(n):
        e += 0.5 * model.mass[i] * y[n + i] * y[n + i] - model.gravity[i] * y[i]
    return e


@njit(cache=True)
def project_locked(
    t: float, y: np.ndarray, model: EomModel, work: np.ndarray, drift: bool = True
) -> bool:
    """Mass-weighted projection of q onto Φ = 0 and |e| = c of every locked joint, and of q̇
    onto Φ_q q̇ = ν, G_c q̇ = 0 (as :func:`project`, with the rows of :func:`locked_row`);
    the mechanical energy it removes (KE + V before minus after, J) is added to W_contact,
    so that the energy balance still closes. ``drift``: the violation is drift, recorded
    in the workspace as the largest violation (``False`` at a capture, where it is the
    penetration the capture removes). Returns: the positions moved by more than the
    projection tolerance."""
    active, driver, mass = model.active, model.driver, model.mass
    n = mass.shape[0]
    nc = model.clear_joint.shape[0]
    nj = active.shape[0]
    joints = model.joint_int.reshape((nj, 3))
    joint_floats = model.joint_f.reshape((nj, 6))
    q = y[:n]
    qd = y[n : 2 * n]
    tolerance = model.settings[S_PROJ_TOL]
    before = _energy(y, model)
    rows = count_rows(active, driver)
    m = 0
    for c in range(nc):
        if _locked(y[2 * n + 2 + c]):
            m += 1
    k = rows + m
    a = np.empty((k, n))
    h = np.empty(n)
    value = np.empty(k)
    inv_mass = 1.0 / mass
    moved = False
    for iteration in range(4):
        phi_q = jacobian(q, joints, joint_floats, active, driver)
        phi = residual(q, t, joints, joint_floats, active, driver)
        r = 0
        for r in range(rows):
            a[r] = phi_q[r]
            value[r] = phi[r]
        r = rows
        for c in range(nc):
            if _locked(y[2 * n + 2 + c]):
                value[r] = locked_row(q, qd, model, c, a[r], h)[1]
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
    nu = velocity_rhs(t, active, driver)
    for r in range(k):
        s = -nu[r] if r < rows else 0.0
        for i in range(n):
            s += a[r, i] * qd[i]
        rate[r] = s
    weighted = a * inv_mass
    qd -= inv_mass * (a.T @ np.linalg.solve(weighted @ a.T, rate))
    y[2 * n + 1] += before - _energy(y, model)
    work[W_PROJECTIONS] += 1.0
    return moved


@njit(cache=True)
def switch_contacts(
    t: float, y: np.ndarray, model: EomModel, work: np.ndarray, before: np.ndarray
) -> bool:
    """The sustained-contact mode's switches after an accepted step (mode on only).

    Release: a locked joint whose multiplier F_N is negative (tensile) at ``y`` becomes a
    free compliant joint (v0 = 0). Capture: a compliant contact in progress (v0 > 0, δ > 0)
    whose normal relative speed |δ̇| is below its capture speed (``geom`` column ``G_CAPTURE``) at
    both ends of the step (``before``: δ and δ̇ at its start, 7 per joint as
    :func:`add_contact_forces` records them; empty: the end only) becomes locked
    (v0 = :data:`LOCKED`). Both ends: the turning point of an impact (δ̇ = 0 at the
    deepest penetration) passes within a step, so it is not captured, and its rebound
    is kept; a pressed pin whose radial oscillation has a speed amplitude of a few capture
    speeds is. The joints locked before the step are projected onto |e| = c with δ̇ = 0
    (:func:`project_locked`, drift) before the capture test, and again after a capture
    (removing the captured pin's small penetration and normal speed). Returns: a
    joint switched or the positions moved beyond the tolerance.
    """
    n = model.mass.shape[0]
    nc = model.clear_joint.shape[0]
    changed = False
    if any_locked(y, model):
        record = np.zeros((nc, 7))
        evaluate(t, y, model, record)
        for c in range(nc):
            if _locked(y[2 * n + 2 + c]) and record[c, 0] < 0.0:
                y[2 * n + 2 + c] = 0.0
                changed = True
    if any_locked(y, model) and project_locked(t, y, model, work):
        changed = True
    q = y[:n]
    qd = y[n : 2 * n]
    rot = _rotations(q)
    memory = y[2 * n + 2 :].copy()
    captured = False
    captured_one = False
    for c in range(nc):
        capture = model.geom[N_GEOM * c + G_CAPTURE]
        if not (y[2 * n + 2 + c] > 0.0 and capture > 0.0):
            continue
        delta, delta_dot = _contact_state(
            q, qd, rot, model.joint_int, model.joint_f, model.clear_joint[c], model.geom, c
        )[:2]
        slow = abs(delta_dot) < capture
        if before.shape[0] > 0:
            slow = slow and before[7 * c + 2] > 0.0 and abs(before[7 * c + 3]) < capture
        if delta > 0.0 and slow:
            y[2 * n + 2 + c] = LOCKED
            captured = True
    if captured:  # a joint whose multiplier would be tensile at once is left compliant
        record = np.zeros((nc, 7))
        evaluate(t, y, model, record)
        for c in range(nc):
            if _locked(y[2 * n + 2 + c]) and memory[c] > 0.0:
                if record[c, 0] < 0.0:
                    y[2 * n + 2 + c] = memory[c]
                else:
                    captured_one = True
        if captured_one:
            project_locked(t, y, model, work, False)
            changed = True
    return changed


@njit(cache=True)
def evaluate(t: float, y: np.ndarray, model: EomModel, contact_out: np.ndarray):
    """q̈, motor torque, contact power and multipliers λ (ideal joints' rows, then the driver's).

    Per clearance joint, (F_N, F_T, δ, δ̇, v_T, e_x, e_y) is written into ``contact_out``
    (nc, 7), a C-contiguous array (a locked joint's F_N is its multiplier, F_T = μ(v_T) F_N:
    :func:`sustained_accelerations`).
    """
    acc = model.gravity.copy()
    contact_power = add_contact_forces(y, model, acc, contact_out.reshape(contact_out.size))
    lam = np.zeros(count_rows(model.active, model.driver))
    if any_locked(y, model):
        torque, locked_power = sustained_accelerations(
            t, y, model, acc, lam, contact_out.reshape(contact_out.size)
        )
        contact_power += locked_power
    else:
        torque = constrained_accelerations(t, y, model, acc, lam)
    return acc, torque, contact_power, lam


#: Joint kinds of ``joint_int`` column 0 (as :mod:`jointplay.model.flat` numbers them).
_REVOLUTE, _PRISMATIC = 0, 1


@njit(cache=True)
def quantities(
    t: float, y: np.ndarray, model: EomModel, out: np.ndarray, penetration: np.ndarray
) -> np.ndarray:
    """The batch engine's quantities at one state, in QUANTITY ORDER; returns q̈.

    ``out`` (P = 2 nb + nj + 1) receives ω_b (rad/s) and α_b (rad/s²) of every body, the
    magnitude of the force transmitted by every joint (N: |F_N n + F_T t| for a clearance
    joint; |λ| of its two rows for an ideal revolute joint, |λ| of its normal row for a
    prismatic joint — as :func:`jointplay.dynamics.simulate._columns` reports them) and the
    motor torque −λ_driver (N·m). ``penetration`` (nc) receives δ = |e| − c of every clearance
    joint (m; negative while free). The same arithmetic as :func:`evaluate`.
    """
    n = model.mass.shape[0]
    f = np.empty(y.shape[0])
    rhs_and_quantities(
        t, y, model, f, np.empty(7 * model.clear_joint.shape[0]),
        np.zeros(count_rows(model.active, model.driver)), out, penetration,
    )  # fmt: skip
    return f[n : 2 * n]


@njit(cache=True)
def rhs_and_quantities(
    t: float, y: np.ndarray, model: EomModel, f: np.ndarray, contacts: np.ndarray,
    lam: np.ndarray, out: np.ndarray, penetration: np.ndarray,
) -> None:  # fmt: skip
    """:func:`rhs_into` and :func:`quantities` at one state from one evaluation of the forces
    (the explicit batch lanes' last stage, whose ẏ is the next step's first): ``f`` receives
    ẏ, ``out`` and ``penetration`` the quantities; ``contacts`` (7 nc) and ``lam`` (the
    multipliers' rows) are work arrays. The same arithmetic as each of the two."""
    n = model.mass.shape[0]
    nb = n // 3
    nc = model.clear_joint.shape[0]
    active, joint_int = model.active, model.joint_int
    nj = active.shape[0]
    torque = _rhs(t, y, model, f, contacts, lam)
    for b in range(nb):
        out[b] = y[n + 3 * b + 2]
        out[nb + b] = f[n + 3 * b + 2]
    row = 0
    for j in range(nj):
        if active[j] == 1:
            if joint_int[3 * j] == _REVOLUTE:
                out[2 * nb + j] = np.hypot(lam[row], lam[row + 1])
            else:
                out[2 * nb + j] = abs(lam[row + 1])
            row += 2
        else:
            for c in range(nc):
                if model.clear_joint[c] == j:
                    out[2 * nb + j] = transmitted_force(y, model, contacts, c)
    out[2 * nb + nj] = torque
    for c in range(nc):
        penetration[c] = contacts[7 * c + 2]


@njit(cache=True)
def film_components(y: np.ndarray, model: EomModel, contacts: np.ndarray, c: int):
    """The film force c_e ė of clearance joint ``c`` in its contact frame, (c_e ė·n, c_e ė·t)
    (N; the journal feels minus this), from its record in ``contacts`` (7 per joint:
    :func:`add_contact_forces`; ė·n = δ̇, ė·t = v_T − R_J ω_b + R_B ω_a); (0, 0) with the film
    off."""
    film = model.geom[N_GEOM * c + G_FILM]
    if not film > 0.0:
        return 0.0, 0.0
    n = model.mass.shape[0]
    j = model.clear_joint[c]
    a, b = model.joint_int[3 * j + 1], model.joint_int[3 * j + 2]
    wa = y[n + 3 * a + 2] if a >= 0 else 0.0
    wb = y[n + 3 * b + 2] if b >= 0 else 0.0
    slide = (
        contacts[7 * c + 4]
        - model.geom[N_GEOM * c + G_R_JOURNAL] * wb
        + model.geom[N_GEOM * c + G_R_BEARING] * wa
    )
    return film * contacts[7 * c + 3], film * slide


@njit(cache=True)
def transmitted_force(y: np.ndarray, model: EomModel, contacts: np.ndarray, c: int) -> float:
    """The magnitude of the force clearance joint ``c`` transmits, |F_N n + F_T t + c_e ė|
    (N): the contact law's forces and the film's (:func:`film_components`; |F_N n + F_T t|
    with the film off), from its record in ``contacts`` (7 per joint)."""
    film_n, film_t = film_components(y, model, contacts, c)
    return np.hypot(contacts[7 * c] + film_n, contacts[7 * c + 1] + film_t)


@njit(cache=True, inline="always")
def rhs_into(t: float, y: np.ndarray, model: EomModel, out: np.ndarray) -> None:
    """:func:`rhs` writing ẏ into ``out`` (the batch engine's form: no allocation, the model
    already unpacked); the same arithmetic."""
    nothing = out[:0]
    _rhs(t, y, model, out, nothing, nothing)


@njit(cache=True, inline="always")
def _rhs(
    t: float, y: np.ndarray, model: EomModel, out: np.ndarray, contacts: np.ndarray,
    lam: np.ndarray,
) -> float:  # fmt: skip
    """ẏ into ``out``; the contacts' records into ``contacts`` and the multipliers into
    ``lam`` unless they are empty (:func:`add_contact_forces`,
    :func:`constrained_accelerations`); returns the motor torque."""
    gravity, driver = model.gravity, model.driver
    n = gravity.shape[0]
    acc = out[n : 2 * n]
    for i in range(n):
        out[i] = y[n + i]
        acc[i] = gravity[i]
    out[2 * n + 1] = add_contact_forces(y, model, acc, contacts)
    n_ideal = 0
    for j in range(model.active.shape[0]):
        n_ideal += model.active[j]
    if any_locked(y, model):  # the sustained-contact mode, with a joint locked
        torque, locked_power = sustained_accelerations(t, y, model, acc, lam, contacts)
        out[2 * n + 1] += locked_power
    elif n_ideal == 0:  # called directly: measured twice as fast as through the general function
        torque = _driver_only_accelerations(t, model, acc, lam)
    else:
        torque = constrained_accelerations(t, y, model, acc, lam)
    crank = int(driver[0])
    out[2 * n] = torque * y[n + 3 * crank + 2] if crank >= 0 else 0.0
    for i in range(2 * n + 2, y.shape[0]):
        out[i] = 0.0
    return torque


@njit(rhs_signature, cache=True)
def rhs(t: float, y: np.ndarray, args: EomArgs) -> np.ndarray:
    """ẏ for the state layout of the module docstring; allocates ẏ and nothing else when
    every joint is clear (the paper's case)."""
    out = np.empty(y.shape[0])
    rhs_into(t, y, unpack(args[0], args[1]), out)
    return out


jacobian_signature = types.boolean(
    types.float64,
    types.float64[::1],
    types.float64[::1],
    ARGS_TYPE,
    types.float64[:, ::1],
)

#: Relative step of the one-dimensional differences of the contact and friction laws
#: (√eps, as a forward difference wants), and the floor of the rates it scales, m/s.


@njit(cache=True, inline="always")
def _add_force_column(
    out: np.ndarray, mass: np.ndarray, column: int, a: int, b: int, fx: float, fy: float,
    dfx: float, dfy: float, on_a: tuple[float, float, float, float],
    on_b: tuple[float, float, float, float],
) -> None:  # fmt: skip
    """Add to column ``column`` of ∂ẏ/∂y the derivative ∂f of a force f acting on body b at the
    arm p_b from its centre of mass (and −f on body a at p_a): ∂q̈ = M⁻¹ (∂f, ∂(p × f)) with
    ∂(p × f) = ∂p × f + p × ∂f; ``on_a`` and ``on_b`` are (p_x, p_y, ∂p_x, ∂p_y)."""
    n = mass.shape[0]
    if b >= 0:
        pbx, pby, dpbx, dpby = on_b
        out[n + 3 * b, column] += dfx / mass[3 * b]
        out[n + 3 * b + 1, column] += dfy / mass[3 * b + 1]
        moment = dpbx * fy - dpby * fx + pbx * dfy - pby * dfx
        out[n + 3 * b + 2, column] += moment / mass[3 * b + 2]
    if a >= 0:
        pax, pay, dpax, dpay = on_a
        out[n + 3 * a, column] -= dfx / mass[3 * a]
        out[n + 3 * a + 1, column] -= dfy / mass[3 * a + 1]
        moment = dpax * fy - dpay * fx + pax * dfy - pay * dfx
        out[n + 3 * a + 2, column] -= moment / mass[3 * a + 2]


@njit(cache=True)
def _film_jacobian(
    out: np.ndarray, film: float, qd: np.ndarray, mass: np.ndarray, a: int, b: int,
    rax: float, ray: float, rbx: float, rby: float, wa: float, wb: float,
) -> None:  # fmt: skip
    """Add one clearance joint's film damping to ∂ẏ/∂y (``out``, :func:`jacobian_state`):
    f = −c_e ė on the journal's body b at its arm r_b, −f on the bearing's body a at r_a,
    power c_e |ė|² into the W_contact row."""
    n = mass.shape[0]
    edx, edy = _eccentricity_rate(qd, a, b, rax, ray, rbx, rby)
    fx, fy = -film * edx, -film * edy
    for side in range(2):
        body = b if side == 0 else a
        if body < 0:
            continue
        sign = 1.0 if side == 0 else -1.0
        rx, ry = (rbx, rby) if side == 0 else (rax, ray)
        w = wb if side == 0 else wa
        for k in range(2, 6):  # φ, ẋ, ẏ, ω of this body (ė does not depend on x, y)
            dvx = dvy = 0.0
            if k == 2:
                dvx, dvy = -sign * w * rx, -sign * w * ry
            elif k < 5:
                if k == 3:
                    dvx = sign
                else:
                    dvy = sign
            else:
                dvx, dvy = -sign * ry, sign * rx
            dfx, dfy = -film * dvx, -film * dvy
            column = 3 * body + k if k < 3 else n + 3 * body + k - 3
            # ∂r of this body's own arm (φ only): ẑ×r
            drbx, drby = (-rby, rbx) if (k == 2 and side == 0) else (0.0, 0.0)
            drax, dray = (-ray, rax) if (k == 2 and side == 1) else (0.0, 0.0)
            _add_force_column(out, mass, column, a, b, fx, fy, dfx, dfy,
                              (rax, ray, drax, dray), (rbx, rby, drbx, drby))  # fmt: skip
            out[2 * n + 1, column] += 2.0 * film * (edx * dvx + edy * dvy)


#: Relative step (√eps) and floor of the steps of :func:`_fixed_differences`: m or rad for
#: positions, m/s or rad/s for rates.


@njit(cache=True)
def _fixed_differences(
    t: float, y: np.ndarray, f: np.ndarray, model: EomModel, out: np.ndarray
) -> None:
    """∂ẏ/∂y by forward differences of ẏ (``f`` at (t, y)) with the fixed step
    √eps·max(|y_j|, floor) in each of the 2n coordinates and rates (the other columns zero:
    passive components, see :func:`jacobian_state`): a step of at most ~10⁻⁸ m or rad that
    never grows, so a free pin's zero columns stay zero (unless it is within that of its
    wall, where the column is the contact's one-sided slope). Its 2n evaluations of ẏ are
    not counted (as the integrator's differences, in ``njev``)."""
    n = model.mass.shape[0]
    size = y.shape[0]
    work = y.copy()
    column = np.empty(size)
    out[:, :] = 0.0
    for j in range(2 * n):
        h = (y[j] + DIFF_STEP * max(abs(y[j]), DIFF_FLOOR)) - y[j]
        work[j] = y[j] + h
        rhs_into(t, work, model, column)
        work[j] = y[j]
        for i in range(size):
            out[i, j] = (column[i] - f[i]) / h


@njit(jacobian_signature, cache=True)
def jacobian_state(t: float, y: np.ndarray, f: np.ndarray, args: EomArgs, out: np.ndarray) -> bool:
    """∂ẏ/∂y in closed form when every joint is clear and none is locked (sustained
    contact); by forward differences with fixed steps (:func:`_fixed_differences`) when some
    joints are ideal and the film damps the clear ones; ``False`` (nothing written, the
    integrator differences) otherwise.

    Why the film beside ideal joints is differenced here: the integrator's differences
    (SciPy's ``num_jac``) adapt each column's step from call to call, growing it tenfold
    whenever the column's difference is lost in round-off. A lubricated pin floats free of
    its wall, so its bodies' x, y columns are exactly zero, and their steps grew (to 10⁻⁵ of
    the coordinate, and beyond) until a difference pushed the pin into the wall: entries of
    ~4·10¹⁰ s⁻² where the derivative is 0, the simplified Newton iteration failing on
    almost every step (issue 22: 23 465 steps, 31 476 Newton failures for the paper
    four-bar with A and B clear, settle 2 + 1 revolution; 1 368 and 211 with fixed steps).

    Every joint clear leaves the driver as the only constraint (or none): q̈ = M⁻¹ Q with
    the crank's row replaced by φ̈_d(t) (see :func:`constrained_accelerations`), so
    ∂q̈/∂(q, q̇) = M⁻¹ ∂Q_contact/∂(q, q̇) with that row zero. Per clearance joint in
    contact, with u any coordinate or rate of its two bodies (module docstring for e, n, t):

    - ∂e/∂x_b = I, ∂e/∂φ_b = ẑ×r_b, ∂ė/∂φ_b = −ω_b r_b, ∂ė/∂v_b = I, ∂ė/∂ω_b = ẑ×r_b (and
      the negatives with r_a for the bearing's body a);
    - ∂δ = n·∂e, ∂n = t (t·∂e)/|e|, ∂t = −n (t·∂e)/|e|;
    - ∂δ̇ = n·∂ė + (ė·t)(t·∂e)/|e|, ∂v_T = t·∂ė − δ̇ (t·∂e)/|e| + R_J ∂ω_b − R_B ∂ω_a;
    - ∂F_N = F_N,δ ∂δ + F_N,δ̇ ∂δ̇, ∂F_T = F_T,v ∂v_T + F_T,F ∂F_N (:func:`jointplay._kernels.contact.law_slopes`);
    - the force on the journal f = −F_N n − F_T t has
      ∂f = −∂F_N n − ∂F_T t + (−F_N t + F_T n)(t·∂e)/|e|, and its moment about b's centre
      p_b × f, p_b = r_b + R_J n, has ∂(p_b × f) = ∂p_b × f + p_b × ∂f (the opposite force
      at p_a = r_a + R_B n on a).

    With film damping c_e (a joint's ``G_FILM`` > 0), every such clearance joint, in contact or
    not, adds f = −c_e ė on the journal at r_b and −f at r_a on the bearing:
    ∂f = −c_e ∂ė (∂ė as above: ∂ė/∂φ_b = −ω_b r_b, ∂ė/∂v_b = I, ∂ė/∂ω_b = ẑ×r_b, the
    negatives with r_a, ω_a for a; ė does not depend on x), moments ∂(r_b × f) =
    ∂r_b × f + r_b × ∂f with ∂r_b/∂φ_b = ẑ×r_b (and −(∂r_a × f + r_a × ∂f) on a), power
    ∂(c_e |ė|²) = 2 c_e ė·∂ė (:func:`_film_jacobian`).

    The work rows follow from W_motor' = τ ω_k, τ = I_k φ̈_d − Q_k, and
    W_contact' = Σ F_N δ̇ + F_T v_T (+ c_e |ė|²). The impact-velocity columns are left zero: those
    components are constant in the ODE, so the integrator never uses their columns (see
    ``n_active`` in :func:`jointplay._kernels.radau.radau_integrate`).

    Args:
        f: ẏ at (t, y) (unused: part of the integrator's interface).
        out: (n_state, n_state), overwritten.
    """
    model = unpack(args[0], args[1])
    joint_int, active, clear_joint = model.joint_int, model.active, model.clear_joint
    law_id, fric_id, mass, gravity = model.law_id, model.fric_id, model.mass, model.gravity
    joint_f, driver, geom = model.joint_f, model.driver, model.geom
    law_p, fric_p = model.law_p, model.fric_p
    rpar, ipar = args[0], args[1]  # the laws read their parameters from rpar at offsets
    o_law = (
        ipar[L_MASS] + ipar[L_GRAVITY] + ipar[L_JOINT_F] + ipar[L_DRIVER] + ipar[L_GEOM]
    )  # where law_p starts in rpar (pack's order of the float fields)
    o_fric = o_law + ipar[L_LAW_P]
    n = mass.shape[0]
    nc = clear_joint.shape[0]
    if any_locked(y, model):  # locked joints are constraints: the integrator differences
        return False
    for j in range(active.shape[0]):
        if active[j] != 0:
            if np.any(
                geom[G_FILM::N_GEOM] > 0.0
            ):  # a film: steady steps, not the integrator's adaptive
                _fixed_differences(t, y, f, model, out)
                return True
            return False
    q = y[:n]
    qd = y[n : 2 * n]
    out[:, :] = 0.0
    for i in range(n):
        out[i, n + i] = 1.0
    plaw = law_p.shape[0] // max(nc, 1)
    pfric = fric_p.shape[0] // max(nc, 1)
    power_row = 2 * n + 1
    rot = _rotations(q)
    for c in range(nc):
        j = clear_joint[c]
        a, b = joint_int[3 * j + 1], joint_int[3 * j + 2]
        (delta, delta_dot, v_t, length, _, _, nx, ny, slide,
         (rax, ray), (rbx, rby), wa, wb) = _contact_state(q, qd, rot, joint_int, joint_f, j, geom, c)  # fmt: skip
        film = geom[N_GEOM * c + G_FILM]  # this joint's c_e; 0: dry
        if film > 0.0:
            _film_jacobian(out, film, qd, mass, a, b, rax, ray, rbx, rby, wa, wb)
        if not delta > 0.0:
            continue
        tx, ty = -ny, nx
        r_j = geom[N_GEOM * c + G_R_JOURNAL]
        r_b = geom[N_GEOM * c + G_R_BEARING]
        v0 = y[2 * n + 2 + c]
        f_n = normal_force(law_id[c], rpar, o_law + plaw * c, delta, delta_dot, v0)
        f_t = 0.0
        if fric_id[c] != FRICTION_NONE:
            f_t = friction_force(fric_id[c], rpar, o_fric + pfric * c, v_t, f_n)
        n_delta, n_rate, t_slip, t_normal = law_slopes(
            law_id[c], rpar, o_law + plaw * c, fric_id[c], o_fric + pfric * c,
            delta, delta_dot, v_t, v0, f_n,
        )  # fmt: skip
        fx = -f_n * nx - f_t * tx
        fy = -f_n * ny - f_t * ty
        pbx, pby = rbx + r_j * nx, rby + r_j * ny  # arms of the contact points
        pax, pay = rax + r_b * nx, ray + r_b * ny
        for side in range(2):
            body = b if side == 0 else a
            if body < 0:
                continue
            sign = 1.0 if side == 0 else -1.0
            rx, ry = (rbx, rby) if side == 0 else (rax, ray)
            w = wb if side == 0 else wa
            for k in range(6):  # x, y, φ, ẋ, ẏ, ω of this body; ∂e = de, ∂ė = dv
                de_x = de_y = dv_x = dv_y = 0.0
                dw_b = dw_a = 0.0
                if k == 0:
                    de_x = sign
                elif k == 1:
                    de_y = sign
                elif k == 2:
                    de_x, de_y = -sign * ry, sign * rx
                    dv_x, dv_y = -sign * w * rx, -sign * w * ry
                elif k == 3:
                    dv_x = sign
                elif k == 4:
                    dv_y = sign
                else:
                    dv_x, dv_y = -sign * ry, sign * rx
                    dw_b, dw_a = (1.0, 0.0) if side == 0 else (0.0, 1.0)
                tangential = (tx * de_x + ty * de_y) / length  # (t·∂e)/|e|
                d_delta = nx * de_x + ny * de_y
                d_rate = nx * dv_x + ny * dv_y + slide * tangential
                d_slip = tx * dv_x + ty * dv_y - delta_dot * tangential + r_j * dw_b - r_b * dw_a
                d_fn = n_delta * d_delta + n_rate * d_rate
                d_ft = t_slip * d_slip + t_normal * d_fn
                dfx = -d_fn * nx - d_ft * tx + (-f_n * tx + f_t * nx) * tangential
                dfy = -d_fn * ny - d_ft * ty + (-f_n * ty + f_t * ny) * tangential
                # ∂p = ∂r (φ of its own body only) + R ∂n, ∂n = t (t·∂e)/|e|
                dpbx, dpby = r_j * tx * tangential, r_j * ty * tangential
                dpax, dpay = r_b * tx * tangential, r_b * ty * tangential
                if k == 2 and side == 0:
                    dpbx -= rby
                    dpby += rbx
                elif k == 2:
                    dpax -= ray
                    dpay += rax
                column = 3 * body + k if k < 3 else n + 3 * body + k - 3
                _add_force_column(out, mass, column, a, b, fx, fy, dfx, dfy,
                                  (pax, pay, dpax, dpay), (pbx, pby, dpbx, dpby))  # fmt: skip
                out[power_row, column] += (
                    d_fn * delta_dot + f_n * d_rate + d_ft * v_t + f_t * d_slip
                )
    crank = int(driver[0])
    if crank >= 0:
        k = 3 * crank + 2
        omega = qd[k]
        force = gravity.copy()
        add_contact_forces(y, model, force, y[:0])
        torque = mass[k] * driver_motion(t, driver)[2] - force[k]
        for column in range(2 * n):  # τ = I_k φ̈_d − Q_k: ∂(τ ω_k) = −ω_k ∂Q_k + τ ∂ω_k
            out[2 * n, column] = -omega * mass[k] * out[n + k, column]
            out[n + k, column] = 0.0  # φ̈_k = φ̈_d(t) is prescribed
        out[2 * n, n + k] += torque
    return True


@njit(cache=True, inline="always")
def onset_check(
    t_old: float, y_old: np.ndarray, t_new: float, y_new: np.ndarray, model: EomModel,
    work: np.ndarray,
) -> float:  # fmt: skip
    """:func:`step_check` on an unpacked model. δ at the step's start is the one the
    workspace ``work`` keeps from the last accepted step's end (:func:`_remember`: the same
    arithmetic, so the same bits) when it holds one, else computed from ``y_old``; δ at its
    end only for the joints free at its start."""
    joint_int, joint_f, clear_joint, geom = (
        model.joint_int, model.joint_f, model.clear_joint, model.geom,
    )  # fmt: skip
    n = model.mass.shape[0]
    nc = clear_joint.shape[0]
    tolerance = model.settings[S_ONSET_TOL]
    remembered = work.shape[0] >= N_WORK + 2 * nc and work[W_HAS_PREVIOUS] > 0.0
    theta = 1.0
    rot_old = y_old[:0]  # computed when first needed
    rot_new = y_new[:0]
    for c in range(nc):
        j = clear_joint[c]
        clearance = geom[N_GEOM * c + G_CLEARANCE]
        if remembered:
            old = work[N_WORK + 2 * c]
        else:
            if rot_old.shape[0] == 0:
                rot_old = _rotations(y_old[:n])
            old = _penetration(y_old[:n], rot_old, joint_int, joint_f, j, clearance)
        if old > 0.0 or _locked(y_old[2 * n + 2 + c]):
            continue
        if rot_new.shape[0] == 0:
            rot_new = _rotations(y_new[:n])
        new = _penetration(y_new[:n], rot_new, joint_int, joint_f, j, clearance)
        theta = min(theta, onset_fraction(old, new, tolerance))
    return theta


@njit(cache=True)
def onset_check_recorded(old: np.ndarray, new: np.ndarray, model: EomModel) -> float:
    """:func:`onset_check` from the contact records (7 per joint, :func:`add_contact_forces`)
    of the step's two ends: the same penetrations, none computed again."""
    tolerance = model.settings[S_ONSET_TOL]
    theta = 1.0
    for c in range(model.clear_joint.shape[0]):
        if old[7 * c + 2] <= 0.0:
            theta = min(theta, onset_fraction(old[7 * c + 2], new[7 * c + 2], tolerance))
    return theta


step_check_signature = types.float64(
    types.float64,
    types.float64[::1],
    types.float64,
    types.float64[::1],
    ARGS_TYPE,
)


@njit(step_check_signature, cache=True)
def step_check(
    t_old: float,
    y_old: np.ndarray,
    t_new: float,
    y_new: np.ndarray,
    args: EomArgs,
) -> float:
    """Contact-onset control: a step that enters contact deeper than the onset tolerance is
    retried, shortened by the secant estimate of the crossing (Flores & Ambrósio 2010); in
    the sustained-contact mode, likewise a step at whose end a locked joint's normal force
    has turned tensile beyond the release tolerance (:func:`release_check`).

    Endpoint checks suffice: the free region |e| <= c is convex, so a pin cannot pass into and
    back out of the wall along a (locally straight) step without ending in contact.
    """
    model = unpack(args[0], args[1])
    theta = onset_check(t_old, y_old, t_new, y_new, model, args[2])
    if any_locked(y_new, model):  # the locked set is constant over a step
        theta = min(theta, release_check(t_old, y_old, t_new, y_new, model))
    return theta


@njit(cache=True, inline="always")
def contact_memory_and_projection(
    t: float, y: np.ndarray, model: EomModel, work: np.ndarray
) -> bool:
    """:func:`after_step` on an unpacked model (the batch engine's form)."""
    nc = model.clear_joint.shape[0]
    kept = work.shape[0] >= N_WORK + 2 * nc  # the workspace holds the last step's end
    record = _contact_records(y, model)
    before = np.zeros(7 * nc if kept and work[W_HAS_PREVIOUS] > 0.0 else 0)
    for c in range(before.shape[0] // 7):
        before[7 * c + 2] = work[N_WORK + 2 * c]
        before[7 * c + 3] = work[N_WORK + 2 * c + 1]
    changed = contact_memory(y, model, record, before)
    if sustained_mode(model) and switch_contacts(t, y, model, work, before):
        changed = True
        record = _contact_records(y, model)
    if project(t, y, model, work):
        changed = True
        record = _contact_records(y, model)
    _remember(record, work)
    return changed


@njit(cache=True, inline="always")
def _remember(record: np.ndarray, work: np.ndarray) -> None:
    """Keep δ and δ̇ of every joint (``record``, 7 per joint) in the workspace, if it has room,
    as the start of the next step."""
    nc = record.shape[0] // 7
    if work.shape[0] < N_WORK + 2 * nc:
        return
    work[W_HAS_PREVIOUS] = 1.0
    for c in range(nc):
        work[N_WORK + 2 * c] = record[7 * c + 2]
        work[N_WORK + 2 * c + 1] = record[7 * c + 3]


@njit(cache=True)
def start_workspace(y: np.ndarray, args: EomArgs) -> None:
    """Record the initial state ``y`` in the workspace (``args[2]``) as the start of the first
    step, for :func:`after_step`'s contact memory."""
    _remember(_contact_records(y, unpack(args[0], args[1])), args[2])


@njit(cache=True, inline="always")
def _contact_records(y: np.ndarray, model: EomModel) -> np.ndarray:
    """δ and δ̇ of every clearance joint at ``y``, in a record of :func:`add_contact_forces`'s
    layout (7 per joint; the other entries are not set)."""
    n = model.mass.shape[0]
    nc = model.clear_joint.shape[0]
    q = y[:n]
    qd = y[n : 2 * n]
    rot = _rotations(q)
    record = np.empty(7 * nc)
    for c in range(nc):
        delta, delta_dot = _contact_state(
            q, qd, rot, model.joint_int, model.joint_f, model.clear_joint[c], model.geom, c
        )[:2]
        record[7 * c + 2] = delta
        record[7 * c + 3] = delta_dot
    return record


@njit(cache=True, inline="always")
def contact_memory(y: np.ndarray, model: EomModel, record: np.ndarray, before: np.ndarray) -> bool:
    """Update each joint's contact-event memory v0 (state slot ``2n + 2 + c``) after a step
    from the penetration δ and its rate δ̇ at the step's end (``record``) and start
    (``before``; empty: unknown), both 7 per joint in :func:`add_contact_forces`'s layout: a
    new event stores max(δ̇ at δ = 0, v_mark) (:func:`impact_rate`), an ended one 0.
    Returns: a slot changed."""
    n = model.mass.shape[0]
    changed = False
    known = before.shape[0] > 0
    for c in range(model.clear_joint.shape[0]):
        delta, delta_dot = record[7 * c + 2], record[7 * c + 3]
        slot = 2 * n + 2 + c
        if delta > 0.0 and y[slot] == 0.0:  # a new contact event begins (not locked)
            rate = (
                impact_rate(before[7 * c + 2], before[7 * c + 3], delta, delta_dot)
                if known
                else delta_dot
            )
            y[slot] = max(rate, model.settings[S_V_MARK])
            changed = True
        elif delta <= 0.0 and y[slot] > 0.0:
            y[slot] = 0.0  # the event has ended
            changed = True
    return changed


@njit(cache=True, inline="always")
def project(t: float, y: np.ndarray, model: EomModel, work: np.ndarray) -> bool:
    """Project q and q̇ onto the ideal constraints when they are violated beyond the
    projection tolerance; record the largest violation and the projections in ``work``.
    Returns: the state changed."""
    joint_int, active = model.joint_int, model.active
    mass, joint_f, driver = model.mass, model.joint_f, model.driver
    settings = model.settings
    n = mass.shape[0]
    q = y[:n]
    qd = y[n : 2 * n]
    nj = active.shape[0]
    crank = int(driver[0])
    if active.sum() == 0:  # the driver alone: check |φ_k − φ_d(t)| without building Φ
        if crank < 0:
            return False
        violation = abs(q[3 * crank + 2] - driver_motion(t, driver)[0])
        work[W_MAX_VIOLATION] = max(work[W_MAX_VIOLATION], violation)
        if violation <= settings[S_PROJ_TOL]:
            return False
    joints = joint_int.reshape((nj, 3))
    joint_floats = joint_f.reshape((nj, 6))
    phi = residual(q, t, joints, joint_floats, active, driver)
    if phi.shape[0] == 0:
        return False
    violation = np.max(np.abs(phi))
    work[W_MAX_VIOLATION] = max(work[W_MAX_VIOLATION], violation)
    if violation <= settings[S_PROJ_TOL]:
        return False
    inv_mass = 1.0 / mass
    for _ in range(3):
        phi_q = jacobian(q, joints, joint_floats, active, driver)
        weighted = phi_q * inv_mass
        q -= inv_mass * (phi_q.T @ np.linalg.solve(weighted @ phi_q.T, phi))
        phi = residual(q, t, joints, joint_floats, active, driver)
        if np.max(np.abs(phi)) <= 1e-3 * settings[S_PROJ_TOL]:
            break
    phi_q = jacobian(q, joints, joint_floats, active, driver)
    weighted = phi_q * inv_mass
    drift = phi_q @ qd - velocity_rhs(t, active, driver)
    qd -= inv_mass * (phi_q.T @ np.linalg.solve(weighted @ phi_q.T, drift))
    work[W_PROJECTIONS] += 1.0
    return True


after_step_signature = types.boolean(types.float64, types.float64[::1], ARGS_TYPE)


@njit(after_step_signature, cache=True)
def after_step(t: float, y: np.ndarray, args: EomArgs) -> bool:
    """Update each joint's contact-event memory v0, capture and release joints in the
    sustained-contact mode (:func:`switch_contacts`) and project onto the ideal (and locked)
    constraints; record the largest violation and the projections in the workspace
    (``args[2]``)."""
    rpar, ipar, work = args
    return contact_memory_and_projection(t, y, unpack(rpar, ipar), work)


@njit(cache=True)
def diagnostics(t: np.ndarray, y: np.ndarray, model: EomModel):
    """Per recorded state: q̈ (N, 3nb), torque (N,), contacts (N, nc, 7), ideal-joint reactions
    (N, nj, 2: force of the joint's link a on its link b, N; zero rows for clearance joints)
    and the constraint violation max |Φ| (N,)."""
    n = model.mass.shape[0]
    nc = model.clear_joint.shape[0]
    count = t.shape[0]
    active, driver = model.active, model.driver
    nj = active.shape[0]
    joint_int = model.joint_int.reshape((nj, 3))
    joint_f = model.joint_f.reshape((nj, 6))
    qdd = np.empty((count, n))
    torque = np.empty(count)
    contacts = np.empty((count, nc, 7))
    reactions = np.zeros((count, nj, 2))
    violation = np.empty(count)
    for i in range(count):
        yi = np.ascontiguousarray(y[i])
        qdd[i], torque[i], _, lam = evaluate(t[i], yi, model, contacts[i])
        row = 0
        for j in range(nj):
            if active[j] == 1:
                reactions[i, j, 0] = lam[row]
                reactions[i, j, 1] = lam[row + 1]
                row += 2
        phi = residual(yi[:n], t[i], joint_int, joint_f, active, driver)
        violation[i] = np.max(np.abs(phi)) if phi.shape[0] else 0.0
    return qdd, torque, contacts, reactions, violation
