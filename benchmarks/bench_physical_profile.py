"""Where the steps of the physical default contact go, and how its peaks converge (issue 22).

The paper's four-bar, the default contact (docs/contact.md: Liu's stiffness, Hunt–Crossley
damping with e = 0.8, Ambrósio friction μ = 0.1) at the fits' 21 µm in all four joints,
from the steady start. Two parts:

``profile`` (settle 2 + 1 revolution, default tolerances): the integrator's counters, the
accepted steps per revolution, per number of joints in contact, and per 10° of crank in the
analysed revolution with their median step, and the cost per revolution of each piece of
work (evaluations, Jacobians, LU pairs, the loop's work around each step) from
micro-timings of the compiled functions at a state in contact, against the measured time.

``convergence`` (three revolutions from the steady start, no settling): the peak contact
force of each joint and the peak |ω3| in each revolution, for a list of tolerances (rtol,
atol_position, atol_velocity); the last, tightest set is the reference. The peaks are located on the
continuous solution in each revolution, as :attr:`SimulationResult.peaks` are.

Run ``python benchmarks/bench_physical_profile.py`` (about 2 minutes on a quiet machine,
most of it the tight-tolerance reference runs); ``--part profile`` or ``--part convergence``
for one part.
"""

from __future__ import annotations

import argparse
import os
import time
from typing import Any

import numpy as np
from bench_dry_profile import (  # the script's folder
    _time_hooks,
    _time_jacobian,
    _time_lu,
    _time_rhs,
    hook_arguments,
)
from numpy.typing import NDArray

from jointplay._kernels import eom
from jointplay.dynamics.peaks import locate_peaks
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import SimulationResult, SolverOptions, Start, simulate
from jointplay.io.config import load_preset

JOINTS = ("O2", "A", "B", "O4")
CLEARANCE = 21e-6  # m
#: (rtol, atol_position m, atol_velocity m/s); the last is the reference.
TOLERANCES = (
    (1e-6, 1e-10, 1e-6),
    (1e-7, 1e-10, 1e-6),
    (1e-8, 1e-10, 1e-6),
    (1e-9, 1e-12, 1e-8),
    (1e-10, 1e-13, 1e-9),
    (1e-11, 1e-14, 1e-10),
)
MICRO_CALLS = 100_000
FloatArray = NDArray[np.float64]


def run(revolutions: int, settle: int, tolerances: tuple[float, float, float]) -> SimulationResult:
    mechanism = load_preset("paper-fourbar")
    joints = ContactModel().joints(mechanism, JOINTS, clearance=CLEARANCE)
    rtol, atol_position, atol_velocity = tolerances
    solver = SolverOptions(rtol=rtol, atol_position=atol_position, atol_velocity=atol_velocity)
    return simulate(
        mechanism,
        joints,
        revolutions=revolutions,
        settle=settle,
        start=Start("steady"),
        solver=solver,
    )


def micro_us(result: SimulationResult, h: float) -> dict[str, float]:
    """µs per call of each piece, at a state in the middle of the run (all joints in contact
    in this case), after a warm-up call."""
    args = result.system.kernel_args()
    i = len(result.t) // 2
    y, t = np.array(result.y[i]), float(result.t[i])
    f = eom.state_rhs(t, y, args).copy()
    out = np.empty((y.size, y.size))
    n = result.system.n_coordinates
    eom.jacobian_state(t, y, f, args, out)
    # the velocities' block: the positions' rows are the identity (bench_dry_profile.py)
    lu = (np.empty((n, n)), np.zeros(n, np.int64), np.empty((n, n)), np.empty((n, n)),
          np.zeros(n, np.int64))  # fmt: skip
    calls: dict[str, tuple[Any, tuple[Any, ...]]] = {
        "rhs": (_time_rhs, (t, y, args)),
        "jacobian": (_time_jacobian, (t, y, f, args, out)),
        "LU pair": (_time_lu, (out[n:], h, *lu, n, n)),
        "hooks": (_time_hooks, hook_arguments(result, i)),
    }
    timings = {}
    for name, (function, arguments) in calls.items():
        function(*arguments, 10)
        start = time.perf_counter()
        function(*arguments, MICRO_CALLS)
        timings[name] = (time.perf_counter() - start) / MICRO_CALLS * 1e6
    return timings


def profile() -> None:
    result = run(1, 2, TOLERANCES[0])
    result = run(1, 2, TOLERANCES[0])  # the first call loads the compiled kernels
    stats = result.solver_stats
    keys = (
        "steps",
        "rejected_by_error",
        "rejected_by_newton",
        "rejected_for_contact_onset",
        "rhs_evaluations",
        "jacobian_evaluations",
        "lu_decompositions",
    )
    print("counters (3 revolutions):", {k: stats[k] for k in keys})
    wall = stats["wall_s"]
    print(f"wall {wall * 1e3:.1f} ms, {wall / 3 * 1e3:.1f} ms per revolution")
    t = result.t
    h = np.diff(t)
    period = 60.0 / 200.0
    print("steps per revolution:", [int(np.sum((t[1:] > k * period) & (t[1:] <= (k + 1) * period))) for k in range(3)])  # fmt: skip
    columns = result._step_columns
    in_contact = np.column_stack([columns[f"pen_{j}"][1:] > 0 for j in JOINTS]).sum(axis=1)
    for k in range(5):
        mask = in_contact == k
        if mask.any():
            print(f"{k} joints in contact at the step's end: {mask.sum()} steps, median h {np.median(h[mask]):.2e} s")  # fmt: skip
    last = t[1:] > 2 * period
    bins = ((t[1:][last] - 2 * period) / period * 36).astype(int)
    print("analysed revolution, per 10° of crank: steps / median h (s)")
    print(" ".join(f"{10 * b}°:{np.sum(bins == b)}/{np.median(h[last][bins == b]):.0e}" for b in range(36) if np.any(bins == b)))  # fmt: skip
    per = micro_us(result, float(np.median(h)))
    print("µs per call:", {k: round(v, 3) for k, v in per.items()})
    lu_pairs = stats["lu_decompositions"] / 2
    parts = {
        "rhs": stats["rhs_evaluations"] * per["rhs"],
        "jacobian": stats["jacobian_evaluations"] * per["jacobian"],
        "LU": lu_pairs * per["LU pair"],
        "hooks": stats["steps"] * per["hooks"],
    }
    accounted = sum(parts.values()) / 1e3
    print(
        "ms per revolution: "
        + ", ".join(f"{k} {v / 3e3:.1f}" for k, v in parts.items())
        + f"; the rest (Newton solves, error estimate, driver) {(wall * 1e3 - accounted) / 3:.1f}"
    )


def revolution_peaks(result: SimulationResult, revolutions: int) -> FloatArray:
    """Peak contact force of each joint and peak |ω3| in each revolution, located on the
    continuous solution (:func:`~jointplay.dynamics.peaks.locate_peaks`, as
    :attr:`SimulationResult.peaks`), shape (revolutions, 5)."""
    period = 60.0 / 200.0
    names = [f"F_{j}" for j in JOINTS] + ["omega3"]
    columns = result._step_columns
    located = locate_peaks(
        result.t,
        {k: columns[k] for k in names},
        result.evaluate,
        [(k * period, (k + 1) * period) for k in range(revolutions)],
    )
    return np.array([[located[k][w].value for k in names] for w in range(revolutions)])


def convergence() -> None:
    rows = []
    for tolerances in TOLERANCES:
        result = run(3, 0, tolerances)
        rows.append((tolerances, result.solver_stats["steps"], revolution_peaks(result, 3)))
        print(f"{tolerances}: {result.solver_stats['steps']} steps", flush=True)
    reference = rows[-1][2]
    names = [f"F_{j}" for j in JOINTS] + ["|ω3|"]
    print()
    print("| rtol / atol_x / atol_v | steps | revolution | " + " | ".join(names) + " |")
    print("|---|---:|---:|" + "---:|" * len(names))
    for tolerances, steps, peaks in rows:
        for k in range(3):
            cells = [
                f"{value:.6g} ({abs(value / ref - 1):.0e})"
                for value, ref in zip(peaks[k], reference[k], strict=True)
            ]
            label = "/".join(f"{v:g}" for v in tolerances)
            print(f"| {label} | {steps} | {k + 1} | " + " | ".join(cells) + " |")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=("profile", "convergence", "both"), default="both")
    args = parser.parse_args()
    print(f"load {os.getloadavg()[0]:.1f}, {os.cpu_count()} CPUs")
    if args.part in ("profile", "both"):
        profile()
    if args.part in ("convergence", "both"):
        convergence()


if __name__ == "__main__":
    main()
