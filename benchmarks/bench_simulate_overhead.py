"""Benchmark: what a warm :func:`~jointplay.dynamics.simulate.simulate` call costs beyond its solver.

Run with ``python benchmarks/bench_simulate_overhead.py`` (``--help`` for options). The case
is the paper's four-bar (preset ``paper-fourbar``, 200 RPM) with 21 µm clearance in all four
joints (journal radius 5 mm), the conventional IMPACT set of Table 3 (k = 1e4 N/mm^1.5,
e = 1.5, c_max = 10 N·s/mm, d = 0.1 mm), a steady start, one revolution and the default
:class:`~jointplay.dynamics.simulate.SolverOptions`.

After ``--warmup`` calls (compilation or loading from Numba's cache), each of ``--repeat``
calls is timed whole (``time.perf_counter`` around ``simulate()``) and by its solver alone
(``solver_stats["wall_s"]``: the compiled integration). The best of each is reported with
their ratio; the target of issue 8 is a whole call of at most 1.3 times its solver time.
With ``--tables`` each call also reads ``steps`` and ``timeseries`` (which are built on
first access), to show the cost a caller pays who wants them.
"""

from __future__ import annotations

import argparse
import time

from jointplay.contact.laws import get_law
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.simulate import Start, simulate
from jointplay.io.config import load_preset

#: Conventional IMPACT parameters (Table 3), SI: k [N/m^1.5], c_max [N·s/m], d_max [m].
CONVENTIONAL = {"stiffness": 1e4 * 1000.0**1.5, "exponent": 1.5, "c_max": 1e4, "d_max": 1e-4}
JOINTS = ("O2", "A", "B", "O4")
CLEARANCE = 21e-6  # m
JOURNAL_RADIUS = 5e-3  # m
#: Largest accepted ratio of a whole warm call to its solver time (issue 8, item 8).
TARGET_RATIO = 1.3


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--warmup", type=int, default=2, help="untimed calls first")
    parser.add_argument("--repeat", type=int, default=10, help="timed calls")
    parser.add_argument("--tables", action="store_true", help="also read steps and timeseries")
    options = parser.parse_args()

    mechanism = load_preset("paper-fourbar")
    law = get_law("impact", **CONVENTIONAL)
    joints = [ClearanceJoint(j, CLEARANCE, JOURNAL_RADIUS, law) for j in JOINTS]
    start = Start("steady")

    def call() -> tuple[float, float]:
        wall = time.perf_counter()
        result = simulate(mechanism, joints, revolutions=1.0, settle=0, start=start)
        if options.tables:
            _ = result.steps, result.timeseries
        return time.perf_counter() - wall, float(result.solver_stats["wall_s"])

    for _ in range(options.warmup):
        call()
    timings = [call() for _ in range(options.repeat)]
    whole = min(w for w, _ in timings)
    solver = min(s for _, s in timings)
    ratio = whole / solver
    print("paper-fourbar, 4 clearance joints, conventional set, steady start, 1 revolution")
    print(
        f"best of {options.repeat} warm calls{' (reading the tables)' if options.tables else ''}:"
    )
    print(f"  solver      {1e3 * solver:8.1f} ms")
    print(f"  whole call  {1e3 * whole:8.1f} ms")
    print(
        f"  ratio       {ratio:8.2f}  (target <= {TARGET_RATIO}: {'met' if ratio <= TARGET_RATIO else 'NOT met'})"
    )


if __name__ == "__main__":
    main()
