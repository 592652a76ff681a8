"""Measure the linearly implicit method (RODAS4) against the Radau IIA kernel (issue 22).

The question of issue 22: would a Rosenbrock method with the analytic Jacobian (one real LU
and six evaluations per step, no Newton iteration, so no Newton failure at a contact onset)
be faster than Radau IIA at the same accuracy on the physical contact? Compared on the first
revolution of the paper's four-bar from the steady start, the dry physical contact
(``ContactModel(lubricant_viscosity=0)``, the default when this was first measured) at the
fits' 21 µm, at several rtol (default atol), against a Radau reference at rtol 1e-11 (atol
1e-14 m, 1e-10 m/s). Peaks are located on the continuous solution, as
:attr:`SimulationResult.peaks`.

Both run through :func:`~jointplay.dynamics.simulate.simulate`
(``SolverOptions(integrator=...)``); RODAS4 is the production kernel
:mod:`jointplay._kernels.lanes.source_rodas` (this script first held a prototype of it). On the paper's
ECS contact sets, where RODAS4 is the faster, see ``benchmarks/bench_clearance.py``.

Run ``python benchmarks/bench_rodas4.py`` (about a minute).
"""

from __future__ import annotations

import os

import numpy as np

from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import SolverOptions, Start, simulate
from jointplay.io.config import load_preset

JOINTS = ("O2", "A", "B", "O4")
NAMES = [f"F_{j}" for j in JOINTS] + ["omega3"]
CLEARANCE = 21e-6  # m


def first_revolution(rtol: float, integrator: str = "radau", atol_x: float = 1e-10,
                     atol_v: float = 1e-6) -> tuple[np.ndarray, dict]:  # fmt: skip
    """Peaks of the first revolution from the steady start and the solver statistics."""
    mechanism = load_preset("paper-fourbar")
    joints = ContactModel(lubricant_viscosity=0.0).joints(mechanism, JOINTS, clearance=CLEARANCE)
    solver = SolverOptions(
        rtol=rtol, atol_position=atol_x, atol_velocity=atol_v, integrator=integrator
    )
    result = simulate(
        mechanism, joints, revolutions=1, settle=0, start=Start("steady"), solver=solver
    )
    return np.array([result.peaks[k]["value"] for k in NAMES]), result.solver_stats


def main() -> None:
    print(f"load {os.getloadavg()[0]:.1f}, {os.cpu_count()} CPUs")
    reference, _ = first_revolution(1e-11, "radau", 1e-14, 1e-10)
    first_revolution(1e-6, "rodas4")  # compile / load
    print("| method | rtol | steps | rhs evals | Jacobians | LUs | max F error | ω3 error | ms |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|")
    for rtol in (1e-5, 1e-6, 1e-7, 1e-8):
        for integrator in ("radau", "rodas4"):
            peaks, stats = first_revolution(rtol, integrator)
            error = np.abs(peaks / reference - 1.0)
            print(
                f"| {integrator} | {rtol:g} | {stats['steps']} | {stats['rhs_evaluations']} | "
                f"{stats['jacobian_evaluations']} | {stats['lu_decompositions']} | "
                f"{error[:4].max():.1e} | {error[4]:.1e} | {stats['wall_s'] * 1e3:.1f} |"
            )


if __name__ == "__main__":
    main()
