"""The short-bearing Reynolds films of :mod:`jointplay._kernels.lanes.source` (``reynolds_force``,
a joint's ``geom`` column ``G_FILM_MODEL``; docs/contact.md, "Reynolds films"), checked
against what does not share their closed forms:

* a numerical solution of the short-bearing Reynolds equation: the pressure
  p(θ, z) = (6μ/h³)(z² − L²/4)(|e| ω_eff sin θ − ė_r cos θ), h = c(1 − ε cos θ), integrated
  over the length (Gauss–Legendre, exact for the parabola) and the angle (``scipy.integrate.quad``)
  on the journal, over the whole film (the full film) or where p > 0 (the π-film: Gümbel's
  half film, p clipped at 0), against the force the compiled right-hand side applies, over a
  grid of ε (0 … 0.98), ε̇ and the wedge speed ω_j + ω_b − 2γ̇;
* frame indifference: a mechanism turning rigidly (ω_j = ω_b = γ̇, ė = Ω ẑ × e) feels no film
  force (the linear damper does);
* the full film's squeeze coefficient grows as (1 + 2ε²)(1 − ε²)^(−5/2) (×166 at ε = 0.9),
  the π-film's pure squeeze is half of it;
* the closed-form Jacobian against central differences of the whole right-hand side;
* the energy balance of a simulation with the film (its power −F·ė in W_contact, the wedge's
  not dissipative);
* each joint its own clearance and coefficient;
* the engines that do not run it refuse it.
"""

from __future__ import annotations

import dataclasses
import math
from collections.abc import Callable

import numpy as np
import numpy.typing as npt
import pytest
from scipy.integrate import quad
from scipy.special import roots_legendre

from _states import perturbed_states
from jointplay._kernels import eom, ids
from jointplay._kernels.capabilities import refusal
from jointplay._kernels.ids import FILM_EPS_CAP
from jointplay._kernels.lanes import source
from jointplay._kernels.lanes.build import lane_layout, lanes_refusal
from jointplay.contact.friction import AmbrosioFriction
from jointplay.contact.laws import get_law
from jointplay.dynamics.batch import simulate_batch
from jointplay.dynamics.batch_inputs import BatchSamples, build_batch
from jointplay.dynamics.clearance import ClearanceJoint, JointFilm
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import SolverOptions, Start, initial_state, simulate
from jointplay.dynamics.system import System, build_system
from jointplay.errors import ConfigError, SettingError
from jointplay.io.config import load_preset
from jointplay.model.mechanism import Driver, Ground, JointFit, Link, Mechanism, RevoluteJoint

VISCOSITY = 0.05  # Pa·s
LENGTH = 0.01  # m
RADIUS = 5e-3  # m
CLEARANCE = 21e-6  # m
MASS = 1.5  # kg
FORMS = ("short-bearing-pi", "short-bearing-full")
EPSILONS = (0.0, 0.3, 0.6, 0.9, 0.98)
EPS_RATES = (-50.0, -5.0, 0.0, 5.0, 50.0)  # ε̇, 1/s
WEDGE_SPEEDS = (-200.0, 0.0, 20.0, 200.0)  # ω_j + ω_b − 2γ̇, rad/s
#: The issue's done-when: the film force within 1e-3 of the numerical Reynolds solution.
REYNOLDS_RTOL = 1e-3
JACOBIAN_RTOL = 1e-3
FOURBAR_JOINTS = ("O2", "A", "B", "O4")


def _spinner() -> Mechanism:
    """One link driven about ground pin O, its centre of mass on the pin: the journal's centre
    is the body's position, e = (x, y), ė = (ẋ, ẏ), ω_j = φ̇, ω_b = 0 (the ground)."""
    return Mechanism(
        name="spinner",
        ground=Ground({"O": (0.0, 0.0)}),
        links=(Link("crank", {"O": (0.0, 0.0), "P": (0.1, 0.0)}, MASS, (0.0, 0.0), 0.02),),
        joints=(RevoluteJoint("O", "ground", "O", "crank", "O", fit=JointFit(diameter=0.01)),),
        driver=Driver("crank", "O", speed=10.0),
        gravity=(0.0, 0.0),
    )


def _law():
    return get_law("restitution", penalty=1e9, restitution=0.8, exponent=1.0)


def _spinner_system(form: str) -> System:
    film = JointFilm(VISCOSITY, LENGTH, model=form)
    # smooth surfaces (σ = 0): the film alone up to the wall, without the asperities' share
    # (tests/_kernels/test_mixed_lubrication.py)
    joint = ClearanceJoint("O", CLEARANCE, RADIUS, _law(), film_from=film, roughness=0.0)
    return build_system(_spinner(), [joint])


def _reynolds_force(
    form: str, eps: float, eps_rate: float, wedge_speed: float, gamma: float
) -> npt.NDArray[np.float64]:
    """The force on the journal (N, global frame) of the short-bearing film integrated
    numerically: e at angle γ, θ measured from e, ė_r = ε̇ c, |e| ω_eff = ε c Ω / 2."""
    e_r = eps_rate * CLEARANCE
    wedge = 0.5 * eps * CLEARANCE * wedge_speed
    nodes, weights = roots_legendre(4)
    z = 0.5 * LENGTH * nodes
    shape = float(np.sum(0.5 * LENGTH * weights * (z**2 - LENGTH**2 / 4)))  # ∫ (z² − L²/4) dz

    def pressure(theta: float) -> float:  # ∫ p dz
        h = CLEARANCE * (1.0 - eps * math.cos(theta))
        p = 6.0 * VISCOSITY / h**3 * shape * (wedge * math.sin(theta) - e_r * math.cos(theta))
        return p if form == "short-bearing-full" else max(p, 0.0)

    # break points: where the pressure changes sign (θ = atan2(ė_r, wedge) + kπ) and θ = 0
    turn = math.atan2(e_r, wedge) % math.pi
    points = sorted({0.0, turn, turn + math.pi} - {2 * math.pi})
    size = quad(lambda th: abs(pressure(th)), 0.0, 2 * math.pi, points=points, limit=400)[0]

    def integral(g: Callable[[float], float]) -> float:
        return quad(
            lambda th: pressure(th) * g(th), 0.0, 2 * math.pi, points=points, limit=400,
            epsabs=1e-13 * size, epsrel=1e-11,
        )[0]  # fmt: skip

    radial, tangential = -RADIUS * integral(math.cos), -RADIUS * integral(math.sin)
    n = np.array([math.cos(gamma), math.sin(gamma)])
    t = np.array([-n[1], n[0]])
    return radial * n + tangential * t


def _spinner_state(
    system: System, eps: float, eps_rate: float, wedge_speed: float, gamma: float
) -> npt.NDArray[np.float64]:
    """e = ε c (cos γ, sin γ), ė = ε̇ c n + |e| γ̇ t with γ̇ = 3 rad/s, ω_j = Ω + 2γ̇."""
    gamma_rate = 3.0
    n = np.array([math.cos(gamma), math.sin(gamma)])
    t = np.array([-n[1], n[0]])
    y = np.zeros(system.n_state)
    y[0:2] = eps * CLEARANCE * n
    y[3:5] = eps_rate * CLEARANCE * n + eps * CLEARANCE * gamma_rate * t
    y[5] = wedge_speed + 2.0 * gamma_rate
    return y


@pytest.mark.parametrize("form", FORMS)
def test_the_film_force_is_the_numerical_reynolds_solution(form: str) -> None:
    """Over ε ∈ {0, 0.3, 0.6, 0.9, 0.98} × ε̇ × Ω, the force the right-hand side applies to
    the journal (m ẍ: no gravity, no contact) and the one the outputs report
    (``eom.film_forces``) equal the numerical integral of the pressure to 1e-3 (measured:
    < 1e-9)."""
    system = _spinner_system(form)
    assert system.model.geom[ids.G_FILM_MODEL] == (1.0 if form == "short-bearing-pi" else 2.0)
    args = system.kernel_args()
    rpar, ipar = eom.pack(system.model)
    worst = 0.0
    for k, (eps, eps_rate, speed) in enumerate(
        (e, r, w) for e in EPSILONS for r in EPS_RATES for w in WEDGE_SPEEDS
    ):
        gamma = 0.7 + 0.9 * k  # the frame turned at every point
        y = _spinner_state(system, eps, eps_rate, speed, gamma)
        expected = _reynolds_force(form, eps, eps_rate, speed, gamma)
        force = MASS * eom.state_rhs(0.0, y, args)[3:5]
        record = np.zeros((1, 7))
        eom.evaluate(0.0, y, rpar, ipar, record)
        assert record[0, 2] < 0.0  # the pin floats: the film alone
        film_n, film_t = eom.film_forces(y[None], rpar, ipar, record[None])[0, 0]
        n = np.array([math.cos(gamma), math.sin(gamma)]) if eps > 0 else np.array([1.0, 0.0])
        reported = -(film_n * n + film_t * np.array([-n[1], n[0]]))
        scale = float(np.hypot(*expected))
        if scale == 0.0:
            assert np.hypot(*force) < 1e-9 and np.hypot(*reported) < 1e-9  # N: round-off
            continue
        error = max(np.hypot(*(force - expected)), np.hypot(*(reported - expected))) / scale
        assert error < REYNOLDS_RTOL, (eps, eps_rate, speed, force, expected)
        worst = max(worst, error)
    assert worst < 1e-9  # what it measures (the closed forms are exact)


#: The π-film matrix against its integrals by quadrature: the closed form loses digits to
#: cancellation only as ε nears the cap (measured 4e-11 at ε = 0.995).
MATRIX_RTOL = 1e-9


@pytest.mark.parametrize("eps", [0.0, 0.5, 0.98, FILM_EPS_CAP])
def test_the_pi_film_matrix_is_its_half_films_integrals_up_to_the_cap(eps: float) -> None:
    """``reynolds_matrix`` (evaluated without forming the half film's angles: one arctangent,
    two square roots) equals (−I_cc, I_sc, −I_sc, I_ss), the integrals of cos²θ, sin θ cos θ
    and sin²θ over (1 − ε cos θ)³ across the half θ ∈ (θ₁, θ₁ + π), θ₁ = −atan2(wedge, ė_r)
    − π/2, by quadrature, up to the film's eccentricity cap, for squeeze and wedge of either
    sign, their ratio large and small, and the pin at rest (±0: the half atan2 gives)."""
    cases = [
        (1.0, 0.0), (-1.0, 0.0), (0.0, 1.0), (0.0, -1.0), (0.3, -2.0), (-5.0, 0.01),
        (1e-3, -1e-3), (-0.7, -0.7), (0.0, 0.0), (-0.0, 0.0),
    ]  # fmt: skip
    for rate, wedge in cases:
        theta_1 = -math.atan2(wedge, rate) - 0.5 * math.pi
        points = [0.0] if theta_1 < 0.0 < theta_1 + math.pi else None

        def integral(g: Callable[[float], float], theta_1: float = theta_1, points=points) -> float:
            return quad(
                lambda th: g(th) / (1.0 - eps * math.cos(th)) ** 3, theta_1, theta_1 + math.pi,
                points=points, limit=400, epsabs=1e-13 / (1.0 - eps) ** 3, epsrel=1e-12,
            )[0]  # fmt: skip

        i_cc = integral(lambda th: math.cos(th) ** 2)
        i_ss = integral(lambda th: math.sin(th) ** 2)
        i_sc = integral(lambda th: math.sin(th) * math.cos(th))
        expected = np.array([-i_cc, i_sc, -i_sc, i_ss])
        got = np.array(source.reynolds_matrix(ids.FILM_SHORT_PI, eps, rate, wedge))
        scale = float(np.max(np.abs(expected)))
        assert np.max(np.abs(got - expected)) <= MATRIX_RTOL * scale, (eps, rate, wedge, got)


def test_the_pi_film_differs_from_the_fixed_half_film_under_squeeze() -> None:
    """Gümbel's half film follows the pressure's sign: with squeeze and wedge together its
    positive half is not the fixed (π, 2π) of the rotating-journal formulas (the closed forms
    of Flores et al.'s lubricated joints, docs/contact.md), which it equals without
    squeeze. The numerical reference tells the two apart."""
    eps, speed, gamma = 0.6, 200.0, 0.0
    system = _spinner_system("short-bearing-pi")
    args = system.kernel_args()
    k_scale = VISCOSITY * RADIUS * LENGTH**3 / CLEARANCE**2
    omega = 0.5 * speed
    for eps_rate in (0.0, 50.0):
        y = _spinner_state(system, eps, eps_rate, speed, gamma)
        force = MASS * eom.state_rhs(0.0, y, args)[3:5]
        s = 1 - eps**2
        fixed = k_scale * np.array(
            [-(2 * eps**2 * omega / s**2 + math.pi * (1 + 2 * eps**2) * eps_rate / (2 * s**2.5)),
             math.pi * eps * omega / (2 * s**1.5) + 2 * eps * eps_rate / s**2]
        )  # fmt: skip
        close = np.hypot(*(force - fixed)) < 1e-9 * np.hypot(*fixed)
        assert close == (eps_rate == 0.0)


@pytest.mark.parametrize("form", FORMS)
def test_a_rigidly_turning_joint_feels_no_film(form: str) -> None:
    """The paper four-bar turning as one rigid body about the origin (every body's ω = Ω,
    v = Ω ẑ × r): at the moving joints A and B ω_j = ω_b = γ̇ and ė = Ω ẑ × e, so the film's
    force is zero (to round-off); the linear damper's is c_e Ω |e|."""
    mechanism = load_preset("paper-fourbar").with_gravity((0.0, 0.0))

    def system_of(model: str) -> System:
        joints = [
            ClearanceJoint(j, 1e-4, 5e-3, _law(), film_damping=1e4, film_model=model)
            for j in FOURBAR_JOINTS
        ]
        return build_system(mechanism, joints)

    forces = {}
    for model in (form, "linear"):
        system = system_of(model)
        n = system.n_coordinates
        y = initial_state(system, Start("steady"))
        omega = 25.0
        for body in range(n // 3):  # the pins off-centre (|e| < 0.5 c), every body turning
            y[3 * body : 3 * body + 2] += 2e-5 * np.array([0.6 + 0.3 * body, 0.8 - 0.5 * body])
            x, yy = y[3 * body : 3 * body + 2]
            y[n + 3 * body : n + 3 * body + 3] = [-omega * yy, omega * x, omega]
        rpar, ipar = eom.pack(system.model)
        record = np.zeros((4, 7))
        eom.evaluate(0.0, y, rpar, ipar, record)
        eccentric = np.hypot(record[:, 5], record[:, 6])
        assert np.all((eccentric > 1e-6) & (eccentric < 1e-4))
        films = eom.film_forces(y[None], rpar, ipar, record[None])[0]
        forces[model] = {
            joint.joint: float(np.hypot(*films[c])) for c, joint in enumerate(system.clearances)
        }
    for joint in ("A", "B"):  # between two moving bodies (O2, O4: the bearing is the ground)
        drag = forces["linear"][joint]
        assert drag > 1.0  # N: the damper drags a rigidly turning joint
        assert forces[form][joint] < 1e-9 * drag


def test_the_full_film_squeeze_grows_as_its_coefficient() -> None:
    """Pure squeeze (Ω = 0), the pin approaching the wall: F_r = −C0 (1 + 2ε²)(1 − ε²)^(−5/2)
    ė_r for the full film (×166 at ε = 0.9 against ε = 0; the linear damper's is flat). The
    π-film keeps the positive half, the thin side |θ| < π/2: half of the full film at ε = 0,
    more than half off-centre (the thin side carries more), no tangential force (symmetric
    about the line of centres)."""
    c0 = math.pi * VISCOSITY * RADIUS * LENGTH**3 / CLEARANCE**3
    eps_rate = 5.0
    gamma = 1.1
    n = np.array([math.cos(gamma), math.sin(gamma)])
    t = np.array([-n[1], n[0]])
    radial = {}
    for form in FORMS:
        system = _spinner_system(form)
        args = system.kernel_args()
        for eps in EPSILONS:
            y = _spinner_state(system, eps, eps_rate, 0.0, gamma)
            force = MASS * eom.state_rhs(0.0, y, args)[3:5]
            radial[form, eps] = float(force @ n)
            assert abs(force @ t) < 1e-9 * abs(force @ n)
    for eps in EPSILONS:
        growth = (1 + 2 * eps**2) * (1 - eps**2) ** -2.5
        full = radial["short-bearing-full", eps]
        assert full == pytest.approx(-c0 * growth * eps_rate * CLEARANCE, rel=1e-9)
        share = radial["short-bearing-pi", eps] / full
        assert share == pytest.approx(0.5, rel=1e-12) if eps == 0 else 0.5 < share < 1.0
    assert radial["short-bearing-full", 0.9] / radial["short-bearing-full", 0.0] == (
        pytest.approx(166.5, abs=0.1)
    )


def _states(system: System, seed: int) -> list[npt.NDArray[np.float64]]:
    """States near the nominal assembly, pins off-centre by up to ~1.5 clearances (some in
    contact, most in the film), rates up to ~1 m/s and 10 rad/s."""
    return perturbed_states(system, seed, position=5e-5)


def _central_differences(system: System, t: float, y: npt.NDArray[np.float64]):
    """Central differences of ẏ, step 1e-7 max(|y_j|, 0.1) in the positions (≥ 1e-8 m or
    rad: 1e-4 c) and 1e-5 max(|y_j|, 0.1) in the rates (larger than test_eom_film.py's:
    near the wall the film's closed forms lose ~5 digits to cancellation, which smaller
    steps turn into a 1e-3 error of the reference itself; the force is linear in the
    rates, so a large step costs nothing there)."""
    n = system.n_coordinates
    columns = []
    args = system.kernel_args()
    for j in range(2 * n):
        h = (1e-7 if j < n else 1e-5) * max(abs(y[j]), 1e-1)
        up, down = y.copy(), y.copy()
        up[j] += h
        down[j] -= h
        columns.append((eom.state_rhs(t, up, args) - eom.state_rhs(t, down, args)) / (2 * h))
    return np.array(columns).T


@pytest.mark.parametrize("form", FORMS)
def test_closed_form_jacobian_with_the_reynolds_film_equals_differences(form: str) -> None:
    """:func:`eom.jacobian_state` (``jacobian_clear`` with ``reynolds_jacobian``: the film
    force's forward differences in e, ė, ω_a, ω_b chained to the bodies' coordinates) against
    central differences of the whole right-hand side, in and out of contact, with friction."""
    mechanism = load_preset("paper-fourbar").with_gravity((0.0, -9.81))
    fric = AmbrosioFriction(mu=0.1, v0=1e-4, v1=1e-3)
    law = get_law("restitution", penalty=1e9, restitution=0.6, exponent=1.0)
    system = build_system(
        mechanism,
        [ClearanceJoint(j, 1e-4, 5e-3, law, fric, film_damping=300.0, film_model=form)
         for j in FOURBAR_JOINTS],
    )  # fmt: skip
    n = system.n_coordinates
    size = system.n_state
    touching = free = 0
    for i, y in enumerate(_states(system, seed=17)):
        t = 1e-3 * i
        contacts = np.zeros((4, 7))
        eom.evaluate(t, y, *eom.pack(system.model), contacts)
        touching += int(np.sum(contacts[:, 2] > 0))
        free += int(np.sum(contacts[:, 2] <= 0))
        jac = np.full((size, size), np.nan)
        args = system.kernel_args()
        assert eom.jacobian_state(t, y, eom.state_rhs(t, y, args), args, jac)
        expected = _central_differences(system, t, y)
        scale = np.maximum(np.max(np.abs(expected), axis=0), 1e-300)
        np.testing.assert_array_less(np.abs(jac[:, : 2 * n] - expected) / scale, JACOBIAN_RTOL)
        # the film's own part is there: the linear damper's Jacobian differs
        linear = build_system(
            mechanism,
            [dataclasses.replace(c, film_model="linear") for c in system.clearances],
        )
        other = np.full((size, size), np.nan)
        eom.jacobian_state(
            t, y, eom.state_rhs(t, y, linear.kernel_args()), linear.kernel_args(), other
        )
        assert np.max(np.abs(other[:, : 2 * n] - expected) / scale) > 10 * JACOBIAN_RTOL
    assert touching and free


@pytest.mark.parametrize("form", FORMS)
def test_the_energy_balance_closes_with_the_reynolds_film(form: str) -> None:
    """Half a revolution of the paper four-bar at 100 µm, lubricated with the film: the
    energy balance KE + V − W_motor + W_contact stays constant (the film's power −F·ė in
    W_contact; its wedge part is not a dissipation: W_contact's rate changes sign)."""
    mechanism = load_preset("paper-fourbar")
    contact = ContactModel(film_model=form)
    joints = [j.with_clearance(1e-4) for j in contact.joints(mechanism)]
    assert {j.film_model for j in joints} == {form}
    result = simulate(
        mechanism, joints, revolutions=0.5, settle=0, start=Start("steady"),
        solver=SolverOptions(rtol=1e-8),
    )  # fmt: skip
    assert result.solver_stats["energy_residual"] < 1e-5
    n = result.system.n_coordinates
    w_contact = result.y[:, 2 * n + 1]
    assert np.ptp(w_contact) > 0.0


def test_two_joints_with_different_clearances_feel_their_own_film() -> None:
    """O2 at 21 µm and A at 85 µm, the same π-film oil: each joint's coefficient is its own
    C0 = π μ R L³ / c³ (×69 apart) and its ε its own |e| / c; the film forces each joint
    reports equal the numerical Reynolds solution of its own geometry."""
    mechanism = load_preset("paper-fourbar").with_gravity((0.0, 0.0))
    contact = ContactModel(film_model="short-bearing-pi")
    joints = {j.joint: j for j in contact.joints(mechanism)}
    system = build_system(
        mechanism, [joints["O2"].with_clearance(21e-6), joints["A"].with_clearance(85e-6)]
    )
    films = system.film_dampings
    width = mechanism.bearing_width("O2") or 0.01
    for c, clearance in enumerate((21e-6, 85e-6)):
        assert films[c] == pytest.approx(
            math.pi * 0.05 * system.clearances[c].journal_radius * width**3 / clearance**3,
            rel=1e-12,
        )
    assert films[0] / films[1] == pytest.approx((85 / 21) ** 3)
    n = system.n_coordinates
    y = initial_state(system, Start("steady"))
    rng = np.random.default_rng(3)
    y[n : 2 * n] += rng.normal(scale=1e-3, size=n)
    rpar, ipar = eom.pack(system.model)
    record = np.zeros((2, 7))
    eom.evaluate(0.0, y, rpar, ipar, record)
    forces = eom.film_forces(y[None], rpar, ipar, record[None])[0]
    assert np.hypot(*forces[0]) > 10 * np.hypot(*forces[1])  # the tight joint's film is stiffer
    other = build_system(
        mechanism, [joints["O2"].with_clearance(21e-6), joints["A"].with_clearance(21e-6)]
    )
    rpar2, ipar2 = eom.pack(other.model)
    eom.evaluate(0.0, y, rpar2, ipar2, record)
    changed = eom.film_forces(y[None], rpar2, ipar2, record[None])[0]
    assert np.array_equal(changed[0], forces[0]) and not np.allclose(changed[1], forces[1])


def test_the_film_model_is_declared_and_checked() -> None:
    """The setting reaches each joint; a Reynolds film takes its coefficient from the geometry
    (uncapped), not a fixed film damping; unknown forms are refused; the default is the
    π-film, and a fixed film damping the linear damper's."""
    mechanism = load_preset("paper-fourbar")
    assert {j.film_model for j in ContactModel().joints(mechanism)} == {"short-bearing-pi"}
    fixed = ContactModel(film_damping="1e4 N*s/m").joints(mechanism)
    assert {(j.film_model, j.film_damping) for j in fixed} == {("linear", 1e4)}
    linear = ContactModel(film_model="linear").joints(mechanism, clearance=5e-6)[0]
    full = ContactModel(film_model="short-bearing-full").joints(mechanism, clearance=5e-6)[0]
    assert linear.film_damping == 1e6  # capped
    width = mechanism.bearing_width(full.joint) or 0.01
    assert full.film_damping == pytest.approx(
        math.pi * 0.05 * full.journal_radius * width**3 / 5e-6**3, rel=1e-12
    )
    assert full.film_damping > 1e6  # uncapped
    with pytest.raises(SettingError, match="film_model"):
        ContactModel(film_model="long-bearing")
    with pytest.raises(SettingError, match="film_damping"):
        ContactModel(film_model="short-bearing-pi", film_damping="1e4 N*s/m")
    assert ContactModel(film_model="short-bearing-pi", film_damping=0.0).lubricated is False
    with pytest.raises((SettingError, ConfigError)):
        ClearanceJoint("O2", 1e-4, 5e-3, _law(), film_model="reynolds")
    described = ContactModel(film_model="short-bearing-pi").describe()
    assert described["lubrication"]["film_model"] == "short-bearing-pi"
    assert ContactModel().describe()["lubrication"]["film_model"] == "short-bearing-pi"
    assert "film_model" not in ContactModel(film_model="linear").describe()["lubrication"]


def test_engines_without_the_reynolds_film_refuse_it() -> None:
    """The JAX backend and the explicit lanes refuse a Reynolds film by name (they would run
    the linear damper's equations, or none); the implicit engines (the cuda backend's lanes
    too) run it."""
    assert refusal("jax", ["film_damping", "film_model"]) is not None
    assert "Reynolds film" in str(refusal("jax", ["film_model"]))
    for engine in ("single", "batch-implicit", "lanes-implicit"):
        assert refusal(engine, ["film_damping", "film_model"]) is None
    system = _spinner_system("short-bearing-pi")
    rpar, ipar = eom.pack(system.model)
    message = lanes_refusal(ipar, rpar, "explicit")
    assert message is not None and "Reynolds film" in message
    assert lanes_refusal(ipar, rpar, "implicit") is None
    linear = build_system(
        _spinner(), [ClearanceJoint("O", CLEARANCE, RADIUS, _law(), film_damping=1e3)]
    )
    message = lanes_refusal(*eom.pack(linear.model)[::-1], "explicit")
    assert message is not None and "Reynolds film" not in message


@pytest.mark.parametrize("vectorised", [True, False])
def test_the_batch_inputs_carry_each_joints_film_model(vectorised: bool) -> None:
    """The batch engine's packed samples (both builders) hold each joint's film form and its
    uncapped C0 at each sample's own clearance (a linear film would be capped at 1e6)."""
    mechanism = load_preset("paper-fourbar")
    joints = ContactModel(film_model="short-bearing-full").joints(mechanism)
    clearances = np.array([4e-6, 21e-6, 60e-6])
    samples = BatchSamples(clearances={j: clearances for j in FOURBAR_JOINTS})
    problem = build_batch(mechanism, joints, samples, vectorised=vectorised)
    lay = lane_layout(problem.ipar)
    start, nc = int(lay[source.LY_GEOM]), int(lay[source.LY_NC])
    geom = problem.rpar[:, start : start + ids.N_GEOM * nc].reshape(3, nc, ids.N_GEOM)
    assert np.all(geom[..., ids.G_FILM_MODEL] == ids.FILM_SHORT_FULL)
    for c, joint in enumerate(joints):
        width = mechanism.bearing_width(joint.joint) or 0.01
        expected = math.pi * 0.05 * joint.journal_radius * width**3 / clearances**3
        np.testing.assert_allclose(geom[:, c, ids.G_FILM], expected, rtol=1e-12)
    assert geom[0, 0, ids.G_FILM] > 1e6


def test_the_batch_engine_runs_the_reynolds_film_as_the_single_engine() -> None:
    """The CPU backends' implicit lanes (the batch engine) and the single engine give the
    same settled joint-force peaks with the full film at 130 µm (where the linear damper's
    are 190–250 N, the film's 32–72 N)."""
    mechanism = load_preset("paper-fourbar")
    joints = [
        j.with_clearance(130e-6)
        for j in ContactModel(film_model="short-bearing-full").joints(mechanism)
    ]
    single = simulate(mechanism, joints, revolutions=1, settle=2, start=Start("steady"))
    samples = BatchSamples(clearances={j.joint: np.array([130e-6]) for j in joints})
    batch = simulate_batch(mechanism, joints, samples, backend="local", revolutions=1, settle=2)
    assert batch.method == "implicit"
    for joint in FOURBAR_JOINTS:
        peak = single.peaks[f"F_{joint}"]["value"]
        assert batch.peaks[f"F_{joint}"].iloc[0] == pytest.approx(peak, rel=1e-4)
        assert peak < 80.0


def test_a_study_takes_the_reynolds_film_where_its_engine_has_it() -> None:
    """The dynamic responses of a study run a Reynolds film on the cuda backend's implicit
    lanes (the same source as the CPU's, checked on the simulator in test_lanes_cuda.py) and
    refuse it on the gpu backend (JAX) before any lane starts, naming it."""
    from jointplay.execution.backends import Backend
    from jointplay.tolerance.response_dynamic import DynamicResponses, contact_parts

    mechanism = load_preset("paper-fourbar")
    reynolds = contact_parts(mechanism, ContactModel(film_model="short-bearing-pi"))
    where = {"journal_radius": {"O2": 5e-3}, "method": "implicit"}
    DynamicResponses(mechanism, ("clearance_O2",), backend=Backend("cuda"), **where, **reynolds)
    with pytest.raises(SettingError, match="Reynolds film"):
        DynamicResponses(mechanism, ("clearance_O2",), backend=Backend("gpu"), **where, **reynolds)
