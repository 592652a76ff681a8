"""The compiled equations of motion equal the plain NumPy ones of ``dynamics/reference.py``.

The reference (:class:`~jointplay.dynamics.reference.ReferenceModel`) is written from the
model objects: joint points placed with NumPy, forces from the law objects' ``force``
methods, the constrained accelerations from the full augmented (KKT) system. The kernel
(:func:`jointplay._kernels.eom.state_rhs`) uses flat buffers, the compiled laws and the Schur
complement (a scalar when only the driver is left). They agree at random states with
contacts active, for every subset shape (all joints clear, ideal and clear mixed), several
laws, friction on and off, gravity on, and both the four-bar and the slider-crank.

Named tolerances, relative to the largest entry of each block of ẏ (q̇, q̈, work rates):

* ``ALL_CLEAR_RTOL``: only the driver constraint is left; round-off only.
* ``MIXED_RTOL`` (+ a truncation term): the reference differentiates the ideal joints'
  constraints numerically.
* ``JACOBIAN_RTOL``: the closed-form Jacobian against differences of the compiled rhs.
"""

from __future__ import annotations

from collections.abc import Sequence

import numpy as np
import numpy.typing as npt
import pytest

import _generic_hooks as hooks
from jointplay._kernels import eom, ids, shared
from jointplay.contact.friction import AdamsFriction, AmbrosioFriction, FrictionLaw
from jointplay.contact.laws import ContactLaw, get_law
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.reference import DIFFERENCE_STEP, ReferenceModel
from jointplay.dynamics.simulate import Start, initial_state
from jointplay.dynamics.system import System, build_system
from jointplay.io.config import load_preset
from jointplay.model.mechanism import Mechanism

#: All joints clear, four-bar: only the driver constraint is left and both sides evaluate
#: the same closed-form expressions (the reference through a KKT solve): round-off only,
#: measured ≤ 2e-16 relative; 1e-12 leaves room for a few ulp amplified by the solve.
ALL_CLEAR_RTOL = 1e-12
#: Ideal joints left: the reference differentiates their constraints numerically
#: (central differences, step h = ``DIFFERENCE_STEP`` = 1e-5): Φ_q to ~1e-10, and γ from a
#: second difference along q̇ whose round-off is ~eps·L/h² ≈ 2e-7 m/s² on lengths L ~ 0.1 m
#: and whose truncation is ~(h·ω)²/12 relative for link rates ω. Four-bar (ω ≲ 40 rad/s):
#: measured ≤ 8e-8 relative to the largest acceleration. The tolerance is this floor ...
MIXED_RTOL = 1e-6
#: ... plus ``(h·max|ω|)²``, a bound of the truncation term: the slider-crank turns at
#: 5000 rpm (ω = 524 rad/s), where it reaches 2e-6 (measured; it scales as h², as it must).


def _mixed_rtol(system: System, y: npt.NDArray[np.float64]) -> float:
    n = system.n_coordinates
    omega = np.max(np.abs(y[n + 2 : 2 * n : 3]))
    return MIXED_RTOL + (DIFFERENCE_STEP * omega) ** 2


#: Closed-form Jacobian (:func:`eom.jacobian_state`) against central differences of the
#: compiled rhs, relative to each column's largest entry: the differences (relative step
#: 1e-7) carry truncation and round-off errors, and the closed form differences the scalar
#: laws forward with step √eps; measured ≤ 6e-5 (states near the damping STEP's ends);
#: a wrong or missing term shows as O(1).
JACOBIAN_RTOL = 1e-3

N_STATES = 8

FOURBAR_JOINTS = ("O2", "A", "B", "O4")


def _laws() -> dict[str, ContactLaw]:
    """One law per kernel branch: the cubic-STEP damped IMPACT and two Hunt–Crossley types."""
    return {
        # δ ~ 1e-4 m below d_max: the damping STEP ramp is exercised.
        "impact": get_law("impact", stiffness=1e10, exponent=1.5, c_max=1e4, d_max=3e-4),
        "lankarani-nikravesh": get_law("lankarani-nikravesh", stiffness=1e10, restitution=0.8),
        "restitution": get_law("restitution", penalty=1e9, restitution=0.6, exponent=1.0),
    }


def _frictions() -> dict[str, FrictionLaw | None]:
    return {
        "none": None,
        "ambrosio": AmbrosioFriction(mu=0.1, v0=1e-4, v1=1e-3),
        "adams": AdamsFriction(mu_static=0.15, mu_dynamic=0.1, v_static=1e-3, v_dynamic=1e-2),
    }


def _system(
    mechanism: Mechanism, joints: Sequence[str], law: ContactLaw, friction: FrictionLaw | None
) -> System:
    clearances = [ClearanceJoint(j, 1e-4, 5e-3, law, friction) for j in joints]
    return build_system(mechanism, clearances)


def _random_states(system: System, seed: int) -> list[npt.NDArray[np.float64]]:
    """States near the nominal assembly with pins off-centre by up to ~3 clearances.

    Positions are perturbed by ~1e-4 m and angles by ~1e-3 rad, so most clearance joints
    (c = 1e-4 m) penetrate their bearing while some are free; velocities are of the
    mechanism's size (m/s, 10 rad/s), and each impact-velocity slot is either unset (0) or
    a positive entry rate.
    """
    rng = np.random.default_rng(seed)
    y0 = initial_state(system, Start())
    n = system.n_coordinates
    nc = len(system.clearances)
    states = []
    for _ in range(N_STATES):
        y = y0.copy()
        scale = np.tile([1.5e-4, 1.5e-4, 1.5e-3], n // 3)
        y[:n] += scale * rng.standard_normal(n)
        y[n : 2 * n] += np.tile([1.0, 1.0, 10.0], n // 3) * rng.standard_normal(n)
        y[2 * n : 2 * n + 2] = rng.standard_normal(2)
        y[2 * n + 2 :] = np.where(rng.random(nc) < 0.5, 0.0, rng.uniform(0.01, 1.0, nc))
        states.append(y)
    return states


def _assert_rhs_equal(system: System, rtol: float | None, seed: int) -> int:
    """Compare kernel and reference at random states; return how many had a contact.

    ``rtol`` None: the mixed tolerance of each state (:func:`_mixed_rtol`).
    """
    reference = ReferenceModel(system)
    n = system.n_coordinates
    blocks = {"q̇": slice(0, n), "q̈": slice(n, 2 * n), "work rates": slice(2 * n, 2 * n + 2)}
    touching = 0
    for i, y in enumerate(_random_states(system, seed)):
        t = 1e-3 * i
        got = eom.state_rhs(t, y, system.kernel_args())
        expected = reference.rhs(t, y)
        contacts = np.empty((len(system.clearances), 7))
        eom.evaluate(t, y, *eom.pack(system.model), contacts)
        touching += bool(np.any(contacts[:, 2] > 0.0))
        assert got.shape == y.shape
        assert np.all(got[2 * n + 2 :] == 0.0)  # the impact-velocity memory is constant
        tolerance = _mixed_rtol(system, y) if rtol is None else rtol
        for name, block in blocks.items():
            scale = np.max(np.abs(expected[block]))
            np.testing.assert_allclose(
                got[block],
                expected[block],
                rtol=0,
                atol=tolerance * scale,
                err_msg=f"{name}, state {i}",
            )
    return touching


@pytest.fixture(scope="module")
def fourbar_with_gravity() -> Mechanism:
    return load_preset("paper-fourbar").with_gravity((0.0, -9.81))


@pytest.mark.parametrize("law", ["impact", "lankarani-nikravesh", "restitution"])
@pytest.mark.parametrize("friction", ["none", "ambrosio", "adams"])
def test_all_clear_fourbar_equals_reference(
    fourbar_with_gravity: Mechanism, law: str, friction: str
) -> None:
    system = _system(fourbar_with_gravity, FOURBAR_JOINTS, _laws()[law], _frictions()[friction])
    assert _assert_rhs_equal(system, ALL_CLEAR_RTOL, seed=1) >= N_STATES // 2


@pytest.mark.parametrize("joints", [("O2",), ("A",), ("B", "O4"), ("O2", "A", "O4")])
@pytest.mark.parametrize("law", ["impact", "lankarani-nikravesh"])
def test_mixed_fourbar_equals_reference(
    fourbar_with_gravity: Mechanism, joints: tuple[str, ...], law: str
) -> None:
    system = _system(fourbar_with_gravity, joints, _laws()[law], _frictions()["ambrosio"])
    assert _assert_rhs_equal(system, None, seed=2) >= N_STATES // 2


@pytest.mark.parametrize("joints", [("B",), ("A", "B"), ("O2", "A", "B")])
@pytest.mark.parametrize("friction", ["none", "adams"])
def test_slider_crank_equals_reference(
    slider_crank: Mechanism, joints: tuple[str, ...], friction: str
) -> None:
    """The prismatic joint stays ideal, so the constraints are never the driver alone."""
    mechanism = slider_crank.with_gravity((0.0, -9.81))
    system = _system(mechanism, joints, _laws()["restitution"], _frictions()[friction])
    assert _assert_rhs_equal(system, None, seed=3) >= N_STATES // 2


def test_free_pins_give_the_ideal_driver_torque_only(paper_fourbar: Mechanism) -> None:
    """Pins centred: no contact force, so a body's q̈ is gravity alone (off here) and only
    the crank accelerates, with the driver's φ̈ = 0 at constant speed."""
    system = _system(paper_fourbar, FOURBAR_JOINTS, _laws()["impact"], None)
    y = initial_state(system, Start("steady"))
    n = system.n_coordinates
    ydot = eom.state_rhs(0.0, y, system.kernel_args())
    np.testing.assert_array_equal(ydot[:n], y[n : 2 * n])
    np.testing.assert_array_equal(ydot[n : 2 * n], 0.0)
    assert ydot[2 * n] == 0.0 and ydot[2 * n + 1] == 0.0


def _central_differences(
    system: System, t: float, y: npt.NDArray[np.float64]
) -> npt.NDArray[np.float64]:
    """∂ẏ/∂(q, q̇) by central differences of the compiled rhs (relative step 1e-7)."""
    n = system.n_coordinates
    columns = []
    for j in range(2 * n):
        h = 1e-7 * max(abs(y[j]), 1e-3 if j < n else 1e-1)
        up, down = y.copy(), y.copy()
        up[j] += h
        down[j] -= h
        columns.append(
            (
                eom.state_rhs(t, up, system.kernel_args())
                - eom.state_rhs(t, down, system.kernel_args())
            )
            / (2 * h)
        )
    return np.array(columns).T


@pytest.mark.parametrize("law", ["impact", "lankarani-nikravesh", "restitution"])
@pytest.mark.parametrize("friction", ["none", "ambrosio"])
def test_closed_form_jacobian_equals_differences(
    fourbar_with_gravity: Mechanism, law: str, friction: str
) -> None:
    system = _system(fourbar_with_gravity, FOURBAR_JOINTS, _laws()[law], _frictions()[friction])
    n = system.n_coordinates
    size = system.n_state
    for i, y in enumerate(_random_states(system, seed=4)):
        t = 1e-3 * i
        jac = np.full((size, size), np.nan)
        assert eom.jacobian_state(
            t, y, eom.state_rhs(t, y, system.kernel_args()), system.kernel_args(), jac
        )
        expected = _central_differences(system, t, y)
        scale = np.maximum(np.max(np.abs(expected), axis=0), 1e-300)
        np.testing.assert_array_less(np.abs(jac[:, : 2 * n] - expected) / scale, JACOBIAN_RTOL)
        # Work integrals and impact-velocity memory: columns not used by the integrator.
        np.testing.assert_array_equal(jac[:, 2 * n :], 0.0)


def test_closed_form_jacobian_of_a_coasting_mechanism(fourbar_with_gravity: Mechanism) -> None:
    """Driver off: no constraint at all, the crank's row stays, the motor does no work."""
    clearances = [ClearanceJoint(j, 1e-4, 5e-3, _laws()["impact"]) for j in FOURBAR_JOINTS]
    system = build_system(fourbar_with_gravity, clearances, driven=False)
    n = system.n_coordinates
    for y in _random_states(system, seed=6)[:3]:
        jac = np.zeros((system.n_state, system.n_state))
        assert eom.jacobian_state(
            0.0, y, eom.state_rhs(0.0, y, system.kernel_args()), system.kernel_args(), jac
        )
        expected = _central_differences(system, 0.0, y)
        scale = np.maximum(np.max(np.abs(expected), axis=0), 1e-300)
        np.testing.assert_array_less(np.abs(jac[:, : 2 * n] - expected) / scale, JACOBIAN_RTOL)
        np.testing.assert_array_equal(jac[2 * n], 0.0)


def test_closed_form_jacobian_declines_when_ideal_joints_remain(
    fourbar_with_gravity: Mechanism,
) -> None:
    system = _system(fourbar_with_gravity, ("A",), _laws()["impact"], None)
    y = _random_states(system, seed=5)[0]
    jac = np.zeros((system.n_state, system.n_state))
    assert not eom.jacobian_state(
        0.0, y, eom.state_rhs(0.0, y, system.kernel_args()), system.kernel_args(), jac
    )


def test_a_system_is_immutable_and_each_run_has_its_own_workspace(
    fourbar_with_gravity: Mechanism,
) -> None:
    """The kernels' model is read-only; what after_step records goes to a new workspace."""
    system = _system(fourbar_with_gravity, ("A",), _laws()["impact"], None)
    assert all(not array.flags.writeable for array in system.model)
    assert not system.flat.joint_f.flags.writeable and not system.flat.driver.flags.writeable
    first, second = system.kernel_args(), system.kernel_args()
    assert not first[0].flags.writeable and not first[1].flags.writeable
    assert first[2] is not second[2]
    y = _random_states(system, seed=7)[0]  # off the constraints: after_step projects
    assert hooks.after_step(0.0, y, first)
    assert first[2][ids.W_PROJECTIONS] == 1.0 and first[2][ids.W_MAX_VIOLATION] > 0.0
    np.testing.assert_array_equal(second[2], 0.0)
    np.testing.assert_array_equal(system.kernel_args()[2], 0.0)


def test_the_contact_memory_is_the_rate_at_the_instant_of_contact(
    fourbar_with_gravity: Mechanism,
) -> None:
    """A step from δ0 <= 0 to δ1 > 0 stores δ̇ interpolated to δ = 0 (linear in δ), not the
    rate at the step's end, which depends on where the step ended; with no known start, the
    rate at the end."""
    assert eom.impact_rate(-1e-6, 0.3, 3e-6, 0.1) == pytest.approx(0.25)
    assert eom.impact_rate(1e-6, 0.3, 3e-6, 0.1) == 0.1  # in contact already at the start
    system = _system(fourbar_with_gravity, ("A",), _laws()["impact"], None)
    rpar, ipar = eom.pack(system.model)
    lay = eom.lay_of(ipar)
    memory = shared.compiled["contact_memory"]  # the source's, as the single engine runs it
    slot = 2 * system.n_coordinates + 2
    y = np.zeros(system.n_state)
    start, end = np.zeros(7), np.zeros(7)
    start[2:4] = (-1e-6, 0.3)  # (δ, δ̇) in the record layout
    end[2:4] = (3e-6, 0.1)
    assert memory(y, rpar, lay, end, start)
    assert y[slot] == pytest.approx(0.25)
    assert not memory(y, rpar, lay, end, start)  # the event goes on: kept
    y[slot] = 0.0
    assert memory(y, rpar, lay, end, end)  # no known start: after_step passes the end as both
    assert y[slot] == 0.1
    end[2] = -1e-7  # the pin leaves the wall: the event ends
    assert memory(y, rpar, lay, end, start) and y[slot] == 0.0
