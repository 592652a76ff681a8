"""What the compiled integrators (Radau IIA, RODAS4, DOPRI5) share: the hooks land steps on events
and project the state; they never raise, a failure is a status, and a hook that misbehaves
cannot hang them."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from _ode_problems import (
    always_halve,
    bounce,
    cartesian_pendulum,
    decay,
    dopri_integrate,
    free_fall,
    land_on_ground,
    nan_rhs,
    odd_theta,
    poison_state,
    project_on_circle,
    radau_integrate,
    rodas_integrate,
    run_kernel,
    square,
    van_der_pol,
)
from jointplay._kernels import driver, ids

INTEGRATORS = {
    "radau": radau_integrate,
    "rodas4": rodas_integrate,
    "dopri5": dopri_integrate,
}


@pytest.fixture(params=list(INTEGRATORS))
def integrator(request: pytest.FixtureRequest) -> Any:
    return INTEGRATORS[request.param]


def test_bouncing_ball_steps_land_on_each_impact(integrator: Any) -> None:
    g, e, h0, tol = 9.81, 0.8, 1.0, 1e-10
    p = np.array([g, e, tol])
    run = run_kernel(
        free_fall,
        (0.0, 2.0),
        [h0, 0.0],
        p,
        rtol=1e-8,
        atol=1e-10,
        step_check=land_on_ground,
        after_step=bounce,
        integrator=integrator,
    )
    assert run.status == ids.STATUS_SUCCESS
    assert run.counts["n_rejected_check"] > 0
    # Impact k at t_k: t_1 = √(2h/g), then flights of 2·e^k·v_1/g with v_1 = √(2gh).
    v1 = np.sqrt(2 * g * h0)
    impacts = [np.sqrt(2 * h0 / g)]
    while impacts[-1] + 2 * e ** len(impacts) * v1 / g < 2.0:
        impacts.append(impacts[-1] + 2 * e ** len(impacts) * v1 / g)
    bounced = np.flatnonzero((run.y[:, 0] == 0.0) & (run.y[:, 1] > 0.0))
    assert len(bounced) == len(impacts)
    # A landing overshoots by at most tol in height, i.e. tol/|v| in time; the flights
    # themselves are exact (quadratic solution), so 1e-8 s is a loose bound.
    np.testing.assert_allclose(run.t[bounced], impacts, atol=1e-8)
    # Each rebound leaves with e times the impact speed.
    np.testing.assert_allclose(
        run.y[bounced, 1], e ** np.arange(1, len(impacts) + 1) * v1, rtol=1e-7
    )


def test_after_step_projection_keeps_pendulum_on_its_circle(integrator: Any) -> None:
    p = np.array([9.81, 0.5])
    y0 = [0.5, 0.0, 0.0, 0.0]  # horizontal, at rest
    options: dict[str, Any] = {"rtol": 1e-4, "atol": 1e-7, "integrator": integrator}
    free = run_kernel(cartesian_pendulum, (0.0, 10.0), y0, p, **options)
    projected = run_kernel(
        cartesian_pendulum, (0.0, 10.0), y0, p, after_step=project_on_circle, **options
    )
    assert free.status == projected.status == ids.STATUS_SUCCESS
    radius_free = np.hypot(free.y[:, 0], free.y[:, 1])
    radius = np.hypot(projected.y[:, 0], projected.y[:, 1])
    assert np.max(np.abs(radius_free - 0.5)) > 1e-6  # drift without the hook
    np.testing.assert_allclose(radius, 0.5, rtol=4 * np.finfo(float).eps)
    # Energy m(g z + |v|²/2) stays at its initial 0 within the tolerance scale.
    energy = 9.81 * projected.y[:, 1] + 0.5 * (projected.y[:, 2] ** 2 + projected.y[:, 3] ** 2)
    assert np.max(np.abs(energy)) < 1e-2


def test_step_check_that_never_accepts_cannot_loop_forever(integrator: Any) -> None:
    result = run_kernel(
        decay, (0.0, 1.0), [1.0], [1.0], rtol=1e-6, atol=1e-9, step_check=always_halve,
        max_steps=20, integrator=integrator,
    )  # fmt: skip
    assert result.status == ids.STATUS_TOO_MANY_STEPS
    assert result.counts["n_steps"] == 20
    assert 0 < result.counts["n_rejected_check"] <= driver.MAX_CHECK_REJECTIONS * 20


def test_step_check_nan_zero_or_negative_accepts(integrator: Any) -> None:
    result = run_kernel(
        decay, (0.0, 1.0), [1.0], [1.0], rtol=1e-6, atol=1e-9, step_check=odd_theta,
        integrator=integrator,
    )  # fmt: skip
    assert result.status == ids.STATUS_SUCCESS
    assert result.counts["n_rejected_check"] == 0


def test_blow_up_gives_step_too_small(integrator: Any) -> None:
    result = run_kernel(
        square, (0.0, 2.0), [1.0], [0.0], rtol=1e-6, atol=1e-9, integrator=integrator
    )
    assert result.status == ids.STATUS_STEP_TOO_SMALL
    assert result.t[-1] == pytest.approx(1.0, abs=1e-5)  # the blow-up time 1/y(0)


def test_step_limit_gives_too_many_steps(integrator: Any) -> None:
    result = run_kernel(
        van_der_pol, (0.0, 3000.0), [2.0, 0.0], [1000.0], rtol=1e-6, atol=1e-6, max_steps=10,
        integrator=integrator,
    )  # fmt: skip
    assert result.status == ids.STATUS_TOO_MANY_STEPS
    assert result.counts["n_steps"] == 10 and result.t.shape[0] == 11


def test_non_finite_right_hand_side_gives_non_finite(integrator: Any) -> None:
    result = run_kernel(
        nan_rhs, (0.0, 1.0), [1.0, 2.0], [0.0], rtol=1e-6, atol=1e-9, integrator=integrator
    )
    assert result.status == ids.STATUS_NON_FINITE
    assert result.t.shape[0] == 1 and result.counts["nfev"] == 1


def test_non_finite_state_from_after_step_gives_non_finite(integrator: Any) -> None:
    result = run_kernel(
        decay, (0.0, 1.0), [1.0], [0.5], rtol=1e-6, atol=1e-9, after_step=poison_state,
        integrator=integrator,
    )  # fmt: skip
    assert result.status == ids.STATUS_NON_FINITE
    assert np.all(np.isfinite(result.y)) and result.t[-1] <= 0.5


def test_empty_interval_records_only_the_initial_point(integrator: Any) -> None:
    result = run_kernel(
        decay, (2.0, 2.0), [1.0], [1.0], rtol=1e-6, atol=1e-9, integrator=integrator
    )
    assert result.status == ids.STATUS_SUCCESS
    assert result.t.tolist() == [2.0] and result.y.tolist() == [[1.0]]


def test_an_empty_system_jumps_to_the_end(integrator: Any) -> None:
    """SciPy's: no component, no step; the record is the start and ``t_bound``."""
    result = run_kernel(decay, (0.0, 3.0), [], [1.0], rtol=1e-6, atol=1e-9, integrator=integrator)
    assert result.status == ids.STATUS_SUCCESS
    assert result.t.tolist() == [0.0, 3.0] and result.y.shape == (2, 0)
    assert sum(result.counts.values()) == 0


def test_an_interrupt_stops_with_a_status(integrator: Any) -> None:
    """The C-level signal handler's bytes, read before every step."""
    flags = np.zeros(4, dtype=np.uint8)
    flags[0] = ids.INTERRUPT_SIGNALS[0]
    result = run_kernel(
        decay, (0.0, 1.0), [1.0], [1.0], rtol=1e-6, atol=1e-9, interrupt=flags,
        integrator=integrator,
    )  # fmt: skip
    assert result.status == ids.STATUS_INTERRUPTED
    assert result.counts["n_steps"] == 0 and result.t.tolist() == [0.0]
