"""The generic integrate on the one integrator loop (:mod:`jointplay._kernels.driver`, issue 38).

Radau IIA, RODAS4 and DOPRI5 run through the lanes' loop (``lanes.source.lane``, every
engine's) with the lanes' own steps (``radau_*``, ``rodas_*``, ``dopri_*`` of the lane source):
one loop and one set of steps per method, for every engine.
"""

from __future__ import annotations

import numba
import numpy as np
import pytest

from _ode_problems import (
    decay,
    dopri_integrate,
    radau_integrate,
    rodas_integrate,
    run_kernel,
    van_der_pol,
)
from jointplay._kernels import driver, ids
from jointplay._kernels.lanes import build
from jointplay._kernels.lanes.source import lane

INTEGRATES = {"radau": radau_integrate, "rodas": rodas_integrate, "dopri": dopri_integrate}


@numba.njit(cache=True)
def van_der_pol_jacobian(t, y, f, args, out):
    """∂f/∂y of ``van_der_pol``."""
    mu = args[0][0]
    out[0, 0], out[0, 1] = 0.0, 1.0
    out[1, 0], out[1, 1] = -2.0 * mu * y[0] * y[1] - 1.0, mu * (1.0 - y[0] * y[0])
    return True


@numba.njit(cache=True)
def mirrored_van_der_pol(t, y, args):
    """The Van der Pol oscillator run backwards in time: −f(−t, y)."""
    return -van_der_pol(-t, y, args)


@numba.njit(cache=True)
def mirrored_jacobian(t, y, f, args, out):
    """Its ∂/∂y: −J(−t, y)."""
    van_der_pol_jacobian(-t, y, f, args, out)
    for i in range(2):
        for j in range(2):
            out[i, j] = -out[i, j]
    return True


def test_every_method_runs_the_lanes_loop_and_steps() -> None:
    """Each method's compiled entry is the entry's code with its loop the lanes' (every
    engine's), and every step of that loop the lane source's function of the method's
    prefix: one loop, one set of steps per method, not one per engine."""
    for integrate in INTEGRATES.values():
        result = run_kernel(decay, (0.0, 1.0), [1.0], [1.0], rtol=1e-6, atol=1e-9,
                            integrator=integrate)  # fmt: skip
        assert result.status == ids.STATUS_SUCCESS
    cores = {key[0]: core for key, core in driver._specialisations.items()}
    attempts = set()
    for name in INTEGRATES:
        assert cores[name].py_func.__code__ is driver.drive.__code__
        loop = cores[name].py_func.__globals__["LANE"].py_func
        assert loop.__code__ is lane.__code__
        for alias in build.STEPS:
            step = loop.__globals__[f"step_{alias}"].py_func
            assert step.__code__ is build.source_function(f"{name}_{alias}").__code__
        attempts.add(loop.__globals__["step_attempt"].py_func.__code__)
    assert len(attempts) == 3  # the same loop, three different steps


@pytest.mark.parametrize("name", list(INTEGRATES))
def test_backwards_is_forwards_mirrored(name: str) -> None:
    """Lane time is ``direction·t``: integrating the mirrored problem backwards takes the
    same steps as forwards, to the bit (negation commutes with rounding). With the exact
    Jacobian: differences would step in the direction of each user's f (SciPy's), which the
    mirror turns round."""
    forwards = run_kernel(van_der_pol, (0.0, 2.0), [2.0, 0.0], [5.0], rtol=1e-6, atol=1e-8,
                          jac=van_der_pol_jacobian, integrator=INTEGRATES[name])  # fmt: skip
    backwards = run_kernel(mirrored_van_der_pol, (0.0, -2.0), [2.0, 0.0], [5.0], rtol=1e-6,
                           atol=1e-8, jac=mirrored_jacobian,
                           integrator=INTEGRATES[name])  # fmt: skip
    assert forwards.status == backwards.status == ids.STATUS_SUCCESS
    np.testing.assert_array_equal(backwards.t, -forwards.t)
    np.testing.assert_array_equal(backwards.y, forwards.y)
    assert backwards.counts == forwards.counts


def test_the_budget_is_the_loops() -> None:
    """``max_steps`` ends every method with the same status."""
    for integrate in INTEGRATES.values():
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
    for integrator in METHODS.values():  # the lanes' own steps
        record = driver.steps_of(integrator.steps)
        assert record in build.LANES.values() and record["integrator"]["name"] == integrator.name
    assert lane_methods("lanes-explicit", "batch-implicit") == batch.METHODS
    assert batch.METHODS == ("explicit", "implicit")
    assert [i.name for i in INTEGRATORS.values() if i.explicit] == ["dopri5"]
