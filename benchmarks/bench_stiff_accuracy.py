"""Issue 40 item 2: which tolerance controls the error of stiff multi-impact contact.

Lankarani–Nikravesh and Flores, K 1e10 N/m^1.5, e 0.8, no friction, dry, 21 µm in all four
joints of the paper four-bar, steady start, settle 0, 0.1 revolution (the ``simulate``
command of docs/performance.md, "Stiff multi-impact contact: the onset tolerance").

``grid``: for each law a converged reference (rtol 1e-11, atol 1e-15 m and 1e-11 m/s, onset
1e-7 of the clearance), then the worst error of the α and joint-force peaks, the ω peaks'
and the cost (steps, wall) over rtol 1e-6..1e-10 × atol ×1, ×1e-2, ×1e-4 × onset 1e-2..1e-5
of the clearance. ``cases``: 18 neighbouring cases (18, 21, 24 µm × e 0.7, 0.8, 0.9 × both
laws), each against its own reference, for a few tolerance sets: how many miss 1e-3.

Run: ``PYTHONPATH=src python benchmarks/bench_stiff_accuracy.py [grid|cases]`` (both by
default; a minute or two on one core after the kernels compile).
"""

from __future__ import annotations

import dataclasses
import itertools
import sys
import time

from jointplay.dynamics.settings import RunSettings, simulate_run
from jointplay.dynamics.simulate import SolverOptions
from jointplay.io.config import load_preset
from jointplay.settings.simulation import contact_model

PEAKS = ("omega3", "omega4", "alpha3", "alpha4", "F_O2", "F_A", "F_B", "F_O4")
LAWS = ("lankarani-nikravesh", "flores")


def run(mechanism, law: str, clearance: float, restitution: float, solver: SolverOptions):
    """The peaks, steps and wall time of one run (the command line's contact model)."""
    values = {
        "contact": law,
        "k": "1e10 N/m^1.5",
        "restitution": restitution,
        "friction": 0.0,
        "lubrication": "dry",
    }
    contact = contact_model(values, mechanism)
    joints = [dataclasses.replace(j, clearance=clearance) for j in contact.joints(mechanism)]
    settings = RunSettings(contact=contact, settle=0, revolutions=0.1, solver=solver)
    wall = time.perf_counter()
    result = simulate_run(mechanism, joints, settings)
    wall = time.perf_counter() - wall
    return {k: result.peaks[k]["value"] for k in PEAKS}, result.solver_stats["steps"], wall


def tolerances(clearance: float, rtol: float, atol: float, onset: float) -> SolverOptions:
    """rtol; atol as a factor on both defaults; onset as a fraction of the clearance."""
    return SolverOptions(
        rtol=rtol,
        atol_position=1e-10 * atol,
        atol_velocity=1e-6 * atol,
        onset_tolerance=clearance * onset,
    )


def errors(peaks: dict[str, float], reference: dict[str, float]) -> tuple[float, float]:
    """The worst relative error of the α and force peaks, and of the ω peaks."""
    error = {k: abs(peaks[k] / reference[k] - 1) for k in PEAKS}
    return (
        max(v for k, v in error.items() if not k.startswith("omega")),
        max(v for k, v in error.items() if k.startswith("omega")),
    )


def grid(mechanism) -> None:
    c = 21e-6
    for law in LAWS:
        reference, steps, _ = run(mechanism, law, c, 0.8, tolerances(c, 1e-11, 1e-5, 1e-7))
        tighter, _, _ = run(mechanism, law, c, 0.8, tolerances(c, 1e-12, 1e-6, 1e-7))
        print(
            f"== {law}: reference {steps} steps, rtol 1e-12 moves it {errors(tighter, reference)}"
        )
        for rtol, atol, onset in itertools.product(
            (1e-6, 1e-7, 1e-8, 1e-9, 1e-10), (1, 1e-2, 1e-4), (1e-2, 1e-3, 1e-4, 1e-5)
        ):
            peaks, steps, wall = run(mechanism, law, c, 0.8, tolerances(c, rtol, atol, onset))
            worst, omega = errors(peaks, reference)
            print(
                f"rtol {rtol:5.0e} atol x{atol:5.0e} onset {onset:5.0e} c   "
                f"F/α {worst:.1e}  ω {omega:.1e}  steps {steps:5d}  {wall:.3f} s",
                flush=True,
            )


#: Tolerance sets of ``cases``: (rtol, atol factor, onset fraction of the clearance).
SETS = {
    "old default (onset 1e-2)": (1e-6, 1, 1e-2),
    "default (onset 1e-4)": (1e-6, 1, 1e-4),
    "onset 1e-5": (1e-6, 1, 1e-5),
    "atol x1e-2, onset 1e-4": (1e-6, 1e-2, 1e-4),
    "rtol 1e-7, onset 1e-4": (1e-7, 1, 1e-4),
    "rtol 1e-7, atol x1e-2, onset 1e-4": (1e-7, 1e-2, 1e-4),
}


def cases(mechanism) -> None:
    worst = dict.fromkeys(SETS, 0.0)
    missed = dict.fromkeys(SETS, 0)
    steps = dict.fromkeys(SETS, 0)
    for law, c, e in itertools.product(LAWS, (18e-6, 21e-6, 24e-6), (0.7, 0.8, 0.9)):
        reference, _, _ = run(mechanism, law, c, e, tolerances(c, 1e-11, 1e-5, 1e-7))
        line = []
        for name, (rtol, atol, onset) in SETS.items():
            peaks, n, _ = run(mechanism, law, c, e, tolerances(c, rtol, atol, onset))
            error = errors(peaks, reference)[0]
            worst[name] = max(worst[name], error)
            missed[name] += error > 1e-3
            steps[name] += n
            line.append(f"{error:.0e}")
        print(f"{law[:5]} {c * 1e6:.0f} µm e {e}: " + " ".join(line), flush=True)
    for name in SETS:
        print(
            f"{name:36s} worst {worst[name]:.1e}, {missed[name]:2d}/18 miss 1e-3, {steps[name]} steps"
        )


if __name__ == "__main__":
    which = sys.argv[1:] or ["grid", "cases"]
    fourbar = load_preset("paper-fourbar")
    for name in which:
        {"grid": grid, "cases": cases}[name](fourbar)
