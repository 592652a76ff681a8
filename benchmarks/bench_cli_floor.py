"""The floor of a default ``jointplay simulate --no-plots`` (issue 41, item 5).

``python benchmarks/bench_cli_floor.py [N]``: each line runs in a fresh interpreter, once to
warm the file cache and then N times (default 5); best and median wall time and CPU time
(user + system of the child, ``os.wait4``), and the ratios to ``jointplay --version``. The
imports in order show what the command cannot avoid: Python, NumPy, Numba, Numba's CPU target
with one kernel loaded from the cache, the simulation modules, the command itself.
Figures: docs/performance.md, "Command-line start-up: the floor".
"""

from __future__ import annotations

import os
import statistics
import subprocess
import sys
import tempfile
import time


def run(args: list[str]) -> tuple[float, float]:
    """Wall and CPU seconds of ``python ARGS`` in a fresh interpreter."""
    start = time.perf_counter()
    child = subprocess.Popen(
        [sys.executable, *args], stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL
    )
    _, status, usage = os.wait4(child.pid, 0)
    if status != 0:
        raise SystemExit(f"python {' '.join(args)} failed (status {status})")
    return time.perf_counter() - start, usage.ru_utime + usage.ru_stime


def main(repeat: int) -> None:
    out = tempfile.mkdtemp()
    cases = {
        "python -c pass": ["-c", "pass"],
        "jointplay --version": ["-m", "jointplay", "--version"],
        "import numpy": ["-c", "import numpy"],
        "import numba": ["-c", "import numba"],
        "import numba + first cached kernel": ["-c", "import jointplay._kernels.constraints"],
        "import jointplay.dynamics.simulate": ["-c", "import jointplay.dynamics.simulate"],
        "simulate --no-plots": [
            "-m", "jointplay", "simulate", "--no-plots", "--out", f"{out}/run", "--force",
        ],
    }  # fmt: skip
    base: tuple[float, float] | None = None
    for name, args in cases.items():
        run(args)
        walls, cpus = zip(*(run(args) for _ in range(repeat)), strict=True)
        wall, cpu = statistics.median(walls), statistics.median(cpus)
        if name == "jointplay --version":
            base = (wall, cpu)
        ratio = f"  ({wall / base[0]:.1f}x / {cpu / base[1]:.1f}x of --version)" if base else ""
        print(
            f"{name:40s} wall best {min(walls):.3f} median {wall:.3f}"
            f"  cpu best {min(cpus):.3f} median {cpu:.3f}{ratio}",
            flush=True,
        )


if __name__ == "__main__":
    main(int(sys.argv[1]) if len(sys.argv) > 1 else 5)
