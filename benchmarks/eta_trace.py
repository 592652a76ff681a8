"""The time-left estimate of a real run, traced: is the rule of :mod:`jointplay.progress` kept?

Runs a ``jointplay`` command in this process (default: the 200-sample dynamic tolerance
study of issue 25) with :class:`jointplay.progress.Eta` replaced by a subclass that records,
at every redraw of the progress bar, the elapsed time, the work done and the time left shown.
After the run it compares, from 10 % of the work on (before that nothing is shown):

* the time left shown against the one the average speed since the start gives,
  (work left) / (done / elapsed): the rule is that the shown one is never more than 20 %
  below it;
* the time left shown against the time that was in fact left (the first redraw with all
  the work done, minus the moment of the sample).

Usage (from the repository root; the progress bar is drawn only on a terminal, so the script
sets ``TTY_COMPATIBLE=1`` for Rich)::

    python benchmarks/eta_trace.py [--trace trace.csv] -- tolerance --preset paper-fourbar \\
        --responses dynamic -n 200 --seed 1 --out /tmp/eta-run

It prints the machine's load average before and after, the number of samples of the trace
and the two deviations (largest and median), and writes the trace as CSV with ``--trace``.
"""

from __future__ import annotations

import argparse
import csv
import io
import os
import statistics
import sys
import time
from contextlib import redirect_stderr

DEFAULT = ["tolerance", "--preset", "paper-fourbar", "--responses", "dynamic", "-n", "200",
           "--seed", "1", "--out", "/tmp/jointplay-eta-trace", "--force"]  # fmt: skip


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--trace", help="write the trace (CSV) here")
    parser.add_argument("command", nargs="*", help="the jointplay arguments (after --)")
    options = parser.parse_args(argv)
    command = options.command or DEFAULT
    os.environ["TTY_COMPATIBLE"] = "1"  # Rich draws the bar only on a terminal

    import jointplay.progress
    from jointplay.cli._app import run

    rows: list[tuple[float, float, float, float | None]] = []  # wall, elapsed, done, shown
    totals: set[float] = set()

    class Traced(jointplay.progress.Eta):
        def remaining(self, elapsed: float) -> float | None:
            left = super().remaining(elapsed)
            rows.append((time.perf_counter(), elapsed, self._done, left))
            totals.add(self.total)
            return left

    jointplay.progress.Eta = Traced  # type: ignore[misc]
    load_before = os.getloadavg()
    with redirect_stderr(io.StringIO()):  # the bar's drawing: not wanted in the terminal
        status = run(command)
    end = time.perf_counter()
    load_after = os.getloadavg()
    if status != 0 or not rows:
        print(f"jointplay {' '.join(command)} exited {status}; {len(rows)} trace samples")
        return 1
    total = max(totals)  # one bar: its work in all
    # the bar's end: its first redraw with all the work done (what follows, the report's
    # writing, is not the bar's time left); the command's end if it never drew that
    end = next((wall for wall, _, done, _ in rows if done >= total), end)
    below, error, kept = [], [], []
    for wall, elapsed, done, shown in rows:
        if shown is None or done < 0.1 * total or done >= total or elapsed <= 0:
            continue
        elapsed_rate = (total - done) / (done / elapsed)
        actual = end - wall
        below.append(max(0.0, 1.0 - shown / elapsed_rate))
        error.append((shown - actual) / actual)
        kept.append((wall, elapsed, done, shown, elapsed_rate, actual))
    print(f"command: jointplay {' '.join(command)}")
    print(f"load average (1, 5, 15 min) before: {load_before}, after: {load_after}")
    steps = sorted({done for _, _, done, _ in rows})
    print(f"run: {rows[-1][1]:.1f} s of progress bar, {total:.0f} units of work arriving in "
          f"{len(steps)} steps ({', '.join(f'{d:g}' for d in steps)}); {len(rows)} redraws, "
          f"{len(kept)} with a time left shown (from 10 % of the work)")  # fmt: skip
    if kept:
        print(f"shown time left below the elapsed-rate one: largest {100 * max(below):.1f} %, "
              f"median {100 * statistics.median(below):.1f} % (rule: at most 20 %)")  # fmt: skip
        print(f"shown time left against the time in fact left: from "
              f"{100 * min(error):+.0f} % to {100 * max(error):+.0f} %, median "
              f"{100 * statistics.median(error):+.0f} %")  # fmt: skip
    if options.trace:
        with open(options.trace, "w", newline="") as handle:
            writer = csv.writer(handle)
            writer.writerow(["elapsed_s", "done", "shown_left_s", "elapsed_rate_left_s",
                             "actual_left_s"])  # fmt: skip
            for _, elapsed, done, shown, rate, actual in kept:
                writer.writerow([f"{elapsed:.2f}", f"{done:g}", f"{shown:.1f}", f"{rate:.1f}",
                                 f"{actual:.1f}"])  # fmt: skip
    return 0 if not below or max(below) <= 0.2 + 1e-9 else 2


if __name__ == "__main__":
    sys.exit(main())
