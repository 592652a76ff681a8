"""Film damping (issue 22): what an isotropic film damping c_e on the journals' centres
(``ContactModel(film_damping=...)``, docs/contact.md "Film damping (opt-in)") does to the cost
and the convergence of the physical default contact.

The paper's four-bar, the physical default contact (Liu stiffness, Hunt–Crossley e = 0.8,
Ambrósio friction μ = 0.1) at 21 µm in all four joints, steady start, for c_e in
:data:`FILMS` N·s/m. Parts (``--part``):

``steady``: settle 2 + 1 revolution at the default tolerances, best of 3 interleaved over
the c_e values: steps, rhs evaluations, Jacobians (the closed form), ms per revolution
(the integration's wall time over 3), settled peaks (located on the continuous solution
in the analysed revolution); the conventional set (``ifm-conventional``) as the yardstick.

``convergence``: the same runs at rtol 1e-6 (the default), 1e-7, 1e-8 and 1e-10 (with
tight atol, as benchmarks/bench_physical_profile.py), each settled peak's change against
the tightest, relative (forces: issue 22's target 1e-3, ω3: 1e-5 at the default tolerances).

``batch``: ``simulate_batch`` implicit, 16 samples of clearances 6–21 µm (all four joints),
settle 2 + 1, local backend on the machine's cores, best of 2: samples/s (target ≥ 40 on 2
cores).

``study``: a 200-sample dynamic Monte Carlo tolerance study of the paper four-bar (seed 1)
with ``RunSettings(contact=ContactModel(film_damping=c_e))`` against the conventional one:
wall time, ratio (target ≤ 2×), and whether its convergence check passes.

Run ``python benchmarks/bench_film_damping.py`` (about 10 minutes on 2 quiet cores) or one
part with ``--part``; ``--films 0 100`` for a subset.
"""

from __future__ import annotations

import argparse
import os
import time

import numpy as np
from numpy.typing import NDArray

from jointplay.dynamics.batch import BatchSamples, simulate_batch
from jointplay.dynamics.peaks import locate_peaks
from jointplay.dynamics.setup import ContactModel, conventional_contact
from jointplay.dynamics.simulate import SimulationResult, SolverOptions, Start, simulate
from jointplay.io.config import load_preset

JOINTS = ("O2", "A", "B", "O4")
CLEARANCE = 21e-6  # m
FILMS = (0.0, 10.0, 100.0, 1000.0)  # N·s/m
#: (rtol, atol_position m, atol_velocity m/s); the first is the default, the last the reference.
TOLERANCES = (
    (1e-6, 1e-10, 1e-6),
    (1e-7, 1e-10, 1e-6),
    (1e-8, 1e-10, 1e-6),
    (1e-10, 1e-13, 1e-9),
)
NAMES = [f"F_{j}" for j in JOINTS] + ["omega3"]
FloatArray = NDArray[np.float64]


def contact(film: float | None) -> ContactModel:
    """The physical default with film damping ``film`` N·s/m; ``None``: the conventional set."""
    return conventional_contact() if film is None else ContactModel(film_damping=film)


def label(film: float | None) -> str:
    return "conventional" if film is None else f"c_e = {film:g}"


def run(
    film: float | None, tolerances: tuple[float, float, float] = TOLERANCES[0]
) -> SimulationResult:
    mechanism = load_preset("paper-fourbar")
    joints = contact(film).joints(mechanism, JOINTS, clearance=CLEARANCE)
    rtol, atol_position, atol_velocity = tolerances
    solver = SolverOptions(rtol=rtol, atol_position=atol_position, atol_velocity=atol_velocity)
    return simulate(
        mechanism, joints, revolutions=1, settle=2, start=Start("steady"), solver=solver
    )


def settled_peaks(result: SimulationResult) -> FloatArray:
    """Peak |F| of each joint and peak |ω3| in the analysed (third) revolution, located on
    the continuous solution (as :attr:`SimulationResult.peaks`)."""
    period = 60.0 / 200.0
    columns = result._step_columns
    located = locate_peaks(
        result.t, {k: columns[k] for k in NAMES}, result.evaluate, [(2 * period, 3 * period)]
    )
    return np.array([located[k][0].value for k in NAMES])


def load() -> str:
    return "/".join(f"{v:.2f}" for v in os.getloadavg())


def steady(films: list[float | None]) -> None:
    for film in films:
        run(film)  # loads the compiled kernels
    best: dict[float | None, SimulationResult] = {}
    print(f"load before {load()}")
    for _ in range(3):
        for film in films:  # interleaved
            result = run(film)
            if (
                film not in best
                or result.solver_stats["wall_s"] < best[film].solver_stats["wall_s"]
            ):
                best[film] = result
    print(f"load after {load()}")
    print()
    print("| contact | steps (3 rev) | rhs | Jacobians | ms/rev | energy residual | "
          + " | ".join(f"{k} peak" for k in NAMES) + " |")  # fmt: skip
    print("|---|---:|---:|---:|---:|---:|" + "---:|" * len(NAMES))
    for film, result in best.items():
        stats = result.solver_stats
        peaks = settled_peaks(result)
        print(
            f"| {label(film)} | {stats['steps']} | {stats['rhs_evaluations']} | "
            f"{stats['jacobian_evaluations']} | {stats['wall_s'] / 3 * 1e3:.1f} | "
            f"{stats['energy_residual']:.1e} | " + " | ".join(f"{p:.4f}" for p in peaks) + " |"
        )


def convergence(films: list[float | None]) -> None:
    print(
        "| contact | rtol | steps | " + " | ".join(NAMES) + " | largest change of a force / of ω3 |"
    )
    print("|---|---:|---:|" + "---:|" * len(NAMES) + "---|")
    for film in films:
        rows = [(tolerances, run(film, tolerances)) for tolerances in TOLERANCES]
        reference = settled_peaks(rows[-1][1])
        for tolerances, result in rows:
            peaks = settled_peaks(result)
            change = np.abs(peaks - reference) / np.abs(reference)
            print(
                f"| {label(film)} | {tolerances[0]:.0e} | {result.solver_stats['steps']} | "
                + " | ".join(f"{p:.4f}" for p in peaks)
                + f" | {change[:4].max():.1e} / {change[4]:.1e} |",
                flush=True,
            )


def batch(films: list[float | None]) -> None:
    mechanism = load_preset("paper-fourbar")
    samples = BatchSamples(clearances=dict.fromkeys(JOINTS, np.linspace(6e-6, 21e-6, 16)))
    print(f"{os.cpu_count()} CPUs, load before {load()}")
    print("| contact | method | samples/s (best of 2) | failed |")
    print("|---|---|---:|---:|")
    for film in films:
        joints = contact(film).joints(mechanism, JOINTS, clearance=CLEARANCE)
        method = "implicit" if film is not None else "auto"
        rates = []
        for _ in range(3):  # the first loads the compiled kernels
            start = time.perf_counter()
            result = simulate_batch(
                mechanism, joints, samples, revolutions=1, settle=2, start=Start("steady"),
                method=method, backend="local",
            )  # fmt: skip
            rates.append(len(samples) / (time.perf_counter() - start))
        print(
            f"| {label(film)} | {result.method} | {max(rates[1:]):.1f} | {int((~result.ok).sum())} |",
            flush=True,
        )
    print(f"load after {load()}")


def study(films: list[float | None], samples: int) -> None:
    from jointplay.dynamics.settings import RunSettings
    from jointplay.tolerance.analysis import tolerance_study

    mechanism = load_preset("paper-fourbar")
    print(f"{os.cpu_count()} CPUs, load before {load()}")
    print("| contact | wall s | converged (largest change over spread) | failed |")
    print("|---|---:|---|---:|")
    for film in films:
        start = time.perf_counter()
        result = tolerance_study(
            mechanism, responses="dynamic", run_settings=RunSettings(contact=contact(film)),
            samples=samples, seed=1,
        )  # fmt: skip
        wall = time.perf_counter() - start
        check = result.convergence
        converged = (
            "n/a"
            if check is None
            else f"{check.finding is None} ({check.share:.2f}, {check.response})"
        )
        failed = len(result.result.failures)
        print(f"| {label(film)} | {wall:.1f} | {converged} | {failed} |", flush=True)
    print(f"load after {load()}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--part", choices=("steady", "convergence", "batch", "study"), nargs="*")
    parser.add_argument("--films", type=float, nargs="*", default=list(FILMS))
    parser.add_argument("--conventional", action="store_true", help="add the conventional set")
    parser.add_argument("--samples", type=int, default=200, help="the study's samples")
    args = parser.parse_args()
    films: list[float | None] = list(args.films) + ([None] if args.conventional else [])
    parts = args.part or ["steady", "convergence", "batch", "study"]
    for part in parts:
        print(f"\n## {part}\n", flush=True)
        if part == "study":
            study(films, args.samples)
        else:
            {"steady": steady, "convergence": convergence, "batch": batch}[part](films)


if __name__ == "__main__":
    main()
