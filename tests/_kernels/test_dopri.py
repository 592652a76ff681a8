"""Tests of the compiled DOPRI5 kernel (explicit Dormand–Prince 5(4)).

The non-stiff problems of the Radau kernel's tests (``tests/_ode_problems.py``), checked
against exact solutions and independent references (SciPy's DOP853 at tight tolerances),
the method's order under fixed steps, and what an explicit driver must do itself: reuse
the last stage as the next step's first, evaluate afresh after a hook changed the state.
The hooks and statuses it shares with Radau and RODAS4 are tested in
``test_kernel_statuses.py``. Every tolerance is a named constant with its reason.
"""

from __future__ import annotations

from typing import Any

import numba
import numpy as np
import numpy.typing as npt
import pytest

from _ode_problems import (
    CONTACT_PARAMETERS,
    decay,
    dopri_integrate,
    flag_contact_change,
    harmonic,
    land_on_contact,
    mass_on_floor,
    run_kernel,
    run_scipy,
    tolerance_units,
    van_der_pol,
)
from jointplay._kernels import driver, ids
from jointplay._kernels.lanes import build, source

#: Global error against an exact or reference solution, in units of ``atol + rtol·|y|``:
#: the error estimate is the embedded order-4 solution's, the solution propagated is of order
#: 5, so the global error stays within a few units (measured 0.26 on the decay).
GLOBAL_ERROR_UNITS = 10.0


def run(fun: Any, t_span: tuple[float, float], y0: Any, p: Any, **options: Any) -> Any:
    return run_kernel(fun, t_span, y0, p, integrator=dopri_integrate, **options)


def test_the_generic_dopri5_runs_the_lanes_own_steps() -> None:
    """DOPRI5 in ``jointplay.integrate`` is the explicit lanes' steps (one copy of the
    tableau's arithmetic for every engine): every step of its loop is the lane source's."""
    loop = driver._core("dopri").__globals__["LANE"].py_func
    for alias in build.STEPS:
        step = loop.__globals__[f"step_{alias}"].py_func
        assert step.__code__ is getattr(source, f"dopri_{alias}").__code__


def test_fixed_step_order_is_five() -> None:
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
    assert order == pytest.approx(5.0, abs=0.3)


def test_global_error_falls_with_tolerance() -> None:
    """Error ∝ tol: the order-4 estimate sets h ∝ tol^(1/5), the order-5 solution's global
    error is O(h⁵)."""
    mu = np.array([1.0])
    reference = run_scipy(
        van_der_pol, (0.0, 10.0), [2.0, 0.0], mu, method="DOP853", rtol=1e-13, atol=1e-13
    ).y[:, -1]
    tolerances = 10.0 ** -np.arange(4.0, 11.0)
    errors = [
        np.max(np.abs(run(van_der_pol, (0.0, 10.0), [2.0, 0.0], mu, rtol=tol, atol=tol).y[-1]
                      - reference))
        for tol in tolerances
    ]  # fmt: skip
    slope = np.polyfit(np.log(tolerances), np.log(errors), 1)[0]
    assert np.all(np.diff(np.log(errors)) < 0)
    assert 0.8 <= slope <= 1.2, slope


def test_exponential_decay_matches_exact_solution() -> None:
    lam = np.array([1.0, 10.0, 100.0])
    rtol, atol = 1e-6, 1e-9
    result = run(decay, (0.0, 10.0), np.ones(3), lam, rtol=rtol, atol=atol)
    assert result.status == ids.STATUS_SUCCESS and result.t[-1] == 10.0
    assert tolerance_units(result.y, np.exp(-np.outer(result.t, lam)), rtol, atol) < (
        GLOBAL_ERROR_UNITS
    )
    # An explicit method: no Jacobian, no LU, no Newton iteration.
    assert result.counts["njev"] == result.counts["nlu"] == result.counts["n_rejected_newton"] == 0


def test_the_last_stage_is_the_next_steps_first() -> None:
    """First same as last: six evaluations per attempted step, plus ``f(t0)`` (the first
    step given, none spent choosing it) — seven would mean the last stage is thrown away."""
    result = run(decay, (0.0, 2.0), [1.0, 1.0], [1.0, 3.0], rtol=1e-8, atol=1e-10,
                 first_step=1e-3)  # fmt: skip
    attempts = result.counts["n_steps"] + result.counts["n_rejected_error"]
    assert result.counts["n_steps"] > 20
    assert result.counts["nfev"] == 1 + 6 * attempts


@numba.njit(cache=True)
def kick_at_one(t, y, args):
    """``after_step`` that doubles the velocity of a harmonic oscillator once, at the first
    step ending at or after t = 1 (args[0][0] is the flag), and says so."""
    if t >= 1.0 and args[0][0] == 0.0:
        args[0][0] = 1.0
        y[1] *= 2.0
        return True
    return False


def test_a_state_changed_by_the_hook_is_evaluated_afresh() -> None:
    """After the kick the solution is the oscillator's from the kicked state; a driver that
    kept the last stage's ``f`` (from the state before the kick) would start the next step
    with the old velocity's derivative and leave the exact solution."""
    rtol, atol = 1e-9, 1e-12
    result = run(harmonic, (0.0, 3.0), [1.0, 0.0], [0.0], rtol=rtol, atol=atol,
                 after_step=kick_at_one)  # fmt: skip
    assert result.status == ids.STATUS_SUCCESS
    kicked = int(np.argmax(result.t >= 1.0))
    t_kick = result.t[kicked]
    x0, v0 = np.cos(t_kick), -2.0 * np.sin(t_kick)
    later = result.t[kicked:] - t_kick
    exact = np.stack([x0 * np.cos(later) + v0 * np.sin(later),
                      -x0 * np.sin(later) + v0 * np.cos(later)], axis=1)  # fmt: skip
    assert tolerance_units(result.y[kicked:], exact, rtol, atol) < GLOBAL_ERROR_UNITS


#: The drop onto an undamped Hertz floor (c = 0: the force is continuous at onset, as the
#: IMPACT law's is, whose damping ramps in from zero).
HERTZ_FLOOR = CONTACT_PARAMETERS.copy()
HERTZ_FLOOR[3] = 0.0


@pytest.fixture(scope="module")
def hertz_floor_reference() -> npt.NDArray[np.float64]:
    """State of the drop at t = 0.5 s from SciPy's DOP853 at rtol 1e-13."""
    return run_scipy(
        mass_on_floor, (0.0, 0.5), [0.1, 0.0], HERTZ_FLOOR, method="DOP853", rtol=1e-13,
        atol=1e-13,
    ).y[:, -1]  # fmt: skip


@pytest.mark.parametrize(("fun", "p"), [(van_der_pol, [1.0]), (mass_on_floor, HERTZ_FLOOR)])
def test_steps_are_scipys_rk45(fun: Any, p: Any) -> None:
    """The same method and step control as SciPy's ``RK45`` (Dormand–Prince 5(4), factor
    0.9·err^(−1/5) within [1/5, 10], no growth after a rejection, the same first step): the
    same steps (times within 1.3e-8 relative, measured) and the same solution within a
    fraction of the tolerance (measured 0.20 and 0.04 units), the floor's impacts included.
    The arithmetic is not SciPy's to the bit, so over a longer run a step decision can tip
    and the two sequences part (seen on Van der Pol, μ = 5, at rtol 1e-9)."""
    y0 = [2.0, 0.0] if fun is van_der_pol else [0.1, 0.0]
    rtol, atol = 1e-6, 1e-9
    ours = run(fun, (0.0, 0.5 if fun is mass_on_floor else 10.0), y0, p, rtol=rtol, atol=atol)
    scipy = run_scipy(fun, (0.0, ours.t[-1]), y0, p, method="RK45", rtol=rtol, atol=atol)
    assert ours.status == ids.STATUS_SUCCESS
    assert ours.t.shape == scipy.t.shape
    np.testing.assert_allclose(ours.t, scipy.t, rtol=1e-7)
    assert tolerance_units(ours.y, scipy.y.T, rtol, atol) < 1.0


#: Contact drop onto the Hertz floor, onset located by ``step_check``: measured 11, 146, 74,
#: 58 and 50 units over rtol 1e-4 to 1e-8 (Radau: 0.2–2.8). The method's own, not the
#: location's: SciPy's RK45 lands 33–263 units off without it. Hence the single engine runs
#: DOPRI5 at a fifth of the tolerances (``EXPLICIT_TOLERANCE_SCALE``), and only on contact
#: that is not stiff.
CONTACT_LOCATED_UNITS = 300.0


@pytest.mark.parametrize("rtol", [1e-4, 1e-6, 1e-8])
def test_contact_onset_located_by_step_check(
    rtol: float, hertz_floor_reference: npt.NDArray[np.float64]
) -> None:
    atol = rtol * 1e-3
    p = HERTZ_FLOOR.copy()
    p[4] = atol
    result = run(
        mass_on_floor, (0.0, 0.5), [0.1, 0.0], p, rtol=rtol, atol=atol,
        step_check=land_on_contact, after_step=flag_contact_change,
    )  # fmt: skip
    assert result.status == ids.STATUS_SUCCESS
    assert result.counts["n_rejected_check"] >= 1
    on_floor = np.abs(result.y[:, 0]) <= atol
    assert np.any(on_floor & (np.abs(result.t - np.sqrt(2 * 0.1 / 9.81)) < 1e-6))
    assert tolerance_units(result.y[-1], hertz_floor_reference, rtol, atol) < (
        CONTACT_LOCATED_UNITS
    )
