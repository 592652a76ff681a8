"""Measure a linearly implicit method (RODAS4) against the Radau IIA kernel (issue 22).

The question of issue 22: would a Rosenbrock method with the analytic Jacobian (one real LU
and six evaluations per step, no Newton iteration, so no Newton failure at a contact onset)
be faster than Radau IIA at the same accuracy on the physical default contact? This script
holds a prototype RODAS4 driver on the same compiled model (:mod:`jointplay._kernels.eom`:
right-hand side, closed-form Jacobian, contact-onset step control and contact memory) and
compares the two on the first revolution of the paper's four-bar from the steady start, the
default contact at the fits' 21 µm, at several rtol (default atol), against a Radau reference
at rtol 1e-11 (atol 1e-14 m, 1e-10 m/s). Peaks are located on the continuous solution
(:func:`~jointplay.dynamics.peaks.locate_peaks`, cubic Hermite between steps, as
:attr:`SimulationResult.peaks`).

RODAS4 ([HW96] §IV.7, the coefficients of Hairer's ``rodas.f``; order 4, embedded order 3,
stiffly accurate, L-stable): per step the Jacobian at the step's start (closed form, as
Radau's), ∂f/∂t by one forward difference, one LU of ``1/(hγ)·I − J`` reduced to the
accelerations as Radau's Newton matrices are (``dx = hγ (b_x + dv)``), six evaluations; the
error is the last stage (``y₁ − ŷ₁``) in Radau's norm; the step factor
``clip(0.9·err^(−1/4), 0.2, 6)``, not grown after a rejection; the onset check and the
contact memory as in the Radau driver. A prototype: no dense output of its own, no
predictive controller.

Run ``python benchmarks/bench_rodas4.py`` (about a minute).

References:
    .. [HW96] E. Hairer, G. Wanner, *Solving Ordinary Differential Equations II*, 2nd ed.,
       Springer, 1996, §IV.7 (RODAS, Table 7.2 and ``rodas.f``).
"""

from __future__ import annotations

import math
import os
import time
from typing import Any

import numba
import numpy as np

from jointplay._kernels import eom, radau
from jointplay._kernels.common import EPS, error_scale, num_jac, rms_norm, select_initial_step
from jointplay._kernels.linalg import lu_factor
from jointplay.dynamics import simulate as simulate_module
from jointplay.dynamics.peaks import locate_peaks
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import SolverOptions, Start, simulate
from jointplay.dynamics.system import build_system
from jointplay.io.config import load_preset

JOINTS = ("O2", "A", "B", "O4")
NAMES = [f"F_{j}" for j in JOINTS] + ["omega3"]
CLEARANCE = 21e-6  # m
PERIOD = 60.0 / 200.0  # s

# RODAS4 (Hairer's rodas.f): stage couplings a_ij, C_ij, nodes c_i, d_i = γ_i (∂f/∂t terms).
GAMMA = 0.25
A = np.zeros((6, 6))
A[1, 0] = 1.544
A[2, :2] = (0.9466785280815826, 0.2557011698983284)
A[3, :3] = (3.314825187068521, 2.896124015972201, 0.9986419139977817)
A[4, :4] = (1.221224509226641, 6.019134481288629, 12.53708332932087, -0.6878860361058950)
CC = np.zeros((6, 6))
CC[1, 0] = -5.6688
CC[2, :2] = (-2.430093356833875, -0.2063599157091915)
CC[3, :3] = (-0.1073529058151375, -9.594562251023355, -20.47028614809616)
CC[4, :4] = (7.496443313967647, -10.24680431464352, -33.99990352819905, 11.70890893206160)
CC[5, :5] = (
    8.083246795921522,
    -7.981132988064893,
    -31.52159432874371,
    16.31930543123136,
    -6.058818238834054,
)
NODES = np.array([0.0, 0.386, 0.21, 0.63, 1.0, 1.0])
D = np.array([0.25, -0.1043, 0.1035, -0.0362, 0.0, 0.0])


@numba.njit(cache=True)
def _factor(jac: Any, alpha: float, m: int, n_active: int) -> Any:
    """LU of ``α·I − J`` reduced to the accelerations (as Radau's real Newton matrix)."""
    nk = n_active - m
    a = np.empty((nk, nk))
    for i in range(nk):
        for j in range(nk):
            a[i, j] = -jac[m + i, m + j]
        a[i, i] += alpha
        for j in range(m):
            a[i, j] -= jac[m + i, j] / alpha
    return lu_factor(a)


@numba.njit(cache=True)
def rodas4(t0: float, y0: Any, t_bound: float, args: Any, rtol: float, atol: Any,
           max_step: float, m: int) -> Any:  # fmt: skip
    """Integrate the model's ODE with RODAS4; returns (status, t, y, counters) with counters
    (steps, error rejections, onset rejections, evaluations, Jacobians, LUs)."""
    n = y0.shape[0]
    n_active = 2 * m
    counters = np.zeros(6, dtype=np.int64)
    t = t0
    y = y0.copy()
    ts = np.empty(64)
    ys = np.empty((64, n))
    ts, ys = radau._record(ts, ys, 0, t, y)
    rows = 1
    f = eom.rhs(t, y, args).copy()
    h, extra = select_initial_step(eom.rhs, args, t, y, t_bound, max_step, f, 1.0, rtol, atol)
    counters[3] += 1 + extra
    jac = np.empty((n, n))
    ft = np.zeros(n)
    k = np.zeros((6, n))
    stage = np.empty(n)
    x = np.empty(n)
    work = np.empty(n_active - m)
    factor = np.full(n, EPS**0.5)
    rejected = False
    while t < t_bound:
        if not eom.jacobian_state(t, y, f, args, jac):
            jac = num_jac(eom.rhs, args, t, y, f, atol, factor, n_active)
        counters[4] += 1
        dt = math.sqrt(EPS) * max(1e-5, abs(t))
        f_later = eom.rhs(t + dt, y, args)
        counters[3] += 1
        for j in range(n):
            ft[j] = (f_later[j] - f[j]) / dt
        n_check = 0
        scale_factor = 1.0
        y_new = np.empty(n)
        while True:
            h = min(h, max_step, t_bound - t)
            if h < 10.0 * abs(np.nextafter(t, np.inf) - t):
                return -1, ts[:rows].copy(), ys[:rows].copy(), counters
            alpha = 1.0 / (h * GAMMA)
            lu, piv = _factor(jac, alpha, m, n_active)
            counters[5] += 1
            finite = True
            for s in range(6):
                if s == 0:
                    fs = f
                else:
                    for j in range(n):
                        acc = y[j]
                        for i in range(min(s, 5)):
                            acc += A[min(s, 4), i] * k[i, j]
                        if s == 5:  # the last stage starts from the embedded solution
                            acc += k[4, j]
                        stage[j] = acc
                    fs = eom.rhs(t + NODES[s] * h, stage, args)
                    counters[3] += 1
                for j in range(n):
                    acc = fs[j] + D[s] * h * ft[j]
                    for i in range(s):
                        acc += CC[s, i] / h * k[i, j]
                    x[j] = acc
                    finite = finite and math.isfinite(acc)
                radau._newton_solve_in_place(lu, piv, jac, alpha, x, work, m, n_active)
                for j in range(n):
                    k[s, j] = x[j]
            for j in range(n):
                y_new[j] = stage[j] + k[5, j]
            err = rms_norm(k[5], error_scale(y, y_new, atol, rtol)) if finite else np.inf
            scale_factor = max(0.2, min(6.0, err**0.25 / 0.9)) if err > 0.0 else 1.0 / 6.0
            if not err <= 1.0:
                h /= scale_factor if finite else 5.0
                rejected = True
                counters[1] += 1
                continue
            theta = eom.step_check(t, y, t + h, y_new, args)
            shortest = 10.0 * abs(np.nextafter(t, np.inf) - t)
            if theta < 1.0 and n_check < radau.MAX_CHECK_REJECTIONS and theta * h >= shortest:
                h *= theta
                n_check += 1
                counters[2] += 1
                continue
            break
        t += h
        eom.after_step(t, y_new, args)
        y = y_new
        f = eom.rhs(t, y, args).copy()
        counters[3] += 1
        counters[0] += 1
        ts, ys = radau._record(ts, ys, rows, t, y)
        rows += 1
        h_new = h / scale_factor
        h = min(h_new, h) if rejected else h_new
        rejected = False
    return 0, ts[:rows].copy(), ys[:rows].copy(), counters


def first_revolution_rodas4(rtol: float) -> tuple[np.ndarray, np.ndarray, float]:
    """Peaks of the first revolution with RODAS4 at ``rtol`` (default atol), its counters
    and its wall time."""
    mechanism = load_preset("paper-fourbar")
    joints = ContactModel().joints(mechanism, JOINTS, clearance=CLEARANCE)
    start = Start("steady")
    solver = SolverOptions()
    system = build_system(
        mechanism, joints, ramp_time=start.ramp_time, onset_tolerance=None, driven=start.driven
    )
    y0 = np.ascontiguousarray(simulate_module.initial_state(system, start), dtype=float)
    n = system.n_coordinates
    atol = np.concatenate(
        [
            np.full(n, solver.atol_position),
            np.full(n, solver.atol_velocity),
            np.full(2, 1e-6),
            np.full(len(joints), 1.0),
        ]
    )
    args = system.kernel_args()
    eom.start_workspace(y0, args)
    wall = time.perf_counter()
    status, t, y, counters = rodas4(0.0, y0, PERIOD, args, rtol, atol, PERIOD / 360.0, n)
    wall = time.perf_counter() - wall
    assert status == 0, status
    columns, qdd = simulate_module._columns(system, t, y)

    def evaluate(times: np.ndarray) -> dict[str, np.ndarray]:
        states = simulate_module._interpolate(system, t, y, qdd, times)
        return simulate_module._columns(system, times, states)[0]

    located = locate_peaks(t, {k: columns[k] for k in NAMES}, evaluate, [(0.0, PERIOD)])
    return np.array([located[k][0].value for k in NAMES]), counters, wall


def first_revolution_radau(rtol: float, atol_x: float = 1e-10, atol_v: float = 1e-6) -> Any:
    mechanism = load_preset("paper-fourbar")
    joints = ContactModel().joints(mechanism, JOINTS, clearance=CLEARANCE)
    solver = SolverOptions(rtol=rtol, atol_position=atol_x, atol_velocity=atol_v)
    result = simulate(
        mechanism, joints, revolutions=1, settle=0, start=Start("steady"), solver=solver
    )
    return np.array([result.peaks[k]["value"] for k in NAMES]), result.solver_stats


def main() -> None:
    print(f"load {os.getloadavg()[0]:.1f}, {os.cpu_count()} CPUs")
    reference, _ = first_revolution_radau(1e-11, 1e-14, 1e-10)
    first_revolution_rodas4(1e-6)  # compile / load
    print("| method | rtol | steps | rhs evals | Jacobians | LUs | max F error | ω3 error | ms |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for rtol in (1e-5, 1e-6, 1e-7, 1e-8):
        peaks, stats = first_revolution_radau(rtol)
        error = np.abs(peaks / reference - 1.0)
        print(
            f"| Radau IIA | {rtol:g} | {stats['steps']} | {stats['rhs_evaluations']} | "
            f"{stats['jacobian_evaluations']} | {stats['lu_decompositions'] // 2} pairs | "
            f"{error[:4].max():.1e} | {error[4]:.1e} | {stats['wall_s'] * 1e3:.1f} |"
        )
        peaks, counters, wall = first_revolution_rodas4(rtol)
        error = np.abs(peaks / reference - 1.0)
        print(
            f"| RODAS4 | {rtol:g} | {counters[0]} | {counters[3]} | {counters[4]} | "
            f"{counters[5]} real | {error[:4].max():.1e} | {error[4]:.1e} | {wall * 1e3:.1f} |"
        )


if __name__ == "__main__":
    main()
