"""Samples per second of the JAX batch kernel (issue 14): 1k, 10k, 100k and 1M lanes.

The paper's four-bar, every joint clear (21 µm nominal), one revolution from the steady start
(no settling), the contact sets of the paper: the conventional IMPACT set (Table 3,
jointplay's default law, explicit Dormand–Prince) and the spherical ECS set (Table 5, the
stiff one, implicit Radau IIA). Each lane is one sample: link lengths drawn uniformly within
their ISO 2768-1 c tolerances and radial clearances within 10–21 µm; ``--distinct`` samples
are built one by one (``build_system`` + ``initial_state`` + ``eom.pack``, as the batch
engine builds its inputs) and tiled to the batch size.

Compile time (tracing and XLA compilation, or loading from the persistent cache) is reported
apart from run time. By default the persistent compilation cache is a fresh temporary
folder, so the compile time is that of a first run on a new machine; each size is then
compiled again in a new executable from that cache (``compile_cached_s``), the cost of every
later run. Goals of the issue (one H100): 100 000 conventional samples in <= 5 s including
compilation, 1 000 000 in <= 60 s.

Standalone: ``PYTHONPATH=src python3 benchmarks/bench_gpu.py --out gpu.json``; it needs
numpy, scipy, numba, pandas and jax only (not pint, pydantic or dask). ``--check`` first
compares a few lanes with the Numba batch kernel and with the single engine.
"""

from __future__ import annotations

import argparse
import json
import math
import os
import platform
import sys
import tempfile
import time
from pathlib import Path
from typing import Any

import numpy as np

#: Tolerance study inputs: the ISO 2768-1 c length tolerances of the paper's Table 1 (m) and
#: the radial clearance range of the samples (m).
LENGTHS = {"crank": 0.108, "coupler": 0.2705, "rocker": 0.2705, "ground": 0.2794}
LENGTH_TOL = {"crank": 0.8e-3, "coupler": 1.2e-3, "rocker": 1.2e-3, "ground": 1.2e-3}
CLEARANCE_RANGE = (10e-6, 21e-6)
JOINTS = ("O2", "A", "B", "O4")
SIZES = (1_000, 10_000, 100_000, 1_000_000)


def paper_fourbar(lengths: dict[str, float]) -> Any:
    """The paper's four-bar (the ``paper-fourbar`` preset) with the given link lengths (m),
    built from the template so that no unit parser (pint) is needed."""
    from jointplay.model.mechanism import JointFit
    from jointplay.model.templates import FourBarGeometry, LinkBody, four_bar

    bodies = {
        name: LinkBody(mass=mass, width=0.022, thickness=0.01)
        for name, mass in (("crank", 0.14), ("coupler", 0.26), ("rocker", 0.31))
    }
    fits = {
        joint: JointFit(
            diameter=0.01,
            fit="H8/g7",
            pin_length=0.03 if joint in ("O2", "O4") else 0.02,
            pin_mass=0.02,
            clearance=2.1e-5,
        )
        for joint in JOINTS
    }
    return four_bar(
        FourBarGeometry(**lengths),
        speed=200.0 * 2.0 * math.pi / 60.0,
        bodies=bodies,
        fits=fits,
        name="paper-fourbar",
    )


def contact_law(name: str) -> Any:
    """The IMPACT law of the conventional set (Table 3) or the spherical ECS set (Table 5)."""
    from jointplay.dynamics.setup import DEFAULT_IMPACT

    if name == "conventional":
        return DEFAULT_IMPACT
    from jointplay.study.ecs import ecs_parameters

    # The paper's Table 5 as its ifm-ecs-spherical method reads it (study/methods.py).
    return ecs_parameters(paper_fourbar(LENGTHS), "spherical", "paper").impact_law()


def build_inputs(law_name: str, distinct: int, seed: int, method: str) -> dict[str, Any]:
    """Kernel inputs of ``distinct`` random samples (module docstring), at the tolerances
    ``simulate_batch`` gives ``method`` (the explicit one runs at a fifth of the defaults)."""
    from jointplay._kernels import eom
    from jointplay.dynamics.batch import EXPLICIT_TOLERANCE_SCALE
    from jointplay.dynamics.clearance import ClearanceJoint
    from jointplay.dynamics.simulate import SolverOptions, Start, initial_state
    from jointplay.dynamics.system import build_system

    rng = np.random.default_rng(seed)
    law = contact_law(law_name)
    rpars, y0s, ipar, systems = [], [], None, []
    for _ in range(distinct):
        lengths = {k: v + rng.uniform(-LENGTH_TOL[k], LENGTH_TOL[k]) for k, v in LENGTHS.items()}
        mechanism = paper_fourbar(lengths)
        clearances = [
            ClearanceJoint(j, float(rng.uniform(*CLEARANCE_RANGE)), 0.005, law) for j in JOINTS
        ]
        system = build_system(mechanism, clearances)
        rpar, ipar_k = eom.pack(system.model)
        if ipar is None:
            ipar = ipar_k
        rpars.append(rpar)
        y0s.append(initial_state(system, Start("steady")))
        systems.append((mechanism, clearances))
    solver = SolverOptions()
    n = 9
    atol = np.concatenate(
        [
            np.full(n, solver.atol_position),
            np.full(n, solver.atol_velocity),
            np.full(2, 1e-6),
            np.ones(len(JOINTS)),
        ]
    )
    rtol = solver.rtol
    if method == "explicit":
        rtol *= EXPLICIT_TOLERANCE_SCALE
        atol[n : 2 * n] *= EXPLICIT_TOLERANCE_SCALE
    period = 60.0 / 200.0
    return {
        "ipar": ipar, "rpar": np.array(rpars), "y0": np.array(y0s), "period": period,
        "rtol": rtol, "atol": atol, "systems": systems,
    }  # fmt: skip


def tiled(inputs: dict[str, Any], n: int) -> tuple[Any, ...]:
    """``run_batch``'s positional arguments for ``n`` lanes (the distinct samples tiled)."""
    index = np.arange(n) % inputs["rpar"].shape[0]
    period = inputs["period"]
    return (
        inputs["ipar"], inputs["rpar"][index], inputs["y0"][index], np.zeros(n),
        np.full(n, period), np.full(n, period / 360.0), inputs["rtol"], inputs["atol"],
        2_000_000,
    )  # fmt: skip


def check(inputs: dict[str, Any], method: str, lanes: int) -> dict[str, Any]:
    """The JAX kernel against the Numba batch kernel and the single engine on a few lanes."""
    from jointplay._kernels.jax_batch import run_batch

    args = tiled(inputs, lanes)
    ours = run_batch(*args, method)
    report: dict[str, Any] = {"lanes": lanes, "method": method, "status": ours.status.tolist()}
    try:
        from jointplay._kernels.batch import run_batch as numba_batch
    except ImportError as exc:
        report["numba"] = f"not run: {exc}"
    else:
        theirs = numba_batch(*args, method)
        scale = np.maximum(np.abs(theirs.peaks), 1e-300)
        report["numba_peaks_max_rel"] = float(np.nanmax(np.abs(ours.peaks - theirs.peaks) / scale))
        report["numba_same_steps"] = bool(np.all(ours.n_steps == theirs.n_steps))
    from jointplay.dynamics.simulate import Start, simulate

    worst: dict[str, float] = {}
    for lane in range(min(lanes, 2)):
        mechanism, clearances = inputs["systems"][lane]
        result = simulate(mechanism, clearances, revolutions=1, settle=0, start=Start("steady"))
        keys = ["omega3", "omega4", "alpha3", "alpha4"] + [f"F_{j}" for j in JOINTS] + ["torque"]
        columns = [1, 2, 4, 5, 6, 7, 8, 9, 10]  # QUANTITY ORDER: ω, α of crank, coupler, rocker
        for key, column in zip(keys, columns, strict=True):
            reference = result.peaks[key]["value"]
            error = abs(ours.peaks[lane, column] / reference - 1.0)
            worst[key] = max(worst.get(key, 0.0), error)
    report["single_engine_max_rel"] = worst
    return report


def compare(path: Path, name: str, inputs: dict[str, Any], method: str) -> dict[str, Any]:
    """This device's results for 4 lanes against those stored in ``path`` (written there, with
    the device that made them, when the file or the set is missing)."""
    import jax

    from jointplay._kernels.jax_batch import run_batch

    out = run_batch(*tiled(inputs, 4), method)
    stored = dict(np.load(path)) if path.exists() else {}
    if f"{name}_peaks" not in stored:
        stored[f"{name}_peaks"] = out.peaks
        stored[f"{name}_stats"] = out.stats
        stored[f"{name}_steps"] = out.n_steps
        stored["device"] = np.array(str(jax.devices()[0]))
        np.savez(path, **stored)
        return {"written": str(path)}
    rel = np.abs(out.peaks - stored[f"{name}_peaks"]) / np.maximum(np.abs(out.peaks), 1e-300)
    stats = np.abs(out.stats - stored[f"{name}_stats"]) / np.maximum(np.abs(out.stats), 1e-300)
    return {
        "against": str(stored["device"]),
        "peaks_max_rel": float(np.nanmax(rel)),
        "stats_max_rel": float(np.nanmax(stats)),
        "same_steps": bool(np.all(out.n_steps == stored[f"{name}_steps"])),
        "steps": out.n_steps.tolist(),
    }


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--out", type=Path, required=True, help="JSON file to write")
    parser.add_argument("--sizes", type=int, nargs="+", default=list(SIZES))
    parser.add_argument("--sets", nargs="+", default=["conventional", "spherical-ecs"],
                        choices=["conventional", "spherical-ecs"])  # fmt: skip
    parser.add_argument("--ecs-method", default="implicit", choices=["explicit", "implicit"])
    parser.add_argument("--ecs-max-lanes", type=int, default=100_000,
                        help="largest batch of the ECS set (it is much slower)")  # fmt: skip
    parser.add_argument("--distinct", type=int, default=64, help="distinct samples, tiled")
    parser.add_argument("--chunk", type=int, default=None, help="lanes per chunk")
    parser.add_argument("--check", action="store_true", help="compare a few lanes first")
    parser.add_argument("--reference", type=Path, default=None,
                        help="npz of a few lanes' results on another device: write it if "
                        "missing, else compare with it")  # fmt: skip
    parser.add_argument("--time-limit", type=float, default=float("inf"),
                        help="skip sizes once this many seconds have been spent")  # fmt: skip
    args = parser.parse_args()
    if os.environ.get("JOINTPLAY_JAX_CACHE") is None:
        os.environ["JOINTPLAY_JAX_CACHE"] = tempfile.mkdtemp(prefix="jointplay-jax-")

    import jax

    from jointplay._kernels import jax_batch

    results: dict[str, Any] = {
        "benchmark": "bench_gpu",
        "device": str(jax.devices()[0]),
        "device_kind": jax.devices()[0].device_kind,
        "jax": jax.__version__,
        "python": platform.python_version(),
        "cpus": os.cpu_count(),
        "chunk": args.chunk or jax_batch.DEFAULT_CHUNK,
        "cache": os.environ["JOINTPLAY_JAX_CACHE"],
        "runs": [],
    }
    began = time.perf_counter()

    def save() -> None:
        args.out.write_text(json.dumps(results, indent=2))

    for name in args.sets:
        law = "conventional" if name == "conventional" else "spherical"
        method = "explicit" if name == "conventional" else args.ecs_method
        inputs = build_inputs(law, args.distinct, seed=1, method=method)
        if args.reference is not None:
            results.setdefault("reference", {})[name] = compare(
                args.reference, name, inputs, method
            )
            print(name, "reference:", json.dumps(results["reference"][name]), flush=True)
        if args.check:
            results.setdefault("checks", {})[name] = check(inputs, method, 4)
            print(name, "check:", json.dumps(results["checks"][name]), flush=True)
            save()
        for size in args.sizes:
            if name != "conventional" and size > args.ecs_max_lanes:
                continue
            if time.perf_counter() - began > args.time_limit:
                results["runs"].append({"set": name, "lanes": size, "skipped": "time limit"})
                continue
            timings: dict[str, float] = {}
            clock = time.perf_counter()
            out = jax_batch.run_batch(*tiled(inputs, size), method, chunk_size=args.chunk,
                                      timings=timings)  # fmt: skip
            total = time.perf_counter() - clock
            jax_batch._executables.clear()  # the next call loads from the persistent cache
            jax.clear_caches()
            cached: dict[str, float] = {}
            probe = min(size, args.chunk or jax_batch.DEFAULT_CHUNK)
            clock = time.perf_counter()
            jax_batch.run_batch(*tiled(inputs, probe), method, chunk_size=args.chunk,
                                timings=cached)  # fmt: skip
            run = {
                "set": name,
                "method": method,
                "lanes": size,
                "compile_s": timings["compile_s"],
                "run_s": timings["run_s"],
                "total_s": total,
                "samples_per_s": size / timings["run_s"],
                "samples_per_s_with_compile": size / total,
                "compile_cached_s": cached["compile_s"],
                "succeeded": int(np.sum(out.status == 0)),
                "mean_steps": float(np.mean(out.n_steps)),
                "mean_rejected": float(np.mean(out.n_rejected)),
            }
            results["runs"].append(run)
            print(json.dumps(run), flush=True)
            save()
    results["wall_s"] = time.perf_counter() - began
    save()
    print(f"wrote {args.out}", file=sys.stderr)


if __name__ == "__main__":
    main()
