"""Population life of the paper four-bar (issue 43): mechanisms per second and re-simulations
per life of :func:`jointplay.study.life.population_life`.

N mechanisms (``--samples``, default 2000) drawn as made from the H8/g7 fit and the ISO
2768-m lengths, dry joints (``--lubrication dry``: under the default lubricated contact the
joints run in full film and nothing wears), Archard k = 1e-6, each worn until its radial
clearance passes the fit's largest plus 20 µm (the README's wear example) or ``--hours``
(600 h); first step ``--update-hours`` (50 h), the update rule's tolerance 1 %. Every update
step of the mechanisms still running is one block through the running response model
(:class:`~jointplay.tolerance.response_running.RunningResponses`) on ``--backend`` (``local``,
``processes``, ``dask``, ``gpu``: passed through to :func:`jointplay.tolerance.execution.run`,
so the script is the same for 10⁴–10⁵ mechanisms on a GPU once the running model runs on the
batch engine).

Run ``python benchmarks/bench_life.py --samples 20 --backend processes --workers 2``;
``--json out.json`` writes the row. Prints the wall time, mechanisms per second, the
simulations per life (mean and largest), and the time 2 000 mechanisms would take at the
measured rate (the issue's target: ≤ 10 min on 2 cores).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time

import numpy as np

from jointplay.dynamics.settings import RunSettings
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.wear import WearSettings
from jointplay.execution.backends import Backend
from jointplay.io.config import load_preset
from jointplay.study.life import population_life

HOUR = 3600.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=2000, help="mechanisms (default 2000)")
    parser.add_argument("--backend", default="processes", help="local, processes, dask, gpu")
    parser.add_argument("--workers", type=int, default=None, help="processes: workers")
    parser.add_argument("--dask-scheduler", default=None)
    parser.add_argument("--hours", type=float, default=600.0, help="hours simulated")
    parser.add_argument("--update-hours", type=float, default=50.0, help="first step, h")
    parser.add_argument("--tolerance", type=float, default=0.01)
    parser.add_argument("--json", default=None, help="write the row here")
    args = parser.parse_args()

    mechanism = load_preset("paper-fourbar")
    backend = Backend(
        "dask" if args.dask_scheduler else args.backend,
        workers=args.workers if args.backend == "processes" else None,
        scheduler=args.dask_scheduler,
    )
    run = RunSettings.of(contact=ContactModel(lubrication="dry"))
    started = time.perf_counter()
    result = population_life(
        mechanism,
        "H8/g7",
        "m",
        [],
        hours=args.hours * HOUR,
        samples=args.samples,
        clearance_allowance=20e-6,
        wear=WearSettings(coefficient=1e-6),
        run_settings=run,
        first_step=args.update_hours * HOUR,
        tolerance=args.tolerance,
        backend=backend,
    )
    wall = time.perf_counter() - started
    sims = result.lives.resimulations
    row = {
        "samples": result.n,
        "backend": backend.kind,
        "workers": backend.workers,
        "cpus": os.cpu_count(),
        "machine": platform.machine(),
        "wall_s": wall,
        "mechanisms_per_s": result.n / wall,
        "simulations_per_life_mean": float(np.mean(sims)),
        "simulations_per_life_max": int(np.max(sims)),
        "simulations_per_s": float(np.sum(sims)) / wall,
        "extrapolated_2000_s": 2000 * wall / result.n,
        "headline": result.headline(),
    }
    for key, value in row.items():
        print(f"{key}: {value:.4g}" if isinstance(value, float) else f"{key}: {value}")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump(row, handle, indent=2)


if __name__ == "__main__":
    main()
