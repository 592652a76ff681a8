"""Benchmark: the compiled Radau IIA kernel against SciPy's ``solve_ivp(method="Radau")``.

Run with ``python benchmarks/bench_radau.py [--repeat N]``. Each problem is solved by

* the kernel (:func:`jointplay._kernels.driver.run_core`'s Radau IIA) with a Numba-jitted
  right-hand side, after one warm-up call that compiles it (or loads it from the cache);
* SciPy's Radau with the same right-hand side written in NumPy, as a user of SciPy would.

Both use the same tolerances and finite-difference Jacobians, so they take nearly the
same steps; the table shows steps, right-hand-side evaluations (outside the Jacobians,
SciPy's count), Jacobians, the best wall time of ``--repeat`` runs and the speed-up.
"""

from __future__ import annotations

import argparse
import time
from collections.abc import Callable
from dataclasses import dataclass
from typing import Any

import numba
import numpy as np
from scipy.integrate import solve_ivp

from jointplay._kernels import driver, ids

# ---------------------------------------------------------------------------------------
# Problems: a jitted right-hand side for the kernel, a NumPy one for SciPy.
# ---------------------------------------------------------------------------------------
MU = 1000.0
#: Mass [kg], gravity [m/s²], Hertz stiffness [N/m^1.5], damping [N·s/m].
FLOOR = np.array([1.0, 9.81, 1e7, 50.0])


@numba.njit(cache=True)
def van_der_pol_jit(t, y, args):
    """Van der Pol oscillator, μ = p[0]."""
    mu = args[0][0]
    return np.array([y[1], mu * (1.0 - y[0] * y[0]) * y[1] - y[0]])


def van_der_pol_numpy(t: float, y: np.ndarray) -> np.ndarray:
    """Van der Pol oscillator, μ = MU."""
    return np.array([y[1], MU * (1.0 - y[0] * y[0]) * y[1] - y[0]])


@numba.njit(cache=True)
def floor_contact_jit(t, y, args):
    """Mass on a stiff damped floor: F = max(0, k·δ^1.5 + c·δ̇) for δ = −x > 0."""
    p = args[0]
    force = 0.0
    if y[0] < 0.0:
        force = max(0.0, p[2] * (-y[0]) ** 1.5 - p[3] * y[1])
    return np.array([y[1], -p[1] + force / p[0]])


def floor_contact_numpy(t: float, y: np.ndarray) -> np.ndarray:
    """Mass on a stiff damped floor (the same law, in NumPy)."""
    m, g, k, c = FLOOR
    force = max(0.0, k * (-y[0]) ** 1.5 - c * y[1]) if y[0] < 0.0 else 0.0
    return np.array([y[1], -g + force / m])


@dataclass(frozen=True)
class Problem:
    """One benchmark case."""

    name: str
    jit_rhs: Any
    numpy_rhs: Callable[[float, np.ndarray], np.ndarray]
    params: np.ndarray
    t_span: tuple[float, float]
    y0: np.ndarray
    rtol: float
    atol: float


PROBLEMS = [
    Problem(
        "Van der Pol μ=1000, rtol 1e-3",
        van_der_pol_jit,
        van_der_pol_numpy,
        np.array([MU]),
        (0.0, 3000.0),
        np.array([2.0, 0.0]),
        1e-3,
        1e-6,
    ),
    Problem(
        "Van der Pol μ=1000, rtol 1e-6",
        van_der_pol_jit,
        van_der_pol_numpy,
        np.array([MU]),
        (0.0, 3000.0),
        np.array([2.0, 0.0]),
        1e-6,
        1e-6,
    ),
    Problem(
        "mass on stiff floor, rtol 1e-6",
        floor_contact_jit,
        floor_contact_numpy,
        FLOOR,
        (0.0, 0.5),
        np.array([0.1, 0.0]),
        1e-6,
        1e-9,
    ),
]


def best_time(run: Callable[[], Any], repeat: int) -> tuple[float, Any]:
    """Best wall time of ``repeat`` runs, and the last run's result."""
    best = np.inf
    result = None
    for _ in range(repeat):
        start = time.perf_counter()
        result = run()
        best = min(best, time.perf_counter() - start)
    return best, result


def bench(problem: Problem, repeat: int) -> list[tuple[str, int, int, int, float]]:
    """Rows (solver, steps, nfev, njev, seconds) for one problem."""
    atol = np.full(problem.y0.shape[0], problem.atol)

    def run_kernel() -> Any:
        return driver.run_core(
            "radau",
            problem.jit_rhs,
            driver.accept_every_step,
            driver.no_after_step,
            problem.t_span[0],
            problem.y0,
            problem.t_span[1],
            (problem.params,),
            problem.rtol,
            atol,
            np.inf,
            0.0,
            10**7,
        )

    def run_scipy() -> Any:
        return solve_ivp(
            problem.numpy_rhs,
            problem.t_span,
            problem.y0,
            method="Radau",
            rtol=problem.rtol,
            atol=problem.atol,
        )

    start = time.perf_counter()
    run_kernel()  # warm-up: compile, or load from Numba's cache
    warm_up = time.perf_counter() - start
    kernel_time, (status, _, _, counters) = best_time(run_kernel, max(repeat, 10))
    assert status == ids.STATUS_SUCCESS
    scipy_time, sol = best_time(run_scipy, repeat)
    assert sol.status == 0
    counts = dict(zip(ids.COUNTER_NAMES, counters.tolist(), strict=True))
    print(f"  (kernel warm-up call: {warm_up:.2f} s)")
    return [
        ("kernel", counts["n_steps"], counts["nfev"], counts["njev"], kernel_time),
        ("SciPy", sol.t.shape[0] - 1, sol.nfev, sol.njev, scipy_time),
    ]


def main() -> None:
    """Run every problem and print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="runs per solver (best is kept)")
    options = parser.parse_args()
    header = f"{'problem':32s} {'solver':7s} {'steps':>7s} {'nfev':>8s} {'njev':>6s}"
    header += f" {'time [ms]':>10s} {'speed-up':>9s}"
    lines = []
    for problem in PROBLEMS:
        print(f"{problem.name} ...")
        rows = bench(problem, options.repeat)
        scipy_time = rows[1][4]
        for solver, steps, nfev, njev, seconds in rows:
            speed_up = f"{scipy_time / seconds:8.1f}x" if solver == "kernel" else ""
            lines.append(
                f"{problem.name:32s} {solver:7s} {steps:7d} {nfev:8d} {njev:6d}"
                f" {1e3 * seconds:10.2f} {speed_up:>9s}"
            )
    print()
    print(header)
    print("-" * len(header))
    print("\n".join(lines))


if __name__ == "__main__":
    main()
