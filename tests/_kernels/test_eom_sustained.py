"""The sustained-contact kernels of :mod:`jointplay._kernels.eom`: a locked clearance joint is
the bilateral constraint |e| = c with the normal force as its multiplier.

Checked against closed forms and differences, at states built by hand:

* the constraint row G_c = ∂δ/∂q and the acceleration term γ_c (δ̈ = G_c q̈ − γ_c) of
  :func:`sustained.locked_row` against central differences of δ along a path q(s) = q + q̇ s + q̈ s²/2;
* a pendulum hanging at rest on its locked pin: F_N = m g, q̈ = 0 (statics);
* a free crank spinning about its locked pin (frictionless, no gravity): F_N = m ω² (d + c),
  the centripetal force of its centre of mass at d + c from the bearing's centre;
* the mode off: a locked v0 slot is never written, and the kernels ignore nothing.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

from jointplay._kernels import constraints, eom, shared
from jointplay.contact.friction import AmbrosioFriction
from jointplay.contact.laws import get_law
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import Start, initial_state
from jointplay.dynamics.system import System, build_system
from jointplay.io.config import load_preset
from jointplay.model.mechanism import Driver, Ground, JointFit, Link, Mechanism, RevoluteJoint

CLEARANCE = 21e-6  # m
ARM = 0.1  # m, centre of mass from the pin
MASS = 1.5  # kg
#: Central differences of δ (|e| ~ c = 21 µm) with steps 1e-9 (G) and 1e-6 s (path):
#: truncation and round-off measured ≤ 3e-4 relative; a wrong or missing term is O(1).
DIFF_RTOL = 2e-3
#: Closed-form statics and the spinning crank: round-off of a 4 × 4 solve only.
EXACT_RTOL = 1e-12
Vector = npt.NDArray[np.float64]


def _crank(gravity: tuple[float, float]) -> Mechanism:
    """One link hanging from (or spinning about) ground pin O, its centre of mass ARM away."""
    return Mechanism(
        name="pendulum",
        ground=Ground({"O": (0.0, 0.0)}),
        links=(Link("crank", {"O": (0.0, 0.0), "P": (2 * ARM, 0.0)}, MASS, (ARM, 0.0), 0.02),),
        joints=(RevoluteJoint("O", "ground", "O", "crank", "O", fit=JointFit(diameter=0.01)),),
        driver=Driver("crank", "O", speed=10.0),
        gravity=gravity,
    )


def _locked_system(gravity: tuple[float, float], friction: bool = False) -> System:
    law = get_law("restitution", penalty=1e9, restitution=0.8, exponent=1.0)
    joint = ClearanceJoint(
        "O", CLEARANCE, 5e-3, law, AmbrosioFriction(mu=0.1) if friction else None,
        capture_speed=1e-4,
    )  # fmt: skip
    return build_system(_crank(gravity), [joint], driven=False)


def _state(system: System, q: list[float], qd: list[float]) -> npt.NDArray[np.float64]:
    y = np.zeros(system.n_state)
    y[:3] = q
    y[3:6] = qd
    y[8] = eom.LOCKED
    return y


@pytest.mark.parametrize("friction", [False, True])
def test_a_hanging_pendulum_rests_on_its_pin_with_its_weight(friction: bool) -> None:
    system = _locked_system((0.0, -9.81), friction)
    # hanging straight down: the pin on the bottom of the hole, e = (0, -c)
    y = _state(system, [0.0, -ARM - CLEARANCE, -math.pi / 2], [0.0, 0.0, 0.0])
    contacts = np.zeros((1, 7))
    qdd, torque, power, _ = eom.evaluate(0.0, y, *eom.pack(system.model), contacts)
    assert contacts[0, 0] == pytest.approx(MASS * 9.81, rel=EXACT_RTOL)
    assert contacts[0, 1] == 0.0  # at rest: no slip, no friction
    assert contacts[0, 2] == pytest.approx(0.0, abs=1e-16)  # δ = 0 on the wall (eps·ARM)
    np.testing.assert_allclose(qdd, 0.0, atol=1e-10 * 9.81)  # round-off of cos(-π/2) ≠ 0
    assert power == 0.0
    assert torque == 0.0  # not driven
    # ẏ from the integrator's rhs is the same
    np.testing.assert_allclose(eom.state_rhs(0.0, y, system.kernel_args())[3:6], qdd, atol=0)


def test_a_spinning_crank_pulls_its_pin_with_the_centripetal_force() -> None:
    system = _locked_system((0.0, 0.0))
    omega = 30.0
    radius = ARM + CLEARANCE  # centre of mass from the bearing's centre
    y = _state(system, [radius, 0.0, 0.0], [0.0, omega * radius, omega])
    contacts = np.zeros((1, 7))
    qdd, _, power, _ = eom.evaluate(0.0, y, *eom.pack(system.model), contacts)
    assert contacts[0, 0] == pytest.approx(MASS * omega**2 * radius, rel=EXACT_RTOL)
    np.testing.assert_allclose(
        qdd, [-(omega**2) * radius, 0.0, 0.0], atol=EXACT_RTOL * omega**2 * radius
    )
    assert power == pytest.approx(0.0, abs=1e-12)  # no normal speed, no friction


def _locked_row(
    model: eom.EomModel, q: Vector, qd: Vector, c: int, g: Vector, h: Vector
) -> tuple[float, float, float, float, float]:
    """The sustained mode's ``locked_row`` (:mod:`jointplay._kernels.sustained`) at (q, q̇)."""
    rpar, ipar = eom.pack(model)
    y = np.concatenate([q, qd, np.zeros(2 + len(model.clear_joint))])
    return shared.compiled["locked_row"](y, rpar, ipar, eom.lay_of(ipar), c, g, h)  # type: ignore[no-any-return]


def _delta(model: eom.EomModel, q: Vector, qd: Vector, c: int) -> float:
    n = q.shape[0]
    return float(_locked_row(model, q, qd, c, np.zeros(n), np.zeros(n))[1])


def _slope(model: eom.EomModel, q: Vector, qd: Vector, c: int, i: int) -> float:
    """∂δ/∂q_i by a central difference (step 1e-9)."""
    step = np.zeros(q.shape[0])
    step[i] = 1e-9
    return (_delta(model, q + step, qd, c) - _delta(model, q - step, qd, c)) / 2e-9


def _path_rates(
    model: eom.EomModel, q: Vector, qd: Vector, qdd: Vector, c: int
) -> tuple[float, float]:
    """δ̇ and δ̈ along q(s) = q + q̇ s + q̈ s²/2 at s = 0 by central differences (step 1e-6 s)."""
    s = 1e-6
    ahead, here, behind = (
        _delta(model, q + qd * h + 0.5 * qdd * h * h, qd, c) for h in (s, 0.0, -s)
    )
    return (ahead - behind) / (2 * s), (ahead - 2 * here + behind) / s**2


def test_the_constraint_row_and_its_acceleration_term_equal_differences() -> None:
    mechanism = load_preset("paper-fourbar").with_gravity((0.0, -9.81))
    joints = ContactModel(sustained_contact=True).joints(
        mechanism, ("O2", "A", "B", "O4"), clearance=CLEARANCE
    )
    system = build_system(mechanism, joints)
    model = system.model
    n = system.n_coordinates
    rng = np.random.default_rng(3)
    y0 = initial_state(system, Start("steady"))
    for _ in range(4):
        q = y0[:n] + np.tile([1e-5, 1e-5, 1e-4], n // 3) * rng.standard_normal(n)
        qd = y0[n : 2 * n] + rng.normal(0.0, 0.1, n)
        qdd = rng.normal(0.0, 100.0, n)
        for c in range(len(joints)):
            g = np.zeros(n)
            h = np.zeros(n)
            gamma, _, rate, _, mu = _locked_row(model, q, qd, c, g, h)
            numeric = np.array([_slope(model, q, qd, c, i) for i in range(n)])
            np.testing.assert_allclose(g, numeric, rtol=0, atol=DIFF_RTOL * np.max(np.abs(g)))
            first, second = _path_rates(model, q, qd, qdd, c)
            assert rate == pytest.approx(first, rel=DIFF_RTOL)
            assert g @ qdd - gamma == pytest.approx(second, rel=DIFF_RTOL)
            # the unit contact force: its normal part is −Gᵀ, its friction μ per newton
            assert abs(mu) == pytest.approx(0.1) or mu == 0.0
            assert np.max(np.abs(h + g)) <= (abs(mu) + 1e-12) * 2 * np.max(np.abs(g))


def test_with_the_mode_off_no_joint_reads_as_locked(paper_fourbar: Mechanism) -> None:
    """With every joint's capture speed 0, no joint is ever read as locked,
    and the closed-form Jacobian stays available."""
    joints = ContactModel().joints(paper_fourbar, ("O2", "A", "B", "O4"), clearance=CLEARANCE)
    system = build_system(paper_fourbar, joints)
    assert not system.sustained_mode
    y = initial_state(system, Start("steady"))
    y[2 * system.n_coordinates + 2 :] = eom.LOCKED  # even a negative slot is not "locked"
    rpar, ipar = eom.pack(system.model)
    assert not shared.compiled["locked"](y, rpar, eom.lay_of(ipar))


#: The locked solve against its own equations: round-off of a 7 × 7 LU on accelerations of
#: ~1e3 m/s² (measured ≤ 1e-12 relative).
SOLVE_RTOL = 1e-9


@pytest.mark.parametrize("friction", [False, True])
def test_the_locked_solve_satisfies_its_equations_with_ideal_joints(friction: bool) -> None:
    """General four-bar, B clear and locked, the other joints ideal, gravity on: at random
    states the returned q̈, λ and F_N satisfy Φ_q q̈ = γ, G_B q̈ = γ_B and
    M q̈ = Q_gravity − Φ_qᵀ λ + h_B F_N (:func:`sustained.sustained_accelerations`)."""
    mechanism = load_preset("general-fourbar").with_gravity((0.0, -9.81))
    law = get_law("restitution", penalty=1e9, restitution=0.8, exponent=1.0)
    joint = ClearanceJoint(
        "B", CLEARANCE, 5e-3, law, AmbrosioFriction(mu=0.1) if friction else None,
        capture_speed=1e-4,
    )  # fmt: skip
    system = build_system(mechanism, [joint])
    model = system.model
    n = system.n_coordinates
    nj = len(model.active)
    joints, floats = model.joint_int.reshape(nj, 3), model.joint_f.reshape(nj, 6)
    rng = np.random.default_rng(5)
    y0 = initial_state(system, Start("steady"))
    for i in range(4):
        y = y0.copy()
        y[n : 2 * n] += rng.normal(0.0, 1.0, n)
        y[2 * n + 2] = eom.LOCKED
        t = 0.01 * i
        contacts = np.zeros((1, 7))
        qdd, torque, _, lam = eom.evaluate(t, y, *eom.pack(model), contacts)
        q, qd = y[:n], y[n : 2 * n]
        phi_q = constraints.jacobian(q, joints, floats, model.active, model.driver)
        gamma = constraints.acceleration_rhs(q, qd, t, joints, floats, model.active, model.driver)
        g, h = np.zeros(n), np.zeros(n)
        gamma_b = _locked_row(model, q, qd, 0, g, h)[0]
        scale = np.max(np.abs(qdd))
        np.testing.assert_allclose(phi_q @ qdd, gamma, rtol=0, atol=SOLVE_RTOL * scale)
        assert g @ qdd == pytest.approx(gamma_b, abs=SOLVE_RTOL * scale)
        residual = model.mass * qdd - model.gravity + phi_q.T @ lam - h * contacts[0, 0]
        force = np.max(np.abs(model.mass * qdd))
        np.testing.assert_allclose(residual, 0.0, atol=SOLVE_RTOL * force)
        assert torque == -lam[-1]
        assert contacts[0, 1] == pytest.approx(
            (0.1 if friction else 0.0) * np.sign(contacts[0, 4]) * contacts[0, 0], rel=1e-12
        )
