"""Population life of the paper four-bar (issue 43): mechanisms per second and re-simulations
per life of :func:`jointplay.study.life.population_life`.

N mechanisms (``--samples``, default 2000) drawn as made from the H8/g7 fit and the ISO
2768-m lengths, Archard k = 1e-6, each worn until its radial clearance passes the fit's
largest plus 20 µm (the README's wear example) or ``--hours`` (600 h), the update rule's
tolerance 1 %. **Dry joints** (``--lubrication dry``): under the default lubricated contact the
paper four-bar's joints run in full film and nothing wears, every life is censored, and there
is no life distribution to time (``--lubrication default`` runs it anyway).

The defaults are the settings measured to fit the issue's 10 minutes on 2 idle cores with
B10 unchanged (docs/performance.md, "Population life"): each update simulation is the steady
start, one start-up revolution and one analysed (``--settle 1``, ``--revolutions 1``; the
running model's default is 2 + 1, whose one-revolution wear rate is no less noisy), and fixed
steps of 75 h (``--update-hours 75 --smallest-hours 75``: the step control cannot act on the
dry four-bar, whose wear rate's noise holds every step at the smallest, and its rejected
tries on the way there cost 2 of 6.7 simulations a life; the lives are the same bit for bit
without them). Each life is then known to about 8 % (rms, against 22 simulations a life at
settle 2 and 50 h steps) instead of 5 % at the CLI example's settings; ``--settle 0`` is 1.5×
cheaper again at 9 %.

Every update step of the mechanisms still running is one block through the running response
model (:class:`~jointplay.tolerance.response_running.RunningResponses`, the batch engine's
lanes) on ``--backend`` (``local``: this process's threads, ``NUMBA_NUM_THREADS``;
``processes``, ``dask``, ``cuda``: passed through to
:func:`jointplay.tolerance.execution.run`), so the script is the same for 10⁴–10⁵ mechanisms
on a GPU (``--backend cuda``; the JAX ``gpu`` backend refuses the running responses).

Run ``python benchmarks/bench_life.py --samples 40 --backend local``; ``--json out.json``
writes the row, ``--lives out.npz`` each life. The kernels are compiled (or loaded from
Numba's cache) by a warm-up of two mechanisms first, timed apart (``warmup_s``). The machine
is shared: the row carries the load average before and after, and the CPU seconds of this
process and its workers (``cpu_s``), whose rate (``simulations_per_cpu_s``) does not depend
on the other jobs, with the time 2 000 mechanisms would take at the measured wall rate and on
2 idle cores at the measured CPU rate (the issue's target: ≤ 10 min on 2 cores).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import resource
import time

import numpy as np

from jointplay.dynamics.settings import RunSettings
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.wear import WearSettings
from jointplay.execution.backends import Backend
from jointplay.io.config import load_preset
from jointplay.study.life import population_life
from jointplay.study.life_result import LifeResult

HOUR = 3600.0


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=2000, help="mechanisms (default 2000)")
    parser.add_argument("--backend", default="processes", help="local, processes, dask, cuda")
    parser.add_argument("--workers", type=int, default=None, help="processes: workers")
    parser.add_argument("--dask-scheduler", default=None)
    parser.add_argument("--hours", type=float, default=600.0, help="hours simulated")
    parser.add_argument("--update-hours", type=float, default=75.0, help="first step, h")
    parser.add_argument(
        "--smallest-hours", type=float, default=75.0, help="smallest step, h (0: a quarter)"
    )
    parser.add_argument("--tolerance", type=float, default=0.01)
    parser.add_argument("--settle", type=int, default=1, help="start-up revolutions")
    parser.add_argument("--revolutions", type=float, default=None, help="analysed revolutions")
    parser.add_argument("--lubrication", default="dry", help="dry or default (lubricated)")
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--json", default=None, help="write the row here")
    parser.add_argument("--lives", default=None, help="write each life (h) here (.npz)")
    args = parser.parse_args()

    mechanism = load_preset("paper-fourbar")
    backend = Backend(
        "dask" if args.dask_scheduler else args.backend,
        workers=args.workers if args.backend == "processes" else None,
        scheduler=args.dask_scheduler,
    )
    contact = ContactModel() if args.lubrication == "default" else ContactModel(lubrication="dry")
    run = RunSettings.of(contact=contact, settle=args.settle, revolutions=args.revolutions)

    def population(samples: int, hours: float) -> LifeResult:
        return population_life(
            mechanism,
            "H8/g7",
            "m",
            [],
            hours=hours,
            samples=samples,
            seed=args.seed,
            clearance_allowance=20e-6,
            wear=WearSettings(coefficient=1e-6),
            run_settings=run,
            first_step=args.update_hours * HOUR,
            tolerance=args.tolerance,
            backend=backend,
            min_step=args.smallest_hours * HOUR if args.smallest_hours > 0 else None,
        )

    started = time.perf_counter()
    population(2, args.update_hours * HOUR)  # compiles or loads the kernels, starts workers
    warmup = time.perf_counter() - started
    load_before = os.getloadavg()
    cpu_before = _cpu_s()
    started = time.perf_counter()
    result = population(args.samples, args.hours * HOUR)
    wall = time.perf_counter() - started
    cpu = _cpu_s() - cpu_before
    sims = result.lives.resimulations
    row = {
        "samples": result.n,
        "backend": backend.kind,
        "workers": backend.workers,
        "cpus": os.cpu_count(),
        "machine": platform.machine(),
        "lubrication": args.lubrication,
        "settle": run.settle,
        "revolutions": run.revolutions,
        "update_hours": args.update_hours,
        "smallest_step_hours": result.settings["min_step_s"] / HOUR,
        "tolerance": args.tolerance,
        "warmup_s": warmup,
        "load_average_before": load_before[0],
        "load_average_after": os.getloadavg()[0],
        "wall_s": wall,
        "cpu_s": cpu,
        "mechanisms_per_s": result.n / wall,
        "simulations": int(np.sum(sims)),
        "simulations_per_life_mean": float(np.mean(sims)),
        "simulations_per_life_max": int(np.max(sims)),
        "accepted_steps_per_life_mean": float(np.mean([len(h) - 1 for h in result.lives.history])),
        "simulations_per_s": float(np.sum(sims)) / wall,
        "simulations_per_cpu_s": float(np.sum(sims)) / cpu,
        "extrapolated_2000_s": 2000 * wall / result.n,
        "extrapolated_2000_s_on_2_free_cores": 2000 * cpu / result.n / 2,
        "censored": int(np.sum(result.lives.censored)),
        "headline": result.headline(),
    }
    for key, value in row.items():
        print(f"{key}: {value:.4g}" if isinstance(value, float) else f"{key}: {value}")
    if args.lives:
        np.savez(
            args.lives,
            life_h=result.lives.life / HOUR,
            censored=result.lives.censored,
            simulations=sims,
        )
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump(row, handle, indent=2)


def _cpu_s() -> float:
    """CPU seconds of this process and its finished and living workers (user + system)."""
    own = resource.getrusage(resource.RUSAGE_SELF)
    children = resource.getrusage(resource.RUSAGE_CHILDREN)  # workers that have ended
    total = own.ru_utime + own.ru_stime + children.ru_utime + children.ru_stime
    for pid in _worker_pids():
        try:
            with open(f"/proc/{pid}/stat", encoding="ascii") as handle:
                fields = handle.read().rsplit(")", 1)[1].split()
            total += (int(fields[11]) + int(fields[12])) / os.sysconf("SC_CLK_TCK")
        except (OSError, IndexError, ValueError):
            continue
    return total


def _worker_pids() -> list[int]:
    """The living child processes of this one (the pool's workers), from /proc."""
    import multiprocessing

    return [p.pid for p in multiprocessing.active_children() if p.pid is not None]


if __name__ == "__main__":
    main()
