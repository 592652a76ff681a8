"""Film damping (:class:`~jointplay.dynamics.setup.ContactModel`'s ``film_damping``) on the
paper's four-bar: the physical default contact, 21 µm in all four joints, steady start.

- the physical default lubricates (each joint's c_e from its geometry and
  :data:`DEFAULT_VISCOSITY`), the paper's methods do not; 0 gives dry joints;
- on, the energy balance still closes (the film's power c_e |ė|² is in W_contact);
- the reported joint force is what the joint transmits, |F_N n + F_T t + c_e ė|, checked
  against ė from the states (``dex_*``, ``dey_*``) and n, t from the eccentricity;
- the batch engine runs it on its implicit lanes, with the same steps as simulate(); the
  explicit lanes and the JAX GPU backend refuse it, the cuda backend runs it (implicit).
- between steps q and q̇ come from the quintic through q and q̇ at three step ends, or next
  to a contact's start or end q̇ is the derivative of q's cubic (a contact onset inside a
  step makes no spurious α peak, on both engines, and the located peaks meet the accuracy
  contract at the default tolerances); off, the Hermite of q̇ with q̈, bit for bit.
"""

from __future__ import annotations

import numpy as np
import pytest

from jointplay.dynamics.batch import (
    BatchSamples,
    _check_implicit_only,
    choose_method,
    simulate_batch,
)
from jointplay.dynamics.clearance import FILM_DAMPING_CAP, ClearanceJoint, JointFilm
from jointplay.dynamics.setup import DEFAULT_IMPACT, DEFAULT_VISCOSITY, ContactModel
from jointplay.dynamics.simulate import (
    SimulationResult,
    SolverOptions,
    Start,
    _interpolate,
    hermite,
    hermite_three_points,
    simulate,
    smooth_steps,
)
from jointplay.dynamics.system import build_system
from jointplay.errors import SettingError
from jointplay.execution.executors import executor
from jointplay.model.mechanism import Mechanism

JOINTS = ("O2", "A", "B", "O4")
CLEARANCE = 21e-6
FILM = 100.0  # N·s/m
#: The energy balance's relative residual over one revolution: measured ~1e-8 with the
#: film off and on (docs/performance.md); a film power left out of W_contact shows as
#: the film's dissipated work, ~1e-2 relative.
ENERGY_RESIDUAL = 1e-6


def _joints(mechanism: Mechanism, **contact: object) -> list[ClearanceJoint]:
    return ContactModel(**contact).joints(mechanism, JOINTS, clearance=CLEARANCE)  # type: ignore[arg-type]


def _run(mechanism: Mechanism, **contact: object) -> SimulationResult:
    return simulate(
        mechanism, _joints(mechanism, **contact), revolutions=1, settle=0, start=Start("steady")
    )


@pytest.fixture(scope="module")
def with_film(paper_fourbar: Mechanism) -> SimulationResult:
    return _run(paper_fourbar, film_damping=f"{FILM} N*s/m")


def test_the_setting_parses_and_is_described() -> None:
    # the physical default lubricates; the paper's methods and the sustained mode stay dry
    default = ContactModel()
    assert default.lubricated and default.fixed_film is None
    assert default.viscosity == DEFAULT_VISCOSITY and default.lubricant_viscosity is None
    assert not ContactModel(law=DEFAULT_IMPACT, method="ifm-conventional").lubricated
    assert not ContactModel(sustained_contact=True).lubricated
    assert ContactModel(film_damping=0).fixed_film == 0.0
    assert not ContactModel(film_damping="0").lubricated
    assert not ContactModel(lubricant_viscosity="0").lubricated
    assert ContactModel(lubricant_viscosity="50 mPa*s").lubricant_viscosity == pytest.approx(0.05)
    assert ContactModel(film_damping="0.1 kN*s/m").fixed_film == pytest.approx(100.0)
    described = ContactModel(film_damping=100).describe()
    assert described["lubrication"]["film_damping_N_s_m"] == 100.0
    assert "film damping 100" in described["text"]
    assert "0.05 Pa*s oil" in default.describe()["text"]
    dry = ContactModel(film_damping=0).describe()
    assert dry["lubrication"]["lubricated"] is False and "dry joints" in dry["text"]
    with pytest.raises(SettingError, match="has no unit"):
        ContactModel(film_damping="5")  # only a zero goes without a unit
    with pytest.raises(SettingError, match="film_damping must be >= 0"):
        ContactModel(film_damping=-1.0)
    with pytest.raises(SettingError, match="lubricant_viscosity must be >= 0"):
        ContactModel(lubricant_viscosity=-1.0)
    with pytest.raises(SettingError, match="sustained_contact runs dry joints"):
        ContactModel(film_damping=1.0, sustained_contact=True)


def test_the_default_film_follows_each_joints_geometry(paper_fourbar: Mechanism) -> None:
    """c_e = π μ R L³ / c³ (the short-bearing squeeze film at ε = 0), capped for the linear
    damper, uncapped as the default π-film's C0: computed by hand for the paper's pins
    (R = 5 mm, L = 10 mm, μ = 0.05 Pa·s), and recomputed with the clearance."""
    joints = ContactModel(film_model="linear").joints(paper_fourbar, JOINTS, clearance=CLEARANCE)
    by_hand = 3.141592653589793 * 0.05 * 0.005 * 0.01**3 / CLEARANCE**3  # 8.48e4 N·s/m
    for joint in joints:
        assert joint.film_from == JointFilm(0.05, 0.01, model="linear")
        assert joint.film_damping == pytest.approx(by_hand, rel=1e-12)
        assert joint.with_clearance(2 * CLEARANCE).film_damping == pytest.approx(by_hand / 8)
        assert joint.with_clearance(1e-6).film_damping == FILM_DAMPING_CAP
    for joint in ContactModel().joints(paper_fourbar, JOINTS, clearance=CLEARANCE):
        assert joint.film_from == JointFilm(0.05, 0.01, model="short-bearing-pi")
        assert joint.film_damping == pytest.approx(by_hand, rel=1e-12)
        tight = 3.141592653589793 * 0.05 * 0.005 * 0.01**3 / 1e-6**3
        assert joint.with_clearance(1e-6).film_damping == pytest.approx(tight, rel=1e-12)
    # each joint its own value (the kernels once took the smallest for every joint)
    mixed = [joints[0].with_clearance(2 * CLEARANCE), *joints[1:]]
    np.testing.assert_allclose(
        build_system(paper_fourbar, mixed).film_dampings, [by_hand / 8] + [by_hand] * 3,
        rtol=1e-12,
    )  # fmt: skip


def test_off_is_the_contact_without_it(paper_fourbar: Mechanism) -> None:
    joints = _joints(paper_fourbar, film_damping=0.0)
    assert all(j.film_damping == 0.0 and j.film_from is None for j in joints)
    assert _joints(paper_fourbar, lubricant_viscosity=0.0) == joints
    assert not build_system(paper_fourbar, joints).lubricated


def test_the_energy_balance_closes_with_the_film(
    paper_fourbar: Mechanism, with_film: SimulationResult
) -> None:
    assert with_film.success
    assert with_film.solver_stats["energy_residual"] < ENERGY_RESIDUAL
    assert all(j.film_damping == FILM for j in _joints(paper_fourbar, film_damping=FILM))


def test_the_joint_force_includes_the_film(with_film: SimulationResult) -> None:
    data = with_film.steps
    for joint in JOINTS:
        ex, ey = data[f"ex_{joint}"].to_numpy(), data[f"ey_{joint}"].to_numpy()
        e = np.hypot(ex, ey)
        centred = e == 0  # the steady start's centred pins: n = (1, 0), as the kernel takes it
        e[centred] = 1.0
        nx, ny = np.where(centred, 1.0, ex / e), np.where(centred, 0.0, ey / e)
        fn, ft = data[f"Fn_{joint}"].to_numpy(), data[f"Ft_{joint}"].to_numpy()
        dex, dey = data[f"dex_{joint}"].to_numpy(), data[f"dey_{joint}"].to_numpy()
        fx = fn * nx - ft * ny + FILM * dex  # the force the journal exerts, t = ẑ × n
        fy = fn * ny + ft * nx + FILM * dey
        np.testing.assert_allclose(data[f"F_{joint}"], np.hypot(fx, fy), rtol=1e-9, atol=1e-9)
        # the film's share is not negligible: the reported force is not the contact's alone
        assert np.max(np.abs(data[f"F_{joint}"] - np.hypot(fn, ft))) > 0.1  # N


def test_the_batch_engine_runs_the_film_on_its_implicit_lanes(paper_fourbar: Mechanism) -> None:
    clearances = np.array([21e-6, 12e-6])
    samples = BatchSamples(clearances=dict.fromkeys(JOINTS, clearances))
    joints = _joints(paper_fourbar, film_damping=FILM)
    result = simulate_batch(paper_fourbar, joints, samples, settle=0)
    assert result.method == "implicit" and "film damping" in result.method_reason
    assert choose_method(paper_fourbar, joints).method == "implicit"
    assert result.ok.all()
    for i, clearance in enumerate(clearances):
        single = simulate(
            paper_fourbar,
            ContactModel(film_damping=FILM).joints(paper_fourbar, JOINTS, clearance=clearance),
            revolutions=1,
            settle=0,
            start=Start("steady"),
        )
        assert result.counters.loc[i, "n_steps"] == single.solver_stats["steps"]
        peak = single.steps["F_B"].abs().max()
        # the batch's peaks are taken where it evaluates (not only at the accepted steps):
        # measured up to 2.2 % (film) and 1.5 % (F_A, no film) from the steps' largest values;
        # that quantities() reports the film is tests/_kernels/test_eom_film.py's check
        assert result.peaks.loc[i, "F_B"] == pytest.approx(peak, rel=5e-2)
    with pytest.raises(SettingError, match="explicit lanes integrate compliant contacts only"):
        simulate_batch(paper_fourbar, joints, samples, method="explicit")
    with pytest.raises(
        SettingError, match=r"gpu backend \(JAX\) integrates compliant contacts only"
    ):
        simulate_batch(paper_fourbar, joints, samples, backend="gpu")  # JAX: no implicit lanes
    with pytest.raises(SettingError, match="explicit lanes integrate compliant contacts only"):
        simulate_batch(paper_fourbar, joints, samples, backend="cuda", method="explicit")
    # the cuda backend's implicit lanes run the film (tests/_kernels/test_lanes_cuda.py):
    # not refused, here only checked not to be (without a GPU the backend says so instead)
    _check_implicit_only(["film_damping"], "auto", executor("cuda"))
    _check_implicit_only(["film_damping"], "implicit", executor("cuda"))
    with pytest.raises(SettingError, match="sustained_contact"):
        _check_implicit_only(["sustained_contact", "film_damping"], "auto", executor("cuda"))


# --- located peaks with a stiff film (docs/performance.md, "Peak location with a film") -----
#: The case that showed the defect: all four joints at 8 µm, c_e = 1e5 N·s/m, settle 2 + 1.
#: With the velocities interpolated as the Hermite of q̇ with q̈, the default tolerances
#: located |α3| = 2 342 rad/s² inside the step where joint A's contact begins (q̈ jumps
#: there) against 412 at rtol 1e-8 (the batch's implicit lanes: 559); with the derivative of
#: q's cubic, measured 412.14 (single) and 412.11 (batch) against 412.11.
STIFF_FILM = 1e5  # N·s/m
SMALL_CLEARANCE = 8e-6  # m
#: Located |α3| at the default tolerances against rtol 1e-8 (measured 7.0e-5 relative with
#: the three-point quintic, 2.2e-3 with the cubic's derivative alone; the spurious peak of
#: the Hermite of q̇ with q̈ was 4.7× the reference).
ONSET_PEAK_RTOL = 1e-3
#: Batch implicit lanes against the single engine, same steps, only the peak search differs
#: (as tests/_kernels/test_batch.py's PEAK_SEARCH_* bounds; measured with this film at 8 and
#: 21 µm: ω 4e-16, the others ≤ 6.3e-5).
PEAK_SEARCH_OMEGA_RTOL = 6e-7
PEAK_SEARCH_OTHER_RTOL = 2e-4
PEAK_KEYS = ("omega3", "omega4", "alpha3", "alpha4", "F_O2", "F_A", "F_B", "F_O4", "torque")


def _stiff_film_run(mechanism: Mechanism, solver: SolverOptions | None = None) -> SimulationResult:
    joints = ContactModel(film_damping=STIFF_FILM).joints(
        mechanism, JOINTS, clearance=SMALL_CLEARANCE
    )
    return simulate(
        mechanism,
        joints,
        revolutions=1,
        settle=2,
        start=Start("steady"),
        **({"solver": solver} if solver else {}),
    )


@pytest.fixture(scope="module")
def stiff_film(paper_fourbar: Mechanism) -> tuple[SimulationResult, SimulationResult]:
    """The default-tolerance run and its rtol 1e-8 reference."""
    return _stiff_film_run(paper_fourbar), _stiff_film_run(paper_fourbar, SolverOptions(rtol=1e-8))


def test_a_contact_onset_makes_no_spurious_peak_with_a_stiff_film(
    stiff_film: tuple[SimulationResult, SimulationResult],
) -> None:
    default, tight = stiff_film
    reference = tight.peaks["alpha3"]["value"]
    assert default.peaks["alpha3"]["value"] == pytest.approx(reference, rel=ONSET_PEAK_RTOL)


def test_nor_on_the_batch_engines_implicit_lanes(
    paper_fourbar: Mechanism, stiff_film: tuple[SimulationResult, SimulationResult]
) -> None:
    default, tight = stiff_film
    reference = tight.peaks["alpha3"]["value"]
    joints = ContactModel(film_damping=STIFF_FILM).joints(
        paper_fourbar, JOINTS, clearance=SMALL_CLEARANCE
    )
    samples = BatchSamples(clearances=dict.fromkeys(JOINTS, np.array([SMALL_CLEARANCE])))
    batch = simulate_batch(
        paper_fourbar, joints, samples, revolutions=1, settle=2, start=Start("steady"),
        method="implicit", backend="local",
    )  # fmt: skip
    assert batch.ok.all()
    assert batch.peaks.loc[0, "alpha3"] == pytest.approx(reference, rel=ONSET_PEAK_RTOL)
    # the same steps, the peak searches agree (the engines interpolate alike)
    assert batch.counters.loc[0, "n_steps"] == default.solver_stats["steps"]
    for key in PEAK_KEYS:
        bound = PEAK_SEARCH_OMEGA_RTOL if key.startswith("omega") else PEAK_SEARCH_OTHER_RTOL
        assert batch.peaks.loc[0, key] == pytest.approx(default.peaks[key]["value"], rel=bound)


def test_with_the_film_the_velocities_are_the_derivative_of_the_positions_interpolant(
    stiff_film: tuple[SimulationResult, SimulationResult],
) -> None:
    """Between accepted steps q̇ is d/dt of q's interpolant (which takes only q and q̇ at
    step ends, never q̈): central differences of the interpolated q match it, and at the
    steps the interpolant gives the steps' q̇."""
    default, _ = stiff_film
    t, y = default.t, default.y
    n = default.system.n_coordinates
    inside = 0.5 * (t[:-1] + t[1:])[::50]
    h = 1e-4 * np.min(np.diff(t))
    states = _interpolate(
        default.system,
        t,
        y,
        default._step_accelerations,
        default._step_touching,
        np.concatenate([inside - h, inside + h, inside]),
    )
    m = inside.size
    differences = (states[m : 2 * m, :n] - states[:m, :n]) / (2 * h)
    scale = np.max(np.abs(y[:, n : 2 * n]), axis=0)  # each coordinate's largest rate
    error = np.abs(differences - states[2 * m :, n : 2 * n]) / scale
    assert np.max(error) < 1e-6, np.max(error)
    at_steps = _interpolate(
        default.system, t, y, default._step_accelerations, default._step_touching, t[1:-1]
    )
    np.testing.assert_allclose(at_steps[:, n : 2 * n], y[1:-1, n : 2 * n], rtol=1e-12, atol=1e-12)


def test_without_the_film_the_velocities_are_the_hermite_of_the_accelerations(
    paper_fourbar: Mechanism,
) -> None:
    """The film off: q̇ between steps is, bit for bit, the cubic Hermite of q̇ with q̈."""
    result = _run(paper_fourbar, film_damping=0.0)
    t, y, qdd = result.t, result.y, result._step_accelerations
    n = result.system.n_coordinates
    samples = np.linspace(t[0], t[-1], 997)
    states = _interpolate(result.system, t, y, qdd, result._step_touching, samples)
    np.testing.assert_array_equal(states[:, n : 2 * n], hermite(t, y[:, n : 2 * n], qdd, samples))


#: Issue 22: the paper four-bar with some joints ideal, lubricated by default (c_e 8.5e4
#: N·s/m at 21 µm), one revolution from the steady start. Measured (2 shared cores): with
#: the Jacobian left to the integrator's adaptive differences, A,B 8 102 steps and 11 147
#: Newton failures, B 3 984 and 4 784; with eom's fixed-step differences 451 and 56, 425
#: and 37; dry 2 843 and 1 570 steps. Peaks against rtol 1e-8: within 1.1e-6 (A,B) and
#: 3.3e-7 (B) with the three-point quintic between steps; 7.4e-4 and 1.2e-3 with the
#: cubic's derivative alone (docs/performance.md, "Peak location with a film").
IDEAL_BESIDE = {("A", "B"): (900, 150), ("B",): (900, 150)}
PEAKS_AGAINST_TIGHT = 2e-5


def _beside_ideal(
    mechanism: Mechanism,
    names: tuple[str, ...],
    solver: SolverOptions | None = None,
    **contact: object,
) -> SimulationResult:
    joints = ContactModel(**contact).joints(mechanism, list(names), clearance=CLEARANCE)  # type: ignore[arg-type]
    return simulate(
        mechanism, joints, revolutions=1, settle=0, start=Start("steady"), solver=solver
    )


@pytest.mark.parametrize("names", list(IDEAL_BESIDE))
def test_lubricated_pins_beside_ideal_joints_cost_no_more_than_dry_ones(
    paper_fourbar: Mechanism, names: tuple[str, ...]
) -> None:
    """The linear film's stiff columns are differenced with fixed steps
    (eom.jacobian_state), so Newton converges: steps and Newton failures bounded, fewer steps
    than dry, and the peaks those of a run at 100x tighter tolerances."""
    lubricated = _beside_ideal(paper_fourbar, names, film_model="linear")
    assert np.all(lubricated.system.film_dampings > 8e4)
    assert lubricated.system.model.active.sum() == 4 - len(names)
    stats = lubricated.solver_stats
    most_steps, most_newton = IDEAL_BESIDE[names]
    assert stats["steps"] < most_steps and stats["rejected_by_newton"] < most_newton, stats
    dry = _beside_ideal(paper_fourbar, names, film_damping=0)
    assert stats["steps"] < dry.solver_stats["steps"]
    tight = _beside_ideal(paper_fourbar, names, SolverOptions().tightened(100), film_model="linear")
    for key, peak in tight.peaks.items():
        assert lubricated.peaks[key]["value"] == pytest.approx(
            peak["value"], rel=PEAKS_AGAINST_TIGHT
        ), key


def test_reynolds_pins_beside_ideal_joints_settle_to_the_tight_peaks(
    paper_fourbar: Mechanism,
) -> None:
    """The default π-film at B beside ideal joints, settled (2 revolutions): the peaks those
    of a run at 100x tighter tolerances. (Unsettled, from the steady start, the default
    tolerances miss the pin's first excursion: α4 +1.3 % at settle 0, measured.)"""

    def run(solver: SolverOptions | None) -> SimulationResult:
        joints = ContactModel().joints(paper_fourbar, ["B"], clearance=CLEARANCE)
        return simulate(
            paper_fourbar, joints, revolutions=1, settle=2, start=Start("steady"), solver=solver
        )

    lubricated, tight = run(None), run(SolverOptions().tightened(100))
    assert lubricated.system.clearances[0].film_model == "short-bearing-pi"
    for key, peak in tight.peaks.items():
        assert lubricated.peaks[key]["value"] == pytest.approx(
            peak["value"], rel=PEAKS_AGAINST_TIGHT
        ), key


def test_the_summary_gives_each_joints_film(paper_fourbar: Mechanism) -> None:
    joints = ContactModel().joints(paper_fourbar, JOINTS, clearance=CLEARANCE)
    joints[0] = joints[0].with_clearance(2 * CLEARANCE)  # a looser O2: a weaker film
    result = simulate(paper_fourbar, joints, revolutions=0.05, settle=0, start=Start("steady"))
    summary = result.summary()
    films = {j: summary["clearance_joints"][j]["film_damping_N_s_m"] for j in JOINTS}
    assert films == {j.joint: j.film_damping for j in joints}
    assert films["O2"] == pytest.approx(films["A"] / 8)
    assert "film_damping_applied_N_s_m" not in summary  # each joint's own film is applied


def test_the_three_point_quintic_is_fifth_order() -> None:
    """On q = sin(ωt) with steps h, the interpolated rates' largest error falls as h⁵ (the
    derivative of a one-step cubic: h³; measured orders 5.56 and 5.30), and the quintic
    reproduces q and q̇ at the steps."""
    errors = []
    for h in (0.1, 0.05, 0.025):
        t = np.arange(0.0, 2.0 + h / 2, h)
        t = t + 0.3 * h * np.sin(7 * t)  # uneven steps
        q, v = np.sin(3 * t)[:, None], 3 * np.cos(3 * t)[:, None]
        index = np.arange(1, t.size - 1)
        inside = t[index] + 0.37 * np.diff(t)[index]
        value, rate = hermite_three_points(t, q, v, inside, index)
        errors.append(np.max(np.abs(rate[:, 0] - 3 * np.cos(3 * inside))))
        assert np.max(np.abs(value[:, 0] - np.sin(3 * inside))) < errors[-1]
        at_ends, rate_at_ends = hermite_three_points(t, q, v, t[index + 1], index)
        np.testing.assert_allclose(at_ends, q[index + 1], atol=1e-12)
        np.testing.assert_allclose(rate_at_ends, v[index + 1], atol=1e-9)
    orders = np.log2(np.array(errors[:-1]) / np.array(errors[1:]))
    assert np.all(orders > 4.5), orders


def test_the_steps_next_to_a_contacts_start_or_end_keep_the_cubic() -> None:
    touching = np.array([[0, 1], [0, 1], [0, 1], [1, 1], [1, 1], [1, 1], [1, 0], [1, 0]], bool)
    # step 0 has no step end before it; 2 and 3 touch A's start, 5 and 6 B's end
    expected = [False, True, False, False, True, False, False]
    assert smooth_steps(touching).tolist() == expected


#: The issue's accuracy contract (forces 1e-3, ω 1e-5 of a converged solution), and the
#: bound here: the default run's located peaks of the lubricated default, settle 2 + 1,
#: against rtol 1e-10 with 1/8° steps. Measured with the three-point quintic ≤ 8e-7
#: (6 µm, 21 µm); with the cubic's derivative alone 2.5e-3 (α3), 1.3e-3 (F_O4) and 1.2e-3
#: (F_B), which this bound fails.
DEFAULT_PEAKS_RTOL = 2e-5


@pytest.mark.parametrize("clearance", [6e-6, 21e-6])
def test_the_lubricated_defaults_located_peaks_meet_the_accuracy_contract(
    paper_fourbar: Mechanism, clearance: float
) -> None:
    joints = ContactModel().joints(paper_fourbar, JOINTS, clearance=clearance)
    degree = 1 / (paper_fourbar.driver.speed * 180 / np.pi)

    def run(solver: SolverOptions) -> SimulationResult:
        return simulate(
            paper_fourbar, joints, revolutions=1, settle=2, start=Start("steady"), solver=solver
        )

    default = run(SolverOptions())
    reference = run(
        SolverOptions(rtol=1e-10, atol_position=1e-14, atol_velocity=1e-10, max_step=degree / 8)
    )
    for key in PEAK_KEYS:
        assert default.peaks[key]["value"] == pytest.approx(
            reference.peaks[key]["value"], rel=DEFAULT_PEAKS_RTOL
        ), key
