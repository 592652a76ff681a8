"""Which statistics of irregular (chaotic) running converge: one long trajectory against an
ensemble, on the dry paper four-bar (issue 40, item 1; docs/performance.md, "Accuracy of
irregular (chaotic) running").

For each of F_O2, F_A, F_B, F_O4 and omega4, the mean and the 95th percentile of the
per-revolution peak, with their 95 % intervals, at the default tolerances and at rtol and both
absolute tolerances 100 times tighter, and whether the two agree (``agrees``: the difference
within the root sum of the facing half-widths):

- one trajectory: settle 2 + ``--revolutions`` (default 150) analysed revolutions;
- an ensemble: ``--runs`` (default 12) runs from start angles 0.01 deg apart, settle 2 +
  ``--run-revolutions`` (default 20) each, the runs as batches.

The test (``tests/dynamics/test_irregular_contract.py``) judges the ensemble's means; this
script shows what it does not judge. Several minutes on 2 cores (the tight long run costs
most). Run: ``python benchmarks/bench_irregular_contract.py``.
"""

from __future__ import annotations

import argparse
import dataclasses
import time

from jointplay.dynamics.ensemble import simulate_ensemble
from jointplay.dynamics.irregular import PeakDistribution, agrees, peak_distribution
from jointplay.dynamics.settings import RunSettings, simulate_run
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import SolverOptions
from jointplay.io.config import load_preset

QUANTITIES = ("F_O2", "F_A", "F_B", "F_O4", "omega4")


def _solver(factor: float) -> SolverOptions:
    base = SolverOptions()
    return dataclasses.replace(base.tightened(factor), max_steps=10 * base.max_steps)


def _run(revolutions: int, factor: float) -> RunSettings:
    return RunSettings(
        contact=ContactModel(lubrication="dry"),
        settle=2,
        revolutions=float(revolutions),
        solver=_solver(factor),
    )


def _row(label: str, pair: list[dict[str, PeakDistribution]]) -> None:
    for quantity in QUANTITIES:
        a, b = pair[0][quantity], pair[1][quantity]
        verdict = agrees(a, b, ("mean", "quantile"))
        for statistic in ("mean", "quantile"):
            x, y = getattr(a, statistic), getattr(b, statistic)
            print(
                f"{label:10s} {quantity:7s} {statistic:8s} "
                f"{x.value:10.4g} [{x.low:.4g}, {x.high:.4g}]   "
                f"{y.value:10.4g} [{y.low:.4g}, {y.high:.4g}]   "
                f"{'agree' if verdict[statistic] else 'DIFFER'}"
            )


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--revolutions", type=int, default=150)
    parser.add_argument("--runs", type=int, default=12)
    parser.add_argument("--run-revolutions", type=int, default=20)
    args = parser.parse_args()
    mechanism = load_preset("paper-fourbar")
    print("which      quantity statistic  default [95 %]              x100 tighter [95 %]")
    started = time.perf_counter()
    single = []
    for factor in (1.0, 100.0):
        running = simulate_run(mechanism, None, _run(args.revolutions, factor)).running
        per = running.analysed_per_revolution
        single.append({q: peak_distribution(per[q]) for q in QUANTITIES})
    _row("one run", single)
    ensembles = [
        simulate_ensemble(mechanism, None, _run(args.run_revolutions, f), runs=args.runs)
        for f in (1.0, 100.0)
    ]
    _row("ensemble", [e.distributions for e in ensembles])
    print(f"{time.perf_counter() - started:.0f} s")


if __name__ == "__main__":
    main()
