"""The single engine's model and its cold callers over the lane source.

The equations — right-hand side, contact and friction forces, film damping, the quantities,
the contact memory and the closed-form Jacobian — are written once, in
:mod:`jointplay._kernels.lanes.source` (and ``source_radau``), and the single engine
integrates them by the lanes' own loop with its trajectory recorded
(:data:`jointplay._kernels.lanes.cpu.traced`, through
:func:`jointplay.dynamics.integrate.integrate_mechanism`). This module packs the model
(:func:`pack`), evaluates the recorded states (:func:`evaluate`, :func:`diagnostics`,
:func:`film_forces`, :func:`batch_quantities`) and gives the state's right-hand side and its
Jacobian as functions of ``(t, y, args)`` (:func:`state_rhs`, :func:`jacobian_state`: the
generic ``jointplay.integrate``'s ``fun`` and ``jac``, compiled on first use), which the
tests and benchmarks evaluate the model with.

The model is an :class:`EomModel`: a named tuple of flat arrays that
:mod:`jointplay.dynamics.system` builds once, read-only. :func:`state_rhs` and
:func:`jacobian_state` take ``args = (rpar, ipar, workspace)``: the model packed into two read-only buffers
(:func:`pack`: the floats, and the field lengths, the integers and the source's layout
``lay``) and a workspace (:func:`new_workspace`). State vector::

    y = [q (3 nb), q̇ (3 nb), W_motor, W_contact, v0 (n_clear)]

- q, q̇: centre-of-mass position and angle of every moving link and their rates;
- W_motor = ∫ τ ω_crank dt, the work of the motor (J);
- W_contact = ∫ Σ (F_N δ̇ + F_T v_T) dt, the work absorbed by the clearance contacts (J) —
  so KE + V_gravity − W_motor + W_contact is constant (energy balance);
- v0: penetration rate at the start of the current contact event of each clearance joint
  (m/s, 0 while free); it has zero time derivative and is set after each accepted step (the
  source's ``contact_memory``): after the step in which the contact begins, at δ̇
  interpolated to the instant δ = 0 between the step's ends (linear in δ), so that it does
  not depend on where the step happened to end.
  In the sustained-contact mode (a joint's ``geom`` column ``G_CAPTURE`` > 0) a negative v0
  (:data:`LOCKED`) marks a joint locked onto its bearing's wall: |e| = c is then a
  constraint whose multiplier is the normal force; with the mode off (the default) no slot is
  ever negative and each kernel pays one comparison for the mode.

Ideal joints and the driver are constraints Φ(q, t) = 0 (see :mod:`constraints`); with the
diagonal mass matrix M the accelerations follow from the Schur complement
(Φ_q M⁻¹ Φ_qᵀ) λ = Φ_q M⁻¹ Q − γ, q̈ = M⁻¹ (Q − Φ_qᵀ λ), and the motor torque is −λ_driver.
Position and velocity drift is removed after every accepted step by mass-weighted projection
(Hairer, Lubich & Wanner, *Geometric Numerical Integration*, §IV.4). The integrators use
that q̇ = d/dt q and that W_motor, W_contact and v0 do not feed back (the lanes' Newton
systems are on the velocities alone).

Clearance joint (Flores et al., *Kinematics and Dynamics of Multibody Systems with Imperfect
Joints*, 2008; docs/contact-laws.md §5): bearing on body a, journal on body b,
eccentricity e = r_J − r_B, penetration δ = |e| − c, normal n = e/|e|, δ̇ = ė·n,
v_T = ė·t + R_J ω_b − R_B ω_a with t = ẑ × n. The force on the journal, −F_N n − F_T t, acts
at Q_J = r_J + R_J n; its opposite acts on the bearing at Q_B = r_B + R_B n. Film damping
(each joint's ``geom`` column ``G_FILM`` = c_e > 0, the lubricated default; docs/contact.md):
−c_e ė on the journal at its centre and +c_e ė on the bearing at its centre, in contact or
not; its power c_e |ė|² is added to W_contact.

The source's functions are inlined into :func:`state_rhs` and :func:`jacobian_state`
(``inline="always"``, :mod:`shared`): after
editing the source, delete the on-disk caches (the README's ``find src -name "*.nb[ic]"
-delete``): Numba does not follow that dependency.
"""

from __future__ import annotations

from typing import NamedTuple

import numpy as np
from numba import njit

from jointplay._kernels.ids import (
    FLOAT_FIELDS,
    INT_FIELDS,
    LOCKED,
    MODEL_FIELDS,
    N_WORK,
    RELEASE_TOL,
)
from jointplay._kernels.lanes.build import lane_layout
from jointplay._kernels.lanes.source import LY_ACTIVE, LY_N, LY_NC, LY_NIDEAL, LY_NJ, N_LAY
from jointplay._kernels.shared import apart, compiled, pick

# The lane source, compiled for the CPU (jointplay._kernels.shared): inlined into state_rhs
# and jacobian_state; the cold callers' copies (``apart``) are compiled once and called.
_rhs, _any_film, _locked, _constraint_rows, _jacobian_clear = pick(
    compiled, "rhs any_film locked constraint_rows jacobian_clear"
)
# impact_rate: δ̇ (m/s) at δ = 0 between a step's ends, linear in δ (the source's).
_constraint_residual, impact_rate = pick(compiled, "constraint_residual impact_rate")
_rhs_apart, _rhs_and_quantities, _film_components, _jacobian_fixed = pick(
    apart, "rhs rhs_and_quantities film_components jacobian_fixed"
)

__all__ = [
    "LOCKED",
    "RELEASE_TOL",
    "EomModel",
    "batch_quantities",
    "diagnostics",
    "evaluate",
    "film_forces",
    "jacobian_state",
    "new_workspace",
    "pack",
    "state_rhs",
]  # fmt: skip


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
            film damping c_e (``G_FILM``, N·s/m; 0: dry) and the capture speed of its
            sustained-contact mode (``G_CAPTURE``, m/s; 0: off).
        law_id: (nc) int64: normal-force law (:mod:`jointplay._kernels.ids`' ``LAW_*``).
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


def new_workspace(n_clear: int = 0) -> np.ndarray:
    """An empty workspace for one integration of a model with ``n_clear`` clearance joints:
    ``N_WORK + 2 n_clear`` zeros (see ``W_*``)."""
    return np.zeros(N_WORK + 2 * n_clear)


def pack(model: EomModel) -> tuple[np.ndarray, np.ndarray]:
    """``model`` as the two read-only buffers the compiled kernels take.

    ``rpar``: the float fields; ``ipar``: the field lengths (in :class:`EomModel`'s order,
    ``ids.MODEL_FIELDS``), the integer fields, then the lane source's layout ``lay``
    (:func:`jointplay._kernels.lanes.build.lane_layout`, the last ``N_LAY`` entries), so that
    the kernels read the model as the source does.
    A first-class function call costs in proportion to the number of arrays it is given, so
    the integrator passes the model as two arrays rather than as 13.
    """
    lengths = np.array([len(getattr(model, name)) for name in MODEL_FIELDS], dtype=np.int64)
    ipar = np.concatenate([lengths, *(getattr(model, name) for name in INT_FIELDS)])
    ipar = np.concatenate([ipar, lane_layout(ipar.astype(np.int64))])
    rpar = np.concatenate([getattr(model, name) for name in FLOAT_FIELDS])
    return _readonly(rpar.astype(np.float64)), _readonly(ipar.astype(np.int64))


def _readonly(array: np.ndarray) -> np.ndarray:
    array.flags.writeable = False
    return array


@njit(cache=True, inline="always")
def lay_of(ipar: np.ndarray) -> np.ndarray:
    """The source's ``lay`` of a model packed by :func:`pack` (a view: its last entries)."""
    return ipar[ipar.shape[0] - N_LAY :]


#: ``args`` as the kernels' annotations spell it: ``(rpar, ipar, workspace)``, the first two
#: read-only (:func:`pack`), the workspace writable (:func:`new_workspace`).
EomArgs = tuple[np.ndarray, np.ndarray, np.ndarray]


@njit(cache=True, inline="always")
def _constraint_work(y: np.ndarray, rpar: np.ndarray, lay: np.ndarray):
    """The source's work arrays for the constrained accelerations, (Φ_q, Schur complement,
    λ): allocated when some joint is ideal, else empty views (every joint clear: the driver's
    row needs no matrix, and the right-hand side allocates nothing but ẏ)."""
    if lay[LY_NIDEAL] > 0:
        rows = _constraint_rows(rpar, lay)
        return np.empty((rows, lay[LY_N])), np.empty((rows, rows)), np.zeros(rows)
    return y[:0].reshape((0, 0)), y[:0].reshape((0, 0)), y[:0]


@njit(cache=True)
def state_rhs(t: float, y: np.ndarray, args: EomArgs) -> np.ndarray:
    """ẏ for the state layout of the module docstring (the source's ``rhs``); allocates ẏ and
    nothing else when every joint is clear (the paper's case)."""
    rpar, ipar = args[0], args[1]
    lay = lay_of(ipar)
    out = np.empty(y.shape[0])
    phi_q, schur, lam = _constraint_work(y, rpar, lay)
    _rhs(t, y, rpar, ipar, lay, out, y[:0], False, phi_q, schur, lam)
    return out


@njit(cache=True)
def evaluate(t: float, y: np.ndarray, rpar: np.ndarray, ipar: np.ndarray, contact_out: np.ndarray):
    """q̈, motor torque, contact power and multipliers λ (ideal joints' rows, then the driver's).

    Per clearance joint, (F_N, F_T, δ, δ̇, v_T, e_x, e_y) is written into ``contact_out``
    (nc, 7), a C-contiguous array (a locked joint's F_N is its multiplier, F_T = μ(v_T) F_N:
    :func:`jointplay._kernels.sustained.sustained_accelerations`).
    """
    lay = lay_of(ipar)
    n = lay[LY_N]
    rows = _constraint_rows(rpar, lay)
    f = np.empty(y.shape[0])
    lam = np.zeros(rows)
    torque = _rhs_apart(
        t, y, rpar, ipar, lay, f, contact_out.reshape(contact_out.size), True,
        np.empty((rows, n)), np.empty((rows, rows)), lam,
    )  # fmt: skip
    return f[n : 2 * n].copy(), torque, f[2 * n + 1], lam


@njit(cache=True)
def batch_quantities(
    t: float, y: np.ndarray, rpar: np.ndarray, ipar: np.ndarray, out: np.ndarray,
    penetration: np.ndarray,
) -> np.ndarray:  # fmt: skip
    """The batch engine's quantities at one state, in QUANTITY ORDER (the source's
    ``rhs_and_quantities``); returns q̈.

    ``out`` (P = 2 nb + nj + 1) receives ω_b (rad/s) and α_b (rad/s²) of every body, the
    magnitude of the force transmitted by every joint (N: |F_N n + F_T t + c_e ė| for a
    clearance joint; |λ| of its two rows for an ideal revolute joint, |λ| of its normal row
    for a prismatic joint — as :func:`jointplay.dynamics.simulate._columns` reports them) and
    the motor torque −λ_driver (N·m). ``penetration`` (nc) receives δ = |e| − c of every
    clearance joint (m; negative while free).
    """
    lay = lay_of(ipar)
    n = lay[LY_N]
    rows = _constraint_rows(rpar, lay)
    f = np.empty(y.shape[0])
    _rhs_and_quantities(
        t, y, rpar, ipar, lay, f, np.empty(7 * lay[LY_NC]), out, penetration,
        np.empty((rows, n)), np.empty((rows, rows)), np.zeros(rows),
    )  # fmt: skip
    return f[n : 2 * n]


@njit(cache=True)
def film_forces(y: np.ndarray, rpar: np.ndarray, ipar: np.ndarray, contacts: np.ndarray):
    """The film force c_e ė of every clearance joint in its contact frame, (c_e ė·n, c_e ė·t),
    at every state (``y``: (N, S); ``contacts``: (N, nc, 7), the records of :func:`evaluate`)
    as an (N, nc, 2) array, N (the journal feels minus this; zeros with the film off)."""
    lay = lay_of(ipar)
    nc = lay[LY_NC]
    out = np.zeros((y.shape[0], nc, 2))
    if not _any_film(rpar, lay):
        return out
    for i in range(y.shape[0]):
        record = contacts[i].reshape(7 * nc)
        for c in range(nc):
            out[i, c, 0], out[i, c, 1] = _film_components(y[i], rpar, ipar, lay, record, c)
    return out


@njit(cache=True)
def jacobian_state(t: float, y: np.ndarray, f: np.ndarray, args: EomArgs, out: np.ndarray) -> bool:
    """∂ẏ/∂y in closed form when every joint is clear and none is locked (the source's
    ``jacobian_clear``, whose docstring derives it); by forward differences with fixed steps
    (``jacobian_fixed``) when some joints are ideal and the film damps the clear ones;
    ``False`` (nothing written, the integrator differences) otherwise.

    Why the film beside ideal joints is differenced here: the integrator's differences
    (SciPy's ``num_jac``) adapt each column's step from call to call, growing it tenfold
    whenever the column's difference is lost in round-off. A lubricated pin floats free of
    its wall, so its bodies' x, y columns are exactly zero, and their steps grew (to 10⁻⁵ of
    the coordinate, and beyond) until a difference pushed the pin into the wall: entries of
    ~4·10¹⁰ s⁻² where the derivative is 0, the simplified Newton iteration failing on
    almost every step (issue 22: 23 465 steps, 31 476 Newton failures for the paper
    four-bar with A and B clear, settle 2 + 1 revolution; 1 368 and 211 with fixed steps).

    The rows of q̇ are the identity (∂q̇/∂q̇ = I: the fixed differences give exactly that);
    the impact-velocity columns are left zero: those components are constant in the ODE, so
    the integrator never uses their columns (``n_active`` in
    :func:`jointplay._kernels.driver.run_core`).

    Args:
        f: ẏ at (t, y).
        out: (n_state, n_state), overwritten.
    """
    rpar, ipar = args[0], args[1]
    lay = lay_of(ipar)
    if _locked(y, rpar, lay):  # locked joints are constraints: the integrator differences
        return False
    film = _any_film(rpar, lay)
    if lay[LY_NIDEAL] > 0 and not film:
        return False
    n = lay[LY_N]
    size = y.shape[0]
    out[:, :] = 0.0
    for i in range(n):
        out[i, n + i] = 1.0
    work = np.empty(size)
    if lay[LY_NIDEAL] == 0:
        _jacobian_clear(t, y, rpar, ipar, lay, out[n:], work, y[:0])
    else:  # a film: steady steps, not the integrator's adaptive
        phi_q, schur, lam = _constraint_work(y, rpar, lay)
        _jacobian_fixed(
            t, y, f, rpar, ipar, lay, out[n:], y.copy(), work, np.empty(7 * lay[LY_NC]),
            phi_q, schur, lam,
        )  # fmt: skip
    return True


@njit(cache=True)
def diagnostics(t: np.ndarray, y: np.ndarray, rpar: np.ndarray, ipar: np.ndarray):
    """Per recorded state: q̈ (N, 3nb), torque (N,), contacts (N, nc, 7), ideal-joint reactions
    (N, nj, 2: force of the joint's link a on its link b, N; zero rows for clearance joints)
    and the constraint violation max |Φ| (N,)."""
    lay = lay_of(ipar)
    n = lay[LY_N]
    nc = lay[LY_NC]
    nj = lay[LY_NJ]
    rows = _constraint_rows(rpar, lay)
    count = t.shape[0]
    qdd = np.empty((count, n))
    torque = np.empty(count)
    contacts = np.empty((count, nc, 7))
    reactions = np.zeros((count, nj, 2))
    violation = np.zeros(count)
    phi = np.zeros(rows)
    for i in range(count):
        yi = np.ascontiguousarray(y[i])
        qdd[i], torque[i], _, lam = evaluate(t[i], yi, rpar, ipar, contacts[i])
        row = 0
        for j in range(nj):
            if ipar[lay[LY_ACTIVE] + j] == 1:
                reactions[i, j, 0] = lam[row]
                reactions[i, j, 1] = lam[row + 1]
                row += 2
        if rows > 0:
            _constraint_residual(t[i], yi, rpar, ipar, lay, phi)
            violation[i] = np.max(np.abs(phi))
    return qdd, torque, contacts, reactions, violation
