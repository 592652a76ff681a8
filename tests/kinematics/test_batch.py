"""The vectorised four-bar closed form against the scalar one of jointplay.kinematics.fourbar."""

from __future__ import annotations

import numpy as np
import pytest

from jointplay.errors import AssemblyError
from jointplay.kinematics import batch, fourbar
from jointplay.model.templates import FourBarGeometry

#: Both forms evaluate the same closed form with different but exact operations (direction
#: cosines vs atan2/arccos); they agree to rounding, amplified near the limit positions.
RTOL, ATOL = 1e-9, 1e-9

PAPER = (0.108, 0.2705, 0.2705, 0.2814)  # crank, coupler, rocker, ground, m
LINKAGES = np.array(
    [
        PAPER,
        (0.05, 0.2, 0.15, 0.18),
        (0.1079, 0.2710, 0.2698, 0.2820),
    ]
)
OMEGA2 = 20.9  # rad/s


def _geometry(row: np.ndarray) -> FourBarGeometry:
    return FourBarGeometry(
        crank=float(row[0]), coupler=float(row[1]), rocker=float(row[2]), ground=float(row[3])
    )


def _angle_error(cos: np.ndarray, sin: np.ndarray, theta: np.ndarray) -> np.ndarray:
    return np.abs(np.angle((cos + 1j * sin) * np.exp(-1j * theta)))


@pytest.mark.parametrize("branch", [1, -1])
def test_positions_velocities_accelerations_match_the_scalar_closed_form(branch: int) -> None:
    theta2 = np.linspace(0.0, 2 * np.pi, 73)[:-1] + 0.01
    c2, s2 = np.cos(theta2), np.sin(theta2)
    states = batch.positions(LINKAGES, c2, s2, branch)
    omega3, omega4 = batch.velocities(LINKAGES, states, c2, s2, OMEGA2)
    alpha3, alpha4 = batch.accelerations(LINKAGES, states, c2, s2, OMEGA2, omega3, omega4)
    for i, row in enumerate(LINKAGES):
        g = _geometry(row)
        t3, t4 = fourbar.positions(g, theta2, branch)
        w3, w4 = fourbar.velocities(g, theta2, t3, t4, OMEGA2)
        a3, a4 = fourbar.accelerations(g, theta2, t3, t4, OMEGA2, w3, w4)
        assert np.max(_angle_error(states.c3[i], states.s3[i], t3)) < ATOL
        assert np.max(_angle_error(states.c4[i], states.s4[i], t4)) < ATOL
        np.testing.assert_allclose(states.ax[i], row[0] * c2, rtol=1e-15)
        scale_w = np.max(np.abs(w4))
        np.testing.assert_allclose(omega3[i], w3, rtol=RTOL, atol=ATOL * scale_w)
        np.testing.assert_allclose(omega4[i], w4, rtol=RTOL, atol=ATOL * scale_w)
        scale_a = np.max(np.abs(a4))
        np.testing.assert_allclose(alpha3[i], a3, rtol=RTOL, atol=ATOL * scale_a)
        np.testing.assert_allclose(alpha4[i], a4, rtol=RTOL, atol=ATOL * scale_a)


def test_loop_closes_and_link_lengths_are_kept() -> None:
    theta2 = np.linspace(0.0, 2 * np.pi, 37)
    c2, s2 = np.cos(theta2), np.sin(theta2)
    states = batch.positions(LINKAGES, c2, s2)
    b, c, d = LINKAGES[:, 1:2], LINKAGES[:, 2:3], LINKAGES[:, 3:4]
    bx, by = batch.coupler_point(states, 1.0, 0.0)  # unit offset along the coupler
    np.testing.assert_allclose(np.hypot(bx - states.ax, by - states.ay), 1.0, rtol=1e-12)
    # B from the coupler and from the rocker coincide: A + b e3 = O4 + c e4.
    np.testing.assert_allclose(states.ax + b * states.c3, d + c * states.c4, rtol=0, atol=1e-12)
    np.testing.assert_allclose(states.ay + b * states.s3, c * states.s4, rtol=0, atol=1e-12)


def test_transmission_angle_min_is_the_minimum_over_the_cycle() -> None:
    theta2 = np.linspace(0.0, 2 * np.pi, 20001)
    for row, expected in zip(LINKAGES, batch.transmission_angle_min(LINKAGES), strict=True):
        mu = fourbar.transmission_angle(_geometry(row), theta2)
        assert expected == pytest.approx(np.min(np.minimum(mu, np.pi - mu)), abs=1e-9)


def test_turns_fully_agrees_with_the_scalar_assembly_check() -> None:
    rng = np.random.default_rng(4)
    lengths = np.array(PAPER) * rng.uniform(0.6, 1.4, size=(300, 4))
    lengths[0, 0] = -0.1  # a negative length never assembles
    ok = batch.turns_fully(lengths)
    assert ok.any() and not ok.all()
    for row, turns in zip(lengths[1:], ok[1:], strict=True):
        try:
            fourbar.check_full_rotation(_geometry(row))
        except AssemblyError:
            assert not turns
        else:
            assert turns
    assert not ok[0]
