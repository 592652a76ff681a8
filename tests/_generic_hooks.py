"""The generic loop's contact hooks over the lane source: the tests' independent reference.

Until 2026-11-30 the single engine ran the generic loop of :mod:`jointplay._kernels.driver`
(``jointplay.integrate``) with four hooks of :mod:`jointplay._kernels.eom`: the state's
right-hand side (``eom.state_rhs``), the contact-onset check, the contact memory and
projection after each step, and the Jacobian (``eom.jacobian_state``). The engines now
integrate by the lanes' loop (:data:`jointplay._kernels.lanes.cpu.traced`); the two hooks
only that loop needed live here, where the tests that compare the lanes with a loop and step
functions written apart use them (``tests/_kernels/test_traced_lanes.py``, the implicit
lanes', the film's and the JAX backend's tests). The same compiled pieces of the lane source
as the engines (:mod:`jointplay._kernels.shared`), arranged as the old loop called them.

``args = (rpar, ipar, workspace)``: :meth:`jointplay.dynamics.system.System.kernel_args`.
"""

from __future__ import annotations

import numpy as np
from numba import njit

from jointplay._kernels.eom import EomArgs, lay_of
from jointplay._kernels.ids import N_WORK, S_ONSET_TOL, W_HAS_PREVIOUS
from jointplay._kernels.lanes.source import LY_N, LY_NC, LY_SETTINGS
from jointplay._kernels.shared import compiled, pick

_locked, _penetration_and_rate, _contact_memory, _onset_fraction, _project = pick(
    compiled, "locked penetration_and_rate contact_memory onset_fraction project"
)
_sustained_on, _release_fraction, _switch_contacts = pick(
    compiled, "sustained_on release_fraction switch_contacts"
)

__all__ = ["after_step", "start_workspace", "step_check"]


@njit(cache=True, inline="always")
def _onset_retry(
    y_old: np.ndarray, y_new: np.ndarray, rpar: np.ndarray, ipar: np.ndarray, work: np.ndarray
) -> float:
    """Contact-onset control: the smallest fraction of the step to retry (1: none), from δ at
    the step's start — the one the workspace ``work`` keeps from the last accepted step's end
    (:func:`_remember`: the same arithmetic, so the same bits) when it holds one, else
    computed from ``y_old`` — and δ at its end for the joints free at its start (the source's
    ``onset_fraction``: secant to half the onset tolerance; Flores & Ambrósio 2010)."""
    lay = lay_of(ipar)
    n = lay[LY_N]
    nc = lay[LY_NC]
    tolerance = rpar[lay[LY_SETTINGS] + S_ONSET_TOL]
    remembered = work.shape[0] >= N_WORK + 2 * nc and work[W_HAS_PREVIOUS] > 0.0
    theta = 1.0
    for c in range(nc):
        if remembered:
            old = work[N_WORK + 2 * c]
        else:
            old = _penetration_and_rate(y_old, rpar, ipar, lay, c)[0]
        if old > 0.0 or y_old[2 * n + 2 + c] < 0.0:  # in contact, or locked
            continue
        new = _penetration_and_rate(y_new, rpar, ipar, lay, c)[0]
        theta = min(theta, _onset_fraction(old, new, tolerance))
    return theta


@njit(cache=True)
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
    has turned tensile beyond the release tolerance (the source's ``release_fraction``:
    :func:`jointplay._kernels.sustained.sustained_release_fraction`).

    Endpoint checks suffice: the free region |e| <= c is convex, so a pin cannot pass into and
    back out of the wall along a (locally straight) step without ending in contact.
    """
    rpar, ipar = args[0], args[1]
    lay = lay_of(ipar)
    theta = _onset_retry(y_old, y_new, rpar, ipar, args[2])
    if _locked(y_new, rpar, lay):  # the locked set is constant over a step
        theta = min(theta, _release_fraction(t_old, y_old, t_new, y_new, rpar, ipar, lay))
    return theta


@njit(cache=True, inline="always")
def _records(y: np.ndarray, rpar: np.ndarray, ipar: np.ndarray) -> np.ndarray:
    """δ and δ̇ of every clearance joint at ``y``, in the contact records' layout (7 per
    joint; the other entries are not set)."""
    lay = lay_of(ipar)
    nc = lay[LY_NC]
    record = np.empty(7 * nc)
    for c in range(nc):
        record[7 * c + 2], record[7 * c + 3] = _penetration_and_rate(y, rpar, ipar, lay, c)
    return record


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
    _remember(_records(y, args[0], args[1]), args[2])


@njit(cache=True)
def after_step(t: float, y: np.ndarray, args: EomArgs) -> bool:
    """Update each joint's contact-event memory v0 (the source's ``contact_memory``: a new
    event stores max(δ̇ at δ = 0, v_mark), an ended one 0; the step's start from the
    workspace, else from its end), capture and release joints in the sustained-contact mode
    (:func:`jointplay._kernels.sustained.sustained_switch_contacts`) and project onto the ideal (and
    locked) constraints; record the largest violation and the projections in the workspace
    (``args[2]``), and δ, δ̇ of every joint at the state the next step starts from."""
    rpar, ipar, work = args
    lay = lay_of(ipar)
    nc = lay[LY_NC]
    record = _records(y, rpar, ipar)
    before = record.copy()  # unknown start: δ > 0 at both ends, so v0 = δ̇ at the end
    if work.shape[0] >= N_WORK + 2 * nc and work[W_HAS_PREVIOUS] > 0.0:
        for c in range(nc):
            before[7 * c + 2] = work[N_WORK + 2 * c]
            before[7 * c + 3] = work[N_WORK + 2 * c + 1]
    changed = _contact_memory(y, rpar, lay, record, before)
    if _sustained_on(rpar, lay):
        switched = _switch_contacts(t, y, rpar, ipar, lay, work, before)
        # the records of the state the next step starts from: the switches' projection onto
        # the locked joints moves q even when it stays below the tolerance (not "switched")
        if switched or _locked(y, rpar, lay):
            record = _records(y, rpar, ipar)
        changed = changed or switched
    empty = y[:0].reshape((0, 0))
    if _project(t, y, rpar, ipar, lay, work, empty, empty, y[:0]):
        changed = True
        record = _records(y, rpar, ipar)
    _remember(record, work)
    return changed
