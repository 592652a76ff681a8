"""What both compiled integrators (Radau IIA, RODAS4) share: they never raise; a failure
is a status, and a hook that misbehaves cannot hang them."""

from __future__ import annotations

from typing import Any

import numpy as np
import pytest

from _ode_problems import (
    always_halve,
    decay,
    nan_rhs,
    odd_theta,
    poison_state,
    run_kernel,
    square,
    van_der_pol,
)
from jointplay._kernels import common, radau, rodas

INTEGRATORS = {"radau": radau.radau_integrate, "rodas4": rodas.rodas_integrate}


@pytest.fixture(params=list(INTEGRATORS))
def integrator(request: pytest.FixtureRequest) -> Any:
    return INTEGRATORS[request.param]


def test_step_check_that_never_accepts_cannot_loop_forever(integrator: Any) -> None:
    result = run_kernel(
        decay, (0.0, 1.0), [1.0], [1.0], rtol=1e-6, atol=1e-9, step_check=always_halve,
        max_steps=20, integrator=integrator,
    )  # fmt: skip
    assert result.status == common.STATUS_TOO_MANY_STEPS
    assert result.counts["n_steps"] == 20
    assert 0 < result.counts["n_rejected_check"] <= radau.MAX_CHECK_REJECTIONS * 20


def test_step_check_nan_zero_or_negative_accepts(integrator: Any) -> None:
    result = run_kernel(
        decay, (0.0, 1.0), [1.0], [1.0], rtol=1e-6, atol=1e-9, step_check=odd_theta,
        integrator=integrator,
    )  # fmt: skip
    assert result.status == common.STATUS_SUCCESS
    assert result.counts["n_rejected_check"] == 0


def test_blow_up_gives_step_too_small(integrator: Any) -> None:
    result = run_kernel(
        square, (0.0, 2.0), [1.0], [0.0], rtol=1e-6, atol=1e-9, integrator=integrator
    )
    assert result.status == common.STATUS_STEP_TOO_SMALL
    assert result.t[-1] == pytest.approx(1.0, abs=1e-5)  # the blow-up time 1/y(0)


def test_step_limit_gives_too_many_steps(integrator: Any) -> None:
    result = run_kernel(
        van_der_pol, (0.0, 3000.0), [2.0, 0.0], [1000.0], rtol=1e-6, atol=1e-6, max_steps=10,
        integrator=integrator,
    )  # fmt: skip
    assert result.status == common.STATUS_TOO_MANY_STEPS
    assert result.counts["n_steps"] == 10 and result.t.shape[0] == 11


def test_non_finite_right_hand_side_gives_non_finite(integrator: Any) -> None:
    result = run_kernel(
        nan_rhs, (0.0, 1.0), [1.0, 2.0], [0.0], rtol=1e-6, atol=1e-9, integrator=integrator
    )
    assert result.status == common.STATUS_NON_FINITE
    assert result.t.shape[0] == 1 and result.counts["nfev"] == 1


def test_non_finite_state_from_after_step_gives_non_finite(integrator: Any) -> None:
    result = run_kernel(
        decay, (0.0, 1.0), [1.0], [0.5], rtol=1e-6, atol=1e-9, after_step=poison_state,
        integrator=integrator,
    )  # fmt: skip
    assert result.status == common.STATUS_NON_FINITE
    assert np.all(np.isfinite(result.y)) and result.t[-1] <= 0.5


def test_empty_interval_records_only_the_initial_point(integrator: Any) -> None:
    result = run_kernel(
        decay, (2.0, 2.0), [1.0], [1.0], rtol=1e-6, atol=1e-9, integrator=integrator
    )
    assert result.status == common.STATUS_SUCCESS
    assert result.t.tolist() == [2.0] and result.y.tolist() == [[1.0]]


def test_an_interrupt_stops_with_a_status(integrator: Any) -> None:
    """The C-level signal handler's bytes, read before every step."""
    flags = np.zeros(4, dtype=np.uint8)
    flags[0] = common.INTERRUPT_SIGNALS[0]
    result = run_kernel(
        decay, (0.0, 1.0), [1.0], [1.0], rtol=1e-6, atol=1e-9, interrupt=flags,
        integrator=integrator,
    )  # fmt: skip
    assert result.status == common.STATUS_INTERRUPTED
    assert result.counts["n_steps"] == 0 and result.t.tolist() == [0.0]
