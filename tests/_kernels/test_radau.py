"""Tests of the compiled Radau IIA kernel.

Three tiers, as elsewhere in jointplay:

* building blocks: the LU routines against NumPy, the step-size controller against SciPy;
* reference solutions: SciPy's ``solve_ivp(method="Radau")`` (the algorithm this kernel
  ports, run with the *same* jitted right-hand side, so the two differ only in round-off
  and in decisions that round-off tips) and exact or published solutions;
* convergence: the global error against the tolerance, and the order of the method.

There is no separate "uncompiled" run: SciPy's own Radau plays the plain reference.
Every tolerance is a named constant with its reason. The problems live in
``tests/_ode_problems.py``, shared with the RODAS4 kernel's tests.
"""

from __future__ import annotations

from typing import Any

import numpy as np
import numpy.typing as npt
import pytest
from scipy.integrate._ivp import radau as scipy_radau
from scipy.integrate._ivp.radau import predict_factor as scipy_predict_factor

from _ode_problems import (
    CONTACT_PARAMETERS,
    TWO_MASSES,
    TWO_MASSES_Y0,
    assert_counts_close,
    contact_drop_reference,
    decay,
    decline_jacobian,
    flag_contact_change,
    harmonic,
    land_on_contact,
    mass_on_floor,
    robertson,
    run_kernel,
    run_scipy,
    tolerance_units,
    two_masses,
    two_masses_jacobian,
    van_der_pol,
    van_der_pol_with_idle_component,
)
from jointplay._kernels import ids
from jointplay._kernels.lanes import source_radau
from jointplay._kernels.lanes.cpu import compiled as lanes

# ---------------------------------------------------------------------------------------
# Named tolerances.
# ---------------------------------------------------------------------------------------
#: Kernel vs SciPy on smooth problems, in units of the error tolerance
#: ``atol + rtol·|y|``: the two run the same algorithm on the same f, so they differ by
#: round-off amplified through the steps (measured ≤ 2e-5 units); 1e-2 leaves margin for
#: a round-off-tipped step-size decision while staying far below the tolerance itself.
SMOOTH_AGREEMENT_UNITS = 1e-2
#: Kernel vs SciPy step and evaluation counts on smooth problems: identical when measured
#: (decay 242, Van der Pol 919, Robertson 188 steps); ±10 % allows a tipped decision.
SMOOTH_COUNT_RATIO = 1.10
#: Global error against an exact or reference solution, in tolerance units. A
#: variable-step method controls the *local* error; the global error of these runs was
#: measured at ≤ 0.4 units (decay, Van der Pol, Robertson); 5 units is the usual margin.
GLOBAL_ERROR_UNITS = 5.0
#: Contact problem without event location: the damping term makes the force jump by
#: ``c·|v|`` at contact onset, a discontinuity no step-size controller resolves; the
#: error then depends on where a step happens to straddle the onset. Measured global
#: errors at rtol 1e-6: kernel 37, SciPy 39 units; over rtol 1e-3…1e-8, up to ~900
#: (either code). The bound checks both stay in that regime, not a tight accuracy.
CONTACT_UNLOCATED_UNITS = 200.0
#: Kernel vs SciPy step counts on the contact problem (148 vs 157 measured at rtol 1e-6):
#: the jump at onset makes the rejection sequence round-off sensitive.
CONTACT_COUNT_RATIO = 1.5
#: Deepest penetration of the contact problem, kernel against SciPy (relative): measured
#: 3.0e-6 at rtol 1e-6; about 10x.
CONTACT_PEAK_RTOL = 3e-5
#: Contact problem with onset landed on by ``step_check`` and flagged by ``after_step``:
#: measured 2.5–24 units over rtol 1e-3…1e-8.
CONTACT_LOCATED_UNITS = 50.0


# ---------------------------------------------------------------------------------------
# Building blocks.
# ---------------------------------------------------------------------------------------
#: The Radau IIA constants of the source (:mod:`jointplay._kernels.lanes.source_radau`, the one
#: copy the single engine and the lanes run), as SciPy's ``radau`` module names them.
_CONSTANTS = {
    "C": [source_radau.RC1, source_radau.RC2, source_radau.RC3],
    "E": [source_radau.RE1, source_radau.RE2, source_radau.RE3],
    "MU_REAL": source_radau.MU_REAL,
    "MU_COMPLEX": complex(source_radau.MU_COMPLEX_RE, source_radau.MU_COMPLEX_IM),
    "T": np.reshape(source_radau.RT, (3, 3)),
    "TI": np.reshape(source_radau.RTI, (3, 3)),
    "P": np.reshape(source_radau.RP, (3, 3)),
    "NEWTON_MAXITER": source_radau.NEWTON_MAXITER,
    "MIN_FACTOR": source_radau.R_MIN_FACTOR,
    "MAX_FACTOR": source_radau.R_MAX_FACTOR,
}


@pytest.mark.parametrize("name", sorted(_CONSTANTS))
def test_method_constants_are_scipys(name: str) -> None:
    np.testing.assert_array_equal(_CONSTANTS[name], getattr(scipy_radau, name))


def _lu_solve(a: np.ndarray, b: np.ndarray) -> np.ndarray:
    """``a⁻¹ b`` by the source's LU (real, or complex as pairs of floats)."""
    n = a.shape[0]
    piv = np.zeros(n, dtype=np.int64)
    if not np.iscomplexobj(a):
        lu, x = a.copy(), b.copy()
        lanes["lu_real"](lu, piv, n)
        lanes["lu_solve_real"](lu, piv, x, n)
        return x
    re, im = a.real.copy(), a.imag.copy()
    xr, xi = b.real.copy(), b.imag.copy()
    lanes["lu_complex"](re, im, piv, n)
    lanes["lu_solve_complex"](re, im, piv, xr, xi, n)
    return xr + 1j * xi


@pytest.mark.parametrize("n", [1, 2, 5, 17, 60])
@pytest.mark.parametrize("dtype", [np.float64, np.complex128])
def test_lu_solve_matches_numpy(n: int, dtype: type) -> None:
    rng = np.random.default_rng(n)
    a = rng.standard_normal((n, n))
    b = rng.standard_normal(n)
    if dtype is np.complex128:
        a = a + 1j * rng.standard_normal((n, n))
        b = b + 1j * rng.standard_normal(n)
    if n > 1:
        a[0, 0] = 0.0  # forces a row interchange
    x = _lu_solve(a, b)
    # Partial pivoting is backward stable: residual ~ eps·cond; these matrices have
    # cond < 1e4, so 1e-10 relative is a loose, round-off-only bound.
    np.testing.assert_allclose(x, np.linalg.solve(a, b), rtol=1e-10, atol=1e-12)


@pytest.mark.parametrize("gamma", [source_radau.MU_REAL, _CONSTANTS["MU_COMPLEX"]])
@pytest.mark.parametrize(
    ("n_second", "n_active", "n"), [(0, 5, 5), (3, 6, 6), (3, 7, 9), (0, 4, 6)]
)
def test_reduced_newton_solve_equals_full_solve(
    gamma: complex, n_second: int, n_active: int, n: int
) -> None:
    """The reduced factors solve the full system (γ/h·I − J) x = b for a Jacobian with the
    declared structure: rows [0, m) = [0, I, 0], columns from n_active on zero."""
    rng = np.random.default_rng(n + n_active)
    h = 1e-3
    jac = rng.standard_normal((n, n)) * 1e3
    jac[:n_second] = 0.0
    jac[:n_second, n_second : 2 * n_second] = np.eye(n_second)
    jac[:, n_active:] = 0.0
    b = rng.standard_normal(n) + (1j * rng.standard_normal(n) if np.iscomplexobj(gamma) else 0)
    nk = n_active - n_second
    a_re, c_re, c_im = np.empty((nk, nk)), np.empty((nk, nk)), np.empty((nk, nk))
    piv_re, piv_c = np.zeros(nk, dtype=np.int64), np.zeros(nk, dtype=np.int64)
    rows = jac[n_second:]
    lanes["factor_newton"](rows, h, a_re, piv_re, c_re, c_im, piv_c, n_second, nk)
    if np.iscomplexobj(gamma):
        xr, xi = b.real.copy(), b.imag.copy()
        mu = gamma / h
        lanes["solve_complex"](c_re, c_im, piv_c, rows, mu.real, mu.imag, xr, xi,
                               np.empty(nk), np.empty(nk), n_second, nk, n)  # fmt: skip
        x = xr + 1j * xi
    else:
        x = b.real.copy()
        lanes["solve_real"](a_re, piv_re, rows, gamma / h, x, np.empty(nk), n_second, nk, n)
    # Round-off only: cond(γ/h·I − J) < 1e3 here, so 1e-10 relative is loose.
    np.testing.assert_allclose(x, np.linalg.solve(gamma / h * np.eye(n) - jac, b), rtol=1e-10)


def test_lu_of_singular_matrix_gives_non_finite_not_an_error() -> None:
    x = _lu_solve(np.array([[1.0, 2.0], [2.0, 4.0]]), np.array([1.0, 1.0]))
    assert not np.all(np.isfinite(x))


@pytest.mark.parametrize(
    ("h_abs", "h_abs_old", "error_norm", "error_norm_old"),
    [(0.1, None, 0.5, None), (0.1, 0.05, 2.0, 0.3), (0.2, 0.1, 0.01, 0.9), (0.1, 0.1, 0.0, 0.5)],
)
def test_step_size_controller_matches_scipy(
    h_abs: float, h_abs_old: float | None, error_norm: float, error_norm_old: float | None
) -> None:
    expected = scipy_predict_factor(h_abs, h_abs_old, np.float64(error_norm), error_norm_old)
    got = lanes["predict"](
        h_abs,
        np.nan if h_abs_old is None else h_abs_old,
        error_norm,
        np.nan if error_norm_old is None else error_norm_old,
    )
    assert got == pytest.approx(expected, rel=1e-15)


# ---------------------------------------------------------------------------------------
# Reference solutions.
# ---------------------------------------------------------------------------------------
def test_exponential_decay_matches_exact_solution_and_scipy() -> None:
    lam = np.array([1.0, 10.0, 100.0])
    rtol, atol = 1e-6, 1e-9
    run = run_kernel(decay, (0.0, 10.0), np.ones(3), lam, rtol=rtol, atol=atol)
    sol = run_scipy(decay, (0.0, 10.0), np.ones(3), lam, rtol=rtol, atol=atol)
    assert run.status == ids.STATUS_SUCCESS
    assert run.t[-1] == 10.0
    exact = np.exp(-np.outer(run.t, lam))
    assert tolerance_units(run.y, exact, rtol, atol) < GLOBAL_ERROR_UNITS
    assert tolerance_units(run.y[-1], sol.y[:, -1], rtol, atol) < SMOOTH_AGREEMENT_UNITS
    assert_counts_close(run, sol, SMOOTH_COUNT_RATIO)


def test_stiff_van_der_pol_matches_scipy_and_reference() -> None:
    mu = np.array([1000.0])
    rtol, atol = 1e-6, 1e-6
    y0 = [2.0, 0.0]
    run = run_kernel(van_der_pol, (0.0, 3000.0), y0, mu, rtol=rtol, atol=atol)
    sol = run_scipy(van_der_pol, (0.0, 3000.0), y0, mu, rtol=rtol, atol=atol)
    # Reference: LSODA at rtol = atol = 1e-12 (agrees with SciPy's Radau at 1e-10 to
    # 1e-9); an independent (BDF/Adams) method.
    reference = run_scipy(
        van_der_pol, (0.0, 3000.0), y0, mu, method="LSODA", rtol=1e-12, atol=1e-12
    ).y[:, -1]
    assert run.status == ids.STATUS_SUCCESS
    assert run.t.shape[0] > 64  # the recording arrays grew
    assert tolerance_units(run.y[-1], sol.y[:, -1], rtol, atol) < SMOOTH_AGREEMENT_UNITS
    assert tolerance_units(run.y[-1], reference, rtol, atol) < GLOBAL_ERROR_UNITS
    assert_counts_close(run, sol, SMOOTH_COUNT_RATIO)


def test_robertson_matches_scipy_and_published_values() -> None:
    rtol, atol = 1e-6, np.array([1e-8, 1e-12, 1e-8])
    y0 = [1.0, 0.0, 0.0]
    run = run_kernel(robertson, (0.0, 40.0), y0, [0.0], rtol=rtol, atol=atol)
    sol = run_scipy(robertson, (0.0, 40.0), y0, [0.0], rtol=rtol, atol=atol)
    # y(40) from the IVP test set (Hairer & Wanner II, §IV.10; Mazzia & Magherini), 7
    # significant digits as published: rounding (≤ 2e-7 relative) plus this run's global
    # error (measured ≤ 2e-7 relative) stay well inside 2e-6.
    published = np.array([0.7158271, 0.9185535e-5, 0.2841637])
    assert run.status == ids.STATUS_SUCCESS
    np.testing.assert_allclose(run.y[-1], published, rtol=2e-6)
    # Mass conservation y1 + y2 + y3 = 1: Runge–Kutta methods keep linear invariants,
    # and so do the Newton increments up to the finite-difference Jacobian's error in
    # (1, 1, 1)·J = 0; measured 2e-16.
    np.testing.assert_allclose(run.y.sum(axis=1), 1.0, atol=1e-12)
    assert tolerance_units(run.y[-1], sol.y[:, -1], rtol, atol) < SMOOTH_AGREEMENT_UNITS
    assert_counts_close(run, sol, SMOOTH_COUNT_RATIO)


def test_backward_integration_with_first_and_max_step_matches_scipy() -> None:
    lam = np.array([1.0, 10.0])
    options: dict[str, Any] = {"rtol": 1e-6, "atol": 1e-9, "max_step": 0.05, "first_step": 1e-3}
    run = run_kernel(decay, (1.0, -1.0), np.ones(2), lam, **options)
    sol = run_scipy(decay, (1.0, -1.0), np.ones(2), lam, **options)
    assert run.status == ids.STATUS_SUCCESS
    assert run.t[1] == pytest.approx(1.0 - 1e-3, rel=1e-15)
    assert np.all(np.diff(run.t) < 0) and np.all(-np.diff(run.t) <= 0.05 + 1e-15)
    assert tolerance_units(run.y[-1], sol.y[:, -1], 1e-6, 1e-9) < SMOOTH_AGREEMENT_UNITS
    assert_counts_close(run, sol, SMOOTH_COUNT_RATIO)


@pytest.fixture(scope="module")
def contact_reference() -> npt.NDArray[np.float64]:
    return contact_drop_reference()


def test_contact_drop_matches_scipy(contact_reference: npt.NDArray[np.float64]) -> None:
    rtol, atol = 1e-6, 1e-9
    run = run_kernel(
        mass_on_floor, (0.0, 0.5), [0.1, 0.0], CONTACT_PARAMETERS, rtol=rtol, atol=atol
    )
    sol = run_scipy(mass_on_floor, (0.0, 0.5), [0.1, 0.0], CONTACT_PARAMETERS, rtol=rtol, atol=atol)
    assert run.status == ids.STATUS_SUCCESS
    # Identical up to the step that first reaches the floor (free fall is integrated
    # exactly, so the error estimate there is pure round-off and tips the next decision).
    before = run.t < 0.14
    np.testing.assert_allclose(run.y[before], sol.y.T[: before.sum()], rtol=1e-12, atol=1e-15)
    # Peak penetration and rebound: the physics agrees.
    assert run.y[:, 0].min() == pytest.approx(sol.y[0].min(), rel=CONTACT_PEAK_RTOL)
    assert tolerance_units(run.y[-1], contact_reference, rtol, atol) < CONTACT_UNLOCATED_UNITS
    assert tolerance_units(sol.y[:, -1], contact_reference, rtol, atol) < CONTACT_UNLOCATED_UNITS
    assert_counts_close(run, sol, CONTACT_COUNT_RATIO)


@pytest.mark.parametrize("rtol", [1e-4, 1e-6, 1e-8])
def test_contact_onset_located_by_step_check(
    rtol: float, contact_reference: npt.NDArray[np.float64]
) -> None:
    atol = rtol * 1e-3
    p = CONTACT_PARAMETERS.copy()
    p[4] = atol  # land within atol of the floor
    run = run_kernel(
        mass_on_floor,
        (0.0, 0.5),
        [0.1, 0.0],
        p,
        rtol=rtol,
        atol=atol,
        step_check=land_on_contact,
        after_step=flag_contact_change,
    )
    assert run.status == ids.STATUS_SUCCESS
    assert run.counts["n_rejected_check"] >= 1
    # A recorded step lands on the floor (|x| <= δ_tol) at the free-fall impact time.
    on_floor = np.abs(run.y[:, 0]) <= atol
    t_impact = np.sqrt(2 * 0.1 / 9.81)
    assert np.any(on_floor & (np.abs(run.t - t_impact) < 1e-6))
    assert tolerance_units(run.y[-1], contact_reference, rtol, atol) < CONTACT_LOCATED_UNITS


# ---------------------------------------------------------------------------------------
# Convergence.
# ---------------------------------------------------------------------------------------
def test_global_error_falls_with_tolerance() -> None:
    """Error ∝ tol^(5/4): local error estimate O(h⁴) sets h ∝ tol^(1/4); global error O(h⁵)."""
    mu = np.array([1.0])
    reference = run_scipy(
        van_der_pol, (0.0, 10.0), [2.0, 0.0], mu, method="DOP853", rtol=1e-13, atol=1e-13
    ).y[:, -1]
    tolerances = 10.0 ** -np.arange(3.0, 10.0)
    errors = []
    for tol in tolerances:
        run = run_kernel(van_der_pol, (0.0, 10.0), [2.0, 0.0], mu, rtol=tol, atol=tol)
        errors.append(np.max(np.abs(run.y[-1] - reference)))
    slope = np.polyfit(np.log(tolerances), np.log(errors), 1)[0]
    assert np.all(np.diff(np.log(errors)) < np.log(2.0))  # never grows by more than 2x
    assert 1.0 <= slope <= 1.6, slope  # measured 1.31


def test_fixed_step_order_is_five() -> None:
    """With max_step = first_step = h and loose tolerances every step has size h."""
    steps = np.array([2 * np.pi / n for n in (8, 16, 32)])
    errors = []
    for h in steps:
        run = run_kernel(
            harmonic,
            (0.0, 2 * np.pi),
            [1.0, 0.0],
            [0.0],
            rtol=1e-2,
            atol=1e-2,
            max_step=h,
            first_step=h,
        )
        assert run.counts["n_rejected_error"] == 0
        np.testing.assert_allclose(np.diff(run.t), h, rtol=1e-9)
        errors.append(np.max(np.abs(run.y[-1] - [1.0, 0.0])))
    order = np.polyfit(np.log(steps), np.log(errors), 1)[0]
    assert order == pytest.approx(5.0, abs=0.3)  # Radau IIA, 3 stages: order 2s − 1 = 5


# ---------------------------------------------------------------------------------------
# Hooks.
# ---------------------------------------------------------------------------------------
@pytest.mark.parametrize("rtol", [1e-4, 1e-7])
def test_second_order_and_passive_structure_give_the_same_solution(rtol: float) -> None:
    """n_second and n_active change the linear algebra, not the method: the same steps up
    to round-off-tipped decisions, and a fraction of the Jacobian's evaluations."""
    atol = 1e-9
    options: dict[str, Any] = {"rtol": rtol, "atol": atol}
    full = run_kernel(two_masses, (0.0, 0.05), TWO_MASSES_Y0, TWO_MASSES, **options)
    reduced = run_kernel(
        two_masses, (0.0, 0.05), TWO_MASSES_Y0, TWO_MASSES, n_second=2, n_active=4, **options
    )
    sol = run_scipy(two_masses, (0.0, 0.05), TWO_MASSES_Y0, TWO_MASSES, **options)
    assert full.status == reduced.status == ids.STATUS_SUCCESS
    assert tolerance_units(reduced.y[-1], full.y[-1], rtol, atol) < SMOOTH_AGREEMENT_UNITS
    assert tolerance_units(reduced.y[-1], sol.y[:, -1], rtol, atol) < SMOOTH_AGREEMENT_UNITS
    assert_counts_close(reduced, sol, SMOOTH_COUNT_RATIO, steps_only=True)
    np.testing.assert_array_equal(reduced.y[:, 5], 2.0)  # the constant component stays put


def test_jacobian_function_replaces_the_differences() -> None:
    rtol, atol = 1e-7, 1e-9
    structure: dict[str, Any] = {"n_second": 2, "n_active": 4}
    differenced = run_kernel(
        two_masses, (0.0, 0.05), TWO_MASSES_Y0, TWO_MASSES, rtol=rtol, atol=atol, **structure
    )
    exact = run_kernel(
        two_masses, (0.0, 0.05), TWO_MASSES_Y0, TWO_MASSES, rtol=rtol, atol=atol,
        jac=two_masses_jacobian, **structure,
    )  # fmt: skip
    declined = run_kernel(
        two_masses, (0.0, 0.05), TWO_MASSES_Y0, TWO_MASSES, rtol=rtol, atol=atol,
        jac=decline_jacobian, **structure,
    )  # fmt: skip
    assert exact.status == ids.STATUS_SUCCESS
    # The exact Jacobian changes the Newton iterates (not what they converge to).
    assert tolerance_units(exact.y[-1], differenced.y[-1], rtol, atol) < SMOOTH_AGREEMENT_UNITS
    # A jac that declines leaves the differences, bit for bit.
    np.testing.assert_array_equal(declined.y, differenced.y)
    assert declined.counts == differenced.counts


def test_hold_after_failure_changes_nothing_without_rejections() -> None:
    lam = np.array([1.0, 10.0, 100.0])
    options: dict[str, Any] = {"rtol": 1e-6, "atol": 1e-9}
    scipy_like = run_kernel(decay, (0.0, 10.0), np.ones(3), lam, **options)
    held = run_kernel(decay, (0.0, 10.0), np.ones(3), lam, hold_after_failure=True, **options)
    assert scipy_like.counts["n_rejected_error"] == scipy_like.counts["n_rejected_newton"] == 0
    np.testing.assert_array_equal(held.y, scipy_like.y)


def test_hold_after_failure_on_contact_keeps_the_accuracy(
    contact_reference: npt.NDArray[np.float64],
) -> None:
    """RADAU5's growth limit after rejections: the same accuracy regime as SciPy's
    controller on the unlocated contact drop."""
    rtol, atol = 1e-6, 1e-9
    held = run_kernel(
        mass_on_floor, (0.0, 0.5), [0.1, 0.0], CONTACT_PARAMETERS, rtol=rtol, atol=atol,
        hold_after_failure=True,
    )  # fmt: skip
    assert held.status == ids.STATUS_SUCCESS
    assert held.counts["n_rejected_error"] + held.counts["n_rejected_newton"] > 0
    assert tolerance_units(held.y[-1], contact_reference, rtol, atol) < CONTACT_UNLOCATED_UNITS


def test_difference_factor_of_an_idle_component_stays_finite() -> None:
    """SciPy's factor of a column f does not depend on grows 10x per Jacobian without bound
    (inf after ~316 Jacobians, then a NaN Jacobian); the kernel caps it."""
    run = run_kernel(
        van_der_pol_with_idle_component, (0.0, 6000.0), [2.0, 0.0, 1.0], [1000.0],
        rtol=1e-8, atol=1e-6,
    )  # fmt: skip
    assert run.counts["njev"] > 400
    assert run.status == ids.STATUS_SUCCESS
