"""Test problems for the compiled integrators (Radau IIA, RODAS4) and the helpers that run
them: every right-hand side and hook is jitted with ``cache=True`` and takes the same
``args`` type, a 1-tuple of float64 arrays, so each driver compiles (or loads from the
cache) once. Exact, published or reference solutions are named where a problem is.
"""

from __future__ import annotations

import functools
from typing import Any, NamedTuple

import numba
import numpy as np
import numpy.typing as npt
from scipy.integrate import solve_ivp

from jointplay._kernels import driver, ids


# ---------------------------------------------------------------------------------------
# Problems. Every function takes args = (p,), p a float64 array.
# ---------------------------------------------------------------------------------------
@numba.njit(cache=True)
def decay(t, y, args):
    """Linear decay y_i' = −λ_i y_i, λ = p; exact solution y_i(0)·exp(−λ_i t)."""
    return -args[0] * y


@numba.njit(cache=True)
def van_der_pol(t, y, args):
    """Van der Pol oscillator y'' = μ(1 − y²)y' − y, μ = p[0] (stiff for μ = 1000)."""
    mu = args[0][0]
    return np.array([y[1], mu * (1.0 - y[0] * y[0]) * y[1] - y[0]])


@numba.njit(cache=True)
def robertson(t, y, args):
    """Robertson's chemical kinetics (Hairer & Wanner II, §IV.1, (1.3))."""
    return np.array(
        [
            -0.04 * y[0] + 1e4 * y[1] * y[2],
            0.04 * y[0] - 1e4 * y[1] * y[2] - 3e7 * y[1] * y[1],
            3e7 * y[1] * y[1],
        ]
    )


@numba.njit(cache=True)
def harmonic(t, y, args):
    """Harmonic oscillator y'' = −y; exact solution (cos t, −sin t) from (1, 0)."""
    return np.array([y[1], -y[0]])


@numba.njit(cache=True)
def mass_on_floor(t, y, args):
    """A mass falling onto a stiff damped floor; y = (height x [m], velocity v [m/s]).

    p = (m [kg], g [m/s²], k [N/m^1.5], c [N·s/m], δ_tol [m], in_contact flag). The
    floor force is F = max(0, k·δ^1.5 + c·δ̇) for penetration δ = −x > 0 (a Hertz
    spring with linear damping; Lankarani & Nikravesh, J. Mech. Des. 112, 1990, use the
    Hertz term), and 0 otherwise.
    """
    p = args[0]
    force = 0.0
    if y[0] < 0.0:
        force = max(0.0, p[2] * (-y[0]) ** 1.5 - p[3] * y[1])
    return np.array([y[1], -p[1] + force / p[0]])


@numba.njit(cache=True)
def land_on_contact(t_old, y_old, t_new, y_new, args):
    """Retry a step that enters the floor deeper than δ_tol, by linear interpolation."""
    tol = args[0][4]
    if y_old[0] > 0.0 and y_new[0] < -tol:
        return y_old[0] / (y_old[0] - y_new[0])
    return 1.0


@numba.njit(cache=True)
def flag_contact_change(t, y, args):
    """Remember contact in p[5]; report a change (the force law switched)."""
    p = args[0]
    inside = 1.0 if y[0] < 0.0 else 0.0
    changed = inside != p[5]
    p[5] = inside
    return changed


@numba.njit(cache=True)
def free_fall(t, y, args):
    """Ballistic flight y = (height [m], velocity [m/s]); p = (g, e, δ_tol)."""
    return np.array([y[1], -args[0][0]])


@numba.njit(cache=True)
def land_on_ground(t_old, y_old, t_new, y_new, args):
    """Retry a step whose end is below the ground by more than δ_tol (linear estimate)."""
    tol = args[0][2]
    if y_old[0] > 0.0 and y_new[0] < -tol:
        return y_old[0] / (y_old[0] - y_new[0])
    return 1.0


@numba.njit(cache=True)
def bounce(t, y, args):
    """On the ground and falling: reverse the velocity with restitution e = p[1]."""
    if y[0] <= 0.0 and y[1] < 0.0:
        y[0] = 0.0
        y[1] = -args[0][1] * y[1]
        return True
    return False


@numba.njit(cache=True)
def cartesian_pendulum(t, y, args):
    """Pendulum of length L = p[1] in Cartesian coordinates y = (x, z, ẋ, ż), gravity −z.

    The rod force keeps ``|r| = L`` at acceleration level only,
    λ/m = (|v|² − g z)/L², so the position drifts off the circle.
    """
    g = args[0][0]
    length = args[0][1]
    lam = (y[2] * y[2] + y[3] * y[3] - g * y[1]) / (length * length)
    return np.array([y[2], y[3], -lam * y[0], -g - lam * y[1]])


@numba.njit(cache=True)
def project_on_circle(t, y, args):
    """Project position onto |r| = L and velocity onto the tangent (in place)."""
    length = args[0][1]
    r = np.sqrt(y[0] * y[0] + y[1] * y[1])
    y[0] *= length / r
    y[1] *= length / r
    radial = (y[0] * y[2] + y[1] * y[3]) / (length * length)
    y[2] -= radial * y[0]
    y[3] -= radial * y[1]
    return False


@numba.njit(cache=True)
def square(t, y, args):
    """y' = y², which blows up at t = 1/y(0)."""
    return y * y


@numba.njit(cache=True)
def poison_state(t, y, args):
    """after_step that writes NaN into the state once t > p[0]."""
    if t > args[0][0]:
        y[0] = np.nan
    return False


@numba.njit(cache=True)
def nan_rhs(t, y, args):
    """A right-hand side that is NaN everywhere."""
    return np.full(y.shape[0], np.nan)


@numba.njit(cache=True)
def always_halve(t_old, y_old, t_new, y_new, args):
    """step_check that never accepts: exercises the guard against endless retries."""
    return 0.5


@numba.njit(cache=True)
def odd_theta(t_old, y_old, t_new, y_new, args):
    """step_check returning NaN, 0 or a negative θ: all must mean "accept"."""
    k = int(t_new * 1e3) % 3
    return np.nan if k == 0 else (0.0 if k == 1 else -1.0)


@numba.njit(cache=True)
def two_masses(t, y, args):
    """Two unit masses on a stiff spring chain, second-order form, with passive components.

    y = (x1, x2, v1, v2, W, c2): positions, velocities, the work W dissipated by the
    dampers (a quadrature: nothing depends on it) and the damping c2 of the second mass
    (constant in the ODE: its rate is 0, as the contact memory of the simulator).
    p = (k1 [N/m], c1 [N·s/m], k3 [N/m³]); the coupling spring is cubic (nonlinear).
    """
    k1, c1, k3 = args[0][0], args[0][1], args[0][2]
    x1, x2, v1, v2, c2 = y[0], y[1], y[2], y[3], y[5]
    coupling = k3 * (x2 - x1) ** 3
    a1 = -k1 * x1 - c1 * v1 + coupling
    a2 = -coupling - c2 * v2
    return np.array([v1, v2, a1, a2, c1 * v1 * v1 + c2 * v2 * v2, 0.0])


@numba.njit(cache=True)
def two_masses_jacobian(t, y, f, args, out):
    """The exact Jacobian of :func:`two_masses`."""
    k1, c1, k3 = args[0][0], args[0][1], args[0][2]
    x1, x2, v1, v2, c2 = y[0], y[1], y[2], y[3], y[5]
    stiffness = 3.0 * k3 * (x2 - x1) ** 2
    out[:, :] = 0.0
    out[0, 2] = out[1, 3] = 1.0
    out[2, 0], out[2, 1], out[2, 2] = -k1 - stiffness, stiffness, -c1
    out[3, 0], out[3, 1], out[3, 3], out[3, 5] = stiffness, -stiffness, -c2, -v2
    out[4, 2], out[4, 3], out[4, 5] = 2.0 * c1 * v1, 2.0 * c2 * v2, v2 * v2
    return True


@numba.njit(cache=True)
def decline_jacobian(t, y, f, args, out):
    """A ``jac`` that never provides one."""
    return False


@numba.njit(cache=True)
def van_der_pol_with_idle_component(t, y, args):
    """Van der Pol plus y2 with y2' = 0·y2: f hardly depends on y2 (NaN at y2 = inf)."""
    mu = args[0][0]
    return np.array([y[1], mu * (1.0 - y[0] * y[0]) * y[1] - y[0], 0.0 * y[2]])


# ---------------------------------------------------------------------------------------
# Helpers.
# ---------------------------------------------------------------------------------------
class Run(NamedTuple):
    status: int
    t: npt.NDArray[np.float64]
    y: npt.NDArray[np.float64]
    counts: dict[str, int]


#: The three methods on the generic loop, at the kernels' common interface
#: (:func:`jointplay._kernels.driver.run_core`'s): the lanes' own steps.
radau_integrate = functools.partial(driver.run_core, "radau")
rodas_integrate = functools.partial(driver.run_core, "rodas")
dopri_integrate = functools.partial(driver.run_core, "dopri")


def run_kernel(
    fun: Any,
    t_span: tuple[float, float],
    y0: Any,
    p: Any,
    *,
    rtol: float,
    atol: Any,
    step_check: Any = driver.accept_every_step,
    after_step: Any = driver.no_after_step,
    max_step: float = np.inf,
    first_step: float = 0.0,
    max_steps: int = 100_000,
    integrator: Any = radau_integrate,
    **structure: Any,
) -> Run:
    """Run ``integrator`` (the kernels' common interface) on a test problem."""
    y0 = np.asarray(y0, dtype=np.float64)
    status, t, y, counters = integrator(
        fun,
        step_check,
        after_step,
        t_span[0],
        y0,
        t_span[1],
        (np.asarray(p, dtype=np.float64),),
        rtol,
        np.broadcast_to(np.asarray(atol, dtype=np.float64), y0.shape),
        max_step,
        first_step,
        max_steps,
        **structure,
    )
    return Run(status, t, y, dict(zip(ids.COUNTER_NAMES, counters.tolist(), strict=True)))


def run_scipy(
    fun: Any, t_span: tuple[float, float], y0: Any, p: Any, *, method: str = "Radau", **options: Any
) -> Any:
    args = (np.asarray(p, dtype=np.float64),)
    sol = solve_ivp(
        lambda t, y: fun(t, np.ascontiguousarray(y), args),
        t_span,
        np.asarray(y0, dtype=np.float64),
        method=method,
        **options,
    )
    assert sol.status == 0, sol.message
    return sol


def tolerance_units(
    y: npt.NDArray[np.float64], reference: npt.NDArray[np.float64], rtol: float, atol: Any
) -> float:
    """Largest ``|y − reference| / (atol + rtol·|reference|)``."""
    return float(np.max(np.abs(y - reference) / (atol + rtol * np.abs(reference))))


def assert_counts_close(
    run: Run, sol: Any, ratio: float, *, steps_only: bool = False
) -> tuple[int, int]:
    steps, scipy_steps = run.counts["n_steps"], sol.t.shape[0] - 1
    assert 1 / ratio <= steps / scipy_steps <= ratio, (steps, scipy_steps)
    if not steps_only:
        assert 1 / ratio <= run.counts["nfev"] / sol.nfev <= ratio, (run.counts, sol.nfev)
        assert 1 / ratio <= run.counts["njev"] / sol.njev <= ratio, (run.counts, sol.njev)
    return steps, scipy_steps


#: 1 kg dropped from 0.1 m onto k = 1e7 N/m^1.5, c = 50 N·s/m; δ_tol = 1e-9 m.
CONTACT_PARAMETERS = np.array([1.0, 9.81, 1e7, 50.0, 1e-9, 0.0])


def contact_drop_reference() -> npt.NDArray[np.float64]:
    """State of the contact drop at t = 0.5 s from DOP853 at rtol 1e-13 (explicit; fine
    for this stiffness)."""
    return run_scipy(
        mass_on_floor,
        (0.0, 0.5),
        [0.1, 0.0],
        CONTACT_PARAMETERS,
        method="DOP853",
        rtol=1e-13,
        atol=1e-15,
    ).y[:, -1]


#: Stiff two-mass chain: k1 = 1e6 N/m, c1 = 50 N·s/m, k3 = 1e9 N/m³; c2 = 2 N·s/m.
TWO_MASSES = np.array([1e6, 50.0, 1e9])
TWO_MASSES_Y0 = [1e-3, -2e-3, 0.0, 1.0, 0.0, 2.0]
