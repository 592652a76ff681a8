"""No start gives a film spike (issue 39, item 3): a lubricated pin starts moving with its
bearing (ė = 0), so the rest start of the lubricated default no longer opens with a ~2e5 N
film force at t = 0; a dry pin keeps the paper's start-up."""

from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from jointplay._kernels import constraints as ck
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import Start, initial_state, simulate
from jointplay.dynamics.system import build_system
from jointplay.model.mechanism import Lubrication, Mechanism

JOINTS = ("O2", "A", "B", "O4")


def _relative_speeds(mechanism: Mechanism, contact: ContactModel, mode: str) -> dict[str, float]:
    """|ė| at t = 0 of each clearance joint: its pin centre's velocity relative to its
    bearing centre (the joint's ideal constraint rows applied to the start's q̇)."""
    system = build_system(mechanism, contact.joints(mechanism))
    flat = system.flat
    n = system.n_coordinates
    y0 = initial_state(system, Start(mode))  # type: ignore[arg-type]
    speeds = {}
    for row, name in enumerate(flat.joint_names):
        if name not in JOINTS:
            continue
        only = np.zeros_like(flat.active)
        only[row] = 1
        driver = flat.driver.copy()
        driver[0] = -1  # the joint's rows alone
        phi_q = ck.jacobian(y0[:n], flat.joint_int, flat.joint_f, only, driver)
        speeds[name] = float(np.hypot(*(phi_q @ y0[n : 2 * n])))
    return speeds


@pytest.mark.parametrize("mode", ["rest", "impulsive", "steady"])
def test_a_lubricated_pin_starts_with_its_bearing(paper_fourbar: Mechanism, mode: str) -> None:
    speeds = _relative_speeds(paper_fourbar, ContactModel(), mode)
    assert max(speeds.values()) < 1e-9, speeds  # was 2.26 m/s at A (rest), the crank's ωr


def test_a_dry_pin_keeps_the_paper_start_up(paper_fourbar: Mechanism) -> None:
    mixed = dataclasses.replace(paper_fourbar, joint_lubrication={"A": Lubrication("dry")})
    speeds = _relative_speeds(mixed, ContactModel(), "rest")
    omega_r = paper_fourbar.driver.angular_velocity * 0.108  # the crank pin's speed, m/s
    assert speeds["A"] > 0.5 * omega_r, speeds  # the dry pin flies across its clearance
    assert max(speeds[j] for j in ("O2", "B", "O4")) < 1e-9, speeds
    dry = _relative_speeds(paper_fourbar, ContactModel(lubrication="dry"), "rest")
    assert dry["A"] > 0.5 * omega_r


def test_the_lubricated_rest_start_has_no_film_spike(paper_fourbar: Mechanism) -> None:
    contact = ContactModel()
    result = simulate(
        paper_fourbar, contact.joints(paper_fourbar), revolutions=0.02, settle=0,
        start=Start("rest"),
    )  # fmt: skip
    first = result.timeseries.iloc[0]
    # measured: 1.918e5 N at A at t = 0 before; the film's load is tens of newtons
    assert max(abs(first[f"F_{j}"]) for j in JOINTS) < 1.0
    assert max(result.peaks[f"F_{j}"]["value"] for j in JOINTS) < 100.0


@pytest.mark.parametrize("mode", ["rest", "impulsive"])
def test_the_batch_start_is_the_same(paper_fourbar: Mechanism, mode: str) -> None:
    """The batch engine's vectorised start projects through the lubricated joints too: equal
    to the per-sample :func:`initial_state`, and each sample's lubricated pins start with
    their bearings."""
    from jointplay.dynamics.batch import BatchSamples, build_batch

    rng = np.random.default_rng(5)
    nominal = {"crank": 0.108, "coupler": 0.2705, "rocker": 0.2705, "ground": 0.2794}
    samples = BatchSamples(
        lengths={k: v * (1 + 2e-3 * rng.standard_normal(8)) for k, v in nominal.items()},
        clearances={j: rng.uniform(6e-6, 20e-6, 8) for j in JOINTS},
    )
    joints = ContactModel().joints(paper_fourbar)
    start = Start(mode)  # type: ignore[arg-type]
    fast = build_batch(paper_fourbar, joints, samples, start=start, settle=0)
    slow = build_batch(paper_fourbar, joints, samples, start=start, settle=0, vectorised=False)
    assert fast.vectorised and fast.ok.all() and slow.ok.all()
    np.testing.assert_allclose(fast.y0, slow.y0, rtol=1e-12, atol=1e-12)
    nominal_state = initial_state(build_system(paper_fourbar, joints), Start("steady"))
    n = len(nominal_state) // 2 - 3  # q, q̇, 2 energies, one memory per joint
    coupler = fast.y0[:, n + 3 : n + 6]  # the coupler's ẋ, ẏ, θ̇ (body 2)
    assert (np.abs(coupler[:, 2]) > 1.0).all()  # it moves with the crank (at rest before)
