"""The two GPU backends side by side (issue 44): ``cuda`` (numba-cuda, one thread per sample,
compiled from the lane source) and ``gpu`` (the JAX kernel), through the API a user calls.

Parts (``--part``):

- ``conventional``: the paper's four-bar, every joint clear (11.75 µm nominal), the paper's
  conventional IMPACT set (explicit Dormand–Prince at the batch engine's tolerances), one
  revolution from the steady start, no start-up revolutions; link lengths uniform within
  ±0.2 mm and radial clearances within 6–21 µm, one seed (``bench_batch.samples_of``: the
  same samples on every backend). Sizes ``--samples`` (default 100 000 and 1 000 000).
- ``physical``: the same with the physical default contact (``ContactModel()``: the
  lubricated film, implicit Radau IIA), default 10 000 and 100 000.
- ``design``: ``design_study`` of 6 fits × 4 ISO 2768-1 classes × ``--samples`` samples per
  scheme (default 10 000) with the physical default contact and its defaults (steady start,
  two start-up revolutions left out, one analysed), requirements as ``bench_design.py``.

Each timed run is a whole :func:`~jointplay.dynamics.batch.simulate_batch` (or
``design_study``) call, inputs built and results copied back. The first run in the process
is marked ``first``: it includes the kernel's compilation or its load from the disk caches
(numba-cuda's ``cache=True``; JAX's persistent cache, ``JOINTPLAY_JAX_CACHE``). Run a part
twice, once with empty caches (``NUMBA_CACHE_DIR``, ``JOINTPLAY_JAX_CACHE`` fresh folders)
and once with the caches the first run left, to get "cold" and "later process" figures.
``benchmarks/run_gpu_device.sh`` runs the parts in priority order on a lent GPU machine. ``--chunks`` runs every size
with each chunk size, lanes per launch (0: the executors' default, interrupt-sized chunks of
``execution/executors.py``; a large one: one launch, the throughput a user gets by giving
``chunk_size``).

``--save-lanes K --save FILE.npz`` keeps the first K samples' inputs and results of the
last run (``FILE-cuda.npz``, ``FILE-gpu.npz``); ``--compare FILE-cuda.npz`` (on any machine,
no GPU) runs the CPU lanes (backend ``local``) on those samples and prints the agreement: the largest relative difference of
every peak and mean speed over the lanes, the lanes whose step counts are equal, and each
response's mean and standard deviation over the K lanes on both.

``--part lanes --inputs FILE`` runs the numba-cuda kernel itself (one launch per size) on
kernel inputs written by ``--write-lanes FILE --samples N`` (on a machine with the CPU
kernels: ``simulate_batch``'s own inputs of ``samples_of(N)``, repeated beyond N lanes): it
imports none of the CPU kernels, so on a fresh machine it runs beside their first compilation
(``import jointplay._kernels.eom``, ~3 min on one core); ``--compare FILE --inputs INPUTS``
checks its saved lanes against the CPU lanes.

``--json FILE`` appends the rows (one JSON object per line). ``NUMBA_ENABLE_CUDASIM=1``
with tiny sizes checks the script without a GPU (``--revolutions 0.01``).
"""

from __future__ import annotations

import argparse
import json
import os
import platform
import sys
import time
import traceback
from pathlib import Path
from typing import Any

import numpy as np

sys.path.insert(0, str(Path(__file__).parent))

JOINTS = ("O2", "A", "B", "O4")
FITS = ("H7/h6", "H7/g6", "H8/f7", "H8/g7", "H9/d9", "H11/c11")
CLASSES = ("f", "m", "c", "v")
REQUIREMENTS = ("rocker_speed_error <= 5 %", "joint_force <= 150 N")
DEFAULT_SIZES = {"conventional": (100_000, 1_000_000), "physical": (10_000, 100_000),
                 "design": (10_000,)}  # fmt: skip


def device_name(backend: str) -> str:
    """The device a backend runs on, in words."""
    try:
        if backend == "cuda":
            from numba import cuda

            name = getattr(cuda.get_current_device(), "name", "the CUDA simulator")
            return name.decode() if isinstance(name, bytes) else str(name)
        if backend == "gpu":
            import jax

            return f"{jax.devices()[0].device_kind} ({jax.default_backend()})"
    except Exception as exc:  # a benchmark row says what it could not read
        return f"unknown ({exc})"
    return platform.processor() or platform.machine()


def joints_of(part: str, mechanism: Any) -> list[Any]:
    """The clearance joints of a part: the conventional IMPACT set or the physical default."""
    from jointplay.dynamics.clearance import ClearanceJoint
    from jointplay.dynamics.setup import DEFAULT_IMPACT, ContactModel

    if part == "conventional":
        return [ClearanceJoint(j, 11.75e-6, 0.005, DEFAULT_IMPACT) for j in JOINTS]
    return ContactModel().joints(mechanism, JOINTS, clearance=11.75e-6)


def saved_path(path: Path, backend: str) -> Path:
    """Where ``--save`` keeps a backend's lanes: ``lanes.npz`` → ``lanes-cuda.npz``."""
    return path.with_name(f"{path.stem}-{backend}{path.suffix}")


def batch_runs(args: argparse.Namespace, backend: str, emit: Any) -> None:
    """The ``conventional`` or ``physical`` part on one backend (module docstring)."""
    from bench_batch import samples_of

    from jointplay.dynamics.batch import simulate_batch
    from jointplay.dynamics.simulate import Start
    from jointplay.io.config import load_preset

    mechanism = load_preset("paper-fourbar")
    joints = joints_of(args.part, mechanism)
    sizes = args.samples or DEFAULT_SIZES[args.part]
    runs = [(chunk or None, n) for chunk in args.chunks for n in sizes]
    rate = None
    for index, (chunk, n) in enumerate(runs):
        if rate is not None and n / rate > args.budget:
            emit({"part": args.part, "backend": backend, "samples": n, "chunk": chunk,
                  "skipped": f"~{n / rate:.0f} s at the last rate > --budget"})  # fmt: skip
            continue
        samples = samples_of(n)
        clock = time.perf_counter()
        result = simulate_batch(
            mechanism, joints, samples, revolutions=args.revolutions, settle=0,
            start=Start("steady"), backend=backend, chunk_size=chunk,
        )  # fmt: skip
        wall = time.perf_counter() - clock
        rate = None if index == 0 else n / wall  # the first run includes the compilation
        ok = result.ok
        emit({
            "part": args.part, "backend": backend, "device": device_name(backend),
            "samples": n, "first": index == 0, "seconds": wall,
            "samples_per_s": n / wall, "build_s": result.build_time,
            "method": result.method, "chunk": chunk or "default",
            "failed": result.n_failed,
            "steps_mean": float(result.counters["n_steps"][ok].mean()) if ok.any() else None,
            "steps_max": float(result.counters["n_steps"][ok].max()) if ok.any() else None,
        })  # fmt: skip
        if args.save:  # the last run's lanes
            keep = min(args.save_lanes, n)
            arrays = {f"length_{k}": v[:keep] for k, v in samples.lengths.items()}
            arrays |= {f"clearance_{k}": v[:keep] for k, v in samples.clearances.items()}
            for frame, prefix in ((result.peaks, "peak_"), (result.statistics, "stat_"),
                                  (result.counters, "count_")):  # fmt: skip
                arrays |= {prefix + c: frame[c].to_numpy()[:keep] for c in frame.columns}
            arrays["status"] = result.status[:keep]
            np.savez(saved_path(args.save, backend), part=args.part, backend=backend,
                     method=result.method, revolutions=args.revolutions, **arrays)  # fmt: skip


def design_runs(args: argparse.Namespace, backend: str, emit: Any) -> None:
    """The ``design`` part: a small warm-up design, then the 6 × 4 one (module docstring)."""
    from jointplay.io.config import load_preset
    from jointplay.study.design import design_study
    from jointplay.tolerance.execution import Backend

    mechanism = load_preset("paper-fourbar")
    n = (args.samples or DEFAULT_SIZES["design"])[0]
    for label, fits, classes, samples in (("warm-up", FITS[:1], CLASSES[:1], 8),
                                          ("design", FITS, CLASSES, n)):  # fmt: skip
        clock = time.perf_counter()
        result = design_study(mechanism, fits, classes, REQUIREMENTS, samples=samples,
                              backend=Backend(backend))  # fmt: skip
        wall = time.perf_counter() - clock
        table = result.table
        emit({
            "part": "design", "run": label, "backend": backend, "device": device_name(backend),
            "schemes": len(fits) * len(classes), "samples_per_scheme": samples,
            "samples": len(fits) * len(classes) * samples, "seconds": wall,
            "failed": int(table["failed"].sum()), "best": str(result.best),
        })  # fmt: skip


#: The problems of ``--part lanes``: each part's contact and its batch method.
LANE_PROBLEMS = {"conventional": "explicit", "physical": "implicit"}
PROBLEM_FIELDS = ("ipar", "rpar", "y0", "t_settle", "t_end", "max_step", "rtol", "atol",
                  "max_steps")  # fmt: skip


def write_lanes(path: Path, n: int, revolutions: float) -> None:
    """The kernels' inputs of ``n`` samples of each part (``bench_batch.samples_of(n)``, one
    revolution from the steady start), as ``simulate_batch`` builds them, for ``--part lanes``
    on a machine that has not compiled the CPU kernels (``lanes.cuda`` needs none)."""
    from bench_batch import samples_of

    from jointplay.dynamics.batch import EXPLICIT_TOLERANCE_SCALE
    from jointplay.dynamics.batch_inputs import build_batch
    from jointplay.dynamics.simulate import SolverOptions, Start
    from jointplay.io.config import load_preset

    mechanism = load_preset("paper-fourbar")
    arrays: dict[str, Any] = {}
    for part, method in LANE_PROBLEMS.items():
        problem = build_batch(mechanism, joints_of(part, mechanism), samples_of(n),
                              revolutions=revolutions, settle=0, start=Start("steady"),
                              solver=SolverOptions())  # fmt: skip
        assert problem.ok.all()
        if method == "explicit":
            problem = problem.scaled_tolerances(EXPLICIT_TOLERANCE_SCALE)
        arrays |= {f"{part}_{k}": np.asarray(getattr(problem, k)) for k in PROBLEM_FIELDS}
    np.savez_compressed(path, **arrays)


def problem_of(saved: Any, part: str, lanes: int) -> tuple[Any, ...]:
    """``lanes.cuda.run_batch``'s arguments for ``lanes`` lanes of a saved part (its samples
    repeated beyond their number)."""
    index = np.arange(lanes) % saved[f"{part}_rpar"].shape[0]
    per_lane = [saved[f"{part}_{k}"][index] for k in PROBLEM_FIELDS[1:6]]
    return (saved[f"{part}_ipar"], *per_lane, float(saved[f"{part}_rtol"]),
            saved[f"{part}_atol"], int(saved[f"{part}_max_steps"]), LANE_PROBLEMS[part])  # fmt: skip


def lane_runs(args: argparse.Namespace, emit: Any) -> None:
    """``--part lanes``: the numba-cuda kernel of each part on the saved inputs, one launch
    per size, the first call on two lanes (the compilation, or the disk cache's load)."""
    from jointplay._kernels.lanes import cuda as lanes_cuda

    saved = dict(np.load(args.inputs))
    for part in args.problems.split(","):
        distinct = saved[f"{part}_rpar"].shape[0]
        clock = time.perf_counter()
        lanes_cuda.run_batch(*problem_of(saved, part, 2))
        emit({"part": "lanes", "problem": part, "compile_s": time.perf_counter() - clock,
              "device": device_name("cuda")})  # fmt: skip
        rate = None
        for n in args.samples:
            if rate is not None and n / rate > args.budget:
                emit({"part": "lanes", "problem": part, "samples": n, "skipped": "budget"})
                continue
            timings: dict[str, float] = {}
            clock = time.perf_counter()
            out = lanes_cuda.run_batch(*problem_of(saved, part, n), timings=timings)
            wall = time.perf_counter() - clock
            rate = n / wall
            ok = out.status == 0
            emit({"part": "lanes", "problem": part, "samples": n, "distinct": min(n, distinct),
                  "seconds": wall, "kernel_and_copies_s": timings["run_s"],
                  "samples_per_s": n / wall, "failed": int(np.sum(~ok)),
                  "steps_mean": float(out.n_steps[ok].mean()),
                  "steps_max": int(out.n_steps[ok].max())})  # fmt: skip
            if args.save:
                keep = min(args.save_lanes, n, distinct)
                np.savez(
                    saved_path(args.save, part),
                    part=part,
                    inputs=str(args.inputs),
                    **{k: np.asarray(v)[:keep] for k, v in out._asdict().items()},
                )
        emit(kernel_resources())


def relative(theirs: Any, ours: Any) -> Any:
    """|theirs − ours| / |ours| elementwise (0 where both are NaN: a column no lane fills)."""
    rel = np.abs(theirs - ours) / np.maximum(np.abs(ours), 1e-300)
    return np.where(np.isnan(ours) & np.isnan(theirs), 0.0, rel)


def compare_lanes(path: Path, inputs: Path, emit: Any) -> None:
    """The CPU lanes (:func:`jointplay._kernels.batch.run_batch`) on the lanes saved by
    ``--part lanes`` against the GPU's outputs there: equal steps, peak and statistic
    differences."""
    from jointplay._kernels import batch as kb

    gpu = dict(np.load(path))
    part = str(gpu["part"])
    n = len(gpu["status"])
    cpu = kb.run_batch(*problem_of(dict(np.load(inputs)), part, n))
    both = (cpu.status == 0) & (gpu["status"] == 0)
    row: dict[str, Any] = {
        "compare": str(path),
        "part": part,
        "lanes": n,
        "both_ok": int(both.sum()),
        "same_steps": int(np.sum(cpu.n_steps[both] == gpu["n_steps"][both])),
    }
    for name in ("peaks", "stats"):
        ours, theirs = cpu._asdict()[name][both], gpu[name][both]
        rel = relative(theirs, ours)
        row[name] = {
            "max_rel_per_column": np.nanmax(rel, axis=0).tolist(),
            "lanes_over_1e-3_per_column": np.sum(rel > 1e-3, axis=0).tolist(),
        }
    emit(row)


def kernel_resources() -> dict[str, Any]:
    """Registers and local memory per thread of every compiled numba-cuda lane kernel."""
    from jointplay._kernels.lanes import cuda_kernel

    row: dict[str, Any] = {"kernel_resources": True}
    for method, kernel in cuda_kernel.KERNELS.items():
        name = f"{method}_kernel"
        try:
            row[name] = {
                "registers": list(kernel.get_regs_per_thread().values()),
                "local_bytes": list(kernel.get_local_mem_per_thread().values()),
            }
        except Exception as exc:  # not compiled in this process, or no API
            row[name] = f"unknown ({type(exc).__name__}: {exc})"
    return row


def compare(path: Path, emit: Any) -> None:
    """The CPU lanes on the samples saved in ``path`` against the GPU's results there."""
    from jointplay.dynamics.batch import BatchSamples, simulate_batch
    from jointplay.dynamics.simulate import Start
    from jointplay.io.config import load_preset

    saved = dict(np.load(path))
    part = str(saved["part"])
    samples = BatchSamples(
        lengths={k[7:]: v for k, v in saved.items() if k.startswith("length_")},
        clearances={k[10:]: v for k, v in saved.items() if k.startswith("clearance_")},
    )
    mechanism = load_preset("paper-fourbar")
    cpu = simulate_batch(
        mechanism, joints_of(part, mechanism), samples, revolutions=float(saved["revolutions"]),
        settle=0, start=Start("steady"), backend="local", method=str(saved["method"]),
    )  # fmt: skip
    both = cpu.ok & (saved["status"] == 0)
    row: dict[str, Any] = {
        "compare": str(path),
        "part": part,
        "gpu_backend": str(saved["backend"]),
        "lanes": len(both),
        "both_ok": int(both.sum()),
        "same_steps": int(np.sum(saved["count_n_steps"][both] == cpu.counters["n_steps"][both])),
    }
    columns = [("peak_", cpu.peaks, c) for c in cpu.peaks.columns]
    columns += [("stat_", cpu.statistics, c) for c in cpu.statistics.columns if "_mean" in c]
    for prefix, frame, column in columns:
        ours, theirs = frame[column].to_numpy()[both], saved[prefix + column][both]
        rel = relative(theirs, ours)
        row[column] = {
            "max_rel": float(np.max(rel)), "median_rel": float(np.median(rel)),
            "lanes_over_1e-3": int(np.sum(rel > 1e-3)),
            "mean_cpu": float(np.mean(ours)), "mean_gpu": float(np.mean(theirs)),
            "std_cpu": float(np.std(ours, ddof=1)), "std_gpu": float(np.std(theirs, ddof=1)),
            "mean_difference_in_se": float((np.mean(theirs) - np.mean(ours))
                                           / (np.std(ours, ddof=1) / np.sqrt(len(ours)))),
        }  # fmt: skip
    emit(row)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--part", default="conventional", choices=("conventional", "physical", "design", "lanes")
    )
    parser.add_argument(
        "--inputs",
        type=Path,
        default=None,
        help="--part lanes: the kernels' inputs (--write-lanes)",
    )
    parser.add_argument(
        "--problems",
        default="conventional,physical",
        help="--part lanes: which of the saved problems",
    )
    parser.add_argument(
        "--write-lanes",
        type=Path,
        default=None,
        help="write --samples[0] samples' kernel inputs here and stop",
    )
    parser.add_argument("--backends", default="cuda,gpu", help="comma-separated: cuda, gpu")
    parser.add_argument("--samples", type=int, nargs="+", default=None)
    parser.add_argument("--revolutions", type=float, default=1.0)
    parser.add_argument(
        "--chunks",
        type=int,
        nargs="+",
        default=[0],
        help="lanes per launch, each size run with each (0: the default)",
    )
    parser.add_argument(
        "--budget",
        type=float,
        default=float("inf"),
        help="skip a size whose time at the last rate would exceed this, s",
    )
    parser.add_argument("--save-lanes", type=int, default=2_000)
    parser.add_argument("--save", type=Path, default=None, help="npz of the first lanes")
    parser.add_argument("--compare", type=Path, default=None, help="npz to check on the CPU")
    parser.add_argument("--json", type=Path, default=None, help="append the rows here")
    args = parser.parse_args()
    began = time.perf_counter()
    header = {"python": platform.python_version(), "cpus": os.cpu_count(),
              "numba_cache": os.environ.get("NUMBA_CACHE_DIR"),
              "jax_cache": os.environ.get("JOINTPLAY_JAX_CACHE")}  # fmt: skip

    def emit(row: dict[str, Any]) -> None:
        row = {**row, **header, "process_s": time.perf_counter() - began}
        print(json.dumps(row), flush=True)
        if args.json is not None:
            with args.json.open("a", encoding="utf-8") as handle:
                handle.write(json.dumps(row) + "\n")

    if args.compare is not None:
        if args.inputs is not None:  # lanes saved by --part lanes
            compare_lanes(args.compare, args.inputs, emit)
        else:
            compare(args.compare, emit)
        return
    if args.write_lanes is not None:
        write_lanes(args.write_lanes, args.samples[0], args.revolutions)
        return
    if args.part == "lanes":
        lane_runs(args, emit)
        return
    for backend in args.backends.split(","):
        try:
            (design_runs if args.part == "design" else batch_runs)(args, backend, emit)
            if backend == "cuda":
                emit(kernel_resources())
        except Exception as exc:  # a refusal or failure is a row too
            emit({"part": args.part, "backend": backend, "error": f"{type(exc).__name__}: "
                  f"{exc}", "traceback": traceback.format_exc(limit=4)})  # fmt: skip


if __name__ == "__main__":
    main()
