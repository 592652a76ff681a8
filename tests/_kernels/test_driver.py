"""The generic integrate on the one integrator loop (:mod:`jointplay._kernels.driver`, issue 38).

Radau IIA, RODAS4 and DOPRI5 run through the lanes' loop (``lanes.source.lane``, every
engine's), each bringing only its step
functions; and a new method is one file: the toy Heun–Euler pair below (order 2 with an
embedded Euler step, Hairer, Nørsett & Wanner, *Solving ODEs I*, §II.4) is five functions
and a :class:`~jointplay._kernels.driver.Steps`, and gets the loop's budget, hooks, onset
retries and statuses without a line of its own for them.
"""

from __future__ import annotations

import math

import numba
import numpy as np

from _ode_problems import (
    CONTACT_PARAMETERS,
    decay,
    dopri_integrate,
    land_on_contact,
    mass_on_floor,
    run_kernel,
)
from jointplay._kernels import driver, ids, radau, rodas
from jointplay._kernels.lanes import build
from jointplay._kernels.lanes.source import dopri_attempt, lane


# ---------------------------------------------------------------------------------------
# A fourth method, in one place: Heun's method with Euler's as the error estimate.
# ---------------------------------------------------------------------------------------
@numba.njit(cache=True, error_model="numpy")
def _heun_start(problem, t0, y0, f0, counters):
    """State: the error norm of the try that passed (1,), ``f`` at the Euler point (n,)."""
    return np.zeros(1), np.empty(y0.shape[0])


@numba.njit(cache=True, error_model="numpy")
def _heun_begin(state, problem, t, y, f, h_abs, min_step, counters):
    return h_abs, problem.max_step


@numba.njit(cache=True, error_model="numpy")
def _heun_attempt(state, problem, t, y, f, h, y_new, counters):
    """Euler to ``t + h``, Heun's trapezoid from it; the error is their difference."""
    sc, f_euler = state
    n = y.shape[0]
    for j in range(n):
        y_new[j] = y[j] + h * f[j]
    f_euler[:] = problem.fun(t + h, y_new, problem.args)
    counters[ids.NFEV] += 1
    total = 0.0
    for j in range(n):
        heun = y[j] + 0.5 * h * (f[j] + f_euler[j])
        scale = problem.atol[j] + problem.rtol * max(abs(y[j]), abs(heun))
        total += ((heun - y_new[j]) / scale) ** 2
        y_new[j] = heun
    error = math.sqrt(total / n)
    if not error <= 1.0:
        counters[ids.NREJ_ERROR] += 1
        shrink = 0.9 * error**-0.5 if math.isfinite(error) else 0.2
        return False, abs(h) * max(0.2, min(1.0, shrink))
    sc[0] = error
    return True, abs(h)


@numba.njit(cache=True, error_model="numpy")
def _heun_accept(state, problem, t, y, t_new, y_new, f, h_abs, failed, changed, counters):
    error = state[0][0]
    grow = 5.0 if error == 0.0 else min(5.0, max(0.2, 0.9 * error**-0.5))
    return h_abs * (min(grow, 1.0) if failed else grow)


HEUN = driver.Steps(
    _heun_start, _heun_begin, _heun_attempt, driver.no_retry, driver.evaluate_f, _heun_accept
)


def heun_integrate(*args, **kwargs):
    return driver.run_core("test_heun", HEUN, *args, **kwargs)


# ---------------------------------------------------------------------------------------
# Tests.
# ---------------------------------------------------------------------------------------
def test_every_method_runs_through_the_one_loop() -> None:
    """Each method's compiled entry is the entry's code with the method's steps as globals,
    and its loop the lanes' (every engine's): one loop, not one per method or engine. DOPRI5
    runs the lanes' own steps (its loop's attempt is the source's)."""
    kernels = {"radau": radau.radau_integrate, "rodas": rodas.rodas_integrate}
    kernels |= {"dopri": dopri_integrate, "test_heun": heun_integrate}
    for integrate in kernels.values():
        result = run_kernel(decay, (0.0, 1.0), [1.0], [1.0], rtol=1e-6, atol=1e-9,
                            integrator=integrate)  # fmt: skip
        assert result.status == ids.STATUS_SUCCESS
    cores = {key[0]: core for key, core in driver._specialisations.items()}
    assert set(kernels) <= set(cores)
    attempts = set()
    for name in kernels:
        assert cores[name].py_func.__code__ is driver.drive.__code__
        loop = cores[name].py_func.__globals__["LANE"].py_func
        assert loop.__code__ is lane.__code__
        if name == "dopri":
            assert loop.__globals__["step_attempt"].py_func.__code__ is dopri_attempt.__code__
            attempts.add(dopri_attempt.__code__)
        else:
            attempt = cores[name].py_func.__globals__["ATTEMPT"].py_func
            assert attempt.__module__ != driver.__name__
            attempts.add(attempt.__code__)
    assert len(attempts) == 4  # the same loop, four different steps


def test_a_new_method_is_its_steps_only() -> None:
    """The toy method solves the decay to its order's accuracy and, through the loop, lands
    steps on an event with ``step_check`` as the three methods do."""
    result = run_kernel(decay, (0.0, 1.0), [1.0, 2.0], [1.0, 3.0], rtol=1e-6, atol=1e-9,
                        integrator=heun_integrate)  # fmt: skip
    np.testing.assert_allclose(result.y[-1], [math.exp(-1.0), 2.0 * math.exp(-3.0)], rtol=1e-4)
    assert result.counts["n_rejected_newton"] == result.counts["njev"] == result.counts["nlu"] == 0

    drop = (mass_on_floor, (0.0, 0.5), [0.1, 0.0])
    atol = 1e-7
    p = CONTACT_PARAMETERS.copy()
    p[4] = atol
    plain = run_kernel(*drop, p.copy(), rtol=1e-4, atol=atol, integrator=heun_integrate)
    landed = run_kernel(*drop, p.copy(), rtol=1e-4, atol=atol, integrator=heun_integrate,
                        step_check=land_on_contact)  # fmt: skip
    assert plain.status == landed.status == ids.STATUS_SUCCESS
    assert plain.counts["n_rejected_check"] == 0 < landed.counts["n_rejected_check"]
    onset = math.sqrt(2 * 0.1 / 9.81)  # free fall from 0.1 m
    on_floor = np.abs(landed.y[:, 0]) <= atol
    assert np.any(on_floor & (np.abs(landed.t - onset) < 1e-6))


def test_the_budget_is_the_loops() -> None:
    """``max_steps`` ends every method, the toy one too, with the same status."""
    for integrate in (radau.radau_integrate, dopri_integrate, heun_integrate):
        result = run_kernel(decay, (0.0, 10.0), [1.0], [1.0], rtol=1e-10, atol=1e-12,
                            max_steps=3, integrator=integrate)  # fmt: skip
        assert result.status == ids.STATUS_TOO_MANY_STEPS
        assert result.counts["n_steps"] == 3
        assert len(result.t) == 4


def test_the_records_are_the_engines_integrators() -> None:
    """Every integrator of the single engine has its steps where its record says; the batch
    engines' methods are those of the integrators their lanes have."""
    from jointplay._kernels import batch
    from jointplay._kernels.capabilities import ENGINES
    from jointplay._kernels.integrators import INTEGRATORS, lane_methods
    from jointplay.dynamics.integrate import METHODS

    assert list(METHODS) == list(ENGINES["single"].integrators) == ["radau", "rodas4", "dopri5"]
    for integrator in METHODS.values():  # a kernel module's Steps, or the lanes' own steps
        steps = driver.steps_of(str(integrator.module))
        assert isinstance(steps, driver.Steps) or steps in build.LANES.values()
    assert lane_methods("lanes-explicit", "batch-implicit") == batch.METHODS
    assert batch.METHODS == ("explicit", "implicit")
    assert [i.name for i in INTEGRATORS.values() if i.explicit] == ["dopri5"]
