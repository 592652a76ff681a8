"""Compile the numba-cuda lane kernels to PTX without a GPU: that every batch method's kernel
lowers for a real device (not only runs on the simulator), and its local memory per thread.

numba-cuda's ``compile_ptx`` needs libNVVM, not a driver: install it in a venv of its own
(the test environment has numba-cuda without the CUDA wheels, for the simulator)::

    python -m venv /tmp/cuda-venv && . /tmp/cuda-venv/bin/activate
    pip install -e . "numba-cuda[cu12]>=0.30.4"
    python benchmarks/gpu_ptx.py            # sm_90 (H100/H200); --cc 8 0 for an A100

A device function asks the current device for its compute capability when it compiles; the
script answers with ``--cc`` (no device is opened). Each line: the method, the compile time,
the PTX's length, the kernel's local-memory depot (bytes a thread) and any external function
the PTX calls (which would have to be linked at load: none expected). Measured on the
2-core machine, 2026-11-30: explicit 13 136 B, implicit 26 928 B; 30 s and 82 s.
"""

from __future__ import annotations

import argparse
import re
import time
import types


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--cc", type=int, nargs=2, default=(9, 0), help="compute capability")
    cc = tuple(parser.parse_args().cc)

    import numba.cuda.dispatcher as dispatcher

    dispatcher.get_current_device = lambda: types.SimpleNamespace(compute_capability=cc)  # type: ignore[attr-defined]

    import numba
    from numba import cuda

    from jointplay._kernels.lanes.cuda_kernel import KERNELS

    f8, i8, u8 = numba.float64, numba.int64, numba.uint8
    # the launch's arguments (cuda.run_batch): ipar, rpar, lay, y0, t_settle, t_end,
    # max_step, rtol, atol, max_steps, interrupt, peaks, stats, status, t_reached, counts
    signature = (
        i8[::1], f8[:, ::1], i8[::1], f8[:, ::1], f8[::1], f8[::1], f8[::1], f8, f8[::1], i8,
        u8[::1], f8[:, ::1], f8[:, ::1], i8[::1], f8[::1], i8[:, ::1],
    )  # fmt: skip
    for method, kernel in KERNELS.items():
        clock = time.perf_counter()
        ptx, _ = cuda.compile_ptx(kernel.py_func, signature, cc=cc)
        depot = re.findall(r"__local_depot\d+\[(\d+)\]", ptx)
        extern = sorted(set(re.findall(r"^\.extern \.func.*?(\w+)$", ptx, re.M)))
        print(
            f"{method}: compiled in {time.perf_counter() - clock:.0f} s for sm_{cc[0]}{cc[1]}, "
            f"PTX {len(ptx.splitlines())} lines, local depot {depot} bytes, external {extern}"
        )


if __name__ == "__main__":
    main()
