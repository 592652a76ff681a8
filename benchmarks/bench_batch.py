"""Samples per second of the batch engine (issue 14), per backend and contact set.

The paper's four-bar, every joint clear, one revolution from the steady start (``--settle``
start-up revolutions before it, default none): the conventional IMPACT set (Table 3:
explicit Dormand–Prince), the spherical ECS set (Table 5, stiff: implicit Radau IIA, chosen
automatically) and ``physical``, the default contact (docs/contact.md: implicit). Each
sample draws the four link lengths uniformly within ±0.2 mm and the four radial clearances
within 6–21 µm, from one seed, before dispatch (the same samples on every backend).

Each timed run is :func:`jointplay.dynamics.batch.simulate_batch` from the samples to the
result — the vectorised build of the kernels' inputs included — after a warm-up run of a
few samples on the same backend (imports, loading the compiled kernels, starting the
workers of the process backend, which are kept). Sizes whose estimated time (from the
previous size) exceeds ``--budget`` seconds are skipped.

Run ``python benchmarks/bench_batch.py --backend local,processes --samples 1000,10000``
(``--backend dask --dask-scheduler tcp://HOST:8786`` for a Dask cluster);
``--json out.json`` writes the rows. The GPU backend needs ``pip install 'jointplay[gpu]'``.
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import time
from typing import Any

import numpy as np

from jointplay.dynamics.batch import BatchSamples, simulate_batch
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.setup import DEFAULT_IMPACT, ContactModel
from jointplay.dynamics.simulate import SolverOptions
from jointplay.io.config import load_preset
from jointplay.study.methods import method_law

JOINTS = ("O2", "A", "B", "O4")
SETS = {"conventional": "ifm-conventional", "spherical": "ifm-ecs-spherical"}


def samples_of(n: int, seed: int = 0) -> BatchSamples:
    rng = np.random.default_rng(seed)
    nominal = {"crank": 0.108, "coupler": 0.2705, "rocker": 0.2705, "ground": 0.2794}
    return BatchSamples(
        lengths={k: v + rng.uniform(-2e-4, 2e-4, n) for k, v in nominal.items()},
        clearances={j: rng.uniform(6e-6, 21e-6, n) for j in JOINTS},
    )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--backend", default="local,processes", help="comma-separated")
    parser.add_argument("--samples", default="1000,10000,100000", help="comma-separated sizes")
    parser.add_argument(
        "--sets",
        default="conventional,spherical",
        help="comma-separated: conventional, spherical, physical (the default contact, "
        "docs/contact.md: its stiffness refitted to every sample's clearance)",
    )
    parser.add_argument("--settle", type=int, default=0, help="start-up revolutions left out")
    parser.add_argument("--workers", type=int, default=None, help="processes (default: CPUs)")
    parser.add_argument(
        "--dask-scheduler", default=None, help="the scheduler's address, for --backend dask"
    )
    parser.add_argument("--budget", type=float, default=600.0, help="skip longer runs, s")
    parser.add_argument("--json", default=None, help="write the rows to this file")
    args = parser.parse_args()
    mechanism = load_preset("paper-fourbar")
    machine = (
        f"{platform.processor() or platform.machine()}, {os.cpu_count()} CPUs, "
        f"Python {platform.python_version()}, load {os.getloadavg()[0]:.1f}"
    )
    print(machine)
    rows: list[dict[str, Any]] = []
    for set_name in args.sets.split(","):
        if set_name == "physical":
            joints = ContactModel().joints(mechanism, JOINTS, clearance=11.75e-6)
        else:
            law = (
                DEFAULT_IMPACT
                if set_name == "conventional"
                else method_law(SETS[set_name], mechanism)[0]
            )
            joints = [ClearanceJoint(j, 11.75e-6, 0.005, law) for j in JOINTS]
        for backend in args.backend.split(","):
            options: dict[str, Any] = {
                "backend": backend,
                "solver": SolverOptions(),
                "settle": args.settle,
            }
            if backend == "processes":
                options["workers"] = args.workers
            if backend == "dask":
                options["scheduler"] = args.dask_scheduler
            simulate_batch(mechanism, joints, samples_of(8, seed=99), **options)  # warm-up
            rate = None
            for n in (int(v) for v in args.samples.split(",")):
                if rate is not None and n / rate > args.budget:
                    print(f"{set_name} {backend} {n}: skipped (~{n / rate:.0f} s > budget)")
                    continue
                cpu = time.process_time()
                wall = time.perf_counter()
                result = simulate_batch(mechanism, joints, samples_of(n), **options)
                wall = time.perf_counter() - wall
                cpu = time.process_time() - cpu
                rate = n / wall
                row = {
                    "set": set_name,
                    "backend": backend,
                    "workers": result.workers,
                    "samples": n,
                    "method": result.method,
                    "seconds": wall,
                    "samples_per_s": rate,
                    "build_s": result.build_time,
                    "cpu_s_this_process": cpu,
                    "failed": result.n_failed,
                    "steps_mean": float(result.counters["n_steps"].mean()),
                    "rhs_mean": float(result.counters["n_rhs"].mean()),
                    "machine": machine,
                }
                rows.append(row)
                print(
                    f"{set_name} {backend} {n}: {wall:.2f} s, {rate:,.0f} samples/s "
                    f"({result.method}, {row['steps_mean']:.0f} steps, {result.n_failed} failed)",
                    flush=True,
                )
    print()
    print("| set | backend | workers | samples | method | s | samples/s | steps | rhs |")
    print("|---|---|---:|---:|---|---:|---:|---:|---:|")
    for r in rows:
        print(
            f"| {r['set']} | {r['backend']} | {r['workers']} | {r['samples']:,} | {r['method']} "
            f"| {r['seconds']:.2f} | {r['samples_per_s']:,.0f} | {r['steps_mean']:.0f} "
            f"| {r['rhs_mean']:.0f} |"
        )
    if args.json:
        with open(args.json, "w", encoding="utf-8") as handle:
            json.dump(rows, handle, indent=2)


if __name__ == "__main__":
    main()
