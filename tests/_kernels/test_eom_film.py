"""Film damping in :mod:`jointplay._kernels.eom` (each joint's ``geom`` column ``G_FILM`` = c_e): −c_e ė on the
journal's centre, +c_e ė on the bearing's, in contact or not, its power c_e |ė|² in W_contact.

Checked against a closed form and differences:

* a free pin (no contact, no gravity) whose body's centre of mass is the journal's centre:
  m v̇ = −c_e v, so v(t) = v₀ exp(−c_e t / m) and x(t) = x₀ + v₀ m / c_e (1 − exp(−c_e t / m)),
  integrated by the engine's Radau IIA with its hooks and closed-form Jacobian;
* the closed-form Jacobian (:func:`eom.jacobian_state`) against central differences of the
  compiled rhs with the film on, in and out of contact, with friction;
* the rhs with the film on minus the rhs with it off is exactly the film's force, its moment
  and its power (the film is added, nothing else changes);
* the film off: every ``G_FILM = 0``, the rhs bit-identical to a model without the column
  set;
* two joints with different films: each joint's own c_e acts on it.
"""

from __future__ import annotations

import math

import numpy as np
import numpy.typing as npt
import pytest

import _generic_hooks as hooks
from _states import perturbed_states
from jointplay._kernels import eom
from jointplay.contact.friction import AmbrosioFriction
from jointplay.contact.laws import get_law
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.integrate import integrate
from jointplay.dynamics.simulate import Start, initial_state
from jointplay.dynamics.system import System, build_system
from jointplay.errors import ConfigError
from jointplay.io.config import load_preset
from jointplay.model.mechanism import Driver, Ground, JointFit, Link, Mechanism, RevoluteJoint

CLEARANCE = 21e-6  # m
MASS = 1.5  # kg
FILM = 100.0  # N·s/m
#: Radau IIA at rtol 1e-10 on an exponential decay: its error is ~rtol; a missing or doubled
#: film term changes v(t) by O(1).
DECAY_RTOL = 1e-7
#: As tests/_kernels/test_eom.py's JACOBIAN_RTOL: central differences (relative step 1e-7)
#: against the closed form, relative to each column's largest entry.
JACOBIAN_RTOL = 1e-3
FOURBAR_JOINTS = ("O2", "A", "B", "O4")


def _spinner() -> Mechanism:
    """One link driven about ground pin O, its centre of mass on the pin: the journal's
    centre is the centre of mass, so the crank's rotation does not move it."""
    return Mechanism(
        name="spinner",
        ground=Ground({"O": (0.0, 0.0)}),
        links=(Link("crank", {"O": (0.0, 0.0), "P": (0.1, 0.0)}, MASS, (0.0, 0.0), 0.02),),
        joints=(RevoluteJoint("O", "ground", "O", "crank", "O", fit=JointFit(diameter=0.01)),),
        driver=Driver("crank", "O", speed=10.0),
        gravity=(0.0, 0.0),
    )


def _joint(film: float, friction: bool = False) -> ClearanceJoint:
    law = get_law("restitution", penalty=1e9, restitution=0.8, exponent=1.0)
    return ClearanceJoint(
        "O", CLEARANCE, 5e-3, law, AmbrosioFriction(mu=0.1) if friction else None,
        film_damping=film,
    )  # fmt: skip


def test_a_free_pin_decays_exponentially_with_the_film() -> None:
    system = build_system(_spinner(), [_joint(FILM)])
    assert system.film_dampings.tolist() == [FILM]
    n = system.n_coordinates
    v0 = (1e-3, -0.5e-3)  # m/s: drifts at most |v0| m / c_e = 17 µm < c, never touches
    y0 = np.zeros(system.n_state)
    y0[n : n + 2] = v0
    y0[n + 2] = 2 * math.pi * 10.0 / 60.0  # the driver's speed (rpm → rad/s)
    y0[2] = 0.0
    tau = MASS / FILM
    t_end = 3 * tau
    args = system.kernel_args()
    hooks.start_workspace(y0, args)
    run = integrate(
        eom.state_rhs, (0.0, t_end), y0, args=args, rtol=1e-10,
        atol=np.concatenate([np.full(2 * n, 1e-14), np.full(system.n_state - 2 * n, 1.0)]),
        step_check=hooks.step_check, after_step=hooks.after_step, n_second=n, n_active=2 * n,
        jac=eom.jacobian_state,
    )  # fmt: skip
    decay = np.exp(-run.t / tau)
    for k in range(2):
        np.testing.assert_allclose(run.y[:, n + k], v0[k] * decay, rtol=0, atol=DECAY_RTOL * 1e-3)
        np.testing.assert_allclose(
            run.y[:, k], v0[k] * tau * (1 - decay), rtol=0, atol=DECAY_RTOL * 1e-3 * tau
        )
    assert np.all(np.hypot(run.y[:, 0], run.y[:, 1]) < CLEARANCE)  # free throughout
    # W_contact: the film's work ∫ c_e |v|² dt = m |v0|² / 2 (1 − exp(−2 t / τ))
    work = MASS * (v0[0] ** 2 + v0[1] ** 2) / 2 * (1 - np.exp(-2 * run.t[-1] / tau))
    assert run.y[-1, 2 * n + 1] == pytest.approx(work, rel=1e-6)


def _states(system: System, seed: int) -> list[npt.NDArray[np.float64]]:
    """States near the nominal assembly, pins off-centre by up to ~3 clearances (as
    tests/_kernels/test_eom.py's), so some joints penetrate and some are free."""
    return perturbed_states(system, seed, position=1.5e-4)


def _fourbar(film: float, friction: bool = True) -> System:
    mechanism = load_preset("paper-fourbar").with_gravity((0.0, -9.81))
    law = get_law("restitution", penalty=1e9, restitution=0.6, exponent=1.0)
    fric = AmbrosioFriction(mu=0.1, v0=1e-4, v1=1e-3) if friction else None
    clearances = [
        ClearanceJoint(j, 1e-4, 5e-3, law, fric, film_damping=film) for j in FOURBAR_JOINTS
    ]
    return build_system(mechanism, clearances)


def _central_differences(system: System, t: float, y: npt.NDArray[np.float64]):
    n = system.n_coordinates
    columns = []
    for j in range(2 * n):
        h = 1e-7 * max(abs(y[j]), 1e-3 if j < n else 1e-1)
        up, down = y.copy(), y.copy()
        up[j] += h
        down[j] -= h
        args = system.kernel_args()
        columns.append((eom.state_rhs(t, up, args) - eom.state_rhs(t, down, args)) / (2 * h))
    return np.array(columns).T


@pytest.mark.parametrize("film", [10.0, 1000.0])
@pytest.mark.parametrize("friction", [False, True])
def test_closed_form_jacobian_with_the_film_equals_differences(film: float, friction: bool) -> None:
    system = _fourbar(film, friction)
    n = system.n_coordinates
    size = system.n_state
    touching = free = 0
    for i, y in enumerate(_states(system, seed=7)):
        t = 1e-3 * i
        contacts = np.zeros((4, 7))
        eom.evaluate(t, y, *eom.pack(system.model), contacts)
        touching += int(np.sum(contacts[:, 2] > 0))
        free += int(np.sum(contacts[:, 2] <= 0))
        jac = np.full((size, size), np.nan)
        assert eom.jacobian_state(
            t, y, eom.state_rhs(t, y, system.kernel_args()), system.kernel_args(), jac
        )
        expected = _central_differences(system, t, y)
        scale = np.maximum(np.max(np.abs(expected), axis=0), 1e-300)
        np.testing.assert_array_less(np.abs(jac[:, : 2 * n] - expected) / scale, JACOBIAN_RTOL)
        np.testing.assert_array_equal(jac[:, 2 * n :], 0.0)
    assert touching and free  # both branches seen


@pytest.mark.parametrize("film", [0.0, 1000.0])
def test_with_ideal_joints_and_the_film_the_jacobian_is_differenced_with_fixed_steps(
    film: float,
) -> None:
    """O2 and O4 ideal, A and B clear: with the film, :func:`eom.jacobian_state` differences
    ẏ itself with fixed steps (√eps·max(|y_j|, 1e-3)), equal to central differences; off, it
    leaves the Jacobian to the integrator (``False``: SciPy's adaptive differences, whose
    steps on a free pin's zero columns grow until they reach the wall; issue 22)."""
    mechanism = load_preset("paper-fourbar").with_gravity((0.0, -9.81))
    law = get_law("restitution", penalty=1e9, restitution=0.6, exponent=1.0)
    fric = AmbrosioFriction(mu=0.1, v0=1e-4, v1=1e-3)
    system = build_system(
        mechanism,
        [ClearanceJoint(j, 1e-4, 5e-3, law, fric, film_damping=film) for j in ("A", "B")],
    )
    assert system.model.active.sum() == 2
    n = system.n_coordinates
    size = system.n_state
    args = system.kernel_args()
    for i, y in enumerate(_states(system, seed=11)):
        t = 1e-3 * i
        jac = np.full((size, size), np.nan)
        done = eom.jacobian_state(t, y, eom.state_rhs(t, y, args), args, jac)
        assert done == (film > 0)
        if not done:
            assert np.isnan(jac).all()  # nothing written
            continue
        expected = _central_differences(system, t, y)
        scale = np.maximum(np.max(np.abs(expected), axis=0), 1e-300)
        np.testing.assert_array_less(np.abs(jac[:, : 2 * n] - expected) / scale, JACOBIAN_RTOL)
        np.testing.assert_array_equal(jac[:, 2 * n :], 0.0)


def test_the_film_adds_exactly_its_force_moment_and_power() -> None:
    on, off = _fourbar(FILM), _fourbar(0.0)
    n = on.n_coordinates
    mass = on.model.mass
    for i, y in enumerate(_states(on, seed=8)):
        t = 1e-3 * i
        difference = eom.state_rhs(t, y, on.kernel_args()) - eom.state_rhs(t, y, off.kernel_args())
        expected = np.zeros(n)
        power = 0.0
        q, qd = y[:n], y[n : 2 * n]
        for c, joint in enumerate(on.clearances):
            j = on.flat.joint_index(joint.joint)
            a, b = on.flat.joint_int[j, 1], on.flat.joint_int[j, 2]
            velocity = np.zeros(2)
            arms = {}
            for body, point, sign in (
                (b, on.flat.joint_f[j, 2:4], 1.0),
                (a, on.flat.joint_f[j, 0:2], -1.0),
            ):
                if body < 0:
                    continue
                phi = q[3 * body + 2]
                r = np.array(
                    [math.cos(phi) * point[0] - math.sin(phi) * point[1],
                     math.sin(phi) * point[0] + math.cos(phi) * point[1]]
                )  # fmt: skip
                arms[body] = r
                w = qd[3 * body + 2]
                velocity += sign * (qd[3 * body : 3 * body + 2] + w * np.array([-r[1], r[0]]))
            force = -FILM * velocity  # on the journal's body b
            for body, sign in ((b, 1.0), (a, -1.0)):
                if body < 0:
                    continue
                r = arms[body]
                expected[3 * body : 3 * body + 2] += sign * force
                expected[3 * body + 2] += sign * (r[0] * force[1] - r[1] * force[0])
            power += FILM * float(velocity @ velocity)
            del c
        crank = int(on.model.driver[0])
        expected[3 * crank + 2] = 0.0  # the driver prescribes the crank's φ̈
        np.testing.assert_allclose(difference[n : 2 * n], expected / mass, rtol=1e-9, atol=1e-9)
        assert difference[2 * n + 1] == pytest.approx(power, rel=1e-9)
        np.testing.assert_array_equal(difference[:n], 0.0)


def test_the_reported_joint_force_includes_the_film() -> None:
    """:func:`eom.batch_quantities` (the batch engine's) reports |F_N n + F_T t + c_e ė|."""
    system = _fourbar(FILM)
    n = system.n_coordinates
    nb = n // 3
    for i, y in enumerate(_states(system, seed=9)):
        t = 1e-3 * i
        out = np.empty(2 * nb + 4 + 1)
        eom.batch_quantities(t, y, *eom.pack(system.model), out, np.empty(4))
        contacts = np.zeros((4, 7))
        eom.evaluate(t, y, *eom.pack(system.model), contacts)
        for c, joint in enumerate(system.clearances):
            j = system.flat.joint_index(joint.joint)
            a, b = system.flat.joint_int[j, 1], system.flat.joint_int[j, 2]
            rates = {}
            for body, point in ((b, system.flat.joint_f[j, 2:4]), (a, system.flat.joint_f[j, 0:2])):
                if body < 0:
                    rates[body] = np.zeros(2)
                    continue
                phi, w = y[3 * body + 2], y[n + 3 * body + 2]
                r = np.array(
                    [math.cos(phi) * point[0] - math.sin(phi) * point[1],
                     math.sin(phi) * point[0] + math.cos(phi) * point[1]]
                )  # fmt: skip
                rates[body] = y[n + 3 * body : n + 3 * body + 2] + w * np.array([-r[1], r[0]])
            e_dot = rates[b] - rates[a]
            ex, ey = contacts[c, 5], contacts[c, 6]
            nx, ny = np.array([ex, ey]) / math.hypot(ex, ey)
            f_n, f_t = contacts[c, 0], contacts[c, 1]
            force = f_n * np.array([nx, ny]) + f_t * np.array([-ny, nx]) + FILM * e_dot
            assert out[2 * nb + j] == pytest.approx(math.hypot(*force), rel=1e-12, abs=1e-12)
            assert out[2 * nb + j] != pytest.approx(math.hypot(f_n, f_t), rel=1e-6)


def test_the_film_off_is_the_model_without_it() -> None:
    system = _fourbar(0.0)
    assert system.film_dampings.tolist() == [0.0] * 4 and not system.lubricated


def test_each_joint_keeps_its_own_film() -> None:
    law = get_law("restitution", penalty=1e9, restitution=0.6, exponent=1.0)
    clearances = [ClearanceJoint("O2", 1e-4, 5e-3, law, film_damping=10.0),
                  ClearanceJoint("A", 1e-4, 5e-3, law, film_damping=20.0)]  # fmt: skip
    system = build_system(load_preset("paper-fourbar"), clearances)
    assert system.film_dampings.tolist() == [10.0, 20.0]  # not one value for every joint
    with pytest.raises(ConfigError, match="film_damping must be"):
        ClearanceJoint("O2", 1e-4, 5e-3, law, film_damping=-1.0)
    with pytest.raises(ConfigError, match="does not combine with the sustained-contact"):
        ClearanceJoint("O2", 1e-4, 5e-3, law, capture_speed=1e-4, film_damping=1.0)


def test_two_joints_with_different_films_each_feel_their_own() -> None:
    """Four joints, each its own c_e (10, 40, 160, 640 N·s/m), pins centred (no contact) and
    moving: the film's power c_e |ė|² is summed joint by joint with each joint's own c_e,
    the force on each journal is −c_e ė (:func:`eom.film_forces`, ė from the record), and
    the rhs changes when one joint's c_e changes alone. (The kernels once took the smallest
    c_e for every joint: this fails there.)"""
    mechanism = load_preset("paper-fourbar").with_gravity((0.0, 0.0))
    law = get_law("restitution", penalty=1e9, restitution=0.6, exponent=1.0)
    films = (10.0, 40.0, 160.0, 640.0)
    system = build_system(
        mechanism,
        [ClearanceJoint(j, 1e-4, 5e-3, law, film_damping=f) for j, f in zip(FOURBAR_JOINTS, films, strict=True)],
    )  # fmt: skip
    n = system.n_coordinates
    y = initial_state(system, Start("steady"))
    rng = np.random.default_rng(39)
    y[n : 2 * n] += rng.normal(scale=1e-3, size=n)  # relative velocities at every joint
    record = np.zeros((4, 7))
    _, _, power, _ = eom.evaluate(0.0, y, *eom.pack(system.model), record)
    assert np.all(record[:, 2] < 0.0)  # out of contact: the film alone
    e_dot_sq = np.empty(4)
    for c in range(4):
        film_n, film_t = eom.film_forces(y[None], *eom.pack(system.model), record[None])[0, c]
        e_n = record[c, 3]
        assert film_n == pytest.approx(films[c] * e_n, rel=1e-14)
        e_dot_sq[c] = (film_n**2 + film_t**2) / films[c] ** 2
    assert np.all(e_dot_sq > 0)
    assert power == pytest.approx(float(np.dot(films, e_dot_sq)), rel=1e-12)
    assert power != pytest.approx(min(films) * float(e_dot_sq.sum()), rel=1e-3)
    heavier = build_system(
        mechanism,
        [ClearanceJoint(j, 1e-4, 5e-3, law, film_damping=2 * f if j == "B" else f)
         for j, f in zip(FOURBAR_JOINTS, films, strict=True)],
    )  # fmt: skip
    assert not np.array_equal(
        eom.state_rhs(0.0, y, heavier.kernel_args()), eom.state_rhs(0.0, y, system.kernel_args())
    )
