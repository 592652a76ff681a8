"""Rare defects (issue 23): cross-entropy importance sampling against brute-force Monte Carlo
on the paper's four-bar, where brute force is affordable.

Case: scheme H8/f7 / ISO 2768-1 c, link lengths sampled as made (normal ±3σ, truncated at
the class limits), the requirement ``rocker_swing <= LIMIT`` on the ideal-joint kinematics
(the limit sets DPM ≈ 3e3 by default; ``--n-stage``, ``--n-final`` set the budget). Brute force: ``--brute`` samples (default 10⁶) of the
same specification through the same response model, with the exact (Clopper–Pearson) 95 %
interval of their defect rate. Importance sampling: the design study's own path
(``design_study(..., rare=RareDefects())``: at most 8 pilot stages of 1 000 samples and
10 000 final ones) for ``--seeds`` seeds; each interval is compared with the brute-force
estimate.

``--dynamic`` runs the same comparison through the dynamics (batch engine, conventional IFM
set, steady start, no start-up revolution, a quarter turn analysed) on ``joint_force <=
--force-limit``: brute force then costs about 10 ms a sample per core.

Run ``python benchmarks/bench_rare_defects.py``; record the figures in docs/design.md.
"""

from __future__ import annotations

import argparse
import time

import numpy as np

from jointplay.io.config import load_preset
from jointplay.study.design import RareDefects, Scheme, design_study
from jointplay.tolerance.confidence import YieldEstimate
from jointplay.tolerance.execution import Backend, run
from jointplay.tolerance.methods import truncated_at_limits
from jointplay.tolerance.parts import model_inputs
from jointplay.tolerance.responses import kinematic_model
from jointplay.tolerance.sampling import sample

FIT, CLASS = "H8/f7", "c"
SERIAL = Backend("serial")


def brute_force(
    mechanism, requirement: str, n: int, backend: Backend, dynamic: bool
) -> YieldEstimate:
    """Defects among ``n`` plain Monte Carlo samples (seed 1, apart from the design's 0)."""
    if dynamic:
        result = design_study(
            mechanism, [FIT], [CLASS], [requirement], samples=n, seed=1, confidence=0.5,
            backend=backend, settle=0, revolutions=0.25, contact="ifm-conventional",
        )  # fmt: skip
        row = result.table.iloc[0]
        return YieldEstimate(int(row[f"failures_{requirement}"]), int(row["samples"]))
    scheme = Scheme(dict.fromkeys(("O2", "A", "B", "O4"), FIT), CLASS)
    spec = truncated_at_limits(scheme.spec(mechanism).only("length"))
    names, _ = model_inputs(spec.names, np.empty((0, len(spec))))
    model = kinematic_model(mechanism, names)
    failures = 0
    limit = float(requirement.split("<=")[1].split()[0])
    for start in range(0, n, 200_000):  # in blocks: memory
        block = min(200_000, n - start)
        x = sample(spec, start + block, 1).values[start:]
        _, x = model_inputs(spec.names, x)
        swing = run(model, x, backend=SERIAL).values[
            :, list(model.response_names).index("rocker_swing")
        ]
        failures += int(np.sum(~(np.degrees(swing) <= limit)))
    return YieldEstimate(failures, n)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__)
    parser.add_argument("--brute", type=int, default=1_000_000)
    parser.add_argument("--seeds", type=int, default=10)
    parser.add_argument("--limit", type=float, default=53.065, help="rocker swing limit, deg")
    parser.add_argument("--dynamic", action="store_true")
    parser.add_argument("--force-limit", type=float, default=60.0, help="N (--dynamic)")
    parser.add_argument("--workers", type=int, default=None)
    parser.add_argument("--n-stage", type=int, default=1000, help="pilot stage samples")
    parser.add_argument("--n-final", type=int, default=10000, help="final stage samples")
    args = parser.parse_args()
    mechanism = load_preset("paper-fourbar")
    backend = Backend("processes", workers=args.workers) if args.dynamic else SERIAL
    requirement = (
        f"joint_force <= {args.force_limit:g} N"
        if args.dynamic
        else f"rocker_swing <= {args.limit:g} deg"
    )
    extra = {"settle": 0, "revolutions": 0.25} if args.dynamic else {}
    start = time.perf_counter()
    brute = brute_force(mechanism, requirement, args.brute, backend, args.dynamic)
    brute_s = time.perf_counter() - start
    low, high = brute.dpm_interval
    print(f"case: paper-fourbar, {FIT} / {CLASS}, '{requirement}'")
    print(
        f"brute force: {brute.failures} defects in {brute.samples:,} samples = {brute.dpm:,.0f} "
        f"DPM (exact 95 % interval {low:,.0f}-{high:,.0f}), {brute_s:.1f} s"
    )
    covered = inside = 0
    widths = []
    for seed in range(args.seeds):
        start = time.perf_counter()
        result = design_study(
            mechanism, [FIT], [CLASS], [requirement], samples=100, seed=seed,
            rare=RareDefects(args.n_stage, args.n_final), backend=backend, **extra,
        )  # fmt: skip
        row = result.table.iloc[0]
        seconds = time.perf_counter() - start
        hit = row["dpm_rare_low"] <= brute.dpm <= row["dpm_rare_high"]
        overlap = row["dpm_rare_low"] <= high and low <= row["dpm_rare_high"]
        covered += hit
        inside += low <= row["dpm_rare"] <= high
        widths.append(0.5 * (row["dpm_rare_high"] - row["dpm_rare_low"]) / row["dpm_rare"])
        print(
            f"  seed {seed}: importance sampling {row['dpm_rare']:,.0f} DPM "
            f"(95 % {row['dpm_rare_low']:,.0f}-{row['dpm_rare_high']:,.0f}) from "
            f"{row['rare_samples']:,} samples, {seconds:.1f} s; holds the brute-force "
            f"estimate: {'yes' if hit else 'no'}; intervals overlap: {'yes' if overlap else 'no'}"
        )
    print(
        f"importance sampling: {covered} of {args.seeds} intervals hold the brute-force "
        f"estimate, {inside} of {args.seeds} estimates lie in the brute-force interval; relative half-width median {100 * float(np.median(widths)):.1f} %, largest "
        f"{100 * max(widths):.1f} %"
    )


if __name__ == "__main__":
    main()
