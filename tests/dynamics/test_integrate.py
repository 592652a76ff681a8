"""Tests of :func:`jointplay.dynamics.integrate.integrate`, the Python face of the kernel.

The numerics are tested in ``tests/_kernels/test_radau.py``; here: the result object,
input validation (``ConfigError`` naming the argument), and failures turned into
``IntegrationError`` with a message that says what to change. All functions take
``args = (p,)``, the same type as in the kernel tests, so the driver compiles once.
"""

from __future__ import annotations

import dataclasses
import math
from typing import Any

import numba
import numpy as np
import pytest

from jointplay.dynamics.integrate import IntegrationResult, IntegrationStatus, integrate
from jointplay.errors import ConfigError, IntegrationError


@numba.njit(cache=True)
def decay(t, y, args):
    """y' = −λ y with λ = p."""
    return -args[0] * y


@numba.njit(cache=True)
def van_der_pol(t, y, args):
    """Van der Pol oscillator, μ = p[0]."""
    return np.array([y[1], args[0][0] * (1.0 - y[0] * y[0]) * y[1] - y[0]])


@numba.njit(cache=True)
def square(t, y, args):
    """y' = y², blowing up at t = 1/y(0)."""
    return y * y


@numba.njit(cache=True)
def log_of_state(t, y, args):
    """NaN at the initial state y = −1 (logarithm of a negative number)."""
    return np.log(y)


@numba.njit(cache=True)
def wrong_length(t, y, args):
    """Returns one component too many."""
    return np.zeros(y.shape[0] + 1)


@numba.njit(cache=True)
def oscillator(t, y, args):
    """y'' = −p y as a first-order system (its Jacobian has two zero entries)."""
    return np.array([y[1], -args[0][0] * y[0]])


@numba.njit(cache=True)
def oscillator_jacobian_sparse(t, y, f, args, out):
    """The two non-zero entries only; ``args[0][1]`` drops to 0 if ``out`` ever arrives
    holding anything but zeros."""
    if np.any(out != 0.0):
        args[0][1] = 0.0
    out[0, 1] = 1.0
    out[1, 0] = -args[0][0]
    return True


@numba.njit(cache=True)
def two_arguments(t, y):
    """Lacks the args parameter."""
    return -y


@numba.njit(cache=True)
def count_steps(t, y, args):
    """after_step that counts accepted steps in p[1] (contact-memory style)."""
    args[0][1] += 1.0
    return False


@numba.njit(cache=True)
def cap_step(t_old, y_old, t_new, y_new, args):
    """step_check that halves every step longer than p[1]."""
    return 0.5 if t_new - t_old > args[0][1] else 1.0


P = (np.array([2.0]),)


def test_result_is_frozen_and_complete() -> None:
    result = integrate(decay, (0.0, 1.0), [1.0], args=P, rtol=1e-8, atol=1e-10)
    assert isinstance(result, IntegrationResult)
    assert result.success and result.status is IntegrationStatus.SUCCESS
    assert "reached the end" in result.message
    assert result.t[0] == 0.0 and result.t[-1] == 1.0
    assert result.y.shape == (result.n_steps + 1, 1)
    # 1e-8 relative tolerance → global error of a few 1e-8 (kernel tests: ≤ 5 units).
    assert result.y[-1, 0] == pytest.approx(math.exp(-2.0), rel=5e-8)
    assert result.n_rejected == (
        result.n_rejected_error + result.n_rejected_newton + result.n_rejected_check
    )
    assert result.nfev > 0 and result.njev >= 1 and result.nlu >= 2
    with pytest.raises(dataclasses.FrozenInstanceError):
        result.status = IntegrationStatus.NON_FINITE  # type: ignore[misc]
    with pytest.raises(ValueError, match="read-only"):
        result.y[0, 0] = 3.0


def test_to_frame_has_time_and_named_states() -> None:
    result = integrate(van_der_pol, (0.0, 1.0), [2.0, 0.0], args=(np.array([1.0]),))
    frame = result.to_frame(["x", "v"])
    assert list(frame.columns) == ["t", "x", "v"]
    assert len(frame) == result.t.shape[0]
    assert list(result.to_frame().columns) == ["t", "y0", "y1"]
    with pytest.raises(ConfigError, match="one per state"):
        result.to_frame(["x"])


def test_scalar_and_per_component_atol_agree() -> None:
    mu = (np.array([1.0]),)
    scalar = integrate(van_der_pol, (0.0, 2.0), [2.0, 0.0], args=mu, atol=1e-8)
    vector = integrate(van_der_pol, (0.0, 2.0), [2.0, 0.0], args=mu, atol=[1e-8, 1e-8])
    np.testing.assert_array_equal(scalar.y, vector.y)


def test_hooks_are_called_and_may_update_args() -> None:
    memory = np.array([1.0, 0.0])  # (μ, step counter)
    result = integrate(van_der_pol, (0.0, 1.0), [2.0, 0.0], args=(memory,), after_step=count_steps)
    assert memory[1] == result.n_steps

    limit = np.array([1.0, 0.05])  # (μ, longest step let through)
    checked = integrate(van_der_pol, (0.0, 1.0), [2.0, 0.0], args=(limit,), step_check=cap_step)
    assert checked.n_rejected_check > 0
    assert np.all(np.diff(checked.t) <= 0.05 + 1e-12)


@pytest.mark.parametrize("method", ["radau", "rodas4"])
def test_a_jacobian_writes_only_its_non_zero_entries(method: str) -> None:
    """``out`` arrives zeroed at every call (RODAS4 asks at every step), so a ``jac`` that
    writes only its non-zero entries is exact."""
    p = np.array([4.0, 1.0])
    exact = integrate(oscillator, (0.0, 3.0), [1.0, 0.0], args=(p,), rtol=1e-8, atol=1e-10,
                      jac=oscillator_jacobian_sparse, method=method)  # fmt: skip
    assert p[1] == 1.0, "out held the previous call's entries"
    assert exact.njev > (1 if method == "rodas4" else 0)
    np.testing.assert_allclose(exact.y[-1], [math.cos(6.0), -2.0 * math.sin(6.0)], atol=1e-6)


# ---------------------------------------------------------------------------------------
# Failures become IntegrationError, or data with throw=False.
# ---------------------------------------------------------------------------------------
def test_step_too_small_names_time_and_remedies() -> None:
    with pytest.raises(IntegrationError, match=r"step size fell below.*at t = 1\.0000") as info:
        integrate(square, (0.0, 2.0), [1.0], args=P, rtol=1e-6)
    assert "Loosen rtol/atol" in str(info.value) and "blow-up" in str(info.value)


def test_too_many_steps_names_limit_and_remedies() -> None:
    with pytest.raises(IntegrationError, match="max_steps = 5") as info:
        integrate(van_der_pol, (0.0, 3000.0), [2.0, 0.0], args=(np.array([1000.0]),), max_steps=5)
    assert "Raise max_steps" in str(info.value)


def test_non_finite_initial_derivative_is_reported() -> None:
    with pytest.raises(IntegrationError, match=r"non-finite value.*initial state"):
        integrate(log_of_state, (0.0, 1.0), [-1.0], args=P)


@pytest.mark.parametrize("method", ["radau", "rodas4", "dopri5"])
def test_a_failure_names_the_method_that_failed(method: str) -> None:
    """The message names the method the user chose; only the explicit one is told to try an
    implicit method."""
    result = integrate(square, (0.0, 2.0), [1.0], args=P, throw=False, method=method)
    assert result.status is IntegrationStatus.STEP_TOO_SMALL
    assert result.message.startswith(f"The {method} integration failed")
    assert ("method='radau'" in result.message) == (method == "dopri5")


def test_failure_as_data_without_raising() -> None:
    result = integrate(square, (0.0, 2.0), [1.0], args=P, throw=False)
    assert not result.success
    assert result.status is IntegrationStatus.STEP_TOO_SMALL
    assert result.status == -1 and "step size fell below" in result.message
    assert result.t[-1] == pytest.approx(1.0, abs=1e-4)  # the blow-up time


# ---------------------------------------------------------------------------------------
# Validation: ConfigError naming the argument.
# ---------------------------------------------------------------------------------------
def _python_rhs(t: float, y: Any, args: Any) -> Any:
    return -y


@pytest.mark.parametrize(
    ("kwargs", "match"),
    [
        ({"fun": _python_rhs}, "fun must be a Numba-jitted function"),
        ({"fun": two_arguments}, "fun does not compile"),
        ({"fun": wrong_length}, r"shape of y0 \(1,\)"),
        ({"step_check": decay}, "step_check does not compile"),
        ({"after_step": lambda t, y, a: False}, "after_step must be a Numba-jitted"),
        ({"t_span": (0.0, math.inf)}, "t_span must be finite"),
        ({"t_span": (0.0,)}, "t_span must be two numbers"),
        ({"y0": [[1.0]]}, "y0 must be a non-empty 1-D array"),
        ({"y0": [math.nan]}, r"y0 must be finite; components \[0\]"),
        ({"args": [np.ones(1)]}, "args must be a tuple"),
        ({"args": (2.0,)}, r"args\[0\] must be a NumPy array"),
        ({"rtol": 1e-16}, "rtol must lie in"),
        ({"rtol": 1.5}, "rtol must lie in"),
        ({"atol": -1.0}, "atol must be finite and >= 0"),
        ({"atol": [1e-6, 1e-6]}, r"atol must be a scalar or have shape \(1,\)"),
        ({"max_step": 0.0}, "max_step must be > 0"),
        ({"first_step": 2.0}, r"first_step must lie in \(0, \|t_bound - t0\|\]"),
        ({"max_steps": 0}, "max_steps must be >= 1"),
        ({"max_steps": 10.0}, "max_steps must be an integer"),
        ({"n_second": 1}, r"need 0 <= 2·n_second <= n_active <= n = 1"),
        ({"n_active": 2}, r"need 0 <= 2·n_second <= n_active <= n = 1"),
        ({"n_second": 0.5}, "n_second must be an integer"),
        ({"jac": _python_rhs}, "jac must be a Numba-jitted function"),
        ({"jac": decay}, "jac does not compile"),
    ],
)
def test_invalid_input_raises_config_error(kwargs: dict[str, Any], match: str) -> None:
    call: dict[str, Any] = {"fun": decay, "t_span": (0.0, 1.0), "y0": [1.0], "args": P}
    call.update(kwargs)
    fun, t_span, y0 = call.pop("fun"), call.pop("t_span"), call.pop("y0")
    with pytest.raises(ConfigError, match=match):
        integrate(fun, t_span, y0, **call)
