"""Benchmark: one crank revolution of the paper's four-bar with four clearance joints.

Run with ``python benchmarks/bench_clearance.py`` (``--help`` for options). The case is the
speed requirement of the clearance-joint simulator: the four-bar of Akhadkar, Deoghare &
Vaidya at 200 RPM, clearance 0.021 mm in all four joints (journal radius 5 mm), started
from rest, one revolution, default :class:`~jointplay.dynamics.simulate.SolverOptions`
but for the integrator, with the paper's IFM (MSC ADAMS IMPACT) parameter sets:

==============  ==========================  ===========  ====================  ===
set             k                           c_max        d_max                 e
==============  ==========================  ===========  ====================  ===
conventional    1e4 N/mm^1.5 (Table 3)      10 N·s/mm    0.1 mm                1.5
spherical       2500 N/mm^1.5 (Table 5)     25 N·s/mm    3.67e-5 mm            1.5
cylindrical     242348 N/mm^1.5 (Table 4)   2423 N·s/mm  2.69e-10 mm           1.5
==============  ==========================  ===========  ====================  ===

(k in N/mm^1.5 is k·1000^1.5 N/m^1.5 in SI; c_max 10 N·s/mm = 1e4 N·s/m.)

Each set runs with both integrators (``--integrators``): Radau IIA and RODAS4; the row
marked ``*`` is the integrator the paper's method of that set runs with
(:attr:`jointplay.study.methods.Method.integrator`: RODAS4 for the two ECS sets), the one
the targets of issue 22 (conventional ≤ 15 ms, spherical ≤ 60 ms, cylindrical ≤ 200 ms)
are read against. For each: a warm-up call (compilation or loading from Numba's cache),
then the best wall time of ``--repeat`` calls of the integration alone
(``solver_stats["wall_s"]``), steps, rejections, evaluations, the energy residual, the
peaks of |ω3|, |ω4| and of the contact force in each joint.

Baseline (Radau only): SciPy's ``solve_ivp(method="Radau")`` with the plain NumPy right-hand side of
:class:`~jointplay.dynamics.reference.ReferenceModel` on the same model, initial state and
tolerances (rtol, per-component atol, max_step), without the contact-onset control and
the projection (which need the kernel's hooks). For the conventional set it runs the full
revolution; for the stiff sets, whose full revolution takes SciPy many minutes, it runs
the first ``--baseline-fraction`` of the revolution and the two codes are compared by
their wall time per simulated second over that same interval (the kernel is timed on the
same interval too).
"""

from __future__ import annotations

import argparse
import os
import platform
import time
from dataclasses import dataclass
from typing import Any

import numpy as np
from scipy.integrate import solve_ivp

from jointplay.contact.laws import get_law
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.reference import ReferenceModel
from jointplay.dynamics.simulate import SimulationResult, SolverOptions, Start, simulate
from jointplay.io.config import load_preset
from jointplay.model.mechanism import Mechanism

#: mm-based ADAMS units to SI: k [N/mm^1.5] → N/m^1.5, c [N·s/mm] → N·s/m, d [mm] → m.
K_SI = 1000.0**1.5
PARAMETER_SETS: dict[str, dict[str, float]] = {
    "conventional": {"stiffness": 1e4 * K_SI, "exponent": 1.5, "c_max": 1e4, "d_max": 1e-4},
    "spherical": {"stiffness": 2500 * K_SI, "exponent": 1.5, "c_max": 25e3, "d_max": 3.67e-8},
    "cylindrical": {
        "stiffness": 242348 * K_SI,
        "exponent": 1.5,
        "c_max": 2423e3,
        "d_max": 2.69e-13,
    },
}
#: Targets of issue 22 (one core, after compilation), s.
TARGETS = {"conventional": 0.015, "spherical": 0.060, "cylindrical": 0.200}
#: The integrator the paper's method of each set runs with (``Method.integrator``).
PAPER_INTEGRATOR = {"conventional": "dopri5", "spherical": "rodas4", "cylindrical": "rodas4"}
JOINTS = ("O2", "A", "B", "O4")
CLEARANCE = 21e-6  # m
JOURNAL_RADIUS = 5e-3  # m
#: Required speed-up over the SciPy baseline.
REQUIRED_RATIO = 50.0


def clearances(name: str) -> list[ClearanceJoint]:
    """The four clearance joints with parameter set ``name``."""
    law = get_law("impact", **PARAMETER_SETS[name])
    return [ClearanceJoint(j, CLEARANCE, JOURNAL_RADIUS, law) for j in JOINTS]


def run(
    mechanism: Mechanism, name: str, revolutions: float = 1.0, integrator: str = "radau"
) -> SimulationResult:
    """One simulation from rest with the default solver options but for the integrator."""
    return simulate(
        mechanism,
        clearances(name),
        revolutions=revolutions,
        start=Start("rest"),
        solver=SolverOptions(integrator=integrator),
    )


@dataclass(frozen=True)
class Timing:
    """Best wall time of the integration, the last result and the interval simulated."""

    seconds: float
    result: SimulationResult
    t_end: float


def time_kernel(
    mechanism: Mechanism, name: str, repeat: int, revolutions: float, integrator: str = "radau"
) -> Timing:
    """Warm-up call, then the best of ``repeat`` integration wall times."""
    result = run(mechanism, name, revolutions, integrator)  # warm-up: compile or load
    best = np.inf
    for _ in range(repeat):
        result = run(mechanism, name, revolutions, integrator)
        best = min(best, result.solver_stats["wall_s"])
    return Timing(best, result, float(result.t[-1]))


def time_baseline(result: SimulationResult, t_end: float) -> tuple[float, Any]:
    """SciPy Radau with the NumPy right-hand side, same model, start and tolerances."""
    system = result.system
    n = system.n_coordinates
    options = SolverOptions()
    atol = np.concatenate(
        [
            np.full(n, options.atol_position),
            np.full(n, options.atol_velocity),
            np.full(2, 1e-6),
            np.full(len(system.clearances), 1.0),
        ]
    )
    max_step = result.mechanism.driver.period / 360.0
    reference = ReferenceModel(system)
    start = time.perf_counter()
    # SciPy's num_jac multiplies the difference factor of a column f does not depend on
    # (the work integrals) by 10 per Jacobian without bound; it overflows harmlessly there.
    with np.errstate(over="ignore"):
        sol = solve_ivp(
            reference.rhs,
            (0.0, t_end),
            result.y[0],
            method="Radau",
            rtol=options.rtol,
            atol=atol,
            max_step=max_step,
        )
    return time.perf_counter() - start, sol


def machine() -> str:
    """CPU model and core count, from /proc/cpuinfo where there is one."""
    model = platform.processor() or platform.machine()
    try:
        with open("/proc/cpuinfo", encoding="utf-8") as handle:
            for line in handle:
                if line.startswith("model name"):
                    model = line.split(":", 1)[1].strip()
                    break
    except OSError:
        pass
    return f"{model}, {os.cpu_count()} cores, Python {platform.python_version()}"


def peak(result: SimulationResult, key: str) -> float:
    return result.peaks[key]["value"]


def main() -> None:
    """Time the three sets (and the baseline), print the table."""
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--repeat", type=int, default=3, help="timed runs per set (best kept)")
    parser.add_argument("--sets", nargs="+", default=list(PARAMETER_SETS), choices=PARAMETER_SETS)
    parser.add_argument(
        "--integrators",
        nargs="+",
        default=["radau", "rodas4", "dopri5"],
        choices=["radau", "rodas4", "dopri5"],
        help="integrators to time (DOPRI5, explicit, on the conventional set only)",
    )
    parser.add_argument("--no-baseline", action="store_true", help="skip the SciPy baseline")
    parser.add_argument(
        "--baseline-fraction",
        type=float,
        default=0.1,
        help="part of the revolution the baseline runs for the stiff sets (default 0.1)",
    )
    options = parser.parse_args()
    mechanism = load_preset("paper-fourbar")
    print(f"machine: {machine()}")
    rows = []
    ratios = []
    for name in options.sets:
        for integrator in options.integrators:
            if integrator == "dopri5" and name != "conventional":
                continue  # explicit steps on the stiff sets: limited by stability, millions
            timing = time_kernel(mechanism, name, options.repeat, 1.0, integrator)
            stats = timing.result.solver_stats
            contact = "  ".join(f"{j} {peak(timing.result, f'F_{j}'):9.4g}" for j in JOINTS)
            target = TARGETS[name]
            mark = "*" if PAPER_INTEGRATOR[name] == integrator else " "
            rows.append(
                f"{name:13s} {integrator + mark:7s} {1e3 * timing.seconds:9.1f}"
                f" {1e3 * target:7.0f} {'yes' if timing.seconds <= target else 'NO':>4s}"
                f" {stats['steps']:7d} {stats['rejected_steps']:6d}"
                f" {stats['rejected_by_newton']:6d} {stats['rhs_evaluations']:8d}"
                f" {stats['jacobian_evaluations']:6d} {stats['lu_decompositions']:7d}"
                f" {stats['energy_residual']:9.1e} {peak(timing.result, 'omega3'):8.4f}"
                f" {peak(timing.result, 'omega4'):8.4f}  {contact}"
            )
        if options.no_baseline:
            continue
        fraction = 1.0 if name == "conventional" else options.baseline_fraction
        timing = time_kernel(mechanism, name, options.repeat, fraction)  # Radau
        print(f"{name}: SciPy baseline over {fraction:g} revolution ...", flush=True)
        seconds, sol = time_baseline(timing.result, timing.t_end)
        ratio = seconds / timing.seconds
        ratios.append(
            f"{name:13s} {fraction:9.3g} {1e3 * timing.seconds:11.1f} {seconds:10.2f}"
            f" {sol.t.shape[0] - 1:7d} {sol.nfev:7d} {sol.njev:5d} {ratio:9.0f}x"
            f" {'yes' if ratio >= REQUIRED_RATIO else 'NO':>5s}"
        )
    header = (
        f"{'set':13s} {'integr.':7s} {'time[ms]':>9s} {'target':>7s} {'met':>4s} {'steps':>7s} {'rej':>6s}"
        f" {'newton':>6s} {'nfev':>8s} {'njev':>6s} {'nlu':>7s} {'energy':>9s}"
        f" {'|ω3|max':>8s} {'|ω4|max':>8s}  peak contact force [N]"
    )
    print()
    print("* the integrator of the paper's method of that set (the targets' reading)")
    print(header)
    print("-" * len(header))
    print("\n".join(rows))
    if ratios:
        header = (
            f"{'set':13s} {'interval':>9s} {'kernel[ms]':>11s} {'SciPy[s]':>10s} {'steps':>7s}"
            f" {'nfev':>7s} {'njev':>5s} {'speed-up':>10s} {'>=50x':>5s}"
        )
        print()
        print("SciPy solve_ivp(Radau) + NumPy right-hand side, same model and tolerances")
        print("(interval in revolutions; the kernel timed over the same interval):")
        print(header)
        print("-" * len(header))
        print("\n".join(ratios))


if __name__ == "__main__":
    main()
