"""Inverse dynamics: power balance and the Newton–Euler balance of every link.

The power balance T·ω2 = dT/dt − P_gravity is exact for ideal joints; it is checked to 1e-9
relative to the peak motor power, the issue's tolerance (the residual is round-off, ~1e-14).
"""

from __future__ import annotations

import numpy as np
import pytest

from jointplay.dynamics.inverse import inverse_dynamics
from jointplay.kinematics.analysis import analyse
from jointplay.model.mechanism import GROUND


@pytest.mark.parametrize("gravity", [(0.0, 0.0), (0.0, -9.81), (3.0, -9.81)])
@pytest.mark.parametrize("preset", ["paper_fourbar", "slider_crank"])
def test_power_balance(preset: str, gravity, request) -> None:
    mechanism = request.getfixturevalue(preset).with_gravity(gravity)
    dyn = inverse_dynamics(analyse(mechanism))
    motor, rate = dyn.power_balance()
    assert np.max(np.abs(motor - rate)) < 1e-9 * np.max(np.abs(motor))


@pytest.mark.parametrize("preset", ["paper_fourbar", "slider_crank"])
def test_each_link_is_in_force_and_moment_balance(preset: str, request) -> None:
    mechanism = request.getfixturevalue(preset).with_gravity((0.0, -9.81))
    kin = analyse(mechanism)
    dyn = inverse_dynamics(kin)
    for link in mechanism.links:
        k = kin.flat.body_index(link.name)
        force = np.zeros((len(kin.crank_angle), 2))
        moment = np.zeros(len(kin.crank_angle))
        com = kin.q[:, 3 * k : 3 * k + 2]
        for j, joint in enumerate(mechanism.joints):
            if link.name not in (joint.link_a, joint.link_b):
                continue
            sign = 1.0 if joint.link_b == link.name else -1.0  # force is a's action on b
            f = sign * dyn.force[:, j]
            point = joint.point_b if joint.link_b == link.name else joint.point_a
            r = kin.point(link.name, point)[0] - com
            force += f
            moment += r[:, 0] * f[:, 1] - r[:, 1] * f[:, 0] + sign * dyn.couple[:, j]
        if link.name == mechanism.driver.link:
            moment += dyn.torque
        force += link.mass * np.asarray(mechanism.gravity)
        scale = link.mass * np.max(np.abs(kin.qdd[:, 3 * k : 3 * k + 2])) + 1.0
        np.testing.assert_allclose(
            force, link.mass * kin.qdd[:, 3 * k : 3 * k + 2], atol=1e-9 * scale
        )
        np.testing.assert_allclose(moment, link.inertia * kin.qdd[:, 3 * k + 2], atol=1e-9 * scale)


def test_ground_reaction_balances_the_mechanism(paper_fourbar) -> None:
    """Sum of ground reactions = total m·a of the centres of mass (no gravity)."""
    kin = analyse(paper_fourbar)
    dyn = inverse_dynamics(kin)
    ground_force = sum(
        dyn.force[:, j] for j, joint in enumerate(paper_fourbar.joints) if joint.link_a == GROUND
    )
    total = sum(
        link.mass * kin.qdd[:, 3 * k : 3 * k + 2] for k, link in enumerate(paper_fourbar.links)
    )
    np.testing.assert_allclose(ground_force, total, atol=1e-10)
