"""Tests of the compiled RODAS4 kernel (linearly implicit, order 4).

The same problems as the Radau kernel's tests (``tests/_ode_problems.py``), checked
against exact, published or independent reference solutions (SciPy's LSODA and DOP853 at
tight tolerances), the method's order under fixed steps, and the hooks and statuses it
shares with the Radau driver. Every tolerance is a named constant with its reason.
"""

from __future__ import annotations

from typing import Any

import numba
import numpy as np
import numpy.typing as npt
import pytest

from _ode_problems import (
    CONTACT_PARAMETERS,
    TWO_MASSES,
    TWO_MASSES_Y0,
    contact_drop_reference,
    decay,
    decline_jacobian,
    flag_contact_change,
    harmonic,
    land_on_contact,
    mass_on_floor,
    robertson,
    rodas_integrate,
    run_kernel,
    run_scipy,
    tolerance_units,
    two_masses,
    two_masses_jacobian,
    van_der_pol,
)
from jointplay._kernels import ids
from jointplay._kernels.lanes.cpu import compiled as lanes
from jointplay._kernels.lanes.source_rodas import RODAS_GAMMA

# ---------------------------------------------------------------------------------------
# Named tolerances.
# ---------------------------------------------------------------------------------------
#: Global error against an exact or reference solution, in units of ``atol + rtol·|y|``.
#: The error estimate is the embedded order-3 solution's, so the global error of an order-4
#: method runs a few units: measured 0.93 (decay), 3.8 (stiff Van der Pol), 0.40 and 1.6
#: (Prothero–Robinson at rtol 1e-4 and 1e-6).
GLOBAL_ERROR_UNITS = 10.0
#: The same problem solved with other linear algebra (reduced second-order systems, an
#: exact Jacobian instead of differences): the same method, round-off-tipped decisions;
#: measured ≤ 0.012 units.
SAME_METHOD_UNITS = 0.1
#: Contact drop, onset located by ``step_check``: measured 1.7, 17 and 8.2 units over rtol
#: 1e-4, 1e-6, 1e-8 (the Radau kernel's: 2.5–24).
CONTACT_LOCATED_UNITS = 50.0
#: Contact drop without event location (the damping force jumps at onset): measured 4.9
#: units; the Radau kernel's bound for this regime.
CONTACT_UNLOCATED_UNITS = 200.0

ROD = rodas_integrate


def run(fun: Any, t_span: tuple[float, float], y0: Any, p: Any, **options: Any) -> Any:
    return run_kernel(fun, t_span, y0, p, integrator=ROD, **options)


@numba.njit(cache=True)
def prothero_robinson(t, y, args):
    """y' = λ (y − sin t) + cos t (λ = p[0] ≪ 0): exact solution sin t from y(0) = 0, a
    stiff problem whose right-hand side depends on t."""
    return np.array([args[0][0] * (y[0] - np.sin(t)) + np.cos(t)])


# ---------------------------------------------------------------------------------------
# Method.
# ---------------------------------------------------------------------------------------
def test_stages_are_consistent() -> None:
    """A Rosenbrock method is consistent when the final stage point ``y + Σ A[5] k + k_6``
    reproduces ``y + h f`` to first order; with ``J = 0`` and ``f`` constant it must give
    the exact ``y + h f``, whatever h."""
    f = np.array([2.0, -3.0])
    jac = np.zeros((2, 2))
    for h in (1e-3, 0.5):
        k = np.empty((6, 2))
        stage, x, work = np.empty(2), np.empty(2), np.empty(2)
        lu, piv = np.empty((2, 2)), np.empty(2, dtype=np.int64)
        alpha = 1.0 / (h * RODAS_GAMMA)
        lanes["newton_matrix"](jac, alpha, lu, 0, 2)
        lanes["lu_real"](lu, piv, 2)
        for s in range(6):  # rodas_attempt's stages, f the same at every stage point
            if s > 0:
                lanes["rodas_stage"](k, np.zeros(2), s, stage, 2)
            assert lanes["rodas_right_side"](f, np.zeros(2), k, s, h, x, 2)
            lanes["solve_real"](lu, piv, jac, alpha, x, work, 0, 2, 2)
            k[s] = x
        np.testing.assert_allclose(stage + k[5], h * f, rtol=1e-14)
        np.testing.assert_allclose(k[5], 0.0, atol=1e-14 * h)  # the error estimate: none


def test_fixed_step_order_is_four() -> None:
    """With max_step = first_step = h and loose tolerances every step has size h."""
    steps = np.array([2 * np.pi / n for n in (16, 32, 64)])
    errors = []
    for h in steps:
        result = run(
            harmonic, (0.0, 2 * np.pi), [1.0, 0.0], [0.0], rtol=1e-1, atol=1e-1, max_step=h,
            first_step=h,
        )  # fmt: skip
        assert result.counts["n_rejected_error"] == 0
        np.testing.assert_allclose(np.diff(result.t)[:-1], h, rtol=1e-9)
        errors.append(np.max(np.abs(result.y[-1] - [1.0, 0.0])))
    order = np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert order == pytest.approx(4.0, abs=0.3)  # measured 4.00


def test_global_error_falls_with_tolerance() -> None:
    """Error ∝ tol: the embedded order-3 estimate sets h ∝ tol^(1/4), the global error is
    O(h⁴)."""
    mu = np.array([1.0])
    reference = run_scipy(
        van_der_pol, (0.0, 10.0), [2.0, 0.0], mu, method="DOP853", rtol=1e-13, atol=1e-13
    ).y[:, -1]
    tolerances = 10.0 ** -np.arange(3.0, 10.0)
    errors = [
        np.max(np.abs(run(van_der_pol, (0.0, 10.0), [2.0, 0.0], mu, rtol=tol, atol=tol).y[-1]
                      - reference))
        for tol in tolerances
    ]  # fmt: skip
    slope = np.polyfit(np.log(tolerances), np.log(errors), 1)[0]
    assert np.all(np.diff(np.log(errors)) < 0)
    assert 0.8 <= slope <= 1.2, slope  # measured 0.96


# ---------------------------------------------------------------------------------------
# Reference solutions.
# ---------------------------------------------------------------------------------------
def test_exponential_decay_matches_exact_solution() -> None:
    lam = np.array([1.0, 10.0, 100.0])
    rtol, atol = 1e-6, 1e-9
    result = run(decay, (0.0, 10.0), np.ones(3), lam, rtol=rtol, atol=atol)
    assert result.status == ids.STATUS_SUCCESS and result.t[-1] == 10.0
    assert tolerance_units(result.y, np.exp(-np.outer(result.t, lam)), rtol, atol) < (
        GLOBAL_ERROR_UNITS
    )
    # One Jacobian and one LU per step, no Newton iteration.
    assert result.counts["njev"] == result.counts["n_steps"] == result.counts["nlu"]
    assert result.counts["n_rejected_newton"] == 0


@pytest.mark.parametrize("rtol", [1e-4, 1e-6])
def test_time_dependent_stiff_problem_follows_its_solution(rtol: float) -> None:
    """Prothero–Robinson: the ∂f/∂t term of the stages keeps the solution on sin t (a
    method that left it out would lag behind the forcing by ~1/|λ|·cos t each step)."""
    result = run(prothero_robinson, (0.0, 10.0), [0.0], [-1e4], rtol=rtol, atol=rtol)
    assert result.status == ids.STATUS_SUCCESS
    assert tolerance_units(result.y[:, 0], np.sin(result.t), rtol, rtol) < GLOBAL_ERROR_UNITS


def test_stiff_van_der_pol_matches_reference_in_as_many_steps_as_radau() -> None:
    mu = np.array([1000.0])
    rtol, atol = 1e-6, 1e-6
    result = run(van_der_pol, (0.0, 3000.0), [2.0, 0.0], mu, rtol=rtol, atol=atol)
    radau_run = run_kernel(van_der_pol, (0.0, 3000.0), [2.0, 0.0], mu, rtol=rtol, atol=atol)
    reference = run_scipy(
        van_der_pol, (0.0, 3000.0), [2.0, 0.0], mu, method="LSODA", rtol=1e-12, atol=1e-12
    ).y[:, -1]
    assert result.status == ids.STATUS_SUCCESS
    assert tolerance_units(result.y[-1], reference, rtol, atol) < GLOBAL_ERROR_UNITS
    # Measured 905 against Radau's 919 steps: a stiff problem both resolve alike.
    assert 0.67 < result.counts["n_steps"] / radau_run.counts["n_steps"] < 1.5


def test_robertson_matches_published_values() -> None:
    rtol, atol = 1e-6, np.array([1e-8, 1e-12, 1e-8])
    result = run(robertson, (0.0, 40.0), [1.0, 0.0, 0.0], [0.0], rtol=rtol, atol=atol)
    published = np.array([0.7158271, 0.9185535e-5, 0.2841637])  # as in test_radau.py
    assert result.status == ids.STATUS_SUCCESS
    np.testing.assert_allclose(result.y[-1], published, rtol=2e-6)  # measured 2.6e-7
    # A linear invariant stays: every stage solve is linear (measured 2e-15).
    np.testing.assert_allclose(result.y.sum(axis=1), 1.0, atol=1e-12)


def test_backward_integration_with_first_and_max_step() -> None:
    lam = np.array([1.0, 10.0])
    rtol, atol = 1e-6, 1e-9
    result = run(
        decay, (1.0, -1.0), np.ones(2), lam, rtol=rtol, atol=atol, max_step=0.05,
        first_step=1e-3,
    )  # fmt: skip
    assert result.status == ids.STATUS_SUCCESS
    assert result.t[1] == pytest.approx(1.0 - 1e-3, rel=1e-15)
    assert np.all(np.diff(result.t) < 0) and np.all(-np.diff(result.t) <= 0.05 + 1e-15)
    exact = np.exp(-np.outer(result.t - 1.0, lam))
    assert tolerance_units(result.y, exact, rtol, atol) < GLOBAL_ERROR_UNITS


@pytest.fixture(scope="module")
def contact_reference() -> npt.NDArray[np.float64]:
    return contact_drop_reference()


@pytest.mark.parametrize("rtol", [1e-4, 1e-6, 1e-8])
def test_contact_onset_located_by_step_check(
    rtol: float, contact_reference: npt.NDArray[np.float64]
) -> None:
    atol = rtol * 1e-3
    p = CONTACT_PARAMETERS.copy()
    p[4] = atol
    result = run(
        mass_on_floor, (0.0, 0.5), [0.1, 0.0], p, rtol=rtol, atol=atol,
        step_check=land_on_contact, after_step=flag_contact_change,
    )  # fmt: skip
    assert result.status == ids.STATUS_SUCCESS
    assert result.counts["n_rejected_check"] >= 1
    on_floor = np.abs(result.y[:, 0]) <= atol
    assert np.any(on_floor & (np.abs(result.t - np.sqrt(2 * 0.1 / 9.81)) < 1e-6))
    assert tolerance_units(result.y[-1], contact_reference, rtol, atol) < CONTACT_LOCATED_UNITS


def test_contact_without_location_keeps_the_accuracy(
    contact_reference: npt.NDArray[np.float64],
) -> None:
    """The differenced Jacobian starts afresh at every step: SciPy's adaptive steps, grown
    in free flight where the floor column is zero, once reached across the floor and
    gave a Jacobian a Rosenbrock method cannot live with (100 000 steps of 7e-7 s)."""
    rtol, atol = 1e-6, 1e-9
    result = run(
        mass_on_floor, (0.0, 0.5), [0.1, 0.0], CONTACT_PARAMETERS, rtol=rtol, atol=atol,
        hold_after_failure=True,
    )  # fmt: skip
    assert result.status == ids.STATUS_SUCCESS
    assert result.counts["n_steps"] < 1000
    assert tolerance_units(result.y[-1], contact_reference, rtol, atol) < CONTACT_UNLOCATED_UNITS


# ---------------------------------------------------------------------------------------
# Hooks and structure.
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("rtol", [1e-4, 1e-7])
def test_second_order_and_passive_structure_give_the_same_solution(rtol: float) -> None:
    options: dict[str, Any] = {"rtol": rtol, "atol": 1e-9}
    full = run(two_masses, (0.0, 0.05), TWO_MASSES_Y0, TWO_MASSES, **options)
    reduced = run(
        two_masses, (0.0, 0.05), TWO_MASSES_Y0, TWO_MASSES, n_second=2, n_active=4, **options
    )
    assert full.status == reduced.status == ids.STATUS_SUCCESS
    assert tolerance_units(reduced.y[-1], full.y[-1], rtol, 1e-9) < SAME_METHOD_UNITS
    np.testing.assert_array_equal(reduced.y[:, 5], 2.0)  # the constant component stays put


def test_jacobian_function_replaces_the_differences() -> None:
    rtol, atol = 1e-7, 1e-9
    options: dict[str, Any] = {"rtol": rtol, "atol": atol, "n_second": 2, "n_active": 4}
    differenced = run(two_masses, (0.0, 0.05), TWO_MASSES_Y0, TWO_MASSES, **options)
    exact = run(
        two_masses, (0.0, 0.05), TWO_MASSES_Y0, TWO_MASSES, jac=two_masses_jacobian, **options
    )
    declined = run(
        two_masses, (0.0, 0.05), TWO_MASSES_Y0, TWO_MASSES, jac=decline_jacobian, **options
    )
    assert exact.status == ids.STATUS_SUCCESS
    assert tolerance_units(exact.y[-1], differenced.y[-1], rtol, atol) < SAME_METHOD_UNITS
    np.testing.assert_array_equal(declined.y, differenced.y)
    assert declined.counts == differenced.counts


def test_an_autonomous_problem_skips_the_time_difference() -> None:
    """``autonomous=True`` leaves out the difference of ``f`` in ``t`` (one evaluation per
    step): the same steps and the same bits, as that difference is exactly zero for an
    ``f`` that does not read ``t``. On Prothero–Robinson, which does, the error control
    makes up for the missing term with 1 800 times the steps: the caller's declaration, not
    the default."""
    options: dict[str, Any] = {"rtol": 1e-6, "atol": 1e-9}
    mu = np.array([5.0])
    differenced = run(van_der_pol, (0.0, 5.0), [2.0, 0.0], mu, **options)
    declared = run(van_der_pol, (0.0, 5.0), [2.0, 0.0], mu, autonomous=True, **options)
    np.testing.assert_array_equal(declared.t, differenced.t)
    np.testing.assert_array_equal(declared.y, differenced.y)
    assert declared.counts["nfev"] == differenced.counts["nfev"] - differenced.counts["njev"]
    forced = {"rtol": 1e-4, "atol": 1e-4}
    right = run(prothero_robinson, (0.0, 10.0), [0.0], [-1e4], **forced)
    wrong = run(prothero_robinson, (0.0, 10.0), [0.0], [-1e4], autonomous=True, **forced)
    assert right.counts["n_steps"] < 50  # measured 11
    assert wrong.counts["n_steps"] > 100 * right.counts["n_steps"]  # measured 20 123
