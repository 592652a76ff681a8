"""The sustained-contact mode against the compliant physical default (issue 22).

The paper's four-bar at 200 rpm, the physical default contact (docs/contact.md: Liu's
stiffness, Hunt–Crossley damping with e = 0.8, Ambrósio friction μ = 0.1), 21 µm in all four
joints, from the steady start; ``ContactModel(sustained_contact=True)`` locks a pressed pin
onto its bearing's wall (docs/contact.md, "Sustained contact"). Parts:

``timing``: settle 2 + 1 revolution, default tolerances, mode off and on interleaved, best
of ``--rounds``: ms per revolution (the whole run's wall time / 3), the integrator's
counters; per joint the share of the analysed revolution spent locked, captures and
releases in the run; the settled revolution's peaks, off and on.

``scatter``: mode on, settle 2 + ``--revolutions`` revolutions: each revolution's peaks
(located on the continuous solution), their mean, relative standard deviation and lag-1
autocorrelation (is the settled motion still chaotic?).

``convergence``: mode on, settle 2 + 1 revolution at rtol 1e-6, 1e-7 and 1e-8: the settled
revolution's peaks.

``batch``: ``--samples`` samples of clearances 6–21 µm through the batch engine (local
backend), settle 2 + 1: samples per second with the mode off (``auto`` and ``implicit``)
and on (``implicit``, the only method the mode runs on).

``running``: the tolerance study's running responses (``RunningResponses``: peaks, speed
error, wear rates) of ``--samples`` samples of the paper's four-bar with the dry
conventional set and the mode on (capture 1 mm/s), settle 0 + 1 revolution from the steady
start: milliseconds per sample on the batch engine's implicit lanes (local backend, every
core; serial, one core) against one single-engine simulation per sample (``engine="single"``,
the path before, one core), best of ``--rounds`` after a warm-up; the largest relative
difference of the wear rates.

``modes``: at states of the analysed revolution where all four pins are locked (mode on;
Jacobian by central differences) or all four in compliant contact (mode off; the
closed-form Jacobian), the largest eigenvalues of ∂(q̇, q̈)/∂(q, q̇) (Hz, decay rate): the
compliant model's damped radial contact modes (kHz) and, in both, the pins' lightly damped
pendular modes around their bearings (100–1000 Hz), which set the step.

Run ``python benchmarks/bench_sustained_contact.py`` (about 3 minutes on a quiet machine);
``--part timing`` (or scatter, convergence, modes) for one part.
"""

from __future__ import annotations

import argparse
import os
import time
from typing import Any

import numpy as np
from numpy.typing import NDArray

from jointplay._kernels import eom
from jointplay.dynamics.peaks import locate_peaks
from jointplay.dynamics.setup import ContactModel
from jointplay.dynamics.simulate import SimulationResult, SolverOptions, Start, simulate
from jointplay.io.config import load_preset

JOINTS = ("O2", "A", "B", "O4")
CLEARANCE = 21e-6  # m
PERIOD = 60.0 / 200.0  # s
QUANTITIES = ("F_O2", "F_A", "F_B", "F_O4", "omega3", "omega4", "torque")
FloatArray = NDArray[np.float64]


def run(on: bool, settle: int = 2, revolutions: int = 1, rtol: float = 1e-6) -> SimulationResult:
    mechanism = load_preset("paper-fourbar")
    joints = ContactModel(sustained_contact=on).joints(mechanism, JOINTS, clearance=CLEARANCE)
    return simulate(
        mechanism,
        joints,
        revolutions=revolutions,
        settle=settle,
        start=Start("steady"),
        solver=SolverOptions(rtol=rtol),
    )


def memory(result: SimulationResult) -> FloatArray:
    n = result.system.n_coordinates
    return np.asarray(result.y[:, 2 * n + 2 :])


def switches(result: SimulationResult) -> tuple[FloatArray, FloatArray, FloatArray]:
    """Per joint: the share of the analysed time spent locked (the v0 slot of a step's start
    holds over the step), the captures and the releases of the whole run."""
    locked = memory(result) < 0
    t = result.t
    dt = np.diff(t)
    analysed = t[:-1] >= t[-1] - result.revolutions * PERIOD
    share = (dt[analysed, None] * locked[:-1][analysed]).sum(axis=0) / dt[analysed].sum()
    captures = (locked[1:] & ~locked[:-1]).sum(axis=0)
    releases = (~locked[1:] & locked[:-1]).sum(axis=0)
    return share, captures, releases


def revolution_peaks(result: SimulationResult, settle: int, revolutions: int) -> FloatArray:
    """(revolutions, quantities) peak |value| of each analysed revolution."""
    columns = result._step_columns
    windows = [((settle + k) * PERIOD, (settle + k + 1) * PERIOD) for k in range(revolutions)]
    located = locate_peaks(result.t, {q: columns[q] for q in QUANTITIES}, result.evaluate, windows)
    return np.array([[located[q][w].value for q in QUANTITIES] for w in range(revolutions)])


def load() -> str:
    return "load average " + " ".join(f"{x:.2f}" for x in os.getloadavg())


def timing(rounds: int) -> None:
    print(f"== timing: settle 2 + 1 revolution, best of {rounds}, interleaved ({load()})")
    best: dict[bool, SimulationResult] = {}
    for _ in range(rounds):
        for on in (False, True):
            result = run(on)
            if on not in best or result.solver_stats["wall_s"] < best[on].solver_stats["wall_s"]:
                best[on] = result
    print(f"   ({load()} after)")
    print("mode | ms/rev | steps | rejected (error/Newton/check) | rhs evals | Jacobians | "
          "energy residual")  # fmt: skip
    for on, result in best.items():
        s = result.solver_stats
        print(
            f"{'on ' if on else 'off'} | {s['wall_s'] * 1e3 / 3:6.1f} | {s['steps']:6d} | "
            f"{s['rejected_steps']:5d} ({s['rejected_by_error']}/{s['rejected_by_newton']}/"
            f"{s['rejected_for_contact_onset']}) | {s['rhs_evaluations']:7d} | "
            f"{s['jacobian_evaluations']:5d} | {s['energy_residual']:.1e}"
        )
    share, captures, releases = switches(best[True])
    for j, joint in enumerate(JOINTS):
        print(
            f"joint {joint}: locked {100 * share[j]:5.1f} % of the analysed revolution; "
            f"{captures[j]} captures, {releases[j]} releases in the run"
        )
    off = revolution_peaks(best[False], 2, 1)[0]
    on = revolution_peaks(best[True], 2, 1)[0]
    print("settled revolution's peaks: " + ", ".join(
        f"{q} {a:.2f} / {b:.2f}" for q, a, b in zip(QUANTITIES, off, on, strict=True)
    ) + "  (off / on)")  # fmt: skip


def scatter(revolutions: int) -> None:
    print(f"== scatter: mode on, settle 2 + {revolutions} revolutions")
    for on in (False, True):
        result = run(on, revolutions=revolutions)
        peaks = revolution_peaks(result, 2, revolutions)
        mean = peaks.mean(axis=0)
        rsd = peaks.std(axis=0, ddof=1) / mean
        v = peaks - mean
        lag1 = (v[1:] * v[:-1]).sum(axis=0) / (v * v).sum(axis=0)
        print(f"mode {'on' if on else 'off'} ({result.solver_stats['wall_s']:.1f} s):")
        for k, q in enumerate(QUANTITIES):
            print(
                f"  {q:7s} mean {mean[k]:8.2f}  rsd {100 * rsd[k]:5.1f} %  lag-1 {lag1[k]:+.2f}  "
                f"per revolution {np.array2string(peaks[:, k], precision=1, max_line_width=200)}"
            )


def convergence() -> None:
    print("== convergence: mode on, settle 2 + 1 revolution, peaks of the settled revolution")
    for rtol in (1e-6, 1e-7, 1e-8):
        result = run(True, rtol=rtol)
        peaks = revolution_peaks(result, 2, 1)[0]
        s = result.solver_stats
        print(
            f"rtol {rtol:.0e}: {s['steps']} steps, {s['wall_s']:.2f} s: "
            + ", ".join(f"{q} {p:.2f}" for q, p in zip(QUANTITIES, peaks, strict=True))
        )


def _frequencies(jac: FloatArray, count: int = 5) -> str:
    """The ``count`` largest eigenvalues of ``jac`` (one of each conjugate pair), in Hz."""
    values = np.linalg.eigvals(jac) / (2 * np.pi)
    values = values[values.imag >= 0]
    top = values[np.argsort(-np.abs(values))][:count]
    return ", ".join(f"{v.imag:.0f} Hz (decay {-2 * np.pi * v.real:+.0f}/s)" for v in top)


def modes(states: int) -> None:
    print("== modes: eigenvalues of d(qdot, qddot)/d(q, qdot), analysed revolution")
    for on in (True, False):
        result = run(on)
        n = result.system.n_coordinates
        args = result.system.kernel_args()
        t, y = result.t, result.y
        if on:  # all four pins locked; the Jacobian by central differences
            every = np.nonzero((memory(result) < 0).all(axis=1) & (t > 2 * PERIOD))[0]
        else:  # all four pins in compliant contact; the closed-form Jacobian
            inside = np.zeros(len(t), dtype=bool)
            contacts = np.zeros((len(JOINTS), 7))
            for i in range(len(t)):
                eom.evaluate(t[i], np.array(y[i]), *eom.pack(result.system.model), contacts)
                inside[i] = bool(np.all(contacts[:, 2] > 0))
            every = np.nonzero(inside & (t > 2 * PERIOD))[0]
        what = "locked" if on else "in compliant contact"
        print(
            f"mode {'on' if on else 'off'}: all four {what} at the end of {len(every)} of {len(t)} steps"
        )
        for i in every[:: max(1, len(every) // states)][:states]:
            y0 = np.array(y[i])
            if on:
                jac = np.zeros((2 * n, 2 * n))
                for k in range(2 * n):
                    h = 1e-7 * max(1e-3, abs(y0[k])) if k < n else 1e-6
                    up, down = y0.copy(), y0.copy()
                    up[k] += h
                    down[k] -= h
                    difference = eom.state_rhs(t[i], up, args) - eom.state_rhs(t[i], down, args)
                    jac[:, k] = difference[: 2 * n] / (2 * h)
            else:
                full = np.zeros((y0.size, y0.size))
                eom.jacobian_state(t[i], y0, eom.state_rhs(t[i], y0, args), args, full)
                jac = full[: 2 * n, : 2 * n]
            print(
                f"  t = {t[i]:.4f} s, step {t[i + 1] - t[i]:.1e} s: {_frequencies(jac, 8 if not on else 5)}"
            )


def batch(samples: int, rounds: int) -> None:
    """``samples`` samples (every joint's clearance uniform in 6–21 µm, seed 1), settle 2 + 1,
    the local backend (threads over the lanes): samples per second, mode off (the method
    ``auto`` chooses and ``implicit``) and on (implicit: the only method it runs on)."""
    from jointplay.dynamics.batch import BatchSamples, simulate_batch

    print(f"== batch: {samples} samples, clearances 6-21 um, settle 2 + 1, local backend, "
          f"best of {rounds}, interleaved ({load()})")  # fmt: skip
    mechanism = load_preset("paper-fourbar")
    rng = np.random.default_rng(1)
    inputs = BatchSamples(clearances={j: rng.uniform(6e-6, 21e-6, samples) for j in JOINTS})
    cases = (("off", False, "auto"), ("off", False, "implicit"), ("on", True, "implicit"))
    best: dict[str, tuple[float, Any]] = {}
    for _ in range(rounds):
        for label, on, method in cases:
            joints = ContactModel(sustained_contact=on).joints(mechanism, JOINTS, clearance=21e-6)
            result = simulate_batch(mechanism, joints, inputs, settle=2, method=method)
            key = f"{label} {method}"
            if key not in best or result.wall_time < best[key][0]:
                best[key] = (result.wall_time, result)
    print(f"   ({load()} after)")
    for key, (wall, result) in best.items():
        counters = result.counters
        print(
            f"mode {key:14s} ({result.method}): {samples / wall:5.1f} samples/s, "
            f"{counters['n_steps'].mean():7.0f} steps per sample, {int(result.ok.sum())} ok"
        )


def running(samples: int, rounds: int) -> None:
    import dataclasses

    from jointplay.execution.backends import Backend
    from jointplay.tolerance.analysis import build_model
    from jointplay.tolerance.sampling import sample
    from jointplay.tolerance.spec import ToleranceSpec

    mechanism = load_preset("paper-fourbar")
    spec = ToleranceSpec.from_mechanism(mechanism)
    model, spec = build_model(
        mechanism, spec, "running", settle=0, revolutions=1, contact="ifm-conventional"
    )
    model = dataclasses.replace(model, base=dataclasses.replace(model.base, capture_speed=1e-3))
    x = sample(spec, samples, 7).values
    batch, single = "batch (local: every core)", "single (one core)"
    engines = {
        batch: model,
        "batch (serial: one core)": dataclasses.replace(model, backend=Backend("serial")),
        single: dataclasses.replace(model, engine="single"),
    }
    for engine in engines.values():  # compile
        engine.evaluate(x[:1])
    print(f"== running: {samples} samples, mode on, settle 0 + 1 revolution ({load()})")
    best = dict.fromkeys(engines, np.inf)
    values = {}
    for _ in range(rounds):
        for name, engine in engines.items():
            start = time.perf_counter()
            values[name] = engine.evaluate(x)
            best[name] = min(best[name], time.perf_counter() - start)
    wear = [k for k, n in enumerate(model.response_names) if n.startswith("wear_rate")]
    a, b = values[batch].values[:, wear], values[single].values[:, wear]
    for name, seconds in best.items():
        print(f"{name:26s}: {seconds / samples * 1e3:7.1f} ms per sample ({seconds:.2f} s)")
    print(f"wear rates: largest relative difference {np.max(np.abs(a - b) / np.abs(b)):.1e}")


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parts = ("timing", "scatter", "convergence", "modes", "batch", "running")
    parser.add_argument("--part", choices=parts)
    parser.add_argument("--samples", type=int, default=16)
    parser.add_argument("--rounds", type=int, default=3)
    parser.add_argument("--revolutions", type=int, default=10)
    parser.add_argument("--states", type=int, default=5)
    options = parser.parse_args()
    run(True, settle=0, revolutions=1)  # compile (cached kernels)
    started = time.perf_counter()
    if options.part in (None, "timing"):
        timing(options.rounds)
    if options.part in (None, "modes"):
        modes(options.states)
    if options.part in (None, "convergence"):
        convergence()
    if options.part in (None, "scatter"):
        scatter(options.revolutions)
    if options.part in (None, "batch"):
        batch(options.samples, options.rounds)
    if options.part in (None, "running"):
        running(options.samples, options.rounds)
    print(f"({time.perf_counter() - started:.0f} s)")


if __name__ == "__main__":
    main()
