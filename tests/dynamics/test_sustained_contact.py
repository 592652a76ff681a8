"""The sustained-contact mode (:class:`~jointplay.dynamics.setup.ContactModel`'s
``sustained_contact``) on the paper's four-bar: the physical default contact, 21 µm in all
four joints, from the steady start.

Measured (docs/performance.md, "Sustained-contact mode (issue 22)"): in the first
revolution the peaks of ω3, ω4 and of the four contact forces agree with the compliant
model's within 0.4 % (the force peaks are the start's impacts, before any capture);
the energy balance closes to ~1e-8 relative as with the mode off; releases land within
:data:`~jointplay._kernels.eom.RELEASE_TOL` of F_N = 0.
"""

from __future__ import annotations

import numpy as np
import pytest

from jointplay._kernels import eom, ids
from jointplay.dynamics.batch import BatchSamples, choose_method, simulate_batch
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.setup import DEFAULT_CAPTURE_SPEED, ContactModel
from jointplay.dynamics.simulate import SimulationResult, Start, simulate
from jointplay.dynamics.system import build_system
from jointplay.errors import SettingError
from jointplay.io.config import load_preset
from jointplay.model.mechanism import Mechanism

JOINTS = ("O2", "A", "B", "O4")
CLEARANCE = 21e-6
#: First revolution from the steady start, mode on against off: measured 0.36 % on the
#: peak |ω3|, 0 on |ω4| and on the force peaks (the start's impacts come first). The
#: constraint neglects the ~6e-8 m Hertz approach of the pressed pins (0.3 % of the
#: clearance); 1 % leaves room for that and for the integration error.
AGREEMENT_RTOL = 0.01
#: The energy balance's relative residual: measured 1.2e-8 (off: 1.1e-8) in one revolution.
ENERGY_RESIDUAL = 1e-6
#: The largest drift of the locked joints' |e| = c over a step: measured 2e-11 m (the
#: compliant pins penetrate ~6e-8 m, which a capture removes and does not count).
VIOLATION = 1e-9


def _joints(mechanism: Mechanism, **mode: object) -> list[ClearanceJoint]:
    return ContactModel(**mode).joints(mechanism, JOINTS, clearance=CLEARANCE)  # type: ignore[arg-type]


def _run(mechanism: Mechanism, settle: int = 0, **mode: object) -> SimulationResult:
    return simulate(
        mechanism, _joints(mechanism, **mode), revolutions=1, settle=settle, start=Start("steady")
    )


@pytest.fixture(scope="module")
def compliant(paper_fourbar: Mechanism) -> SimulationResult:
    """The compliant model the mode replaces: the physical contact with dry joints."""
    return _run(paper_fourbar, film_damping=0.0)


@pytest.fixture(scope="module")
def sustained(paper_fourbar: Mechanism) -> SimulationResult:
    return _run(paper_fourbar, sustained_contact=True)


def _memory(result: SimulationResult) -> np.ndarray:
    n = result.system.n_coordinates
    return np.asarray(result.y[:, 2 * n + 2 :])


def test_the_mode_on_without_a_capture_gives_the_same_bits(
    paper_fourbar: Mechanism, compliant: SimulationResult
) -> None:
    """The mode's checks change nothing until a joint is captured: a capture speed no pin
    ever falls below gives the mode-off run bit for bit."""
    never = _run(paper_fourbar, sustained_contact=True, capture_speed=1e-300)
    assert never.system.model.geom[ids.G_CAPTURE :: ids.N_GEOM].tolist() == [1e-300] * 4
    assert not np.any(_memory(never) < 0)
    np.testing.assert_array_equal(never.t, compliant.t)
    np.testing.assert_array_equal(never.y, compliant.y)
    assert "sustained_contact" not in compliant.solver_stats
    assert never.solver_stats["sustained_contact"]["captures"] == dict.fromkeys(JOINTS, 0)


def test_the_first_revolution_agrees_with_the_compliant_model(
    compliant: SimulationResult, sustained: SimulationResult
) -> None:
    assert sustained.success and compliant.success
    assert np.any(_memory(sustained) < 0)  # the mode engaged
    for name in ("omega3", "omega4", *(f"F_{j}" for j in JOINTS)):
        assert sustained.peaks[name]["value"] == pytest.approx(
            compliant.peaks[name]["value"], rel=AGREEMENT_RTOL
        ), name


def test_the_energy_balance_closes_with_the_mode_on(sustained: SimulationResult) -> None:
    assert sustained.solver_stats["energy_residual"] < ENERGY_RESIDUAL
    # the drift projected away after each step (a capture's penetration is not drift)
    assert sustained.solver_stats["max_constraint_violation"] < VIOLATION


def test_joints_are_captured_and_released_at_a_vanishing_normal_force(
    paper_fourbar: Mechanism,
) -> None:
    result = _run(paper_fourbar, settle=2, sustained_contact=True)
    assert result.success
    memory = _memory(result)
    locked = memory < 0
    captures = locked[1:] & ~locked[:-1]
    releases = ~locked[1:] & locked[:-1]
    assert captures.sum() >= 4 and releases.sum() >= 2  # measured: 9 and 7
    stats = result.solver_stats["sustained_contact"]
    assert [stats["captures"][j] for j in JOINTS] == list(captures.sum(axis=0))
    assert [stats["releases"][j] for j in JOINTS] == list(releases.sum(axis=0))
    assert all(0.9 < stats["locked_share"][j] <= 1.0 for j in JOINTS)  # measured 0.96-0.99
    n = result.system.n_coordinates
    model = result.system.model
    for i, c in zip(*np.nonzero(releases), strict=True):
        # F_N as the kernel saw it at the released step's end (still locked there)
        end = np.array(result.y[i + 1])
        end[2 * n + 2 + c] = eom.LOCKED
        start = np.array(result.y[i])
        forces = np.zeros((2, len(JOINTS), 7))
        eom.evaluate(result.t[i + 1], end, *eom.pack(model), forces[1])
        eom.evaluate(result.t[i], start, *eom.pack(model), forces[0])
        f_start, f_end = forces[0, c, 0], forces[1, c, 0]
        assert f_start > 0.0
        assert -eom.RELEASE_TOL * max(f_start, 1.0) <= f_end < 0.0
    # a locked joint's record: F_N the multiplier, F_T = μ F_N, δ = 0 to the projection
    where = np.nonzero(locked.all(axis=1))[0][-1]
    contacts = np.zeros((len(JOINTS), 7))
    eom.evaluate(result.t[where], np.array(result.y[where]), *eom.pack(model), contacts)
    assert np.all(contacts[:, 0] > 0.0)
    np.testing.assert_allclose(np.abs(contacts[:, 1]), 0.1 * contacts[:, 0], rtol=1e-12)
    assert np.max(np.abs(contacts[:, 2])) <= model.settings[ids.S_PROJ_TOL]


def test_the_contact_model_carries_the_mode_to_the_kernels(paper_fourbar: Mechanism) -> None:
    off = ContactModel()
    assert off.capture == 0.0 and "sustained" not in off.describe()["text"]
    on = ContactModel(sustained_contact=True, capture_speed="0.2 mm/s")
    assert on.capture == pytest.approx(2e-4)
    assert on.describe()["capture_speed_m_s"] == pytest.approx(2e-4)
    assert ContactModel(sustained_contact=True).capture == DEFAULT_CAPTURE_SPEED
    joints = on.joints(paper_fourbar, JOINTS, clearance=CLEARANCE)
    assert [j.capture_speed for j in joints] == [on.capture] * len(JOINTS)
    system = build_system(paper_fourbar, joints)
    np.testing.assert_allclose(system.model.geom[ids.G_CAPTURE :: ids.N_GEOM], 2e-4, rtol=1e-15)


@pytest.mark.parametrize("speed", [0.0, -1e-4, "fast", "1 mm"])
def test_a_bad_capture_speed_is_refused(speed: object) -> None:
    with pytest.raises(SettingError, match="capture_speed"):
        ContactModel(sustained_contact=True, capture_speed=speed)  # type: ignore[arg-type]


def test_each_joint_has_its_own_capture_speed(paper_fourbar: Mechanism) -> None:
    """The mode is a property of each joint: O2 with the mode off (capture speed 0) beside
    three joints with it on is never locked, while they are (the kernels once took one
    capture speed for every joint and refused a mixture)."""
    joints = _joints(paper_fourbar, sustained_contact=True)
    joints[0] = ClearanceJoint(
        joints[0].joint, joints[0].clearance, joints[0].journal_radius, joints[0].law,
        joints[0].friction,
    )  # fmt: skip
    assert joints[0].capture_speed == 0.0 and joints[1].capture_speed > 0.0
    result = simulate(paper_fourbar, joints, revolutions=1, settle=0, start=Start("steady"))
    assert result.success
    locked = _memory(result) < 0
    assert not locked[:, 0].any()
    assert locked[:, 1:].any(axis=0).all()
    assert result.solver_stats["sustained_contact"]["captures"]["O2"] == 0
    # the kernels' gate of the mode: the largest of the joints' capture speeds
    assert result.system.model.settings[ids.S_CAPTURE_MAX] == joints[1].capture_speed


def test_the_batch_engine_runs_the_mode_on_its_implicit_lanes(paper_fourbar: Mechanism) -> None:
    """The implicit lanes run the single engine's integration and hooks: the same steps as
    simulate() per sample; the explicit lanes and the GPU backends refuse the mode."""
    clearances = np.array([21e-6, 15e-6])
    samples = BatchSamples(clearances=dict.fromkeys(JOINTS, clearances))
    joints = _joints(paper_fourbar, sustained_contact=True)
    result = simulate_batch(paper_fourbar, joints, samples, settle=0)
    assert result.method == "implicit" and "sustained-contact" in result.method_reason
    assert choose_method(paper_fourbar, joints).method == "implicit"
    assert result.ok.all()
    for i, clearance in enumerate(clearances):
        single = simulate(
            paper_fourbar,
            ContactModel(sustained_contact=True).joints(paper_fourbar, JOINTS, clearance=clearance),
            revolutions=1,
            settle=0,
            start=Start("steady"),
        )
        assert result.counters.loc[i, "n_steps"] == single.solver_stats["steps"]
    with pytest.raises(SettingError, match="explicit lanes integrate compliant contacts only"):
        simulate_batch(paper_fourbar, joints, samples, method="explicit")
    for backend in ("gpu", "cuda"):
        with pytest.raises(SettingError, match=r"integrates? compliant contacts only \(no sustain"):
            simulate_batch(paper_fourbar, joints, samples, backend=backend)


@pytest.mark.parametrize(
    ("preset", "joints", "start", "settle", "capture"),
    [
        # ideal and prismatic joints beside it; at the default 0.1 mm/s this pin is never slow
        # at both ends of a step in this revolution (0 captures, measured with numba 0.68 /
        # llvmlite 0.50), at 1 mm/s it is locked 30 % of the time
        ("flores-slider-crank", ("B",), "rest", 0, "1 mm/s"),
        ("general-fourbar", ("B",), "steady", 1, None),  # ideal joints, Newton-Raphson
    ],
)
def test_the_mode_runs_beside_ideal_joints(
    preset: str, joints: tuple[str, ...], start: str, settle: int, capture: str | None
) -> None:
    """Locked joints solved together with ideal joints: the run succeeds, the mode engages,
    the energy balance closes and the drift stays small (measured: energy 1.4e-8 and 1e-8,
    drift 1e-11 m and 3e-10 m, locked 30 % and 99 % of the time)."""
    mechanism = load_preset(preset)
    clearance = {"general-fourbar": CLEARANCE}.get(preset)
    model = ContactModel(
        sustained_contact=True, **({} if capture is None else {"capture_speed": capture})
    )
    result = simulate(
        mechanism,
        model.joints(mechanism, joints, clearance=clearance),
        revolutions=1,
        settle=settle,
        start=Start(start),
    )
    assert result.success
    stats = result.solver_stats
    assert stats["sustained_contact"]["captures"][joints[0]] >= 1
    assert stats["energy_residual"] < ENERGY_RESIDUAL
    assert stats["max_constraint_violation"] < VIOLATION
