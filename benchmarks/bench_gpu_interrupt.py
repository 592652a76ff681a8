"""Ctrl-C inside a numba-cuda launch (issues 24 item 1 and 26): time from SIGINT to return.

The paper's four-bar, every joint clear (the conventional IMPACT law, explicit lanes), each
lane the steady start with its velocities scaled by ``1 + 0.01 u`` (u uniform in [0, 1),
one seed), integrated for ``--revolutions`` revolutions: a launch long enough to be cut.
The kernel is called directly (:func:`jointplay._kernels.lanes.cuda.run_batch`) inside
:func:`jointplay.execution.interrupts.interrupts_watched`, as the ``cuda`` executor calls it;
a timer thread sends SIGINT to this process ``--after`` seconds into the launch.

Printed (and written by ``--json``):

- ``flags``: how the flags reached the device — ``mapped`` (the interrupt page itself,
  ``cuda.mapped``), ``copied`` (the fallback: the driver refused to register that page) or
  ``simulator``;
- ``compile_s``: the warm-up launch (compilation or the disk cache);
- ``plain_s`` / ``watched_s``: the same ``--overhead-samples`` lanes of one revolution
  without flags (a zero byte in device memory) and with the mapped flags (every warp reads
  host memory once per step): the cost of watching;
- ``signal_to_return_s``: from the SIGINT to ``run_batch``'s return, copies back included
  (issue 24's target: Ctrl-C ≤ 2 s), ``keyboard_interrupt`` whether the context raised it,
  and the lanes ``finished`` / ``interrupted`` / other.

Run ``python benchmarks/bench_gpu_interrupt.py`` on a GPU (defaults: 100 000 lanes of 20
revolutions, SIGINT after 2 s); ``NUMBA_ENABLE_CUDASIM=1 python
benchmarks/bench_gpu_interrupt.py --samples 3 --revolutions 3 --after 3
--overhead-samples 0`` checks it on the simulator. Not yet run on a GPU.
"""

from __future__ import annotations

import argparse
import json
import os
import signal
import threading
import time
from typing import Any

import numpy as np

from jointplay._kernels import eom, ids
from jointplay._kernels.lanes import cuda as lanes_cuda
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.setup import DEFAULT_IMPACT
from jointplay.dynamics.simulate import Start, initial_state
from jointplay.dynamics.system import build_system
from jointplay.execution.interrupts import interrupts_watched
from jointplay.io.config import load_preset

JOINTS = ("O2", "A", "B", "O4")


def problem(n: int, revolutions: float, seed: int = 0) -> tuple[Any, ...]:
    """``run_batch``'s arguments for ``n`` lanes of ``revolutions`` revolutions."""
    mechanism = load_preset("paper-fourbar")
    system = build_system(
        mechanism, [ClearanceJoint(j, 11.75e-6, 0.005, DEFAULT_IMPACT) for j in JOINTS]
    )
    rpar, ipar = eom.pack(system.model)
    y0 = initial_state(system, Start("steady"))
    k = system.n_coordinates
    atol = np.concatenate(
        [np.full(k, 1e-10), np.full(k, 1e-6), np.full(2, 1e-6), np.ones(len(JOINTS))]
    )
    period = mechanism.driver.period
    ys = np.tile(y0, (n, 1))
    ys[:, k : 2 * k] *= 1.0 + 0.01 * np.random.default_rng(seed).random((n, 1))
    return (
        ipar, np.tile(rpar, (n, 1)), ys, np.zeros(n), np.full(n, revolutions * period),
        np.full(n, period / 360.0), 1e-6, atol, 10_000_000, "explicit",
    )  # fmt: skip


def flags_path() -> str:
    """How :func:`lanes_cuda.run_batch` will hand the interrupt page to the device."""
    if lanes_cuda.simulated():
        return "simulator"
    from numba import cuda
    from numba.cuda.cudadrv.driver import CudaAPIError

    with interrupts_watched() as flags:
        if flags is None:
            return "none (not the main thread, or SIGINT has no Python handler)"
        try:
            with cuda.mapped(flags):
                pass
        except CudaAPIError as error:
            return f"copied ({error})"
    return "mapped"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--samples", type=int, default=100_000)
    parser.add_argument("--revolutions", type=float, default=20.0)
    parser.add_argument("--after", type=float, default=2.0, help="SIGINT after this many s")
    parser.add_argument("--overhead-samples", type=int, default=100_000, help="0: skip")
    parser.add_argument("--json", default=None, help="write the row to this file")
    args = parser.parse_args()
    lanes_cuda.raise_unless_available()
    row: dict[str, Any] = {"samples": args.samples, "revolutions": args.revolutions,
                           "after_s": args.after, "flags": flags_path()}  # fmt: skip
    clock = time.perf_counter()
    lanes_cuda.run_batch(*problem(2, 0.01))
    row["compile_s"] = time.perf_counter() - clock
    if args.overhead_samples:
        one = problem(args.overhead_samples, 1.0)
        for name in ("plain_s", "watched_s"):
            with interrupts_watched() as flags:
                clock = time.perf_counter()
                lanes_cuda.run_batch(*one, interrupt=flags if name == "watched_s" else None)
                row[name] = time.perf_counter() - clock
    long = problem(args.samples, args.revolutions)
    sent: list[float] = []

    def interrupt() -> None:
        sent.append(time.perf_counter())
        os.kill(os.getpid(), signal.SIGINT)

    timer = threading.Timer(args.after, interrupt)
    row["keyboard_interrupt"] = False
    clock = time.perf_counter()
    try:
        with interrupts_watched() as flags:
            timer.start()
            try:
                out = lanes_cuda.run_batch(*long, interrupt=flags)
            finally:
                returned = time.perf_counter()
                timer.cancel()  # a launch done before the SIGINT: none is sent
    except KeyboardInterrupt:
        row["keyboard_interrupt"] = True
    row["launch_s"] = returned - clock
    row["signal_to_return_s"] = returned - sent[0] if sent else None
    row["finished"] = int(np.sum(out.status == ids.STATUS_SUCCESS))
    row["interrupted"] = int(np.sum(out.status == ids.STATUS_INTERRUPTED))
    row["other"] = args.samples - row["finished"] - row["interrupted"]
    row["median_steps"] = float(np.median(out.n_steps))
    for key, value in row.items():
        print(f"{key:>20}: {value:.4g}" if isinstance(value, float) else f"{key:>20}: {value}")
    if args.json:
        with open(args.json, "w") as handle:
            json.dump(row, handle, indent=1)


if __name__ == "__main__":
    main()
