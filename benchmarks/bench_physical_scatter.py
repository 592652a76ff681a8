"""The accuracy contract of a sensitive motion: scatter of settled peaks and study statistics (issue 22).

With the physical default contact (docs/contact.md) the peaks of a settled revolution do not
converge at any integrator tolerance (docs/performance.md, "Accuracy: the peaks after the
first revolution do not converge"). This script measures whether the *statistics* do.

``scatter``: the paper's four-bar, single engine (:func:`simulate`), steady start, settle 2
then ``--revolutions`` analysed revolutions, for three clearance sets and the conventional
set. The peak of F_O2, F_A, F_B, F_O4, |ω3|, |ω4| in each analysed revolution is located on
the continuous solution (:func:`~jointplay.dynamics.peaks.locate_peaks`, as
:attr:`SimulationResult.peaks`). Per set and tolerance: mean, standard deviation, CV and
min–max over the revolutions, lag-1 autocorrelation; against the tight run: the difference
of the means over its standard error, and the median paired (same revolution) difference
over the scatter.

``study``: the dynamic tolerance study of the paper's four-bar (``tolerance_study``,
``responses="dynamic"``, Monte Carlo, ``--samples`` samples, ``--seed`` (1), processes backend: what
``jointplay tolerance --preset paper-fourbar --responses dynamic -n N --seed 1 --backend
processes`` runs) with the physical default at rtol 1e-4, 1e-5, 1e-6 (default atol) and a
tight reference (rtol 1e-8, atol 1e-12 m / 1e-8 m/s), and the conventional set at the
default tolerances. The same seed draws the same samples. Every response's mean and 95th
percentile, and the share of F_B peaks <= 150 N, against the reference: paired bootstrap 95 %
CIs of the differences, the differences over the reference's standard deviation, KS p-value,
median paired |Δ| over the standard deviation; and the cost: the study's wall time, the
sampling run's wall time (without the convergence check) and the batch engine's steps and
rhs evaluations per sample (recorded by wrapping ``simulate_batch``).

Run ``python benchmarks/bench_physical_scatter.py --part scatter|study|all``; ``--save
FILE.npz`` keeps the raw peaks.
"""

from __future__ import annotations

import argparse
import dataclasses
import os
import time
from collections.abc import Callable, Sequence
from typing import Any

import numpy as np
from numpy.typing import NDArray

import jointplay.dynamics.batch as batch_module
from jointplay.dynamics.clearance import ClearanceJoint
from jointplay.dynamics.peaks import locate_peaks
from jointplay.dynamics.setup import ContactModel, conventional_contact
from jointplay.dynamics.simulate import SimulationResult, SolverOptions, Start, simulate
from jointplay.io.config import load_preset
from jointplay.tolerance.analysis import tolerance_study
from jointplay.tolerance.execution import Backend
from jointplay.tolerance.methods import MonteCarlo
from jointplay.tolerance.spec import JointTolerance, ToleranceSpec

FloatArray = NDArray[np.float64]
JOINTS = ("O2", "A", "B", "O4")
QUANTITIES = ("F_O2", "F_A", "F_B", "F_O4", "omega3", "omega4")
#: Clearance sets of the scatter part: radial clearance per joint, m.
SETS: dict[str, tuple[str, dict[str, float]]] = {
    "21": ("21 µm (the fits')", dict.fromkeys(JOINTS, 21e-6)),
    "10": ("10 µm", dict.fromkeys(JOINTS, 10e-6)),
    "mixed": ("mixed 15/30/10/25 µm", {"O2": 15e-6, "A": 30e-6, "B": 10e-6, "O4": 25e-6}),
}
DEFAULT = (1e-6, 1e-10, 1e-6)
TIGHT_SCATTER = (1e-9, 1e-12, 1e-8)
SCATTER_TOLERANCES = ((1e-4, 1e-10, 1e-6), (1e-5, 1e-10, 1e-6), DEFAULT, TIGHT_SCATTER)
#: ``--control``: a second tight run, to see how far two tight runs' statistics differ.
CONTROL = (1e-10, 1e-13, 1e-9)
BLOCK = 5  # revolutions per batch mean in the standard errors, with >= 40 revolutions
REFERENCE = (1e-8, 1e-12, 1e-8)
STUDY_TOLERANCES = ((1e-4, 1e-10, 1e-6), (1e-5, 1e-10, 1e-6), DEFAULT)
STUDY_RESPONSES = ("F_O2", "F_A", "F_B", "F_O4", "omega3", "omega4", "alpha3", "alpha4", "torque")
YIELD_LIMIT = 100.0  # N, F_B peak (about the 90th percentile: 150 N is never reached)
BOOTSTRAP = 4000


def load() -> str:
    return "/".join(f"{v:.2f}" for v in os.getloadavg())


def solver_of(tolerances: tuple[float, float, float]) -> SolverOptions:
    rtol, atol_position, atol_velocity = tolerances
    return SolverOptions(rtol=rtol, atol_position=atol_position, atol_velocity=atol_velocity)


def label_of(tolerances: tuple[float, float, float]) -> str:
    return "/".join(f"{v:g}" for v in tolerances)


# --- scatter ---------------------------------------------------------------------------------


def joints_of(clearances: dict[str, float], contact: ContactModel) -> list[ClearanceJoint]:
    mechanism = load_preset("paper-fourbar")
    joints: list[ClearanceJoint] = []
    for joint in JOINTS:
        joints += contact.joints(mechanism, (joint,), clearance=clearances[joint])
    return joints


def revolution_peaks(result: SimulationResult, settle: int, revolutions: int) -> FloatArray:
    """(revolutions, quantities) peak |value| of each analysed revolution, located on the
    continuous solution."""
    period = 60.0 / 200.0
    columns = result._step_columns
    windows = [((settle + k) * period, (settle + k + 1) * period) for k in range(revolutions)]
    located = locate_peaks(result.t, {q: columns[q] for q in QUANTITIES}, result.evaluate, windows)
    return np.array([[located[q][w].value for q in QUANTITIES] for w in range(revolutions)])


def lag1(values: FloatArray) -> float:
    v = values - values.mean()
    return float(np.sum(v[1:] * v[:-1]) / np.sum(v * v)) if np.any(v) else float("nan")


def standard_error(values: FloatArray) -> float:
    """Standard error of the mean of a run's per-revolution peaks: plain with fewer than 40
    revolutions, else from batch means of :data:`BLOCK` revolutions (revolutions of one run
    need not be independent)."""
    if len(values) < 40:
        return float(values.std(ddof=1) / np.sqrt(len(values)))
    blocks = values[: len(values) // BLOCK * BLOCK].reshape(-1, BLOCK).mean(axis=1)
    return float(blocks.std(ddof=1) / np.sqrt(len(blocks)))


def scatter(revolutions: int, settle: int, sets: Sequence[str], control: bool,
            saved: dict[str, Any]) -> None:  # fmt: skip
    mechanism = load_preset("paper-fourbar")
    cases: list[tuple[str, ContactModel, dict[str, float]]] = []
    for key in sets:
        if key == "conventional":
            cases.append(("conventional, 21 µm", conventional_contact(), SETS["21"][1]))
        else:
            cases.append((f"physical, {SETS[key][0]}", ContactModel(), SETS[key][1]))
    tolerances_list = (*SCATTER_TOLERANCES, CONTROL) if control else SCATTER_TOLERANCES
    # the first call loads the compiled kernels
    simulate(mechanism, joints_of(SETS["10"][1], ContactModel()), revolutions=1, settle=0,
             start=Start("steady"))  # fmt: skip
    print(f"\nsettle {settle} + {revolutions} analysed revolutions, steady start, peaks on the "
          "continuous solution; n = revolutions per statistic; SE "
          + ("plain" if revolutions < 40 else f"from batch means of {BLOCK} revolutions")
          + "\n")  # fmt: skip
    for case, contact, clearances in cases:
        peaks: dict[tuple[float, float, float], FloatArray] = {}
        cost: dict[tuple[float, float, float], str] = {}
        for tolerances in tolerances_list:
            before = load()
            result = simulate(
                mechanism,
                joints_of(clearances, contact),
                revolutions=revolutions,
                settle=settle,
                start=Start("steady"),
                solver=solver_of(tolerances),
            )
            stats = result.solver_stats
            peaks[tolerances] = revolution_peaks(result, settle, revolutions)
            saved[f"scatter|{case}|{revolutions}|{label_of(tolerances)}"] = peaks[tolerances]
            total = settle + revolutions
            cost[tolerances] = (
                f"{stats['steps'] / total:.0f} steps, {stats['rhs_evaluations'] / total:.0f} rhs "
                f"per revolution; {stats['wall_s'] / total * 1e3:.1f} ms per revolution "
                f"(load {before} -> {load()})"
            )
        print(f"### {case}\n")
        for tolerances in tolerances_list:
            print(f"- {label_of(tolerances)}: {cost[tolerances]}")
        tight = peaks[TIGHT_SCATTER]
        print()
        print("| quantity | rtol | mean | std | CV | min–max | lag-1 r | Δmean/SE vs tight | "
              "median paired abs(Δ)/std |")  # fmt: skip
        print("|---|---:|---:|---:|---:|---|---:|---:|---:|")
        for j, quantity in enumerate(QUANTITIES):
            for tolerances in tolerances_list:
                v = peaks[tolerances][:, j]
                w = tight[:, j]
                mean, std = v.mean(), v.std(ddof=1)
                if tolerances == TIGHT_SCATTER:
                    versus = paired = "—"
                else:
                    se = np.hypot(standard_error(v), standard_error(w))
                    versus = f"{(mean - w.mean()) / se:+.2f}" if se > 0 else "—"
                    scale = max(std, w.std(ddof=1))
                    paired = f"{np.median(np.abs(v - w)) / scale:.2f}" if scale > 0 else "—"
                print(
                    f"| {quantity} | {tolerances[0]:g} | {mean:.5g} | {std:.3g} | "
                    f"{std / mean:.2%} | {v.min():.5g}–{v.max():.5g} | {lag1(v):+.2f} | "
                    f"{versus} | {paired} |"
                )
        print(flush=True)


# --- study -----------------------------------------------------------------------------------


class CountingBatch:
    """Wraps ``simulate_batch`` (the study's blocks run from this process) and keeps each
    block's counters."""

    def __init__(self, original: Callable[..., Any]) -> None:
        self.original = original
        self.counters: list[Any] = []
        self.placement: list[str] = []

    def __call__(self, *args: Any, **kwargs: Any) -> Any:
        result = self.original(*args, **kwargs)
        self.counters.append(result.counters)
        self.placement.append(f"{result.backend}×{result.workers}/{result.chunk_size}")
        return result


def fixed_clearance_spec(mechanism: Any, clearance: float | None) -> ToleranceSpec | None:
    """The paper four-bar's tolerances with every clearance drawn within ±1 % of
    ``clearance`` (m) instead of its fit (``None``: the fits)."""
    if clearance is None:
        return None
    spec = ToleranceSpec.from_mechanism(mechanism)
    narrow = (0.99 * clearance, 1.01 * clearance)
    inputs = tuple(
        dataclasses.replace(i, tolerance=dataclasses.replace(i.tolerance, limits=narrow))
        if isinstance(i, JointTolerance)
        else i
        for i in spec.inputs
    )
    return dataclasses.replace(spec, inputs=inputs)


def run_study(
    samples: int,
    seed: int,
    contact: Any,
    tolerances: tuple[float, float, float],
    clearance: float | None = None,
) -> dict[str, Any]:
    mechanism = load_preset("paper-fourbar")
    spec = fixed_clearance_spec(mechanism, clearance)
    counting = CountingBatch(batch_module.simulate_batch)
    batch_module.simulate_batch = counting  # type: ignore[assignment]
    before = load()
    start = time.perf_counter()
    try:
        study = tolerance_study(
            mechanism,
            spec,
            responses="dynamic",
            method=MonteCarlo(samples, seed=seed),
            contact=contact,
            solver=solver_of(tolerances),
            backend=Backend("processes"),
        )
    finally:
        batch_module.simulate_batch = counting.original  # type: ignore[assignment]
    wall = time.perf_counter() - start
    run = study.result.run
    names = study.result.response_names
    values = np.column_stack([run.values[:, names.index(f"{r}_peak")] for r in STUDY_RESPONSES])
    sampled, rows = [], 0  # the sampling run's blocks; the convergence check's come after
    for block in counting.counters:
        if rows < samples:
            sampled.append(block)
            rows += len(block)
    steps = float(np.mean(np.concatenate([c["n_steps"].to_numpy() for c in sampled])))
    rhs = float(np.mean(np.concatenate([c["n_rhs"].to_numpy() for c in sampled])))
    check = study.convergence
    return {
        "values": values,
        "ok": run.status == 0,
        "x": study.result.x,
        "wall": wall,
        "run_wall": run.wall_time,
        "load": f"{before} -> {load()}",
        "steps": steps,
        "rhs": rhs,
        "placement": ", ".join(counting.placement),
        "check": "none"
        if check is None
        else (
            f"{'warns' if check.finding else 'passes'}: {check.response} "
            f"{check.share:.0%} of its std (limit {check.limit:.0%})"
        ),
    }


def bootstrap_ci(
    statistic: Callable[[FloatArray], float], a: FloatArray, b: FloatArray, rng: np.random.Generator
) -> tuple[float, float, float]:
    """statistic(a) - statistic(b) and its paired bootstrap 95 % CI (rows resampled together)."""
    n = len(a)
    draws = np.empty(BOOTSTRAP)
    for i in range(BOOTSTRAP):
        rows = rng.integers(0, n, n)
        draws[i] = statistic(a[rows]) - statistic(b[rows])
    low, high = np.percentile(draws, [2.5, 97.5])
    return statistic(a) - statistic(b), float(low), float(high)


def ks_p(a: FloatArray, b: FloatArray) -> float:
    from scipy.stats import ks_2samp

    return float(ks_2samp(a, b).pvalue)


def own_ci(
    statistic: Callable[[FloatArray], float], b: FloatArray, rng: np.random.Generator
) -> float:
    """Half-width of the bootstrap 95 % CI of statistic(b): the study's own Monte Carlo
    uncertainty at its sample count."""
    n = len(b)
    draws = [statistic(b[rng.integers(0, n, n)]) for _ in range(BOOTSTRAP)]
    low, high = np.percentile(draws, [2.5, 97.5])
    return float((high - low) / 2)


def compare(name: str, run: dict[str, Any], reference: dict[str, Any]) -> None:
    rng = np.random.default_rng(0)
    ok = run["ok"] & reference["ok"]
    print(f"\n#### {name} against the reference ({int(ok.sum())} paired samples)\n")
    print("| response | mean (ref ± its own 95 % CI) | Δmean [95 % CI] | Δmean/std | "
          "p95 (ref ± its own 95 % CI) | Δp95 [95 % CI] | Δp95/std | KS p | "
          "median paired abs(Δ)/std | sd(Δ)/(√2·std) |")  # fmt: skip
    print("|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|")
    p95: Callable[[FloatArray], float] = lambda v: float(np.percentile(v, 95))  # noqa: E731
    for j, response in enumerate(STUDY_RESPONSES):
        a, b = run["values"][ok, j], reference["values"][ok, j]
        std = b.std(ddof=1)
        dm, lo, hi = bootstrap_ci(np.mean, a, b, rng)
        dp, plo, phi = bootstrap_ci(p95, a, b, rng)
        d = a - b
        print(
            f"| {response} | {a.mean():.4g} ({b.mean():.4g} ± {own_ci(np.mean, b, rng):.2g}) | "
            f"{dm:+.3g} [{lo:+.3g}, {hi:+.3g}] | {dm / std:+.3f} | "
            f"{p95(a):.4g} ({p95(b):.4g} ± {own_ci(p95, b, rng):.2g}) | "
            f"{dp:+.3g} [{plo:+.3g}, {phi:+.3g}] | {dp / std:+.3f} | {ks_p(a, b):.2f} | "
            f"{np.median(np.abs(d)) / std:.2f} | {d.std(ddof=1) / np.sqrt(2) / std:.2f} |"
        )
    j = STUDY_RESPONSES.index("F_B")
    a, b = run["values"][ok, j], reference["values"][ok, j]
    share: Callable[[FloatArray], float] = lambda v: float(np.mean(v <= YIELD_LIMIT))  # noqa: E731
    dy, ylo, yhi = bootstrap_ci(share, a, b, rng)
    print(
        f"\nyield F_B peak <= {YIELD_LIMIT:g} N: {share(a):.1%} against {share(b):.1%} "
        f"(± {own_ci(share, b, rng):.1%}, the reference's own 95 % CI), "
        f"Δ {dy:+.1%} [{ylo:+.1%}, {yhi:+.1%}]; samples on different sides of the limit: "
        f"{int(np.sum((a <= YIELD_LIMIT) != (b <= YIELD_LIMIT)))}"
    )


def check_rules(run: dict[str, Any], reference: dict[str, Any], name: str) -> None:
    """How the tolerance study's convergence check (re-run K samples with every tolerance
    100x tighter: here the reference) and the proposed one behave on these paired samples.

    current: warn if any response's largest |Δ| over the K samples exceeds 0.1 of its spread.
    proposed: per response, warn only if the mean shift is significant (two-sided t-test of
    the K differences, level 0.05 / responses: Bonferroni) and larger than 0.1 of the spread.
    Warning rates over random K-subsets of the pairs (the rates at which each would warn on
    this study); power of the proposed test for a true shift of s spreads, from the noncentral
    t with the observed sd(Δ)."""
    from scipy.stats import nct, t

    rng = np.random.default_rng(1)
    ok = run["ok"] & reference["ok"]
    d = run["values"][ok] - reference["values"][ok]
    spread = run["values"][ok].std(axis=0, ddof=1)
    r = d.shape[1]
    alpha = 0.05 / r
    print(f"\n#### The convergence check on {name} ({len(d)} pairs, {r} responses)\n")
    print("| K | current rule warns | proposed rule warns | proposed: power at shift "
          "0.1 / 0.2 / 0.5 spread (median response) |")  # fmt: skip
    print("|---:|---:|---:|---|")
    for k in (k for k in (8, 16, 32, 64) if k <= len(d)):
        current = proposed = 0
        draws = 2000
        for _ in range(draws):
            rows = rng.choice(len(d), k, replace=False)
            sub = d[rows]
            current += bool(np.any(np.max(np.abs(sub), axis=0) > 0.1 * spread))
            mean, se = sub.mean(axis=0), sub.std(axis=0, ddof=1) / np.sqrt(k)
            significant = np.abs(mean) > t.ppf(1 - alpha / 2, k - 1) * se
            proposed += bool(np.any(significant & (np.abs(mean) > 0.1 * spread)))
        critical = t.ppf(1 - alpha / 2, k - 1)
        sd_share = np.median(d.std(axis=0, ddof=1) / spread)
        powers = []
        for shift in (0.1, 0.2, 0.5):
            ncp = shift / (sd_share / np.sqrt(k))
            power = 1 - nct.cdf(critical, k - 1, ncp) + nct.cdf(-critical, k - 1, ncp)
            powers.append(power if np.isfinite(power) else 1.0)  # nct fails far in the tail
        print(
            f"| {k} | {current / draws:.0%} | {proposed / draws:.0%} | "
            + " / ".join(f"{p:.0%}" for p in powers)
            + f" (sd(Δ) = {sd_share:.2f} spread) |"
        )


def study(
    samples: int,
    seed: int,
    clearance: float | None,
    saved: dict[str, Any],
    reference_tolerances: tuple[float, float, float] = REFERENCE,
) -> None:
    """``reference_tolerances`` other than :data:`REFERENCE`: that is the reference, and the
    usual reference is compared with it like the loose tolerances."""
    runs: dict[str, dict[str, Any]] = {}
    compared = STUDY_TOLERANCES
    if reference_tolerances != REFERENCE:
        compared = (*STUDY_TOLERANCES, REFERENCE)
    configurations: Sequence[tuple[str, Any, tuple[float, float, float]]] = (
        ("warm-up (not timed)", "ifm-conventional", DEFAULT),
        ("conventional, default tolerances", "ifm-conventional", DEFAULT),
        *((f"physical, rtol {t[0]:g}", None, t) for t in compared),
        (f"physical, reference {label_of(reference_tolerances)}", None, reference_tolerances),
    )
    for name, contact, tolerances in configurations:
        n = 16 if name.startswith("warm-up") else samples
        runs[name] = run_study(n, seed, contact, tolerances, clearance)
        r = runs[name]
        print(f"{name}: {r['wall']:.1f} s ({r['run_wall']:.1f} s sampling), load {r['load']}",
              flush=True)  # fmt: skip
        saved[f"study|{name}"] = r["values"]
    del runs["warm-up (not timed)"]
    print(f"\n{samples} samples, seed {seed}, processes backend, {os.cpu_count()} CPUs; peaks of the "
          "batch engine (settle 2 + 1 revolution, steady start, located between steps)\n")  # fmt: skip
    print("| run | failed | study wall s | sampling wall s | samples/s (sampling) | steps per sample "
          "| rhs per sample | load before -> after | convergence check |")  # fmt: skip
    print("|---|---:|---:|---:|---:|---:|---:|---|---|")
    for name, r in runs.items():
        print(
            f"| {name} | {int((~r['ok']).sum())} | {r['wall']:.1f} | {r['run_wall']:.1f} | "
            f"{samples / r['run_wall']:.1f} | {r['steps']:.0f} | {r['rhs']:.0f} | {r['load']} | "
            f"{r['check']} |"
        )
    reference = runs[f"physical, reference {label_of(reference_tolerances)}"]
    names = list(runs)
    for name in names:
        if name.startswith("physical, rtol"):
            compare(name, runs[name], reference)
    check_rules(runs["physical, rtol 1e-06"], reference, "physical, rtol 1e-06")


def timing(samples: int, seed: int, rounds: int) -> None:
    """Interleaved wall times of the study (conventional, then the physical default at each
    rtol of :data:`STUDY_TOLERANCES`), ``rounds`` times: the machine is shared, so only times
    taken in the same minutes compare."""
    run_study(16, seed, "ifm-conventional", DEFAULT)  # warm-up
    configurations = (
        ("conventional", "ifm-conventional", DEFAULT),
        *((f"physical, rtol {t[0]:g}", None, t) for t in reversed(STUDY_TOLERANCES)),
    )
    print(
        f"\n{samples} samples, seed {seed}; study wall s (sampling wall s), load before -> after\n"
    )
    print("| round | " + " | ".join(name for name, _, _ in configurations) + " |")
    print("|---:|" + "---|" * len(configurations))
    for k in range(rounds):
        cells = []
        for _, contact, tolerances in configurations:
            r = run_study(samples, seed, contact, tolerances)
            cells.append(
                f"{r['wall']:.1f} ({r['run_wall']:.1f}), load {r['load']}, blocks {r['placement']}"
            )
        print(f"| {k + 1} | " + " | ".join(cells) + " |", flush=True)


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument(
        "--part", choices=("scatter", "study", "timing", "all"), default="all",
        help="timing: interleaved study wall times only (not part of all)",
    )  # fmt: skip
    parser.add_argument("--rounds", type=int, default=3, help="timing: rounds")
    parser.add_argument("--revolutions", type=int, default=20, help="scatter: analysed revolutions")
    parser.add_argument("--settle", type=int, default=2)
    parser.add_argument(
        "--sets",
        default="21,10,mixed,conventional",
        help="scatter: clearance sets, of 21, 10, mixed, conventional",
    )
    parser.add_argument(
        "--control", action="store_true", help="scatter: a second tight run (rtol 1e-10)"
    )
    parser.add_argument("--samples", type=int, default=200, help="study: Monte Carlo samples")
    parser.add_argument("--seed", type=int, default=1, help="study: Monte Carlo seed")
    parser.add_argument(
        "--reference",
        default=",".join(f"{v:g}" for v in REFERENCE),
        help="study: the reference's rtol,atol_position,atol_velocity (another one: the "
        "usual reference is compared with it too)",
    )
    parser.add_argument(
        "--clearance-um",
        type=float,
        default=None,
        help="study: every clearance within ±1 %% of this (µm) instead of its fit",
    )
    parser.add_argument("--save", default=None, help="keep the raw peaks in this .npz")
    args = parser.parse_args()
    print(f"load {load()}, {os.cpu_count()} CPUs")
    saved: dict[str, Any] = {}
    if args.part in ("scatter", "all"):
        scatter(args.revolutions, args.settle, args.sets.split(","), args.control, saved)
    if args.part in ("study", "all"):
        clearance = None if args.clearance_um is None else args.clearance_um * 1e-6
        reference = tuple(float(v) for v in args.reference.split(","))
        study(args.samples, args.seed, clearance, saved, reference)  # type: ignore[arg-type]
    if args.part == "timing":
        timing(args.samples, args.seed, args.rounds)
    if args.save:
        np.savez(args.save, **saved)


if __name__ == "__main__":
    main()
