"""The implicit lane on the single source (:mod:`jointplay._kernels.lanes.source_radau`),
compiled for the CPU (:mod:`jointplay._kernels.lanes.cpu`: what ``run_batch(method=
"implicit")`` runs), against the single engine: the Radau kernel of
the generic loop's (:func:`jointplay._kernels.driver.run_core`) with :mod:`eom`'s right-hand
side, Jacobian and hooks and the batch engine's settings, recording every step
(:func:`_single_engine`).

Both run the lane source's Radau IIA steps in the one loop, the lane on the source's
equations, the generic loop on :mod:`eom`'s (the same arithmetic), so the two take the same steps: equal statuses,
counters (steps, rejections, evaluations of f) and times reached, bit for bit. What the lane
reduces as it goes is checked against the recorded steps: for a window opening at an
accepted step, the mean and RMS of ω (trapezoids over the steps) and the deepest
penetrations to ``SAME_ALGORITHM_RTOL`` (``tests/_tolerances.py``: the same sums, in
another order); the peaks at least the largest |value| at the recorded step ends in the
window (the peak rule refines between steps, where an impact's force may peak far above
both ends: how close the refined peaks come to the continuous solution's is
``tests/_kernels/test_batch.py``'s, against :func:`~jointplay.dynamics.simulate.simulate`'s
converged peaks). Cases: the paper four-bar with the conventional contact (``DEFAULT_IMPACT``) and
with the stiff physical default (``ContactModel(film_damping=0)``: dry joints), 0.3 of a
revolution, a lane from t = 0 and a perturbed one whose window opens inside a step; every
contact and friction law; mechanisms with ideal joints (the Jacobian then differenced as
SciPy's ``num_jac``, the projection :func:`projection.project_lapack`'s); film damping; the
sustained-contact mode (the CPU's hooks, :mod:`jointplay._kernels.sustained`).
"""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

import _generic_hooks as hooks
from _tolerances import SAME_ALGORITHM_RTOL
from jointplay._kernels import batch as kb
from jointplay._kernels import driver, eom, ids
from jointplay._kernels.lanes import build, cpu, source, source_radau
from jointplay.contact.friction import AdamsFriction, AmbrosioFriction, FrictionLaw
from jointplay.contact.laws import CONTACT_LAWS, ContactLaw, get_law
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.setup import DEFAULT_IMPACT, ContactModel
from jointplay.dynamics.simulate import Start, initial_state
from jointplay.dynamics.system import build_system
from jointplay.model.mechanism import Mechanism

# The GPU's implicit lane checked on the CPU: its compilation here serves only these tests and
# the CUDA simulator's (~60 CPU-s on a cold cache): the slow tier, which CI runs
pytestmark = pytest.mark.slow

JOINTS = ("O2", "A", "B", "O4")
FIELDS = ("peaks", "stats", "status", "t_reached", "n_steps", "n_rejected", "n_rhs")
#: Parameters of the laws that need more than a stiffness and a restitution (as
#: tests/_kernels/test_lanes.py gives them).
LAW_PARAMETERS: dict[str, dict[str, float]] = {
    "impact": {"stiffness": 1e10, "exponent": 1.5, "c_max": 1e4, "d_max": 3e-4},
    "hertz": {"stiffness": 1e10, "exponent": 1.5},
    "kelvin-voigt": {"stiffness": 1e7, "damping": 1e3},
    "restitution": {"penalty": 1e9, "restitution": 0.6, "exponent": 1.0},
}
FRICTIONS: tuple[FrictionLaw | None, ...] = (
    None,
    AmbrosioFriction(mu=0.1, v0=1e-4, v1=1e-3),
    AdamsFriction(mu_static=0.15, mu_dynamic=0.1, v_static=1e-3, v_dynamic=1e-2),
)


def _joint_slots(ipar: np.ndarray, column: int) -> np.ndarray:
    """Where column ``column`` (``ids.G_*``) of each clearance joint's ``geom`` row sits in a
    lane's ``rpar``."""
    lay = build.lane_layout(ipar)
    nc = int(lay[source.LY_NC])
    return int(lay[source.LY_GEOM]) + ids.N_GEOM * np.arange(nc) + column


def _law(name: str) -> ContactLaw:
    return get_law(name, **LAW_PARAMETERS.get(name, {"stiffness": 1e10, "restitution": 0.8}))


def _problem(
    mechanism: Mechanism, contact: str, revolutions: float = 0.3, film: float | None = None
) -> dict[str, Any]:
    """Three lanes: the steady start from t = 0, a perturbed start whose window opens at 0.1
    of a revolution (inside a step), and a lane with a NaN state (fails at once); ``film``:
    the physical contact's film damping (N·s/m; default: 0, dry joints, the stiff case)."""
    if contact == "impact":
        joints = [ClearanceJoint(j, 11.75e-6, 0.005, DEFAULT_IMPACT) for j in JOINTS]
    elif film is None:
        joints = ContactModel(film_damping=0).joints(mechanism)
    else:
        joints = ContactModel(film_damping=film).joints(mechanism)
    system = build_system(mechanism, joints)
    rpar, ipar = eom.pack(system.model)
    y0 = initial_state(system, Start("steady"))
    n = system.n_coordinates
    atol = np.concatenate([np.full(n, 1e-10), np.full(n, 1e-6), np.full(2, 1e-6), np.ones(4)])
    period = mechanism.driver.period
    ys = np.tile(y0, (3, 1))
    ys[1, n : 2 * n] *= 1.01
    ys[2, 0] = np.nan
    settle = np.array([0.0, 0.1 * period, 0.0])
    return {
        "ipar": ipar, "rpar": np.tile(rpar, (3, 1)), "y0": ys, "t_settle": settle,
        "t_end": settle + revolutions * period, "max_step": np.full(3, period / 360.0),
        "rtol": 1e-6, "atol": atol, "max_steps": 200_000,
    }  # fmt: skip


def _two_lanes(
    mechanism: Mechanism, joints: list[ClearanceJoint], opens: float = 0.1, end: float | None = None
) -> dict[str, Any]:
    """Two lanes of ``mechanism`` with ``joints``: the steady start analysed from t = 0, and a
    perturbed one (velocities 1 % up) whose window opens at ``opens`` of a revolution (inside
    a step); 0.3 of a revolution analysed, or both lanes to ``end`` of a revolution."""
    system = build_system(mechanism, joints)
    rpar, ipar = eom.pack(system.model)
    y0 = initial_state(system, Start("steady"))
    n = system.n_coordinates
    period = mechanism.driver.period
    ys = np.tile(y0, (2, 1))
    ys[1, n : 2 * n] *= 1.01
    settle = np.array([0.0, opens * period])
    t_end = settle + 0.3 * period if end is None else np.full(2, end * period)
    return {
        "ipar": ipar, "rpar": np.tile(rpar, (2, 1)), "y0": ys, "t_settle": settle,
        "t_end": t_end, "max_step": np.full(2, period / 360.0), "rtol": 1e-6,
        "atol": np.concatenate(
            [np.full(n, 1e-10), np.full(n, 1e-6), np.full(2, 1e-6), np.ones(len(joints))]
        ),
        "max_steps": 200_000,
    }  # fmt: skip


def _single_engine(p: dict[str, Any], **kw: Any) -> dict[str, Any]:
    """Each lane through the generic loop (:func:`driver.run_core`'s Radau IIA with :mod:`eom`'s
    hooks, the batch engine's settings): its status, time reached and counters, and from its
    recorded steps in the window the largest |Q| at the step ends (``ends``:
    ``eom.batch_quantities``), the window's statistics when it opens at a recorded step, and
    whether a joint was ever locked (the sustained-contact mode)."""
    args = {**p, **kw}
    ipar = _read_only(args["ipar"])
    n = int(ipar[ids.MODEL_FIELDS.index("mass")])
    nc = int(ipar[ids.MODEL_FIELDS.index("clear_joint")])
    nb, nj, _, _ = kb.layout(ipar)
    interrupt = args.get("interrupt")
    lanes = args["y0"].shape[0]
    out: dict[str, Any] = {
        "status": np.zeros(lanes, dtype=np.int64), "t_reached": np.zeros(lanes),
        "n_steps": np.zeros(lanes, dtype=np.int64), "n_rejected": np.zeros(lanes, dtype=np.int64),
        "n_rhs": np.zeros(lanes, dtype=np.int64), "ends": np.full((lanes, 2 * nb + nj + 1), np.nan),
        "stats": np.full((lanes, 2 * nb + nc), np.nan), "locked": np.zeros(lanes, dtype=bool),
    }  # fmt: skip
    for lane in range(lanes):
        rpar = _read_only(args["rpar"][lane])
        y0 = np.array(args["y0"][lane])
        if interrupt is not None and interrupt[0]:
            out["status"][lane] = ids.STATUS_INTERRUPTED
            continue
        work = eom.new_workspace(nc)
        hooks.start_workspace(y0, (rpar, ipar, work))
        code, ts, ys, counters = driver.run_core(
            "radau", eom.state_rhs, hooks.step_check, hooks.after_step, 0.0, y0, float(args["t_end"][lane]),
            (rpar, ipar, work), args["rtol"], args["atol"], float(args["max_step"][lane]), 0.0,
            args["max_steps"], n_second=n, n_active=2 * n, hold_after_failure=True,
            jac=eom.jacobian_state, interrupt=interrupt,
        )  # fmt: skip
        out["status"][lane] = code
        out["t_reached"][lane] = ts[-1]
        out["n_steps"][lane] = counters[3]
        out["n_rejected"][lane] = counters[4] + counters[5] + counters[6]
        out["n_rhs"][lane] = counters[0]
        out["locked"][lane] = bool((ys[:, 2 * n + 2 :] < 0.0).any())
        if code != ids.STATUS_SUCCESS:
            continue
        settle = float(args["t_settle"][lane])
        window = np.flatnonzero(ts >= settle)
        q = np.empty((window.size, 2 * nb + nj + 1))
        pen = np.empty((window.size, nc))
        for row, i in enumerate(window):
            eom.batch_quantities(ts[i], np.array(ys[i]), rpar, ipar, q[row], pen[row])
        out["ends"][lane] = np.abs(q).max(axis=0)
        if ts[window[0]] == settle:  # the window opens at a recorded step
            h = np.diff(ts[window])
            w = q[:, :nb]
            span = ts[-1] - settle
            out["stats"][lane, :nb] = np.sum(0.5 * h[:, None] * (w[:-1] + w[1:]), axis=0) / span
            out["stats"][lane, nb : 2 * nb] = np.sqrt(
                np.sum(0.5 * h[:, None] * (w[:-1] ** 2 + w[1:] ** 2), axis=0) / span
            )
            out["stats"][lane, 2 * nb :] = pen.max(axis=0)
    return out


def _read_only(array: np.ndarray) -> np.ndarray:
    array = np.array(array)
    array.flags.writeable = False
    return array


def _single_source(p: dict[str, Any], parallel: bool = False, **kw: Any) -> dict[str, Any]:
    args = {**p, **kw}
    lanes, n_q = args["y0"].shape[0], kb.layout(args["ipar"])
    nb, nj, nc, _ = n_q
    out = {
        "peaks": np.full((lanes, 2 * nb + nj + 1), np.nan),
        "stats": np.full((lanes, 2 * nb + 4 * nc), np.nan),
        "status": np.full(lanes, ids.STATUS_RUNNING, dtype=np.int64),
        "t_reached": np.zeros(lanes),
        "counts": np.zeros((lanes, 3), dtype=np.int64),
    }
    interrupt = args.get("interrupt")
    kernel = cpu.implicit_lanes_parallel if parallel else cpu.implicit_lanes
    kernel(
        args["ipar"], args["rpar"], build.lane_layout(args["ipar"]), args["y0"],
        args["t_settle"], args["t_end"], args["max_step"], args["rtol"], args["atol"],
        args["max_steps"], np.zeros(1, dtype=np.uint8) if interrupt is None else interrupt,
        out["peaks"], out["stats"], out["status"], out["t_reached"], out["counts"],
    )  # fmt: skip
    failed = out["status"] != ids.STATUS_SUCCESS  # the contract: as run_batch does
    out["peaks"][failed] = np.nan
    out["stats"][failed] = np.nan
    counts = out.pop("counts")
    out.update(n_steps=counts[:, 0], n_rejected=counts[:, 1], n_rhs=counts[:, 2])
    return out


def _assert_same(new: dict[str, Any], old: dict[str, Any]) -> None:
    """The lane (``new``) took the single engine's (``old``) steps; its reductions agree with
    the recorded steps (module docstring)."""
    for name in ("status", "n_steps", "n_rejected", "n_rhs", "t_reached"):
        np.testing.assert_array_equal(new[name], old[name], err_msg=name)
    done = old["status"] == ids.STATUS_SUCCESS
    ends = old["ends"][done]
    peaks = new["peaks"][done]
    assert (peaks >= ends * (1.0 - 1e-13)).all(), "a peak below a step end's value"
    opened = ~np.isnan(old["stats"][:, 0])
    width = old["stats"].shape[1]
    np.testing.assert_allclose(
        new["stats"][opened, :width], old["stats"][opened], rtol=SAME_ALGORITHM_RTOL, atol=1e-15
    )


def test_the_cpu_implicit_lane_is_the_sources_compilation() -> None:
    assert cpu.implicit_lane.py_func.__code__ is source.lane.__code__
    assert cpu.implicit_lane.py_func.__globals__["step_attempt"].py_func.__code__ is (
        source_radau.radau_attempt.__code__
    )


@pytest.mark.parametrize("contact", ["impact", "physical"])
def test_the_implicit_lane_takes_the_single_engines_steps(
    paper_fourbar: Mechanism, contact: str
) -> None:
    p = _problem(paper_fourbar, contact)
    old = _single_engine(p)
    new = _single_source(p)
    assert list(old["status"]) == [
        ids.STATUS_SUCCESS, ids.STATUS_SUCCESS, ids.STATUS_NON_FINITE,
    ]  # fmt: skip
    assert (old["n_steps"][:2] > 500).all() and (old["n_rejected"][:2] > 50).all()
    _assert_same(new, old)
    assert np.isnan(new["peaks"][2]).all() and np.isnan(new["stats"][2]).all()


def test_the_implicit_lanes_on_threads_are_the_serial_ones(paper_fourbar: Mechanism) -> None:
    p = _problem(paper_fourbar, "physical", revolutions=0.05)
    one = _single_source(p)
    threads = _single_source(p, parallel=True)
    for name in FIELDS:
        np.testing.assert_array_equal(threads[name], one[name], err_msg=name)


def test_too_many_steps_and_interrupts_end_the_lanes_as_the_single_engine(
    paper_fourbar: Mechanism,
) -> None:
    p = _problem(paper_fourbar, "impact", revolutions=0.05)
    few = _single_source(p, max_steps=40)
    _assert_same(few, _single_engine(p, max_steps=40))
    assert list(few["status"][:2]) == [ids.STATUS_TOO_MANY_STEPS] * 2
    flags = np.array([2], dtype=np.uint8)  # SIGINT
    stopped = _single_source(p, interrupt=flags)
    assert (stopped["status"] == ids.STATUS_INTERRUPTED).all()
    assert (stopped["n_steps"] == 0).all() and np.isnan(stopped["peaks"]).all()
    # every lane ends (a loop over lanes once stopped at its first interrupted lane and left
    # the others STATUS_RUNNING, which the batch engine could not read: "1 is not a valid
    # IntegrationStatus"; the block failed and the study went on)
    assert (stopped["status"] != ids.STATUS_RUNNING).all()


@pytest.mark.parametrize("film", [0.0, 1e5])
def test_the_closed_form_jacobian_is_eoms(paper_fourbar: Mechanism, film: float) -> None:
    """At states in contact (every joint pressed by a shifted pin), the rows and columns the
    Newton systems read are :func:`eom.jacobian_state`'s, bit for bit (the single engine
    embeds the same ``jacobian_clear`` in its full matrix: the q̇ rows the identity, the v0
    columns zero); without and with film damping (its terms:
    :func:`source_radau.film_jacobian`)."""
    p = _problem(paper_fourbar, "physical", film=film)
    assert np.all(p["rpar"][0, _joint_slots(p["ipar"], ids.G_FILM)] == film)
    ipar, rpar = p["ipar"], p["rpar"][0]
    lay = build.lane_layout(ipar)
    n = int(lay[source.LY_N])
    size = int(lay[source.LY_SIZE])
    compiled = cpu.compiled["jacobian_clear"]
    rng = np.random.default_rng(26)
    for _ in range(5):
        y = p["y0"][0].copy()
        y[:n] += rng.normal(scale=2e-4, size=n)
        y[n : 2 * n] += rng.normal(scale=0.05, size=n)
        y[2 * n + 2 :] = rng.uniform(0.0, 0.2, size=size - 2 * n - 2)
        full = np.zeros((size, size))
        args = (rpar, ipar, eom.new_workspace(4))
        assert eom.jacobian_state(0.01, y, np.zeros(size), args, full)
        jac = np.full((size - n, 2 * n), np.nan)
        compiled(0.01, y, rpar, ipar, lay, jac, np.empty(size), np.empty(28))
        np.testing.assert_array_equal(jac, full[n:, : 2 * n])
        assert np.count_nonzero(full[n : 2 * n, :n]) > 0  # some joint in contact


def test_what_the_lanes_do_not_cover_is_named(paper_fourbar: Mechanism) -> None:
    """Neither method runs the sustained-contact mode; film damping runs on the implicit
    lanes only (the explicit ones would take microsecond steps at a c_e of 1e5 N·s/m)."""
    p = _problem(paper_fourbar, "physical", film=0.0)
    captured = p["rpar"].copy()
    captured[1, _joint_slots(p["ipar"], ids.G_CAPTURE)[2]] = 1e-4  # one joint of one lane
    damped = p["rpar"].copy()
    damped[1, _joint_slots(p["ipar"], ids.G_FILM)[2]] = 100.0
    for method in ("explicit", "implicit"):
        assert build.lanes_refusal(p["ipar"], p["rpar"], method) is None
        assert "sustained-contact" in str(build.lanes_refusal(p["ipar"], captured, method))
    assert build.lanes_refusal(p["ipar"], damped, "implicit") is None
    refusal = str(build.lanes_refusal(p["ipar"], damped, "explicit"))
    assert "explicit lanes" in refusal and "film damping" in refusal and "implicit" in refusal


@pytest.mark.parametrize(
    "case", ["fourbar-A", "fourbar-AB-physical", "fourbar-AB-dry", "slider-crank-physical"]
)
def test_with_ideal_joints_the_differenced_jacobian_gives_the_single_engines_steps(
    paper_fourbar: Mechanism, slider_crank: Mechanism, case: str
) -> None:
    """Ideal joints left (the driver and the ideal joints' constraints, projection after
    every step, the Jacobian differenced: as SciPy's num_jac dry, with fixed steps with the
    film, the source's ``jacobian_fixed``): the four-bar with one conventional clearance
    joint, with two physical (lubricated) ones and two dry ones, and the slider-crank (a
    prismatic joint) with the physical default; 0.3 of a revolution, two lanes. Measured:
    equal bits (462/431, 155/229, 1 257/1 270 and 453/526 steps)."""
    mechanism = slider_crank if case.startswith("slider") else paper_fourbar
    if case == "fourbar-A":
        joints = [ClearanceJoint("A", 11.75e-6, 0.005, DEFAULT_IMPACT)]
    elif case == "fourbar-AB-physical":
        joints = ContactModel().joints(mechanism, ["A", "B"])
    elif case == "fourbar-AB-dry":
        joints = ContactModel(film_damping=0).joints(mechanism, ["A", "B"])
    else:
        joints = ContactModel().joints(mechanism)
    p = _two_lanes(mechanism, joints)
    assert not build.all_clear(p["ipar"])
    old = _single_engine(p)
    assert (old["status"] == ids.STATUS_SUCCESS).all() and (old["n_steps"] > 100).all()
    _assert_same(_single_source(p), old)


@pytest.mark.parametrize("group", range(3))
def test_every_contact_and_friction_law_gives_the_single_engines_steps(
    paper_fourbar: Mechanism, group: int
) -> None:
    """Every contact law (four per mechanism, one per joint) with the three friction choices
    rotating over the joints, 0.1 of a revolution, two lanes: the same counters and (measured)
    equal bits."""
    names = list(CONTACT_LAWS)[4 * group : 4 * group + 4]
    joints = [
        ClearanceJoint(j, 2e-5, 5e-3, _law(name), FRICTIONS[(k + group) % len(FRICTIONS)])
        for k, (j, name) in enumerate(zip(JOINTS, names, strict=True))
    ]
    p = _two_lanes(paper_fourbar, joints, opens=0.03, end=0.1)
    old = _single_engine(p)
    assert (old["status"] == ids.STATUS_SUCCESS).all() and (old["n_steps"] > 50).all()
    _assert_same(_single_source(p), old)


#: Film damping cases: c_e (N·s/m), the clearance joints and their clearances (m). The third
#: leaves O2 and O4 ideal (the Jacobian differenced, the projection after every step).
FILM_CASES = {
    "c_e=100, four joints": (100.0, JOINTS, (21e-6, 8e-6, 15e-6, 12e-6)),
    "c_e=1e5, four joints": (1e5, JOINTS, (8e-6, 21e-6, 12e-6, 15e-6)),
    "c_e=1e5, A and B": (1e5, ("A", "B"), (10e-6, 18e-6)),
}


def _film_problem(mechanism: Mechanism, case: str) -> dict[str, Any]:
    """:func:`_two_lanes` of the physical default with film damping (:data:`FILM_CASES`)."""
    film, names, clearances = FILM_CASES[case]
    joints = [
        joint.with_clearance(clearance)
        for joint, clearance in zip(
            ContactModel(film_damping=film).joints(mechanism, list(names)), clearances, strict=True
        )
    ]
    p = _two_lanes(mechanism, joints)
    assert np.all(p["rpar"][0, _joint_slots(p["ipar"], ids.G_FILM)] == film)
    return p


@pytest.mark.parametrize("case", FILM_CASES)
def test_with_film_damping_the_implicit_lane_takes_the_single_engines_steps(
    paper_fourbar: Mechanism, case: str
) -> None:
    """The film's force, power and Jacobian terms are the single engine's arithmetic: the same
    statuses, steps, rejections and evaluations of f, the same time reached (measured, 0.3
    of a revolution: 706/666, 156/178 and 187/268 steps, the last with the film's Jacobian
    beside ideal joints by fixed steps, ``jacobian_fixed``); the statistics and peaks as the
    module docstring says (the peaks located between steps on the single engine's
    interpolant, its rule chosen step by step from the joints' contacts)."""
    p = _film_problem(paper_fourbar, case)
    old = _single_engine(p)
    assert (old["status"] == ids.STATUS_SUCCESS).all() and (old["n_steps"] > 100).all()
    _assert_same(_single_source(p), old)


@pytest.mark.parametrize("capture", [None, "1 mm/s"])
def test_in_the_sustained_contact_mode_the_implicit_lane_takes_the_single_engines_steps(
    paper_fourbar: Mechanism, capture: str | None
) -> None:
    """Locked joints (the CPU's hooks: the accelerations with the locked joints as
    constraints, the release control, capture and release with the projection onto the
    locked joints, the Jacobian differenced while a joint is locked): the single engine's
    steps, at the default capture speed (0.1 mm/s) and at 1 mm/s (the mode's joints are dry),
    0.3 of a revolution (measured: 2 571/2 257 and 1 685/2 087 steps)."""
    model = ContactModel(
        sustained_contact=True, **({} if capture is None else {"capture_speed": capture})
    )
    p = _two_lanes(paper_fourbar, model.joints(paper_fourbar, JOINTS, clearance=21e-6))
    old = _single_engine(p)
    assert (old["status"] == ids.STATUS_SUCCESS).all()
    _assert_same(_single_source(p), old)
    assert old["locked"].any()  # the mode engaged: a joint locked at a recorded step
