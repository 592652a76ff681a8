"""The single engine is the lanes' loop that records its trajectory (``source.RECORD``).

``simulate`` integrates through :data:`jointplay._kernels.lanes.cpu.traced` (one loop for every
engine, each integrator its steps in the lane source). The reference is what it ran before:
the generic loop of :mod:`jointplay._kernels.driver` with the contact hooks it ran with
(``eom.state_rhs``, the contact-onset check and the contact memory and projection of
``tests/_generic_hooks.py``, ``eom.jacobian_state``) — the same equations, a loop and step
functions written apart. The two give the same bits: every accepted step's time and state,
and every counter.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import _generic_hooks as hooks
from jointplay._kernels import eom, ids
from jointplay.contact.laws import get_law
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.integrate import integrate, integrate_mechanism
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import Start, initial_state
from jointplay.dynamics.system import build_system
from jointplay.model.mechanism import Mechanism

JOINTS = ("O2", "A", "B", "O4")
COUNTERS = ("nfev", "njev", "nlu", "n_steps", "n_rejected_error", "n_rejected_newton",
            "n_rejected_check")  # fmt: skip


def _joints(mechanism: Mechanism, case: str) -> list[ClearanceJoint]:
    if case == "ifm":  # the paper's conventional IFM set: stiff, damped, every joint clear
        law = get_law("impact", stiffness=1e4 * 1e3**1.5, exponent=1.5, c_max=1e4, d_max=1e-4)
        return [ClearanceJoint(j, 21e-6, 5e-3, law) for j in JOINTS]
    if case == "dry":
        return ContactModel(film_damping=0).joints(mechanism, JOINTS)
    if case == "lubricated, ideal joints beside":  # the constrained equations, film
        return ContactModel().joints(mechanism, ["A"])
    if case == "dry, ideal joints beside":  # the constrained equations, differenced Jacobian
        return ContactModel(film_damping=0).joints(mechanism, ["A"])
    assert case == "sustained contact"
    return ContactModel(sustained_contact=True, film_damping=0).joints(mechanism, JOINTS)


def _both(mechanism: Mechanism, case: str, integrator: str, start: Start) -> tuple[Any, Any]:
    """One short integration by the traced lane and by the driver with the old hooks, as
    ``simulate`` sets them up."""
    system = build_system(mechanism, _joints(mechanism, case), ramp_time=start.ramp_time)
    y0 = initial_state(system, start)
    n = system.n_coordinates
    scale = 0.2 if integrator == "dopri5" else 1.0
    atol = np.concatenate([np.full(n, 1e-7), np.full(n, scale * 1e-4), np.full(2, 1e-6),
                           np.full(len(system.clearances), 1.0)])  # fmt: skip
    t_end = 0.08 * mechanism.driver.period
    options = {"rtol": scale * 1e-6, "atol": atol, "max_step": mechanism.driver.period / 360,
               "max_steps": 20_000}  # fmt: skip
    args = system.kernel_args()
    traced, _ = integrate_mechanism(args, t_end, y0, method=integrator, throw=False, **options)
    hooks.start_workspace(np.ascontiguousarray(y0, dtype=float), args)
    reference = integrate(
        eom.state_rhs, (0.0, t_end), y0, args=args, step_check=hooks.step_check,
        after_step=hooks.after_step, n_second=n, n_active=2 * n, hold_after_failure=True,
        jac=eom.jacobian_state, throw=False, method=integrator,
        autonomous=not start.ramp_time > 0, **options,
    )  # fmt: skip
    return traced, reference


@pytest.mark.parametrize("integrator", ["radau", "rodas4", "dopri5"])
@pytest.mark.parametrize(
    "case",
    ["ifm", "dry", "lubricated, ideal joints beside", "dry, ideal joints beside",
     "sustained contact"],
)  # fmt: skip
def test_the_traced_lane_takes_the_drivers_steps_bit_for_bit(
    paper_fourbar: Mechanism, case: str, integrator: str
) -> None:
    start = Start("rest") if case == "ifm" else Start("steady")
    traced, reference = _both(paper_fourbar, case, integrator, start)
    assert reference.status is traced.status
    assert reference.n_steps > 20
    np.testing.assert_array_equal(traced.t, reference.t)
    np.testing.assert_array_equal(traced.y, reference.y)
    for name in COUNTERS:
        assert getattr(traced, name) == getattr(reference, name), name


def test_a_failing_integration_ends_as_the_drivers(paper_fourbar: Mechanism) -> None:
    """Too few steps: the same status and the same partial trajectory."""
    system = build_system(paper_fourbar, _joints(paper_fourbar, "dry"))
    y0 = initial_state(system, Start("steady"))
    args = system.kernel_args()
    n = system.n_coordinates
    atol = np.full(2 * n + 2 + 4, 1e-6)
    traced, _ = integrate_mechanism(args, 0.05, y0, method="radau", rtol=1e-6, atol=atol,
                                    max_step=1e-3, max_steps=7, throw=False)  # fmt: skip
    hooks.start_workspace(np.ascontiguousarray(y0, dtype=float), args)
    reference = integrate(
        eom.state_rhs, (0.0, 0.05), y0, args=args, rtol=1e-6, atol=atol, max_step=1e-3,
        max_steps=7, step_check=hooks.step_check, after_step=hooks.after_step, n_second=n,
        n_active=2 * n, hold_after_failure=True, jac=eom.jacobian_state, throw=False,
    )  # fmt: skip
    assert traced.status.value == ids.STATUS_TOO_MANY_STEPS == reference.status.value
    np.testing.assert_array_equal(traced.y, reference.y)
    assert traced.message == reference.message
