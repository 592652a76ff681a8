"""Four-bar kinematics: closed form against the general solver, finite differences and
geometric invariants.

Tolerances: the general Newton–Raphson solver stops at |Φ| < 1e-13 m, so angles agree to
~1e-12 rad; the issue asks for 1e-9 rad. Loop closure and link lengths: 1e-12 m (round-off
on lengths of order 0.1–1 m is ~1e-16 m).
"""

from __future__ import annotations

import math

import numpy as np
import pytest
from hypothesis import HealthCheck, assume, example, given, settings
from hypothesis import strategies as st

from jointplay._kernels import constraints as ck
from jointplay.errors import AssemblyError
from jointplay.kinematics import fourbar
from jointplay.kinematics.analysis import analyse, cycle_angles
from jointplay.kinematics.solver import driver_at, guess_from_angles
from jointplay.model.templates import FourBarGeometry, LinkBody, four_bar


def crank_rocker(a: float, b: float, c: float, d: float, branch: int = 1, direction: int = 1):
    return four_bar(
        FourBarGeometry(a, b, c, d),
        speed=20.0,
        direction=direction,  # type: ignore[arg-type]
        branch=branch,  # type: ignore[arg-type]
        bodies={name: LinkBody(mass=0.2) for name in ("crank", "coupler", "rocker")},
    )


grashof_crank_rockers = st.tuples(
    st.floats(0.02, 0.2),  # crank, the shortest link
    st.floats(1.3, 5.0),  # coupler / crank
    st.floats(1.3, 5.0),  # rocker / crank
    st.floats(1.3, 5.0),  # ground / crank
    st.sampled_from([1, -1]),
)


@settings(max_examples=25, deadline=None, suppress_health_check=[HealthCheck.too_slow])
@given(grashof_crank_rockers, st.floats(-0.3, 0.3), st.floats(-0.3, 0.3))
# Found by hypothesis: undamped Newton jumped to the other branch from a guess 0.28 rad off.
@example(params=(0.125, 4.0, 3.0, 2.625, -1), noise3=-0.28125, noise4=0.0625)
def test_closed_form_matches_general_solver(params, noise3, noise4) -> None:
    a, rb, rc, rd, branch = params
    lengths = sorted([a, a * rb, a * rc, a * rd])
    margin = lengths[1] + lengths[2] - lengths[0] - lengths[3]
    assume(margin > 0.05 * lengths[3])  # Grashof with room: no near-singular configurations
    mechanism = crank_rocker(a, a * rb, a * rc, a * rd, branch)
    angles = cycle_angles(mechanism, 4.0)
    closed = analyse(mechanism, angles, method="closed-form")
    # Seed the general solver with deliberately wrong angles: it must find the same branch.
    # Newton follows the branch whose basin holds the guess, so the error must stay well
    # inside half the distance to the other branch (a third of it here); beyond that the
    # other assembly is the correct answer to the solver's question.
    other = analyse(crank_rocker(a, a * rb, a * rc, a * rd, -branch), angles[:1])
    separation = min(
        abs(math.remainder(closed.q[0, k] - other.q[0, k], 2 * math.pi)) for k in (5, 8)
    )
    assume(max(abs(noise3), abs(noise4)) < separation / 3)
    start = {0: angles[0], 1: closed.q[0, 5] + noise3, 2: closed.q[0, 8] + noise4}
    # Nor near a singular position: with the crank held, the loop closure's Jacobian in the
    # coupler and rocker angles has determinant ∝ sin(θ3 − θ4), so a guess with the two nearly
    # aligned gives Newton an arbitrary direction (found by hypothesis: params=(0.125, 3.4375,
    # 4.0625, 2.25, -1), noise4=0.28 put them 0.009 rad apart, and the damped steps walked
    # to the other branch).
    assume(abs(math.sin(start[1] - start[2])) > 0.1)
    general = analyse(
        mechanism, angles, method="general", q_start=guess_from_angles(closed.flat, start)
    )
    for link in ("coupler", "rocker"):
        dphi = np.angle(np.exp(1j * (closed.angle(link) - general.angle(link))))
        assert np.max(np.abs(dphi)) < 1e-9
        assert np.allclose(closed.omega(link), general.omega(link), rtol=1e-9, atol=1e-9)
        assert np.allclose(closed.alpha(link), general.alpha(link), rtol=1e-8, atol=1e-7)
    # Loop closure and link lengths from the closed form's positions.
    for i, angle in enumerate(angles):
        phi = ck.residual(
            closed.q[i], 0.0, *closed.flat.kernel_args()[:3], driver_at(closed.flat, angle)
        )
        assert np.max(np.abs(phi)) < 1e-12
    o2 = np.zeros(2)
    o4 = np.array([a * rd, 0.0])
    pa = closed.point("crank", "A")[0]
    pb = closed.point("coupler", "B")[0]
    np.testing.assert_allclose(np.linalg.norm(pa - o2, axis=1), a, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(pb - pa, axis=1), a * rb, atol=1e-12)
    np.testing.assert_allclose(np.linalg.norm(pb - o4, axis=1), a * rc, atol=1e-12)
    np.testing.assert_allclose(closed.point("rocker", "B")[0], pb, atol=1e-12)


@pytest.mark.parametrize("branch", [1, -1])
@pytest.mark.parametrize("direction", [1, -1])
def test_rates_match_finite_differences(branch: int, direction: int) -> None:
    mechanism = crank_rocker(0.108, 0.2705, 0.2705, 0.2794, branch, direction)
    omega2 = mechanism.driver.angular_velocity
    h = 1e-5  # rad of crank; central differences are O(h²) ≈ 1e-10 relative
    base = np.radians(np.arange(0, 360, 7.0))
    res = analyse(mechanism, base)
    plus = analyse(mechanism, base + h)
    minus = analyse(mechanism, base - h)
    for link in ("coupler", "rocker"):
        dphi = np.angle(np.exp(1j * (plus.angle(link) - minus.angle(link)))) / (2 * h)
        np.testing.assert_allclose(res.omega(link), dphi * omega2, rtol=1e-7, atol=1e-7)
        domega = (plus.omega(link) - minus.omega(link)) / (2 * h)
        np.testing.assert_allclose(res.alpha(link), domega * omega2, rtol=1e-6, atol=1e-5)
    # Any point (a coupler point off the line A-B): velocity and acceleration too.
    point = (0.1, 0.05)
    p_plus, p_minus = plus.point("coupler", point)[0], minus.point("coupler", point)[0]
    _, vel, acc = res.point("coupler", point)
    np.testing.assert_allclose(vel, (p_plus - p_minus) / (2 * h) * omega2, rtol=1e-6, atol=1e-7)
    v_plus, v_minus = plus.point("coupler", point)[1], minus.point("coupler", point)[1]
    np.testing.assert_allclose(acc, (v_plus - v_minus) / (2 * h) * omega2, rtol=1e-6, atol=1e-5)


def test_branch_plus_puts_b_above_the_ground_line_at_zero(paper_fourbar) -> None:
    res = analyse(paper_fourbar, np.array([0.0]))
    assert res.point("rocker", "B")[0][0, 1] > 0
    lower = crank_rocker(0.108, 0.2705, 0.2705, 0.2794, branch=-1)
    assert analyse(lower, np.array([0.0])).point("rocker", "B")[0][0, 1] < 0


@pytest.mark.parametrize(
    ("lengths", "kind"),
    [
        ((0.108, 0.2705, 0.2705, 0.2794), "crank-rocker"),
        ((0.2794, 0.2705, 0.2705, 0.108), "double-crank"),  # Table 1 read literally
        ((0.3, 0.1, 0.3, 0.35), "double-rocker"),
        ((0.3, 0.35, 0.1, 0.3), "rocker-crank"),
        ((0.2, 0.3, 0.4, 0.55), "triple-rocker"),
        ((0.1, 0.3, 0.2, 0.2), "change-point"),
    ],
)
def test_grashof_classification(lengths, kind) -> None:
    assert fourbar.grashof(FourBarGeometry(*lengths)).kind == kind


def test_non_grashof_crank_is_rejected_with_lengths_and_angles() -> None:
    mechanism = crank_rocker(0.2, 0.3, 0.4, 0.55)
    with pytest.raises(AssemblyError) as info:
        analyse(mechanism)
    message = str(info.value)
    assert "crank 200 mm" in message and "ground 550 mm" in message
    assert "°" in message and "triple-rocker" in message


def test_unassemblable_geometry_is_rejected() -> None:
    with pytest.raises(AssemblyError, match="cannot be assembled"):
        fourbar.positions(FourBarGeometry(0.1, 0.1, 0.1, 1.0), [0.0])


def test_paper_mechanism_figures(paper_fourbar) -> None:
    geometry = paper_fourbar.template.geometry
    extended, folded = fourbar.rocker_limit_positions(geometry)
    swing = math.degrees(abs(extended.rocker_angle - folded.rocker_angle))
    assert swing == pytest.approx(52.6, abs=0.1)  # docs/paper-reading.md: "a 52.6° rocker swing"
    # At the limit positions the rocker is momentarily at rest.
    res = analyse(paper_fourbar, np.array([extended.crank_angle, folded.crank_angle]))
    np.testing.assert_allclose(res.omega("rocker"), 0.0, atol=1e-9)
    # Extreme transmission angles at crank angles 0 and 180°, law of cosines by hand.
    mu = np.degrees(fourbar.transmission_angle(geometry, np.radians([0.0, 180.0])))
    b = c = 270.5
    for f, value in zip((279.4 - 108.0, 279.4 + 108.0), mu, strict=True):
        assert value == pytest.approx(
            math.degrees(math.acos((b * b + c * c - f * f) / (2 * b * c))), rel=1e-12
        )


@pytest.mark.parametrize(
    "lengths", [(0.108, 0.2705, 0.2705, 0.2794), (0.05, 0.20, 0.15, 0.18), (0.03, 0.1, 0.1, 0.1)]
)
def test_transmission_angle_range_is_the_extremes_over_a_dense_grid(lengths) -> None:
    """The closed-form extremes (crank along the ground line) against 0.01° sampling."""
    from jointplay.kinematics.fourbar import (
        transmission_angle,
        transmission_angle_deviation,
        transmission_angle_range,
    )

    geometry = FourBarGeometry(*lengths)
    mu = transmission_angle(geometry, np.radians(np.arange(0.0, 360.0, 0.01)))
    low, high = transmission_angle_range(geometry)
    # 0.01° grid: the extremes are flat there, so the grid comes within 1e-8 rad of them.
    assert low == pytest.approx(mu.min(), abs=1e-8) and low <= mu.min()
    assert high == pytest.approx(mu.max(), abs=1e-8) and high >= mu.max()
    assert transmission_angle_deviation(geometry) == pytest.approx(
        np.minimum(mu, np.pi - mu).min(), abs=1e-8
    )
