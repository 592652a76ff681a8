"""The design study's speed.

``--part responses`` (the default; issue 42): samples per second of the design's own
response models on one block of the paper four-bar, scheme H9/d9 class m, the lubricated
default contact (steady start, two start-up revolutions left out, one analysed):
:class:`~jointplay.tolerance.responses.RunningResponses` on the batch engine (the speed
error and the wear rates computed in the lanes), the batch engine's peaks alone
(:class:`~jointplay.tolerance.responses.PeakResponses`), and the single-engine path the
running responses had before (``engine="single"``: one simulation per sample), on the same
machine, one after the other. Each model is warmed up (compiled) on two samples first; the
timed block is ``--block`` samples (the single engine ``--single`` of them). ``--threads``
sets Numba's threads of the batch engine (default all); ``--contact`` another contact set
(e.g. ``ifm-conventional``, dry: the explicit lanes).

``--part study`` (issue 10): 6 fits × 4 ISO 2768 classes × 200 dynamic samples (four
clearance joints, conventional IFM set, steady start, two start-up revolutions left out,
one analysed revolution, Archard wear per sample) in <= 5 minutes on the project's 2-core
machine (``--samples``, ``--workers``). A small warm-up design (serial) loads the imports
and the compiled kernels first; the timed run includes starting the worker processes. The
worker processes' CPU time is printed too: on a machine shared with other jobs the wall
time overstates what two idle cores need.
"""

from __future__ import annotations

import argparse
import os
import platform
import resource
import time

from jointplay.io.config import load_preset
from jointplay.study.design import design_study
from jointplay.tolerance.execution import Backend

TARGET_S = 300.0
FITS = ("H7/h6", "H7/g6", "H8/f7", "H8/g7", "H9/d9", "H11/c11")
CLASSES = ("f", "m", "c", "v")
REQUIREMENTS = ("rocker_speed_error <= 5 %", "joint_force <= 150 N")


def responses(block: int, single: int, seed: int, contact: str | None) -> None:
    """Samples per second of the design's response models on one block (module docstring)."""
    import dataclasses

    import numba

    from jointplay.dynamics.settings import RunSettings
    from jointplay.dynamics.wear import OutputSpeedReference, WearSettings
    from jointplay.study.design_schemes import schemes
    from jointplay.tolerance.parts import Process, model_inputs
    from jointplay.tolerance.response_dynamic import PeakResponses, run_model
    from jointplay.tolerance.response_running import RunningResponses
    from jointplay.tolerance.sampling import sample

    mechanism = load_preset("paper-fourbar")
    scheme = schemes(mechanism, ["H9/d9"], ["m"])[0]
    spec = scheme.spec(mechanism, Process())
    names, x = model_inputs(spec.names, sample(spec, block, seed).values)
    base = run_model(mechanism, names, RunSettings.of(None, contact=contact))
    fields = {f.name: getattr(base, f.name) for f in dataclasses.fields(base)}
    running = RunningResponses(base, OutputSpeedReference.of(mechanism), WearSettings())
    models = {
        "RunningResponses, batch engine": (running, block),
        "PeakResponses (batch engine's peaks)": (PeakResponses(**fields), block),
        "RunningResponses, single engine (before)": (
            dataclasses.replace(running, engine="single"),
            min(single, block),
        ),
    }
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPU(s), "
          f"{numba.get_num_threads()} Numba thread(s)")  # fmt: skip
    print(f"paper four-bar, {scheme.label}, {contact or 'lubricated default'}, method "
          f"{base.method_choice().method}")  # fmt: skip
    for label, (model, n) in models.items():
        model.evaluate(x[:2])  # compile and warm up
        start = time.perf_counter()
        evaluation = model.evaluate(x[:n])
        elapsed = time.perf_counter() - start
        failed = int((~evaluation.ok).sum())
        print(f"{label:42s} {n:4d} samples in {elapsed:7.2f} s: {n / elapsed:7.2f} samples/s "
              f"({failed} failed)")  # fmt: skip


def study(samples: int, workers: int | None) -> None:
    """The design study of issue 10 (module docstring)."""
    mechanism = load_preset("paper-fourbar")
    design_study(
        mechanism,
        FITS[:1],
        CLASSES[:1],
        REQUIREMENTS,
        samples=2,
        contact="ifm-conventional",
        backend=Backend("serial"),
    )
    before = resource.getrusage(resource.RUSAGE_CHILDREN)
    start = time.perf_counter()
    result = design_study(
        mechanism,
        FITS,
        CLASSES,
        REQUIREMENTS,
        samples=samples,
        contact="ifm-conventional",  # the conventional set, as the recorded timings
        backend=Backend("processes", workers=workers),
    )
    elapsed = time.perf_counter() - start
    after = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu = (after.ru_utime - before.ru_utime) + (after.ru_stime - before.ru_stime)
    n = len(FITS) * len(CLASSES) * samples
    failed = int(result.table["failed"].sum())
    print(f"machine: {platform.processor() or platform.machine()}, {os.cpu_count()} CPU(s)")
    print(
        f"design: {len(FITS)} fits x {len(CLASSES)} classes x {samples} samples = {n} "
        f"dynamic simulations in {elapsed:.1f} s ({n / elapsed:.1f}/s, {failed} failed); "
        f"target {TARGET_S:.0f} s: {'met' if elapsed <= TARGET_S else 'MISSED'}"
    )
    print(
        f"worker CPU time {cpu:.0f} s ({cpu / n * 1e3:.0f} ms per sample): on two idle cores "
        f"about {cpu / 2:.0f} s; a wall time far above that means the cores were shared"
    )
    print(f"best: {result.best}; binding: {result.binding}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--part", choices=("responses", "study"), default="responses")
    parser.add_argument("--block", type=int, default=64)
    parser.add_argument("--single", type=int, default=8)
    parser.add_argument("--seed", type=int, default=42)
    parser.add_argument("--threads", type=int, default=None)
    parser.add_argument("--contact", default=None, help="a contact set (default: the default)")
    parser.add_argument("--samples", type=int, default=200)
    parser.add_argument("--workers", type=int, default=None)
    args = parser.parse_args()
    if args.part == "responses":
        if args.threads is not None:
            import numba

            numba.set_num_threads(args.threads)
        responses(args.block, args.single, args.seed, args.contact)
    else:
        study(args.samples, args.workers)


if __name__ == "__main__":
    main()
